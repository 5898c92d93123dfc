#include "houle/surface/train_grid.hpp"

#include <cmath>
#include <numbers>

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"
#include "train_grid_impl.hpp"

namespace houle {

namespace {
void check_trains(const TrainGridFrame& frame) noexcept {
  HOULE_ASSERT(frame.count <= TrainGridFrame::max_trains, "TrainGridFrame: at most max_trains trains");
  HOULE_ASSERT(frame.count == 0 || frame.trains != nullptr, "TrainGridFrame: `count` trains");
  for (std::uint32_t t = 0; t < frame.count && frame.trains != nullptr; ++t) {
    const TrainGrid& g = frame.trains[t];
    HOULE_ASSERT((g.nx == 0 && g.ny == 0) || (g.nx >= 2 && g.ny >= 2 && std::uint64_t(g.nx) * g.ny < (1ull << 31)),
                 "TrainGrid: nx, ny >= 2 with nx * ny < 2^31, or both 0");
    HOULE_ASSERT(g.nx == 0 || (g.phi != nullptr && g.b_re != nullptr && g.b_im != nullptr && g.kx != nullptr && g.ky != nullptr &&
                               g.fold != nullptr && g.lean != nullptr),
                 "TrainGrid: nx * ny values in each field array");
  }
}
}  // namespace

void set_train_grid_time(TrainGridFrame& frame, const double* omega_t_minus_phase) noexcept {
  check_trains(frame);
  HOULE_ASSERT(frame.count == 0 || omega_t_minus_phase != nullptr, "set_train_grid_time: a phase per train");
  constexpr double two_pi = 2.0 * std::numbers::pi;
  for (std::uint32_t t = 0; t < frame.count; ++t) {
    frame.time_phase[t] = float(std::remainder(omega_t_minus_phase[t], two_pi));
    frame.far_phase[t] = float(std::remainder(frame.trains[t].far_offset + omega_t_minus_phase[t], two_pi));
  }
}

TrainGridFields train_grid_fields(const TrainGrid& grid, float x, float y) noexcept {
  const detail::TrainGridLanes<simd::scalar> l = detail::train_grid_lanes<simd::scalar>(grid, x, y);
  const float phi = grid.nx < 2 ? float(double(l.phi) - grid.far_offset) : l.phi;
  return {phi, l.b_re, l.b_im, l.kx, l.ky, l.fold, l.lean};
}

namespace {
void check_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n, GerstnerOutput out) noexcept {
  check_trains(frame);
  HOULE_ASSERT(n == 0 || (x != nullptr && y != nullptr), "train_grid_eval: n points in x and y");
  HOULE_ASSERT(n == 0 || (out.height != nullptr && out.grad_x != nullptr && out.grad_y != nullptr),
               "train_grid_eval: n floats in each of out.height, out.grad_x, out.grad_y");
}
}  // namespace

void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  check_eval(frame, x, y, n, out);
  simd::active_table<detail::SurfaceTable>().train_grid_eval(frame, x, y, n, out);
}

void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  check_eval(frame, x, y, n, out);
  simd::table_for<detail::SurfaceTable>(isa).train_grid_eval(frame, x, y, n, out);
}

namespace {
void check_filtered(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n, const NodeFootprint& footprint,
                    GerstnerOutput out, float* slope_variance) noexcept {
  check_eval(frame, x, y, n, out);
  HOULE_ASSERT(n == 0 || slope_variance != nullptr, "train_grid_eval: n floats in slope_variance");
  HOULE_ASSERT(footprint.cell >= 0.0f && footprint.pixel_angle >= 0.0f && std::isfinite(footprint.cell) &&
                   std::isfinite(footprint.pixel_angle) && std::isfinite(footprint.eye_x) && std::isfinite(footprint.eye_y) &&
                   std::isfinite(footprint.eye_height),
               "train_grid_eval: a finite footprint, cell and pixel angle >= 0");
}
}  // namespace

void train_grid_eval(const TrainGridFrame& frame, const float* x, const float* y, std::size_t n, const NodeFootprint& footprint,
                     GerstnerOutput out, float* slope_variance, TrainGridKeep keep) noexcept {
  check_filtered(frame, x, y, n, footprint, out, slope_variance);
  simd::active_table<detail::SurfaceTable>().train_grid_eval_filtered(frame, x, y, n, footprint, out, slope_variance, keep);
}

void train_grid_eval(Isa isa, const TrainGridFrame& frame, const float* x, const float* y, std::size_t n,
                     const NodeFootprint& footprint, GerstnerOutput out, float* slope_variance, TrainGridKeep keep) noexcept {
  check_filtered(frame, x, y, n, footprint, out, slope_variance);
  simd::table_for<detail::SurfaceTable>(isa).train_grid_eval_filtered(frame, x, y, n, footprint, out, slope_variance, keep);
}

float node_wave_weight(const NodeFootprint& footprint, float x, float y, float kx, float ky) noexcept {
  const detail::FootprintLanes<simd::scalar> l = detail::footprint_lanes<simd::scalar>(footprint, x, y);
  return detail::footprint_weight<simd::scalar>(l, kx, ky);
}

}  // namespace houle
