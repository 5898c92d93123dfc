#include "houle/surface/march.hpp"

#include <algorithm>
#include <cmath>

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"
#include "march_context.hpp"
#include "march_impl.hpp"

namespace houle {
namespace {

constexpr float slab_margin = 1e-3f;  // m

/// Cone, knobs and noise: everything but the surface.
void set_ray_params(detail::MarchContext& c, const MarchParams& p, float grid_min, float grid_max) noexcept {
  // Knobs are clamped to sane values here: the frame loop has no error path.
  const MarchQuality& q = p.quality;
  c.pixel_angle = std::isfinite(p.pixel_angle) && p.pixel_angle > 0.0f ? p.pixel_angle : 0.0f;
  c.cone_width = std::isfinite(p.cone_width) && p.cone_width > 0.0f ? p.cone_width : 0.0f;
  c.step_fraction = std::isfinite(q.step_fraction) && q.step_fraction > 1e-6f ? q.step_fraction : 1e-6f;
  c.min_step = std::isfinite(q.min_step) && q.min_step > 1e-7f ? q.min_step : 1e-7f;
  c.max_distance = std::isfinite(q.max_distance) && q.max_distance > 0.0f ? std::min(q.max_distance, 1e9f) : 1e5f;
  c.refine_iterations = std::clamp(q.refine_iterations, 0, 64);
  c.max_steps = std::max(q.max_steps, 1);

  float noise_total = 0.0f;
  if (p.noise != nullptr && p.noise->octaves > 0) {
    const CapillaryFrame& n = *p.noise;
    const CapillaryParams& np = n.params;
    c.noise = &n;
    c.noise_pairs = detail::capillary_lattice().pairs;
    c.octaves = std::min<std::uint32_t>(n.octaves, CapillaryFrame::max_octaves);
    float top = 0.0f;
    const double s = double(capillary_fade_rate(np));
    CapillaryParams first = np;
    for (std::uint32_t i = 0; i < c.octaves; ++i) {
      // Octave i's share of the published bounds (those of the first i + 1 octaves, whole, less those
      // of the first i); the 1e-4 margin covers the float differences.
      first.max_octaves = int(i);
      const float lo = capillary_height_bound(first, capillary_top_level(first));
      const float slo = capillary_slope_bound(first, capillary_top_level(first));
      first.max_octaves = int(i + 1);
      const float hi = capillary_height_bound(first, capillary_top_level(first));
      const float shi = capillary_slope_bound(first, capillary_top_level(first));
      c.octave_height[i] = (hi - lo) * (1.0f + 1e-4f);
      c.octave_slope[i] = (shi - slo) * (1.0f + 1e-4f);
      noise_total += c.octave_height[i];
      // level > i  <=>  log_k(lambda_1 sin / (N cone)) + 1/s > i  <=>  cone / sin < (lambda_1 / N) k^(1/s - i).
      c.octave_cone[i] = float(double(np.base_wavelength) / double(np.samples_per_wavelength) *
                               std::pow(double(np.lacunarity), 1.0 / s - double(i)) * (1.0 + 1e-3));
      // noise_bounds relies on it (lacunarity > 1): the octaves that count are always the first n.
      HOULE_ASSERT(i == 0 || c.octave_cone[i] < c.octave_cone[i - 1], "octave thresholds fall with the octave");
      top = std::max(top, c.octave_height[i]);
      // The order of the sums is the one the per-octave selects had: the same bits.
      c.octaves_height[i + 1] = c.octaves_height[i] + c.octave_height[i];
      c.octaves_slope[i + 1] = c.octaves_slope[i] + c.octave_slope[i];
    }
    const double log2_k = std::log2(double(np.lacunarity));
    c.max_level = capillary_top_level(np);
    c.level_offset = float(std::log2(double(np.base_wavelength) / double(np.samples_per_wavelength)) / log2_k + 1.0 / s);
    c.inv_log2_lacunarity = float(1.0 / log2_k);
    // smoothstep' <= 1.5 s on each octave fading, at most ceil(1/s) at a time; |dlevel/dt| =
    // pixel_angle / (cone ln k).
    c.level_rate = float(1.5 * s * std::ceil(1.0 / s) * double(top) / std::log(double(np.lacunarity)) * (1.0 + 1e-4));
  }
  // The slab reaches a millimetre past the surface's bounds: a ray's z at the slab's end is rounded,
  // and at exactly the bound it could end a rounding above a trough (or a flat sea, whose slab is
  // empty) and miss it.
  c.z_lo = grid_min - noise_total - slab_margin;
  c.z_hi = grid_max + noise_total + slab_margin;
}

detail::MarchContext make_context(const SurfaceFrame& frame, const MarchParams& p) noexcept {
  const SurfaceFrameView v = frame.view();
  detail::MarchContext c;
  c.height = v.height;
  c.height_pairs = v.height_pairs;
  c.grad_x = v.grad_x;
  c.grad_y = v.grad_y;
  c.slope_variance = v.slope_variance;
  c.tile_min = v.tile_min;
  c.tile_max = v.tile_max;
  c.tile_slope_x = v.tile_slope_x;
  c.tile_slope_y = v.tile_slope_y;
  c.stride = v.stride;
  c.levels = v.levels;
  c.cells = float(v.cells);
  c.stride_f = float(v.stride);
  c.tiles_per_side = float(v.tiles_per_side);
  c.inv_tile_cells = 1.0f / float(v.tile_cells);
  c.centre_x = v.centre_x;
  c.centre_y = v.centre_y;
  c.far_height = v.far_height;
  for (std::uint32_t l = 0; l < v.levels; ++l) {
    c.level_reach[l] = v.level[l].reach;
    c.level_origin_x[l] = v.level[l].origin_x;
    c.level_origin_y[l] = v.level[l].origin_y;
  }
  const SurfaceLevel& l0 = v.level[0];
  c.inv_cell0 = float(1.0 / double(l0.cell));
  c.tile_size0 = l0.cell * float(v.tile_cells);
  c.reach0 = l0.reach;
  c.level_floats = float(v.level_floats);
  c.level_tiles = float(std::size_t(v.tiles_per_side) * v.tiles_per_side);
  c.global = v.global;

  set_ray_params(c, p, c.global.h_min, c.global.h_max);
  return c;
}

const detail::SurfaceTable& table(Isa isa) noexcept { return simd::table_for<detail::SurfaceTable>(isa); }

// The knobs' documented ranges (MarchQuality); set_ray_params still clamps them in release builds.
void check_params(const MarchParams& p) noexcept {
  const MarchQuality& q = p.quality;
  HOULE_ASSERT(q.step_fraction > 0.0f && q.min_step > 0.0f, "MarchQuality: step_fraction > 0 and min_step > 0");
  HOULE_ASSERT(q.refine_iterations >= 0 && q.max_steps >= 1, "MarchQuality: refine_iterations >= 0 and max_steps >= 1");
}

void check_rays(const MarchRays& rays, std::size_t n) noexcept {
  HOULE_ASSERT(n == 0 || (rays.ox != nullptr && rays.oy != nullptr && rays.oz != nullptr && rays.dx != nullptr &&
                          rays.dy != nullptr && rays.dz != nullptr),
               "march_rays: n origins and directions");
}

void march_row(const detail::SurfaceTable& k, const SurfaceFrame& frame, const Camera& cam, const MarchParams& params,
               std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x, float sub_y, const MarchHits& hits) noexcept {
  check_params(params);
  const detail::MarchContext c = make_context(frame, params);
  constexpr std::size_t chunk = 256;  // on the stack: 7 KiB
  float ox[chunk], oy[chunk], oz[chunk], dx[chunk], dy[chunk], dz[chunk];
  std::fill(ox, ox + chunk, cam.position[0]);
  std::fill(oy, oy + chunk, cam.position[1]);
  std::fill(oz, oz + chunk, cam.position[2]);
  for (std::size_t i = 0; i < n; i += chunk) {
    const std::size_t m = std::min(chunk, n - i);
    camera_row_rays(cam, row, x0 + std::uint32_t(i), m, sub_x, sub_y, dx, dy, dz);
    const MarchRays rays{ox, oy, oz, dx, dy, dz, nullptr};
    const auto at = [i](auto* p) { return p != nullptr ? p + i : p; };
    const MarchHits h{at(hits.t),      at(hits.x),      at(hits.y),           at(hits.z),          at(hits.grad_x),
                      at(hits.grad_y), at(hits.status), at(hits.noise_level), at(hits.evaluations),
                      at(hits.slope_variance)};
    k.march_rays(c, rays, m, h);
  }
}

}  // namespace

void march_rays(const SurfaceFrame& frame, const MarchParams& params, const MarchRays& rays, std::size_t n,
                const MarchHits& hits) noexcept {
  check_params(params);
  check_rays(rays, n);
  simd::active_table<detail::SurfaceTable>().march_rays(make_context(frame, params), rays, n, hits);
}

void march_rays(Isa isa, const SurfaceFrame& frame, const MarchParams& params, const MarchRays& rays, std::size_t n,
                const MarchHits& hits) noexcept {
  check_params(params);
  check_rays(rays, n);
  table(isa).march_rays(make_context(frame, params), rays, n, hits);
}

void march_camera_row(const SurfaceFrame& frame, const Camera& camera, const MarchParams& params, std::uint32_t row,
                      std::uint32_t x0, std::size_t n, float sub_x, float sub_y, const MarchHits& hits) noexcept {
  march_row(simd::active_table<detail::SurfaceTable>(), frame, camera, params, row, x0, n, sub_x, sub_y, hits);
}

void march_camera_row(Isa isa, const SurfaceFrame& frame, const Camera& camera, const MarchParams& params,
                      std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x, float sub_y,
                      const MarchHits& hits) noexcept {
  march_row(table(isa), frame, camera, params, row, x0, n, sub_x, sub_y, hits);
}

MarchPlan::MarchPlan() : c_(std::make_unique<detail::MarchContext>()) {}
MarchPlan::~MarchPlan() = default;
MarchPlan::MarchPlan(MarchPlan&&) noexcept = default;
MarchPlan& MarchPlan::operator=(MarchPlan&&) noexcept = default;

void MarchPlan::prepare(const SurfaceFrame& frame, const MarchParams& params) noexcept {
  check_params(params);
  *c_ = make_context(frame, params);
}

void MarchPlan::march(const MarchRays& rays, std::size_t n, const MarchHits& hits) const noexcept {
  check_rays(rays, n);
  simd::active_table<detail::SurfaceTable>().march_rays(*c_, rays, n, hits);
}

MarchProbe::MarchProbe(const SurfaceFrame& frame, const MarchParams& params)
    : c_(std::make_unique<detail::MarchContext>(make_context(frame, params))) {}
MarchProbe::~MarchProbe() = default;

float MarchProbe::f(float ox, float oy, float oz, float dx, float dy, float dz, float t) const noexcept {
  using S = simd::scalar;
  bool finite = false;
  const detail::MarchRay<S> r = detail::make_march_ray<S>(*c_, ox, oy, oz, dx, dy, dz, finite);
  return detail::full_g<S>(*c_, r, t, 1.0f);
}

float MarchProbe::noise_level(float dz, float t) const noexcept {
  if (c_->noise == nullptr) return 0.0f;
  using S = simd::scalar;
  bool finite = false;
  const detail::MarchRay<S> r = detail::make_march_ray<S>(*c_, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, dz, finite);
  return detail::noise_level<S>(*c_, r.level_offset, c_->cone_width + t * c_->pixel_angle);
}

float MarchProbe::noise_height_bound(float dz, float t) const noexcept {
  using S = simd::scalar;
  bool finite = false;
  const detail::MarchRay<S> r = detail::make_march_ray<S>(*c_, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, dz, finite);
  float h = 0.0f, g = 0.0f;
  detail::noise_bounds<S>(*c_, (c_->cone_width + t * c_->pixel_angle) * r.inv_sin, h, g);
  return h;
}

float MarchProbe::noise_slope_bound(float dz, float t) const noexcept {
  using S = simd::scalar;
  bool finite = false;
  const detail::MarchRay<S> r = detail::make_march_ray<S>(*c_, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, dz, finite);
  float h = 0.0f, g = 0.0f;
  detail::noise_bounds<S>(*c_, (c_->cone_width + t * c_->pixel_angle) * r.inv_sin, h, g);
  return g;
}

float MarchProbe::grid_height(float x, float y) const noexcept {
  using S = simd::scalar;
  const detail::Located<S> s = detail::locate<S>(*c_, x, y);
  return detail::grid_field<S>(*c_, c_->height, s, c_->far_height);
}

float MarchProbe::grid_level(float x, float y) const noexcept {
  const detail::Located<simd::scalar> s = detail::locate<simd::scalar>(*c_, x, y);
  return s.far ? float(c_->levels) : s.level;
}

float MarchProbe::slab_min() const noexcept { return c_->z_lo; }
float MarchProbe::slab_max() const noexcept { return c_->z_hi; }

float SurfaceFrame::height_at(float x, float y) const noexcept {
  using S = simd::scalar;
  const detail::MarchContext c = make_context(*this, MarchParams{});
  const detail::Located<S> s = detail::locate<S>(c, x, y);
  return detail::grid_field<S>(c, c.height, s, c.far_height);
}

}  // namespace houle
