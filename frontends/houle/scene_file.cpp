#include "scene_file.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>
#include <variant>

#define TOML_HEADER_ONLY 1
#define TOML_EXCEPTIONS 0  // errors as parse_result values, like the rest of houle
#include <toml++/toml.h>

#include "height_map_image.hpp"
#include "input_file.hpp"
#include "houle/sim/scene_keys.hpp"
#include "houle/sim/wave_rays.hpp"
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
  // Where a field the checks name is in the file: the deepest part of its path the file wrote
  // ("trains[1].period", else "trains[1]", else the file's start: a default value that is wrong with
  // the others).
  Where place(std::string path) const {
    while (!path.empty()) {
      if (const auto it = where.find(path); it != where.end()) return it->second;
      const auto cut = path.find_last_of(".[");
      path = cut == std::string::npos ? std::string() : path.substr(0, cut);
    }
    return {1, 1};
  }
};

// Levenshtein distance, for "did you mean" on a misspelt key.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

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

  void read(std::string_view key, double& out) {
    if (const toml::node* n = get(key)) {
      if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())) {
        out = *v;
      } else {
        wrong(*n, key, "a number");
      }
    }
  }
  void read(std::string_view key, std::optional<double>& out) {
    if (get(key)) {
      double v = 0.0;
      read(key, v);
      out = v;
    }
  }
  /// An integer; one beyond what `Int` holds is refused with the key's range (validation checks the rest).
  template <class Int>
    requires std::is_integral_v<Int> && (!std::is_same_v<Int, bool>)
  void read(std::string_view key, Int& out, const scene_keys::Range& range = scene_keys::any) {
    const toml::node* n = get(key);
    if (!n) return;
    const auto v = n->value_exact<std::int64_t>();
    if (!v) return wrong(*n, key, "an integer");
    if (*v >= std::int64_t(std::numeric_limits<Int>::min()) && *v <= std::int64_t(std::numeric_limits<Int>::max())) {
      out = Int(*v);
      return;
    }
    const std::string bounds = range.bounded() ? scene_keys::describe(range)
                                               : "[" + std::to_string(std::numeric_limits<Int>::min()) + ", " +
                                                     std::to_string(std::numeric_limits<Int>::max()) + "]";
    ctx_.fail(ctx_.at(*n), field(key), "a count in " + bounds + ", got " + std::to_string(*v));
  }
  void read(std::string_view key, bool& out) {
    if (const toml::node* n = get(key)) {
      if (const auto v = n->value_exact<bool>()) out = *v; else wrong(*n, key, "true or false");
    }
  }
  void read(std::string_view key, std::string& out) {
    if (const toml::node* n = get(key)) {
      if (const auto v = n->value_exact<std::string>()) out = *v; else wrong(*n, key, "a string");
    }
  }
  template <class E>
  void choice(std::string_view key, E& out, std::span<const scene_keys::Choice> choices) {
    const toml::node* n = get(key);
    if (!n) return;
    const auto s = n->value_exact<std::string>();
    if (!s) return wrong(*n, key, "a string");
    std::string list;
    for (const scene_keys::Choice& c : choices) {
      if (*s == c.name) {
        out = E(c.value);
        return;
      }
      list += (list.empty() ? "\"" : ", \"") + std::string(c.name) + "\"";
    }
    ctx_.fail(ctx_.at(*n), field(key), "expected one of " + list + ", got \"" + *s + "\"");
  }
  void read(std::string_view key, Point2& p) {
    double v[2];
    if (numbers(key, v, 2)) p = {v[0], v[1]};
  }
  void read(std::string_view key, std::optional<Point2>& p) {
    double v[2];
    if (numbers(key, v, 2)) p = Point2{v[0], v[1]};
  }
  void read(std::string_view key, Point3& p) {
    double v[3];
    if (numbers(key, v, 3)) p = {v[0], v[1], v[2]};
  }
  void read(std::string_view key, LinearRgb& c) {
    double v[3];
    if (numbers(key, v, 3)) c = {float(v[0]), float(v[1]), float(v[2])};
  }
  /// Array of [x, y] pairs.
  void read(std::string_view key, std::vector<Point2>& out) {
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
  /// A sub-table, or null if absent (an error if the key holds something else).
  const toml::table* table(std::string_view key) {
    const toml::node* n = get(key);
    if (n && !n->is_table()) wrong(*n, key, "a table");
    return n ? n->as_table() : nullptr;
  }
  /// Each table of an array of tables ([[key]]), with its field path "key[i]".
  template <class F>
  void tables(std::string_view key, F&& each) {
    const toml::node* n = get(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) {
      wrong(*n, key, "an array of tables ([[" + field(key) + "]])");
      return;
    }
    for (std::size_t i = 0; i < a->size(); ++i) each(*(*a)[i].as_table(), field(key) + "[" + std::to_string(i) + "]");
  }
  std::string field(std::string_view key) const { return path_.empty() ? std::string(key) : path_ + "." + std::string(key); }
  bool has(std::string_view key) const { return t_.contains(key); }
  Where where() const { return ctx_.at(t_); }

  void finish() {
    for (const auto& [key, node] : t_) {
      if (!read_.count(std::string(key.str()))) {
        ctx_.fail({key.source().begin.line, key.source().begin.column}, field(key.str()),
                  "unknown key" + suggestion(key.str()) + " (see docs/scenes.md)");
      }
    }
  }

 private:
  // "; did you mean `period`?" for the table's closest key, if a typo away (a third of its letters).
  std::string suggestion(std::string_view unknown) const {
    std::string_view best;
    std::size_t best_distance = std::max<std::size_t>(1, unknown.size() / 3) + 1;
    for (const std::string& k : read_) {
      const std::size_t d = edit_distance(unknown, k);
      if (d < best_distance) best = k, best_distance = d;
    }
    return best.empty() ? std::string() : "; did you mean `" + std::string(best) + "`?";
  }
  const toml::node* get(std::string_view key) {
    read_.insert(std::string(key));
    const toml::node* n = t_.get(key);
    if (n) ctx_.where[field(key)] = ctx_.at(*n);
    return n;
  }
  /// [x, y] or [x, y, z] (n numbers).
  bool numbers(std::string_view key, double* out, std::size_t count) {
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
  void wrong(const toml::node& n, std::string_view key, const std::string& expected) {
    ctx_.fail(ctx_.at(n), field(key), "expected " + expected + ", got " + type_name(n));
  }

  const toml::table& t_;
  std::string path_;
  Context& ctx_;
  std::set<std::string> read_;
};

// One table of a section into `item`, key by key as scene_keys lists them (the caller finishes `r`).
template <class S>
void read_keys(Reader& r, const scene_keys::Section<S>& section, S& item, Context& ctx) {
  for (const scene_keys::Key<S>& k : section.keys) {
    std::visit(
        [&](auto member) {
          auto& v = item.*member;
          using T = std::remove_cvref_t<decltype(v)>;
          if constexpr (std::is_enum_v<T>) r.choice(k.name, v, k.choices);
          else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) r.read(k.name, v, k.range);
          else r.read(k.name, v);
        },
        k.member);
    if (k.required && !r.has(k.name)) ctx.fail(r.where(), r.field(k.name), "required, missing: " + std::string(k.doc));
  }
}

