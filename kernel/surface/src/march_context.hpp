// What the marcher kernels read: the SurfaceFrame, the cone, the quality knobs and the noise bounds,
// flattened once per call in baseline code (march.cpp) so that the per-ISA kernels only do arithmetic.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/simd/gather.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/surface/march.hpp"
#include "houle/surface/surface_frame.hpp"

namespace houle::detail {

// A level index (< max_levels) and an octave count (<= max_octaves) are within every ISA's
// gather_window (16 floats on AVX2).
static_assert(SurfaceFrame::max_levels <= 16 && CapillaryFrame::max_octaves < 16);

struct MarchContext {
  // Surface grid (SurfaceFrameView).
  const float* height = nullptr;
  const float* height_pairs = nullptr;  ///< SurfaceFrameView::height_pairs
  const float* grad_x = nullptr;
  const float* grad_y = nullptr;
  const float* slope_variance = nullptr;
  const float* tile_min = nullptr;
  const float* tile_max = nullptr;
  const float* tile_slope_x = nullptr;
  const float* tile_slope_y = nullptr;
  std::size_t stride = 0;       ///< floats between node rows
  std::uint32_t levels = 0;
  float cells = 0.0f;           ///< cells per side
  float stride_f = 0.0f;        ///< stride as a float (exact)
  float tiles_per_side = 0.0f;
  float inv_tile_cells = 0.0f;  ///< exact: tile_cells is a power of two
  float centre_x = 0.0f, centre_y = 0.0f, far_height = 0.0f;
  // Levels. Level l's cell, tile and reach are level 0's times 2^l (exact in float), so a lane computes
  // them from its level index; only the origins are looked up.
  float level_reach[SurfaceFrame::max_levels] = {};  ///< m, Chebyshev radius about the centre
  /// m, node (0, 0) of each level; padded so that a lane reads its level's with simd::gather_window.
  float level_origin_x[simd::max_window_floats] = {};
  float level_origin_y[simd::max_window_floats] = {};
  float inv_cell0 = 0.0f;     ///< 1/m
  float tile_size0 = 0.0f;    ///< m
  float reach0 = 0.0f;        ///< m
  float level_floats = 0.0f;  ///< floats between levels in the node arrays (exact, < 2^24)
  float level_tiles = 0.0f;   ///< tiles per level
  TileBounds global{};          ///< grid only
  float z_lo = 0.0f, z_hi = 0.0f;  ///< m, the slab the rays are clipped to (grid slab widened by the noise bound)

  // Cone and quality.
  float pixel_angle = 0.0f, cone_width = 0.0f;
  float step_fraction = 0.0f, min_step = 0.0f, max_distance = 0.0f;
  std::int32_t refine_iterations = 0, max_steps = 0;

  // Capillary noise (null: none). Octave i's share of the height and slope bounds
  // (capillary_height_bound and capillary_slope_bound are sums of these with weights W_i <= [level > i]).
  const CapillaryFrame* noise = nullptr;
  /// capillary_lattice().pairs, looked up once per call: per sample its guard was 1 % of the render's
  /// instructions (callgrind).
  const std::int32_t* noise_pairs = nullptr;
  std::uint32_t octaves = 0;
  float octave_height[CapillaryFrame::max_octaves] = {};
  float octave_slope[CapillaryFrame::max_octaves] = {};
  /// Octave i can have weight (level > i) only while cone width / sin(grazing) < octave_cone[i]
  /// (= (lambda_1 / N) k^(1/s - i), s = capillary_fade_rate, times 1 + 1e-3 so that the float level
  /// never disagrees).
  float octave_cone[CapillaryFrame::max_octaves] = {};
  /// The first n octaves' shares summed in order (n = 0..octaves), padded for simd::gather_window.
  float octaves_height[simd::max_window_floats] = {};
  float octaves_slope[simd::max_window_floats] = {};
  float max_level = 0.0f;           ///< capillary_top_level
  float level_offset = 0.0f;        ///< log2(lambda_1 / N) / log2(k) + 1/s: level = offset + (log2 sin - log2 footprint) / log2 k
  float inv_log2_lacunarity = 0.0f;
  /// |dN/dlevel| <= 1.5 s ceil(1/s) max_i octave_height, |dlevel/dt| <= pixel_angle / (cone ln k): their product
  /// without the 1/cone factor.
  float level_rate = 0.0f;
};

}  // namespace houle::detail
