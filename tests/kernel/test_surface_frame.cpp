// SurfaceFrame: placement, fill, and the bounds the marcher relies on (they must really bound H).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "houle/surface/camera.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/surface/surface_frame.hpp"
#include "coastal_waves.hpp"

namespace {

using houle::SurfaceFrame;
using houle::SurfaceFrameConfig;

using houle::test::coastal_waves;

/// 4 levels of 128 cells.
SurfaceFrameConfig small_config() {
  SurfaceFrameConfig cfg;
  cfg.levels = 4;
  cfg.cells = 128;
  return cfg;
}

/// A SurfaceSampler of the GerstnerFrame its context points to, unfiltered.
void gerstner_sampler(void* c, const houle::SurfaceSamples& s) noexcept {
  houle::gerstner_eval(*static_cast<const houle::GerstnerFrame*>(c), s.x, s.y, s.n, {s.height, s.grad_x, s.grad_y});
  std::fill(s.slope_variance, s.slope_variance + s.n, 0.0f);
}

SurfaceFrame make_frame(const SurfaceFrameConfig& config = {}) {
  auto f = SurfaceFrame::create(config);
  EXPECT_TRUE(f.ok()) << f.error().field << ": " << f.error().message;
  return std::move(f.value());
}

TEST(SurfaceFrame, RejectsInvalidConfigs) {
  EXPECT_GT(SurfaceFrame::bytes_bound({}), 0u);
  const auto bad = [](auto change) {
    SurfaceFrameConfig c;
    change(c);
    EXPECT_EQ(SurfaceFrame::bytes_bound(c), 0u);
    return SurfaceFrame::create(c).ok();
  };
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.levels = 0; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.levels = 17; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.tile_cells = 12; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.cells = 100; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.cells = 48; }));  // < 4 tiles
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.finest_cell = 0.0f; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.finest_cell = NAN; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.blend_fraction = 0.0f; }));
  EXPECT_FALSE(bad([](SurfaceFrameConfig& c) { c.far_height = INFINITY; }));
  const auto e = SurfaceFrame::create(SurfaceFrameConfig{.levels = 0});
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().field, "surface.levels");
}

TEST(SurfaceFrame, LevelsSnapToTilesNestAndCoverTheirReach) {
  SurfaceFrameConfig cfg;
  SurfaceFrame f = make_frame(cfg);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> pos(-500.0f, 500.0f);
  for (int trial = 0; trial < 50; ++trial) {
    const float cx = pos(rng), cy = pos(rng);
    f.begin_frame(cx, cy);
    for (std::uint32_t l = 0; l < cfg.levels; ++l) {
      const houle::SurfaceLevel& s = f.level(l);
      const double cell = std::ldexp(double(cfg.finest_cell), int(l)), tile = cell * cfg.tile_cells;
      EXPECT_EQ(double(s.cell), cell);
      // Origins on the tile lattice: nodes at fixed world points whatever the camera does.
      EXPECT_EQ(std::fmod(double(s.origin_x), tile), 0.0);
      EXPECT_EQ(std::fmod(double(s.origin_y), tile), 0.0);
      // The reach square lies inside the grid (bilinear taps included).
      const double extent = cell * cfg.cells;
      EXPECT_LE(s.origin_x, cx - s.reach);
      EXPECT_GE(s.origin_x + extent, cx + s.reach + cell);
      EXPECT_LE(s.origin_y, cy - s.reach);
      EXPECT_GE(s.origin_y + extent, cy + s.reach + cell);
      if (l > 0) {
        EXPECT_EQ(s.reach, 2.0f * f.level(l - 1).reach);
        // The finer grid lies inside this one (blend partner and nested tile bounds).
        EXPECT_LE(s.origin_x, f.level(l - 1).origin_x);
        EXPECT_GE(s.origin_x + extent, f.level(l - 1).origin_x + extent / 2);
      }
    }
  }
}

/// Node (i, j) of level l belongs to a tile the fill covered.
bool node_filled(const SurfaceFrame& f, std::uint32_t l, std::size_t i, std::size_t j) {
  const std::size_t tc = f.config().tile_cells, nt = f.tiles_per_side();
  for (std::size_t tj : {j / tc, j / tc - (j % tc == 0 && j > 0 ? 1 : 0)}) {
    for (std::size_t ti : {i / tc, i / tc - (i % tc == 0 && i > 0 ? 1 : 0)}) {
      if (ti < nt && tj < nt && f.tile_filled(l, std::uint32_t(ti), std::uint32_t(tj))) return true;
    }
  }
  return false;
}

