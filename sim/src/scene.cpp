#include "houle/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/animation.hpp"  // quality_preset
#include "houle/sim/build_cost.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_keys.hpp"
#include "houle/sim/sea_state.hpp"
#include "houle/sim/wave_rays.hpp"
#include "clip_line.hpp"

namespace houle {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

std::string num(double v) { return scene_keys::number_text(v); }
std::string at(std::string_view name, std::size_t i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

// "what was expected, got <value>"
Error bad(std::string field, const std::string& expected, double got) {
  return Error{std::move(field), expected + ", got " + num(got)};
}


// Every key's range (scene_keys.hpp), item by item; the checks below assume these passed.
Expected<void> check_key_ranges(Scene& s) {
  Expected<void> first;
  scene_keys::for_each_section([&]<class S>(const scene_keys::Section<S>& section) {
    if (!first) return;
    if (section.table_in) first = scene_keys::check_keys(section, section.table_in(s), std::string(section.path));
    if (!section.array_in) return;
    const std::vector<S>& items = section.array_in(s);
    for (std::size_t i = 0; i < items.size() && first; ++i) first = scene_keys::check_keys(section, items[i], at(section.path, i));
  });
  return first;
}

// Does segment [a, b] meet the rectangle grown by `margin`?
bool segment_meets_rect(Point2 a, Point2 b, const Domain& d, double margin) noexcept {
  const Domain grown{d.x_min - margin, d.y_min - margin, d.x_max + margin, d.y_max + margin};
  double t0 = 0.0, t1 = 0.0;
  return detail::clip_line(grown, a.x, a.y, b.x - a.x, b.y - a.y, t0, t1) && t0 <= 1.0 && t1 >= 0.0;
}

Expected<void> check_domain(const Domain& d) {
  if (!(d.x_max > d.x_min)) return bad("domain.x_max", "a value > x_min = " + num(d.x_min) + " m", d.x_max);
  if (!(d.y_max > d.y_min)) return bad("domain.y_max", "a value > y_min = " + num(d.y_min) + " m", d.y_max);
  const std::string side = "a side of at most " + num(scene_limits::max_domain_side) + " m, got ";
  if (d.x_max - d.x_min > scene_limits::max_domain_side) return Error{"domain.x_max", side + num(d.x_max - d.x_min) + " m"};
  if (d.y_max - d.y_min > scene_limits::max_domain_side) return Error{"domain.y_max", side + num(d.y_max - d.y_min) + " m"};
  // Coordinates reach the renderer as floats: keep their precision near a millimetre.
  const double far = std::max({std::abs(d.x_min), std::abs(d.x_max), std::abs(d.y_min), std::abs(d.y_max)});
  if (far > scene_limits::max_coordinate) {
    return bad("domain", "bounds within " + num(scene_limits::max_coordinate) + " m of the origin", far);
  }
  return {};
}

// Counts that bound the scene build's memory and time (docs/scenes.md, "Limits").
Expected<void> check_counts(const Scene& s) {
  const auto written = std::size_t(std::count_if(s.trains.begin(), s.trains.end(), [](const WaveTrain& t) { return t.sea_state < 0; }));
  const std::tuple<const char*, std::size_t, std::size_t> counts[] = {
      {"floor.shoals", s.floor.shoals.size(), scene_limits::max_items},
      {"floor.bars", s.floor.bars.size(), scene_limits::max_items},
      {"floor.channels", s.floor.channels.size(), scene_limits::max_items},
      {"walls", s.walls.size(), scene_limits::max_items},
      {"trains", written, scene_limits::max_trains},
      {"sea_states", s.sea_states.size(), scene_limits::max_sea_states},
      {"boxes", s.boxes.size(), scene_limits::max_items},
      {"spheres", s.spheres.size(), scene_limits::max_items}};
  for (const auto& [field, n, most] : counts) {
    if (n > most) return Error{field, "at most " + std::to_string(most) + " entries, got " + std::to_string(n)};
  }
  std::size_t components = 0;
  for (std::size_t i = 0; i < s.sea_states.size(); ++i) {
    components += s.sea_states[i].components;
    if (components > scene_limits::max_components) {
      return Error{at("sea_states", i) + ".components", "at most " + std::to_string(scene_limits::max_components) +
                                                             " components in all sea states together, got " +
                                                             std::to_string(components) + " up to this one"};
    }
  }
  for (std::size_t i = 0; i < s.walls.size(); ++i) {
    if (s.walls[i].points.size() > scene_limits::max_wall_points) {
      return Error{at("walls", i) + ".points", "at most " + std::to_string(scene_limits::max_wall_points) +
                                                   " points, got " + std::to_string(s.walls[i].points.size())};
    }
  }
  return {};
}

// A height map holds three keys of [floor.height_map]; its samples replace the others.
Expected<void> check_height_map(const HeightMap& m) {
  if (m.nx < 2) return bad("floor.height_map.nx", "at least 2 samples", m.nx);
  if (m.ny < 2) return bad("floor.height_map.ny", "at least 2 samples", m.ny);
  const auto& origin = scene_keys::key(scene_keys::height_map, "origin");
  const auto& cell = scene_keys::key(scene_keys::height_map, "cell");
  const auto& mode = scene_keys::key(scene_keys::height_map, "mode");
  if (auto e = scene_keys::check_value(m.origin, origin.range, origin.unit, "floor.height_map.origin"); !e) return e;
  if (auto e = scene_keys::check_value(m.cell, cell.range, cell.unit, "floor.height_map.cell"); !e) return e;
  if (auto e = scene_keys::check_choice(int(m.mode), mode.choices, "floor.height_map.mode"); !e) return e;
  const std::uint64_t expected = std::uint64_t(m.nx) * m.ny;
  if (m.depth.size() != expected) {
    return Error{"floor.height_map.depth", "nx * ny = " + std::to_string(expected) + " values, got " +
                                               std::to_string(m.depth.size())};
  }
  for (std::size_t i = 0; i < m.depth.size(); ++i) {
    if (!std::isfinite(m.depth[i])) return Error{at("floor.height_map.depth", i), "a finite depth (m)"};
  }
  return {};
}

Expected<void> check_walls(const std::vector<Wall>& walls, const Domain& d) {
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const Wall& w = walls[i];
    const std::string p = at("walls", i) + ".points";
    if (w.points.size() < 2) return bad(p, "a polyline of at least 2 points", double(w.points.size()));
    for (std::size_t j = 0; j + 1 < w.points.size(); ++j) {
      const Point2 a = w.points[j], b = w.points[j + 1];
      if (a.x == b.x && a.y == b.y) return Error{at(p, j + 1), "a point distinct from the previous one"};
      if (!segment_meets_rect(a, b, d, 0.5 * w.thickness)) {
        return Error{at(p, j + 1), "a segment that meets the domain [" + num(d.x_min) + ", " + num(d.x_max) + "] x [" +
                                       num(d.y_min) + ", " + num(d.y_max) + "] m (this one lies outside it)"};
      }
    }
  }
  return {};
}

Expected<void> check_trains(const std::vector<WaveTrain>& trains) {
  for (std::size_t i = 0; i < trains.size(); ++i) {
    const WaveTrain& t = trains[i];
    const std::string p = at("trains", i);
    if (t.direction && t.direction->x == 0.0 && t.direction->y == 0.0) {
      return Error{p + ".direction", "a finite non-zero vector"};
    }
    if (t.period.has_value() == t.wavelength.has_value()) {
      return Error{p + ".period", "exactly one of period (s) and wavelength (m)"};
    }
    // Stokes / Miche deep-water limit H/L0 = 0.142 (docs/physics.md 2.6), i.e. k0 A = 0.446.
    const double l0 = two_pi / deep_water_wavenumber(train_omega(t));
    if (t.amplitude > 0.071 * l0) {
      return bad(p + ".amplitude", "at most the deep-water breaking (Stokes) limit 0.071 L0 = " + num(0.071 * l0) +
                                       " m (H/L0 = 0.142, L0 = " + num(l0) + " m)", t.amplitude);
    }
  }
  return {};
}

Expected<void> check_camera(const Scene& s) {
  const ViewCamera& cam = s.camera;
  const Bathymetry floor(s.floor);
  // The still camera, or each key of a moving one: looking somewhere, above the sea floor.
  const auto check_view = [&](Point3 position, Point3 look_at, const std::string& field) -> Expected<void> {
    // The renderer holds both as floats: closer than a centimetre the view direction is lost.
    const double apart = std::hypot(look_at.x - position.x, look_at.y - position.y, look_at.z - position.z);
    if (!(apart >= 0.01)) return bad(field + ".look_at", "a point at least 0.01 m from " + field + ".position", apart);
    const double floor_z = -floor.depth(position.x, position.y);
    if (position.z < floor_z) {
      return bad(field + ".position.z", "a height above the sea floor there (z = " + num(floor_z) + " m)", position.z);
    }
    return {};
  };
  if (cam.keys.empty()) return check_view(cam.position, cam.look_at, "camera");
  if (cam.keys.size() > scene_limits::max_items) {
    return Error{"camera.keys", "at most " + std::to_string(scene_limits::max_items) + " entries, got " +
                                    std::to_string(cam.keys.size())};
  }
  for (std::size_t i = 0; i < cam.keys.size(); ++i) {
    const CameraKey& k = cam.keys[i];
    if (i > 0 && !(k.time > cam.keys[i - 1].time)) {
      return bad(at("camera.keys", i) + ".time", "a time after the key before's (" + num(cam.keys[i - 1].time) + " s)", k.time);
    }
    if (auto e = check_view(k.position, k.look_at, at("camera.keys", i)); !e) return e;
  }
  return {};
}

// Crapper's limit of a capillary wave's steepness, H/L = 0.73, for the coarsest octave.
Expected<void> check_capillary(const CapillaryNoise& c) {
  if (c.amplitude > 0.365 * c.base_wavelength) {
    return bad("capillary.amplitude", "at most 0.365 base_wavelength = " + num(0.365 * c.base_wavelength) +
                                          " m (Crapper's limit of a capillary wave's steepness, H/L = 0.73)", c.amplitude);
  }
  return {};
}

Expected<void> check_dwt(const Scene& s) {
  const DwtSettings& d = s.dwt;
  if (d.initial_rays == 1) return bad("dwt.initial_rays", "0 (automatic) or at least 2", 1.0);
  if (d.initial_rays > d.max_rays) {
    return bad("dwt.initial_rays", "at most dwt.max_rays = " + std::to_string(d.max_rays), d.initial_rays);
  }
  if (d.initial_rays > 0) return {};
  for (std::size_t i = 0; i < s.trains.size(); ++i) {
    const FrontSize f = front_size(s, i, d);
    if (f.rays <= d.max_rays) continue;
    return bad("dwt.insertion_distance",
               "at least " + num(f.width / d.max_rays) + " m: trains[" + std::to_string(i) + "]'s front is " +
                   num(f.width) + " m wide, and a ray every insertion distance would exceed dwt.max_rays = " +
                   std::to_string(d.max_rays),
               d.insertion_distance);
  }
  return {};
}

}  // namespace

