// The floor hits of secondary rays (floor_hits.hpp), written once for every width (included by
// render_isa.cpp). The walk is SceneObjects::hit_cell's on level 0 of its maximum mipmap, in float:
// an Amanatides-Woo step per cell for every lane together, a cell's highest corner to reject it, the
// bilinear cell's quadratic to meet it. Only +, -, *, simd::div, simd::sqrt, comparisons, exact
// conversions and gathers: every SIMD path gives the scalar path's bits (tests/kernel/test_floor_hits.cpp).
#pragma once
#include <cstddef>
#include <limits>

#include "floor_hits.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"

namespace houle::detail {

template <class A>
struct FloorHit {
  simd::vfloat<A> t, nx, ny, nz;
  simd::vmask<A> left;
};

/// One packet's floor walk in progress (floor_walk_start, floor_walk_step): its rays, the cell each
/// lane is in and the hits found so far.
template <class A>
struct FloorWalk {
  using V = simd::vfloat<A>;
  FloorHit<A> h;
  simd::vmask<A> walking;
  V ox, oy, oz, dx, dy, dz, t_max;
  // Set where a lane walks. (Not braces: a batch's braces are an initializer list.)
  V t1 = V(0.0f), fi = V(0.0f), fj = V(0.0f), si = V(0.0f), sj = V(0.0f), step_x = V(0.0f), step_y = V(0.0f),
    next_x = V(0.0f), next_y = V(0.0f), t = V(0.0f);
  int steps = 0;
};

/// Sets up the floor walk of each lane's ray (floor_hits.hpp); `valid` false lanes get no hit. The
/// walk is done when no lane is walking.
template <class A>
inline FloorWalk<A> floor_walk_start(const FloorGridView& f, simd::vmask<A> valid, simd::vfloat<A> ox, simd::vfloat<A> oy,
                                     simd::vfloat<A> oz, simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> dz,
                                     simd::vfloat<A> t_max) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f), inf(std::numeric_limits<float>::infinity());
  FloorWalk<A> w;
  w.h = {inf, zero, zero, one, M(valid & !(dz != zero))};
  w.walking = M(false);
  w.ox = ox, w.oy = oy, w.oz = oz, w.dx = dx, w.dy = dy, w.dz = dz, w.t_max = t_max;
  if (f.nx == 0) {  // no floor, nothing to meet; or one too large for the kernel, left whole
    w.h.left = f.too_large ? valid : M(false);
    return w;
  }
  // Where the ray is inside the floor's height range, before t_max.
  const M moving = valid & (dz != zero);
  const V inv_dz = simd::div(one, simd::select(moving, dz, one));
  const V t_lo = (V(f.z_lo) - oz) * inv_dz, t_hi = (V(f.z_hi) - oz) * inv_dz;
  V t0 = max_as_std(zero, simd::select(dz < zero, t_hi, t_lo));
  V t1 = min_as_std(t_max, simd::select(dz < zero, t_lo, t_hi));
  const V inv_dx = simd::div(one, simd::select(dx == zero, one, dx)), inv_dy = simd::div(one, simd::select(dy == zero, one, dy));
  // The ray meets no cell whose highest corner is below its lowest point on [t0, t1]: it walks only
  // the box of the highest band at or below that point (FloorBand). Band 0 holds every cell, so its box
  // is the whole plane and clips nothing: a packet all of whose lanes reach below band 1 (rays into
  // deep water) skips the bands.
  const V z_low = min_as_std(oz + t0 * dz, oz + t1 * dz);
  static_assert(floor_bands > 1);
  if (simd::any(z_low >= V(f.bands[1].z))) {
    V x0(-inf), x1(inf), y0(-inf), y1(inf);
    for (int k = 1; k < floor_bands; ++k) {
      const FloorBand& b = f.bands[k];
      const M in = z_low >= V(b.z);
      x0 = simd::select(in, V(b.x0), x0);
      x1 = simd::select(in, V(b.x1), x1);
      y0 = simd::select(in, V(b.y0), y0);
      y1 = simd::select(in, V(b.y1), y1);
    }
    // Along an axis the ray does not move on, all of it or none (the box's infinite sides give
    // infinite distances, never NaN, as the origin is finite where it is walked).
    const V ax = (x0 - ox) * inv_dx, bx = (x1 - ox) * inv_dx, ay = (y0 - oy) * inv_dy, by = (y1 - oy) * inv_dy;
    const V in_x = simd::select((ox >= x0) & (ox <= x1), zero - inf, inf);
    const V in_y = simd::select((oy >= y0) & (oy <= y1), zero - inf, inf);
    t0 = max_as_std(t0, max_as_std(simd::select(dx == zero, in_x, min_as_std(ax, bx)),
                                   simd::select(dy == zero, in_y, min_as_std(ay, by))));
    t1 = min_as_std(t1, min_as_std(simd::select(dx == zero, zero - in_x, max_as_std(ax, bx)),
                                   simd::select(dy == zero, zero - in_y, max_as_std(ay, by))));
  }
  const V px = ox + t0 * dx - V(f.origin_x), py = oy + t0 * dy - V(f.origin_y);
  const V cx = px * V(f.inv_cell), cy = py * V(f.inv_cell);
  // Below 2^22 cells a position keeps its fraction of a cell: a ray starting further out, or with a
  // NaN, is left to SceneObjects.
  constexpr float cell_limit = 4.0e6f;
  const V acx = simd::abs(cx), acy = simd::abs(cy);
  const M near = (acx < V(cell_limit)) & (acy < V(cell_limit)) & (oz == oz) & (dz == dz);
  w.h.left = w.h.left | (moving & !near);
  w.walking = moving & near & (t0 <= t1);
  if (!simd::any(w.walking)) return w;

  w.t1 = t1;
  w.fi = simd::floor_exact(simd::select(w.walking, cx, zero));
  w.fj = simd::floor_exact(simd::select(w.walking, cy, zero));
  w.si = simd::select(dx > zero, one, V(-1.0f));
  w.sj = simd::select(dy > zero, one, V(-1.0f));
  const V cell(f.cell);
  w.step_x = simd::select(dx == zero, inf, cell * simd::abs(inv_dx));
  w.step_y = simd::select(dy == zero, inf, cell * simd::abs(inv_dy));
  w.next_x = simd::select(dx > zero, t0 + ((w.fi + one) * cell - px) * inv_dx,
                          simd::select(dx < zero, t0 + (w.fi * cell - px) * inv_dx, inf));
  w.next_y = simd::select(dy > zero, t0 + ((w.fj + one) * cell - py) * inv_dy,
                          simd::select(dy < zero, t0 + (w.fj * cell - py) * inv_dy, inf));
  w.t = t0;
  return w;
}

