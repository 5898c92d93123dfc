#include "shadow_mask.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace houle::detail {
namespace {

using Vec3 = std::array<float, 3>;

// The bitmap's cells (at most per side) and the margin (m) by which each caster's projected bounds
// are widened: float rounding of the crossing point and of the exact tests, with room to spare.
constexpr float max_cells = 512.0f, min_cell = 0.25f, margin = 0.05f;
// A box at rest is cut into pieces at most this long (m) along its own axes: a long wall block turned
// by its yaw would otherwise mark its whole axis-aligned bounding rectangle.
constexpr float piece = 1.0f;
constexpr int max_pieces = 64;

struct Rect {
  float x0, y0, x1, y1;
};

/// The shadow along `slope` (towards_xy / towards_z) on z = 0 of the axis-aligned box lo..hi: the
/// bounding rectangle of its corners' shadows, widened by the margin.
Rect project(const Vec3& lo, const Vec3& hi, float slope_x, float slope_y) {
  Rect r{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
         -std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  for (const float z : {lo[2], hi[2]}) {
    for (const float x : {lo[0], hi[0]}) {
      r.x0 = std::min(r.x0, x - slope_x * z);
      r.x1 = std::max(r.x1, x - slope_x * z);
    }
    for (const float y : {lo[1], hi[1]}) {
      r.y0 = std::min(r.y0, y - slope_y * z);
      r.y1 = std::max(r.y1, y - slope_y * z);
    }
  }
  const float m = margin + 1e-5f * std::max({std::abs(r.x0), std::abs(r.x1), std::abs(r.y0), std::abs(r.y1)});
  return {r.x0 - m, r.y0 - m, r.x1 + m, r.y1 + m};
}

}  // namespace

ShadowMask ShadowMask::build(const std::vector<RenderBox>& boxes, const std::vector<RenderSphere>& spheres,
                             const Vec3& towards) {
  ShadowMask mask;
  if (!(towards[2] > 0.0f)) return mask;
  mask.view_.slope_x = towards[0] / towards[2];
  mask.view_.slope_y = towards[1] / towards[2];
  std::vector<Rect> rects;
  const auto add_cube = [&](const Vec3& c, float reach) {
    rects.push_back(project({c[0] - reach, c[1] - reach, c[2] - reach}, {c[0] + reach, c[1] + reach, c[2] + reach},
                            mask.view_.slope_x, mask.view_.slope_y));
  };
  for (const RenderBox& b : boxes) {
    const auto& e = b.half_extent;
    if (b.motion > 0.0f) {
      add_cube(b.center, b.motion + std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]));
      continue;
    }
    // At rest: x and y turned by the yaw, z up. Each piece's axis-aligned bounds.
    const float c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
    const int nx = std::clamp(int(std::ceil(2.0f * e[0] / piece)), 1, max_pieces);
    const int ny = std::clamp(int(std::ceil(2.0f * e[1] / piece)), 1, max_pieces);
    const float hx = e[0] / float(nx), hy = e[1] / float(ny);
    const float wx = std::abs(c) * hx + std::abs(s) * hy, wy = std::abs(s) * hx + std::abs(c) * hy;
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) {
        const float lx = -e[0] + (2.0f * float(i) + 1.0f) * hx, ly = -e[1] + (2.0f * float(j) + 1.0f) * hy;
        const float px = b.center[0] + c * lx - s * ly, py = b.center[1] + s * lx + c * ly;
        rects.push_back(project({px - wx, py - wy, b.center[2] - e[2]}, {px + wx, py + wy, b.center[2] + e[2]},
                                mask.view_.slope_x, mask.view_.slope_y));
      }
    }
  }
  for (const RenderSphere& sp : spheres) add_cube(sp.center, sp.motion + sp.radius);
  if (rects.empty()) return mask;

  Rect all = rects.front();
  for (const Rect& r : rects) all = {std::min(all.x0, r.x0), std::min(all.y0, r.y0), std::max(all.x1, r.x1), std::max(all.y1, r.y1)};
  const float cell = std::max({min_cell, (all.x1 - all.x0) / max_cells, (all.y1 - all.y0) / max_cells});
  mask.view_.x0 = all.x0;
  mask.view_.y0 = all.y0;
  mask.view_.inv_cell = 1.0f / cell;
  mask.view_.nx = std::int32_t(std::ceil((all.x1 - all.x0) / cell)) + 1;
  mask.view_.ny = std::int32_t(std::ceil((all.y1 - all.y0) / cell)) + 1;
  mask.cells_.assign(std::size_t(mask.view_.nx) * std::size_t(mask.view_.ny), 0.0f);
  // Every cell a rectangle touches, one more on each side for the rounding of the cell index.
  const auto index = [&](float x, float x0, std::int32_t n) {
    return std::clamp(std::int64_t(std::floor((x - x0) * mask.view_.inv_cell)), std::int64_t(0), std::int64_t(n) - 1);
  };
  for (const Rect& r : rects) {
    const std::int64_t i0 = std::max<std::int64_t>(index(r.x0, all.x0, mask.view_.nx) - 1, 0);
    const std::int64_t i1 = std::min<std::int64_t>(index(r.x1, all.x0, mask.view_.nx) + 1, mask.view_.nx - 1);
    const std::int64_t j0 = std::max<std::int64_t>(index(r.y0, all.y0, mask.view_.ny) - 1, 0);
    const std::int64_t j1 = std::min<std::int64_t>(index(r.y1, all.y0, mask.view_.ny) + 1, mask.view_.ny - 1);
    for (std::int64_t j = j0; j <= j1; ++j) {
      std::fill_n(mask.cells_.begin() + std::ptrdiff_t(j * mask.view_.nx + i0), std::ptrdiff_t(i1 - i0 + 1), 1.0f);
    }
  }
  return mask;
}

std::size_t ShadowMask::marked_cells() const noexcept { return std::size_t(std::count(cells_.begin(), cells_.end(), 1.0f)); }

}  // namespace houle::detail
