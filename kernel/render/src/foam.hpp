// The surf map as the renderer reads it (docs/rendering.md 3.7) and the foam cover of a row of sea
// hits, a packet at a time (templates in foam_impl.hpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "houle/runtime/isa.hpp"

namespace houle {
struct SurfMap;  // renderer.hpp
}  // namespace houle

namespace houle::detail {

/// A view of a packed surf map for the kernels: node (i, j)'s foam, dir_x, dir_y and amplitude are
/// nodes[4 (j nx + i) + 0..3].
struct SurfView {
  const float* nodes = nullptr;
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f;  ///< m
  float u_end = 0.0f, v_end = 0.0f;  ///< nx - 1, ny - 1: a bilinear lookup's bounds in cells
  std::int32_t nx = 0;
};

/// The surf map packed once per scene: a node's four fields side by side, so that a pixel's bilinear
/// lookup touches two cache lines, not eight (the map of the built-in coast is a few MB, beyond the
/// caches, and 80 % of its sea pixels read it).
struct PackedSurf {
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f;  ///< m
  std::uint32_t nx = 0, ny = 0;
  std::vector<std::array<float, 4>> nodes;  ///< foam, dir_x, dir_y, amplitude

  SurfView view() const noexcept;
};
/// m's nodes must fit the kernels' 32-bit indices (surf_map_fits).
PackedSurf pack(const SurfMap& m);
/// Whether a map of nx * ny nodes can be packed: 4 nx ny floats addressable with int32.
bool surf_map_fits(std::uint32_t nx, std::uint32_t ny) noexcept;

/// One row of sea hits: side > 0 from above (the others get no foam), the hit (x, y, z), the surface's
/// gradient there and the ray's length t (m).
struct FoamInput {
  const float* side;
  const float *x, *y, *z, *gx, *gy, *t;
};
/// cover[i] = the foam cover of hit i for a footprint of t pixel_angle m, 0 where side <= 0.
void foam_cover(const SurfView& m, const FoamInput& in, std::size_t n, float pixel_angle, float* cover) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void foam_cover(Isa isa, const SurfView& m, const FoamInput& in, std::size_t n, float pixel_angle, float* cover) noexcept;

}  // namespace houle::detail
