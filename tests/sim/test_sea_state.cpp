// Sea states (sea_state.hpp, docs/physics.md 2.9): the spectrum against Pierson-Moskowitz's closed
// form, the components' variance, peak and directional spread against what was asked, the same
// components on every call, the limits (test_sea_state_record.cpp: a long record's Hs on the surface
// they make).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "angles.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/sea_state.hpp"
#include "open_sea.hpp"

namespace {

using houle::SeaState;
using houle::WaveTrain;
using houle_test::pi;

std::vector<WaveTrain> components(const SeaState& s) {
  auto c = houle::sea_state_components(s, 0);
  EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().field + ": " + c.error().message);
  return c.ok() ? c.value() : std::vector<WaveTrain>{};
}

using houle_test::open_sea;

TEST(SeaState, PiersonMoskowitzIsJonswapWithGammaOne) {
  // The closed form S(f) = 5/16 Hs^2 fp^4 f^-5 exp(-5/4 (fp/f)^4), whose integral is Hs^2 / 16.
  SeaState s;
  s.significant_height = 2.0;
  s.peak_period = 9.0;
  s.gamma = 1.0;
  const double fp = 1.0 / 9.0;
  const houle::JonswapSpectrum pm_spectrum(s);
  for (double x : {0.6, 0.9, 1.0, 1.1, 1.5, 3.0}) {
    const double f = x * fp;
    const double pm = 5.0 / 16.0 * 4.0 * std::pow(fp, 4.0) * std::pow(f, -5.0) * std::exp(-1.25 * std::pow(fp / f, 4.0));
    EXPECT_NEAR(pm_spectrum.density(f) / pm, 1.0, 1e-6) << "f/fp " << x;
  }
  // JONSWAP's peak is gamma times PM's peak at the same variance's shape: S_J(fp) / S_PM(fp) =
  // gamma * I_PM / I_J, and the enhancement is gone a few sigma from the peak.
  SeaState j = s;
  j.gamma = 3.3;
  const houle::JonswapSpectrum jonswap(j);
  const double peak = jonswap.density(fp) / pm_spectrum.density(fp);
  const double far = jonswap.density(2.0 * fp) / pm_spectrum.density(2.0 * fp);
  EXPECT_NEAR(peak / far, 3.3, 1e-9);
}

TEST(SeaState, ComponentsCarryTheVarianceOfHs) {
  for (std::uint32_t n : {1u, 8u, 32u, 100u, 256u}) {
    for (double gamma : {1.0, 3.3, 7.0}) {
      SeaState s;
      s.significant_height = 1.7;
      s.peak_period = 7.0;
      s.gamma = gamma;
      s.components = n;
      double variance = 0.0;
      for (const WaveTrain& t : components(s)) variance += t.amplitude * t.amplitude / 2.0;
      EXPECT_NEAR(variance / (1.7 * 1.7 / 16.0), 1.0, 0.01) << n << " components, gamma " << gamma;
    }
  }
}

TEST(SeaState, ComponentsRecoverThePeakAndTheSpectrum) {
  // Equal-energy bins over [0.5, 5] fp: component i lies inside its bin, where the spectrum's
  // cumulative share of that band (Simpson on the density) is between i / N and (i + 1) / N. Each
  // holds m0 / N over the band between its neighbours' midpoints, so (a^2 / 2) / that width estimates
  // the density: the densest is at fp.
  for (double gamma : {1.0, 3.3, 7.0}) {
    SeaState s;
    s.significant_height = 2.0;
    s.peak_period = 8.0;
    s.gamma = gamma;
    s.components = 64;
    const std::vector<WaveTrain> c = components(s);
    ASSERT_EQ(c.size(), 64u);
    const double fp = 1.0 / 8.0;
    const houle::JonswapSpectrum spectrum(s);
    // Simpson's rule over [a, b] in 200 intervals.
    const auto integral = [&](double a, double b) {
      const int n = 200;
      const double h = (b - a) / n;
      double sum = spectrum.density(a) + spectrum.density(b);
      for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * spectrum.density(a + i * h);
      return sum * h / 3.0;
    };
    std::vector<double> f, below;  // each component's frequency, and the variance of the band under it
    double lo = 0.5 * fp, sum = 0.0;
    for (const WaveTrain& t : c) {
      f.push_back(1.0 / *t.period);
      sum += integral(lo, f.back());
      below.push_back(sum);
      lo = f.back();
    }
    const double band = sum + integral(lo, 5.0 * fp);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double u = below[i] / band * 64.0;
      EXPECT_GT(u, double(i)) << "gamma " << gamma << ", component " << i;
      EXPECT_LT(u, double(i + 1)) << "gamma " << gamma << ", component " << i;
    }
    double best = 0.0, f_peak = 0.0;
    for (std::size_t i = 1; i + 1 < f.size(); ++i) {
      const double density = c[i].amplitude * c[i].amplitude / 2.0 / (0.5 * (f[i + 1] - f[i - 1]));
      if (density > best) best = density, f_peak = f[i];
    }
    EXPECT_NEAR(f_peak / fp, 1.0, 0.03) << "gamma " << gamma;
  }
}

