#include "houle/surface/camera.hpp"

#include <cmath>
#include <numbers>

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "surface_table.hpp"

namespace houle {
namespace {

using Vec = std::array<double, 3>;

Vec to_double(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<float, 3> to_float(const Vec& v) { return {float(v[0]), float(v[1]), float(v[2])}; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
bool finite(const std::array<float, 3>& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

Expected<Camera> make_camera(const CameraParams& p) {
  if (!finite(p.position)) return Error{"camera.position", "three finite coordinates in m"};
  if (!finite(p.look_at)) return Error{"camera.look_at", "three finite coordinates in m"};
  if (!finite(p.up)) return Error{"camera.up", "three finite components"};
  if (!(p.vertical_fov > 0.0f && p.vertical_fov < float(std::numbers::pi))) {
    return Error{"camera.vertical_fov", "an angle in (0, pi) rad"};
  }
  if (p.width == 0 || p.height == 0) return Error{"camera.size", "width and height of at least 1 pixel"};
  const Vec pos = to_double(p.position), at = to_double(p.look_at);
  Vec f{at[0] - pos[0], at[1] - pos[1], at[2] - pos[2]};
  const double fn = norm(f);
  if (!(fn > 0.0)) return Error{"camera.look_at", "a point different from the camera position"};
  for (double& c : f) c /= fn;
  // An up hint within ~0.06 degrees of the view direction leaves the image's roll undefined: then z
  // is up in the image, or north for a camera looking straight down or up (as on a map). One of
  // them is at least 45 degrees off any view direction parallel to the other.
  Vec r{};
  double rn = 0.0;
  for (const Vec& hint : {to_double(p.up), Vec{0.0, 0.0, 1.0}, Vec{0.0, 1.0, 0.0}}) {
    r = cross(f, hint);
    rn = norm(r);
    if (rn > 1e-6 * norm(hint)) break;
  }
  for (double& c : r) c /= rn;
  const Vec u = cross(r, f);
  Camera cam;
  cam.position = p.position;
  cam.forward = to_float(f);
  cam.right = to_float(r);
  cam.up = to_float(u);
  cam.width = p.width;
  cam.height = p.height;
  cam.pixel_scale = float(2.0 * std::tan(0.5 * double(p.vertical_fov)) / double(p.height));
  cam.pixel_angle = cam.pixel_scale;
  return cam;
}

namespace {
void check_row(const Camera& c, std::uint32_t row, std::uint32_t x0, std::size_t n, const float* dx, const float* dy,
               const float* dz) noexcept {
  HOULE_ASSERT(row < c.height && x0 <= c.width && n <= c.width - x0, "camera_row_rays: pixels of the image");
  HOULE_ASSERT(n == 0 || (dx != nullptr && dy != nullptr && dz != nullptr), "camera_row_rays: n floats in dx, dy, dz");
}
}  // namespace

void camera_row_rays(const Camera& c, std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x, float sub_y,
                     float* dx, float* dy, float* dz) noexcept {
  check_row(c, row, x0, n, dx, dy, dz);
  simd::active_table<detail::SurfaceTable>().camera_row_rays(c, row, x0, n, sub_x, sub_y, dx, dy, dz);
}

void camera_row_rays(Isa isa, const Camera& c, std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x,
                     float sub_y, float* dx, float* dy, float* dz) noexcept {
  check_row(c, row, x0, n, dx, dy, dz);
  simd::table_for<detail::SurfaceTable>(isa).camera_row_rays(c, row, x0, n, sub_x, sub_y, dx, dy, dz);
}

std::array<float, 3> camera_ray(const Camera& c, float image_x, float image_y) noexcept {
  // The operations of camera_row_rays (camera_impl.hpp) in the same order (float(row) + sub_y ==
  // image_y exactly), so both give the same bits for the same image point.
  const float b = (0.5f * float(c.height) - image_y) * c.pixel_scale;
  const float vx = c.forward[0] + b * c.up[0], vy = c.forward[1] + b * c.up[1], vz = c.forward[2] + b * c.up[2];
  const float a = (image_x - 0.5f * float(c.width)) * c.pixel_scale;
  const float x = vx + a * c.right[0], y = vy + a * c.right[1], z = vz + a * c.right[2];
  const float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
  return {x * inv, y * inv, z * inv};
}

}  // namespace houle
