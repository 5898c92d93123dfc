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
#include <cstdint>
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
  /// Shoals, bars and channels a sample visits, on average over the features' box (the build's cost).
  double features_per_sample() const noexcept {
    if (bins_.nx == 0) return double(floor_.shoals.size() + floor_.bars.size() + floor_.channels.size());
    return double(bins_.items.size()) / double(std::size_t(bins_.nx) * bins_.ny);
  }

 private:
  SeaFloor floor_;
  bool uniform_ = true;
  double length_scale_ = std::numeric_limits<double>::infinity();
  // Precomputed: shoreward unit vector and the plateau blend half-width (m of depth); each shoal's
  // axis and each bar's normal as unit vectors (cos, sin).
  double shore_x_ = 0.0, shore_y_ = 1.0, blend_ = 0.0;
  std::vector<double> shoal_axis_, bar_normal_;

  // With many features, a grid of bins over the box where the shoals and channels lie (and the bars'
  // points): a point visits only the features whose support meets its bin, in the order of the full
  // sum (so the depth is the same to the bit); outside the box only the bars, which run on for ever.
  // Items are feature indices tagged by kind in their top two bits (shoal, bar, channel).
  struct Bins {
    double x0 = 0.0, y0 = 0.0, size_x = 0.0, size_y = 0.0;
    std::uint32_t nx = 0, ny = 0;
    std::vector<std::uint32_t> first;  // per bin, its items' start; one past the last at the end
    std::vector<std::uint32_t> items;
  };
  Bins bins_;
  void build_bins();
  void add_shoal(std::size_t i, double x, double y, DepthSample& r) const noexcept;
  void add_bar(std::size_t i, double x, double y, DepthSample& r) const noexcept;
  void add_channel(std::size_t i, double x, double y, DepthSample& r) const noexcept;
};

}  // namespace houle
