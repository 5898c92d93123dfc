#include "houle/surface/surface_frame.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <utility>

#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"

namespace houle {
namespace {

constexpr std::size_t align_floats = 16;  // 64 bytes: the widest batch (AVX-512) and a cache line
constexpr std::uint32_t max_tile_cells = 64;

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }
bool power_of_two(std::uint32_t n) { return n != 0 && (n & (n - 1)) == 0; }

struct Layout {
  std::size_t stride, level_floats, tile_floats, flag_floats, total_floats;
  std::uint32_t tiles;
};

Layout layout(const SurfaceFrameConfig& c) {
  Layout l{};
  l.stride = round_up(std::size_t(c.cells) + 1, align_floats);
  l.level_floats = round_up(l.stride * (std::size_t(c.cells) + 1), align_floats);
  l.tiles = c.cells / c.tile_cells;
  l.tile_floats = round_up(std::size_t(c.levels) * l.tiles * l.tiles, align_floats);
  l.flag_floats = round_up((std::size_t(c.levels) * l.tiles * l.tiles + 3) / 4, align_floats);  // one byte per tile
  // height, grad_x, grad_y, slope variance, height pairs (two floats a node); four tile arrays; the tiles'
  // fill flags; the fill's x and y rows per part; per part, the bounds pass's 4 column arrays, with a
  // batch of slack after each (the column kernel works in whole batches).
  l.total_floats = 6 * c.levels * l.level_floats + 4 * l.tile_floats + l.flag_floats +
                   2 * SurfaceFrame::max_fill_parts * l.stride +
                   SurfaceFrame::max_fill_parts * 4 * (l.stride + align_floats);
  return l;
}

/// Why `c` is invalid, if it is.
Expected<void> check(const SurfaceFrameConfig& c) {
  if (c.levels < 1 || c.levels > SurfaceFrame::max_levels) {
    return Error{"surface.levels", "an integer in [1, " + std::to_string(SurfaceFrame::max_levels) + "]"};
  }
  if (!power_of_two(c.tile_cells) || c.tile_cells < 2 || c.tile_cells > max_tile_cells) {
    return Error{"surface.tile_cells", "a power of two in [2, " + std::to_string(max_tile_cells) + "]"};
  }
  // >= 4 tiles per side keeps each level inside the next coarser one (nested bounds, morph partner).
  if (c.cells % c.tile_cells != 0 || c.cells < 4 * c.tile_cells || c.cells > 8192) {
    return Error{"surface.cells", "a multiple of tile_cells, at least 4 tile_cells and at most 8192"};
  }
  if (!(c.finest_cell > 0.0f) || !std::isfinite(c.finest_cell) ||
      !std::isfinite(std::ldexp(double(c.finest_cell) * c.cells, int(c.levels)))) {
    return Error{"surface.finest_cell", "a finite cell size > 0 m"};
  }
  if (!(c.blend_fraction > 0.0f && c.blend_fraction <= 0.5f)) return Error{"surface.blend_fraction", "a value in (0, 0.5]"};
  if (!std::isfinite(c.far_height)) return Error{"surface.far_height", "a finite height in m"};
  // Node indices and offsets pass through float in the marcher: keep them below 2^24.
  if (std::size_t(c.levels) * layout(c).level_floats >= (std::size_t(1) << 24)) {
    return Error{"surface", "levels * (cells + 1)^2 too large (node offsets must stay below 2^24)"};
  }
  return {};
}

/// The tile rows node row j of a level belongs to: `upper` (j's own) and `lower` (the one below, on a
/// tile boundary; else the same).
void row_tiles(std::uint32_t j, std::uint32_t tile_cells, std::uint32_t tiles, std::uint32_t& upper, std::uint32_t& lower) {
  upper = std::min(j / tile_cells, tiles - 1);
  lower = j % tile_cells == 0 && j > 0 ? j / tile_cells - 1 : upper;
}

/// Chebyshev distance range [lo, hi] from (cx, cy) to the points of box [x0, x1] x [y0, y1].
void chebyshev_range(double x0, double x1, double y0, double y1, double cx, double cy, double& lo, double& hi) {
  const double ax = std::max({x0 - cx, cx - x1, 0.0}), ay = std::max({y0 - cy, cy - y1, 0.0});
  lo = std::max(ax, ay);
  hi = std::max(std::max(std::fabs(x0 - cx), std::fabs(x1 - cx)), std::max(std::fabs(y0 - cy), std::fabs(y1 - cy)));
}

/// Widen bounds for the rounding of the marcher's float bilinear interpolation (a few ulps
/// of the heights involved; 2^-20 relative is 16 ulps).
void add_margins(float& h_min, float& h_max, float& sx, float& sy) {
  const float m = std::ldexp(std::max(std::fabs(h_min), std::fabs(h_max)), -20) + 1e-30f;
  h_min -= m;
  h_max += m;
  sx += std::ldexp(sx, -16) + 1e-30f;
  sy += std::ldexp(sy, -16) + 1e-30f;
}

}  // namespace

void SurfaceFrame::FreeAligned::operator()(float* p) const noexcept {
  ::operator delete(p, std::align_val_t{align_floats * sizeof(float)});
}

std::size_t SurfaceFrame::bytes_bound(const SurfaceFrameConfig& config) noexcept {
  if (!check(config)) return 0;
  return layout(config).total_floats * sizeof(float);
}

