#include "houle/surface/capillary.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "capillary_impl.hpp"
#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"

namespace houle {
namespace detail {
namespace {

constexpr int period = capillary_period;

/// Lattice value q in [-127, 127] at (i, j) in [0, 256)^2: a fixed integer hash (Wellons' lowbias32),
/// so the table is the same for every build and platform.
std::int32_t lattice_q(std::uint32_t i, std::uint32_t j) {
  std::uint32_t x = (j * std::uint32_t(period) + i) ^ 0x68e31da4u;
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return std::int32_t(x % 255u) - 127;
}

std::uint32_t lattice_byte(std::int32_t q) { return std::uint32_t(q) & 0xffu; }

/// Fills the table in place: one hash per lattice point and a sliding window along each row (word
/// c + 1 is word c shifted by a byte plus one new column). Built at run time, once: ~0.3 ms, where
/// a constexpr table would strain compilers' evaluation budgets (GCC 2^25 operations, clang 2^20).
void fill_lattice(CapillaryLattice& t) {
  std::int64_t s1 = 0, s2 = 0;
  for (std::uint32_t j = 0; j < std::uint32_t(period); ++j) {
    const std::int32_t q0 = lattice_q(0, j), q1 = lattice_q(1, j);
    s1 += q0 + q1;
    s2 += std::int64_t(q0) * q0 + std::int64_t(q1) * q1;
    // Bytes 0..2: columns -1 (= 255), 0, 1; byte 3 takes column c + 2 in the loop.
    std::uint32_t word = lattice_byte(lattice_q(period - 1, j)) | lattice_byte(q0) << 8 | lattice_byte(q1) << 16;
    std::int32_t* row = t.words + (j + 1) * period;  // padded row j + 1 holds lattice row j
    for (std::uint32_t c = 0; c < std::uint32_t(period); ++c) {
      const std::uint32_t col = c + 2;
      std::int32_t q = col == std::uint32_t(period) ? q0 : q1;  // columns 256, 257 wrap to 0, 1
      if (col < std::uint32_t(period)) {
        q = lattice_q(col, j);
        s1 += q;
        s2 += std::int64_t(q) * q;
      }
      word |= lattice_byte(q) << 24;
      row[c] = std::int32_t(word);  // modular conversion (C++20)
      word >>= 8;
    }
  }
  for (std::uint32_t c = 0; c < std::uint32_t(period); ++c) {
    t.words[c] = t.words[std::uint32_t(period) * period + c];  // row 0 <- lattice row 255
    t.words[(period + 1) * period + c] = t.words[period + c];  // rows 257, 258 <- lattice rows 0, 1
    t.words[(period + 2) * period + c] = t.words[2 * period + c];
  }
  for (std::size_t k = 0; k < capillary_pair_words / 2; ++k) {
    t.pairs[2 * k] = t.words[k];
    t.pairs[2 * k + 1] = t.words[k + period];
  }
  const double n = double(period) * period, mean = double(s1) / n;
  t.value_variance = (double(s2) / n - mean * mean) / (127.0 * 127.0);
}

struct LatticeHolder {
  CapillaryLattice table;
  LatticeHolder() noexcept : table{} { fill_lattice(table); }
};

// The interpolant's bounds on this lattice (docs/physics.md 6.1): |N| <= 1.30 and |grad N| <= 3.31 per
// lattice unit. Any lattice of values in [-1, 1] allows 1.25^2 and 3.75 sqrt(2) (max sum|w| = 1.25, max
// sum|w'| = 3, both at t = 1/2); this fixed one stays well inside, and the tighter bounds let the marcher
// step further (tests/kernel/test_capillary.cpp bounds every cell by its Bernstein coefficients and
// checks these). The integrals int_0^1 sum w^2 = 57/70 and int_0^1 sum w'^2 = 7/3 give the slope
// variance of iid lattice values.
constexpr double value_overshoot = 1.30;
constexpr double gradient_overshoot = 3.31;
constexpr double slope_integrals = (57.0 / 70.0) * (7.0 / 3.0);
constexpr double bound_margin = 1.0 + 1.0 / 4096.0;

// Capillary-gravity phase speed c = sqrt(g / kappa + (sigma / rho) kappa) (docs/physics.md 6.3).
constexpr double gravity = 9.81;               // m/s^2
constexpr double surface_tension = 0.074 / 1000.0;  // sigma / rho, m^3/s^2

// Per-octave drift direction around params.direction (rad): ripples spread about the wind, and
// octaves that move differently make the sum change shape instead of sliding as one picture.
constexpr double drift_spread[CapillaryFrame::max_octaves] = {0.0, 0.45, -0.35, 0.8, -0.6, 0.2, -0.9, 0.55};

/// Octave weight W_i(level), i 0-based, as the kernel computes it (in float).
float octave_weight(float level, int i, float fade_rate) {
  level = level > 0.0f ? level : 0.0f;  // NaN too, as in the kernel
  float t = (level - float(i)) * fade_rate;
  t = t < 1.0f ? t : 1.0f;
  t = t > 0.0f ? t : 0.0f;
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

const CapillaryLattice& capillary_lattice() noexcept {
  static const LatticeHolder holder;  // function-local: built on first use, no global constructor
  return holder.table;
}

}  // namespace detail

CapillaryOctave capillary_octave(const CapillaryParams& p, int i) noexcept {
  HOULE_ASSERT(i >= 0 && std::size_t(i) < CapillaryFrame::max_octaves, "capillary_octave: an octave below max_octaves");
  CapillaryOctave o{};
  const double k = p.lacunarity, scale = std::pow(k, -double(i));
  o.amplitude = double(p.amplitude) * scale;
  o.spacing = double(p.base_wavelength) * scale;
  // Orientations from the golden-ratio sequence over [0, pi/2) (a square lattice repeats every
  // quarter turn): well spread, no two octaves share grid axes.
  const double turn = std::fmod((i + 1) * 0.6180339887498949, 1.0) * (std::numbers::pi / 2.0);
  o.cos_angle = std::cos(turn);
  o.sin_angle = std::sin(turn);
  const double kappa = 2.0 * std::numbers::pi / o.spacing;
  const double speed = double(p.animation_rate) * std::sqrt(detail::gravity / kappa + detail::surface_tension * kappa);
  const double heading = double(p.direction) + detail::drift_spread[i % CapillaryFrame::max_octaves];
  o.velocity_x = speed * std::cos(heading);
  o.velocity_y = speed * std::sin(heading);
  // Non-integer shifts (R2 sequence) so the octaves' lattices do not line up at the origin.
  o.shift_u = std::fmod((i + 1) * 0.7548776662466927, 1.0) * CapillaryFrame::period;
  o.shift_v = std::fmod((i + 1) * 0.5698402909980532, 1.0) * CapillaryFrame::period;
  return o;
}

Expected<CapillaryFrame> make_capillary_frame(const CapillaryParams& p, double time_s, double origin_x, double origin_y) {
  if (!(p.amplitude >= 0.0f) || !std::isfinite(p.amplitude)) return Error{"amplitude", "a finite value >= 0 m"};
  if (!(p.base_wavelength > 0.0f) || !std::isfinite(p.base_wavelength)) {
    return Error{"base_wavelength", "a finite value > 0 m"};
  }
  if (!(p.lacunarity >= 1.25f && p.lacunarity <= 4.0f)) return Error{"lacunarity", "a value in [1.25, 4]"};
  if (p.max_octaves < 0 || p.max_octaves > int(CapillaryFrame::max_octaves)) {
    return Error{"max_octaves", "an integer in [0, " + std::to_string(CapillaryFrame::max_octaves) + "]"};
  }
  if (!(p.animation_rate >= 0.0f) || !std::isfinite(p.animation_rate)) return Error{"animation_rate", "a finite value >= 0"};
  if (!std::isfinite(p.direction)) return Error{"direction", "a finite angle in rad"};
  if (!(p.samples_per_wavelength >= 1.0f) || !std::isfinite(p.samples_per_wavelength)) {
    return Error{"samples_per_wavelength", "a finite value >= 1"};
  }
  if (!std::isfinite(time_s)) return Error{"time", "a finite time in s"};
  if (!std::isfinite(origin_x) || !std::isfinite(origin_y)) return Error{"origin", "a finite point in m"};

  CapillaryFrame f{};
  f.params = p;
  f.octaves = std::uint32_t(p.max_octaves);
  f.fade_rate = capillary_fade_rate(p);
  const double period = CapillaryFrame::period;
  double finest = p.base_wavelength;
  for (int i = 0; i < p.max_octaves; ++i) {
    const CapillaryOctave o = capillary_octave(p, i);
    finest = o.spacing;
    const double c = o.cos_angle / o.spacing, s = o.sin_angle / o.spacing;
    f.mxu[i] = float(c);
    f.myu[i] = float(s);
    f.mxv[i] = float(-s);
    f.myv[i] = float(c);
    // The lattice point under the local origin now, in double, modulo the period: the pattern
    // moves with the velocity, so the world point X sees lattice coordinates of X - V t.
    const double wx = origin_x - o.velocity_x * time_s, wy = origin_y - o.velocity_y * time_s;
    const double lattice_u = c * wx + s * wy + o.shift_u, lattice_v = -s * wx + c * wy + o.shift_v;
    f.off_u[i] = float(lattice_u - period * std::floor(lattice_u / period));
    f.off_v[i] = float(lattice_v - period * std::floor(lattice_v / period));
    f.value_scale[i] = float(o.amplitude / 508.0);
  }
  // |u| stays below 2^21 (exact floor and int conversion need < 2^22): a safety clamp only, floats
  // lose the fine octaves long before it.
  f.coord_limit = float(std::ldexp(finest, 21) / std::numbers::sqrt2 - 2.0 * period * finest);
  return f;
}

namespace {
void check_eval(const CapillaryFrame& frame, const float* x, const float* y, const float* level, std::size_t n,
                const float* h, const float* grad_x, const float* grad_y) noexcept {
  HOULE_ASSERT(frame.octaves <= CapillaryFrame::max_octaves, "capillary_eval: at most max_octaves octaves in the frame");
  HOULE_ASSERT(n == 0 || (x != nullptr && y != nullptr && level != nullptr && h != nullptr),
               "capillary_eval: n floats in each of x, y, level and h");
  HOULE_ASSERT((grad_x == nullptr) == (grad_y == nullptr), "capillary_eval: grad_x and grad_y both given or both null");
}
}  // namespace

void capillary_eval(const CapillaryFrame& frame, const float* x, const float* y, const float* level, std::size_t n,
                    float* h, float* grad_x, float* grad_y) noexcept {
  check_eval(frame, x, y, level, n, h, grad_x, grad_y);
  simd::active_table<detail::SurfaceTable>().capillary_eval(frame, x, y, level, n, h, grad_x, grad_y);
}

void capillary_eval(Isa isa, const CapillaryFrame& frame, const float* x, const float* y, const float* level,
                    std::size_t n, float* h, float* grad_x, float* grad_y) noexcept {
  check_eval(frame, x, y, level, n, h, grad_x, grad_y);
  simd::table_for<detail::SurfaceTable>(isa).capillary_eval(frame, x, y, level, n, h, grad_x, grad_y);
}

float capillary_footprint(float distance_m, float pixel_angle_rad, float sin_grazing) noexcept {
  const float s = sin_grazing > 1e-3f ? sin_grazing : 1e-3f;
  return distance_m * pixel_angle_rad / s;
}

float capillary_fade_rate(const CapillaryParams& p) noexcept {
  return std::min(1.0f, float(std::log2(double(p.lacunarity))));
}

float capillary_top_level(const CapillaryParams& p) noexcept {
  return p.max_octaves > 0 ? float(p.max_octaves - 1) + 1.0f / capillary_fade_rate(p) : 0.0f;
}

float octave_level(const CapillaryParams& p, float footprint_m) noexcept {
  const float top = capillary_top_level(p);
  if (std::isnan(footprint_m)) return 0.0f;
  if (!(footprint_m > 0.0f)) return top;
  const double l = std::log2(double(p.base_wavelength) / (double(p.samples_per_wavelength) * footprint_m)) /
                       std::log2(double(p.lacunarity)) + 1.0 / double(capillary_fade_rate(p));
  return l <= 0.0 ? 0.0f : (l >= top ? top : float(l));
}

float octave_level(const CapillaryParams& p, float distance_m, float pixel_angle_rad, float sin_grazing) noexcept {
  return octave_level(p, capillary_footprint(distance_m, pixel_angle_rad, sin_grazing));
}

float capillary_height_bound(const CapillaryParams& p, float level) noexcept {
  double sum = 0.0;
  for (int i = 0; i < p.max_octaves; ++i) sum += detail::octave_weight(level, i, capillary_fade_rate(p)) * std::pow(double(p.lacunarity), -double(i));
  return float(double(p.amplitude) * detail::value_overshoot * sum * detail::bound_margin);
}

float capillary_slope_bound(const CapillaryParams& p, float level) noexcept {
  double sum = 0.0;
  for (int i = 0; i < p.max_octaves; ++i) sum += detail::octave_weight(level, i, capillary_fade_rate(p));
  return float(double(p.amplitude) / p.base_wavelength * detail::gradient_overshoot * sum * detail::bound_margin);
}

float octave_slope_variance(const CapillaryParams& p) noexcept {
  const double g = double(p.amplitude) / p.base_wavelength;
  return float(g * g * detail::capillary_lattice().value_variance * detail::slope_integrals);
}

DroppedSlopeVariance::DroppedSlopeVariance(const CapillaryParams& p) noexcept
    : octave_variance(octave_slope_variance(p)), fade_rate(capillary_fade_rate(p)), octaves(p.max_octaves) {}

float DroppedSlopeVariance::operator()(float level) const noexcept {
  double missing = 0.0;
  for (int i = 0; i < octaves; ++i) {
    const double w = detail::octave_weight(level, i, fade_rate);
    missing += 1.0 - w * w;
  }
  return float(octave_variance * missing);
}

float dropped_slope_variance(const CapillaryParams& p, float level) noexcept { return DroppedSlopeVariance(p)(level); }

float capillary_lattice_value(std::int32_t i, std::int32_t j) noexcept {
  // Byte 1 of word (row j + 1, column i) is q(i, j): read back from the packed table the kernel uses.
  const std::int32_t word = detail::capillary_lattice().words[((j & 255) + 1) * detail::capillary_period + (i & 255)];
  return float(simd::signed_byte<1>(word)) / 127.0f;
}

}  // namespace houle
