// Where a command's scene comes from: a file, or the built-in coast when none is named.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "houle/sim/scene.hpp"

namespace houle::cli {

/// The scene named by the positionals (at most one), or the built-in coast. On error, prints
/// "file:line:col: error: field: what" (gcc's form, for editors) and returns nothing.
std::optional<Scene> scene_from_args(const std::vector<std::string>& positionals, const char* command);
/// What messages call that scene: its file, or "built-in coast".
std::string scene_name(const std::vector<std::string>& positionals);

}  // namespace houle::cli