TEST(SurfaceFrame, GerstnerFillEqualsDirectEvaluationAtNodes) {
  // Every filled node holds gerstner_eval's bits, except in each level's outer band, where it holds
  // the morph h + w (p - h) toward the next level's bilinear surface p (w = smoothstep of the
  // Chebyshev distance across the band, reaching 1 a cell before the level's reach).
  SurfaceFrameConfig cfg = small_config();
  SurfaceFrame f = make_frame(cfg);
  const auto waves = coastal_waves();
  const auto frame = houle::make_gerstner_frame(waves, 12.25);
  ASSERT_TRUE(frame.ok());
  const float cx = 13.7f, cy = -41.2f;
  const auto direct = [&](houle::Isa isa, float x, float y, float out[3]) {
    houle::gerstner_eval(isa, frame.value(), &x, &y, 1, {&out[0], &out[1], &out[2]});
  };
  for (houle::Isa isa : houle::supported_isas()) {
    f.begin_frame(cx, cy);
    houle::fill_gerstner(isa, f, frame.value());
    const std::size_t n = cfg.cells + 1;
    std::vector<float> x(n), y(n), h(n), gx(n), gy(n);
    std::size_t mismatches = 0, checked = 0, morphed = 0;
    double worst_morph = 0.0;
    for (std::uint32_t l = 0; l < cfg.levels; ++l) {
      const houle::SurfaceLevel& s = f.level(l);
      const float band_end = s.reach - s.cell, band_start = band_end - cfg.blend_fraction * s.reach;
      for (std::size_t j = 0; j < n; j += 7) {
        for (std::size_t i = 0; i < n; ++i) x[i] = s.origin_x + float(i) * s.cell, y[i] = s.origin_y + float(j) * s.cell;
        houle::gerstner_eval(isa, frame.value(), x.data(), y.data(), n, {h.data(), gx.data(), gy.data()});
        for (std::size_t i = 0; i < n; ++i) {
          if (!node_filled(f, l, i, j)) continue;
          ++checked;
          const std::size_t k = j * f.stride() + i;
          const float stored[3] = {f.heights(l)[k], f.grad_x(l)[k], f.grad_y(l)[k]};
          const float raw[3] = {h[i], gx[i], gy[i]};
          const float r = std::max(std::fabs(x[i] - cx), std::fabs(y[i] - cy));
          if (!(r > band_start)) {
            mismatches += stored[0] != raw[0] || stored[1] != raw[1] || stored[2] != raw[2];
            continue;
          }
          // The partner's bilinear value from direct evaluations at its cell's corners.
          ++morphed;
          const float v = std::min((r - band_start) / (band_end - band_start), 1.0f), w = v * v * (3 - 2 * v);
          float p[3] = {cfg.far_height, 0.0f, 0.0f};
          if (l + 1 < cfg.levels) {
            const houle::SurfaceLevel& q = f.level(l + 1);
            const float u = (x[i] - q.origin_x) / q.cell, t = (y[i] - q.origin_y) / q.cell;
            const float u0 = std::floor(u), t0 = std::floor(t), fu = u - u0, ft = t - t0;
            float c00[3], c10[3], c01[3], c11[3];
            direct(isa, q.origin_x + u0 * q.cell, q.origin_y + t0 * q.cell, c00);
            direct(isa, q.origin_x + (u0 + 1) * q.cell, q.origin_y + t0 * q.cell, c10);
            direct(isa, q.origin_x + u0 * q.cell, q.origin_y + (t0 + 1) * q.cell, c01);
            direct(isa, q.origin_x + (u0 + 1) * q.cell, q.origin_y + (t0 + 1) * q.cell, c11);
            for (int e = 0; e < 3; ++e) {
              const float a = c00[e] + fu * (c10[e] - c00[e]), b = c01[e] + fu * (c11[e] - c01[e]);
              p[e] = a + ft * (b - a);
            }
          }
          for (int e = 0; e < 3; ++e) worst_morph = std::max(worst_morph, std::fabs(double(stored[e]) - (raw[e] + w * (p[e] - raw[e]))));
        }
      }
    }
    EXPECT_EQ(mismatches, 0u) << houle::isa_name(isa);
    EXPECT_LT(worst_morph, 1e-6) << houle::isa_name(isa);
    EXPECT_GT(morphed, 100u);
    EXPECT_GT(checked, std::size_t(cfg.levels) * n * n / 7 / 2);  // most nodes are filled
  }
}

// Fills the frame, then checks every level's tiles against the surface the marcher samples.
struct BoundsCheck {
  std::size_t samples = 0, height_violations = 0, slope_violations = 0;
  double worst_slope_use = 0.0;  // max over segments of |dH| / bound (<= 1)
};