Expected<SurfaceFrame> SurfaceFrame::create(const SurfaceFrameConfig& config) {
  if (Expected<void> valid = check(config); !valid) return valid.error();
  const Layout l = layout(config);
  float* p = static_cast<float*>(
      ::operator new(l.total_floats * sizeof(float), std::align_val_t{align_floats * sizeof(float)}, std::nothrow));
  if (p == nullptr) return Error{"surface", "out of memory (" + std::to_string(l.total_floats * sizeof(float)) + " bytes)"};
  SurfaceFrame f;
  f.config_ = config;
  f.memory_.reset(p);
  f.stride_ = l.stride;
  f.level_floats_ = l.level_floats;
  f.tiles_ = l.tiles;
  // Zeroed once so that an unfilled frame reads as flat water rather than garbage.
  std::fill(p, p + l.total_floats, 0.0f);
  const std::size_t grid = config.levels * l.level_floats;
  f.height_ = p;
  f.grad_x_ = p + grid;
  f.grad_y_ = p + 2 * grid;
  f.variance_ = p + 3 * grid;
  f.height_pairs_ = p + 4 * grid;
  f.tile_min_ = p + 6 * grid;
  f.tile_max_ = f.tile_min_ + l.tile_floats;
  f.tile_sx_ = f.tile_max_ + l.tile_floats;
  f.tile_sy_ = f.tile_sx_ + l.tile_floats;
  // Raw storage from operator new: bytes may live in it.
  f.needed_ = reinterpret_cast<std::uint8_t*>(f.tile_sy_ + l.tile_floats);
  f.row_x_ = f.tile_sy_ + l.tile_floats + l.flag_floats;
  f.row_y_ = f.row_x_ + SurfaceFrame::max_fill_parts * l.stride;
  f.scratch_ = f.row_y_ + SurfaceFrame::max_fill_parts * l.stride;
  f.begin_frame(0.0f, 0.0f);
  f.global_ = {config.far_height, config.far_height, 0.0f, 0.0f};
  return f;
}

SurfaceFrame::SurfaceFrame(SurfaceFrame&&) noexcept = default;
SurfaceFrame& SurfaceFrame::operator=(SurfaceFrame&&) noexcept = default;
SurfaceFrame::~SurfaceFrame() = default;

void SurfaceFrame::begin_frame(float centre_x, float centre_y) noexcept {
  morphed_ = false;
  centre_x_ = centre_x;
  centre_y_ = centre_y;
  viewer_ = {};
  const double n = config_.cells, tc = config_.tile_cells;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    const double cell = std::ldexp(double(config_.finest_cell), int(l)), tile = tc * cell;
    SurfaceLevel& s = levels_[l];
    // Origin on the tile lattice nearest to a grid centred on c: nodes stay at fixed world points.
    s.origin_x = float(std::floor((centre_x - 0.5 * n * cell) / tile + 0.5) * tile);
    s.origin_y = float(std::floor((centre_y - 0.5 * n * cell) / tile + 0.5) * tile);
    s.cell = float(cell);
    // The origin is within half a tile of centred; one more cell keeps bilinear taps inside.
    s.reach = float((0.5 * n - 0.5 * tc - 1.0) * cell);
  }
  // The tiles anything can sample: those reaching level l's annulus, from where level l - 1 starts to
  // morph toward it out to its reach (one cell of slack for rounding).
  const double beta = config_.blend_fraction;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    const SurfaceLevel& s = levels_[l];
    const double cell = s.cell, tile = tc * cell;
    const double inner = l == 0 ? -1.0 : (1.0 - beta) * levels_[l - 1].reach - cell, outer = double(s.reach) + cell;
    for (std::uint32_t tj = 0; tj < tiles_; ++tj) {
      for (std::uint32_t ti = 0; ti < tiles_; ++ti) {
        const double x0 = s.origin_x + ti * tile, y0 = s.origin_y + tj * tile;
        double r_lo, r_hi;
        chebyshev_range(x0 - cell, x0 + tile + cell, y0 - cell, y0 + tile + cell, centre_x, centre_y, r_lo, r_hi);
        needed_[(std::size_t(l) * tiles_ + tj) * tiles_ + ti] = r_lo <= outer && r_hi >= inner;
      }
    }
  }
}

namespace {

/// A horizontal wedge: the rays from `apex` between directions e1 and e2 (counter-clockwise, < 180 degrees).
struct Wedge {
  double ax, ay, e1x, e1y, e2x, e2y;

  bool contains(double x, double y) const {
    const double vx = x - ax, vy = y - ay;
    return e1x * vy - e1y * vx >= 0.0 && vx * e2y - vy * e2x >= 0.0;
  }
  /// Whether the ray from the apex along (dx, dy) meets the box (slab method).
  bool ray_meets(double dx, double dy, double x0, double x1, double y0, double y1) const {
    double lo = 0.0, hi = std::numeric_limits<double>::infinity();
    const double o[2] = {ax, ay}, d[2] = {dx, dy}, b0[2] = {x0, y0}, b1[2] = {x1, y1};
    for (int k = 0; k < 2; ++k) {
      if (d[k] == 0.0) {
        if (o[k] < b0[k] || o[k] > b1[k]) return false;
        continue;
      }
      double t0 = (b0[k] - o[k]) / d[k], t1 = (b1[k] - o[k]) / d[k];
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
    }
    return lo <= hi;
  }
  /// Convex sets: they meet iff a box corner is inside the wedge or an edge ray meets the box.
  bool meets_box(double x0, double x1, double y0, double y1) const {
    return contains(x0, y0) || contains(x1, y0) || contains(x0, y1) || contains(x1, y1) ||
           ray_meets(e1x, e1y, x0, x1, y0, y1) || ray_meets(e2x, e2y, x0, x1, y0, y1);
  }
};

/// A convex polygon in the horizontal plane, counter-clockwise.
struct Footprint {
  static constexpr int max_points = 9;
  double x[max_points], y[max_points];
  int n = 0;

