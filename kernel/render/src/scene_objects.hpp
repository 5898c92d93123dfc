// The renderer's non-sea geometry: oriented boxes, spheres and the floor height grid (sea bed and
// land), with nearest-hit and any-hit (shadow) queries for one ray at a time. Built once per scene;
// queries allocate nothing and are exact: closed forms for boxes and spheres, found through a bounding
// volume hierarchy (walls arrive as many boxes); the floor's bilinear cells solved as quadratics along
// the ray, found by a hierarchical grid walk over a maximum mipmap of the heights (Tevs et al. 2008,
// docs/rendering.md 1.5, here on the CPU with a 2-D DDA per level).
//
// The arithmetic is double: rays here are few per pixel, and the grid walk and quadratics are then
// robust for the long, grazing rays a low camera sends over the beach.
//
// Primary rays of a still camera keep what they met from one frame to the next (the renderer's memo,
// docs/rendering.md 2.4), but for the rays that may meet a moving (floating) object: those are found
// afresh each frame.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/render/renderer.hpp"
#include "floor_hits.hpp"

namespace houle::detail {

struct SceneRay {
  double ox = 0.0, oy = 0.0, oz = 0.0;  ///< m
  double dx = 0.0, dy = 0.0, dz = 1.0;  ///< unit
};

enum class HitKind : std::uint8_t { none = 0, floor = 1, box = 2, sphere = 3 };

struct SurfaceHit {
  float t = std::numeric_limits<float>::infinity();  ///< m along the ray; +inf for none
  HitKind kind = HitKind::none;
  std::uint32_t index = 0;             ///< which box or sphere
  std::array<float, 3> normal{0.0f, 0.0f, 1.0f};  ///< unit, outward (floor: up)
};

class SceneObjects {
 public:
  /// Blocks of each mipmap level per side of a block of the next: level k's blocks are
  /// block_cells^k floor cells wide.
  static constexpr int block_cells = 8;
  static constexpr int max_levels = 8;

  /// Validates the scene's geometry (field names as in RenderScene) and precomputes the floor bounds.
  static Expected<SceneObjects> build(const RenderScene& scene);

  /// The nearest hit with t in [t_min, t_max) (the reference walk: the floor from the ray's start).
  SurfaceHit intersect(const SceneRay& ray, double t_min, double t_max) const noexcept;
  /// The nearest hit with t in [t_min, t_max) of a secondary ray (reflected, refracted): intersect's
  /// hit, found by a floor walk that starts where the floor's clearance map (the highest ground
  /// around each cell) no longer shows the ray above all of it. The hit is the same one; its t and
  /// normal may differ from intersect's in the last bits of the double arithmetic (the walk enters
  /// the hit's cell from another start).
  SurfaceHit intersect_secondary(const SceneRay& ray, double t_min, double t_max) const noexcept;
  /// Whether any box or sphere moves (Renderer::move_box, move_sphere).
  bool has_movers() const noexcept { return !movers_.empty(); }
  /// Whether the ray meets a moving object's present bounds with t in [0, t_max).
  bool meets_movers(const SceneRay& ray, double t_max) const noexcept;
  /// The nearest box or sphere hit with t in [t_min, t_max) (the floor left out).
  SurfaceHit intersect_objects(const SceneRay& ray, double t_min, double t_max) const noexcept {
    return hit_objects(ray, t_min, t_max);
  }
  /// The same, walking only below the boxes of object_bounds() whose bits are set in `cut` (box i:
  /// 1 << i): floor_hits' bits, which leave out only boxes the ray cannot meet. The walk then skips
  /// the hierarchy above the cut and the cut's other boxes.
  SurfaceHit intersect_objects(const SceneRay& ray, double t_min, double t_max, std::uint32_t cut) const noexcept {
    return hit_objects(ray, t_min, t_max, false, cut);
  }
  /// Boxes holding every box and sphere, wherever the moving ones may go: the hierarchy's nodes on a
  /// cut through it, taken at build.
  const ObjectBounds& object_bounds() const noexcept { return bounds_; }
  /// The floor as floor_hits reads it (nx = 0 without a floor, and too_large for one beyond its
  /// 32-bit indices).
  FloorGridView floor_grid() const noexcept;
  /// Whether anything lies on the ray with t in [t_min, t_max) (shadow rays); the floor only when
  /// `floor` is set (walked from its clearance, as intersect_secondary does).
  bool occluded(const SceneRay& ray, double t_min, double t_max, bool floor = true) const noexcept;
  /// Moves box `k` or sphere `k` (one with motion > 0; others are left alone): the centre is clamped
  /// to within its motion of its place in the scene, per axis.
  void move_box(std::size_t k, const BoxPose& pose) noexcept;
  void move_sphere(std::size_t k, const std::array<float, 3>& center) noexcept;
  /// Diffuse reflectance of what was hit.
  LinearRgb albedo(const SurfaceHit& hit) const noexcept;

  bool has_floor() const noexcept { return nx_ > 0; }
  /// The floor's z at (x, y) (bilinear, edges extended); -inf without a floor.
  double floor_height(double x, double y) const noexcept;
  double floor_z_min() const noexcept { return z_min_; }
  double floor_z_max() const noexcept { return z_max_; }

