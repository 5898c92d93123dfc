// One wave ray's state and its integration in phase (docs/physics.md 2.2). Internal to houle_sim.
//
// With the phase phi = integral of k ds as the independent variable (equal-phase stepping):
//   dx/dphi = cos(theta) / k,  dy/dphi = sin(theta) / k,
//   dtheta/dphi = (1/k) dtheta/ds = -[2 / (2kh + sinh 2kh)] (-sin(theta) h_x + cos(theta) h_y),
//   ds/dphi = 1 / k,  dtau/dphi = 1 / (k Cg).
// (1/k)(1/C) dC/dh = 2 / (2kh + sinh 2kh): k cancels, so the bending rate per radian of phase is
// finite at every depth.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"
#include "dispersion_table.hpp"

namespace houle::detail {

/// The wave's local properties at a point (what the tracer reads on every step first: one line).
struct LocalWave {
  double depth = 0.0;                  ///< m, the floor's depth there (may be <= 0: land)
  double k = 0.0;                      ///< rad/m
  double cg = 0.0;                     ///< m/s, group celerity
  double ks = 0.0;                     ///< shoaling coefficient sqrt(Cg0 / Cg)
  double h = 0.0;                      ///< depth used (clamped to the medium's floor)
  double tanh_kh = 0.0;
  double kh = 0.0;
  double c = 0.0;                      ///< m/s, phase celerity
  double hx = 0.0, hy = 0.0;           ///< the gradient of h
  double bend = 0.0;                   ///< 2 / (2kh + sinh 2kh)
};

/// What the rays propagate through: floor, frequency, and the step-size limits.
struct Medium {
  const Bathymetry* floor = nullptr;
  double omega = 0.0, k0 = 0.0;
  /// Depth used for evaluation below it (RK stages that poke past the shoreline): keeps every
  /// quantity finite; the tracer stops rays at h_min > this anyway.
  double h_eval_min = 0.0;
  bool uniform = false;        ///< flat floor: rays are straight, k constant
  LocalWave uniform_wave{};
  /// Uniform floor: the sweep's phase step and its path and travel time (dphi / k, ds / Cg), so that
  /// a full step needs no division.
  double step_dphi = 0.0, step_ds = 0.0, step_dtau = 0.0;
  double ds_max = std::numeric_limits<double>::infinity();  ///< m, longest sub-step
  double max_turn = 0.05;      ///< rad, largest turn per sub-step
};

inline LocalWave wave_from_depth(const Medium& m, double depth) noexcept {
  LocalWave w;
  w.depth = depth;
  w.h = std::max(depth, m.h_eval_min);
  w.kh = kh_from_table(m.k0 * w.h);
  w.k = w.kh / w.h;
  // tanh kh and sinh 2kh from one expm1 (e = e^{-2kh} - 1), without cancellation at small kh.
  const double two_kh = 2.0 * w.kh;
  const double e = std::expm1(-two_kh);
  w.tanh_kh = -e / (2.0 + e);
  double n = 0.5;
  if (two_kh < 2e-4) {
    n = 1.0 - w.kh * w.kh / 3.0;
    w.bend = 1.0 / (two_kh * (1.0 + two_kh * two_kh / 12.0));  // 2 / (2x + sinh 2x) to O(x^2)
  } else if (two_kh < 40.0) {
    const double sinh_2kh = -e * (2.0 + e) / (2.0 * (1.0 + e));
    n = 0.5 * (1.0 + two_kh / sinh_2kh);
    w.bend = 2.0 / (two_kh + sinh_2kh);
  }
  w.c = gravity / m.omega * w.tanh_kh;
  w.cg = n * w.c;
  w.ks = 1.0 / std::sqrt(2.0 * n * w.tanh_kh);
  return w;
}

inline LocalWave wave_at(const Medium& m, double x, double y) noexcept {
  if (m.uniform) return m.uniform_wave;
  const DepthSample d = m.floor->sample(x, y);
  LocalWave w = wave_from_depth(m, d.depth);
  w.hx = d.depth > m.h_eval_min ? d.grad_x : 0.0;
  w.hy = d.depth > m.h_eval_min ? d.grad_y : 0.0;
  return w;
}

struct RayState {
  double x = 0.0, y = 0.0;  ///< m
  double theta = 0.0;       ///< rad
  double phi = 0.0;         ///< rad
  double s = 0.0;           ///< m of path
  double tau = 0.0;         ///< s of travel
};

struct RayRate {
  double x, y, theta, s, tau;  ///< d/dphi
};

inline RayRate ray_rate(const LocalWave& w, double theta) noexcept {
  const double c = std::cos(theta), s = std::sin(theta);
  const double inv_k = 1.0 / w.k;
  return {c * inv_k, s * inv_k, -w.bend * (-s * w.hx + c * w.hy), inv_k, inv_k / w.cg};
}

inline RayState lerp(const RayState& a, const RayState& b, double u) noexcept {
  return {a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.theta + u * (b.theta - a.theta),
          a.phi + u * (b.phi - a.phi), a.s + u * (b.s - a.s), a.tau + u * (b.tau - a.tau)};
}

/// Advances `st` by dphi > 0 on a varying floor (its wave at the start is `w`, updated to the end): see
/// advance(). Kept out of line so that the straight path stays small.
template <class Stop>
[[gnu::noinline]] bool advance_curved(const Medium& m, RayState& st, LocalWave& w, double dphi, Stop& stop) {
  RayRate r0 = ray_rate(w, st.theta);
  const double ds = dphi / w.k;
  const double turn = std::fabs(r0.theta) * dphi;
  const int n = std::clamp(int(std::max(std::ceil(ds / m.ds_max), std::ceil(turn / m.max_turn))), 1, 256);
  const double h = dphi / n;
  for (int i = 0; i < n; ++i) {
    // Classical RK4 on (x, y, theta); s and tau ride along.
    const RayRate& k1 = r0;
    const LocalWave w2 = wave_at(m, st.x + 0.5 * h * k1.x, st.y + 0.5 * h * k1.y);
    const RayRate k2 = ray_rate(w2, st.theta + 0.5 * h * k1.theta);
    const LocalWave w3 = wave_at(m, st.x + 0.5 * h * k2.x, st.y + 0.5 * h * k2.y);
    const RayRate k3 = ray_rate(w3, st.theta + 0.5 * h * k2.theta);
    const LocalWave w4 = wave_at(m, st.x + h * k3.x, st.y + h * k3.y);
    const RayRate k4 = ray_rate(w4, st.theta + h * k3.theta);
    RayState next = st;
    next.x += h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x);
    next.y += h / 6.0 * (k1.y + 2.0 * k2.y + 2.0 * k3.y + k4.y);
    next.theta += h / 6.0 * (k1.theta + 2.0 * k2.theta + 2.0 * k3.theta + k4.theta);
    next.s += h / 6.0 * (k1.s + 2.0 * k2.s + 2.0 * k3.s + k4.s);
    next.tau += h / 6.0 * (k1.tau + 2.0 * k2.tau + 2.0 * k3.tau + k4.tau);
    next.phi += h;
    const LocalWave w_next = wave_at(m, next.x, next.y);
    const double u = stop(st, next, w_next.depth);
    if (u <= 1.0) {
      st = lerp(st, next, u);
      w = wave_at(m, st.x, st.y);
      return true;
    }
    st = next;
    w = w_next;
    r0 = ray_rate(w, st.theta);
  }
  return false;
}