void read_height_map(Reader& r, SeaFloor& floor, Context& ctx) {
  HeightMapFile file;
  read_keys(r, scene_keys::height_map, file, ctx);
  r.finish();  // an unknown key before the image is loaded
  if (ctx.error) return;
  if (auto e = scene_keys::check_keys(scene_keys::height_map, file, std::string(scene_keys::height_map.path)); !e) {
    ctx.fail(ctx.place(e.error().field), e.error().field, e.error().message);
    return;
  }
  Expected<HeightMap> map = load_height_map((std::filesystem::path(ctx.dir) / file.file).string(), file);
  if (!map) return ctx.fail(ctx.place(r.field("file")), r.field("file"), map.error().message);
  floor.height_map = std::move(map.value());
}

// The tables that hold sections ("" the root, "floor", "camera"), each read once and finished after
// the sections: a key none of them reads is unknown.
class Tables {
 public:
  Tables(const toml::table& root, Context& ctx) : ctx_(ctx) { readers_.emplace("", Reader(root, "", ctx)); }

  /// The reader of the table at `path`, or null where the file has none.
  Reader* at(const std::string& path) {
    if (const auto it = readers_.find(path); it != readers_.end()) return it->second ? &*it->second : nullptr;
    const auto cut = path.find_last_of('.');
    Reader* parent = at(cut == std::string::npos ? "" : path.substr(0, cut));
    const toml::table* t = parent ? parent->table(path.substr(cut + 1)) : nullptr;
    auto& slot = readers_[path];
    if (t) slot.emplace(*t, path, ctx_);
    return t ? &*slot : nullptr;
  }
  void finish() {
    for (auto& [path, reader] : readers_) {
      if (reader) reader->finish();
    }
  }

