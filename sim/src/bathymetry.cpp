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
  build_bins();
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
  if (bins_.nx == 0) {
    for (std::size_t i = 0; i < floor_.shoals.size(); ++i) add_shoal(i, x, y, r);
    for (std::size_t i = 0; i < floor_.bars.size(); ++i) add_bar(i, x, y, r);
    for (std::size_t i = 0; i < floor_.channels.size(); ++i) add_channel(i, x, y, r);
    return r;
  }
  const double u = (x - bins_.x0) / bins_.size_x, v = (y - bins_.y0) / bins_.size_y;
  if (!(u >= 0.0 && u < double(bins_.nx) && v >= 0.0 && v < double(bins_.ny))) {
    for (std::size_t i = 0; i < floor_.bars.size(); ++i) add_bar(i, x, y, r);
    return r;
  }
  const std::size_t bin = std::size_t(v) * bins_.nx + std::size_t(u);
  for (std::uint32_t k = bins_.first[bin]; k < bins_.first[bin + 1]; ++k) {
    const std::uint32_t item = bins_.items[k], i = item & 0x3fffffffu;
    switch (item >> 30) {
      case 0: add_shoal(i, x, y, r); break;
      case 1: add_bar(i, x, y, r); break;
      default: add_channel(i, x, y, r); break;
    }
  }
  return r;
}

void Bathymetry::add_shoal(std::size_t i, double x, double y, DepthSample& r) const noexcept {
  const Shoal& s = floor_.shoals[i];
  const double c = shoal_axis_[2 * i], sn = shoal_axis_[2 * i + 1];
  const double dx = x - s.center.x, dy = y - s.center.y;
  const double xa = (dx * c + dy * sn) / s.semi_axis_a, yb = (-dx * sn + dy * c) / s.semi_axis_b;
  const Profile p = cubic_profile(xa * xa + yb * yb);
  if (p.f == 0.0) return;
  const double du_dx = 2.0 * (xa * c / s.semi_axis_a - yb * sn / s.semi_axis_b);
  const double du_dy = 2.0 * (xa * sn / s.semi_axis_a + yb * c / s.semi_axis_b);
  r.depth -= s.height * p.f;
  r.grad_x -= s.height * p.df * du_dx;
  r.grad_y -= s.height * p.df * du_dy;
}

void Bathymetry::add_bar(std::size_t i, double x, double y, DepthSample& r) const noexcept {
  const Bar& s = floor_.bars[i];
  const double nx = bar_normal_[2 * i], ny = bar_normal_[2 * i + 1];
  const double d = ((x - s.point.x) * nx + (y - s.point.y) * ny) / s.half_width;
  const Profile p = cubic_profile(d * d);
  if (p.f == 0.0) return;
  r.depth -= s.height * p.f;
  r.grad_x -= s.height * p.df * 2.0 * d * nx / s.half_width;
  r.grad_y -= s.height * p.df * 2.0 * d * ny / s.half_width;
}

void Bathymetry::add_channel(std::size_t i, double x, double y, DepthSample& r) const noexcept {
  // Squared distance to a segment is C1 (its gradient is 2 (p - closest point)).
  const Channel& s = floor_.channels[i];
  const double ax = s.to.x - s.from.x, ay = s.to.y - s.from.y;
  const double len2 = ax * ax + ay * ay;
  const double t = len2 > 0.0 ? std::clamp(((x - s.from.x) * ax + (y - s.from.y) * ay) / len2, 0.0, 1.0) : 0.0;
  const double dx = x - (s.from.x + t * ax), dy = y - (s.from.y + t * ay);
  const double w2 = s.half_width * s.half_width;
  const Profile p = cubic_profile((dx * dx + dy * dy) / w2);
  if (p.f == 0.0) return;
  r.depth += s.depth * p.f;
  r.grad_x += s.depth * p.df * 2.0 * dx / w2;
  r.grad_y += s.depth * p.df * 2.0 * dy / w2;
}

