// What a whole frame costs at each quality preset: the built-in coast animated through
// houle::Animation (trace and resample once per scene, then per frame: retessellation, capillary
// noise, march, intersect, shade) at 640x360 and 1280x720 with 2 threads, for draft, realtime and
// film (film at 640x360 only). This is the accuracy/time trade the presets name (docs/accuracy.md):
// the counters split each frame into Animation::last_times()'s stages so a change in one preset's
// frame time can be attributed. Frames advance at 30 fps of animation time (a frame is a pure
// function of time, so every run renders the same sequence).
//
// The frame-time distribution: each benchmark runs as repetitions (10, or 5 / 3 for the slow
// variants, see repetitions()) and reports only the aggregates (mean, median, stddev, cv and p99
// over repetitions; every counter gets them too).
// Within a repetition, frame_p99_ms / frame_max_ms are the per-frame p99 and maximum of that
// repetition's frames (the tail a player would see), next to the mean stage times.
//
// Also the per-frame retessellation alone (SeaSurface::set_time, SurfaceFrame::begin_frame at the
// camera's ground point, fill with SeaSurface::sample, as Animation::render does) at each preset's
// surface grid and sea_cell: ns per grid cell filled.
//
// Everything runs on the dispatched ISA (the label says which); the scalar path is the same program
// under HOULE_ISA=scalar (ctest runs realtime at 640x360 that way too).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "houle/render/framebuffer.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/surface/surface_frame.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

constexpr unsigned render_threads = 2;
constexpr double frame_dt = 1.0 / 30.0;  // s of animation time between frames
// Repetitions per size and preset: 10 where a frame is cheap (640x360 draft and realtime), fewer
// where one frame takes ~1 s or more on a loaded 2-core machine, so the smoke run (min_time per
// repetition) stays short. With few repetitions p99 is the slowest repetition.
int repetitions(houle::QualityPreset q, long width) {
  if (q == houle::QualityPreset::film) return 3;
  return width > 640 ? 5 : 10;
}

const houle::Scene& coast() {
  static const houle::Scene s = houle::builtin_coast();
  return s;
}

/// Nearest-rank percentile of v (copied: the statistic must not reorder the caller's data).
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * double(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}
double p99(const std::vector<double>& v) { return percentile(v, 0.99); }

// ---- Whole frames ----------------------------------------------------------------------------------

/// One Animation per (preset, size), created once (tracing, resampling, allocation) and warmed by
/// one frame so the first frame's allocations stay out of every timing.
houle::Animation* animation(houle::QualityPreset q, std::uint32_t w, std::uint32_t h, std::string* error) {
  using Key = std::tuple<int, std::uint32_t, std::uint32_t>;
  static std::map<Key, std::unique_ptr<houle::Animation>> cache;
  const Key key{int(q), w, h};
  auto it = cache.find(key);
  if (it == cache.end()) {
    houle::Expected<houle::Animation> a =
        houle::Animation::create(coast(), houle::quality_preset(q), w, h, render_threads);
    if (!a) {
      *error = a.error().field + ": " + a.error().message;
      return nullptr;
    }
    auto p = std::make_unique<houle::Animation>(std::move(a.value()));
    houle::Framebuffer fb(static_cast<int>(w), static_cast<int>(h));
    p->render(0.0, fb);
    it = cache.emplace(key, std::move(p)).first;
  }
  return it->second.get();
}

