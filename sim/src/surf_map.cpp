// Where the waves break, for the renderer's foam (sea_surface.hpp surf_map, docs/rendering.md 3.7).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include "houle/sim/sea_surface.hpp"

namespace houle {
namespace {

// Foam lines a wall's toe out to toe_reach m from its face where the waves there reach
// crash_amplitude m (all of a train's fields summed: incident, diffracted, reflected), less below.
constexpr double toe_reach = 2.5, crash_amplitude = 0.25;

/// The local wave vector (rad/m) at node n: the carrier's plus the gradient of B's phase,
/// Im(conj(B) grad B) / |B|^2 with grad B by central differences (one-sided at the grid's edges). Where
/// the model's carrier is not the wave's (the parabolic model's marched field, a wave carried past the
/// rays' end) B's phase turns it.
std::pair<double, double> wave_vector(const TrainField& f, const TrainGrid& g, std::size_t n) {
  const std::size_t i = n % g.nx, j = n / g.nx;
  const std::complex<double> b(f.b_re[n], f.b_im[n]);
  const double b2 = std::norm(b);
  const auto phase_slope = [&](std::size_t lo, std::size_t hi, double span) {
    const std::complex<double> d = std::complex<double>(f.b_re[hi] - f.b_re[lo], f.b_im[hi] - f.b_im[lo]);
    return b2 > 0.0 && span > 0.0 ? (std::conj(b) * d).imag() / (b2 * span) : 0.0;
  };
  const std::size_t w = i > 0 ? n - 1 : n, e = i + 1 < g.nx ? n + 1 : n;
  const std::size_t s = j > 0 ? n - g.nx : n, north = j + 1 < g.ny ? n + g.nx : n;
  const double gx = phase_slope(w, e, double(e - w) * double(g.cell));
  const double gy = phase_slope(s, north, double((north - s) / g.nx) * double(g.cell));
  return {double(f.kx[n]) + gx, double(f.ky[n]) + gy};
}

/// The steps of the foam search: the eight neighbours and the eight knight's moves between them, so
/// that a step within 30 degrees of any direction of travel exists and foam can spread sideways.
constexpr std::array<std::array<std::int64_t, 2>, 16> foam_steps{{{1, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 1}, {-1, 2},
                                                                  {-1, 1}, {-2, 1}, {-1, 0}, {-2, -1}, {-1, -1},
                                                                  {-1, -2}, {0, -1}, {1, -2}, {1, -1}, {2, -1}}};

/// A step of the foam search costs its length along the waves' travel plus foam_spread_cost times its
/// length across it beyond half a cell. A step to a neighbour within 30 degrees of the travel crosses it
/// by at most half a cell: foam carried along the travel thins by its distance whatever the travel's
/// direction, and foam that spreads sideways (by knight's moves) thins faster.
constexpr double foam_spread_cost = 24.0;

/// Foam carried behind the break line (docs/rendering.md 3.7): per node, the largest
/// breaking(m) e^{-G/L} over the nodes m upstream of it, G the cost of the way from m to the node along
/// the waves' drift (its length along the drift, and across it), L = foam_decay_wavelengths local
/// wavelengths of train f: behind a break the foam spreads a little and thins to its sides (a node d
/// cells to the side of the drift, s along it, costs s + 12d). The drift is all the trains' (`drift`,
/// per node): foam floats on the water that all the waves move, whichever of them broke. A
/// shortest-path search on -ln foam over foam_steps, each step taken only within 30 degrees of the
/// drift and only into nodes the train reaches; it stops where foam falls below 1 %.
std::vector<float> carried_foam(const TrainField& f, const TrainGrid& g, const std::vector<std::array<double, 2>>& drift) {
  const std::size_t nodes = std::size_t(g.nx) * g.ny;
  constexpr double infinite = std::numeric_limits<double>::infinity(), cutoff = 4.605170185988091;  // -ln 0.01
  constexpr double cos_cone = 0.866025404;  // cos 30 deg: a knight's move (26.6 deg) spreads the foam
  std::vector<double> cost(nodes, infinite);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (f.breaking[n] > 0.0f) cost[n] = f.breaking[n] < 1.0f ? -std::log(double(f.breaking[n])) : 0.0;
  }
  // Whether a node's foam could strengthen a neighbour's (inside the surf zone every neighbour already
  // has foam as strong: most of the seeds).
  const auto improves = [&](std::size_t n, double c) {
    const std::int64_t i = std::int64_t(n % g.nx), j = std::int64_t(n / g.nx);
    for (const auto& [di, dj] : foam_steps) {
      if (i + di < 0 || j + dj < 0 || i + di >= std::int64_t(g.nx) || j + dj >= std::int64_t(g.ny)) continue;
      if (cost[std::size_t((j + dj) * std::int64_t(g.nx) + i + di)] > c) return true;
    }
    return false;
  };
  using Entry = std::pair<double, std::uint32_t>;
  std::vector<Entry> seeds;
  for (std::size_t n = 0; n < nodes; ++n) {
    if (cost[n] < infinite && improves(n, cost[n])) seeds.push_back({cost[n], std::uint32_t(n)});
  }
  if (seeds.empty()) return f.breaking;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open(std::greater<>(), std::move(seeds));  // ties by node: deterministic
  const auto carries = [&](std::size_t n) { return f.b_re[n] != 0.0f || f.b_im[n] != 0.0f; };
  while (!open.empty()) {
    const auto [c, n] = open.top();
    open.pop();
    if (c > cost[n] || !carries(n) || !improves(n, c)) continue;
    const std::int64_t i = std::int64_t(n % g.nx), j = std::int64_t(n / g.nx);
    const auto [kx, ky] = wave_vector(f, g, n);
    const double k = std::hypot(kx, ky), d = std::hypot(drift[n][0], drift[n][1]);
    if (!(k > 0.0) || !(d > 0.0)) continue;
    const double ux = drift[n][0] / d, uy = drift[n][1] / d;
    const double per_metre = k / (2.0 * 3.141592653589793 * foam_decay_wavelengths);
    for (const auto& [di, dj] : foam_steps) {
      if (i + di < 0 || j + dj < 0 || i + di >= std::int64_t(g.nx) || j + dj >= std::int64_t(g.ny)) continue;
      const double along = double(di) * ux + double(dj) * uy, across = std::fabs(double(di) * uy - double(dj) * ux);
      if (along < cos_cone * std::hypot(double(di), double(dj))) continue;
      const std::size_t m = std::size_t((j + dj) * std::int64_t(g.nx) + i + di);
      const double next = c + (along + foam_spread_cost * std::max(0.0, across - 0.5)) * double(g.cell) * per_metre;
      if (next < cost[m] && next <= cutoff && carries(m)) {
        cost[m] = next;
        open.push({next, std::uint32_t(m)});
      }
    }
  }
  std::vector<float> foam(f.breaking);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (cost[n] <= cutoff) foam[n] = std::max(foam[n], float(std::exp(-cost[n])));
  }
  return foam;
}

