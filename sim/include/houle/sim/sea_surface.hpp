// The sea surface of a scene at any time: every train, traced or analytic, and the reflected waves of
// traced trains, summed (paper eq. 8).
//
// Once per scene each traced train's rays (wave_rays.hpp) are resampled onto a regular grid over the
// domain holding the static fields of the train: phase phi = integral of k ds, amplitude A and the
// local wave vector (k cos theta, k sin theta). Samples are splatted with a tent kernel wide enough
// to close the gaps between rays; nodes no ray reached carry no wave (the lee of a wall without
// diffraction, land). Outside the domain a train continues as straight crests with its entry
// wavenumber and amplitude (the tracer's own convention upstream of the domain).
//
// The shape along the rays is the depth-aware trochoid of houle/surface/train_grid.hpp, which also
// evaluates the summed trains per frame (SIMD; only the phase changes per frame: omega t reduced in
// double). Per node, once per scene: the fold Q = q k A coth(kh) (Airy orbits flatten into ellipses
// whose horizontal axis is A coth kh) and the lean L = Q e^{-kh} (the crest leans shoreward as the
// water shoals, Fournier & Reeves 1986; docs/physics.md 3.2 gives no constants, so none are invented
// beyond this), scaled together so that sqrt(Q^2 + L^2) <= 0.9: the profile never folds.
#pragma once
#include <cstddef>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/surface/train_grid.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {

/// One train's static fields: the arrays behind its TrainGrid (empty for analytic trains).
struct TrainField {
  double omega = 0.0;  ///< rad/s
  double phase = 0.0;  ///< rad, the train's phase offset
  std::vector<float> phi, amplitude, kx, ky, fold, lean;
  /// K' on the grid (0 where no wave arrived), or empty: 1 everywhere (no diffraction in this train).
  /// Only probe() reads it.
  std::vector<float> diffraction;
};

/// One train at a point: what `houle probe` reports.
struct TrainProbe {
  float amplitude = 0.0f;        ///< m, local A: shoaling, refraction and diffraction applied
  float relative_amplitude = 0.0f;  ///< A / A0 (A0 the deep-water amplitude): Ks Kr K'
  float diffraction = 1.0f;      ///< K', the diffraction coefficient in A (1 without diffraction)
  float wavelength = 0.0f;       ///< m, local 2 pi / k
  float direction_deg = 0.0f;    ///< direction of travel, degrees counter-clockwise from +x
  float phase = 0.0f;            ///< rad, theta = phi - (omega t - phase) reduced to [-pi, pi]
};

class SeaSurface {
 public:
  /// `cell` is the resampling grid's spacing in m (> 0).
  static Expected<SeaSurface> build(const Scene& scene, const WaveField& field, float cell = 0.5f);

  SeaSurface(SeaSurface&&) noexcept = default;
  SeaSurface& operator=(SeaSurface&&) noexcept = default;

  /// Fixes the time every later eval() uses (per-frame phases reduced modulo 2 pi in double).
  void set_time(double time_s) noexcept;
  /// Height (m, above still water) and gradient at n points; no allocation.
  void eval(const float* x, const float* y, std::size_t n, float* height, float* grad_x, float* grad_y) const noexcept;
  /// For SurfaceFrame::fill: `context` is a const SeaSurface*.
  static void sample(void* context, const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                     float* grad_y) noexcept;

  /// Field `train` of trains() (a scene train or a reflected wave) at (x, y) at the time set last.
  TrainProbe probe(std::size_t train, float x, float y) const noexcept;

  /// The scene's trains in order, then one field per reflected wave (WaveField::reflections).
  const std::vector<TrainField>& trains() const noexcept { return trains_; }
  /// Per field of trains(), the grid the kernel evaluates (far fields included).
  const std::vector<TrainGrid>& grids() const noexcept { return grids_; }
  /// Bound of |h| (the sum of the largest amplitudes): for the marcher's slab.
  float height_bound() const noexcept { return height_bound_; }

 private:
  SeaSurface() = default;
  // The grids point into trains_' arrays and frame_ into grids_: moving keeps both (vectors move
  // their buffers), copying would not.
  SeaSurface(const SeaSurface&) = delete;

  std::vector<TrainField> trains_;
  std::vector<TrainGrid> grids_;  ///< per train, pointing into trains_' arrays
  TrainGridFrame frame_{};
  std::vector<float> amplitude0_;  ///< per field of trains_, the deep-water A0 of its train
  float height_bound_ = 0.0f;
};

}  // namespace houle
