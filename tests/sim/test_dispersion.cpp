// Dispersion against converged references and the values of docs/physics.md 1 and 8.1-8.3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "houle/sim/dispersion.hpp"
#include "dispersion_table.hpp"  // sim/src: the ray tracer's tabulated kh
#include "ulp.hpp"
#include "angles.hpp"

namespace {

using houle_test::pi;

// Independent oracle: bisection on x tanh x = y in long double (no shared start, no Newton).
double reference_kh(double y) {
  long double lo = 0.0L, hi = std::max<long double>(y, std::sqrt((long double)y)) + 1.0L;
  for (int i = 0; i < 200; ++i) {
    const long double mid = 0.5L * (lo + hi);
    (mid * std::tanh(mid) < (long double)y ? lo : hi) = mid;
  }
  return double(0.5L * (lo + hi));
}

std::vector<double> log_space(double a, double b, int n) {
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i) v[i] = a * std::pow(b / a, double(i) / (n - 1));
  return v;
}

TEST(Dispersion, SolveKhMatchesConvergedRootOverKhRange) {
  // Tolerance 1e-6 relative (the brief); measured ~1e-16.
  double worst = 0.0;
  for (double kh : log_space(1e-4, 50.0, 4001)) {
    const double y = double((long double)kh * std::tanh((long double)kh));
    const double ref = reference_kh(y);
    worst = std::max(worst, std::fabs(houle::solve_kh(y) / ref - 1.0));
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("solve_kh vs bisection oracle, kh in [1e-4, 50]: max rel err %.2e\n", worst);
}

TEST(Dispersion, ResidualBelow1e12OverWholeRange) {
  // docs/physics.md 8.1: relative residual of x tanh x = y below 1e-12 for y in [1e-8, 1e4].
  double worst = 0.0;
  for (double y : log_space(1e-8, 1e4, 20001)) {
    const double x = houle::solve_kh(y);
    worst = std::max(worst, std::fabs(x * std::tanh(x) - y) / y);
  }
  EXPECT_LT(worst, 1e-12);
  std::printf("solve_kh relative residual, y in [1e-8, 1e4]: max %.2e\n", worst);
}

TEST(Dispersion, TracerTableMatchesTheSolver) {
  // The ray tracer's kh(k0h) table (cubic Hermite in sqrt(k0h)): stated tolerance 1e-12 relative.
  double worst = 0.0;
  for (double y : log_space(1e-10, 1e4, 200001)) {
    worst = std::max(worst, std::fabs(houle::detail::kh_from_table(y) / houle::solve_kh(y) - 1.0));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(houle::detail::kh_from_table(0.0), 0.0);
  EXPECT_EQ(houle::detail::kh_from_table(-1.0), 0.0);
  EXPECT_EQ(houle::detail::kh_from_table(std::numeric_limits<double>::quiet_NaN()), 0.0);
  std::printf("kh table vs solver, k0h in [1e-10, 1e4]: max rel err %.2e\n", worst);
}

TEST(Dispersion, WarmStartGivesTheSameRoot) {
  for (double y : log_space(1e-6, 1e3, 301)) {
    const double x = houle::solve_kh(y);
    for (double f : {0.5, 0.9, 1.01, 2.0, 10.0}) EXPECT_NEAR(houle::solve_kh(y, f * x) / x, 1.0, 1e-14) << y;
    EXPECT_EQ(houle::solve_kh(y, -1.0), x);  // bad guesses fall back to the explicit start
  }
}

TEST(Dispersion, DeepAndShallowLimits) {
  const double omega = 2.0 * pi / 7.0, k0 = houle::deep_water_wavenumber(omega);
  // Deep: k -> omega^2 / g (tanh kh = 1 to double precision beyond kh ~ 19).
  for (double h : {500.0, 1000.0, 1e4}) EXPECT_NEAR(houle::linear_wave(omega, h).k / k0, 1.0, 1e-14);
  EXPECT_NEAR(houle::linear_wave(omega, 100.0).c / (houle::gravity / omega), 1.0, 1e-6);
  // Shallow: k -> omega / sqrt(g h), with relative correction kh^2 / 6.
  for (double h : {1e-6, 1e-4, 1e-3}) {
    const houle::LinearWave w = houle::linear_wave(omega, h);
    EXPECT_NEAR(w.k * std::sqrt(houle::gravity * h) / omega, 1.0, w.kh * w.kh) << h;
    EXPECT_NEAR(w.c / std::sqrt(houle::gravity * h), 1.0, w.kh * w.kh) << h;
    EXPECT_NEAR(w.n, 1.0, w.kh * w.kh);
  }
  // docs/physics.md 1.1: kh > pi => C within 0.4 % of g/omega and n = 0.512 at kh = pi.
  EXPECT_NEAR(houle::group_velocity_ratio(pi), 0.512, 5e-4);
  EXPECT_LT(1.0 - std::tanh(pi), 0.0038);
}

template <class T>
void check_group_ratio_range_and_monotone() {
  T prev = T(1);
  for (double kh : log_space(1e-9, 2000.0, 40001)) {
    const T n = houle::group_velocity_ratio(T(kh));
    ASSERT_TRUE(std::isfinite(n)) << kh;
    ASSERT_GE(n, T(0.5)) << kh;
    ASSERT_LE(n, T(1)) << kh;
    ASSERT_LE(n, prev) << "n must not increase with kh, at kh = " << kh;
    prev = n;
  }
}

TEST(Dispersion, GroupRatioInHalfToOneAndMonotone) {
  check_group_ratio_range_and_monotone<double>();
  check_group_ratio_range_and_monotone<float>();
}

TEST(Dispersion, NoNanOrInfAtExtremeKh) {
  for (double kh : {1e-8, 1e-4, 20.0, 40.0, 89.0, 360.0, 1000.0}) {
    for (double v : {houle::group_velocity_ratio(kh), houle::shoaling_coefficient(kh),
                     houle::celerity_depth_derivative(kh / 3.0, kh)}) {
      EXPECT_TRUE(std::isfinite(v)) << kh;
    }
    for (float v : {houle::group_velocity_ratio(float(kh)), houle::shoaling_coefficient(float(kh))}) {
      EXPECT_TRUE(std::isfinite(v)) << kh;
    }
  }
  // Depths that put kh at 1e-8 and 1000 (float and double paths).
  const double omega = 2.0 * pi / 10.0, k0 = houle::deep_water_wavenumber(omega);
  for (double kh : {1e-8, 1000.0}) {
    const double h = kh * std::tanh(kh) / k0;
    const houle::LinearWave w = houle::linear_wave(omega, h);
    ASSERT_TRUE(w.wet);
    EXPECT_NEAR(w.kh / kh, 1.0, 1e-12);
    for (double v : {w.k, w.c, w.cg, w.n}) EXPECT_TRUE(std::isfinite(v) && v > 0.0);
    const float depth = float(h);
    for (houle::Isa isa : houle::supported_isas()) {
      float k = -1.0f;
      houle::dispersion_k_batch(isa, omega, &depth, 1, &k);
      EXPECT_TRUE(std::isfinite(k) && k > 0.0f) << houle::isa_name(isa);
      EXPECT_NEAR(double(k) * double(depth) / kh, 1.0, 2e-6) << houle::isa_name(isa) << " kh " << kh;
    }
  }
}

TEST(Dispersion, LandIsAFlagNeverNan) {
  const double omega = 1.0;
  for (double h : {0.0, -0.0, -1.0, -1e9, std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()}) {
    const houle::LinearWave w = houle::linear_wave(omega, h);
    EXPECT_FALSE(w.wet);
    EXPECT_EQ(w.k, 0.0);
    EXPECT_EQ(w.c, 0.0);
    EXPECT_EQ(w.cg, 0.0);
  }
  EXPECT_FALSE(houle::linear_wave(0.0, 10.0).wet);
  EXPECT_EQ(houle::solve_kh(0.0), 0.0);
  EXPECT_EQ(houle::solve_kh(-3.0), 0.0);
  EXPECT_EQ(houle::solve_kh(std::numeric_limits<double>::quiet_NaN()), 0.0);
  EXPECT_EQ(houle::shoaling_coefficient(0.0), 0.0);
  EXPECT_EQ(houle::shoaling_coefficient(-1.0f), 0.0f);
  EXPECT_EQ(houle::celerity_depth_derivative(1.0, -1.0), 0.0);
  const std::vector<float> depth = {0.0f, -0.0f, -5.0f, std::numeric_limits<float>::quiet_NaN(),
                                    -std::numeric_limits<float>::infinity(), 1e-38f, 3.0f};
  for (houle::Isa isa : houle::supported_isas()) {
    std::vector<float> k(depth.size(), -1.0f);
    houle::dispersion_k_batch(isa, omega, depth.data(), depth.size(), k.data());
    for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(k[i], 0.0f) << houle::isa_name(isa) << " " << i;
    for (std::size_t i = 5; i < depth.size(); ++i) EXPECT_TRUE(std::isfinite(k[i]) && k[i] > 0.0f);
  }
}

TEST(Dispersion, ShoalingCoefficientReferenceValues) {
  // docs/physics.md 1.3 (dispersion_check.py), 4 decimals.
  const struct {
    double k0h, ks;
  } table[] = {{0.01, 2.2417}, {0.1, 1.2894}, {0.5, 0.9553}, {1.0, 0.9130}, {2.0, 0.9548}, {5.0, 0.9996}};
  for (const auto& r : table) EXPECT_NEAR(houle::shoaling_coefficient(houle::solve_kh(r.k0h)), r.ks, 5e-5) << r.k0h;
  // The minimum is 0.9130 at k0h = 1.00 (kh = 1.20).
  double best = 10.0, where = 0.0;
  for (double y : log_space(0.3, 3.0, 20001)) {
    const double ks = houle::shoaling_coefficient(houle::solve_kh(y));
    if (ks < best) best = ks, where = y;
  }
  EXPECT_NEAR(best, 0.9130, 5e-5);
  EXPECT_NEAR(where, 1.0, 0.01);
  // Green's law (4 k0h)^(-1/4) within 0.3 % for k0h <= 0.01.
  double worst = 0.0;
  for (double y : log_space(1e-6, 0.01, 401)) {
    worst = std::max(worst, std::fabs(houle::shoaling_coefficient(houle::solve_kh(y)) / std::pow(4.0 * y, -0.25) - 1.0));
  }
  EXPECT_LT(worst, 0.003);
  std::printf("Ks: min %.5f at k0h = %.4f; Green's law max deviation for k0h <= 0.01: %.3f %%\n", best, where,
              100.0 * worst);
  // Deep water: Ks -> 1.
  EXPECT_NEAR(houle::shoaling_coefficient(30.0), 1.0, 1e-15);
}

TEST(Dispersion, CelerityDepthDerivativeMatchesFiniteDifferences) {
  // docs/physics.md 2.2 / ray_checks.py: (1/C) dC/dh = 2k / (2kh + sinh 2kh) at fixed omega, to 7 digits.
  const double omega = 2.0 * pi / 8.0;
  for (double h : {0.5, 3.0, 10.0, 40.0}) {
    const double e = 1e-6;
    const double fd = (houle::linear_wave(omega, h + e).c - houle::linear_wave(omega, h - e).c) / (2.0 * e) /
                      houle::linear_wave(omega, h).c;
    const houle::LinearWave w = houle::linear_wave(omega, h);
    EXPECT_NEAR(houle::celerity_depth_derivative(w.k, w.kh) / fd, 1.0, 1e-7) << h;
  }
}

TEST(Dispersion, FloatBatchAccuracyAgainstDouble) {
  // Stated tolerance: 1e-6 relative for kh in [1e-4, 50] on every ISA.
  const double omega = 2.0 * pi / 5.0, k0 = houle::deep_water_wavenumber(omega);
  std::vector<float> depth;
  std::vector<double> ref;
  for (double kh : log_space(1e-4, 50.0, 5003)) {
    const float h = float(kh * std::tanh(kh) / k0);
    depth.push_back(h);
    ref.push_back(houle::solve_kh(k0 * double(h)) / double(h));
  }
  for (houle::Isa isa : houle::supported_isas()) {
    std::vector<float> k(depth.size());
    houle::dispersion_k_batch(isa, omega, depth.data(), depth.size(), k.data());
    double worst = 0.0;
    for (std::size_t i = 0; i < k.size(); ++i) worst = std::max(worst, std::fabs(double(k[i]) / ref[i] - 1.0));
    EXPECT_LT(worst, 1e-6) << houle::isa_name(isa);
    std::printf("dispersion_k_batch %s vs double: max rel err %.2e (kh in [1e-4, 50])\n", houle::isa_name(isa).data(),
                worst);
  }
}

// Stated tolerance of every SIMD path against the scalar path: the kernel uses only + - * and the
// correctly rounded simd::div / simd::sqrt, min/max and selects, without contraction: every ISA gives
// the scalar bits, tolerance 0.
std::int64_t simd_ulp_tolerance(houle::Isa) { return 0; }

TEST(Dispersion, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> log_depth(-4.0, 3.0), u(0.0, 1.0);
  const std::vector<std::size_t> sizes = {0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1000};
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (int trial = 0; trial < 10; ++trial) {
      const double omega = 0.3 + 6.0 * u(rng);
      for (std::size_t n : sizes) {
        std::vector<float> depth(n), ref(n), got(n);
        for (auto& d : depth) d = u(rng) < 0.05 ? -float(u(rng)) : float(std::pow(10.0, log_depth(rng)));
        houle::dispersion_k_batch(houle::Isa::scalar, omega, depth.data(), n, ref.data());
        houle::dispersion_k_batch(isa, omega, depth.data(), n, got.data());
        for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, houle::test::ulp_distance(ref[i], got[i]));
      }
    }
    EXPECT_LE(worst, simd_ulp_tolerance(isa)) << houle::isa_name(isa);
    std::printf("dispersion_k_batch %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(simd_ulp_tolerance(isa)));
  }
}

TEST(Dispersion, BatchMayWorkInPlace) {
  std::vector<float> buf = {1.0f, 2.0f, 3.0f, -1.0f, 5.0f};
  std::vector<float> expected(buf.size());
  houle::dispersion_k_batch(1.2, buf.data(), buf.size(), expected.data());
  houle::dispersion_k_batch(1.2, buf.data(), buf.size(), buf.data());
  EXPECT_EQ(buf, expected);
}

}  // namespace
