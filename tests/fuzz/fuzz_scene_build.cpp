// libFuzzer target: scene text -> parse -> validate -> trace every train -> SeaSurface::build, then
// the surface at 0 s and 1e6 s over the domain. Whatever validates must build without crashing and
// give finite heights within the surface's own bound.
//
// The caps below only keep one execution short (a few ms) so the fuzzer explores; they are far
// inside the limits the scene validation enforces (docs/scenes.md, "Limits"), which bound memory.
// The estimated build time caps what the others do not: a parabolic march resolving 1 m waves over
// the domain (7 million nodes, 24 s under the sanitizers) timed the fuzzer out. 5 s of estimate, as
// the scene fuzzer's ctest run (tests/CMakeLists.txt), takes the shipped scenes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "houle/sim/animation.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
#include "scene_file.hpp"

namespace {

constexpr double max_extent_m = 400.0;
constexpr std::uint32_t max_rays = 256, max_samples = 1u << 15;
constexpr std::size_t max_trains = 3;
constexpr int probes = 24;  // per side of the grid of surface probes
constexpr double max_estimated_s = 5.0;  // estimate_build_cost at the draft quality, one thread

bool quick(const houle::Scene& s) {
  const double ex = s.domain.x_max - s.domain.x_min, ey = s.domain.y_max - s.domain.y_min;
  const houle::DwtSettings& d = s.dwt;
  return ex <= max_extent_m && ey <= max_extent_m && s.trains.size() <= max_trains && d.max_rays <= max_rays &&
         d.max_samples <= max_samples && d.initial_rays <= max_rays && d.step >= 1e-3 * std::max(ex, ey) &&
         d.insertion_distance <= 0.25 * std::max(ex, ey);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > houle::cli::max_scene_file_bytes) return -1;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  houle::Expected<houle::Scene> parsed = houle::cli::parse_scene(text, "fuzz.toml", "/nonexistent");
  if (!parsed) return 0;
  houle::Scene scene = std::move(parsed.value());
  // Seeds (scenes/) use the default caps: bring them down rather than skip them.
  scene.dwt.max_rays = std::min(scene.dwt.max_rays, max_rays);
  scene.dwt.max_samples = std::min(scene.dwt.max_samples, max_samples);
  scene.dwt.on_cap = houle::OnCap::warn;  // the caps above are ours: a truncated field is still checked
  if (!quick(scene)) return -1;
  // Lower caps can make a valid scene invalid (an automatic ray count over max_rays): what must build
  // is what validates with them.
  houle::Expected<houle::Scene> capped = houle::validate(std::move(scene));
  if (!capped) return -1;
  scene = std::move(capped.value());
  if (houle::estimate_build_cost(scene, houle::quality_preset(houle::QualityPreset::draft), 0, 1).seconds() > max_estimated_s) return -1;

  const houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 1);
  if (!field) __builtin_trap();  // the scene validated: tracing has no reason to refuse it
  const houle::Domain& d = scene.domain;
  const float cell = float(std::max(d.x_max - d.x_min, d.y_max - d.y_min) / 64.0);
  houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), cell);
  if (!sea) __builtin_trap();
  const float bound = sea->height_bound();
  if (!std::isfinite(bound) || bound < 0.0f) __builtin_trap();
  float x[probes], y[probes], h[probes], gx[probes], gy[probes];
  for (double t : {0.0, 1e6}) {
    sea->set_time(t);
    for (int j = 0; j < probes; ++j) {
      for (int i = 0; i < probes; ++i) {
        // The domain and a margin around it (outside, the sea continues its edge).
        x[i] = float(d.x_min + (d.x_max - d.x_min) * (1.2 * i / (probes - 1) - 0.1));
        y[i] = float(d.y_min + (d.y_max - d.y_min) * (1.2 * j / (probes - 1) - 0.1));
      }
      sea->eval(x, y, probes, h, gx, gy);
      for (int i = 0; i < probes; ++i) {
        if (!std::isfinite(h[i]) || !std::isfinite(gx[i]) || !std::isfinite(gy[i])) __builtin_trap();
        if (std::abs(h[i]) > bound * 1.001f + 1e-6f) __builtin_trap();
      }
    }
  }
  return 0;
}
