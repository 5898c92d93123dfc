// A sea state on deep (100 m) open water, 400 m square, without walls or ripples: every component is
// an analytic train. For the sea-state tests (test_sea_state.cpp, test_sea_state_record.cpp).
#pragma once
#include "houle/sim/scene.hpp"

namespace houle_test {

inline houle::Scene open_sea(const houle::SeaState& s) {
  houle::Scene scene;
  scene.domain = {0.0, 0.0, 400.0, 400.0};
  scene.floor.base.depth = 100.0;
  scene.capillary.amplitude = 0.0;
  scene.sea_states = {s};
  return scene;
}

}  // namespace houle_test
