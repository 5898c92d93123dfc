// Surface tracking costs on every supported ISA: the per-frame grid fill from Gerstner trains and the
// marching of a frame of primary rays (one thread), with and without capillary noise.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/surface/march.hpp"
#include "houle/surface/surface_frame.hpp"
#include "coastal_waves.hpp"

namespace {

using houle::test::coastal_waves;

struct BenchScene {
  houle::SurfaceFrame frame;
  houle::GerstnerFrame waves;
  houle::Camera camera;
  houle::CapillaryFrame noise;
};

/// 5 m above the sea looking 8 degrees down, 60 degree vertical fov; the default SurfaceFrame
/// (8 levels of 256^2 cells from 0.25 m).
BenchScene& scene(std::uint32_t width, std::uint32_t height) {
  static BenchScene* s = nullptr;
  if (s == nullptr || s->camera.width != width) {
    auto f = houle::SurfaceFrame::create({});
    auto w = houle::make_gerstner_frame(coastal_waves(), 12.5);
    houle::CameraParams cp;
    cp.position = {0.0f, 0.0f, 5.0f};
    cp.look_at = {0.0f, 100.0f, 5.0f - 100.0f * std::tan(8.0f * 0.017453292f)};
    cp.width = width;
    cp.height = height;
    auto cam = houle::make_camera(cp);
    auto n = houle::make_capillary_frame(houle::CapillaryParams{}, 12.5);
    delete s;
    s = new BenchScene{std::move(f.value()), w.value(), cam.value(), n.value()};
    s->frame.begin_frame(0.0f, 0.0f);
    houle::fill_gerstner(s->frame, s->waves);
  }
  return *s;
}

/// Per-frame grid fill: all tiles (`view` false) or the camera's frustum only.
void bm_fill(benchmark::State& state, houle::Isa isa, bool view) {
  BenchScene& s = scene(640, 360);
  const houle::SurfaceFrameConfig& c = s.frame.config();
  float cx = 0.0f;
  double nodes = 0.0;
  for (auto _ : state) {
    s.frame.begin_frame(cx, 0.0f);  // a moving camera: the grids re-snap
    if (view) s.frame.restrict_to_view(s.camera);
    houle::fill_gerstner(isa, s.frame, s.waves);
    cx += 0.37f;
    benchmark::ClobberMemory();
  }
  // Nodes evaluated per frame: (tile_cells + 1)^2 per filled tile at most; count filled tiles.
  std::size_t filled = 0;
  for (std::uint32_t l = 0; l < c.levels; ++l) {
    for (std::uint32_t j = 0; j < s.frame.tiles_per_side(); ++j) {
      for (std::uint32_t i = 0; i < s.frame.tiles_per_side(); ++i) filled += s.frame.tile_filled(l, i, j);
    }
  }
  nodes = double(filled) * c.tile_cells * c.tile_cells;
  s.frame.begin_frame(0.0f, 0.0f);
  houle::fill_gerstner(s.frame, s.waves);
  // Inverted rates are times per item, printed in s with an SI prefix (ms, us, ns).
  state.counters["frame_time"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["node_time"] = benchmark::Counter(double(state.iterations()) * nodes,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["nodes"] = nodes;
}

/// The bounds pass alone (tile and global bounds of a filled frame).
void bm_finish(benchmark::State& state) {
  BenchScene& s = scene(640, 360);
  for (auto _ : state) {
    s.frame.finish_frame();
    benchmark::ClobberMemory();
  }
  // Inverted rates are times per item, printed in s with an SI prefix (ms, us, ns).
  state.counters["frame_time"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void bm_march(benchmark::State& state, houle::Isa isa, bool noise) {
  const auto width = std::uint32_t(state.range(0)), height = std::uint32_t(state.range(1));
  BenchScene& s = scene(width, height);
  houle::MarchParams p;
  p.pixel_angle = s.camera.pixel_angle;
  if (noise) p.noise = &s.noise;
  std::vector<float> t(width), x(width), y(width), z(width), gx(width), gy(width);
  std::vector<houle::MarchStatus> status(width);
  std::vector<std::uint32_t> evaluations(width);
  const houle::MarchHits hits{t.data(), x.data(), y.data(), z.data(), gx.data(), gy.data(), status.data(), nullptr,
                              evaluations.data()};
  double evals = 0.0, sea_evals = 0.0, sea = 0.0, packet_evals = 0.0;
  const std::size_t lanes = houle::isa_width(isa);
  for (auto _ : state) {
    evals = sea_evals = sea = packet_evals = 0.0;
    for (std::uint32_t row = 0; row < height; ++row) {
      houle::march_camera_row(isa, s.frame, s.camera, p, row, 0, width, 0.5f, 0.5f, hits);
      for (std::uint32_t i = 0; i < width; ++i) {
        const bool hit = status[i] == houle::MarchStatus::hit;
        evals += evaluations[i];
        sea_evals += hit ? evaluations[i] : 0.0;
        sea += hit;
      }
      // A packet steps while any of its lanes does (the march's packets are consecutive pixels).
      for (std::size_t i = 0; i < width; i += lanes) {
        const auto first = evaluations.begin() + std::ptrdiff_t(i);
        packet_evals += double(*std::max_element(first, first + std::ptrdiff_t(std::min<std::size_t>(lanes, width - i)))) *
                        double(lanes);
      }
    }
    benchmark::ClobberMemory();
  }
  const double rays = double(width) * height;
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays));
  // Inverted rates are times per item, printed in s with an SI prefix (ms, us, ns).
  state.counters["frame_time"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["ray_time"] = benchmark::Counter(double(state.iterations()) * rays,
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["Mrays_per_s"] = benchmark::Counter(double(state.iterations()) * rays * 1e-6, benchmark::Counter::kIsRate);
  state.counters["evals_per_ray"] = evals / rays;
  state.counters["evals_per_sea_ray"] = sea > 0.0 ? sea_evals / sea : 0.0;
  state.counters["sea_fraction"] = sea / rays;
  // The share of the packets' lanes that do work while their packet steps.
  state.counters["lane_use"] = packet_evals > 0.0 ? evals / packet_evals : 0.0;
}

const bool registered = [] {
  benchmark::RegisterBenchmark("surface_finish_frame", bm_finish)->Unit(benchmark::kMillisecond);
  for (houle::Isa isa : houle::supported_isas()) {
    const std::string name(houle::isa_name(isa));
    benchmark::RegisterBenchmark(("surface_fill_gerstner/all/" + name).c_str(), bm_fill, isa, false)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("surface_fill_gerstner/view/" + name).c_str(), bm_fill, isa, true)
        ->Unit(benchmark::kMillisecond);
    for (bool noise : {false, true}) {
      benchmark::RegisterBenchmark(("march_frame/" + std::string(noise ? "noise/" : "grid/") + name).c_str(), bm_march,
                                   isa, noise)
          ->Args({640, 360})
          ->Args({1280, 720})
          ->Unit(benchmark::kMillisecond);
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
