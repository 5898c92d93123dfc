// Fresnel integrals in the pi/2 convention (as scipy.special.fresnel, which returns (S, C)):
//   C(x) = int_0^x cos(pi t^2 / 2) dt,   S(x) = int_0^x sin(pi t^2 / 2) dt,
// and the auxiliary functions f, g of Abramowitz & Stegun 7.3.5-7.3.6, defined for z >= 0 by
//   int_z^inf e^{i pi t^2/2} dt = (g(z) + i f(z)) e^{i pi z^2/2}.
// The diffraction code works with g + i f rather than with C and S: it is smooth and of size
// ~1/(pi z), so the deep shadow (where 1/2 - C and 1/2 - S cancel) keeps full relative precision,
// and its large phase pi z^2/2 can be merged exactly with the plane-wave phase (docs/physics.md 4.4).
// Internal to houle_sim (and its tests).
#pragma once
#include <complex>

namespace houle::detail {

struct FresnelCS {
  double c;  ///< C(x)
  double s;  ///< S(x)
};

/// C(x) and S(x) for any real x (odd functions; +-1/2 at +-inf; NaN in, NaN out). About 1e-15
/// absolute and relative (power series for |x| < fresnel_series_limit, continued fraction beyond).
FresnelCS fresnel(double x) noexcept;

/// g(z) + i f(z) for z >= 0 (|z| is used). g(0) = f(0) = 1/2; f ~ 1/(pi z), g ~ 1/(pi^2 z^3) at inf.
/// Relative error about 1e-15 in f and 3e-14 in g (g is the small part: |g| < |f|/(pi z^2)).
std::complex<double> fresnel_aux(double z) noexcept;

/// int_z^inf e^{i pi t^2/2} dt for any real z: (1/2 - C(z)) + i (1/2 - S(z)), computed without the
/// cancellation of that form for large z (the phase pi z^2/2 is reduced exactly modulo 2 pi).
std::complex<double> fresnel_tail(double z) noexcept;

/// |x| below which the power series is used (the continued fraction converges slowly there).
inline constexpr double fresnel_series_limit = 1.5;

/// Cheap g(z) + i f(z) for z >= 0 (|z| is used) from the rational fits A&S 7.3.32-7.3.33:
/// absolute error <= 2e-3 in f and in g. For float kernels; no loop, no branch but the abs.
std::complex<float> fresnel_aux_fg(float z) noexcept;

}  // namespace houle::detail
