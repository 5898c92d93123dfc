// Sea states expanded into trains (sea_state.hpp, docs/physics.md 2.9).
#include "houle/sim/sea_state.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>

#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_keys.hpp"

namespace houle {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * pi;
// The band the components cover, in multiples of fp: below 0.5 fp the spectrum holds e^-20 of its
// peak, above 5 fp about 0.2 % of the variance (the f^-4 tail), which the components carry too.
constexpr double band_lo = 0.5, band_hi = 5.0;
// Tabulation of the spectrum over the band and of the directional distribution: fine enough that
// the bins' edges and centroids, and the direction quantiles, move by far less than a bin.
constexpr std::size_t table_points = 4096;

// JONSWAP without its constant: f^-5 exp(-5/4 (fp/f)^4) gamma^r, in units of fp (x = f / fp).
double jonswap_shape(double gamma, double x) noexcept {
  if (!(x > 0.0)) return 0.0;
  const double sigma = x <= 1.0 ? 0.07 : 0.09;
  const double r = std::exp(-(x - 1.0) * (x - 1.0) / (2.0 * sigma * sigma));
  return std::pow(x, -5.0) * std::exp(-1.25 * std::pow(x, -4.0)) * std::pow(gamma, r);
}

// Integral of the shape over x in (0, inf): Simpson's rule on [0.2, 20] (below 0.2 the shape is
// under e^-700; around the peak the grid of 1/1600 resolves sigma = 0.07 with 100 points) plus the
// tail above 20, where gamma^r = 1 and the exponential is 1 - 5/4 x^-4 + ...: x^-4 / 4 - 5 x^-8 / 32.
double jonswap_shape_integral(double gamma) noexcept {
  constexpr double lo = 0.2, hi = 20.0;
  constexpr std::size_t n = 31680;  // even
  const double h = (hi - lo) / double(n);
  double sum = jonswap_shape(gamma, lo) + jonswap_shape(gamma, hi);
  for (std::size_t i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * jonswap_shape(gamma, lo + double(i) * h);
  return sum * h / 3.0 + std::pow(hi, -4.0) / 4.0 - 5.0 * std::pow(hi, -8.0) / 32.0;
}

// splitmix64's finaliser (Steele, Lea & Flood 2014): a fixed mixing of 64 bits, the same everywhere.
std::uint64_t mix(std::uint64_t z) noexcept {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// A number in [0, 1) from the hash of (seed, sea state, component, purpose).
double unit_hash(std::uint32_t seed, std::size_t sea_state, std::size_t component, std::uint64_t purpose) noexcept {
  const std::uint64_t h = mix(mix(mix(mix(seed) ^ sea_state) ^ component) ^ purpose);
  return double(h >> 11) * 0x1p-53;
}

// The inverse of a cumulative table: x where cdf(x) = u, linear between the table's points (cdf
// rising from 0 to 1 over xs).
template <std::size_t N>
double inverse(const std::array<double, N>& xs, const std::array<double, N>& cdf, double u) noexcept {
  const std::size_t i = std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  if (i == 0) return xs.front();
  if (i >= N) return xs.back();
  const double span = cdf[i] - cdf[i - 1];
  return span > 0.0 ? xs[i - 1] + (xs[i] - xs[i - 1]) * (u - cdf[i - 1]) / span : xs[i - 1];
}

}  // namespace

JonswapSpectrum::JonswapSpectrum(const SeaState& s) noexcept
    : fp_(1.0 / s.peak_period), gamma_(s.gamma),
      scale_(s.significant_height * s.significant_height / 16.0 / (jonswap_shape_integral(s.gamma) / s.peak_period)) {}

double JonswapSpectrum::density(double f) const noexcept { return scale_ * jonswap_shape(gamma_, f / fp_); }

double cos2s_exponent(double spread_rad) noexcept { return 2.0 / (spread_rad * spread_rad) - 1.0; }

Expected<std::vector<WaveTrain>> sea_state_components(const SeaState& s, std::size_t index) {
  const std::size_t n = s.components;
  const std::string field = "sea_states[" + std::to_string(index) + "]";
  // Cumulative variance and first moment of the shape over the band (trapezoids; x = f / fp).
  static_assert(table_points % 2 == 0);
  std::array<double, table_points> x{}, energy{}, moment{};
  for (std::size_t i = 0; i < table_points; ++i) x[i] = band_lo + (band_hi - band_lo) * double(i) / double(table_points - 1);
  for (std::size_t i = 1; i < table_points; ++i) {
    const double s0 = jonswap_shape(s.gamma, x[i - 1]), s1 = jonswap_shape(s.gamma, x[i]), dx = x[i] - x[i - 1];
    energy[i] = energy[i - 1] + 0.5 * (s0 + s1) * dx;
    moment[i] = moment[i - 1] + 0.5 * (s0 * x[i - 1] + s1 * x[i]) * dx;
  }
  const double total = energy.back();
  for (std::size_t i = 0; i < table_points; ++i) {
    energy[i] /= total;
    moment[i] /= total;
  }
  // The first moment at a point of the cumulative energy, linear between the table's points like it.
  const auto moment_at = [&](double u) {
    const std::size_t i = std::size_t(std::upper_bound(energy.begin(), energy.end(), u) - energy.begin());
    if (i == 0) return 0.0;
    if (i >= table_points) return moment.back();
    const double span = energy[i] - energy[i - 1];
    return span > 0.0 ? moment[i - 1] + (moment[i] - moment[i - 1]) * (u - energy[i - 1]) / span : moment[i - 1];
  };

  // The cos-2s distribution's cumulative table over [-reach, reach]: beyond 10 sigma it holds nothing
  // a quantile (j + 0.5) / N of N <= 256 can reach (for small sigma it is a Gaussian of deviation sigma).
  const double spread = s.spread_deg * pi / 180.0;
  std::array<double, table_points> theta{}, directions{};
  if (spread > 0.0) {
    const double exponent = cos2s_exponent(spread), reach = std::min(pi, 10.0 * spread);
    for (std::size_t i = 0; i < table_points; ++i) theta[i] = -reach + 2.0 * reach * double(i) / double(table_points - 1);
    const auto d = [&](double t) { return std::pow(std::max(std::cos(0.5 * t), 0.0), 2.0 * exponent); };
    for (std::size_t i = 1; i < table_points; ++i) {
      directions[i] = directions[i - 1] + 0.5 * (d(theta[i - 1]) + d(theta[i])) * (theta[i] - theta[i - 1]);
    }
    const double sum = directions.back();
    for (double& c : directions) c /= sum;
  }
  // Bin k's direction quantile: the rank of k's golden-ratio number among the bins' (every quantile
  // (j + 0.5) / N once; neighbouring frequencies get distant directions).
  const double offset = unit_hash(s.seed, index, 0, 1);
  const auto golden = [&](std::size_t k) {
    const double v = offset + double(k) * 0.6180339887498949;
    return v - std::floor(v);
  };

  const double fp = 1.0 / s.peak_period;
  const double m0 = s.significant_height * s.significant_height / 16.0;
  const double amplitude = std::sqrt(2.0 * m0 / double(n));
  std::vector<WaveTrain> out;
  out.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double u0 = double(k) / double(n), u1 = double(k + 1) / double(n);
    const double f = fp * (moment_at(u1) - moment_at(u0)) * double(n);  // the bin's energy centroid
    std::size_t rank = 0;
    for (std::size_t j = 0; j < n; ++j) rank += golden(j) < golden(k);
    const double deviation = spread > 0.0 ? inverse(theta, directions, (double(rank) + 0.5) / double(n)) : 0.0;
    WaveTrain t;
    t.period = 1.0 / f;
    t.amplitude = amplitude;
    t.direction_deg = std::remainder(s.direction_deg + deviation * 180.0 / pi, 360.0);  // within a train's range
    t.phase = two_pi * unit_hash(s.seed, index, k, 2);
    t.steepness = s.steepness;
    t.sea_state = std::int32_t(index);
    // A written train's shortest period (docs/scenes.md, trains.period): shorter waves are ripples.
    if (1.0 / f < 1.0) {
      char what[96];
      std::snprintf(what, sizeof what, "component %zu has a period of %.3g s", k, 1.0 / f);
      return Error{field + ".peak_period",
                   "long enough that every component is a wave train of at least 1 s (" + std::string(what) +
                       "): expected a longer peak_period or fewer components, got " + scene_keys::number_text(s.peak_period)};
    }
    // Stokes / Miche deep-water limit (docs/physics.md 2.6), as for a written train.
    const double l0 = two_pi / deep_water_wavenumber(two_pi * f);
    if (amplitude > 0.071 * l0) {
      char what[160];
      std::snprintf(what, sizeof what, "component %zu of period %.3g s has amplitude %.3g m over 0.071 L0 = %.3g m", k,
                    1.0 / f, amplitude, 0.071 * l0);
      return Error{field + ".significant_height",
                   "at most what keeps every component under the deep-water breaking (Stokes) limit (" + std::string(what) +
                       "): expected a lower significant_height or more components, got " +
                       scene_keys::number_text(s.significant_height)};
    }
    out.push_back(t);
  }
  return out;
}

}  // namespace houle
