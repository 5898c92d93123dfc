// Capillary value noise: SIMD vs scalar bits, a double-precision oracle built from the same octave
// geometry and lattice, bounds, continuity in level / space / time, slope-variance bookkeeping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "houle/surface/capillary.hpp"
#include "houle/runtime/isa.hpp"
#include "ulp.hpp"

namespace {

using houle::CapillaryFrame;
using houle::CapillaryParams;

// Lattice values (times 127) of the fixed hash at (0, 0), (17, 201), (255, 255).
constexpr float kPinned00 = -79.0f, kPinned17_201 = 42.0f, kPinned255_255 = 12.0f;

struct Samples {
  std::vector<float> x, y, level, h, gx, gy;
  explicit Samples(std::size_t n) : x(n), y(n), level(n), h(n, -7.0f), gx(n, -7.0f), gy(n, -7.0f) {}
  std::size_t size() const { return x.size(); }
  void eval(const CapillaryFrame& f) {
    houle::capillary_eval(f, x.data(), y.data(), level.data(), size(), h.data(), gx.data(), gy.data());
  }
  void eval(houle::Isa isa, const CapillaryFrame& f) {
    houle::capillary_eval(isa, f, x.data(), y.data(), level.data(), size(), h.data(), gx.data(), gy.data());
  }
};

CapillaryFrame noise_frame_of(const CapillaryParams& p, double t, double ox = 0.0, double oy = 0.0) {
  auto f = houle::make_capillary_frame(p, t, ox, oy);
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().field + ": " + f.error().message);
  return f.ok() ? f.value() : CapillaryFrame{};
}

// ---- Double-precision oracle: eq. 9 with the octave geometry of capillary_octave ----

double smoothstep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
// Catmull-Rom weights for lattice offsets -1, 0, 1, 2 and their derivatives (docs/rendering.md 5.1).
void catmull_rom(double t, double w[4], double d[4]) {
  w[0] = (-t * t * t + 2 * t * t - t) / 2;
  w[1] = (3 * t * t * t - 5 * t * t + 2) / 2;
  w[2] = (-3 * t * t * t + 4 * t * t + t) / 2;
  w[3] = (t * t * t - t * t) / 2;
  d[0] = (-3 * t * t + 4 * t - 1) / 2;
  d[1] = (9 * t * t - 10 * t) / 2;
  d[2] = (-9 * t * t + 8 * t + 1) / 2;
  d[3] = (3 * t * t - 2 * t) / 2;
}
struct NoiseRef {
  double h = 0, gx = 0, gy = 0;
};
NoiseRef reference(const CapillaryParams& p, double level, double X, double Y, double t) {
  NoiseRef r;
  if (!(level > 0)) level = 0;
  for (int i = 0; i < p.max_octaves; ++i) {
    const double weight = smoothstep01(level - i);
    if (weight == 0.0) continue;
    const houle::CapillaryOctave o = houle::capillary_octave(p, i);
    const double wx = X - o.velocity_x * t, wy = Y - o.velocity_y * t;
    double u = (o.cos_angle * wx + o.sin_angle * wy) / o.spacing + o.shift_u;
    double v = (-o.sin_angle * wx + o.cos_angle * wy) / o.spacing + o.shift_v;
    u -= 256.0 * std::floor(u / 256.0);
    v -= 256.0 * std::floor(v / 256.0);
    const double cu = std::floor(u), cv = std::floor(v);
    double wu[4], du[4], wv[4], dv[4];
    catmull_rom(u - cu, wu, du);
    catmull_rom(v - cv, wv, dv);
    double n = 0, nu = 0, nv = 0;
    for (int b = 0; b < 4; ++b) {
      for (int a = 0; a < 4; ++a) {
        const double q = houle::capillary_lattice_value(int(cu) - 1 + a, int(cv) - 1 + b);
        n += wu[a] * wv[b] * q;
        nu += du[a] * wv[b] * q;
        nv += wu[a] * dv[b] * q;
      }
    }
    const double s = weight * o.amplitude / o.spacing;
    r.h += weight * o.amplitude * n;
    r.gx += s * (nu * o.cos_angle - nv * o.sin_angle);
    r.gy += s * (nu * o.sin_angle + nv * o.cos_angle);
  }
  return r;
}

// ---- SIMD paths ----

