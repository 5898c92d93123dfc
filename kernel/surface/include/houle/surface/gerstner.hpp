// Trochoidal (Gerstner) wave trains over a flat deep sea, evaluated as a height field.
//
// A train moves the surface particle with rest position u to
//   P(u) = u + q A D cos(theta),  z(u) = A sin(theta),  theta = k D.u - omega t + phi
// (D unit direction of travel, q in [0,1] steepness). The height at a horizontal point x is z(u)
// where P(u) = x, found by Newton's method on the summed trains; the gradient follows from the
// exact Jacobian (docs/physics.md 3.1), not from the one-train shortcut.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "houle/runtime/expected.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

struct GerstnerWave {
  float dir_x = 1.0f, dir_y = 0.0f;  ///< direction of travel (normalised on use)
  float wavenumber = 0.0f;           ///< k = 2 pi / L, rad/m, > 0
  float amplitude = 0.0f;            ///< A, m, >= 0
  float steepness = 0.0f;            ///< q in [0, 1]; 0 is a sine wave
  float omega = 0.0f;                ///< rad/s
  float phase = 0.0f;                ///< phi, rad
};

/// The trains' parameters at one time, ready for evaluation: SoA, with the time-dependent phase
/// omega t - phi reduced modulo 2 pi in double so that float never sees a large phase.
struct GerstnerFrame {
  static constexpr std::size_t max_waves = 32;
  std::uint32_t count = 0;
  alignas(64) float kx[max_waves];   ///< k D_x
  alignas(64) float ky[max_waves];   ///< k D_y
  alignas(64) float amp[max_waves];  ///< A
  alignas(64) float qax[max_waves];  ///< q A D_x
  alignas(64) float qay[max_waves];  ///< q A D_y
  alignas(64) float phase[max_waves];  ///< (omega t - phi) mod 2 pi, in [-pi, pi]
};

/// Fails when there are more than max_waves trains, a parameter is out of range, or
/// sum(q k A) >= 1 (the surface would fold onto itself: no height field).
Expected<GerstnerFrame> make_gerstner_frame(std::span<const GerstnerWave> waves, double time);

struct GerstnerOutput {
  float* height;  ///< n floats
  float* grad_x;  ///< n floats, dh/dx
  float* grad_y;  ///< n floats, dh/dy
};

/// Height and gradient at the n points (x[i], y[i]). Arrays need no alignment and may have any n.
/// Coordinates should be local (near the origin): float k x loses phase precision beyond ~1e4 rad.
/// `newton_steps` (>= 1) inverts the horizontal displacement; 3 reaches float precision for q k A <= 0.7.
void gerstner_eval(const GerstnerFrame& frame, const float* x, const float* y, std::size_t n,
                   GerstnerOutput out, int newton_steps = 3) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void gerstner_eval(Isa isa, const GerstnerFrame& frame, const float* x, const float* y, std::size_t n,
                   GerstnerOutput out, int newton_steps = 3) noexcept;

}  // namespace houle
