#include "houle/surface/train_grid.hpp"

#include <cmath>
#include <numbers>

#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"
#include "train_grid_impl.hpp"

namespace houle {

void set_train_grid_time(TrainGridFrame& frame, const double* omega_t_minus_phase) noexcept {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  for (std::uint32_t t = 0; t < frame.count; ++t) {
    frame.time_phase[t] = float(std::remainder(omega_t_minus_phase[t], two_pi));
    frame.far_phase[t] = float(std::remainder(frame.trains[t].far_offset + omega_t_minus_phase[t], two_pi));
  }
}

TrainGridFields train_grid_fields(const TrainGrid& grid, float x, float y) noexcept {
  const detail::TrainGridLanes<simd::scalar> l = detail::train_grid_lanes<simd::scalar>(grid, x, y);
  const float phi = l.inside ? l.phi : float(double(l.phi) - grid.far_offset);
  return {phi, l.amplitude, l.kx, l.ky, l.fold, l.lean};
}

void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  simd::active_table<detail::SurfaceTable>().train_grid_eval(frame, x, y, n, out);
}

void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  simd::table_for<detail::SurfaceTable>(isa).train_grid_eval(frame, x, y, n, out);
}

}  // namespace houle
