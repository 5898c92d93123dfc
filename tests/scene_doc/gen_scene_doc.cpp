// Prints docs/scenes.md: every key from the table the parser and validation use
// (houle/sim/scene_keys.hpp), defaults from the structs' initialisers, limits from their constants.
// scripts/regen-scene-doc writes the file; the test scene_doc_current fails when it is stale.
#include <cmath>
#include <iostream>
#include <string>
#include <type_traits>
#include <variant>

#include "height_map_image.hpp"  // max_height_map_side
#include "houle/sim/build_cost.hpp"  // max_build_seconds
#include "houle/sim/scene_keys.hpp"
#include "scene_file.hpp"        // max_scene_file_bytes

namespace {

using namespace houle;
namespace keys = houle::scene_keys;

std::string num(double v) { return keys::number_text(v); }
std::string num(float v) { return keys::number_text(v); }

std::string quoted(std::string_view name) { return "\"" + std::string(name) + "\""; }

// A default value as a file would write it; empty where there is none.
template <class T>
std::string value_text(const T& v, std::span<const keys::Choice> choices) {
  if constexpr (std::is_enum_v<T>) {
    for (const keys::Choice& c : choices) {
      if (c.value == int(v)) return "`" + quoted(c.name) + "`";
    }
    return "";
  } else if constexpr (std::is_same_v<T, bool>) {
    return v ? "true" : "false";
  } else if constexpr (std::is_integral_v<T>) {
    return std::to_string(v);
  } else if constexpr (std::is_same_v<T, double>) {
    return num(v);
  } else if constexpr (std::is_same_v<T, Point2>) {
    return "[" + num(v.x) + ", " + num(v.y) + "]";
  } else if constexpr (std::is_same_v<T, Point3>) {
    return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]";
  } else if constexpr (std::is_same_v<T, LinearRgb>) {
    return "[" + num(v.r) + ", " + num(v.g) + ", " + num(v.b) + "]";
  } else if constexpr (std::is_same_v<T, std::optional<double>> || std::is_same_v<T, std::optional<Point2>>) {
    return v ? value_text(*v, choices) : "";
  } else {
    return "";  // strings and point lists: required keys, without a default
  }
}

// The unit column: the shape of a point or list, then the unit of each number.
template <class T>
std::string unit_text(std::string_view unit) {
  const std::string u = unit.empty() ? "" : " " + std::string(unit);
  if constexpr (std::is_same_v<T, Point2> || std::is_same_v<T, std::optional<Point2>>) return "[x, y]" + u;
  if constexpr (std::is_same_v<T, Point3>) return "[x, y, z]" + u;
  if constexpr (std::is_same_v<T, LinearRgb>) return "[r, g, b]" + u;
  if constexpr (std::is_same_v<T, std::vector<Point2>>) return "[[x, y], ...]" + u;
  if constexpr (std::is_same_v<T, bool>) return "bool";
  return std::string(unit);
}

// The range column: the bounds of a number (of each coordinate of a point), or an enum's names.
template <class T>
std::string range_text(const keys::Range& range, std::span<const keys::Choice> choices) {
  if constexpr (std::is_enum_v<T>) {
    std::string names;
    for (const keys::Choice& c : choices) names += (names.empty() ? "`" : ", `") + quoted(c.name) + "`";
    return names;
  }
  const std::string bounds = keys::describe(range);
  constexpr bool composite = std::is_class_v<T> && !std::is_same_v<T, std::optional<double>>;
  return composite && !bounds.empty() ? "each " + bounds : bounds;
}

template <class S>
void print_section(const keys::Section<S>& section) {
  const std::string brackets = section.array ? "[[" : "[";
  const std::string closing = section.array ? "]]" : "]";
  std::cout << "\n## `" << brackets << section.path << closing << "` — " << section.title << "\n"
            << "| key | unit | default | range | meaning |\n|---|---|---|---|---|\n";
  const S defaults{};
  for (const keys::Key<S>& k : section.keys) {
    std::visit(
        [&](auto member) {
          using T = std::remove_cvref_t<decltype(defaults.*member)>;
          std::string meaning(k.doc);
          for (std::size_t i = 0; i < k.choices.size(); ++i) {
            meaning += (i == 0 ? " — `" : "; `") + quoted(k.choices[i].name) + "`: " + std::string(k.choices[i].doc);
          }
          std::cout << "| `" << k.name << "` | " << unit_text<T>(k.unit) << " | "
                    << (k.required ? "(required)" : value_text(defaults.*member, k.choices)) << " | "
                    << range_text<T>(k.range, k.choices) << " | " << meaning << " |\n";
        },
        k.member);
  }
  if (!section.notes.empty()) std::cout << "\n" << section.notes << "\n";
}

