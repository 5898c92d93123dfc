// The per-frame surface contract: what the marcher samples (paper section 3, docs/rendering.md 1.1-1.2).
//
// The sea height z = H(x, y) for one frame is held in nested square grids centred under the camera
// (clipmap-like LOD levels). Level l has `cells` x `cells` cells of size finest_cell 2^l and stores,
// at each of its (cells + 1)^2 nodes, the height and its gradient (SoA, rows 64-byte aligned and
// padded). Per tile (tile_cells x tile_cells cells) it keeps [h_min, h_max] and slope bounds, and
// for the whole frame the slab [z_min, z_max] (the paper's H_box) and a global slope bound.
//
// Which level is sampled where. With r = max(|x - c_x|, |y - c_y|) (c = the frame centre, the
// camera's ground point, continuous), level l is sampled for reach_{l-1} < r <= reach_l
// (reach_l = (cells / 2 - tile_cells / 2 - 1) cell_l, doubling per level) and beyond the last level's
// reach the sea is the flat plane z = far_height. H is bilinear in the nodes of the level sampled.
//
// No popping: in the outer band of each level (width blend_fraction reach_l, ending one cell before
// reach_l) finish_frame() morphs the nodes toward the next coarser level (the far plane for the last):
//   node <- node + w (p - node),  w = smoothstep((r_node - band_start) / band_width),
// p the coarser level's bilinear value there (geomorphing, as in CDLOD clipmaps). Cells touching a
// reach are then wholly the coarser surface, so H is continuous across levels with one bilinear
// fetch per sample, and continuous in the camera position: grid origins snap to the tile size (nodes
// stay on fixed world points, the surface does not swim) and only w, which follows the continuous
// centre, moves with the camera. Gradients are morphed the same way (they are shading gradients).
//
// Bounds are rigorous for that H: bilinear pieces reach their extremes and steepest edges at nodes,
// and a level's tile also bounds the finer levels inside it, so a bound read at a sample holds along
// the ray until it leaves the tile or the level's reach (march.hpp uses this).
//
// Memory is allocated once by create() (bytes_bound() says how much); a frame is begin_frame(centre),
// optionally restrict_to_view(camera), filling the node arrays (fill(), fill_gerstner(), or writing
// heights()/grad_x()/grad_y() directly, e.g. from traced wave rays), then finish_frame() (fill does
// it) for the morph and the bounds. No allocation and no failure per frame. Coordinates are world m
// as floats: keep the scene near the origin.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

#include "houle/runtime/assert.hpp"
#include "houle/surface/camera.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/surface/node_footprint.hpp"

