// The renderer (renderer.hpp) on small images: determinism across thread counts and frame histories,
// the allocation-free frame loop, finite output in hard cases, and plausibility of the picture
// (sky, sea, Fresnel, sunlit faces, glint). Plus the exact ray queries of scene_objects.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "allocation_counter.hpp"
#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/render/colour.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/render/renderer.hpp"
#include "houle/surface/surface_frame.hpp"
#include "scene_objects.hpp"
#include "shadow_mask.hpp"

namespace {

using houle::Camera;
using houle::Framebuffer;
using houle::LinearRgb;
using houle::RenderQuality;
using houle::Renderer;
using houle::RenderScene;
using houle::RenderView;

constexpr std::uint32_t W = 64, H = 36;

std::vector<houle::GerstnerWave> two_trains() {
  const auto wave = [](float dx, float dy, float length, float amp, float q, float phase) {
    const float k = 2.0f * 3.14159265f / length;
    return houle::GerstnerWave{dx, dy, k, amp, q, std::sqrt(9.81f * k), phase};
  };
  return {wave(0.3f, 1.0f, 20.0f, 0.3f, 0.5f, 0.0f), wave(1.0f, 0.2f, 7.0f, 0.1f, 0.4f, 1.0f)};
}

houle::SurfaceFrameConfig small_frame_config() {
  houle::SurfaceFrameConfig c;
  c.levels = 6;
  c.cells = 64;
  c.tile_cells = 8;
  c.finest_cell = 0.25f;
  return c;
}

/// A frame of the two trains at time t, centred under (cx, cy). Nearly flat when `flat`: one 1 mm,
/// 50 m swell (slopes below 1.3e-4; StillWaterIsAMirrorWithAWaterline has the perfectly flat sea).
houle::SurfaceFrame make_surface(double t, float cx = 0.0f, float cy = 0.0f, bool flat = false) {
  auto f = houle::SurfaceFrame::create(small_frame_config());
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().field + ": " + f.error().message);
  const auto waves = flat ? std::vector<houle::GerstnerWave>{{1.0f, 0.0f, 2.0f * 3.14159265f / 50.0f, 1e-3f, 0.0f, 1.1f, 0.0f}}
                          : two_trains();
  auto g = houle::make_gerstner_frame(waves, t);
  EXPECT_TRUE(g.ok());
  f->begin_frame(cx, cy);
  houle::fill_gerstner(f.value(), g.value());
  return std::move(f.value());
}

/// The still sea, z = 0 everywhere (no trains, no ripples), centred under (cx, cy).
houle::SurfaceFrame still_surface(float cx = 0.0f, float cy = 0.0f) {
  auto f = houle::SurfaceFrame::create(small_frame_config());
  EXPECT_TRUE(f.ok());
  auto still = houle::make_gerstner_frame({}, 0.0);
  EXPECT_TRUE(still.ok());
  f->begin_frame(cx, cy);
  houle::fill_gerstner(f.value(), still.value());
  return std::move(f.value());
}

houle::CapillaryFrame make_noise(double t) {
  auto n = houle::make_capillary_frame(houle::CapillaryParams{}, t);
  EXPECT_TRUE(n.ok());
  return n.value();
}

Camera make_cam(std::array<float, 3> pos, std::array<float, 3> at, std::uint32_t w = W, std::uint32_t h = H,
                std::array<float, 3> up = {0.0f, 0.0f, 1.0f}) {
  houle::CameraParams p;
  p.position = pos;
  p.look_at = at;
  p.up = up;
  p.width = w;
  p.height = h;
  auto c = houle::make_camera(p);
  EXPECT_TRUE(c.ok());
  return c.value();
}

/// 4 m above the sea looking north, 4 degrees down.
Camera default_cam(std::uint32_t w = W, std::uint32_t h = H) {
  return make_cam({0.0f, 0.0f, 4.0f}, {0.0f, 60.0f, 4.0f - 60.0f * std::tan(4.0f * 0.0174533f)}, w, h);
}

/// Flat floor at z = -5 (40 x 40 cells of 5 m), a box on the left, a sphere on the right; the sun in
/// the south-east, behind the camera's right shoulder (its glint is outside the view).
RenderScene test_scene() {
  RenderScene s;
  s.floor.origin_x = -100.0f;
  s.floor.origin_y = -50.0f;
  s.floor.cell = 5.0f;
  s.floor.nx = s.floor.ny = 41;
  s.floor.z.assign(41 * 41, -5.0f);
  s.boxes.push_back({{-12.0f, 20.0f, 1.0f}, {2.0f, 2.0f, 2.0f}, 0.0f, {0.8f, 0.3f, 0.2f}});
  s.spheres.push_back({{5.0f, 20.0f, 0.5f}, 1.5f, {0.3f, 0.6f, 0.3f}});
  s.sun_direction = {0.8f, -0.4f, 0.45f};
  return s;
}

Renderer make_renderer(const RenderScene& scene, std::uint32_t w, std::uint32_t h, const RenderQuality& q,
                       unsigned threads) {
  auto r = Renderer::create(scene, w, h, q, threads);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().field + ": " + r.error().message);
  return std::move(r.value());
}

bool same_bytes(const Framebuffer& a, const Framebuffer& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

LinearRgb pixel(const Framebuffer& fb, int x, int y) {
  const float* p = &fb.rgb[(std::size_t(y) * std::size_t(fb.width) + std::size_t(x)) * 3];
  return {p[0], p[1], p[2]};
}

std::size_t count_nonfinite(const Framebuffer& fb) {
  return std::size_t(std::count_if(fb.rgb.begin(), fb.rgb.end(), [](float v) { return !std::isfinite(v); }));
}

/// Image position (pixel units) of world point p.
std::array<float, 2> project(const Camera& c, std::array<float, 3> p) {
  const float d[3] = {p[0] - c.position[0], p[1] - c.position[1], p[2] - c.position[2]};
  const auto dot = [&](const std::array<float, 3>& v) { return d[0] * v[0] + d[1] * v[1] + d[2] * v[2]; };
  const float f = dot(c.forward);
  return {dot(c.right) / f / c.pixel_scale + 0.5f * float(c.width), 0.5f * float(c.height) - dot(c.up) / f / c.pixel_scale};
}

// ---- Determinism and the frame loop --------------------------------------------------------------

TEST(Renderer, IdenticalBytesForOneAndTwoThreads) {
  const RenderScene scene = test_scene();
  RenderQuality q;
  q.samples_per_pixel = 4;
  const houle::SurfaceFrame surface = make_surface(3.0);
  const houle::CapillaryFrame noise = make_noise(3.0);
  const Camera cam = default_cam();
  Renderer one = make_renderer(scene, W, H, q, 1);
  Renderer two = make_renderer(scene, W, H, q, 2);
  EXPECT_EQ(two.threads(), 2u);
  Framebuffer a(W, H), b(W, H);
  one.render(surface, &noise, nullptr, cam, a);
  two.render(surface, &noise, nullptr, cam, b);
  EXPECT_TRUE(same_bytes(a, b));
  EXPECT_EQ(one.last_counters().sea, two.last_counters().sea);
  EXPECT_GT(one.last_counters().sea, 0u);
  EXPECT_GT(one.last_counters().object, 0u);
  EXPECT_GT(one.last_counters().sky, 0u);
  EXPECT_EQ(one.last_counters().sea + one.last_counters().object + one.last_counters().sky, std::uint64_t(W) * H * 4);
}

TEST(Renderer, NoStateCarriedBetweenFrames) {
  const RenderScene scene = test_scene();
  const RenderQuality q;
  const Camera cam = default_cam();
  Renderer fresh = make_renderer(scene, W, H, q, 2);
  Renderer used = make_renderer(scene, W, H, q, 2);
  Framebuffer alone(W, H), after(W, H);
  for (double t : {1.0, 2.0, 7.5}) {
    const houle::SurfaceFrame s = make_surface(t, float(t), 0.0f);
    const houle::CapillaryFrame n = make_noise(t);
    const Camera other = make_cam({float(t), 0.0f, 3.0f}, {0.0f, 50.0f, 0.0f});
    used.render(s, &n, nullptr, other, after);
  }
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  fresh.render(s, &n, nullptr, cam, alone);
  used.render(s, &n, nullptr, cam, after);
  EXPECT_TRUE(same_bytes(alone, after));
}

TEST(Renderer, StillCameraReusesPrimaryHitsAndChangesNoByte) {
  // A beach rising out of the sea ahead: primary rays meet the floor above the sea's slab, whose
  // bottom would move with the waves. With the scene's bound of the sea's height the cut stays put and
  // a still camera keeps every primary hit from frame to frame; without it, or with a bound the frame
  // exceeds, the cut follows each frame's slab and the hits are found again whenever it moves. Either
  // way every frame has the bytes of a fresh renderer's, also after the camera moved and came back.
  RenderScene scene = test_scene();
  for (std::uint32_t j = 0; j < scene.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < scene.floor.nx; ++i) {
      scene.floor.z[j * scene.floor.nx + i] = -3.0f + 0.06f * float(j) * 5.0f - 0.8f * std::sin(0.7f * float(i));
    }
  }
  RenderScene bounded = scene, exceeded = scene;
  bounded.sea_height_bound = 0.4f;  // two_trains' amplitudes
  exceeded.sea_height_bound = 0.1f;
  RenderQuality q;
  q.samples_per_pixel = 4;
  const Camera cam = default_cam();
  const Camera other = make_cam({1.0f, 0.0f, 3.0f}, {0.0f, 50.0f, 0.0f});
  Renderer kept_bounded = make_renderer(bounded, W, H, q, 2), kept_unbounded = make_renderer(scene, W, H, q, 2);
  Renderer kept_exceeded = make_renderer(exceeded, W, H, q, 2);
  Framebuffer kept(W, H), alone(W, H);
  const double times[] = {1.0, 1.1, 1.1, 1.1, 1.2, 4.0, 1.15, 2.5, 2.6, 0.3};
  for (std::size_t frame = 0; frame < std::size(times); ++frame) {
    const double t = times[frame];
    const houle::SurfaceFrame s = make_surface(t, 0.0f, 0.0f, frame == 5);  // a flat sea: its slab moves up
    const houle::CapillaryFrame n = make_noise(t);
    const Camera& c = frame == 7 ? other : cam;
    for (const RenderScene* sc : {&bounded, &scene, &exceeded}) {
      Renderer& used = sc == &bounded ? kept_bounded : sc == &scene ? kept_unbounded : kept_exceeded;
      used.render(s, &n, nullptr, c, kept);
      Renderer fresh = make_renderer(*sc, W, H, q, 1);
      fresh.render(s, &n, nullptr, c, alone);
      EXPECT_TRUE(same_bytes(kept, alone)) << "t " << t << " bound " << sc->sea_height_bound;
      // A kept colour counts as the sky or an object as the hit it was kept with (its flags).
      const houle::RenderCounters &k = used.last_counters(), &f = fresh.last_counters();
      EXPECT_EQ(k.sea, f.sea) << "t " << t << " bound " << sc->sea_height_bound;
      EXPECT_EQ(k.object, f.object) << "t " << t << " bound " << sc->sea_height_bound;
      EXPECT_EQ(k.sky, f.sky) << "t " << t << " bound " << sc->sea_height_bound;
    }
    const houle::RenderCounters& b = kept_bounded.last_counters();
    const std::uint64_t samples = b.sea + b.object + b.sky;
    // A moving camera keeps nothing (the first frame, the camera away and back); the hits and the
    // colours off the sea are written in the camera's second still frame (1, and 9 after the move) and
    // read from its third.
    const bool reads = frame >= 2 && frame <= 6;
    EXPECT_EQ(b.reused, reads ? samples : 0u) << "t " << t;
    // In the repeats of the second frame's time every sample that is not sea (the sky, the beach) takes
    // its kept colour; later, all but those the waves have just left, which are shaded and kept then.
    if (frame == 2 || frame == 3) {
      EXPECT_EQ(b.kept_colour, b.object + b.sky) << "t " << t;
    } else if (reads) {
      EXPECT_GT(b.kept_colour, (b.object + b.sky) * 9 / 10) << "t " << t;
      EXPECT_LE(b.kept_colour, b.object + b.sky) << "t " << t;
    } else {
      EXPECT_EQ(b.kept_colour, 0u) << "t " << t;
    }
    // Unbounded or exceeded, the cut follows the frame's slab: only the repeats of a time have the cut
    // of the frame before, and only the second repeat reads what the first wrote.
    EXPECT_EQ(kept_unbounded.last_counters().reused, frame == 3 ? samples : 0u) << "t " << t;
    EXPECT_EQ(kept_exceeded.last_counters().reused, frame == 3 ? samples : 0u) << "t " << t;
  }
}

