// What lies where in a scene (scene_geometry.hpp): the place of a point, the islands, the pierheads
// near the domain's edge. The oracles are the scenes' own numbers (a shoal's profile, a wall's
// thickness, the dispersion relation).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_geometry.hpp"

namespace {

using houle::Place;

// A flat sea `depth` m deep, 200 m x 200 m, one train (4 s: L = 24.2 m at 8 m) towards +y.
houle::Scene open_sea(double depth = 8.0) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 200.0, 200.0};
  s.floor.base.depth = depth;
  houle::WaveTrain t;
  t.period = 4.0;
  t.amplitude = 0.2;
  s.trains = {t};
  return s;
}

houle::Shoal round_shoal(houle::Point2 centre, double radius, double height) {
  houle::Shoal sh;
  sh.center = centre;
  sh.semi_axis_a = sh.semi_axis_b = radius;
  sh.height = height;
  return sh;
}

houle::Wall wall(houle::Point2 a, houle::Point2 b, double thickness = 2.0) {
  houle::Wall w;
  w.points = {a, b};
  w.thickness = thickness;
  return w;
}

Place locate(const houle::Scene& s, double x, double y) {
  return houle::locate(s, houle::Bathymetry(s.floor), x, y);
}

TEST(ScenePlaces, WaterLandWallOutside) {
  houle::Scene s = open_sea();
  s.floor.shoals = {round_shoal({100.0, 150.0}, 10.0, 9.0)};  // 1 m above still water at its centre
  s.walls = {wall({20.0, 50.0}, {80.0, 50.0}, 4.0)};            // 2 m either side of y = 50
  EXPECT_EQ(locate(s, 100.0, 20.0), Place::water);
  EXPECT_EQ(locate(s, 100.0, 150.0), Place::land);
  EXPECT_EQ(locate(s, 50.0, 50.0), Place::wall);
  EXPECT_EQ(locate(s, 50.0, 51.99), Place::wall);
  EXPECT_EQ(locate(s, 50.0, 52.01), Place::water);
  EXPECT_EQ(locate(s, 81.9, 50.0), Place::wall);  // the round cap beyond the end
  EXPECT_EQ(locate(s, 82.1, 50.0), Place::water);
  // The domain's edge is inside; a hair beyond it is outside, whatever the floor or walls there.
  EXPECT_EQ(locate(s, 0.0, 200.0), Place::water);
  EXPECT_EQ(locate(s, -0.01, 100.0), Place::outside);
  EXPECT_EQ(locate(s, 100.0, 4800.0), Place::outside);
  EXPECT_EQ(houle::place_name(Place::outside), "outside");
  EXPECT_EQ(houle::place_name(Place::wall), "wall");
  // The profile's land ends where 9 (1 - u)^3 = 8: u = 1 - (8/9)^(1/3), r = 10 sqrt(u) = 1.97 m.
  EXPECT_EQ(locate(s, 101.9, 150.0), Place::land);
  EXPECT_EQ(locate(s, 102.1, 150.0), Place::water);
}

TEST(ScenePlaces, AThinWallIsTheTracersMillimetre) {
  houle::Scene s = open_sea();
  s.walls = {wall({20.0, 50.0}, {80.0, 50.0}, 0.0)};
  EXPECT_EQ(locate(s, 50.0, 50.0005), Place::wall);
  EXPECT_EQ(locate(s, 50.0, 50.002), Place::water);
}

TEST(IslandSearch, AShoalThroughTheSurfaceIsOneIslandAroundItsTop) {
  houle::Scene s = open_sea();
  s.floor.shoals = {round_shoal({100.0, 150.0}, 10.0, 9.0)};
  const auto islands = houle::find_islands(s);
  ASSERT_EQ(islands.size(), 1u);
  // Land reaches 1.97 m from the centre: the grid's land nodes lie within that, at least the centre's.
  EXPECT_GE(islands[0].low.x, 98.0);
  EXPECT_LE(islands[0].low.x, 100.0);
  EXPECT_GE(islands[0].high.y, 150.0);
  EXPECT_LE(islands[0].high.y, 152.0);
}

