#include "scene_generator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <type_traits>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_keys.hpp"

namespace houle::test {
namespace {

namespace keys = scene_keys;
constexpr double inf = std::numeric_limits<double>::infinity();

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  double unit() { return double(engine_() >> 11) * 0x1p-53; }
  bool chance(double p) { return unit() < p; }
  double uniform(double lo, double hi) { return std::clamp(lo + (hi - lo) * unit(), lo, hi); }
  double log_uniform(double lo, double hi) { return std::clamp(lo * std::pow(hi / lo, unit()), lo, hi); }
  std::int64_t integer(std::int64_t lo, std::int64_t hi) { return lo + std::int64_t(engine_() % std::uint64_t(hi - lo + 1)); }

 private:
  std::mt19937_64 engine_;
};

// How many items an array holds: mostly none or a few, sometimes its limit.
std::size_t count(Draw& d, std::size_t most) {
  const double p = d.unit();
  if (p < 0.4) return 0;
  if (p < 0.8) return std::size_t(d.integer(1, 3));
  if (p < 0.97 || most <= 16) return std::size_t(d.integer(4, std::int64_t(std::min<std::size_t>(most, 16))));
  return d.chance(0.5) ? most : std::size_t(d.integer(17, std::int64_t(most)));
}

// A number in `r`, its ends included; `scale` (m, s, ...) sets the size of unbounded values.
double number(Draw& d, const keys::Range& r, double scale) {
  const double lo = r.lo_open ? std::nextafter(r.lo, inf) : r.lo, hi = r.hi_open ? std::nextafter(r.hi, -inf) : r.hi;
  const double p = d.unit();
  if (std::isfinite(lo) && std::isfinite(hi)) {
    if (p < 0.05) return lo;
    if (p < 0.10) return hi;
    if (lo > 0.0 && hi > 100.0 * lo && p < 0.7) return d.log_uniform(lo, hi);
    return d.uniform(lo, hi);
  }
  const double huge = std::numeric_limits<double>::max();
  if (std::isfinite(lo)) {
    if (p < 0.05) return lo;
    if (p < 0.08) return huge;
    return lo + scale * d.log_uniform(1e-3, 1e3);
  }
  if (p < 0.03) return d.chance(0.5) ? huge : -huge;
  return (d.chance(0.5) ? 1.0 : -1.0) * scale * d.log_uniform(1e-3, 1e3);
}

struct Context {
  Draw& d;
  Domain domain;
  double size() const { return std::max(domain.x_max - domain.x_min, domain.y_max - domain.y_min); }
  // Positions mostly in and around the domain, sometimes anywhere in range.
  double coordinate(const keys::Range& r, double lo, double hi) {
    if (d.chance(0.85)) return d.uniform(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo));
    return number(d, r, size());
  }
  Point2 point(const keys::Range& r) {
    return {coordinate(r, domain.x_min, domain.x_max), coordinate(r, domain.y_min, domain.y_max)};
  }
};

template <class S>
void draw_keys(Context& c, const keys::Section<S>& section, S& item) {
  Draw& d = c.d;
  for (const keys::Key<S>& k : section.keys) {
    std::visit(
        [&](auto member) {
          auto& v = item.*member;
          using T = std::remove_cvref_t<decltype(v)>;
          const double scale = k.unit == "m" ? c.size() : 1.0;
          if constexpr (std::is_enum_v<T>) {
            v = T(k.choices[std::size_t(d.integer(0, std::int64_t(k.choices.size()) - 1))].value);
          } else if constexpr (std::is_same_v<T, bool>) {
            v = d.chance(0.5);
          } else if constexpr (std::is_integral_v<T>) {
            v = T(std::llround(number(d, k.range, 1.0)));
          } else if constexpr (std::is_same_v<T, double>) {
            v = number(d, k.range, scale);
          } else if constexpr (std::is_same_v<T, std::optional<double>>) {
            v = d.chance(0.5) ? std::optional<double>(number(d, k.range, scale)) : std::nullopt;
          } else if constexpr (std::is_same_v<T, Point2>) {
            v = c.point(k.range);
          } else if constexpr (std::is_same_v<T, std::optional<Point2>>) {
            v = d.chance(0.5) ? std::optional<Point2>(Point2{number(d, k.range, 1.0), number(d, k.range, 1.0)}) : std::nullopt;
          } else if constexpr (std::is_same_v<T, Point3>) {
            if (k.range.lo == keys::coordinate.lo && k.range.hi == keys::coordinate.hi) {
              const Point2 p = c.point(k.range);
              v = {p.x, p.y, c.coordinate(k.range, -20.0, 20.0)};
            } else {
              v = {number(d, k.range, scale), number(d, k.range, scale), number(d, k.range, scale)};
            }
          } else if constexpr (std::is_same_v<T, LinearRgb>) {
            v = {float(number(d, k.range, 1.0)), float(number(d, k.range, 1.0)), float(number(d, k.range, 1.0))};
          } else if constexpr (std::is_same_v<T, std::vector<Point2>>) {
            v.resize(d.chance(0.95) ? std::size_t(d.integer(2, 6)) : std::size_t(d.integer(7, scene_limits::max_wall_points)));
            for (Point2& p : v) p = c.point(k.range);
          }
        },
        k.member);
  }
}

