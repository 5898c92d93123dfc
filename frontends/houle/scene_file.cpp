#include "scene_file.hpp"

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#define TOML_HEADER_ONLY 1
#define TOML_EXCEPTIONS 0  // errors as parse_result values, like the rest of houle
#include <toml++/toml.h>

#include "height_map_image.hpp"
#include "toml_ascii.hpp"

namespace houle::cli {
namespace {

struct Where {
  std::uint32_t line = 1, column = 1;
};

// Everything one parse needs: the first error, and where each field was written so that sim's
// validation errors (which name fields, not lines) can be placed in the file.
struct Context {
  std::string file, dir;
  std::optional<Error> error;
  std::map<std::string, Where> where;

  Where at(const toml::node& n) const { return {n.source().begin.line, n.source().begin.column}; }
  void fail(Where w, const std::string& field, const std::string& what) {
    if (!error) error = Error{file + ":" + std::to_string(w.line) + ":" + std::to_string(w.column), field + ": " + what};
  }
};

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date or time";
  }
}

// Reads the keys of one table; any key not read by the time finish() runs is an error.
class Reader {
 public:
  Reader(const toml::table& t, std::string path, Context& ctx) : t_(t), path_(std::move(path)), ctx_(ctx) {
    ctx_.where[path_] = ctx_.at(t);
  }

