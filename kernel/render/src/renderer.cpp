#include "houle/render/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "houle/render/optics.hpp"
#include "houle/render/sky.hpp"
#include "houle/runtime/assert.hpp"
#include "houle/runtime/thread_pool.hpp"
#include "floor_hits.hpp"
#include "foam.hpp"
#include "ray_pack.hpp"
#include "sand.hpp"
#include "sand_impl.hpp"
#include "scene_objects.hpp"
#include "sea_light.hpp"
#include "shadow_mask.hpp"
#include "under_light.hpp"
#include "under_light_impl.hpp"

namespace houle {
namespace {

using Clock = std::chrono::steady_clock;
using Vec3 = std::array<float, 3>;
using detail::HitKind;
using detail::SceneRay;
using detail::SurfaceHit;

// Fixed sub-pixel positions (pixel units from the pixel's corner): deterministic, so identical frames
// give identical bytes. 4: the rotated grid; 8: Direct3D's standard 8x pattern.
struct Offset {
  float x, y;
};
constexpr Offset offsets_1[] = {{0.5f, 0.5f}};
constexpr Offset offsets_4[] = {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}};
constexpr Offset offsets_8[] = {{0.5625f, 0.3125f}, {0.4375f, 0.6875f}, {0.8125f, 0.5625f}, {0.3125f, 0.1875f},
                                {0.1875f, 0.8125f}, {0.0625f, 0.4375f}, {0.6875f, 0.9375f}, {0.9375f, 0.0625f}};

// Extra-terrestrial solar illuminance (klx) and the sky light's transmission into the sea (the mean
// Fresnel transmittance of a uniform sky, 1 - 0.066).
constexpr double solar_constant_klx = 128.0;
constexpr float sky_water_transmission = 0.934f;
// The exposure never follows a sun near or below the horizon further down than this (klx): the sky
// would otherwise be blown up without limit.
constexpr double min_reference_klx = 10.0;
// Per pixel and sample, up to Renderer::max_kept_bytes: what the primary ray met, the marcher's t_max
// from it, its flags (kept_meets_movers, kept_colour, kept_sky) and, off the sea, its colour
// (primary_hits, shade_sample). A 1920 x 1080 image keeps 81 MiB at one sample and 162 MiB at two;
// at 4 samples it would be 324 MiB and at 8 (film) 648 MiB, which such renders do without.
static_assert(sizeof(SurfaceHit) + sizeof(float) + sizeof(std::uint8_t) + 3 * sizeof(float) == Renderer::kept_hit_bytes);
constexpr std::uint8_t kept_meets_movers = 1;  // the primary ray meets a moving object's bounds
constexpr std::uint8_t kept_colour = 2;        // the colour off the sea is kept
// With kept_colour: the primary ray met nothing. A kept colour is counted from the flags, so that a
// frame that only copies kept colours reads none of the kept hits (28 bytes a pixel).
constexpr std::uint8_t kept_sky = 4;

LinearRgb operator*(LinearRgb a, float s) { return {a.r * s, a.g * s, a.b * s}; }
LinearRgb operator*(LinearRgb a, LinearRgb b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
LinearRgb operator+(LinearRgb a, LinearRgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
float dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
SceneRay make_ray(const Vec3& o, const Vec3& n, float offset, const Vec3& d) {
  return {double(o[0]) + double(n[0] * offset), double(o[1]) + double(n[1] * offset),
          double(o[2]) + double(n[2] * offset), double(d[0]), double(d[1]), double(d[2])};
}
Vec3 along(const Vec3& o, const Vec3& d, float t) { return {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}; }

/// Direct sunlight's transmittance through the atmosphere per channel (R, G, B at 610, 550, 465 nm):
/// Kasten-Young 1989 air mass, Rayleigh optical depth 0.008735 lambda^-4.08 (lambda in um) and the
/// Angstrom aerosol term beta lambda^-1.3 with Preetham's beta = 0.04608 T - 0.04586. A sun below the
/// horizon is taken on it.
LinearRgb sun_transmittance(double cos_zenith, double turbidity) {
  const double c = std::clamp(cos_zenith, 0.0, 1.0);
  const double zenith_deg = std::acos(c) * 180.0 / std::numbers::pi;
  const double air_mass = 1.0 / (c + 0.50572 * std::pow(96.07995 - zenith_deg, -1.6364));
  const double beta = std::max(0.04608 * turbidity - 0.04586, 0.0);
  const double lambda_um[3] = {0.610, 0.550, 0.465};
  float t[3];
  for (int k = 0; k < 3; ++k) {
    const double tau = 0.008735 * std::pow(lambda_um[k], -4.08) + beta * std::pow(lambda_um[k], -1.3);
    t[k] = float(std::exp(-air_mass * tau));
  }
  return {t[0], t[1], t[2]};
}

/// The display exposure for a sky (docs/rendering.md 4.5): the log-average luminance L_a of the sky
/// from the horizon to 40 degrees up (what a coastal view shows, directly and in the sea's mirror), in
/// the renderer's units (`scale` per channel), is brought to display_key; a sky dimmer than
/// full_adaptation_kcd (an early dusk) is compensated for only two thirds of its fall (in log), so
/// dusk and night stay dark. `kcd_per_unit` converts the units to kcd/m^2.
float sky_exposure(const PreethamSky& sky, LinearRgb scale, double kcd_per_unit) {
  constexpr double display_key = 0.18, full_adaptation_kcd = 1.0;
  constexpr int rows = 8, columns = 32;
  double sum = 0.0;
  for (int i = 0; i < rows; ++i) {
    const double e = (i + 0.5) / rows * 40.0 * std::numbers::pi / 180.0;
    for (int j = 0; j < columns; ++j) {
      const double a = (j + 0.5) / columns * 2.0 * std::numbers::pi;
      const Vec3 v{float(std::cos(e) * std::cos(a)), float(std::cos(e) * std::sin(a)), float(std::sin(e))};
      sum += std::log(std::max(double(luminance(sky.radiance(v) * scale)), 1e-30));
    }
  }
  const double l_a = std::exp(sum / (rows * columns));
  const double adaptation = std::cbrt(std::min(1.0, l_a * kcd_per_unit / full_adaptation_kcd));
  return float(display_key / l_a * adaptation);
}

/// Sky irradiance on a horizontal surface (klx per channel: kcd/m^2 times sr), midpoint rule.
LinearRgb sky_irradiance_klx(const PreethamSky& sky) {
  constexpr int rows = 32, columns = 64;
  double e[3] = {0.0, 0.0, 0.0};
  const double d_theta = 0.5 * std::numbers::pi / rows, d_phi = 2.0 * std::numbers::pi / columns;
  for (int i = 0; i < rows; ++i) {
    const double theta = (i + 0.5) * d_theta;
    const double w = std::cos(theta) * std::sin(theta) * d_theta * d_phi;
    for (int j = 0; j < columns; ++j) {
      const double phi = (j + 0.5) * d_phi;
      const Vec3 v{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
      const LinearRgb l = sky.radiance(v);
      e[0] += w * l.r;
      e[1] += w * l.g;
      e[2] += w * l.b;
    }
  }
  return {float(e[0]), float(e[1]), float(e[2])};
}

bool finite(LinearRgb c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

/// Per-thread row buffers (SoA, `width` entries each), sized once by create().
struct alignas(64) Scratch {
  enum Array {
    dx, dy, dz, ox, oy, oz, t_max, t, hx, hy, hz, gx, gy, level, rough, side, nx, ny, nz, rx, ry, rz, tx, ty, tz, kr,
    ax, ay, az, sky_r, sky_g, sky_b, foam, on_sand, qx, qy, qz, footprint, sand_r, sand_g, sand_b, lit,
    seen_r, seen_g, seen_b, seen_t, seen_path, seen_illumination, under_r, under_g, under_b,
    air_hit, reflected_r, reflected_g, reflected_b, light_r, light_g, light_b, glint_lobe, glint_variance,
    // What the ray into the water meets (light_under_water): met > 0, its normal and albedo; ask: under_light's.
    met, met_nx, met_ny, met_nz, met_r, met_g, met_b, ask,
    // A row's primary or secondary rays, packed (nearest_hits): ray k is pixel ray_pixel[k]'s.
    ray_ox, ray_oy, ray_oz, ray_dx, ray_dy, ray_dz, ray_reach, hit_t, hit_nx, hit_ny, hit_nz, hit_left, hit_objects, count
  };
  std::vector<float> memory;
  float* a[count] = {};
  std::vector<float> accumulated;  // 3 per pixel: the samples' sum, with more than one
  std::vector<MarchStatus> status;
  SurfaceHit* object = nullptr;  // the row's primary hits: own_object, or the memo's row
  // The memo's row of colours off the sea and its flags, while they may be read and written (render()'s
  // keep_colours, a still camera): null otherwise.
  float* kept_rgb = nullptr;
  std::uint8_t* kept_flags = nullptr;
  std::vector<SurfaceHit> own_object;
  std::vector<SurfaceHit> under;  // what the ray into the water from a sea hit meets (shade_sample)
  std::vector<SurfaceHit> air;    // what the ray into the air from a sea hit meets (with reflect_objects)
  std::vector<std::uint32_t> ray_pixel;
  std::int64_t march_ns = 0, intersect_ns = 0, shade_ns = 0;
  RenderCounters counters;

  explicit Scratch(std::uint32_t width) {
    const std::size_t stride = (std::size_t(width) + 15) / 16 * 16;
    memory.assign(stride * count, 0.0f);
    for (int k = 0; k < count; ++k) a[k] = memory.data() + stride * std::size_t(k);
    accumulated.assign(std::size_t(width) * 3, 0.0f);
    status.assign(width, MarchStatus::miss);
    own_object.assign(width, SurfaceHit{});
    object = own_object.data();
    under.assign(width, SurfaceHit{});
    air.assign(width, SurfaceHit{});
    ray_pixel.assign(stride, 0);  // padded, as the arrays: pack_rays writes whole batches
  }
};

}  // namespace

struct Renderer::Impl {
  // Scene, fixed at create().
  RenderQuality quality;
  std::uint32_t width = 0, height = 0;
  detail::SceneObjects objects;
  SkyLut sky;
  std::optional<WaterColourLut> water;  // no default state: set by create()
  const Offset* offsets = offsets_1;
  int samples = 1;
  float max_distance = 1e5f;
  float sea_height_bound = std::numeric_limits<float>::infinity();  ///< RenderScene's

  // Light in the renderer's relative units (see renderer.hpp).
  Vec3 sun{0.0f, 0.0f, 1.0f};
  LinearRgb sand;             ///< the dry sand's reflectance
  detail::PackedSurf surf;   ///< where waves break (empty: nowhere)
  LinearRgb sun_rgb;          ///< a white surface facing the sun reflects this
  LinearRgb ambient;          ///< a white horizontal surface reflects this of the sky's light
  LinearRgb sky_scale;        ///< sky kcd/m^2 -> relative radiance (dimmed and tinted after sunset)
  Vec3 sun_water{0.0f, 0.0f, 1.0f};  ///< towards the sun under a flat sea (refracted)
  LinearRgb sun_water_rgb;    ///< the sun's light after entering the sea
  LinearRgb ambient_water;    ///< the sky's light after entering the sea
  LinearRgb sea_lit;          ///< I_sea for this lighting
  float sea_illumination = 0.0f;  ///< luminance on a white horizontal surface: scales I_sea
  float sea_shade_illumination = 0.0f;  ///< the same in an object's shadow: the sky's share alone
  float casters_top = -std::numeric_limits<float>::infinity();  ///< m, highest point of a box or sphere
  detail::ShadowMask sun_mask, sun_water_mask;  ///< where lines along sun and sun_water can meet them
  detail::UnderLightParams under_light;  ///< the light above in the sea's terms, and views of the masks
  float exposure = 1.0f;          ///< display_exposure()
  std::array<float, 3> rgb_absorption{};

  std::unique_ptr<detail::ThreadPool> pool;
  std::vector<std::unique_ptr<Scratch>> scratch;
  // The primary rays' object and floor hits, row by row (row r, sample k: entries (r samples + k) width
  // onwards), the marcher's t_max from each, its flags and the colour of a pixel off the sea, and the
  // camera and cut they were found for: a still camera finds them there the next frame. Apart, so that
  // a kept sea pixel reads 5 bytes, not its hit (which only the shading of what is not sea reads).
  std::vector<SurfaceHit> memo_hits;
  std::vector<float> memo_t_max;
  std::vector<std::uint8_t> memo_flags;
  std::vector<float> memo_rgb;  // 3 per entry, valid where the flags say kept_colour
  // The frame before's camera and cut. The memo is used only where this frame's are the same (a
  // still camera), so that a moving camera writes none that the next frame would not read.
  Camera memo_camera;
  double memo_cut = std::numeric_limits<double>::quiet_NaN();  // NaN: no frame yet
  bool memo_use = false;     // this frame: a still camera, and a memo
  bool memo_refill = true;   // this frame: the memo holds no hits of this camera yet
  bool memo_valid = false;   // after the frame: the memo holds its camera's hits
  // This frame keeps the colours off the sea: nothing but the camera and the cut changes them (no
  // movers, a camera above the sea, the shaded view).
  bool keep_colours = false;
  FrameTimes times;
  RenderCounters counters;

  // The frame being rendered (set by render()).
  const SurfaceFrame* surface = nullptr;
  const CapillaryFrame* noise = nullptr;
  DroppedSlopeVariance dropped;  // of the noise's parameters (render()'s noise_params), for the glint
  Camera camera;
  Framebuffer* out = nullptr;
  RenderView view = RenderView::shaded;
  bool aovs = false;  // out has an AOV to fill
  MarchParams march;
  MarchPlan march_plan;  // march's, prepared once per frame for every row
  bool camera_under = false;
  double primary_floor_lo = 0.0;
  detail::SeaLightParams sea_light;  // this frame's light for the sea seen from above

  void render_row(Scratch& s, std::uint32_t row) noexcept;
  /// Shades one sample of the row into rgb (3 per pixel): sets it for the first sample, adds to it after.
  void shade_sample(Scratch& s, float* rgb, bool first) noexcept;
  void add_aovs(const Scratch& s, std::uint32_t row, int sample) const noexcept;
  LinearRgb shade_primary(const Scratch& s, std::size_t i, RenderCounters& c) const noexcept;
  static bool colour_kept(const Scratch& s, std::size_t i) noexcept;
  static LinearRgb kept_primary(Scratch& s, std::size_t i) noexcept;
  static void add_sample(Scratch& s, float* rgb, std::size_t i, LinearRgb c, bool first) noexcept;
  /// The sky's radiance along pixel i's direction in air (shade_sample's air_directions).
  LinearRgb sky_radiance(const Scratch& s, std::size_t i) const noexcept {
    return LinearRgb{s.a[Scratch::sky_r][i], s.a[Scratch::sky_g][i], s.a[Scratch::sky_b][i]} * sky_scale;
  }
  // `travelled`: m from the camera to where the ray starts (0 for primary rays): with the hit's t it
  // gives the pixel's footprint there.
  LinearRgb albedo(const SurfaceHit& h, const Vec3& p, float travelled) const noexcept;
  /// The albedo at pixel i's floor hit (shade_sample's sand_albedo) or object hit h.
  LinearRgb albedo(const Scratch& s, std::size_t i, const SurfaceHit& h) const noexcept {
    return h.kind == HitKind::floor ? LinearRgb{s.a[Scratch::sand_r][i], s.a[Scratch::sand_g][i], s.a[Scratch::sand_b][i]}
                                    : objects.albedo(h);
  }
  LinearRgb lit_in_air(const SurfaceHit& h, const Vec3& p, const Vec3& d, LinearRgb albedo) const noexcept;
  LinearRgb lit_in_water(const SurfaceHit& h, const Vec3& p, const Vec3& d, LinearRgb albedo) const noexcept;
  LinearRgb through_water(LinearRgb object, float distance, float light_path, float illumination) const noexcept;
  LinearRgb from_air(const SurfaceHit& h, const Vec3& p, const Vec3& d, float travelled, LinearRgb sky_along_d) const noexcept;
  LinearRgb through_water_to(const SurfaceHit& h, LinearRgb albedo, const Vec3& p, const Vec3& d,
                             float illumination) const noexcept;
  void nearest_hits(Scratch& s, std::size_t rays, SurfaceHit* hits) const noexcept;
  void primary_hits(Scratch& s, std::size_t memo_row) noexcept;
  void find_water_hits(Scratch& s, bool meets_sea) const noexcept;
  void find_air_hits(Scratch& s) const noexcept;
  void light_under_water(Scratch& s) const noexcept;
  bool sunlit(const Vec3& p, const Vec3& offset_normal, float offset) const noexcept;
  float sun_path_in_water(const Vec3& p) const noexcept { return detail::sun_path_in_water<simd::scalar>(under_light, p[2]); }
};

// ---- Shading ----------------------------------------------------------------------------------

LinearRgb Renderer::Impl::albedo(const SurfaceHit& h, const Vec3& p, float travelled) const noexcept {
  if (h.kind != HitKind::floor) return objects.albedo(h);
  const auto c = detail::sand_at<simd::scalar>(sand, p[0], p[1], p[2], (travelled + h.t) * camera.pixel_angle);
  return {c.r, c.g, c.b};
}

LinearRgb Renderer::Impl::lit_in_air(const SurfaceHit& h, const Vec3& p, const Vec3& d, LinearRgb albedo) const noexcept {
  Vec3 n = h.normal;
  if (dot(n, d) > 0.0f) n = {-n[0], -n[1], -n[2]};  // the side the ray sees
  LinearRgb light = ambient * (0.5f * (1.0f + n[2]));
  const float cos_sun = dot(n, sun);
  if (cos_sun > 0.0f) {
    const float offset = 1e-3f + 1e-4f * h.t;
    const bool lit = !quality.shadows || !objects.occluded(make_ray(p, n, offset, sun), 0.0, double(max_distance));
    if (lit) light = light + sun_rgb * cos_sun;
  }
  return albedo * light;
}

LinearRgb Renderer::Impl::lit_in_water(const SurfaceHit& h, const Vec3& p, const Vec3& d, LinearRgb albedo) const noexcept {
  // under_light's lighting, a lane's worth, with exact shadow rays where the masks leave the line open.
  const auto f = detail::sea_bed_facet<simd::scalar>(under_light, h.normal[0], h.normal[1], h.normal[2], d[0], d[1], d[2]);
  bool lit = f.facing;
  if (lit && quality.shadows) {
    // Shadows of boxes and spheres along the refracted sun up to the still sea level, and on from there
    // along the sun in air (docs/rendering.md 3.5): a jetty's shadow on the sea bed is the shadow of the
    // whole jetty, not of its submerged foot alone (which drew a thin line offset from it). Not of the
    // floor: the refracted sun is within 48 degrees of the zenith, steeper than sea beds, and a walk per
    // pixel would cost as much as the refracted ray itself. The waves' own focusing and shadowing are
    // ignored.
    const Vec3 n{f.nx, f.ny, f.nz};
    const float offset = 1e-3f + 1e-4f * h.t;
    const double reach = double(std::max(0.0f, -p[2])) / double(sun_water[2]);
    lit = !sun_water_mask.may_meet(along(p, n, offset)) ||
          !objects.occluded(make_ray(p, n, offset, sun_water), 0.0, reach, false);
    if (lit) lit = sunlit(along(p, sun_water, sun_path_in_water(p)), sun, offset);
  }
  const auto c = detail::sea_bed_light<simd::scalar>(under_light, f, {albedo.r, albedo.g, albedo.b}, lit);
  return {c.r, c.g, c.b};
}

/// Eq. 12 for `object` seen through `distance` m of water, with the object's light having come down
/// `light_path` m of water itself (docs/rendering.md 3.4's refinement, exact in the LUT because K is a
/// per-wavelength exponential): K(d + s) I_obj + (1 - K(d)) I_sea, I_sea lit by `illumination`
/// (sea_illumination, or less in an object's shadow).
LinearRgb Renderer::Impl::through_water(LinearRgb object, float distance, float light_path, float illumination) const noexcept {
  if (quality.spectral_absorption) {
    return water->mix(object, distance, light_path, illumination);
  }
  const LinearRgb sea = water->sea_colour() * illumination;
  const float k[3] = {std::exp(-rgb_absorption[0] * distance), std::exp(-rgb_absorption[1] * distance),
                      std::exp(-rgb_absorption[2] * distance)};
  const float ks[3] = {std::exp(-rgb_absorption[0] * light_path), std::exp(-rgb_absorption[1] * light_path),
                       std::exp(-rgb_absorption[2] * light_path)};
  return {object.r * k[0] * ks[0] + sea.r * (1.0f - k[0]), object.g * k[1] * ks[1] + sea.g * (1.0f - k[1]),
          object.b * k[2] * ks[2] + sea.b * (1.0f - k[2])};
}

/// Radiance arriving at p from direction d through air, which meets h (find_air_hits): the object or
/// floor lit, or the sky (sky_along_d, looked up a row at a time).
LinearRgb Renderer::Impl::from_air(const SurfaceHit& h, const Vec3& p, const Vec3& d, float travelled,
                                   LinearRgb sky_along_d) const noexcept {
  if (h.kind == HitKind::none) return sky_along_d;
  const Vec3 q = along(p, d, h.t);
  return lit_in_air(h, q, d, albedo(h, q, travelled));
}

/// Radiance arriving at p from direction d through water, which meets h (find_water_hits) of that albedo:
/// eq. 12 on the floor or an object within reach, I_sea otherwise.
LinearRgb Renderer::Impl::through_water_to(const SurfaceHit& h, LinearRgb albedo, const Vec3& p, const Vec3& d,
                                           float illumination) const noexcept {
  if (h.kind == HitKind::none) return water->sea_colour() * illumination;
  const Vec3 q = along(p, d, h.t);
  return through_water(lit_in_water(h, q, d, albedo), h.t, sun_path_in_water(q), illumination);
}

/// Whether the sun reaches the sea's surface at p past the boxes and spheres (docs/rendering.md 3.5):
/// its glint and its share of the water's light are in their shadow otherwise. The ray goes only as
/// far as the highest object. Forced inline: it is asked for nearly every sea pixel and almost always
/// answers at the mask, and out of line the call cost more than the answer.
__attribute__((always_inline)) inline bool Renderer::Impl::sunlit(const Vec3& p, const Vec3& offset_normal, float offset) const noexcept {
  if (!quality.shadows || !(sun[2] > 0.0f) || !(casters_top > p[2])) return true;
  if (!sun_mask.may_meet(along(p, offset_normal, offset))) return true;  // the line misses every caster
  const double reach = double(casters_top - p[2]) / double(sun[2]) + 1.0;
  return !objects.occluded(make_ray(p, offset_normal, offset, sun), 0.0, reach, false);
}

LinearRgb Renderer::Impl::shade_primary(const Scratch& s, std::size_t i, RenderCounters& c) const noexcept {
  const Vec3 d{s.a[Scratch::dx][i], s.a[Scratch::dy][i], s.a[Scratch::dz][i]};
  const MarchStatus status = s.status[i];
  const bool sea = status == MarchStatus::hit || status == MarchStatus::hit_from_below;
  if (view == RenderView::sea_reflectance) {
    c.sea += sea;
    const float k = sea ? s.a[Scratch::kr][i] : 0.0f;
    return {k, k, k};
  }
  if (!sea) {
    const SurfaceHit& h = s.object[i];
    if (h.kind == HitKind::none) {
      ++c.sky;
      return camera_under ? sea_lit : sky_radiance(s, i);
    }
    ++c.object;
    const Vec3 p = along(camera.position, d, h.t);
    if (!camera_under) return lit_in_air(h, p, d, albedo(s, i, h));
    return through_water(lit_in_water(h, p, d, albedo(s, i, h)), h.t, sun_path_in_water(p), sea_illumination);
  }
  // From below (a sea hit seen from above is lit by sea_light in shade_sample).
  ++c.sea;
  const float t = s.a[Scratch::t][i];
  const Vec3 p{s.a[Scratch::hx][i], s.a[Scratch::hy][i], s.a[Scratch::hz][i]};
  const float kr = s.a[Scratch::kr][i];
  // The ray that leaves into air, kept above the horizon (shade_sample).
  const Vec3 air{s.a[Scratch::ax][i], s.a[Scratch::ay][i], s.a[Scratch::az][i]};
  const SurfaceHit& under = s.under[i];
  // The interface sent r back down into the sea and tr (outside Snell's window: none) up.
  const Vec3 r{s.a[Scratch::rx][i], s.a[Scratch::ry][i], s.a[Scratch::rz][i]};
  const LinearRgb reflected = through_water_to(under, albedo(s, i, under), p, r, sea_illumination);
  const LinearRgb transmitted = kr < 1.0f ? from_air(s.air[i], p, air, t, sky_radiance(s, i)) : LinearRgb{};
  return through_water(reflected * kr + transmitted * (1.0f - kr), t, 0.0f, sea_illumination);
}

/// Where pack_rays (and primary_hits) put a row's rays for nearest_hits.
static detail::RayPackOutput packed_rays(Scratch& s) {
  float* const* a = s.a;
  return {a[Scratch::ray_ox], a[Scratch::ray_oy], a[Scratch::ray_oz], a[Scratch::ray_dx], a[Scratch::ray_dy],
          a[Scratch::ray_dz], a[Scratch::ray_reach], s.ray_pixel.data()};
}

/// The nearest hit of each of the row's `rays` packed rays within its reach, into hits[pixel] (the
/// other pixels' entries are left as they are): the floor a packet at a time (floor_hits,
/// docs/rendering.md 1.5), then the boxes and spheres before it one by one where the packets say the
/// ray may meet their bounds, walking below the bounds' boxes they name; the rays the packets leave
/// go through SceneObjects' walk.
void Renderer::Impl::nearest_hits(Scratch& s, std::size_t rays, SurfaceHit* hits) const noexcept {
  float* const* a = s.a;
  detail::floor_hits(objects.floor_grid(), objects.object_bounds(),
                     {a[Scratch::ray_ox], a[Scratch::ray_oy], a[Scratch::ray_oz], a[Scratch::ray_dx], a[Scratch::ray_dy],
                      a[Scratch::ray_dz], a[Scratch::ray_reach]},
                     rays,
                     {a[Scratch::hit_t], a[Scratch::hit_nx], a[Scratch::hit_ny], a[Scratch::hit_nz], a[Scratch::hit_left],
                      a[Scratch::hit_objects]});
  const auto ray = [a](std::size_t k) {
    return SceneRay{a[Scratch::ray_ox][k], a[Scratch::ray_oy][k], a[Scratch::ray_oz][k],
                    a[Scratch::ray_dx][k], a[Scratch::ray_dy][k], a[Scratch::ray_dz][k]};
  };
  // The arrays held here: a hit's HitKind is a byte, whose store may alias anything, so that the
  // compiler would read every pointer again per ray.
  const float *reach = a[Scratch::ray_reach], *left = a[Scratch::hit_left], *meet = a[Scratch::hit_objects],
              *t = a[Scratch::hit_t], *nx = a[Scratch::hit_nx], *ny = a[Scratch::hit_ny], *nz = a[Scratch::hit_nz];
  const std::uint32_t* pixel = s.ray_pixel.data();
  for (std::size_t k = 0; k < rays; ++k) {
    SurfaceHit& h = hits[pixel[k]];
    if (left[k] > 0.0f) {
      h = objects.intersect_secondary(ray(k), 0.0, double(reach[k]));
      continue;
    }
    if (meet[k] > 0.0f) {
      h = objects.intersect_objects(ray(k), 0.0, double(std::min(t[k], reach[k])), std::uint32_t(meet[k]));
      if (h.kind != HitKind::none) continue;
    }
    // Field by field: a whole SurfaceHit built and copied is stored in parts and read back whole,
    // which stalls the store's forwarding.
    const bool floor = t[k] < reach[k];
    h.t = floor ? t[k] : std::numeric_limits<float>::infinity();
    h.kind = floor ? HitKind::floor : HitKind::none;
    h.index = 0;
    h.normal = {floor ? nx[k] : 0.0f, floor ? ny[k] : 0.0f, floor ? nz[k] : 1.0f};
  }
}

/// For each pixel of the row, what its ray into the water meets (a sea hit's refracted ray, or its
/// reflected one from below) in s.under, and where a pixel's ray meets the floor (that one, or the
/// primary ray's; the footprint there in m) for the sand. `meets_sea`: some pixel's ray met the sea.
void Renderer::Impl::find_water_hits(Scratch& s, bool meets_sea) const noexcept {
  float* const* a = s.a;
  const auto hit_point = [&](std::size_t i) { return Vec3{a[Scratch::hx][i], a[Scratch::hy][i], a[Scratch::hz][i]}; };
  std::size_t rays = 0;
  if (meets_sea) {
    // From above the refracted ray (none under total reflection), from below the reflected one.
    rays = detail::pack_rays({a[Scratch::side], a[Scratch::kr], a[Scratch::t], a[Scratch::hx], a[Scratch::hy],
                              a[Scratch::hz], a[Scratch::nx], a[Scratch::ny], a[Scratch::nz], a[Scratch::tx],
                              a[Scratch::ty], a[Scratch::tz], a[Scratch::rx], a[Scratch::ry], a[Scratch::rz]},
                             width, {true, std::min(underwater_reach, max_distance)}, packed_rays(s));
    // s.under is read at sea hits only: those without a ray meet nothing, nearest_hits sets the others.
    for (std::size_t i = 0; i < width; ++i) {
      if (a[Scratch::side][i] > 0.0f && !(a[Scratch::kr][i] < 1.0f)) s.under[i] = SurfaceHit{};
    }
    nearest_hits(s, rays, s.under.data());
  }
  // The floor hits, for the sand: those of the rays just packed, and those of the primary rays that
  // met no sea.
  std::fill_n(a[Scratch::on_sand], width, 0.0f);
  const auto on_sand = [&](std::size_t i, const Vec3& q, float travelled) {
    a[Scratch::on_sand][i] = 1.0f;
    a[Scratch::qx][i] = q[0];
    a[Scratch::qy][i] = q[1];
    a[Scratch::qz][i] = q[2];
    a[Scratch::footprint][i] = travelled * camera.pixel_angle;
  };
  for (std::size_t k = 0; k < rays; ++k) {
    const std::size_t i = s.ray_pixel[k];
    const SurfaceHit& h = s.under[i];
    if (h.kind != HitKind::floor) continue;
    const Vec3 d{a[Scratch::ray_dx][k], a[Scratch::ray_dy][k], a[Scratch::ray_dz][k]};
    on_sand(i, along(hit_point(i), d, h.t), a[Scratch::t][i] + h.t);
  }
  for (std::size_t i = 0; i < width; ++i) {
    if (a[Scratch::side][i] != 0.0f || colour_kept(s, i)) continue;  // the flag first: no kept hit read
    const SurfaceHit& h = s.object[i];
    if (h.kind != HitKind::floor) continue;
    on_sand(i, along(camera.position, {a[Scratch::dx][i], a[Scratch::dy][i], a[Scratch::dz][i]}, h.t), h.t);
  }
}

/// For each sea hit, what its ray into the air meets (from above the reflected ray, from below the
/// refracted one, both kept above the horizon), in s.air: objects and the floor with reflect_objects,
/// nothing (the sky) without.
void Renderer::Impl::find_air_hits(Scratch& s) const noexcept {
  float* const* a = s.a;
  // s.air is read at sea hits only: those without a ray meet nothing, nearest_hits sets the others.
  std::size_t rays = 0;
  if (quality.reflect_objects) {
    // From above the reflected ray, from below the refracted one (none under total reflection).
    rays = detail::pack_rays({a[Scratch::side], a[Scratch::kr], a[Scratch::t], a[Scratch::hx], a[Scratch::hy],
                              a[Scratch::hz], a[Scratch::nx], a[Scratch::ny], a[Scratch::nz], a[Scratch::ax],
                              a[Scratch::ay], a[Scratch::az], a[Scratch::ax], a[Scratch::ay], a[Scratch::az]},
                             width, {false, max_distance}, packed_rays(s));
  }
  for (std::size_t i = 0; i < width; ++i) {
    const float side = a[Scratch::side][i];
    if (side != 0.0f && (!quality.reflect_objects || (side < 0.0f && !(a[Scratch::kr][i] < 1.0f)))) s.air[i] = SurfaceHit{};
  }
  nearest_hits(s, rays, s.air.data());
  // What they meet lit, for sea_light (the sky it looks up itself).
  std::fill_n(a[Scratch::air_hit], width, 0.0f);
  for (std::size_t k = 0; k < rays; ++k) {
    const std::size_t i = s.ray_pixel[k];
    if (!(a[Scratch::side][i] > 0.0f) || s.air[i].kind == HitKind::none) continue;
    const LinearRgb c = from_air(s.air[i], {a[Scratch::hx][i], a[Scratch::hy][i], a[Scratch::hz][i]},
                                 {a[Scratch::ax][i], a[Scratch::ay][i], a[Scratch::az][i]}, a[Scratch::t][i], LinearRgb{});
    a[Scratch::air_hit][i] = 1.0f;
    a[Scratch::reflected_r][i] = c.r;
    a[Scratch::reflected_g][i] = c.g;
    a[Scratch::reflected_b][i] = c.b;
  }
}

/// For each sea hit seen from above, whether the sun reaches it (s.lit) and the light its refracted ray
/// brings up (s.under_*: eq. 12 on what it meets, I_sea if nothing): the light and the shadow masks a
/// packet at a time (under_light), the shadow rays where a mask says a caster may be in the way, then
/// the water's absorption a packet at a time.
void Renderer::Impl::light_under_water(Scratch& s) const noexcept {
  float* const* a = s.a;
  std::size_t first = width, end = 0;  // the pixels whose refracted ray meets something
  for (std::size_t i = 0; i < width; ++i) {
    const SurfaceHit& h = s.under[i];
    const bool met = a[Scratch::side][i] > 0.0f && a[Scratch::kr][i] < 1.0f && h.kind != HitKind::none;
    a[Scratch::met][i] = met ? 1.0f : 0.0f;
    a[Scratch::seen_t][i] = met ? h.t : 0.0f;
    if (!met) continue;
    const LinearRgb c = albedo(s, i, h);
    a[Scratch::met_nx][i] = h.normal[0], a[Scratch::met_ny][i] = h.normal[1], a[Scratch::met_nz][i] = h.normal[2];
    a[Scratch::met_r][i] = c.r, a[Scratch::met_g][i] = c.g, a[Scratch::met_b][i] = c.b;
    first = std::min(first, i);
    end = i + 1;
  }
  detail::under_light(under_light,
                      {a[Scratch::side], a[Scratch::hx], a[Scratch::hy], a[Scratch::hz], a[Scratch::nx], a[Scratch::ny],
                       a[Scratch::nz], a[Scratch::t], a[Scratch::met], a[Scratch::tx], a[Scratch::ty], a[Scratch::tz],
                       a[Scratch::seen_t], a[Scratch::met_nx], a[Scratch::met_ny], a[Scratch::met_nz], a[Scratch::met_r],
                       a[Scratch::met_g], a[Scratch::met_b]},
                      width,
                      {a[Scratch::lit], a[Scratch::ask], a[Scratch::seen_r], a[Scratch::seen_g], a[Scratch::seen_b],
                       a[Scratch::seen_path]});
  for (std::size_t i = 0; i < width; ++i) {
    const float ask = a[Scratch::ask][i];
    if (ask == 0.0f) continue;
    const Vec3 p{a[Scratch::hx][i], a[Scratch::hy][i], a[Scratch::hz][i]};
    if (ask != 2.0f) {  // 1 or 3: in an object's shadow the sea loses the glint and the sun's share of its light
      const Vec3 n{a[Scratch::nx][i], a[Scratch::ny][i], a[Scratch::nz][i]};
      a[Scratch::lit][i] = sunlit(p, n, 1e-3f + 1e-4f * a[Scratch::t][i]) ? 1.0f : 0.0f;
    }
    if (ask != 1.0f) {
      const SurfaceHit& h = s.under[i];
      const Vec3 tr{a[Scratch::tx][i], a[Scratch::ty][i], a[Scratch::tz][i]};
      const LinearRgb seen = lit_in_water(h, along(p, tr, h.t), tr, albedo(s, i, h));
      a[Scratch::seen_r][i] = seen.r;
      a[Scratch::seen_g][i] = seen.g;
      a[Scratch::seen_b][i] = seen.b;
    }
  }
  for (std::size_t i = first; i < end; ++i) {
    a[Scratch::seen_illumination][i] =
        a[Scratch::met][i] > 0.0f ? (a[Scratch::lit][i] > 0.0f ? sea_illumination : sea_shade_illumination) : 0.0f;
  }
  if (quality.spectral_absorption && first < end) {
    const auto from = [&](int array) { return a[array] + first; };
    water->mix({from(Scratch::seen_r), from(Scratch::seen_g), from(Scratch::seen_b), from(Scratch::seen_t),
                from(Scratch::seen_path), from(Scratch::seen_illumination)},
               end - first, {from(Scratch::under_r), from(Scratch::under_g), from(Scratch::under_b)});
  }
  for (std::size_t i = 0; i < width; ++i) {
    if (!(a[Scratch::side][i] > 0.0f)) continue;
    LinearRgb c;
    if (a[Scratch::met][i] == 0.0f) {
      c = water->sea_colour() * (a[Scratch::lit][i] > 0.0f ? sea_illumination : sea_shade_illumination);
    } else if (!quality.spectral_absorption) {
      c = through_water({a[Scratch::seen_r][i], a[Scratch::seen_g][i], a[Scratch::seen_b][i]}, a[Scratch::seen_t][i],
                        a[Scratch::seen_path][i], a[Scratch::seen_illumination][i]);
    } else {
      continue;
    }
    a[Scratch::under_r][i] = c.r;
    a[Scratch::under_g][i] = c.g;
    a[Scratch::under_b][i] = c.b;
  }
}

void Renderer::Impl::shade_sample(Scratch& s, float* rgb, bool first) noexcept {
  const std::size_t w = width;
  float* const* a = s.a;
  // Eq. 8 normals, bent towards the viewer's side where a steep facet would face away from the ray
  // (docs/rendering.md 3.3 (a)), the exact Fresnel split, the rays into air kept above the horizon
  // (3.3 (b)) and the sky along them, the foam, for the whole row in SIMD batches; then each pixel's
  // own rays. A row that meets no sea (above the horizon) needs none of the sea's: only the sky along
  // its own rays and the sand where they meet the floor (the sea's arrays are read at sea hits only),
  // and nothing at all where the still camera's colours off the sea are kept (docs/rendering.md 2.4).
  bool meets_sea = false, all_kept = s.kept_flags != nullptr;
  for (std::size_t i = 0; i < w; ++i) {
    const MarchStatus st = s.status[i];
    const float side = st == MarchStatus::hit ? 1.0f : st == MarchStatus::hit_from_below ? -1.0f : 0.0f;
    a[Scratch::side][i] = side;
    meets_sea |= side != 0.0f;
    all_kept &= side != 0.0f || colour_kept(s, i);
  }
  if (!meets_sea && all_kept) {
    for (std::size_t i = 0; i < w; ++i) add_sample(s, rgb, i, kept_primary(s, i), first);
    return;
  }
  if (meets_sea) {
    sea_normals({a[Scratch::side], a[Scratch::gx], a[Scratch::gy], a[Scratch::dx], a[Scratch::dy], a[Scratch::dz]}, w,
                {a[Scratch::nx], a[Scratch::ny], a[Scratch::nz]});
    const ReflectRefractInput in{a[Scratch::dx], a[Scratch::dy], a[Scratch::dz], a[Scratch::nx], a[Scratch::ny], a[Scratch::nz]};
    reflect_refract(in, w, 1.0f, water_refractive_index,
                    {a[Scratch::rx], a[Scratch::ry], a[Scratch::rz], a[Scratch::tx], a[Scratch::ty], a[Scratch::tz],
                     a[Scratch::kr]});
  }
  const bool shaded = view == RenderView::shaded;
  if (shaded) {
    // Off the sea the ray into the air is the pixel's own (air_directions passes it through).
    const float *ax = a[Scratch::dx], *ay = a[Scratch::dy], *az = a[Scratch::dz];
    if (meets_sea) {
      air_directions({a[Scratch::side], a[Scratch::dx], a[Scratch::dy], a[Scratch::dz], a[Scratch::rx], a[Scratch::ry],
                      a[Scratch::rz], a[Scratch::tx], a[Scratch::ty], a[Scratch::tz]},
                     w, min_reflected_dz, {a[Scratch::ax], a[Scratch::ay], a[Scratch::az]});
      ax = a[Scratch::ax], ay = a[Scratch::ay], az = a[Scratch::az];
    }
    sky.lookup(ax, ay, az, w, a[Scratch::sky_r], a[Scratch::sky_g], a[Scratch::sky_b]);
    if (meets_sea && surf.nx != 0) {
      detail::foam_cover(surf.view(),
                         {a[Scratch::side], a[Scratch::hx], a[Scratch::hy], a[Scratch::hz], a[Scratch::gx], a[Scratch::gy],
                          a[Scratch::t]},
                         w, camera.pixel_angle, a[Scratch::foam]);
    }
    // The sand where the rays into the water (or primary rays) meet the floor is coloured a packet at a
    // time.
    find_water_hits(s, meets_sea);
    if (meets_sea) find_air_hits(s);
    detail::sand_albedo(sand, {a[Scratch::on_sand], a[Scratch::qx], a[Scratch::qy], a[Scratch::qz], a[Scratch::footprint]},
                        w, {a[Scratch::sand_r], a[Scratch::sand_g], a[Scratch::sand_b]});
    if (meets_sea) light_under_water(s);
  }
  if (shaded && meets_sea) {
    const detail::SeaLightInput light{a[Scratch::side], a[Scratch::kr], a[Scratch::sky_r], a[Scratch::sky_g],
                                      a[Scratch::sky_b], a[Scratch::air_hit], a[Scratch::reflected_r],
                                      a[Scratch::reflected_g], a[Scratch::reflected_b], a[Scratch::under_r],
                                      a[Scratch::under_g], a[Scratch::under_b], a[Scratch::lit], a[Scratch::nx],
                                      a[Scratch::ny], a[Scratch::nz], a[Scratch::dx], a[Scratch::dy], a[Scratch::dz],
                                      a[Scratch::rough], surf.nx != 0 ? a[Scratch::foam] : nullptr};
    const detail::SeaLightOutput lit{a[Scratch::light_r], a[Scratch::light_g], a[Scratch::light_b], a[Scratch::glint_lobe]};
    detail::sea_light(sea_light, light, w, lit);
    // The sun's glint, widened by the slope variance of the octaves and trains the LOD left out at
    // each pixel (docs/rendering.md 5.4, 5.5), where its lobe still may reach the camera: sea_light
    // asked first with the most the LOD can leave out, so that most pixels skip the sum over the
    // octaves too.
    for (std::size_t i = 0; i < w; ++i) {
      if (!(a[Scratch::glint_lobe][i] > 0.0f)) continue;
      const float variance = (noise != nullptr ? dropped(a[Scratch::level][i]) : 0.0f) + a[Scratch::rough][i];
      a[Scratch::glint_variance][i] = variance;
      a[Scratch::glint_lobe][i] = detail::glint_lobe_at(sea_light, light, i, variance) ? 1.0f : 0.0f;
    }
    detail::sea_glint(sea_light, light, a[Scratch::glint_variance], w, lit);
  }
  for (std::size_t i = 0; i < w; ++i) {
    LinearRgb c;
    if (shaded && a[Scratch::side][i] > 0.0f) {  // sea_light's
      ++s.counters.sea;
      c = {a[Scratch::light_r][i], a[Scratch::light_g][i], a[Scratch::light_b][i]};
    } else if (a[Scratch::side][i] == 0.0f && colour_kept(s, i)) {  // a sea hit from below keeps none
      c = kept_primary(s, i);
    } else {
      c = shade_primary(s, i, s.counters);
      if (s.kept_flags != nullptr && a[Scratch::side][i] == 0.0f) {
        float* kept = s.kept_rgb + 3 * i;
        kept[0] = c.r, kept[1] = c.g, kept[2] = c.b;
        s.kept_flags[i] |= s.object[i].kind == HitKind::none ? kept_colour | kept_sky : kept_colour;
      }
    }
    add_sample(s, rgb, i, c, first);
  }
}

/// Whether pixel i's colour off the sea is kept from an earlier frame of the still camera.
bool Renderer::Impl::colour_kept(const Scratch& s, std::size_t i) noexcept {
  return s.kept_flags != nullptr && (s.kept_flags[i] & kept_colour) != 0;
}

/// Pixel i's kept colour off the sea, counted as shade_primary counts it.
LinearRgb Renderer::Impl::kept_primary(Scratch& s, std::size_t i) noexcept {
  ++((s.kept_flags[i] & kept_sky) != 0 ? s.counters.sky : s.counters.object);
  ++s.counters.kept_colour;
  const float* kept = s.kept_rgb + 3 * i;
  return {kept[0], kept[1], kept[2]};
}

/// Adds pixel i's sample c to rgb (sets it for the first sample); a sample that is not finite adds 0,
/// and is counted.
void Renderer::Impl::add_sample(Scratch& s, float* rgb, std::size_t i, LinearRgb c, bool first) noexcept {
  if (!finite(c)) {
    ++s.counters.nonfinite;
    c = {};
  }
  float* p = rgb + 3 * i;
  p[0] = (first ? 0.0f : p[0]) + c.r;  // the first sample as a sum from 0 gives it: 0 + c, +0 for -0
  p[1] = (first ? 0.0f : p[1]) + c.g;
  p[2] = (first ? 0.0f : p[2]) + c.b;
}

/// The AOVs of one sample of a row's pixels, from what the march and shade_sample left in the scratch
/// (framebuffer.hpp says what each holds): the first sample sets them, the others add to them.
void Renderer::Impl::add_aovs(const Scratch& s, std::uint32_t row, int sample) const noexcept {
  const std::size_t w = width, o = std::size_t(row) * w;
  float* const* a = s.a;
  const float share = 1.0f / float(samples);
  const bool first = sample == 0;
  for (std::size_t i = 0; i < w; ++i) {
    const MarchStatus st = s.status[i];
    const bool sea = st == MarchStatus::hit || st == MarchStatus::hit_from_below;
    const HitKind kind = s.object[i].kind;
    const Vec3 d{a[Scratch::dx][i], a[Scratch::dy][i], a[Scratch::dz][i]};
    float t = std::numeric_limits<float>::infinity();
    Vec3 n{0.0f, 0.0f, 0.0f};
    if (sea) {
      t = a[Scratch::t][i];
      n = {a[Scratch::nx][i], a[Scratch::ny][i], a[Scratch::nz][i]};
    } else if (kind != HitKind::none) {
      t = s.object[i].t;
      n = s.object[i].normal;
    }
    if (dot(n, d) > 0.0f) n = {-n[0], -n[1], -n[2]};
    if (!out->depth.empty()) {
      const float z = sea || kind != HitKind::none ? t * dot(d, camera.forward) : t;
      out->depth[o + i] = first ? z : std::min(out->depth[o + i], z);
    }
    if (!out->normal.empty()) {
      float* p = &out->normal[3 * (o + i)];
      for (int c = 0; c < 3; ++c) p[c] = (first ? 0.0f : p[c]) + n[c] * share;
    }
    if (!out->alpha.empty()) {
      const bool covered = sea || kind != HitKind::none || camera_under;
      out->alpha[o + i] = (first ? 0.0f : out->alpha[o + i]) + (covered ? share : 0.0f);
    }
    if (!out->sea.empty()) out->sea[o + i] = (first ? 0.0f : out->sea[o + i]) + (sea ? share : 0.0f);
  }
}

/// The primary rays' object and floor hits for the row's directions, into s.object, and the marcher's
/// t_max from them (docs/rendering.md 2.4). They depend on the camera, the cut and the objects' poses
/// only: with the memo (a still camera; `memo_row`: the row's first entry; without it, the scratch's
/// own row), a ray keeps the hit found when the camera and the cut were this frame's unless it meets a
/// moving object's bounds, now or then; the others are found, a packet at a time (nearest_hits), into
/// the memo's row.
void Renderer::Impl::primary_hits(Scratch& s, std::size_t memo_row) noexcept {
  float* const* a = s.a;
  const Vec3& o = camera.position;
  const bool movers = objects.has_movers();
  const bool kept = memo_use;
  s.object = kept ? memo_hits.data() + memo_row : s.own_object.data();
  float* const kept_t_max = kept ? memo_t_max.data() + memo_row : nullptr;
  std::uint8_t* const kept_flags = kept ? memo_flags.data() + memo_row : nullptr;
  // On a refill the flags of every pixel are cleared below before the shading writes a colour.
  s.kept_rgb = keep_colours ? memo_rgb.data() + 3 * memo_row : nullptr;
  s.kept_flags = keep_colours ? kept_flags : nullptr;
  std::size_t rays = 0;
  // A still camera without movers keeps every hit: the row's t_max is the memo's.
  if (kept && !memo_refill && !movers) {
    std::copy_n(kept_t_max, width, a[Scratch::t_max]);
    s.counters.reused += width;
    return;
  }
  // A ray that goes up from above every box, sphere (wherever a moving one may be) and the floor's
  // highest sample meets nothing: a camera above the scene sends its sky pixels through no packet.
  const bool above_all = double(o[2]) > std::max(double(casters_top), objects.floor_z_max());
  // The arrays held here: a flag is a byte, whose store may alias anything (as in nearest_hits).
  const float *dx = a[Scratch::dx], *dy = a[Scratch::dy], *dz = a[Scratch::dz];
  float* const t_max = a[Scratch::t_max];
  float *ray_ox = a[Scratch::ray_ox], *ray_oy = a[Scratch::ray_oy], *ray_oz = a[Scratch::ray_oz];
  float *ray_dx = a[Scratch::ray_dx], *ray_dy = a[Scratch::ray_dy], *ray_dz = a[Scratch::ray_dz];
  float* const ray_reach = a[Scratch::ray_reach];
  std::uint32_t* const ray_pixel = s.ray_pixel.data();
  SurfaceHit* const object = s.object;
  const double drop = primary_floor_lo - double(o[2]);
  for (std::size_t i = 0; i < width; ++i) {
    const Vec3 d{dx[i], dy[i], dz[i]};
    if (above_all && d[2] > 0.0f) {
      object[i] = SurfaceHit{};
      t_max[i] = max_distance;
      if (kept) kept_t_max[i] = max_distance, kept_flags[i] = 0;
      continue;
    }
    // Past the cut a ray from above has crossed the sea: its floor and objects there are not seen.
    const float reach = d[2] < 0.0f ? std::min(max_distance, float(drop / double(d[2]))) : max_distance;
    const bool meets_movers = movers && objects.meets_movers(make_ray(o, d, 0.0f, d), double(reach));
    if (kept && !memo_refill && !meets_movers && (kept_flags[i] & kept_meets_movers) == 0) {
      t_max[i] = kept_t_max[i];
      ++s.counters.reused;
      continue;
    }
    if (kept) kept_flags[i] = meets_movers ? kept_meets_movers : 0;
    ray_ox[rays] = o[0], ray_oy[rays] = o[1], ray_oz[rays] = o[2];
    ray_dx[rays] = d[0], ray_dy[rays] = d[1], ray_dz[rays] = d[2];
    ray_reach[rays] = reach;
    ray_pixel[rays++] = std::uint32_t(i);
  }
  nearest_hits(s, rays, object);
  for (std::size_t k = 0; k < rays; ++k) {
    const std::size_t i = ray_pixel[k];
    const float t = object[i].kind != HitKind::none ? object[i].t : max_distance;
    t_max[i] = t;
    if (kept) kept_t_max[i] = t;
  }
}

void Renderer::Impl::render_row(Scratch& s, std::uint32_t row) noexcept {
  const std::size_t w = width;
  float* const* a = s.a;
  // One sample is shaded straight into the frame (shade_sample leaves no colour that is not finite);
  // more are summed in the scratch, then averaged.
  float* dst = out->rgb.data() + std::size_t(row) * w * 3;
  float* rgb = samples == 1 ? dst : s.accumulated.data();
  const MarchRays rays{a[Scratch::ox], a[Scratch::oy], a[Scratch::oz], a[Scratch::dx],
                       a[Scratch::dy], a[Scratch::dz], a[Scratch::t_max]};
  const MarchHits hits{a[Scratch::t],  a[Scratch::hx], a[Scratch::hy], a[Scratch::hz], a[Scratch::gx],
                       a[Scratch::gy], s.status.data(), a[Scratch::level], nullptr, a[Scratch::rough]};
  for (int k = 0; k < samples; ++k) {
    const auto t0 = Clock::now();
    camera_row_rays(camera, row, 0, w, offsets[k].x, offsets[k].y, a[Scratch::dx], a[Scratch::dy], a[Scratch::dz]);
    primary_hits(s, (std::size_t(row) * samples + k) * w);
    const auto t1 = Clock::now();
    march_plan.march(rays, w, hits);
    const auto t2 = Clock::now();
    shade_sample(s, rgb, k == 0);
    if (aovs) add_aovs(s, row, k);
    const auto t3 = Clock::now();
    s.intersect_ns += (t1 - t0).count();
    s.march_ns += (t2 - t1).count();
    s.shade_ns += (t3 - t2).count();
  }
  if (samples == 1) return;
  const auto t4 = Clock::now();
  const float inv = 1.0f / float(samples);
  const float* acc = s.accumulated.data();
  std::uint64_t nonfinite = 0;  // a sum of finite samples can still overflow
  for (std::size_t i = 0; i < 3 * w; ++i) {
    const float v = acc[i] * inv;
    const bool finite = std::isfinite(v);
    dst[i] = finite ? v : 0.0f;
    nonfinite += !finite;
  }
  s.counters.nonfinite += nonfinite;
  s.shade_ns += (Clock::now() - t4).count();
}

// ---- Renderer ---------------------------------------------------------------------------------

Expected<Renderer> Renderer::create(const RenderScene& scene, std::uint32_t width, std::uint32_t height,
                                    const RenderQuality& quality, unsigned threads) {
  constexpr std::uint32_t max_side = 1u << 15;
  if (width == 0 || height == 0 || width > max_side || height > max_side) {
    return Error{"size", "width and height in [1, 32768] pixels"};
  }
  auto impl = std::make_unique<Impl>();
  switch (quality.samples_per_pixel) {
    case 1:
      impl->offsets = offsets_1;
      break;
    case 4:
      impl->offsets = offsets_4;
      break;
    case 8:
      impl->offsets = offsets_8;
      break;
    default:
      return Error{"quality.samples_per_pixel", "1, 4 or 8"};
  }
  impl->samples = quality.samples_per_pixel;
  impl->quality = quality;
  impl->width = width;
  impl->height = height;
  const float md = quality.march.max_distance;
  impl->max_distance = std::isfinite(md) && md > 0.0f ? std::min(md, 1e9f) : 1e5f;
  impl->sea_height_bound = scene.sea_height_bound;

  auto objects = detail::SceneObjects::build(scene);
  if (!objects) return objects.error();
  impl->objects = std::move(objects.value());

  auto sky = PreethamSky::make(double(scene.turbidity), scene.sun_direction);
  if (!sky) return sky.error();
  impl->sky.bake(sky.value());

  WaterColourParams wp;
  wp.sea_dominant_nm = double(scene.sea_dominant_wavelength_nm);
  wp.cdom_absorption_440_per_m = double(scene.water_extra_absorption);
  auto water = WaterColourLut::make(wp);
  if (!water) {
    const std::string field = water.error().field == "sea_dominant_nm" ? "sea_dominant_wavelength_nm"
                              : water.error().field == "cdom_absorption_440_per_m" ? "water_extra_absorption"
                                                                                     : water.error().field;
    return Error{field, water.error().message};
  }
  impl->water = std::move(water.value());
  impl->rgb_absorption = impl->water->rgb_absorption_per_m();

  // Light. The relative unit is E_ref / pi (kcd/m^2) with E_ref the sun's illuminance (floored): a
  // white Lambertian surface facing the sun then has luminance E_sun / E_ref (1 for a sun above ~15 deg).
  // A sun below the horizon lights nothing directly (its disc sets over its diameter), and the sky of a
  // sun on the horizon is dimmed and turns blue with the sun's depression (docs/rendering.md 6.4).
  Impl& r = *impl;
  r.sun = sky->sun_direction();
  r.sand = scene.floor.sand;
  const SurfMap& surf = scene.surf;
  const std::size_t surf_nodes = std::size_t(surf.nx) * surf.ny;
  if ((surf.nx == 0) != (surf.ny == 0) || (surf.nx != 0 && (surf.nx < 2 || surf.ny < 2)) ||
      !(std::isfinite(surf.cell) && surf.cell > 0.0f) || surf.foam.size() != surf_nodes ||
      surf.dir_x.size() != surf_nodes || surf.dir_y.size() != surf_nodes || surf.amplitude.size() != surf_nodes ||
      !detail::surf_map_fits(surf.nx, surf.ny)) {
    return Error{"surf", "nx, ny >= 2 (or both 0), at most 2^29 nodes, a cell > 0 m and nx * ny values in each field"};
  }
  r.surf = detail::pack(surf);
  const float elevation = std::asin(std::clamp(r.sun[2], -1.0f, 1.0f));
  const LinearRgb transmittance = sun_transmittance(double(r.sun[2]), double(scene.turbidity));
  const double e_sun = solar_constant_klx * double(luminance(transmittance));
  const double e_ref = std::max(e_sun, min_reference_klx);
  const LinearRgb twilight = twilight_sky_factor(elevation);
  r.sun_rgb = transmittance * float(solar_constant_klx / e_ref * double(sun_disc_above_horizon(elevation)));
  r.sky_scale = twilight * float(std::numbers::pi / e_ref);
  r.ambient = sky_irradiance_klx(sky.value()) * twilight * float(1.0 / e_ref);
  if (r.sun[2] > 0.0f) {
    const ReflectRefract sun_in = reflect_refract({-r.sun[0], -r.sun[1], -r.sun[2]}, {0.0f, 0.0f, 1.0f});
    r.sun_water = {-sun_in.refracted[0], -sun_in.refracted[1], -sun_in.refracted[2]};
    r.sun_water_rgb = r.sun_rgb * (1.0f - sun_in.reflectance);
  }
  r.ambient_water = r.ambient * sky_water_transmission;
  r.exposure = sky_exposure(sky.value(), r.sky_scale, e_ref / std::numbers::pi);
  r.sea_illumination = luminance(r.sun_rgb) * std::max(r.sun[2], 0.0f) + luminance(r.ambient);
  r.sea_shade_illumination = luminance(r.ambient);
  r.sea_lit = r.water->sea_colour() * r.sea_illumination;
  // As high as a box or sphere can reach: a moving one (Renderer::move_box) anywhere within its motion
  // of its place, a box tilted any way (its half diagonal).
  for (const RenderBox& b : scene.boxes) {
    const auto& e = b.half_extent;
    const float reach = b.motion > 0.0f ? b.motion + std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) : e[2];
    r.casters_top = std::max(r.casters_top, b.center[2] + reach);
  }
  for (const RenderSphere& s : scene.spheres) r.casters_top = std::max(r.casters_top, s.center[2] + s.motion + s.radius);
  if (quality.shadows && r.sun[2] > 0.0f) {
    r.sun_mask = detail::ShadowMask::build(scene.boxes, scene.spheres, r.sun);
    r.sun_water_mask = detail::ShadowMask::build(scene.boxes, scene.spheres, r.sun_water);
  }
  r.under_light = {{r.ambient_water.r, r.ambient_water.g, r.ambient_water.b},
                   {r.sun_water_rgb.r, r.sun_water_rgb.g, r.sun_water_rgb.b},
                   {r.sun_water[0], r.sun_water[1], r.sun_water[2]},
                   {r.sun[0], r.sun[1], r.sun[2]},
                   r.casters_top,
                   quality.shadows,
                   r.sun_mask.view(),
                   r.sun_water_mask.view()};

  auto pool = detail::ThreadPool::create(threads);
  if (!pool) return pool.error();
  r.pool = std::move(pool.value());
  for (unsigned w = 0; w < r.pool->size(); ++w) r.scratch.push_back(std::make_unique<Scratch>(width));
  const std::size_t memo_entries = std::size_t(width) * height * std::size_t(r.samples);
  if (memo_entries <= max_kept_bytes / kept_hit_bytes) {
    r.memo_hits.resize(memo_entries);
    r.memo_t_max.resize(memo_entries);
    r.memo_flags.resize(memo_entries);
    r.memo_rgb.resize(3 * memo_entries);
  }
  return Renderer(std::move(impl));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

float Renderer::display_exposure() const noexcept { return impl_->exposure; }
const FrameTimes& Renderer::last_times() const noexcept { return impl_->times; }
const RenderCounters& Renderer::last_counters() const noexcept { return impl_->counters; }
std::uint32_t Renderer::width() const noexcept { return impl_->width; }
std::uint32_t Renderer::height() const noexcept { return impl_->height; }
unsigned Renderer::threads() const noexcept { return impl_->pool->size(); }

void Renderer::move_box(std::size_t box, const BoxPose& pose) noexcept { impl_->objects.move_box(box, pose); }
void Renderer::move_sphere(std::size_t sphere, const std::array<float, 3>& center) noexcept {
  impl_->objects.move_sphere(sphere, center);
}

void Renderer::fill_surface(SurfaceFrame& surface, SurfaceSampler sampler, void* context) noexcept {
  HOULE_ASSERT(sampler != nullptr, "Renderer::fill_surface: a sampler");
  const unsigned parts = std::min(impl_->pool->size(), SurfaceFrame::max_fill_parts);
  surface.begin_fill(sampler, context);
  impl_->pool->for_ranges(parts, 1, [&](std::size_t part, std::size_t, unsigned) noexcept {
    surface.fill_part(sampler, context, unsigned(part), parts);
  });
  // The morph and the tiles' bounds too: alone on one thread they left the other idle.
  impl_->pool->for_ranges(parts, 1, [&](std::size_t part, std::size_t, unsigned) noexcept {
    surface.morph_part(unsigned(part), parts);
  });
  impl_->pool->for_ranges(parts, 1, [&](std::size_t part, std::size_t, unsigned) noexcept {
    surface.bound_part(unsigned(part), parts);
  });
  surface.finish_frame();
}

void Renderer::render(const SurfaceFrame& surface, const CapillaryFrame* noise, const CapillaryParams* noise_params,
                      const Camera& camera, Framebuffer& out, RenderView view) noexcept {
  const auto start = Clock::now();
  Impl& r = *impl_;
  r.times = {};
  r.counters = {};
  HOULE_ASSERT(out.width == int(r.width) && out.height == int(r.height) &&
                   out.rgb.size() == std::size_t(r.width) * r.height * 3,
               "Renderer::render: a framebuffer of the renderer's width x height");
  HOULE_ASSERT(camera.width == r.width && camera.height == r.height,
               "Renderer::render: a camera of the renderer's width and height");
  const std::size_t pixels = std::size_t(r.width) * r.height;
  const bool aov_sizes = (out.depth.empty() || out.depth.size() == pixels) &&
                         (out.normal.empty() || out.normal.size() == 3 * pixels) &&
                         (out.alpha.empty() || out.alpha.size() == pixels) && (out.sea.empty() || out.sea.size() == pixels);
  HOULE_ASSERT(aov_sizes, "Renderer::render: each AOV of the framebuffer empty or of its width x height");
  // Without assertions a wrong call still writes nothing.
  if (out.width != int(r.width) || out.height != int(r.height) || out.rgb.size() != std::size_t(r.width) * r.height * 3 ||
      camera.width != r.width || camera.height != r.height || !aov_sizes) {
    return;
  }
  r.surface = &surface;
  r.noise = noise != nullptr && noise->octaves > 0 ? noise : nullptr;
  const CapillaryParams* params = r.noise == nullptr ? nullptr : noise_params != nullptr ? noise_params : &noise->params;
  r.dropped = params != nullptr ? DroppedSlopeVariance(*params) : DroppedSlopeVariance();
  // At least dropped(level) at every level: each octave leaves out at most all its variance.
  const float dropped_max = r.noise != nullptr ? float(double(r.dropped.octave_variance) * r.dropped.octaves) : 0.0f;
  r.sea_light = {{r.sky_scale.r, r.sky_scale.g, r.sky_scale.b}, {r.sun_rgb.r, r.sun_rgb.g, r.sun_rgb.b},
                 {r.ambient.r, r.ambient.g, r.ambient.b}, {r.sun[0], r.sun[1], r.sun[2]}, dropped_max};
  r.camera = camera;
  r.out = &out;
  r.view = view;
  r.aovs = !out.depth.empty() || !out.normal.empty() || !out.alpha.empty() || !out.sea.empty();
  r.march = {};
  r.march.pixel_angle = camera.pixel_angle;
  r.march.quality = r.quality.march;
  r.march.noise = r.noise;
  r.march_plan.prepare(surface, r.march);
  r.camera_under = camera.position[2] < surface.height_at(camera.position[0], camera.position[1]);
  // Below the sea's slab a primary ray from above has crossed the sea: the floor and the objects
  // matter only above it. The scene's bound of the sea's height, when this frame lies within it, gives
  // a cut that does not move with the waves, so that a still camera's primary hits hold from frame to
  // frame (primary_hits); the frame's own slab otherwise.
  const float grid_min = surface.view().global.h_min;
  const float noise_bound = r.noise != nullptr ? capillary_height_bound(r.noise->params, capillary_top_level(r.noise->params)) : 0.0f;
  const double frame_cut = double(std::min(surface.z_min(), grid_min - noise_bound)) - 0.01;
  const double scene_cut = -(double(r.sea_height_bound) + double(noise_bound)) - 0.01;
  r.primary_floor_lo = r.camera_under                                       ? -std::numeric_limits<double>::infinity()
                       : std::isfinite(scene_cut) && scene_cut <= frame_cut ? scene_cut
                                                                            : frame_cut;
  // Every field of the camera, bit for bit (no padding: sizeof is the sum of the fields).
  static_assert(sizeof(Camera) == 16 * 4);
  const bool still = std::memcmp(&r.memo_camera, &camera, sizeof(Camera)) == 0 && r.primary_floor_lo == r.memo_cut;
  r.memo_use = still && !r.memo_hits.empty();
  r.memo_refill = !(still && r.memo_valid);
  r.memo_valid = r.memo_use;
  r.memo_camera = camera;
  r.memo_cut = r.primary_floor_lo;
  r.keep_colours = r.memo_use && !r.objects.has_movers() && !r.camera_under && view == RenderView::shaded;
  for (auto& s : r.scratch) {
    s->march_ns = s->intersect_ns = s->shade_ns = 0;
    s->counters = {};
    std::fill_n(s->a[Scratch::ox], r.width, r.camera.position[0]);
    std::fill_n(s->a[Scratch::oy], r.width, r.camera.position[1]);
    std::fill_n(s->a[Scratch::oz], r.width, r.camera.position[2]);
  }
  r.pool->for_ranges(r.height, 1, [&r](std::size_t row, std::size_t, unsigned lane) noexcept {
    r.render_row(*r.scratch[lane], std::uint32_t(row));
  });

  double march_ns = 0.0, intersect_ns = 0.0, shade_ns = 0.0;
  for (const auto& s : r.scratch) {
    march_ns += double(s->march_ns);
    intersect_ns += double(s->intersect_ns);
    shade_ns += double(s->shade_ns);
    r.counters.sea += s->counters.sea;
    r.counters.object += s->counters.object;
    r.counters.sky += s->counters.sky;
    r.counters.nonfinite += s->counters.nonfinite;
    r.counters.reused += s->counters.reused;
    r.counters.kept_colour += s->counters.kept_colour;
  }
  const double n = double(r.scratch.size()) * 1e6;
  r.times.march_ms = march_ns / n;
  r.times.intersect_ms = intersect_ns / n;
  r.times.shade_ms = shade_ns / n;
  r.times.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace houle
