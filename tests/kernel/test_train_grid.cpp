#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "houle/surface/train_grid.hpp"
#include "ulp.hpp"

namespace {

/// A train's arrays and the grid that points into them.
struct Train {
  std::vector<float> phi, b_re, b_im, kx, ky, fold, lean;
  houle::TrainGrid grid;

  void bind() {
    grid.phi = phi.data();
    grid.b_re = b_re.data();
    grid.b_im = b_im.data();
    grid.kx = kx.data();
    grid.ky = ky.data();
    grid.fold = fold.data();
    grid.lean = lean.data();
  }
};

/// Straight crests of wavenumber k along `angle`, amplitude a, fold q and lean l (Q and L: per metre
/// of amplitude they are q / a and l / a) on an nx x ny grid; the far field is the same wave, so the
/// surface is one train everywhere.
Train uniform_train(double k, double angle, float a, float q, float l, std::uint32_t nx, std::uint32_t ny, float cell) {
  Train t;
  houle::TrainGrid& g = t.grid;
  g.origin_x = -0.5f * cell * float(nx - 1);
  g.origin_y = -0.5f * cell * float(ny - 1);
  g.cell = cell;
  g.nx = nx;
  g.ny = ny;
  g.far_kx = float(k * std::cos(angle));
  g.far_ky = float(k * std::sin(angle));
  g.far_amplitude = a;
  g.far_fold = q / a;
  g.far_lean = l / a;
  g.far_offset = 0.75;
  for (std::uint32_t j = 0; j < ny; ++j) {
    for (std::uint32_t i = 0; i < nx; ++i) {
      const double x = g.origin_x + double(i) * cell, y = g.origin_y + double(j) * cell;
      t.phi.push_back(float(g.far_kx * x + g.far_ky * y - g.far_offset));
      t.b_re.push_back(a);
      t.b_im.push_back(0.0f);
      t.kx.push_back(g.far_kx);
      t.ky.push_back(g.far_ky);
      t.fold.push_back(g.far_fold);
      t.lean.push_back(g.far_lean);
    }
  }
  t.bind();
  return t;
}

/// Independent random fields per node (|B| <= 1, fold and lean inside the fold-free disc).
Train random_train(std::mt19937& rng) {
  std::uniform_int_distribution<std::uint32_t> size(2, 40);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Train t;
  houle::TrainGrid& g = t.grid;
  g.nx = size(rng);
  g.ny = size(rng);
  g.cell = 0.2f + 2.0f * u(rng);
  g.origin_x = -20.0f * u(rng);
  g.origin_y = -20.0f * u(rng);
  g.far_kx = 0.1f + u(rng);
  g.far_ky = u(rng) - 0.5f;
  g.far_amplitude = u(rng);
  g.far_fold = 0.5f * u(rng);
  g.far_lean = 0.3f * u(rng);
  g.far_offset = 100.0 * u(rng);
  for (std::size_t n = 0; n < std::size_t(g.nx) * g.ny; ++n) {
    t.phi.push_back(200.0f * u(rng) - 100.0f);
    const float b = u(rng), arg = 6.2831853f * u(rng);
    t.b_re.push_back(b * std::cos(arg));
    t.b_im.push_back(b * std::sin(arg));
    t.kx.push_back(2.0f * u(rng) - 1.0f);
    t.ky.push_back(2.0f * u(rng) - 1.0f);
    const float r = 0.9f * u(rng), a = 6.2831853f * u(rng);
    t.fold.push_back(r * std::cos(a));
    t.lean.push_back(r * std::sin(a));
  }
  t.bind();
  return t;
}

struct Outputs {
  std::vector<float> h, gx, gy;
  explicit Outputs(std::size_t n) : h(n), gx(n), gy(n) {}
  houle::GerstnerOutput view() { return {h.data(), gx.data(), gy.data()}; }
};

houle::TrainGridFrame frame_of(const std::vector<houle::TrainGrid>& grids, double t) {
  houle::TrainGridFrame f;
  f.count = std::uint32_t(grids.size());
  f.trains = grids.data();
  std::vector<double> tau;
  for (std::size_t i = 0; i < grids.size(); ++i) tau.push_back(1.3 * double(i + 1) * t - 0.2);
  houle::set_train_grid_time(f, tau.data());
  return f;
}

/// `count` random trains, their grids and the scales of their sums' heights and slopes.
struct RandomTrains {
  std::vector<Train> trains;
  std::vector<houle::TrainGrid> grids;
  float height_scale = 0.0f, slope_scale = 0.0f;

