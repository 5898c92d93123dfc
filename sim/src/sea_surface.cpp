#include "houle/sim/sea_surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"

namespace houle {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;
// q k A stays below this so that the first-order trochoid never folds (physics.md 3.1: J > 0).
constexpr float max_fold = 0.9f;

// Straight crests upstream of the domain, in the tracer's convention: phase 0 on the wavefront
// through the domain's most upstream corner.
void set_far_field(TrainField& f, const Scene& scene, const WaveRays& rays, double depth_at_entry) {
  const Domain& d = scene.domain;
  const double corners[4][2] = {{d.x_min, d.y_min}, {d.x_max, d.y_min}, {d.x_min, d.y_max}, {d.x_max, d.y_max}};
  double upstream = INFINITY;
  for (const auto& c : corners) upstream = std::min(upstream, rays.direction_x * c[0] + rays.direction_y * c[1]);
  f.dir_x = float(rays.direction_x);
  f.dir_y = float(rays.direction_y);
  if (rays.analytic) {
    f.far_k = float(rays.analytic_k);
    f.far_amplitude = float(rays.analytic_amplitude);
  } else {
    const LinearWave w = linear_wave(rays.omega, std::max(depth_at_entry, 1e-3));
    f.far_k = float(w.k);
    f.far_amplitude = float(rays.amplitude0 * shoaling_coefficient(w.k * std::max(depth_at_entry, 1e-3)));
  }
  f.far_offset = double(f.far_k) * upstream - rays.phase0;
}

// Tent-splat every ray sample onto the grid; nodes no sample reached keep amplitude 0.
void splat(TrainField& f, const WaveRays& rays, double radius) {
  const std::size_t nodes = f.nx * f.ny;
  std::vector<double> w(nodes, 0.0), phi(nodes, 0.0), amp(nodes, 0.0), kx(nodes, 0.0), ky(nodes, 0.0);
  const bool diffracts = !rays.diffraction.empty();
  std::vector<double> kd(diffracts ? nodes : 0, 0.0);
  const int reach = int(std::ceil(radius / f.cell));
  for (std::size_t s = 0; s < rays.sample_count(); ++s) {
    const double gx = (rays.x[s] - f.origin_x) / f.cell, gy = (rays.y[s] - f.origin_y) / f.cell;
    const int ci = int(std::floor(gx)), cj = int(std::floor(gy));
    const double kxs = rays.k[s] * std::cos(rays.theta[s]), kys = rays.k[s] * std::sin(rays.theta[s]);
    for (int j = std::max(0, cj - reach + 1); j <= std::min(int(f.ny) - 1, cj + reach); ++j) {
      const double wy = 1.0 - std::fabs(j - gy) * f.cell / radius;
      if (wy <= 0.0) continue;
      for (int i = std::max(0, ci - reach + 1); i <= std::min(int(f.nx) - 1, ci + reach); ++i) {
        const double wx = 1.0 - std::fabs(i - gx) * f.cell / radius;
        if (wx <= 0.0) continue;
        const std::size_t n = std::size_t(j) * f.nx + std::size_t(i);
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
  f.phi.resize(nodes);
  f.amplitude.resize(nodes);
  f.kx.resize(nodes);
  f.ky.resize(nodes);
  f.diffraction.assign(diffracts ? nodes : 0, 0.0f);
  for (std::size_t n = 0; n < nodes; ++n) {
    const double x = f.origin_x + double(n % f.nx) * f.cell, y = f.origin_y + double(n / f.nx) * f.cell;
    if (w[n] > 1e-9) {
      f.phi[n] = float(phi[n] / w[n]);
      f.amplitude[n] = float(amp[n] / w[n]);
      f.kx[n] = float(kx[n] / w[n]);
      f.ky[n] = float(ky[n] / w[n]);
      if (diffracts) f.diffraction[n] = float(kd[n] / w[n]);
    } else {
      // No wave here: keep the far field's phase and direction so interpolation towards it is smooth.
      f.phi[n] = float(double(f.far_k) * (f.dir_x * x + f.dir_y * y) - f.far_offset);
      f.amplitude[n] = 0.0f;
      f.kx[n] = f.far_k * f.dir_x;
      f.ky[n] = f.far_k * f.dir_y;
    }
  }
}

}  // namespace

Expected<SeaSurface> SeaSurface::build(const Scene& scene, const WaveField& field, float cell) {
  if (!(cell > 0.0f)) return Error{"cell", "a resampling cell > 0 m"};
  if (field.trains.size() != scene.trains.size()) return Error{"field", "one traced train per scene train"};
  SeaSurface s;
  const Bathymetry floor(scene.floor);
  const Domain& d = scene.domain;
  // The trains, then the reflected waves (fields after the trains': probe() indexes the trains).
  const std::size_t count = field.trains.size() + field.reflections.size();
  for (std::size_t t = 0; t < count; ++t) {
    const bool reflection = t >= field.trains.size();
    const std::size_t train = reflection ? field.reflections[t - field.trains.size()].train : t;
    if (train >= scene.trains.size()) return Error{"field", "a reflected wave of a train the scene has"};
    const WaveRays& rays = reflection ? field.reflections[t - field.trains.size()].rays : field.trains[t];
    TrainField f;
    f.omega = rays.omega;
    f.phase = scene.trains[train].phase;
    f.steepness = float(scene.trains[train].steepness);
    // Entry depth: where the train's rays come in, the domain's upstream edge centre.
    const double cx = 0.5 * (d.x_min + d.x_max) - rays.direction_x * 0.5 * (d.x_max - d.x_min);
    const double cy = 0.5 * (d.y_min + d.y_max) - rays.direction_y * 0.5 * (d.y_max - d.y_min);
    set_far_field(f, scene, rays, floor.depth(std::clamp(cx, d.x_min, d.x_max), std::clamp(cy, d.y_min, d.y_max)));
    if (reflection) f.far_amplitude = 0.0f;  // a reflected wave exists only where its rays went
    if (!rays.analytic) {
      f.origin_x = float(d.x_min);
      f.origin_y = float(d.y_min);
      f.cell = cell;
      f.nx = std::size_t(std::ceil((d.x_max - d.x_min) / cell)) + 1;
      f.ny = std::size_t(std::ceil((d.y_max - d.y_min) / cell)) + 1;
      const double spacing = std::max(scene.dwt.step, scene.dwt.insertion_distance);
      splat(f, rays, std::max(spacing, 2.0 * double(cell)));
    }
    float a_max = f.far_amplitude;
    for (float a : f.amplitude) a_max = std::max(a_max, a);
    s.height_bound_ += a_max;
    s.trains_.push_back(std::move(f));
  }
  s.time_phase_.assign(s.trains_.size(), 0.0f);
  for (const WaveTrain& t : scene.trains) s.amplitude0_.push_back(float(t.amplitude));
  s.set_time(0.0);
  return s;
}

void SeaSurface::set_time(double time_s) noexcept {
  for (std::size_t t = 0; t < trains_.size(); ++t) {
    time_phase_[t] = float(std::remainder(trains_[t].omega * time_s - trains_[t].phase, two_pi));
  }
}

SeaSurface::Local SeaSurface::local(const TrainField& f, float x, float y) const noexcept {
  const float gx = (x - f.origin_x) / f.cell, gy = (y - f.origin_y) / f.cell;
  if (f.nx > 1 && gx >= 0.0f && gy >= 0.0f && gx <= float(f.nx - 1) && gy <= float(f.ny - 1)) {
    const std::size_t i = std::min(std::size_t(gx), f.nx - 2), j = std::min(std::size_t(gy), f.ny - 2);
    const float u = gx - float(i), v = gy - float(j);
    const std::size_t n00 = j * f.nx + i, n10 = n00 + 1, n01 = n00 + f.nx, n11 = n01 + 1;
    auto lerp2 = [&](const std::vector<float>& q) {
      return (q[n00] * (1.0f - u) + q[n10] * u) * (1.0f - v) + (q[n01] * (1.0f - u) + q[n11] * u) * v;
    };
    return {lerp2(f.phi), lerp2(f.amplitude), lerp2(f.kx), lerp2(f.ky)};
  }
  const float kx = f.far_k * f.dir_x, ky = f.far_k * f.dir_y;
  return {float(double(kx) * x + double(ky) * y - f.far_offset), f.far_amplitude, kx, ky};
}

void SeaSurface::eval(const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                      float* grad_y) const noexcept {
  for (std::size_t p = 0; p < n; ++p) {
    float h = 0.0f, hx = 0.0f, hy = 0.0f;
    for (std::size_t t = 0; t < trains_.size(); ++t) {
      const TrainField& f = trains_[t];
      const Local l = local(f, x[p], y[p]);
      if (l.amplitude <= 0.0f) continue;
      const float k = std::sqrt(l.kx * l.kx + l.ky * l.ky);
      const float qka = std::min(f.steepness * k * l.amplitude, max_fold);
      const float theta = l.phi - time_phase_[t];
      const float s0 = std::sin(theta), c0 = std::cos(theta);
      const float th = theta - qka * c0;
      const float stretch = l.amplitude * std::cos(th) * (1.0f + qka * s0);
      h += l.amplitude * std::sin(th);
      hx += stretch * l.kx;
      hy += stretch * l.ky;
    }
    height[p] = h;
    grad_x[p] = hx;
    grad_y[p] = hy;
  }
}

TrainProbe SeaSurface::probe(std::size_t train, float x, float y) const noexcept {
  const TrainField& f = trains_[train];
  const Local l = local(f, x, y);
  float diffraction = 1.0f;
  const float gx = (x - f.origin_x) / f.cell, gy = (y - f.origin_y) / f.cell;
  if (!f.diffraction.empty() && gx >= 0.0f && gy >= 0.0f && gx <= float(f.nx - 1) && gy <= float(f.ny - 1)) {
    // Bilinear, as local() interpolates the other fields.
    const std::size_t i = std::min(std::size_t(gx), f.nx - 2), j = std::min(std::size_t(gy), f.ny - 2);
    const float u = gx - float(i), v = gy - float(j);
    const std::vector<float>& q = f.diffraction;
    const std::size_t n00 = j * f.nx + i;
    diffraction = (q[n00] * (1.0f - u) + q[n00 + 1] * u) * (1.0f - v) + (q[n00 + f.nx] * (1.0f - u) + q[n00 + f.nx + 1] * u) * v;
  }
  const float k = std::sqrt(l.kx * l.kx + l.ky * l.ky);
  TrainProbe p;
  p.amplitude = std::max(l.amplitude, 0.0f);
  p.relative_amplitude = amplitude0_[train] > 0.0f ? p.amplitude / amplitude0_[train] : 0.0f;
  p.wavelength = k > 0.0f ? float(two_pi) / k : 0.0f;
  p.direction_deg = float(std::atan2(l.ky, l.kx) * 180.0 / std::numbers::pi);
  p.phase = float(std::remainder(double(l.phi) - time_phase_[train], two_pi));
  p.diffraction = diffraction;
  return p;
}

void SeaSurface::sample(void* context, const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                        float* grad_y) noexcept {
  static_cast<const SeaSurface*>(context)->eval(x, y, n, height, grad_x, grad_y);
}

}  // namespace houle