BoundsCheck check_bounds(const SurfaceFrame& f, std::mt19937& rng, int per_tile) {
  const auto& cfg = f.config();
  BoundsCheck r;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float cx = f.view().centre_x, cy = f.view().centre_y;
  for (std::uint32_t l = 0; l < cfg.levels; ++l) {
    const houle::SurfaceLevel& s = f.level(l);
    const float tile = s.cell * float(cfg.tile_cells);
    for (std::uint32_t tj = 0; tj < f.tiles_per_side(); ++tj) {
      for (std::uint32_t ti = 0; ti < f.tiles_per_side(); ++ti) {
        const houle::TileBounds b = f.tile(l, ti, tj);
        const float x0 = s.origin_x + float(ti) * tile, y0 = s.origin_y + float(tj) * tile;
        // The bounds hold over the tile within the level's reach (finer levels inside it included).
        const float lo_x = std::max(x0, cx - s.reach), hi_x = std::min(x0 + tile, cx + s.reach);
        const float lo_y = std::max(y0, cy - s.reach), hi_y = std::min(y0 + tile, cy + s.reach);
        if (!(lo_x < hi_x && lo_y < hi_y)) continue;
        for (int k = 0; k < per_tile; ++k) {
          const float ax = lo_x + u(rng) * (hi_x - lo_x), ay = lo_y + u(rng) * (hi_y - lo_y);
          // A short segment inside the same region, sometimes along an axis, sometimes across cells.
          const float len = (k % 3 == 0 ? 0.02f : 1.5f) * s.cell;
          const float bx = std::clamp(ax + len * (2 * u(rng) - 1), lo_x, hi_x);
          const float by = std::clamp(ay + len * (2 * u(rng) - 1), lo_y, hi_y);
          const float ha = f.height_at(ax, ay), hb = f.height_at(bx, by);
          ++r.samples;
          r.height_violations += !(ha >= b.h_min && ha <= b.h_max);
          const double bound = b.slope_x * std::fabs(double(bx) - ax) + b.slope_y * std::fabs(double(by) - ay);
          // 1e-6 m: the rounding of two float bilinear evaluations.
          if (std::fabs(double(hb) - ha) > bound + 1e-6) ++r.slope_violations;
          if (bound > 1e-4) r.worst_slope_use = std::max(r.worst_slope_use, std::fabs(double(hb) - ha) / bound);
        }
      }
    }
  }
  return r;
}

TEST(SurfaceFrame, TileBoundsBoundTheMorphedBilinearSurface) {
  SurfaceFrameConfig cfg;
  cfg.levels = 5;
  cfg.cells = 128;
  cfg.tile_cells = 8;
  SurfaceFrame f = make_frame(cfg);
  const auto frame = houle::make_gerstner_frame(coastal_waves(), 3.0);
  ASSERT_TRUE(frame.ok());
  std::mt19937 rng(11);
  for (int trial = 0; trial < 3; ++trial) {
    f.begin_frame(7.3f * float(trial) - 2.0f, -3.1f * float(trial) + 1.0f);
    houle::fill_gerstner(f, frame.value());
    const BoundsCheck r = check_bounds(f, rng, 24);
    EXPECT_EQ(r.height_violations, 0u);
    EXPECT_EQ(r.slope_violations, 0u);
    EXPECT_LE(r.worst_slope_use, 1.0);
    std::printf("tile bounds: %zu samples, worst |dH| / slope bound %.3f\n", r.samples, r.worst_slope_use);
  }
}