  RandomTrains(std::mt19937& rng, int count) {
    for (int i = 0; i < count; ++i) trains.push_back(random_train(rng));
    for (const Train& t : trains) {
      grids.push_back(t.grid);
      height_scale += 1.0f;
      slope_scale += 2.0f * 1.5f + 2.0f / t.grid.cell;  // |B| <= 1, |k| <= sqrt 2, |dB| <= 2 / cell
    }
  }
};

/// The largest difference, in ulps of the scales, between `isa` and the scalar path at the points,
/// unfiltered and filtered (heights, gradients, the slope variance).
std::int64_t worst_ulps_against_scalar(houle::Isa isa, const houle::TrainGridFrame& frame, const houle::NodeFootprint& footprint,
                                       const std::vector<float>& x, const std::vector<float>& y, float height_scale,
                                       float slope_scale) {
  const std::size_t n = x.size();
  Outputs ref(n), got(n), fref(n), fgot(n);
  std::vector<float> vref(n), vgot(n);
  houle::train_grid_eval(houle::Isa::scalar, frame, x.data(), y.data(), n, ref.view());
  houle::train_grid_eval(isa, frame, x.data(), y.data(), n, got.view());
  houle::train_grid_eval(houle::Isa::scalar, frame, x.data(), y.data(), n, footprint, fref.view(), vref.data());
  houle::train_grid_eval(isa, frame, x.data(), y.data(), n, footprint, fgot.view(), vgot.data());
  std::int64_t worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    worst = std::max({worst, houle::test::ulps_of_scale(ref.h[i], got.h[i], height_scale),
                      houle::test::ulps_of_scale(ref.gx[i], got.gx[i], slope_scale),
                      houle::test::ulps_of_scale(ref.gy[i], got.gy[i], slope_scale),
                      houle::test::ulps_of_scale(fref.h[i], fgot.h[i], height_scale),
                      houle::test::ulps_of_scale(fref.gx[i], fgot.gx[i], slope_scale),
                      houle::test::ulps_of_scale(fref.gy[i], fgot.gy[i], slope_scale),
                      houle::test::ulps_of_scale(vref[i], vgot[i], slope_scale * slope_scale)});
  }
  return worst;
}

// The kernel uses only +, -, *, selects, exact conversions, gathers and (filtered) the correctly
// rounded simd::div and simd::sqrt: every ISA must give the scalar bits, tolerance 0, filtered or not.
TEST(TrainGrid, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-30.0f, 60.0f);  // inside and outside the grids
  const std::vector<std::size_t> sizes = {0, 1, 2, 3, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1000};
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (int trial = 0; trial < 12; ++trial) {
      const RandomTrains r(rng, 1 + trial % 4);
      const houle::TrainGridFrame frame = frame_of(r.grids, 0.37 * trial);
      // A viewer 1-6 m up among the points (or none) and cells of 0.5-3 m: weights from 0 to 1.
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      const houle::NodeFootprint footprint{0.5f + 2.5f * u(rng), trial % 3 == 0 ? 0.0f : 0.002f + 0.02f * u(rng),
                                           coord(rng), coord(rng), (trial % 2 ? 1.0f : -1.0f) * (1.0f + 5.0f * u(rng))};
      for (std::size_t n : sizes) {
        std::vector<float> x(n), y(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = coord(rng), y[i] = coord(rng);
        worst = std::max(worst, worst_ulps_against_scalar(isa, frame, footprint, x, y, r.height_scale, r.slope_scale));
      }
    }
    EXPECT_EQ(worst, 0) << "ISA " << houle::isa_name(isa);
    std::printf("train_grid %s vs scalar: max %lld ulp (tolerance 0)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst));
  }
}

