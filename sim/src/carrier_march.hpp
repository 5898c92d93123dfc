// The carrier phase of a train's sea grid where no incident ray reached (docs/physics.md 2.8): the
// lee of walls and islands, the shallows beyond the rays' last samples. Internal to houle_sim.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace houle::detail {

/// What march_carrier works in, kept by its caller: a scene's build marches every train, and fresh
/// arrays per train cost page faults and zeroing (SeaSurface::ResampleScratch says why it matters).
struct CarrierMarchScratch {
  /// A node on the march's front at a phase.
  struct Entry {
    std::uint64_t key;  ///< the phase's bits as an unsigned integer that orders as the phases do
    std::size_t node;
  };
  std::vector<std::uint8_t> seeded, done;
  std::vector<Entry> front;  ///< the march's min-heap
};

/// Extends `phase` (rad per node, NaN where unset) from the nodes that have one to every node with
/// k[n] > 0 reachable from them, as first arrivals: Dijkstra over a 16-neighbour stencil (the
/// knight's moves cut the grid's anisotropy to 2.6 %), each move costing the mean of its two nodes' k
/// times its length. Every phase set here has a wave vector (kx, ky): the central difference of the
/// phases around it, one-sided at the edge of what was set. Deterministic: ties go to the lower node.
/// A move between two nodes one of which is flagged in `near_wall` is taken only if `crosses_wall`
/// says its segment crosses no wall. Reads nothing `scratch` held before.
void march_carrier(std::size_t nx, std::size_t ny, double cell, const std::vector<float>& k,
                   const std::vector<std::uint8_t>& near_wall,
                   const std::function<bool(std::size_t, std::size_t)>& crosses_wall, std::vector<double>& phase,
                   std::vector<double>& kx, std::vector<double>& ky, CarrierMarchScratch& scratch);

}  // namespace houle::detail
