#include "houle/sim/scene_keys.hpp"

#include <charconv>
#include <cmath>

namespace houle::scene_keys {

bool Range::contains(double v) const noexcept {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

bool Range::bounded() const noexcept { return std::isfinite(lo) || std::isfinite(hi); }

namespace {

// Plain digits where they are short (100000, 0.000001), else the shortest form (1e+308).
template <class T>
std::string shortest(T v) {
  char buf[400];
  char* fixed = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed).ptr;
  if (fixed - buf <= 12) return std::string(buf, fixed);
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

}  // namespace

std::string number_text(double v) { return shortest(v); }
std::string number_text(float v) { return shortest(v); }

std::string describe(const Range& r) {
  if (std::isfinite(r.lo) && std::isfinite(r.hi)) {
    return std::string(r.lo_open ? "(" : "[") + number_text(r.lo) + ", " + number_text(r.hi) + (r.hi_open ? ")" : "]");
  }
  if (std::isfinite(r.lo)) return (r.lo_open ? "> " : ">= ") + number_text(r.lo);
  if (std::isfinite(r.hi)) return (r.hi_open ? "< " : "<= ") + number_text(r.hi);
  return "";
}

namespace {

std::string with_unit(std::string text, std::string_view unit) {
  return unit.empty() ? text : text + " " + std::string(unit);
}

// What a number outside `range` should have been: "a finite value > 0 s", "a value in [0, 1]".
std::string expected_number(const Range& range, std::string_view unit) {
  if (!range.bounded()) return "a finite number";
  const std::string bounds = describe(range);
  if (bounds.front() == '[' || bounds.front() == '(') return with_unit("a value in " + bounds, unit);
  return with_unit("a finite value " + bounds, unit);
}

Error bad(const std::string& field, const std::string& expected, const std::string& got) {
  return Error{field, expected + ", got " + got};
}

Expected<void> check_coordinates(std::span<const double> v, const Range& range, std::string_view unit,
                                       const std::string& field) {
  static constexpr const char* axis[] = {".x", ".y", ".z"};
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (range.contains(v[i])) continue;
    // Unbounded coordinates only need to be finite: the point is at fault, not one axis.
    if (!range.bounded()) {
      std::string expected = "finite coordinates";
      if (!unit.empty()) expected.append(" (").append(unit).append(")");
      return Error{field, expected};
    }
    return bad(field + axis[i], expected_number(range, unit), number_text(v[i]));
  }
  return {};
}

}  // namespace

Expected<void> check_value(double v, const Range& range, std::string_view unit, const std::string& field) {
  if (range.contains(v)) return {};
  return bad(field, expected_number(range, unit), number_text(v));
}

Expected<void> check_value(const std::optional<double>& v, const Range& range, std::string_view unit,
                                 const std::string& field) {
  return v ? check_value(*v, range, unit, field) : Expected<void>{};
}

Expected<void> check_value(std::int64_t v, const Range& range, std::string_view, const std::string& field) {
  if (!range.bounded() || range.contains(double(v))) return {};
  return bad(field, "a count in " + describe(range), std::to_string(v));
}

Expected<void> check_value(Point2 v, const Range& range, std::string_view unit, const std::string& field) {
  const double c[] = {v.x, v.y};
  return check_coordinates(c, range, unit, field);
}

Expected<void> check_value(const std::optional<Point2>& v, const Range& range, std::string_view unit,
                                 const std::string& field) {
  return v ? check_value(*v, range, unit, field) : Expected<void>{};
}

Expected<void> check_value(Point3 v, const Range& range, std::string_view unit, const std::string& field) {
  const double c[] = {v.x, v.y, v.z};
  return check_coordinates(c, range, unit, field);
}

Expected<void> check_value(LinearRgb v, const Range& range, std::string_view, const std::string& field) {
  for (float c : {v.r, v.g, v.b}) {
    if (!range.contains(c)) return bad(field, "linear RGB components in " + describe(range), number_text(c));
  }
  return {};
}

Expected<void> check_value(const std::vector<Point2>& v, const Range& range, std::string_view unit,
                                 const std::string& field) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (auto e = check_value(v[i], range, unit, field + "[" + std::to_string(i) + "]"); !e) return e;
  }
  return {};
}

Expected<void> check_choice(int v, std::span<const Choice> choices, const std::string& field) {
  std::string names;
  for (const Choice& c : choices) {
    if (c.value == v) return {};
    names += (names.empty() ? "one of \"" : ", \"") + std::string(c.name) + "\"";
  }
  return bad(field, names, std::to_string(v));
}