 private:
  Context& ctx_;
  std::map<std::string, std::optional<Reader>> readers_;
};

void read_scene(const toml::table& root, Scene& s, Context& ctx) {
  Tables tables(root, ctx);
  scene_keys::for_each_section([&]<class S>(const scene_keys::Section<S>& section) {
    const std::string path(section.path);
    const auto cut = path.find_last_of('.');
    const std::string name = path.substr(cut + 1);
    Reader* parent = tables.at(cut == std::string::npos ? "" : path.substr(0, cut));
    if (!parent) return;
    if (section.array) {
      parent->tables(name, [&](const toml::table& t, std::string item_path) {
        Reader r(t, std::move(item_path), ctx);
        read_keys(r, section, section.array_in(s).emplace_back(), ctx);
        r.finish();
      });
    } else if (Reader* r = tables.at(path)) {
      // The table's reader is the one its sub-sections' arrays are read from ([camera] and
      // [[camera.keys]]): finished with the others, once every section has been read.
      if constexpr (std::is_same_v<S, HeightMapFile>) read_height_map(*r, s.floor, ctx);
      else read_keys(*r, section, section.table_in(s), ctx);
    }
  });
  tables.finish();
}

}  // namespace

Expected<Scene> parse_scene(std::string_view text, const std::string& name, const std::string& dir,
                            std::vector<Error>* warnings) {
  // Editors on Windows start UTF-8 files with a byte order mark; TOML allows it.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
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
  const auto placed = [&](const Error& e) {
    const Where w = ctx.place(e.field);
    return Error{name + ":" + std::to_string(w.line) + ":" + std::to_string(w.column), e.field + ": " + e.message};
  };
  if (!valid) return placed(valid.error());
  if (warnings) {
    for (const Error& w : trace_cap_warnings(valid.value())) warnings->push_back(placed(w));
  }
  return valid;
}

Expected<Scene> load_scene_file(const std::string& path, std::vector<Error>* warnings) {
  if (path == "-") {
    // Standard input: read up to one byte past the limit, to know it was passed.
    std::string text(max_scene_file_bytes + 1, '\0');
    text.resize(std::fread(text.data(), 1, text.size(), stdin));
    if (std::ferror(stdin)) return Error{"standard input", "cannot read the scene"};
    if (text.size() > max_scene_file_bytes) {
      return Error{"standard input", "scene of more than " + std::to_string(max_scene_file_bytes) +
                                         " bytes is over the limit (height maps belong in image files)"};
    }
    return parse_scene(text, "standard input", ".", warnings);
  }
  const Expected<std::uintmax_t> size = regular_file_size(path);
  if (!size) return Error{path, "cannot read the scene file: " + size.error().message};
  if (size.value() > max_scene_file_bytes) {
    return Error{path, "scene file of " + std::to_string(size.value()) + " bytes is over the limit of " +
                           std::to_string(max_scene_file_bytes) + " (height maps belong in image files)"};
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) return Error{path, "cannot read the scene file"};
  return parse_scene(text.str(), path, std::filesystem::path(path).parent_path().string(), warnings);
}

}  // namespace houle::cli
