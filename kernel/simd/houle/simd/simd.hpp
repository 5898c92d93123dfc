// The SIMD layer: one vocabulary for kernels written once as templates on an architecture tag.
// A kernel `template <class A> void f(...)` uses vfloat<A>, vmask<A> and the functions below;
// A = houle::simd::scalar gives plain float code (the reference), an xsimd arch gives batches.
// Internal to houle: public headers never include this file.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

// Only the per-ISA objects (HOULE_ISA_ID > 0, compiled with that ISA's flags) see xsimd: baseline
// code could not use its batches anyway (ARMv7's baseline has no SIMD at all) and compiles faster.
#if defined(HOULE_ISA_ID) && HOULE_ISA_ID != 0
#define HOULE_SIMD_BATCHES 1
#include <cassert>  // xsimd 8.1's xsimd_arch.hpp uses assert without including it
#include <xsimd/xsimd.hpp>
#else
#define HOULE_SIMD_BATCHES 0
#endif

namespace houle::simd {

/// Width-1 architecture: kernels instantiated with it are the scalar reference.
struct scalar {
  static constexpr const char* name() { return "scalar"; }
};

template <class A>
struct types;

template <>
struct types<scalar> {
  using f = float;
  using m = bool;
  static constexpr std::size_t width = 1;
};

#if HOULE_SIMD_BATCHES
template <class A>
struct types {
  using f = xsimd::batch<float, A>;
  using m = xsimd::batch_bool<float, A>;
  static constexpr std::size_t width = f::size;
};
#endif

template <class A>
using vfloat = typename types<A>::f;
template <class A>
using vmask = typename types<A>::m;
template <class A>
inline constexpr std::size_t width = types<A>::width;

// Memory. Pointers need no particular alignment.
template <class A>
inline vfloat<A> load(const float* p) {
  return vfloat<A>::load_unaligned(p);
}
template <>
inline float load<scalar>(const float* p) {
  return *p;
}
template <class A>
inline void store(float* p, vfloat<A> v) {
  v.store_unaligned(p);
}
template <>
inline void store<scalar>(float* p, float v) {
  *p = v;
}
template <class A>
inline vfloat<A> splat(float x) {
  return vfloat<A>(x);
}

// Lane-wise operations: the scalar overloads mirror xsimd's names so templates read the same.
inline float select(bool m, float a, float b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
using std::abs;
#if HOULE_SIMD_BATCHES
using xsimd::abs;
using xsimd::all;
using xsimd::any;
using xsimd::max;
using xsimd::min;
using xsimd::select;
#endif

/// std::min(a, b) and std::max(a, b) lane by lane, `b < a ? b : a` and `a < b ? b : a`: NaN and signed
/// zeros go as in the scalar code on every ISA (xsimd's min and max follow each instruction set's own
/// rule). On x86 one instruction each: minps(x, y) is `x < y ? x : y`, maxps(x, y) `x > y ? x : y`.
inline float min_as_std(float a, float b) { return b < a ? b : a; }
inline float max_as_std(float a, float b) { return a < b ? b : a; }
#if HOULE_SIMD_BATCHES
template <class A>
inline xsimd::batch<float, A> min_as_std(xsimd::batch<float, A> a, xsimd::batch<float, A> b) {
#if defined(__x86_64__) || defined(__i386__)
  return xsimd::min(b, a);
#else
  return xsimd::select(b < a, b, a);
#endif
}
template <class A>
inline xsimd::batch<float, A> max_as_std(xsimd::batch<float, A> a, xsimd::batch<float, A> b) {
#if defined(__x86_64__) || defined(__i386__)
  return xsimd::max(b, a);
#else
  return xsimd::select(a < b, b, a);
#endif
}
#endif

// Division and square root: use these, never `/` or xsimd::sqrt on batches. xsimd 8.1 computes both
// on NEON (ARMv7 and, by inheritance, AArch64) from a reciprocal estimate plus Newton steps: neither
// correctly rounded nor equal to the scalar result. AArch64 has exact vector instructions; ARMv7 has
// none, so there each lane goes through the (exact) VFP instruction. Every ISA then agrees bit for bit.
inline float div(float a, float b) { return a / b; }
inline float sqrt(float x) { return std::sqrt(x); }
#if HOULE_SIMD_BATCHES
template <class A>
inline xsimd::batch<float, A> div(xsimd::batch<float, A> a, xsimd::batch<float, A> b) {
#if defined(__aarch64__)
  if constexpr (std::is_same_v<A, xsimd::neon64>) return vdivq_f32(a, b);
#elif defined(__arm__)
  if constexpr (std::is_same_v<A, xsimd::neon>) {
    alignas(16) float x[4], y[4];
    a.store_aligned(x);
    b.store_aligned(y);
    for (int i = 0; i < 4; ++i) x[i] /= y[i];
    return xsimd::batch<float, A>::load_aligned(x);
  }
#endif
  return a / b;
}
template <class A>
inline xsimd::batch<float, A> sqrt(xsimd::batch<float, A> x) {
#if defined(__aarch64__)
  if constexpr (std::is_same_v<A, xsimd::neon64>) return vsqrtq_f32(x);
#elif defined(__arm__)
  if constexpr (std::is_same_v<A, xsimd::neon>) {
    alignas(16) float v[4];
    x.store_aligned(v);
    for (float& e : v) e = std::sqrt(e);
    return xsimd::batch<float, A>::load_aligned(v);
  }
#endif
  return xsimd::sqrt(x);
}
#endif

/// Round to nearest (ties to even) with two additions: exact for |x| < 2^22 and identical on every
/// ISA, unlike the round instructions that SSE2 and ARMv7 lack.
template <class V>
inline V round_nearest(V x) {
  constexpr float magic = 12582912.0f;  // 1.5 * 2^23
  return (x + magic) - magic;
}

/// floor(x) for every float (NaN stays NaN, ±0 and ±inf stay themselves), the same on every ISA. x86
/// (SSE4.1 and later) and AArch64 have an instruction for it. The scalar reference and ARMv7 NEON,
/// which has none, truncate to an integer and take one off where that went up, and keep x where it
/// is an integer already (|x| >= 2^23) or a zero, whose sign the truncation would lose.
inline float floor_exact(float x) {
  if (!(std::abs(x) < 8388608.0f) || x == 0.0f) return x;
  const float t = static_cast<float>(static_cast<std::int32_t>(x));
  return t - static_cast<float>(t > x);  // no branch: t > x is a coin toss for the predictor
}
#if HOULE_SIMD_BATCHES
template <class A>
inline xsimd::batch<float, A> floor_exact(xsimd::batch<float, A> x) {
#if defined(__x86_64__) || defined(__i386__)
  return xsimd::floor(x);
#elif defined(__aarch64__)
  return vrndmq_f32(x);
#else
  using V = xsimd::batch<float, A>;
  const V t = xsimd::batch_cast<float>(xsimd::batch_cast<std::int32_t>(x));
  const V f = t - xsimd::select(t > x, V(1.0f), V(0.0f));
  return xsimd::select((xsimd::abs(x) < V(8388608.0f)) & (x != V(0.0f)), f, x);
#endif
}
#endif

/// sin and cos for |r| < 0.78 (below pi/4): sincos without its range reduction, which leaves
/// such arguments as they are (n = 0), so the same bits for less than half the work.
template <class V>
inline void sincos_reduced(V r, V& s, V& c) {
  const V r2 = r * r;
  s = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
  c = (1.0f - 0.5f * r2) + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
}

/// sin and cos together. Range reduction by pi/2 in three parts (Cody-Waite; exact for |x| < ~1e5),
/// then the minimax polynomials of Cephes' sinf/cosf on [-pi/4, pi/4]. Only +, -, *: the result is
/// bit-identical for every width and ISA. Max abs error 1.2e-7 for |x| <= 1e4 (tests/kernel/test_simd).
template <class V>
inline void sincos(V x, V& s, V& c) {
  const V n = round_nearest(x * 0.636619772367581343f);
  const V r = ((x - n * 1.5703125f) - n * 4.837512969970703125e-4f) - n * 7.54978995489188216e-8f;
  V ps, pc;
  sincos_reduced(r, ps, pc);
  // Quadrant q = n mod 4, as m in {-2,-1,0,1,2}: -2 and 2 are quadrant 2, -1 is quadrant 3.
  const V m = n - 4.0f * round_nearest(n * 0.25f);
  const auto odd = (n - 2.0f * round_nearest(n * 0.5f)) != 0.0f;
  const V sin_sign = select((m < -0.5f) | (m > 1.5f), V(-1.0f), V(1.0f));
  const V cos_sign = select((m > 0.5f) | (m < -1.5f), V(-1.0f), V(1.0f));
  s = sin_sign * select(odd, pc, ps);
  c = cos_sign * select(odd, ps, pc);
}

}  // namespace houle::simd