double segment_distance(double px, double py, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double u = len2 > 0.0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(px - (a.x + u * dx), py - (a.y + u * dy));
}

}  // namespace

SurfMap SeaSurface::surf_map(const Scene& scene) const {
  // The traced trains share the domain's resampling grid; analytic trains never break here.
  std::size_t first = trains_.size();
  for (std::size_t t = 0; t < trains_.size() && first == trains_.size(); ++t) {
    if (!trains_[t].breaking.empty()) first = t;
  }
  if (first == trains_.size()) return {};
  const TrainGrid& g = grids_[first];
  const std::size_t nodes = std::size_t(g.nx) * g.ny;
  SurfMap m;
  m.origin_x = g.origin_x;
  m.origin_y = g.origin_y;
  m.cell = g.cell;
  m.nx = g.nx;
  m.ny = g.ny;
  for (std::vector<float>* v : {&m.foam, &m.dir_x, &m.dir_y, &m.amplitude}) v->assign(nodes, 0.0f);
  const auto traced = [&](std::size_t t) {
    return trains_[t].breaking.size() == nodes && grids_[t].nx == g.nx && grids_[t].ny == g.ny;
  };
  // The waves' drift, which carries the foam: the sum of the trains' Stokes drifts |B|^2 omega k.
  std::vector<std::array<double, 2>> drift(nodes, {0.0, 0.0});
  for (std::size_t t = first; t < trains_.size(); ++t) {
    if (!traced(t)) continue;
    const TrainField& f = trains_[t];
    for (std::size_t n = 0; n < nodes; ++n) {
      const double b2 = double(f.b_re[n]) * f.b_re[n] + double(f.b_im[n]) * f.b_im[n];
      if (!(b2 > 0.0)) continue;
      const auto [kx, ky] = wave_vector(f, grids_[t], n);
      drift[n][0] += b2 * f.omega * kx;
      drift[n][1] += b2 * f.omega * ky;
    }
  }
  std::vector<float> sum(nodes, 0.0f);  // the trains' amplitudes, for the walls
  for (std::size_t t = first; t < trains_.size(); ++t) {
    if (!traced(t)) continue;
    const TrainField& f = trains_[t];
    const std::vector<float> foam = carried_foam(f, grids_[t], drift);
    for (std::size_t n = 0; n < nodes; ++n) {
      const float a = std::hypot(f.b_re[n], f.b_im[n]), k = std::hypot(f.kx[n], f.ky[n]);
      sum[n] += a;
      if (foam[n] > m.foam[n] && k > 0.0f) {
        const auto [wx, wy] = wave_vector(f, grids_[t], n);
        const double w = std::hypot(wx, wy);
        m.foam[n] = foam[n];
        m.dir_x[n] = w > 0.0 ? float(wx / w) : 0.0f;
        m.dir_y[n] = w > 0.0 ? float(wy / w) : 0.0f;
        m.amplitude[n] = a;
      }
    }
  }
  for (const Wall& w : scene.walls) {
    const double reach = 0.5 * w.thickness + toe_reach;
    for (std::size_t s = 0; s + 1 < w.points.size(); ++s) {
      const Point2 a = w.points[s], b = w.points[s + 1];
      const auto index = [&](double v, double origin, std::uint32_t count) {
        return std::size_t(std::clamp(std::floor((v - origin) / double(g.cell)), 0.0, double(count - 1)));
      };
      const std::size_t i0 = index(std::min(a.x, b.x) - reach, g.origin_x, g.nx), i1 = index(std::max(a.x, b.x) + reach, g.origin_x, g.nx) + 1;
      const std::size_t j0 = index(std::min(a.y, b.y) - reach, g.origin_y, g.ny), j1 = index(std::max(a.y, b.y) + reach, g.origin_y, g.ny) + 1;
      for (std::size_t j = j0; j <= std::min(j1, std::size_t(g.ny) - 1); ++j) {
        for (std::size_t i = i0; i <= std::min(i1, std::size_t(g.nx) - 1); ++i) {
          const std::size_t n = j * g.nx + i;
          const double d = segment_distance(g.origin_x + double(i) * g.cell, g.origin_y + double(j) * g.cell, a, b) - 0.5 * w.thickness;
          if (!(d < toe_reach) || !(sum[n] > 0.0f)) continue;
          const double u = std::clamp(1.0 - d / toe_reach, 0.0, 1.0);
          const float foam = float(u * u * (3.0 - 2.0 * u) * std::min(1.0, double(sum[n]) / crash_amplitude));
          if (foam > m.foam[n]) {
            m.foam[n] = foam;
            m.dir_x[n] = m.dir_y[n] = 0.0f;
            m.amplitude[n] = sum[n];
          }
        }
      }
    }
  }
  if (!(*std::max_element(m.foam.begin(), m.foam.end()) > 0.0f)) return {};
  return m;
}

}  // namespace houle
