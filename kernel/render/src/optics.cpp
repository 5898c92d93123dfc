// Scalar and dispatched entry points of the interface optics (templates in optics_impl.hpp).
#include "houle/render/optics.hpp"

#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"
#include "optics_impl.hpp"

namespace houle {

float fresnel_reflectance(float cos_i, float n1, float n2) noexcept {
  return detail::fresnel_terms<simd::scalar>(cos_i, n1 / n2).reflectance;
}

void fresnel_reflectance(const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
  simd::active_table<detail::RenderTable>().fresnel_batch(cos_i, eta, reflectance, n);
}

void fresnel_reflectance(Isa isa, const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
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
  simd::active_table<detail::RenderTable>().reflect_refract_batch(in, n, n_outside, n_inside, out);
}

void reflect_refract(Isa isa, const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                     ReflectRefractOutput out) noexcept {
  simd::table_for<detail::RenderTable>(isa).reflect_refract_batch(in, n, n_outside, n_inside, out);
}

}  // namespace houle
