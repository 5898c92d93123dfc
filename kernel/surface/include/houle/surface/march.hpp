// Packet ray marcher: first crossing of rays with the frame's sea surface (paper section 3,
// docs/rendering.md 1.2-1.3, 2.2).
//
// f(t) = o_z + t d_z - S(o_xy + t d_xy), S = H (the SurfaceFrame's LOD grid, morphed between levels)
// plus capillary noise at the octave level of the sample's distance. Per ray:
//   1. clip to the slab [z_min, z_max] (grid slab widened by the noise bound) and to t_max;
//   2. march from the entry: t += max(safe, delta), where `safe` is the largest of the Lipschitz step
//      f / L (L = |d_z| + G_x |d_x| + G_y |d_y|, G from the bounds tile under the sample) and the distance
//      to the tile's [h_min, h_max] plane, clamped to the tile (bounds hold only there), and delta =
//      step_fraction x the cone width at t (a fraction of the pixel footprint). Lipschitz steps cannot
//      pass a crossing; only delta can, over features thinner than delta;
//   3. refine the bracket with a fixed number of Illinois (regula falsi) iterations;
//   4. report t, the hit point and the surface gradient there (bilinear grid gradient, morphed like the
//      heights, plus the noise gradient): the eq. 8 normal is (-grad_x, -grad_y, 1) normalised; and the
//      slope variance the grid left out there (trains too short for the footprint, docs/rendering.md 5.5).
// A ray that starts below the surface (f < 0) looks for the crossing from below the same way.
// Noise is evaluated only inside its envelope: above |f_grid| > noise bound the ray marches against the
// grid alone (docs/design.md 10: coarse march inside an envelope).
//
// Rays are processed in packets of the ISA's width (docs/rendering.md 2.3: take them along screen rows);
// lanes are independent and every ISA gives the scalar path's bits (only +, -, *, simd::div,
// comparisons, selects and exact loads; a lane's result never depends on its companions).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/surface/surface_frame.hpp"

namespace houle {

/// Accuracy knobs (docs/design.md 5: explicit). Defaults are the `realtime` point.
struct MarchQuality {
  float step_fraction = 0.5f;   ///< delta = step_fraction x cone width (pixel footprint across the ray), > 0
  float min_step = 1e-3f;       ///< m, floor of delta near the ray origin, > 0
  int refine_iterations = 1;    ///< Illinois iterations on the final bracket, >= 0
  int max_steps = 1024;         ///< march samples per ray before it gives up (status exhausted), >= 1
  float max_distance = 1e5f;    ///< m, no ray goes further (rays parallel to the sea end here)
};

struct MarchParams {
  /// rad: the ray cone's spread (Camera::pixel_angle for primary rays); sets delta and the noise level.
  float pixel_angle = 1e-3f;
  float cone_width = 0.0f;      ///< m, cone width at t = 0 (secondary rays carry their footprint)
  MarchQuality quality{};
  /// Capillary noise added to the grid (null: none). Its level at distance t is octave_level of the
  /// footprint (cone_width + t pixel_angle) / max(|d_z|, 1e-3) (docs/rendering.md 5.2, along the view).
  const CapillaryFrame* noise = nullptr;
};

/// n rays, SoA, any alignment. Directions must be unit vectors.
struct MarchRays {
  const float* ox = nullptr;
  const float* oy = nullptr;
  const float* oz = nullptr;
  const float* dx = nullptr;
  const float* dy = nullptr;
  const float* dz = nullptr;
  const float* t_max = nullptr;  ///< m, per ray (e.g. the nearest non-sea object); null: max_distance
};

enum class MarchStatus : std::uint8_t {
  miss = 0,            ///< no crossing before the slab exit / t_max (t holds that end)
  hit = 1,             ///< crossed from above (the usual case)
  hit_from_below = 2,  ///< crossed from below (the ray started under water)
  exhausted = 3,       ///< gave up after max_steps samples (t holds the last sample); never seen at defaults in tests
};

/// n entries each; any alignment. Optional arrays may be null.
struct MarchHits {
  float* t = nullptr;       ///< m along the ray
  float* x = nullptr;       ///< hit point (the ray's point at t; for a miss, its end)
  float* y = nullptr;
  float* z = nullptr;
  float* grad_x = nullptr;  ///< dS/dx at the hit (0 for a miss)
  float* grad_y = nullptr;  ///< dS/dy at the hit
  MarchStatus* status = nullptr;
  float* noise_level = nullptr;         ///< optional: capillary level used at the hit (for BRDF compensation)
  std::uint32_t* evaluations = nullptr;  ///< optional: surface evaluations (march + refine + normal)
  /// optional: the slope variance the frame's fill left out at the hit (SurfaceFrame::slope_variance,
  /// interpolated like the heights; 0 for a miss), for the glint's roughness
  float* slope_variance = nullptr;
};

/// Marches n rays against `frame` (filled and finished) with the dispatched ISA.
void march_rays(const SurfaceFrame& frame, const MarchParams& params, const MarchRays& rays, std::size_t n,
                const MarchHits& hits) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void march_rays(Isa isa, const SurfaceFrame& frame, const MarchParams& params, const MarchRays& rays, std::size_t n,
                const MarchHits& hits) noexcept;

/// Primary rays of pixels x0 .. x0 + n - 1 of `row` at sub-pixel offset (sub_x, sub_y) (0.5 = centre),
/// from the camera position, with params.pixel_angle as given (normally camera.pixel_angle). Uses
/// fixed-size stack chunks: no allocation.
void march_camera_row(const SurfaceFrame& frame, const Camera& camera, const MarchParams& params, std::uint32_t row,
                      std::uint32_t x0, std::size_t n, float sub_x, float sub_y, const MarchHits& hits) noexcept;
void march_camera_row(Isa isa, const SurfaceFrame& frame, const Camera& camera, const MarchParams& params,
                      std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x, float sub_y,
                      const MarchHits& hits) noexcept;

namespace detail {
struct MarchContext;
}

/// The marcher's set-up for one frame and its parameters (the levels' tables, the cone, the noise's
/// bounds), made once by prepare() and used for every batch of the frame's rays; march_rays makes it
/// at every call, which cost a row of rays 1.5 us (docs/design.md 10). The frame must stay as it was
/// prepared while the plan marches against it. Construction allocates; prepare() and march() do not.
class MarchPlan {
 public:
  MarchPlan();
  ~MarchPlan();
  MarchPlan(MarchPlan&&) noexcept;
  MarchPlan& operator=(MarchPlan&&) noexcept;