TEST(Capillary, EveryIsaMatchesScalarBitForBitIncludingTailsAndMixedLevels) {
  // Stated tolerance: 0 ulp. The kernel uses only +, -, * and exact int/float conversions, without
  // contraction, and each lane's octave weights depend on its own level only.
  constexpr std::int64_t tolerance = 0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-60.0f, 60.0f), lvl(-0.5f, 6.5f), u01(0.0f, 1.0f);
  const std::vector<std::size_t> sizes = {0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1000};
  CapillaryParams p;
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    std::size_t compared = 0;
    for (int trial = 0; trial < 12; ++trial) {
      p.max_octaves = 3 + trial % 6;
      p.lacunarity = trial % 3 == 2 ? 1.7f : 2.0f;
      const CapillaryFrame f = noise_frame_of(p, 0.731 * trial, 13.0 * trial, -4.0 * trial);
      for (std::size_t n : sizes) {
        Samples ref(n), got(n);
        for (std::size_t i = 0; i < n; ++i) {
          ref.x[i] = coord(rng);
          ref.y[i] = coord(rng);
          const float pick = u01(rng);
          // Mixed levels in every batch: fractional, exact integers, out of range, NaN; a few huge, infinite,
          // NaN and signed-zero coordinates (the clamps' and floors' edge cases).
          ref.level[i] = pick < 0.6f ? lvl(rng) : pick < 0.85f ? std::floor(lvl(rng)) : pick < 0.95f ? 0.0f : NAN;
          const float edge = u01(rng);
          if (edge < 0.01f) ref.x[i] = 1e9f;
          else if (edge < 0.015f) ref.y[i] = -INFINITY;
          else if (edge < 0.02f) ref.x[i] = NAN;
          else if (edge < 0.03f) ref.x[i] = -0.0f, ref.y[i] = 0.0f;
        }
        got.x = ref.x, got.y = ref.y, got.level = ref.level;
        ref.eval(houle::Isa::scalar, f);
        got.eval(isa, f);
        for (std::size_t i = 0; i < n; ++i) {
          worst = std::max({worst, houle::test::ulp_distance(ref.h[i], got.h[i]),
                            houle::test::ulp_distance(ref.gx[i], got.gx[i]), houle::test::ulp_distance(ref.gy[i], got.gy[i])});
        }
        compared += n;
      }
    }
    EXPECT_LE(worst, tolerance) << "ISA " << houle::isa_name(isa);
    std::printf("capillary %s vs scalar: max %lld ulp over %zu samples (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), compared, static_cast<long long>(tolerance));
  }
}

// ---- Against the double oracle ----

TEST(Capillary, MatchesDoubleReference) {
  // Float lattice coordinates |u| <~ 1600 (x up to 20 m at 64 cells/m) carry ~1e-4 cell of rounding,
  // which the gradient feels through the second derivative (<= ~24 per cell). Stated tolerances:
  // 1e-4 of the amplitude for h, 2e-3 of the slope scale a / lambda_1 for the gradient.
  CapillaryParams p;
  const double t = 3.7, slope_scale = p.amplitude / p.base_wavelength;
  const CapillaryFrame f = noise_frame_of(p, t);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coord(-20.0f, 20.0f), lvl(0.0f, 6.0f);
  Samples s(4000);
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = coord(rng), s.y[i] = coord(rng), s.level[i] = lvl(rng);
  s.eval(f);
  double eh = 0, eg = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const NoiseRef r = reference(p, s.level[i], s.x[i], s.y[i], t);
    eh = std::max(eh, std::fabs(s.h[i] - r.h));
    eg = std::max({eg, std::fabs(s.gx[i] - r.gx), std::fabs(s.gy[i] - r.gy)});
  }
  EXPECT_LE(eh, 1e-4 * p.amplitude);
  EXPECT_LE(eg, 2e-3 * slope_scale);
  std::printf("capillary vs double: max |dh| %.2e amplitude, max |dgrad| %.2e slope scale\n", eh / p.amplitude,
              eg / slope_scale);
}

TEST(Capillary, LargeCoordinatesAndTimesStayAccurate) {
  // docs/physics.md 8.22: at x = 1e5 m, t = 1e6 s the float surface matches float64 to 1e-3 A.
  CapillaryParams p;
  const double slope_scale = p.amplitude / p.base_wavelength;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coord(-5.0f, 5.0f);
  double eh = 0, eg = 0;
  for (double t : {1e6, 1e7 + 0.25, 123456789.5}) {
    const double ox = 1e5, oy = -7.3e4;
    const CapillaryFrame f = noise_frame_of(p, t, ox, oy);
    Samples s(500);
    for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = coord(rng), s.y[i] = coord(rng), s.level[i] = 6.0f;
    s.eval(f);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const NoiseRef r = reference(p, 6.0, ox + s.x[i], oy + s.y[i], t);
      eh = std::max(eh, std::fabs(s.h[i] - r.h));
      eg = std::max({eg, std::fabs(s.gx[i] - r.gx), std::fabs(s.gy[i] - r.gy)});
    }
  }
  EXPECT_LE(eh, 1e-3 * p.amplitude);
  EXPECT_LE(eg, 1e-3 * slope_scale);
  std::printf("capillary at 1e5 m, 1e6..1.2e8 s: max |dh| %.2e amplitude, max |dgrad| %.2e slope scale\n",
              eh / p.amplitude, eg / slope_scale);

  // Huge or non-finite *local* coordinates are outside the contract but must stay finite and bounded.
  const CapillaryFrame f = noise_frame_of(p, 1e6);
  Samples s(6);
  const float big[6] = {1e5f, -1e5f, 1e9f, INFINITY, -INFINITY, NAN};
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = big[i], s.y[i] = big[5 - i], s.level[i] = 6.0f;
  s.eval(f);
  const float hb = houle::capillary_height_bound(p, 6.0f), gb = houle::capillary_slope_bound(p, 6.0f);
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_TRUE(std::isfinite(s.h[i]) && std::isfinite(s.gx[i]) && std::isfinite(s.gy[i])) << i;
    EXPECT_LE(std::fabs(s.h[i]), hb);
    EXPECT_LE(std::hypot(s.gx[i], s.gy[i]), gb);
  }
}

