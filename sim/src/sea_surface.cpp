#include "houle/sim/sea_surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "houle/runtime/assert.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"

namespace houle {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;
// sqrt(Q^2 + L^2) stays below this so that the first-order trochoid never folds (docs/physics.md 3.1: J > 0).
constexpr double max_fold = 0.9;
// Depth used where the floor is at or above still water (the wave is gone there anyway): keeps the
// dispersion relation and coth(kh) finite.
constexpr double min_depth = 1e-3;

/// Fold and lean of a train of steepness q, wavenumber k and amplitude a over depth h (sea_surface.hpp).
void shape(double q, double k, double a, double h, float& fold, float& lean) {
  const double kh = k * std::max(h, min_depth);
  double f = q * k * a / std::tanh(kh), l = f * std::exp(-kh);
  const double norm = std::hypot(f, l);
  if (norm > max_fold) {
    f *= max_fold / norm;
    l *= max_fold / norm;
  }
  fold = float(f);
  lean = float(l);
}

// Straight crests upstream of the domain, in the tracer's convention: phase 0 on the wavefront
// through the domain's most upstream corner.
void set_far_field(TrainGrid& g, const Scene& scene, const WaveRays& rays, double steepness, double depth_at_entry) {
  const Domain& d = scene.domain;
  const double corners[4][2] = {{d.x_min, d.y_min}, {d.x_max, d.y_min}, {d.x_min, d.y_max}, {d.x_max, d.y_max}};
  double upstream = INFINITY;
  for (const auto& c : corners) upstream = std::min(upstream, rays.direction_x * c[0] + rays.direction_y * c[1]);
  double k, a, h = depth_at_entry;
  if (rays.analytic) {
    k = rays.analytic_k;
    a = rays.analytic_amplitude;
  } else {
    h = std::max(depth_at_entry, min_depth);
    k = linear_wave(rays.omega, h).k;
    a = rays.amplitude0 * shoaling_coefficient(k * h);
  }
  g.far_kx = float(k * rays.direction_x);
  g.far_ky = float(k * rays.direction_y);
  g.far_amplitude = float(a);
  shape(steepness, k, a, h, g.far_fold, g.far_lean);
  g.far_offset = k * upstream - rays.phase0;
}

// Tent-splat every ray sample onto the grid; nodes no sample reached keep amplitude 0.
void splat(TrainField& f, TrainGrid& g, const WaveRays& rays, const Bathymetry& floor, double steepness, double radius) {
  const std::size_t nodes = std::size_t(g.nx) * g.ny;
  std::vector<double> w(nodes, 0.0), phi(nodes, 0.0), amp(nodes, 0.0), kx(nodes, 0.0), ky(nodes, 0.0);
  const bool diffracts = !rays.diffraction.empty();
  std::vector<double> kd(diffracts ? nodes : 0, 0.0);
  const int reach = int(std::ceil(radius / g.cell));
  for (std::size_t s = 0; s < rays.sample_count(); ++s) {
    const double gx = (rays.x[s] - g.origin_x) / g.cell, gy = (rays.y[s] - g.origin_y) / g.cell;
    const int ci = int(std::floor(gx)), cj = int(std::floor(gy));
    const double kxs = rays.k[s] * std::cos(rays.theta[s]), kys = rays.k[s] * std::sin(rays.theta[s]);
    for (int j = std::max(0, cj - reach + 1); j <= std::min(int(g.ny) - 1, cj + reach); ++j) {
      const double wy = 1.0 - std::fabs(j - gy) * g.cell / radius;
      if (wy <= 0.0) continue;
      for (int i = std::max(0, ci - reach + 1); i <= std::min(int(g.nx) - 1, ci + reach); ++i) {
        const double wx = 1.0 - std::fabs(i - gx) * g.cell / radius;
        if (wx <= 0.0) continue;
        const std::size_t n = std::size_t(j) * g.nx + std::size_t(i);
        const double ww = wx * wy;
        w[n] += ww;
        phi[n] += ww * rays.phase[s];
        amp[n] += ww * rays.amplitude[s];
        kx[n] += ww * kxs;
        ky[n] += ww * kys;
        if (diffracts) kd[n] += ww * double(rays.diffraction[s]);
      }
    }
  }
  for (std::vector<float>* v : {&f.phi, &f.amplitude, &f.kx, &f.ky, &f.fold, &f.lean}) v->resize(nodes);
  f.diffraction.assign(diffracts ? nodes : 0, 0.0f);
  for (std::size_t n = 0; n < nodes; ++n) {
    const double x = g.origin_x + double(n % g.nx) * g.cell, y = g.origin_y + double(n / g.nx) * g.cell;
    if (w[n] > 1e-9) {
      f.phi[n] = float(phi[n] / w[n]);
      f.amplitude[n] = float(amp[n] / w[n]);
      f.kx[n] = float(kx[n] / w[n]);
      f.ky[n] = float(ky[n] / w[n]);
      if (diffracts) f.diffraction[n] = float(kd[n] / w[n]);
      shape(steepness, std::hypot(double(f.kx[n]), double(f.ky[n])), f.amplitude[n], floor.depth(x, y), f.fold[n], f.lean[n]);
    } else {
      // No wave here: keep the far field's phase and direction so interpolation towards it is smooth.
      f.phi[n] = float(double(g.far_kx) * x + double(g.far_ky) * y - g.far_offset);
      f.amplitude[n] = 0.0f;
      f.kx[n] = g.far_kx;
      f.ky[n] = g.far_ky;
      f.fold[n] = 0.0f;
      f.lean[n] = 0.0f;
    }
  }
}

}  // namespace

