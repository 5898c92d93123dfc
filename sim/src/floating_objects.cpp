// Floating objects (floating_objects.hpp, docs/physics.md 2.10).
#include "houle/sim/floating_objects.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/sea_surface.hpp"

namespace houle {
namespace {

constexpr double pi = std::numbers::pi;

std::array<double, 3> normalised(std::array<double, 3> v) noexcept {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

}  // namespace

double sphere_draft(double radius, double density) noexcept {
  // u = d / r solves u^2 (3 - u) = 4 rho / rho_w, increasing on [0, 2]: bisection to the last bit.
  const double target = 4.0 * density / sea_water_density;
  double lo = 0.0, hi = 2.0;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid * mid * (3.0 - mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) * radius;
}

double box_draft(double half_z, double density) noexcept { return 2.0 * half_z * density / sea_water_density; }

std::vector<FloatingObject> floating_objects(const Scene& scene, std::size_t first_box) {
  std::vector<FloatingObject> out;
  constexpr std::size_t n = FloatingObject::samples;
  for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
    const Box& b = scene.boxes[i];
    if (!b.floats) continue;
    FloatingObject f;
    f.box = true;
    f.render_index = first_box + i;
    f.x = b.center.x;
    f.y = b.center.y;
    f.yaw = b.yaw_deg * pi / 180.0;
    f.centre_above = b.half_extent.z - box_draft(b.half_extent.z, b.density);
    // A 4 x 4 grid of the footprint's cell centres, turned by the yaw: symmetric about the centre.
    const double c = std::cos(f.yaw), s = std::sin(f.yaw);
    for (std::size_t k = 0; k < n; ++k) {
      const double u = (double(k % 4) - 1.5) / 2.0 * b.half_extent.x, v = (double(k / 4) - 1.5) / 2.0 * b.half_extent.y;
      f.dx[k] = float(c * u - s * v);
      f.dy[k] = float(s * u + c * v);
    }
    out.push_back(f);
  }
  for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
    const Sphere& sp = scene.spheres[i];
    if (!sp.floats) continue;
    FloatingObject f;
    f.render_index = i;
    f.x = sp.center.x;
    f.y = sp.center.y;
    const double draft = sphere_draft(sp.radius, sp.density);
    f.centre_above = sp.radius - draft;
    // Two rings of 8 on the waterline disc, at the radii that halve its area, the outer turned by
    // half a step: symmetric about the centre.
    const double waterline = std::sqrt(draft * (2.0 * sp.radius - draft));
    for (std::size_t k = 0; k < n; ++k) {
      const double ring = double(k / 8), r = waterline * std::sqrt((ring + 0.5) / 2.0);
      const double a = (double(k % 8) + 0.5 * ring) * pi / 4.0;
      f.dx[k] = float(r * std::cos(a));
      f.dy[k] = float(r * std::sin(a));
    }
    out.push_back(f);
  }
  return out;
}

FloatingPose floating_pose(const FloatingObject& f, const SeaSurface& sea, double bound) noexcept {
  constexpr std::size_t n = FloatingObject::samples;
  float x[n], y[n], h[n], gx[n], gy[n];
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = float(f.x + double(f.dx[k]));
    y[k] = float(f.y + double(f.dy[k]));
  }
  sea.eval(x, y, n, h, gx, gy);
  // The least-squares plane h = mean + a (dx - mean dx) + b (dy - mean dy).
  double mx = 0.0, my = 0.0, mh = 0.0;
  for (std::size_t k = 0; k < n; ++k) mx += f.dx[k], my += f.dy[k], mh += h[k];
  mx /= double(n), my /= double(n), mh /= double(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0, sxh = 0.0, syh = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double u = f.dx[k] - mx, v = f.dy[k] - my, w = h[k] - mh;
    sxx += u * u, sxy += u * v, syy += v * v, sxh += u * w, syh += v * w;
  }
  const double det = sxx * syy - sxy * sxy;
  const double a = det > 0.0 ? (syy * sxh - sxy * syh) / det : 0.0, b = det > 0.0 ? (sxx * syh - sxy * sxh) / det : 0.0;
  FloatingPose p;
  p.heave = std::clamp(mh - a * mx - b * my, -bound, bound);
  p.normal = normalised({-a, -b, 1.0});
  for (int c = 0; c < 3; ++c) p.centre[c] = f.centre_above * p.normal[c];
  p.centre[0] += f.x;
  p.centre[1] += f.y;
  p.centre[2] += p.heave;
  return p;
}

BoxPose box_pose(const FloatingObject& f, const FloatingPose& p) noexcept {
  const std::array<double, 3>& z = p.normal;
  const double cx = std::cos(f.yaw), cy = std::sin(f.yaw);
  const double along = cx * z[0] + cy * z[1];
  const std::array<double, 3> x = normalised({cx - along * z[0], cy - along * z[1], -along * z[2]});
  const std::array<double, 3> y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
  BoxPose b;
  b.center = {float(p.centre[0]), float(p.centre[1]), float(p.centre[2])};
  for (int c = 0; c < 3; ++c) {
    b.axes[0][std::size_t(c)] = float(x[std::size_t(c)]);
    b.axes[1][std::size_t(c)] = float(y[std::size_t(c)]);
    b.axes[2][std::size_t(c)] = float(z[std::size_t(c)]);
  }
  return b;
}

}  // namespace houle