TEST(Renderer, NoHeapAllocationInRender) {
  const RenderScene scene = test_scene();
  RenderQuality q;
  q.samples_per_pixel = 4;
  Renderer r = make_renderer(scene, W, H, q, 2);
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  const Camera cam = default_cam();
  const Camera under = make_cam({0.0f, 0.0f, -2.0f}, {0.0f, 30.0f, 2.0f});
  Framebuffer fb(W, H);
  r.render(s, &n, nullptr, cam, fb);
  long allocations = 0;
  {
    houle::test::AllocationCounter counter;
    r.render(s, &n, nullptr, cam, fb);
    r.render(s, nullptr, nullptr, under, fb);
    r.render(s, &n, nullptr, cam, fb, RenderView::sea_reflectance);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
}

TEST(Renderer, AovsChangeNoPixelAndAllocateNothing) {
  const RenderScene scene = test_scene();
  RenderQuality q;
  q.samples_per_pixel = 4;
  Renderer r = make_renderer(scene, W, H, q, 2);
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  const Camera cam = default_cam();
  Framebuffer plain(W, H), with(W, H, {true, true, true, true});
  r.render(s, &n, nullptr, cam, plain);
  r.render(s, &n, nullptr, cam, with);
  EXPECT_TRUE(same_bytes(plain, with));
  long allocations = 0;
  {
    houle::test::AllocationCounter counter;
    r.render(s, &n, nullptr, cam, with);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  // Four samples a pixel: the shares are quarters, and the picture has pixels of each kind.
  for (const std::vector<float>* v : {&with.alpha, &with.sea}) {
    EXPECT_TRUE(std::all_of(v->begin(), v->end(), [](float x) { return x == std::round(4.0f * x) / 4.0f && x >= 0.0f && x <= 1.0f; }));
  }
  EXPECT_TRUE(std::count(with.alpha.begin(), with.alpha.end(), 0.0f) > 0 && std::count(with.sea.begin(), with.sea.end(), 1.0f) > 0);
}

TEST(Renderer, AovsOfAFlatSeaAndItsObjects) {
  // The sea at z = 0 (within 1 mm): a sea pixel's depth is that of the plane along its ray, its normal
  // is up; an object pixel's depth puts its point on the box's or the sphere's surface; the sky has
  // no surface. One sample a pixel, at its centre.
  const RenderScene scene = test_scene();
  Renderer r = make_renderer(scene, W, H, {}, 2);
  const houle::SurfaceFrame s = make_surface(0.0, 0.0f, 0.0f, true);
  const Camera cam = default_cam();
  Framebuffer fb(W, H, {true, true, true, true});
  r.render(s, nullptr, nullptr, cam, fb);
  int sea = 0, object = 0, sky = 0, marcher_misses = 0;
  for (std::uint32_t y = 0; y < H; ++y) {
    for (std::uint32_t x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      const std::array<float, 3> d = houle::camera_ray(cam, float(x) + 0.5f, float(y) + 0.5f);
      const float along = d[0] * cam.forward[0] + d[1] * cam.forward[1] + d[2] * cam.forward[2];
      const float depth = fb.depth[i], *n = &fb.normal[3 * i];
      if (fb.sea[i] == 1.0f) {
        ++sea;
        const float plane = cam.position[2] / -d[2] * along;
        EXPECT_NEAR(depth, plane, 1e-4f * plane + 2e-3f / -d[2]) << x << ", " << y;
        EXPECT_NEAR(n[2], 1.0f, 1e-6f);
        EXPECT_EQ(fb.alpha[i], 1.0f);
      } else if (fb.alpha[i] == 1.0f) {
        ++object;
        const float t = depth / along;
        const std::array<float, 3> p{cam.position[0] + t * d[0], cam.position[1] + t * d[1], cam.position[2] + t * d[2]};
        const float to_sphere = std::hypot(p[0] - 5.0f, p[1] - 20.0f, p[2] - 0.5f) - 1.5f;
        const float to_box = std::max({std::abs(p[0] + 12.0f), std::abs(p[1] - 20.0f), std::abs(p[2] - 1.0f)}) - 2.0f;
        EXPECT_LT(std::min(std::abs(to_sphere), std::abs(to_box)), 1e-3f) << x << ", " << y;
        EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-4f);  // a sphere's (p - c) / r in float
        EXPECT_LT(n[0] * d[0] + n[1] * d[1] + n[2] * d[2], 0.0f);  // facing the camera
      } else {
        ++sky;
        EXPECT_EQ(fb.alpha[i], 0.0f);
        EXPECT_EQ(depth, std::numeric_limits<float>::infinity());
        EXPECT_TRUE(n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f);
        // Above the horizon; below it only where the marcher itself finds no crossing (it can miss a
        // ray that meets the 1 mm swell near a crest's top, and the picture then shows the sky too).
        if (d[2] <= 0.0f) {
          houle::MarchParams mp;
          mp.pixel_angle = cam.pixel_angle;
          float t, hx, hy, hz, gx, gy;
          houle::MarchStatus st;
          houle::march_camera_row(s, cam, mp, y, x, 1, 0.5f, 0.5f, {&t, &hx, &hy, &hz, &gx, &gy, &st});
          EXPECT_EQ(st, houle::MarchStatus::miss) << x << ", " << y;
          ++marcher_misses;
        }
      }
    }
  }
  EXPECT_GT(sea, 0);
  EXPECT_GT(object, 0);
  EXPECT_GT(sky, 0);
  EXPECT_LE(marcher_misses, 2);
  // Under water the water itself is what the camera sees: every sample is covered.
  const Camera under = make_cam({0.0f, 0.0f, -2.0f}, {0.0f, 30.0f, 2.0f});
  r.render(s, nullptr, nullptr, under, fb);
  EXPECT_TRUE(std::all_of(fb.alpha.begin(), fb.alpha.end(), [](float a) { return a == 1.0f; }));
}

// A release build's fallback for a wrong call; with HOULE_ASSERTS the call aborts (test_contracts.cpp).
#if !defined(HOULE_ENABLE_ASSERTS)
TEST(Renderer, MismatchedSizesWriteNothing) {
  Renderer r = make_renderer(test_scene(), W, H, {}, 1);
  const houle::SurfaceFrame s = make_surface(3.0);
  Framebuffer wrong(W + 1, H);
  r.render(s, nullptr, nullptr, default_cam(), wrong);
  EXPECT_TRUE(std::all_of(wrong.rgb.begin(), wrong.rgb.end(), [](float v) { return v == 0.0f; }));
  Framebuffer fb(W, H);
  r.render(s, nullptr, nullptr, default_cam(W, H + 2), fb);
  EXPECT_TRUE(std::all_of(fb.rgb.begin(), fb.rgb.end(), [](float v) { return v == 0.0f; }));
}
#endif

// ---- Finite output in hard cases -----------------------------------------------------------------

TEST(Renderer, FiniteEverywhereInHardViews) {
  RenderScene scene = test_scene();
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  struct View {
    std::array<float, 3> pos, at, up;
  };
  const View views[] = {
      {{0.0f, 0.0f, 4.0f}, {0.0f, 60.0f, 3.9f}, {0.0f, 0.0f, 1.0f}},     // grazing, horizon in the middle
      {{0.0f, 0.0f, 10.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},     // straight down
      {{0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 50.0f}, {0.0f, 1.0f, 0.0f}},     // straight up
      {{0.0f, 0.0f, -2.0f}, {0.0f, 30.0f, 2.0f}, {0.0f, 0.0f, 1.0f}},    // under water, up at the surface
      {{0.0f, 0.0f, -2.0f}, {0.0f, 0.0f, 10.0f}, {0.0f, 1.0f, 0.0f}},    // under water, straight up
      {{0.0f, 0.0f, -4.9f}, {0.0f, 30.0f, -6.0f}, {0.0f, 0.0f, 1.0f}},   // just above the floor
      {{-12.0f, 20.0f, 1.0f}, {0.0f, 50.0f, 0.0f}, {0.0f, 0.0f, 1.0f}},  // inside the box
      {{0.0f, 0.0f, 0.01f}, {0.0f, 60.0f, 0.01f}, {0.0f, 0.0f, 1.0f}},   // at the water line
  };
  for (bool spectral : {true, false}) {
    for (float sun_z : {0.45f, 0.02f, -0.2f}) {
      scene.sun_direction = {0.0f, 0.9f, sun_z};  // ahead: glint in view
      RenderQuality q;
      q.spectral_absorption = spectral;
      q.samples_per_pixel = 8;
      Renderer r = make_renderer(scene, 32, 18, q, 2);
      for (const View& v : views) {
        const Camera cam = make_cam(v.pos, v.at, 32, 18, v.up);
        Framebuffer fb(32, 18);
        r.render(s, &n, nullptr, cam, fb);
        EXPECT_EQ(count_nonfinite(fb), 0u);
        EXPECT_EQ(r.last_counters().nonfinite, 0u);
        EXPECT_TRUE(std::all_of(fb.rgb.begin(), fb.rgb.end(), [](float x) { return x >= 0.0f; }));
      }
    }
  }
}

// ---- The picture --------------------------------------------------------------------------------

TEST(Renderer, FillSurfaceOnItsThreadsEqualsTheOnePieceFill) {
  // The per-frame retessellation on the renderer's threads (fill, morph and tile bounds in parts):
  // the very frame SurfaceFrame::fill gives, restricted to a view or not. (Under ThreadSanitizer:
  // the parts share no mutable state.)
  Renderer r = make_renderer(test_scene(), W, H, {}, 3);
  auto g = houle::make_gerstner_frame(two_trains(), 1.7);
  ASSERT_TRUE(g.ok());
  const auto sampler = [](void* c, const houle::SurfaceSamples& s) noexcept {
    houle::gerstner_eval(*static_cast<const houle::GerstnerFrame*>(c), s.x, s.y, s.n, {s.height, s.grad_x, s.grad_y});
    std::fill(s.slope_variance, s.slope_variance + s.n, 0.0f);
  };
  for (bool restricted : {false, true}) {
    auto a = houle::SurfaceFrame::create(small_frame_config()), b = houle::SurfaceFrame::create(small_frame_config());
    ASSERT_TRUE(a.ok() && b.ok());
    for (houle::SurfaceFrame* f : {&a.value(), &b.value()}) {
      f->begin_frame(3.0f, -2.0f);
      if (restricted) f->restrict_to_view(default_cam());
    }
    a->fill(sampler, &g.value());
    r.fill_surface(b.value(), sampler, &g.value());
    const houle::SurfaceFrameConfig& c = a->config();
    const std::size_t floats = (c.cells + 1) * a->stride();
    for (std::uint32_t l = 0; l < c.levels; ++l) {
      ASSERT_EQ(std::memcmp(a->heights(l), b->heights(l), floats * sizeof(float)), 0) << "level " << l;
      ASSERT_EQ(std::memcmp(a->grad_x(l), b->grad_x(l), floats * sizeof(float)), 0) << "level " << l;
      ASSERT_EQ(std::memcmp(a->grad_y(l), b->grad_y(l), floats * sizeof(float)), 0) << "level " << l;
      for (std::uint32_t j = 0; j < a->tiles_per_side(); ++j) {
        for (std::uint32_t i = 0; i < a->tiles_per_side(); ++i) {
          const houle::TileBounds ta = a->tile(l, i, j), tb = b->tile(l, i, j);
          ASSERT_TRUE(ta.h_min == tb.h_min && ta.h_max == tb.h_max && ta.slope_x == tb.slope_x && ta.slope_y == tb.slope_y)
              << "level " << l << " tile " << i << ", " << j;
        }
      }
    }
    EXPECT_EQ(a->z_min(), b->z_min());
    EXPECT_EQ(a->z_max(), b->z_max());
  }
}

TEST(Renderer, SkyIsBlueAndSeaDarkerThanSky) {
  // Over deep water: the sea's own body colour, not a sandy floor seen through 5 m of clear water.
  RenderScene scene = test_scene();
  std::fill(scene.floor.z.begin(), scene.floor.z.end(), -50.0f);
  Renderer r = make_renderer(scene, W, H, {}, 2);
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  const Camera cam = default_cam();
  Framebuffer fb(W, H), kr(W, H);
  r.render(s, &n, nullptr, cam, fb);
  r.render(s, &n, nullptr, cam, kr, RenderView::sea_reflectance);
  // Rows above the horizon (4 degrees above the centre, ~2 rows) and above every object are sky.
  double sky = 0.0, sea = 0.0;
  int sky_n = 0, sea_n = 0;
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < int(W); ++x) {
      const LinearRgb c = pixel(fb, x, y);
      EXPECT_GT(c.b, c.r) << x << ", " << y;
      sky += houle::luminance(c);
      ++sky_n;
    }
  }
  for (int y = 0; y < int(H); ++y) {
    for (int x = 0; x < int(W); ++x) {
      if (pixel(kr, x, y).r > 0.0f) sea += houle::luminance(pixel(fb, x, y)), ++sea_n;
    }
  }
  ASSERT_GT(sea_n, int(W * H / 3));
  EXPECT_LT(sea / sea_n, 0.8 * sky / sky_n);
  EXPECT_GT(sea / sea_n, 0.0);
}

