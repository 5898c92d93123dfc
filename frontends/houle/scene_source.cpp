#include "scene_source.hpp"

#include <cstdio>

#include "scene_file.hpp"

namespace houle::cli {

std::optional<Scene> scene_from_args(const std::vector<std::string>& positionals, const char* command) {
  if (positionals.size() > 1) {
    std::fprintf(stderr, "houle %s: one scene file at most, got %zu arguments\n", command, positionals.size());
    return std::nullopt;
  }
  if (positionals.empty()) return builtin_coast();
  Expected<Scene> scene = load_scene_file(positionals[0]);
  if (!scene) {
    std::fprintf(stderr, "%s: error: %s\n", scene.error().field.c_str(), scene.error().message.c_str());
    return std::nullopt;
  }
  return std::move(scene.value());
}

std::optional<SceneRun> take_scene_run(Args& args, const char* command) {
  SceneRun run;
  run.threads = default_threads();
  take_quality(args, run.quality);
  take_threads(args, run.threads);
  const std::vector<std::string> positionals = args.rest();
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return std::nullopt;
  }
  std::optional<Scene> scene = scene_from_args(positionals, command);
  if (!scene) return std::nullopt;
  run.scene = std::move(*scene);
  run.name = scene_name(positionals);
  return run;
}

std::string scene_name(const std::vector<std::string>& positionals) {
  if (positionals.empty()) return "built-in coast";
  return positionals[0] == "-" ? "standard input" : positionals[0];
}

void warn_if_truncated(const char* command, const std::string& scene, const WaveField& field) {
  if (!field.stats.truncated) return;
  std::fprintf(stderr,
               "houle %s: %s: warning: the wave rays reached a cap (dwt.max_rays, dwt.max_samples or the path "
               "length) and stopped: the field beyond them is empty (dwt.on_cap = \"warn\")\n",
               command, scene.c_str());
}

}  // namespace houle::cli