  void number(const char* key, double& out) {
    if (const toml::node* n = get(key)) {
      if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())) {
        out = *v;
      } else {
        wrong(*n, key, "a number");
      }
    }
  }
  void number(const char* key, std::optional<double>& out) {
    if (get(key)) {
      double v = 0.0;
      number(key, v);
      out = v;
    }
  }
  template <class Int>
  void integer(const char* key, Int& out) {
    if (const toml::node* n = get(key)) {
      const auto v = n->value_exact<std::int64_t>();
      if (!v || *v < std::int64_t(std::numeric_limits<Int>::min()) || *v > std::int64_t(std::numeric_limits<Int>::max())) {
        wrong(*n, key, "an integer in range");
      } else {
        out = Int(*v);
      }
    }
  }
  void boolean(const char* key, bool& out) {
    if (const toml::node* n = get(key)) {
      if (const auto v = n->value_exact<bool>()) out = *v; else wrong(*n, key, "true or false");
    }
  }
  std::optional<std::string> string(const char* key) {
    if (const toml::node* n = get(key)) {
      if (const auto v = n->value_exact<std::string>()) return *v;
      wrong(*n, key, "a string");
    }
    return std::nullopt;
  }
  template <class E>
  void choice(const char* key, E& out, std::initializer_list<std::pair<const char*, E>> options) {
    const toml::node* n = get(key);
    const std::optional<std::string> s = string(key);
    if (!s) return;
    std::string list;
    for (const auto& [name, value] : options) {
      if (*s == name) {
        out = value;
        return;
      }
      list += (list.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    wrong(*n, key, "one of " + list + ", got \"" + *s + "\"");
  }
  /// [x, y] or [x, y, z] (n numbers).
  bool numbers(const char* key, double* out, std::size_t count) {
    const toml::node* n = get(key);
    if (!n) return false;
    const toml::array* a = n->as_array();
    bool ok = a && a->size() == count;
    for (std::size_t i = 0; ok && i < count; ++i) {
      const auto v = (*a)[i].value<double>();
      ok = v && ((*a)[i].is_floating_point() || (*a)[i].is_integer());
      if (ok) out[i] = *v;
    }
    if (!ok) wrong(*n, key, "an array of " + std::to_string(count) + " numbers");
    return ok;
  }
  void point(const char* key, Point2& p) {
    double v[2];
    if (numbers(key, v, 2)) p = {v[0], v[1]};
  }
  void point(const char* key, std::optional<Point2>& p) {
    double v[2];
    if (numbers(key, v, 2)) p = Point2{v[0], v[1]};
  }
  void point(const char* key, Point3& p) {
    double v[3];
    if (numbers(key, v, 3)) p = {v[0], v[1], v[2]};
  }
  void colour(const char* key, LinearRgb& c) {
    double v[3];
    if (numbers(key, v, 3)) c = {float(v[0]), float(v[1]), float(v[2])};
  }
  /// A sub-table, or null if absent (an error if the key holds something else).
  const toml::table* table(const char* key) {
    const toml::node* n = get(key);
    if (n && !n->is_table()) wrong(*n, key, "a table");
    return n ? n->as_table() : nullptr;
  }
  /// Each table of an array of tables ([[key]]), with its field path "key[i]".
  template <class F>
  void tables(const char* key, F&& each) {
    const toml::node* n = get(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) {
      wrong(*n, key, "an array of tables ([[" + std::string(key) + "]])");
      return;
    }
    for (std::size_t i = 0; i < a->size(); ++i) each(*(*a)[i].as_table(), field(key) + "[" + std::to_string(i) + "]");
  }
  /// Array of [x, y] pairs.
  void points(const char* key, std::vector<Point2>& out) {
    const toml::node* n = get(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    bool ok = a != nullptr;
    for (std::size_t i = 0; ok && i < a->size(); ++i) {
      const toml::array* p = (*a)[i].as_array();
      ok = p && p->size() == 2 && (*p)[0].value<double>() && (*p)[1].value<double>() && !(*p)[0].is_string() && !(*p)[1].is_string();
      if (ok) out.push_back({*(*p)[0].value<double>(), *(*p)[1].value<double>()});
    }
    if (!ok) wrong(*n, key, "an array of [x, y] points");
  }
  std::string field(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  Where where(const char* key) { const toml::node* n = t_.get(key); return n ? ctx_.at(*n) : ctx_.at(t_); }
  Context& context() { return ctx_; }

  void finish() {
    for (const auto& [key, node] : t_) {
      if (!read_.count(std::string(key.str()))) {
        ctx_.fail({key.source().begin.line, key.source().begin.column}, field(std::string(key.str()).c_str()),
                  "unknown key (see docs/scenes.md)");
      }
    }
  }

 private:
  const toml::node* get(const char* key) {
    read_.insert(key);
    const toml::node* n = t_.get(key);
    if (n) ctx_.where[field(key)] = ctx_.at(*n);
    return n;
  }
  void wrong(const toml::node& n, const char* key, const std::string& expected) {
    ctx_.fail(ctx_.at(n), field(key), "expected " + expected + ", got " + type_name(n));
  }

  const toml::table& t_;
  std::string path_;
  Context& ctx_;
  std::set<std::string> read_;
};

void read_floor(Reader& r, SeaFloor& f) {
  if (const toml::table* t = r.table("base")) {
    Reader b(*t, r.field("base"), r.context());
    b.choice("kind", f.base.kind, {{"flat", FloorKind::flat}, {"planar_beach", FloorKind::planar_beach}});
    b.number("depth", f.base.depth);
    b.number("slope", f.base.slope);
    b.number("shoreward_deg", f.base.shoreward_deg);
    b.point("shoreline", f.base.shoreline);
    b.finish();
  }
  r.tables("shoals", [&](const toml::table& t, std::string path) {
    Reader s(t, path, r.context());
    Shoal& o = f.shoals.emplace_back();
    s.point("center", o.center);
    s.number("semi_axis_a", o.semi_axis_a);
    s.number("semi_axis_b", o.semi_axis_b);
    s.number("orientation_deg", o.orientation_deg);
    s.number("height", o.height);
    s.finish();
  });
  r.tables("bars", [&](const toml::table& t, std::string path) {
    Reader s(t, path, r.context());
    Bar& o = f.bars.emplace_back();
    s.point("point", o.point);
    s.number("along_deg", o.along_deg);
    s.number("half_width", o.half_width);
    s.number("height", o.height);
    s.finish();
  });
  r.tables("channels", [&](const toml::table& t, std::string path) {
    Reader s(t, path, r.context());
    Channel& o = f.channels.emplace_back();
    s.point("from", o.from);
    s.point("to", o.to);
    s.number("half_width", o.half_width);
    s.number("depth", o.depth);
    s.finish();
  });
  if (const toml::table* t = r.table("height_map")) {
    Reader h(*t, r.field("height_map"), r.context());
    HeightMapImage image;
    const std::optional<std::string> file = h.string("file");
    h.point("origin", image.origin);
    h.number("cell", image.cell);
    h.number("depth_at_black", image.depth_at_black);
    h.number("depth_at_white", image.depth_at_white);
    HeightMapMode mode = HeightMapMode::absolute;
    h.choice("mode", mode, {{"absolute", HeightMapMode::absolute}, {"additive", HeightMapMode::additive}});
    h.finish();
    Context& ctx = r.context();
    if (!file) {
      ctx.fail(ctx.where[h.field("file").c_str()], h.field("file"), "the image file of the height map (a string)");
    } else if (!ctx.error) {
      const std::filesystem::path p = std::filesystem::path(ctx.dir) / *file;
      Expected<HeightMap> map = load_height_map(p.string(), image);
      if (!map) {
        ctx.fail(ctx.where[h.field("file")], h.field("file"), map.error().message);
      } else {
        map->mode = mode;
        f.height_map = std::move(map.value());
      }
    }
  }
}

void read_scene(const toml::table& root, Scene& s, Context& ctx) {
  Reader r(root, "", ctx);
  if (const toml::table* t = r.table("domain")) {
    Reader d(*t, "domain", ctx);
    d.number("x_min", s.domain.x_min);
    d.number("y_min", s.domain.y_min);
    d.number("x_max", s.domain.x_max);
    d.number("y_max", s.domain.y_max);
    d.finish();
  }
  if (const toml::table* t = r.table("floor")) {
    Reader f(*t, "floor", ctx);
    read_floor(f, s.floor);
    f.finish();
  }
  r.tables("walls", [&](const toml::table& t, std::string path) {
    Reader w(t, path, ctx);
    Wall& o = s.walls.emplace_back();
    w.points("points", o.points);
    w.number("thickness", o.thickness);
    w.number("reflection", o.reflection);
    w.number("crest_height", o.crest_height);
    w.finish();
  });
  r.tables("trains", [&](const toml::table& t, std::string path) {
    Reader w(t, path, ctx);
    WaveTrain& o = s.trains.emplace_back();
    w.number("direction_deg", o.direction_deg);
    w.point("direction", o.direction);
    w.number("period", o.period);
    w.number("wavelength", o.wavelength);
    w.number("amplitude", o.amplitude);
    w.number("phase", o.phase);
    w.number("steepness", o.steepness);
    w.finish();
  });
  if (const toml::table* t = r.table("capillary")) {
    Reader c(*t, "capillary", ctx);
    c.number("amplitude", s.capillary.amplitude);
    c.number("base_wavelength", s.capillary.base_wavelength);
    c.number("lacunarity", s.capillary.lacunarity);
    c.integer("max_octaves", s.capillary.max_octaves);
    c.number("time_scale", s.capillary.time_scale);
    c.finish();
  }
  r.tables("boxes", [&](const toml::table& t, std::string path) {
    Reader b(t, path, ctx);
    Box& o = s.boxes.emplace_back();
    b.point("center", o.center);
    b.point("half_extent", o.half_extent);
    b.number("yaw_deg", o.yaw_deg);
    b.colour("colour", o.colour);
    b.finish();
  });
  r.tables("spheres", [&](const toml::table& t, std::string path) {
    Reader b(t, path, ctx);
    Sphere& o = s.spheres.emplace_back();
    b.point("center", o.center);
    b.number("radius", o.radius);
    b.colour("colour", o.colour);
    b.finish();
  });
  if (const toml::table* t = r.table("sun")) {
    Reader b(*t, "sun", ctx);
    b.number("azimuth_deg", s.sun.azimuth_deg);
    b.number("elevation_deg", s.sun.elevation_deg);
    b.finish();
  }
  if (const toml::table* t = r.table("sky")) {
    Reader b(*t, "sky", ctx);
    b.number("turbidity", s.sky.turbidity);
    b.finish();
  }
  if (const toml::table* t = r.table("camera")) {
    Reader b(*t, "camera", ctx);
    b.point("position", s.camera.position);
    b.point("look_at", s.camera.look_at);
    b.number("vertical_fov_deg", s.camera.vertical_fov_deg);
    b.finish();
  }
  if (const toml::table* t = r.table("water")) {
    Reader b(*t, "water", ctx);
    b.number("extra_absorption", s.water.extra_absorption);
    b.number("dominant_wavelength_nm", s.water.dominant_wavelength_nm);
    b.finish();
  }
  if (const toml::table* t = r.table("dwt")) {
    Reader b(*t, "dwt", ctx);
    DwtSettings& d = s.dwt;
    b.integer("initial_rays", d.initial_rays);
    b.number("front_width", d.front_width);
    b.number("step", d.step);
    b.number("insertion_distance", d.insertion_distance);
    b.number("min_depth", d.min_depth);
    b.number("min_depth_wavelengths", d.min_depth_wavelengths);
    b.number("breaker_index", d.breaker_index);
    b.number("max_refraction_coefficient", d.max_refraction_coefficient);
    b.boolean("diffraction", d.diffraction);
    b.boolean("reflection", d.reflection);
    b.choice("diffraction_model", d.diffraction_model,
             {{"exact", DiffractionModel::exact}, {"paper", DiffractionModel::paper}, {"paper-corrected", DiffractionModel::paper_corrected}});
    b.integer("max_rays", d.max_rays);
    b.integer("max_samples", d.max_samples);
    b.finish();
  }
  r.finish();
}

}  // namespace

Expected<Scene> parse_scene(std::string_view text, const std::string& name, const std::string& dir) {
  const Expected<std::string> ascii = toml_ascii(text, name);
  if (!ascii) return ascii.error();
  toml::parse_result parsed = toml::parse(ascii.value(), name);
  if (!parsed) {
    const toml::parse_error& e = parsed.error();
    return Error{name + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column),
                 std::string(e.description())};
  }
  Context ctx{name, dir, std::nullopt, {}};
  Scene scene;
  read_scene(parsed.table(), scene, ctx);
  if (ctx.error) return *ctx.error;
  Expected<Scene> valid = validate(std::move(scene));
  if (valid) return valid;
  // Place the problem at the deepest field the file wrote on its path ("trains[1].period", else
  // "trains[1]", else the file's start: a default value that is wrong with the others).
  const Error& e = valid.error();
  std::string path = e.field;
  Where w{1, 1};
  while (!path.empty()) {
    if (const auto it = ctx.where.find(path); it != ctx.where.end()) {
      w = it->second;
      break;
    }
    const auto cut = path.find_last_of(".[");
    path = cut == std::string::npos ? std::string() : path.substr(0, cut);
  }
  return Error{name + ":" + std::to_string(w.line) + ":" + std::to_string(w.column), e.field + ": " + e.message};
}

Expected<Scene> load_scene_file(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path, "cannot read the scene file: " + ec.message()};
  if (size > max_scene_file_bytes) {
    return Error{path, "scene file of " + std::to_string(size) + " bytes is over the limit of " +
                           std::to_string(max_scene_file_bytes) + " (height maps belong in image files)"};
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) return Error{path, "cannot read the scene file"};
  return parse_scene(text.str(), path, std::filesystem::path(path).parent_path().string());
}

}  // namespace houle::cli