// Rows of points as the surface frame fills them (one y, x a node spacing apart): a batch's cells lie
// within a window of the field, which AVX2 and AVX-512 read with loads and permutes instead of
// gathers. Spacings from a tenth of a cell to two cells cover windows that fit and ones that do not;
// rows on the grid's last cells put the window against the end of the arrays. Tolerance 0.
TEST(TrainGrid, RowsOfNodesMatchScalarOnEveryIsa) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::vector<std::size_t> sizes = {1, 3, 8 * 2 + 3, 16 * 3 + 3, 8 * 25 + 3};
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (int trial = 0; trial < 24; ++trial) {
      const RandomTrains r(rng, 1 + trial % 3);
      const houle::TrainGrid& g = r.grids[0];
      const houle::TrainGridFrame frame = frame_of(r.grids, 0.29 * trial);
      const houle::NodeFootprint footprint{0.25f + u(rng), trial % 4 == 0 ? 0.0f : 0.002f + 0.01f * u(rng),
                                           g.origin_x + 5.0f * u(rng), g.origin_y + 5.0f * u(rng), 2.0f + 4.0f * u(rng)};
      for (std::size_t n : sizes) {
        const float spacing = g.cell * (0.1f + 1.9f * u(rng) * u(rng));
        // From before the grid's start or inside it; the last rows' cells are the arrays' last.
        const float x0 = g.origin_x + g.cell * (float(g.nx) * u(rng) - 2.0f);
        const float y = trial % 2 ? g.origin_y + g.cell * (float(g.ny) - 1.0f - 0.5f * u(rng))
                                  : g.origin_y + g.cell * float(g.ny - 1) * u(rng);
        std::vector<float> x(n), ys(n, y);
        for (std::size_t i = 0; i < n; ++i) x[i] = x0 + float(i) * spacing;
        worst = std::max(worst, worst_ulps_against_scalar(isa, frame, footprint, x, ys, r.height_scale, r.slope_scale));
      }
    }
    EXPECT_EQ(worst, 0) << "ISA " << houle::isa_name(isa);
    std::printf("train_grid rows %s vs scalar: max %lld ulp (tolerance 0)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst));
  }
}

