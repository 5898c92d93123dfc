#include "houle/render/sky.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/render/optics.hpp"
#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"
#include "glint_impl.hpp"
#include "sky_impl.hpp"

namespace houle {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double min_view_z = detail::sky_min_view_z;

// Preetham et al. 1999, appendix A.2 (docs/rendering.md 6.1): Perez coefficients linear in turbidity T,
// rows A..E, columns (slope, intercept), for Y, x, y.
constexpr double perez_coeffs[3][5][2] = {
    {{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}},
    {{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}},
    {{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}},
};
// Zenith chromaticity: [T^2, T, 1] M [theta_s^3, theta_s^2, theta_s, 1]^T (the paper's digits).
constexpr double zenith_x[3][4] = {
    {0.00166, -0.00375, 0.00209, 0.0}, {-0.02903, 0.06377, -0.03202, 0.00394}, {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double zenith_y[3][4] = {
    {0.00275, -0.00610, 0.00317, 0.0}, {-0.04214, 0.08970, -0.04153, 0.00516}, {0.15346, -0.26756, 0.06670, 0.26688}};

double zenith_chromaticity(const double (&m)[3][4], double t, double theta_s) {
  const double tv[3] = {t * t, t, 1.0};
  const double sv[4] = {theta_s * theta_s * theta_s, theta_s * theta_s, theta_s, 1.0};
  double r = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) r += tv[i] * m[i][j] * sv[j];
  }
  return r;
}

/// The two factors of the Perez function F = (1 + A e^{B / cos theta}) (1 + C e^{D gamma} + E cos^2 gamma).
double perez_theta(const double (&c)[5], double cos_theta) { return 1.0 + c[0] * std::exp(c[1] / cos_theta); }
double perez_gamma(const double (&c)[5], double gamma) {
  const double cg = std::cos(gamma);
  return 1.0 + c[2] * std::exp(c[3] * gamma) + c[4] * cg * cg;
}

LinearRgb xyy_to_rgb(const SkyXyY& s) {
  const double big_y = s.luminance_kcd;
  const CieXyz xyz{s.x / s.y * big_y, big_y, (1.0 - s.x - s.y) / s.y * big_y};
  const LinearRgb c = xyz_to_linear_srgb(xyz);
  return {std::max(c.r, 0.0f), std::max(c.g, 0.0f), std::max(c.b, 0.0f)};
}

// The unit (x, y) direction of column coordinate p (the inverse of sky_column_of_xy in sky_impl.hpp, for
// the bake).
std::array<double, 2> xy_of_column(double p) {
  const double t = p < 2.0 ? 1.0 - p : p - 3.0;
  const double x = t, y = p < 2.0 ? 1.0 - std::fabs(t) : std::fabs(t) - 1.0;
  const double len = std::hypot(x, y);
  return {x / len, y / len};
}

// The inverse of sky_row_of_z (sky_impl.hpp), for the bake. Its warp k = 0.35 was the best of 0.1-0.6 (and of
// uniform theta, uniform z, smoothstep) by the 99th-percentile lookup error.
double z_of_row(double v) {
  const double w = 1.0 - (1.0 - v) * (1.0 - v);
  return min_view_z + (1.0 - min_view_z) * (detail::sky_row_warp * w / (1.0 + detail::sky_row_warp - w));
}

}  // namespace

