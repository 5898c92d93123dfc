// Functions of an operator X as products of first-degree rational factors,
//   f(X) ~ scale * prod_j (1 + num_j X) / (1 + den_j X),
// for the parabolic wave model (docs/physics.md 10): with X tridiagonal, each factor costs one
// tridiagonal product and one tridiagonal solve. The factors come from the [m/m] Pade approximant of f,
// taken about X = e^{i alpha} - 1 instead of 0 when alpha != 0 (a "rotated" approximant: Milinazzo,
// Zala & Brooke 1997): the functions here have a branch point at X = -1, where evanescent waves begin,
// and rotating the branch cut into the complex plane keeps every denominator away from zero for real X.
// Internal to houle_sim.
#pragma once
#include <complex>
#include <span>
#include <vector>

namespace houle::detail {

using cplx = std::complex<double>;

struct PadeFactors {
  cplx scale = 1.0;
  std::vector<cplx> num, den;  ///< m each

  /// The approximant at a scalar X.
  cplx operator()(cplx x) const noexcept;
};

/// Factors of the [m/m] Pade approximant (m = (taylor.size() - 1) / 2) of g(Y) at Y = 0, given g's
/// Taylor coefficients g_0 .. g_2m, written in X = e^{i alpha} (1 + Y) - 1.
PadeFactors rotated_pade(std::span<const cplx> taylor, double alpha);

/// Taylor coefficients 0 .. n in Y of exp(i sigma (e^{i alpha / 2} sqrt(1 + Y) - 1)): with
/// 1 + X = e^{i alpha} (1 + Y), the one-way propagator exp(i sigma (sqrt(1 + X) - 1)) over a step of
/// sigma radians of the reference wave.
std::vector<cplx> propagator_series(double sigma, double alpha, int n);

/// Taylor coefficients 0 .. n in Y of e^{i alpha p} (1 + Y)^p, i.e. of (1 + X)^p.
std::vector<cplx> power_series(double p, double alpha, int n);

}  // namespace houle::detail
