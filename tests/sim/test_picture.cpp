// What the viewer sees (issue 21): whole scenes rendered through Animation and measured as a viewer
// would look at them: no speckle, no seam at the domain's edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/render/framebuffer.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/effect_plan.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
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

/// The frame as shown: rgb24 through the display transform at the scene's own exposure. Pixels whose
/// radiance is more than 8 times the display's white (the sun's disc and its glint, nothing else in
/// these scenes) are marked in `sun` when it is given.
std::vector<std::uint8_t> shown(const Animation& a, const Framebuffer& fb, std::vector<bool>* sun = nullptr) {
  std::vector<std::uint8_t> out(std::size_t(fb.width) * std::size_t(fb.height) * 3);
  if (sun != nullptr) {
    sun->assign(out.size() / 3, false);
    for (std::size_t i = 0; i < sun->size(); ++i) {
      const houle::LinearRgb c{fb.rgb[3 * i], fb.rgb[3 * i + 1], fb.rgb[3 * i + 2]};
      (*sun)[i] = houle::luminance(c) * a.renderer().display_exposure() > 8.0f;
    }
  }
  houle::encode_frame(fb, houle::ToneMap{a.renderer().display_exposure()}, houle::PixelFormat::rgb24,
                      std::as_writable_bytes(std::span(out)));
  return out;
}

struct Shown {
  double mean = 0.0;        ///< of the 8-bit luma
  double at_255 = 0.0;      ///< share of pixels with a channel at 255, outside the sun and its glint
};
Shown measure(const std::vector<std::uint8_t>& px, std::size_t first_row, std::size_t rows, std::size_t width,
              const std::vector<bool>* sun = nullptr) {
  Shown m;
  for (std::size_t i = first_row * width; i < (first_row + rows) * width; ++i) {
    const std::uint8_t* p = &px[3 * i];
    m.mean += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    m.at_255 += (p[0] == 255 || p[1] == 255 || p[2] == 255) && (sun == nullptr || !(*sun)[i]);
  }
  m.mean /= double(rows * width);
  m.at_255 /= double(rows * width);
  return m;
}

TEST(Picture, TheDefaultExposureNeitherWashesOutNorClips) {
  // The built-in coast's frame 30 averaged 194/255 and a sunset's sky 223-234/255 (issue 21). At the
  // scene's own exposure a day frame sits in the middle of the range, at most 1 % of its pixels
  // outside the sun's glint have a channel at 255, and a sunset sky is not white.
  constexpr std::uint32_t w = 160, h = 90;
  houle::Scene s = houle::builtin_coast();
  {
    Animation a = make_animation(s, w, h);
    Framebuffer fb(w, h);
    a.render(1.0, fb);
    std::vector<bool> sun;
    const std::vector<std::uint8_t> px = shown(a, fb, &sun);
    const Shown m = measure(px, 0, h, w, &sun);
    EXPECT_GT(m.mean, 100.0);
    EXPECT_LT(m.mean, 175.0);
    EXPECT_LE(m.at_255, 0.01);
  }
  s.sun.elevation_deg = 4.0;
  Animation a = make_animation(s, w, h);
  Framebuffer fb(w, h);
  a.render(1.0, fb);
  const int horizon = int(image_row(a.camera(), {140.0f, -1e6f, 0.0f}));
  ASSERT_GT(horizon, 20);
  std::vector<bool> sun;
  const std::vector<std::uint8_t> px = shown(a, fb, &sun);
  const Shown sky = measure(px, 0, std::size_t(horizon - 2), w, &sun);
  EXPECT_LT(sky.mean, 200.0);
  EXPECT_LE(sky.at_255, 0.01);
}

TEST(Picture, DuskAndNightAreDarkerThanDay) {
  // A simple sea (flat 20 m floor, one swell, no tracing) shown at its own exposure as the sun goes
  // down: each step darker down to night (10 degrees below: the night sky's floor), night dark but not
  // black; the sun at the nadir is night too.
  houle::Scene s;
  s.domain = {0.0, 0.0, 200.0, 200.0};
  s.floor.base.kind = houle::FloorKind::flat;
  s.floor.base.depth = 20.0;
  houle::WaveTrain swell;
  swell.direction_deg = 90.0;
  swell.period = 6.0;
  swell.amplitude = 0.3;
  s.trains.push_back(swell);
  s.camera = houle::ViewCamera{{100.0, 0.0, 5.0}, {100.0, 100.0, 0.0}, 50.0, {}};
  constexpr std::uint32_t w = 96, h = 54;
  double last = 256.0;
  double night = 0.0;
  for (double e : {35.0, 4.0, -2.0, -5.0, -10.0, -90.0}) {
    s.sun = houle::Sun{200.0, e};
    Animation a = make_animation(s, w, h);
    Framebuffer fb(w, h);
    a.render(1.0, fb);
    const Shown m = measure(shown(a, fb), 0, h, w);
    if (e == 35.0) {
      EXPECT_GT(m.mean, 100.0);
    }
    if (e == -10.0) night = m.mean;
    if (e == -90.0) {
      EXPECT_LT(m.mean, 1.25 * night);
      EXPECT_LT(m.mean, 40.0);
      EXPECT_GT(m.mean, 3.0);
    } else {
      EXPECT_LT(m.mean, last) << e;
    }
    last = m.mean;
  }
}