  /// The convex hull of the points (Andrew's monotone chain); collinear points are dropped.
  static Footprint hull(double (&px)[max_points], double (&py)[max_points], int count) {
    // By x, then y: insertion sort (std::sort's insertion pass, unrolled for its threshold of 16,
    // trips gcc 12's -Warray-bounds on nine elements).
    int order[max_points];
    for (int i = 0; i < count; ++i) {
      int j = i;
      for (; j > 0 && (px[order[j - 1]] > px[i] || (px[order[j - 1]] == px[i] && py[order[j - 1]] > py[i])); --j) {
        order[j] = order[j - 1];
      }
      order[j] = i;
    }
    const auto turn = [&](int o, int a, int b) {
      return (px[a] - px[o]) * (py[b] - py[o]) - (py[a] - py[o]) * (px[b] - px[o]);
    };
    int chain[2 * max_points], k = 0;
    for (int i = 0; i < count; ++i) {  // lower hull
      while (k >= 2 && turn(chain[k - 2], chain[k - 1], order[i]) <= 0.0) --k;
      chain[k++] = order[i];
    }
    for (int i = count - 2, lower = k + 1; i >= 0; --i) {  // upper hull
      while (k >= lower && turn(chain[k - 2], chain[k - 1], order[i]) <= 0.0) --k;
      chain[k++] = order[i];
    }
    Footprint f;
    f.n = std::max(k - 1, 1);  // the last point repeats the first
    for (int i = 0; i < f.n; ++i) {
      f.x[i] = px[chain[i]];
      f.y[i] = py[chain[i]];
    }
    return f;
  }

  /// Separating axes: the box's (the polygon's extent) and the polygon's edge normals.
  bool meets_box(double x0, double x1, double y0, double y1) const {
    const auto [xlo, xhi] = std::minmax_element(x, x + n);
    const auto [ylo, yhi] = std::minmax_element(y, y + n);
    if (*xhi < x0 || *xlo > x1 || *yhi < y0 || *ylo > y1) return false;
    for (int i = 0; i < n && n >= 3; ++i) {
      const int j = i + 1 == n ? 0 : i + 1;
      const double ex = x[j] - x[i], ey = y[j] - y[i];
      // Outward normal (ey, -ex); the box is outside when its nearest corner is.
      const double near = ey * ((ey > 0.0 ? x0 : x1) - x[i]) - ex * ((ex < 0.0 ? y0 : y1) - y[i]);
      if (near > 0.0) return false;
    }
    return true;
  }
};

}  // namespace

void SurfaceFrame::restrict_to_view(const Camera& cam, float z_lo, float z_hi) noexcept {
  // The frustum is the cone spanned by the four corner rays.
  const double th = 0.5 * double(cam.pixel_scale) * cam.width, tv = 0.5 * double(cam.pixel_scale) * cam.height;
  const auto corners = [&](double widen, double (&d)[4][3]) {
    for (int k = 0; k < 4; ++k) {
      const double a = (k & 1 ? th : -th) * widen, b = (k & 2 ? tv : -tv) * widen;
      for (int c = 0; c < 3; ++c) d[k][c] = double(cam.forward[c]) + a * double(cam.right[c]) + b * double(cam.up[c]);
    }
  };
  const double tc = config_.tile_cells;
  const auto keep_meeting = [&](const auto& region) {
    for (std::uint32_t l = 0; l < config_.levels; ++l) {
      const SurfaceLevel& s = levels_[l];
      const double cell = s.cell, tile = tc * cell;
      for (std::uint32_t tj = 0; tj < tiles_; ++tj) {
        for (std::uint32_t ti = 0; ti < tiles_; ++ti) {
          std::uint8_t& n = needed_[(std::size_t(l) * tiles_ + tj) * tiles_ + ti];
          if (n == 0) continue;
          const double x0 = s.origin_x + ti * tile, y0 = s.origin_y + tj * tile;
          n = region.meets_box(x0 - cell, x0 + tile + cell, y0 - cell, y0 + tile + cell);
        }
      }
    }
  };
  // With a slab and every corner ray crossing its planes the same way, the rays' samples lie in the
  // frustum's slice of the slab: the hull of where the corner rays are in it, and of the camera's own
  // point (SurfaceFrame::height_at is read there).
  const double o[3] = {cam.position[0], cam.position[1], cam.position[2]};
  double corner[4][3];
  corners(1.001, corner);
  int down = 0, up = 0;
  for (const auto& d : corner) {
    down += d[2] < -1e-6;
    up += d[2] > 1e-6;
  }
  if (std::isfinite(z_lo) && std::isfinite(z_hi) && z_lo <= z_hi && (down == 4 || up == 4)) {
    double px[Footprint::max_points], py[Footprint::max_points];
    int count = 0;
    px[count] = o[0];
    py[count++] = o[1];
    for (const auto& d : corner) {
      const double ta = (double(z_lo) - o[2]) / d[2], tb = (double(z_hi) - o[2]) / d[2];
      const double t1 = std::max(ta, tb);
      if (t1 < 0.0) continue;  // this ray never reaches the slab
      for (double t : {std::max(0.0, std::min(ta, tb)), t1}) {
        px[count] = o[0] + t * d[0];
        py[count++] = o[1] + t * d[1];
      }
    }
    keep_meeting(Footprint::hull(px, py, count));
    return;
  }
  // Otherwise their horizontal projection: the wedge spanned by the corner rays' projections, or the
  // whole plane when the frustum holds the vertical.
  for (double vz : {-1.0, 1.0}) {
    const double x = vz * cam.right[2], y = vz * cam.up[2], z = vz * cam.forward[2];
    if (z > 0.0 && std::fabs(x) <= th * z * 1.001 && std::fabs(y) <= tv * z * 1.001) return;  // everything visible
  }
  corners(1.0, corner);
  const double fx = cam.forward[0], fy = cam.forward[1], fn = std::hypot(fx, fy);
  if (!(fn > 1e-6)) return;
  double lo = 0.0, hi = 0.0;
  for (const auto& d : corner) {
    if (!(std::hypot(d[0], d[1]) > 1e-9)) return;  // a corner ray is vertical
    const double angle = std::atan2(fx * d[1] - fy * d[0], fx * d[0] + fy * d[1]);  // from the forward azimuth
    lo = std::min(lo, angle);
    hi = std::max(hi, angle);
  }
  constexpr double margin = 1e-3;  // rad
  lo -= margin;
  hi += margin;
  if (hi - lo >= 3.1) return;  // (nearly) a half plane or more: keep everything
  const double phi = std::atan2(fy, fx);
  keep_meeting(Wedge{o[0], o[1], std::cos(phi + lo), std::sin(phi + lo), std::cos(phi + hi), std::sin(phi + hi)});
}

