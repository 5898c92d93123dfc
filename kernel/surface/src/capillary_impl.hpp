// Capillary value noise, written once for every width (included by surface_isa.cpp).
//
// Lattice: 256 x 256 values q in [-127, 127] (value q / 127), packed so that one 32-bit word holds
// the 4 consecutive values of a row that a Catmull-Rom sample needs: a sample costs 4 lookups per
// octave instead of 16 (gathers cost ~1.4 cycles per element, docs/design.md 10; with packing they are
// ~20% of this kernel's time on Zen 3, the interpolation with its gradient is the rest). The table
// has 259 rows (row p holds lattice row p - 1 mod 256), so the 4 rows of a sample are base + 0..3
// rows without wrapping each one; the kernel reads them as two pairs of rows (p, p + 1), each one
// 64-bit element: half the gathered elements. Only +, -, * and exact conversions: every ISA gives the
// scalar bits.
#pragma once
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "houle/surface/capillary.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

inline constexpr int capillary_period = CapillaryFrame::period;
inline constexpr std::size_t capillary_lattice_words = std::size_t(capillary_period + 3) * capillary_period;
/// Row pairs (p, p + 1) for p = 0..257: the first two rows of a sample start at most at row 255.
inline constexpr std::size_t capillary_pair_words = 2 * std::size_t(capillary_period + 2) * capillary_period;
/// Word (p, c) = bytes (q[c-1], q[c], q[c+1], q[c+2]) of lattice row p - 1, columns mod 256;
/// pairs[2 (p period + c) + r] = word (p + r, c), r = 0, 1.
struct CapillaryLattice {
  std::int32_t words[capillary_lattice_words];
  std::int32_t pairs[capillary_pair_words];
  double value_variance;  ///< of q / 127 over one period: the slope statistics scale with it
};
/// Built on first use (thread-safe, in capillary.cpp: no ISA object holds a copy or a constructor).
const CapillaryLattice& capillary_lattice() noexcept;

template <class A>
struct CapillaryPoint {
  simd::vfloat<A> height, grad_x, grad_y;
};

/// Catmull-Rom weights times 2 (the 1/2 is folded into value_scale) and their derivatives at the
/// fractional position t in [0, 1], Horner form (docs/rendering.md 5.1), one lattice offset at a time.
template <class V>
struct CatmullRom2 {
  V t, t2, a;  // a = 4 - 3t is shared by two weights
  explicit CatmullRom2(V tt) : t(tt), t2(tt * tt), a(4.0f - 3.0f * tt) {}
  template <int J>
  V w() const {
    if constexpr (J == 0) return t * (t * (2.0f - t) - 1.0f);  // -t^3 + 2t^2 - t
    if constexpr (J == 1) return t2 * (3.0f * t - 5.0f) + 2.0f;  // 3t^3 - 5t^2 + 2
    if constexpr (J == 2) return t * (t * a + 1.0f);  // -3t^3 + 4t^2 + t
    if constexpr (J == 3) return t2 * (t - 1.0f);  // t^3 - t^2
  }
  template <int J>
  V d() const {
    if constexpr (J == 0) return t * a - 1.0f;  // -3t^2 + 4t - 1
    if constexpr (J == 1) return t * (9.0f * t - 10.0f);  // 9t^2 - 10t
    if constexpr (J == 2) return t * (8.0f - 9.0f * t) + 1.0f;  // -9t^2 + 8t + 1
    if constexpr (J == 3) return t * (3.0f * t - 2.0f);  // 3t^2 - 2t
  }
};

/// The x-weights (8 with the derivatives, else 4), kept in registers for the 4 rows of a sample.
template <class V, bool Grad>
struct RowWeights {
  V w0, w1, w2, w3, d0, d1, d2, d3;
  explicit RowWeights(const CatmullRom2<V>& c)
      : w0(c.template w<0>()), w1(c.template w<1>()), w2(c.template w<2>()), w3(c.template w<3>()) {
    if constexpr (Grad) {
      d0 = c.template d<0>();
      d1 = c.template d<1>();
      d2 = c.template d<2>();
      d3 = c.template d<3>();
    }
  }
};

/// One lattice row: its value and (with Grad) x-derivative interpolated at the sample (times 2 * 127).
template <bool Grad, class V, class I>
inline void capillary_row(I word, const RowWeights<V, Grad>& wx, V& r, V& dr) {
  const V q0 = simd::to_float_exact(simd::signed_byte<0>(word));
  const V q1 = simd::to_float_exact(simd::signed_byte<1>(word));
  const V q2 = simd::to_float_exact(simd::signed_byte<2>(word));
  const V q3 = simd::to_float_exact(simd::signed_byte<3>(word));
  r = (wx.w0 * q0 + wx.w1 * q1) + (wx.w2 * q2 + wx.w3 * q3);
  if constexpr (Grad) dr = (wx.d0 * q0 + wx.d1 * q1) + (wx.d2 * q2 + wx.d3 * q3);
}

