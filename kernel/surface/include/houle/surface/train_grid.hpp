// Wave trains whose slowly varying fields are given on regular grids (rays traced over a sea floor
// and resampled once per scene, houle/sim/sea_surface.hpp), evaluated as one height field per frame.
//
// Per train, at each grid node: phase phi (rad, the integral of k ds), amplitude A (m), wave vector
// (kx, ky) (rad/m), fold Q and lean L (dimensionless). With the fields interpolated bilinearly at a
// point and tau = omega t - phase the train's time phase,
//   theta = phi - tau,   theta' = theta - Q cos theta - L sin theta,   h = A sin theta',
//   grad h = A cos theta' (1 + Q sin theta - L cos theta) (kx, ky).
// This is the trochoid whose particles sit at x = u + (Q cos theta + L sin theta) / k, inverted to
// first order: Q is the orbit's horizontal excursion times k (q k A coth kh: orbits flatten into
// ellipses as the water shoals) and L shears the crest forward (Fournier & Reeves' lean toward the
// shore). dx/du = 1 - Q sin theta + L cos theta >= 1 - sqrt(Q^2 + L^2), so Q^2 + L^2 < 1 at every node
// keeps the profile from folding (bilinear weights cannot raise that norm). Gradients of the trains
// add (paper eq. 8); the gradient is that of A sin theta' with the fields held locally constant.
//
// Outside its grid (everywhere for a train without one) a train is straight crests with the far
// fields: phi = far_kx x + far_ky y - far_offset.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

/// One train's static fields. Node (i, j) is at origin + (i, j) * cell, element j * nx + i of each
/// array; nx, ny >= 2 with nx * ny < 2^31, or both 0 for no grid. Arrays need no alignment.
struct TrainGrid {
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f;  ///< m
  std::uint32_t nx = 0, ny = 0;
  const float* phi = nullptr;
  const float* amplitude = nullptr;
  const float* kx = nullptr;
  const float* ky = nullptr;
  const float* fold = nullptr;
  const float* lean = nullptr;
  float far_kx = 0.0f, far_ky = 0.0f, far_amplitude = 0.0f, far_fold = 0.0f, far_lean = 0.0f;
  double far_offset = 0.0;  ///< rad
};

/// The trains at one time: `count` trains and their time phases.
struct TrainGridFrame {
  static constexpr std::size_t max_trains = 32;
  std::uint32_t count = 0;
  const TrainGrid* trains = nullptr;
  float time_phase[max_trains] = {};  ///< (omega t - phase) mod 2 pi, reduced in double
  float far_phase[max_trains] = {};   ///< (far_offset + time phase) mod 2 pi: the far field's constant
};

/// Sets frame.time_phase and far_phase from each train's omega t - phase (double, any size).
void set_train_grid_time(TrainGridFrame& frame, const double* omega_t_minus_phase) noexcept;

/// One train's interpolated fields at a point (far fields outside its grid); phi not reduced.
struct TrainGridFields {
  float phi, amplitude, kx, ky, fold, lean;
};
TrainGridFields train_grid_fields(const TrainGrid& grid, float x, float y) noexcept;

/// Height and gradient of the summed trains at the n points. Arrays need no alignment; any n.
void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept;

}  // namespace houle
