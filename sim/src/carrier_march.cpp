#include "carrier_march.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>

namespace houle::detail {
namespace {

using Entry = CarrierMarchScratch::Entry;

constexpr std::uint64_t sign_bit = std::uint64_t(1) << 63;

// The front is a binary min-heap whose comparisons do not branch: which of two children is the
// lesser is a coin toss to a branch predictor, and std::priority_queue's sift-down on (phase, node)
// pairs was half of the march (the buoy scene: 250,000 pops a train from a front of up to 1,800
// entries; this heap cut the march by a quarter). Doubles do not compare without a branch (NaN's
// parity flag); their bits do, mapped so that unsigned order is the phases' order (the sign flipped
// for positives, every bit for negatives; -0 taken as +0, which it equals, so the node decides).
// The phases are finite.
std::uint64_t phase_key(double phase) noexcept {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(phase + 0.0);
  return bits & sign_bit ? ~bits : bits | sign_bit;
}
double key_phase(std::uint64_t key) noexcept { return std::bit_cast<double>(key & sign_bit ? key & ~sign_bit : ~key); }

// The least phase first, then the lower node: no two entries are equal (a node is pushed again only
// at a lesser phase), so the order in which they leave is that of std::priority_queue, whatever the
// heap's shape. Bitwise operators, not short-circuit ones, keep the branches out.
bool before(const Entry& a, const Entry& b) noexcept {
  return (a.key < b.key) | ((a.key == b.key) & (a.node < b.node));
}

// Puts e in the hole at i, moving the hole up past the entries after e.
void rise(std::vector<Entry>& heap, std::size_t i, Entry e) {
  while (i > 0) {
    const std::size_t parent = (i - 1) / 2;
    if (!before(e, heap[parent])) break;
    heap[i] = heap[parent];
    i = parent;
  }
  heap[i] = e;
}

void push(std::vector<Entry>& heap, Entry e) {
  heap.push_back(e);
  rise(heap, heap.size() - 1, e);
}

// Floyd's pop: the hole goes down to a leaf along the lesser children, then the last entry rises
// from there (it rarely rises far).
Entry pop(std::vector<Entry>& heap) {
  const Entry top = heap.front(), last = heap.back();
  heap.pop_back();
  const std::size_t size = heap.size();
  if (size == 0) return top;
  std::size_t i = 0;
  while (2 * i + 2 < size) {
    std::size_t c = 2 * i + 1;
    c += std::size_t(before(heap[c + 1], heap[c]));
    heap[i] = heap[c];
    i = c;
  }
  if (2 * i + 1 < size) {
    heap[i] = heap[2 * i + 1];
    i = 2 * i + 1;
  }
  rise(heap, i, last);
  return top;
}

}  // namespace

void march_carrier(std::size_t nx, std::size_t ny, double cell, const std::vector<float>& k,
                   const std::vector<std::uint8_t>& near_wall,
                   const std::function<bool(std::size_t, std::size_t)>& crosses_wall, std::vector<double>& phase,
                   std::vector<double>& kx, std::vector<double>& ky, CarrierMarchScratch& scratch) {
  const std::size_t nodes = nx * ny;
  std::vector<std::uint8_t>& seeded = scratch.seeded;
  seeded.assign(nodes, 0);
  std::vector<Entry>& front = scratch.front;
  front.clear();
  for (std::size_t n = 0; n < nodes; ++n) {
    if (std::isfinite(phase[n])) {
      seeded[n] = 1;
      push(front, {phase_key(phase[n]), n});
    }
  }
  static constexpr int moves[16][2] = {{1, 0},  {-1, 0}, {0, 1},  {0, -1}, {1, 1},  {1, -1}, {-1, 1}, {-1, -1},
                                       {2, 1},  {2, -1}, {-2, 1}, {-2, -1}, {1, 2}, {1, -2}, {-1, 2}, {-1, -2}};
  std::vector<std::uint8_t>& done = scratch.done;
  done.assign(nodes, 0);
  while (!front.empty()) {
    const Entry e = pop(front);
    const double p = key_phase(e.key);
    const std::size_t n = e.node;
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
      push(front, {phase_key(phase[q]), q});
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