/// Pixels darker than each of their eight neighbours by more than `margin` of the darkest of them:
/// speckle. A smooth picture has none.
int isolated_dark_pixels(const Framebuffer& fb, float margin) {
  int count = 0;
  for (int y = 1; y + 1 < fb.height; ++y) {
    for (int x = 1; x + 1 < fb.width; ++x) {
      float darkest = std::numeric_limits<float>::infinity();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx != 0 || dy != 0) darkest = std::min(darkest, houle::luminance(pixel(fb, x + dx, y + dy)));
        }
      }
      count += houle::luminance(pixel(fb, x, y)) < (1.0f - margin) * darkest;
    }
  }
  return count;
}

TEST(Renderer, NoSpeckleOverFlatFloors) {
  // Flat sea beds seen through a nearly flat sea from 20 m, looking 15 degrees down: the refracted
  // rays all reach the floor, so the picture is smooth whatever the depth and the sun.
  constexpr std::uint32_t w = 96, h = 54;
  const houle::SurfaceFrame flat = make_surface(0.0, 0.0f, 0.0f, true);
  const Camera cam = make_cam({0.0f, -60.0f, 20.0f}, {0.0f, 15.0f, 0.0f}, w, h);
  for (float depth : {3.0f, 5.0f, 6.0f, 7.0f, 8.0f, 12.0f}) {
    for (float elevation_deg : {10.0f, 30.0f, 60.0f, 89.0f}) {
      RenderScene s;
      s.floor.origin_x = s.floor.origin_y = -100.0f;
      s.floor.cell = 1.0f;
      s.floor.nx = s.floor.ny = 201;
      s.floor.z.assign(201 * 201, -depth);
      const float e = elevation_deg * 0.0174533f;
      s.sun_direction = {0.5f * std::cos(e), 0.866f * std::cos(e), std::sin(e)};
      for (bool spectral : {true, false}) {
        RenderQuality q;
        q.spectral_absorption = spectral;
        Renderer r = make_renderer(s, w, h, q, 2);
        Framebuffer fb(w, h);
        r.render(flat, nullptr, nullptr, cam, fb);
        EXPECT_EQ(isolated_dark_pixels(fb, 0.02f), 0) << depth << " m, sun at " << elevation_deg << " deg, spectral " << spectral;
      }
    }
  }
}

TEST(Renderer, StillWaterIsAMirrorWithAWaterline) {
  // No waves and no ripples: the sea is the plane z = 0, the simplest sea. It must be drawn: the sky
  // mirrored near the horizon, a sphere half under water cut at its waterline (lit red above, seen
  // through the water below), its reflection under the waterline.
  constexpr std::uint32_t w = 96, h = 54;
  const houle::SurfaceFrame surface = still_surface(0.0f, 0.0f);
  RenderScene s;
  s.floor.origin_x = s.floor.origin_y = -100.0f;
  s.floor.cell = 5.0f;
  s.floor.nx = s.floor.ny = 41;
  s.floor.z.assign(41 * 41, -10.0f);
  s.spheres.push_back({{0.0f, 20.0f, -1.0f}, 2.0f, {0.8f, 0.15f, 0.1f}});
  s.sun_direction = {-0.6f, -0.5f, 0.62f};  // behind the camera's left shoulder
  const Camera cam = make_cam({0.0f, 0.0f, 3.0f}, {0.0f, 20.0f, 0.0f}, w, h);
  Renderer r = make_renderer(s, w, h, {}, 2);
  Framebuffer fb(w, h), kr(w, h);
  r.render(surface, nullptr, nullptr, cam, fb);
  const houle::RenderCounters counters = r.last_counters();
  r.render(surface, nullptr, nullptr, cam, kr, RenderView::sea_reflectance);
  // Everything below the horizon but the sphere's cap above the water is sea.
  const int horizon = int(std::lround(project(cam, {0.0f, 1e6f, 0.0f})[1]));
  ASSERT_GT(horizon, 5);
  ASSERT_LT(horizon, int(h) - 20);
  EXPECT_EQ(counters.sea + counters.object + counters.sky, std::uint64_t(w) * h);
  EXPECT_GT(counters.sea, std::uint64_t(w) * std::uint64_t(int(h) - horizon - 1) * 9 / 10);
  EXPECT_GT(counters.object, 0u);
  // The sky's mirror: near the horizon the sea reflects most of the sky (K_r >= 0.5 within 10 degrees
  // of grazing) and adds the sea's own colour, so it is not darker than half the sky it mirrors.
  for (int k = 2; k <= 4; ++k) {
    for (int x : {5, 15, 80, 90}) {
      const float sea = houle::luminance(pixel(fb, x, horizon + k)), sky = houle::luminance(pixel(fb, x, horizon - k));
      EXPECT_GT(pixel(kr, x, horizon + k).r, 0.5f) << x << ", " << k;
      EXPECT_GT(sea, 0.5f * sky) << x << ", " << k;
      EXPECT_LT(sea, 1.2f * sky) << x << ", " << k;
    }
  }
  // The waterline, down the sphere's centre column: the cap above water is the sphere in air (red),
  // then, from the waterline's row, the sea (its K_r > 0), showing the cap's reflection and the
  // sphere under the water.
  const int column = int(w / 2);
  const int top = int(std::lround(project(cam, {0.0f, 20.0f, 1.0f})[1]));
  const int waterline = int(std::lround(project(cam, {0.0f, 20.0f - std::sqrt(3.0f), 0.0f})[1]));
  ASSERT_GT(waterline, top + 2);
  for (int y = top + 1; y < waterline - 1; ++y) {
    EXPECT_EQ(pixel(kr, column, y).r, 0.0f) << y;
    EXPECT_GT(pixel(fb, column, y).r, 2.0f * pixel(fb, column, y).b) << y;
  }
  for (int y = waterline + 1; y < waterline + 4; ++y) EXPECT_GT(pixel(kr, column, y).r, 0.0f) << y;
  // Below the waterline the cap's reflection and the sphere under the water show: the sea there is
  // not the open sea beside it.
  for (int y = waterline + 1; y < waterline + 4; ++y) {
    const LinearRgb under = pixel(fb, column, y), beside = pixel(fb, 5, y);
    EXPECT_GT(std::abs(under.r - beside.r), 0.2f * beside.r) << y;
  }
}

