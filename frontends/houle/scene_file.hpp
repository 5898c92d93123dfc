// Scene files: TOML (docs/scenes.md) into houle::Scene. Every error names the file, line and column
// and says what was expected: unknown keys, wrong types, and whatever sim's validate() rejects.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"

namespace houle::cli {

/// Scene files larger than this are refused before parsing (a scene is a few kB; a height map is an
/// image file beside it).
inline constexpr std::size_t max_scene_file_bytes = 1 << 20;

/// Error.field is "file:line:column", Error.message "key.path: what was expected". With `warnings`, a
/// valid scene's likely troubles (trace_cap_warnings) are added there, placed the same way. The path
/// "-" reads standard input (messages name it "standard input"; image paths resolve against ".").
Expected<Scene> load_scene_file(const std::string& path, std::vector<Error>* warnings = nullptr);
/// The same from text; `name` is used in messages, relative image paths resolve against `dir`.
Expected<Scene> parse_scene(std::string_view text, const std::string& name, const std::string& dir,
                            std::vector<Error>* warnings = nullptr);

}  // namespace houle::cli
