// Pinhole camera: frame, pixel angle, and row rays equal to single rays.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
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

// Every ISA's row kernel against the scalar one at 0 ulp (the same template, with a correctly rounded
// sqrt and division and no contraction), over random cameras, offsets and spans of a row that start
// anywhere and end in every kind of tail (8k+3, 16k+3, shorter than a batch).
TEST(Camera, RowRaysGiveTheScalarBitsOnEveryIsa) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coord(-300.0f, 300.0f), u01(0.0f, 1.0f);
  const std::vector<std::size_t> sizes = {0, 1, 2, 3, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1280};
  std::size_t compared = 0;
  for (int trial = 0; trial < 8; ++trial) {
    houle::CameraParams p;
    p.position = {coord(rng), coord(rng), 1.0f + 50.0f * u01(rng)};
    p.look_at = {coord(rng), coord(rng), -10.0f * u01(rng)};
    p.vertical_fov = 0.2f + 2.0f * u01(rng);
    p.width = 1280 + std::uint32_t(trial);
    p.height = 720;
    const auto cam = houle::make_camera(p);
    ASSERT_TRUE(cam.ok());
    for (std::size_t n : sizes) {
      const std::uint32_t x0 = std::uint32_t(u01(rng) * float(p.width - n));
      const std::uint32_t row = std::uint32_t(u01(rng) * float(p.height - 1));
      const float sub_x = u01(rng), sub_y = u01(rng);
      std::vector<float> ref(3 * n + 1), got(3 * n + 1);
      houle::camera_row_rays(houle::Isa::scalar, cam.value(), row, x0, n, sub_x, sub_y, ref.data(), ref.data() + n,
                             ref.data() + 2 * n);
      for (houle::Isa isa : houle::supported_isas()) {
        std::fill(got.begin(), got.end(), -7.0f);  // the last entry must stay: nothing written past n
        houle::camera_row_rays(isa, cam.value(), row, x0, n, sub_x, sub_y, got.data(), got.data() + n,
                               got.data() + 2 * n);
        for (std::size_t i = 0; i < 3 * n; ++i) {
          ASSERT_EQ(std::bit_cast<std::uint32_t>(got[i]), std::bit_cast<std::uint32_t>(ref[i]))
              << houle::isa_name(isa) << ": n " << n << ", entry " << i;
        }
        EXPECT_EQ(got[3 * n], -7.0f) << houle::isa_name(isa) << ": n " << n;
        compared += n;
      }
      if (n > 0) {  // and the scalar row is camera_ray's
        const auto d = houle::camera_ray(cam.value(), float(x0 + n - 1) + sub_x, float(row) + sub_y);
        EXPECT_EQ(d[0], ref[n - 1]);
        EXPECT_EQ(d[2], ref[3 * n - 1]);
      }
    }
  }
  EXPECT_GT(compared, 8u * 3000u);
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