// ---- The table ----------------------------------------------------------------------------------

namespace {

// Floor features narrower than 0.5 m are invisible to waves of 1.5 m and longer (the shortest a train
// may have) and would only shrink the tracer's steps; objects from a millimetre.
constexpr Range feature_size{0.5, scene_limits::max_coordinate};
constexpr Range object_size{0.001, scene_limits::max_coordinate};

constexpr Key<Domain> domain_keys[] = {
    {"x_min", &Domain::x_min, "m", any, "west edge of the rectangle in which wave rays are traced"},
    {"y_min", &Domain::y_min, "m", any, "south edge"},
    {"x_max", &Domain::x_max, "m", any, "east edge, greater than `x_min`"},
    {"y_max", &Domain::y_max, "m", any, "north edge, greater than `y_min`"},
};

constexpr Choice floor_kinds[] = {
    {"flat", int(FloorKind::flat), "`depth` everywhere"},
    {"planar_beach", int(FloorKind::planar_beach),
     "the depth grows seaward with `slope` from 0 at `shoreline` up to `depth`"},
};
constexpr bool beach(const FloorBase& b) { return b.kind == FloorKind::planar_beach; }
constexpr Key<FloorBase> floor_base_keys[] = {
    {"kind", &FloorBase::kind, "", any, "the base shape", floor_kinds},
    {"depth", &FloorBase::depth, "m", {0.0, 11000.0, true}, "flat: the depth; beach: the offshore plateau's depth"},
    {"slope", &FloorBase::slope, "m/m", {1e-6, 1.0},
     "beach: depth gained per metre seaward, the tangent of the bottom slope (1:50 = 0.02)", {}, beach},
    {"shoreward_deg", &FloorBase::shoreward_deg, "deg", angle, "beach: direction from sea towards shore", {}, beach},
    {"shoreline", &FloorBase::shoreline, "m", coordinate,
     "beach: a point of the still-water shoreline (depth 0); landward of it the floor keeps rising with the same "
     "slope",
     {}, beach},
    {"sand_colour", &FloorBase::sand_colour, "", unit_interval,
     "linear RGB reflectance of the dry sand (land and sea bed); wet sand, near and under the water, is darker"},
};

constexpr Key<Shoal> shoal_keys[] = {
    {"center", &Shoal::center, "m", coordinate, "centre"},
    {"semi_axis_a", &Shoal::semi_axis_a, "m", feature_size, "semi-axis along `orientation_deg`"},
    {"semi_axis_b", &Shoal::semi_axis_b, "m", feature_size, "semi-axis across it (equal to `semi_axis_a`: circular)"},
    {"orientation_deg", &Shoal::orientation_deg, "deg", angle, "direction of `semi_axis_a`"},
    {"height", &Shoal::height, "m", elevation,
     "how much the floor rises at the centre (negative: a pit); profile (1 − u)³, smooth to the rim"},
};

constexpr Key<Bar> bar_keys[] = {
    {"point", &Bar::point, "m", coordinate, "a point of the crest line"},
    {"along_deg", &Bar::along_deg, "deg", angle, "direction of the crest line"},
    {"half_width", &Bar::half_width, "m", feature_size, "half width"},
    {"height", &Bar::height, "m", elevation, "rise on the crest line (negative: a trough)"},
};

constexpr Key<Channel> channel_keys[] = {
    {"from", &Channel::from, "m", coordinate, "one end of the axis"},
    {"to", &Channel::to, "m", coordinate, "the other end"},
    {"half_width", &Channel::half_width, "m", feature_size, "half width"},
    {"depth", &Channel::depth, "m", elevation, "extra depth on the axis (negative: a levee)"},
};

constexpr Choice height_map_modes[] = {
    {"absolute", int(HeightMapMode::absolute), "the map is the depth (the base is ignored)"},
    {"additive", int(HeightMapMode::additive), "the map is added to the base's depth"},
};
constexpr Key<HeightMapFile> height_map_keys[] = {
    {"file", &HeightMapFile::file, "path", any,
     "image read by OpenImageIO, relative to the scene file; its first channel is used", {}, nullptr, true},
    {"origin", &HeightMapFile::origin, "m", coordinate, "position of the bottom-left pixel centre (the image's top row is north)"},
    {"cell", &HeightMapFile::cell, "m", {0.01, 10000.0}, "distance between pixel centres"},
    {"depth_at_black", &HeightMapFile::depth_at_black, "m", elevation, "depth where the grey level is 0"},
    {"depth_at_white", &HeightMapFile::depth_at_white, "m", elevation,
     "depth where the grey level is 1 (grey levels between map linearly)"},
    {"mode", &HeightMapFile::mode, "", any, "how the map combines with `[floor.base]`", height_map_modes},
};

constexpr Key<Wall> wall_keys[] = {
    {"points", &Wall::points, "m", coordinate,
     "polyline of at least 2 points, consecutive points distinct; each segment must meet the domain (grown by "
     "half the thickness)",
     {}, nullptr, true},
    {"thickness", &Wall::thickness, "m", {0.0, 20.0},
     "width of the structure at its crest (the widest breakwaters' crests are about 20 m; wider is land: raise the floor)"},
    {"reflection", &Wall::reflection, "", unit_interval, "reflection coefficient α (1 rigid, 0 absorbing)"},
    {"crest_height", &Wall::crest_height, "m", {0.0, 11000.0},
     "height above still water (rendering); a submerged crest would be overtopped, which houle's waves are not"},
};

constexpr Key<WaveTrain> train_keys[] = {
    {"direction_deg", &WaveTrain::direction_deg, "deg", angle, "direction of travel"},
    {"direction", &WaveTrain::direction, "", coordinate,
     "direction of travel as a vector of any non-zero length (overrides `direction_deg`)"},
    {"period", &WaveTrain::period, "s", {1.0, 60.0},
     "wave period; give exactly one of `period` and `wavelength`. Shorter waves are ripples (`[capillary]`), "
     "longer ones tides and tsunamis, which this model does not hold"},
    {"wavelength", &WaveTrain::wavelength, "m", {1.5, 5600.0}, "deep-water wavelength L0 = g T² / 2π (T of 1-60 s)"},
    {"amplitude", &WaveTrain::amplitude, "m", non_negative,
     "deep-water amplitude A0, at most the Stokes limit 0.071 L0 (H/L0 = 0.142); shoaled to the local depth "
     "where rays enter the domain"},
    {"phase", &WaveTrain::phase, "rad", any, "added to the train's phase"},
    {"steepness", &WaveTrain::steepness, "", unit_interval, "Gerstner q (0: sine profile)"},
};

constexpr Key<SeaState> sea_state_keys[] = {
    {"significant_height", &SeaState::significant_height, "m", positive,
     "Hs, four times the standard deviation of the surface height (deep water)"},
    {"peak_period", &SeaState::peak_period, "s", {0.5, 30.0}, "Tp, the period at the spectrum's peak"},
    {"gamma", &SeaState::gamma, "", {1.0, 10.0}, "JONSWAP peak enhancement (1: Pierson-Moskowitz)"},
    {"direction_deg", &SeaState::direction_deg, "deg", angle, "mean direction of travel"},
    {"spread_deg", &SeaState::spread_deg, "deg", {0.0, 80.0},
     "directional spread σ of the cos-2s distribution (its circular standard deviation, SWAN's DSPR): s = 2/σ² − 1; "
     "0: long-crested"},
    {"components", &SeaState::components, "", {1.0, double(scene_limits::max_components)},
     "trains the spectrum is expanded into (docs/accuracy.md: the error against 256)"},
    {"seed", &SeaState::seed, "", any, "another seed gives other phases and other pairings of directions with frequencies"},
    {"steepness", &SeaState::steepness, "", unit_interval, "Gerstner q of every component"},
};

constexpr Key<CapillaryNoise> capillary_keys[] = {
    {"amplitude", &CapillaryNoise::amplitude, "m", {0.0, 1.0},
     "0 switches the ripples off (no noise work at all); at most 0.365 `base_wavelength` (Crapper's limit of "
     "a capillary wave's steepness, H/L = 0.73)"},
    {"base_wavelength", &CapillaryNoise::base_wavelength, "m", {0.01, 10.0},
     "lattice spacing of the coarsest octave (longer than 10 m is swell: a `[[trains]]`)"},
    {"lacunarity", &CapillaryNoise::lacunarity, "", {1.25, 4.0}, "frequency ratio between octaves"},
    {"max_octaves", &CapillaryNoise::max_octaves, "", {0.0, 8.0}, "near the camera; far away octaves fade out"},
    {"time_scale", &CapillaryNoise::time_scale, "", {0.0, 100.0}, "multiplies the ripples' drift (0 freezes them)"},
};

constexpr Key<Box> box_keys[] = {
    {"center", &Box::center, "m", coordinate, "centre"},
    {"half_extent", &Box::half_extent, "m", object_size, "half sizes"},
    {"yaw_deg", &Box::yaw_deg, "deg", angle, "rotation about z"},
    {"colour", &Box::colour, "", unit_interval, "linear RGB reflectance"},
    {"float", &Box::floats, "", any, "heaves, pitches and rolls with the sea surface under it (`center`'s z is then ignored)"},
    {"density", &Box::density, "kg/m³", {0.0, sea_water_density, true, true},
     "of a floating box: its draft is 2 half_extent.z · density / 1025"},
};

constexpr Key<Sphere> sphere_keys[] = {
    {"center", &Sphere::center, "m", coordinate, "centre"},
    {"radius", &Sphere::radius, "m", object_size, "radius"},
    {"colour", &Sphere::colour, "", unit_interval, "linear RGB reflectance"},
    {"float", &Sphere::floats, "", any, "rides the sea surface under it (`center`'s z is then ignored)"},
    {"density", &Sphere::density, "kg/m³", {0.0, sea_water_density, true, true},
     "of a floating sphere: the draft at which the submerged cap holds density / 1025 of its volume"},
};

constexpr Key<Sun> sun_keys[] = {
    {"azimuth_deg", &Sun::azimuth_deg, "deg", angle, "direction towards the sun"},
    {"elevation_deg", &Sun::elevation_deg, "deg", {-90.0, 90.0}, "above the horizon"},
};

constexpr Key<Sky> sky_keys[] = {
    {"turbidity", &Sky::turbidity, "", {1.7, 10.0}, "Preetham turbidity"},
};

constexpr Key<ViewCamera> camera_keys[] = {
    {"position", &ViewCamera::position, "m", coordinate, "must be above the sea floor"},
    {"look_at", &ViewCamera::look_at, "m", coordinate, "point looked at, at least 1 cm from the position"},
    {"vertical_fov_deg", &ViewCamera::vertical_fov_deg, "deg", {0.1, 170.0},
     "vertical field of view (a pinhole camera: wider is a fisheye's, narrower a telescope's)"},
};

constexpr Key<CameraKey> camera_path_keys[] = {
    {"time", &CameraKey::time, "s", {-1.0e6, 1.0e6}, "scene time of the key; keys in strictly increasing time", {}, nullptr, true},
    {"position", &CameraKey::position, "m", coordinate, "where the camera is then", {}, nullptr, true},
    {"look_at", &CameraKey::look_at, "m", coordinate, "point looked at (not the position)", {}, nullptr, true},
    {"vertical_fov_deg", &CameraKey::vertical_fov_deg, "deg", {0.1, 170.0},
     "vertical field of view; [camera]'s when not given"},
};

constexpr Key<Water> water_keys[] = {
    {"extra_absorption", &Water::extra_absorption, "1/m", {0.0, 100.0},
     "added to pure water's absorption (turbidity, plankton); at 100 1/m light is gone within 5 cm"},
    {"dominant_wavelength_nm", &Water::dominant_wavelength_nm, "nm", {380.0, 780.0},
     "sea colour (paper's table: Pacific 473, Atlantic 483, Baltic 540)"},
};

constexpr Choice diffraction_models[] = {
    {"exact", int(DiffractionModel::exact), "Sommerfeld's solution"},
    {"paper", int(DiffractionModel::paper), "the paper's eqs. 1–5 as printed"},
    {"paper-corrected", int(DiffractionModel::paper_corrected), "the same with the two typos of docs/physics.md 4.3 fixed"},
};
constexpr Choice cap_policies[] = {
    {"error", int(OnCap::error), "the trace fails: the field beyond the cap would be missing"},
    {"warn", int(OnCap::warn), "the truncated field is kept and every command warns"},
};
constexpr Key<DwtSettings> dwt_keys[] = {
    {"initial_rays", &DwtSettings::initial_rays, "", {0.0, double(scene_limits::max_rays)},
     "rays per train across the front, 0 or at least 2, at most `max_rays`; 0: front width / insertion distance"},
    {"front_width", &DwtSettings::front_width, "m", {0.0, scene_limits::max_coordinate},
     "width covered by the initial rays, centred on the domain; 0: the whole domain"},
    {"step", &DwtSettings::step, "m", {0.0, scene_limits::max_domain_side, true},
     "arc-length step where a ray enters the domain (rays then advance by equal phase); at most the largest "
     "domain side"},
    {"insertion_distance", &DwtSettings::insertion_distance, "m", {0.0, scene_limits::max_domain_side, true},
     "a ray is inserted between neighbours farther apart than this; at most the largest domain side"},
    {"min_depth", &DwtSettings::min_depth, "m", {0.0, 11000.0, true},
     "rays stop where the depth falls below max(min_depth, min_depth_wavelengths · L0)"},
    {"min_depth_wavelengths", &DwtSettings::min_depth_wavelengths, "", {0.0, 0.5}, "see `min_depth`"},
    {"breaker_index", &DwtSettings::breaker_index, "", {0.1, 1.5},
     "the wave height never exceeds breaker_index · depth"},
    {"max_refraction_coefficient", &DwtSettings::max_refraction_coefficient, "", {1.0, 100.0},
     "cap of the refraction coefficient at caustics"},
    {"diffraction", &DwtSettings::diffraction, "", any, "the sea surface adds each pierhead's diffracted wave"},
    {"diffraction_model", &DwtSettings::diffraction_model, "", any, "the model of each pierhead's diffracted wave",
     diffraction_models},
    {"reflection", &DwtSettings::reflection, "", any,
     "rays that hit a wall with `reflection` > 0 start its reflected wave (alpha · A, mirrored)"},
    {"max_rays", &DwtSettings::max_rays, "", {2.0, double(scene_limits::max_rays)},
     "per-train cap on rays (memory and time), at least `initial_rays`"},
    {"max_samples", &DwtSettings::max_samples, "", {64.0, double(scene_limits::max_samples)},
     "per-train cap on ray samples (memory and time)"},
    {"on_cap", &DwtSettings::on_cap, "", any, "what a trace that reaches a cap (rays, samples, path length) does",
     cap_policies},
};

constexpr Choice wave_model_kinds[] = {
    {"rays", int(WaveModelKind::rays), "geometric optics, each pierhead's diffracted wave added"},
    {"parabolic", int(WaveModelKind::parabolic),
     "a wide-angle parabolic mild-slope model marched along each train: refraction and diffraction together"},
    {"auto", int(WaveModelKind::automatic),
     "parabolic over shoals, bars, channels or a height map (where rays cross), rays over flat floors and plane beaches"},
};
constexpr Key<WaveModel> wave_model_keys[] = {
    {"kind", &WaveModel::kind, "", any, "how each traced train's field is computed", wave_model_kinds},
    {"points_per_wavelength", &WaveModel::points_per_wavelength, "", {4.0, 64.0},
     "parabolic: grid points across the march per wavelength, at the shortest wavelength resolved"},
    {"steps_per_wavelength", &WaveModel::steps_per_wavelength, "", {4.0, 64.0},
     "parabolic: march steps per wavelength"},
    {"amplitude_dispersion", &WaveModel::amplitude_dispersion, "", any,
     "parabolic: the wavenumber depends on the local wave height (Kirby & Dalrymple 1986)"},
};

}  // namespace