double train_omega(const WaveTrain& t) noexcept {
  if (t.period) return *t.period > 0.0 && std::isfinite(*t.period) ? two_pi / *t.period : 0.0;
  if (t.wavelength && *t.wavelength > 0.0 && std::isfinite(*t.wavelength)) {
    return std::sqrt(gravity * two_pi / *t.wavelength);  // L0 = 2 pi g / omega^2
  }
  return 0.0;
}

Point2 train_direction(const WaveTrain& t) noexcept {
  double x, y;
  if (t.direction) {
    x = t.direction->x;
    y = t.direction->y;
  } else {
    x = std::cos(t.direction_deg * std::numbers::pi / 180.0);
    y = std::sin(t.direction_deg * std::numbers::pi / 180.0);
  }
  const double n = std::hypot(x, y);
  if (!(n > 0.0) || !std::isfinite(n)) return {1.0, 0.0};
  return {x / n, y / n};
}

Expected<Scene> validate(Scene scene) {
  if (auto e = check_counts(scene); !e) return e.error();
  if (auto e = check_key_ranges(scene); !e) return e.error();
  if (auto e = check_domain(scene.domain); !e) return e.error();
  if (scene.floor.height_map) {
    if (auto e = check_height_map(*scene.floor.height_map); !e) return e.error();
  }
  if (auto e = check_walls(scene.walls, scene.domain); !e) return e.error();
  if (auto e = check_trains(scene.trains); !e) return e.error();
  if (auto e = check_camera(scene); !e) return e.error();
  if (auto e = check_capillary(scene.capillary); !e) return e.error();
  if (auto e = check_dwt(scene); !e) return e.error();
  // The sea states' components, again from scratch: a valid scene validates to itself.
  std::erase_if(scene.trains, [](const WaveTrain& t) { return t.sea_state >= 0; });
  for (std::size_t i = 0; i < scene.sea_states.size(); ++i) {
    Expected<std::vector<WaveTrain>> components = sea_state_components(scene.sea_states[i], i);
    if (!components) return components.error();
    scene.trains.insert(scene.trains.end(), components->begin(), components->end());
  }
  // Whatever validates builds: at the cheapest quality, at least (build_cost.hpp).
  const BuildCost draft = estimate_build_cost(scene, quality_preset(QualityPreset::draft), 0, 1);
  if (auto e = check_build_cost(draft, "at the draft quality"); !e) return e.error();
  return scene;
}

}  // namespace houle
