#include "houle/surface/gerstner.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"

namespace houle {

Expected<GerstnerFrame> make_gerstner_frame(std::span<const GerstnerWave> waves, double time) {
  if (waves.size() > GerstnerFrame::max_waves) {
    return Error{"waves", "at most " + std::to_string(GerstnerFrame::max_waves) + " trains, got " + std::to_string(waves.size())};
  }
  GerstnerFrame f{};
  double fold = 0.0;
  for (std::size_t i = 0; i < waves.size(); ++i) {
    const GerstnerWave& w = waves[i];
    const std::string field = "waves[" + std::to_string(i) + "]";
    const double norm = std::hypot(double(w.dir_x), double(w.dir_y));
    if (!(norm > 0.0) || !std::isfinite(norm)) return Error{field + ".direction", "a finite non-zero vector"};
    if (!(w.wavenumber > 0.0f) || !std::isfinite(w.wavenumber)) return Error{field + ".wavenumber", "a finite value > 0 rad/m"};
    if (!(w.amplitude >= 0.0f) || !std::isfinite(w.amplitude)) return Error{field + ".amplitude", "a finite value >= 0 m"};
    if (!(w.steepness >= 0.0f && w.steepness <= 1.0f)) return Error{field + ".steepness", "a value in [0, 1]"};
    if (!std::isfinite(w.omega) || !std::isfinite(w.phase)) return Error{field + ".omega", "finite omega and phase"};
    const double dx = w.dir_x / norm, dy = w.dir_y / norm, k = w.wavenumber, a = w.amplitude, q = w.steepness;
    fold += q * k * a;
    f.kx[i] = float(k * dx);
    f.ky[i] = float(k * dy);
    f.amp[i] = w.amplitude;
    f.qax[i] = float(q * a * dx);
    f.qay[i] = float(q * a * dy);
    f.phase[i] = float(std::remainder(double(w.omega) * time - double(w.phase), 2.0 * std::numbers::pi));
  }
  if (!(fold < 1.0)) {
    return Error{"waves", "sum of steepness * wavenumber * amplitude below 1 (the surface folds), got " + std::to_string(fold)};
  }
  f.count = static_cast<std::uint32_t>(waves.size());
  return f;
}

namespace {
void check_eval(const GerstnerFrame& frame, const float* x, const float* y, std::size_t n, GerstnerOutput out,
                int newton_steps) noexcept {
  HOULE_ASSERT(frame.count <= GerstnerFrame::max_waves, "gerstner_eval: at most max_waves trains in the frame");
  HOULE_ASSERT(n == 0 || (x != nullptr && y != nullptr), "gerstner_eval: n points in x and y");
  HOULE_ASSERT(n == 0 || (out.height != nullptr && out.grad_x != nullptr && out.grad_y != nullptr),
               "gerstner_eval: n floats in each of out.height, out.grad_x, out.grad_y");
  HOULE_ASSERT(newton_steps >= 1, "gerstner_eval: newton_steps >= 1");
}
}  // namespace

void gerstner_eval(const GerstnerFrame& frame, const float* x, const float* y, std::size_t n, GerstnerOutput out,
                   int newton_steps) noexcept {
  check_eval(frame, x, y, n, out, newton_steps);
  simd::active_table<detail::SurfaceTable>().gerstner_eval(frame, x, y, n, out, newton_steps);
}

void gerstner_eval(Isa isa, const GerstnerFrame& frame, const float* x, const float* y, std::size_t n,
                   GerstnerOutput out, int newton_steps) noexcept {
  check_eval(frame, x, y, n, out, newton_steps);
  simd::table_for<detail::SurfaceTable>(isa).gerstner_eval(frame, x, y, n, out, newton_steps);
}

}  // namespace houle
