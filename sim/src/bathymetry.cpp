#include "houle/sim/bathymetry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace houle {
namespace {

constexpr double deg = std::numbers::pi / 180.0;

// (1 - u)^3 for u < 1, else 0; and its derivative in u. C2 at u = 1.
struct Profile {
  double f = 0.0, df = 0.0;
};
Profile cubic_profile(double u) noexcept {
  if (!(u < 1.0)) return {};
  const double a = 1.0 - u;
  return {a * a * a, -3.0 * a * a};
}

// Catmull-Rom weights and their derivatives at t in [0, 1] (samples at -1, 0, 1, 2).
void catmull_rom(double t, double w[4], double dw[4]) noexcept {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
  dw[0] = 0.5 * (-3.0 * t2 + 4.0 * t - 1.0);
  dw[1] = 0.5 * (9.0 * t2 - 10.0 * t);
  dw[2] = 0.5 * (-9.0 * t2 + 8.0 * t + 1.0);
  dw[3] = 0.5 * (3.0 * t2 - 2.0 * t);
}

// Grid coordinate clamped to [0, n - 1]: cell index and fraction; `inside` is false where clamping
// froze the coordinate (the gradient along it is then 0).
struct GridCoord {
  long i = 0;
  double t = 0.0;
  bool inside = true;
};
GridCoord grid_coord(double u, std::uint32_t n) noexcept {
  const double last = double(n - 1);
  GridCoord g;
  if (!(u > 0.0)) {
    g.inside = u == 0.0;
    u = 0.0;
  } else if (u >= last) {
    g.inside = u == last;
    u = last;
  }
  g.i = std::min(long(u), long(n) - 2);
  g.t = u - double(g.i);
  return g;
}

long mirror(long i, long n) noexcept { return i < 0 ? -i : (i >= n ? 2 * (n - 1) - i : i); }

DepthSample sample_height_map(const HeightMap& m, double x, double y) noexcept {
  const GridCoord gx = grid_coord((x - m.origin.x) / m.cell, m.nx);
  const GridCoord gy = grid_coord((y - m.origin.y) / m.cell, m.ny);
  double wx[4], dwx[4], wy[4], dwy[4];
  catmull_rom(gx.t, wx, dwx);
  catmull_rom(gy.t, wy, dwy);
  const long nx = long(m.nx), ny = long(m.ny);
  double v = 0.0, vx = 0.0, vy = 0.0;
  for (int b = 0; b < 4; ++b) {
    // Beyond the grid the stencil is mirrored about the edge sample, which makes the slope across the
    // edge 0 there: the surface joins the clamped (constant) outside with a continuous gradient.
    const long j = mirror(gy.i - 1 + b, ny);
    double row = 0.0, row_dx = 0.0;
    for (int a = 0; a < 4; ++a) {
      const long i = mirror(gx.i - 1 + a, nx);
      const double s = double(m.depth[std::size_t(j * nx + i)]);
      row += wx[a] * s;
      row_dx += dwx[a] * s;
    }
    v += wy[b] * row;
    vx += wy[b] * row_dx;
    vy += dwy[b] * row;
  }
  return {v, gx.inside ? vx / m.cell : 0.0, gy.inside ? vy / m.cell : 0.0};
}

}  // namespace

Bathymetry::Bathymetry(SeaFloor floor) : floor_(std::move(floor)) {
  const FloorBase& b = floor_.base;
  uniform_ = b.kind == FloorKind::flat && floor_.shoals.empty() && floor_.bars.empty() && floor_.channels.empty() &&
             !floor_.height_map;
  double scale = std::numeric_limits<double>::infinity();
  if (b.kind == FloorKind::planar_beach) {
    shore_x_ = std::cos(b.shoreward_deg * deg);
    shore_y_ = std::sin(b.shoreward_deg * deg);
    // The plateau blend spans 2 * blend_ of depth, i.e. 2 * blend_ / slope metres across.
    blend_ = 0.1 * b.depth;
    if (b.slope > 0.0) scale = std::min(scale, 2.0 * blend_ / b.slope);
  }
  for (const Shoal& s : floor_.shoals) {
    scale = std::min({scale, s.semi_axis_a, s.semi_axis_b});
    shoal_axis_.push_back(std::cos(s.orientation_deg * deg));
    shoal_axis_.push_back(std::sin(s.orientation_deg * deg));
  }
  for (const Bar& s : floor_.bars) {
    scale = std::min(scale, s.half_width);
    bar_normal_.push_back(-std::sin(s.along_deg * deg));
    bar_normal_.push_back(std::cos(s.along_deg * deg));
  }
  for (const Channel& s : floor_.channels) scale = std::min(scale, s.half_width);
  if (floor_.height_map) scale = std::min(scale, floor_.height_map->cell);
  length_scale_ = scale;
}

