#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"
#include "scene_file.hpp"
#include "scene_source.hpp"

namespace houle::cli {

int cmd_validate(std::span<char* const> argv) {
  Args args("validate", argv);
  if (args.flag("--help")) {
    std::puts("usage: houle validate SCENE...\n\nChecks scene files; prints `SCENE: ok` or the first error of each as\nfile:line:column: error: field: what was expected, and warnings (a trace likely to\nreach dwt.max_samples) as file:line:column: warning: field: why. Exit code 2 if any is invalid.");
    return 0;
  }
  const std::vector<std::string> files = args.rest();
  if (args.failed() || files.empty()) {
    std::fprintf(stderr, "houle %s\n", args.failed() ? args.error().message.c_str() : "validate: expected at least one scene file");
    return 2;
  }
  int status = 0;
  for (const std::string& f : files) {
    std::vector<Error> warnings;
    const Expected<Scene> scene = load_scene_file(f, &warnings);
    for (const Error& w : warnings) std::fprintf(stderr, "%s: warning: %s\n", w.field.c_str(), w.message.c_str());
    if (scene) {
      std::printf("%s: ok\n", scene_name({f}).c_str());
    } else {
      std::fprintf(stderr, "%s: error: %s\n", scene.error().field.c_str(), scene.error().message.c_str());
      status = 2;
    }
    // Each result as soon as it is known: a run stopped on a later file keeps the earlier ones.
    std::fflush(stdout);
  }
  return status;
}

}  // namespace houle::cli
