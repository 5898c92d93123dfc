// Where a line towards the sun can meet a box or sphere: their shadows cast along the line's direction
// onto the plane z = 0, as a bitmap (docs/rendering.md 3.5). A line is known by the point where it
// crosses that plane, so a shadow ray from anywhere, above the water or below it, whose line crosses a
// clear cell meets no caster and need not be traced: the renderer asks the mask per pixel before the
// ray. Built once per scene from each caster's reach (a moving one anywhere within its motion, tilted
// any way); conservative: a cell is marked wherever a caster's bounds, widened by a margin, project.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "houle/render/renderer.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

/// A mask as the lookups read it (ShadowMask::view).
struct ShadowMaskView {
  float slope_x = 0.0f, slope_y = 0.0f;  ///< towards_xy / towards_z
  float x0 = 0.0f, y0 = 0.0f, inv_cell = 1.0f;
  std::int32_t nx = 0, ny = 0;
  const float* cells = nullptr;  ///< nx ny cells, row by row: 1 marked, 0 clear
};

/// ShadowMask::may_meet lane by lane, for the lines through (x, y, z): false where a line meets no
/// caster, true where it may (NaN too). Only -, *, comparisons, exact conversions and a gather: every
/// SIMD path gives the scalar path's answer.
template <class A>
inline simd::vmask<A> shadow_may_meet(const ShadowMaskView& m, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z) {
  using V = simd::vfloat<A>;
  const V u = (x - V(m.slope_x) * z - V(m.x0)) * V(m.inv_cell), v = (y - V(m.slope_y) * z - V(m.y0)) * V(m.inv_cell);
  const auto inside = (u >= V(0.0f)) & (v >= V(0.0f)) & (u < V(float(m.nx))) & (v < V(float(m.ny)));
  const auto finite = ((u - u) == V(0.0f)) & ((v - v) == V(0.0f));
  if (!simd::any(inside)) return !finite;
  // Lanes off the bitmap read cell 0 and are not asked it.
  const V ui = simd::select(inside, u, V(0.0f)), vi = simd::select(inside, v, V(0.0f));
  const simd::vint<A> cell = simd::to_int_exact(simd::floor_exact(vi)) * simd::vint<A>(m.nx) +
                             simd::to_int_exact(simd::floor_exact(ui));
  // A lane on the bitmap is finite.
  return (inside & (simd::gather(m.cells, cell) != V(0.0f))) | !finite;
}

class ShadowMask {
 public:
  ShadowMask() = default;
  /// The casters' shadows along `towards` (unit, z > 0; otherwise an empty mask: no line meets anything).
  static ShadowMask build(const std::vector<RenderBox>& boxes, const std::vector<RenderSphere>& spheres,
                          const std::array<float, 3>& towards);
  /// false: the line through `o` along `towards` meets no box or sphere. true: it may (NaN too).
  bool may_meet(const std::array<float, 3>& o) const noexcept {
    return shadow_may_meet<simd::scalar>(view(), o[0], o[1], o[2]);
  }
  ShadowMaskView view() const noexcept {
    ShadowMaskView v = view_;
    v.cells = cells_.data();
    return v;
  }
  std::size_t marked_cells() const noexcept;

 private:
  ShadowMaskView view_;  // cells: null here (the vector's own data, set by view())
  // A float per cell, not a bit or a byte: one gather per lane tells (512 x 512 cells at most).
  std::vector<float> cells_;
};

}  // namespace houle::detail
