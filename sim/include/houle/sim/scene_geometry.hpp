// What lies where in a scene: the place of a point (water, land, a wall, outside the domain) as the
// ray tracer sees it, and the shapes `houle info` warns about (islands, pierheads near the domain's
// edge).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

enum class Place : std::uint8_t {
  water,    ///< inside the domain, floor below still water, not in a wall
  land,     ///< inside the domain, floor at or above still water (depth <= 0)
  wall,     ///< inside a wall's footprint (within max(thickness / 2, 1 mm) of its axis), in the domain
  outside,  ///< outside the domain, where no ray is traced
};
/// "water", "land", "wall", "outside".
std::string_view place_name(Place place) noexcept;

/// Where (x, y) lies in `scene`, whose floor is `floor`: outside the domain first, then in a wall
/// (the tracer's own test: a ray starting there is dead), then land, else water.
Place locate(const Scene& scene, const Bathymetry& floor, double x, double y);

/// Land rising through the surface inside the domain and touching none of its edges: a shoal or a
/// height map's land standing in the water.
struct Island {
  Point2 low, high;  ///< m, corners of its bounding box (on the sampling grid)
};
/// The islands of a valid scene. The floor is sampled on a grid of 1 m cells (coarser for domains wider
/// than 512 m: at most 512 cells a side) and land nodes joined across cell sides, so land narrower
/// than a cell may go unseen, except a shoal's top (its centre is checked too). No land in the domain
/// (Bathymetry::min_depth_bound > 0) costs no sample.
std::vector<Island> find_islands(const Scene& scene);

/// A pierhead (a wall end in water, inside the domain) closer to the domain's edge than a wavelength
/// of a traced train: waves pass the narrow gap between it and the edge (the sea beyond the edge is
/// open) and diffract round it, which a wall meant to reach the edge would not let them do.
struct EdgePierhead {
  std::size_t wall = 0;       ///< Scene::walls index
  Point2 end;                 ///< m, the wall end
  double edge_distance = 0.0;  ///< m to the nearest domain edge
  std::size_t train = 0;      ///< the train with the longest local wavelength there
  double wavelength = 0.0;    ///< m, that train's wavelength at the end's depth (linear dispersion)
};
/// The pierheads of a valid scene within one wavelength of the domain's edge (none when diffraction
/// is off or no train is traced).
std::vector<EdgePierhead> pierheads_near_edge(const Scene& scene);

}  // namespace houle