template <class S>
void draw_section(Context& c, const keys::Section<S>& section, Scene& s) {
  if (section.table_in) draw_keys(c, section, section.table_in(s));
  if (!section.array_in) return;
  std::vector<S>& items = section.array_in(s);
  const bool trains = std::is_same_v<S, WaveTrain>;
  items.resize(count(c.d, trains ? scene_limits::max_trains : scene_limits::max_items));
  for (S& item : items) draw_keys(c, section, item);
}

// The rules between keys (scene.cpp), met by adjusting the drawn values.
void meet_the_rules(Draw& d, Scene& s) {
  for (WaveTrain& t : s.trains) {
    if (t.period.has_value() == t.wavelength.has_value()) {
      if (d.chance(0.5)) t.period = t.period.value_or(d.uniform(1.0, 20.0)), t.wavelength.reset();
      else t.wavelength = t.wavelength.value_or(d.uniform(1.5, 600.0)), t.period.reset();
    }
    if (t.direction && t.direction->x == 0.0 && t.direction->y == 0.0) t.direction.reset();
    const double l0 = 2.0 * std::numbers::pi / deep_water_wavenumber(train_omega(t));
    t.amplitude = 0.071 * l0 * (d.chance(0.05) ? 1.0 : std::pow(d.unit(), 3.0));
  }
  s.capillary.amplitude = std::min(s.capillary.amplitude, 0.365 * s.capillary.base_wavelength * d.unit());
  for (Wall& w : s.walls) {
    // Each segment meets the domain: every point but the ends inside it, and the first of two.
    const Domain& m = s.domain;
    for (std::size_t j = 0; j < w.points.size(); ++j) {
      if (j == 0 ? w.points.size() == 2 : j + 1 < w.points.size()) {
        w.points[j] = {d.uniform(m.x_min, m.x_max), d.uniform(m.y_min, m.y_max)};
      }
    }
    for (std::size_t j = 1; j < w.points.size(); ++j) {
      if (w.points[j].x == w.points[j - 1].x && w.points[j].y == w.points[j - 1].y) w.points[j].x += 1.0;
    }
  }
  DwtSettings& dwt = s.dwt;
  if (dwt.initial_rays == 1) dwt.initial_rays = 2;
  if (dwt.initial_rays > dwt.max_rays) dwt.initial_rays = d.chance(0.5) ? 0 : dwt.max_rays;
  if (dwt.initial_rays == 0) {
    const Domain& m = s.domain;
    const double diagonal = std::hypot(m.x_max - m.x_min, m.y_max - m.y_min);
    dwt.insertion_distance = std::max(dwt.insertion_distance, 1.01 * diagonal / dwt.max_rays);
  }
  ViewCamera& cam = s.camera;
  // A camera path's keys in increasing time, mostly (a key that repeats the time before stays, to be refused).
  if (d.chance(0.9)) {
    std::sort(cam.keys.begin(), cam.keys.end(), [](const CameraKey& a, const CameraKey& b) { return a.time < b.time; });
  }
  const double floor_z = -Bathymetry(s.floor).depth(cam.position.x, cam.position.y);
  if (cam.position.z < floor_z) cam.position.z = std::min(floor_z + d.log_uniform(0.01, 100.0), scene_limits::max_coordinate);
  if (std::hypot(cam.look_at.x - cam.position.x, cam.look_at.y - cam.position.y, cam.look_at.z - cam.position.z) < 0.01) {
    cam.look_at.y = cam.position.y + (cam.position.y > 0.0 ? -1.0 : 1.0);
  }
}

HeightMap draw_height_map(Context& c) {
  Draw& d = c.d;
  HeightMap m;
  m.nx = std::uint32_t(d.chance(0.9) ? d.integer(2, 64) : d.integer(65, 2048));
  m.ny = std::uint32_t(d.chance(0.9) ? d.integer(2, 64) : d.integer(65, 2048));
  const auto& cell = keys::key(keys::height_map, "cell");
  m.cell = d.chance(0.7) ? std::clamp(c.size() / double(std::max(m.nx, m.ny)), cell.range.lo, cell.range.hi)
                         : number(d, cell.range, 1.0);
  m.origin = c.point(keys::coordinate);
  m.mode = d.chance(0.5) ? HeightMapMode::absolute : HeightMapMode::additive;
  const double deep = d.log_uniform(0.1, 11000.0), high = -d.log_uniform(0.1, 11000.0);
  // Grey levels as an image holds them (16 bits), so that the scene file reads back the same floor.
  m.depth.resize(std::size_t(m.nx) * m.ny);
  for (float& v : m.depth) v = float(deep + (high - deep) * (double(d.integer(0, 65535)) / 65535.0));
  return m;
}

}  // namespace

