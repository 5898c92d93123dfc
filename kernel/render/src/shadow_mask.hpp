// Where a line towards the sun can meet a box or sphere: their shadows cast along the line's direction
// onto the plane z = 0, as a bitmap (docs/rendering.md 3.5). A line is known by the point where it
// crosses that plane, so a shadow ray from anywhere, above the water or below it, whose line crosses a
// clear cell meets no caster and need not be traced: the renderer asks the mask per pixel before the
// ray. Built once per scene from each caster's reach (a moving one anywhere within its motion, tilted
// any way); conservative: a cell is marked wherever a caster's bounds, widened by a margin, project.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "houle/render/renderer.hpp"

namespace houle::detail {

class ShadowMask {
 public:
  ShadowMask() = default;
  /// The casters' shadows along `towards` (unit, z > 0; otherwise an empty mask: no line meets anything).
  static ShadowMask build(const std::vector<RenderBox>& boxes, const std::vector<RenderSphere>& spheres,
                          const std::array<float, 3>& towards);
  /// false: the line through `o` along `towards` meets no box or sphere. true: it may (NaN too).
  bool may_meet(const std::array<float, 3>& o) const noexcept {
    const float u = (o[0] - slope_x_ * o[2] - x0_) * inv_cell_, v = (o[1] - slope_y_ * o[2] - y0_) * inv_cell_;
    if (!(u >= 0.0f && v >= 0.0f && u < float(nx_) && v < float(ny_))) return !(std::isfinite(u) && std::isfinite(v));
    return cells_[std::size_t(v) * nx_ + std::size_t(u)] != 0;
  }
  std::size_t marked_cells() const noexcept;

 private:
  float slope_x_ = 0.0f, slope_y_ = 0.0f;  ///< towards_xy / towards_z
  float x0_ = 0.0f, y0_ = 0.0f, inv_cell_ = 1.0f;
  std::uint32_t nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> cells_;
};

}  // namespace houle::detail
