// Scene validation: the built-in scenes are valid, and each kind of mistake names its field.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

#include "houle/sim/animation.hpp"
#include "houle/sim/camera_path.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/scene_keys.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

using houle::Scene;

std::string error_field(const Scene& s) {
  const auto r = houle::validate(s);
  return r.ok() ? std::string("<valid>") : r.error().field;
}

Scene with_train() {
  Scene s;
  houle::WaveTrain t;
  t.period = 8.0;
  t.amplitude = 1.0;
  s.trains = {t, t};
  return s;
}

TEST(Scene, DefaultsAndBuiltinsAreValid) {
  EXPECT_EQ(error_field(Scene{}), "<valid>");
  EXPECT_EQ(error_field(with_train()), "<valid>");
  const auto coast = houle::validate(houle::builtin_coast());
  ASSERT_TRUE(coast.ok()) << coast.error().field << ": " << coast.error().message;
  EXPECT_EQ(coast->trains.size(), 3u);
  EXPECT_EQ(coast->walls.size(), 1u);
  EXPECT_EQ(coast->floor.shoals.size(), 2u);
  EXPECT_GT(coast->capillary.amplitude, 0.0);
  // The jetty is drawn as stone blocks by the renderer, not stored as boxes.
  EXPECT_TRUE(coast->boxes.empty());
  EXPECT_GE(houle::make_render_scene(coast.value()).boxes.size(), 30u);
  const auto fig4 = houle::validate(houle::paper_fig4());
  ASSERT_TRUE(fig4.ok()) << fig4.error().field << ": " << fig4.error().message;
  EXPECT_EQ(fig4->dwt.initial_rays, 70u);
  EXPECT_EQ(fig4->dwt.step, 0.4);
  EXPECT_EQ(fig4->dwt.insertion_distance, 1.0);
  EXPECT_EQ(fig4->domain.x_max - fig4->domain.x_min, 100.0);
}

TEST(Scene, TrainErrorsNameTheField) {
  Scene s = with_train();
  s.trains[1].period = -3.0;
  const auto r = houle::validate(s);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "trains[1].period");
  EXPECT_NE(r.error().message.find("in [1, 60] s"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("-3"), std::string::npos) << r.error().message;

  s = with_train();
  s.trains[0].wavelength = 50.0;  // both given
  EXPECT_EQ(error_field(s), "trains[0].period");
  s.trains[0].period.reset();
  s.trains[0].wavelength.reset();  // neither given
  EXPECT_EQ(error_field(s), "trains[0].period");

  // Stokes limit in deep water: A <= 0.071 L0. T = 8 s: L0 = 99.9 m, limit 7.09 m.
  s = with_train();
  s.trains[1].amplitude = 7.0;
  EXPECT_EQ(error_field(s), "<valid>");
  s.trains[1].amplitude = 7.2;
  EXPECT_EQ(error_field(s), "trains[1].amplitude");
  s.trains[1].amplitude = -0.1;
  EXPECT_EQ(error_field(s), "trains[1].amplitude");

  s = with_train();
  s.trains[0].steepness = 1.5;
  EXPECT_EQ(error_field(s), "trains[0].steepness");
  s = with_train();
  s.trains[0].direction = houle::Point2{0.0, 0.0};
  EXPECT_EQ(error_field(s), "trains[0].direction");
  s = with_train();
  s.trains[0].direction_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_field(s), "trains[0].direction_deg");
}

