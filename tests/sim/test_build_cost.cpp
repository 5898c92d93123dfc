// The build's cost, estimated before the build (build_cost.hpp): what validate refuses because no
// quality could build it, and what the commands refuse at theirs. The estimate against measured
// memory is tests/robust/build_cost_sweep.py.
#include <gtest/gtest.h>

#include <string>

#include "houle/sim/animation.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/scene.hpp"

namespace {

houle::Scene beach_4km(int trains) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 4000.0, 4000.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.shoreline = {0.0, 3900.0};
  houle::WaveTrain t;
  t.period = 8.0;
  s.trains.assign(std::size_t(trains), t);
  s.camera.position = {2000.0, -20.0, 6.0};
  s.camera.look_at = {2000.0, 80.0, 0.0};
  return s;
}

std::string refusal(const houle::Scene& s) {
  const auto v = houle::validate(s);
  return v ? std::string("<valid>") : v.error().field + ": " + v.error().message;
}

// Issue 22: one train over 4 km with the tracer's caps at their maxima passed the old check at the
// realtime quality (3.1 GiB estimated) and peaked at 4.71 GiB: it builds at draft quality, and is
// refused before the build at realtime. 16 trains over 4 km validated, and no quality could build
// them: validate refuses them.
TEST(BuildCost, WhatNoQualityCanBuildDoesNotValidate) {
  houle::Scene fine = beach_4km(1);
  fine.dwt.step = fine.dwt.insertion_distance = 0.05;
  fine.dwt.max_rays = houle::scene_limits::max_rays;
  fine.dwt.max_samples = houle::scene_limits::max_samples;
  fine.dwt.on_cap = houle::OnCap::warn;
  EXPECT_EQ(refusal(fine), "<valid>");
  const houle::Quality rt = houle::quality_preset(houle::QualityPreset::realtime);
  const auto at_realtime = houle::check_build_cost(houle::estimate_build_cost(fine, rt, 640 * 360, 2), "at realtime");
  ASSERT_FALSE(at_realtime);
  EXPECT_EQ(at_realtime.error().message.rfind("needs an estimated ", 0), 0u) << at_realtime.error().message;
  EXPECT_EQ(refusal(beach_4km(16)).rfind("scene: needs an estimated ", 0), 0u) << refusal(beach_4km(16));
  EXPECT_NE(refusal(beach_4km(16)).find("at the draft quality"), std::string::npos) << refusal(beach_4km(16));
  // One train at the default caps builds at draft; at film quality (0.25 m cells) it would not.
  const houle::Scene one = beach_4km(1);
  EXPECT_EQ(refusal(one), "<valid>");
  const houle::BuildCost film = houle::estimate_build_cost(one, houle::quality_preset(houle::QualityPreset::film), 1920 * 1080, 2);
  EXPECT_FALSE(houle::check_build_cost(film, "at film quality"));
}

// Time: 1024 walls of many points across a 4 km domain, each carrier move near a wall tested against
// every wall, and an insertion distance spreading each sample over the whole grid.
TEST(BuildCost, BuildsOfHoursAreRefused) {
  houle::Scene s = beach_4km(1);
  s.dwt.insertion_distance = 4000.0;
  const std::string r = refusal(s);
  EXPECT_EQ(r.rfind("scene: would take an estimated ", 0), 0u) << r;
  EXPECT_NE(r.find("over the limit of 300 s"), std::string::npos) << r;
}

// Rays that take no sample still cost: 650,000 initial rays entering dry land.
TEST(BuildCost, InitialRaysCountWithoutSamples) {
  houle::Scene s = beach_4km(1);
  s.domain = {0.0, 0.0, 20.0, 20.0};
  s.floor.base.shoreline = {0.0, -100.0};  // all land
  s.trains[0].direction_deg = 45.0;
  s.dwt.initial_rays = s.dwt.max_rays = 650000;
  const houle::BuildCost c = houle::estimate_build_cost(s, houle::quality_preset(houle::QualityPreset::draft), 0, 1);
  EXPECT_EQ(c.samples, 0u);
  EXPECT_GT(c.rays, 650000u * 40u);
  EXPECT_GT(c.trace_s, 1.0);
}

}  // namespace
