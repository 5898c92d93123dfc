// The sea surface of a scene at any time: every train, traced or analytic, summed (paper eq. 8).
//
// Once per scene each traced train becomes a grid over the domain (houle/surface/train_grid.hpp)
// holding its static field as a carrier phase, the carrier's wave vector and a complex amplitude B
// relative to the carrier (docs/physics.md 7). Everything of the train's frequency that reaches a
// node adds into B as linear waves do: its incident rays, its reflected waves' rays, and at every
// pierhead the diffracted wave (the exact semi-infinite solution minus its geometric-optics part, or
// a paper model's). Ray families are tent-splatted (each sample extrapolated to the node along its
// wave vector) and normalised per family, so that no family outvotes another; geometric-optics
// edges are cut exactly at the shadow lines where a pierhead's diffracted wave takes over. The
// carrier is the least phase offered at the node (the first wave to arrive): continuous across
// shadow lines, so the grid interpolates smoothly. Nodes no wave reached carry B = 0. Outside the
// domain a train is the wave at the nearest point of the domain's edge, carried on along its wave
// vector (train_grid.hpp; upstream this is the tracer's entry wave, docs/physics.md 2.8).
//
// The shape is the depth-aware trochoid of train_grid.hpp: per node, once per scene, the fold
// q k coth(kh) and the lean (fold e^{-kh}) per metre of amplitude (Airy orbits flatten into ellipses
// whose horizontal axis is A coth kh; the crest leans shoreward as the water shoals, Fournier &
// Reeves 1986; docs/physics.md 3.2 gives no constants, so none are invented beyond this), scaled
// down where the largest |B| around the node would let the profile fold.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "houle/render/renderer.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/surface/train_grid.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {

class Bathymetry;

/// Foam left behind the break line fades by e over this many local wavelengths travelled
/// (docs/rendering.md 3.7).
inline constexpr double foam_decay_wavelengths = 2.0;

/// One train's static fields: the arrays behind its TrainGrid (empty for analytic trains).
struct TrainField {
  double omega = 0.0;  ///< rad/s
  double phase = 0.0;  ///< rad, the train's phase offset
  std::vector<float> phi, b_re, b_im, kx, ky, fold, lean;
  /// Per node, how much the wave breaks (docs/rendering.md 3.7): 1 where its height is within 20 % of
  /// the breaking limit (gamma_b h, or the Stokes limit), rising from 0 at 55 % of it; 0 below.
  std::vector<float> breaking;
  /// K' on the grid: |B| against the incident wave without the structures (0 where no wave arrived),
  /// or empty: 1 everywhere (no pierhead diffracts this train). Only probe() reads it.
  std::vector<float> diffraction;
  /// With SeaParts::keep, per node the amplitude (m) of each part of B before the breaking cap: the
  /// incident rays, the pierheads' diffracted waves, the reflected waves. Only probe() reads them.
  /// With the parabolic model the incident part is the marched field (the incident wave refracted and
  /// diffracted) and the diffracted part that of the reflected waves at the pierheads.
  std::vector<float> incident, diffracted, reflected;
  /// Which model gave the incident field (rays for analytic trains); the parabolic model's march grid
  /// (nodes) and the shortest wavelength it resolves (m).
  WaveModelKind model = WaveModelKind::rays;
  std::uint64_t model_nodes = 0;
  double resolved_wavelength = 0.0;
};

/// Whether SeaSurface::build keeps each train's parts for probe() (memory the frames never read).
enum class SeaParts : bool { drop, keep };

/// One train at a point: what `houle probe` reports.
struct TrainProbe {
  float amplitude = 0.0f;        ///< m, local |B|: shoaling, refraction, diffraction and reflection applied
  float relative_amplitude = 0.0f;  ///< A / A0 (A0 the deep-water amplitude): Ks Kr K'
  float diffraction = 1.0f;      ///< K', the diffraction coefficient in A (1 without diffraction)
  float wavelength = 0.0f;       ///< m, local 2 pi / k
  float direction_deg = 0.0f;    ///< direction of travel, degrees counter-clockwise from +x
  float phase = 0.0f;            ///< rad, theta = phi - (omega t - phase) reduced to [-pi, pi]
  /// The amplitude (m) of each part of the field, with SeaParts::keep (else 0): incident rays,
  /// diffracted waves, reflected waves. They add as waves, not as amplitudes; breaking scales them as
  /// it scales their sum, and shoreward of the rays' end they go on with the wave.
  float incident = 0.0f, diffracted = 0.0f, reflected = 0.0f;
};