Expected<PreethamSky> PreethamSky::make(double turbidity, std::array<float, 3> sun_direction) {
  if (!(turbidity >= 1.7 && turbidity <= 10.0)) return Error{"turbidity", "a value in [1.7, 10]"};
  const double sx = sun_direction[0], sy = sun_direction[1], sz = sun_direction[2];
  const double len = std::sqrt(sx * sx + sy * sy + sz * sz);
  if (!(len > 0.0) || !std::isfinite(len)) return Error{"sun_direction", "a finite non-zero vector"};

  PreethamSky s;
  s.turbidity_ = turbidity;
  s.sun_unit_ = {sx / len, sy / len, sz / len};
  s.sun_direction_ = {float(s.sun_unit_[0]), float(s.sun_unit_[1]), float(s.sun_unit_[2])};
  const double theta_s = std::acos(std::clamp(s.sun_unit_[2], 0.0, 1.0));
  s.sun_zenith_ = theta_s;
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < 5; ++c) s.perez_[k][c] = perez_coeffs[k][c][0] * turbidity + perez_coeffs[k][c][1];
  }
  const double t = turbidity;
  const double chi = (4.0 / 9.0 - t / 120.0) * (pi - 2.0 * theta_s);
  s.zenith_.luminance_kcd = (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
  s.zenith_.x = zenith_chromaticity(zenith_x, t, theta_s);
  s.zenith_.y = zenith_chromaticity(zenith_y, t, theta_s);
  const double zen[3] = {s.zenith_.luminance_kcd, s.zenith_.x, s.zenith_.y};
  for (int k = 0; k < 3; ++k) {
    // value(theta, gamma) = value_zenith F(theta, gamma) / F(0, theta_s)
    s.scale_[k] = zen[k] / (perez_theta(s.perez_[k], 1.0) * perez_gamma(s.perez_[k], theta_s));
  }
  return s;
}

SkyXyY PreethamSky::evaluate(double view_zenith_rad, double gamma_rad) const noexcept {
  const double ct = std::cos(view_zenith_rad);
  double v[3];
  for (int k = 0; k < 3; ++k) v[k] = scale_[k] * perez_theta(perez_[k], ct) * perez_gamma(perez_[k], gamma_rad);
  return {v[0], v[1], v[2]};
}

SkyXyY PreethamSky::evaluate(std::array<float, 3> view) const noexcept {
  double x = view[0], y = view[1], z = view[2];
  if (!(z >= min_view_z)) {
    // Lift onto the clamp cone at the same azimuth (straight down: any azimuth will do).
    const double h = std::hypot(x, y);
    const double r = std::sqrt(1.0 - min_view_z * min_view_z);
    x = h > 0.0 ? x / h * r : r;
    y = h > 0.0 ? y / h * r : 0.0;
    z = min_view_z;
  }
  const double theta = std::acos(std::min(z, 1.0));
  const double cos_gamma = x * sun_unit_[0] + y * sun_unit_[1] + z * sun_unit_[2];
  return evaluate(theta, std::acos(std::clamp(cos_gamma, -1.0, 1.0)));
}

LinearRgb PreethamSky::radiance(std::array<float, 3> view) const noexcept { return xyy_to_rgb(evaluate(view)); }

SkyLut::SkyLut() : pairs_(std::size_t(height) * width * 3 * 2, 0.0f) {}