// What the fill keeps of a run (TrainGridKeep): written with the first frame's results and read back at
// other times and for other viewers, both give the bits of the evaluation without it, on every ISA, for
// rows of nodes as the frame fills them and for scattered points, with tails. A grid without nodes (the
// far field) is among the trains: its phase's constant changes with the time too. Tolerance 0.
TEST(TrainGrid, KeptFieldsGiveTheBitsOfTheGridsAtEveryTime) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), coord(-30.0f, 60.0f);
  const std::vector<std::size_t> sizes = {1, 3, 16, 8 * 2 + 3, 16 * 3 + 3, 8 * 25 + 3};
  for (houle::Isa isa : houle::supported_isas()) {
    int compared = 0;
    for (int trial = 0; trial < 8; ++trial) {
      RandomTrains r(rng, 1 + trial % 3);
      houle::TrainGrid far = r.grids[0];
      far.nx = far.ny = 0;
      far.far_offset = 0.7;
      r.grids.push_back(far);
      const houle::TrainGrid& g = r.grids[0];
      const houle::NodeFootprint footprint{0.25f + u(rng), trial % 4 == 0 ? 0.0f : 0.002f + 0.01f * u(rng),
                                           g.origin_x + 5.0f * u(rng), g.origin_y + 5.0f * u(rng), 2.0f + 4.0f * u(rng)};
      for (std::size_t n : sizes) {
        std::vector<float> x(n), y(n);
        const float x0 = g.origin_x + g.cell * (float(g.nx) * u(rng) - 2.0f), row_y = g.origin_y + g.cell * float(g.ny) * u(rng);
        const float spacing = g.cell * (0.1f + 1.9f * u(rng));
        for (std::size_t i = 0; i < n; ++i) {
          x[i] = trial % 2 ? x0 + float(i) * spacing : coord(rng);
          y[i] = trial % 2 ? row_y : coord(rng);
        }
        std::vector<float> keep((n + 15) / 16 * 16 * houle::train_grid_keep_floats(std::uint32_t(r.grids.size())));
        for (int step = 0; step < 3; ++step) {
          const houle::TrainGridFrame frame = frame_of(r.grids, 0.41 * trial + 1.7 * step);
          Outputs ref(n), got(n);
          std::vector<float> vref(n), vgot(n);
          // The viewer moves too: what is kept does not depend on it.
          houle::NodeFootprint seen = footprint;
          seen.eye_x += 3.0f * float(step);
          seen.eye_height += 0.5f * float(step);
          houle::train_grid_eval(isa, frame, x.data(), y.data(), n, seen, ref.view(), vref.data());
          houle::train_grid_eval(isa, frame, x.data(), y.data(), n, seen, got.view(), vgot.data(),
                                 {keep.data(), step > 0});
          for (std::size_t i = 0; i < n; ++i) {
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ref.h[i]), std::bit_cast<std::uint32_t>(got.h[i])) << step << " " << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ref.gx[i]), std::bit_cast<std::uint32_t>(got.gx[i])) << step << " " << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ref.gy[i]), std::bit_cast<std::uint32_t>(got.gy[i])) << step << " " << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(vref[i]), std::bit_cast<std::uint32_t>(vgot[i])) << step << " " << i;
          }
          compared += int(n);
        }
        // Kept means read: zeroed fields (no amplitude, no wave vector) give a flat sea.
        std::fill(keep.begin(), keep.end(), 0.0f);
        Outputs flat(n);
        std::vector<float> variance(n, 1.0f);
        houle::train_grid_eval(isa, frame_of(r.grids, 0.0), x.data(), y.data(), n, footprint, flat.view(), variance.data(),
                               {keep.data(), true});
        for (std::size_t i = 0; i < n; ++i) {
          ASSERT_EQ(flat.h[i], 0.0f);
          ASSERT_EQ(variance[i], 0.0f);
        }
      }
    }
    std::printf("train_grid kept %s: %d points, the same bits\n", houle::isa_name(isa).data(), compared);
  }
}

// A grid holding one straight-crested train is that train: the closed form in double, on the grid
// and off it (the far field), and the gradient is the derivative of the height.
TEST(TrainGrid, UniformGridIsTheClosedFormTrochoid) {
  const double k = 0.35, angle = 0.6, t = 4.2;
  const float a = 0.8f, q = 0.5f, l = 0.3f;
  const Train train = uniform_train(k, angle, a, q, l, 31, 23, 1.25f);
  const std::vector<houle::TrainGrid> grids = {train.grid};
  const houle::TrainGridFrame frame = frame_of(grids, t);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coord(-40.0f, 40.0f);
  double worst_h = 0.0, worst_g = 0.0;
  for (int i = 0; i < 4000; ++i) {
    const float x = coord(rng), y = coord(rng), e = 1e-2f;
    const float xs[5] = {x, x + e, x - e, x, x}, ys[5] = {y, y, y, y + e, y - e};
    Outputs o(5);
    houle::train_grid_eval(frame, xs, ys, 5, o.view());
    const double theta = k * (std::cos(angle) * x + std::sin(angle) * y) - 0.75 - (1.3 * t - 0.2);
    const double h = a * std::sin(theta - q * std::cos(theta) - l * std::sin(theta));
    worst_h = std::max(worst_h, std::fabs(o.h[0] - h));
    worst_g = std::max({worst_g, double(std::fabs((o.h[1] - o.h[2]) / (2 * e) - o.gx[0])),
                        double(std::fabs((o.h[3] - o.h[4]) / (2 * e) - o.gy[0]))});
  }
  std::printf("uniform train: max |h - closed form| %.3g m, max |grad - central difference| %.3g\n", worst_h, worst_g);
  EXPECT_LT(worst_h, 2e-5);  // float phases of ~15 rad: a few 1e-6 rad
  EXPECT_LT(worst_g, 2e-3);  // central difference error ~ e^2 k^3 A + float rounding / e
}

