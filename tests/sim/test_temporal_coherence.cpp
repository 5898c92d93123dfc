// Frame coherence of the capillary far field (issue 4's temporal stability): the paper's Plate 1
// (ripples only, deep flat water) rendered through Animation at `realtime`.
//   * Consecutive frames differ in proportion to the time step: halving dt halves the mean absolute
//     difference (MAD) of the far field, i.e. the picture moves smoothly and does not shimmer.
//   * No isolated pixel flips: a pixel brighter (or darker) than both its time neighbours by more than
//     a threshold while its eight spatial neighbours are not.
//   * No octave pops as the LOD moves with distance: raising the camera moves every pixel's octave level;
//     the largest per-pixel change must shrink with the rise like the rest of the picture, not stay at
//     the size of an octave switching on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "houle/surface/camera.hpp"
#include "houle/render/colour.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"

namespace {

using houle::Animation;
using houle::Framebuffer;

constexpr std::uint32_t W = 160, H = 90;
constexpr int max_octaves = 6;

/// scenes/paper_plate1.toml: a flat face perturbed by fractal noise, seen from 4 m.
houle::Scene plate1(double camera_z = 4.0) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 100.0, 100.0};
  s.floor.base.kind = houle::FloorKind::flat;
  s.floor.base.depth = 50.0;
  s.capillary = houle::CapillaryNoise{0.03, 1.0, 2.0, max_octaves, 1.0};
  s.sun = houle::Sun{90.0, 25.0};
  s.camera = houle::ViewCamera{{50.0, 0.0, camera_z}, {50.0, 60.0, camera_z - 4.0}, 50.0, {}};
  return s;
}

Animation make_animation(const houle::Scene& s) {
  auto a = Animation::create(s, houle::quality_preset(houle::QualityPreset::realtime), W, H, 2);
  EXPECT_TRUE(a.ok()) << (a.ok() ? "" : a.error().field + ": " + a.error().message);
  return std::move(a.value());
}

/// Per pixel: the luminance of the linear image.
std::vector<float> luminance(const Framebuffer& fb) {
  std::vector<float> l(std::size_t(W) * H);
  for (std::size_t i = 0; i < l.size(); ++i) l[i] = houle::luminance({fb.rgb[3 * i], fb.rgb[3 * i + 1], fb.rgb[3 * i + 2]});
  return l;
}

std::vector<float> render(Animation& a, double t) {
  Framebuffer fb(W, H);
  a.render(t, fb);
  return luminance(fb);
}

/// The capillary octave level (capillary.hpp octave_level) at each pixel centre's point of the still
/// sea, -1 where the ray does not go down.
std::vector<float> octave_levels(const Animation& a, const houle::CapillaryParams& cp) {
  const houle::Camera& c = a.camera();
  std::vector<float> level(std::size_t(W) * H, -1.0f);
  for (std::uint32_t y = 0; y < H; ++y) {
    for (std::uint32_t x = 0; x < W; ++x) {
      const auto d = houle::camera_ray(c, float(x) + 0.5f, float(y) + 0.5f);
      if (d[2] < 0.0f) level[std::size_t(y) * W + x] = houle::octave_level(cp, -c.position[2] / d[2], c.pixel_angle, -d[2]);
    }
  }
  return level;
}

/// The far field: pixels where the LOD has dropped some octaves but not all (0 < level < 6); nearer
/// all six are there, farther the sea is the smooth grid alone.
std::vector<bool> far_field(const Animation& a) {
  houle::CapillaryParams cp;
  cp.amplitude = 0.03f;
  cp.base_wavelength = 1.0f;
  cp.max_octaves = max_octaves;
  std::vector<bool> far;
  for (float l : octave_levels(a, cp)) far.push_back(l > 0.0f && l < float(max_octaves));
  return far;
}

struct Difference {
  double mad = 0.0, max = 0.0, mean = 0.0;  // of |b - a| over the far field, and the mean of a there
  std::size_t pixels = 0;
};

Difference difference(const std::vector<float>& a, const std::vector<float>& b, const std::vector<bool>& far) {
  Difference d;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!far[i]) continue;
    const double e = std::fabs(double(b[i]) - double(a[i]));
    d.mad += e;
    d.max = std::max(d.max, e);
    d.mean += a[i];
    ++d.pixels;
  }
  d.mad /= double(d.pixels);
  d.mean /= double(d.pixels);
  return d;
}