/// The diffraction SeaSurface::build did, summed over the trains: tests prove that a scene without a
/// pierhead does none; `houle info` reports it.
struct DiffractionWork {
  std::size_t pierheads = 0;      ///< pierheads whose diffracted wave was added, once per train they diffract
  std::uint64_t evaluations = 0;  ///< grid nodes x those pierheads at which the diffracted wave was computed
};

class SeaSurface {
 public:
  /// `cell` is the resampling grid's spacing in m (> 0); traced trains are resampled on up to
  /// `threads` threads (the result does not depend on it).
  static Expected<SeaSurface> build(const Scene& scene, const WaveField& field, float cell = 0.5f,
                                    SeaParts parts = SeaParts::drop, unsigned threads = 1);

  SeaSurface(SeaSurface&&) noexcept = default;
  SeaSurface& operator=(SeaSurface&&) noexcept = default;

  /// Fixes the time every later eval() uses (per-frame phases reduced modulo 2 pi in double).
  void set_time(double time_s) noexcept;
  /// Height (m, above still water) and gradient at n points; no allocation.
  void eval(const float* x, const float* y, std::size_t n, float* height, float* grad_x, float* grad_y) const noexcept;
  /// For SurfaceFrame::fill: `context` is a const SeaSurface*. Unlike eval(), each train fades out
  /// where the run's footprint cannot resolve it, its slopes going into the run's slope variance.
  /// It keeps sample_keep_floats() floats per node where the frame lets it (SurfaceFrame::keep_static).
  static void sample(void* context, const SurfaceSamples& samples) noexcept;
  std::size_t sample_keep_floats() const noexcept { return train_grid_keep_floats(frame_.count); }

  /// Train `train` of the scene at (x, y) at the time set last.
  TrainProbe probe(std::size_t train, float x, float y) const noexcept;

  /// Where the waves break, for the renderer's foam (docs/rendering.md 3.7): the traced trains'
  /// breaking measure carried shoreward with the waves and decaying behind the break line (over
  /// foam_decay_wavelengths local wavelengths), the strongest at each node with its direction and
  /// amplitude, and foam at the toes of the scene's walls where waves reach them. Empty (nx = ny = 0)
  /// when nothing breaks.
  SurfMap surf_map(const Scene& scene) const;

  /// The scene's trains in order (each with its reflected waves).
  const std::vector<TrainField>& trains() const noexcept { return trains_; }
  /// Per field of trains(), the grid the kernel evaluates (far fields included).
  const std::vector<TrainGrid>& grids() const noexcept { return grids_; }
  /// Bound of |h| (the sum of the largest amplitudes): for the marcher's slab.
  float height_bound() const noexcept { return height_bound_; }
  const DiffractionWork& diffraction_work() const noexcept { return diffraction_work_; }

 private:
  SeaSurface() = default;
  // The grids point into trains_' arrays and frame_ into grids_: moving keeps both (vectors move
  // their buffers), copying would not.
  SeaSurface(const SeaSurface&) = delete;
  /// A resampling's per-node working arrays (sea_surface.cpp), one per thread of the build.
  struct ResampleScratch;
  /// Fills train t's grid (its geometry set) from its rays and reflected waves, over the floor's
  /// depths at its nodes, adding its diffraction to `work`; returns max |B|. Touches train t and
  /// `scratch` only, and reads nothing `scratch` held before.
  float resample(std::size_t t, const Scene& scene, const Bathymetry& floor, const std::vector<float>& depths,
                 const WaveRays& rays, const std::vector<const WaveRays*>& reflected, SeaParts parts,
                 DiffractionWork& work, ResampleScratch& scratch);

  std::vector<TrainField> trains_;
  std::vector<TrainGrid> grids_;  ///< per train, pointing into trains_' arrays
  TrainGridFrame frame_{};
  std::vector<float> amplitude0_;  ///< per train, its deep-water A0
  float height_bound_ = 0.0f;
  DiffractionWork diffraction_work_{};
  SeaParts parts_ = SeaParts::drop;
};

}  // namespace houle