TEST(Renderer, SunBelowTheHorizonGivesTwilightThenNight) {
  // The frame's mean luminance (linear) as the sun goes down: daylight, sunset, twilight falling by
  // about a factor 10 per 2.5 degrees and turning blue, then night. A sun below the horizon lights
  // nothing directly: the box's sunny face is no brighter than its shaded one.
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  const Camera cam = default_cam();
  const auto frame = [&](float elevation_deg) {
    RenderScene scene = test_scene();
    const float e = elevation_deg * 0.0174533f;
    scene.sun_direction = {0.8f * std::cos(e), -0.6f * std::cos(e), std::sin(e)};
    Renderer r = make_renderer(scene, W, H, {}, 1);
    Framebuffer fb(W, H);
    r.render(s, &n, nullptr, cam, fb);
    return fb;
  };
  const auto mean = [](const Framebuffer& fb) {
    double sum = 0.0;
    for (int y = 0; y < fb.height; ++y) {
      for (int x = 0; x < fb.width; ++x) sum += houle::luminance(pixel(fb, x, y));
    }
    return sum / (double(fb.width) * fb.height);
  };
  const double day = mean(frame(35.0f));
  double last = mean(frame(0.0f));
  for (float e : {-1.0f, -2.5f, -5.0f, -7.5f, -10.0f, -20.0f}) {
    const double m = mean(frame(e));
    EXPECT_LT(m, last) << e;  // darker at every step down
    last = m;
  }
  EXPECT_LT(mean(frame(-5.0f)), 0.05 * mean(frame(0.0f)));
  EXPECT_LT(mean(frame(-10.0f)), 1e-3 * day);
  EXPECT_LT(mean(frame(-90.0f)), 1e-3 * day);
  EXPECT_GT(mean(frame(-90.0f)), 0.0);  // night is dark, not black
  // Twilight is blue: the sky's blue over red grows as the sun goes down.
  const LinearRgb sunset = pixel(frame(0.5f), int(W) / 2, 2), dusk = pixel(frame(-6.0f), int(W) / 2, 2);
  EXPECT_GT(dusk.b / dusk.r, 1.5f * sunset.b / sunset.r);
  // No sunlight from below the horizon: a box face turned to the set sun's azimuth is lit like the
  // others, by the sky alone. The box's east face (+x, towards the sun's azimuth) against its south face.
  const Framebuffer night = frame(-8.0f);
  const auto east = project(cam, {-10.0f, 20.0f, 1.0f}), south = project(cam, {-12.0f, 18.0f, 1.0f});
  const LinearRgb e = pixel(night, int(east[0]), int(east[1])), so = pixel(night, int(south[0]), int(south[1]));
  EXPECT_LT(houle::luminance(e), 1.5f * houle::luminance(so));
}

TEST(Renderer, FresnelStraightDownAndGrazing) {
  RenderScene scene = test_scene();
  scene.boxes.clear();
  scene.spheres.clear();
  Renderer r = make_renderer(scene, W, H, {}, 1);
  const houle::SurfaceFrame flat = make_surface(0.0, 0.0f, 0.0f, true);
  // Straight down: K_r = ((1.34 - 1) / (1.34 + 1))^2 = 0.02111 (docs/rendering.md 3.2).
  const Camera down = make_cam({0.0f, 0.0f, 10.0f}, {0.0f, 0.0f, 0.0f}, W, H, {0.0f, 1.0f, 0.0f});
  Framebuffer fb(W, H);
  r.render(flat, nullptr, nullptr, down, fb, RenderView::sea_reflectance);
  EXPECT_NEAR(pixel(fb, W / 2, H / 2).r, 0.02111f, 2e-4f);
  EXPECT_EQ(r.last_counters().sea, std::uint64_t(W) * H);

  // Grazing: 2 m above a flat sea looking at the horizon. Just below it K_r is large and the sea
  // shows the sky it reflects.
  const Camera level = make_cam({0.0f, 0.0f, 2.0f}, {0.0f, 100.0f, 2.0f});
  Framebuffer kr(W, H), img(W, H);
  r.render(flat, nullptr, nullptr, level, kr, RenderView::sea_reflectance);
  r.render(flat, nullptr, nullptr, level, img);
  // The horizon is the centre line (2 m is nothing against the ~0.01 rad/px scale at 100+ m).
  const int below = int(H) / 2 + 1, above = int(H) / 2 - 2;
  ASSERT_EQ(pixel(kr, W / 2, above).r, 0.0f);
  EXPECT_GT(pixel(kr, W / 2, below).r, 0.5f);
  EXPECT_GT(houle::luminance(pixel(img, W / 2, below)), 0.5f * houle::luminance(pixel(img, W / 2, above)));
  // Further down the reflectance falls towards the 2 % of normal incidence.
  EXPECT_LT(pixel(kr, W / 2, H - 1).r, pixel(kr, W / 2, below).r);
}

TEST(Renderer, BoxIsLitOnItsSunnySide) {
  const RenderScene scene = test_scene();
  const std::uint32_t w = 128, h = 72;
  Renderer r = make_renderer(scene, w, h, {}, 2);
  const houle::SurfaceFrame s = make_surface(3.0);
  const Camera cam = default_cam(w, h);
  Framebuffer fb(w, h);
  r.render(s, nullptr, nullptr, cam, fb);
  // The box at (-12, 20, 1), half size 2: its east face (+x) faces the sun (0.8, -0.4, 0.45) at
  // N.L = 0.8, its south face (-y) at 0.4; both are in view.
  const auto east = project(cam, {-10.0f, 20.0f, 1.5f});
  const auto south = project(cam, {-12.0f, 18.0f, 1.5f});
  const LinearRgb e = pixel(fb, int(east[0]), int(east[1]));
  const LinearRgb so = pixel(fb, int(south[0]), int(south[1]));
  EXPECT_GT(houle::luminance(e), 1.3f * houle::luminance(so));
  // The box is red: its lit face too.
  EXPECT_GT(e.r, e.g);
  EXPECT_GT(e.r, e.b);
  // Without the sun's contribution the two faces are alike: put the sun behind the box's back (north-west).
  RenderScene back = scene;
  back.sun_direction = {-0.8f, 0.5f, 0.3f};
  Renderer rb = make_renderer(back, w, h, {}, 2);
  Framebuffer fb2(w, h);
  rb.render(s, nullptr, nullptr, cam, fb2);
  EXPECT_NEAR(houle::luminance(pixel(fb2, int(east[0]), int(east[1]))),
              houle::luminance(pixel(fb2, int(south[0]), int(south[1]))), 1e-3f);
}

TEST(Renderer, SunGlintInFrontIsTheBrightestThing) {
  RenderScene scene = test_scene();
  scene.sun_direction = {0.0f, 1.0f, 0.12f};  // low sun straight ahead
  Renderer r = make_renderer(scene, W, H, {}, 2);
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  Framebuffer fb(W, H);
  r.render(s, &n, nullptr, default_cam(), fb);
  float sea_max = 0.0f, sky_max = 0.0f;
  for (int y = 0; y < int(H); ++y) {
    for (int x = 0; x < int(W); ++x) {
      const float l = houle::luminance(pixel(fb, x, y));
      (y < 10 ? sky_max : sea_max) = std::max(y < 10 ? sky_max : sea_max, l);
    }
  }
  EXPECT_GT(sea_max, 2.0f * sky_max);
}

TEST(Renderer, GlintAtOneSampleIsTheSupersampledGlint) {
  // The sun's glitter path at one sample per pixel against 8 samples (film): the lobe through the
  // pixel's slope distribution must give each pixel about the average of its sub-pixel glints, not a
  // point sample of them (sparkles that flicker from frame to frame). Measured as the RMS difference
  // of the displayed glint region, relative to its mean.
  RenderScene scene = test_scene();
  scene.sun_direction = {0.0f, 1.0f, 0.2f};  // low sun straight ahead
  const houle::SurfaceFrame s = make_surface(3.0);
  const houle::CapillaryFrame n = make_noise(3.0);
  constexpr std::uint32_t w = 160, h = 90;
  const Camera cam = make_cam({0.0f, 0.0f, 4.0f}, {0.0f, 60.0f, 4.0f - 60.0f * std::tan(6.0f * 0.0174533f)}, w, h);
  RenderQuality one, eight;
  eight.samples_per_pixel = 8;
  Renderer a = make_renderer(scene, w, h, one, 2), b = make_renderer(scene, w, h, eight, 2);
  Framebuffer fa(w, h), fb(w, h);
  a.render(s, &n, nullptr, cam, fa);
  b.render(s, &n, nullptr, cam, fb);
  const houle::ToneMap tm{0.5f};
  double diff2 = 0.0, sum = 0.0;
  int count = 0;
  for (int y = int(h) / 2; y < int(h); ++y) {
    for (int x = int(w) / 3; x < 2 * int(w) / 3; ++x) {  // the glitter path, below the sun
      const float da = houle::luminance(houle::tone_map(pixel(fa, x, y), tm));
      const float db = houle::luminance(houle::tone_map(pixel(fb, x, y), tm));
      diff2 += double(da - db) * double(da - db);
      sum += db;
      ++count;
    }
  }
  const double rel = std::sqrt(diff2 / count) / (sum / count);
  std::printf("glint at 1 sample against 8: relative RMS difference %.3f\n", rel);
  EXPECT_LT(rel, 0.1);
}

