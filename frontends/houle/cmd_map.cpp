#include <algorithm>
#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "frame_files.hpp"
#include "frame_writer.hpp"
#include "houle/sim/bathymetry.hpp"
#include "probe_sea.hpp"
#include "scene_source.hpp"

#if HOULE_WITH_OIIO
#include "image_module.hpp"
#endif

namespace houle::cli {
namespace {

constexpr const char* help = R"(usage: houle map [SCENE] --grid X0:X1:DX,Y0:Y1:DY [--fields F,...] --out FILE.exr|FILE.csv

Writes fields of SCENE's sea (the built-in coast without one) on a regular grid of points: what
houle probe reads at one point (the same build: the realtime quality's resampling grid), as a map.

  --grid X0:X1:DX,Y0:Y1:DY   the points X0, X0 + DX, ... up to X1 (inclusive) times the same in y, in m
                             (DX, DY > 0; at most 16384 points a side and 67108864 values in all;
                             no point more than 100 km outside the domain)
  --fields F,...             what to write, in this order (default depth,hs):
                               depth       m below still water (negative on land)
                               hs          significant wave height, m: 4 sqrt(sum of a_i^2 / 2) over
                                           the trains' local amplitudes a_i (their energies add)
                             and per train i, a channel or column each, named FIELD.i:
                               amplitude   local amplitude, m (shoaling, refraction, diffraction and
                                           reflection applied)
                               kd          K', the diffraction coefficient in it (1 without diffraction)
                               reflected   amplitude of its reflected waves, m
                               wavelength  local wavelength, m
                               direction   direction of travel, degrees counter-clockwise from +x
  --out FILE                 .exr: one 32-bit float channel per field (named as above), the image's
                             top row at Y1 (north up) and its left column at X0; the header holds
                             houle:grid (the --grid text) and Software.
                             .csv: a header line x,y,FIELDS..., then a row per point, y by y from Y0,
                             x by x from X0 within a row.

Values are those the sea surface evaluates everywhere, as houle probe's JSON and CSV give them: on
land and in walls too (see `houle probe --help` for where a point lies).)";

// A grid axis: X0:X1:DX into its points (X0 + i DX up to X1; the last step may land a rounding error
// short of X1 and still counts), or an error for `args`.
std::vector<double> parse_axis(Args& args, std::string_view text, char name) {
  const auto v = parse_list(text, ':');
  const std::string axis(1, name);
  if (!v || v->size() != 3) {
    args.fail("--grid expects X0:X1:DX,Y0:Y1:DY in m, got '" + std::string(text) + "' for " + axis);
    return {};
  }
  const double a = (*v)[0], b = (*v)[1], d = (*v)[2];
  if (!(d > 0.0)) args.fail("--grid: the step D" + axis + " must be > 0 m, got " + std::string(text));
  else if (b < a) args.fail("--grid: " + axis + "1 must be >= " + axis + "0, got " + std::string(text));
  else if ((b - a) / d >= 16384.0) args.fail("--grid: more than 16384 points along " + axis + " in " + std::string(text));
  if (args.failed()) return {};
  const double steps = (b - a) / d;
  std::vector<double> points(std::size_t(std::floor(steps + 1e-9 * std::max(1.0, steps))) + 1);
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = std::min(a + double(i) * d, b);
  return points;
}

enum class Field { depth, hs, amplitude, kd, reflected, wavelength, direction };
constexpr std::pair<const char*, Field> field_names[] = {
    {"depth", Field::depth}, {"hs", Field::hs}, {"amplitude", Field::amplitude}, {"kd", Field::kd},
    {"reflected", Field::reflected}, {"wavelength", Field::wavelength}, {"direction", Field::direction}};

// A channel of the output: a field, for train `train` if the field is per train.
struct Channel {
  Field field;
  std::size_t train = 0;
  std::string name;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Writes `text` to `path` whole: under a temporary name, renamed when complete.
bool write_text_file(const std::string& path, const std::string& text, std::string& error) {
  const std::string tmp = temp_path(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  bool ok = f != nullptr && std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (f != nullptr) ok = std::fclose(f) == 0 && ok;
  std::error_code ec;
  if (ok) std::filesystem::rename(tmp, path, ec);
  if (!ok || ec) {
    error = ec ? ec.message() : std::string(std::strerror(errno));
    std::filesystem::remove(tmp, ec);
    return false;
  }
  return true;
}

}  // namespace

int cmd_map(std::span<char* const> argv) {
  Args args("map", argv);
  if (args.flag("--help")) {
    std::puts(help);
    return 0;
  }
  const std::optional<std::string> grid = args.value("--grid");
  const std::string fields_text = args.value("--fields").value_or("depth,hs");
  const std::optional<std::string> out = args.value("--out");
  const std::vector<std::string> positionals = args.rest();
  std::vector<double> xs, ys;
  if (!grid) {
    args.fail("expects --grid X0:X1:DX,Y0:Y1:DY");
  } else if (const auto comma = grid->find(','); comma == std::string::npos) {
    args.fail("--grid expects X0:X1:DX,Y0:Y1:DY in m, got '" + *grid + "'");
  } else {
    xs = parse_axis(args, std::string_view(*grid).substr(0, comma), 'X');
    if (!args.failed()) ys = parse_axis(args, std::string_view(*grid).substr(comma + 1), 'Y');
  }
  std::vector<Field> fields;
  for (std::string_view rest = fields_text; !args.failed();) {
    const auto comma = rest.find(',');
    const std::string_view name = rest.substr(0, comma);
    const auto it = std::find_if(std::begin(field_names), std::end(field_names), [&](const auto& f) { return name == f.first; });
    if (it == std::end(field_names)) {
      args.fail("--fields expects a list of depth, hs, amplitude, kd, reflected, wavelength and direction, got '" +
                std::string(name) + "'");
    } else if (std::find(fields.begin(), fields.end(), it->second) != fields.end()) {
      args.fail("--fields names " + std::string(name) + " twice");
    } else {
      fields.push_back(it->second);
    }
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  const std::string ext = out ? lower_extension(*out) : "";
  if (!args.failed() && !out) args.fail("expects --out FILE.exr or FILE.csv");
  if (!args.failed() && ext != ".exr" && ext != ".csv") args.fail("--out expects a .exr or .csv file, got '" + *out + "'");
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
#if !HOULE_WITH_OIIO
  if (ext == ".exr") {
    std::fprintf(stderr, "houle map: %s: this houle was built without OpenImageIO: write a .csv\n", out->c_str());
    return 2;
  }
#endif
  if (Expected<void> ok = check_raw_output(*out); !ok) {
    std::fprintf(stderr, "houle map: %s: %s\n", ok.error().field.c_str(), ok.error().message.c_str());
    return 2;
  }
  const std::optional<Scene> scene = scene_from_args(positionals, "map");
  if (!scene) return 2;
  const std::string name = scene_name(positionals);
  for (const double x : {xs.front(), xs.back()}) {
    for (const double y : {ys.front(), ys.back()}) {
      if (distance_outside(scene->domain, x, y) > max_probe_distance) {
        std::fprintf(stderr, "houle map: --grid %s: the point (%g, %g) lies more than %g km outside the domain\n", grid->c_str(), x,
                     y, max_probe_distance / 1e3);
        return 2;
      }
    }
  }
  std::vector<Channel> channels;
  const std::size_t trains = scene->trains.size();
  for (const Field f : fields) {
    const char* field_name = std::find_if(std::begin(field_names), std::end(field_names), [&](const auto& n) { return n.second == f; })->first;
    if (f == Field::depth || f == Field::hs) {
      channels.push_back({f, 0, field_name});
    } else {
      for (std::size_t k = 0; k < trains; ++k) channels.push_back({f, k, std::string(field_name) + "." + std::to_string(k)});
    }
  }
  const std::size_t nx = xs.size(), ny = ys.size(), nc = channels.size();
  if (nc == 0) {
    std::fprintf(stderr, "houle map: %s has no trains: the per-train fields %s make no channel\n", name.c_str(), fields_text.c_str());
    return 2;
  }
  if (double(nx) * double(ny) * double(nc) > double(1 << 26)) {
    std::fprintf(stderr, "houle map: --grid %s with %zu channels makes %zu x %zu x %zu values, more than 67108864\n",
                 grid->c_str(), nc, nx, ny, nc);
    return 2;
  }
  int exit_code = 0;
  std::optional<SeaSurface> sea = build_probe_sea(*scene, name, "map", exit_code);
  if (!sea) return exit_code;
  sea->set_time(0.0);
  const Bathymetry floor(scene->floor);

  // Row r of the image is ys[ny - 1 - r]: north up.
  std::vector<float> values(nx * ny * nc);
  std::vector<TrainProbe> probes(trains);
  for (std::size_t r = 0; r < ny; ++r) {
    const double y = ys[ny - 1 - r];
    for (std::size_t i = 0; i < nx; ++i) {
      const double x = xs[i];
      double energy = 0.0;  // sum of a^2 / 2, m^2
      for (std::size_t k = 0; k < trains; ++k) {
        probes[k] = sea->probe(k, float(x), float(y));
        energy += 0.5 * double(probes[k].amplitude) * double(probes[k].amplitude);
      }
      float* v = &values[(r * nx + i) * nc];
      for (const Channel& c : channels) {
        const TrainProbe& p = probes.empty() ? TrainProbe{} : probes[c.train];
        switch (c.field) {
          case Field::depth: *v++ = float(floor.depth(x, y)); break;
          case Field::hs: *v++ = float(4.0 * std::sqrt(energy)); break;
          case Field::amplitude: *v++ = p.amplitude; break;
          case Field::kd: *v++ = p.diffraction; break;
          case Field::reflected: *v++ = p.reflected; break;
          case Field::wavelength: *v++ = p.wavelength; break;
          case Field::direction: *v++ = p.direction_deg; break;
        }
      }
    }
  }

  std::string error;
  if (ext == ".csv") {
    std::string text = "x,y";
    for (const Channel& c : channels) text += "," + c.name;
    text += "\n";
    char buf[32];
    for (std::size_t j = 0; j < ny; ++j) {
      for (std::size_t i = 0; i < nx; ++i) {
        std::snprintf(buf, sizeof buf, "%g,%g", xs[i], ys[j]);
        text += buf;
        const float* v = &values[((ny - 1 - j) * nx + i) * nc];
        for (std::size_t c = 0; c < nc; ++c) {
          std::snprintf(buf, sizeof buf, std::isfinite(v[c]) ? ",%.6g" : ",", double(v[c]));
          text += buf;
        }
        text += "\n";
      }
    }
    if (!write_text_file(*out, text, error)) {
      std::fprintf(stderr, "houle map: %s: cannot write: %s\n", out->c_str(), error.c_str());
      return 1;
    }
  } else {
#if HOULE_WITH_OIIO
    Expected<const ImageModule*> module = image_module();
    if (!module) {
      std::fprintf(stderr, "houle map: %s: %s\n", module.error().field.c_str(), module.error().message.c_str());
      return 1;
    }
    std::vector<const char*> names;
    for (const Channel& c : channels) names.push_back(c.name.c_str());
    const std::vector<int> storage(nc, linear_float);
    const ImageLayout layout{int(nx), int(ny), int(nc), names.data(), storage.data()};
    const ImageAttribute attributes[] = {{.name = "houle:grid", .type = ImageAttribute::text, .string = grid->c_str()},
                                         {.name = "Software", .type = ImageAttribute::text, .string = "houle " HOULE_VERSION}};
    const std::string tmp = temp_path(*out);
    char message[512] = "";
    std::error_code ec;
    const bool ok = module.value()->write_image(tmp.c_str(), out->c_str(), &layout, values.data(), attributes,
                                                int(std::size(attributes)), message, sizeof message) == 0;
    if (ok) std::filesystem::rename(tmp, *out, ec);
    if (!ok || ec) {
      std::filesystem::remove(tmp, ec);
      std::fprintf(stderr, "houle map: %s: cannot write the image: %s\n", out->c_str(), ok ? ec.message().c_str() : message);
      return 1;
    }
#endif
  }
  std::fprintf(stderr, "houle map: %zu x %zu points, %zu channels written to %s\n", nx, ny, nc, out->c_str());
  return 0;
}

}  // namespace houle::cli
