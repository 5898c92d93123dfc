// Optics of a smooth air/water interface: Fresnel reflectance and the reflected and refracted rays
// (docs/rendering.md 3.2, 3.3). The per-packet templates the shading calls live in src/optics_impl.hpp;
// these are their scalar and batch entry points.
//
// Directions are unit vectors in world space (z up) as std::array<float, 3> {x, y, z}.
#pragma once
#include <array>
#include <cstddef>

#include "houle/runtime/isa.hpp"

namespace houle {

/// Refractive index of sea water used throughout (the paper's value; fresnel_water.csv).
inline constexpr float water_refractive_index = 1.34f;

/// Unpolarised reflectance of a smooth non-absorbing dielectric interface, the paper's eq. 11, which is
/// exact: K_r = (r_s^2 + r_p^2) / 2. `cos_i` is the cosine of the incidence angle in the incident
/// medium (clamped to [0, 1]); n1 is that medium's index, n2 the other side's. Returns 1 under total
/// internal reflection ((n1/n2) sin(theta_i) >= 1). The transmitted fraction is K_t = 1 - K_r.
float fresnel_reflectance(float cos_i, float n1, float n2) noexcept;

/// Batch form: reflectance[i] = K_r(cos_i[i]) for the index ratio eta = n1/n2. Any n, no alignment.
void fresnel_reflectance(const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void fresnel_reflectance(Isa isa, const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept;

/// What a ray does at the interface.
struct ReflectRefract {
  std::array<float, 3> reflected{};  ///< unit, back into the incident medium
  std::array<float, 3> refracted{};  ///< unit, into the other medium; {0, 0, 0} under TIR
  float reflectance = 1.0f;          ///< K_r (eq. 11); K_t = 1 - K_r
  float cos_i = 0.0f;                ///< cosine of incidence, in [0, 1]
  float cos_t = 0.0f;                ///< cosine of refraction, in [0, 1]; 0 under TIR
  bool total_internal_reflection = false;
  bool from_outside = true;  ///< the ray arrived from the side the normal points to (index n_outside)
};

/// Reflection and refraction of the unit direction `incident` (travelling towards the surface) at a
/// surface with unit normal `normal`, which points into the medium of index n_outside (air above the
/// sea). A ray arriving from the other side (dot(normal, incident) > 0, e.g. looking up from under
/// water) is handled by flipping the normal and swapping the indices, so the sides are decided by the
/// normal given: with perturbed shading normals, pass one that is on the viewer's side (bend it first).
ReflectRefract reflect_refract(std::array<float, 3> incident, std::array<float, 3> normal,
                               float n_outside = 1.0f, float n_inside = water_refractive_index) noexcept;

/// Structure-of-arrays batch of reflect_refract: n rays, every array n floats, no alignment needed.
struct ReflectRefractInput {
  const float *ix, *iy, *iz;  ///< unit incident directions
  const float *nx, *ny, *nz;  ///< unit normals (pointing into the n_outside medium)
};
struct ReflectRefractOutput {
  float *rx, *ry, *rz;   ///< reflected directions
  float *tx, *ty, *tz;   ///< refracted directions, 0 under TIR
  float* reflectance;    ///< K_r
};
void reflect_refract(const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                     ReflectRefractOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void reflect_refract(Isa isa, const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                     ReflectRefractOutput out) noexcept;

/// The shading normals of a row of sea hits (docs/rendering.md 3.3 (a)): the height field's normal
/// (-gx, -gy, 1), normalised, bent where it faces away from the unit ray d until N.d = -0.01 for a hit
/// from above (side > 0; +0.01 from below, side < 0) and renormalised; (0, 0, 1) where side is 0.
struct SeaNormalsInput {
  const float* side;      ///< > 0: hit from above, < 0: from below, 0: no sea hit
  const float *gx, *gy;   ///< the surface's gradient at the hit
  const float *dx, *dy, *dz;  ///< unit ray directions
};
struct SeaNormalsOutput {
  float *nx, *ny, *nz;
};
void sea_normals(const SeaNormalsInput& in, std::size_t n, SeaNormalsOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void sea_normals(Isa isa, const SeaNormalsInput& in, std::size_t n, SeaNormalsOutput out) noexcept;

/// The direction of a row's rays in air (docs/rendering.md 3.3 (b)): from a sea hit seen from above
/// (side > 0) the reflected ray r, from below (side < 0) the refracted ray t, each lifted to a z of at
/// least min_dz and renormalised (straight down becomes straight up); elsewhere the primary ray d.
struct AirDirectionsInput {
  const float* side;  ///< as in SeaNormalsInput
  const float *dx, *dy, *dz, *rx, *ry, *rz, *tx, *ty, *tz;
};
struct AirDirectionsOutput {
  float *x, *y, *z;
};
void air_directions(const AirDirectionsInput& in, std::size_t n, float min_dz, AirDirectionsOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void air_directions(Isa isa, const AirDirectionsInput& in, std::size_t n, float min_dz, AirDirectionsOutput out) noexcept;

}  // namespace houle