void SkyLut::bake(const PreethamSky& sky) noexcept {
  // evaluate() per texel, with the zenith-angle factor of the Perez function hoisted out of each row:
  // three exp() and one acos() per texel instead of six and two.
  for (int j = 0; j < height; ++j) {
    const double z = z_of_row(double(j) / (height - 1));
    const double r = std::sqrt(std::max(1.0 - z * z, 0.0));
    double row_scale[3];
    for (int k = 0; k < 3; ++k) row_scale[k] = sky.scale_[k] * perez_theta(sky.perez_[k], z);
    float* row = &pairs_[std::size_t(j) * width * 3 * 2];
    for (int i = 0; i <= width; ++i) {
      const auto xy = xy_of_column(4.0 * (i == width ? 0 : i) / width);  // the extra column repeats column 0
      const double cos_gamma =
          std::clamp(r * xy[0] * sky.sun_unit_[0] + r * xy[1] * sky.sun_unit_[1] + z * sky.sun_unit_[2], -1.0, 1.0);
      const double gamma = std::acos(cos_gamma);
      SkyXyY v;
      double* out[3] = {&v.luminance_kcd, &v.x, &v.y};
      for (int k = 0; k < 3; ++k) {
        const double* c = sky.perez_[k];
        *out[k] = row_scale[k] * (1.0 + c[2] * std::exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
      }
      const LinearRgb rgb = xyy_to_rgb(v);
      const float c[3] = {rgb.r, rgb.g, rgb.b};
      for (int k = 0; k < 3; ++k) {
        if (i < width) row[2 * (3 * i + k)] = c[k];        // the first of its own pair
        if (i > 0) row[2 * (3 * (i - 1) + k) + 1] = c[k];  // the second of its left neighbour's
      }
    }
  }
}

static_assert(SkyLut::width == detail::sky_columns && SkyLut::height == detail::sky_rows);

LinearRgb SkyLut::lookup(std::array<float, 3> d) const noexcept {
  const auto c = detail::sky_lookup<simd::scalar>(pairs_.data(), d[0], d[1], d[2]);
  return {c.r, c.g, c.b};
}

namespace {
void check_lookup(const float* x, const float* y, const float* z, std::size_t n, const float* r, const float* g,
                  const float* b) noexcept {
  HOULE_ASSERT(n == 0 || (x != nullptr && y != nullptr && z != nullptr && r != nullptr && g != nullptr && b != nullptr),
               "SkyLut::lookup: n floats in every array");
}
}  // namespace

void SkyLut::lookup(const float* x, const float* y, const float* z, std::size_t n, float* r, float* g,
                    float* b) const noexcept {
  check_lookup(x, y, z, n, r, g, b);
  simd::active_table<detail::RenderTable>().sky_lookup_batch(pairs_.data(), x, y, z, n, r, g, b);
}

void SkyLut::lookup(Isa isa, const float* x, const float* y, const float* z, std::size_t n, float* r, float* g,
                    float* b) const noexcept {
  check_lookup(x, y, z, n, r, g, b);
  simd::table_for<detail::RenderTable>(isa).sky_lookup_batch(pairs_.data(), x, y, z, n, r, g, b);
}

// ---- The sun below the horizon ----

LinearRgb twilight_sky_factor(float sun_elevation_rad) noexcept {
  if (!(sun_elevation_rad < 0.0f)) return {1.0f, 1.0f, 1.0f};
  constexpr float per_degree = -0.4f;  // log10 of the sky's luminance per degree of depression
  constexpr float night = 3e-4f;
  constexpr float blue_depression_deg = 6.0f;  // the tint is whole at the end of civil twilight
  // The blue hour's tint, luminance 1: the sky's red fades faster than its blue once the sun's light
  // reaches it only through the ozone layer's Chappuis band; green is kept, so the glow stays orange.
  constexpr LinearRgb blue{0.82f, 0.98f, 1.74f};
  const float depression_deg = std::min(-sun_elevation_rad * float(180.0 / pi), 90.0f);
  const float level = std::max(std::pow(10.0f, per_degree * depression_deg), night);
  const float u = std::min(depression_deg / blue_depression_deg, 1.0f);
  const float w = u * u * (3.0f - 2.0f * u);
  return {level * (1.0f + w * (blue.r - 1.0f)), level * (1.0f + w * (blue.g - 1.0f)), level * (1.0f + w * (blue.b - 1.0f))};
}

float sun_disc_above_horizon(float sun_elevation_rad) noexcept {
  // The disc's share above the horizon as a linear ramp over its diameter: the visible area's exact
  // shape would change nothing a viewer sees at the few pixels it covers.
  const float u = (sun_elevation_rad + sun_angular_radius_rad) / (2.0f * sun_angular_radius_rad);
  return std::clamp(u, 0.0f, 1.0f);
}

// ---- Sun ----

float gaussian_slope_density(float cos_theta_h, float slope_variance) noexcept {
  return detail::gaussian_slope_density(cos_theta_h, slope_variance);
}

float sun_glint(std::array<float, 3> n, std::array<float, 3> v, std::array<float, 3> l, float slope_variance,
                float n_outside, float n_inside) noexcept {
  const float normal[3] = {n[0], n[1], n[2]}, view[3] = {v[0], v[1], v[2]}, sun[3] = {l[0], l[1], l[2]};
  return detail::sun_glint<simd::scalar>(normal, view, sun, slope_variance, n_outside, n_inside);
}

}  // namespace houle
