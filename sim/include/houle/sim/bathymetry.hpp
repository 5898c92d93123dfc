// Still-water depth h(x, y) and its gradient, evaluated from a SeaFloor (scene.hpp).
//
// h = base (flat, or a planar beach whose offshore plateau is joined by a C1 quadratic blend)
//   + features (shoals, bars, channels: (1 - u)^3 profiles, C2 in u, C1 in (x, y) at worst)
//   (+ or instead of the base: the height map, Catmull-Rom bicubic with the stencil mirrored at the
//   edges, C1 everywhere; constant beyond the edges).
// Everything is analytic with an exact gradient, so the ray equations (docs/physics.md 2.2) see a C1 floor.
// Depth may be negative (land): this module reports the floor as it is, and the callers decide what is
// water (the ray tracer never hands h <= h_min to the dispersion solver). Catmull-Rom can overshoot the
// samples near a steep shoreline by at most 28 % of the local range (2-D weights: negative part
// <= 0.28125); that moves the shoreline inside one cell, never lets a negative depth through as water.
#pragma once
#include <limits>
#include <vector>

#include "houle/sim/scene.hpp"

namespace houle {

struct DepthSample {
  double depth = 0.0;   ///< m, positive below still water; <= 0 is land
  double grad_x = 0.0;  ///< d depth / dx
  double grad_y = 0.0;  ///< d depth / dy
};

class Bathymetry {
 public:
  /// Takes a copy of the floor (height map included). The floor should be valid (validate()).
  explicit Bathymetry(SeaFloor floor);

  DepthSample sample(double x, double y) const noexcept;
  double depth(double x, double y) const noexcept { return sample(x, y).depth; }

  /// Same depth everywhere: a flat base and nothing else.
  bool uniform() const noexcept { return uniform_; }
  /// A lower bound of the depth over the rectangle (exact for flat and planar bases; features and
  /// the map's interpolation overshoot counted at their worst).
  double min_depth_bound(const Domain& domain) const noexcept;
  /// Smallest horizontal length over which the floor changes shape (feature radii, map cell, the
  /// beach's plateau blend), m; +inf for a uniform floor. The ray tracer keeps its steps below a
  /// quarter of it.
  double length_scale() const noexcept { return length_scale_; }

  const SeaFloor& floor() const noexcept { return floor_; }

 private:
  SeaFloor floor_;
  bool uniform_ = true;
  double length_scale_ = std::numeric_limits<double>::infinity();
  // Precomputed: shoreward unit vector and the plateau blend half-width (m of depth); each shoal's
  // axis and each bar's normal as unit vectors (cos, sin).
  double shore_x_ = 0.0, shore_y_ = 1.0, blend_ = 0.0;
  std::vector<double> shoal_axis_, bar_normal_;
};

}  // namespace houle
