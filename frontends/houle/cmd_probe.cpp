#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/scene_geometry.hpp"
#include "houle/sim/sea_surface.hpp"
#include "probe_sea.hpp"
#include "scene_source.hpp"

namespace houle::cli {
namespace {

// Points x times: a bound on the output (16 trains a row in CSV make 16 million lines at most).
constexpr std::size_t max_probes = 1000000;

// A number for JSON (which has no NaN or infinity: such a value is `none`, null) or CSV (empty).
std::string number(double v, const char* none) {
  char buf[32];
  if (!std::isfinite(v)) return none;
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

enum class Format { text, json, csv };

// The times of --times T0:T1:DT (T0, T0 + DT, ... up to T1 inclusive), or an error for `args`.
std::vector<double> parse_times(Args& args, const std::string& text) {
  const auto v = parse_list(text, ':');
  if (!v || v->size() != 3) {
    args.fail("--times expects T0:T1:DT in s (from T0 to T1 inclusive in steps of DT), got '" + text + "'");
    return {};
  }
  const double t0 = (*v)[0], t1 = (*v)[1], dt = (*v)[2];
  if (!(dt > 0.0)) {
    args.fail("--times " + text + ": the step DT must be > 0 s");
    return {};
  }
  if (t1 < t0) {
    args.fail("--times " + text + ": T1 must be >= T0");
    return {};
  }
  // The last step may land a rounding error short of T1: it still counts.
  const double steps = (t1 - t0) / dt;
  if (!(steps < double(max_probes))) {
    args.fail("--times " + text + ": more than " + std::to_string(max_probes) + " times (at most " +
                std::to_string(max_probes) + " points x times)");
    return {};
  }
  std::vector<double> times(std::size_t(std::floor(steps + 1e-9 * std::max(1.0, steps))) + 1);
  for (std::size_t i = 0; i < times.size(); ++i) times[i] = std::min(t0 + double(i) * dt, t1);
  return times;
}

void print_text_row(double x, double y, double t, Place place, double depth, float h, float gx, float gy) {
  std::printf("(%g, %g) t=%.10g s: ", x, y, t);
  switch (place) {
    case Place::land: std::printf("on land (floor %.2f m above still water): no waves\n", -depth); return;
    case Place::wall: std::printf("inside a wall: no water\n"); return;
    case Place::outside:
      std::printf("outside the domain (no rays traced; each train continues the wave at the edge), depth %.2f m, ", depth);
      break;
    case Place::water: std::printf("water %.2f m deep, ", depth); break;
  }
  std::printf("height %.4f m, gradient (%.4f, %.4f)\n", h, gx, gy);
}

}  // namespace

int cmd_probe(std::span<char* const> argv) {
  Args args("probe", argv);
  if (args.flag("--help")) {
    std::puts(R"(usage: houle probe [SCENE] --at X,Y[,T] [--at ...] [--times T0:T1:DT] [--json | --csv]

Queries the waves of SCENE (the built-in coast without one) at points (m) and times T (s, default 0):
where the point is, the depth, the surface height and gradient, and per train the local amplitude,
the amplitude relative to the deep-water one (shoaling x refraction x diffraction), the diffraction
coefficient K', the wavelength, the direction of travel and the phase.

  --at X,Y[,T]       a point, and the time there (repeatable)
  --times T0:T1:DT   every --at point at T0, T0 + DT, ... up to T1 inclusive (DT > 0, T1 >= T0, at
                     most 1000000 points x times); the points then take no T of their own
  --json             one JSON array, an object per point and time (point by point, time by time):
                     x, y, t, where, depth, height, grad_x, grad_y, trains (a list of objects with
                     the per-train fields below); a value that is not finite is null
  --csv              a header line, then a row per point, time and train (in that order):
                     x,y,t,where,depth,height,grad_x,grad_y,train,amplitude,relative_amplitude,
                     diffraction,wavelength,direction_deg,phase,incident,diffracted,reflected (a
                     scene without trains gives one row
                     per point and time, its train fields empty; a value that is not finite is empty)

where: water; land (the floor at or above still water: no waves); wall (within half its thickness
of a wall's axis: no water); outside (outside the scene's domain, where no rays are traced and each
train continues the wave at the nearest point of the domain's edge; more than 100 km out is refused). depth: m below still water,
from the scene's floor (negative on land). height (m above still water), grad_x, grad_y: the trains
and their reflected waves summed (capillary ripples not included). Per train: amplitude (m), relative_amplitude (A/A0), diffraction (K'), wavelength
(m), direction_deg (travel, counter-clockwise from +x), phase (rad, in [-pi, pi]), and the amplitude
(m) of each part of its field: incident (its rays), diffracted (every pierhead's diffracted wave),
reflected (its reflected waves); the parts add as waves, not as amplitudes, and breaking scales them
as it scales their sum. The text output
says plainly where a point is on land or in a wall and gives no wave values there; JSON and CSV give
the values the surface evaluates everywhere, with `where` beside them.)");
    return 0;
  }
  const std::vector<std::string> at = args.values("--at");
  const std::optional<std::string> times_text = args.value("--times");
  const bool json = args.flag("--json"), csv = args.flag("--csv");
  const std::vector<std::string> positionals = args.rest();
  const Format format = json ? Format::json : csv ? Format::csv : Format::text;
  if (json && csv) args.fail("--json and --csv exclude each other");
  std::vector<std::vector<double>> points;
  for (const std::string& a : at) {
    const auto p = parse_list(a);
    if (!p || p->size() < 2 || p->size() > 3) {
      args.fail("--at expects X,Y or X,Y,T in m and s, got '" + a + "'");
      break;
    }
    if (times_text && p->size() == 3) {
      args.fail("--at " + a + " gives its own time, and --times gives the times of every point: give --at X,Y with --times");
      break;
    }
    points.push_back(*p);
  }
  if (!args.failed() && points.empty()) args.fail("expects at least one --at X,Y[,T]");
  std::vector<double> times;
  if (times_text && !args.failed()) {
    times = parse_times(args, *times_text);
    if (!args.failed() && times.size() * points.size() > max_probes) {
      args.fail("--times " + *times_text + " at " + std::to_string(points.size()) + " points makes " +
                std::to_string(times.size() * points.size()) + " probes (points x times), more than " +
                std::to_string(max_probes));
    }
  }
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  const std::optional<Scene> scene = scene_from_args(positionals, "probe");
  if (!scene) return 2;
  for (const std::vector<double>& p : points) {
    if (distance_outside(scene->domain, p[0], p[1]) > max_probe_distance) {
      std::fprintf(stderr, "houle probe: --at %g,%g: more than %g km outside the domain [%g, %g] x [%g, %g] m, where single-precision positions no longer hold the waves\n",
                   p[0], p[1], max_probe_distance / 1e3, scene->domain.x_min, scene->domain.x_max, scene->domain.y_min,
                   scene->domain.y_max);
      return 2;
    }
  }
  int exit_code = 0;
  std::optional<SeaSurface> sea = build_probe_sea(*scene, scene_name(positionals), "probe", exit_code);
  if (!sea) return exit_code;
  const Bathymetry floor(scene->floor);
  if (format == Format::json) std::printf("[");
  if (format == Format::csv) {
    std::printf("x,y,t,where,depth,height,grad_x,grad_y,train,amplitude,relative_amplitude,diffraction,wavelength,"
                "direction_deg,phase,incident,diffracted,reflected\n");
  }
  bool first = true;
  for (const std::vector<double>& p : points) {
    const float x = float(p[0]), y = float(p[1]);
    const Place place = locate(*scene, floor, p[0], p[1]);
    const double depth = floor.depth(p[0], p[1]);
    const std::string where(place_name(place));
    const std::size_t n_times = times.empty() ? 1 : times.size();
    for (std::size_t ti = 0; ti < n_times; ++ti) {
      const double t = !times.empty() ? times[ti] : p.size() > 2 ? p[2] : 0.0;
      sea->set_time(t);
      float h, gx, gy;
      sea->eval(&x, &y, 1, &h, &gx, &gy);
      // Point and time fields, as JSON members or the first CSV columns.
      char head[256];
      if (format == Format::json) {
        std::snprintf(head, sizeof head, "\"x\": %g, \"y\": %g, \"t\": %.10g, \"where\": \"%s\", \"depth\": %s", p[0], p[1], t,
                      where.c_str(), number(depth, "null").c_str());
        std::printf("%s\n {%s, \"height\": %s, \"grad_x\": %s, \"grad_y\": %s, \"trains\": [", first ? "" : ",", head,
                    number(h, "null").c_str(), number(gx, "null").c_str(), number(gy, "null").c_str());
      } else if (format == Format::csv) {
        std::snprintf(head, sizeof head, "%g,%g,%.10g,%s,%s,%s,%s,%s", p[0], p[1], t, where.c_str(), number(depth, "").c_str(),
                      number(h, "").c_str(), number(gx, "").c_str(), number(gy, "").c_str());
        if (scene->trains.empty()) std::printf("%s,,,,,,,,,,\n", head);
      } else {
        print_text_row(p[0], p[1], t, place, depth, h, gx, gy);
      }
      first = false;
      const bool text_values = place == Place::water || place == Place::outside;
      for (std::size_t k = 0; k < scene->trains.size(); ++k) {
        const TrainProbe tp = sea->probe(k, x, y);
        if (format == Format::json) {
          std::printf("%s{\"amplitude\": %s, \"relative_amplitude\": %s, \"diffraction\": %s, \"wavelength\": %s, "
                      "\"direction_deg\": %s, \"phase\": %s, \"incident\": %s, \"diffracted\": %s, \"reflected\": %s}",
                      k ? ", " : "", number(tp.amplitude, "null").c_str(), number(tp.relative_amplitude, "null").c_str(),
                      number(tp.diffraction, "null").c_str(), number(tp.wavelength, "null").c_str(),
                      number(tp.direction_deg, "null").c_str(), number(tp.phase, "null").c_str(),
                      number(tp.incident, "null").c_str(), number(tp.diffracted, "null").c_str(),
                      number(tp.reflected, "null").c_str());
        } else if (format == Format::csv) {
          std::printf("%s,%zu,%s,%s,%s,%s,%s,%s,%s,%s,%s\n", head, k, number(tp.amplitude, "").c_str(),
                      number(tp.relative_amplitude, "").c_str(), number(tp.diffraction, "").c_str(),
                      number(tp.wavelength, "").c_str(), number(tp.direction_deg, "").c_str(), number(tp.phase, "").c_str(),
                      number(tp.incident, "").c_str(), number(tp.diffracted, "").c_str(), number(tp.reflected, "").c_str());
        } else if (text_values) {
          std::printf("  train %zu: amplitude %.4f m (x%.3f of deep water, diffraction K' %.3f), wavelength %.3f m, towards "
                      "%.1f deg, phase %.3f rad; parts: incident %.4f m, diffracted %.4f m, reflected %.4f m\n",
                      k, tp.amplitude, tp.relative_amplitude, tp.diffraction, tp.wavelength, tp.direction_deg, tp.phase,
                      tp.incident, tp.diffracted, tp.reflected);
        }
      }
      if (format == Format::json) std::printf("]}");
    }
  }
  if (format == Format::json) std::printf("\n]\n");
  return 0;
}

}  // namespace houle::cli
