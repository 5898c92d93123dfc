// Pinhole camera: primary ray directions for pixel centres (and sub-pixel offsets) and the pixel's
// angular size, which sets the marcher's accuracy and the capillary LOD (docs/rendering.md 1.2, 5.2).
//
// World frame: x east, y north, z up, still water at z = 0; lengths in m, angles in rad. Pixel
// (0, 0) is the top-left one; pixel (px, py) covers [px, px + 1] x [py, py + 1] in image
// coordinates, so its centre is (px + 0.5, py + 0.5). Directions are unit vectors (std::array
// {x, y, z}, as in optics.hpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

#include "houle/runtime/expected.hpp"
#include "houle/runtime/isa.hpp"

namespace houle {

struct CameraParams {
  std::array<float, 3> position{0.0f, 0.0f, 5.0f};  ///< m, world
  std::array<float, 3> look_at{0.0f, 100.0f, 0.0f};  ///< m, a point the optical axis passes through
  std::array<float, 3> up{0.0f, 0.0f, 1.0f};         ///< hint for the image's up direction (need not be unit)
  float vertical_fov = 1.0471976f;                   ///< rad, full vertical field of view, in (0, pi)
  std::uint32_t width = 640, height = 360;           ///< pixels, >= 1
};

/// A validated camera. `right`, `up` and `forward` are orthonormal and right-handed
/// (right = forward x up_hint normalised, up = right x forward): looking north, right is east.
struct Camera {
  std::array<float, 3> position{};
  std::array<float, 3> forward{}, right{}, up{};
  std::uint32_t width = 0, height = 0;
  /// Image-plane size of a pixel at unit distance along `forward`: 2 tan(fov / 2) / height.
  float pixel_scale = 0.0f;
  /// theta_pix (rad): the angle a pixel subtends at the image centre, = pixel_scale to first order
  /// (docs/rendering.md 5.2 uses this value everywhere; off-axis pixels are smaller by cos^2 of their angle,
  /// which makes the marcher's step and the noise LOD slightly conservative there).
  float pixel_angle = 0.0f;
};

/// Fails on a non-finite input, a look_at equal to the position, a field of view outside (0, pi) or
/// an empty image. An up hint parallel to the view direction falls back to z, then to north (y).
Expected<Camera> make_camera(const CameraParams& params);

/// Unit direction through image point (image_x, image_y) (pixel units, see above).
std::array<float, 3> camera_ray(const Camera& camera, float image_x, float image_y) noexcept;

/// Directions for pixels x0 .. x0 + n - 1 of `row`, each at offset (sub_x, sub_y) inside its pixel
/// (0.5, 0.5 = centre; supersampling passes other offsets in [0, 1)). Writes n floats to each of dx,
/// dy, dz (any alignment). Same values as camera_ray, computed with the row's common terms hoisted,
/// with the dispatched ISA (every ISA gives the same bits).
void camera_row_rays(const Camera& camera, std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x,
                     float sub_y, float* dx, float* dy, float* dz) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void camera_row_rays(Isa isa, const Camera& camera, std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x,
                     float sub_y, float* dx, float* dy, float* dz) noexcept;

}  // namespace houle