TEST(Scene, FloorWallAndViewErrors) {
  Scene s;
  s.floor.base.depth = 0.0;
  EXPECT_EQ(error_field(s), "floor.base.depth");
  s = Scene{};
  s.floor.shoals.push_back(houle::Shoal{{10, 10}, -2.0, 3.0, 0.0, 1.0});
  EXPECT_EQ(error_field(s), "floor.shoals[0].semi_axis_a");
  s = Scene{};
  s.floor.height_map = houle::HeightMap{3, 2, {0, 0}, 1.0, {1, 2, 3, 4, 5}, houle::HeightMapMode::absolute};
  EXPECT_EQ(error_field(s), "floor.height_map.depth");
  s.floor.height_map->depth.push_back(std::numeric_limits<float>::infinity());
  EXPECT_EQ(error_field(s), "floor.height_map.depth[5]");

  // A jetty whose second segment leaves the domain entirely is an error; one ending on the edge is not.
  s = Scene{};
  houle::Wall w;
  w.points = {{50, 0}, {50, 60}};
  s.walls = {w};
  EXPECT_EQ(error_field(s), "<valid>");
  s.walls[0].points = {{-50, -50}, {-10, -80}};
  EXPECT_EQ(error_field(s), "walls[0].points[1]");
  s.walls[0].points = {{50, 10}, {50, 10}};
  EXPECT_EQ(error_field(s), "walls[0].points[1]");
  s.walls[0].points = {{50, 10}, {50, 20}};
  s.walls[0].reflection = 1.2;
  EXPECT_EQ(error_field(s), "walls[0].reflection");

  // Camera below the sea floor (flat 20 m: the floor is at z = -20).
  s = Scene{};
  s.camera.position.z = -19.0;
  EXPECT_EQ(error_field(s), "<valid>");
  s.camera.position.z = -21.0;
  EXPECT_EQ(error_field(s), "camera.position.z");
  s = Scene{};
  s.camera.vertical_fov_deg = 180.0;
  EXPECT_EQ(error_field(s), "camera.vertical_fov_deg");
  s = Scene{};
  s.camera.look_at = s.camera.position;
  EXPECT_EQ(error_field(s), "camera.look_at");

  s = Scene{};
  s.capillary.lacunarity = 1.0;
  EXPECT_EQ(error_field(s), "capillary.lacunarity");
  s = Scene{};
  s.sun.elevation_deg = 95.0;
  EXPECT_EQ(error_field(s), "sun.elevation_deg");
  s = Scene{};
  s.water.dominant_wavelength_nm = 200.0;
  EXPECT_EQ(error_field(s), "water.dominant_wavelength_nm");
  s = Scene{};
  s.dwt.step = 0.0;
  EXPECT_EQ(error_field(s), "dwt.step");
  s = Scene{};
  s.domain.x_max = -1.0;
  EXPECT_EQ(error_field(s), "domain.x_max");
  s = Scene{};
  s.spheres.push_back(houle::Sphere{{1, 2, 3}, 1.0, {2.0f, 0.0f, 0.0f}});
  EXPECT_EQ(error_field(s), "spheres[0].colour");
}

TEST(Scene, TrainHelpers) {
  houle::WaveTrain t;
  t.period = 10.0;
  EXPECT_NEAR(houle::train_omega(t), 2.0 * std::numbers::pi / 10.0, 1e-15);
  // The deep-water wavelength of T = 10 s is g T^2 / (2 pi) = 156.13 m: the same omega.
  houle::WaveTrain u;
  u.wavelength = 9.81 * 100.0 / (2.0 * std::numbers::pi);
  EXPECT_NEAR(houle::train_omega(u), houle::train_omega(t), 1e-14);
  t.direction_deg = 90.0;
  EXPECT_NEAR(houle::train_direction(t).x, 0.0, 1e-15);
  EXPECT_NEAR(houle::train_direction(t).y, 1.0, 1e-15);
  t.direction = houle::Point2{3.0, -4.0};
  EXPECT_NEAR(houle::train_direction(t).x, 0.6, 1e-15);
  EXPECT_NEAR(houle::train_direction(t).y, -0.8, 1e-15);
  houle::WaveTrain none;
  EXPECT_EQ(houle::train_omega(none), 0.0);
}

