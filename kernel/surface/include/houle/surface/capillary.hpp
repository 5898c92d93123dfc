// Capillary ripples: fractal value noise with a continuous distance level (paper eq. 9,
// docs/physics.md 6, docs/rendering.md 5).
//
//   h(x, y) = sum_{i=1..n_max} W_i(level) a_i N_i(x, y, t),   a_i = amplitude k^(1-i)
//   W_i(level) = smoothstep(clamp((level - (i - 1)) s, 0, 1)),   s = min(1, log2 k)
//
// N_i is 2-D lattice value noise (lattice values in [-1, 1], Catmull-Rom interpolation, C1) of
// spacing lambda_i = base_wavelength k^(1-i), with the lattice rotated by a fixed angle per octave
// (no shared grid axes) and translated at the octave's own capillary-gravity phase speed (cheap
// animation: 16 lattice values per octave per sample, no 3-D lattice). For level = n + D this is
// the paper's F(n, D) with octave n+1 faded in by smoothstep(D) so h is C1 in level:
// h(level = n with D = 1) = h(level = n + 1 with D = 0). In the paper's units
// h = amplitude k F_paper(x / (k base_wavelength)). For k < 2 an octave fades over 1/s levels, a
// factor 2 of footprint, not over the factor k: with k = 1.25 all the octaves went within 25 % of
// distance, a hard circle (docs/rendering.md 5.2); several octaves then fade at once.
//
// Coordinates are local: (x, y) in m from the frame's origin, which (like time) is folded into the
// per-octave lattice offsets in double, so float never sees large world coordinates or times.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/runtime/expected.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

struct CapillaryParams {
  float amplitude = 0.01f;              ///< m, bound of octave 1's lattice values (octave i: k^(1-i) of it)
  float base_wavelength = 0.5f;         ///< m, lattice spacing lambda_1 of octave 1 (> 0)
  float lacunarity = 2.0f;              ///< k, frequency ratio between octaves, in [1.25, 4]
  int max_octaves = 6;                  ///< n_max in [0, CapillaryFrame::max_octaves]: levels are clamped to it
  float animation_rate = 1.0f;          ///< multiplies the physical drift speeds (0 freezes), >= 0
  float direction = 0.0f;               ///< rad, mean drift direction (octaves spread around it)
  float samples_per_wavelength = 2.0f;  ///< N of the LOD rule: octave i is whole while lambda_i >= N footprint (>= 1)
};

/// Everything about one frame that does not depend on the pixel. Fixed size, no heap.
/// Octave i (0-based here) maps local (x, y) in m to lattice units
///   u = mxu[i] x + myu[i] y + off_u[i],  v = mxv[i] x + myv[i] y + off_v[i]
/// with off_* = (world origin, drift and a fixed per-octave shift) reduced modulo the period in double.
struct CapillaryFrame {
  static constexpr std::size_t max_octaves = 8;
  static constexpr int period = 256;  ///< lattice period in cells, per octave
  CapillaryParams params{};           ///< as validated (for the bound helpers)
  std::uint32_t octaves = 0;          ///< n_max
  float coord_limit = 0.0f;           ///< m: |x|, |y| are clamped to it (lattice coordinates < 2^21: exact floor)
  alignas(32) float mxu[max_octaves] = {};
  alignas(32) float myu[max_octaves] = {};
  alignas(32) float mxv[max_octaves] = {};
  alignas(32) float myv[max_octaves] = {};
  alignas(32) float off_u[max_octaves] = {};  ///< lattice units, [0, period] (period itself only by rounding)
  alignas(32) float off_v[max_octaves] = {};
  alignas(32) float value_scale[max_octaves] = {};  ///< a_i / 508 (the kernel sums 2w * 2w * q with |q| <= 127)
  float fade_rate = 1.0f;  ///< s = min(1, log2 k): W_i ramps over 1/s levels
};

/// One octave's geometry in double (0-based i), shared by make_capillary_frame and by references.
struct CapillaryOctave {
  double amplitude;         ///< m, bound of the lattice values
  double spacing;           ///< m, lattice spacing lambda_i
  double cos_angle, sin_angle;  ///< lattice orientation: u = (cos x + sin y) / spacing + ..., v = (-sin x + cos y) / spacing + ...
  double velocity_x, velocity_y;  ///< m/s in world (animation_rate applied): the pattern moves with it
  double shift_u, shift_v;  ///< fixed lattice offset, lattice units
};
/// Octave i of params (i < CapillaryFrame::max_octaves; params need not be validated).
CapillaryOctave capillary_octave(const CapillaryParams& params, int i) noexcept;

