// Wave trains whose slowly varying fields are given on regular grids (rays traced over a sea floor
// and resampled once per scene, houle/sim/sea_surface.hpp), evaluated as one height field per frame.
//
// Per train, at each grid node: a carrier phase phi (rad, continuous: the phase of the first wave to
// arrive), its wave vector (kx, ky) (rad/m), the complex amplitude B = b_re + i b_im (m) of everything
// of the train's frequency that reaches the node, relative to the carrier (docs/physics.md 7: the
// incident wave, the reflected waves and each pierhead's diffracted wave, summed as linear waves of one
// frequency sum), and the fold f and lean l per metre of amplitude (1/m). With the fields
// interpolated bilinearly at a point, tau = omega t - phase the train's time phase, theta = phi - tau and
//   w = B e^{i theta}   (the linear wave: its imaginary part is the height of a sine profile),
//   delta = f Re w + l Im w,   h = Im w cos delta - Re w sin delta.
// For one wave (B = A real) this is h = A sin(theta - Q cos theta - L sin theta) with Q = f A and
// L = l A: the trochoid whose particles sit at x = u + (Q cos theta + L sin theta) / k, inverted to
// first order (Q the orbit's horizontal excursion times k, q k A coth kh; L shears the crest forward,
// Fournier & Reeves' lean). dx/du >= 1 - sqrt(Q^2 + L^2), so sqrt(f^2 + l^2) |B| < 1 keeps the profile
// from folding: the sea surface bounds f and l by the largest |B| around each node. The gradient is
// the exact derivative of h with f, l and k held locally constant and B bilinear in its cell (where
// waves of several directions meet, B varies within a wavelength and its gradient matters).
//
// Off its grid a train is its grid's nearest edge point carried on along that point's wave vector
// (phi grows by k . offset, B, k, fold and lean stay), so the sea beyond the domain continues the sea
// at its edge. A train without a grid is straight crests with the far fields everywhere:
// phi = far_kx x + far_ky y - far_offset, B = far_amplitude.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/surface/gerstner.hpp"
#include "houle/surface/node_footprint.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

/// One train's static fields. Node (i, j) is at origin + (i, j) * cell, element j * nx + i of each
/// array; nx, ny >= 2 with nx * ny < 2^31, or both 0 for no grid. Arrays need no alignment.
struct TrainGrid {
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f;  ///< m
  std::uint32_t nx = 0, ny = 0;
  const float* phi = nullptr;
  const float* b_re = nullptr;
  const float* b_im = nullptr;
  const float* kx = nullptr;
  const float* ky = nullptr;
  const float* fold = nullptr;
  const float* lean = nullptr;
  float far_kx = 0.0f, far_ky = 0.0f, far_amplitude = 0.0f;
  float far_fold = 0.0f, far_lean = 0.0f;  ///< 1/m, per metre of amplitude
  double far_offset = 0.0;  ///< rad
};

/// The trains at one time: `count` trains and their time phases.
struct TrainGridFrame {
  /// A scene's 16 written trains and 256 sea-state components (sim's scene_limits).
  static constexpr std::size_t max_trains = 272;
  std::uint32_t count = 0;
  const TrainGrid* trains = nullptr;
  float time_phase[max_trains] = {};  ///< (omega t - phase) mod 2 pi, reduced in double
  float far_phase[max_trains] = {};   ///< (far_offset + time phase) mod 2 pi: the far field's constant
};

/// Sets frame.time_phase and far_phase from each train's omega t - phase (double, any size).
void set_train_grid_time(TrainGridFrame& frame, const double* omega_t_minus_phase) noexcept;

/// One train's interpolated fields at a point (off its grid, its nearest edge point's carried on; the far
/// fields for a train without a grid); phi not reduced.
struct TrainGridFields {
  float phi, b_re, b_im, kx, ky, fold, lean;
};
TrainGridFields train_grid_fields(const TrainGrid& grid, float x, float y) noexcept;

/// Height and gradient of the summed trains at the n points. Arrays need no alignment; any n.
void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept;

/// Floats per point that the filtered train_grid_eval keeps (TrainGridKeep) for `trains` trains: each
/// train's fields and their gradients.
constexpr std::size_t train_grid_keep_floats(std::uint32_t trains) noexcept { return 11 * std::size_t(trains); }

/// Where the filtered train_grid_eval keeps what changes neither with the time nor with the viewer at
/// its points: the trains' interpolated fields (docs/design.md 3). `data`: room for
/// train_grid_keep_floats(frame.count) floats per point, the points rounded up to 16; no alignment
/// needed. `kept`: data holds what an earlier call wrote for the same points and trains on the same
/// ISA (the time and the footprint may differ), which is read instead of the grids; otherwise this
/// call writes it. The results are the same bits with and without it.
struct TrainGridKeep {
  float* data = nullptr;
  bool kept = false;
};

/// The same, each train weighted by node_wave_weight(footprint, point, its local wave vector), so that
/// nodes hold no wave they cannot sample (docs/rendering.md 5.5); slope_variance[i] gets the slope
/// variance per axis the weights removed there (n floats).
void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     const NodeFootprint& footprint, GerstnerOutput out, float* slope_variance,
                     TrainGridKeep keep = {}) noexcept;
void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     const NodeFootprint& footprint, GerstnerOutput out, float* slope_variance,
                     TrainGridKeep keep = {}) noexcept;

}  // namespace houle
