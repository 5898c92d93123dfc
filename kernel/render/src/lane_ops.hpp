// What the render room's kernels share: a colour per lane, and std::max, std::min (simd.hpp) and
// std::clamp lane by lane with the standard functions' operand order, so that a kernel's scalar
// instance is the scalar code it replaced, NaNs included.
#pragma once
#include "houle/simd/simd.hpp"

namespace houle::detail {

/// Linear sRGB, a colour per lane.
template <class A>
struct Rgb {
  simd::vfloat<A> r, g, b;
};

using simd::max_as_std;
using simd::min_as_std;

/// std::clamp(v, lo, hi) lane by lane, NaN included (it stays NaN); lo <= hi, as std::clamp requires.
template <class V>
inline V clamp_as_std(V v, V lo, V hi) {
  return max_as_std(min_as_std(v, hi), lo);
}

}  // namespace houle::detail