TEST(Renderer, GlintSpreadsOverTheSlopeVarianceTheFillLeftOut) {
  // A still sea whose frame says the fill left out a slope variance v (the trains too short for the
  // footprint, docs/rendering.md 5.5), the sun 30 degrees up ahead, the camera 10 m up looking at the
  // sun's mirror point: the glint spreads over the slopes of the left-out waves, its peak falls and its
  // area grows, but the light it carries stays the sun's reflection, only redistributed: the frames'
  // sums differ by under 10 % of what moved.
  RenderScene scene = test_scene();
  scene.boxes.clear();
  scene.spheres.clear();
  scene.sun_direction = {0.0f, 0.8660254f, 0.5f};
  constexpr std::uint32_t w = 160, h = 120;
  const Camera cam = make_cam({0.0f, 0.0f, 10.0f}, {0.0f, 17.32f, 0.0f}, w, h);
  Renderer r = make_renderer(scene, w, h, {}, 2);
  const auto frame = [&](float variance) {
    auto f = houle::SurfaceFrame::create(small_frame_config());
    EXPECT_TRUE(f.ok());
    f->begin_frame(0.0f, 10.0f);
    f->fill([](void* c, const houle::SurfaceSamples& s) noexcept {
      std::fill(s.height, s.height + s.n, 0.0f);
      std::fill(s.grad_x, s.grad_x + s.n, 0.0f);
      std::fill(s.grad_y, s.grad_y + s.n, 0.0f);
      std::fill(s.slope_variance, s.slope_variance + s.n, *static_cast<const float*>(c));
    }, &variance);
    Framebuffer fb(w, h);
    r.render(f.value(), nullptr, nullptr, cam, fb);
    std::vector<double> l(std::size_t(w) * h);
    for (std::size_t i = 0; i < l.size(); ++i) l[i] = houle::luminance({fb.rgb[3 * i], fb.rgb[3 * i + 1], fb.rgb[3 * i + 2]});
    return l;
  };
  const std::vector<double> narrow = frame(0.0005f), wide = frame(0.0015f);
  double sum = 0.0, moved = 0.0, peak_narrow = 0.0, peak_wide = 0.0;
  for (std::size_t i = 0; i < narrow.size(); ++i) {
    sum += wide[i] - narrow[i];
    moved += std::fabs(wide[i] - narrow[i]);
    peak_narrow = std::max(peak_narrow, narrow[i]);
    peak_wide = std::max(peak_wide, wide[i]);
  }
  const auto area = [](const std::vector<double>& l, double above) { return std::count_if(l.begin(), l.end(), [&](double v) { return v > above; }); };
  std::printf("glint over v = 0.0005 and 0.0015: peaks %.1f and %.1f, pixels over a tenth of the first %ld and %ld, "
              "sum changed by %.3f of what moved\n", peak_narrow, peak_wide, long(area(narrow, 0.1 * peak_narrow)),
              long(area(wide, 0.1 * peak_narrow)), sum / moved);
  EXPECT_LT(peak_wide, 0.6 * peak_narrow);
  EXPECT_GT(area(wide, 0.1 * peak_narrow), area(narrow, 0.1 * peak_narrow));
  EXPECT_LT(std::fabs(sum), 0.1 * moved);
}

/// A 2 x 2 x 4 m pillar at (0, 20) with its centre `rest_z` m up and the given motion, moved to stand
/// 3 m out of still water when it moves, the sun 45 degrees up in the east: its shadow falls west,
/// 3 m through the air and on through the water. Looking straight down at a point 2 m west of the
/// pillar (in the shadow of its part above the water) and at a point 4 m further north (in no
/// shadow), over a floor 1 m and 50 m down: the shadowed one is darker.
void expect_pillar_shadows_the_sea(float rest_z, float motion) {
  const houle::SurfaceFrame surface = still_surface(-3.0f, 20.0f);
  for (float depth : {1.0f, 50.0f}) {
    RenderScene s;
    s.floor.origin_x = s.floor.origin_y = -100.0f;
    s.floor.cell = 5.0f;
    s.floor.nx = s.floor.ny = 41;
    s.floor.z.assign(41 * 41, -depth);
    s.floor.sand = {0.8f, 0.75f, 0.6f};
    s.boxes.push_back({{0.0f, 20.0f, rest_z}, {1.0f, 1.0f, 2.0f}, 0.0f, {0.5f, 0.5f, 0.5f}, motion});
    s.sun_direction = {0.7071f, 0.0f, 0.7071f};
    Renderer r = make_renderer(s, W, H, {}, 1);
    if (motion > 0.0f) {
      houle::BoxPose pose;
      pose.center = {0.0f, 20.0f, 1.0f};
      r.move_box(0, pose);
    }
    const auto centre = [&](float x, float y) {
      Framebuffer fb(W, H);
      r.render(surface, nullptr, nullptr, make_cam({x, y, 10.0f}, {x, y, 0.0f}, W, H, {0.0f, 1.0f, 0.0f}), fb);
      return houle::luminance(pixel(fb, int(W) / 2, int(H) / 2));
    };
    const float shadow = centre(-3.0f, 20.0f), open = centre(-3.0f, 24.0f);
    EXPECT_LT(shadow, 0.7f * open) << depth << " m: " << shadow << " against " << open;
  }
}

TEST(Renderer, ObjectsShadowTheSeaWhereTheSunPutsThem) {
  // A fixed pillar 3 m out of the water: over the shallow floor its shadow drew only the pillar's
  // submerged foot (a thin band at its base), and over deep water none (the sun lit the water's own
  // light there).
  expect_pillar_shadows_the_sea(1.0f, 0.0f);
}

TEST(Renderer, MovedObjectsShadowTheSeaWhereTheyAre) {
  // The pillar floating (motion 5 m), at rest wholly under the water and moved up to stand 3 m out of
  // it: the sea's shadow rays reach as high as a moving object can go, so it shadows the water as the
  // fixed pillar does (they went only as high as the objects at rest: no shadow on the water).
  expect_pillar_shadows_the_sea(-3.0f, 5.0f);
}

TEST(Renderer, FoamWhereTheSurfMapSaysWavesBreak) {
  // Deep water, the two trains, and a surf map that says waves break west of x = 0 (travelling
  // north, 0.3 m): the sea there is foamed, whiter and brighter than east of it, and more on the
  // crests than in the troughs; east of it, and with no map at all, the sea is the same.
  RenderScene scene;
  scene.sun_direction = {0.3f, -0.5f, 0.8f};
  RenderScene surfing = scene;
  houle::SurfMap& m = surfing.surf;
  m.origin_x = m.origin_y = -100.0f;
  m.cell = 1.0f;
  m.nx = m.ny = 201;
  const std::size_t nodes = 201 * 201;
  m.foam.assign(nodes, 0.0f);
  m.dir_x.assign(nodes, 0.0f);
  m.dir_y.assign(nodes, 1.0f);
  m.amplitude.assign(nodes, 0.3f);
  for (std::size_t n = 0; n < nodes; ++n) m.foam[n] = n % 201 <= 99 ? 1.0f : 0.0f;  // x <= -1
  const houle::SurfaceFrame s = make_surface(3.0);
  const Camera cam = default_cam();
  Renderer plain = make_renderer(scene, W, H, {}, 1), foamy = make_renderer(surfing, W, H, {}, 1);
  Framebuffer a(W, H), b(W, H);
  plain.render(s, nullptr, nullptr, cam, a);
  foamy.render(s, nullptr, nullptr, cam, b);
  double west = 0.0, east = 0.0, west_plain = 0.0, crest = 0.0, trough = 0.0;
  double red = 0.0, blue = 0.0, red_plain = 0.0, blue_plain = 0.0;
  int crests = 0, troughs = 0;
  for (int y = int(H) / 2 + 4; y < int(H); ++y) {
    for (int x = 0; x < int(W); ++x) {
      const auto d = houle::camera_ray(cam, float(x) + 0.5f, float(y) + 0.5f);
      const float t = -cam.position[2] / d[2], wx = cam.position[0] + t * d[0];
      if (std::abs(wx) < 2.0f) continue;
      const float lb = houle::luminance(pixel(b, x, y)), la = houle::luminance(pixel(a, x, y));
      if (wx > 0.0f) {
        EXPECT_EQ(lb, la) << x << ", " << y;  // no foam, the same sea
        east += lb;
      } else {
        west += lb;
        west_plain += la;
        red += pixel(b, x, y).r, blue += pixel(b, x, y).b;
        red_plain += pixel(a, x, y).r, blue_plain += pixel(a, x, y).b;
      }
    }
  }
  EXPECT_GT(west, 1.5 * west_plain);
  EXPECT_GT(red / blue, 1.3 * red_plain / blue_plain);  // whiter: less of the sea's blue
  // Crests against troughs along one column of the foamed half: the brightest pixels are crests.
  const int column = int(W) / 5;
  for (int y = int(H) / 2 + 4; y < int(H); ++y) {
    const auto d = houle::camera_ray(cam, float(column) + 0.5f, float(y) + 0.5f);
    const float t = -cam.position[2] / d[2];
    const float h = s.height_at(cam.position[0] + t * d[0], cam.position[1] + t * d[1]);
    const float l = houle::luminance(pixel(b, column, y));
    if (h > 0.1f) crest += l, ++crests;
    if (h < -0.1f) trough += l, ++troughs;
  }
  ASSERT_GT(crests, 0);
  ASSERT_GT(troughs, 0);
  EXPECT_GT(crest / crests, trough / troughs);
  std::printf("foam: west %.3f (plain %.3f), east %.3f\n", west, west_plain, east);
}

TEST(Renderer, ClearWaterShowsTheFloorDeepWaterHidesIt) {
  // Looking straight down through 5 m of pure water onto a white floor, and through 500 m.
  RenderScene shallow;
  shallow.floor.nx = shallow.floor.ny = 2;
  shallow.floor.origin_x = shallow.floor.origin_y = -1000.0f;
  shallow.floor.cell = 2000.0f;
  shallow.floor.z.assign(4, -5.0f);
  shallow.floor.sand = {1.0f, 1.0f, 1.0f};
  shallow.sun_direction = {0.0f, 0.3f, 1.0f};
  RenderScene deep = shallow;
  deep.floor.z.assign(4, -500.0f);
  const houle::SurfaceFrame flat = make_surface(0.0, 0.0f, 0.0f, true);
  const Camera down = make_cam({0.0f, 0.0f, 10.0f}, {0.0f, 0.0f, 0.0f}, W, H, {0.0f, 1.0f, 0.0f});
  for (bool spectral : {true, false}) {
    RenderQuality q;
    q.spectral_absorption = spectral;
    Renderer a = make_renderer(shallow, W, H, q, 1);
    Renderer b = make_renderer(deep, W, H, q, 1);
    Framebuffer fa(W, H), fbd(W, H);
    a.render(flat, nullptr, nullptr, down, fa);
    b.render(flat, nullptr, nullptr, down, fbd);
    const LinearRgb ca = pixel(fa, W / 2, H / 2), cb = pixel(fbd, W / 2, H / 2);
    EXPECT_GT(houle::luminance(ca), 2.0f * houle::luminance(cb)) << spectral;
    EXPECT_GT(ca.b, ca.r) << spectral;  // the red is absorbed first
    EXPECT_GT(cb.b, cb.r) << spectral;
  }
}

