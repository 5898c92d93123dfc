#include "probe_sea.hpp"

#include <algorithm>
#include <cstdio>

#include "houle/sim/animation.hpp"
#include "scene_source.hpp"

namespace houle::cli {

double distance_outside(const Domain& d, double x, double y) {
  return std::max({d.x_min - x, x - d.x_max, d.y_min - y, y - d.y_max, 0.0});
}

std::optional<SeaSurface> build_probe_sea(const Scene& scene, const std::string& name, const char* command, int& exit_code) {
  const float sea_cell = Quality{}.sea_cell;  // the realtime quality's resampling grid
  exit_code = 2;
  if (const Expected<void> fits = check_build_memory(scene, sea_cell, 0); !fits) {
    std::fprintf(stderr, "houle %s: %s: %s: %s\n", command, name.c_str(), fits.error().field.c_str(), fits.error().message.c_str());
    return std::nullopt;
  }
  Expected<WaveField> field = trace_wave_field(scene, 2);
  if (!field) {
    std::fprintf(stderr, "houle %s: %s: %s: %s\n", command, name.c_str(), field.error().field.c_str(), field.error().message.c_str());
    return std::nullopt;
  }
  warn_if_truncated(command, name, field.value());
  Expected<SeaSurface> sea = SeaSurface::build(scene, field.value(), sea_cell, SeaParts::keep, 2);
  if (!sea) {
    std::fprintf(stderr, "houle %s: %s\n", command, sea.error().message.c_str());
    exit_code = 1;
    return std::nullopt;
  }
  return std::move(sea.value());
}

}  // namespace houle::cli
