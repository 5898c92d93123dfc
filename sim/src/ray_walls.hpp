// Walls as the ray tracer and the sea surface see them: capsules (segments thickened by a radius) and
// the pierheads at their free ends, where the sea surface diffracts. Internal to houle_sim.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/scene.hpp"

namespace houle::detail {

/// Thinner walls are traced as this radius (m): a thin wall must still stop rays that cross it.
inline constexpr double min_wall_radius = 1e-3;

struct Capsule {
  double ax, ay, bx, by;  ///< segment, m
  double radius;          ///< m, >= min_wall_radius
  std::uint32_t wall;     ///< index into Scene::walls
};

struct WallHit {
  bool hit = false;
  double u = 2.0;          ///< where along the chord (0 = its start, 1 = its end)
  std::uint32_t wall = 0;
};

/// Squared distance from (px, py) to the capsule's segment.
double point_segment_dist2(double px, double py, const Capsule& c) noexcept;

/// Every wall segment of a scene as a capsule.
std::vector<Capsule> wall_capsules(const std::vector<Wall>& walls);

/// First contact of the chord p0 -> p1 with any capsule. A chord that starts inside a capsule (deeper
/// than 1e-9 m) hits at u = 0; one that only touches the surface, or starts on it and moves away or
/// along it, does not hit (so rays can start on a wall's surface and graze its face).
WallHit first_wall_hit(std::span<const Capsule> capsules, double x0, double y0, double x1, double y1) noexcept;
/// first_wall_hit(...).hit without finding where: the chord comes deeper than the touch tolerance into
/// some capsule. No bisection and the first such capsule ends the search (a front of 40,000 rays
/// checked against a thousand capsules took 23 s through first_wall_hit).
bool wall_blocks(std::span<const Capsule> capsules, double x0, double y0, double x1, double y1) noexcept;

/// Outward unit normal of wall `wall`'s surface at the point (x, y) on it (from the nearest of its
/// capsules' axes); false if the point lies on an axis (no direction) or the wall has no capsule.
bool wall_normal(const std::vector<Capsule>& capsules, std::uint32_t wall, double x, double y, double& nx,
                 double& ny) noexcept;

/// A wall end that can diffract: inside the domain (farther than the wall's radius from its edges) and
/// in water deeper than h_min.
struct PierheadSite {
  double x, y;            ///< M, m
  double ux, uy;          ///< unit vector from M along the wall (into the structure)
  double radius;          ///< m, the wall's half thickness (>= min_wall_radius)
  double reflection;      ///< alpha
  std::uint32_t wall;
};
std::vector<PierheadSite> pierhead_sites(const Scene& scene, const Bathymetry& floor, double h_min);

}  // namespace houle::detail