TEST(Picture, WallBlocksLeaveNoGapOnTheirTop) {
  // Walls are drawn as blocks whose yaw wobbles; between neighbours the wobble opened wedges that a
  // raised view showed as dark dashes across the jetty's top. Every point of a wall's top (its axis
  // and out to 95 % of its half thickness, every 5 cm) must lie on some block, but within 0.5 m of
  // the wall's two free ends, whose corners the end blocks' wobble trims by up to 0.1 m.
  const houle::Scene s = houle::builtin_coast();
  const houle::RenderScene r = houle::make_render_scene(s);
  int points = 0, uncovered = 0;
  for (const houle::Wall& w : s.walls) {
    for (std::size_t k = 0; k + 1 < w.points.size(); ++k) {
      const houle::Point2 a = w.points[k], b = w.points[k + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y), ux = (b.x - a.x) / len, uy = (b.y - a.y) / len;
      for (double along = 0.0; along <= len; along += 0.05) {
        if ((k == 0 && along < 0.5) || (k + 2 == w.points.size() && along > len - 0.5)) continue;
        for (double across = -0.95; across <= 0.951; across += 0.19) {
          const double x = a.x + ux * along - uy * across * 0.5 * w.thickness;
          const double y = a.y + uy * along + ux * across * 0.5 * w.thickness;
          bool on = false;
          for (const houle::RenderBox& box : r.boxes) {
            const double c = std::cos(double(box.yaw_rad)), sn = std::sin(double(box.yaw_rad));
            const double dx = x - double(box.center[0]), dy = y - double(box.center[1]);
            on = on || (std::abs(c * dx + sn * dy) <= double(box.half_extent[0]) &&
                        std::abs(-sn * dx + c * dy) <= double(box.half_extent[1]));
          }
          ++points;
          uncovered += !on;
        }
      }
    }
  }
  EXPECT_GT(points, 1000);
  EXPECT_EQ(uncovered, 0) << "of " << points;
}

TEST(Picture, SurfMovesWithTheWavesWithoutFlicker) {
  // A 0.4 m swell breaking on a 1:20 beach, seen from 12 m over the surf zone at 120 frames a second:
  // no pixel departs from both its time neighbours in the same direction by more than 5 % of the
  // frame's mean luminance while none of its eight neighbours does (isolated flips: flicker), and
  // foam is there (the surf map is not empty).
  houle::Scene s;
  s.domain = {0.0, 0.0, 100.0, 160.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 12.0;
  s.floor.base.slope = 0.05;
  s.floor.base.shoreline = {0.0, 150.0};
  houle::WaveTrain swell;
  swell.direction_deg = 90.0;
  swell.period = 5.0;
  swell.amplitude = 0.4;
  s.trains = {swell};
  s.camera = houle::ViewCamera{{50.0, 110.0, 12.0}, {50.0, 145.0, 0.0}, 50.0, {}};
  constexpr std::uint32_t w = 160, h = 90;
  Animation a = make_animation(s, w, h);
  ASSERT_TRUE(houle::plan_effects(s, houle::quality_preset(houle::QualityPreset::realtime)).surf);
  {
    auto waves = houle::trace_wave_field(s);
    ASSERT_TRUE(waves.ok());
    auto sea = houle::SeaSurface::build(s, waves.value(), 0.5f);
    ASSERT_TRUE(sea.ok());
    const houle::SurfMap m = sea->surf_map(s);
    ASSERT_GT(m.nx, 0u);
    EXPECT_GT(std::count(m.foam.begin(), m.foam.end(), 1.0f), 1000);
  }
  const auto frame = [&](double t) {
    Framebuffer fb(w, h);
    a.render(t, fb);
    std::vector<float> l(std::size_t(w) * h);
    for (std::size_t i = 0; i < l.size(); ++i) l[i] = houle::luminance({fb.rgb[3 * i], fb.rgb[3 * i + 1], fb.rgb[3 * i + 2]});
    return l;
  };
  for (double t0 : {1.0, 2.3}) {
    const std::vector<float> f0 = frame(t0), f1 = frame(t0 + 1.0 / 120.0), f2 = frame(t0 + 2.0 / 120.0);
    double mean = 0.0;
    for (float v : f1) mean += v;
    const double threshold = 0.05 * mean / double(f1.size());
    const auto flips = [&](std::size_t i) {
      const double up = double(f1[i]) - f0[i], down = double(f1[i]) - f2[i];
      return (up > threshold && down > threshold) || (up < -threshold && down < -threshold);
    };
    std::size_t isolated = 0;
    for (std::uint32_t y = 1; y + 1 < h; ++y) {
      for (std::uint32_t x = 1; x + 1 < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        if (!flips(i)) continue;
        bool neighbour = false;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            if (dx != 0 || dy != 0) neighbour |= flips(std::size_t(int(i) + dy * int(w) + dx));
          }
        }
        isolated += !neighbour;
      }
    }
    EXPECT_EQ(isolated, 0u) << "t " << t0;
  }
}

