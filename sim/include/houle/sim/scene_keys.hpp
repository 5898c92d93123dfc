// The scene file's keys, each described once: its name, the member it fills, its unit, range and
// documentation. The parser (frontends/houle/scene_file.cpp) reads keys through this table,
// `validate` checks their ranges with it, and docs/scenes.md is generated from it
// (tests/scene_doc/gen_scene_doc.cpp). Defaults are those of the structs' member initialisers.
// What no single key's range can say (x_min < x_max, wall geometry, one of period and wavelength)
// stays explicit code in scene.cpp.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

/// [floor.height_map] as a scene file writes it: an image whose grey levels map linearly to depths
/// (black 0, white 1). A frontend reads the image into SeaFloor::height_map (sim does no file I/O).
struct HeightMapFile {
  std::string file;               ///< image path, relative to the scene file
  Point2 origin{};                ///< m, the bottom-left pixel centre; the image's top row is north
  double cell = 1.0;              ///< m between pixel centres
  double depth_at_black = 20.0;   ///< m
  double depth_at_white = -2.0;   ///< m (negative: land)
  HeightMapMode mode = HeightMapMode::absolute;
};

namespace scene_keys {

/// Where a number (or each component of a point) may lie; every number must also be finite.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  bool contains(double v) const noexcept;
  bool bounded() const noexcept;
};
inline constexpr Range any{};
inline constexpr Range positive{0.0, std::numeric_limits<double>::infinity(), true, false};
inline constexpr Range non_negative{0.0, std::numeric_limits<double>::infinity()};
inline constexpr Range unit_interval{0.0, 1.0};
/// Positions (each coordinate): within scene_limits::max_coordinate of the origin, where the renderer's
/// 32-bit floats still hold a centimetre.
inline constexpr Range coordinate{-scene_limits::max_coordinate, scene_limits::max_coordinate};
/// Angles in degrees: a turn either way.
inline constexpr Range angle{-360.0, 360.0};
/// Heights and depths of the floor and of structures: the deepest sea is 11 km deep.
inline constexpr Range elevation{-11000.0, 11000.0};

/// "> 0", ">= 0", "[1.25, 4]", "(0, 180)"; empty for `any`.
std::string describe(const Range& range);
/// Shortest text that reads back as the same number (std::to_chars; plain digits up to 12 characters,
/// 100000 rather than 1e+05), so a message never contradicts
/// itself ("a value <= 1, got 1").
std::string number_text(double v);
std::string number_text(float v);

/// One allowed name of an enum key, its value (the enum's underlying integer) and what it means.
struct Choice {
  std::string_view name;
  int value;
  std::string_view doc;
};

/// The member a key fills in an item of type S.
template <class S>
using Member = std::variant<double S::*, std::optional<double> S::*, int S::*, std::uint32_t S::*, bool S::*,
                            Point2 S::*, std::optional<Point2> S::*, Point3 S::*, LinearRgb S::*,
                            std::vector<Point2> S::*, std::string S::*, FloorKind S::*, HeightMapMode S::*,
                            DiffractionModel S::*, OnCap S::*, WaveModelKind S::*>;

template <class S>
struct Key {
  std::string_view name;
  Member<S> member;
  std::string_view unit;           ///< of the value, or of each coordinate of a point ("m", "deg")
  Range range = any;               ///< of the value, or of each component
  std::string_view doc;
  std::span<const Choice> choices = {};  ///< enum keys: the names a file may write
  /// Checked only for items where this holds (the beach's keys of a flat floor are ignored); null: always.
  bool (*applies)(const S&) = nullptr;
  bool required = false;           ///< a file must write it (no default)
};