TEST(IslandSearch, NoneUnderTheSurfaceOrJoinedToTheCoast) {
  houle::Scene s = open_sea();
  s.floor.shoals = {round_shoal({100.0, 150.0}, 10.0, 7.9)};  // 0.1 m under the surface
  EXPECT_TRUE(houle::find_islands(s).empty());
  // A beach whose land reaches the north edge, and a shoal standing on its shoreline: one coast.
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.slope = 0.05;
  s.floor.base.shoreline = {0.0, 180.0};
  s.floor.shoals = {round_shoal({100.0, 178.0}, 10.0, 3.0)};
  EXPECT_TRUE(houle::find_islands(s).empty());
  // Moved 30 m seaward (1.5 m of water), the same shoal is an island.
  s.floor.shoals[0].center.y = 150.0;
  EXPECT_EQ(houle::find_islands(s).size(), 1u);
}

TEST(IslandSearch, AShoalTopSmallerThanACellIsSeen) {
  // Plate 3's rock: 1.1 m of water, a shoal 1.2 m high, 5 m x 3 m: land only within ~0.8 x 0.5 m.
  houle::Scene s = open_sea(1.1);
  // Centred between grid nodes, 0.71 m from the nearest: no node is on land.
  s.floor.shoals = {round_shoal({70.5, 88.5}, 5.0, 1.2)};
  s.floor.shoals[0].semi_axis_b = 3.0;
  const auto islands = houle::find_islands(s);
  ASSERT_EQ(islands.size(), 1u);
  EXPECT_EQ(islands[0].low.x, 70.5);
  EXPECT_EQ(islands[0].high.y, 88.5);
}

TEST(IslandSearch, AHeightMapIsland) {
  houle::Scene s = open_sea();
  houle::HeightMap m;
  m.nx = m.ny = 201;
  m.depth.resize(std::size_t(m.nx) * m.ny);
  for (std::uint32_t j = 0; j < m.ny; ++j) {
    for (std::uint32_t i = 0; i < m.nx; ++i) {
      const double r = std::hypot(double(i) - 60.0, double(j) - 40.0);
      m.depth[std::size_t(j) * m.nx + i] = float(r < 12.0 ? -1.0 + 9.0 * r / 12.0 : 8.0);  // out of the water within 1.33 m
    }
  }
  s.floor.height_map = std::move(m);
  const auto islands = houle::find_islands(s);
  ASSERT_EQ(islands.size(), 1u);
  EXPECT_NEAR(0.5 * (islands[0].low.x + islands[0].high.x), 60.0, 1.0);
  EXPECT_NEAR(0.5 * (islands[0].low.y + islands[0].high.y), 40.0, 1.0);
}

TEST(EdgePierheads, AWallEndWithinAWavelengthOfTheEdge) {
  houle::Scene s = open_sea(60.0);
  s.trains[0].period.reset();
  s.trains[0].wavelength = 4.0;  // deep water at 60 m: L = 4 m
  s.trains[0].direction_deg = 270.0;
  s.walls = {wall({60.0, 100.0}, {197.0, 100.0})};  // its end 3 m from the east edge
  const auto near = houle::pierheads_near_edge(s);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0].wall, 0u);
  EXPECT_EQ(near[0].end.x, 197.0);
  EXPECT_DOUBLE_EQ(near[0].edge_distance, 3.0);
  EXPECT_EQ(near[0].train, 0u);
  const double k = houle::linear_wave(houle::train_omega(s.trains[0]), 60.0).k;
  EXPECT_DOUBLE_EQ(near[0].wavelength, 2.0 * std::numbers::pi / k);
  EXPECT_NEAR(near[0].wavelength, 4.0, 1e-6);

  // A longer train reaches the other end too (60 m from the west edge) only once its wavelength does.
  houle::WaveTrain swell = s.trains[0];
  swell.wavelength = 50.0;
  s.trains.push_back(swell);
  EXPECT_EQ(houle::pierheads_near_edge(s).size(), 1u);
  s.trains[1].wavelength = 70.0;
  const auto both = houle::pierheads_near_edge(s);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0].train, 1u);

  // Nothing to cut: the end 60 m in, diffraction off, the train not traced, or the end on the edge.
  s.trains.pop_back();
  s.walls[0].points[1].x = 140.0;
  EXPECT_TRUE(houle::pierheads_near_edge(s).empty());
  s.walls[0].points[1].x = 197.0;
  s.dwt.diffraction = false;
  EXPECT_TRUE(houle::pierheads_near_edge(s).empty());
  s.dwt.diffraction = true;
  s.trains[0].amplitude = 0.0;
  EXPECT_TRUE(houle::pierheads_near_edge(s).empty());
  s.trains[0].amplitude = 0.2;
  s.walls[0].points[1].x = 199.5;  // its 1 m radius reaches the edge: no free end
  EXPECT_TRUE(houle::pierheads_near_edge(s).empty());
}

}  // namespace