// ---- Bounds ----

// The interpolant's bounds per lattice unit that capillary_height_bound and capillary_slope_bound use.
constexpr double kValueBound = 1.30, kGradientBound = 3.31;

/// The Bernstein coefficients on [a, a + h] of the Catmull-Rom weights (cubics: from their values and
/// derivatives at the ends) and of their derivatives (quadratics: from their values at the ends and
/// the middle), per lattice offset.
struct SubInterval {
  double w[4][4], d[3][4];  // [coefficient][offset]
  SubInterval(double a, double h) {
    double wa[4], da[4], wb[4], db[4], wm[4], dm[4];
    catmull_rom(a, wa, da);
    catmull_rom(a + h, wb, db);
    catmull_rom(a + h / 2, wm, dm);
    for (int i = 0; i < 4; ++i) {
      w[0][i] = wa[i], w[1][i] = wa[i] + h * da[i] / 3, w[2][i] = wb[i] - h * db[i] / 3, w[3][i] = wb[i];
      d[0][i] = da[i], d[1][i] = 2 * dm[i] - (da[i] + db[i]) / 2, d[2][i] = db[i];
    }
  }
};

TEST(Capillary, LatticeBoundsHoldOnEveryCell) {
  // On each cell the interpolant N and its partials are polynomials in (u, v), and a polynomial lies
  // within the range of its Bernstein coefficients. Those on 8 x 8 sub-cells of all 65,536 cells
  // bound |N| and |grad N| (the larger |dN/du| and |dN/dv| of each sub-cell, combined) over the whole
  // lattice: the bounds used must hold them, and not by more than 1 % (looser would waste steps).
  constexpr int n = 8;
  std::vector<SubInterval> parts;
  for (int k = 0; k < n; ++k) parts.emplace_back(double(k) / n, 1.0 / n);
  double value = 0, gradient = 0;
  for (int j = 0; j < 256; ++j) {
    for (int i = 0; i < 256; ++i) {
      double q[4][4];
      for (int b = 0; b < 4; ++b) {
        for (int a = 0; a < 4; ++a) q[b][a] = std::round(127.0 * houle::capillary_lattice_value(i - 1 + a, j - 1 + b)) / 127.0;
      }
      for (const SubInterval& su : parts) {
        // Contracted along u first: rw[l][b], rd[l][b] for coefficient l of row b.
        double rw[4][4] = {}, rd[3][4] = {};
        for (int b = 0; b < 4; ++b) {
          for (int a = 0; a < 4; ++a) {
            for (int l = 0; l < 4; ++l) rw[l][b] += su.w[l][a] * q[b][a];
            for (int l = 0; l < 3; ++l) rd[l][b] += su.d[l][a] * q[b][a];
          }
        }
        for (const SubInterval& sv : parts) {
          double du = 0, dv = 0;
          for (int l = 0; l < 4; ++l) {
            for (int k = 0; k < 4; ++k) {
              double c = 0;
              for (int b = 0; b < 4; ++b) c += sv.w[k][b] * rw[l][b];
              value = std::max(value, std::fabs(c));
            }
            for (int k = 0; k < 3; ++k) {
              double c = 0;
              for (int b = 0; b < 4; ++b) c += sv.d[k][b] * rw[l][b];
              dv = std::max(dv, std::fabs(c));
            }
          }
          for (int l = 0; l < 3; ++l) {
            for (int k = 0; k < 4; ++k) {
              double c = 0;
              for (int b = 0; b < 4; ++b) c += sv.w[k][b] * rd[l][b];
              du = std::max(du, std::fabs(c));
            }
          }
          gradient = std::max(gradient, std::hypot(du, dv));
        }
      }
    }
  }
  std::printf("capillary lattice: |N| <= %.4f (used %.2f), |grad N| <= %.4f (used %.2f)\n", value, kValueBound,
              gradient, kGradientBound);
  EXPECT_LE(value, kValueBound);
  EXPECT_GT(value, kValueBound / 1.01);
  EXPECT_LE(gradient, kGradientBound);
  EXPECT_GT(gradient, kGradientBound / 1.01);
}

