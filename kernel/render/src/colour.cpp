#include "houle/render/colour.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "colour_impl.hpp"
#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle {
namespace {

// ---- Compiled-in tables (generated, see the .inc headers for provenance) ----

constexpr double cie_rows[][4] = {
#include "data/cie1931_2deg.inc"
};
constexpr double d65_rows[][2] = {
#include "data/d65_5nm.inc"
};
constexpr double water_rows[][2] = {
#include "data/water_absorption_5nm.inc"
};
constexpr double smits_rows[][9] = {
#include "data/smits1999_basis.inc"
};

static_assert(std::size(cie_rows) == spectrum_samples && std::size(d65_rows) == spectrum_samples &&
              std::size(water_rows) == spectrum_samples && std::size(smits_rows) == 10);

constexpr bool on_grid() {
  for (int i = 0; i < spectrum_samples; ++i) {
    const double nm = spectrum_wavelength_nm(i);
    if (cie_rows[i][0] != nm || d65_rows[i][0] != nm || water_rows[i][0] != nm) return false;
  }
  for (int b = 0; b < 10; ++b) {
    if (smits_rows[b][0] != 380.0 + 34.0 * b || smits_rows[b][1] != 414.0 + 34.0 * b) return false;
  }
  return true;
}
static_assert(on_grid(), "tables must be on the 380-780/5 nm grid and Smits' bins 380 + 34 k nm");

constexpr SpectralData make_spectral_data() {
  SpectralData d{};
  for (int i = 0; i < spectrum_samples; ++i) {
    d.x_bar[i] = cie_rows[i][1];
    d.y_bar[i] = cie_rows[i][2];
    d.z_bar[i] = cie_rows[i][3];
    d.d65[i] = d65_rows[i][1];
    d.water_absorption[i] = water_rows[i][1];
  }
  return d;
}
constexpr SpectralData data = make_spectral_data();

// ---- Matrices ----

using Mat3 = std::array<std::array<double, 3>, 3>;
using Vec3d = std::array<double, 3>;

constexpr Vec3d mul(const Mat3& m, const Vec3d& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

constexpr Mat3 inverse(const Mat3& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1], c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2],
               c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  return {{{c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
           {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
           {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}}};
}

/// RGB -> XYZ for sRGB's primaries (0.64, 0.33), (0.30, 0.60), (0.15, 0.06) and white (wx, wy):
/// the primaries' XYZ (at Y = 1) as columns, each scaled so that RGB (1, 1, 1) is the white at Y = 1.
constexpr Mat3 srgb_primaries_to_xyz(double wx, double wy) {
  const double px[3] = {0.64, 0.30, 0.15}, py[3] = {0.33, 0.60, 0.06};
  Mat3 p{};
  for (int j = 0; j < 3; ++j) {
    p[0][j] = px[j] / py[j];
    p[1][j] = 1.0;
    p[2][j] = (1.0 - px[j] - py[j]) / py[j];
  }
  const Vec3d s = mul(inverse(p), Vec3d{wx / wy, 1.0, (1.0 - wx - wy) / wy});
  for (auto& row : p) {
    for (int j = 0; j < 3; ++j) row[j] *= s[j];
  }
  return p;
}

// docs/rendering.md 4.2, as printed (7 decimals).
constexpr Mat3 xyz_to_srgb = {{{3.2409699, -1.5373832, -0.4986108},
                               {-0.9692436, 1.8759675, 0.0415551},
                               {0.0556301, -0.2039770, 1.0569715}}};
constexpr Mat3 srgb_to_xyz = {{{0.4123908, 0.3575843, 0.1804808},
                               {0.2126390, 0.7151687, 0.0721923},
                               {0.0193308, 0.1191948, 0.9505322}}};
// Smits' design condition: the same primaries, white E.
constexpr Mat3 xyz_to_srgb_e = inverse(srgb_primaries_to_xyz(1.0 / 3.0, 1.0 / 3.0));

constexpr bool matches_printed(const Mat3& derived, const Mat3& printed) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double d = derived[i][j] - printed[i][j];
      if (d > 6e-8 || d < -6e-8) return false;
    }
  }
  return true;
}
// The printed matrices are the derivation rounded to 7 decimals: checks the derivation used for E.
static_assert(matches_printed(inverse(srgb_primaries_to_xyz(0.3127, 0.3290)), xyz_to_srgb));
static_assert(matches_printed(srgb_primaries_to_xyz(0.3127, 0.3290), srgb_to_xyz));

