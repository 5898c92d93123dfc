// What the render room's kernels share: a colour per lane, and std::max, std::min and std::clamp lane
// by lane with the standard functions' operand order, so that a kernel's scalar instance is the scalar
// code it replaced, NaNs included (xsimd's min and max follow the instructions, which return the second
// operand when either is NaN).
#pragma once
#include "houle/simd/simd.hpp"

namespace houle::detail {

/// Linear sRGB, a colour per lane.
template <class A>
struct Rgb {
  simd::vfloat<A> r, g, b;
};

/// std::max(a, b) and std::min(a, b) lane by lane, NaNs included.
template <class V>
inline V max_as_std(V a, V b) {
  return simd::select(a < b, b, a);
}
template <class V>
inline V min_as_std(V a, V b) {
  return simd::select(b < a, b, a);
}

/// std::clamp(v, lo, hi) lane by lane, NaN included (it stays NaN).
template <class V>
inline V clamp_as_std(V v, V lo, V hi) {
  return simd::select(v < lo, lo, simd::select(hi < v, hi, v));
}

}  // namespace houle::detail