  void prepare(const SurfaceFrame& frame, const MarchParams& params) noexcept;
  /// march_rays on the prepared frame and parameters, with the dispatched ISA.
  void march(const MarchRays& rays, std::size_t n, const MarchHits& hits) const noexcept;

 private:
  std::unique_ptr<detail::MarchContext> c_;
};

/// The marcher's surface for one frame and parameters, evaluated one point at a time by the scalar
/// reference exactly as the marcher does (LOD level, noise at the level for t): for dense references
/// in tests and for tools. Construction allocates (it is not frame-loop code).
class MarchProbe {
 public:
  MarchProbe(const SurfaceFrame& frame, const MarchParams& params);
  ~MarchProbe();
  MarchProbe(const MarchProbe&) = delete;
  MarchProbe& operator=(const MarchProbe&) = delete;

  /// f(t) = o_z + t d_z - S(o_xy + t d_xy) for the ray (o, d).
  float f(float ox, float oy, float oz, float dx, float dy, float dz, float t) const noexcept;
  /// The noise level the marcher uses at distance t on a ray with vertical component dz (0 without noise).
  float noise_level(float dz, float t) const noexcept;
  /// The marcher's bounds of |noise| and |grad noise| at distance t on a ray with vertical component dz
  /// (its envelope: they must bound capillary_height_bound and capillary_slope_bound at the level used).
  float noise_height_bound(float dz, float t) const noexcept;
  float noise_slope_bound(float dz, float t) const noexcept;
  /// The grid part of S at (x, y) (SurfaceFrame::height_at).
  float grid_height(float x, float y) const noexcept;
  /// The level of the grid read at (x, y): the number of levels' reaches below its Chebyshev distance
  /// to the centre, at most levels - 1; `levels` beyond the last reach (the far plane).
  float grid_level(float x, float y) const noexcept;
  /// The slab [z_lo, z_hi] rays are clipped to (grid slab widened by the noise bound).
  float slab_min() const noexcept;
  float slab_max() const noexcept;

 private:
  std::unique_ptr<detail::MarchContext> c_;
};

}  // namespace houle