void SurfaceFrame::set_viewer(const Camera& camera) noexcept {
  viewer_ = {0.0f, camera.pixel_angle, camera.position[0], camera.position[1], camera.position[2] - config_.far_height};
}

bool SurfaceFrame::tile_filled(std::uint32_t l, std::uint32_t tile_x, std::uint32_t tile_y) const noexcept {
  HOULE_ASSERT(l < config_.levels && tile_x < tiles_ && tile_y < tiles_, "SurfaceFrame::tile_filled: a tile of the frame");
  return needed_[(std::size_t(l) * tiles_ + tile_y) * tiles_ + tile_x] != 0;
}

void SurfaceFrame::set_noise_bounds(float height_m, float slope) noexcept {
  noise_height_ = std::isfinite(height_m) && height_m > 0.0f ? height_m : 0.0f;
  noise_slope_ = std::isfinite(slope) && slope > 0.0f ? slope : 0.0f;
}

float SurfaceFrame::slope_bound() const noexcept {
  return std::sqrt(global_.slope_x * global_.slope_x + global_.slope_y * global_.slope_y) + noise_slope_;
}

TileBounds SurfaceFrame::tile(std::uint32_t l, std::uint32_t tx, std::uint32_t ty) const noexcept {
  HOULE_ASSERT(l < config_.levels && tx < tiles_ && ty < tiles_, "SurfaceFrame::tile: a tile of the frame");
  const std::size_t i = (std::size_t(l) * tiles_ + ty) * tiles_ + tx;
  return {tile_min_[i], tile_max_[i], tile_sx_[i], tile_sy_[i]};
}

SurfaceFrameView SurfaceFrame::view() const noexcept {
  SurfaceFrameView v;
  v.levels = config_.levels;
  v.cells = config_.cells;
  v.tile_cells = config_.tile_cells;
  v.tiles_per_side = tiles_;
  v.stride = stride_;
  v.level_floats = level_floats_;
  v.centre_x = centre_x_;
  v.centre_y = centre_y_;
  v.blend_fraction = config_.blend_fraction;
  v.far_height = config_.far_height;
  v.height = height_;
  v.height_pairs = height_pairs_;
  v.grad_x = grad_x_;
  v.grad_y = grad_y_;
  v.slope_variance = variance_;
  v.tile_min = tile_min_;
  v.tile_max = tile_max_;
  v.tile_slope_x = tile_sx_;
  v.tile_slope_y = tile_sy_;
  v.level = levels_.data();
  v.global = global_;
  return v;
}

void SurfaceFrame::fill(SurfaceSampler sampler, void* context) noexcept {
  HOULE_ASSERT(sampler != nullptr, "SurfaceFrame::fill: a sampler");
  begin_fill(sampler, context);
  fill_part(sampler, context, 0, 1);
  finish_frame();
}

template <class F>
void SurfaceFrame::for_each_run(std::uint32_t l, std::uint32_t j, F&& f) const noexcept {
  const std::uint32_t tc = config_.tile_cells;
  const std::uint8_t* need = needed_ + std::size_t(l) * tiles_ * tiles_;
  // The tile rows this node row belongs to (two on a tile boundary); runs of needed tiles.
  std::uint32_t upper, lower;
  row_tiles(j, tc, tiles_, upper, lower);
  const auto wanted = [&](std::uint32_t t) { return need[upper * tiles_ + t] != 0 || need[lower * tiles_ + t] != 0; };
  for (std::uint32_t ti = 0; ti < tiles_;) {
    if (!wanted(ti)) {
      ++ti;
      continue;
    }
    std::uint32_t end = ti + 1;
    while (end < tiles_ && wanted(end)) ++end;
    f(std::size_t(ti) * tc, std::size_t(end - ti) * tc + 1);
    ti = end;
  }
}

