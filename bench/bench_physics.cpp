// What the wave physics costs, variant beside variant in one process so the ratios are measured
// under the same load:
// - dispersion: the batched float wavenumber kernel (dispersion_k_batch) on every supported ISA
//   against the scalar double solver (linear_wave, cold start and warm start from the previous
//   depth): the price of double accuracy and of the full LinearWave record per depth.
// - diffraction coefficient: the exact Sommerfeld field against the paper's Larras fit (as printed
//   and corrected) and the float A&S Fresnel path, per evaluation: how much the exact solution
//   costs over the (much less accurate, see diffraction.hpp) fits.
// - DWT scene build: trace_wave_field for the paper's Fig. 4 scene, the built-in coast and its swell
//   alone (one train: what the second thread does within a train), 1 and 2 threads (Fig. 4 also on
//   fresh pages, as a process's first build), with the tracer's own stats as counters (the paper:
//   < 5 s on a 180 MHz R5000, its 125 diffracted rays included), SeaSurface::build (the per-scene
//   resampling, with each pierhead's diffracted wave) at each preset's sea_cell, SeaSurface::surf_map
//   (where the waves break and the foam they carry) and SeaSurface::eval per sample (height +
//   gradient of the traced sea, the retessellation's kernel).
// - the DWT accuracy knob: Fig. 4 with step x insertion distance, samples and rays as counters:
//   the trace's time against its resolution.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <optional>
#include <cmath>
#include <complex>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "houle/runtime/bulk_memory.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

constexpr double pi = 3.14159265358979323846;