/// Advances `st` by dphi > 0 (its wave at the start is `w`, updated to the end). After each sub-step,
/// `stop(from, to, depth_at_to)` returns where along that chord (0..1) an event happens, or > 1 for
/// none; on an event the state is interpolated there, `w` re-evaluated, and advance returns true.
/// `cos_t`, `sin_t` are cos and sin of st.theta (the caller keeps them: on a uniform floor theta
/// never changes, and this saves a sincos per step).
template <class Stop>
bool advance(const Medium& m, RayState& st, LocalWave& w, double dphi, double cos_t, double sin_t, Stop&& stop) {
  if (!m.uniform) return advance_curved(m, st, w, dphi, stop);
  // Straight line at constant k: exact. The end is copied field by field from scalars: copying the
  // struct `next` (built on the stack for `stop`) made GCC reload it in 16-byte halves that straddle
  // its 8-byte stores, a failed store forward on every step (a tenth of a Fig. 4 trace).
  const bool full = dphi == m.step_dphi;  // w is m.uniform_wave
  const double ds = full ? m.step_ds : dphi / w.k;
  const double x = st.x + cos_t * ds, y = st.y + sin_t * ds, phi = st.phi + dphi, s = st.s + ds;
  const double tau = st.tau + (full ? m.step_dtau : ds / w.cg);
  const RayState next{x, y, st.theta, phi, s, tau};
  const double u = stop(st, next, w.depth);
  if (u <= 1.0) {
    st = lerp(st, next, u);
    return true;
  }
  st.x = x;
  st.y = y;
  st.phi = phi;
  st.s = s;
  st.tau = tau;
  return false;
}

}  // namespace houle::detail