 private:
  struct Box {
    double cx, cy, cz, hx, hy, hz;
    double axes[3][3];  // the local axes in world coordinates
    LinearRgb colour;
    std::int32_t mover;  // index into movers_, -1 for a box that never moves
  };
  struct Sphere {
    double cx, cy, cz, radius;
    LinearRgb colour;
    std::int32_t mover;
  };
  // A moving object: where the scene put its centre, how far it may go, and the bounds of where it
  // is now (the bounding volume hierarchy holds the bounds of everywhere it may go).
  struct Mover {
    double rest[3], motion, lo[3], hi[3];
  };
  /// A mover for an object at `center` reaching `reach` from its centre in any orientation (index
  /// into movers_), or -1 when motion is 0. Its present bounds start as everywhere it may go.
  std::int32_t add_mover(const std::array<float, 3>& center, float motion, double reach);
  /// intersect (skip_clear false) or intersect_secondary (true).
  SurfaceHit nearest(const SceneRay& ray, double t_min, double t_max, bool skip_clear) const noexcept;
  /// Nearest box or sphere hit in [t_min, t_max) (with `any`: the first found), walking from the root,
  /// or with `cut` > 0 from the cut's boxes whose bits it sets.
  SurfaceHit hit_objects(const SceneRay& ray, double t_min, double t_max, bool any = false,
                         std::uint32_t cut = 0) const noexcept;
  bool hit_box(std::uint32_t k, const SceneRay& r, double t_min, double& best, SurfaceHit& hit) const noexcept;
  bool hit_sphere(std::uint32_t k, const SceneRay& r, double t_min, double& best, SurfaceHit& hit) const noexcept;
  void build_bvh();
  /// Where a floor query walks: t0 .. t1 along the ray from the first level `level`; `walk` false
  /// when the ray cannot meet the floor within [t_min, t_max).
  struct FloorSpan {
    double t0, t1;
    int level;
    bool walk;
  };
  FloorSpan floor_span(const SceneRay& ray, double t_min, double t_max) const noexcept;
  /// The first level for a walk from t0 to t1 along the ray.
  int first_level(const SceneRay& ray, double t0, double t1) const noexcept;
  /// Nearest floor hit in [t_min, t_max) (t_max when none); writes the normal on a hit when `normal`
  /// is not null. With `skip_clear` the walk starts at clear_until.
  double floor_hit(const SceneRay& ray, double t_min, double t_max, std::array<float, 3>* normal, bool skip_clear) const noexcept;
  /// For a ray that does not descend: a t in [t0, t1] before which it provably stays above the floor
  /// (t1: above it all along), from the clearance map in at most a few jumps of clear_cells cells.
  double clear_until(const SceneRay& ray, double t0, double t1) const noexcept;
  void build_clearance();
  void build_floor_grid();
  float sample(std::int64_t i, std::int64_t j) const noexcept;
  struct FloorQuery;
  bool walk_level(int level, FloorQuery& q, double ta, double tb, std::int64_t steps) const noexcept;
  bool hit_cell(FloorQuery& q, std::int64_t i, std::int64_t j, double ta, double tb) const noexcept;

  std::vector<Box> boxes_;
  std::vector<Sphere> spheres_;
  std::vector<Mover> movers_;
  // Bounding volume hierarchy over boxes and spheres (walls are many boxes). A node is a leaf when
  // count > 0 (primitives_[first .. first + count)), else its children are nodes first, first + 1.
  struct Node {
    float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {0.0f, 0.0f, 0.0f};
    std::uint32_t first = 0, count = 0;
  };
  static constexpr std::uint32_t sphere_bit = 0x80000000u;  // primitive ids: box index, or sphere index | bit
  static constexpr int max_bvh_depth = 64;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> primitives_;
  ObjectBounds bounds_;
  std::uint32_t cut_nodes_[max_object_bounds] = {};  // the node of each of bounds_' boxes
  void cut_bounds();
  // Floor.
  double origin_x_ = 0.0, origin_y_ = 0.0, cell_ = 1.0;
  std::int64_t nx_ = 0, ny_ = 0;  // samples per side
  std::vector<float> z_;
  // Maximum mipmap: level 0 per cell, the highest of its corners (with the edge samples repeated:
  // sample()); then block (bi, bj) of level k bounds samples bi B^k .. (bi + 1) B^k (clamped to the grid) in each axis,
  // so a block bounds every cell inside it, and the clamped block of one beyond the grid bounds the
  // edge samples that the extended floor repeats there. The top level has a single block.
  int levels_ = 0;
  std::int64_t level_nx_[max_levels] = {}, level_ny_[max_levels] = {};
  std::vector<float> level_max_[max_levels];
  double level_size_[max_levels] = {}, level_inv_size_[max_levels] = {};  // m and 1/m: cell_ B^k
  // The clearance map: per floor cell (level 0's), the highest sample within clear_cells cells of it
  // in each axis (a dilated maximum), over which secondary rays jump instead of walking.
  static constexpr int clear_cells = 4;
  std::vector<float> clear_max_;
  // floor_hits's grids: the samples and level 0's cell maxima, with a border of the edges repeated.
  std::vector<float> grid_z_, grid_cell_max_;
  std::array<FloorBand, floor_bands> bands_{};
  double z_min_ = -std::numeric_limits<double>::infinity(), z_max_ = -std::numeric_limits<double>::infinity();
  LinearRgb sand_{};
};

}  // namespace houle::detail