constexpr Section<Domain> domain{"domain", false, "where water is simulated", "", domain_keys,
                                 [](Scene& s) -> Domain& { return s.domain; }};
constexpr Section<FloorBase> floor_base{"floor.base", false, "the sea floor's base shape", "", floor_base_keys,
                                        [](Scene& s) -> FloorBase& { return s.floor.base; }};
constexpr Section<Shoal> shoals{"floor.shoals", true, "elliptic mounds (shoals, submerged rocks) or pits", "",
                                shoal_keys, nullptr, [](Scene& s) -> std::vector<Shoal>& { return s.floor.shoals; }};
constexpr Section<Bar> bars{"floor.bars", true, "along-shore bars (ridges along a line)", "", bar_keys, nullptr,
                            [](Scene& s) -> std::vector<Bar>& { return s.floor.bars; }};
constexpr Section<Channel> channels{"floor.channels", true, "troughs along a segment", "", channel_keys, nullptr,
                                    [](Scene& s) -> std::vector<Channel>& { return s.floor.channels; }};
constexpr Section<HeightMapFile> height_map{
    "floor.height_map", false, "a sampled sea floor from an image",
    "Interpolated bicubically (Catmull-Rom), clamped to its edge values outside. Larger images than the limit "
    "below are refused.",
    height_map_keys};