Expected<SeaSurface> SeaSurface::build(const Scene& scene, const WaveField& field, float cell) {
  if (!(cell > 0.0f)) return Error{"cell", "a resampling cell > 0 m"};
  if (field.trains.size() != scene.trains.size()) return Error{"field", "one traced train per scene train"};
  // The trains, then the reflected waves (fields after the trains': probe() indexes the trains).
  const std::size_t count = field.trains.size() + field.reflections.size();
  if (count > TrainGridFrame::max_trains) {
    return Error{"trains", "at most " + std::to_string(TrainGridFrame::max_trains) +
                               " wave trains and reflected waves together, got " + std::to_string(count)};
  }
  SeaSurface s;
  const Bathymetry floor(scene.floor);
  const Domain& d = scene.domain;
  s.trains_.resize(count);
  s.grids_.resize(count);
  for (std::size_t t = 0; t < count; ++t) {
    const bool reflection = t >= field.trains.size();
    const std::size_t train = reflection ? field.reflections[t - field.trains.size()].train : t;
    if (train >= scene.trains.size()) return Error{"field", "a reflected wave of a train the scene has"};
    const WaveRays& rays = reflection ? field.reflections[t - field.trains.size()].rays : field.trains[t];
    TrainField& f = s.trains_[t];
    TrainGrid& g = s.grids_[t];
    s.amplitude0_.push_back(float(scene.trains[train].amplitude));
    f.omega = rays.omega;
    f.phase = scene.trains[train].phase;
    // Entry depth: where the train's rays come in, the domain's upstream edge centre.
    const double cx = 0.5 * (d.x_min + d.x_max) - rays.direction_x * 0.5 * (d.x_max - d.x_min);
    const double cy = 0.5 * (d.y_min + d.y_max) - rays.direction_y * 0.5 * (d.y_max - d.y_min);
    const double steepness = scene.trains[train].steepness;
    set_far_field(g, scene, rays, steepness, floor.depth(std::clamp(cx, d.x_min, d.x_max), std::clamp(cy, d.y_min, d.y_max)));
    if (reflection) g.far_amplitude = g.far_fold = g.far_lean = 0.0f;  // a reflected wave exists only where its rays went
    if (!rays.analytic) {
      g.origin_x = float(d.x_min);
      g.origin_y = float(d.y_min);
      g.cell = cell;
      const double nx = std::ceil((d.x_max - d.x_min) / cell) + 1, ny = std::ceil((d.y_max - d.y_min) / cell) + 1;
      if (!(nx * ny < 2147483648.0)) return Error{"cell", "a resampling grid of fewer than 2^31 nodes over the domain"};
      g.nx = std::uint32_t(nx);
      g.ny = std::uint32_t(ny);
      const double spacing = std::max(scene.dwt.step, scene.dwt.insertion_distance);
      splat(f, g, rays, floor, steepness, std::max(spacing, 2.0 * double(cell)));
      g.phi = f.phi.data();
      g.amplitude = f.amplitude.data();
      g.kx = f.kx.data();
      g.ky = f.ky.data();
      g.fold = f.fold.data();
      g.lean = f.lean.data();
    }
    float a_max = g.far_amplitude;
    for (float a : f.amplitude) a_max = std::max(a_max, a);
    s.height_bound_ += a_max;
  }
  s.frame_.count = std::uint32_t(s.grids_.size());
  s.frame_.trains = s.grids_.data();
  s.set_time(0.0);
  return s;
}