TEST(TemporalCoherence, FarFieldDifferenceShrinksWithTheTimeStep) {
  Animation a = make_animation(plate1());
  const std::vector<bool> far = far_field(a);
  const double t0 = 2.0;
  const std::vector<float> base = render(a, t0);
  // 60 fps down to 480 fps.
  std::vector<Difference> d;
  for (double fps : {60.0, 120.0, 240.0, 480.0}) {
    d.push_back(difference(base, render(a, t0 + 1.0 / fps), far));
    std::printf("far field (%zu px, mean luminance %.4f), dt 1/%.0f s: MAD %.3e, max %.3e\n", d.back().pixels,
                d.back().mean, fps, d.back().mad, d.back().max);
  }
  ASSERT_GT(d[0].pixels, std::size_t(W) * H / 5);
  ASSERT_GT(d.back().mad, 0.0);  // the ripples do move
  // Stated tolerance: each halving of dt divides the MAD by 2 within 20 % (a linear change in t; a
  // flicker independent of dt would hold the ratio near 1).
  for (std::size_t k = 0; k + 1 < d.size(); ++k) {
    const double ratio = d[k].mad / d[k + 1].mad;
    std::printf("MAD(dt) / MAD(dt / 2) = %.3f\n", ratio);
    EXPECT_NEAR(ratio, 2.0, 0.4) << "step " << k;
  }
  // At 60 fps the far field changes by a few percent of its brightness per frame, not by its whole.
  EXPECT_LT(d[0].mad, 0.05 * d[0].mean);
}

TEST(TemporalCoherence, NoIsolatedPixelFlipsInTheFarField) {
  Animation a = make_animation(plate1());
  const std::vector<bool> far = far_field(a);
  const double dt = 1.0 / 120.0;
  for (double t0 : {1.0, 3.7, 9.2}) {
    const std::vector<float> f0 = render(a, t0), f1 = render(a, t0 + dt), f2 = render(a, t0 + 2.0 * dt);
    const Difference d = difference(f0, f1, far);
    // A flip: the middle frame departs from both neighbours in the same direction by more than 5 % of
    // the far field's mean brightness (6 times the frame-to-frame MAD measured here, and fixed, so a
    // picture that shimmers everywhere cannot raise it).
    const double threshold = 0.05 * d.mean;
    const auto flips = [&](std::size_t i) {
      const double up = double(f1[i]) - f0[i], down = double(f1[i]) - f2[i];
      return (up > threshold && down > threshold) || (up < -threshold && down < -threshold);
    };
    std::size_t flipped = 0, isolated = 0;
    for (std::uint32_t y = 1; y + 1 < H; ++y) {
      for (std::uint32_t x = 1; x + 1 < W; ++x) {
        const std::size_t i = std::size_t(y) * W + x;
        if (!far[i] || !flips(i)) continue;
        ++flipped;
        bool neighbour = false;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            if (dx != 0 || dy != 0) neighbour |= flips(std::size_t(int(i) + dy * int(W) + dx));
          }
        }
        isolated += !neighbour;
      }
    }
    std::printf("t %.1f s, dt 1/120 s: MAD %.3e, flip threshold %.3e: %zu pixels flip, %zu of them isolated\n", t0,
                d.mad, threshold, flipped, isolated);
    EXPECT_EQ(isolated, 0u) << "t " << t0;
  }
}

TEST(TemporalCoherence, NoOctavePopsAsTheCameraRises) {
  // Rising from 4 m scales every pixel's distance, so every pixel's octave level moves (by 0.0036 per
  // centimetre). With the D blend a pixel changes smoothly, by about the same amount at each small
  // step; an octave that switched on or off at a level would put a pixel's whole change into one step.
  // The camera rises 1 cm in 8 steps at a fixed time; a pixel jumps when one step holds more than half
  // of its total absolute change (4 x its mean step) and more than 0.005 in luminance (well above
  // float noise, well below what an octave's normal does to the shading).
  constexpr int steps = 8;
  constexpr double step_m = 1.25e-3, t = 2.5;
  std::vector<std::vector<float>> f;
  std::vector<bool> far;
  for (int k = 0; k <= steps; ++k) {
    Animation a = make_animation(plate1(4.0 + step_m * k));
    if (k == 0) far = far_field(a);
    f.push_back(render(a, t));
  }
  std::size_t jumps = 0;
  for (std::size_t i = 0; i < far.size(); ++i) {
    if (!far[i]) continue;
    double big = 0.0, sum = 0.0;
    for (int k = 0; k < steps; ++k) {
      const double d = std::fabs(double(f[std::size_t(k) + 1][i]) - f[std::size_t(k)][i]);
      big = std::max(big, d);
      sum += d;
    }
    jumps += big > 4.0 * sum / steps && big > 5e-3;
  }
  for (int k = 0; k < steps; k += steps / 2) {
    const Difference d = difference(f[std::size_t(k)], f[std::size_t(k) + 1], far);
    std::printf("camera rises %.2f mm at %.2f mm: far field MAD %.3e, max %.3e\n", 1e3 * step_m, 1e3 * step_m * k, d.mad,
                d.max);
  }
  std::printf("far field pixels whose change over a 1 cm rise sits in one 1.25 mm step: %zu\n", jumps);
  EXPECT_EQ(jumps, 0u);
}

}  // namespace