// Two sine waves of one frequency crossing at 70 degrees, held as one train: the first as the carrier,
// the second in B = a1 + a2 e^{i (k2 - k1) . x} (docs/physics.md 7). The grid gives their sum, to
// B's bilinear interpolation error (|k2 - k1| cell)^2 / 8 of a2, and the gradient is the height's.
TEST(TrainGrid, CrossingWavesInOneGridAreTheirSum) {
  const double k = 0.8, a1 = 0.5, a2 = 0.3, angle2 = 70.0 * 3.14159265358979 / 180.0;
  const float cell = 0.25f;
  Train t = uniform_train(k, 0.0, float(a1), 0.0f, 0.0f, 161, 161, cell);
  const houle::TrainGrid& g = t.grid;
  for (std::uint32_t j = 0; j < g.ny; ++j) {
    for (std::uint32_t i = 0; i < g.nx; ++i) {
      const double x = g.origin_x + double(i) * cell, y = g.origin_y + double(j) * cell;
      const double dphi = k * (std::cos(angle2) * x + std::sin(angle2) * y) - k * x;
      t.b_re[j * g.nx + i] = float(a1 + a2 * std::cos(dphi));
      t.b_im[j * g.nx + i] = float(a2 * std::sin(dphi));
    }
  }
  t.bind();
  const std::vector<houle::TrainGrid> grids = {t.grid};
  const double time = 1.7;
  const houle::TrainGridFrame frame = frame_of(grids, time);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> coord(-19.0f, 19.0f);
  double worst_h = 0.0, worst_g = 0.0;
  for (int n = 0; n < 4000; ++n) {
    const float x = coord(rng), y = coord(rng), e = 1e-3f;
    const float xs[5] = {x, x + e, x - e, x, x}, ys[5] = {y, y, y, y + e, y - e};
    Outputs o(5);
    houle::train_grid_eval(frame, xs, ys, 5, o.view());
    const double tau = 1.3 * time - 0.2 + 0.75;
    const double h = a1 * std::sin(k * x - tau) + a2 * std::sin(k * (std::cos(angle2) * x + std::sin(angle2) * y) - tau);
    worst_h = std::max(worst_h, std::fabs(o.h[0] - h));
    // Central differences inside one cell only (B's gradient steps at cell edges).
    const float u = (x - g.origin_x) / cell, v = (y - g.origin_y) / cell;
    if (std::fabs(u - std::round(u)) < 0.01f || std::fabs(v - std::round(v)) < 0.01f) continue;
    worst_g = std::max({worst_g, double(std::fabs((o.h[1] - o.h[2]) / (2 * e) - o.gx[0])),
                        double(std::fabs((o.h[3] - o.h[4]) / (2 * e) - o.gy[0]))});
  }
  const double dk = k * std::hypot(std::cos(angle2) - 1.0, std::sin(angle2));
  const double bound = a2 * dk * dk * cell * cell / 8.0;
  std::printf("crossing waves: max |h - sum| %.3g m (interpolation bound %.3g), max |grad - central difference| %.3g\n",
              worst_h, bound, worst_g);
  EXPECT_LT(worst_h, bound + 1e-5);
  EXPECT_LT(worst_g, 5e-3);  // float heights differenced over 2 mm: ~1e-7 / 2e-3
}