/// One cell of a walking packet: each walking lane tests its cell and moves to the next. A lane
/// still walking after max_floor_steps cells is left to SceneObjects.
template <class A>
inline __attribute__((always_inline)) void floor_walk_step(const FloorGridView& f, FloorWalk<A>& w) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  using I = simd::vint<A>;
  const V zero(0.0f), one(1.0f), inf(std::numeric_limits<float>::infinity());
  const V ox = w.ox, oy = w.oy, oz = w.oz, dx = w.dx, dy = w.dy, dz = w.dz, fi = w.fi, fj = w.fj;
  const V cell(f.cell);
  const V i_hi(float(f.nx - 1)), j_hi(float(f.ny - 1));
  const V t_exit = min_as_std(min_as_std(w.next_x, w.next_y), w.t1);
  const V ta = w.t, tb = max_as_std(t_exit, w.t);
  const V za = oz + ta * dz, zb = oz + tb * dz;
  // Beyond the grid a cell has the heights of the border cell it clamps to (the view's border).
  const I ci = simd::to_int_exact(clamp_as_std(fi, V(-1.0f), i_hi) + one);
  const I cj = simd::to_int_exact(clamp_as_std(fj, V(-1.0f), j_hi) + one);
  const V top = simd::gather(f.cell_max, cj * I(f.nx + 1) + ci);
  const M candidate = w.walking & !(min_as_std(za, zb) > top);
  if (simd::any(candidate)) {
    const I k = cj * I(f.nx + 2) + ci;
    V h00, h10, h01, h11;
    simd::gather_adjacent(f.z, k, h00, h10);
    simd::gather_adjacent(f.z, k + I(f.nx + 2), h01, h11);
    // Along the ray, s = t - ta: the bilinear h = h00 + e u + f v + g u v becomes a + b s + c s^2.
    const V inv_cell(f.inv_cell);
    const V u0 = (ox + ta * dx - (V(f.origin_x) + fi * cell)) * inv_cell;
    const V v0 = (oy + ta * dy - (V(f.origin_y) + fj * cell)) * inv_cell;
    const V du = dx * inv_cell, dv = dy * inv_cell;
    const V e = h10 - h00, ef = h01 - h00, g = h00 - h10 - h01 + h11;
    const V a = h00 + e * u0 + ef * v0 + g * u0 * v0;
    const V b = e * du + ef * dv + g * (u0 * dv + v0 * du);
    const V c = g * du * dv;
    const V a0 = za - a;  // height above the ground on entering
    const V s_end = tb - ta;
    // c s^2 + qb s + qc = 0 with qb = b - dz, qc = -a0 (< 0 where it matters); the stable pair of roots.
    const V qb = b - dz, qc = zero - a0;
    const V disc = qb * qb - V(4.0f) * c * qc;
    const V root = simd::sqrt(simd::select(disc >= zero, disc, zero));
    const V qq = V(-0.5f) * (qb + simd::select(qb < zero, zero - root, root));
    const V r1 = simd::select(qq != zero, simd::div(qc, simd::select(qq != zero, qq, one)), inf);
    const V r2 = simd::select(c != zero, simd::div(qq, simd::select(c != zero, c, one)), inf);
    V s = simd::select((disc >= zero) & (r1 >= zero) & (r1 <= s_end), r1, inf);
    s = simd::select((disc >= zero) & (r2 >= zero) & (r2 <= s_end) & (r2 < s), r2, s);
    s = simd::select(a0 <= zero, zero, s);  // at or under the ground on entering
    const M hit = candidate & (s <= s_end) & (ta + s < w.t_max);
    if (simd::any(hit)) {
      const V u = clamp_as_std(u0 + du * s, zero, one), v = clamp_as_std(v0 + dv * s, zero, one);
      const V gx = (e + g * v) * inv_cell, gy = (ef + g * u) * inv_cell;
      const V inv = simd::div(one, simd::sqrt(gx * gx + gy * gy + one));
      w.h.t = simd::select(hit, ta + s, w.h.t);
      w.h.nx = simd::select(hit, zero - gx * inv, w.h.nx);
      w.h.ny = simd::select(hit, zero - gy * inv, w.h.ny);
      w.h.nz = simd::select(hit, inv, w.h.nz);
      w.walking = w.walking & !hit;
    }
  }
  w.walking = w.walking & !(t_exit >= w.t1);
  const M along_x = w.next_x <= w.next_y;
  w.fi = simd::select(along_x, fi + w.si, fi);
  w.fj = simd::select(along_x, fj, fj + w.sj);
  w.t = simd::select(along_x, w.next_x, w.next_y);
  w.next_x = simd::select(along_x, w.next_x + w.step_x, w.next_x);
  w.next_y = simd::select(along_x, w.next_y, w.next_y + w.step_y);
  if (++w.steps == max_floor_steps) {
    w.h.left = w.h.left | w.walking;  // not done within max_floor_steps cells
    w.walking = M(false);
  }
}

