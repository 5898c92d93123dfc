// K', the diffraction coefficient, along the rays: exact at knots (the exact model from its Fresnel
// arguments, the paper's models through their formulas), interpolated in between after the sweep.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "houle/sim/diffraction.hpp"
#include "sommerfeld_tabulated.hpp"
#include "train_tracer.hpp"

namespace houle::detail {
namespace {

// K' of one of the paper's models at r/L, theta in the breakwater frame (the exact model is
// evaluated from its Fresnel arguments in the tracer: TrainTracer::k_factor).
double coefficient(DiffractionModel model, double r_over_l, double theta, double theta0, double alpha) {
  const auto d = diffraction(model, r_over_l, theta, theta0, alpha);
  return d.ok() ? d->K : 1.0;
}

// Undiffracted samples take the incident-only coefficient where v (docs/physics.md 4.4, pi/2 convention)
// is below band_end, blended to 1 from band_start.
constexpr double band_start = 4.0, band_end = 8.0;

}  // namespace

// Does an undiffracted sample at (x, y) lie in some fan's lit-side band?
bool TrainTracer::in_band(double x, double y) const noexcept {
  for (const Fan& f : fans_) {
    // |v| = v_scale sqrt((r + p.d0) / 2), d0 the unit vector towards theta0: no atan2 needed to
    // see that a point is far from the shadow line (|v| >= band_end: outside the band either side).
    const double px = x - f.site.x, py = y - f.site.y;
    const double r = dist(px, py);
    if (f.v_scale * f.v_scale * 0.5 * (r + px * f.d0x + py * f.d0y) >= band_end * band_end) continue;
    // On the lit side cos((theta - theta0) / 2) >= 0, so that |v| is v and the point is in the band.
    if (!beyond_shadow_line(f, px, py)) return true;
  }
  return false;
}

// theta > pi + theta0 (breakwater_polar's angle, without its atan2): the point (px, py) from the
// pierhead lies below the structure's line and counter-clockwise of the shadow line (direction
// pi + theta0) in the breakwater frame.
bool TrainTracer::beyond_shadow_line(const Fan& f, double px, double py) noexcept {
  const double u = px * f.frame.ux + py * f.frame.uy, v = px * f.frame.vx + py * f.frame.vy;
  return v < 0.0 && f.sin_theta0 * u - f.cos_theta0 * v > 0.0;
}

TrainTracer::HalfAngles TrainTracer::half_angles(const Fan& f, double px, double py, bool lee) noexcept {
  const double u = px * f.frame.ux + py * f.frame.uy, v = px * f.frame.vx + py * f.frame.vy;
  const double r = std::sqrt(u * u + v * v);
  double c = 0.0, s = 1.0;  // cos and sin of theta / 2
  if (v == 0.0 && u > 0.0) {
    c = lee ? -1.0 : 1.0;
    s = 0.0;
  } else if (r > 0.0) {
    if (u >= 0.0) {
      c = std::sqrt((r + u) / (2.0 * r));
      s = std::fabs(v) / std::sqrt(2.0 * r * (r + u));
    } else {
      s = std::sqrt((r - u) / (2.0 * r));
      c = std::fabs(v) / std::sqrt(2.0 * r * (r - u));
    }
    if (v < 0.0) c = -c;
  }
  return {r, c * f.cos_half_theta0 + s * f.sin_half_theta0, c * f.cos_half_theta0 - s * f.sin_half_theta0};
}

// K' at a sample of a ray of `family` (-1: undiffracted) with phase phi. The exact model goes
// straight to the Fresnel arguments (half_angles); the paper's models through their formulas.
double TrainTracer::k_factor(Lane& lane, std::int32_t family, double x, double y, double phi) {
  const bool exact = set_.diffraction_model == DiffractionModel::exact;
  if (family >= 0) {
    const Fan& f = fans_[std::size_t(family)];
    ++lane.stats.diffraction_evaluations;
    if (exact) {
      // k r with the optical distance from M (docs/physics.md 4.7): the phase gained since M.
      const double s = std::sqrt(4.0 / pi * std::max(0.0, phi - f.phi_m));
      const HalfAngles h = half_angles(f, x - f.site.x, y - f.site.y, true);
      return sommerfeld_modulus_at(s * h.minus, s * h.plus, f.site.reflection);
    }
    const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
    // Optical distance from M (docs/physics.md 4.7): the phase gained since M, in wavelengths.
    const double r_over_l = std::max(0.0, (phi - f.phi_m) / two_pi);
    // A sample exactly on the structure's line can only be on its lee face (fans start there).
    const double theta = p.kind == BreakwaterPointKind::on_structure ? two_pi : p.theta;
    return coefficient(set_.diffraction_model, r_over_l, theta, f.theta0, f.site.reflection);
  }
  double K = 1.0;
  for (const Fan& f : fans_) {
    // Undiffracted rays near a shadow line: the incident-only coefficient |G(s1)| (they carry no
    // reflected wave), blended to 1 from v = 4 to 8 so that nothing jumps at the band's edge.
    const double px = x - f.site.x, py = y - f.site.y;
    if (f.v_scale * f.v_scale * 0.5 * (dist(px, py) + px * f.d0x + py * f.d0y) >= band_end * band_end) continue;
    if (beyond_shadow_line(f, px, py)) continue;  // not this pierhead's lit side
    const HalfAngles h = half_angles(f, px, py, false);
    const double v = f.v_scale * std::sqrt(h.r) * h.minus;
    if (v >= band_end) continue;
    ++lane.stats.diffraction_evaluations;
    double kf = 0.0;
    if (exact) {
      kf = sommerfeld_modulus_at(v, 0.0, 0.0);
    } else {
      const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
      kf = coefficient(set_.diffraction_model, p.r_over_L, p.theta, f.theta0, 0.0);
    }
    const double t = std::clamp((v - band_start) / (band_end - band_start), 0.0, 1.0);
    K *= kf + (1.0 - kf) * (t * t * (3.0 - 2.0 * t));
  }
  return K;
}

// K' for one ray's samples that carry a diffraction coefficient (they hold a_geo): exact at the
// knots the sweep left (and at both ends of each run of such samples), linear in path length in
// between; then the breaking cap once more, so H <= gamma_b h holds whatever the interpolation did.
// `out` holds the samples in ray order (its amplitudes are `amplitude`); the lane's k_scratch and
// a_scratch hold the ray's staged k_exact and a_break, from `begin`.
void TrainTracer::apply_diffraction(Lane& lane, const WaveRays& out, double* amplitude, std::int32_t family,
                                    std::size_t begin, std::size_t end) {
  auto k_exact = [&](std::size_t t) -> double& { return lane.k_scratch[t - begin]; };
  std::size_t i = begin;
  while (i < end) {
    if (!(out.sample_flags[i] & sample_flag::diffraction)) {
      ++i;
      continue;
    }
    std::size_t run_end = i;
    while (run_end < end && (out.sample_flags[run_end] & sample_flag::diffraction)) ++run_end;
    for (std::size_t e : {i, run_end - 1}) {
      double& K = k_exact(e);
      if (knot_pending(K)) K = k_factor(lane, family, out.x[e], out.y[e], out.phase[e]);
    }
    std::size_t last = i;
    double path = 0.0, path_last = 0.0;
    lane.path_scratch.resize(run_end - i);  // path length from sample i
    for (std::size_t t = i + 1; t < run_end; ++t) {
      path += dist(out.x[t] - out.x[t - 1], out.y[t] - out.y[t - 1]);
      lane.path_scratch[t - i] = path;
      double& K = k_exact(t);
      if (std::isnan(K)) continue;
      if (K == pending_knot) K = k_factor(lane, family, out.x[t], out.y[t], out.phase[t]);
      // Knot t: interpolate the samples since the previous knot.
      const double k_last = k_exact(last), k_t = K;
      for (std::size_t q = last + 1; q < t; ++q) {
        const double u = path > path_last ? (lane.path_scratch[q - i] - path_last) / (path - path_last) : 1.0;
        k_exact(q) = k_last + u * (k_t - k_last);
      }
      last = t;
      path_last = path;
    }
    for (std::size_t t = i; t < run_end; ++t) {
      amplitude[t] = std::min(amplitude[t] * k_exact(t), lane.a_scratch[t - begin]);
    }
    i = run_end;
  }
}

}  // namespace houle::detail