TEST(Renderer, UnderWaterTotalInternalReflectionOutsideSnellsWindow) {
  RenderScene scene = test_scene();
  Renderer r = make_renderer(scene, W, H, {}, 2);
  const houle::SurfaceFrame flat = make_surface(0.0, 0.0f, 0.0f, true);
  // 3 m under a flat sea looking up at 45 degrees with a 60 degree field: both sides of 48.3 degrees.
  const Camera cam = make_cam({0.0f, 0.0f, -3.0f}, {0.0f, 10.0f, 7.0f});
  Framebuffer kr(W, H), img(W, H);
  r.render(flat, nullptr, nullptr, cam, kr, RenderView::sea_reflectance);
  int total = 0, partial = 0;
  for (int y = 0; y < int(H); ++y) {
    for (int x = 0; x < int(W); ++x) {
      const float k = pixel(kr, x, y).r;
      total += k == 1.0f;
      partial += k > 0.0f && k < 1.0f;
    }
  }
  EXPECT_GT(total, 0);
  EXPECT_GT(partial, 0);
  r.render(flat, nullptr, nullptr, cam, img);
  EXPECT_EQ(count_nonfinite(img), 0u);
}

TEST(Renderer, RejectsInvalidInput) {
  RenderQuality q;
  q.samples_per_pixel = 3;
  EXPECT_FALSE(Renderer::create(test_scene(), W, H, q, 1).ok());
  EXPECT_FALSE(Renderer::create(test_scene(), 0, H, {}, 1).ok());
  RenderScene s = test_scene();
  s.boxes[0].half_extent[1] = 0.0f;
  auto r = Renderer::create(s, W, H, {}, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "boxes[0].half_extent");
  s = test_scene();
  s.floor.z.pop_back();
  EXPECT_FALSE(Renderer::create(s, W, H, {}, 1).ok());
  s = test_scene();
  s.turbidity = 20.0f;
  EXPECT_FALSE(Renderer::create(s, W, H, {}, 1).ok());
  s = test_scene();
  s.sea_dominant_wavelength_nm = 100.0f;
  r = Renderer::create(s, W, H, {}, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "sea_dominant_wavelength_nm");
  EXPECT_TRUE(Renderer::create(test_scene(), W, H, {}, 0).ok());  // 0 threads: the caller alone
}

// ---- Scene object queries ------------------------------------------------------------------------

using houle::detail::HitKind;
using houle::detail::SceneObjects;
using houle::detail::SceneRay;

SceneRay ray_to(std::array<double, 3> o, std::array<double, 3> d) {
  const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {o[0], o[1], o[2], d[0] / n, d[1] / n, d[2] / n};
}

TEST(SceneObjects, PlanarFloorMatchesThePlaneInsideAndBeyondTheGrid) {
  // z = 0.1 x - 0.05 y - 3 sampled on a grid is exactly bilinear; outside it the edges extend.
  RenderScene s;
  s.floor.origin_x = -20.0f;
  s.floor.origin_y = -10.0f;
  s.floor.cell = 2.0f;
  s.floor.nx = 21;
  s.floor.ny = 31;
  for (std::uint32_t j = 0; j < s.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < s.floor.nx; ++i) {
      const double x = -20.0 + 2.0 * i, y = -10.0 + 2.0 * j;
      s.floor.z.push_back(float(0.1 * x - 0.05 * y - 3.0));
    }
  }
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  const SceneObjects& o = built.value();
  const auto plane_t = [](const SceneRay& r) {
    // oz + t dz = 0.1 (ox + t dx) - 0.05 (oy + t dy) - 3
    return (0.1 * r.ox - 0.05 * r.oy - 3.0 - r.oz) / (r.dz - 0.1 * r.dx + 0.05 * r.dy);
  };
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const double a = 0.031 * k, e = -0.05 - 0.004 * k;  // azimuths all round, down 3 to 48 degrees
    const SceneRay r = ray_to({1.3, 2.7, 4.0}, {std::cos(a), std::sin(a), std::tan(e) * 1.0});
    const double tp = plane_t(r);
    const double x = r.ox + tp * r.dx, y = r.oy + tp * r.dy;
    const bool inside = x >= -20.0 && x <= 20.0 && y >= -10.0 && y <= 50.0;
    const houle::detail::SurfaceHit h = o.intersect(r, 0.0, 1e5);
    ASSERT_EQ(h.kind, HitKind::floor) << k;
    if (inside) {
      EXPECT_NEAR(h.t, tp, 1e-4 * tp) << k;
      EXPECT_NEAR(h.normal[0], -0.1 / std::sqrt(1.0125), 1e-5);
      ++checked;
    }
    // Wherever it is, the hit lies on the floor.
    const double hx = r.ox + h.t * r.dx, hy = r.oy + h.t * r.dy, hz = r.oz + h.t * r.dz;
    EXPECT_NEAR(hz, o.floor_height(hx, hy), 1e-3) << k;
  }
  EXPECT_GT(checked, 50);
  // Beyond the grid's east edge the floor is the edge column's z: 0.1 * 20 - 0.05 y - 3.
  EXPECT_NEAR(o.floor_height(500.0, 0.0), -1.0, 1e-6);
  // A ray that stays above the highest sample misses; one that ends at z = 0, above the floor, misses too.
  EXPECT_EQ(o.intersect(ray_to({0.0, 0.0, 10.0}, {1.0, 0.0, 0.0}), 0.0, 1e5).kind, HitKind::none);
  const SceneRay down = ray_to({0.0, 0.0, 4.0}, {0.0, 0.3, -1.0});
  EXPECT_EQ(o.intersect(down, 0.0, (0.0 - down.oz) / down.dz).kind, HitKind::none);
  EXPECT_EQ(o.intersect(down, 0.0, 1e5).kind, HitKind::floor);
  EXPECT_FALSE(o.occluded(ray_to({0.0, 0.0, -2.0}, {0.0, 0.0, 1.0}), 0.0, 1e5));
  EXPECT_TRUE(o.occluded(ray_to({0.0, 0.0, -2.0}, {0.0, 0.0, -1.0}), 0.0, 1e5));
}

/// Uniform in [0, 1) from a linear congruential generator: the same sequence everywhere.
struct Lcg {
  std::uint32_t seed;
  double operator()() {
    seed = seed * 1664525u + 1013904223u;
    return double(seed >> 8) / double(1u << 24);
  }
};

/// A floor of nx x ny samples `cell` m apart from (x0, y0), z = height(i, j) taken row by row.
template <class Height>
RenderScene floor_grid(float x0, float y0, float cell, std::uint32_t nx, std::uint32_t ny, Height&& height) {
  RenderScene s;
  s.floor.origin_x = x0;
  s.floor.origin_y = y0;
  s.floor.cell = cell;
  s.floor.nx = nx;
  s.floor.ny = ny;
  for (std::uint32_t j = 0; j < ny; ++j) {
    for (std::uint32_t i = 0; i < nx; ++i) s.floor.z.push_back(float(height(i, j)));
  }
  return s;
}

TEST(Renderer, LandIsSandWetNearTheWaterDryAbove) {
  // A beach rising 1:10 out of still water, seen straight down from 8 m with the sun overhead: the
  // sand is the scene's colour, darker where wet (10 cm above the water) than where dry (2.5 m up),
  // and not one flat value across the dry beach (its grain: the pixels there are 13 cm wide).
  RenderScene s = floor_grid(-50.0f, -50.0f, 1.0f, 101, 101, [](std::uint32_t, std::uint32_t j) { return 0.1 * (double(j) - 50.0); });
  s.floor.sand = {0.7f, 0.5f, 0.3f};
  s.sun_direction = {0.0f, 0.0f, 1.0f};
  const houle::SurfaceFrame surface = still_surface(0.0f, 0.0f);
  Renderer r = make_renderer(s, W, H, {}, 1);
  const auto look = [&](float x, float y) {
    Framebuffer fb(W, H);
    r.render(surface, nullptr, nullptr, make_cam({x, y, 8.0f}, {x, y, 0.0f}, W, H, {0.0f, 1.0f, 0.0f}), fb);
    return pixel(fb, int(W) / 2, int(H) / 2);
  };
  const LinearRgb wet = look(0.0f, 1.0f), dry = look(0.0f, 25.0f);
  EXPECT_GT(dry.r, dry.g);
  EXPECT_GT(dry.g, dry.b);
  EXPECT_LT(houle::luminance(wet), 0.75f * houle::luminance(dry));
  float lo = 1e30f, hi = 0.0f;
  for (float x = -20.0f; x <= 20.0f; x += 2.5f) {
    const float l = houle::luminance(look(x, 25.0f));
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
  EXPECT_GT(hi, 1.04f * lo);  // grain
  EXPECT_LT(hi, 1.3f * lo);
}

TEST(SceneObjects, BumpyFloorMatchesADenseMarch) {
  // Random heights: the hierarchical walk and the per-cell quadratics against stepping along the ray
  // by 2 mm with floor_height (the first sign change, bisected), rays from above in all directions,
  // from grazing to steep, starting inside and outside the grid.
  Lcg rnd{12345u};
  const RenderScene s = floor_grid(-30.0f, -20.0f, 1.5f, 53, 41, [&](std::uint32_t i, std::uint32_t j) {
    return 2.0 * std::sin(0.15 * i) * std::cos(0.2 * j) - 1.0 + 0.8 * (rnd() - 0.5);
  });
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  const SceneObjects& o = built.value();
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    const std::array<double, 3> origin{-50.0 + 100.0 * rnd(), -40.0 + 80.0 * rnd(), 1.5 + 3.0 * rnd()};
    const double az = 6.283185 * rnd(), el = -0.02 - 0.6 * rnd() * rnd();
    const SceneRay r = ray_to(origin, {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)});
    const double reach = 150.0;
    const auto f = [&](double t) { return r.oz + t * r.dz - o.floor_height(r.ox + t * r.dx, r.oy + t * r.dy); };
    double ref = reach;
    if (f(0.0) > 0.0) {
      for (double t = 0.002; t <= reach; t += 0.002) {
        if (f(t) <= 0.0) {
          double a = t - 0.002, b = t;
          for (int it = 0; it < 40; ++it) (f(0.5 * (a + b)) > 0.0 ? a : b) = 0.5 * (a + b);
          ref = b;
          break;
        }
      }
    }
    const houle::detail::SurfaceHit h = o.intersect(r, 0.0, reach);
    if (ref < reach) {
      ++hits;
      ASSERT_EQ(h.kind, HitKind::floor) << k;
      EXPECT_NEAR(h.t, ref, 1e-4 * ref + 1e-5) << k;
      EXPECT_EQ(o.occluded(r, 0.0, reach), true) << k;
      EXPECT_EQ(o.occluded(r, 0.0, 0.99 * ref), false) << k;
    } else {
      EXPECT_EQ(h.kind, HitKind::none) << k << " t " << h.t;
    }
  }
  EXPECT_GT(hits, 200);
}