TEST(SurfaceFrame, SlabBoundsEverySampleIncludingFarPlaneAndNoise) {
  SurfaceFrameConfig cfg = small_config();
  cfg.far_height = 0.0f;
  SurfaceFrame f = make_frame(cfg);
  const auto frame = houle::make_gerstner_frame(coastal_waves(), 8.0);
  ASSERT_TRUE(frame.ok());
  f.begin_frame(-20.0f, 35.0f);
  houle::fill_gerstner(f, frame.value());
  std::mt19937 rng(2);
  const float reach = f.level(cfg.levels - 1).reach;
  std::uniform_real_distribution<float> d(-1.5f * reach, 1.5f * reach);
  float lo = 1e9f, hi = -1e9f;
  for (int i = 0; i < 200000; ++i) {
    const float h = f.height_at(-20.0f + d(rng), 35.0f + d(rng));
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  EXPECT_GE(lo, f.z_min());
  EXPECT_LE(hi, f.z_max());
  // Not absurdly loose: the slab is within the sum of amplitudes (1.2 m) plus margins.
  EXPECT_GT(f.z_min(), -1.25f);
  EXPECT_LT(f.z_max(), 1.25f);
  std::printf("slab [%.4f, %.4f] m, samples [%.4f, %.4f] m\n", f.z_min(), f.z_max(), lo, hi);
  const float z0 = f.z_min(), z1 = f.z_max(), g = f.slope_bound();
  f.set_noise_bounds(0.05f, 2.0f);
  EXPECT_EQ(f.z_min(), z0 - 0.05f);
  EXPECT_EQ(f.z_max(), z1 + 0.05f);
  EXPECT_EQ(f.slope_bound(), g + 2.0f);
}

TEST(SurfaceFrame, FillEqualsFinishFrameAndIsDeterministic) {
  SurfaceFrameConfig cfg;
  cfg.levels = 5;
  cfg.cells = 128;
  SurfaceFrame a = make_frame(cfg), b = make_frame(cfg);
  const auto frame = houle::make_gerstner_frame(coastal_waves(), 1.0);
  ASSERT_TRUE(frame.ok());
  a.begin_frame(3.0f, 4.0f);
  houle::fill_gerstner(a, frame.value());
  // b: a different frame first (state must not carry over), then the same one, bounds recomputed.
  b.begin_frame(-100.0f, 50.0f);
  houle::fill_gerstner(b, frame.value());
  b.begin_frame(3.0f, 4.0f);
  houle::fill_gerstner(b, frame.value());
  b.finish_frame();
  for (std::uint32_t l = 0; l < cfg.levels; ++l) {
    for (std::uint32_t j = 0; j < a.tiles_per_side(); ++j) {
      for (std::uint32_t i = 0; i < a.tiles_per_side(); ++i) {
        const houle::TileBounds x = a.tile(l, i, j), y = b.tile(l, i, j);
        ASSERT_EQ(x.h_min, y.h_min);
        ASSERT_EQ(x.h_max, y.h_max);
        ASSERT_EQ(x.slope_x, y.slope_x);
        ASSERT_EQ(x.slope_y, y.slope_y);
      }
    }
  }
  EXPECT_EQ(a.z_min(), b.z_min());
  EXPECT_EQ(a.z_max(), b.z_max());
}

// Each run of nodes is told its level's cell and, after set_viewer (until the next begin_frame), the
// camera's pixel angle, ground point and height over the far plane (the mean sea).
TEST(SurfaceFrame, SamplersAreToldWhatTheNodesCanHold) {
  SurfaceFrameConfig cfg;
  cfg.levels = 3;
  cfg.cells = 64;
  cfg.far_height = 0.5f;
  SurfaceFrame f = make_frame(cfg);
  struct Seen {
    std::vector<houle::NodeFootprint> runs;
  } seen;
  const auto sampler = [](void* c, const houle::SurfaceSamples& s) noexcept {
    auto& r = *static_cast<Seen*>(c);
    r.runs.push_back(s.footprint);
    std::fill(s.height, s.height + s.n, 0.0f);
    std::fill(s.grad_x, s.grad_x + s.n, 0.0f);
    std::fill(s.grad_y, s.grad_y + s.n, 0.0f);
    std::fill(s.slope_variance, s.slope_variance + s.n, 0.0f);
  };
  auto cam = houle::make_camera({{3.0f, 4.0f, 12.0f}, {3.0f, 40.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 1.0f, 320, 180});
  ASSERT_TRUE(cam.ok());
  for (bool viewer : {true, false}) {
    f.begin_frame(3.0f, 4.0f);
    if (viewer) f.set_viewer(cam.value());
    seen.runs.clear();
    f.fill(sampler, &seen);
    ASSERT_FALSE(seen.runs.empty());
    std::vector<bool> level_seen(cfg.levels, false);
    for (const houle::NodeFootprint& r : seen.runs) {
      std::uint32_t l = 0;
      while (l < cfg.levels && f.level(l).cell != r.cell) ++l;
      ASSERT_LT(l, cfg.levels) << "a run with the cell of no level: " << r.cell;
      level_seen[l] = true;
      if (viewer) {
        EXPECT_EQ(r.pixel_angle, cam.value().pixel_angle);
        EXPECT_EQ(r.eye_x, 3.0f);
        EXPECT_EQ(r.eye_y, 4.0f);
        EXPECT_EQ(r.eye_height, 11.5f);
      } else {
        EXPECT_EQ(r.pixel_angle, 0.0f);  // begin_frame forgot the viewer
      }
    }
    EXPECT_EQ(std::count(level_seen.begin(), level_seen.end(), true), int(cfg.levels));
  }
}

// The fill, the morph and the tiles' bounds split into parts (as Renderer::fill_surface runs them on
// its threads), parts run in any order, give the very frame of the one-piece fill: nodes, morph and
// bounds.
TEST(SurfaceFrame, FillInPartsEqualsTheWholeFill) {
  SurfaceFrameConfig cfg = small_config();
  const auto waves = houle::make_gerstner_frame(coastal_waves(), 2.5);
  ASSERT_TRUE(waves.ok());
  SurfaceFrame whole = make_frame(cfg);
  whole.begin_frame(7.0f, -3.0f);
  houle::fill_gerstner(whole, waves.value());
  for (unsigned parts : {2u, 3u, SurfaceFrame::max_fill_parts}) {
    SurfaceFrame split = make_frame(cfg);
    split.begin_frame(7.0f, -3.0f);
    split.begin_fill(gerstner_sampler, const_cast<houle::GerstnerFrame*>(&waves.value()));
    for (unsigned p = parts; p-- > 0;) split.fill_part(gerstner_sampler, const_cast<houle::GerstnerFrame*>(&waves.value()), p, parts);
    for (unsigned p = parts; p-- > 0;) split.morph_part(p, parts);
    for (unsigned p = 0; p < parts; ++p) split.bound_part(p, parts);
    split.finish_frame();
    const std::size_t floats = (cfg.cells + 1) * whole.stride();
    for (std::uint32_t l = 0; l < cfg.levels; ++l) {
      for (std::size_t k = 0; k < floats; ++k) {
        ASSERT_EQ(whole.heights(l)[k], split.heights(l)[k]) << parts << " parts, level " << l << " float " << k;
        ASSERT_EQ(whole.grad_x(l)[k], split.grad_x(l)[k]);
        ASSERT_EQ(whole.grad_y(l)[k], split.grad_y(l)[k]);
      }
      for (std::uint32_t j = 0; j < whole.tiles_per_side(); ++j) {
        for (std::uint32_t i = 0; i < whole.tiles_per_side(); ++i) {
          ASSERT_EQ(whole.tile(l, i, j).h_min, split.tile(l, i, j).h_min);
          ASSERT_EQ(whole.tile(l, i, j).h_max, split.tile(l, i, j).h_max);
          ASSERT_EQ(whole.tile(l, i, j).slope_x, split.tile(l, i, j).slope_x);
          ASSERT_EQ(whole.tile(l, i, j).slope_y, split.tile(l, i, j).slope_y);
        }
      }
    }
    EXPECT_EQ(whole.z_min(), split.z_min());
    EXPECT_EQ(whole.z_max(), split.z_max());
  }
}

/// A sampler that keeps one float per node (x / 2 + y / 4 + the cell: what a run's nodes are) and
/// counts how each run was offered the keep.
struct KeepProbe {
  int off = 0, write = 0, read = 0;
  bool mismatch = false;
};
void keep_probe_sampler(void* c, const houle::SurfaceSamples& s) noexcept {
  KeepProbe& p = *static_cast<KeepProbe*>(c);
  ++(s.keep == nullptr ? p.off : s.kept ? p.read : p.write);
  for (std::size_t i = 0; i < s.n; ++i) {
    const float node = 0.5f * s.x[i] + 0.25f * s.y[i] + s.footprint.cell;
    if (s.keep != nullptr && !s.kept) s.keep[i] = node;
    if (s.keep != nullptr && s.kept && s.keep[i] != node) p.mismatch = true;
    s.height[i] = s.grad_x[i] = s.grad_y[i] = s.slope_variance[i] = 0.0f;
  }
}

// keep_static, node by node: a fill offers the sampler nothing at a level's new origin, then room to
// write where its nodes are new and what it wrote, at the same nodes, from the next fill on, whatever
// the viewer; another context starts over, a camera walking along or turning round reuses the nodes
// it has seen, and what does not fit the memory keeps nothing.
TEST(SurfaceFrame, KeepsTheStaticPartForTheFillsOfOneLayout) {
  SurfaceFrame f = make_frame(small_config());
  f.keep_static(1);
  const auto cam = [](float x, float y, float z, float dx = 20.0f, float dy = 30.0f) {
    auto c = houle::make_camera({{x, y, z}, {x + dx, y + dy, 0.0f}, {0.0f, 0.0f, 1.0f}, 1.0f, 160, 90});
    EXPECT_TRUE(c.ok());
    return c.value();
  };
  KeepProbe a, b;
  // 'o', 'w', 'r': every run offered nothing, room to write, what was written; '?': a mix.
  const auto fill = [&](const houle::Camera& c, KeepProbe& probe, const houle::Camera* viewer = nullptr) {
    probe = {};
    f.begin_frame(c.position[0], c.position[1]);
    f.restrict_to_view(c);
    f.set_viewer(viewer != nullptr ? *viewer : c);
    f.fill(keep_probe_sampler, &probe);
    EXPECT_FALSE(probe.mismatch);
    return probe.off > 0 && probe.write == 0 && probe.read == 0   ? 'o'
           : probe.write > 0 && probe.off == 0 && probe.read == 0 ? 'w'
           : probe.read > 0 && probe.off == 0 && probe.write == 0 ? 'r'
                                                                  : '?';
  };
  std::string modes;
  for (int k = 0; k < 4; ++k) modes += fill(cam(3.0f, 4.0f, 10.0f), a);
  const houle::Camera raised = cam(3.0f, 4.0f, 14.0f);
  modes += fill(cam(3.0f, 4.0f, 10.0f), a, &raised);  // another viewer, the same nodes
  for (int k = 0; k < 3; ++k) modes += fill(cam(5003.0f, 4.0f, 10.0f), a);  // every level moved
  for (int k = 0; k < 3; ++k) modes += fill(cam(5003.0f, 4.0f, 10.0f), b);  // another context
  EXPECT_EQ(modes, "owrrrowrowr");
  // Turned round at the same point: other tiles are written, those seen before read; turned back,
  // nearly every run is read (a run's last node leaves what the sampler wrote past it in the next
  // tile's first 16 nodes, so a run that needs those again writes them again).
  modes.clear();
  for (int k = 0; k < 3; ++k) modes += fill(cam(5003.0f, 4.0f, 10.0f, -20.0f, -30.0f), b);
  EXPECT_TRUE(modes[0] == 'w' || modes[0] == '?') << modes;
  EXPECT_EQ(modes.substr(1), "rr");
  fill(cam(5003.0f, 4.0f, 10.0f), b);
  EXPECT_EQ(b.off, 0);
  EXPECT_GT(b.read, 4 * b.write);
  // Walking 0.5 m a frame: the coarse levels are read while the fine ones move on.
  int reads = 0, runs = 0;
  for (int k = 0; k < 24; ++k) {
    fill(cam(5003.0f + 0.5f * float(k), 4.0f, 10.0f), b);
    reads += b.read;
    runs += b.off + b.write + b.read;
  }
  EXPECT_GT(reads, runs / 2);
  EXPECT_LT(reads, runs);
  std::printf("walking: %d of %d runs read\n", reads, runs);
  // Too many floats per node for a level's share of max_kept_bytes: never written.
  f.keep_static(std::size_t(1) << 20);
  EXPECT_EQ(SurfaceFrame::kept_bytes_bound(small_config(), std::size_t(1) << 20), 0u);
  modes.clear();
  for (int k = 0; k < 3; ++k) modes += fill(cam(3.0f, 4.0f, 10.0f), a);
  EXPECT_EQ(modes, "ooo");
  f.keep_static(0);
  modes.clear();
  for (int k = 0; k < 3; ++k) modes += fill(cam(3.0f, 4.0f, 10.0f), a);
  EXPECT_EQ(modes, "ooo");
}

// restrict_to_view with a slab keeps, of the tiles begin_frame marks, every one that holds a point a
// camera ray can sample in the slab (corners of the image included) and the camera's own point; a
// view straight down then fills a small part of them, and a view of the horizon its wedge as before.
TEST(SurfaceFrame, RestrictionToTheViewsSliceOfTheSlabKeepsEveryTileARaySamples) {
  const SurfaceFrameConfig cfg;  // the defaults: 8 levels
  SurfaceFrame all = make_frame(cfg), part = make_frame(cfg), wedge = make_frame(cfg);
  const float z_lo = -1.5f, z_hi = 2.0f;
  struct Look {
    float px, py, pz, dx, dy, dz, most_filled;
  };
  const Look looks[] = {
      {120.0f, 100.0f, 120.0f, 0.1f, 0.0f, -1.0f, 0.4f},     // straight down, high (34 %)
      {3.0f, -4.0f, 6.0f, 0.05f, 0.05f, -1.0f, 0.02f},       // straight down, low (1 %)
      {-50.0f, 20.0f, 40.0f, 30.0f, 17.0f, -40.0f, 0.2f},    // steeply down, turned (17 %)
      {7.0f, 9.0f, 0.5f, 1.0f, -2.0f, -0.6f, 0.35f},         // in the slab, the top corners up: the wedge (32 %)
      {7.0f, 9.0f, -6.0f, -1.0f, 3.0f, 4.0f, 0.05f},         // under the slab, looking up (3 %)
      {7.0f, 9.0f, 6.0f, 100.0f, 40.0f, -3.0f, 0.35f},       // the horizon: the wedge (29 %)
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const double tc = cfg.tile_cells;
  // The tile of level l holding (x, y); false outside the level's grid.
  const auto tile_of = [&](const SurfaceFrame& f, std::uint32_t l, double x, double y, std::uint32_t& ti, std::uint32_t& tj) {
    const houle::SurfaceLevel& s = f.level(l);
    const double i = std::floor((x - s.origin_x) / (tc * s.cell)), j = std::floor((y - s.origin_y) / (tc * s.cell));
    if (i < 0.0 || j < 0.0 || i >= f.tiles_per_side() || j >= f.tiles_per_side()) return false;
    ti = std::uint32_t(i);
    tj = std::uint32_t(j);
    return true;
  };
  for (const Look& look : looks) {
    houle::CameraParams cp;
    cp.position = {look.px, look.py, look.pz};
    cp.look_at = {look.px + look.dx, look.py + look.dy, look.pz + look.dz};
    if (std::fabs(look.dz) > 10.0f * std::hypot(look.dx, look.dy)) cp.up = {0.0f, 1.0f, 0.0f};  // straight down or up
    cp.width = 640;
    cp.height = 360;
    const auto cam = houle::make_camera(cp);
    ASSERT_TRUE(cam.ok());
    all.begin_frame(look.px, look.py);
    part.begin_frame(look.px, look.py);
    part.restrict_to_view(cam.value(), z_lo, z_hi);
    wedge.begin_frame(look.px, look.py);
    wedge.restrict_to_view(cam.value());
    std::size_t marked = 0, filled = 0, wedge_filled = 0;
    for (std::uint32_t l = 0; l < cfg.levels; ++l) {
      for (std::uint32_t j = 0; j < part.tiles_per_side(); ++j) {
        for (std::uint32_t i = 0; i < part.tiles_per_side(); ++i) {
          marked += all.tile_filled(l, i, j);
          filled += part.tile_filled(l, i, j);
          wedge_filled += wedge.tile_filled(l, i, j);
          EXPECT_TRUE(all.tile_filled(l, i, j) || !part.tile_filled(l, i, j));
        }
      }
    }
    const auto check = [&](double x, double y, const char* what) {
      for (std::uint32_t l = 0; l < cfg.levels; ++l) {
        std::uint32_t ti, tj;
        if (!tile_of(all, l, x, y, ti, tj) || !all.tile_filled(l, ti, tj)) continue;
        ASSERT_TRUE(part.tile_filled(l, ti, tj)) << what << " (" << x << ", " << y << ") level " << l << ", look "
                                                 << look.dx << " " << look.dy << " " << look.dz;
      }
    };
    check(look.px, look.py, "the camera's point");
    for (int k = 0; k < 4000; ++k) {
      const float ix = k < 4 ? float(k & 1) * 640.0f : u(rng) * 640.0f, iy = k < 4 ? float(k >> 1) * 360.0f : u(rng) * 360.0f;
      const auto d = houle::camera_ray(cam.value(), ix, iy);
      if (d[2] == 0.0f) continue;
      const double ta = (double(z_lo) - look.pz) / d[2], tb = (double(z_hi) - look.pz) / d[2];
      const double t1 = std::max(ta, tb), t0 = std::max(0.0, std::min(ta, tb));
      if (t1 < 0.0) continue;
      const double t = t0 + (t1 - t0) * (k % 3 == 0 ? double(k % 2) : double(u(rng)));
      check(look.px + t * d[0], look.py + t * d[1], "a sample");
    }
    std::printf("look %g %g %g: %zu of %zu tiles, the wedge %zu\n", look.dx, look.dy, look.dz, filled, marked, wedge_filled);
    EXPECT_LE(double(filled), look.most_filled * double(marked)) << look.dx << " " << look.dy << " " << look.dz;
    EXPECT_LE(filled, wedge_filled);
  }
}

// The marcher reads a cell's two nodes of a row as one pair (SurfaceFrameView::height_pairs): for every
// cell of every filled tile, both rows' pairs hold the final (morphed) heights, after a fill restricted
// to the view in one part or in several.
TEST(SurfaceFrame, HeightPairsHoldTheHeightsOfEveryFilledCell) {
  SurfaceFrameConfig cfg = small_config();
  const auto waves = houle::make_gerstner_frame(coastal_waves(), 1.5);
  ASSERT_TRUE(waves.ok());
  // Looking north, then south: the view's edge among the tile rows lies on either side of the camera.
  for (unsigned parts : {1u, 3u}) {
    const float north = parts == 1 ? 1.0f : -1.0f;
    auto cam = houle::make_camera({{3.0f, 4.0f, 12.0f}, {3.0f, 4.0f + 36.0f * north, 0.0f}, {0.0f, 0.0f, 1.0f}, 1.0f, 320, 180});
    ASSERT_TRUE(cam.ok());
    SurfaceFrame f = make_frame(cfg);
    f.begin_frame(3.0f, 4.0f);
    f.restrict_to_view(cam.value());
    f.begin_fill(gerstner_sampler, const_cast<houle::GerstnerFrame*>(&waves.value()));
    for (unsigned p = 0; p < parts; ++p) f.fill_part(gerstner_sampler, const_cast<houle::GerstnerFrame*>(&waves.value()), p, parts);
    for (unsigned p = 0; p < parts; ++p) f.morph_part(p, parts);
    for (unsigned p = 0; p < parts; ++p) f.bound_part(p, parts);
    f.finish_frame();
    const houle::SurfaceFrameView v = f.view();
    const std::uint32_t tc = cfg.tile_cells;
    std::size_t cells = 0, filled = 0;
    for (std::uint32_t l = 0; l < cfg.levels; ++l) {
      const float* h = f.heights(l);
      const float* pairs = v.height_pairs + 2 * l * v.level_floats;
      for (std::uint32_t tj = 0; tj < v.tiles_per_side; ++tj) {
        for (std::uint32_t ti = 0; ti < v.tiles_per_side; ++ti) {
          if (!f.tile_filled(l, ti, tj)) continue;
          ++filled;
          for (std::uint32_t j = tj * tc; j <= (tj + 1) * tc; ++j) {
            for (std::uint32_t i = ti * tc; i < (ti + 1) * tc; ++i, ++cells) {
              const std::size_t k = j * v.stride + i;
              ASSERT_EQ(pairs[2 * k], h[k]) << parts << " parts, level " << l << " node " << i << ", " << j;
              ASSERT_EQ(pairs[2 * k + 1], h[k + 1]) << parts << " parts, level " << l << " node " << i << ", " << j;
            }
          }
        }
      }
    }
    EXPECT_LT(filled, std::size_t(cfg.levels) * v.tiles_per_side * v.tiles_per_side);  // the view left tiles out
    EXPECT_GT(cells, 0u);
  }
}

TEST(SurfaceFrame, SurfaceIsContinuousAcrossLevelsAndInTheCameraPosition) {
  // No popping: H(x, y) changes by O(epsilon) when the point or the camera moves by epsilon, including
  // across reach boundaries, blend bands and tile snapping of the grids.
  SurfaceFrameConfig cfg;
  cfg.levels = 5;
  cfg.cells = 128;
  SurfaceFrame a = make_frame(cfg), b = make_frame(cfg);
  const auto frame = houle::make_gerstner_frame(coastal_waves(), 6.0);
  ASSERT_TRUE(frame.ok());
  const float cx = 0.37f, cy = -0.81f;
  a.begin_frame(cx, cy);
  houle::fill_gerstner(a, frame.value());
  // Moved by 1 mm: across a tile-snap boundary of level 0 if there is one nearby, since 1 mm is tiny.
  const float eps = 1e-3f;
  b.begin_frame(cx + eps, cy - eps);
  houle::fill_gerstner(b, frame.value());
  double worst_move = 0.0, worst_step = 0.0;
  for (std::uint32_t l = 0; l < cfg.levels; ++l) {
    // Along a ray from the centre through every band and boundary of every level.
    const float reach = a.level(l).reach;
    for (int k = 0; k <= 4000; ++k) {
      const float r = reach * (0.45f + 0.6f * float(k) / 4000.0f);
      const float x = cx + r * 0.8f, y = cy + r * 0.6f;
      worst_move = std::max(worst_move, std::fabs(double(a.height_at(x, y)) - b.height_at(x, y)));
      const float dh = a.height_at(x + eps, y) - a.height_at(x, y);
      worst_step = std::max(worst_step, std::fabs(double(dh)));
    }
  }
  std::printf("camera moved 1.4 mm: max |dH| %.2e m; point moved 1 mm: max |dH| %.2e m\n", worst_move, worst_step);
  EXPECT_LT(worst_move, 2e-4);
  EXPECT_LT(worst_step, 2e-3);
}

}  // namespace
