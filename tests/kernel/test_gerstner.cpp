#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "ulp.hpp"

namespace {

using houle::GerstnerWave;

std::vector<GerstnerWave> random_waves(std::mt19937& rng, int count, double fold_budget) {
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), len(0.5f, 40.0f), q(0.0f, 1.0f), u(0.0f, 1.0f);
  std::vector<GerstnerWave> w(count);
  for (auto& wave : w) {
    const float a = angle(rng), wavelength = len(rng);
    wave.dir_x = std::cos(a);
    wave.dir_y = std::sin(a);
    wave.wavenumber = 6.2831853f / wavelength;
    wave.steepness = q(rng);
    // Share the fold budget so that sum(q k A) < fold_budget.
    wave.amplitude = float(fold_budget / count * u(rng) / (wave.wavenumber * std::max(wave.steepness, 0.05f)));
    wave.omega = std::sqrt(9.81f * wave.wavenumber);
    wave.phase = angle(rng);
  }
  return w;
}

// Double-precision model of the same surface at rest position u (the oracle).
struct Ref {
  double px, py, z;
};
Ref reference_at(const std::vector<GerstnerWave>& waves, double t, double ux, double uy) {
  Ref r{ux, uy, 0.0};
  for (const auto& w : waves) {
    const double n = std::hypot(double(w.dir_x), double(w.dir_y));
    const double dx = w.dir_x / n, dy = w.dir_y / n;
    const double th = w.wavenumber * (dx * ux + dy * uy) - double(w.omega) * t + w.phase;
    r.px += double(w.steepness) * w.amplitude * dx * std::cos(th);
    r.py += double(w.steepness) * w.amplitude * dy * std::cos(th);
    r.z += double(w.amplitude) * std::sin(th);
  }
  return r;
}

struct GerstnerOutputs {
  std::vector<float> h, gx, gy;
  explicit GerstnerOutputs(std::size_t n) : h(n, -7.0f), gx(n, -7.0f), gy(n, -7.0f) {}
  houle::GerstnerOutput view() { return {h.data(), gx.data(), gy.data()}; }
};

// Stated tolerance of every SIMD path against the scalar reference, in ulps of the output's scale
// (sum of amplitudes for heights, sum of k A for slopes). The kernel uses only +, -, * and the
// correctly rounded simd::div, without contraction: every ISA gives the scalar bits, tolerance 0.
std::int64_t gerstner_ulp_tolerance(houle::Isa) { return 0; }

TEST(Gerstner, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> coord(-60.0f, 60.0f);
  const std::vector<std::size_t> sizes = {0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1000};
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (int trial = 0; trial < 20; ++trial) {
      const auto waves = random_waves(rng, 1 + trial % 8, 0.9);
      const auto frame = houle::make_gerstner_frame(waves, 0.37 * trial);
      ASSERT_TRUE(frame.ok()) << frame.error().message;
      float height_scale = 0.0f, slope_scale = 0.0f;
      for (const auto& w : waves) height_scale += w.amplitude, slope_scale += w.amplitude * w.wavenumber;
      for (std::size_t n : sizes) {
        std::vector<float> x(n), y(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = coord(rng), y[i] = coord(rng);
        GerstnerOutputs ref(n), got(n);
        houle::gerstner_eval(houle::Isa::scalar, frame.value(), x.data(), y.data(), n, ref.view());
        houle::gerstner_eval(isa, frame.value(), x.data(), y.data(), n, got.view());
        for (std::size_t i = 0; i < n; ++i) {
          worst = std::max({worst, houle::test::ulps_of_scale(ref.h[i], got.h[i], height_scale),
                            houle::test::ulps_of_scale(ref.gx[i], got.gx[i], slope_scale),
                            houle::test::ulps_of_scale(ref.gy[i], got.gy[i], slope_scale)});
        }
      }
    }
    EXPECT_LE(worst, gerstner_ulp_tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("gerstner %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(gerstner_ulp_tolerance(isa)));
  }
}

TEST(Gerstner, HeightAndGradientMatchDoubleOracle) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-50.0, 50.0);
  const double t = 3.25;
  for (int trial = 0; trial < 30; ++trial) {
    const auto waves = random_waves(rng, 1 + trial % 6, 0.7);
    const auto frame = houle::make_gerstner_frame(waves, t);
    ASSERT_TRUE(frame.ok());
    double amp_sum = 0.0;
    for (const auto& w : waves) amp_sum += w.amplitude;
    for (int i = 0; i < 200; ++i) {
      // Pick a particle, find where it is displaced to, and ask the kernel for the height there.
      const double ux = coord(rng), uy = coord(rng);
      const Ref r = reference_at(waves, t, ux, uy);
      const float x = float(r.px), y = float(r.py);
      GerstnerOutputs o(1);
      houle::gerstner_eval(frame.value(), &x, &y, 1, o.view(), 4);
      EXPECT_NEAR(o.h[0], r.z, 2e-5 * amp_sum + 1e-6);
      // Gradient against central differences of the double surface, via the rest positions.
      const double e = 1e-4;
      const Ref ax = reference_at(waves, t, ux + e, uy), bx = reference_at(waves, t, ux - e, uy);
      const Ref ay = reference_at(waves, t, ux, uy + e), by = reference_at(waves, t, ux, uy - e);
      // [dP/du]^T grad h = dz/du, solved for grad h.
      const double a = (ax.px - bx.px) / (2 * e), b = (ax.py - bx.py) / (2 * e);
      const double c = (ay.px - by.px) / (2 * e), d = (ay.py - by.py) / (2 * e);
      const double zu = (ax.z - bx.z) / (2 * e), zv = (ay.z - by.z) / (2 * e);
      const double det = a * d - b * c;
      const double gx = (d * zu - b * zv) / det, gy = (a * zv - c * zu) / det;
      EXPECT_NEAR(o.gx[0], gx, 2e-4 * (1.0 + std::fabs(gx)));
      EXPECT_NEAR(o.gy[0], gy, 2e-4 * (1.0 + std::fabs(gy)));
    }
  }
}

