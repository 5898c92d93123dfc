// The loop every batch kernel shares: elements [0, n) in whole batches, read and written in place,
// then the tail through the same full-width code on a padded copy, so that every lane is computed
// alike (a lane never depends on its companions, and the scalar path gives the same bits). The body
// is written once, as a generic lambda taking the batch it works on:
//
//   simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY { b.store(out, f<A>(b.load(in))); });
//
// It is instantiated twice, for whole batches and for the tail (A = scalar: whole batches only).
// Internal to houle: public headers never include this file.
#pragma once
#include <algorithm>
#include <cstddef>
#include <iterator>

#include "houle/simd/simd.hpp"

/// After a loop body's parameter list: the body is inlined into the loop as if written there. Without
/// it gcc 12 keeps large bodies (the marcher's, reflect_refract's) out of line and calls them per batch.
#define HOULE_BATCH_BODY __attribute__((always_inline))

namespace houle::simd {

/// 0, 1, 2, ... : a batch's lane numbers (Batch::indices).
alignas(64) inline constexpr float lane_numbers[16] = {0.0f, 1.0f, 2.0f,  3.0f,  4.0f,  5.0f,  6.0f,  7.0f,
                                                       8.0f, 9.0f, 10.0f, 11.0f, 12.0f, 13.0f, 14.0f, 15.0f};

/// One batch of a loop over n elements: elements index() to index() + lanes() - 1. Tail is true for
/// the last, partial batch: its loads go through a copy padded with `pad`, its stores through a copy
/// of which only lanes() are written out.
template <class A, bool Tail>
class Batch {
 public:
  static constexpr std::size_t W = width<A>;

  Batch(std::size_t index, std::size_t lanes) : index_(index), lanes_(lanes) {}
  std::size_t index() const { return index_; }
  std::size_t lanes() const { return Tail ? lanes_ : W; }
  /// The lanes' element indices, index() onwards, as floats (exact below 2^24).
  vfloat<A> indices() const {
    static_assert(W <= std::size(lane_numbers));
    return vfloat<A>(float(index_)) + simd::load<A>(lane_numbers);
  }

  /// p[index()] onwards; padding lanes (in the tail) get `pad`, which should be a harmless input.
  vfloat<A> load(const float* p, float pad = 0.0f) const {
    if constexpr (Tail) {
      alignas(64) float t[W];
      std::fill(t, t + W, pad);
      std::copy(p + index_, p + index_ + lanes_, t);
      return simd::load<A>(t);
    } else {
      return simd::load<A>(p + index_);
    }
  }
  void store(float* p, vfloat<A> v) const {
    if constexpr (Tail) {
      alignas(64) float t[W];
      simd::store<A>(t, v);
      std::copy(t, t + lanes_, p + index_);
    } else {
      simd::store<A>(p + index_, v);
    }
  }
  /// p[index() + l] = convert(lane l), for outputs that are not float.
  template <class T, class Convert>
  void store(T* p, vfloat<A> v, Convert convert) const {
    alignas(64) float t[W];
    simd::store<A>(t, v);
    for (std::size_t l = 0; l < lanes(); ++l) p[index_ + l] = convert(t[l]);
  }

 private:
  std::size_t index_, lanes_;
};

/// body(b) for each batch b of [0, n) (see above). Inlined too, like the loops it replaces.
template <class A, class Body>
inline __attribute__((always_inline)) void for_batches(std::size_t n, Body&& body) {
  constexpr std::size_t W = width<A>;
  std::size_t i = 0;
  for (; i + W <= n; i += W) body(Batch<A, false>(i, W));
  if constexpr (W > 1) {
    if (i < n) body(Batch<A, true>(i, n - i));
  }
}

/// pair(b0, b1) for pairs of whole batches of [0, n), then one(b) for each batch left (a whole one,
/// the tail, or both): for kernels whose batches wait on memory, two independent batches in flight.
template <class A, class Pair, class One>
inline __attribute__((always_inline)) void for_batch_pairs(std::size_t n, Pair&& pair, One&& one) {
  constexpr std::size_t W = width<A>;
  std::size_t i = 0;
  for (; i + 2 * W <= n; i += 2 * W) pair(Batch<A, false>(i, W), Batch<A, false>(i + W, W));
  if (i + W <= n) {
    one(Batch<A, false>(i, W));
    i += W;
  }
  if constexpr (W > 1) {
    if (i < n) one(Batch<A, true>(i, n - i));
  }
}

}  // namespace houle::simd
