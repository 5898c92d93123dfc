// Pinhole camera: frame, pixel angle, and row rays equal to single rays.
#include <gtest/gtest.h>

#include <cmath>

#include "houle/surface/camera.hpp"

namespace {

double dot(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  return double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
}

TEST(Camera, LookingNorthRightIsEastAndTheCentreRayIsTheAxis) {
  houle::CameraParams p;
  p.position = {0.0f, 0.0f, 5.0f};
  p.look_at = {0.0f, 100.0f, 5.0f};
  p.width = 640;
  p.height = 360;
  const auto cam = houle::make_camera(p);
  ASSERT_TRUE(cam.ok());
  const houle::Camera& c = cam.value();
  EXPECT_NEAR(c.right[0], 1.0f, 1e-7f);
  EXPECT_NEAR(c.up[2], 1.0f, 1e-7f);
  EXPECT_NEAR(c.forward[1], 1.0f, 1e-7f);
  // theta_pix = 2 tan(fov / 2) / H (docs/rendering.md 5.2): 1.604e-3 rad at 720 rows and 60 degrees.
  EXPECT_NEAR(c.pixel_angle, 2.0 * std::tan(0.5 * 1.0471976) / 360.0, 1e-9);
  const auto d = houle::camera_ray(c, 320.0f, 180.0f);  // the image centre (a pixel corner)
  EXPECT_NEAR(d[1], 1.0f, 1e-7f);
  // The top-left pixel looks left (west) and up; the bottom-right one right and down.
  const auto tl = houle::camera_ray(c, 0.5f, 0.5f), br = houle::camera_ray(c, 639.5f, 359.5f);
  EXPECT_LT(tl[0], 0.0f);
  EXPECT_GT(tl[2], 0.0f);
  EXPECT_NEAR(tl[0], -br[0], 1e-6f);
  EXPECT_NEAR(tl[2], -br[2], 1e-6f);
  // Half the vertical fov between the axis and the top edge's centre.
  const auto top = houle::camera_ray(c, 320.0f, 0.0f);
  EXPECT_NEAR(std::acos(dot(top, c.forward)), 0.5 * 1.0471976, 1e-6);
}

TEST(Camera, RowRaysEqualSingleRaysAndAreUnit) {
  houle::CameraParams p;
  p.position = {3.0f, -2.0f, 7.0f};
  p.look_at = {40.0f, 80.0f, -3.0f};
  p.width = 101;
  p.height = 37;
  p.vertical_fov = 0.7f;
  const auto cam = houle::make_camera(p);
  ASSERT_TRUE(cam.ok());
  float dx[101], dy[101], dz[101];
  for (std::uint32_t row = 0; row < p.height; row += 3) {
    houle::camera_row_rays(cam.value(), row, 0, 101, 0.25f, 0.75f, dx, dy, dz);
    for (std::uint32_t i = 0; i < 101; ++i) {
      const auto d = houle::camera_ray(cam.value(), float(i) + 0.25f, float(row) + 0.75f);
      EXPECT_EQ(d[0], dx[i]);
      EXPECT_EQ(d[1], dy[i]);
      EXPECT_EQ(d[2], dz[i]);
      EXPECT_NEAR(dot(d, d), 1.0, 1e-6);
    }
  }
}

TEST(Camera, RejectsDegenerateInput) {
  houle::CameraParams p;
  p.look_at = p.position;
  EXPECT_FALSE(houle::make_camera(p).ok());
  p = {};
  p.vertical_fov = 3.2f;
  EXPECT_FALSE(houle::make_camera(p).ok());
  p = {};
  p.width = 0;
  EXPECT_FALSE(houle::make_camera(p).ok());
  p = {};
  p.position[0] = NAN;
  EXPECT_FALSE(houle::make_camera(p).ok());
}

// Straight down or up the default hint (z) is the view axis: north is up in the image, as on a map;
// a hint along a horizontal view falls back to z.
TEST(Camera, AnUpHintAlongTheViewFallsBackToZThenNorth) {
  houle::CameraParams p;
  p.position = {100.0f, 50.0f, 30.0f};
  p.look_at = {100.0f, 50.0f, 0.0f};
  auto cam = houle::make_camera(p);
  ASSERT_TRUE(cam.ok());
  EXPECT_NEAR(cam.value().up[1], 1.0f, 1e-7f);
  EXPECT_NEAR(cam.value().right[0], 1.0f, 1e-7f);  // east to the right, as on a map
  p.look_at = {100.0f, 50.0f, 60.0f};  // straight up
  cam = houle::make_camera(p);
  ASSERT_TRUE(cam.ok());
  EXPECT_NEAR(cam.value().up[1], 1.0f, 1e-7f);
  p.look_at = {200.0f, 50.0f, 30.0f};  // east, with an up hint pointing east
  p.up = {1.0f, 0.0f, 0.0f};
  cam = houle::make_camera(p);
  ASSERT_TRUE(cam.ok());
  EXPECT_NEAR(cam.value().up[2], 1.0f, 1e-7f);
  for (const auto& v : {cam.value().forward, cam.value().right, cam.value().up}) EXPECT_NEAR(dot(v, v), 1.0, 1e-6);
}

}  // namespace