// The lean steepens the front face (the side the wave travels towards) and eases the back; no lean
// gives a symmetric profile.
TEST(TrainGrid, LeanSteepensTheFrontFace) {
  const double k = 0.5;
  auto steepest = [&](float lean) {
    const Train train = uniform_train(k, 0.0, 1.0f, 0.5f, lean, 2, 2, 1.0f);  // evaluated off the grid
    const std::vector<houle::TrainGrid> grids = {train.grid};
    const houle::TrainGridFrame frame = frame_of(grids, 0.0);
    float front = 0.0f, back = 0.0f;  // steepest descent (front) and ascent (back) along +x
    for (int i = 0; i < 4000; ++i) {
      const float x = 30.0f + float(i) * 0.01f, y = 0.0f;
      float h, gx, gy;
      houle::train_grid_eval(frame, &x, &y, 1, {&h, &gx, &gy});
      front = std::min(front, gx);
      back = std::max(back, gx);
    }
    return std::pair{-front, back};
  };
  const auto [front0, back0] = steepest(0.0f);
  const auto [front1, back1] = steepest(0.4f);
  std::printf("max slope front/back: no lean %.4f/%.4f, lean 0.4 %.4f/%.4f\n", front0, back0, front1, back1);
  EXPECT_NEAR(front0, back0, 1e-3 * back0);
  EXPECT_GT(front1, 1.2f * back1);
}

// What a node can hold (houle/surface/node_footprint.hpp), against the footprint worked out by hand:
// a viewer 10 m up at the origin with pixels of 0.01 rad sees the point (0, 100) at t = sqrt(10100) m,
// so its footprint is t 0.01 = 1.005 m across the view (x) and t^2 0.01 / 10 = 101 m along it (y).
// A wave is whole while its wavelength spans two footprints along its wave vector and gone at one;
// without a viewer, whole from four cells and gone at two.
TEST(TrainGrid, WavesFadeWhereTheFootprintCannotHoldThem) {
  const houle::NodeFootprint viewer{0.0f, 0.01f, 0.0f, 0.0f, 10.0f};
  const double across = 0.01 * std::sqrt(10100.0), along = 0.01 * 10100.0 / 10.0;
  const auto weight = [&](const houle::NodeFootprint& f, double wavelength, double angle) {
    const double k = 2.0 * 3.141592653589793 / wavelength;
    return houle::node_wave_weight(f, 0.0f, 100.0f, float(k * std::cos(angle)), float(k * std::sin(angle)));
  };
  for (double below : {0.999, 0.9, 0.5, 0.1}) {
    EXPECT_EQ(weight(viewer, 2.0 * across / below, 0.0), 1.0f);  // crests along the view: the width counts
    EXPECT_EQ(weight(viewer, 2.0 * along / below, 1.5707963), 1.0f);  // crests across it: the length
    EXPECT_EQ(weight(viewer, across * below, 0.0), 0.0f);
    EXPECT_EQ(weight(viewer, along * below, 1.5707963), 0.0f);
  }
  // In between, falling monotonically with the wavelength; and a wave across the view outlasts one
  // along it.
  float last = 1.0f;
  for (double r = 2.0; r >= 1.0; r -= 0.05) {
    const float w = weight(viewer, r * across, 0.0);
    EXPECT_LE(w, last);
    last = w;
  }
  EXPECT_EQ(weight(viewer, 3.0 * across, 0.0), 1.0f);
  EXPECT_EQ(weight(viewer, 3.0 * across, 1.5707963), 0.0f);
  const houle::NodeFootprint grid{0.5f, 0.0f, 0.0f, 0.0f, 10.0f};
  EXPECT_EQ(weight(grid, 2.001, 0.3), 1.0f);
  EXPECT_GT(weight(grid, 1.5, 0.3), 0.0f);
  EXPECT_LT(weight(grid, 1.5, 0.3), 1.0f);
  EXPECT_EQ(weight(grid, 0.999, 0.3), 0.0f);
  // A viewer at the height of the sea: |d_z| held at 1e-3 as in the marcher, nothing infinite.
  const houle::NodeFootprint level{0.0f, 0.01f, 0.0f, 0.0f, 0.0f};
  const double held = 0.01 * 100.0 / 1e-3;  // t theta / |d_z|, t = 100 m
  EXPECT_EQ(weight(level, 0.99 * held, 1.5707963), 0.0f);
  EXPECT_EQ(weight(level, 2.01 * held, 1.5707963), 1.0f);
  EXPECT_EQ(weight(level, 2.01 * 0.01 * 100.0, 0.0), 1.0f);
}

