#include "houle/sim/scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/dispersion.hpp"
#include "houle/sim/effect_plan.hpp"
#include "ray_walls.hpp"

namespace houle {
namespace {

// Island search grid: the renderer's floor cell (render_scene.cpp), and no more than this many cells
// a side, so that the largest domain (4 km) costs a quarter of a million depth samples (0.15 s with
// 200 shoals and a height map on one core).
constexpr double island_cell = 1.0;         // m
constexpr double max_island_cells = 512.0;  // per side

bool in_domain(const Domain& d, double x, double y) noexcept {
  return x >= d.x_min && x <= d.x_max && y >= d.y_min && y <= d.y_max;
}

}  // namespace

std::string_view place_name(Place place) noexcept {
  switch (place) {
    case Place::water: return "water";
    case Place::land: return "land";
    case Place::wall: return "wall";
    case Place::outside: return "outside";
  }
  return "water";
}

Place locate(const Scene& scene, const Bathymetry& floor, double x, double y) {
  if (!in_domain(scene.domain, x, y)) return Place::outside;
  if (!scene.walls.empty() && detail::wall_blocks(detail::wall_capsules(scene.walls), x, y, x, y)) return Place::wall;
  return floor.depth(x, y) > 0.0 ? Place::water : Place::land;
}

std::vector<Island> find_islands(const Scene& scene) {
  const Bathymetry floor(scene.floor);
  const Domain& d = scene.domain;
  if (floor.min_depth_bound(d) > 0.0) return {};
  const double width = d.x_max - d.x_min, height = d.y_max - d.y_min;
  const double cell = std::max(island_cell, std::max(width, height) / max_island_cells);
  const std::size_t nx = std::size_t(std::ceil(width / cell)) + 1, ny = std::size_t(std::ceil(height / cell)) + 1;
  const double sx = width / double(nx - 1), sy = height / double(ny - 1);
  // 0 water, 1 land not yet joined to a component, 2 land joined.
  std::vector<std::uint8_t> land(nx * ny);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) land[j * nx + i] = floor.depth(d.x_min + double(i) * sx, d.y_min + double(j) * sy) <= 0.0;
  }
  std::vector<Island> out;
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < land.size(); ++start) {
    if (land[start] != 1) continue;
    land[start] = 2;
    stack.assign(1, start);
    std::size_t i0 = nx, i1 = 0, j0 = ny, j1 = 0;
    while (!stack.empty()) {
      const std::size_t n = stack.back();
      stack.pop_back();
      const std::size_t i = n % nx, j = n / nx;
      i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
      const auto visit = [&](std::size_t m) {
        if (land[m] == 1) land[m] = 2, stack.push_back(m);
      };
      if (i > 0) visit(n - 1);
      if (i + 1 < nx) visit(n + 1);
      if (j > 0) visit(n - nx);
      if (j + 1 < ny) visit(n + nx);
    }
    if (i0 > 0 && j0 > 0 && i1 + 1 < nx && j1 + 1 < ny) {
      out.push_back(Island{{d.x_min + double(i0) * sx, d.y_min + double(j0) * sy},
                           {d.x_min + double(i1) * sx, d.y_min + double(j1) * sy}});
    }
  }
  // A shoal's top is its highest point (on a flat base): land there that no grid node saw is an
  // island narrower than a cell.
  for (const Shoal& s : scene.floor.shoals) {
    const Point2 c = s.center;
    if (!(c.x > d.x_min && c.x < d.x_max && c.y > d.y_min && c.y < d.y_max) || floor.depth(c.x, c.y) > 0.0) continue;
    const std::size_t i = std::size_t(std::lround((c.x - d.x_min) / sx)), j = std::size_t(std::lround((c.y - d.y_min) / sy));
    if (land[std::min(j, ny - 1) * nx + std::min(i, nx - 1)] == 0) out.push_back(Island{c, c});
  }
  return out;
}

std::vector<EdgePierhead> pierheads_near_edge(const Scene& scene) {
  std::vector<EdgePierhead> out;
  if (!scene.dwt.diffraction || scene.walls.empty()) return out;
  const EffectPlan plan = plan_effects(scene, Quality{});
  const Bathymetry floor(scene.floor);
  const Domain& d = scene.domain;
  // The pierheads scene_has_pierheads counts (in water deeper than the smallest h_min of any train).
  for (const detail::PierheadSite& p : detail::pierhead_sites(scene, floor, scene.dwt.min_depth)) {
    const double edge = std::min({p.x - d.x_min, d.x_max - p.x, p.y - d.y_min, d.y_max - p.y});
    const double depth = floor.depth(p.x, p.y);
    EdgePierhead near{p.wall, {p.x, p.y}, edge, 0, 0.0};
    for (std::size_t t = 0; t < scene.trains.size(); ++t) {
      const LinearWave w = linear_wave(train_omega(scene.trains[t]), depth);
      if (!plan.train_rays[t] || !w.wet) continue;
      const double wavelength = 2.0 * std::numbers::pi / w.k;
      if (wavelength > near.wavelength) near.train = t, near.wavelength = wavelength;
    }
    if (edge < near.wavelength) out.push_back(near);
  }
  return out;
}

}  // namespace houle