namespace {
/// A run's kept floats: its nodes rounded up to 16 (SurfaceSamples::keep).
std::size_t kept_run_floats(std::size_t count, std::size_t per_node) noexcept { return (count + 15) / 16 * 16 * per_node; }
}  // namespace

bool SurfaceFrame::kept_run(std::uint32_t l, std::uint32_t j, std::size_t i0, std::size_t count) noexcept {
  std::uint8_t* written = keep_written_.get() + (std::size_t(l) * (config_.cells + 1) + j) * keep_row_blocks_;
  const std::size_t first = i0 / 16, last = (i0 + count - 1) / 16;
  // Nodes of the last 16 the run needs; the sampler writes whole batches, so in the last 16 it writes
  // past them what is not the nodes'.
  const auto needs = [&](std::size_t b) { return b < last ? std::size_t(16) : i0 + count - 16 * last; };
  bool kept = true;
  for (std::size_t b = first; b <= last && kept; ++b) kept = written[b] >= needs(b);
  if (!kept) {
    for (std::size_t b = first; b <= last; ++b) written[b] = std::uint8_t(needs(b));
  }
  return kept;
}

void SurfaceFrame::begin_fill(SurfaceSampler sampler, void* context) noexcept {
  morphed_ = bounded_ = false;
  if (keep_per_node_ == 0) return;
  if (sampler != keep_sampler_ || context != keep_context_) {  // another sea: nothing kept is its
    for (KeptLevel& k : keep_levels_) k.current = false;
    keep_sampler_ = sampler;
    keep_context_ = context;
  }
  const std::size_t level_flags = std::size_t(config_.cells + 1) * keep_row_blocks_;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    KeptLevel& k = keep_levels_[l];
    const SurfaceLevel& s = levels_[l];
    if (k.current && k.origin_x == s.origin_x && k.origin_y == s.origin_y) {
      k.fresh = false;
      continue;
    }
    std::fill_n(keep_written_.get() + l * level_flags, level_flags, std::uint8_t(0));
    k.origin_x = s.origin_x;
    k.origin_y = s.origin_y;
    k.current = k.fresh = true;
  }
}

void SurfaceFrame::fill_part(SurfaceSampler sampler, void* context, unsigned part, unsigned parts) noexcept {
  HOULE_ASSERT(sampler != nullptr, "SurfaceFrame::fill_part: a sampler");
  HOULE_ASSERT(parts >= 1 && parts <= max_fill_parts && part < parts, "SurfaceFrame::fill_part: part < parts <= max_fill_parts");
  HOULE_ASSERT(keep_per_node_ == 0 || (sampler == keep_sampler_ && context == keep_context_),
               "SurfaceFrame::fill_part: begin_fill's sampler and context");
  const std::uint32_t nodes = config_.cells + 1;
  float* row_x = row_x_ + std::size_t(part) * stride_;
  float* row_y = row_y_ + std::size_t(part) * stride_;
  // Node rows are dealt out round-robin over all levels: parts get equal shares of every level.
  std::size_t row_index = 0;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    const SurfaceLevel& s = levels_[l];
    NodeFootprint footprint = viewer_;
    footprint.cell = s.cell;
    for (std::uint32_t j = 0; j < nodes; ++j, ++row_index) {
      if (row_index % parts != part) continue;
      const float y = s.origin_y + float(j) * s.cell;
      const std::size_t o = j * stride_;
      float* const keep_row = keep_ && !keep_levels_[l].fresh
                                  ? keep_.get() + l * keep_level_floats_ + j * kept_run_floats(nodes, keep_per_node_)
                                  : nullptr;
      for_each_run(l, j, [&](std::size_t i0, std::size_t count) {
        float* const keep = keep_row != nullptr ? keep_row + i0 * keep_per_node_ : nullptr;
        // Node coordinates exactly as the marcher's grid coordinates invert them: origin + i * cell.
        for (std::size_t i = 0; i < count; ++i) row_x[i] = s.origin_x + float(i0 + i) * s.cell;
        std::fill(row_y, row_y + count, y);
        SurfaceSamples run{row_x, row_y, count, footprint, heights(l) + o + i0, grad_x(l) + o + i0, grad_y(l) + o + i0,
                           slope_variance(l) + o + i0, keep, keep != nullptr && kept_run(l, j, i0, count)};
        sampler(context, run);
      });
    }
  }
}

std::size_t SurfaceFrame::kept_bytes_bound(const SurfaceFrameConfig& config, std::size_t floats_per_node) noexcept {
  // A run starts on a tile's first node: at a multiple of 16, each node's place is the same in every run.
  if (!check(config) || config.tile_cells % 16 != 0) return 0;
  const std::size_t nodes = config.cells + 1, level = nodes * kept_run_floats(nodes, floats_per_node) * sizeof(float);
  return level <= max_kept_bytes / config.levels ? config.levels * level : 0;
}

void SurfaceFrame::keep_static(std::size_t floats_per_node) noexcept {
  keep_.reset();
  keep_written_.reset();
  keep_level_floats_ = keep_per_node_ = keep_row_blocks_ = 0;
  keep_sampler_ = nullptr;
  keep_context_ = nullptr;
  for (KeptLevel& k : keep_levels_) k = {};
  const std::size_t bytes = floats_per_node > 0 ? kept_bytes_bound(config_, floats_per_node) : 0;
  if (bytes == 0) return;
  const std::size_t nodes = config_.cells + 1, row_blocks = (nodes + 15) / 16;
  // Not value-initialised: the pages a view never needs are never touched.
  keep_.reset(new (std::nothrow) float[bytes / sizeof(float)]);
  keep_written_.reset(new (std::nothrow) std::uint8_t[std::size_t(config_.levels) * nodes * row_blocks]);
  if (!keep_ || !keep_written_) {  // an optimisation only: without the memory, none
    keep_.reset();
    keep_written_.reset();
    return;
  }
  keep_level_floats_ = bytes / sizeof(float) / config_.levels;
  keep_per_node_ = floats_per_node;
  keep_row_blocks_ = row_blocks;
}

