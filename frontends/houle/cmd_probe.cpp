#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/sea_surface.hpp"
#include "scene_source.hpp"

namespace houle::cli {

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
      std::printf("%s\n {\"x\": %g, \"y\": %g, \"t\": %g, \"height\": %.6g, \"grad_x\": %.6g, \"grad_y\": %.6g, \"trains\": [",
                  i ? "," : "", x, y, t, h, gx, gy);
    } else {
      std::printf("(%g, %g) t=%g s: height %.4f m, gradient (%.4f, %.4f)\n", x, y, t, h, gx, gy);
    }
    for (std::size_t k = 0; k < scene->trains.size(); ++k) {
      const TrainProbe p = sea->probe(k, x, y);
      if (json) {
        std::printf("%s{\"amplitude\": %.6g, \"relative_amplitude\": %.6g, \"diffraction\": %.6g, \"wavelength\": %.6g, "
                    "\"direction_deg\": %.6g, \"phase\": %.6g}",
                    k ? ", " : "", p.amplitude, p.relative_amplitude, p.diffraction, p.wavelength, p.direction_deg, p.phase);
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