// Values that validated and then made the build refuse, or render garbage (issue 22): refused by
// validate, by the key, with the range and the value in its shortest exact form.
TEST(Scene, WhatCannotRenderDoesNotValidate) {
  const auto refused = [](void (*change)(Scene&)) {
    Scene s = with_train();
    change(s);
    const auto r = houle::validate(s);
    return r.ok() ? std::string("<valid>") : r.error().field + ": " + r.error().message;
  };
  EXPECT_EQ(refused([](Scene& s) { s.camera.position.x = 1e308; }), "camera.position.x: a value in [-100000, 100000] m, got 1e+308");
  EXPECT_EQ(refused([](Scene& s) { s.spheres.push_back({{0, 0, 0}, 1e308}); }), "spheres[0].radius: a value in [0.001, 100000] m, got 1e+308");
  EXPECT_EQ(refused([](Scene& s) { s.boxes.push_back({{0, 0, 0}, {1e308, 1, 1}}); }), "boxes[0].half_extent.x: a value in [0.001, 100000] m, got 1e+308");
  EXPECT_EQ(refused([](Scene& s) { s.water.extra_absorption = 1e308; }), "water.extra_absorption: a value in [0, 100] 1/m, got 1e+308");
  EXPECT_EQ(refused([](Scene& s) { s.floor.shoals.push_back({{10, 10}, 5, 5, 0, 1e308}); }), "floor.shoals[0].height: a value in [-11000, 11000] m, got 1e+308");
  EXPECT_EQ(refused([](Scene& s) { s.capillary.amplitude = 1000; }), "capillary.amplitude: a value in [0, 1] m, got 1000");
  EXPECT_EQ(refused([](Scene& s) { s.capillary.amplitude = 0.5; }).substr(0, 53), "capillary.amplitude: at most 0.365 base_wavelength = ");
  EXPECT_EQ(refused([](Scene& s) { s.walls.push_back({{{0, 50}, {50, 50}}, 1e6}); }), "walls[0].thickness: a value in [0, 20] m, got 1000000");
  EXPECT_EQ(refused([](Scene& s) { s.trains[0].period = 1e-6; }), "trains[0].period: a value in [1, 60] s, got 0.000001");
  EXPECT_EQ(refused([](Scene& s) { s.trains[0].steepness = 1.0000001; }), "trains[0].steepness: a value in [0, 1], got 1.0000001");
  EXPECT_EQ(refused([](Scene& s) { s.camera.position = {0, 0, 6}, s.camera.look_at = {0, 1e-3, 6}; }),
            "camera.look_at: a point at least 0.01 m from camera.position, got 0.001");
  // initial_rays is blamed for its own excess, and an automatic count over the cap on the insertion distance.
  EXPECT_EQ(refused([](Scene& s) { s.dwt.initial_rays = 40000; }), "dwt.initial_rays: at most dwt.max_rays = 32768, got 40000");
  EXPECT_EQ(refused([](Scene& s) { s.dwt.insertion_distance = 1e-3; }).rfind("dwt.insertion_distance: at least 0.0061", 0), 0u);
}

// validate cannot trace, but it can tell when the initial rays alone, crossing the domain at the
// entry step, would already take more samples than the cap.
TEST(Scene, ATraceLikelyToReachItsCapIsWarnedOf) {
  Scene s = with_train();
  s.trains.resize(1);
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.shoreline = {0.0, 190.0};  // rays are traced
  EXPECT_TRUE(houle::trace_cap_warnings(s).empty());
  s.dwt.step = 0.005;  // 201 rays x 40001 steps
  const std::vector<houle::Error> w = houle::trace_cap_warnings(s);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].field, "dwt.max_samples");
  EXPECT_NE(w[0].message.find("201 initial rays cross the 200 m domain in 40001 steps"), std::string::npos) << w[0].message;
  // Under a larger cap the initial rays fit, the rays insertion adds on the beach still do not.
  s.dwt.max_samples = 1u << 24;
  const std::vector<houle::Error> inserted = houle::trace_cap_warnings(s);
  ASSERT_EQ(inserted.size(), 1u);
  EXPECT_NE(inserted[0].message.find("with those that insertion adds"), std::string::npos) << inserted[0].message;
  s.dwt.step = 0.01;
  EXPECT_TRUE(houle::trace_cap_warnings(s).empty());
}