// Per-item counters: items/s from SetItemsProcessed, and ns per item.
void set_item_counters(benchmark::State& state, std::size_t items_per_iteration) {
  const double items = double(state.iterations()) * double(items_per_iteration);
  state.SetItemsProcessed(static_cast<std::int64_t>(items));
  state.counters["ns_per_item"] = benchmark::Counter(items, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// ---- Dispersion ------------------------------------------------------------------------------------

// 4099 depths (a 16k+3 count: every ISA's tail runs), log-spaced from 1 cm to 200 m, i.e. kh from
// the shallow series to deep water for an 8 s swell, plus a few land points (depth <= 0).
constexpr std::size_t depth_count = 4099;
constexpr double swell_omega = 2.0 * pi / 8.0;  // rad/s

const std::vector<float>& depths() {
  static const std::vector<float> d = [] {
    std::vector<float> v(depth_count);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(std::log(0.01), std::log(200.0));
    for (std::size_t i = 0; i < depth_count; ++i) v[i] = i % 97 == 0 ? -0.5f : float(std::exp(u(rng)));
    return v;
  }();
  return d;
}

void bm_dispersion_batch(benchmark::State& state, houle::Isa isa) {
  const std::vector<float>& d = depths();
  std::vector<float> k(d.size());
  for (auto _ : state) {
    houle::dispersion_k_batch(isa, swell_omega, d.data(), d.size(), k.data());
    benchmark::DoNotOptimize(k.data());
    benchmark::ClobberMemory();
  }
  set_item_counters(state, d.size());
  state.SetLabel(std::string(houle::isa_name(isa)));
}

// The scalar double reference, one full LinearWave per depth from Fenton & McKee's start.
void bm_linear_wave(benchmark::State& state) {
  const std::vector<float>& d = depths();
  for (auto _ : state) {
    double sum = 0.0;
    for (float h : d) sum += houle::linear_wave(swell_omega, double(h)).k;
    benchmark::DoNotOptimize(sum);
  }
  set_item_counters(state, d.size());
}

// The same along a ray: depths change slowly, each solve starts from the previous kh (sorted depths).
void bm_linear_wave_warm(benchmark::State& state) {
  static const std::vector<float> sorted = [] {
    std::vector<float> v = depths();
    std::sort(v.begin(), v.end());
    return v;
  }();
  for (auto _ : state) {
    double sum = 0.0, kh = 0.0;
    for (float h : sorted) {
      const houle::LinearWave w = houle::linear_wave(swell_omega, double(h), kh);
      kh = w.kh;
      sum += w.k;
    }
    benchmark::DoNotOptimize(sum);
  }
  set_item_counters(state, sorted.size());
}

// ---- Diffraction coefficient -----------------------------------------------------------------------

// 1000 fixed points: r/L in [0.5, 10] (the paper models' range), theta strictly inside (0, 2 pi)
// (water on both sides of the shadow line), normal incidence, rigid wall.
struct DiffractionPoint {
  double r_over_L, theta;
};
constexpr std::size_t diffraction_points = 1000;
constexpr double theta0 = pi / 2;
constexpr double rigid = 1.0;

const std::vector<DiffractionPoint>& diffraction_set() {
  static const std::vector<DiffractionPoint> p = [] {
    std::vector<DiffractionPoint> v(diffraction_points);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> r(0.5, 10.0), t(1e-3, 2.0 * pi - 1e-3);
    for (auto& q : v) q = {r(rng), t(rng)};
    return v;
  }();
  return p;
}

void bm_diffraction(benchmark::State& state, houle::DiffractionModel model) {
  const auto& pts = diffraction_set();
  // Validity is checked once, outside the timed loop.
  for (const auto& q : pts) {
    if (!houle::diffraction(model, q.r_over_L, q.theta, theta0, rigid)) {
      state.SkipWithError("diffraction rejected a point of the fixed set");
      return;
    }
  }
  for (auto _ : state) {
    double sum = 0.0;
    for (const auto& q : pts) sum += houle::diffraction(model, q.r_over_L, q.theta, theta0, rigid).value().K;
    benchmark::DoNotOptimize(sum);
  }
  set_item_counters(state, pts.size());
  state.SetLabel(std::string(houle::diffraction_model_name(model)));
}

// The field alone (no validation, no Expected): double, and the float A&S path.
void bm_sommerfeld_field(benchmark::State& state) {
  const auto& pts = diffraction_set();
  for (auto _ : state) {
    double sum = 0.0;
    for (const auto& q : pts) sum += std::abs(houle::sommerfeld_field(2.0 * pi * q.r_over_L, q.theta, theta0, rigid));
    benchmark::DoNotOptimize(sum);
  }
  set_item_counters(state, pts.size());
}

void bm_sommerfeld_field_fg(benchmark::State& state) {
  const auto& pts = diffraction_set();
  for (auto _ : state) {
    float sum = 0.0f;
    for (const auto& q : pts) sum += std::abs(houle::sommerfeld_field_fg(2.0 * pi * q.r_over_L, q.theta, theta0, 1.0f));
    benchmark::DoNotOptimize(sum);
  }
  set_item_counters(state, pts.size());
}

// ---- DWT scene build ---------------------------------------------------------------------------------

// coast_swell: the coast's first train alone, one large front of curving rays (what one train does
// with a second thread).
enum class SceneId { fig4, coast, coast_swell };
const char* scene_name(SceneId s) {
  return s == SceneId::fig4 ? "paper_fig4" : s == SceneId::coast ? "builtin_coast" : "builtin_coast_swell";
}
const houle::Scene& scene(SceneId s) {
  static const houle::Scene fig4 = houle::paper_fig4(), coast = houle::builtin_coast();
  static const houle::Scene swell = [] {
    houle::Scene c = houle::builtin_coast();
    c.trains.resize(1);
    return c;
  }();
  return s == SceneId::fig4 ? fig4 : s == SceneId::coast ? coast : swell;
}

void set_dwt_counters(benchmark::State& state, const houle::DwtStats& s) {
  state.counters["rays"] = double(s.rays);
  state.counters["inserted_rays"] = double(s.inserted_rays);
  state.counters["samples"] = double(s.samples);
  state.counters["truncated"] = s.truncated ? 1.0 : 0.0;
  state.counters["shared_steps"] = double(s.shared_steps);
  state.counters["samples_per_s"] =
      benchmark::Counter(double(s.samples) * double(state.iterations()), benchmark::Counter::kIsRate);
}

// `cold`: every build on fresh pages, as the first in a process (the huge pages that earlier builds
// freed are given back, untimed), rather than on the pages the previous build left.
void bm_trace(benchmark::State& state, SceneId id, bool cold) {
  const houle::Scene& s = scene(id);
  const auto threads = unsigned(state.range(0));
  houle::DwtStats stats;
  for (auto _ : state) {
    if (cold) {
      state.PauseTiming();
      houle::BulkLayout::release_cached();
      state.ResumeTiming();
    }
    houle::Expected<houle::WaveField> f = houle::trace_wave_field(s, threads);
    if (!f) {
      state.SkipWithError(f.error().message.c_str());
      return;
    }
    stats = f.value().stats;
    benchmark::DoNotOptimize(f.value().trains.data());
  }
  set_dwt_counters(state, stats);
  state.SetLabel(scene_name(id));
}

// The accuracy knob: Fig. 4 with Scene::dwt.step and insertion_distance varied (m, args in cm).
void bm_trace_knob(benchmark::State& state) {
  houle::DwtSettings dwt = scene(SceneId::fig4).dwt;
  dwt.step = double(state.range(0)) / 100.0;
  dwt.insertion_distance = double(state.range(1)) / 100.0;
  houle::DwtStats stats;
  for (auto _ : state) {
    houle::Expected<houle::WaveField> f = houle::trace_wave_field(scene(SceneId::fig4), dwt, 1);
    if (!f) {
      state.SkipWithError(f.error().message.c_str());
      return;
    }
    stats = f.value().stats;
    benchmark::DoNotOptimize(f.value().trains.data());
  }
  set_dwt_counters(state, stats);
}

// The whole scene build a user waits for (trace, then the sea surface at realtime's 0.5 m cells) with
// each wave model (docs/physics.md 10.6), on range(0) threads.
void bm_scene_build(benchmark::State& state, SceneId id, houle::WaveModelKind kind) {
  houle::Scene s = scene(id);
  s.wave_model.kind = kind;
  const auto threads = unsigned(state.range(0));
  for (auto _ : state) {
    houle::Expected<houle::WaveField> f = houle::trace_wave_field(s, threads);
    if (!f) {
      state.SkipWithError(f.error().message.c_str());
      return;
    }
    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(s, f.value(), 0.5f, houle::SeaParts::drop, threads);
    if (!sea) {
      state.SkipWithError(sea.error().message.c_str());
      return;
    }
    benchmark::DoNotOptimize(sea.value().grids().data());
  }
}

// Traced once per scene and kept: SeaSurface::build's input.
const houle::WaveField* traced(SceneId id) {
  static std::map<SceneId, std::unique_ptr<houle::WaveField>> cache;
  auto it = cache.find(id);
  if (it == cache.end()) {
    houle::Expected<houle::WaveField> f = houle::trace_wave_field(scene(id), 2);
    if (!f) return nullptr;
    it = cache.emplace(id, std::make_unique<houle::WaveField>(std::move(f.value()))).first;
  }
  return it->second.get();
}

// SeaSurface::build at sea_cell = range(0) cm (the presets: draft 100, realtime 50, film 25).
void bm_sea_build(benchmark::State& state, SceneId id) {
  const houle::WaveField* f = traced(id);
  if (!f) {
    state.SkipWithError("tracing failed");
    return;
  }
  const float cell = float(state.range(0)) / 100.0f;
  std::size_t nodes = 0;
  houle::DiffractionWork diffraction;
  for (auto _ : state) {
    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene(id), *f, cell);
    if (!sea) {
      state.SkipWithError(sea.error().message.c_str());
      return;
    }
    nodes = 0;
    for (const houle::TrainGrid& g : sea.value().grids()) nodes += std::size_t(g.nx) * g.ny;
    diffraction = sea.value().diffraction_work();
    benchmark::DoNotOptimize(sea.value().trains().data());
  }
  state.counters["grid_nodes"] = double(nodes);
  state.counters["diffraction_evaluations"] = double(diffraction.evaluations);
  state.counters["samples_in"] = double(f->stats.samples);
  state.counters["samples_per_s"] =
      benchmark::Counter(double(f->stats.samples) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(scene_name(id));
}

// The traced sea of scene `id` at realtime's sea_cell, or none (the benchmark skipped with the error).
std::optional<houle::SeaSurface> realtime_sea(benchmark::State& state, SceneId id) {
  const houle::WaveField* f = traced(id);
  if (!f) {
    state.SkipWithError("tracing failed");
    return std::nullopt;
  }
  houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene(id), *f, 0.5f);
  if (!sea) {
    state.SkipWithError(sea.error().message.c_str());
    return std::nullopt;
  }
  return std::move(sea.value());
}

// SeaSurface::surf_map at realtime's sea_cell: where the waves break and the foam they carry, once
// per scene (docs/rendering.md 3.7).
void bm_surf_map(benchmark::State& state, SceneId id) {
  std::optional<houle::SeaSurface> sea = realtime_sea(state, id);
  if (!sea) return;
  std::size_t foaming = 0;
  for (auto _ : state) {
    const houle::SurfMap m = sea->surf_map(scene(id));
    foaming = std::size_t(std::count_if(m.foam.begin(), m.foam.end(), [](float v) { return v > 0.0f; }));
    benchmark::DoNotOptimize(m.foam.data());
  }
  state.counters["foam_nodes"] = double(foaming);
  state.SetLabel(scene_name(id));
}

// Height + gradient per sample of the traced sea (SeaSurface::eval, every train summed: what the
// per-frame retessellation calls for each grid node), at realtime's sea_cell, 1003 random points
// over the domain per call (an 8k+3 count), a new time per iteration.
void bm_sea_eval(benchmark::State& state, SceneId id) {
  std::optional<houle::SeaSurface> sea = realtime_sea(state, id);
  if (!sea) return;
  const houle::Domain& d = scene(id).domain;
  constexpr std::size_t n = 1003;
  std::vector<float> x(n), y(n), h(n), gx(n), gy(n);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> ux(d.x_min, d.x_max), uy(d.y_min, d.y_max);
  for (std::size_t i = 0; i < n; ++i) x[i] = float(ux(rng)), y[i] = float(uy(rng));
  double t = 0.0;
  for (auto _ : state) {
    sea->set_time(t);
    sea->eval(x.data(), y.data(), n, h.data(), gx.data(), gy.data());
    t += 1.0 / 30.0;
    benchmark::DoNotOptimize(h.data());
    benchmark::ClobberMemory();
  }
  set_item_counters(state, n);
  state.counters["trains"] = double(sea->trains().size());
  state.SetLabel(scene_name(id));
}

const bool registered = [] {
  for (houle::Isa isa : houle::supported_isas()) {
    benchmark::RegisterBenchmark(("dispersion_k_batch/" + std::string(houle::isa_name(isa))).c_str(),
                                 bm_dispersion_batch, isa);
  }
  benchmark::RegisterBenchmark("linear_wave/double", bm_linear_wave);
  benchmark::RegisterBenchmark("linear_wave/double_warm", bm_linear_wave_warm);

  for (auto m : {houle::DiffractionModel::exact, houle::DiffractionModel::paper,
                 houle::DiffractionModel::paper_corrected}) {
    benchmark::RegisterBenchmark(("diffraction/" + std::string(houle::diffraction_model_name(m))).c_str(),
                                 bm_diffraction, m);
  }
  benchmark::RegisterBenchmark("sommerfeld_field/double", bm_sommerfeld_field);
  benchmark::RegisterBenchmark("sommerfeld_field_fg/float", bm_sommerfeld_field_fg);

  for (SceneId id : {SceneId::fig4, SceneId::coast, SceneId::coast_swell}) {
    benchmark::RegisterBenchmark(("trace_wave_field/" + std::string(scene_name(id))).c_str(), bm_trace, id, false)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  benchmark::RegisterBenchmark("trace_wave_field_cold/paper_fig4", bm_trace, SceneId::fig4, true)
      ->ArgName("threads")
      ->Arg(1)
      ->Arg(2)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("trace_knob/paper_fig4", bm_trace_knob)
      ->ArgNames({"step_cm", "insert_cm"})
      ->ArgsProduct({{20, 40, 80}, {50, 100, 200}})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (SceneId id : {SceneId::fig4, SceneId::coast}) {
    benchmark::RegisterBenchmark(("sea_surface_build/" + std::string(scene_name(id))).c_str(), bm_sea_build, id)
        ->ArgName("cell_cm")
        ->Arg(100)
        ->Arg(50)
        ->Arg(25)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("sea_surface_eval/" + std::string(scene_name(id))).c_str(), bm_sea_eval, id);
    benchmark::RegisterBenchmark(("surf_map/" + std::string(scene_name(id))).c_str(), bm_surf_map, id)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    for (const houle::WaveModelKind kind : {houle::WaveModelKind::rays, houle::WaveModelKind::parabolic}) {
      benchmark::RegisterBenchmark(("scene_build/" + std::string(scene_name(id)) + "/" + std::string(houle::wave_model_name(kind))).c_str(),
                                   bm_scene_build, id, kind)
          ->ArgName("threads")
          ->Arg(1)
          ->Arg(2)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