TEST(SceneObjects, RaysReachTheLowestGround) {
  // A beach whose deepest row continues flat beyond the grid (the extended edge): rays going down
  // meet that ground exactly where they reach the floor's lowest height, the end of the span the walk
  // searches. Every one of them must find it, from the full walk and from the secondary rays' jumps
  // (rounding at the span's end used to drop about one in ten).
  Lcg rnd{31337u};
  const RenderScene s = floor_grid(0.0f, 0.0f, 1.0f, 60, 50, [](std::uint32_t, std::uint32_t j) { return -5.7 + 0.1 * j; });
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  const SceneObjects& o = built.value();
  for (int k = 0; k < 2000; ++k) {
    const double az = 3.6 + 2.0 * rnd(), el = -0.3 - 0.8 * rnd();
    const SceneRay r = ray_to({600.0 + 800.0 * rnd(), -200.0 - 800.0 * rnd(), 0.5 * (rnd() - 0.5)},
                              {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)});
    const double expected = (-5.7f - r.oz) / r.dz;
    const houle::detail::SurfaceHit full = o.intersect(r, 0.0, 1000.0), jumped = o.intersect_secondary(r, 0.0, 1000.0);
    ASSERT_EQ(full.kind, HitKind::floor) << k;
    ASSERT_EQ(jumped.kind, HitKind::floor) << k;
    EXPECT_NEAR(full.t, expected, 1e-5 * expected) << k;
    EXPECT_NEAR(jumped.t, expected, 1e-5 * expected) << k;
  }
}

TEST(SceneObjects, SecondaryRaysFindIntersectsHits) {
  // Reflected, refracted and shadow rays jump over the floor where its clearance map shows them above
  // all of it: the same hits as intersect()'s full walk, up to the last bits of t and the normal,
  // for rays up and down from just above the floor, from above the water, inside and outside the grid.
  Lcg rnd{2718u};
  RenderScene s = floor_grid(-40.0f, -10.0f, 1.0f, 120, 130, [&](std::uint32_t i, std::uint32_t j) {
    return 2.0 - 0.1 * j + 0.8 * std::sin(0.3 * i) * std::cos(0.23 * j) + 0.4 * (rnd() - 0.5);
  });
  for (int k = 0; k < 6; ++k) {
    s.boxes.push_back({{float(80.0 * rnd() - 40.0), float(120.0 * rnd()), float(2.0 * rnd() - 1.5)},
                       {float(0.3 + 2.0 * rnd()), float(0.3 + rnd()), float(0.3 + 1.5 * rnd())}, float(6.28 * rnd()), {}});
  }
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  const SceneObjects& o = built.value();
  int floor_hits = 0, misses = 0;
  for (int k = 0; k < 20000; ++k) {
    const double x = -60.0 + 160.0 * rnd(), y = -30.0 + 170.0 * rnd();
    const double ground = o.floor_height(x, y);
    // From 1 mm to 6 m above the ground or the still water, whichever is higher.
    const double z = std::max(ground, -0.5 + rnd()) + (k % 4 == 0 ? 1e-3 : 6.0 * rnd() * rnd());
    const double az = 6.283185 * rnd(), el = (k % 2 ? 1.0 : -1.0) * 1.5 * rnd() * rnd();
    const SceneRay r = ray_to({x, y, z}, {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)});
    const double reach = k % 3 == 0 ? 30.0 : 1000.0;
    const houle::detail::SurfaceHit ref = o.intersect(r, 0.0, reach), h = o.intersect_secondary(r, 0.0, reach);
    ASSERT_EQ(h.kind, ref.kind) << k << ": t " << h.t << " vs " << ref.t;
    ASSERT_EQ(h.index, ref.index) << k;
    EXPECT_EQ(o.occluded(r, 0.0, reach), ref.kind != HitKind::none) << k;
    if (ref.kind == HitKind::none) {
      ++misses;
      continue;
    }
    EXPECT_NEAR(h.t, ref.t, 1e-6f * ref.t + 1e-9f) << k;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(h.normal[std::size_t(a)], ref.normal[std::size_t(a)], 1e-5f) << k;
    floor_hits += ref.kind == HitKind::floor;
  }
  EXPECT_GT(floor_hits, 5000);
  EXPECT_GT(misses, 2000);
}

TEST(SceneObjects, FlatFloorMeetsEveryRayThatGoesDownToIt) {
  // A level floor is the floor's whole height range, so a walk starts and ends at the same height:
  // the ray must still meet it, whatever rounding puts the ray's z at the span's ends. Refracted rays
  // that missed a flat floor this way were the dark specks over flat floors at 3, 6, 7, 8 and 12 m
  // (none at 5, 20 or 50: the rounding's luck).
  Lcg rnd{97u};
  int missed = 0, rays = 0;
  for (double depth = 0.5; depth <= 50.0; depth += 0.25) {
    const RenderScene s = floor_grid(0.0f, 0.0f, 1.0f, 201, 201, [&](std::uint32_t, std::uint32_t) { return -depth; });
    auto built = SceneObjects::build(s);
    ASSERT_TRUE(built.ok());
    for (int k = 0; k < 200; ++k, ++rays) {
      // Refracted rays: from just under a wavy surface, within Snell's window of the vertical.
      const std::array<double, 3> origin{20.0 + 160.0 * rnd(), 20.0 + 160.0 * rnd(), 0.3 * (rnd() - 0.5)};
      const double az = 6.283185 * rnd(), el = -1.57 + 0.9 * rnd();
      const SceneRay r = ray_to(origin, {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)});
      const houle::detail::SurfaceHit h = built->intersect(r, 0.0, 1000.0);
      missed += h.kind != HitKind::floor;
      if (h.kind == HitKind::floor) {
        EXPECT_NEAR(r.oz + h.t * r.dz, -depth, 1e-6 * depth) << depth;
      }
    }
  }
  EXPECT_EQ(missed, 0) << "of " << rays;
}

TEST(SceneObjects, HierarchyFindsWhatEachObjectAloneFinds) {
  // 150 random boxes and spheres: the nearest hit through the hierarchy equals the nearest of the
  // hits of one-object scenes, and any-hit agrees with it.
  std::uint32_t seed = 777u;
  const auto rnd = [&seed] {
    seed = seed * 1664525u + 1013904223u;
    return float(seed >> 8) / float(1u << 24);
  };
  RenderScene all;
  std::vector<SceneObjects> single;
  for (int k = 0; k < 150; ++k) {
    RenderScene one;
    if (k % 3 == 0) {
      one.spheres.push_back({{80.0f * rnd() - 40.0f, 80.0f * rnd() - 40.0f, 6.0f * rnd() - 3.0f}, 0.2f + 2.0f * rnd(), {}});
      all.spheres.push_back(one.spheres.back());
    } else {
      one.boxes.push_back({{80.0f * rnd() - 40.0f, 80.0f * rnd() - 40.0f, 6.0f * rnd() - 3.0f},
                           {0.2f + 3.0f * rnd(), 0.2f + 0.5f * rnd(), 0.2f + 2.0f * rnd()},
                           6.28f * rnd(), {}});
      all.boxes.push_back(one.boxes.back());
    }
    single.push_back(std::move(SceneObjects::build(one).value()));
  }
  auto built = SceneObjects::build(all);
  ASSERT_TRUE(built.ok());
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const SceneRay r = ray_to({60.0 * rnd() - 30.0, 60.0 * rnd() - 30.0, 8.0 * rnd() - 4.0},
                              {rnd() - 0.5, rnd() - 0.5, 0.3 * (rnd() - 0.5)});
    const double t_max = k % 2 ? 1e5 : 20.0;
    float ref = std::numeric_limits<float>::infinity();
    for (const SceneObjects& o : single) ref = std::min(ref, o.intersect(r, 0.0, t_max).t);
    const houle::detail::SurfaceHit h = built->intersect(r, 0.0, t_max);
    EXPECT_EQ(h.t, ref) << k;
    EXPECT_EQ(built->occluded(r, 0.0, t_max), ref < t_max) << k;
    hits += ref < t_max;
  }
  EXPECT_GT(hits, 500);
}