void SeaSurface::set_time(double time_s) noexcept {
  double tau[TrainGridFrame::max_trains];
  for (std::size_t t = 0; t < trains_.size(); ++t) tau[t] = trains_[t].omega * time_s - trains_[t].phase;
  set_train_grid_time(frame_, tau);
}

void SeaSurface::eval(const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                      float* grad_y) const noexcept {
  train_grid_eval(frame_, x, y, n, {height, grad_x, grad_y});
}

TrainProbe SeaSurface::probe(std::size_t train, float x, float y) const noexcept {
  HOULE_ASSERT(train < trains_.size(), "SeaSurface::probe: a field of trains()");
  const TrainGrid& g = grids_[train];
  const TrainGridFields l = train_grid_fields(g, x, y);
  float diffraction = 1.0f;
  const std::vector<float>& q = trains_[train].diffraction;
  const float gx = (x - g.origin_x) / g.cell, gy = (y - g.origin_y) / g.cell;
  if (!q.empty() && gx >= 0.0f && gy >= 0.0f && gx <= float(g.nx - 1) && gy <= float(g.ny - 1)) {
    // Bilinear, as the kernel interpolates the other fields.
    const std::size_t i = std::min(std::size_t(gx), std::size_t(g.nx) - 2), j = std::min(std::size_t(gy), std::size_t(g.ny) - 2);
    const float u = gx - float(i), v = gy - float(j);
    const std::size_t n00 = j * g.nx + i;
    diffraction = (q[n00] * (1.0f - u) + q[n00 + 1] * u) * (1.0f - v) + (q[n00 + g.nx] * (1.0f - u) + q[n00 + g.nx + 1] * u) * v;
  }
  const float k = std::sqrt(l.kx * l.kx + l.ky * l.ky);
  TrainProbe p;
  p.amplitude = std::max(l.amplitude, 0.0f);
  p.relative_amplitude = amplitude0_[train] > 0.0f ? p.amplitude / amplitude0_[train] : 0.0f;
  p.wavelength = k > 0.0f ? float(two_pi) / k : 0.0f;
  p.direction_deg = float(std::atan2(l.ky, l.kx) * 180.0 / std::numbers::pi);
  p.phase = float(std::remainder(double(l.phi) - double(frame_.time_phase[train]), two_pi));
  p.diffraction = diffraction;
  return p;
}

void SeaSurface::sample(void* context, const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                        float* grad_y) noexcept {
  HOULE_ASSERT(context != nullptr, "SeaSurface::sample: a SeaSurface as the context");
  static_cast<const SeaSurface*>(context)->eval(x, y, n, height, grad_x, grad_y);
}

}  // namespace houle
