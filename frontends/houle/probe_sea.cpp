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
  exit_code = 2;
  // The realtime quality's resampling grid, or the draft's where that would not fit (validate made
  // sure the draft's does).
  float sea_cell = Quality{}.sea_cell;
  if (const Expected<void> fits = check_build_cost(estimate_build_cost(scene, Quality{}, 0, 2), "on 0.5 m cells"); !fits) {
    const Quality draft = quality_preset(QualityPreset::draft);
    if (const Expected<void> coarse = check_build_cost(estimate_build_cost(scene, draft, 0, 2), "on 1 m cells"); !coarse) {
      std::fprintf(stderr, "houle %s: %s: %s: %s\n", command, name.c_str(), coarse.error().field.c_str(), coarse.error().message.c_str());
      return std::nullopt;
    }
    sea_cell = draft.sea_cell;
    std::fprintf(stderr, "houle %s: %s: note: the sea is resampled on %g m cells: %s\n", command, name.c_str(), double(sea_cell),
                 fits.error().message.c_str());
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