namespace houle {

struct SurfaceFrameConfig {
  std::uint32_t levels = 8;        ///< LOD levels, 1..SurfaceFrame::max_levels
  std::uint32_t cells = 256;       ///< cells per side of every level, a multiple of tile_cells, >= 4 tile_cells
  std::uint32_t tile_cells = 16;   ///< cells per side of a bounds tile, a power of two >= 2
  float finest_cell = 0.25f;       ///< m, cell size of level 0 (> 0; a power of two makes nesting exact)
  float blend_fraction = 0.15f;    ///< width of each level's morph band, as a fraction of its reach, (0, 0.5]
  float far_height = 0.0f;         ///< m, the sea beyond the last level (still water)
};

/// Placement of one level in the current frame.
struct SurfaceLevel {
  float origin_x = 0.0f, origin_y = 0.0f;  ///< m, world position of node (0, 0), a multiple of the tile size
  float cell = 0.0f;                       ///< m
  float reach = 0.0f;  ///< m, Chebyshev radius about the centre up to which this level (or a finer one) is sampled
};

/// Bounds of one tile, valid for H over the part of the tile within its level's reach (for a frame
/// restricted to a view: over the part the view's rays can reach).
struct TileBounds {
  float h_min = 0.0f, h_max = 0.0f;   ///< m
  float slope_x = 0.0f, slope_y = 0.0f;  ///< bounds of |dH/dx| and |dH/dy| (m/m)
};

/// Everything the marcher reads, as raw pointers: node (i, j) of level l (i along x, j along y,
/// 0..cells) is element l * level_floats + j * stride + i of height/grad_x/grad_y; tile (ti, tj) of
/// level l is element l * tiles_per_side^2 + tj * tiles_per_side + ti of the tile arrays.
struct SurfaceFrameView {
  std::uint32_t levels = 0, cells = 0, tile_cells = 0, tiles_per_side = 0;
  std::size_t stride = 0;        ///< floats between node rows (a multiple of 16)
  std::size_t level_floats = 0;  ///< floats between levels (a multiple of 16)
  float centre_x = 0.0f, centre_y = 0.0f;  ///< m
  float blend_fraction = 0.0f, far_height = 0.0f;
  const float* height = nullptr;
  /// Per node k of a needed tile's cells, (height[k], height[k + 1]) at elements 2k and 2k + 1: a cell's
  /// two nodes of a row in one 64-bit gather for the marcher.
  const float* height_pairs = nullptr;
  const float* grad_x = nullptr;
  const float* grad_y = nullptr;
  const float* slope_variance = nullptr;  ///< per node, the roughness the fill left out (SurfaceSamples)
  const float* tile_min = nullptr;
  const float* tile_max = nullptr;
  const float* tile_slope_x = nullptr;
  const float* tile_slope_y = nullptr;
  const SurfaceLevel* level = nullptr;  ///< `levels` entries
  TileBounds global;  ///< whole frame, grid only (no noise), far plane included
};

/// A run of n nodes of one level to evaluate, and what they can hold (NodeFootprint).
struct SurfaceSamples {
  const float* x = nullptr;
  const float* y = nullptr;
  std::size_t n = 0;
  NodeFootprint footprint{};
  float* height = nullptr;
  float* grad_x = nullptr;  ///< dh/dx
  float* grad_y = nullptr;  ///< dh/dy
  /// The slope variance per axis of the detail the sampler left out for the footprint (0 when it
  /// filters nothing): the glint's roughness (docs/rendering.md 5.5).
  float* slope_variance = nullptr;
  /// Where the sampler may keep what it computes at these nodes that changes neither with the time
  /// nor with the viewer (SurfaceFrame::keep_static; null: nowhere): its floats per node for n rounded
  /// up to 16 nodes, no alignment promised. `kept`: it holds what the sampler wrote for this same run
  /// (the same nodes) on an earlier frame; otherwise the sampler writes it now.
  float* keep = nullptr;
  bool kept = false;
};

/// Evaluates height and gradient at a run of nodes: the generic way to fill a frame (analytic trains,
/// traced wave rays, tests). Must not allocate or fail; arrays need no alignment.
using SurfaceSampler = void (*)(void* context, const SurfaceSamples& samples) noexcept;

class SurfaceFrame {
 public:
  static constexpr std::uint32_t max_levels = 16;

  /// Allocates everything the frame will ever need. Fails on an invalid config or out of memory.
  static Expected<SurfaceFrame> create(const SurfaceFrameConfig& config);
  /// Bytes create() allocates for `config` (0 when the config is invalid).
  static std::size_t bytes_bound(const SurfaceFrameConfig& config) noexcept;

  SurfaceFrame(SurfaceFrame&&) noexcept;
  SurfaceFrame& operator=(SurfaceFrame&&) noexcept;
  ~SurfaceFrame();

  const SurfaceFrameConfig& config() const noexcept { return config_; }

  /// Starts a frame centred on the ground point (centre_x, centre_y) m: places the levels and marks
  /// for filling every tile that can be sampled (each level's annulus). Node values and bounds are
  /// undefined until filled and finished.
  void begin_frame(float centre_x, float centre_y) noexcept;
  /// Optional, after begin_frame: fill only the tiles that rays from the camera position through its
  /// image can sample, plus a cell, and the camera's own point. With a slab [z_lo, z_hi] that holds
  /// every sample the rays will take (the frame's z_min() and z_max() once filled: the caller checks)
  /// and every corner ray going down (or every one up), that is the frustum's slice of the slab: a top-
  /// down view fills a few levels. Otherwise it is the frustum's horizontal wedge, typically a quarter
  /// of the tiles, or everything when the frustum holds the vertical. The frame is then valid for those
  /// rays only: rays from elsewhere or leaving the region read stale heights (and conservative bounds,
  /// so nothing breaks).
  void restrict_to_view(const Camera& camera, float z_lo = -std::numeric_limits<float>::infinity(),
                        float z_hi = std::numeric_limits<float>::infinity()) noexcept;
  /// Optional, after begin_frame: the fill's samplers are told the footprint of `camera`'s pixels at
  /// each node (NodeFootprint), so that they leave out what those pixels cannot resolve. Without it
  /// only the node spacing limits them.
  void set_viewer(const Camera& camera) noexcept;
  /// Whether the current fill covers tile (tile_x, tile_y) of level l.
  bool tile_filled(std::uint32_t l, std::uint32_t tile_x, std::uint32_t tile_y) const noexcept;
  const SurfaceLevel& level(std::uint32_t l) const noexcept {
    HOULE_ASSERT(l < config_.levels, "SurfaceFrame::level: a level of the config");
    return levels_[l];
  }
  /// Floats between node rows of the arrays below.
  std::size_t stride() const noexcept { return stride_; }
  /// Level l's node arrays ((cells + 1) rows of `stride` floats), for fills that write them directly.
  /// Raw samples until finish_frame(), which morphs the band nodes in place.
  float* heights(std::uint32_t l) noexcept { return height_ + node_offset(l); }
  float* grad_x(std::uint32_t l) noexcept { return grad_x_ + node_offset(l); }
  float* grad_y(std::uint32_t l) noexcept { return grad_y_ + node_offset(l); }
  const float* heights(std::uint32_t l) const noexcept { return height_ + node_offset(l); }
  const float* grad_x(std::uint32_t l) const noexcept { return grad_x_ + node_offset(l); }
  const float* grad_y(std::uint32_t l) const noexcept { return grad_y_ + node_offset(l); }
  /// Level l's per-node slope variance left out of the heights (SurfaceSamples::slope_variance); zero
  /// unless a sampler writes it.
  float* slope_variance(std::uint32_t l) noexcept { return variance_ + node_offset(l); }
  const float* slope_variance(std::uint32_t l) const noexcept { return variance_ + node_offset(l); }