TEST(ShadowMask, ALineThroughAClearCellMeetsNoCaster) {
  // The renderer skips a sea pixel's shadow ray where the mask is clear (docs/rendering.md 3.5): that
  // must never hide a caster. 120 random boxes (walls up to 30 m long, turned any way) and spheres, a
  // third of them moving and put anywhere within their motion, tilted; for suns from 2 to 89 degrees
  // up, rays that graze a caster (aimed just inside a box's corner or a sphere's outline, from up to
  // 60 m below along the sun) and rays from anywhere: every ray that meets a caster crosses a marked
  // cell, and most of the open sea is clear.
  std::uint32_t seed = 4242u;
  const auto rnd = [&seed] {
    seed = seed * 1664525u + 1013904223u;
    return float(seed >> 8) / float(1u << 24);
  };
  using V = std::array<float, 3>;
  RenderScene s;
  for (int k = 0; k < 120; ++k) {
    const V c{200.0f * rnd() - 100.0f, 200.0f * rnd() - 100.0f, 6.0f * rnd() - 3.0f};
    const float motion = k % 3 == 0 ? 2.0f * rnd() : 0.0f;
    if (k % 4 == 0) {
      s.spheres.push_back({c, 0.2f + 2.0f * rnd(), {}, motion});
    } else {
      s.boxes.push_back({c, {0.2f + (k % 5 == 0 ? 15.0f : 3.0f) * rnd(), 0.2f + 1.0f * rnd(), 0.2f + 3.0f * rnd()},
                         6.28f * rnd(), {}, motion});
    }
  }
  SceneObjects o = std::move(SceneObjects::build(s).value());
  // Where each caster is now: boxes at rest turned by their yaw, moving ones moved (up to 0.95 of their
  // motion) and tilted.
  std::vector<houle::BoxPose> boxes(s.boxes.size());
  std::vector<V> spheres(s.spheres.size());
  for (std::size_t k = 0; k < s.boxes.size(); ++k) {
    const houle::RenderBox& b = s.boxes[k];
    float yaw = b.yaw_rad, tilt = 0.0f;
    V c = b.center;
    if (b.motion > 0.0f) {
      tilt = 3.0f * rnd();
      yaw = 6.28f * rnd();
      const float m = 0.95f * b.motion / std::sqrt(3.0f);
      for (float& x : c) x += m * (2.0f * rnd() - 1.0f);
    }
    const float cy = std::cos(yaw), sy = std::sin(yaw), ct = std::cos(tilt), st = std::sin(tilt);
    boxes[k].center = c;
    boxes[k].axes = {{{cy, sy, 0.0f}, {-sy * ct, cy * ct, st}, {sy * st, -cy * st, ct}}};
    if (b.motion > 0.0f) o.move_box(k, boxes[k]);
  }
  for (std::size_t k = 0; k < s.spheres.size(); ++k) {
    const float m = 0.95f * s.spheres[k].motion / std::sqrt(3.0f);
    for (int a = 0; a < 3; ++a) spheres[k][a] = s.spheres[k].center[a] + m * (2.0f * rnd() - 1.0f);
    if (s.spheres[k].motion > 0.0f) o.move_sphere(k, spheres[k]);
  }
  int met = 0, open = 0, open_clear = 0;
  for (int sun = 0; sun < 40; ++sun) {
    const float elevation = (2.0f + 87.0f * rnd()) * 3.14159265f / 180.0f, azimuth = 6.28f * rnd();
    const V towards{std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
    const houle::detail::ShadowMask mask = houle::detail::ShadowMask::build(s.boxes, s.spheres, towards);
    for (int k = 0; k < 1000; ++k) {
      V origin;
      if (k % 2 == 0) {
        V aim;
        if (k % 8 == 0) {
          // Just inside a sphere's outline as the sun sees it.
          const std::size_t i = std::min(std::size_t(rnd() * float(s.spheres.size())), s.spheres.size() - 1);
          V u{towards[1], -towards[0], 0.0f};  // across the sun
          const float a = 6.28f * rnd(), ul = std::sqrt(u[0] * u[0] + u[1] * u[1]);
          const V w{-towards[2] * u[1] / ul, towards[2] * u[0] / ul, (towards[0] * u[1] - towards[1] * u[0]) / ul};
          for (int c = 0; c < 3; ++c) {
            aim[c] = spheres[i][c] + 0.999f * s.spheres[i].radius * (std::cos(a) * u[c] / ul + std::sin(a) * w[c]);
          }
        } else {
          // Just inside one of a box's corners.
          const std::size_t i = std::min(std::size_t(rnd() * float(s.boxes.size())), s.boxes.size() - 1);
          aim = boxes[i].center;
          for (int axis = 0; axis < 3; ++axis) {
            const float e = 0.999f * s.boxes[i].half_extent[axis] * (rnd() < 0.5f ? -1.0f : 1.0f);
            for (int c = 0; c < 3; ++c) aim[c] += e * boxes[i].axes[axis][c];
          }
        }
        const float back = 60.0f * rnd();
        for (int c = 0; c < 3; ++c) origin[c] = aim[c] - back * towards[c];
      } else {
        origin = {300.0f * rnd() - 150.0f, 300.0f * rnd() - 150.0f, 6.0f * rnd() - 4.0f};
      }
      const SceneRay r = ray_to({origin[0], origin[1], origin[2]}, {towards[0], towards[1], towards[2]});
      if (o.occluded(r, 0.0, 1e5, false)) {
        ++met;
        EXPECT_TRUE(mask.may_meet(origin)) << "sun " << sun << " ray " << k;
      }
      if (k % 2 == 1) {
        ++open;
        open_clear += !mask.may_meet(origin);
      }
    }
  }
  EXPECT_GT(met, 15000);
  EXPECT_GT(open_clear, open / 2) << "the mask marks most of the sea: it would save few rays";
  std::printf("shadow mask: %d rays met a caster; %d of %d rays from anywhere skipped\n", met, open_clear, open);
}

TEST(SceneObjects, BoxesAndSpheres) {
  RenderScene s;
  s.boxes.push_back({{10.0f, 0.0f, 0.0f}, {1.0f, 2.0f, 0.5f}, 0.5f, {1.0f, 0.0f, 0.0f}});
  s.spheres.push_back({{0.0f, 10.0f, 1.0f}, 2.0f, {0.0f, 1.0f, 0.0f}});
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  const SceneObjects& o = built.value();
  // Sphere head on: t = 10 - 2.
  auto h = o.intersect(ray_to({0.0, 0.0, 1.0}, {0.0, 1.0, 0.0}), 0.0, 1e5);
  ASSERT_EQ(h.kind, HitKind::sphere);
  EXPECT_NEAR(h.t, 8.0f, 1e-5f);
  EXPECT_NEAR(h.normal[1], -1.0f, 1e-6f);
  // The rotated box along its local x axis (yaw 0.5): hits its -x face at distance 10 - 1.
  const double c = std::cos(0.5), sn = std::sin(0.5);
  h = o.intersect(ray_to({10.0 - 10.0 * c, -10.0 * sn, 0.0}, {c, sn, 0.0}), 0.0, 1e5);
  ASSERT_EQ(h.kind, HitKind::box);
  EXPECT_NEAR(h.t, 9.0f, 1e-5f);
  EXPECT_NEAR(h.normal[0], -c, 1e-6);
  EXPECT_NEAR(h.normal[1], -sn, 1e-6);
  // From above onto its top face.
  h = o.intersect(ray_to({10.0, 0.0, 5.0}, {0.0, 0.0, -1.0}), 0.0, 1e5);
  ASSERT_EQ(h.kind, HitKind::box);
  EXPECT_NEAR(h.t, 4.5f, 1e-5f);
  EXPECT_EQ(h.normal[2], 1.0f);
  // t_max excludes it; the empty floor never occludes.
  EXPECT_EQ(o.intersect(ray_to({10.0, 0.0, 5.0}, {0.0, 0.0, -1.0}), 0.0, 4.0).kind, HitKind::none);
  EXPECT_TRUE(o.occluded(ray_to({10.0, 0.0, 5.0}, {0.0, 0.0, -1.0}), 0.0, 5.0));
  EXPECT_FALSE(o.occluded(ray_to({10.0, 0.0, 5.0}, {0.0, 0.0, 1.0}), 0.0, 1e5));
  EXPECT_FALSE(o.has_floor());
}

TEST(SceneObjects, MovedBoxIsHitInItsNewPose) {
  // A 2 x 2 x 2 box that may move by 3 m, tilted 30 degrees about x (its local z in the y-z plane)
  // and lifted 1 m: a ray straight down onto its centre meets its top face at 1 / cos 30 above the
  // centre, with the face's tilted normal; beyond its bounds a ray meets nothing.
  RenderScene s;
  s.boxes.push_back({{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}, 0.0f, {0.5f, 0.5f, 0.5f}, 3.0f});
  auto built = SceneObjects::build(s);
  ASSERT_TRUE(built.ok());
  SceneObjects& o = built.value();
  const float a = 30.0f * 3.14159265f / 180.0f;
  houle::BoxPose pose;
  pose.center = {0.0f, 0.0f, 1.0f};
  pose.axes = {{{1.0f, 0.0f, 0.0f}, {0.0f, std::cos(a), std::sin(a)}, {0.0f, -std::sin(a), std::cos(a)}}};
  o.move_box(0, pose);
  auto h = o.intersect(ray_to({0.0, 0.0, 10.0}, {0.0, 0.0, -1.0}), 0.0, 1e5);
  ASSERT_EQ(h.kind, HitKind::box);
  EXPECT_NEAR(h.t, 10.0 - (1.0 + 1.0 / std::cos(double(a))), 1e-5);
  EXPECT_NEAR(h.normal[1], -std::sin(a), 1e-6);
  EXPECT_NEAR(h.normal[2], std::cos(a), 1e-6);
  // Moved too far: clamped to 3 m from where the scene put it.
  pose.center = {0.0f, 0.0f, 50.0f};
  o.move_box(0, pose);
  h = o.intersect(ray_to({0.0, 0.0, 100.0}, {0.0, 0.0, -1.0}), 0.0, 1e5);
  ASSERT_EQ(h.kind, HitKind::box);
  EXPECT_NEAR(h.t, 100.0 - (3.0 + 1.0 / std::cos(double(a))), 1e-4);
}

TEST(Renderer, MovingObjectsGiveTheBytesOfAFreshRenderer) {
  // A box and a sphere that heave and tilt from frame to frame in front of a still camera, beside a
  // fixed box and over a beach: the renderer that keeps its primary hits gives each frame the bytes of
  // a fresh renderer with the objects in the same place, and still reuses the hits away from them.
  RenderScene scene = test_scene();
  for (std::uint32_t j = 0; j < scene.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < scene.floor.nx; ++i) {
      scene.floor.z[j * scene.floor.nx + i] = -3.0f + 0.06f * float(j) * 5.0f - 0.8f * std::sin(0.7f * float(i));
    }
  }
  scene.boxes.push_back({{-3.0f, 15.0f, 0.3f}, {1.0f, 0.6f, 0.5f}, 0.3f, {0.9f, 0.8f, 0.1f}, 1.5f});
  scene.spheres[0].motion = 1.0f;
  scene.sea_height_bound = 0.4f;  // two_trains' amplitudes: the primary rays' cut stays put
  RenderQuality q;
  q.samples_per_pixel = 4;
  const Camera cam = default_cam();
  Renderer used = make_renderer(scene, W, H, q, 2);
  Framebuffer kept(W, H), alone(W, H);
  const auto place = [](Renderer& r, double t) {
    const float tilt = float(0.3 * std::sin(1.3 * t)), heave = float(0.8 * std::sin(0.9 * t));
    houle::BoxPose p;
    p.center = {-3.0f, 15.0f, 0.3f + heave};
    p.axes = {{{std::cos(tilt), 0.0f, std::sin(tilt)}, {0.0f, 1.0f, 0.0f}, {-std::sin(tilt), 0.0f, std::cos(tilt)}}};
    r.move_box(1, p);
    r.move_sphere(0, {5.0f, 20.0f, 0.5f - heave});
  };
  for (double t : {1.0, 1.1, 1.2, 4.0, 4.0, 2.6, 0.3}) {
    const houle::SurfaceFrame s = make_surface(t);
    const houle::CapillaryFrame n = make_noise(t);
    place(used, t);
    used.render(s, &n, nullptr, cam, kept);
    Renderer fresh = make_renderer(scene, W, H, q, 1);
    place(fresh, t);
    fresh.render(s, &n, nullptr, cam, alone);
    EXPECT_TRUE(same_bytes(kept, alone)) << "t " << t;
    const houle::RenderCounters& k = used.last_counters();
    if (t != 1.0 && t != 1.1) {  // the camera's first frame keeps nothing, its second writes the memo
      EXPECT_GT(k.reused, 0u) << "t " << t;
      EXPECT_LT(k.reused, k.sea + k.object + k.sky) << "t " << t;
    }
  }
  // The objects moved: the frames differ from one with them at rest.
  Renderer still = make_renderer(scene, W, H, q, 1);
  const houle::SurfaceFrame s = make_surface(0.3);
  const houle::CapillaryFrame n = make_noise(0.3);
  still.render(s, &n, nullptr, cam, alone);
  EXPECT_FALSE(same_bytes(kept, alone));
}

}  // namespace