constexpr Section<Wall> walls{
    "walls", true, "sea walls, breakwaters, jetties",
    "An end in the water is a pierhead: waves diffract around it into the lee.\n\n"
    "Points may lie outside the domain. The wall is drawn whole, but waves meet only its part inside the "
    "domain, where rays are traced: for them the wall is clipped to the domain. An end outside the domain or "
    "within half the thickness of its edge, like an end on land or in water shallower than where rays stop "
    "(`dwt.min_depth`), is no pierhead: the wall is taken to continue beyond it.",
    wall_keys, nullptr, [](Scene& s) -> std::vector<Wall>& { return s.walls; }};
constexpr Section<WaveTrain> trains{"trains", true, "wave trains from the open sea", "", train_keys, nullptr,
                                    [](Scene& s) -> std::vector<WaveTrain>& { return s.trains; }};
constexpr Section<SeaState> sea_states{
    "sea_states", true, "sea states: wave spectra expanded into trains",
    "A JONSWAP spectrum with cos-2s directional spreading, expanded into `components` trains that are traced "
    "over the floor like written ones (docs/physics.md 2.9): equal-energy frequency bins over [0.5, 5] / Tp, each "
    "a train of amplitude Hs / √(8 N) at its bin's centroid; the direction quantiles dealt to the bins in a "
    "golden-ratio order; phases from a fixed hash of the seed. The same scene gives the same components on "
    "every machine. Every component must stay under the Stokes limit (0.071 L0 at its period). The "
    "components follow the written trains wherever trains are listed (`houle info`, `houle probe`). Where "
    "the floor or walls need rays, each component is a traced train estimated at the rays' caps: for many "
    "components, lower `dwt.max_rays` and `dwt.max_samples` to what a train needs (`houle info` prints it).",
    sea_state_keys, nullptr, [](Scene& s) -> std::vector<SeaState>& { return s.sea_states; }};