TEST(Capillary, HeightAndSlopeWithinAnalyticBounds) {
  CapillaryParams p;
  const CapillaryFrame f = noise_frame_of(p, 2.0);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> coord(-100.0f, 100.0f);
  // The bounds themselves (docs/physics.md 6.1): 1.30 sum k^-i and 3.31 (a / lambda_1) per octave, the
  // lattice's (LatticeBoundsHoldOnEveryCell). (With the documented 2^-12 rounding margin.)
  const double margin = 1.0 + 1.0 / 4096.0;
  EXPECT_NEAR(houle::capillary_height_bound(p, 6.0f), margin * p.amplitude * kValueBound * (2.0 - 1.0 / 32.0), 1e-6 * p.amplitude);
  EXPECT_NEAR(houle::capillary_slope_bound(p, 6.0f), margin * 6 * kGradientBound * p.amplitude / p.base_wavelength,
              1e-6 * p.amplitude / p.base_wavelength);
  EXPECT_EQ(houle::capillary_height_bound(p, 0.0f), 0.0f);
  for (float level : {0.5f, 1.0f, 2.3f, 4.0f, 5.5f, 6.0f}) {
    Samples s(20000);
    for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = coord(rng), s.y[i] = coord(rng), s.level[i] = level;
    s.eval(f);
    const float hb = houle::capillary_height_bound(p, level), gb = houle::capillary_slope_bound(p, level);
    double hmax = 0, gmax = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      hmax = std::max(hmax, double(std::fabs(s.h[i])));
      gmax = std::max(gmax, std::hypot(double(s.gx[i]), double(s.gy[i])));
    }
    EXPECT_LE(hmax, hb) << "level " << level;
    EXPECT_LE(gmax, gb) << "level " << level;
    std::printf("capillary level %.1f: |h| <= %.3e m (bound %.3e, %.0f%%), |grad| <= %.3e (bound %.3e, %.0f%%)\n", level,
                hmax, double(hb), 100 * hmax / hb, gmax, double(gb), 100 * gmax / gb);
  }
  // Nondecreasing in level, so the largest level a segment sees bounds it.
  for (float l = 0.0f; l < 6.0f; l += 0.05f) {
    EXPECT_LE(houle::capillary_height_bound(p, l), houle::capillary_height_bound(p, l + 0.05f));
    EXPECT_LE(houle::capillary_slope_bound(p, l), houle::capillary_slope_bound(p, l + 0.05f));
  }
}

// ---- Continuity: level, space, time ----

TEST(Capillary, ContinuousInLevelAtEveryInteger) {
  // F(n, D = 1) = F(n + 1, D = 0): across each integer level the surface moves by O(eps) (smoothstep
  // even makes it O(eps^2)). Stated bound: 2 eps * 1.5 (max smoothstep slope) * 1.5625 (a_i + a_{i-1}).
  CapillaryParams p;
  const CapillaryFrame f = noise_frame_of(p, 1.0);
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> coord(-30.0f, 30.0f);
  const float eps = 1e-3f;
  for (int n = 0; n <= p.max_octaves; ++n) {
    Samples lo(512), hi(512);
    for (std::size_t i = 0; i < lo.size(); ++i) {
      lo.x[i] = hi.x[i] = coord(rng);
      lo.y[i] = hi.y[i] = coord(rng);
      lo.level[i] = float(n) - eps;
      hi.level[i] = float(n) + eps;
    }
    lo.eval(f);
    hi.eval(f);
    const double a_n = p.amplitude * std::pow(2.0, -n), a_prev = n > 0 ? 2 * a_n : 0.0;
    const double hb = 2 * eps * 1.5 * 1.5625 * (a_n + a_prev) + 1e-7 * p.amplitude;
    const double gb = 2 * eps * 1.5 * 3.75 * std::sqrt(2.0) * 2 * p.amplitude / p.base_wavelength + 1e-6;
    double dh = 0, dg = 0;
    for (std::size_t i = 0; i < lo.size(); ++i) {
      dh = std::max(dh, double(std::fabs(hi.h[i] - lo.h[i])));
      dg = std::max({dg, double(std::fabs(hi.gx[i] - lo.gx[i])), double(std::fabs(hi.gy[i] - lo.gy[i]))});
    }
    EXPECT_LE(dh, hb) << "level " << n;
    EXPECT_LE(dg, gb) << "level " << n;
  }
}

TEST(Capillary, OctavesAboveTheLevelContributeExactlyNothing) {
  // Skipped, not multiplied by zero: a level-2 sample equals the bits of a 2-octave surface.
  CapillaryParams p6, p2;
  p2.max_octaves = 2;
  const CapillaryFrame f6 = noise_frame_of(p6, 4.5, 3.0, 2.0), f2 = noise_frame_of(p2, 4.5, 3.0, 2.0);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> coord(-30.0f, 30.0f);
  Samples a(333), b(333);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a.x[i] = b.x[i] = coord(rng);
    a.y[i] = b.y[i] = coord(rng);
    a.level[i] = 2.0f;
    b.level[i] = 2.0f;
  }
  a.level[7] = 6.0f;  // a full-detail companion in the same batch changes nothing for the others
  a.eval(f6);
  b.eval(f2);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i == 7) continue;
    EXPECT_EQ(a.h[i], b.h[i]);
    EXPECT_EQ(a.gx[i], b.gx[i]);
    EXPECT_EQ(a.gy[i], b.gy[i]);
  }
}