DepthSample Bathymetry::sample(double x, double y) const noexcept {
  DepthSample r;
  const FloorBase& b = floor_.base;
  const bool absolute_map = floor_.height_map && floor_.height_map->mode == HeightMapMode::absolute;
  if (!absolute_map) {
    if (b.kind == FloorKind::flat) {
      r.depth = b.depth;
    } else {
      // raw = slope * (seaward distance from the shoreline); below the plateau minus blend_ it is
      // the plane, above it plus blend_ the plateau, and in between raw - t^2 / (4 blend_) joins
      // them with a continuous slope.
      const double raw = -b.slope * ((x - b.shoreline.x) * shore_x_ + (y - b.shoreline.y) * shore_y_);
      const double t = raw - (b.depth - blend_);
      double d_raw = 1.0;  // d depth / d raw
      if (t <= 0.0) {
        r.depth = raw;
      } else if (t >= 2.0 * blend_) {
        r.depth = b.depth;
        d_raw = 0.0;
      } else {
        r.depth = raw - t * t / (4.0 * blend_);
        d_raw = 1.0 - t / (2.0 * blend_);
      }
      r.grad_x = -b.slope * shore_x_ * d_raw;
      r.grad_y = -b.slope * shore_y_ * d_raw;
    }
  }
  if (floor_.height_map) {
    const DepthSample m = sample_height_map(*floor_.height_map, x, y);
    r.depth += m.depth;
    r.grad_x += m.grad_x;
    r.grad_y += m.grad_y;
  }
  for (std::size_t i = 0; i < floor_.shoals.size(); ++i) {
    const Shoal& s = floor_.shoals[i];
    const double c = shoal_axis_[2 * i], sn = shoal_axis_[2 * i + 1];
    const double dx = x - s.center.x, dy = y - s.center.y;
    const double xa = (dx * c + dy * sn) / s.semi_axis_a, yb = (-dx * sn + dy * c) / s.semi_axis_b;
    const Profile p = cubic_profile(xa * xa + yb * yb);
    if (p.f == 0.0) continue;
    const double du_dx = 2.0 * (xa * c / s.semi_axis_a - yb * sn / s.semi_axis_b);
    const double du_dy = 2.0 * (xa * sn / s.semi_axis_a + yb * c / s.semi_axis_b);
    r.depth -= s.height * p.f;
    r.grad_x -= s.height * p.df * du_dx;
    r.grad_y -= s.height * p.df * du_dy;
  }
  for (std::size_t i = 0; i < floor_.bars.size(); ++i) {
    const Bar& s = floor_.bars[i];
    const double nx = bar_normal_[2 * i], ny = bar_normal_[2 * i + 1];
    const double d = ((x - s.point.x) * nx + (y - s.point.y) * ny) / s.half_width;
    const Profile p = cubic_profile(d * d);
    if (p.f == 0.0) continue;
    r.depth -= s.height * p.f;
    r.grad_x -= s.height * p.df * 2.0 * d * nx / s.half_width;
    r.grad_y -= s.height * p.df * 2.0 * d * ny / s.half_width;
  }
  for (const Channel& s : floor_.channels) {
    // Squared distance to a segment is C1 (its gradient is 2 (p - closest point)).
    const double ax = s.to.x - s.from.x, ay = s.to.y - s.from.y;
    const double len2 = ax * ax + ay * ay;
    const double t = len2 > 0.0 ? std::clamp(((x - s.from.x) * ax + (y - s.from.y) * ay) / len2, 0.0, 1.0) : 0.0;
    const double dx = x - (s.from.x + t * ax), dy = y - (s.from.y + t * ay);
    const double w2 = s.half_width * s.half_width;
    const Profile p = cubic_profile((dx * dx + dy * dy) / w2);
    if (p.f == 0.0) continue;
    r.depth += s.depth * p.f;
    r.grad_x += s.depth * p.df * 2.0 * dx / w2;
    r.grad_y += s.depth * p.df * 2.0 * dy / w2;
  }
  return r;
}

double Bathymetry::min_depth_bound(const Domain& d) const noexcept {
  const FloorBase& b = floor_.base;
  double lo = 0.0;
  const bool absolute_map = floor_.height_map && floor_.height_map->mode == HeightMapMode::absolute;
  if (!absolute_map) {
    if (b.kind == FloorKind::flat) {
      lo = b.depth;
    } else {
      // The base is monotone in the (linear) raw depth: its minimum is at a corner.
      lo = std::numeric_limits<double>::infinity();
      for (double x : {d.x_min, d.x_max}) {
        for (double y : {d.y_min, d.y_max}) {
          const double raw = -b.slope * ((x - b.shoreline.x) * shore_x_ + (y - b.shoreline.y) * shore_y_);
          lo = std::min(lo, std::min(raw, b.depth));
        }
      }
    }
  }
  if (floor_.height_map && !floor_.height_map->depth.empty()) {
    const auto [mn, mx] = std::minmax_element(floor_.height_map->depth.begin(), floor_.height_map->depth.end());
    // Catmull-Rom in 2-D: the negative weights sum to at most 0.28125.
    lo += double(*mn) - 0.28125 * (double(*mx) - double(*mn));
  }
  for (const Shoal& s : floor_.shoals) lo -= std::max(s.height, 0.0);
  for (const Bar& s : floor_.bars) lo -= std::max(s.height, 0.0);
  for (const Channel& s : floor_.channels) lo -= std::max(-s.depth, 0.0);
  return lo;
}

}  // namespace houle
