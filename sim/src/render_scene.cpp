// The renderer's view of a scene (animation.hpp: make_render_scene).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/animation.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/floating_objects.hpp"

namespace houle {
namespace {

constexpr double deg = std::numbers::pi / 180.0;
// Sea floor grid spacing, m: fine enough for the floor seen through shallow water, cheap to build.
constexpr double floor_cell = 1.0;
constexpr LinearRgb stone{0.32f, 0.30f, 0.27f};
// Blocks of a wall: one every `pitch` m along each segment, from 1 m under the sea floor's reach
// (2 m below still water) up to the crest. The yaw wobbles by a fixed pattern so the blocks do not
// look machined; neighbours differ by up to 6 degrees, so each block reaches past its share of the
// segment by half the wall's thickness times sin 6 degrees (and 1 cm): the wobble then opens no gap
// between blocks, which showed as dark dashes across a jetty's top seen from above.
constexpr double block_pitch = 3.0, wobble_overlap = 0.1045;

void add_wall_blocks(RenderScene& r, const Wall& w) {
  int n = 0;
  for (std::size_t j = 0; j + 1 < w.points.size(); ++j) {
    const Point2 a = w.points[j], b = w.points[j + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const double yaw = std::atan2(b.y - a.y, b.x - a.x);
    const int count = std::max(1, int(std::ceil(len / block_pitch)));
    for (int i = 0; i < count; ++i, ++n) {
      const double t = (i + 0.5) / count;
      RenderBox box;
      const double bottom = -std::max(2.0, w.crest_height), top = w.crest_height;
      box.center = {float(a.x + t * (b.x - a.x)), float(a.y + t * (b.y - a.y)), float(0.5 * (top + bottom))};
      const double half_thickness = 0.5 * std::max(w.thickness, 0.2);
      box.half_extent = {float(0.5 * len / count + half_thickness * wobble_overlap + 0.01), float(half_thickness),
                         float(0.5 * (top - bottom))};
      box.yaw_rad = float(yaw + double((n * 7) % 5 - 2) * 2.0 * deg);
      box.colour = stone;
      r.boxes.push_back(box);
    }
  }
}

}  // namespace

RenderScene make_render_scene(const Scene& scene) {
  RenderScene r;
  const Bathymetry bathymetry(scene.floor);
  if (!bathymetry.uniform() || bathymetry.depth(0.0, 0.0) < 200.0) {
    const Domain& d = scene.domain;
    FloorGrid& f = r.floor;
    f.sand = scene.floor.base.sand_colour;
    f.origin_x = float(d.x_min);
    f.origin_y = float(d.y_min);
    f.cell = float(floor_cell);
    f.nx = std::uint32_t(std::ceil((d.x_max - d.x_min) / floor_cell)) + 1;
    f.ny = std::uint32_t(std::ceil((d.y_max - d.y_min) / floor_cell)) + 1;
    f.z.resize(std::size_t(f.nx) * f.ny);
    for (std::uint32_t j = 0; j < f.ny; ++j) {
      for (std::uint32_t i = 0; i < f.nx; ++i) {
        f.z[std::size_t(j) * f.nx + i] = float(-bathymetry.depth(d.x_min + i * floor_cell, d.y_min + j * floor_cell));
      }
    }
  }
  for (const Wall& w : scene.walls) add_wall_blocks(r, w);
  for (const Box& b : scene.boxes) {
    const double z = b.floats ? b.half_extent.z - box_draft(b.half_extent.z, b.density) : b.center.z;
    r.boxes.push_back({{float(b.center.x), float(b.center.y), float(z)},
                       {float(b.half_extent.x), float(b.half_extent.y), float(b.half_extent.z)},
                       float(b.yaw_deg * deg), b.colour});
  }
  for (const Sphere& s : scene.spheres) {
    const double z = s.floats ? s.radius - sphere_draft(s.radius, s.density) : s.center.z;
    r.spheres.push_back({{float(s.center.x), float(s.center.y), float(z)}, float(s.radius), s.colour});
  }
  const double az = scene.sun.azimuth_deg * deg, el = scene.sun.elevation_deg * deg;
  r.sun_direction = {float(std::cos(el) * std::cos(az)), float(std::cos(el) * std::sin(az)), float(std::sin(el))};
  r.turbidity = float(scene.sky.turbidity);
  r.water_extra_absorption = float(scene.water.extra_absorption);
  r.sea_dominant_wavelength_nm = float(scene.water.dominant_wavelength_nm);
  return r;
}

}  // namespace houle
