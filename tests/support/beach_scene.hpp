// The plane beach the ray and parabolic oracles share: contours along x, the shore to the north
// beyond the domain (10 m deep at y = 0, 2 m at y = 400), an 8 s train of 0.05 m (linear: its
// amplitude dispersion is negligible), a narrow front of rays that enters through the southern edge.
#pragma once
#include "houle/sim/scene.hpp"

namespace houle_test {

inline houle::Scene beach_scene(double direction_deg, double step) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 800.0, 400.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 12.0;
  s.floor.base.slope = 0.02;
  s.floor.base.shoreward_deg = 90.0;
  s.floor.base.shoreline = {0.0, 500.0};
  houle::WaveTrain t;
  t.direction_deg = direction_deg;
  t.period = 8.0;
  t.amplitude = 0.05;
  s.trains = {t};
  s.dwt.front_width = 100.0;
  s.dwt.step = step;
  s.camera.position = {400.0, -10.0, 5.0};
  return s;
}

}  // namespace houle_test