/// The frame at time_s for local coordinates measured from the world point (origin_x, origin_y) m.
/// Fails on out-of-range parameters or non-finite time/origin.
Expected<CapillaryFrame> make_capillary_frame(const CapillaryParams& params, double time_s, double origin_x = 0.0,
                                              double origin_y = 0.0);

/// Height h (m) and gradient (dh/dx, dh/dy) at local points (x[i], y[i]) with level[i] in [0, n_max]
/// (clamped; NaN counts as 0). Level is per sample and is held constant in the gradient: give every
/// sample of a pixel (hit test, normal) the same level (docs/rendering.md 5.3). Octaves above a sample's
/// level are skipped, so cost follows distance. Arrays need no alignment; any n; results do not
/// depend on the other samples in the call, and every ISA gives the scalar path's bits.
/// grad_x and grad_y may both be null: heights only (~25% cheaper), the same height bits.
/// Keep |x|, |y| small (camera- or tile-relative): at 20 m the finest octave's float lattice
/// coordinate carries ~1e-4 cell of rounding (heights to ~3e-5 amplitude, gradients to ~5e-4 of
/// amplitude / base_wavelength); |x|, |y| are clamped to coord_limit.
void capillary_eval(const CapillaryFrame& frame, const float* x, const float* y, const float* level, std::size_t n,
                    float* h, float* grad_x, float* grad_y) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void capillary_eval(Isa isa, const CapillaryFrame& frame, const float* x, const float* y, const float* level,
                    std::size_t n, float* h, float* grad_x, float* grad_y) noexcept;

/// Pixel footprint on the water along the view direction (docs/rendering.md 5.2):
/// distance * pixel_angle / sin(grazing), sin clamped below at 1e-3.
float capillary_footprint(float distance_m, float pixel_angle_rad, float sin_grazing) noexcept;
/// Continuous level for a footprint (m): clamp(log_k(lambda_1 / (N footprint)) + 1/s, 0, top) with
/// top = capillary_top_level. Octave i is whole while lambda_i >= N footprint and fades out over the
/// next factor max(k, 2). footprint <= 0 gives top, NaN gives 0.
float octave_level(const CapillaryParams& params, float footprint_m) noexcept;
/// octave_level of capillary_footprint(distance_m, pixel_angle_rad, sin_grazing).
float octave_level(const CapillaryParams& params, float distance_m, float pixel_angle_rad, float sin_grazing) noexcept;
/// The fade rate s = min(1, log2 k) and the highest level, n_max - 1 + 1/s (n_max for k >= 2), where
/// every octave is whole.
float capillary_fade_rate(const CapillaryParams& params) noexcept;
float capillary_top_level(const CapillaryParams& params) noexcept;

/// Bounds for levels <= level (all are nondecreasing in level; use the largest level a ray segment
/// can see). Height: max |h| <= amplitude 1.30 sum_i W_i k^(1-i) (the Catmull-Rom interpolant's bound on
/// houle's lattice, docs/physics.md 6.1), for the marcher's slab H_box. Slope: max |grad h| <=
/// (amplitude / lambda_1) 3.31 sum_i W_i (a bound on the gradient's length: a Lipschitz constant, m/m).
/// Both carry a 2^-12 relative margin for rounding.
float capillary_height_bound(const CapillaryParams& params, float level) noexcept;
float capillary_slope_bound(const CapillaryParams& params, float level) noexcept;

/// Per-axis slope variance (dimensionless) of one octave; the same for every octave because
/// a_i / lambda_i is constant: (amplitude / lambda_1)^2 var(lattice) (57/70) (7/3). The slopes are
/// isotropic (x and y variances equal, covariance 0) and independent between octaves.
float octave_slope_variance(const CapillaryParams& params) noexcept;
/// Per-axis slope variance that a surface at `level` lacks compared with n_max octaves:
/// octave_slope_variance * sum_i (1 - W_i^2). Add it to the BRDF's slope variance (docs/rendering.md 5.4)
/// so total roughness does not change with distance.
float dropped_slope_variance(const CapillaryParams& params, float level) noexcept;
/// dropped_slope_variance with what does not depend on the level (the fade rate, a log2, and the
/// octave's variance) worked out once: the renderer asks it per sea pixel. The same bits.
struct DroppedSlopeVariance {
  float octave_variance = 0.0f, fade_rate = 1.0f;
  int octaves = 0;
  explicit DroppedSlopeVariance(const CapillaryParams& params) noexcept;
  DroppedSlopeVariance() noexcept = default;
  float operator()(float level) const noexcept;
};

/// Lattice value at integer point (i, j), in [-1, 1], period 256 in both: for reference implementations.
float capillary_lattice_value(std::int32_t i, std::int32_t j) noexcept;

}  // namespace houle
