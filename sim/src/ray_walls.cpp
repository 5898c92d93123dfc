#include "ray_walls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace houle::detail {
namespace {

constexpr double touch_tolerance = 1e-9;  // m: closer than radius - this is inside

double clamp01(double v) noexcept { return std::clamp(v, 0.0, 1.0); }


// Closest points of segments p0 + u d (u in [0,1]) and a + t e (t in [0,1]) (Ericson, Real-Time
// Collision Detection 5.1.9). Returns u; dist2 receives the squared distance.
double closest_on_chord(double p0x, double p0y, double dx, double dy, const Capsule& c, double& dist2) noexcept {
  const double ex = c.bx - c.ax, ey = c.by - c.ay;
  const double rx = p0x - c.ax, ry = p0y - c.ay;
  const double a = dx * dx + dy * dy, e = ex * ex + ey * ey, f = ex * rx + ey * ry;
  double u = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    u = t = 0.0;
  } else if (a <= 0.0) {
    t = clamp01(f / e);
  } else {
    const double cc = dx * rx + dy * ry;
    if (e <= 0.0) {
      u = clamp01(-cc / a);
    } else {
      const double b = dx * ex + dy * ey, denom = a * e - b * b;
      u = denom > 0.0 ? clamp01((b * f - cc * e) / denom) : 0.0;
      t = (b * u + f) / e;
      if (t < 0.0) {
        t = 0.0;
        u = clamp01(-cc / a);
      } else if (t > 1.0) {
        t = 1.0;
        u = clamp01((b - cc) / a);
      }
    }
  }
  const double qx = p0x + u * dx - (c.ax + t * ex), qy = p0y + u * dy - (c.ay + t * ey);
  dist2 = qx * qx + qy * qy;
  return u;
}

// Cheap reject: the chord's bounding box must overlap the segment's grown by the radius.
bool boxes_overlap(double cx0, double cx1, double cy0, double cy1, const Capsule& c) noexcept {
  return !(cx1 < std::min(c.ax, c.bx) - c.radius || cx0 > std::max(c.ax, c.bx) + c.radius ||
           cy1 < std::min(c.ay, c.by) - c.radius || cy0 > std::max(c.ay, c.by) + c.radius);
}