  /// Evaluates every node to be filled with `sampler` (runs of at most cells + 1 points along a row),
  /// then finish_frame().
  void fill(SurfaceSampler sampler, void* context) noexcept;
  /// fill() in `parts` (1..max_fill_parts) pieces that may run concurrently (the sampler must allow
  /// it): begin_fill(sampler, context), then fill_part(sampler, context, p, parts) once for every p
  /// in [0, parts) from any threads, then finish_frame(). Every node is computed alike: the frame does
  /// not depend on parts.
  static constexpr unsigned max_fill_parts = 8;
  void begin_fill(SurfaceSampler sampler, void* context) noexcept;
  void fill_part(SurfaceSampler sampler, void* context, unsigned part, unsigned parts) noexcept;
  /// finish_frame()'s morph and its tiles' own bounds in `parts` pieces that may run concurrently, after
  /// every fill_part: morph_part(p, parts) for every p, then bound_part(p, parts) for every p, then
  /// finish_frame(), which is left the merging of nested bounds and the global ones. The frame does not
  /// depend on parts.
  void morph_part(unsigned part, unsigned parts) noexcept;
  void bound_part(unsigned part, unsigned parts) noexcept;
  /// Morphs the band nodes (once per fill) and computes tile bounds, global bounds and the slab.
  void finish_frame() noexcept;

  /// Most bytes keep_static() takes.
  static constexpr std::size_t max_kept_bytes = std::size_t(320) << 20;
  /// Bytes keep_static(floats_per_node) takes for `config`: a place for every node of every level, or
  /// 0 (nothing kept) where that is over max_kept_bytes, for tiles of fewer than 16 cells and for an
  /// invalid config.
  static std::size_t kept_bytes_bound(const SurfaceFrameConfig& config, std::size_t floats_per_node) noexcept;
  /// Lets the fill's samplers keep `floats_per_node` floats per node of what changes neither with the
  /// time nor with the viewer (SurfaceSamples::keep), in memory allocated here, once
  /// (kept_bytes_bound; untouched pages cost nothing until a view needs them). Each node has its place
  /// in its level's share, and each 16 nodes of a row a count of those written: a run whose nodes are
  /// all written is read back, any other run is written. A level's origin moving forgets what it
  /// kept, and its first fill there keeps nothing (so that a single frame touches none of the
  /// memory). A fixed camera pays that part of the fill once; a moving one, for the tiles the view
  /// newly needs and for each move of a level's origin (docs/design.md 3). 0, or no memory for it
  /// (kept_bytes_bound 0 included): nothing kept.
  void keep_static(std::size_t floats_per_node) noexcept;

  /// Bounds of anything added on top of the grid (capillary noise: capillary_height_bound and
  /// capillary_slope_bound at the highest level used), included in slab() and slope_bound().
  void set_noise_bounds(float height_m, float slope) noexcept;

  /// The paper's H_box [z_min, z_max] in m: grid, far plane and noise bound.
  float z_min() const noexcept { return global_.h_min - noise_height_; }
  float z_max() const noexcept { return global_.h_max + noise_height_; }
  /// Bound of |grad H| over the frame, noise included.
  float slope_bound() const noexcept;
  TileBounds tile(std::uint32_t l, std::uint32_t tile_x, std::uint32_t tile_y) const noexcept;
  std::uint32_t tiles_per_side() const noexcept { return tiles_; }

