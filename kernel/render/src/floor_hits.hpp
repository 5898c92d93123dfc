// Where a sea pixel's secondary rays meet the floor, a packet at a time (templates in
// floor_hits_impl.hpp; docs/rendering.md 1.5). A sea hit's ray into the water (refracted, or from
// below reflected) meets the floor within a few cells, and its ray into the air (reflected, or from
// below refracted) leaves the floor's height range within a few: per ray, SceneObjects' hierarchical
// walk spends more on setting up than on walking, and every sea pixel sends both. Here the rays of a
// row walk the floor's cells together in float lanes; a level ray, or one that walks further than the
// kernel's steps, is left to SceneObjects' walk.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>

#include "houle/runtime/isa.hpp"

namespace houle::detail {

/// Where the cells of a height band are (FloorGridView::bands): every cell whose highest corner is at
/// or above z lies in [x0, x1] x [y0, y1] (m), widened by a cell for the walk's rounding, and infinite
/// on a side where such a cell is on the grid's border (beyond it the floor repeats that cell). A ray
/// whose lowest point is at or above z can meet no cell outside.
struct FloorBand {
  float z = std::numeric_limits<float>::infinity();
  float x0 = -std::numeric_limits<float>::infinity(), x1 = std::numeric_limits<float>::infinity();
  float y0 = -std::numeric_limits<float>::infinity(), y1 = std::numeric_limits<float>::infinity();
};
inline constexpr int floor_bands = 16;

/// The floor's height grid as the kernel reads it (SceneObjects::floor_grid), with a border: the
/// floor beyond the grid repeats its edge samples, so every cell beyond it has the heights of the
/// border cell it is clamped to, and no lane needs more than a clamp of its cell index.
struct FloorGridView {
  const float* z = nullptr;         ///< (nx + 2) (ny + 2) samples: sample (i, j), i in [-1, nx], at (j + 1) (nx + 2) + i + 1
  const float* cell_max = nullptr;  ///< (nx + 1) (ny + 1) cells: cell (i, j), i in [-1, nx - 1], at (j + 1) (nx + 1) + i + 1
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f, inv_cell = 1.0f;  ///< m, 1/m
  std::int32_t nx = 0, ny = 0;      ///< samples per side; 0: no grid (no floor, or too_large)
  float z_lo = 0.0f, z_hi = 0.0f;   ///< m: a little below the lowest sample, the highest sample
  bool too_large = false;           ///< a floor beyond the kernel's 32-bit indices: every ray is left
  /// Bands at heights rising with the index, from the lowest cell's maximum to the highest's (each
  /// band's cells hold the next one's): a ray over the sea bed walks only the box of the band below
  /// its lowest point (a ray up from the sea, only where the floor rises near the surface).
  FloorBand bands[floor_bands] = {};
};

/// Where the scene's boxes and spheres are, wherever the moving ones may go (SceneObjects::object_bounds):
/// a box around them all, and boxes that together hold them all (a cut through its hierarchy). The
/// second, because one box around a dog-legged jetty, or around objects far apart, holds much empty
/// water that rays would be sent through SceneObjects' walk for; the first, so that a packet tests
/// them only where it may meet one. count 0 for none.
inline constexpr int max_object_bounds = 16;
struct ObjectBounds {
  int count = 0;
  float all_lo[3] = {}, all_hi[3] = {};  ///< m
  float lo[max_object_bounds][3] = {}, hi[max_object_bounds][3] = {};  ///< m
};

/// Rays from (ox, oy, oz) along the unit (dx, dy, dz), each met up to t_max (m).
struct FloorRays {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *t_max;
};
/// t: the nearest floor hit in [0, t_max), +inf for none; (nx, ny, nz) its normal (up); left: 1 for a
/// ray the kernel leaves to SceneObjects (a level one, one with a NaN, or one not done within
/// max_floor_steps cells), whose t and normal are then meaningless; 0 otherwise. objects: which of the
/// object bounds' boxes the ray may meet before min(t, t_max), as bits (box i: 2^i, exact in the
/// float; a conservative test: a box's bit is 0 only where the ray cannot meet it), 0 for none.
struct FloorHits {
  float *t, *nx, *ny, *nz, *left, *objects;
};
inline constexpr int max_floor_steps = 64;

/// The floor hits of n rays, and which of the object bounds' boxes they may meet before them.
void floor_hits(const FloorGridView& f, const ObjectBounds& b, const FloorRays& in, std::size_t n, FloorHits out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void floor_hits(Isa isa, const FloorGridView& f, const ObjectBounds& b, const FloorRays& in, std::size_t n,
                FloorHits out) noexcept;

}  // namespace houle::detail