// First u in [0, 1] where the chord comes within the capsule's radius, or 2 if it never gets deeper than
// the touch tolerance. The distance from a point moving on a line to a segment is convex in u, so it
// crosses the radius at most once before its minimum: bisection is safe.
double capsule_entry(double x0, double y0, double x1, double y1, const Capsule& c) noexcept {
  const double dx = x1 - x0, dy = y1 - y0;
  double min_d2 = 0.0;
  const double u_min = closest_on_chord(x0, y0, dx, dy, c, min_d2);
  const double inner = c.radius - touch_tolerance;
  if (min_d2 >= inner * inner) return 2.0;
  const double r2 = c.radius * c.radius;
  if (point_segment_dist2(x0, y0, c) <= r2) return 0.0;
  double lo = 0.0, hi = u_min;  // outside at lo, inside at hi
  for (int i = 0; i < 60 && hi - lo > 1e-13; ++i) {
    const double mid = 0.5 * (lo + hi);
    (point_segment_dist2(x0 + mid * dx, y0 + mid * dy, c) <= r2 ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

double point_segment_dist2(double px, double py, const Capsule& c) noexcept {
  const double ex = c.bx - c.ax, ey = c.by - c.ay;
  const double len2 = ex * ex + ey * ey;
  const double t = len2 > 0.0 ? clamp01(((px - c.ax) * ex + (py - c.ay) * ey) / len2) : 0.0;
  const double dx = px - (c.ax + t * ex), dy = py - (c.ay + t * ey);
  return dx * dx + dy * dy;
}
std::vector<Capsule> wall_capsules(const std::vector<Wall>& walls) {
  std::vector<Capsule> out;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const double r = std::max(0.5 * walls[w].thickness, min_wall_radius);
    for (std::size_t j = 0; j + 1 < walls[w].points.size(); ++j) {
      const Point2 a = walls[w].points[j], b = walls[w].points[j + 1];
      out.push_back(Capsule{a.x, a.y, b.x, b.y, r, std::uint32_t(w)});
    }
  }
  return out;
}

WallHit first_wall_hit(std::span<const Capsule> capsules, double x0, double y0, double x1, double y1) noexcept {
  WallHit best;
  const double cx0 = std::min(x0, x1), cx1 = std::max(x0, x1), cy0 = std::min(y0, y1), cy1 = std::max(y0, y1);
  for (const Capsule& c : capsules) {
    if (!boxes_overlap(cx0, cx1, cy0, cy1, c)) continue;
    const double u = capsule_entry(x0, y0, x1, y1, c);
    if (u < best.u) best = WallHit{true, u, c.wall};
  }
  return best;
}

bool wall_blocks(std::span<const Capsule> capsules, double x0, double y0, double x1, double y1) noexcept {
  const double cx0 = std::min(x0, x1), cx1 = std::max(x0, x1), cy0 = std::min(y0, y1), cy1 = std::max(y0, y1);
  for (const Capsule& c : capsules) {
    if (!boxes_overlap(cx0, cx1, cy0, cy1, c)) continue;
    // capsule_entry's test for a chord that enters (then its entry is found in [0, 1]).
    double min_d2 = 0.0;
    closest_on_chord(x0, y0, x1 - x0, y1 - y0, c, min_d2);
    const double inner = c.radius - touch_tolerance;
    if (min_d2 < inner * inner) return true;
  }
  return false;
}

bool wall_normal(const std::vector<Capsule>& capsules, std::uint32_t wall, double x, double y, double& nx,
                 double& ny) noexcept {
  double best = std::numeric_limits<double>::infinity();
  for (const Capsule& c : capsules) {
    if (c.wall != wall) continue;
    const double ex = c.bx - c.ax, ey = c.by - c.ay;
    const double len2 = ex * ex + ey * ey;
    const double t = len2 > 0.0 ? clamp01(((x - c.ax) * ex + (y - c.ay) * ey) / len2) : 0.0;
    const double dx = x - (c.ax + t * ex), dy = y - (c.ay + t * ey);
    const double d2 = dx * dx + dy * dy;
    if (d2 < best) best = d2, nx = dx, ny = dy;
  }
  if (!(best > 0.0) || !std::isfinite(best)) return false;
  const double n = std::sqrt(best);
  nx /= n;
  ny /= n;
  return true;
}

std::vector<PierheadSite> pierhead_sites(const Scene& scene, const Bathymetry& floor, double h_min) {
  std::vector<PierheadSite> out;
  const Domain& d = scene.domain;
  for (std::size_t w = 0; w < scene.walls.size(); ++w) {
    const Wall& wall = scene.walls[w];
    const std::size_t n = wall.points.size();
    if (n < 2) continue;
    const double r = std::max(0.5 * wall.thickness, min_wall_radius);
    for (int end = 0; end < 2; ++end) {
      const Point2 m = end == 0 ? wall.points[0] : wall.points[n - 1];
      const Point2 next = end == 0 ? wall.points[1] : wall.points[n - 2];
      const bool inside = m.x > d.x_min + r && m.x < d.x_max - r && m.y > d.y_min + r && m.y < d.y_max - r;
      if (!inside || !(floor.depth(m.x, m.y) > h_min)) continue;
      const double len = std::hypot(next.x - m.x, next.y - m.y);
      if (!(len > 0.0)) continue;
      out.push_back(PierheadSite{m.x, m.y, (next.x - m.x) / len, (next.y - m.y) / len, r, wall.reflection,
                                 std::uint32_t(w)});
    }
  }
  return out;
}

}  // namespace houle::detail
