// Where a line crosses a rectangle: the domain's entry front, rays leaving it, walls reaching it.
#pragma once
#include <algorithm>
#include <limits>

#include "houle/sim/scene.hpp"

namespace houle::detail {

/// Parameter range [t0, t1] of the line p + t d inside the rectangle (Liang-Barsky); false if it misses.
inline bool clip_line(const Domain& d, double px, double py, double dx, double dy, double& t0, double& t1) noexcept {
  t0 = -std::numeric_limits<double>::infinity();
  t1 = std::numeric_limits<double>::infinity();
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {px - d.x_min, d.x_max - px, py - d.y_min, d.y_max - py};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double r = q[i] / p[i];
      if (p[i] < 0.0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  return t0 <= t1;
}

}  // namespace houle::detail