constexpr Section<CapillaryNoise> capillary{"capillary", false, "short ripples (fractal noise, paper eq. 9)", "",
                                            capillary_keys,
                                            [](Scene& s) -> CapillaryNoise& { return s.capillary; }};
constexpr std::string_view floating_notes =
    "With `float = true` the object sits at its draft in still water and, each frame, heaves, pitches and rolls "
    "with the plane fitted to the sea surface under its waterplane at that frame's time (docs/physics.md 2.10).";
constexpr Section<Box> boxes{"boxes", true, "box objects (blocks, rocks)", floating_notes, box_keys, nullptr,
                             [](Scene& s) -> std::vector<Box>& { return s.boxes; }};
constexpr Section<Sphere> spheres{"spheres", true, "sphere objects (buoys, rocks)", floating_notes, sphere_keys, nullptr,
                                  [](Scene& s) -> std::vector<Sphere>& { return s.spheres; }};
constexpr Section<Sun> sun{"sun", false, "the sun", "", sun_keys, [](Scene& s) -> Sun& { return s.sun; }};
constexpr Section<Sky> sky{"sky", false, "the sky", "", sky_keys, [](Scene& s) -> Sky& { return s.sky; }};
constexpr Section<ViewCamera> camera{"camera", false, "the view", "", camera_keys,
                                     [](Scene& s) -> ViewCamera& { return s.camera; }};
