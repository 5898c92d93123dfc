#include "fresnel_integrals.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace houle::detail {
namespace {

using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();

// 1 / z by Smith's method: std::complex's operator/ calls libgcc's __divdc3 (full C Annex G
// handling of infinities and NaNs), a fifth of a sea grid's build when it was used in the fraction
// below, whose operands are finite and never both tiny.
cplx reciprocal(cplx z) noexcept {
  const double a = z.real(), b = z.imag();
  if (std::fabs(a) >= std::fabs(b)) {
    const double r = b / a, den = a + b * r;
    return {1.0 / den, -r / den};
  }
  const double r = a / b, den = a * r + b;
  return {r / den, -1.0 / den};
}

// C(x) + i S(x) = sum_k (i pi x^2/2)^k / k! * x / (2k+1)   (termwise integration of e^{i pi t^2/2}).
// For |x| < 1.5 the largest term is ~7 for a sum of ~0.8: about one digit lost to cancellation.
cplx series(double x) noexcept {
  const cplx w{0.0, pi / 2 * x * x};
  cplx term{1.0, 0.0};  // w^k / k!
  cplx sum{1.0, 0.0};
  for (int k = 1; k < 60; ++k) {
    term *= w / double(k);
    const cplx add = term / double(2 * k + 1);
    sum += add;
    if (std::abs(add) < 0.25 * eps * std::abs(sum)) break;
  }
  return x * sum;
}

// g + i f = z h, with h the even part of the classic continued fraction of erfc(w) e^{w^2}
// taken at w = (1 - i) (sqrt(pi)/2) z (since C + iS = (1+i)/2 erf(w)):
//   h = 1/(b0 + a1/(b1 + a2/(b2 + ...))),  b_n = 1 - i pi z^2 + 4n,  a_n = -(2n-1)(2n),
// evaluated forward by the modified Lentz method. It needs ~50 terms at z = 1.5, 14 at z = 3, 4 at
// z = 10; below 1.5 it converges too slowly and the series takes over.
cplx continued_fraction(double z) noexcept {
  constexpr double tiny = 1e-300;
  const cplx b0{1.0, -pi * z * z};
  cplx b = b0;
  cplx c = 1.0 / tiny;
  cplx d = reciprocal(b0);
  cplx h = d;
  for (int n = 1; n < 500; ++n) {
    const double a = -double(2 * n - 1) * double(2 * n);
    b += 4.0;
    d = reciprocal(a * d + b);
    c = b + a * reciprocal(c);
    const cplx delta = c * d;
    h *= delta;
    if (std::abs(delta.real() - 1.0) + std::abs(delta.imag()) < 3.0 * eps) break;
  }
  return z * h;
}

// e^{i pi z^2/2} with the phase reduced exactly: z^2 = s + e exactly (fma), s mod 4 is exact,
// so the angle keeps ~1e-16 absolute accuracy however large z is. A plain std::polar(1, pi z*z/2)
// would lose ~z^2 * 1e-16 rad.
cplx unit_phase_pi2_z2(double z) noexcept {
  const double s = z * z;
  const double e = std::fma(z, z, -s);
  const double turns = std::fmod(s, 4.0) + e;  // in units of pi/2, in [-tiny, 4 + tiny]
  return std::polar(1.0, pi / 2 * turns);
}

}  // namespace

cplx fresnel_aux(double z) noexcept {
  z = std::fabs(z);
  if (std::isnan(z)) return {z, z};
  if (z < fresnel_series_limit) {
    // Tail = (1+i)/2 - (C + iS); both are O(1) here, no cancellation. The phase is small.
    const cplx tail = cplx{0.5, 0.5} - series(z);
    return tail * std::polar(1.0, -pi / 2 * z * z);
  }
  // Past ~1e150 z^2 overflows inside the fraction; f = 1/(pi z) is then exact to double precision
  // and g ~ 1/(pi^2 z^3) underflows.
  if (z > 1e150) return {0.0, 1.0 / (pi * z)};
  return continued_fraction(z);
}

cplx fresnel_tail(double z) noexcept {
  if (std::isnan(z)) return {z, z};
  if (z < 0.0) return cplx{1.0, 1.0} - fresnel_tail(-z);  // the whole line integrates to 1 + i
  if (z < fresnel_series_limit) return cplx{0.5, 0.5} - series(z);
  if (z > 1e150) return {0.0, 0.0};  // |tail| < 1e-150, and z^2 would overflow
  return continued_fraction(z) * unit_phase_pi2_z2(z);
}

FresnelCS fresnel(double x) noexcept {
  if (std::isnan(x)) return {x, x};
  const double ax = std::fabs(x);
  cplx cs;
  if (ax < fresnel_series_limit) {
    cs = series(ax);
  } else {
    cs = cplx{0.5, 0.5} - fresnel_tail(ax);
  }
  return x < 0.0 ? FresnelCS{-cs.real(), -cs.imag()} : FresnelCS{cs.real(), cs.imag()};
}

std::complex<float> fresnel_aux_fg(float z) noexcept {
  z = std::fabs(z);
  const float f = (1.0f + 0.926f * z) / (2.0f + z * (1.792f + z * 3.104f));
  const float g = 1.0f / (2.0f + z * (4.142f + z * (3.492f + z * 6.670f)));
  return {g, f};
}

}  // namespace houle::detail
