#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "carrier_march.hpp"

namespace {

constexpr int moves[16][2] = {{1, 0}, {-1, 0}, {0, 1},   {0, -1},  {1, 1},  {1, -1},  {-1, 1}, {-1, -1},
                              {2, 1}, {2, -1}, {-2, 1}, {-2, -1}, {1, 2}, {1, -2}, {-1, 2}, {-1, -2}};

struct Grid {
  std::size_t nx, ny;
  double cell;
  std::vector<float> k;
  std::vector<std::uint8_t> near_wall;
  std::vector<double> seeds;  ///< NaN where unset
};

// A wall along x = (wall_i + 0.5) cells for rows below wall_j: a move crosses it when its ends lie on
// both sides of the line and either end is in those rows.
struct Wall {
  long wall_i, wall_j;
  std::size_t nx;
  bool operator()(std::size_t a, std::size_t b) const {
    const long ia = long(a % nx), ja = long(a / nx), ib = long(b % nx), jb = long(b / nx);
    return (ia <= wall_i) != (ib <= wall_i) && std::min(ja, jb) < wall_j;
  }
};

// Random wavenumbers (some nodes dry), seeds of either sign with exact ties, +0 and -0 among them.
Grid random_grid(std::mt19937& rng, std::size_t nx, std::size_t ny, const Wall& wall) {
  Grid g{nx, ny, 0.5, std::vector<float>(nx * ny), std::vector<std::uint8_t>(nx * ny, 0), std::vector<double>(nx * ny, NAN)};
  std::uniform_real_distribution<float> k(0.05f, 3.0f);
  std::uniform_real_distribution<double> phase(-20.0, 20.0), u(0.0, 1.0);
  for (std::size_t n = 0; n < nx * ny; ++n) {
    g.k[n] = u(rng) < 0.1 ? 0.0f : k(rng);
    const long i = long(n % nx);
    g.near_wall[n] = std::abs(i - wall.wall_i) <= 3 ? 1 : 0;
  }
  const double tied = phase(rng);
  const double values[] = {tied, tied, 0.0, -0.0, phase(rng), phase(rng), -phase(rng)};
  for (int s = 0; s < 14; ++s) {
    const std::size_t n = std::size_t(u(rng) * double(nx * ny)) % (nx * ny);
    if (g.k[n] > 0.0f) g.seeds[n] = values[s % 7];
  }
  return g;
}

// The first arrivals by brute force: relax every move until nothing changes (Bellman-Ford), each
// move's cost computed as the march computes it; seeded nodes keep their phase.
std::vector<double> first_arrivals(const Grid& g, const Wall& wall) {
  std::vector<double> phase = g.seeds;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t q = 0; q < g.nx * g.ny; ++q) {
      if (std::isfinite(g.seeds[q]) || !(g.k[q] > 0.0f)) continue;
      const long i = long(q % g.nx), j = long(q / g.nx);
      for (const auto& m : moves) {
        const long a = i - m[0], b = j - m[1];
        if (a < 0 || b < 0 || a >= long(g.nx) || b >= long(g.ny)) continue;
        const std::size_t n = std::size_t(b) * g.nx + std::size_t(a);
        if (!std::isfinite(phase[n])) continue;
        if ((g.near_wall[n] || g.near_wall[q]) && wall(n, q)) continue;
        const double step = 0.5 * (double(g.k[n]) + double(g.k[q])) * g.cell * std::sqrt(double(m[0] * m[0] + m[1] * m[1]));
        if (!(phase[n] + step >= phase[q])) {
          phase[q] = phase[n] + step;
          changed = true;
        }
      }
    }
  }
  return phase;
}

// The march's front is ordered on the phases' bits (carrier_march.cpp): negative phases, +0 and -0
// and exact ties must leave it in the phases' order, or a node is settled before a shorter way to it
// is seen. Each march reuses the last one's scratch, a larger grid's first.
TEST(CarrierMarch, SettlesEveryNodeAtItsFirstArrival) {
  std::mt19937 rng(11);
  houle::detail::CarrierMarchScratch scratch;
  for (int trial = 0; trial < 12; ++trial) {
    const std::size_t nx = trial % 2 ? 23 : 37, ny = trial % 2 ? 19 : 29;
    const Wall wall{long(nx / 2), long(ny * 2 / 3), nx};
    const Grid g = random_grid(rng, nx, ny, wall);
    const std::vector<double> expected = first_arrivals(g, wall);
    std::vector<double> phase = g.seeds, kx(nx * ny, 0.0), ky(nx * ny, 0.0);
    houle::detail::march_carrier(nx, ny, g.cell, g.k, g.near_wall, wall, phase, kx, ky, scratch);
    std::size_t reached = 0;
    for (std::size_t n = 0; n < nx * ny; ++n) {
      if (std::isnan(expected[n])) {
        EXPECT_TRUE(std::isnan(phase[n])) << trial << " " << n;
        continue;
      }
      ++reached;
      EXPECT_EQ(phase[n], expected[n]) << trial << " " << n;  // the same sums: equal to the bit
    }
    EXPECT_GT(reached, nx * ny / 2) << trial;
  }
}

}  // namespace
