// Where a command's scene comes from: a file, or the built-in coast when none is named.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"

namespace houle::cli {

/// The scene named by the positionals (at most one), or the built-in coast. On error, prints
/// "file:line:col: error: field: what" (gcc's form, for editors) and returns nothing.
std::optional<Scene> scene_from_args(const std::vector<std::string>& positionals, const char* command);
/// What `info` and `bench` take last, alike: --quality, --threads and the scene. Takes them from
/// `args` (its other options already taken); on an error, prints it and returns nothing.
struct SceneRun {
  Scene scene;
  std::string name;  ///< scene_name()
  QualityPreset quality = QualityPreset::realtime;
  unsigned threads = 1;
};
std::optional<SceneRun> take_scene_run(Args& args, const char* command);

/// What messages call that scene: its file, or "built-in coast".
std::string scene_name(const std::vector<std::string>& positionals);

/// With dwt.on_cap = "warn" a trace may stop at a cap and leave part of the field empty: every command
/// that traced says so on stderr ("houle <command>: <scene>: warning: ...").
void warn_if_truncated(const char* command, const std::string& scene, const WaveField& field);

}  // namespace houle::cli