TEST(SeaState, ComponentsRecoverTheMeanDirectionAndTheSpread) {
  // The energy-weighted circular mean and spread sqrt(2 (1 - |E e^{i theta}|)) of the components.
  for (double spread : {5.0, 25.0, 40.0}) {
    for (std::uint32_t n : {16u, 64u}) {
      SeaState s;
      s.direction_deg = 120.0;
      s.spread_deg = spread;
      s.components = n;
      std::complex<double> m1 = 0.0;
      double energy = 0.0;
      for (const WaveTrain& t : components(s)) {
        m1 += t.amplitude * t.amplitude * std::polar(1.0, t.direction_deg * pi / 180.0);
        energy += t.amplitude * t.amplitude;
      }
      m1 /= energy;
      EXPECT_NEAR(std::arg(m1) * 180.0 / pi, 120.0, 0.01 * spread) << spread << " deg, " << n;
      const double recovered = std::sqrt(2.0 * (1.0 - std::abs(m1))) * 180.0 / pi;
      EXPECT_NEAR(recovered / spread, 1.0, n >= 64 ? 0.02 : 0.05) << spread << " deg, " << n << " components";
    }
  }
  SeaState long_crested;
  long_crested.spread_deg = 0.0;
  for (const WaveTrain& t : components(long_crested)) EXPECT_EQ(t.direction_deg, 90.0);
  // The exponent that gives the spread: s = 2 / sigma^2 - 1 (25 deg: s = 9.5).
  EXPECT_NEAR(houle::cos2s_exponent(25.0 * pi / 180.0), 2.0 / std::pow(25.0 * pi / 180.0, 2.0) - 1.0, 1e-12);
}

TEST(SeaState, TheSameComponentsEveryTimeAndOtherOnesForAnotherSeed) {
  SeaState s;
  s.components = 32;
  const std::vector<WaveTrain> a = components(s), b = components(s);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(*a[i].period, *b[i].period);
    EXPECT_EQ(a[i].direction_deg, b[i].direction_deg);
    EXPECT_EQ(a[i].phase, b[i].phase);
    EXPECT_EQ(a[i].sea_state, 0);
  }
  // Every direction quantile once: the directions sorted are the same for any seed, their pairing
  // with the frequencies and the phases are not.
  SeaState other = s;
  other.seed = 7;
  const std::vector<WaveTrain> c = components(other);
  std::vector<double> da, dc;
  int moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    da.push_back(a[i].direction_deg);
    dc.push_back(c[i].direction_deg);
    moved += a[i].phase != c[i].phase;
    EXPECT_EQ(*a[i].period, *c[i].period);
  }
  EXPECT_EQ(moved, int(a.size()));
  EXPECT_NE(da, dc);
  std::sort(da.begin(), da.end());
  std::sort(dc.begin(), dc.end());
  EXPECT_EQ(da, dc);
  // The default sea state's components on the machine that wrote this: another machine, library or
  // compiler must give them too (a change of the bins, the deal or the hash shows here).
  const struct {
    std::size_t k;
    double period, direction_deg, phase;
  } fixed[] = {{0, 10.649171953300677, 65.536458633206848, 1.9515341303243032},
               {13, 7.7872805202691131, 68.521534268580382, 5.1212981657882573},
               {31, 2.832154538858449, 78.464505653897106, 6.0673826457571529}};
  for (const auto& f : fixed) {
    EXPECT_NEAR(*a[f.k].period, f.period, 1e-12) << f.k;
    EXPECT_NEAR(a[f.k].direction_deg, f.direction_deg, 1e-10) << f.k;
    EXPECT_NEAR(a[f.k].phase, f.phase, 1e-12) << f.k;
  }
}

TEST(SeaState, ValidateExpandsOnceAndLimitsTheComponents) {
  SeaState s;
  s.components = 20;
  houle::Scene scene = open_sea(s);
  houle::WaveTrain written;
  written.period = 5.0;
  scene.trains = {written};
  auto valid = houle::validate(scene);
  ASSERT_TRUE(valid.ok()) << valid.error().field << ": " << valid.error().message;
  ASSERT_EQ(valid->trains.size(), 21u);
  EXPECT_EQ(valid->trains[0].sea_state, -1);
  EXPECT_EQ(valid->trains[20].sea_state, 0);
  // Validated again: the same trains, not twice the components.
  auto again = houle::validate(valid.value());
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->trains.size(), 21u);
  EXPECT_EQ(again->trains[20].phase, valid->trains[20].phase);
  // 16 written trains and 256 components are allowed, one more component is not.
  scene.trains.assign(16, written);
  scene.sea_states = {s, s};
  scene.sea_states[0].components = 200;
  scene.sea_states[1].components = 56;
  ASSERT_TRUE(houle::validate(scene).ok());
  scene.sea_states[1].components = 57;
  auto over = houle::validate(scene);
  ASSERT_FALSE(over.ok());
  EXPECT_EQ(over.error().field, "sea_states[1].components");
  // A sea state too steep for its short components.
  scene.sea_states = {s};
  scene.sea_states[0].significant_height = 30.0;
  scene.sea_states[0].peak_period = 6.0;
  auto steep = houle::validate(scene);
  ASSERT_FALSE(steep.ok());
  EXPECT_EQ(steep.error().field, "sea_states[0].significant_height");
}

TEST(SeaState, ComponentsCountInTheMemoryEstimate) {
  // 256 components over a 4 km beach, each a traced train with its grid: validate refuses it (the
  // draft build's estimate, over 100 GiB of sea grids), before any tracing; one component fits.
  SeaState s;
  s.components = 256;
  houle::Scene scene = open_sea(s);
  scene.domain = {0.0, 0.0, 4000.0, 4000.0};
  scene.floor.base.kind = houle::FloorKind::planar_beach;
  scene.floor.base.depth = 30.0;
  scene.floor.base.shoreline = {0.0, 3000.0};
  scene.camera.position = {2000.0, -20.0, 6.0};
  scene.camera.look_at = {2000.0, 80.0, 0.0};
  auto refused = houle::validate(scene);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("sea grids"), std::string::npos) << refused.error().message;
  scene.sea_states[0].components = 1;
  auto valid = houle::validate(scene);
  EXPECT_TRUE(valid.ok()) << valid.error().field << ": " << valid.error().message;
}

}  // namespace