void Bathymetry::build_bins() {
  const std::size_t features = floor_.shoals.size() + floor_.bars.size() + floor_.channels.size();
  if (features < 16) return;  // the plain sum is as quick
  // Each feature's box (a shoal's ellipse, a channel's capsule; a bar's point and width, the box only
  // places the grid), grown by a relative margin so that rounding never drops a feature a point sees.
  struct Extent {
    double x0, y0, x1, y1;
  };
  std::vector<Extent> boxes;
  for (std::size_t i = 0; i < floor_.shoals.size(); ++i) {
    const Shoal& s = floor_.shoals[i];
    const double c = std::abs(shoal_axis_[2 * i]), sn = std::abs(shoal_axis_[2 * i + 1]);
    const double hx = s.semi_axis_a * c + s.semi_axis_b * sn, hy = s.semi_axis_a * sn + s.semi_axis_b * c;
    boxes.push_back({s.center.x - hx, s.center.y - hy, s.center.x + hx, s.center.y + hy});
  }
  for (const Bar& s : floor_.bars) {
    boxes.push_back({s.point.x - s.half_width, s.point.y - s.half_width, s.point.x + s.half_width, s.point.y + s.half_width});
  }
  for (const Channel& s : floor_.channels) {
    boxes.push_back({std::min(s.from.x, s.to.x) - s.half_width, std::min(s.from.y, s.to.y) - s.half_width,
                     std::max(s.from.x, s.to.x) + s.half_width, std::max(s.from.y, s.to.y) + s.half_width});
  }
  Extent all = boxes.front();
  for (Extent& b : boxes) {
    const double m = 1e-9 * (std::abs(b.x0) + std::abs(b.x1) + std::abs(b.y0) + std::abs(b.y1)) + 1e-9;
    b = {b.x0 - m, b.y0 - m, b.x1 + m, b.y1 + m};
    all = {std::min(all.x0, b.x0), std::min(all.y0, b.y0), std::max(all.x1, b.x1), std::max(all.y1, b.y1)};
  }
  const std::size_t shoals = floor_.shoals.size(), bars = floor_.bars.size();
  // About two features a bin if they were spread evenly, at most 256 x 256 bins; fewer while the
  // lists would pass 2^22 items (features that cover everything gain nothing from bins).
  std::uint32_t n = std::uint32_t(std::clamp(std::ceil(std::sqrt(double(features) / 2.0)), 1.0, 256.0));
  for (;; n = (n + 1) / 2) {
    bins_.x0 = all.x0;
    bins_.y0 = all.y0;
    bins_.size_x = std::max((all.x1 - all.x0) / n, 1e-9);
    bins_.size_y = std::max((all.y1 - all.y0) / n, 1e-9);
    bins_.nx = bins_.ny = n;
    std::vector<std::vector<std::uint32_t>> lists(std::size_t(n) * n);
    std::size_t total = 0;
    const auto cell = [&](double v, double origin, double size) {
      return std::uint32_t(std::clamp(std::floor((v - origin) / size), 0.0, double(n - 1)));
    };
    for (std::size_t f = 0; f < boxes.size() && total <= (1u << 22); ++f) {
      const Extent& b = boxes[f];
      const bool bar = f >= shoals && f < shoals + bars;
      const std::uint32_t tag = f < shoals ? std::uint32_t(f) : bar ? (1u << 30) | std::uint32_t(f - shoals)
                                                                     : (2u << 30) | std::uint32_t(f - shoals - bars);
      const std::uint32_t i0 = bar ? 0 : cell(b.x0, bins_.x0, bins_.size_x), i1 = bar ? n - 1 : cell(b.x1, bins_.x0, bins_.size_x);
      const std::uint32_t j0 = bar ? 0 : cell(b.y0, bins_.y0, bins_.size_y), j1 = bar ? n - 1 : cell(b.y1, bins_.y0, bins_.size_y);
      for (std::uint32_t j = j0; j <= j1; ++j) {
        for (std::uint32_t i = i0; i <= i1; ++i) {
          if (bar) {
            // The bin meets the bar's strip if its centre is within the half width plus the bin's
            // extent along the bar's normal.
            const double nx = bar_normal_[2 * (f - shoals)], ny = bar_normal_[2 * (f - shoals) + 1];
            const double cx = bins_.x0 + (i + 0.5) * bins_.size_x, cy = bins_.y0 + (j + 0.5) * bins_.size_y;
            const Bar& s = floor_.bars[f - shoals];
            const double reach = s.half_width + 0.5 * (std::abs(nx) * bins_.size_x + std::abs(ny) * bins_.size_y);
            if (std::abs((cx - s.point.x) * nx + (cy - s.point.y) * ny) > reach * (1.0 + 1e-9) + 1e-9) continue;
          }
          lists[std::size_t(j) * n + i].push_back(tag);
          ++total;
        }
      }
    }
    if (total > (1u << 22) && n > 1) continue;
    bins_.first.assign(1, 0);
    bins_.items.clear();
    for (const auto& l : lists) {
      bins_.items.insert(bins_.items.end(), l.begin(), l.end());
      bins_.first.push_back(std::uint32_t(bins_.items.size()));
    }
    return;
  }
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
