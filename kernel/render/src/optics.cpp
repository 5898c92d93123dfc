// Scalar and dispatched entry points of the interface optics (templates in optics_impl.hpp).
#include "houle/render/optics.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"
#include "optics_impl.hpp"

namespace houle {

float fresnel_reflectance(float cos_i, float n1, float n2) noexcept {
  return detail::fresnel_terms<simd::scalar>(cos_i, n1 / n2).reflectance;
}

namespace {
void check_fresnel(const float* cos_i, const float* reflectance, std::size_t n) noexcept {
  HOULE_ASSERT(n == 0 || (cos_i != nullptr && reflectance != nullptr), "fresnel_reflectance: n floats in cos_i and reflectance");
}
void check_reflect_refract(const ReflectRefractInput& in, std::size_t n, const ReflectRefractOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.ix != nullptr && in.iy != nullptr && in.iz != nullptr && in.nx != nullptr &&
                          in.ny != nullptr && in.nz != nullptr),
               "reflect_refract: n floats in every input array");
  HOULE_ASSERT(n == 0 || (out.rx != nullptr && out.ry != nullptr && out.rz != nullptr && out.tx != nullptr &&
                          out.ty != nullptr && out.tz != nullptr && out.reflectance != nullptr),
               "reflect_refract: n floats in every output array");
}
void check_sea_normals(const SeaNormalsInput& in, std::size_t n, const SeaNormalsOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.side != nullptr && in.gx != nullptr && in.gy != nullptr && in.dx != nullptr &&
                          in.dy != nullptr && in.dz != nullptr && out.nx != nullptr && out.ny != nullptr &&
                          out.nz != nullptr),
               "sea_normals: n floats in every array");
}
void check_air_directions(const AirDirectionsInput& in, std::size_t n, const AirDirectionsOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.side != nullptr && in.dx != nullptr && in.dy != nullptr && in.dz != nullptr &&
                          in.rx != nullptr && in.ry != nullptr && in.rz != nullptr && in.tx != nullptr &&
                          in.ty != nullptr && in.tz != nullptr && out.x != nullptr && out.y != nullptr &&
                          out.z != nullptr),
               "air_directions: n floats in every array");
}
}  // namespace

void fresnel_reflectance(const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
  check_fresnel(cos_i, reflectance, n);
  simd::active_table<detail::RenderTable>().fresnel_batch(cos_i, eta, reflectance, n);
}

void fresnel_reflectance(Isa isa, const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
  check_fresnel(cos_i, reflectance, n);
  simd::table_for<detail::RenderTable>(isa).fresnel_batch(cos_i, eta, reflectance, n);
}

ReflectRefract reflect_refract(std::array<float, 3> incident, std::array<float, 3> normal, float n_outside,
                               float n_inside) noexcept {
  const auto r = detail::interface_rays<simd::scalar>(incident[0], incident[1], incident[2], normal[0], normal[1],
                                                      normal[2], n_outside, n_inside);
  ReflectRefract out;
  out.reflected = {r.rx, r.ry, r.rz};
  out.refracted = {r.tx, r.ty, r.tz};
  out.reflectance = r.reflectance;
  out.cos_i = r.cos_i;
  out.cos_t = r.cos_t;
  out.total_internal_reflection = r.tir;
  out.from_outside = r.from_outside;
  return out;
}

void reflect_refract(const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                     ReflectRefractOutput out) noexcept {
  check_reflect_refract(in, n, out);
  simd::active_table<detail::RenderTable>().reflect_refract_batch(in, n, n_outside, n_inside, out);
}

void reflect_refract(Isa isa, const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                     ReflectRefractOutput out) noexcept {
  check_reflect_refract(in, n, out);
  simd::table_for<detail::RenderTable>(isa).reflect_refract_batch(in, n, n_outside, n_inside, out);
}

void sea_normals(const SeaNormalsInput& in, std::size_t n, SeaNormalsOutput out) noexcept {
  check_sea_normals(in, n, out);
  simd::active_table<detail::RenderTable>().sea_normals_batch(in, n, out);
}

void sea_normals(Isa isa, const SeaNormalsInput& in, std::size_t n, SeaNormalsOutput out) noexcept {
  check_sea_normals(in, n, out);
  simd::table_for<detail::RenderTable>(isa).sea_normals_batch(in, n, out);
}

void air_directions(const AirDirectionsInput& in, std::size_t n, float min_dz, AirDirectionsOutput out) noexcept {
  check_air_directions(in, n, out);
  simd::active_table<detail::RenderTable>().air_directions_batch(in, n, min_dz, out);
}

void air_directions(Isa isa, const AirDirectionsInput& in, std::size_t n, float min_dz, AirDirectionsOutput out) noexcept {
  check_air_directions(in, n, out);
  simd::table_for<detail::RenderTable>(isa).air_directions_batch(in, n, min_dz, out);
}

}  // namespace houle
