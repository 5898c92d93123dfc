#include "houle/sim/dispersion.hpp"

#include <cmath>

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "sim_table.hpp"

namespace houle {
namespace {

// Newton on f(x) = x tanh x - y, f' = tanh x + x (1 - tanh^2 x) > 0. From x > 0 the iterate stays
// positive (f / f' < x), and from Fenton & McKee's start (within 1.7 %) it converges in <= 4 steps
// (docs/physics.md 1.2); a warm start nearer the root needs fewer. Convergence is quadratic with a
// relative constant below 1, so once a step is below 1e-8 x the iterate it produced is within
// ~1e-16 x: stop there rather than spend a step confirming it.
double newton_kh(double y, double x) noexcept {
  for (int i = 0; i < 8; ++i) {
    const double t = std::tanh(x);
    const double dx = (x * t - y) / (t + x * (1.0 - t * t));
    x -= dx;
    if (std::fabs(dx) <= 1e-8 * x) break;
  }
  return x;
}

// Fenton & McKee (1990): x = y / tanh(y^(3/4))^(2/3), within 1.63 % and exact in both limits.
double fenton_mckee(double y) noexcept { return y / std::pow(std::tanh(std::pow(y, 0.75)), 2.0 / 3.0); }

bool positive_finite(double y) noexcept { return y > 0.0 && y < INFINITY; }

// Below `series_limit` the two-term series is exact to rounding (next term 0.156 kh^4) while the
// direct form rounds 2kh / sinh 2kh to just above 1 in float (n would exceed 1 and stop being monotone).
template <class T>
T group_velocity_ratio_impl(T kh) noexcept {
  constexpr T series_limit = sizeof(T) == sizeof(float) ? T(0.02) : T(1e-4);
  if (!(kh > T(0))) return T(1);
  if (kh < series_limit) return T(1) - kh * kh / T(3);
  if (kh > T(20)) return T(0.5);  // 2kh / sinh 2kh < 2e-16 there
  return T(0.5) * (T(1) + T(2) * kh / std::sinh(T(2) * kh));
}

template <class T>
T shoaling_coefficient_impl(T kh) noexcept {
  if (!(kh > T(0))) return T(0);
  return T(1) / std::sqrt(T(2) * group_velocity_ratio_impl(kh) * std::tanh(kh));
}

LinearWave make_linear_wave(double omega, double depth, double kh) noexcept {
  LinearWave w;
  if (!(kh > 0.0)) return w;
  w.kh = kh;
  w.k = kh / depth;
  // C = (g / omega) tanh kh rather than omega / k: no division by a huge k in very shallow water.
  w.c = gravity / omega * std::tanh(kh);
  w.n = group_velocity_ratio(kh);
  w.cg = w.n * w.c;
  w.wet = true;
  return w;
}

}  // namespace

double solve_kh(double k0h) noexcept {
  if (!positive_finite(k0h)) return 0.0;
  return newton_kh(k0h, fenton_mckee(k0h));
}

double solve_kh(double k0h, double guess) noexcept {
  if (!positive_finite(k0h)) return 0.0;
  return newton_kh(k0h, positive_finite(guess) ? guess : fenton_mckee(k0h));
}

double group_velocity_ratio(double kh) noexcept { return group_velocity_ratio_impl(kh); }
float group_velocity_ratio(float kh) noexcept { return group_velocity_ratio_impl(kh); }
double shoaling_coefficient(double kh) noexcept { return shoaling_coefficient_impl(kh); }
float shoaling_coefficient(float kh) noexcept { return shoaling_coefficient_impl(kh); }

double celerity_depth_derivative(double k, double kh) noexcept {
  if (!(kh > 0.0) || !(k > 0.0)) return 0.0;
  if (kh > 350.0) return 0.0;  // sinh would overflow; the true value is below 1e-300 k
  return 2.0 * k / (2.0 * kh + std::sinh(2.0 * kh));
}

LinearWave linear_wave(double omega, double depth) noexcept {
  if (!positive_finite(omega) || !positive_finite(depth)) return {};
  return make_linear_wave(omega, depth, solve_kh(deep_water_wavenumber(omega) * depth));
}

LinearWave linear_wave(double omega, double depth, double kh_guess) noexcept {
  if (!positive_finite(omega) || !positive_finite(depth)) return {};
  return make_linear_wave(omega, depth, solve_kh(deep_water_wavenumber(omega) * depth, kh_guess));
}

double amplitude_dispersion_k(double omega, double depth, double amplitude, double k_linear) noexcept {
  if (!positive_finite(depth) || !positive_finite(k_linear)) return 0.0;
  if (!positive_finite(amplitude)) return k_linear;
  const double w2 = omega * omega;
  // f1 D written as tanh kh (cosh 4kh + 8 - 2 tanh^2 kh) / (8 cosh^4 kh): finite as kh -> 0, and 1
  // (to e^-40) beyond kh = 20, where cosh 4kh would overflow first.
  const auto residual = [&](double k) {
    const double kh = k * depth, e = k * amplitude;
    double f1d = 1.0, f2 = 0.0;
    if (kh < 20.0) {
      const double t = std::tanh(kh), c = std::cosh(kh);
      f1d = t * (std::cosh(4.0 * kh) + 8.0 - 2.0 * t * t) / (8.0 * c * c * c * c);
      const double r = kh < 1e-4 ? 1.0 : kh / std::sinh(kh);
      f2 = r * r * r * r;
    }
    return gravity * k * (1.0 + f1d * e * e) * std::tanh(kh + f2 * e) - w2;
  };
  // residual(k_linear) >= 0 (both corrections raise the phase speed) and residual -> -omega^2 as k
  // -> 0: bracket the root, then Illinois regula falsi to 1e-9 relative (the march needs far less).
  double hi = k_linear, f_hi = residual(hi);
  if (!(f_hi > 0.0)) return k_linear;
  double lo = 0.5 * k_linear, f_lo = residual(lo);
  while (f_lo > 0.0 && lo > 1e-6 * k_linear) {
    hi = lo;
    f_hi = f_lo;
    lo *= 0.5;
    f_lo = residual(lo);
  }
  if (f_lo > 0.0) return lo;
  int side = 0;
  double k = hi;
  for (int i = 0; i < 60 && hi - lo > 1e-9 * hi; ++i) {
    k = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    const double f = residual(k);
    if (f > 0.0) {
      hi = k;
      f_hi = f;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    } else {
      lo = k;
      f_lo = f;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    }
    if (std::fabs(f) <= 1e-10 * w2) break;
  }
  return k;
}

namespace {
void check_batch(double omega, const float* depth, std::size_t n, const float* k) noexcept {
  HOULE_ASSERT(omega > 0.0, "dispersion_k_batch: omega > 0 rad/s");
  HOULE_ASSERT(n == 0 || (depth != nullptr && k != nullptr), "dispersion_k_batch: n floats in depth and k");
}
}  // namespace

void dispersion_k_batch(double omega, const float* depth, std::size_t n, float* k) noexcept {
  check_batch(omega, depth, n, k);
  simd::active_table<detail::SimTable>().dispersion_k_batch(float(deep_water_wavenumber(omega)), depth, n, k);
}

void dispersion_k_batch(Isa isa, double omega, const float* depth, std::size_t n, float* k) noexcept {
  check_batch(omega, depth, n, k);
  simd::table_for<detail::SimTable>(isa).dispersion_k_batch(float(deep_water_wavenumber(omega)), depth, n, k);
}

}  // namespace houle
