// Sky and sun for reflections (docs/rendering.md 6): the Preetham, Shirley, Smits 1999 daylight model,
// its per-frame bake into a small lat-long table, and the sun as an analytic glint lobe.
//
// World z is up; directions are unit std::array<float, 3> {x, y, z}. Sky radiance is linear sRGB in
// kcd/m^2 (the model's luminance unit: Y of the result is the sky luminance); the renderer scales it by
// its exposure like everything else.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

/// CIE xyY: luminance in kcd/m^2 and chromaticity.
struct SkyXyY {
  double luminance_kcd = 0.0;
  double x = 0.0, y = 0.0;
};

/// Views below the horizon are evaluated at this zenith angle, just under 90 degrees (as Mitsuba does):
/// reflected sea rays often graze, and the Perez function's 1/cos(theta) must stay finite.
inline constexpr double sky_max_view_zenith_rad = 1.5697963267948966;  // pi/2 - 0.001

class PreethamSky {
 public:
  /// turbidity in [1.7, 10] (the model's fit covers about 2-6); sun_direction a non-zero vector (it is
  /// normalised), pointing to the sun. A sun below the horizon is treated as on it (zenith 90 degrees).
  static Expected<PreethamSky> make(double turbidity, std::array<float, 3> sun_direction);

  double turbidity() const noexcept { return turbidity_; }
  double sun_zenith_rad() const noexcept { return sun_zenith_; }
  std::array<float, 3> sun_direction() const noexcept { return sun_direction_; }

  /// Zenith luminance and chromaticity (the model's Y_z, x_z, y_z).
  SkyXyY zenith() const noexcept { return zenith_; }
  /// The model at view zenith angle theta and angle gamma between view and sun, no clamping.
  SkyXyY evaluate(double view_zenith_rad, double gamma_rad) const noexcept;
  /// The model seen along a unit direction; below the horizon the direction is lifted to
  /// sky_max_view_zenith_rad at the same azimuth.
  SkyXyY evaluate(std::array<float, 3> view) const noexcept;
  /// evaluate(view) as linear sRGB (kcd/m^2), negative channels clamped to 0.
  LinearRgb radiance(std::array<float, 3> view) const noexcept;

 private:
  friend class SkyLut;  // bakes from the coefficients directly
  PreethamSky() = default;
  double turbidity_ = 0.0, sun_zenith_ = 0.0;
  std::array<float, 3> sun_direction_{};
  std::array<double, 3> sun_unit_{};
  double perez_[3][5] = {};  // A..E for Y, x, y
  double scale_[3] = {};     // zenith value / F(0, theta_s) for Y, x, y
  SkyXyY zenith_;
};

/// The sky baked into a lat-long table over the upper hemisphere, for a bilinear lookup per ray instead
/// of six exp() and two acos(). Columns: azimuth, `width` steps over the full turn (plus one repeated
/// column so the seam needs no wrap), uniform in a "diamond angle" that costs a division where atan2
/// costs a polynomial and branches (0.64x-1.27x the uniform 2.8 degrees). Rows: from the horizon (sky_max_view_zenith_rad) to the zenith, spaced about
/// uniformly in zenith angle near the zenith and packed towards the horizon (a rational warp and a
/// sqrt of the view's z; no trigonometry). Against direct evaluation the lookup is within 0.5 % of
/// the luminance for 99 % of directions; the worst, a few %, is at the sun, where the model has a cusp.
/// Bake once per frame (or when the sun or turbidity change); the lookup reads only.
class SkyLut {
 public:
  static constexpr int width = 128;
  static constexpr int height = 32;

  SkyLut();  ///< allocates the table (black); bake() fills it without allocating
  void bake(const PreethamSky& sky) noexcept;
  /// Bilinear lookup along a unit direction; below the horizon gives the horizon at that azimuth.
  LinearRgb lookup(std::array<float, 3> direction) const noexcept;
  /// lookup() of n unit directions (x, y, z) into (r, g, b): the same bits, a packet at a time. Any n,
  /// no alignment.
  void lookup(const float* x, const float* y, const float* z, std::size_t n, float* r, float* g, float* b) const noexcept;
  /// The same on a given ISA (it must be supported): for tests and benchmarks.
  void lookup(Isa isa, const float* x, const float* y, const float* z, std::size_t n, float* r, float* g,
              float* b) const noexcept;

 private:
  std::vector<float> pairs_;  // per row, column and channel the texel and its right neighbour (sky_impl.hpp)
};

// ---- The sun below the horizon ------------------------------------------------------------------

/// The factor (per linear sRGB channel) by which the sky of a sun on the horizon (PreethamSky puts a
/// lower sun there) is dimmed and tinted for a sun at `sun_elevation_rad` (docs/rendering.md 6.4):
/// (1, 1, 1) with the sun up; below, civil twilight's fall of about a factor 10 per 2.5 degrees of
/// depression, turning blue, down to a floor of 3e-4 (a clear night under a full moon, whose light the
/// sky then stands for) from about 8.8 degrees on.
LinearRgb twilight_sky_factor(float sun_elevation_rad) noexcept;
/// The share of the sun's disc above the horizon at `sun_elevation_rad` (its centre), 0 to 1.
float sun_disc_above_horizon(float sun_elevation_rad) noexcept;

// ---- Sun ----------------------------------------------------------------------------------------

/// The sun's angular radius (docs/rendering.md 6.3) and the slope variance its disc alone spreads a mirror
/// reflection by; it is added to every lobe so that a perfectly smooth sea still has a finite glint.
inline constexpr float sun_angular_radius_rad = 4.65e-3f;
inline constexpr float sun_disc_slope_variance = 1e-5f;

/// Isotropic Gaussian (Beckmann) distribution of facet normals for surface slopes of variance
/// `slope_variance` per axis: D = exp(-tan^2(theta_h) / (2 s)) / (2 pi s cos^4(theta_h)), normalised so
/// that the integral of D cos(theta_h) over the hemisphere is 1. In 1/sr.
float gaussian_slope_density(float cos_theta_h, float slope_variance) noexcept;

/// The sun's glint on the sea as an analytic lobe (docs/rendering.md 5.4, 6.3; Bruneton et al. 2010):
/// radiance towards the eye per unit sun irradiance (1/sr),
///   L / E_sun = F(v.h) D(h) / (4 cos(theta_v) (1 + Lambda(v) + Lambda(l))),
/// h the half vector, D the Gaussian slope density with variance slope_variance +
/// sun_disc_slope_variance, Lambda Smith's shadowing term for it, F the exact Fresnel reflectance
/// from n_outside into n_inside. `normal` is the resolved (mean) surface normal, `view` the unit
/// direction from the surface to the eye, `sun` the unit direction to the sun; slope_variance is the
/// variance of the slopes the geometry no longer resolves (filtered far-field roughness), >= 0.
/// 0 when the eye or the sun is below the surface.
float sun_glint(std::array<float, 3> normal, std::array<float, 3> view, std::array<float, 3> sun,
                float slope_variance, float n_outside = 1.0f, float n_inside = 1.34f) noexcept;

}  // namespace houle