/// Adds lattice row `Row` of the sample's 4 x 4 neighbourhood (its word), weighted in y, to n (and,
/// with Grad, to dn/du, dn/dv).
template <int Row, bool Grad, class V, class I>
inline void capillary_add_row(I word, const RowWeights<V, Grad>& wu, const CatmullRom2<V>& wv, V& n, V& nu, V& nv) {
  V r, dr;
  capillary_row<Grad>(word, wu, r, dr);
  const V w = wv.template w<Row>();
  if constexpr (Row == 0) {
    n = w * r;
  } else {
    n = n + w * r;
  }
  if constexpr (Grad) {
    const V d = wv.template d<Row>();
    if constexpr (Row == 0) {
      nu = w * dr;
      nv = d * r;
    } else {
      nu = nu + w * dr;
      nv = nv + d * r;
    }
  }
}

/// Height and (with Grad; otherwise gradient 0) gradient at a batch of points.
template <class A, bool Grad>
inline CapillaryPoint<A> capillary_point(const CapillaryFrame& f, const std::int32_t* pairs, simd::vfloat<A> x,
                                         simd::vfloat<A> y, simd::vfloat<A> level) {
  using V = simd::vfloat<A>;
  using I = simd::vint<A>;
  // std::min and std::max's rule: NaN goes to a defined value the same way on every ISA.
  level = simd::max_as_std(V(0.0f), level);
  const V lim(f.coord_limit);
  x = simd::min_as_std(lim, simd::max_as_std(-lim, x));
  y = simd::min_as_std(lim, simd::max_as_std(-lim, y));

  V h(0.0f), gx(0.0f), gy(0.0f);
  for (std::uint32_t i = 0; i < f.octaves; ++i) {
    const V fi(static_cast<float>(i));
    // Weights decrease with i: once no lane needs octave i, none needs the finer ones.
    if (!simd::any(level > fi)) break;
    V t = (level - fi) * f.fade_rate;
    t = simd::max_as_std(V(0.0f), simd::min_as_std(V(1.0f), t));
    // Per-lane weight 1, smoothstep(D) or 0: the result of a lane never depends on its companions.
    const V weight = t * t * (3.0f - 2.0f * t);

    const V mxu(f.mxu[i]), myu(f.myu[i]), mxv(f.mxv[i]), myv(f.myv[i]);
    const V u = (mxu * x + myu * y) + f.off_u[i];
    const V v = (mxv * x + myv * y) + f.off_v[i];
    const V cu = simd::floor_exact(u), cv = simd::floor_exact(v);
    const RowWeights<V, Grad> wu(CatmullRom2<V>(u - cu));  // fractions are exact
    const CatmullRom2<V> wv(v - cv);
    // Two's-complement & 255 is the cell modulo the period, also for negative cells.
    const I base = ((simd::to_int_exact(cv) & 255) << 8) | (simd::to_int_exact(cu) & 255);
    // Row by row, each y-weight made when needed: fewer live registers than all 16 weights at once.
    I w0, w1, w2, w3;
    simd::gather_pair(pairs, base, w0, w1);
    simd::gather_pair(pairs + 4 * capillary_period, base, w2, w3);  // rows + 2
    V n, nu, nv;
    capillary_add_row<0>(w0, wu, wv, n, nu, nv);
    capillary_add_row<1>(w1, wu, wv, n, nu, nv);
    capillary_add_row<2>(w2, wu, wv, n, nu, nv);
    capillary_add_row<3>(w3, wu, wv, n, nu, nv);

    const V aw = weight * f.value_scale[i];
    h = h + aw * n;
    if constexpr (Grad) {
      gx = gx + aw * (nu * mxu + nv * mxv);
      gy = gy + aw * (nu * myu + nv * myv);
    }
  }
  return {h, gx, gy};
}

template <class A, bool Grad>
void capillary_eval_points(const CapillaryFrame& f, const float* x, const float* y, const float* level, std::size_t n,
                           float* h, float* gx, float* gy) {
  const std::int32_t* pairs = capillary_lattice().pairs;
  // Padding lanes of the tail have level 0, so they add no octave and no cost.
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const CapillaryPoint<A> p = capillary_point<A, Grad>(f, pairs, b.load(x), b.load(y), b.load(level));
    b.store(h, p.height);
    if constexpr (Grad) {
      b.store(gx, p.grad_x);
      b.store(gy, p.grad_y);
    }
  });
}

/// Without gradient outputs (both null) the derivative work is skipped: about a third of the cost,
/// for ray-marching steps that need only heights.
template <class A>
void capillary_eval(const CapillaryFrame& f, const float* x, const float* y, const float* level, std::size_t n,
                    float* h, float* gx, float* gy) noexcept {
  if (gx == nullptr && gy == nullptr) {
    capillary_eval_points<A, false>(f, x, y, level, n, h, gx, gy);
  } else {
    capillary_eval_points<A, true>(f, x, y, level, n, h, gx, gy);
  }
}

}  // namespace houle::detail
