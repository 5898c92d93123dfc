#include <cmath>
#include <cstdio>
#include <numbers>

#include "cli.hpp"
#include "commands.hpp"
#include "scene_source.hpp"

namespace houle::cli {

int cmd_info(std::span<char* const> argv) {
  Args args("info", argv);
  if (args.flag("--help")) {
    std::puts("usage: houle info [SCENE]\n\nDescribes a scene (the built-in coast without SCENE): domain, sea floor, wave trains,\nstructures and objects.");
    return 0;
  }
  const std::vector<std::string> positionals = args.rest();
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  const std::optional<Scene> scene = scene_from_args(positionals, "info");
  if (!scene) return 2;
  const Scene& s = *scene;
  std::printf("scene: %s\n", positionals.empty() ? "built-in coast" : positionals[0].c_str());
  std::printf("domain: [%g, %g] x [%g, %g] m\n", s.domain.x_min, s.domain.x_max, s.domain.y_min, s.domain.y_max);
  std::printf("sea floor: %s, depth %g m; %zu shoals, %zu bars, %zu channels%s\n",
              s.floor.base.kind == FloorKind::flat ? "flat" : "planar beach", s.floor.base.depth, s.floor.shoals.size(),
              s.floor.bars.size(), s.floor.channels.size(), s.floor.height_map ? ", height map" : "");
  std::printf("trains: %zu\n", s.trains.size());
  for (std::size_t i = 0; i < s.trains.size(); ++i) {
    const WaveTrain& t = s.trains[i];
    const double omega = train_omega(t);
    const Point2 d = train_direction(t);
    std::printf("  [%zu] period %.3g s, deep-water wavelength %.4g m, amplitude %g m, towards %.1f deg\n", i,
                2.0 * std::numbers::pi / omega, 2.0 * std::numbers::pi * 9.81 / (omega * omega), t.amplitude,
                std::atan2(d.y, d.x) * 180.0 / std::numbers::pi);
  }
  std::printf("walls: %zu, boxes: %zu, spheres: %zu\n", s.walls.size(), s.boxes.size(), s.spheres.size());
  std::printf("capillary ripples: %s\n", s.capillary.amplitude > 0.0 ? "on" : "off");
  return 0;
}

}  // namespace houle::cli