void SurfaceFrame::finish_frame() noexcept {
  if (!morphed_) morph_part(0, 1);
  if (!bounded_) bound_part(0, 1);
  for (std::uint32_t l = 1; l < config_.levels; ++l) merge_finer(l);
  finish_global();
  bounded_ = false;  // a later finish_frame() (without a new fill) bounds again, as before
}

void SurfaceFrame::morph_part(unsigned part, unsigned parts) noexcept {
  HOULE_ASSERT(parts >= 1 && parts <= max_fill_parts && part < parts, "SurfaceFrame::morph_part: part < parts <= max_fill_parts");
  // Level l's morph reads level l + 1 where that level is not morphed itself (its band lies beyond
  // level l's reach), so neither the order of the levels nor of the rows matters. Node rows are dealt
  // out round-robin over all levels, as in fill_part.
  std::size_t row_index = 0;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    for (std::uint32_t j = 0; j <= config_.cells; ++j, ++row_index) {
      if (row_index % parts == part) morph_row(l, j);
    }
  }
  // Read by finish_frame() once every part is done; one part writes it, so parts never race on it.
  if (part == 0) morphed_ = true;
}

void SurfaceFrame::bound_part(unsigned part, unsigned parts) noexcept {
  HOULE_ASSERT(parts >= 1 && parts <= max_fill_parts && part < parts, "SurfaceFrame::bound_part: part < parts <= max_fill_parts");
  std::size_t row_index = 0;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    for (std::uint32_t tj = 0; tj < tiles_; ++tj, ++row_index) {
      if (row_index % parts == part) bound_tile_row(l, tj, part);
    }
  }
  // The morph is done: the pairs take the final heights. Node rows round-robin, as in fill_part (a
  // pair row reads only its own heights).
  row_index = 0;
  for (std::uint32_t l = 0; l < config_.levels; ++l) {
    for (std::uint32_t j = 0; j <= config_.cells; ++j, ++row_index) {
      if (row_index % parts == part) pair_row(l, j);
    }
  }
  if (part == 0) bounded_ = true;  // as morphed_ above
}

namespace {

/// Per node column of a tile row: the bounds pass's statistics (detail::ColumnStatsJob), which the
/// tiles then reduce over their own columns.
struct ColumnStats {
  float* lo;
  float* hi;
  float* dx;
  float* dy;

  /// Reduces columns [i0, i0 + tc] into a tile's bounds (height differences, not yet slopes).
  void reduce(std::size_t i0, std::uint32_t tc, float& l, float& h, float& sx, float& sy) const {
    for (std::size_t i = i0; i <= i0 + tc; ++i) {
      l = std::min(l, lo[i]);
      h = std::max(h, hi[i]);
      sy = std::max(sy, dy[i]);
      if (i < i0 + tc) sx = std::max(sx, dx[i]);
    }
  }
};

}  // namespace

void SurfaceFrame::morph_row(std::uint32_t l, std::uint32_t j) noexcept {
  // Geomorphing (as in CDLOD): in the outer band of its reach a level's nodes move toward the next
  // coarser level's bilinear surface, reaching it a cell before the reach so that every cell touching
  // the reach is wholly the coarser surface. H stays one bilinear fetch per sample, continuous across
  // levels, and continuous in the camera position (w follows the continuous centre).
  const SurfaceLevel& s = levels_[l];
  const bool last = l + 1 == config_.levels;
  const float band_end = s.reach - s.cell, band_start = band_end - config_.blend_fraction * s.reach;
  const float inv_band = 1.0f / (band_end - band_start);
  const std::uint32_t nodes = config_.cells + 1;
  // Node (i, j) lies at the partner's (px + i/2, py + j/2); px, py integers (origins on the tile lattice).
  std::int64_t px = 0, py = 0;
  if (!last) {
    const SurfaceLevel& p = levels_[l + 1];
    px = std::llround((double(s.origin_x) - p.origin_x) / p.cell);
    py = std::llround((double(s.origin_y) - p.origin_y) / p.cell);
  }
  float* fields[4] = {heights(l), grad_x(l), grad_y(l), slope_variance(l)};
  const float* partners[4] = {last ? nullptr : heights(l + 1), last ? nullptr : grad_x(l + 1),
                              last ? nullptr : grad_y(l + 1), last ? nullptr : slope_variance(l + 1)};
  const float far_values[4] = {config_.far_height, 0.0f, 0.0f, 0.0f};
  const float dy = std::fabs(s.origin_y + float(j) * s.cell - centre_y_);
  // On a row inside the band's inner edge, the nodes more than a cell inside it in x keep their
  // values (the test below would pass them over one by one): [inner_lo, inner_hi) is skipped.
  std::size_t inner_lo = nodes, inner_hi = nodes;
  if (!(dy > band_start)) {
    const double a = std::ceil((double(centre_x_) - band_start - s.origin_x) / s.cell) + 1.0;
    const double b = std::floor((double(centre_x_) + band_start - s.origin_x) / s.cell) - 1.0;
    if (a <= b && a < nodes && b >= 0.0) {
      inner_lo = std::size_t(std::max(a, 0.0));
      inner_hi = std::size_t(std::min(b + 1.0, double(nodes)));
    }
  }
  const auto morph_node = [&](std::size_t i) {
    const float r = std::max(std::fabs(s.origin_x + float(i) * s.cell - centre_x_), dy);
    if (!(r > band_start)) return;
    float x = (r - band_start) * inv_band;
    x = x < 1.0f ? x : 1.0f;
    const float w = x * x * (3.0f - 2.0f * x);
    const std::size_t k = j * stride_ + i;
    for (int f = 0; f < 4; ++f) {
      float p = far_values[f];
      if (!last) {
        // The partner's bilinear value at fractions 0 or 1/2, horizontal first as in the marcher.
        const float* q = partners[f] + std::size_t(py + std::int64_t(j / 2)) * stride_ + std::size_t(px + std::int64_t(i / 2));
        const float u0 = (i & 1) ? q[0] + 0.5f * (q[1] - q[0]) : q[0];
        if (j & 1) {
          const float* q1 = q + stride_;
          const float u1 = (i & 1) ? q1[0] + 0.5f * (q1[1] - q1[0]) : q1[0];
          p = u0 + 0.5f * (u1 - u0);
        } else {
          p = u0;
        }
      }
      fields[f][k] = fields[f][k] + w * (p - fields[f][k]);
    }
  };
  // Filled nodes only: the runs of needed tiles, less the inner range.
  for_each_run(l, j, [&](std::size_t i0, std::size_t count) {
    const std::size_t end = i0 + count;
    for (std::size_t i = i0; i < std::min(end, inner_lo); ++i) morph_node(i);
    for (std::size_t i = std::max(i0, inner_hi); i < end; ++i) morph_node(i);
  });
}