TEST(Capillary, GradientIsContinuousAcrossLatticeLines) {
  // One octave whose lattice has (u, v) ~ (1.3, 1.7) at the local origin, so float resolves u to
  // ~1e-7 cell. Along a line of constant v, extrapolate the gradient linearly to u = 2 from either
  // side (error O(delta^2) for a C1 function); a C0 seam would leave a jump of order a/lambda.
  // Stated tolerance: 2e-5 of the slope scale a/lambda_1.
  CapillaryParams p;
  p.max_octaves = 1;
  const houle::CapillaryOctave o = houle::capillary_octave(p, 0);
  const double A = 1.3 - o.shift_u, B = 1.7 - o.shift_v;  // wanted minus fixed shift, lattice units
  const double ox = o.spacing * (o.cos_angle * A - o.sin_angle * B), oy = o.spacing * (o.sin_angle * A + o.cos_angle * B);
  const CapillaryFrame f = noise_frame_of(p, 0.0, ox, oy);
  ASSERT_NEAR(f.off_u[0], 1.3, 1e-4);
  ASSERT_NEAR(f.off_v[0], 1.7, 1e-4);
  const double slope_scale = p.amplitude / p.base_wavelength, delta = 2.5e-4;  // cells
  double worst = 0;
  for (int line = 0; line < 2; ++line) {  // crossing u = 2, then v = 2
    for (double along = -0.45; along <= 0.45; along += 0.05) {  // position along the line, cells
      Samples s(4);
      const double steps[4] = {-2 * delta, -delta, delta, 2 * delta};
      for (int k = 0; k < 4; ++k) {
        // Local point with lattice (du, dv) from (1.3, 1.7): world = spacing R (du, dv).
        const double du = line == 0 ? 0.7 + steps[k] : along, dv = line == 0 ? along : 0.3 + steps[k];
        s.x[k] = float(o.spacing * (o.cos_angle * du - o.sin_angle * dv));
        s.y[k] = float(o.spacing * (o.sin_angle * du + o.cos_angle * dv));
        s.level[k] = 1.0f;
      }
      s.eval(f);
      const double left_x = 2.0 * s.gx[1] - s.gx[0], right_x = 2.0 * s.gx[2] - s.gx[3];
      const double left_y = 2.0 * s.gy[1] - s.gy[0], right_y = 2.0 * s.gy[2] - s.gy[3];
      worst = std::max({worst, std::fabs(left_x - right_x), std::fabs(left_y - right_y)});
      EXPECT_LT(std::fabs(s.h[1] - s.h[2]), 1e-3 * p.amplitude);
    }
  }
  EXPECT_LE(worst, 2e-5 * slope_scale);
  std::printf("capillary gradient jump across lattice lines: %.2e slope scale\n", worst / slope_scale);
}

TEST(Capillary, AnalyticGradientMatchesCentralDifferences) {
  // (1) The kernel's analytic gradient against central differences (e = 1e-6 m, in double) of the
  // oracle's heights, all octaves, far from the world origin. Stated tolerance 2e-3 of the slope
  // scale a / lambda_1 (float lattice coordinates, as in MatchesDoubleReference).
  CapillaryParams p;
  const double slope_scale = p.amplitude / p.base_wavelength, t = 7.25, ox = 5432.1, oy = -876.5;
  const CapillaryFrame f = noise_frame_of(p, t, ox, oy);
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f), lvl(0.0f, 6.0f);
  Samples s(2000);
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = coord(rng), s.y[i] = coord(rng), s.level[i] = lvl(rng);
  s.eval(f);
  double worst = 0;
  const double e = 1e-6;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double X = ox + s.x[i], Y = oy + s.y[i], l = s.level[i];
    const double fx = (reference(p, l, X + e, Y, t).h - reference(p, l, X - e, Y, t).h) / (2 * e);
    const double fy = (reference(p, l, X, Y + e, t).h - reference(p, l, X, Y - e, t).h) / (2 * e);
    worst = std::max({worst, std::fabs(fx - s.gx[i]), std::fabs(fy - s.gy[i])});
  }
  EXPECT_LE(worst, 2e-3 * slope_scale);
  std::printf("capillary gradient vs central differences of the oracle: max %.2e slope scale\n", worst / slope_scale);

  // (2) The kernel against its own float heights. Float resolves lattice coordinates near 256 only
  // to 1.5e-5 cell, so use one octave placed (through the origin) at lattice coordinates of a few
  // cells, and steps of 1e-3 cell. Stated tolerance 1e-2 of the slope scale: 2 ulp / 2e-3 cell of
  // rounding (~2e-3), and O(step) error where a stencil straddles a lattice line (f'' jumps there).
  double worst_self = 0;
  for (float wavelength : {0.5f, 0.0371f}) {
    CapillaryParams q;
    q.max_octaves = 1;
    q.base_wavelength = wavelength;
    const houle::CapillaryOctave o = houle::capillary_octave(q, 0);
    const double A = 1.3 - o.shift_u, B = 1.7 - o.shift_v;
    const CapillaryFrame g = noise_frame_of(q, 0.0, o.spacing * (o.cos_angle * A - o.sin_angle * B),
                                      o.spacing * (o.sin_angle * A + o.cos_angle * B));
    const float step = float(1e-3 * o.spacing);
    std::uniform_real_distribution<float> near(float(-1.5 * o.spacing), float(1.5 * o.spacing));
    for (int i = 0; i < 1000; ++i) {
      const float x = near(rng), y = near(rng);
      Samples c(5);
      const float xs[5] = {x, x + step, x - step, x, x}, ys[5] = {y, y, y, y + step, y - step};
      for (int k = 0; k < 5; ++k) c.x[k] = xs[k], c.y[k] = ys[k], c.level[k] = 1.0f;
      c.eval(g);
      const double fx = (double(c.h[1]) - c.h[2]) / (double(xs[1]) - xs[2]);
      const double fy = (double(c.h[3]) - c.h[4]) / (double(ys[3]) - ys[4]);
      const double scale = double(q.amplitude) / wavelength;
      worst_self = std::max({worst_self, std::fabs(fx - c.gx[0]) / scale, std::fabs(fy - c.gy[0]) / scale});
    }
  }
  EXPECT_LE(worst_self, 1e-2);
  std::printf("capillary gradient vs central differences of its own heights: max %.2e slope scale\n", worst_self);
}

