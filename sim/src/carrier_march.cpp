#include "carrier_march.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>

namespace houle::detail {

void march_carrier(std::size_t nx, std::size_t ny, double cell, const std::vector<float>& k,
                   const std::vector<std::uint8_t>& near_wall,
                   const std::function<bool(std::size_t, std::size_t)>& crosses_wall, std::vector<double>& phase,
                   std::vector<double>& kx, std::vector<double>& ky, CarrierMarchScratch& scratch) {
  const std::size_t nodes = nx * ny;
  std::vector<std::uint8_t>& seeded = scratch.seeded;
  seeded.assign(nodes, 0);
  // A min-heap on the scratch's storage (what std::priority_queue with std::greater does, without
  // owning it): the least phase first, then the lower node.
  using Entry = std::pair<double, std::size_t>;
  std::vector<Entry>& front = scratch.front;
  front.clear();
  const auto push = [&](double p, std::size_t n) {
    front.emplace_back(p, n);
    std::push_heap(front.begin(), front.end(), std::greater<Entry>{});
  };
  for (std::size_t n = 0; n < nodes; ++n) {
    if (std::isfinite(phase[n])) {
      seeded[n] = 1;
      push(phase[n], n);
    }
  }
  static constexpr int moves[16][2] = {{1, 0},  {-1, 0}, {0, 1},  {0, -1}, {1, 1},  {1, -1}, {-1, 1}, {-1, -1},
                                       {2, 1},  {2, -1}, {-2, 1}, {-2, -1}, {1, 2}, {1, -2}, {-1, 2}, {-1, -2}};
  std::vector<std::uint8_t>& done = scratch.done;
  done.assign(nodes, 0);
  while (!front.empty()) {
    std::pop_heap(front.begin(), front.end(), std::greater<Entry>{});
    const auto [p, n] = front.back();
    front.pop_back();
    if (done[n] || p > phase[n]) continue;
    done[n] = 1;
    const long i = long(n % nx), j = long(n / nx);
    for (const auto& m : moves) {
      const long a = i + m[0], b = j + m[1];
      if (a < 0 || b < 0 || a >= long(nx) || b >= long(ny)) continue;
      const std::size_t q = std::size_t(b) * nx + std::size_t(a);
      if (done[q] || seeded[q] || !(k[q] > 0.0f)) continue;
      const double step = 0.5 * (double(k[n]) + double(k[q])) * cell * std::sqrt(double(m[0] * m[0] + m[1] * m[1]));
      if (std::isfinite(phase[q]) && phase[q] <= p + step) continue;
      if ((near_wall[n] || near_wall[q]) && crosses_wall(n, q)) continue;
      phase[q] = p + step;
      push(phase[q], q);
    }
  }
  // Wave vectors of the marched nodes from their neighbours' phases.
  const auto set = [&](long a, long b) { return a >= 0 && b >= 0 && a < long(nx) && b < long(ny) && std::isfinite(phase[std::size_t(b) * nx + std::size_t(a)]); };
  const auto at = [&](long a, long b) { return phase[std::size_t(b) * nx + std::size_t(a)]; };
  const auto derivative = [&](long i, long j, long di, long dj) {
    const bool back = set(i - di, j - dj), ahead = set(i + di, j + dj);
    if (back && ahead) return (at(i + di, j + dj) - at(i - di, j - dj)) / (2.0 * cell);
    if (ahead) return (at(i + di, j + dj) - at(i, j)) / cell;
    if (back) return (at(i, j) - at(i - di, j - dj)) / cell;
    return 0.0;
  };
  for (std::size_t n = 0; n < nodes; ++n) {
    if (seeded[n] || !std::isfinite(phase[n])) continue;
    const long i = long(n % nx), j = long(n / nx);
    kx[n] = derivative(i, j, 1, 0);
    ky[n] = derivative(i, j, 0, 1);
  }
}

}  // namespace houle::detail
