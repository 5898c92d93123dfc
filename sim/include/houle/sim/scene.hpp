// The scene model: everything a coastal scene is made of, as plain structs with sensible defaults.
//
// Frame: x east, y north, z up, metres; still water at z = 0; depth h is positive below it (h <= 0 is
// land). Angles in a plane are degrees counter-clockwise from +x (a train with direction_deg = 90
// travels towards +y). A Scene is data only: `validate` checks it and says which field is wrong and
// what was expected; frontends fill it from files (images go into SeaFloor::height_map).
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "houle/render/colour.hpp"  // LinearRgb: linear (not gamma-encoded) RGB reflectance in [0, 1]
#include "houle/runtime/expected.hpp"
#include "houle/sim/diffraction.hpp"

namespace houle {

struct Point2 {
  double x = 0.0, y = 0.0;  ///< m
};
struct Point3 {
  double x = 0.0, y = 0.0, z = 0.0;  ///< m
};

/// The rectangle where water is simulated (rays are traced inside it).
struct Domain {
  double x_min = 0.0, y_min = 0.0;    ///< m
  double x_max = 200.0, y_max = 200.0;  ///< m
};

// ---- Sea floor: a base, additive features, optionally a height map -----------------------------

enum class FloorKind : std::uint8_t {
  flat,          ///< depth everywhere
  planar_beach,  ///< depth grows seaward with `slope` from 0 at the shoreline up to `depth`
};

struct FloorBase {
  FloorKind kind = FloorKind::flat;
  double depth = 20.0;  ///< m > 0: the flat depth, or the beach's offshore depth (its plateau)
  /// Planar beach only: tan of the bottom slope, > 0 (depth gained per metre seaward; 1:50 = 0.02).
  double slope = 0.02;
  /// Planar beach only: direction from sea towards shore, degrees.
  double shoreward_deg = 90.0;
  /// Planar beach only: a point of the still-water shoreline (depth 0 there). Landward of it the
  /// floor keeps rising with the same slope (negative depth).
  Point2 shoreline{0.0, 0.0};
  /// Linear RGB reflectance of the dry sand (land and sea bed); wet sand is darker (docs/rendering.md 3.6).
  LinearRgb sand_colour{0.55f, 0.5f, 0.4f};
};

/// Elliptic mound (height > 0, a shoal or a submerged rock) or pit (height < 0).
/// Profile height (1 - u)^3, u = (x'/a)^2 + (y'/b)^2 < 1: C2, flat top, zero slope at the rim.
struct Shoal {
  Point2 center{};
  double semi_axis_a = 20.0;      ///< m > 0, along orientation_deg
  double semi_axis_b = 20.0;      ///< m > 0, across it (equal to a: circular)
  double orientation_deg = 0.0;
  double height = 5.0;            ///< m the floor rises at the centre (depth decreases by it)
};

/// Ridge along an infinite line (an along-shore bar): height (1 - (d/half_width)^2)^3 at distance d.
struct Bar {
  Point2 point{};                 ///< a point of the crest line
  double along_deg = 0.0;         ///< direction of the crest line
  double half_width = 10.0;       ///< m > 0
  double height = 1.5;            ///< m the floor rises on the crest line (negative: a trough)
};

/// Trough along a segment with rounded ends: extra depth (1 - (d/half_width)^2)^3 at distance d from
/// the segment [from, to].
struct Channel {
  Point2 from{}, to{};
  double half_width = 5.0;        ///< m > 0
  double depth = 2.0;             ///< m the floor is lowered on the axis (negative: a levee)
};

enum class HeightMapMode : std::uint8_t {
  absolute,  ///< the map is the depth; the base is ignored
  additive,  ///< the map is added to the base's depth
};

/// Sampled depth (an image, a survey). Sample (i, j) lies at origin + (i, j) * cell; it is
/// interpolated bicubically (Catmull-Rom, C1; the stencil is mirrored at the edges, so the slope
/// across an edge is 0 there) and clamped to its edge values outside.
struct HeightMap {
  std::uint32_t nx = 0, ny = 0;   ///< samples per row / column, each >= 2
  Point2 origin{};                ///< m, position of sample (0, 0)
  double cell = 1.0;              ///< m between samples, > 0
  std::vector<float> depth;       ///< m, nx * ny values, row-major (i fastest); positive = water
  HeightMapMode mode = HeightMapMode::absolute;
};

struct SeaFloor {
  FloorBase base{};
  std::vector<Shoal> shoals;
  std::vector<Bar> bars;
  std::vector<Channel> channels;
  std::optional<HeightMap> height_map;
};

// ---- Structures and objects -----------------------------------------------------------------------

/// A sea wall, breakwater or jetty: a thick polyline (capsules of radius thickness/2 around each
/// segment). Its ends inside the domain and in water are pierheads (diffraction sources); ends on the
/// domain edge or on land are not (the wall continues beyond them).
struct Wall {
  std::vector<Point2> points;     ///< >= 2, consecutive points distinct
  double thickness = 2.0;         ///< m >= 0
  double reflection = 0.5;        ///< alpha in [0, 1]: 1 rigid and fully reflecting, 0 absorbing
  double crest_height = 1.5;      ///< m above still water (for rendering)
};

/// Sea water's density (kg/m^3): a floating object of density rho has rho / this of its volume under
/// the still water line.
inline constexpr double sea_water_density = 1025.0;

/// Boxes and spheres may float (floating_object.hpp): each frame they heave, pitch and roll with the
/// sea surface under them; their centre's z is then set by their draft, not by `center`.
struct Box {
  Point3 center{};
  Point3 half_extent{1.0, 1.0, 1.0};  ///< m, each > 0
  double yaw_deg = 0.0;               ///< rotation about z
  LinearRgb colour{0.5f, 0.5f, 0.5f};
  bool floats = false;
  double density = 500.0;             ///< kg/m^3 in (0, sea_water_density): sets the draft of a floating box
};

struct Sphere {
  Point3 center{};
  double radius = 1.0;  ///< m > 0
  LinearRgb colour{0.5f, 0.5f, 0.5f};
  bool floats = false;
  double density = 500.0;  ///< kg/m^3 in (0, sea_water_density): sets the draft of a floating sphere
};

// ---- Waves ---------------------------------------------------------------------------------------

/// A monochromatic long-crested train. Give exactly one of period and wavelength.
struct WaveTrain {
  double direction_deg = 90.0;            ///< direction of travel (used when direction is empty)
  std::optional<Point2> direction;        ///< direction of travel as a vector (any non-zero length)
  std::optional<double> period;           ///< s > 0
  std::optional<double> wavelength;       ///< m > 0, deep-water L0 = g T^2 / (2 pi)
  /// m >= 0, in deep water (A0). Where rays enter the domain it is A0 Ks(h) (shoaled to the local depth).
  /// At most the Stokes limit H/L0 = 0.142, i.e. A0 <= 0.071 L0.
  double amplitude = 0.5;
  double phase = 0.0;                     ///< rad, added to the train's phase
  double steepness = 0.5;                 ///< Gerstner q in [0, 1] (0: sine profile)
  /// The sea state this train is a component of (validate() adds them, sea_state.hpp); -1: written
  /// as a train.
  std::int32_t sea_state = -1;
};

/// A sea state: a JONSWAP spectrum (Pierson-Moskowitz with gamma = 1) with cos-2s directional
/// spreading, expanded by validate() into `components` trains (sea_state.hpp: equal-energy
/// frequency bins, stratified directions, phases from a fixed hash; the same on every machine).
struct SeaState {
  double significant_height = 1.0;  ///< m > 0, Hs = 4 sqrt(m0)
  double peak_period = 8.0;         ///< s, Tp
  double gamma = 3.3;               ///< JONSWAP peak enhancement in [1, 10]; 1: Pierson-Moskowitz
  double direction_deg = 90.0;      ///< mean direction of travel
  /// deg: directional spread sigma (the circular standard deviation, SWAN's DSPR) of the cos-2s
  /// distribution, s = 2 / sigma^2 - 1 (sigma in rad); 0: long-crested (every component along the mean).
  double spread_deg = 25.0;
  std::uint32_t components = 32;    ///< trains it is expanded into
  std::uint32_t seed = 0;           ///< another seed, other phases and pairings of directions with frequencies
  double steepness = 0.5;           ///< Gerstner q of every component
};

/// Short-wave ripples (houle::CapillaryParams in the kernel).
struct CapillaryNoise {
  double amplitude = 0.01;        ///< m >= 0; 0 switches the noise off
  double base_wavelength = 0.5;   ///< m > 0, lattice spacing of the coarsest octave
  double lacunarity = 2.0;        ///< frequency ratio between octaves, in [1.25, 4]
  int max_octaves = 6;            ///< in [0, 8]
  double time_scale = 1.0;        ///< >= 0, multiplies the ripples' drift speed (0 freezes them)
};

// ---- Light, view, water ---------------------------------------------------------------------------

struct Sun {
  double azimuth_deg = 200.0;  ///< direction towards the sun, in the horizontal plane
  double elevation_deg = 35.0;  ///< above the horizon, in [-90, 90]
};

struct Sky {
  double turbidity = 3.0;  ///< Preetham turbidity, in [1.7, 10]
};

/// Where a moving camera is at one time (docs/scenes.md, [[camera.keys]]).
struct CameraKey {
  double time = 0.0;  ///< s of scene time; keys in strictly increasing time
  Point3 position{};
  Point3 look_at{};
  std::optional<double> vertical_fov_deg;  ///< in [0.1, 170]; the [camera] one when not given
};

struct ViewCamera {
  Point3 position{100.0, -20.0, 6.0};
  Point3 look_at{100.0, 80.0, 0.0};
  double vertical_fov_deg = 50.0;  ///< in (0, 180)
  /// Empty: the camera stands still at position. Else it follows these keys (camera_path.hpp) and
  /// position and look_at are not used.
  std::vector<CameraKey> keys;
};

struct Water {
  double extra_absorption = 0.0;        ///< 1/m >= 0, added to pure water's (turbidity, plankton)
  double dominant_wavelength_nm = 490;  ///< sea colour, in [380, 780]
};

// ---- Dynamic Wave Tracing settings ---------------------------------------------------------------

/// Accuracy knobs of the ray tracer (wave_rays.hpp). Defaults are the paper's (Fig. 4).
/// What a trace that reaches one of its caps (dwt.max_rays, dwt.max_samples, the path length) does:
/// the sweep stops there and the field beyond is missing, so by default that is an error.
enum class OnCap : std::uint8_t { error, warn };

struct DwtSettings {
  /// Initial rays per train across the front; 0: enough to space them below the insertion distance.
  std::uint32_t initial_rays = 0;
  /// m across the crests covered by the initial rays, centred on the domain; 0: the whole domain.
  double front_width = 0.0;
  /// m, arc-length step where a ray enters the domain. Rays advance by equal phase increments
  /// (k_entry * step), so the step scales with the local wavelength and sample j of every ray lies on
  /// the same crest.
  double step = 0.4;
  /// m, b_max: a ray is inserted between live neighbours farther apart than this.
  double insertion_distance = 1.0;
  /// m, rays stop where the depth falls below max(min_depth, min_depth_wavelengths * L0).
  double min_depth = 0.02;
  double min_depth_wavelengths = 0.01;
  /// gamma_b: the wave height never exceeds gamma_b h (McCowan 0.78; see docs/physics.md 2.6).
  double breaker_index = 0.78;
  /// Cap of the refraction coefficient Kr at caustics (docs/physics.md 2.5).
  double max_refraction_coefficient = 2.5;
  /// Effect plan: trains that need no rays (train_needs_rays) get an analytic description instead.
  /// false traces them anyway (tests, benchmarks).
  bool analytic_shortcut = true;
  /// Diffraction at pierheads: the sea surface adds each pierhead's diffracted wave, of this model
  /// (sea_surface.hpp); the rays are geometric optics only.
  bool diffraction = true;
  DiffractionModel diffraction_model = DiffractionModel::exact;
  /// Reflection on walls with alpha > 0: the rays that hit them seed a reflected wave (wave_rays.hpp).
  bool reflection = true;
  /// Caps that bound memory and time (dwt_bound); beyond them insertion stops and the stats say so.
  std::uint32_t max_rays = 1u << 15;      ///< per train
  std::uint32_t max_samples = 1u << 22;   ///< per train
  OnCap on_cap = OnCap::error;            ///< warn: the truncated field is kept and every command says so
};

// ---- Wave model ----------------------------------------------------------------------------------

/// How a traced train's field is computed (docs/physics.md 10; rays are traced in every case: they
/// give the wall reflections and the carrier's entry).
enum class WaveModelKind : std::uint8_t {
  rays,       ///< geometric optics, each pierhead's diffracted wave added (docs/physics.md 2, 4.7)
  parabolic,  ///< a wide-angle parabolic mild-slope model marched along the train: refraction and
              ///< diffraction together, amplitude dispersion, breaking
  automatic,  ///< parabolic over a floor whose rays cross (shoals, bars, channels, a height map), rays
              ///< over flat floors and plane beaches (where they are exact)
};

struct WaveModel {
  WaveModelKind kind = WaveModelKind::automatic;
  /// Parabolic model: grid points per wavelength across the march, at the shortest wavelength it
  /// resolves (where the deep-water wave would break, or at dwt's min depth).
  double points_per_wavelength = 10.0;
  /// Parabolic model: march steps per wavelength of the row's mean wave.
  double steps_per_wavelength = 8.0;
  /// Parabolic model: the wavenumber depends on the local amplitude (Kirby & Dalrymple 1986).
  bool amplitude_dispersion = true;
};

// ---- The scene -----------------------------------------------------------------------------------

/// What `validate` accepts at most: together they bound the memory and time of a scene build
/// (docs/scenes.md, "Limits"). Animation::create also refuses a scene whose estimated memory at the
/// chosen quality exceeds max_animation_bytes.
namespace scene_limits {
inline constexpr double max_domain_side = 4000.0;     ///< m, each side of the domain
inline constexpr double max_coordinate = 100000.0;    ///< m, |bound| of the domain from the origin
inline constexpr std::size_t max_trains = 16;
inline constexpr std::size_t max_sea_states = 16;
inline constexpr std::size_t max_components = 256;  ///< sea-state components, all sea states together
inline constexpr std::size_t max_items = 1024;        ///< shoals, bars, channels, walls, boxes, spheres (each)
inline constexpr std::size_t max_wall_points = 4096;  ///< per wall
inline constexpr std::uint32_t max_rays = 1u << 20;    ///< dwt.max_rays (per train)
inline constexpr std::uint32_t max_samples = 1u << 24;  ///< dwt.max_samples (per train)
inline constexpr std::uint64_t max_animation_bytes = 4ull << 30;
}  // namespace scene_limits

struct Scene {
  Domain domain{};
  SeaFloor floor{};
  std::vector<Wall> walls;
  std::vector<WaveTrain> trains;  ///< written trains, then the sea states' components (validate())
  std::vector<SeaState> sea_states;
  CapillaryNoise capillary{};
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;
  Sun sun{};
  Sky sky{};
  ViewCamera camera{};
  Water water{};
  DwtSettings dwt{};
  WaveModel wave_model{};
};

/// The scene if it is valid, with its sea states' components as trains after the written ones
/// (sea_state_components; done again, a valid scene's validate() changes nothing); otherwise the
/// first problem, e.g. {"trains[1].period", "a finite value > 0 s, got -3"}.
Expected<Scene> validate(Scene scene);

/// omega = 2 pi / T (rad/s) of a train, from its period or its deep-water wavelength; 0 if neither
/// is a positive finite number.
double train_omega(const WaveTrain& train) noexcept;
/// Unit direction of travel of a train (from `direction` when set, else `direction_deg`); {1, 0} for a
/// zero or non-finite vector.
Point2 train_direction(const WaveTrain& train) noexcept;

/// The built-in coast: a 1:30 sloping beach, a jetty with a pierhead in the water, three trains from
/// the sea, capillary ripples and two submerged rocks. Valid by construction.
Scene builtin_coast();

/// The paper's Fig. 4 / Plate 2 scene: 100 m x 100 m flat bottom, a semi-infinite sea wall from the
/// west edge to the middle, 70 initial rays, 0.4 m step, 1.0 m insertion distance. The initial front
/// spans the whole 100 m (1.43 m spacing), so the first insertion pass already splits every tube:
/// docs/physics.md 2.1 notes the paper does not say which reading it used.
Scene paper_fig4();

}  // namespace houle