TEST(Capillary, HeightOnlyPathGivesTheSameHeights) {
  // Null gradient pointers skip the derivative work; heights keep their bits on every ISA.
  CapillaryParams p;
  const CapillaryFrame f = noise_frame_of(p, 8.0, -3.0, 9.0);
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> coord(-40.0f, 40.0f), lvl(-0.5f, 6.5f);
  for (houle::Isa isa : houle::supported_isas()) {
    Samples s(16 * 9 + 5);
    for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = coord(rng), s.y[i] = coord(rng), s.level[i] = lvl(rng);
    s.eval(isa, f);
    std::vector<float> h(s.size(), -7.0f);
    houle::capillary_eval(isa, f, s.x.data(), s.y.data(), s.level.data(), s.size(), h.data(), nullptr, nullptr);
    for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(houle::test::ulp_distance(h[i], s.h[i]), 0) << houle::isa_name(isa);
  }
}

TEST(Capillary, ContinuousInTimeIncludingOffsetWraps) {
  // |h(t + dt) - h(t)| <= L v_max dt (the pattern of each octave translates at <= v_max), plus float
  // noise 1e-4 a; in particular where an octave's offset wraps modulo the period.
  CapillaryParams p;
  double vmax = 0;
  for (int i = 0; i < p.max_octaves; ++i) {
    const houle::CapillaryOctave o = houle::capillary_octave(p, i);
    vmax = std::max(vmax, std::hypot(o.velocity_x, o.velocity_y));
  }
  const double L = houle::capillary_slope_bound(p, 6.0f), noise = 1e-4 * p.amplitude;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
  Samples pts(64);
  for (std::size_t i = 0; i < pts.size(); ++i) pts.x[i] = coord(rng), pts.y[i] = coord(rng), pts.level[i] = 6.0f;
  auto max_change = [&](double t0, double t1) {
    Samples a = pts, b = pts;
    a.eval(noise_frame_of(p, t0, 250.0, -40.0));
    b.eval(noise_frame_of(p, t1, 250.0, -40.0));
    double d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, double(std::fabs(a.h[i] - b.h[i])));
    return d;
  };
  // O(dt) at ordinary times.
  for (double t : {0.0, 1.5, 1e6, 3.3e7}) {
    for (double dt : {1e-2, 1e-3}) EXPECT_LE(max_change(t, t + dt), L * vmax * dt + noise) << "t " << t << " dt " << dt;
  }
  // Find offset wraps in a minute of a long run and check continuity across each.
  int wraps = 0;
  const double t0 = 1e6, step = 0.05;
  CapillaryFrame prev = noise_frame_of(p, t0, 250.0, -40.0);
  for (double t = t0 + step; t < t0 + 60.0; t += step) {
    const CapillaryFrame cur = noise_frame_of(p, t, 250.0, -40.0);
    for (int i = 0; i < p.max_octaves; ++i) {
      for (int uv = 0; uv < 2; ++uv) {
        const float a = uv ? prev.off_v[i] : prev.off_u[i], b = uv ? cur.off_v[i] : cur.off_u[i];
        if (std::fabs(a - b) < 128.0f) continue;
        // Bisect the wrap time to 1e-7 s, then compare the surface just before and just after.
        double lo = t - step, hi = t;
        while (hi - lo > 1e-7) {
          const double mid = 0.5 * (lo + hi);
          const CapillaryFrame m = noise_frame_of(p, mid, 250.0, -40.0);
          const float om = uv ? m.off_v[i] : m.off_u[i];
          (std::fabs(om - a) < 128.0f ? lo : hi) = mid;
        }
        EXPECT_LE(max_change(lo, hi), L * vmax * (hi - lo) + noise) << "wrap of octave " << i << " at t " << lo;
        ++wraps;
      }
    }
    prev = cur;
  }
  EXPECT_GE(wraps, 2);
  std::printf("capillary: continuity checked across %d offset wraps\n", wraps);
}

// ---- Slope variance of dropped octaves (docs/rendering.md 5.4) ----