// The filtered eval is the train times its weight, and the slope variance it loses is the measured
// variance of the dropped slopes: for a sine train of amplitude a and wavenumber k, (k a)^2 / 2 along
// k, (k a)^2 / 4 per axis, times 1 - w^2 (w^2 of it is still drawn).
TEST(TrainGrid, AFadedTrainsSlopesGoIntoTheSlopeVariance) {
  const double k = 2.0 * 3.141592653589793 / 3.0, angle = 0.4;  // 3 m waves
  const float a = 0.1f;
  const Train train = uniform_train(k, angle, a, 0.0f, 0.0f, 41, 41, 0.5f);
  const std::vector<houle::TrainGrid> grids = {train.grid};
  const houle::TrainGridFrame frame = frame_of(grids, 1.3);
  // Points along one wavelength, on the grid and off it.
  constexpr std::size_t n = 1000;
  std::vector<float> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double s = 3.0 * (double(i) + 0.5) / double(n) + (i % 2 ? 0.0 : 30.0);
    x[i] = float(s * std::cos(angle));
    y[i] = float(s * std::sin(angle));
  }
  Outputs whole(n);
  houle::train_grid_eval(frame, x.data(), y.data(), n, whole.view());
  double measured = 0.0;
  for (std::size_t i = 0; i < n; ++i) measured += 0.5 * (double(whole.gx[i]) * whole.gx[i] + double(whole.gy[i]) * whole.gy[i]);
  measured /= double(n);
  EXPECT_NEAR(measured, (k * a) * (k * a) / 4.0, 1e-3 * measured);
  for (float cell : {0.5f, 1.0f, 1.4f, 2.0f}) {  // whole, fading, gone
    const houle::NodeFootprint f{cell, 0.0f, 0.0f, 0.0f, 5.0f};
    Outputs faded(n);
    std::vector<float> variance(n);
    houle::train_grid_eval(frame, x.data(), y.data(), n, f, faded.view(), variance.data());
    for (std::size_t i = 0; i < n; ++i) {
      const float w = houle::node_wave_weight(f, x[i], y[i], train.grid.far_kx, train.grid.far_ky);
      EXPECT_NEAR(faded.h[i], w * whole.h[i], 1e-6f) << cell;
      EXPECT_NEAR(faded.gx[i], w * whole.gx[i], 1e-6f) << cell;
      EXPECT_NEAR(faded.gy[i], w * whole.gy[i], 1e-6f) << cell;
      EXPECT_NEAR(variance[i], (1.0 - double(w) * w) * measured, 1e-3 * measured) << cell;
      if (w == 1.0f) {
        EXPECT_EQ(faded.h[i], whole.h[i]);  // bit for bit where nothing fades
        EXPECT_EQ(variance[i], 0.0f);
      }
    }
    const float w0 = houle::node_wave_weight(f, 0.0f, 0.0f, train.grid.far_kx, train.grid.far_ky);
    EXPECT_EQ(w0, cell == 0.5f ? 1.0f : cell == 2.0f ? 0.0f : w0) << cell;
    if (cell == 1.0f || cell == 1.4f) {
      EXPECT_GT(w0, 0.0f);
      EXPECT_LT(w0, 1.0f);
    }
  }
}

}  // namespace
