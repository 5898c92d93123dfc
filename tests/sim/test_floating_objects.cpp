// Floating objects (floating_objects.hpp, docs/physics.md 2.10): drafts against Archimedes, poses
// against the analytic surface of one long train, and through Animation a frame alone against the
// same frame in a sequence.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "angles.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/floating_objects.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

using houle_test::pi;

TEST(FloatingObjects, DraftsHoldTheirWeightInWater) {
  // A sphere's submerged cap pi d^2 (3 r - d) / 3 is density / 1025 of 4/3 pi r^3: half-dense floats
  // at its equator; a box's draft is its height times the ratio.
  EXPECT_NEAR(houle::sphere_draft(1.5, 0.5 * houle::sea_water_density), 1.5, 1e-12);
  for (double rho : {50.0, 300.0, 700.0, 1000.0}) {
    const double r = 0.8, d = houle::sphere_draft(r, rho);
    EXPECT_NEAR(pi * d * d * (3.0 * r - d) / 3.0 / (4.0 / 3.0 * pi * r * r * r), rho / houle::sea_water_density, 1e-12);
  }
  EXPECT_NEAR(houle::box_draft(2.0, 512.5), 2.0, 1e-12);
  // At rest the renderer gets them at their draft, whatever z the scene file wrote.
  houle::Scene s;
  houle::Sphere sp;
  sp.center = {10.0, 20.0, 7.0};
  sp.radius = 0.8;
  sp.floats = true;
  sp.density = 300.0;
  s.spheres = {sp};
  houle::Box b;
  b.center = {30.0, 20.0, -4.0};
  b.half_extent = {1.0, 1.0, 0.5};
  b.floats = true;
  b.density = 820.0;
  s.boxes = {b};
  const houle::RenderScene r = houle::make_render_scene(s);
  EXPECT_FLOAT_EQ(r.spheres[0].center[2], float(0.8 - houle::sphere_draft(0.8, 300.0)));
  EXPECT_FLOAT_EQ(r.boxes.back().center[2], float(0.5 - 1.0 * 820.0 / houle::sea_water_density));
}

// One long train along +x (wavelength 100 m, amplitude 0.5 m, a sine profile) on deep water.
houle::Scene swell() {
  houle::Scene s;
  s.domain = {0.0, 0.0, 200.0, 200.0};
  s.floor.base.depth = 150.0;
  s.capillary.amplitude = 0.0;
  houle::WaveTrain t;
  t.direction_deg = 0.0;
  t.wavelength = 100.0;
  t.amplitude = 0.5;
  t.steepness = 0.0;
  s.trains = {t};
  return s;
}

houle::Box floating_box(houle::Point3 center, houle::Point3 half_extent, double yaw_deg, double density) {
  houle::Box b;
  b.center = center;
  b.half_extent = half_extent;
  b.yaw_deg = yaw_deg;
  b.floats = true;
  b.density = density;
  return b;
}

