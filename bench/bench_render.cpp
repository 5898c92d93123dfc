// Whole frames of the renderer (renderer.hpp) at 640x360 and 1280x720: a Gerstner sea with capillary
// noise, a sloping beach with a box and a sphere on it, on the active ISA, with 1 and 2 threads.
// Counters give the per-stage times of the last frame's FrameTimes (averaged over the iterations),
// per sample (primary ray) for marching and shading, and rays per second. The renderer uses the
// dispatched ISA; the scalar path is the same program under HOULE_ISA=scalar (a ctest entry too).
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/render/renderer.hpp"
#include "houle/surface/surface_frame.hpp"
#include "coastal_waves.hpp"

namespace {

using houle::test::coastal_waves;

/// A beach: 400 m x 400 m at 2 m, the floor rising northwards from -12 m to +3 m (land beyond
/// y = 150 m), a box and a sphere at the water line; the sun 35 degrees up in the south-west.
houle::RenderScene coast() {
  houle::RenderScene s;
  houle::FloorGrid& f = s.floor;
  f.origin_x = -200.0f;
  f.origin_y = -100.0f;
  f.cell = 2.0f;
  f.nx = f.ny = 201;
  for (std::uint32_t j = 0; j < f.ny; ++j) {
    for (std::uint32_t i = 0; i < f.nx; ++i) {
      const float y = f.origin_y + f.cell * float(j), x = f.origin_x + f.cell * float(i);
      f.z.push_back(std::min(3.0f, -12.0f + 0.06f * (y + 100.0f) + 0.5f * std::sin(0.05f * x)));
    }
  }
  s.boxes.push_back({{-15.0f, 60.0f, 1.0f}, {4.0f, 2.0f, 3.0f}, 0.4f, {0.6f, 0.55f, 0.5f}});
  s.spheres.push_back({{12.0f, 45.0f, 0.0f}, 2.5f, {0.7f, 0.2f, 0.15f}});
  s.sun_direction = {-0.5f, -0.6f, 0.57f};
  return s;
}

struct BenchFrame {
  houle::SurfaceFrame surface;
  houle::CapillaryFrame noise;
};

BenchFrame& frame() {
  static BenchFrame* f = [] {
    auto s = houle::SurfaceFrame::create({});
    auto w = houle::make_gerstner_frame(coastal_waves(), 12.5);
    auto n = houle::make_capillary_frame(houle::CapillaryParams{}, 12.5);
    auto* b = new BenchFrame{std::move(s.value()), n.value()};
    b->surface.begin_frame(0.0f, 0.0f);
    houle::fill_gerstner(b->surface, w.value());
    return b;
  }();
  return *f;
}

void bm_render(benchmark::State& state) {
  const auto width = std::uint32_t(state.range(0)), height = std::uint32_t(state.range(1));
  const auto threads = unsigned(state.range(2));
  const int spp = int(state.range(3));
  BenchFrame& f = frame();
  houle::CameraParams cp;
  cp.position = {0.0f, 0.0f, 5.0f};
  cp.look_at = {0.0f, 100.0f, 5.0f - 100.0f * std::tan(8.0f * 0.017453292f)};
  cp.width = width;
  cp.height = height;
  const houle::Camera cam = houle::make_camera(cp).value();
  houle::RenderQuality q;
  q.samples_per_pixel = spp;
  auto r = houle::Renderer::create(coast(), width, height, q, threads);
  if (!r) {
    state.SkipWithError(r.error().message.c_str());
    return;
  }
  houle::Framebuffer fb(static_cast<int>(width), static_cast<int>(height));
  double march = 0.0, intersect = 0.0, shade = 0.0, total = 0.0;
  for (auto _ : state) {
    r->render(f.surface, &f.noise, nullptr, cam, fb);
    const houle::FrameTimes& t = r->last_times();
    march += t.march_ms;
    intersect += t.intersect_ms;
    shade += t.shade_ms;
    total += t.total_ms;
    benchmark::ClobberMemory();
  }
  const double n = double(state.iterations());
  const houle::RenderCounters& c = r->last_counters();
  const double samples = double(width) * height * spp;
  state.counters["march_ms"] = march / n;
  state.counters["intersect_ms"] = intersect / n;
  state.counters["shade_ms"] = shade / n;
  state.counters["total_ms"] = total / n;
  // Stage times are thread time / threads: per sample they are wall ns at this thread count.
  state.counters["march_ns_per_ray"] = march / n * 1e6 / samples;
  state.counters["shade_ns_per_sample"] = shade / n * 1e6 / samples;
  state.counters["rays_per_s"] = benchmark::Counter(n * samples, benchmark::Counter::kIsRate);
  state.counters["sea_fraction"] = double(c.sea) / samples;
  state.counters["object_fraction"] = double(c.object) / samples;
  state.counters["nonfinite"] = double(c.nonfinite);
  state.SetLabel(std::string(houle::isa_name(houle::active_isa())));
}

const bool registered = [] {
  for (auto size : {std::array<long, 2>{640, 360}, std::array<long, 2>{1280, 720}}) {
    for (long threads : {1, 2}) {
      benchmark::RegisterBenchmark("render_frame", bm_render)
          ->Args({size[0], size[1], threads, 1})
          ->ArgNames({"w", "h", "threads", "spp"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