void print_limits() {
  namespace lim = scene_limits;
  const auto map_side = std::to_string(cli::max_height_map_side);
  std::cout << R"md(
## Limits

houle refuses, before it allocates anything, whatever would exhaust memory or take unbounded time;
the message names the file (and line when a key is at fault) and what was expected.

| what | limit | refused by |
|---|---|---|
)md" << "| scene file | " << (cli::max_scene_file_bytes >> 20) << " MiB | every command |\n"
            << "| height map image | " << map_side << " x " << map_side << " pixels | every command |\n"
            << "| domain | each side at most " << num(lim::max_domain_side) << " m, bounds within "
            << num(lim::max_coordinate / 1000.0) << " km of the origin | `validate` |\n"
            << "| `[[trains]]` | at most " << lim::max_trains << " | `validate` |\n"
            << "| `[[sea_states]]` | at most " << lim::max_sea_states << ", with at most " << lim::max_components
            << " components together (each a traced train: they count in the memory estimate below) | `validate` |\n"
            << "| `[[floor.shoals]]`, `[[floor.bars]]`, `[[floor.channels]]`, `[[walls]]`, `[[boxes]]`, "
               "`[[spheres]]` | at most "
            << lim::max_items << " each; at most " << lim::max_wall_points << " points per wall | `validate` |\n"
            << "| `dwt.max_rays`, `dwt.max_samples` | at most " << lim::max_rays << " and " << lim::max_samples
            << " per train | `validate` |\n"
            << "| estimated peak memory of the scene build (traced rays, the sea's resampling grids and their "
               "scratch, the floor grid, the walls' blocks, image buffers; sim/src/build_cost.cpp) | "
            << (lim::max_animation_bytes >> 30)
            << " GiB | `validate` at the draft quality; `render`, `bench`, `info` at theirs (and again once the rays "
               "are traced, before the sea's grids), `probe` on 0.5 m cells or else 1 m |\n"
            << "| estimated CPU time of the scene build (one core of the development machine) | " << num(houle::max_build_seconds)
            << R"md( s | the same |
| image size (`--size`) | each side 1..16384, at most 64 Mpixels | `render`, `bench` |
| frames (`--frames`) | at most 10 000 000 per run, numbered below 2^31 | `render` |
)md";
}

}  // namespace

int main() {
  std::cout << "# Scene files\n\n"
            << "<!-- Generated by scripts/regen-scene-doc from the scene key table, sim/src/scene_keys.cpp: edit the table, not this file. -->\n\n"
            << R"md(A scene is a TOML file. Every key is optional unless its default says "(required)": a missing key
takes the default below. Unknown keys, wrong types and out-of-range values are errors reported as
`file:line:column: error: field: what was expected` (`houle validate SCENE`). Every number must be finite,
and lie in its range (for a point, each coordinate). Frame: x east, y north, z up, metres; still water
at z = 0; depth is positive below it (depth <= 0 is land). Angles in the horizontal plane are degrees
counter-clockwise from +x (a train with `direction_deg = 90` travels north). Ranges hold what houle
can compute and show: positions within )md" << num(scene_limits::max_coordinate / 1000.0) << R"md( km of the origin (the renderer's 32-bit floats still hold
a centimetre there), angles within a turn either way, heights and depths within 11 km (the deepest
sea). Files over )md"
            << (cli::max_scene_file_bytes >> 20) << R"md( MiB are refused
(height maps belong in image files).

The paper's scenes, the built-in coast and a sea state with a floating buoy and pontoon (`buoy.toml`) are in `scenes/`.
)md";
  keys::for_each_section([](const auto& section) { print_section(section); });
  print_limits();
}