TEST(FloatingObjects, PoseFollowsTheSurfaceUnderTheObject) {
  // A small box (2 m on a 100 m wave) and sphere ride the plane of the sine h = A sin(k x - w t):
  // heave = h at the centre, tilt = atan of the slope A k cos(k x - w t), about y, the yaw kept.
  houle::Scene s = swell();
  const houle::Box b = floating_box({100.0, 100.0, 5.0}, {1.0, 0.5, 0.4}, 30.0, 600.0);
  houle::Sphere sp;
  sp.center = {60.0, 120.0, -3.0};
  sp.radius = 0.6;
  sp.floats = true;
  s.boxes = {b};
  s.spheres = {sp};
  auto valid = houle::validate(s);
  ASSERT_TRUE(valid.ok());
  auto field = houle::trace_wave_field(valid.value());
  ASSERT_TRUE(field.ok());
  auto sea = houle::SeaSurface::build(valid.value(), field.value());
  ASSERT_TRUE(sea.ok());
  const auto objects = houle::floating_objects(valid.value(), 3);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_TRUE(objects[0].box);
  EXPECT_EQ(objects[0].render_index, 3u);
  EXPECT_NEAR(objects[0].centre_above, 0.4 - 0.8 * 600.0 / houle::sea_water_density, 1e-12);
  EXPECT_FALSE(objects[1].box);
  EXPECT_EQ(objects[1].render_index, 0u);
  const double k = 2.0 * pi / 100.0, a = 0.5, omega = std::sqrt(houle::gravity * k);
  for (double t : {0.0, 1.7, 4.1, 6.3}) {
    sea->set_time(t);
    for (const houle::FloatingObject& f : objects) {
      const houle::FloatingPose p = houle::floating_pose(f, sea.value(), 0.5);
      // The sea's phase convention: h = A sin(k x - omega t + k x_upstream) with the crest's phase 0
      // at the domain's upstream edge, x = 0.
      const double theta = k * f.x - omega * t;
      EXPECT_NEAR(p.heave, a * std::sin(theta), 0.01 * a) << "t " << t;
      const double slope = a * k * std::cos(theta);
      EXPECT_NEAR(p.normal[0], -slope / std::sqrt(1.0 + slope * slope), 0.02 * a * k) << "t " << t;
      EXPECT_NEAR(p.normal[1], 0.0, 1e-3 * a * k) << "t " << t;
      for (int c = 0; c < 3; ++c) {
        const double expected = (c == 0 ? f.x : c == 1 ? f.y : p.heave) + f.centre_above * p.normal[std::size_t(c)];
        EXPECT_NEAR(p.centre[std::size_t(c)], expected, 1e-9);
      }
      if (f.box) {
        // Orthonormal axes, z the normal, x the yaw's direction turned into the plane (in the plane
        // of that direction and the normal).
        const houle::BoxPose bp = houle::box_pose(f, p);
        const auto dot = [&](int i, int j) {
          double d = 0.0;
          for (std::size_t c = 0; c < 3; ++c) d += double(bp.axes[std::size_t(i)][c]) * bp.axes[std::size_t(j)][c];
          return d;
        };
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) EXPECT_NEAR(dot(i, j), i == j ? 1.0 : 0.0, 1e-6);
          EXPECT_NEAR(bp.axes[2][std::size_t(i)], p.normal[std::size_t(i)], 1e-6);
        }
        const double yaw = 30.0 * pi / 180.0, e[3] = {std::cos(yaw), std::sin(yaw), 0.0};
        const auto& x = bp.axes[0];
        const auto& n = p.normal;
        const double det = x[0] * (e[1] * n[2] - e[2] * n[1]) - x[1] * (e[0] * n[2] - e[2] * n[0]) + x[2] * (e[0] * n[1] - e[1] * n[0]);
        EXPECT_NEAR(det, 0.0, 1e-6);
        EXPECT_GT(x[0] * e[0] + x[1] * e[1], 0.9);
      }
    }
  }
}

bool same_frame_bytes(const houle::Framebuffer& a, const houle::Framebuffer& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

TEST(FloatingObjects, AFrameAloneIsThatFrameOfASequence) {
  // A buoy and a raft in front of the camera: each frame of a sequence has the bytes of the same frame
  // rendered by a fresh Animation, and the buoy moves (the frames are not those of a still buoy).
  houle::Scene s = swell();
  s.camera = {{100.0, 60.0, 3.0}, {100.0, 100.0, 0.0}, 40.0, {}};
  houle::Sphere buoy;
  buoy.center = {98.0, 80.0, 0.0};
  buoy.radius = 1.0;
  buoy.colour = {0.9f, 0.3f, 0.1f};
  buoy.floats = true;
  const houle::Box raft = floating_box({103.0, 84.0, 0.0}, {1.5, 1.0, 0.3}, 20.0, 400.0);
  s.spheres = {buoy};
  s.boxes = {raft};
  const houle::Quality q = houle::quality_preset(houle::QualityPreset::draft);
  constexpr std::uint32_t w = 96, h = 54;
  auto seq = houle::Animation::create(s, q, w, h, 2);
  ASSERT_TRUE(seq.ok()) << seq.error().field << ": " << seq.error().message;
  houle::Framebuffer in_sequence(w, h), alone(w, h), still(w, h);
  for (int n : {0, 1, 2, 3, 10, 11, 40}) {
    const double t = n / 30.0;
    seq->render(t, in_sequence);
    auto fresh = houle::Animation::create(s, q, w, h, 1);
    ASSERT_TRUE(fresh.ok());
    fresh->render(t, alone);
    EXPECT_TRUE(same_frame_bytes(in_sequence, alone)) << "frame " << n;
  }
  houle::Scene fixed = s;
  fixed.spheres[0].floats = false;
  fixed.boxes[0].floats = false;
  auto anchored = houle::Animation::create(fixed, q, w, h, 1);
  ASSERT_TRUE(anchored.ok());
  anchored->render(40 / 30.0, still);
  EXPECT_FALSE(same_frame_bytes(in_sequence, still));
}

}  // namespace
