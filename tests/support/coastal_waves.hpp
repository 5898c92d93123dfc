// docs/rendering.md 1.3's coastal test sea as trochoids: 7 trains from a 0.6 m swell down to 0.55 m chop.
// Shared by the kernel tests and benchmarks so they measure and check the same surface.
#pragma once
#include <cmath>
#include <vector>

#include "houle/surface/gerstner.hpp"

namespace houle::test {

inline std::vector<GerstnerWave> coastal_waves() {
  const double trains[][3] = {{0.6, 40, 0}, {0.3, 17, 25}, {0.15, 8, -40}, {0.08, 4, 70},
                              {0.04, 2.1, 10}, {0.02, 1.1, -65}, {0.01, 0.55, 35}};  // A m, L m, direction deg
  std::vector<GerstnerWave> w;
  int i = 0;
  for (const auto& t : trains) {
    const double k = 2 * 3.141592653589793 / t[1], a = t[2] * 3.141592653589793 / 180;
    w.push_back({float(std::cos(a)), float(std::sin(a)), float(k), float(t[0]), 0.5f, float(std::sqrt(9.81 * k)),
                 float(1.3 * i++)});
  }
  return w;
}

}  // namespace houle::test