TEST(Capillary, DroppedSlopeVarianceMatchesMeasurement) {
  // Stated tolerance 10 %. Octaves have independent, isotropic slopes of equal variance, so the
  // variance a level lacks is octave_slope_variance * sum(1 - W_i^2).
  CapillaryParams p;
  const CapillaryFrame f = noise_frame_of(p, 0.5);
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> coord(-400.0f, 400.0f);
  const std::size_t n = 100000;
  Samples full(n);
  for (std::size_t i = 0; i < n; ++i) full.x[i] = coord(rng), full.y[i] = coord(rng), full.level[i] = 6.0f;
  full.eval(f);
  auto variance = [](const std::vector<double>& v) {
    double m = 0, s = 0;
    for (double e : v) m += e;
    m /= double(v.size());
    for (double e : v) s += (e - m) * (e - m);
    return s / double(v.size());
  };
  auto axis_mean_variance = [&](const Samples& a, const Samples* minus) {
    std::vector<double> gx(n), gy(n);
    for (std::size_t i = 0; i < n; ++i) {
      gx[i] = a.gx[i] - (minus ? minus->gx[i] : 0.0f);
      gy[i] = a.gy[i] - (minus ? minus->gy[i] : 0.0f);
    }
    return 0.5 * (variance(gx) + variance(gy));
  };
  const double var_full = axis_mean_variance(full, nullptr);
  EXPECT_NEAR(var_full, 6 * houle::octave_slope_variance(p), 0.1 * var_full);
  for (float level : {0.0f, 1.0f, 2.5f, 3.0f, 4.7f, 5.9f}) {
    Samples s = full;
    std::fill(s.level.begin(), s.level.end(), level);
    s.eval(f);
    const double expected = houle::dropped_slope_variance(p, level);
    const double lacked = var_full - axis_mean_variance(s, nullptr);
    EXPECT_NEAR(lacked, expected, 0.1 * expected + 1e-9) << "level " << level;
    std::printf("capillary level %.1f: dropped slope variance %.3e, measured %.3e", level, expected, lacked);
    if (level == std::floor(level)) {
      // At whole levels the dropped part is a whole set of octaves: measure its slopes directly.
      const double direct = axis_mean_variance(full, &s);
      EXPECT_NEAR(direct, expected, 0.1 * expected + 1e-9) << "level " << level;
      std::printf(" (dropped octaves' own slopes %.3e)", direct);
    }
    std::printf("\n");
  }
  EXPECT_EQ(houle::dropped_slope_variance(p, 6.0f), 0.0f);
}

// ---- Level of detail ----

TEST(Capillary, OctaveLevelFollowsFootprint) {
  // docs/rendering.md 5.2 table: 1280x720, 60 deg fov (theta_pix = 1.604e-3), lambda_1 = 0.5 m, k = 2, N = 2.
  CapillaryParams p;
  const float theta = 1.604e-3f;
  const float t[7] = {2, 5, 10, 20, 50, 100, 200}, across[7] = {6, 5.96f, 4.96f, 3.96f, 2.64f, 1.64f, 0.64f};
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(houle::octave_level(p, t[i] * theta), across[i], 0.01f) << "t " << t[i];
  // Grazing views: footprint along the view divides by sin(grazing); one octave per doubling.
  EXPECT_NEAR(houle::octave_level(p, 20.0f, theta, 0.25f), houle::octave_level(p, 80.0f * theta), 1e-5f);
  EXPECT_NEAR(houle::octave_level(p, 10.0f * theta) - houle::octave_level(p, 20.0f * theta), 1.0f, 1e-5f);
  EXPECT_EQ(houle::octave_level(p, 0.0f), 6.0f);
  EXPECT_EQ(houle::octave_level(p, INFINITY), 0.0f);
  EXPECT_EQ(houle::octave_level(p, NAN), 0.0f);
  EXPECT_FLOAT_EQ(houle::capillary_footprint(10.0f, 1e-3f, 0.0f), 10.0f);  // sin clamped at 1e-3
}

TEST(Capillary, OctavesFadeOverAtLeastAFactorTwoOfFootprint) {
  // With lacunarity 1.25 an octave used to fade over a factor 1.25 of footprint: at 0.25 m amplitude
  // the ripples ended at a hard circle (issue 21). Each octave now fades over a factor max(k, 2). The
  // height bound of a single octave follows its weight: where is it 99 % and 1 % of its whole value?
  for (float k : {1.25f, 1.5f, 2.0f, 3.0f}) {
    CapillaryParams p;
    p.lacunarity = k;
    p.max_octaves = 1;
    const float whole = houle::capillary_height_bound(p, houle::capillary_top_level(p));
    float w99 = 0.0f, w01 = 0.0f;
    for (float w = 0.01f; w < 10.0f; w *= 1.001f) {
      const float b = houle::capillary_height_bound(p, houle::octave_level(p, w)) / whole;
      if (b >= 0.99f) w99 = w;
      if (b >= 0.01f) w01 = w;
    }
    // smoothstep goes from 1 % to 99 % over 0.882 of its ramp: a factor F^0.882 of footprint.
    EXPECT_GT(w01 / w99, 0.99f * std::pow(std::max(k, 2.0f), 0.882f)) << "k " << k;
    // The octave is whole while it has N samples per wavelength.
    EXPECT_NEAR(w99, p.base_wavelength / p.samples_per_wavelength, 0.05f * p.base_wavelength) << "k " << k;
  }
}

