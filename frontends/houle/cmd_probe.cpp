#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/sea_surface.hpp"
#include "scene_source.hpp"

namespace houle::cli {
namespace {

// Positions are floats: 100 km out they still resolve 8 mm, a small fraction of the shortest
// wavelength; at 1e9 m the resolution is 64 m and the height is noise, then inf and NaN.
constexpr double max_probe_distance = 100e3;  // m outside the domain

double distance_outside(const Domain& d, double x, double y) {
  return std::max({d.x_min - x, x - d.x_max, d.y_min - y, y - d.y_max, 0.0});
}

// JSON has no NaN or infinity: such a value is null.
std::string json_number(double v) {
  char buf[32] = "null";
  if (std::isfinite(v)) std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

int cmd_probe(std::span<char* const> argv) {
  Args args("probe", argv);
  if (args.flag("--help")) {
    std::puts(R"(usage: houle probe [SCENE] --at X,Y[,T] [--at ...] [--json]

Queries the waves of SCENE (the built-in coast without one) at points (m) and times T (s, default 0):
the surface height and gradient, and per train the local amplitude, the amplitude relative to the
deep-water one (shoaling x refraction x diffraction), the diffraction coefficient K', the wavelength, the direction of travel and
the phase.)");
    return 0;
  }
  const std::vector<std::string> at = args.values("--at");
  const bool json = args.flag("--json");
  const std::vector<std::string> positionals = args.rest();
  std::vector<std::vector<double>> points;
  for (const std::string& a : at) {
    const auto p = parse_list(a);
    if (!p || p->size() < 2 || p->size() > 3) {
      args.fail("--at expects X,Y or X,Y,T in m and s, got '" + a + "'");
      break;
    }
    points.push_back(*p);
  }
  if (!args.failed() && points.empty()) args.fail("expects at least one --at X,Y[,T]");
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
  const float sea_cell = Quality{}.sea_cell;  // the realtime quality's resampling grid
  if (const Expected<void> fits = check_build_memory(*scene, sea_cell, 0); !fits) {
    std::fprintf(stderr, "houle probe: %s: %s: %s\n", scene_name(positionals).c_str(), fits.error().field.c_str(),
                 fits.error().message.c_str());
    return 2;
  }
  Expected<WaveField> field = trace_wave_field(*scene, 2);
  if (!field) {
    std::fprintf(stderr, "houle probe: %s: %s\n", field.error().field.c_str(), field.error().message.c_str());
    return 2;
  }
  Expected<SeaSurface> sea = SeaSurface::build(*scene, field.value(), sea_cell);
  if (!sea) {
    std::fprintf(stderr, "houle probe: %s\n", sea.error().message.c_str());
    return 1;
  }
  if (json) std::printf("[");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float x = float(points[i][0]), y = float(points[i][1]);
    const double t = points[i].size() > 2 ? points[i][2] : 0.0;
    sea->set_time(t);
    float h, gx, gy;
    sea->eval(&x, &y, 1, &h, &gx, &gy);
    if (json) {
      std::printf("%s\n {\"x\": %g, \"y\": %g, \"t\": %g, \"height\": %s, \"grad_x\": %s, \"grad_y\": %s, \"trains\": [",
                  i ? "," : "", x, y, t, json_number(h).c_str(), json_number(gx).c_str(), json_number(gy).c_str());
    } else {
      std::printf("(%g, %g) t=%g s: height %.4f m, gradient (%.4f, %.4f)\n", x, y, t, h, gx, gy);
    }
    for (std::size_t k = 0; k < scene->trains.size(); ++k) {
      const TrainProbe p = sea->probe(k, x, y);
      if (json) {
        std::printf("%s{\"amplitude\": %s, \"relative_amplitude\": %s, \"diffraction\": %s, \"wavelength\": %s, "
                    "\"direction_deg\": %s, \"phase\": %s}",
                    k ? ", " : "", json_number(p.amplitude).c_str(), json_number(p.relative_amplitude).c_str(),
                    json_number(p.diffraction).c_str(), json_number(p.wavelength).c_str(),
                    json_number(p.direction_deg).c_str(), json_number(p.phase).c_str());
      } else {
        std::printf("  train %zu: amplitude %.4f m (x%.3f of deep water, diffraction K' %.3f), wavelength %.3f m, towards %.1f "
                    "deg, phase %.3f rad\n",
                    k, p.amplitude, p.relative_amplitude, p.diffraction, p.wavelength, p.direction_deg, p.phase);
      }
    }
    if (json) std::printf("]}");
  }
  if (json) std::printf("\n]\n");
  return 0;
}

}  // namespace houle::cli
