// Checks shared by the hard-case sweeps and the random-scene properties: a surface or frame is
// finite, bounded and continuous, with the worst values kept so the tests can print them.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "houle/render/framebuffer.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle::test {

struct SurfaceSweep {
  bool finite = true;
  float worst_height_ratio = 0.0f;  ///< max |h| / height_bound
  float max_slope = 0.0f;           ///< max |grad h|
  /// Continuity: max |h(p + d) - h(p)| over the probes at step d and at d / 4. A continuous surface
  /// has jump_fine ~ jump_coarse / 4; a seam or fold keeps jump_fine ~ jump_coarse.
  float jump_coarse = 0.0f, jump_fine = 0.0f;
  float worst_x = 0.0f, worst_y = 0.0f;  ///< m, where jump_fine was found
  int skipped = 0;                       ///< probes left out of the jumps (covered_only)
};

/// Is (x, y) in a grid cell whose four nodes all carry a wave, for every traced train? Where rays
/// end (lee of a wall, the edge of their coverage, a cap) the phase of the uncovered node is the far
/// field's, many radians from the rays', and the surface oscillates within that one cell.
inline bool in_covered_cell(const SeaSurface& s, float x, float y) {
  for (const TrainGrid& g : s.grids()) {
    if (g.nx == 0) continue;
    const float gx = (x - g.origin_x) / g.cell, gy = (y - g.origin_y) / g.cell;
    if (!(gx >= 0.0f && gy >= 0.0f && gx < float(g.nx - 1) && gy < float(g.ny - 1))) return false;
    const std::size_t n = std::size_t(gy) * g.nx + std::size_t(gx);
    const auto wave = [&](std::size_t m) { return g.b_re[m] != 0.0f || g.b_im[m] != 0.0f; };
    if (!(wave(n) && wave(n + 1) && wave(n + g.nx) && wave(n + g.nx + 1))) return false;
  }
  return true;
}

/// The surface at the time set last, on a grid of n x n probes over the rectangle, each paired with
/// a point `step` (m) away along a fixed oblique direction. With `covered_only`, the continuity
/// jumps count only probe triples inside covered cells (in_covered_cell).
inline SurfaceSweep sweep_surface(const SeaSurface& s, double x0, double y0, double x1, double y1, float step, int n = 48,
                                  bool covered_only = false) {
  SurfaceSweep r;
  const float bound = std::max(s.height_bound(), 1e-12f);
  const float ex = 0.8f, ey = 0.6f;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Irrational-ish offsets so probes do not line up with grid nodes.
      const float x = float(x0 + (x1 - x0) * (i + 0.37) / n), y = float(y0 + (y1 - y0) * (j + 0.61) / n);
      const float xs[3] = {x, x + step * ex, x + 0.25f * step * ex}, ys[3] = {y, y + step * ey, y + 0.25f * step * ey};
      float h[3], gx[3], gy[3];
      s.eval(xs, ys, 3, h, gx, gy);
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(h[k]) || !std::isfinite(gx[k]) || !std::isfinite(gy[k])) r.finite = false;
        r.worst_height_ratio = std::max(r.worst_height_ratio, std::fabs(h[k]) / bound);
        r.max_slope = std::max(r.max_slope, std::hypot(gx[k], gy[k]));
      }
      if (covered_only && !(in_covered_cell(s, xs[0], ys[0]) && in_covered_cell(s, xs[1], ys[1]))) {
        ++r.skipped;
        continue;
      }
      r.jump_coarse = std::max(r.jump_coarse, std::fabs(h[1] - h[0]));
      if (std::fabs(h[2] - h[0]) > r.jump_fine) {
        r.jump_fine = std::fabs(h[2] - h[0]);
        r.worst_x = x, r.worst_y = y;
      }
    }
  }
  return r;
}

struct FrameStats {
  bool finite = true;
  float min = INFINITY, max = -INFINITY, mean = 0.0f;
};

inline FrameStats frame_stats(const Framebuffer& fb) {
  FrameStats r;
  double sum = 0.0;
  for (float v : fb.rgb) {
    if (!std::isfinite(v)) {
      r.finite = false;
      continue;
    }
    r.min = std::min(r.min, v);
    r.max = std::max(r.max, v);
    sum += v;
  }
  r.mean = float(sum / double(fb.rgb.size()));
  return r;
}

/// Worst ratios of the traced amplitudes to their physical limits: breaking, H = 2A <= gamma_b h, and
/// energy, A <= A0 Ks(kh) Kr_max (refraction capped at caustics; the rays carry no diffraction).
struct AmplitudeWorst {
  bool finite = true;
  double breaking = 0.0;     ///< max 2A / (gamma_b h)
  double energy = 0.0;       ///< max A / (A0 Ks Kr_max) over all samples
  double caustic = 0.0;      ///< the same over samples behind a crossing only
  std::size_t samples = 0, crossed = 0;
};

inline AmplitudeWorst amplitude_worst(const Scene& scene, const WaveField& field) {
  AmplitudeWorst w;
  const Bathymetry floor(scene.floor);
  for (std::size_t t = 0; t < field.trains.size(); ++t) {
    const WaveRays& r = field.trains[t];
    for (std::size_t i = 0; i < r.sample_count(); ++i) {
      const double a = r.amplitude[i], k = r.k[i];
      if (!std::isfinite(a) || !std::isfinite(k) || !std::isfinite(r.x[i]) || !std::isfinite(r.y[i]) ||
          !std::isfinite(r.phase[i]) || !std::isfinite(r.theta[i])) {
        w.finite = false;
        continue;
      }
      const double h = floor.depth(r.x[i], r.y[i]);
      if (h > 0.0) w.breaking = std::max(w.breaking, 2.0 * a / (scene.dwt.breaker_index * h));
      const double cap = r.amplitude0 * shoaling_coefficient(k * std::max(h, r.min_depth)) *
                         scene.dwt.max_refraction_coefficient;
      const double ratio = a / cap;
      w.energy = std::max(w.energy, ratio);
      if (r.sample_flags[i] & sample_flag::crossed) {
        w.caustic = std::max(w.caustic, ratio);
        ++w.crossed;
      }
      ++w.samples;
    }
  }
  return w;
}

}  // namespace houle::test
