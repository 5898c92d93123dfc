// Linear (Airy) wave dispersion over finite depth (docs/physics.md 1).
//
//   omega^2 = g k tanh(k h);  with x = k h and y = k0 h = omega^2 h / g:  x tanh x = y.
//   C = omega / k,  Cg = n C,  n = (1 + 2kh / sinh 2kh) / 2 in [1/2, 1],  Ks = sqrt(Cg0 / Cg).
//
// Land (h <= 0) has no wave: every function here returns a defined value for it (0 or a flag), never
// NaN or infinity. Everything in double except the batched float kernel, which is what per-sample
// code uses (one omega, many depths).
#pragma once
#include <cstddef>

#include "houle/runtime/isa.hpp"

namespace houle {

/// m/s^2, the value docs/physics.md and the tests' oracle values use.
inline constexpr double gravity = 9.81;

/// The root x > 0 of x tanh x = y (x = kh, y = k0 h), Fenton & McKee's explicit start followed by
/// Newton's method to convergence (<= 5 iterations; relative residual < 1e-12 for y in [1e-8, 1e4]).
/// Returns 0 when y <= 0 or y is not finite (land or no wave).
double solve_kh(double k0h) noexcept;
/// The same from a nearby root (e.g. the previous sample along a ray): usually 1-2 iterations.
/// A guess that is not > 0 falls back to Fenton & McKee.
double solve_kh(double k0h, double guess) noexcept;

/// n = Cg / C at kh, in [1/2, 1], non-increasing in kh. Series 1 - (kh)^2/3 below kh = 1e-4 (float:
/// 0.02), and 1/2 above kh = 20, so sinh never overflows (docs/physics.md 1.1). kh <= 0 gives 1 (the
/// shallow limit).
double group_velocity_ratio(double kh) noexcept;
float group_velocity_ratio(float kh) noexcept;

/// Shoaling coefficient Ks = sqrt(Cg0 / Cg) = 1 / sqrt(2 n tanh kh) at kh (Cg0 = g / (2 omega), the
/// deep-water group speed). Minimum 0.9130 at k0h = 1; 1 in deep water. kh <= 0 gives 0 (land).
double shoaling_coefficient(double kh) noexcept;
float shoaling_coefficient(float kh) noexcept;

/// (1/C) dC/dh at fixed omega = 2k / (2kh + sinh 2kh), 1/m: 1/(2h) in shallow water, -> 0 in deep
/// water (0 beyond 2kh = 700). Rays bend by dtheta/ds = -(1/C) dC/dh dh/dn (docs/physics.md 2.2).
double celerity_depth_derivative(double k, double kh) noexcept;

/// Everything linear theory says about one wave at one depth.
struct LinearWave {
  double k = 0.0;    ///< rad/m
  double kh = 0.0;
  double c = 0.0;    ///< phase speed, m/s
  double cg = 0.0;   ///< group speed, m/s
  double n = 0.0;    ///< cg / c
  bool wet = false;  ///< false on land (depth <= 0) or for omega <= 0: then every field is 0
};
LinearWave linear_wave(double omega, double depth) noexcept;
/// The same from a nearby kh (warm start, see solve_kh).
LinearWave linear_wave(double omega, double depth, double kh_guess) noexcept;

/// Wavenumber (rad/m) of a wave of amplitude `amplitude` (m) at `depth` (m) by Kirby & Dalrymple's
/// (1986) composite dispersion relation, which the parabolic model uses (docs/physics.md 10.3):
///   omega^2 = g k (1 + f1 (kA)^2 D) tanh(kh + f2 kA),   f1 = tanh^5 kh,   f2 = (kh / sinh kh)^4,
///   D = (cosh 4kh + 8 - 2 tanh^2 kh) / (8 sinh^4 kh):
/// Stokes' third order in deep and intermediate water (omega^2 = g k (1 + (kA)^2) in deep water),
/// Hedges' tanh k(h + A) in shallow water. `k_linear` is the linear root at that depth (the start of
/// the iteration); the result, to 1e-9 relative, lies in (0, k_linear], k_linear for amplitude <= 0.
/// 0 on land.
double amplitude_dispersion_k(double omega, double depth, double amplitude, double k_linear) noexcept;

/// Deep-water wavenumber k0 = omega^2 / g, rad/m.
inline double deep_water_wavenumber(double omega) noexcept { return omega * omega / gravity; }

/// Wavenumber k[i] (rad/m) at depth[i] (m) for one omega (rad/s > 0), in float: Hunt's 6-term
/// rational start and Newton steps, with a tanh built from + - * / only, so every ISA gives the scalar
/// path's bits (x86-64, AArch64). Relative error <= 1e-6 against the converged double root for
/// 1e-4 <= kh <= 50; finite for every depth. depth <= 0 or NaN gives k = 0 (land). Any n, no
/// alignment; k may alias depth.
void dispersion_k_batch(double omega, const float* depth, std::size_t n, float* k) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void dispersion_k_batch(Isa isa, double omega, const float* depth, std::size_t n, float* k) noexcept;

}  // namespace houle
