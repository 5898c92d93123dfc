// What the viewer sees (issue 21): whole scenes rendered through Animation and measured as a viewer
// would look at them: no speckle, no seam at the domain's edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"
#include "houle/surface/camera.hpp"

namespace {

using houle::Animation;
using houle::Framebuffer;

Animation make_animation(const houle::Scene& s, std::uint32_t w, std::uint32_t h,
                         houle::QualityPreset q = houle::QualityPreset::realtime) {
  auto a = Animation::create(s, houle::quality_preset(q), w, h, 2);
  EXPECT_TRUE(a.ok()) << (a.ok() ? "" : a.error().field + ": " + a.error().message);
  return std::move(a.value());
}

float luma(const Framebuffer& fb, int x, int y) {
  const float* p = &fb.rgb[(std::size_t(y) * std::size_t(fb.width) + std::size_t(x)) * 3];
  return houle::luminance({p[0], p[1], p[2]});
}

/// Image row of world point p (may lie outside the image).
float image_row(const houle::Camera& c, std::array<float, 3> p) {
  const float d[3] = {p[0] - c.position[0], p[1] - c.position[1], p[2] - c.position[2]};
  const auto dot = [&](const std::array<float, 3>& v) { return d[0] * v[0] + d[1] * v[1] + d[2] * v[2]; };
  return 0.5f * float(c.height) - dot(c.up) / dot(c.forward) / c.pixel_scale;
}

/// Pixels of rows [y0, y1) darker than each of their eight neighbours by more than 10 % of the darkest:
/// speckle.
int isolated_dark_pixels(const Framebuffer& fb, int y0, int y1) {
  int count = 0;
  for (int y = std::max(y0, 1); y < std::min(y1, fb.height - 1); ++y) {
    for (int x = 1; x + 1 < fb.width; ++x) {
      float darkest = std::numeric_limits<float>::infinity();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx != 0 || dy != 0) darkest = std::min(darkest, luma(fb, x + dx, y + dy));
        }
      }
      count += luma(fb, x, y) < 0.9f * darkest;
    }
  }
  return count;
}

TEST(Picture, NoSeamOrSpeckleBeyondTheDomainsEdge) {
  // The built-in coast from a raised camera: the domain ends at y = 0, where the floor (the beach at
  // 5.7 m there) extends level. Beyond the edge the sea must look as it does inside: no band of
  // speckle (refracted rays missing the level floor) starting at the edge.
  houle::Scene s = houle::builtin_coast();
  s.camera.position = {120.0, 230.0, 70.0};
  s.camera.look_at = {140.0, 60.0, 0.0};
  constexpr std::uint32_t w = 320, h = 180;
  Animation a = make_animation(s, w, h);
  Framebuffer fb(w, h);
  a.render(1.0, fb);
  const int edge = int(image_row(a.camera(), {120.0f, 0.0f, 0.0f}));
  const int horizon = int(image_row(a.camera(), {120.0f, -1e6f, 0.0f}));
  ASSERT_GT(edge, horizon + 20);
  ASSERT_LT(edge, int(h) / 2);
  EXPECT_EQ(isolated_dark_pixels(fb, horizon + 3, edge + 3), 0);
}

}  // namespace
