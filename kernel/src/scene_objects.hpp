// The renderer's non-sea geometry: oriented boxes, spheres and the floor height grid (sea bed and
// land), with nearest-hit and any-hit (shadow) queries for one ray at a time. Built once per scene;
// queries allocate nothing and are exact (closed forms; the floor's bilinear cells are solved as
// quadratics along the ray, found by a two-level grid walk over per-block height bounds).
//
// The arithmetic is double: rays here are few per pixel, and the grid walk and quadratics are then
// robust for the long, grazing rays a low camera sends over the beach.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "houle/kernel/colour.hpp"
#include "houle/kernel/expected.hpp"
#include "houle/kernel/renderer.hpp"

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
  /// Floor cells per side of a bounds block: the coarse level of the grid walk.
  static constexpr int block_cells = 8;

  /// Validates the scene's geometry (field names as in RenderScene) and precomputes the floor bounds.
  static Expected<SceneObjects> build(const RenderScene& scene);

  /// The nearest hit with t in [t_min, t_max). The floor is searched only where the ray is at or
  /// above floor_z_lo (m): a primary ray below the sea's slab has crossed the sea already.
  SurfaceHit intersect(const SceneRay& ray, double t_min, double t_max,
                       double floor_z_lo = -std::numeric_limits<double>::infinity()) const noexcept;
  /// Whether anything lies on the ray with t in [t_min, t_max) (shadow rays).
  bool occluded(const SceneRay& ray, double t_min, double t_max) const noexcept;
  /// Diffuse reflectance of what was hit.
  LinearRgb albedo(const SurfaceHit& hit) const noexcept;

  bool has_floor() const noexcept { return nx_ > 0; }
  /// The floor's z at (x, y) (bilinear, edges extended); -inf without a floor.
  double floor_height(double x, double y) const noexcept;
  double floor_z_min() const noexcept { return z_min_; }
  double floor_z_max() const noexcept { return z_max_; }

 private:
  struct Box {
    double cx, cy, cz, hx, hy, hz, cos_yaw, sin_yaw;
    LinearRgb colour;
  };
  struct Sphere {
    double cx, cy, cz, radius;
    LinearRgb colour;
  };
  /// Nearest box or sphere hit in [t_min, t_max).
  SurfaceHit hit_objects(const SceneRay& ray, double t_min, double t_max) const noexcept;
  /// Nearest floor hit in [t_min, t_max) where the ray is at or above z_lo (t_max when none); writes
  /// the normal on a hit when `normal` is not null.
  double floor_hit(const SceneRay& ray, double t_min, double t_max, double z_lo,
                   std::array<float, 3>* normal) const noexcept;
  float sample(std::int64_t i, std::int64_t j) const noexcept;

  std::vector<Box> boxes_;
  std::vector<Sphere> spheres_;
  // Floor.
  double origin_x_ = 0.0, origin_y_ = 0.0, cell_ = 1.0;
  std::int64_t nx_ = 0, ny_ = 0, bx_ = 0, by_ = 0;  // samples and blocks per side
  std::vector<float> z_;
  std::vector<float> block_min_, block_max_;  // bounds of each block's samples (edges included)
  double z_min_ = -std::numeric_limits<double>::infinity(), z_max_ = -std::numeric_limits<double>::infinity();
  LinearRgb sand_{};
};

}  // namespace houle::detail