TEST(Gerstner, SineWaveIsExact) {
  const GerstnerWave w{1.0f, 0.0f, 0.5f, 0.3f, 0.0f, 2.0f, 0.25f};
  const double t = 1.5;
  const auto frame = houle::make_gerstner_frame({&w, 1}, t);
  ASSERT_TRUE(frame.ok());
  for (float x = -20.0f; x <= 20.0f; x += 0.37f) {
    const float y = 3.0f;
    GerstnerOutputs o(1);
    houle::gerstner_eval(frame.value(), &x, &y, 1, o.view());
    const double th = 0.5 * x - 2.0 * t + 0.25;
    EXPECT_NEAR(o.h[0], 0.3 * std::sin(th), 1e-6);
    EXPECT_NEAR(o.gx[0], 0.15 * std::cos(th), 1e-6);
    EXPECT_EQ(o.gy[0], 0.0f);
  }
}

TEST(Gerstner, PhaseStaysAccurateAtHugeTimes) {
  // docs/physics.md 8.22: at t = 1e6 s the float surface must match double to 1e-3 A.
  GerstnerWave w{0.6f, 0.8f, 6.2831853f / 3.0f, 0.2f, 0.5f, 0.0f, 0.1f};
  w.omega = std::sqrt(9.81f * w.wavenumber);
  for (double t : {1e6, 1e7, 123456789.5}) {
    const auto frame = houle::make_gerstner_frame({&w, 1}, t);
    ASSERT_TRUE(frame.ok());
    const std::vector<GerstnerWave> waves{w};
    const Ref r = reference_at(waves, t, 1.25, -2.5);
    const float x = float(r.px), y = float(r.py);
    GerstnerOutputs o(1);
    houle::gerstner_eval(frame.value(), &x, &y, 1, o.view());
    EXPECT_NEAR(o.h[0], r.z, 1e-3 * w.amplitude) << "t = " << t;
  }
}

TEST(Gerstner, RejectsInvalidTrains) {
  GerstnerWave w{1.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f};
  EXPECT_FALSE(houle::make_gerstner_frame({&w, 1}, 0.0).ok());  // q k A = 1: folds
  w.steepness = 0.5f;
  EXPECT_TRUE(houle::make_gerstner_frame({&w, 1}, 0.0).ok());
  w.wavenumber = -1.0f;
  const auto bad = houle::make_gerstner_frame({&w, 1}, 0.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "waves[0].wavenumber");
  w.wavenumber = 1.0f;
  w.dir_x = w.dir_y = 0.0f;
  EXPECT_FALSE(houle::make_gerstner_frame({&w, 1}, 0.0).ok());
  const std::vector<GerstnerWave> many(houle::GerstnerFrame::max_waves + 1, GerstnerWave{1, 0, 1, 0.001f, 0, 1, 0});
  EXPECT_FALSE(houle::make_gerstner_frame(many, 0.0).ok());
}

TEST(Isa, NamesRoundTripAndScalarIsAlwaysSupported) {
  for (const houle::Isa isa : houle::all_isas) {
    EXPECT_EQ(houle::parse_isa(houle::isa_name(isa)), isa);
  }
  EXPECT_FALSE(houle::parse_isa("avx3").has_value());
  ASSERT_FALSE(houle::supported_isas().empty());
  EXPECT_EQ(houle::supported_isas().back(), houle::Isa::scalar);
  EXPECT_TRUE(houle::isa_supported(houle::active_isa()));
}

}  // namespace