void SurfaceFrame::pair_row(std::uint32_t l, std::uint32_t j) noexcept {
  const std::uint32_t tc = config_.tile_cells;
  std::uint32_t upper, lower;
  row_tiles(j, tc, tiles_, upper, lower);
  const std::uint8_t* need = needed_ + std::size_t(l) * tiles_ * tiles_;
  const std::size_t o = node_offset(l) + j * stride_;
  const float* h = height_ + o;
  float* pairs = height_pairs_ + 2 * o;
  for (std::uint32_t ti = 0; ti < tiles_; ++ti) {
    if (need[upper * tiles_ + ti] == 0 && need[lower * tiles_ + ti] == 0) continue;
    for (std::size_t i = std::size_t(ti) * tc; i < std::size_t(ti + 1) * tc; ++i) {
      pairs[2 * i] = h[i];
      pairs[2 * i + 1] = h[i + 1];
    }
  }
}

void SurfaceFrame::bound_tile_row(std::uint32_t l, std::uint32_t tj, unsigned part) noexcept {
  const SurfaceLevel& s = levels_[l];
  const std::uint32_t tc = config_.tile_cells, nt = tiles_;
  const float* h = heights(l);
  const std::size_t column = stride_ + align_floats, base = std::size_t(part) * 4 * column;
  const ColumnStats own{scratch_ + base, scratch_ + base + column, scratch_ + base + 2 * column,
                        scratch_ + base + 3 * column};
  const auto& kernels = simd::active_table<detail::SurfaceTable>();
  const std::size_t row = std::size_t(l) * nt * nt + std::size_t(tj) * nt;
  std::uint32_t first = nt, end = 0;
  for (std::uint32_t ti = 0; ti < nt; ++ti) {
    tile_min_[row + ti] = std::numeric_limits<float>::infinity();  // empty unless filled (or merged below)
    tile_max_[row + ti] = -std::numeric_limits<float>::infinity();
    tile_sx_[row + ti] = tile_sy_[row + ti] = 0.0f;
    if (needed_[row + ti] == 0) continue;
    first = std::min(first, ti);
    end = ti + 1;
  }
  if (first == nt) return;
  // H is bilinear in the (morphed) nodes: extremes and steepest edges are at nodes, so per-column
  // statistics of the tile row reduced over each tile's columns bound it exactly.
  const std::size_t j0 = std::size_t(tj) * tc;
  kernels.surface_column_stats({h + j0 * stride_, stride_, tc + 1, std::size_t(first) * tc, std::size_t(end) * tc,
                                own.lo, own.hi, own.dx, own.dy});
  for (std::uint32_t ti = first; ti < end; ++ti) {
    const std::size_t k = row + ti;
    if (needed_[k] == 0) continue;
    float lo = std::numeric_limits<float>::infinity(), hi = -lo, sx = 0.0f, sy = 0.0f;
    own.reduce(std::size_t(ti) * tc, tc, lo, hi, sx, sy);
    float slope_x = sx / s.cell, slope_y = sy / s.cell;
    add_margins(lo, hi, slope_x, slope_y);
    tile_min_[k] = lo;
    tile_max_[k] = hi;
    tile_sx_[k] = slope_x;
    tile_sy_[k] = slope_y;
  }
}

