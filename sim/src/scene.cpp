#include "houle/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"

namespace houle {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

bool finite(double v) noexcept { return std::isfinite(v); }
bool finite(Point2 p) noexcept { return finite(p.x) && finite(p.y); }
bool finite(Point3 p) noexcept { return finite(p.x) && finite(p.y) && finite(p.z); }

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
std::string at(const char* name, std::size_t i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

// "what was expected, got <value>"
Error bad(std::string field, const std::string& expected, double got) {
  return Error{std::move(field), expected + ", got " + num(got)};
}

// A null optional means the check passed.
using Check = std::optional<Error>;

Check positive(const std::string& field, double v, const char* unit) {
  if (finite(v) && v > 0.0) return {};
  return bad(field, std::string("a finite value > 0 ") + unit, v);
}
Check non_negative(const std::string& field, double v, const char* unit) {
  if (finite(v) && v >= 0.0) return {};
  return bad(field, std::string("a finite value >= 0 ") + unit, v);
}
Check in_range(const std::string& field, double v, double lo, double hi, const char* unit) {
  if (finite(v) && v >= lo && v <= hi) return {};
  return bad(field, "a value in [" + num(lo) + ", " + num(hi) + "]" + (*unit ? std::string(" ") + unit : ""), v);
}
Check finite_value(const std::string& field, double v) {
  if (finite(v)) return {};
  return bad(field, "a finite number", v);
}
Check finite_point(const std::string& field, Point2 p) {
  if (finite(p)) return {};
  return Error{field, "finite coordinates (m)"};
}
Check finite_point(const std::string& field, Point3 p) {
  if (finite(p)) return {};
  return Error{field, "finite coordinates (m)"};
}
Check colour(const std::string& field, LinearRgb c) {
  for (float v : {c.r, c.g, c.b}) {
    if (!(v >= 0.0f && v <= 1.0f)) return bad(field, "linear RGB components in [0, 1]", v);
  }
  return {};
}

// Does segment [a, b] meet the rectangle grown by `margin`? (Liang-Barsky clipping.)
bool segment_meets_rect(Point2 a, Point2 b, const Domain& d, double margin) noexcept {
  double t0 = 0.0, t1 = 1.0;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - (d.x_min - margin), (d.x_max + margin) - a.x, a.y - (d.y_min - margin),
                       (d.y_max + margin) - a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double r = q[i] / p[i];
      if (p[i] < 0.0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  return t0 <= t1;
}

Check check_domain(const Domain& d) {
  for (double v : {d.x_min, d.y_min, d.x_max, d.y_max}) {
    if (!finite(v)) return Error{"domain", "finite bounds (m)"};
  }
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
Check check_counts(const Scene& s) {
  const std::pair<const char*, std::size_t> counts[] = {
      {"floor.shoals", s.floor.shoals.size()}, {"floor.bars", s.floor.bars.size()},
      {"floor.channels", s.floor.channels.size()}, {"walls", s.walls.size()},
      {"trains", s.trains.size()}, {"boxes", s.boxes.size()}, {"spheres", s.spheres.size()}};
  for (const auto& [field, n] : counts) {
    const std::size_t most = std::string_view(field) == "trains" ? scene_limits::max_trains : scene_limits::max_items;
    if (n > most) return Error{field, "at most " + std::to_string(most) + " entries, got " + std::to_string(n)};
  }
  for (std::size_t i = 0; i < s.walls.size(); ++i) {
    if (s.walls[i].points.size() > scene_limits::max_wall_points) {
      return Error{at("walls", i) + ".points", "at most " + std::to_string(scene_limits::max_wall_points) +
                                                   " points, got " + std::to_string(s.walls[i].points.size())};
    }
  }
  return {};
}

Check check_floor(const SeaFloor& f) {
  const FloorBase& b = f.base;
  if (b.kind != FloorKind::flat && b.kind != FloorKind::planar_beach) {
    return Error{"floor.base.kind", "flat or planar_beach"};
  }
  if (auto e = positive("floor.base.depth", b.depth, "m")) return e;
  if (b.kind == FloorKind::planar_beach) {
    if (auto e = in_range("floor.base.slope", b.slope, 1e-6, 1.0, "(tan of the slope)")) return e;
    if (auto e = finite_value("floor.base.shoreward_deg", b.shoreward_deg)) return e;
    if (auto e = finite_point("floor.base.shoreline", b.shoreline)) return e;
  }
  for (std::size_t i = 0; i < f.shoals.size(); ++i) {
    const Shoal& s = f.shoals[i];
    const std::string p = at("floor.shoals", i);
    if (auto e = finite_point(p + ".center", s.center)) return e;
    if (auto e = positive(p + ".semi_axis_a", s.semi_axis_a, "m")) return e;
    if (auto e = positive(p + ".semi_axis_b", s.semi_axis_b, "m")) return e;
    if (auto e = finite_value(p + ".orientation_deg", s.orientation_deg)) return e;
    if (auto e = finite_value(p + ".height", s.height)) return e;
  }
  for (std::size_t i = 0; i < f.bars.size(); ++i) {
    const Bar& s = f.bars[i];
    const std::string p = at("floor.bars", i);
    if (auto e = finite_point(p + ".point", s.point)) return e;
    if (auto e = finite_value(p + ".along_deg", s.along_deg)) return e;
    if (auto e = positive(p + ".half_width", s.half_width, "m")) return e;
    if (auto e = finite_value(p + ".height", s.height)) return e;
  }
  for (std::size_t i = 0; i < f.channels.size(); ++i) {
    const Channel& s = f.channels[i];
    const std::string p = at("floor.channels", i);
    if (auto e = finite_point(p + ".from", s.from)) return e;
    if (auto e = finite_point(p + ".to", s.to)) return e;
    if (auto e = positive(p + ".half_width", s.half_width, "m")) return e;
    if (auto e = finite_value(p + ".depth", s.depth)) return e;
  }
  if (f.height_map) {
    const HeightMap& m = *f.height_map;
    if (m.nx < 2) return bad("floor.height_map.nx", "at least 2 samples", m.nx);
    if (m.ny < 2) return bad("floor.height_map.ny", "at least 2 samples", m.ny);
    if (auto e = finite_point("floor.height_map.origin", m.origin)) return e;
    if (auto e = positive("floor.height_map.cell", m.cell, "m")) return e;
    const std::uint64_t expected = std::uint64_t(m.nx) * m.ny;
    if (m.depth.size() != expected) {
      return Error{"floor.height_map.depth", "nx * ny = " + std::to_string(expected) + " values, got " +
                                                 std::to_string(m.depth.size())};
    }
    for (std::size_t i = 0; i < m.depth.size(); ++i) {
      if (!std::isfinite(m.depth[i])) return Error{at("floor.height_map.depth", i), "a finite depth (m)"};
    }
  }
  return {};
}

Check check_walls(const std::vector<Wall>& walls, const Domain& d) {
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const Wall& w = walls[i];
    const std::string p = at("walls", i);
    if (w.points.size() < 2) return bad(p + ".points", "a polyline of at least 2 points", double(w.points.size()));
    if (auto e = non_negative(p + ".thickness", w.thickness, "m")) return e;
    if (auto e = in_range(p + ".reflection", w.reflection, 0.0, 1.0, "")) return e;
    if (auto e = finite_value(p + ".crest_height", w.crest_height)) return e;
    for (std::size_t j = 0; j < w.points.size(); ++j) {
      if (auto e = finite_point(at((p + ".points").c_str(), j), w.points[j])) return e;
    }
    for (std::size_t j = 0; j + 1 < w.points.size(); ++j) {
      const Point2 a = w.points[j], b = w.points[j + 1];
      if (a.x == b.x && a.y == b.y) return Error{at((p + ".points").c_str(), j + 1), "a point distinct from the previous one"};
      if (!segment_meets_rect(a, b, d, 0.5 * w.thickness)) {
        return Error{at((p + ".points").c_str(), j + 1),
                     "a segment that meets the domain [" + num(d.x_min) + ", " + num(d.x_max) + "] x [" +
                         num(d.y_min) + ", " + num(d.y_max) + "] m (this one lies outside it)"};
      }
    }
  }
  return {};
}

Check check_trains(const std::vector<WaveTrain>& trains) {
  for (std::size_t i = 0; i < trains.size(); ++i) {
    const WaveTrain& t = trains[i];
    const std::string p = at("trains", i);
    if (t.direction) {
      if (!finite(*t.direction) || (t.direction->x == 0.0 && t.direction->y == 0.0)) {
        return Error{p + ".direction", "a finite non-zero vector"};
      }
    } else if (auto e = finite_value(p + ".direction_deg", t.direction_deg)) {
      return e;
    }
    if (t.period.has_value() == t.wavelength.has_value()) {
      return Error{p + ".period", "exactly one of period (s) and wavelength (m)"};
    }
    if (t.period) {
      if (auto e = positive(p + ".period", *t.period, "s")) return e;
    } else if (auto e = positive(p + ".wavelength", *t.wavelength, "m")) {
      return e;
    }
    if (auto e = non_negative(p + ".amplitude", t.amplitude, "m")) return e;
    // Stokes / Miche deep-water limit H/L0 = 0.142 (docs/physics.md 2.6), i.e. k0 A = 0.446.
    const double l0 = two_pi / deep_water_wavenumber(train_omega(t));
    if (t.amplitude > 0.071 * l0) {
      return bad(p + ".amplitude", "at most the deep-water breaking (Stokes) limit 0.071 L0 = " + num(0.071 * l0) +
                                       " m (H/L0 = 0.142, L0 = " + num(l0) + " m)", t.amplitude);
    }
    if (auto e = finite_value(p + ".phase", t.phase)) return e;
    if (auto e = in_range(p + ".steepness", t.steepness, 0.0, 1.0, "")) return e;
  }
  return {};
}

Check check_objects(const Scene& s) {
  for (std::size_t i = 0; i < s.boxes.size(); ++i) {
    const Box& b = s.boxes[i];
    const std::string p = at("boxes", i);
    if (auto e = finite_point(p + ".center", b.center)) return e;
    if (auto e = positive(p + ".half_extent.x", b.half_extent.x, "m")) return e;
    if (auto e = positive(p + ".half_extent.y", b.half_extent.y, "m")) return e;
    if (auto e = positive(p + ".half_extent.z", b.half_extent.z, "m")) return e;
    if (auto e = finite_value(p + ".yaw_deg", b.yaw_deg)) return e;
    if (auto e = colour(p + ".colour", b.colour)) return e;
  }
  for (std::size_t i = 0; i < s.spheres.size(); ++i) {
    const Sphere& b = s.spheres[i];
    const std::string p = at("spheres", i);
    if (auto e = finite_point(p + ".center", b.center)) return e;
    if (auto e = positive(p + ".radius", b.radius, "m")) return e;
    if (auto e = colour(p + ".colour", b.colour)) return e;
  }
  return {};
}

Check check_view(const Scene& s) {
  const CapillaryNoise& c = s.capillary;
  if (auto e = non_negative("capillary.amplitude", c.amplitude, "m")) return e;
  if (auto e = positive("capillary.base_wavelength", c.base_wavelength, "m")) return e;
  if (auto e = in_range("capillary.lacunarity", c.lacunarity, 1.25, 4.0, "")) return e;
  if (c.max_octaves < 0 || c.max_octaves > 8) return bad("capillary.max_octaves", "an integer in [0, 8]", c.max_octaves);
  if (auto e = non_negative("capillary.time_scale", c.time_scale, "")) return e;

  if (auto e = finite_value("sun.azimuth_deg", s.sun.azimuth_deg)) return e;
  if (auto e = in_range("sun.elevation_deg", s.sun.elevation_deg, -90.0, 90.0, "degrees")) return e;
  if (auto e = in_range("sky.turbidity", s.sky.turbidity, 1.7, 10.0, "")) return e;

  const ViewCamera& cam = s.camera;
  if (auto e = finite_point("camera.position", cam.position)) return e;
  if (auto e = finite_point("camera.look_at", cam.look_at)) return e;
  if (cam.position.x == cam.look_at.x && cam.position.y == cam.look_at.y && cam.position.z == cam.look_at.z) {
    return Error{"camera.look_at", "a point different from camera.position"};
  }
  if (!(cam.vertical_fov_deg > 0.0 && cam.vertical_fov_deg < 180.0)) {
    return bad("camera.vertical_fov_deg", "a value in (0, 180) degrees", cam.vertical_fov_deg);
  }
  const double floor_z = -Bathymetry(s.floor).depth(cam.position.x, cam.position.y);
  if (cam.position.z < floor_z) {
    return bad("camera.position.z", "a height above the sea floor there (z = " + num(floor_z) + " m)", cam.position.z);
  }
  if (auto e = non_negative("water.extra_absorption", s.water.extra_absorption, "1/m")) return e;
  if (auto e = in_range("water.dominant_wavelength_nm", s.water.dominant_wavelength_nm, 380.0, 780.0, "nm")) return e;
  return {};
}

Check check_dwt(const DwtSettings& d) {
  if (d.initial_rays == 1) return bad("dwt.initial_rays", "0 (automatic) or at least 2", 1.0);
  if (auto e = non_negative("dwt.front_width", d.front_width, "m")) return e;
  if (auto e = positive("dwt.step", d.step, "m")) return e;
  if (auto e = positive("dwt.insertion_distance", d.insertion_distance, "m")) return e;
  if (auto e = positive("dwt.min_depth", d.min_depth, "m")) return e;
  if (auto e = in_range("dwt.min_depth_wavelengths", d.min_depth_wavelengths, 0.0, 0.5, "")) return e;
  if (auto e = in_range("dwt.breaker_index", d.breaker_index, 0.1, 1.5, "")) return e;
  if (auto e = in_range("dwt.max_refraction_coefficient", d.max_refraction_coefficient, 1.0, 100.0, "")) return e;
  if (d.diffraction_model != DiffractionModel::exact && d.diffraction_model != DiffractionModel::paper &&
      d.diffraction_model != DiffractionModel::paper_corrected) {
    return Error{"dwt.diffraction_model", "exact, paper or paper_corrected"};
  }
  if (d.max_rays < 2 || d.max_rays < d.initial_rays || d.max_rays > scene_limits::max_rays) {
    return bad("dwt.max_rays", "at least 2, at least initial_rays and at most " + std::to_string(scene_limits::max_rays),
               d.max_rays);
  }
  if (d.max_samples < 64 || d.max_samples > scene_limits::max_samples) {
    return bad("dwt.max_samples", "a count in [64, " + std::to_string(scene_limits::max_samples) + "]", d.max_samples);
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
  if (auto e = check_domain(scene.domain)) return *e;
  if (auto e = check_counts(scene)) return *e;
  if (auto e = check_floor(scene.floor)) return *e;
  if (auto e = check_walls(scene.walls, scene.domain)) return *e;
  if (auto e = check_trains(scene.trains)) return *e;
  if (auto e = check_objects(scene)) return *e;
  if (auto e = check_view(scene)) return *e;
  if (auto e = check_dwt(scene.dwt)) return *e;
  return scene;
}

}  // namespace houle