/// N packets walked together: a step waits mostly for its gathers, and the other packets' steps fill
/// that wait (as the marcher's packets, docs/design.md 10). Each packet takes exactly the steps it
/// takes alone: the same bits.
template <class A, std::size_t N>
inline __attribute__((always_inline)) void floor_walks(const FloorGridView& f, FloorWalk<A> (&w)[N]) {
  for (;;) {
    bool stepped = false;
    for (std::size_t k = 0; k < N; ++k) {
      if (!simd::any(w[k].walking)) continue;
      floor_walk_step<A>(f, w[k]);
      stepped = true;
    }
    if (!stepped) return;
  }
}

/// Whether each lane's ray may meet the box lo..hi with t in [0, t_end]: a slab test against the box
/// grown by `margin`. Where a ray lies in a slab's plane the NaN leaves that slab out: conservative.
/// A box inside another meets a subset of its rays: float rounding keeps the order of the planes.
template <class A>
inline simd::vmask<A> meets_box(const float (&lo)[3], const float (&hi)[3], const simd::vfloat<A> (&o)[3],
                                const simd::vfloat<A> (&inv)[3], simd::vfloat<A> margin, simd::vfloat<A> t_end) {
  using V = simd::vfloat<A>;
  V t0(0.0f), t1 = t_end;
  for (int k = 0; k < 3; ++k) {
    const V ta = (V(lo[k]) - margin - o[k]) * inv[k], tb = (V(hi[k]) + margin - o[k]) * inv[k];
    t0 = max_as_std(t0, min_as_std(ta, tb));
    t1 = min_as_std(t1, max_as_std(ta, tb));
  }
  return t0 <= t1;
}

