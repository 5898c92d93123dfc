// One wave ray's state and its integration in phase (physics.md 2.2). Internal to houle_sim.
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

namespace houle::detail {

/// The wave's local properties at a point.
struct LocalWave {
  double h = 0.0, hx = 0.0, hy = 0.0;  ///< depth and gradient (h clamped to the medium's floor)
  double k = 0.0, kh = 0.0;            ///< rad/m
  double c = 0.0, cg = 0.0;            ///< m/s
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
  double ds_max = std::numeric_limits<double>::infinity();  ///< m, longest sub-step
  double max_turn = 0.05;      ///< rad, largest turn per sub-step
};

inline LocalWave wave_from_depth(const Medium& m, double h, double kh_guess) noexcept {
  LocalWave w;
  w.h = std::max(h, m.h_eval_min);
  w.kh = solve_kh(m.k0 * w.h, kh_guess);
  w.k = w.kh / w.h;
  const double t = std::tanh(w.kh);
  w.c = gravity / m.omega * t;
  // One sinh for n and for the bending factor; beyond 2kh = 40 both have reached their limits.
  const double two_kh = 2.0 * w.kh;
  const double sh = two_kh < 40.0 ? std::sinh(two_kh) : std::numeric_limits<double>::infinity();
  w.cg = w.c * group_velocity_ratio(w.kh);
  w.bend = two_kh < 40.0 ? 2.0 / (two_kh + sh) : 0.0;
  return w;
}

inline LocalWave wave_at(const Medium& m, double x, double y, double kh_guess) noexcept {
  if (m.uniform) return m.uniform_wave;
  const DepthSample d = m.floor->sample(x, y);
  LocalWave w = wave_from_depth(m, d.depth, kh_guess);
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

/// Advances `st` by dphi > 0 (its wave at the start is `w`, updated to the end). After each sub-step,
/// `stop(from, to)` returns where along that chord (0..1) an event happens, or > 1 for none; on an
/// event the state is interpolated there, `w` re-evaluated, and advance returns true.
template <class Stop>
bool advance(const Medium& m, RayState& st, LocalWave& w, double dphi, Stop&& stop) {
  if (m.uniform) {
    // Straight line at constant k: exact.
    RayState next = st;
    next.x += std::cos(st.theta) * dphi / w.k;
    next.y += std::sin(st.theta) * dphi / w.k;
    next.phi += dphi;
    next.s += dphi / w.k;
    next.tau += dphi / (w.k * w.cg);
    const double u = stop(st, next);
    if (u <= 1.0) {
      st.x += u * (next.x - st.x);
      st.y += u * (next.y - st.y);
      st.phi += u * dphi;
      st.s += u * (next.s - st.s);
      st.tau += u * (next.tau - st.tau);
      return true;
    }
    st = next;
    return false;
  }
  RayRate r0 = ray_rate(w, st.theta);
  const double ds = dphi / w.k;
  const double turn = std::fabs(r0.theta) * dphi;
  const int n = std::clamp(int(std::max(std::ceil(ds / m.ds_max), std::ceil(turn / m.max_turn))), 1, 256);
  const double h = dphi / n;
  for (int i = 0; i < n; ++i) {
    // Classical RK4 on (x, y, theta); s and tau ride along.
    const double guess = w.kh;
    const RayRate k1 = r0;
    const LocalWave w2 = wave_at(m, st.x + 0.5 * h * k1.x, st.y + 0.5 * h * k1.y, guess);
    const RayRate k2 = ray_rate(w2, st.theta + 0.5 * h * k1.theta);
    const LocalWave w3 = wave_at(m, st.x + 0.5 * h * k2.x, st.y + 0.5 * h * k2.y, guess);
    const RayRate k3 = ray_rate(w3, st.theta + 0.5 * h * k2.theta);
    const LocalWave w4 = wave_at(m, st.x + h * k3.x, st.y + h * k3.y, guess);
    const RayRate k4 = ray_rate(w4, st.theta + h * k3.theta);
    RayState next = st;
    next.x += h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x);
    next.y += h / 6.0 * (k1.y + 2.0 * k2.y + 2.0 * k3.y + k4.y);
    next.theta += h / 6.0 * (k1.theta + 2.0 * k2.theta + 2.0 * k3.theta + k4.theta);
    next.s += h / 6.0 * (k1.s + 2.0 * k2.s + 2.0 * k3.s + k4.s);
    next.tau += h / 6.0 * (k1.tau + 2.0 * k2.tau + 2.0 * k3.tau + k4.tau);
    next.phi += h;
    const double u = stop(st, next);
    if (u <= 1.0) {
      st.x += u * (next.x - st.x);
      st.y += u * (next.y - st.y);
      st.theta += u * (next.theta - st.theta);
      st.phi += u * h;
      st.s += u * (next.s - st.s);
      st.tau += u * (next.tau - st.tau);
      w = wave_at(m, st.x, st.y, guess);
      return true;
    }
    st = next;
    w = wave_at(m, st.x, st.y, guess);
    r0 = ray_rate(w, st.theta);
  }
  return false;
}

}  // namespace houle::detail