LinearRgb to_rgb(const Vec3d& v) { return {float(v[0]), float(v[1]), float(v[2])}; }
Vec3d xyz_vec(const CieXyz& c) { return {c.x, c.y, c.z}; }

/// Sum S(lambda) x_bar(lambda) dlambda over the grid (and y, z).
CieXyz integrate(const Spectrum& s) {
  CieXyz c;
  for (int i = 0; i < spectrum_samples; ++i) {
    c.x += s[i] * data.x_bar[i];
    c.y += s[i] * data.y_bar[i];
    c.z += s[i] * data.z_bar[i];
  }
  c.x *= spectrum_step_nm;
  c.y *= spectrum_step_nm;
  c.z *= spectrum_step_nm;
  return c;
}

/// The illuminant scaled so that its own Y is 1: E(lambda) rho(lambda) integrates to a reflectance's XYZ.
Spectrum normalised_illuminant(Illuminant illuminant) {
  Spectrum e{};
  for (int i = 0; i < spectrum_samples; ++i) e[i] = illuminant == Illuminant::d65 ? data.d65[i] : 1.0;
  const double k = 1.0 / integrate(e).y;
  for (double& v : e) v *= k;
  return e;
}

Spectrum times(const Spectrum& a, const Spectrum& b) {
  Spectrum p{};
  for (int i = 0; i < spectrum_samples; ++i) p[i] = a[i] * b[i];
  return p;
}

// Scene-time constant: the D65 spectrum at Y = 1 (a white object under the scene light).
const Spectrum& d65_unit() {
  static const Spectrum e = normalised_illuminant(Illuminant::d65);
  return e;
}

float luminance_of(LinearRgb c) { return detail::luminance_of<simd::scalar>({c.r, c.g, c.b}); }

/// Grey mixing of docs/rendering.md 4.2, in double: the fraction t of grey (Y, Y, Y) to mix in.
double grey_fraction(const Vec3d& rgb, double y) {
  const double lo = std::min({rgb[0], rgb[1], rgb[2]});
  if (lo >= 0.0) return 0.0;
  if (!(y > 0.0)) return 1.0;
  return -lo / (y - lo);
}

}  // namespace

const SpectralData& spectral_data() noexcept { return data; }

CieXyz spectrum_to_xyz(const Spectrum& radiance) noexcept { return integrate(radiance); }

CieXyz reflectance_to_xyz(const Spectrum& reflectance, Illuminant illuminant) noexcept {
  return integrate(times(reflectance, illuminant == Illuminant::d65 ? d65_unit() : normalised_illuminant(illuminant)));
}

LinearRgb reflectance_to_linear_srgb(const Spectrum& reflectance, Illuminant illuminant) noexcept {
  const Vec3d xyz = xyz_vec(reflectance_to_xyz(reflectance, illuminant));
  return to_rgb(mul(illuminant == Illuminant::d65 ? xyz_to_srgb : xyz_to_srgb_e, xyz));
}

LinearRgb xyz_to_linear_srgb(const CieXyz& xyz) noexcept { return to_rgb(mul(xyz_to_srgb, xyz_vec(xyz))); }

CieXyz linear_srgb_to_xyz(LinearRgb rgb) noexcept {
  const Vec3d v = mul(srgb_to_xyz, Vec3d{rgb.r, rgb.g, rgb.b});
  return {v[0], v[1], v[2]};
}

float luminance(LinearRgb c) noexcept { return luminance_of(c); }