/// A TOML table ([path]) or array of tables ([[path]]) and its keys.
template <class S>
struct Section {
  std::string_view path;           ///< "domain", "floor.shoals"
  bool array;                      ///< [[path]]
  std::string_view title;          ///< what it describes, for docs/scenes.md
  std::string_view notes;          ///< prose after its keys in docs/scenes.md, may be empty
  std::span<const Key<S>> keys;
  /// Where its items live in a Scene: the one table, or the array. Both null for [floor.height_map],
  /// whose image the frontend reads into SeaFloor::height_map.
  S& (*table_in)(Scene&) = nullptr;
  std::vector<S>& (*array_in)(Scene&) = nullptr;
};

extern const Section<Domain> domain;
extern const Section<FloorBase> floor_base;
extern const Section<Shoal> shoals;
extern const Section<Bar> bars;
extern const Section<Channel> channels;
extern const Section<HeightMapFile> height_map;
extern const Section<Wall> walls;
extern const Section<WaveTrain> trains;
extern const Section<SeaState> sea_states;
extern const Section<CapillaryNoise> capillary;
extern const Section<Box> boxes;
extern const Section<Sphere> spheres;
extern const Section<Sun> sun;
extern const Section<Sky> sky;
extern const Section<ViewCamera> camera;
extern const Section<CameraKey> camera_path;
extern const Section<Water> water;
extern const Section<DwtSettings> dwt;
extern const Section<WaveModel> wave_model;

/// Calls visit(section) for every section, in the order of docs/scenes.md.
template <class Visit>
void for_each_section(Visit&& visit) {
  visit(domain);
  visit(floor_base);
  visit(shoals);
  visit(bars);
  visit(channels);
  visit(height_map);
  visit(walls);
  visit(trains);
  visit(sea_states);
  visit(capillary);
  visit(boxes);
  visit(spheres);
  visit(sun);
  visit(sky);
  visit(camera);
  visit(camera_path);
  visit(water);
  visit(dwt);
  visit(wave_model);
}

/// The key `name` of a section (which must have it).
template <class S>
const Key<S>& key(const Section<S>& section, std::string_view name) {
  for (const Key<S>& k : section.keys) {
    if (k.name == name) return k;
  }
  std::abort();  // a misspelt name in houle's own code
}

// The range check of one value, named `field` in the error.
Expected<void> check_value(double v, const Range& range, std::string_view unit, const std::string& field);
Expected<void> check_value(const std::optional<double>& v, const Range& range, std::string_view unit,
                                 const std::string& field);
Expected<void> check_value(std::int64_t v, const Range& range, std::string_view unit, const std::string& field);
Expected<void> check_value(Point2 v, const Range& range, std::string_view unit, const std::string& field);
Expected<void> check_value(const std::optional<Point2>& v, const Range& range, std::string_view unit,
                                 const std::string& field);
Expected<void> check_value(Point3 v, const Range& range, std::string_view unit, const std::string& field);
Expected<void> check_value(LinearRgb v, const Range& range, std::string_view unit, const std::string& field);
Expected<void> check_value(const std::vector<Point2>& v, const Range& range, std::string_view unit,
                                 const std::string& field);
Expected<void> check_choice(int v, std::span<const Choice> choices, const std::string& field);

/// The first key of `item` outside its range (or not one of its choices), named "<path>.<key>"; success
/// when every key is in range.
template <class S>
Expected<void> check_keys(const Section<S>& section, const S& item, const std::string& path) {
  for (const Key<S>& k : section.keys) {
    if (k.applies && !k.applies(item)) continue;
    const std::string field = path + "." + std::string(k.name);
    const Expected<void> e = std::visit(
        [&](auto member) -> Expected<void> {
          const auto& v = item.*member;
          using T = std::remove_cvref_t<decltype(v)>;
          if constexpr (std::is_enum_v<T>) {
            return check_choice(int(v), k.choices, field);
          } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
            return check_value(std::int64_t(v), k.range, k.unit, field);
          } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>) {
            return {};
          } else {
            return check_value(v, k.range, k.unit, field);
          }
        },
        k.member);
    if (!e) return e;
  }
  return {};
}

}  // namespace scene_keys
}  // namespace houle
