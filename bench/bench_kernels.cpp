// Per-sample kernels on every supported ISA, so one run shows the SIMD speed-up side by side: the
// primary rays' directions, Gerstner height + gradient, capillary noise (height + gradient, and height only) at every
// octave, i.e. the cost of a sample near the camera where the LOD keeps all of them, two of the
// shading's table lookups (the sky along a direction, the water's colour along a path, eq. 12), the
// light of a sea hit seen from above and the light on the sea bed under it, and a moving camera's
// primary rays' floor walk.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/render/sky.hpp"
#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"
#include "floor_hits.hpp"
#include "scene_objects.hpp"
#include "sea_light.hpp"
#include "shadow_mask.hpp"
#include "under_light.hpp"

namespace {

// Items per second, and their inverse in nanoseconds: an inverted rate is seconds per item, so the
// count is given in billions.
void count_samples(benchmark::State& state, std::size_t per_iteration) {
  const double samples = double(state.iterations()) * double(per_iteration);
  state.SetItemsProcessed(static_cast<std::int64_t>(samples));
  state.counters["ns_per_sample"] =
      benchmark::Counter(samples * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// A camera 50 degrees high over the built-in coast's beach, looking out to sea.
houle::CameraParams beach_camera(std::array<float, 3> position, std::array<float, 3> look_at, std::uint32_t width,
                                 std::uint32_t height) {
  houle::CameraParams p;
  p.position = position;
  p.look_at = look_at;
  p.vertical_fov = 0.8726646f;
  p.width = width;
  p.height = height;
  return p;
}

// A 1283-pixel row of a 1283x720 image (an 8k+3 width: the tail is included).
void bm_camera_rows(benchmark::State& state, houle::Isa isa) {
  const houle::CameraParams p = beach_camera({110.0f, 178.0f, 6.0f}, {140.0f, 60.0f, 0.0f}, 1283, 720);
  const houle::Camera camera = houle::make_camera(p).value();
  std::vector<float> dx(p.width), dy(p.width), dz(p.width);
  std::uint32_t row = 0;
  for (auto _ : state) {
    houle::camera_row_rays(isa, camera, row, 0, p.width, 0.5f, 0.5f, dx.data(), dy.data(), dz.data());
    row = row + 1 < p.height ? row + 1 : 0;
    benchmark::DoNotOptimize(dx.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, p.width);
}

// Four trains of a moderate swell and a 1003-point row (an 8k+3 width: the tail is included).
void bm_gerstner(benchmark::State& state, houle::Isa isa) {
  const std::vector<houle::GerstnerWave> waves = {
      {1.0f, 0.2f, 0.157f, 0.8f, 0.5f, 1.24f, 0.0f}, {0.7f, 0.7f, 0.35f, 0.3f, 0.6f, 1.85f, 1.0f},
      {0.9f, -0.4f, 0.78f, 0.1f, 0.6f, 2.77f, 2.0f}, {0.2f, 1.0f, 1.6f, 0.04f, 0.5f, 3.96f, 3.0f}};
  const auto frame = houle::make_gerstner_frame(waves, 12.5);
  const std::size_t n = 1003;
  std::vector<float> x(n), y(n), h(n), gx(n), gy(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> c(-50.0f, 50.0f);
  for (std::size_t i = 0; i < n; ++i) x[i] = c(rng), y[i] = c(rng);
  for (auto _ : state) {
    houle::gerstner_eval(isa, frame.value(), x.data(), y.data(), n, {h.data(), gx.data(), gy.data()});
    benchmark::DoNotOptimize(h.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// The default ripples (6 octaves) at level range(0) on 1003 points within 20 m of the origin.
void bm_capillary(benchmark::State& state, houle::Isa isa, bool gradient) {
  const auto frame = houle::make_capillary_frame(houle::CapillaryParams{}, 12.5);
  const std::size_t n = 1003;
  std::vector<float> x(n), y(n), level(n, float(state.range(0))), h(n), gx(n), gy(n);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> c(-20.0f, 20.0f);
  for (std::size_t i = 0; i < n; ++i) x[i] = c(rng), y[i] = c(rng);
  for (auto _ : state) {
    houle::capillary_eval(isa, frame.value(), x.data(), y.data(), level.data(), n, h.data(),
                          gradient ? gx.data() : nullptr, gradient ? gy.data() : nullptr);
    benchmark::DoNotOptimize(h.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// The sky table at 1003 directions, every azimuth, from the horizon up (reflected rays' spread).
void bm_sky(benchmark::State& state, houle::Isa isa) {
  const auto sky = houle::PreethamSky::make(3.0, {0.3f, -0.5f, 0.81f});
  houle::SkyLut lut;
  lut.bake(sky.value());
  const std::size_t n = 1003;
  std::vector<float> x(n), y(n), z(n), r(n), g(n), b(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const float az = 6.2831853f * u(rng), el = 1.5f * u(rng);
    x[i] = std::cos(az) * std::cos(el), y[i] = std::sin(az) * std::cos(el), z[i] = std::sin(el);
  }
  for (auto _ : state) {
    lut.lookup(isa, x.data(), y.data(), z.data(), n, r.data(), g.data(), b.data());
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// The water colour of 1003 objects of random colours seen through 0 to 20 m of water.
void bm_water_mix(benchmark::State& state, houle::Isa isa) {
  const auto water = houle::WaterColourLut::make(houle::WaterColourParams{});
  const std::size_t n = 1003;
  std::vector<float> r(n), g(n), b(n), d(n), s(n), e(n, 1.0f), out_r(n), out_g(n), out_b(n);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) r[i] = u(rng), g[i] = u(rng), b[i] = u(rng), d[i] = 20.0f * u(rng), s[i] = 5.0f * u(rng);
  for (auto _ : state) {
    water.value().mix(isa, {r.data(), g.data(), b.data(), d.data(), s.data(), e.data()}, n,
                      {out_r.data(), out_g.data(), out_b.data()});
    benchmark::DoNotOptimize(out_r.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// 1003 sea hits seen from above, a third under foam, a fifth whose reflection meets an object, some
// in the glint's lobe.
void bm_sea_light(benchmark::State& state, houle::Isa isa) {
  const houle::detail::SeaLightParams p{{2.0f, 3.0f, 4.0f}, {5.0f, 6.0f, 7.0f}, {0.5f, 0.25f, 0.125f},
                                        {0.8660254f, 0.0f, 0.5f}, 1e-3f};
  const std::size_t n = 1003;
  std::vector<std::vector<float>> f(21, std::vector<float>(n));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    for (auto& v : f) v[i] = u(rng);
    f[0][i] = 1.0f;                           // side: from above
    f[1][i] = 0.02f + 0.3f * u(rng);          // kr
    f[5][i] = i % 5 == 0 ? 1.0f : 0.0f;       // air_hit
    f[12][i] = 1.0f;                          // lit
    f[13][i] = 0.05f * (u(rng) - 0.5f), f[14][i] = 0.05f * (u(rng) - 0.5f), f[15][i] = 1.0f;  // normal
    const float a = 0.2f + 1.0f * u(rng);
    f[16][i] = std::cos(a), f[17][i] = 0.0f, f[18][i] = -std::sin(a);  // the ray, towards the sun
    f[19][i] = i % 3 == 0 ? u(rng) : 0.0f;    // foam
    f[20][i] = 0.005f * u(rng);               // rough
  }
  const houle::detail::SeaLightInput in{f[0].data(),  f[1].data(),  f[2].data(),  f[3].data(),  f[4].data(),
                                        f[5].data(),  f[6].data(),  f[7].data(),  f[8].data(),  f[9].data(),
                                        f[10].data(), f[11].data(), f[12].data(), f[13].data(), f[14].data(),
                                        f[15].data(), f[16].data(), f[17].data(), f[18].data(), f[20].data(),
                                        f[19].data()};
  std::vector<float> r(n), g(n), b(n), lobe(n);
  for (auto _ : state) {
    houle::detail::sea_light(isa, p, in, n, {r.data(), g.data(), b.data(), lobe.data()});
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// 1003 sea hits seen from above over 30 m of water beside a 20 m wall, 6 in 7 of whose rays into the
// water meet the sea bed 1-8 m down: the masks are asked everywhere, a few lanes are left open.
void bm_under_light(benchmark::State& state, houle::Isa isa) {
  const std::vector<houle::RenderBox> wall{{{0.0f, 0.0f, 0.5f}, {10.0f, 1.0f, 1.5f}}};
  const std::array<float, 3> sun{-0.6f, 0.0f, 0.8f}, sun_water{-0.45f, 0.0f, 0.893f};
  const auto sun_mask = houle::detail::ShadowMask::build(wall, {}, sun);
  const auto water_mask = houle::detail::ShadowMask::build(wall, {}, sun_water);
  const houle::detail::UnderLightParams p{{0.2f, 0.3f, 0.4f}, {0.9f, 0.85f, 0.7f}, {sun_water[0], sun_water[1], sun_water[2]},
                                          {sun[0], sun[1], sun[2]}, 2.0f, true, sun_mask.view(), water_mask.view()};
  const std::size_t n = 1003;
  std::vector<std::vector<float>> f(19, std::vector<float>(n));
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    for (auto& v : f) v[i] = u(rng);
    f[0][i] = 1.0f;                                                        // side: from above
    f[1][i] = 30.0f * u(rng) - 15.0f, f[2][i] = 30.0f * u(rng) - 15.0f;  // the sea hit
    f[3][i] = 0.3f * (u(rng) - 0.5f);
    f[4][i] = 0.05f * (u(rng) - 0.5f), f[5][i] = 0.05f * (u(rng) - 0.5f), f[6][i] = 1.0f;  // its normal
    f[7][i] = 50.0f * u(rng);                                              // t
    f[8][i] = i % 7 == 3 ? 0.0f : 1.0f;                                    // met
    f[9][i] = 0.3f * (u(rng) - 0.5f), f[10][i] = 0.3f * (u(rng) - 0.5f), f[11][i] = -0.95f;  // refracted
    f[12][i] = 1.0f + 7.0f * u(rng);                                       // hit_t
    f[13][i] = 0.1f * (u(rng) - 0.5f), f[14][i] = 0.1f * (u(rng) - 0.5f), f[15][i] = 1.0f;  // the bed's normal
  }
  const houle::detail::UnderLightInput in{f[0].data(),  f[1].data(),  f[2].data(),  f[3].data(),  f[4].data(),
                                          f[5].data(),  f[6].data(),  f[7].data(),  f[8].data(),  f[9].data(),
                                          f[10].data(), f[11].data(), f[12].data(), f[13].data(), f[14].data(),
                                          f[15].data(), f[16].data(), f[17].data(), f[18].data()};
  std::vector<float> lit(n), ask(n), r(n), g(n), b(n), path(n);
  for (auto _ : state) {
    houle::detail::under_light(isa, p, in, n, {lit.data(), ask.data(), r.data(), g.data(), b.data(), path.data()});
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  count_samples(state, n);
}

// The primary rays of the fly-along's camera at 4 s (scenes/coast_flyby.toml) over the built-in
// coast, 640x360, those that go down (the renderer sends the others from above the scene through no
// packet): their floor hits and object-bounds tests a row at a time, as a moving camera's intersect
// stage finds them (docs/rendering.md 2.4), each down to 1.3 m under the still water (about the
// coast's cut). Per ray.
void bm_primary_floor(benchmark::State& state, houle::Isa isa) {
  static const houle::detail::SceneObjects objects =
      houle::detail::SceneObjects::build(houle::make_render_scene(houle::builtin_coast())).value();
  const houle::CameraParams p = beach_camera({90.0f, 176.0f, 7.0f}, {135.0f, 60.0f, 0.0f}, 640, 360);
  const houle::Camera camera = houle::make_camera(p).value();
  constexpr float cut = -1.3f;
  struct Row {
    std::vector<float> ox, oy, oz, dx, dy, dz, t_max;
  };
  std::vector<Row> rows(p.height);
  std::vector<float> dx(p.width), dy(p.width), dz(p.width);
  std::size_t rays = 0;
  for (std::uint32_t r = 0; r < p.height; ++r) {
    houle::camera_row_rays(camera, r, 0, p.width, 0.5f, 0.5f, dx.data(), dy.data(), dz.data());
    for (std::uint32_t i = 0; i < p.width; ++i) {
      if (!(dz[i] < 0.0f)) continue;
      Row& w = rows[r];
      w.ox.push_back(p.position[0]), w.oy.push_back(p.position[1]), w.oz.push_back(p.position[2]);
      w.dx.push_back(dx[i]), w.dy.push_back(dy[i]), w.dz.push_back(dz[i]);
      w.t_max.push_back((cut - p.position[2]) / dz[i]);
      ++rays;
    }
  }
  std::vector<float> out[6];
  for (std::vector<float>& o : out) o.resize(p.width);
  const houle::detail::FloorGridView grid = objects.floor_grid();
  const houle::detail::ObjectBounds bounds = objects.object_bounds();
  for (auto _ : state) {
    for (const Row& w : rows) {
      const houle::detail::FloorRays in{w.ox.data(), w.oy.data(), w.oz.data(), w.dx.data(),
                                        w.dy.data(), w.dz.data(), w.t_max.data()};
      houle::detail::floor_hits(isa, grid, bounds, in, w.ox.size(),
                                {out[0].data(), out[1].data(), out[2].data(), out[3].data(), out[4].data(), out[5].data()});
    }
    benchmark::DoNotOptimize(out[0].data());
    benchmark::ClobberMemory();
  }
  count_samples(state, rays);
}

const bool registered = [] {
  for (houle::Isa isa : houle::supported_isas()) {
    const std::string name(houle::isa_name(isa));
    benchmark::RegisterBenchmark(("camera_row_rays/" + name).c_str(), bm_camera_rows, isa);
    benchmark::RegisterBenchmark(("gerstner_eval/" + name).c_str(), bm_gerstner, isa);
    benchmark::RegisterBenchmark(("capillary_eval/gradient/" + name).c_str(), bm_capillary, isa, true)
        ->ArgName("level")
        ->Arg(3)
        ->Arg(6);
    benchmark::RegisterBenchmark(("capillary_eval/height/" + name).c_str(), bm_capillary, isa, false)
        ->ArgName("level")
        ->Arg(6);
    benchmark::RegisterBenchmark(("sky_lookup/" + name).c_str(), bm_sky, isa);
    benchmark::RegisterBenchmark(("water_mix/" + name).c_str(), bm_water_mix, isa);
    benchmark::RegisterBenchmark(("sea_light/" + name).c_str(), bm_sea_light, isa);
    benchmark::RegisterBenchmark(("under_light/" + name).c_str(), bm_under_light, isa);
    benchmark::RegisterBenchmark(("floor_hits/primary/" + name).c_str(), bm_primary_floor, isa)
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