// The initial rays alone may fit under the cap while the rays insertion adds over a refracting
// floor do not: a 1 km beach took 4,194,304 samples (the cap) and stopped, and validate said nothing.
TEST(Scene, ATraceLikelyToReachItsCapWithInsertedRaysIsWarnedOf) {
  Scene s = with_train();
  s.trains.resize(1);
  s.domain = {0.0, 0.0, 1000.0, 1000.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 15.0;
  s.floor.base.slope = 0.02;
  s.floor.base.shoreline = {0.0, 950.0};
  const std::vector<houle::Error> w = houle::trace_cap_warnings(s);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].field, "dwt.max_samples");
  EXPECT_NE(w[0].message.find("with those that insertion adds"), std::string::npos) << w[0].message;
  s.dwt.max_samples = 1u << 24;
  EXPECT_TRUE(houle::trace_cap_warnings(s).empty());
}

// Validation takes its ranges from the key table: a number just outside its key's range is refused
// and named like the key.
TEST(Scene, EveryBoundedNumberKeyIsCheckedByName) {
  namespace keys = houle::scene_keys;
  int checked = 0;
  keys::for_each_section([&]<class S>(const keys::Section<S>& section) {
    for (const keys::Key<S>& k : section.keys) {
      const auto* member = std::get_if<double S::*>(&k.member);
      if (!member || !k.range.bounded()) continue;
      Scene s;
      S* item = section.table_in ? &section.table_in(s) : section.array_in ? &section.array_in(s).emplace_back() : nullptr;
      if (!item || (k.applies && !k.applies(*item))) continue;
      const double lo = k.range.lo, hi = k.range.hi, inf = std::numeric_limits<double>::infinity();
      for (double bad : {k.range.lo_open ? lo : std::nextafter(lo, -inf), k.range.hi_open ? hi : std::nextafter(hi, inf)}) {
        if (std::isinf(bad)) continue;
        (*item).*(*member) = bad;
        EXPECT_EQ(error_field(s), std::string(section.path) + (section.array ? "[0]." : ".") + std::string(k.name)) << bad;
        ++checked;
      }
    }
  });
  EXPECT_GE(checked, 30);
}

}  // namespace

// ---- A moving camera ([[camera.keys]], camera_path.hpp) ----

namespace {

houle::ViewCamera flying_camera() {
  houle::ViewCamera c;
  c.vertical_fov_deg = 50.0;
  c.keys = {{0.0, {0.0, 0.0, 6.0}, {10.0, 100.0, 0.0}, std::nullopt},
            {2.0, {20.0, 1.0, 8.0}, {30.0, 100.0, 0.0}, 40.0},
            {3.0, {30.0, 5.0, 7.0}, {40.0, 90.0, 1.0}, std::nullopt},
            {7.0, {80.0, -4.0, 6.0}, {60.0, 100.0, 0.0}, 60.0}};
  return c;
}

std::array<double, 7> pose_values(const houle::CameraPose& p) {
  return {p.position.x, p.position.y, p.position.z, p.look_at.x, p.look_at.y, p.look_at.z, p.vertical_fov_deg};
}

}  // namespace

TEST(CameraPath, PassesThroughEveryKeyAtItsTimeAndStandsStillOutside) {
  const houle::ViewCamera c = flying_camera();
  for (const houle::CameraKey& k : c.keys) {
    const houle::CameraPose p = houle::camera_pose(c, k.time);
    EXPECT_EQ(pose_values(p), pose_values({k.position, k.look_at, k.vertical_fov_deg.value_or(c.vertical_fov_deg)})) << k.time;
  }
  EXPECT_EQ(pose_values(houle::camera_pose(c, -5.0)), pose_values(houle::camera_pose(c, 0.0)));
  EXPECT_EQ(pose_values(houle::camera_pose(c, std::numeric_limits<double>::quiet_NaN())), pose_values(houle::camera_pose(c, 0.0)));
  EXPECT_EQ(pose_values(houle::camera_pose(c, 1e9)), pose_values(houle::camera_pose(c, 7.0)));
  // Without keys: the still camera.
  houle::ViewCamera still;
  EXPECT_EQ(pose_values(houle::camera_pose(still, 3.0)), pose_values({still.position, still.look_at, still.vertical_fov_deg}));
}