/// Mean absolute difference of vertically adjacent pixels' luminance over rows [y0, y1), over the
/// rows' mean luminance: what a stripe pattern one or two pixels wide (moiré) adds to a smooth picture.
double stripe_energy(const Framebuffer& fb, int y0, int y1) {
  double diff = 0.0, sum = 0.0;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < fb.width; ++x) {
      diff += std::fabs(double(luma(fb, x, y + 1)) - double(luma(fb, x, y)));
      sum += double(luma(fb, x, y));
    }
  }
  return diff / sum;
}

TEST(Picture, ShortTrainsFadeIntoRoughnessInsteadOfMoire) {
  // A 1 s train (1.56 m waves) on deep water seen at 320 x 180 from 3 m and from 25 m up: far away the
  // pixels' footprint spans several wavelengths, and point-sampled waves (and nodes more than half a
  // wavelength apart) alias into bands across the whole sea. The train must fade into the glint's
  // roughness there (docs/rendering.md 5.5): the far sea's stripe energy under 3 % (1.7 % and 1.6 %;
  // before the fade 17 % and 23 %), while near the low camera, where the waves are drawn, it stays
  // over 10 % (22 %, unchanged by the fade).
  houle::Scene s;
  s.domain = {0.0, 0.0, 400.0, 400.0};
  s.floor.base.depth = 20.0;
  houle::WaveTrain chop;
  chop.direction_deg = 80.0;
  chop.period = 1.0;
  chop.amplitude = 0.04;
  s.trains = {chop};
  s.capillary.amplitude = 0.0;
  s.sun = {230.0, 35.0};
  constexpr std::uint32_t w = 320, h = 180;
  for (double height : {3.0, 25.0}) {
    s.camera = houle::ViewCamera{{200.0, 20.0, height}, {200.0, 120.0, 0.0}, 50.0, {}};
    Animation a = make_animation(s, w, h);
    Framebuffer fb(w, h);
    a.render(1.0, fb);
    const auto row = [&](double ahead) { return int(image_row(a.camera(), {200.0f, float(20.0 + ahead), 0.0f})); };
    // The far sea: from where a pixel's footprint along the view, t^2 theta / height, spans a
    // wavelength (30 m ahead of the low camera, 83 m of the high one) to 2 km.
    const double wavelength = 9.81 / (2.0 * 3.141592653589793), theta = a.camera().pixel_angle;
    const int far0 = std::max(row(2000.0), 0), far1 = row(std::sqrt(wavelength * height / theta - height * height));
    ASSERT_GT(far1 - far0, 15) << height;
    const double far = stripe_energy(fb, far0, far1);
    std::printf("camera %.0f m: stripe energy of the far sea (rows %d-%d) %.3f\n", height, far0, far1, far);
    EXPECT_LT(far, 0.03) << "camera " << height << " m";
    if (height == 3.0) {
      const int near0 = row(25.0), near1 = std::min(row(8.0), int(h) - 1);
      ASSERT_GT(near1 - near0, 15);
      const double near = stripe_energy(fb, near0, near1);
      std::printf("camera %.0f m: stripe energy of the near sea (rows %d-%d) %.3f\n", height, near0, near1, near);
      EXPECT_GT(near, 0.1);
    }
  }
}

}  // namespace