void bm_frame(benchmark::State& state, houle::QualityPreset q) {
  const auto w = std::uint32_t(state.range(0)), h = std::uint32_t(state.range(1));
  std::string error;
  houle::Animation* a = animation(q, w, h, &error);
  if (!a) {
    state.SkipWithError(error.c_str());
    return;
  }
  houle::Framebuffer fb(static_cast<int>(w), static_cast<int>(h));
  std::vector<double> frame_ms;
  frame_ms.reserve(std::size_t(state.max_iterations));
  double surface = 0.0, noise = 0.0, march = 0.0, intersect = 0.0, shade = 0.0;
  double t = 0.0;
  for (auto _ : state) {
    a->render(t, fb);
    t += frame_dt;
    const houle::AnimationTimes& s = a->last_times();
    surface += s.surface_ms;
    noise += s.noise_ms;
    march += s.render.march_ms;
    intersect += s.render.intersect_ms;
    shade += s.render.shade_ms;
    frame_ms.push_back(s.surface_ms + s.noise_ms + s.render.total_ms);
    benchmark::DoNotOptimize(fb.rgb.data());
    benchmark::ClobberMemory();
  }
  const double n = double(state.iterations());
  state.counters["surface_ms"] = surface / n;
  state.counters["noise_ms"] = noise / n;
  state.counters["march_ms"] = march / n;
  state.counters["intersect_ms"] = intersect / n;
  state.counters["shade_ms"] = shade / n;
  state.counters["frame_p99_ms"] = percentile(frame_ms, 0.99);
  state.counters["frame_max_ms"] = frame_ms.empty() ? 0.0 : *std::max_element(frame_ms.begin(), frame_ms.end());
  state.counters["fps"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.SetItemsProcessed(static_cast<std::int64_t>(n * double(w) * double(h)));  // pixels/s
  state.SetLabel(std::string(houle::quality_name(q)) + " " + std::string(houle::isa_name(houle::active_isa())));
}

// ---- Retessellation alone --------------------------------------------------------------------------

struct Retessellation {
  houle::SeaSurface sea;
  houle::SurfaceFrame frame;
  float centre_x = 0.0f, centre_y = 0.0f;  ///< m, the camera's ground point
};

Retessellation* retessellation(houle::QualityPreset q, std::string* error) {
  static std::map<int, std::unique_ptr<Retessellation>> cache;
  static const houle::Expected<houle::WaveField> waves = houle::trace_wave_field(coast(), render_threads);
  auto it = cache.find(int(q));
  if (it != cache.end()) return it->second.get();
  if (!waves) {
    *error = waves.error().field + ": " + waves.error().message;
    return nullptr;
  }
  const houle::Quality quality = houle::quality_preset(q);
  houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(coast(), waves.value(), quality.sea_cell);
  if (!sea) {
    *error = sea.error().field + ": " + sea.error().message;
    return nullptr;
  }
  houle::Expected<houle::SurfaceFrame> frame = houle::SurfaceFrame::create(quality.surface);
  if (!frame) {
    *error = frame.error().field + ": " + frame.error().message;
    return nullptr;
  }
  auto r = std::make_unique<Retessellation>(Retessellation{std::move(sea.value()), std::move(frame.value()),
                                                           float(coast().camera.position.x),
                                                           float(coast().camera.position.y)});
  return cache.emplace(int(q), std::move(r)).first->second.get();
}

/// The fill of every tile begin_frame marks, frame after frame at a fixed centre; `kept`: with the
/// static fields kept (SurfaceFrame::keep_static, as Animation fills), read back from the third frame.
void bm_retessellate(benchmark::State& state, houle::QualityPreset q, bool kept) {
  std::string error;
  Retessellation* r = retessellation(q, &error);
  if (!r) {
    state.SkipWithError(error.c_str());
    return;
  }
  const std::size_t keep_floats = kept ? r->sea.sample_keep_floats() : 0;
  r->frame.keep_static(keep_floats);
  // Cells filled per frame (the tiles begin_frame marks; the same every frame for a fixed centre).
  r->frame.begin_frame(r->centre_x, r->centre_y);
  const houle::SurfaceFrameConfig& c = r->frame.config();
  std::size_t tiles = 0;
  for (std::uint32_t l = 0; l < c.levels; ++l) {
    for (std::uint32_t tj = 0; tj < r->frame.tiles_per_side(); ++tj) {
      for (std::uint32_t ti = 0; ti < r->frame.tiles_per_side(); ++ti) tiles += r->frame.tile_filled(l, ti, tj) ? 1 : 0;
    }
  }
  const std::size_t cells = tiles * std::size_t(c.tile_cells) * c.tile_cells;
  double t = 0.0;
  for (auto _ : state) {
    r->sea.set_time(t);
    r->frame.begin_frame(r->centre_x, r->centre_y);
    r->frame.fill(&houle::SeaSurface::sample, &r->sea);
    t += frame_dt;
    benchmark::DoNotOptimize(r->frame.z_max());
    benchmark::ClobberMemory();
  }
  const double items = double(state.iterations()) * double(cells);
  state.SetItemsProcessed(static_cast<std::int64_t>(items));
  state.counters["ns_per_cell"] = benchmark::Counter(items, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["cells"] = double(cells);
  state.counters["sea_cell_m"] = double(houle::quality_preset(q).sea_cell);
  // 0 where the level's nodes do not fit its share of the keep (film): then nothing is kept.
  state.counters["kept_MiB"] = double(houle::SurfaceFrame::kept_bytes_bound(c, keep_floats)) / double(1 << 20);
  state.SetLabel(std::string(houle::quality_name(q)));
}

const bool registered = [] {
  struct Size {
    long w, h;
  };
  for (auto q : {houle::QualityPreset::draft, houle::QualityPreset::realtime, houle::QualityPreset::film}) {
    for (Size s : {Size{640, 360}, Size{1280, 720}}) {
      if (q == houle::QualityPreset::film && s.w > 640) continue;
      benchmark::RegisterBenchmark(("frame/" + std::string(houle::quality_name(q))).c_str(), bm_frame, q)
          ->Args({s.w, s.h})
          ->ArgNames({"w", "h"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Repetitions(repetitions(q, s.w))
          ->ReportAggregatesOnly(true)
          ->ComputeStatistics("p99", p99);
    }
  }
  for (auto q : {houle::QualityPreset::draft, houle::QualityPreset::realtime, houle::QualityPreset::film}) {
    for (bool kept : {false, true}) {
      benchmark::RegisterBenchmark(("retessellate/" + std::string(houle::quality_name(q)) + (kept ? "/kept" : "")).c_str(),
                                   bm_retessellate, q, kept)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