// ---- Determinism and validation ----

TEST(Capillary, DeterministicAndPinned) {
  CapillaryParams p;
  Samples a(100), b(100);
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> coord(-50.0f, 50.0f), lvl(0.0f, 6.0f);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a.x[i] = b.x[i] = coord(rng);
    a.y[i] = b.y[i] = coord(rng);
    a.level[i] = b.level[i] = lvl(rng);
  }
  a.eval(noise_frame_of(p, 12.5, 1.0, 2.0));
  b.eval(noise_frame_of(p, 12.5, 1.0, 2.0));
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(houle::test::float_order(a.h[i]), houle::test::float_order(b.h[i]));
    EXPECT_EQ(houle::test::float_order(a.gx[i]), houle::test::float_order(b.gx[i]));
    EXPECT_EQ(houle::test::float_order(a.gy[i]), houle::test::float_order(b.gy[i]));
  }
  // The lattice is a fixed hash: pin it so any change to it is deliberate.
  EXPECT_EQ(houle::capillary_lattice_value(0, 0), houle::capillary_lattice_value(256, -256));
  EXPECT_FLOAT_EQ(houle::capillary_lattice_value(0, 0) * 127.0f, kPinned00);
  EXPECT_FLOAT_EQ(houle::capillary_lattice_value(17, 201) * 127.0f, kPinned17_201);
  EXPECT_FLOAT_EQ(houle::capillary_lattice_value(255, 255) * 127.0f, kPinned255_255);
}

TEST(Capillary, RejectsInvalidParameters) {
  auto field_of = [](CapillaryParams p, double t = 0.0, double ox = 0.0) {
    const auto f = houle::make_capillary_frame(p, t, ox, 0.0);
    return f.ok() ? std::string() : f.error().field;
  };
  CapillaryParams p;
  EXPECT_EQ(field_of(p), "");
  p.amplitude = -1.0f;
  EXPECT_EQ(field_of(p), "amplitude");
  p = {};
  p.base_wavelength = 0.0f;
  EXPECT_EQ(field_of(p), "base_wavelength");
  p = {};
  p.lacunarity = 1.0f;
  EXPECT_EQ(field_of(p), "lacunarity");
  p = {};
  p.max_octaves = 9;
  EXPECT_EQ(field_of(p), "max_octaves");
  p = {};
  p.animation_rate = NAN;
  EXPECT_EQ(field_of(p), "animation_rate");
  p = {};
  p.samples_per_wavelength = 0.5f;
  EXPECT_EQ(field_of(p), "samples_per_wavelength");
  p = {};
  EXPECT_EQ(field_of(p, INFINITY), "time");
  EXPECT_EQ(field_of(p, 0.0, NAN), "origin");
  p.max_octaves = 0;  // no octaves: a flat surface
  const CapillaryFrame f = noise_frame_of(p, 0.0);
  Samples s(3);
  s.level = {0.0f, 3.0f, 6.0f};
  s.eval(f);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(s.h[i], 0.0f);
}

// ---- Timing (printed, not asserted: performance lives in bench/) ----

TEST(Capillary, PrintsNanosecondsPerSample) {
  // Thread CPU time, best of 5: the machine may be shared. Not asserted.
  auto cpu_ns = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return 1e9 * double(ts.tv_sec) + double(ts.tv_nsec);
  };
  CapillaryParams p;
  const CapillaryFrame f = noise_frame_of(p, 3.0);
  std::mt19937 rng(37);
  // A screen-like walk: neighbouring samples are neighbouring points, as a marcher's are.
  Samples s(1 << 14);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.x[i] = -20.0f + 0.005f * float(i % 128) + 0.001f * float(rng() % 7);
    s.y[i] = 5.0f + 0.005f * float(i / 128);
  }
  for (float level : {6.0f, 2.0f}) {
    std::fill(s.level.begin(), s.level.end(), level);
    for (houle::Isa isa : {houle::Isa::scalar, houle::active_isa()}) {
      double best = 1e30, best_h = 1e30;
      for (int rep = 0; rep < 5; ++rep) {
        double t0 = cpu_ns();
        s.eval(isa, f);
        best = std::min(best, (cpu_ns() - t0) / double(s.size()));
        t0 = cpu_ns();
        houle::capillary_eval(isa, f, s.x.data(), s.y.data(), s.level.data(), s.size(), s.h.data(), nullptr, nullptr);
        best_h = std::min(best_h, (cpu_ns() - t0) / double(s.size()));
      }
      std::printf("capillary %s, level %.0f: %.2f ns/sample with gradient, %.2f height only\n",
                  houle::isa_name(isa).data(), level, best, best_h);
    }
  }
}

}  // namespace
