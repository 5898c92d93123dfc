// The parabolic model's rational approximations (sim/src/pade_factors.hpp, docs/physics.md 10.2)
// against the functions they approximate, and the amplitude-dependent wavenumber (docs/physics.md
// 10.3) against its limits.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "houle/sim/dispersion.hpp"
#include "angles.hpp"
#include "pade_factors.hpp"

namespace {

using houle::detail::cplx;
using houle_test::pi;

// The propagator over a step of pi/4 (8 steps per wavelength), [3/3]: within the stated error for
// waves up to 60 deg off the march (X = -sin^2), unitary for every real X (nothing grows), and
// damping evanescent waves no less than it transmits them (|R| <= 1 below X = -1 too).
TEST(PadeFactors, PropagatorIsAccurateAndNeverGrows) {
  const double sigma = pi / 4.0;
  const houle::detail::PadeFactors r = houle::detail::rotated_pade(houle::detail::propagator_series(sigma, 0.0, 6), 0.0);
  ASSERT_EQ(r.num.size(), 3u);
  double worst40 = 0.0, worst60 = 0.0, largest = 0.0;
  for (double x = -200.0; x <= 20.0; x += 0.001) {
    const cplx exact = std::exp(cplx(0.0, sigma) * (std::sqrt(cplx(1.0 + x)) - 1.0));
    const double e = std::abs(r(x) - exact);
    if (x >= -0.4132 && x <= 1.0) worst40 = std::max(worst40, e);  // sin^2 40 deg
    if (x >= -0.75 && x <= 1.0) worst60 = std::max(worst60, e);
    largest = std::max(largest, std::abs(r(x)));
  }
  std::printf("propagator: %.2e within 40 deg, %.2e within 60 deg, largest |R| %.15f\n", worst40, worst60, largest);
  EXPECT_LT(worst40, 2e-5);
  EXPECT_LT(worst60, 5e-4);
  EXPECT_LE(largest, 1.0 + 1e-12);
}

// The flux transforms (1 + X)^(+-1/4), [2/2] rotated by 45 deg: within 4e-3 for waves up to 40 deg
// off the march and 1.2e-2 up to 60 deg, and finite (bounded by 2.6) over the evanescent range, where
// an unrotated approximant has its poles.
TEST(PadeFactors, RotatedPowersAreAccurateAndPoleFree) {
  for (const double p : {0.25, -0.25}) {
    const houle::detail::PadeFactors r = houle::detail::rotated_pade(houle::detail::power_series(p, pi / 4.0, 4), pi / 4.0);
    double worst40 = 0.0, worst60 = 0.0, largest = 0.0;
    for (double x = -0.75; x <= 1.0; x += 0.001) {
      const double e = std::abs(r(x) / std::pow(1.0 + x, p) - 1.0);
      worst60 = std::max(worst60, e);
      if (x >= -0.4132) worst40 = std::max(worst40, e);
    }
    for (double x = -500.0; x <= -1.0; x += 0.01) largest = std::max(largest, std::abs(r(x)));
    std::printf("(1 + X)^%g: relative error %.2e within 40 deg, %.2e within 60 deg, largest %.3f below X = -1\n", p,
                worst40, worst60, largest);
    EXPECT_LT(worst40, 4e-3);
    EXPECT_LT(worst60, 1.2e-2);
    EXPECT_LT(largest, 2.6) << "p " << p;
  }
}

// Kirby & Dalrymple's composite relation: the linear root for no amplitude, Stokes' third order in
// deep water (omega^2 = g k (1 + (kA)^2)), Hedges' tanh k(h + A) in shallow water (up to the
// composite's own O((kh)^2) departure from it), never above the linear k.
TEST(AmplitudeDispersion, MeetsItsLimits) {
  const double omega = 2.0 * pi / 8.0;
  for (const double h : {0.3, 2.0, 10.0, 300.0}) {
    const double k_lin = houle::linear_wave(omega, h).k;
    EXPECT_EQ(houle::amplitude_dispersion_k(omega, h, 0.0, k_lin), k_lin);
    for (const double a : {0.01, 0.1, 0.5}) {
      const double k = houle::amplitude_dispersion_k(omega, h, a, k_lin);
      EXPECT_LE(k, k_lin) << "h " << h << " a " << a;
      EXPECT_GT(k, 0.5 * k_lin);
      if (h == 300.0) {
        EXPECT_NEAR(houle::gravity * k * (1.0 + k * a * k * a) / (omega * omega), 1.0, 3e-9);  // k to 1e-9
      }
      if (h == 0.3) {
        // The composite's f2 = (kh / sinh kh)^4 is 1 - O((kh)^2), not quite Hedges' 1.
        const double kh = k_lin * h;
        EXPECT_NEAR(houle::gravity * k * std::tanh(k * (h + a)) / (omega * omega), 1.0, kh * kh * a / h);
      }
    }
  }
  EXPECT_EQ(houle::amplitude_dispersion_k(omega, 0.0, 0.1, 0.0), 0.0);  // land
}

}  // namespace