float srgb_encode(float linear) noexcept {
  const float c = std::clamp(linear, 0.0f, 1.0f);  // NaN stays NaN: clamp compares
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) noexcept {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

std::uint8_t srgb_encode_u8(float linear) noexcept {
  const float e = srgb_encode(linear);
  return static_cast<std::uint8_t>(e >= 0.0f ? std::lround(e * 255.0f) : 0);
}

namespace {
LinearRgb grey_mapped(LinearRgb c) {
  const auto m = detail::grey_mapped<simd::scalar>({c.r, c.g, c.b});
  return {m.r, m.g, m.b};
}
}  // namespace

LinearRgb gamut_map_to_grey(LinearRgb c) noexcept { return grey_mapped(c); }

// ---- Smits ----

SmitsWeights smits_weights(LinearRgb c) noexcept {
  const auto w = detail::smits_lanes<simd::scalar>({c.r, c.g, c.b});
  return {w.white, SmitsBasis(w.secondary_column), w.secondary, SmitsBasis(w.primary_column), w.primary};
}

Spectrum smits_basis_spectrum(SmitsBasis basis) noexcept {
  Spectrum s{};
  for (int i = 0; i < spectrum_samples; ++i) {
    // A sample on a bin edge (550 nm) belongs to the bin above; 720-780 nm continue the last bin.
    const int bin = std::min(int((spectrum_wavelength_nm(i) - 380.0) / 34.0), 9);
    s[i] = smits_rows[bin][2 + static_cast<int>(basis)];
  }
  return s;
}

Spectrum smits_spectrum(LinearRgb rgb) noexcept {
  const SmitsWeights w = smits_weights(rgb);
  const Spectrum white = smits_basis_spectrum(SmitsBasis::white), sec = smits_basis_spectrum(w.secondary),
                 pri = smits_basis_spectrum(w.primary);
  Spectrum s{};
  for (int i = 0; i < spectrum_samples; ++i) {
    s[i] = w.white * white[i] + w.secondary_weight * sec[i] + w.primary_weight * pri[i];
  }
  return s;
}

// ---- Sea colours ----

namespace {
struct SeaEntry {
  std::string_view name;
  double dominant_nm;
};
// The paper's table (sec. 4): "main colour" C of each sea.
constexpr SeaEntry seas[] = {{"Pacific", 473.0},     {"Indian", 474.0},      {"Mediterranean", 473.0},
                             {"Atlantic", 483.0},    {"Baltic", 540.0},      {"Panama Gulf", 487.2},
                             {"Senegal Coast", 512.0}};
}  // namespace

double sea_dominant_wavelength_nm(Sea sea) noexcept { return seas[static_cast<int>(sea)].dominant_nm; }
std::string_view sea_name(Sea sea) noexcept { return seas[static_cast<int>(sea)].name; }

Spectrum gaussian_spectrum(double centre_nm, double sigma_nm) noexcept {
  Spectrum s{};
  for (int i = 0; i < spectrum_samples; ++i) {
    const double u = (spectrum_wavelength_nm(i) - centre_nm) / sigma_nm;
    s[i] = std::exp(-0.5 * u * u);
  }
  return s;
}

SeaColour sea_colour(double dominant_nm, double sigma_nm, double luminance_y) noexcept {
  HOULE_ASSERT(sigma_nm > 0.0, "sea_colour: sigma_nm > 0");
  SeaColour out{};
  const Spectrum g = gaussian_spectrum(dominant_nm, sigma_nm);
  const CieXyz xyz = integrate(g);
  const double sum = xyz.x + xyz.y + xyz.z;
  out.chromaticity_x = xyz.x / sum;
  out.chromaticity_y = xyz.y / sum;
  // Emitted light, no illuminant weighting (sea_colours.csv); scaled to the wanted Y.
  const double k = xyz.y > 0.0 ? luminance_y / xyz.y : 0.0;
  const Vec3d lin = mul(xyz_to_srgb, Vec3d{k * xyz.x, k * xyz.y, k * xyz.z});
  const double t = grey_fraction(lin, luminance_y);
  out.unmapped = to_rgb(lin);
  out.linear = to_rgb({lin[0] + t * (luminance_y - lin[0]), lin[1] + t * (luminance_y - lin[1]),
                       lin[2] + t * (luminance_y - lin[2])});
  // The grey as a spectrum is D65 at that Y (its sRGB is (Y, Y, Y) to 3e-4).
  const Spectrum& grey = d65_unit();
  for (int i = 0; i < spectrum_samples; ++i) out.radiance[i] = (1.0 - t) * k * g[i] + t * luminance_y * grey[i];
  return out;
}

// ---- Water ----

Spectrum water_absorption(double cdom_absorption_440_per_m) noexcept {
  Spectrum a = data.water_absorption;
  if (cdom_absorption_440_per_m != 0.0) {
    for (int i = 0; i < spectrum_samples; ++i) {
      a[i] += cdom_absorption_440_per_m * std::exp(-0.014 * (spectrum_wavelength_nm(i) - 440.0));
    }
  }
  return a;
}

LinearRgb water_transmittance_rgb(double distance_m, double cdom_absorption_440_per_m) noexcept {
  const Spectrum a = water_absorption(cdom_absorption_440_per_m);
  Spectrum t{};
  for (int i = 0; i < spectrum_samples; ++i) t[i] = std::exp(-a[i] * distance_m);
  const Vec3d white = mul(xyz_to_srgb, xyz_vec(integrate(d65_unit())));
  const Vec3d rgb = mul(xyz_to_srgb, xyz_vec(integrate(times(t, d65_unit()))));
  return to_rgb({rgb[0] / white[0], rgb[1] / white[1], rgb[2] / white[2]});
}

Expected<WaterColourLut> WaterColourLut::make(const WaterColourParams& p) {
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!(finite(p.sea_dominant_nm) && p.sea_dominant_nm >= 380.0 && p.sea_dominant_nm <= 780.0)) {
    return Error{"sea_dominant_nm", "a wavelength in [380, 780] nm"};
  }
  if (!(finite(p.sea_sigma_nm) && p.sea_sigma_nm >= 1.0 && p.sea_sigma_nm <= 400.0)) {
    return Error{"sea_sigma_nm", "a width in [1, 400] nm"};
  }
  if (!(finite(p.sea_luminance) && p.sea_luminance >= 0.0)) return Error{"sea_luminance", "a finite value >= 0"};
  if (!(finite(p.cdom_absorption_440_per_m) && p.cdom_absorption_440_per_m >= 0.0)) {
    return Error{"cdom_absorption_440_per_m", "a finite value >= 0 1/m"};
  }
  if (!(p.lut_entries >= 4 && p.lut_entries <= 65536)) return Error{"lut_entries", "a count in [4, 65536]"};
  if (!(finite(p.lut_half_distance_m) && p.lut_half_distance_m > 0.0)) {
    return Error{"lut_half_distance_m", "a finite value > 0 m"};
  }
  if (!(finite(p.rgb_fit_distance_m) && p.rgb_fit_distance_m > 0.0)) {
    return Error{"rgb_fit_distance_m", "a finite value > 0 m"};
  }

  WaterColourLut lut;
  const int n = p.lut_entries;
  lut.entries_ = n;
  lut.half_distance_m_ = float(p.lut_half_distance_m);
  std::vector<float> table(std::size_t(n) * row_floats, 0.0f);

  const Spectrum a = water_absorption(p.cdom_absorption_440_per_m);
  const Spectrum& light = d65_unit();
  const SeaColour sea = houle::sea_colour(p.sea_dominant_nm, p.sea_sigma_nm, p.sea_luminance);
  lut.sea_colour_ = sea.linear;

  Spectrum lit[smits_basis_count];  // basis reflectance under the scene light
  for (int b = 0; b < smits_basis_count; ++b) lit[b] = times(smits_basis_spectrum(SmitsBasis(b)), light);

  // Nominal RGB of each basis: white, cyan, magenta, yellow, red, green, blue.
  constexpr double nominal[smits_basis_count][3] = {{1, 1, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0},
                                                    {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3d correction[smits_basis_count];
  double y0[smits_basis_count];
  for (int e = 0; e < n; ++e) {
    const double u = double(e) / (n - 1);
    const bool infinite = e == n - 1;  // d = infinity: nothing of the object is left
    const double d = infinite ? 0.0 : p.lut_half_distance_m * u / (1.0 - u);
    Spectrum k{};
    for (int i = 0; i < spectrum_samples; ++i) k[i] = infinite ? 0.0 : std::exp(-a[i] * d);
    float* row = &table[std::size_t(e) * row_floats];
    for (int b = 0; b < smits_basis_count; ++b) {
      const CieXyz xyz = integrate(times(lit[b], k));
      Vec3d rgb = mul(xyz_to_srgb, xyz_vec(xyz));
      if (e == 0) {
        y0[b] = xyz.y;
        for (int c = 0; c < 3; ++c) correction[b][c] = nominal[b][c] - rgb[c];
      }
      const double fade = xyz.y / y0[b];  // 1 at d = 0, the basis's transmitted luminance after
      for (int c = 0; c < 3; ++c) row[3 * b + c] = float(rgb[c] + fade * correction[b][c]);
    }
    Spectrum sea_in{};
    for (int i = 0; i < spectrum_samples; ++i) sea_in[i] = (1.0 - k[i]) * sea.radiance[i];
    const Vec3d rgb = mul(xyz_to_srgb, xyz_vec(integrate(sea_in)));
    for (int c = 0; c < 3; ++c) row[3 * smits_basis_count + c] = float(rgb[c]);
  }

  // Each value with the next row's beside it (detail::WaterTable).
  lut.pairs_.assign(std::size_t(n - 1) * row_floats * 2, 0.0f);
  for (std::size_t q = 0; q + row_floats < table.size(); ++q) {
    lut.pairs_[2 * q] = table[q];
    lut.pairs_[2 * q + 1] = table[q + row_floats];
  }

  const LinearRgb fit = water_transmittance_rgb(p.rgb_fit_distance_m, p.cdom_absorption_440_per_m);
  const double fit_t[3] = {fit.r, fit.g, fit.b};
  for (int c = 0; c < 3; ++c) {
    // Transmittance slightly above 1 (blue, a few cm) or <= 0 (red, far): clamp to a sane coefficient.
    const double t = std::clamp(fit_t[c], 1e-6, 1.0);
    // A floor keeps e^{-a d} well defined (0, not NaN) at d = infinity.
    lut.rgb_absorption_[c] = float(std::max(-std::log(t) / p.rgb_fit_distance_m, 1e-6));
  }
  return lut;
}

detail::WaterTable WaterColourLut::table() const noexcept {
  static_assert(row_floats == detail::water_row_floats);
  return {pairs_.data(), entries_, half_distance_m_};
}

namespace {
LinearRgb rgb(const detail::Rgb<simd::scalar>& c) { return {c.r, c.g, c.b}; }
}  // namespace

LinearRgb WaterColourLut::absorbed(LinearRgb object, float distance_m) const noexcept {
  const detail::WaterTable w = table();
  return rgb(detail::water_absorbed<simd::scalar>(w, detail::water_position<simd::scalar>(w, distance_m),
                                                  {object.r, object.g, object.b}));
}

LinearRgb WaterColourLut::sea_part(float distance_m) const noexcept {
  const detail::WaterTable w = table();
  return rgb(detail::water_sea_part<simd::scalar>(w, detail::water_position<simd::scalar>(w, distance_m)));
}

LinearRgb WaterColourLut::transmitted(LinearRgb object, float distance_m) const noexcept {
  return mix(object, distance_m, 0.0f, 1.0f);
}

LinearRgb WaterColourLut::mix(LinearRgb object, float distance_m, float light_path_m, float illumination) const noexcept {
  return rgb(detail::water_mix<simd::scalar>(table(), {object.r, object.g, object.b}, distance_m, light_path_m, illumination));
}

namespace {
void check_mix(const WaterMixInput& in, std::size_t n, const WaterMixOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.r != nullptr && in.g != nullptr && in.b != nullptr && in.distance_m != nullptr &&
                          in.light_path_m != nullptr && in.illumination != nullptr && out.r != nullptr &&
                          out.g != nullptr && out.b != nullptr),
               "WaterColourLut::mix: n floats in every array");
}
}  // namespace

void WaterColourLut::mix(const WaterMixInput& in, std::size_t n, WaterMixOutput out) const noexcept {
  check_mix(in, n, out);
  simd::active_table<detail::RenderTable>().water_mix_batch(table(), in, n, out);
}

void WaterColourLut::mix(Isa isa, const WaterMixInput& in, std::size_t n, WaterMixOutput out) const noexcept {
  check_mix(in, n, out);
  simd::table_for<detail::RenderTable>(isa).water_mix_batch(table(), in, n, out);
}

LinearRgb WaterColourLut::transmitted_rgb_approx(LinearRgb object, float distance_m) const noexcept {
  const float d = distance_m > 0.0f ? distance_m : 0.0f;
  const float kr = std::exp(-rgb_absorption_[0] * d), kg = std::exp(-rgb_absorption_[1] * d),
              kb = std::exp(-rgb_absorption_[2] * d);
  return {kr * object.r + (1.0f - kr) * sea_colour_.r, kg * object.g + (1.0f - kg) * sea_colour_.g,
          kb * object.b + (1.0f - kb) * sea_colour_.b};
}

}  // namespace houle