Scene generate_scene(std::uint64_t seed) {
  Draw d(seed);
  Scene s;
  // The domain first: positions and lengths are drawn around it.
  const double most = scene_limits::max_domain_side;
  const auto side = [&] { return d.chance(0.7) ? d.log_uniform(10.0, 400.0) : d.chance(0.5) ? d.log_uniform(1e-3, most) : most; };
  const double wx = side(), wy = side();
  const double far = scene_limits::max_coordinate;
  const double x0 = d.chance(0.8) ? d.uniform(-wx, 0.0) : d.uniform(-far, far - wx);
  const double y0 = d.chance(0.8) ? d.uniform(-wy, 0.0) : d.uniform(-far, far - wy);
  s.domain = {x0, y0, x0 + wx, y0 + wy};
  Context c{d, s.domain};
  keys::for_each_section([&]<class S>(const keys::Section<S>& section) {
    if constexpr (!std::is_same_v<S, Domain> && !std::is_same_v<S, HeightMapFile>) draw_section(c, section, s);
  });
  if (d.chance(0.1)) s.floor.height_map = draw_height_map(c);
  meet_the_rules(d, s);
  return s;
}

// ---- The scene as TOML --------------------------------------------------------------------------

namespace {

std::string text(double v) { return keys::number_text(v); }
std::string text(Point2 p) { return std::string("[").append(text(p.x)).append(", ").append(text(p.y)).append("]"); }

template <class S>
void write_keys(std::ostream& out, const keys::Section<S>& section, const S& item) {
  for (const keys::Key<S>& k : section.keys) {
    std::visit(
        [&](auto member) {
          const auto& v = item.*member;
          using T = std::remove_cvref_t<decltype(v)>;
          const std::string name(k.name);
          if constexpr (std::is_enum_v<T>) {
            for (const keys::Choice& ch : k.choices) {
              if (ch.value == int(v)) out << name << " = \"" << ch.name << "\"\n";
            }
          } else if constexpr (std::is_same_v<T, bool>) {
            out << name << " = " << (v ? "true" : "false") << "\n";
          } else if constexpr (std::is_integral_v<T>) {
            out << name << " = " << std::int64_t(v) << "\n";
          } else if constexpr (std::is_same_v<T, double>) {
            out << name << " = " << text(v) << "\n";
          } else if constexpr (std::is_same_v<T, std::optional<double>> || std::is_same_v<T, std::optional<Point2>>) {
            if (v) out << name << " = " << text(*v) << "\n";
          } else if constexpr (std::is_same_v<T, Point2>) {
            out << name << " = " << text(v) << "\n";
          } else if constexpr (std::is_same_v<T, Point3>) {
            out << name << " = [" << text(v.x) << ", " << text(v.y) << ", " << text(v.z) << "]\n";
          } else if constexpr (std::is_same_v<T, LinearRgb>) {
            out << name << " = [" << text(v.r) << ", " << text(v.g) << ", " << text(v.b) << "]\n";
          } else if constexpr (std::is_same_v<T, std::vector<Point2>>) {
            out << name << " = [";
            for (std::size_t i = 0; i < v.size(); ++i) out << (i ? ", " : "") << text(v[i]);
            out << "]\n";
          }
        },
        k.member);
  }
}

}  // namespace

std::string height_map_pgm(const HeightMap& m, double& depth_at_black, double& depth_at_white) {
  const auto [lo, hi] = std::minmax_element(m.depth.begin(), m.depth.end());
  depth_at_black = *hi;
  depth_at_white = *lo == *hi ? double(*hi) - 1.0 : double(*lo);
  std::ostringstream out;
  out << "P2\n" << m.nx << " " << m.ny << "\n65535\n";
  for (std::uint32_t j = m.ny; j-- > 0;) {  // the image's first row is north
    for (std::uint32_t i = 0; i < m.nx; ++i) {
      const double grey = (double(m.depth[std::size_t(j) * m.nx + i]) - depth_at_black) / (depth_at_white - depth_at_black);
      out << std::lround(std::clamp(grey, 0.0, 1.0) * 65535.0) << (i + 1 < m.nx ? " " : "\n");
    }
  }
  return out.str();
}

std::string scene_toml(const Scene& scene, const std::string& map_file) {
  std::ostringstream out;
  Scene s = scene;
  keys::for_each_section([&]<class S>(const keys::Section<S>& section) {
    if constexpr (std::is_same_v<S, HeightMapFile>) {
      if (!s.floor.height_map) return;
      const HeightMap& m = *s.floor.height_map;
      HeightMapFile f{map_file, m.origin, m.cell, 0.0, 0.0, m.mode};
      height_map_pgm(m, f.depth_at_black, f.depth_at_white);
      out << "\n[" << section.path << "]\nfile = \"" << map_file << "\"\n";
      write_keys(out, section, f);
    } else {
      if (section.table_in) {
        out << "\n[" << section.path << "]\n";
        write_keys(out, section, section.table_in(s));
      }
      if (section.array_in) {
        for (const S& item : section.array_in(s)) {
          out << "\n[[" << section.path << "]]\n";
          write_keys(out, section, item);
        }
      }
    }
  });
  return out.str();
}

}  // namespace houle::test