TEST(CameraPath, MovesSmoothlyAndKeepsTheFieldOfViewBetweenItsKeys) {
  // C1: the curves' values and velocities agree on both sides of every inner key (one-sided
  // differences, 1e-6 s), and no velocity jumps between neighbouring samples elsewhere.
  const houle::ViewCamera c = flying_camera();
  const double h = 1e-6;
  for (std::size_t k = 1; k + 1 < c.keys.size(); ++k) {
    const double t = c.keys[k].time;
    const auto before = pose_values(houle::camera_pose(c, t - h)), at = pose_values(houle::camera_pose(c, t)),
               after = pose_values(houle::camera_pose(c, t + h));
    for (std::size_t q = 0; q < 6; ++q) {
      const double left = (at[q] - before[q]) / h, right = (after[q] - at[q]) / h;
      EXPECT_NEAR(left, right, 1e-3 * (1.0 + std::abs(left))) << "key " << k << " value " << q;
    }
  }
  double fov_lo = 1e9, fov_hi = -1e9;
  for (double t = 0.0; t <= 7.0; t += 0.01) {
    const houle::CameraPose p = houle::camera_pose(c, t);
    const std::size_t seg = t < 2.0 ? 0 : t < 3.0 ? 1 : 2;
    const double a = c.keys[seg].vertical_fov_deg.value_or(50.0), b = c.keys[seg + 1].vertical_fov_deg.value_or(50.0);
    EXPECT_GE(p.vertical_fov_deg, std::min(a, b)) << t;
    EXPECT_LE(p.vertical_fov_deg, std::max(a, b)) << t;
    fov_lo = std::min(fov_lo, p.vertical_fov_deg);
    fov_hi = std::max(fov_hi, p.vertical_fov_deg);
  }
  EXPECT_NEAR(fov_lo, 40.0, 1e-6);
  EXPECT_NEAR(fov_hi, 60.0, 1e-6);
}

TEST(CameraPath, KeysAreValidatedOneByOne) {
  Scene s;
  s.camera = flying_camera();
  EXPECT_EQ(error_field(s), "<valid>");
  s.camera.keys[2].time = 2.0;  // not after the key before
  EXPECT_EQ(error_field(s), "camera.keys[2].time");
  s.camera = flying_camera();
  s.camera.keys[1].look_at = s.camera.keys[1].position;
  EXPECT_EQ(error_field(s), "camera.keys[1].look_at");
  s.camera = flying_camera();
  s.camera.keys[3].position.z = -21.0;  // the flat floor is at z = -20
  EXPECT_EQ(error_field(s), "camera.keys[3].position.z");
  s.camera = flying_camera();
  s.camera.keys[0].vertical_fov_deg = 180.0;
  EXPECT_EQ(error_field(s), "camera.keys[0].vertical_fov_deg");
  // The still camera's own position is not used by a moving one.
  s.camera = flying_camera();
  s.camera.position = s.camera.look_at;
  EXPECT_EQ(error_field(s), "<valid>");
}

TEST(CameraPath, AFrameDependsOnlyOnItsTime) {
  // Frame n of a flight is the same whether rendered alone or after others, and its camera is the
  // path's at its time.
  Scene s;
  s.domain = {0.0, 0.0, 100.0, 100.0};
  s.floor.base.depth = 8.0;
  houle::WaveTrain t;
  t.period = 5.0;
  t.amplitude = 0.3;
  s.trains = {t};
  s.camera = flying_camera();
  const houle::Quality q = houle::quality_preset(houle::QualityPreset::draft);
  auto a = houle::Animation::create(s, q, 64, 36, 1), b = houle::Animation::create(s, q, 64, 36, 1);
  ASSERT_TRUE(a.ok() && b.ok());
  houle::Framebuffer fa(64, 36), fb(64, 36);
  a->render(2.5, fa);
  b->render(0.5, fb);
  b->render(6.0, fb);
  b->render(2.5, fb);
  EXPECT_EQ(fa.rgb, fb.rgb);
  const auto expected = houle::make_camera(houle::camera_params(houle::camera_pose(s.camera, 2.5), 64, 36));
  ASSERT_TRUE(expected.ok());
  EXPECT_EQ(std::memcmp(&a->camera(), &expected.value(), sizeof(houle::Camera)), 0);
  b->render(0.5, fb);
  EXPECT_NE(std::memcmp(&a->camera(), &b->camera(), sizeof(houle::Camera)), 0);
}
