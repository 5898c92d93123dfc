// Where rays that go down into the water meet the floor, a packet at a time (templates in
// water_floor_impl.hpp; docs/rendering.md 1.5). A sea hit's refracted ray, and from below its
// reflected one, reach the floor within a few cells: per ray, SceneObjects' hierarchical walk spends
// more on setting up than on walking, and every sea pixel sends one. Here the rays of a row walk the
// floor's cells together in float lanes; a ray that does not descend, or that walks further than the
// kernel's steps, is left to SceneObjects' walk.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/runtime/isa.hpp"

namespace houle::detail {

/// The floor's height grid as the kernel reads it (SceneObjects::water_floor), with a border: the
/// floor beyond the grid repeats its edge samples, so every cell beyond it has the heights of the
/// border cell it is clamped to, and no lane needs more than a clamp of its cell index.
struct WaterFloorView {
  const float* z = nullptr;         ///< (nx + 2) (ny + 2) samples: sample (i, j), i in [-1, nx], at (j + 1) (nx + 2) + i + 1
  const float* cell_max = nullptr;  ///< (nx + 1) (ny + 1) cells: cell (i, j), i in [-1, nx - 1], at (j + 1) (nx + 1) + i + 1
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f, inv_cell = 1.0f;  ///< m, 1/m
  std::int32_t nx = 0, ny = 0;      ///< samples per side; 0: no floor
  float z_lo = 0.0f, z_hi = 0.0f;   ///< m: a little below the lowest sample, the highest sample
};

/// Rays from (ox, oy, oz) along the unit (dx, dy, dz), each met up to t_max (m).
struct WaterRays {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *t_max;
};
/// t: the nearest floor hit in [0, t_max), +inf for none; (nx, ny, nz) its normal (up); left: 1 for a
/// ray the kernel leaves to SceneObjects (one that does not descend, or is not done within
/// max_water_steps cells), whose t and normal are then meaningless; 0 otherwise.
struct WaterHits {
  float *t, *nx, *ny, *nz, *left;
};
inline constexpr int max_water_steps = 64;

/// The floor hits of n rays.
void water_floor(const WaterFloorView& f, const WaterRays& in, std::size_t n, WaterHits out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void water_floor(Isa isa, const WaterFloorView& f, const WaterRays& in, std::size_t n, WaterHits out) noexcept;

}  // namespace houle::detail