  /// The grid surface H at (x, y) (no noise), evaluated exactly as the marcher does: for tests and tools.
  float height_at(float x, float y) const noexcept;

  SurfaceFrameView view() const noexcept;

 private:
  struct FreeAligned {
    void operator()(float* p) const noexcept;
  };
  SurfaceFrame() = default;
  std::size_t node_offset(std::uint32_t l) const noexcept {
    HOULE_ASSERT(l < config_.levels, "SurfaceFrame: the node arrays of a level of the config");
    return l * level_floats_;
  }
  void morph_row(std::uint32_t l, std::uint32_t j) noexcept;
  /// Node row j of level l's height pairs (SurfaceFrameView::height_pairs), over the cells of needed tiles.
  void pair_row(std::uint32_t l, std::uint32_t j) noexcept;
  /// Tile row tj of level l's own bounds, with part `part`'s column scratch.
  void bound_tile_row(std::uint32_t l, std::uint32_t tj, unsigned part) noexcept;
  /// Widens level l's tiles by the finer level's tiles inside its inner square (final ones: levels in order).
  void merge_finer(std::uint32_t l) noexcept;
  void finish_global() noexcept;
  /// f(i0, count) for each run of node row j of level l that the fill evaluates: the nodes of needed
  /// tiles, from node i0 on.
  template <class F>
  void for_each_run(std::uint32_t l, std::uint32_t j, F&& f) const noexcept;
  /// Whether the run of node row j of level l from node i0 (a multiple of 16) holds what the sampler
  /// wrote (all its nodes); if not, records it as written (by the sampler, now).
  bool kept_run(std::uint32_t l, std::uint32_t j, std::size_t i0, std::size_t count) noexcept;

  SurfaceFrameConfig config_{};
  std::unique_ptr<float, FreeAligned> memory_;
  std::size_t stride_ = 0, level_floats_ = 0;
  std::uint32_t tiles_ = 0;
  float* height_ = nullptr;
  float* height_pairs_ = nullptr;  ///< 2 floats per node
  float* grad_x_ = nullptr;
  float* grad_y_ = nullptr;
  float* variance_ = nullptr;
  float* tile_min_ = nullptr;
  float* tile_max_ = nullptr;
  float* tile_sx_ = nullptr;
  float* tile_sy_ = nullptr;
  std::uint8_t* needed_ = nullptr;  ///< per tile: filled this frame
  float* row_x_ = nullptr;  ///< fill scratch: per part, node x coordinates of a row
  float* row_y_ = nullptr;  ///< fill scratch: per part, the row's y repeated
  float* scratch_ = nullptr;  ///< bounds pass: per part, column statistics
  std::array<SurfaceLevel, max_levels> levels_{};
  float centre_x_ = 0.0f, centre_y_ = 0.0f;
  NodeFootprint viewer_{};  ///< the fill's footprint but for the cell: no viewer until set_viewer
  TileBounds global_{};
  float noise_height_ = 0.0f, noise_slope_ = 0.0f;
  bool morphed_ = false;  ///< the band nodes hold their morphed values (finish once per fill)
  bool bounded_ = false;  ///< the tiles' own bounds are those of the morphed nodes (bound_part ran)

  // keep_static: the kept floats (a share per level: node (i, j) at (j round16(cells + 1) + i) floats
  // per node), per level, node row and 16 nodes of it how many of those, from the first, hold what the
  // sampler wrote (keep_written_), and per level the origin they belong to.
  struct KeptLevel {
    float origin_x = 0.0f, origin_y = 0.0f;
    bool current = false;  ///< the origin is this fill's, keep_written_'s share holds for it
    bool fresh = false;    ///< this fill is the origin's first: nothing kept (a single frame writes none)
  };
  std::unique_ptr<float[]> keep_;
  std::unique_ptr<std::uint8_t[]> keep_written_;
  std::size_t keep_level_floats_ = 0, keep_per_node_ = 0, keep_row_blocks_ = 0;
  SurfaceSampler keep_sampler_ = nullptr;  ///< of the last fill
  void* keep_context_ = nullptr;
  std::array<KeptLevel, max_levels> keep_levels_{};
};

/// Fills `frame` (after begin_frame) from analytic Gerstner trains with the dispatched
/// gerstner_eval, bounds included.
void fill_gerstner(SurfaceFrame& frame, const GerstnerFrame& waves, int newton_steps = 3) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void fill_gerstner(Isa isa, SurfaceFrame& frame, const GerstnerFrame& waves, int newton_steps = 3) noexcept;

}  // namespace houle