/// Which of the boxes of b each lane's ray may meet with t in [0, t_end], as bits (box i: 2^i; exact
/// in a float, as b holds at most 16), the boxes grown by more than the tests' float rounding along
/// such a ray (1e-5 of its coordinates' and length's magnitude), so that it says no only where the
/// exact test would. The box around them all first: a lane that misses it misses them all, so the
/// result does not depend on the other lanes.
template <class A>
inline simd::vfloat<A> may_meet(const ObjectBounds& b, simd::vfloat<A> ox, simd::vfloat<A> oy, simd::vfloat<A> oz,
                                simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> dz, simd::vfloat<A> t_end) {
  using V = simd::vfloat<A>;
  static_assert(max_object_bounds <= 24, "the bits of a float's mantissa");
  const V margin = V(1e-3f) + V(1e-5f) * (simd::abs(ox) + simd::abs(oy) + simd::abs(oz) + t_end);
  const V o[3] = {ox, oy, oz};
  const V inv[3] = {simd::div(V(1.0f), dx), simd::div(V(1.0f), dy), simd::div(V(1.0f), dz)};
  V bits(0.0f);
  if (!simd::any(meets_box<A>(b.all_lo, b.all_hi, o, inv, margin, t_end))) return bits;
  for (int i = 0; i < b.count; ++i) {
    bits = bits + simd::select(meets_box<A>(b.lo[i], b.hi[i], o, inv, margin, t_end), V(float(1u << i)), V(0.0f));
  }
  return bits;
}

/// The floor walk of n rays (a ray with t_max > 0, not NaN, is valid), two packets at a time, and
/// may_meet of the object bounds up to the floor's hit.
template <class A>
void floor_hits_batch(const FloorGridView& f, const ObjectBounds& bounds, const FloorRays& in, std::size_t n,
                      FloorHits out) noexcept {
  using V = simd::vfloat<A>;
  const auto start = [&](const auto& b) HOULE_BATCH_BODY {
    const V t_max = b.load(in.t_max);
    return floor_walk_start<A>(f, t_max > V(0.0f), b.load(in.ox), b.load(in.oy), b.load(in.oz), b.load(in.dx),
                               b.load(in.dy), b.load(in.dz, -1.0f), t_max);
  };
  const auto store = [&](const auto& b, const FloorWalk<A>& w) HOULE_BATCH_BODY {
    const FloorHit<A>& h = w.h;
    const simd::vmask<A> valid = w.t_max > V(0.0f);
    V meet(0.0f);
    if (bounds.count > 0 && simd::any(valid)) {
      meet = simd::select(valid, may_meet<A>(bounds, w.ox, w.oy, w.oz, w.dx, w.dy, w.dz, min_as_std(h.t, w.t_max)), meet);
    }
    b.store(out.objects, meet);
    b.store(out.t, h.t);
    b.store(out.nx, h.nx);
    b.store(out.ny, h.ny);
    b.store(out.nz, h.nz);
    b.store(out.left, simd::select(h.left, V(1.0f), V(0.0f)));
  };
  simd::for_batch_pairs<A>(
      n,
      [&](const auto& b0, const auto& b1) HOULE_BATCH_BODY {
        FloorWalk<A> w[2] = {start(b0), start(b1)};
        floor_walks<A, 2>(f, w);
        store(b0, w[0]);
        store(b1, w[1]);
      },
      [&](const auto& b) HOULE_BATCH_BODY {
        FloorWalk<A> w[1] = {start(b)};
        floor_walks<A, 1>(f, w);
        store(b, w[0]);
      });
}

}  // namespace houle::detail