constexpr Section<CameraKey> camera_path{
    "camera.keys", true, "a moving camera",
    "With keys the camera flies through them: position, look_at and the field of view are each a cubic "
    "Hermite curve through the keys with Catmull-Rom tangents (the neighbouring keys' difference over their "
    "time apart; one-sided at the first and last key), so they move smoothly and pass through every key at its "
    "time; the field of view stays between its two keys' values. Before the first key and after the last the "
    "camera stands at that key. Frame n shows the camera at its own time n / fps, whatever was rendered before "
    "it. `camera.position` and `camera.look_at` are then unused.",
    camera_path_keys, nullptr, [](Scene& s) -> std::vector<CameraKey>& { return s.camera.keys; }};
constexpr Section<Water> water{"water", false, "the water's colour", "", water_keys,
                               [](Scene& s) -> Water& { return s.water; }};
constexpr Section<DwtSettings> dwt{"dwt", false, "accuracy knobs of the wave-ray tracer", "", dwt_keys,
                                   [](Scene& s) -> DwtSettings& { return s.dwt; }};
constexpr Section<WaveModel> wave_model{
    "wave_model", false, "which model computes each traced train's field",
    "Rays are traced in every case (they give the walls' reflected waves). Over a floor whose rays cross, "
    "behind a shoal or round an island, rays can only cap their amplitudes; the parabolic model marches the "
    "wave itself. `docs/physics.md` 10 describes it, `docs/accuracy.md` compares both.",
    wave_model_keys, [](Scene& s) -> WaveModel& { return s.wave_model; }};

}  // namespace houle::scene_keys
