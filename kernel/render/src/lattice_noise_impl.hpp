// Value noise on the unit lattice, written once for every width: it breaks the surf's foam
// (foam_impl.hpp) and the sand's grain (sand_impl.hpp) into patches. Integer hashing, floor and products
// only: the same bits on every machine and ISA.
#pragma once
#include <cstdint>
#include <type_traits>

#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

/// a * c modulo 2^32 (the scalar path multiplies unsigned: a signed product must not overflow).
template <class I>
inline I wrapping_product(I a, std::uint32_t c) {
  if constexpr (std::is_same_v<I, std::int32_t>) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * c);
  } else {
    return a * I(static_cast<std::int32_t>(c));
  }
}

/// The value at lattice point (i, j) in [-1, 1]: an integer hash, the same bits on every machine. The
/// shifts are logical: an arithmetic shift, then the sign's copies masked off.
template <class I, class V>
inline V lattice_value(I i, I j) {
  I h = wrapping_product(i, 0x8da6b343u) ^ wrapping_product(j, 0xd8163841u);
  h = wrapping_product(h ^ ((h >> 15) & I(0x1ffff)), 0x2c1b3c6du);
  h = h ^ ((h >> 12) & I(0xfffff));
  return simd::to_float_exact(h & I(0xffff)) * V(2.0f / 65535.0f) - V(1.0f);
}

/// Value noise in [-1, 1] on the unit lattice (a hash per lattice point, smoothstep between), for
/// |x|, |y| < 2^22 (further out a float keeps at most one bit of the fraction).
template <class A>
inline simd::vfloat<A> lattice_noise(simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  using I = simd::vint<A>;
  const V fx = simd::floor_exact(x), fy = simd::floor_exact(y);
  const I i = simd::to_int_exact(fx), j = simd::to_int_exact(fy);
  V u = x - fx, v = y - fy;
  u = u * u * (V(3.0f) - V(2.0f) * u);
  v = v * v * (V(3.0f) - V(2.0f) * v);
  const V v00 = lattice_value<I, V>(i, j), v10 = lattice_value<I, V>(i + I(1), j);
  const V v01 = lattice_value<I, V>(i, j + I(1)), v11 = lattice_value<I, V>(i + I(1), j + I(1));
  const V a = v00 + u * (v10 - v00);
  const V b = v01 + u * (v11 - v01);
  return a + v * (b - a);
}

}  // namespace houle::detail
