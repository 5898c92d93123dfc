// The scenes houle knows without a file: the default coast and the paper's Fig. 4 (scenes/coast.toml
// and scenes/paper_fig4.toml are the same as files). Walls are drawn as stone blocks by the renderer
// (make_render_scene), so they need no boxes here.
#include "houle/sim/scene.hpp"

namespace houle {

Scene builtin_coast() {
  Scene s;
  s.domain = {0.0, 0.0, 240.0, 200.0};

  // Shore to the north: still-water line at y = 170, 1:30 beach, 12 m offshore plateau (beyond the
  // domain: the whole domain lies on the slope, 5.7 m deep at its southern edge).
  s.floor.base.kind = FloorKind::planar_beach;
  s.floor.base.depth = 12.0;
  s.floor.base.slope = 1.0 / 30.0;
  s.floor.base.shoreward_deg = 90.0;
  s.floor.base.shoreline = {0.0, 170.0};
  // Two submerged rocks, their tops about 1 m under still water.
  s.floor.shoals.push_back(Shoal{{60.0, 90.0}, 8.0, 8.0, 0.0, 1.6});
  s.floor.shoals.push_back(Shoal{{195.0, 70.0}, 12.0, 7.0, 30.0, 2.2});

  // A jetty from the beach out to sea with a dog-leg; its seaward end (135, 95) is a pierhead in
  // 2.5 m of water.
  Wall jetty;
  jetty.points = {{150.0, 190.0}, {150.0, 115.0}, {135.0, 95.0}};
  jetty.thickness = 4.0;
  jetty.reflection = 0.6;
  jetty.crest_height = 1.8;
  s.walls.push_back(jetty);

  // Three trains from the sea (south), slightly spread in direction and period.
  WaveTrain swell;
  swell.direction_deg = 80.0;
  swell.period = 6.0;
  swell.amplitude = 0.35;
  swell.steepness = 0.6;
  WaveTrain sea;
  sea.direction_deg = 100.0;
  sea.period = 4.2;
  sea.amplitude = 0.2;
  sea.phase = 1.3;
  sea.steepness = 0.5;
  WaveTrain chop;
  chop.direction_deg = 70.0;
  chop.period = 2.8;
  chop.amplitude = 0.08;
  chop.phase = 4.1;
  chop.steepness = 0.4;
  s.trains = {swell, sea, chop};

  s.capillary = CapillaryNoise{0.01, 0.6, 2.0, 6, 1.0};
  s.sun = Sun{250.0, 30.0};
  s.sky = Sky{3.0};
  // On the beach, 6 m up, looking out to sea past the jetty.
  s.camera = ViewCamera{{110.0, 178.0, 6.0}, {140.0, 60.0, 0.0}, 50.0, {}};
  s.water = Water{0.05, 495.0};

  // Shortest wavelength about 12 m (deep) and 8 m near the breakers: 0.75 m steps and rays at most 2 m
  // apart keep >= 10 samples per wavelength along and across the crests.
  s.dwt.step = 0.75;
  s.dwt.insertion_distance = 2.0;
  return s;
}

Scene paper_fig4() {
  Scene s;
  s.domain = {0.0, 0.0, 100.0, 100.0};
  s.floor.base.kind = FloorKind::flat;
  s.floor.base.depth = 10.0;

  // Semi-infinite sea wall: from the west edge to the middle of the domain; pierhead M = (50, 50).
  Wall wall;
  wall.points = {{0.0, 50.0}, {50.0, 50.0}};
  wall.thickness = 1.0;
  wall.reflection = 1.0;
  wall.crest_height = 1.5;
  s.walls.push_back(wall);

  // One train from the south, normal to the wall. The paper gives no wavelength; 2.5 s gives
  // L = 9.76 m (deep at 10 m), so the 100 m scene spans about five wavelengths behind the wall.
  WaveTrain t;
  t.direction_deg = 90.0;
  t.period = 2.5;
  t.amplitude = 0.15;
  t.steepness = 0.5;
  s.trains = {t};

  s.capillary.amplitude = 0.0;
  s.camera = ViewCamera{{50.0, -30.0, 25.0}, {50.0, 60.0, 0.0}, 55.0, {}};

  s.dwt.initial_rays = 70;
  s.dwt.front_width = 0.0;  // the whole 100 m: see the header
  s.dwt.step = 0.4;
  s.dwt.insertion_distance = 1.0;
  return s;
}

}  // namespace houle