void SurfaceFrame::merge_finer(std::uint32_t l) noexcept {
  const SurfaceLevel& s = levels_[l];
  const std::uint32_t tc = config_.tile_cells, nt = tiles_;
  const double cx = centre_x_, cy = centre_y_, tile = double(tc) * s.cell;
  const std::size_t base = std::size_t(l) * nt * nt;
  // A level is sampled only outside the finer level's reach, but a ray stepping through one of its
  // tiles may enter that inner square: merge the finer tiles there, so that a tile bounds H over all
  // of it within this level's reach. The finer tiles are whole halves of this level's tiles.
  const SurfaceLevel& f = levels_[l - 1];
  const double inner = f.reach, ftile = double(tc) * f.cell;
  const std::int64_t qx = std::llround((double(s.origin_x) - f.origin_x) / ftile);
  const std::int64_t qy = std::llround((double(s.origin_y) - f.origin_y) / ftile);
  const std::size_t fbase = std::size_t(l - 1) * nt * nt;
  for (std::uint32_t tj = 0; tj < nt; ++tj) {
    for (std::uint32_t ti = 0; ti < nt; ++ti) {
      const double x0 = s.origin_x + ti * tile, y0 = s.origin_y + tj * tile;
      double r_lo, r_hi;
      chebyshev_range(x0, x0 + tile, y0, y0 + tile, cx, cy, r_lo, r_hi);
      if (r_lo > inner) continue;
      const std::size_t k = base + std::size_t(tj) * nt + ti;
      for (int b = 0; b < 2; ++b) {
        for (int a = 0; a < 2; ++a) {
          const std::int64_t ci = qx + 2 * std::int64_t(ti) + a, cj = qy + 2 * std::int64_t(tj) + b;
          if (ci < 0 || cj < 0 || ci >= std::int64_t(nt) || cj >= std::int64_t(nt)) continue;
          const double fx0 = f.origin_x + double(ci) * ftile, fy0 = f.origin_y + double(cj) * ftile;
          double f_lo, f_hi;
          chebyshev_range(fx0, fx0 + ftile, fy0, fy0 + ftile, cx, cy, f_lo, f_hi);
          if (f_lo > inner) continue;
          const std::size_t fk = fbase + std::size_t(cj) * nt + std::size_t(ci);
          if (!(tile_min_[fk] <= tile_max_[fk])) continue;  // empty: outside what rays can see
          tile_min_[k] = std::min(tile_min_[k], tile_min_[fk]);
          tile_max_[k] = std::max(tile_max_[k], tile_max_[fk]);
          tile_sx_[k] = std::max(tile_sx_[k], tile_sx_[fk]);
          tile_sy_[k] = std::max(tile_sy_[k], tile_sy_[fk]);
        }
      }
    }
  }
}

void SurfaceFrame::finish_global() noexcept {
  // The last level's tiles within its reach bound everything inside it (they include the finer
  // levels); beyond is the far plane.
  const std::uint32_t l = config_.levels - 1, nt = tiles_;
  const SurfaceLevel& s = levels_[l];
  const double tile_m = double(config_.tile_cells) * s.cell;
  TileBounds g{config_.far_height, config_.far_height, 0.0f, 0.0f};
  for (std::uint32_t tj = 0; tj < nt; ++tj) {
    for (std::uint32_t ti = 0; ti < nt; ++ti) {
      const double x0 = s.origin_x + ti * tile_m, y0 = s.origin_y + tj * tile_m;
      double r_lo, r_hi;
      chebyshev_range(x0, x0 + tile_m, y0, y0 + tile_m, centre_x_, centre_y_, r_lo, r_hi);
      if (r_lo > s.reach) continue;
      const TileBounds t = tile(l, ti, tj);
      if (!(t.h_min <= t.h_max)) continue;
      g.h_min = std::min(g.h_min, t.h_min);
      g.h_max = std::max(g.h_max, t.h_max);
      g.slope_x = std::max(g.slope_x, t.slope_x);
      g.slope_y = std::max(g.slope_y, t.slope_y);
    }
  }
  global_ = g;
  // Tiles left empty are never sampled by the rays the fill was restricted to; give them the global
  // bounds so that anything else reading them still gets finite, conservative values.
  const std::size_t all = std::size_t(config_.levels) * nt * nt;
  for (std::size_t k = 0; k < all; ++k) {
    if (tile_min_[k] <= tile_max_[k]) continue;
    tile_min_[k] = g.h_min;
    tile_max_[k] = g.h_max;
    tile_sx_[k] = g.slope_x;
    tile_sy_[k] = g.slope_y;
  }
}

namespace {

struct GerstnerFill {
  const GerstnerFrame* waves;
  int newton_steps;
  Isa isa;
  bool dispatched;
};

void gerstner_sampler(void* context, const SurfaceSamples& s) noexcept {
  const auto& c = *static_cast<const GerstnerFill*>(context);
  if (c.dispatched) {
    gerstner_eval(*c.waves, s.x, s.y, s.n, {s.height, s.grad_x, s.grad_y}, c.newton_steps);
  } else {
    gerstner_eval(c.isa, *c.waves, s.x, s.y, s.n, {s.height, s.grad_x, s.grad_y}, c.newton_steps);
  }
  std::fill(s.slope_variance, s.slope_variance + s.n, 0.0f);  // unfiltered
}

}  // namespace

void fill_gerstner(SurfaceFrame& frame, const GerstnerFrame& waves, int newton_steps) noexcept {
  GerstnerFill c{&waves, newton_steps, active_isa(), true};
  frame.fill(&gerstner_sampler, &c);
}

void fill_gerstner(Isa isa, SurfaceFrame& frame, const GerstnerFrame& waves, int newton_steps) noexcept {
  GerstnerFill c{&waves, newton_steps, isa, false};
  frame.fill(&gerstner_sampler, &c);
}

}  // namespace houle
