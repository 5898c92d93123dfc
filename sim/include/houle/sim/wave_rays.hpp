// Dynamic Wave Tracing (DWT, [GL98] and docs/physics.md 2, 5): wave orthogonals traced once per scene
// over the sea floor, per train, with refraction, shoaling, ray insertion, caustic caps, breaking,
// walls and their reflected waves. Rays are geometric optics only: diffraction is the sea surface's.
//
// How a train is traced (the choices [GL98] leaves open, and why; docs/physics.md 2):
// - Rays start where the train enters the domain, on a straight front perpendicular to its direction
//   (outside the domain the sea is taken as uniform at the entry depth: phase = k_entry x distance
//   from the upstream corner's wavefront, amplitude A0 Ks(h_entry), direction unchanged). A wall
//   that runs out beyond the domain's edge shadows the entries behind it (their straight path from a
//   domain diagonal upstream crosses it): those rays are dead from the start, a cut in the front as
//   an entry on land is, flagged HIT_WALL.
// - Equal-phase stepping (docs/physics.md 2.2): rays advance by the same phase increment
//   dphi = k_ref * step (k_ref: the deepest entry point's k), i.e. ds = dphi / k. Sample j of every
//   ray then lies on the same crest, so neighbours are compared, inserted and tessellated on a common
//   wavefront, and samples per wavelength stay constant as waves shorten towards the shore.
// - Integration: classical RK4 in phi of x, y, theta (bending with the PHASE speed, dtheta/ds =
//   -(1/C) dC/dn), plus s and travel time; sub-steps keep ds <= a quarter of the floor's length scale
//   and the turn per sub-step <= 0.05 rad. A uniform floor is stepped exactly (straight lines).
// - Amplitude: energy flux in ray tubes, incrementally, A_j+1 = A_j sqrt(Cg_j b_j / (Cg_j+1 b_j+1)),
//   b = mean perpendicular spacing to the neighbours over the tubes that exist at both steps (a new,
//   dead or crossed neighbour changes nothing at that step: amplitude stays continuous). Initial rays
//   not yet in the domain (an oblique front enters at staggered phases) bound their neighbours' tubes
//   from their straight path outside. Caps: Kr <= max_refraction_coefficient (caustics), then
//   H <= gamma_b h and H <= 0.142 L tanh kh (breaking; the excess is dissipated and the ray flagged
//   BROKEN).
// - Insertion: between live neighbours farther apart than b_max (never across a dead or crossed
//   neighbour), repeated within a step until none is: at the midpoint on the common wavefront,
//   bisecting direction, mean amplitude (a midpoint inside a wall or on land gives a dead ray, a cut).
// - Turned back: an incident ray that refraction turns against the train's direction of travel ends
//   there (round an island or a steep shoal, where the floor changes within a wavelength and rays no
//   longer describe the wave); reflected waves are exempt. Traced on, such rays filled the domain
//   upstream with back-scattered rays and the inserted rays between them.
// - The wavenumber comes from a tabulated kh(k0h) (relative error 1e-14, sim/src/dispersion_table).
// - Diffraction is not traced: rays end where they meet a wall, and neither the rays passing a
//   pierhead nor the reflected wave's seeds carry any diffraction coefficient. The sea surface
//   (sea_surface.hpp) adds each pierhead's diffracted wave per grid node, from the exact Sommerfeld
//   solution or a paper model, and cuts the rays' families at the shadow lines there.
// - Reflection (docs/physics.md 2.6 ends rays on walls; the reflected wave is added here): the rays of a
//   train that end on a wall with alpha > 0 seed a second trace, the train's reflected wave, as its
//   own WaveRays. Each seed starts at the hit point with the direction mirrored about the wall
//   surface's normal there (angle of reflection = angle of incidence), amplitude alpha A_hit and the
//   incident phase (a rigid wall is an antinode: with alpha = 1 the envelope is 2 A at the wall).
//   Seeds are ordered as the mirror image orders them (reversed) and a seed whose neighbour did not
//   hit the same wall is separated from it by a cut, so tubes, insertion, caustics and breaking work
//   exactly as for the incident front (seeds reach the phase grid at staggered phases like an oblique
//   front). One order only: reflected rays end on walls (they are not reflected again).
// - TrainMesh (issue 3 asked for a rays x steps tessellation): the rays are instead resampled once
//   per scene onto a regular grid per train (sea_surface.hpp TrainField: phase, amplitude, wave
//   vector), which the per-frame surface samples. The grid has no holes or folds where rays cross or
//   end, costs the same however many rays were inserted, and sums trains (and reflected waves) by
//   adding grids; the ray structure (next_on_step, tube_next) stays available for a mesh if one is
//   ever needed.
// - Memory: the samples are staged per ray in chunks of 32 (slabs sized from an estimate, more
//   slabs if it is exceeded; nothing moves) and copied per ray into one output block
//   (houle/runtime/bulk_memory.hpp: huge pages, as first touches dominated the build); everything is bounded by the caps in DwtSettings
//   (dwt_bound): past a cap, insertion or tracing stops and DwtStats::truncated says so. This is
//   scene-build work: nothing here runs per frame.
//
// Nothing here throws, prints or reads the environment; results depend only on (scene, settings).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "houle/runtime/assert.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

/// Per-ray flags: what befell the ray and how it ended (BROKEN, HIT_WALL, LEFT_DOMAIN, CROSSED, DEAD of the paper and
/// docs/physics.md 2.2).
namespace ray_flag {
inline constexpr std::uint8_t broken = 1u << 0;         ///< its height reached the breaking limit
inline constexpr std::uint8_t hit_wall = 1u << 1;       ///< ended on a wall
inline constexpr std::uint8_t left_domain = 1u << 2;    ///< ended on the domain's edge
inline constexpr std::uint8_t crossed = 1u << 3;        ///< crossed a neighbour (a caustic)
inline constexpr std::uint8_t dead = 1u << 4;           ///< ended (any reason; set with the reason)
inline constexpr std::uint8_t reached_shore = 1u << 5;  ///< ended where the depth fell to h_min
inline constexpr std::uint8_t truncated = 1u << 6;      ///< stopped by a cap (path length or samples)
}  // namespace ray_flag

/// Per-sample flags.
namespace sample_flag {
inline constexpr std::uint8_t broken = 1u << 0;     ///< amplitude limited by breaking here
inline constexpr std::uint8_t crossed = 1u << 1;    ///< a tube of this ray has crossed (at or before here)
inline constexpr std::uint8_t off_grid = 1u << 2;   ///< not on the phase grid: a ray's start or end point
inline constexpr std::uint8_t tube_next = 1u << 3;  ///< a sound tube joins this sample to the next ray in
                                                    ///< order with a sample on the same step (next_on_step):
                                                    ///< a quad may join them
}  // namespace sample_flag

/// One train's rays. Rays are ordered across the front, r + 1 lying to the left of r (counter-
/// clockwise from the direction of travel). A ray inserted at step j sits between its parents, so on
/// an earlier step the neighbour of r is the next ray in order that has a sample there
/// (next_on_step); a tube_next flag says the two are joined by a sound tube (never across a ray
/// that has ended there, nor across a crossing).
/// Samples of ray r are [sample_begin[r], sample_begin[r + 1]); on-grid samples are on step
/// first_step[r], first_step[r] + 1, ... in order (an off-grid first sample comes before them, an
/// off-grid last sample after them), and sample s on step j has phase exactly phase0 + j * phase_step.
struct WaveRays {
  // The train.
  double omega = 0.0;          ///< rad/s
  double direction_x = 1.0, direction_y = 0.0;  ///< unit direction of travel where rays enter
  double amplitude0 = 0.0;     ///< m, deep-water amplitude A0
  double phase_step = 0.0;     ///< rad between steps (dphi)
  double phase0 = 0.0;         ///< rad, phase of step 0 (0: the wavefront through the upstream corner)
  double min_depth = 0.0;      ///< m, h_min where rays stopped
  /// No rays were needed (uniform floor, no walls, or amplitude 0): straight crests with wavenumber
  /// analytic_k and amplitude A0 Ks everywhere, phase analytic_k * (direction . (x, y) - upstream).
  bool analytic = false;
  double analytic_k = 0.0;     ///< rad/m
  double analytic_amplitude = 0.0;  ///< m

  // Per ray (ray_count() entries; sample_begin has one more).
  std::vector<std::uint32_t> sample_begin;
  std::vector<std::int32_t> first_step;    ///< step of the first on-grid sample
  std::vector<std::uint8_t> flags;         ///< ray_flag bits
  std::vector<std::int32_t> parent_a, parent_b;  ///< inserted rays: their two parents; -1 otherwise

  // Per sample: read-only views into one block (`sample_storage`, shared by copies; see
  // houle/runtime/bulk_memory.hpp for why one block).
  std::span<const double> x, y;        ///< m
  std::span<const double> theta;       ///< rad, direction of the ray (of travel of the crest)
  std::span<const double> k;           ///< rad/m, local wavenumber
  std::span<const double> amplitude;   ///< m, A (height H = 2A), all factors and caps applied
  std::span<const double> phase;       ///< rad, phi = integral of k ds (the surface phase is phi - omega t + train phase)
  std::span<const double> time;        ///< s, travel time integral of ds / Cg
  std::span<const std::uint8_t> sample_flags;  ///< sample_flag bits
  std::shared_ptr<const std::byte[]> sample_storage;

  std::size_t ray_count() const noexcept { return flags.size(); }
  std::size_t sample_count() const noexcept { return x.size(); }
  /// Index of ray r's on-grid sample on `step`, or -1 if it has none there.
  std::int64_t sample_at_step(std::size_t r, std::int64_t step) const noexcept {
    HOULE_ASSERT(r < ray_count(), "WaveRays::sample_at_step: a ray of this train");
    const std::size_t begin = sample_begin[r], end = sample_begin[r + 1];
    if (begin == end) return -1;
    const std::size_t head = (sample_flags[begin] & sample_flag::off_grid) ? 1 : 0;
    const std::int64_t i = std::int64_t(begin + head) + (step - first_step[r]);
    if (step < first_step[r] || i >= std::int64_t(end) || (sample_flags[std::size_t(i)] & sample_flag::off_grid)) return -1;
    return i;
  }
  /// The first ray after r in order with an on-grid sample on `step`, or -1.
  std::int64_t next_on_step(std::size_t r, std::int64_t step) const noexcept {
    for (std::size_t q = r + 1; q < ray_count(); ++q) {
      if (sample_at_step(q, step) >= 0) return std::int64_t(q);
    }
    return -1;
  }
};

/// What tracing did: tests prove skipped work is zero; `houle info` reports it.
struct DwtStats {
  std::uint64_t rays = 0;             ///< all rays traced (initial + inserted)
  std::uint64_t initial_rays = 0;
  std::uint64_t inserted_rays = 0;    ///< by the spacing rule
  std::uint64_t samples = 0;
  std::uint64_t steps = 0;            ///< wavefront steps swept
  std::uint64_t crossings = 0;        ///< neighbour pairs that crossed
  std::uint64_t broken_rays = 0;
  std::uint64_t wall_hits = 0, left_domain = 0, reached_shore = 0;
  std::uint64_t turned_back = 0;      ///< incident rays refraction turned against the train's direction
  std::uint64_t reflected_rays = 0;   ///< rays of reflected waves (included in `rays`)
  std::uint64_t insertions_refused = 0;  ///< wanted but refused at the max_rays cap
  std::uint64_t shared_steps = 0;     ///< steps whose rays advanced on two threads (large fronts)
  bool truncated = false;             ///< a cap (max_rays, max_samples, path length) was reached
  DwtStats& operator+=(const DwtStats& o) noexcept;
};

/// The wave a train's rays make after reflection on walls (one order of reflection).
struct ReflectedWave {
  std::size_t train = 0;  ///< the incident train (Scene::trains index)
  WaveRays rays;          ///< seeded on the walls; phase and omega continue the incident train's
};

struct WaveField {
  std::vector<WaveRays> trains;  ///< one per Scene::trains entry, same order
  /// Reflected waves of traced trains that hit a wall with alpha > 0 (DwtSettings::reflection), in
  /// train order.
  std::vector<ReflectedWave> reflections;
  DwtStats stats;                ///< totals over the trains and their reflections
};

/// Effect plan: does train `i` need rays? No when its amplitude is 0, or when there is no wall and the
/// floor is uniform or deep everywhere in the domain (depth >= L0 / 2: C within 0.2 % of deep water),
/// where crests are straight and the phase is analytic.
bool train_needs_rays(const Scene& scene, std::size_t train) noexcept;
/// Which model fills the traced trains' fields (scene.wave_model, `auto` resolved), and why: the
/// effect plan reports both (docs/physics.md 10.6).
struct TrainModel {
  WaveModelKind kind = WaveModelKind::rays;  ///< rays or parabolic
  std::string_view why;
};
TrainModel scene_wave_model(const Scene& scene) noexcept;
/// "rays", "parabolic" or "auto": the scene file's names.
std::string_view wave_model_name(WaveModelKind kind) noexcept;

/// Effect plan: is there any diffraction work for the sea surface (a wall end in water inside the
/// domain, diffraction on)?
bool scene_has_pierheads(const Scene& scene) noexcept;

/// Effect plan: can any traced ray be reflected (a wall with alpha > 0, reflection on)?
bool scene_has_reflecting_walls(const Scene& scene) noexcept;

/// Worst case of one train's trace under the settings' caps: the tracer never produces more.
struct DwtBound {
  std::size_t rays = 0;
  std::size_t samples = 0;
};
DwtBound dwt_bound(const Scene& scene, std::size_t train, const DwtSettings& settings) noexcept;

/// A train's front as the tracer starts it: its width across the direction of travel (m, after
/// dwt.front_width), the domain's extent along that direction (m) and the initial rays; ray i enters
/// on the line through `start` along the direction of travel, `start` + (i + 0.5) width / rays metres
/// to its left (left: (-dy, dx)).
struct FrontSize {
  double width = 0.0, length = 0.0;
  std::size_t rays = 0;
  Point2 start{};
};
FrontSize front_size(const Scene& scene, std::size_t train, const DwtSettings& settings) noexcept;

/// What a trace is likely to meet before it starts: a traced train whose initial rays, crossing the
/// domain at dwt.step without a single insertion, would already take more than dwt.max_samples (field
/// "dwt.max_samples", with the figures). A likelihood, not a certainty: rays may end early on land.
std::vector<Error> trace_cap_warnings(const Scene& scene);

/// Traces train `train` of a valid scene (Error if the scene or settings are invalid). With
/// `threads` >= 2, steps over a large front of curving rays (64 or more) advance on two threads, and
/// the final gather is shared; the result is bit-identical to one thread's.
Expected<WaveRays> trace_train(const Scene& scene, std::size_t train, const DwtSettings& settings, DwtStats* stats = nullptr,
                               unsigned threads = 1);
/// The reflected wave of train `train` from its traced rays `incident` (trace_train's result with
/// the same settings): no rays when nothing hit a reflecting wall, or reflection is off. Stats count
/// its rays as reflected_rays. `threads` as for trace_train.
Expected<WaveRays> trace_reflection(const Scene& scene, std::size_t train, const WaveRays& incident,
                                    const DwtSettings& settings, DwtStats* stats = nullptr, unsigned threads = 1);
/// Traces every train with scene.dwt (or the given settings), then its reflection. `threads` > 1
/// traces trains in parallel, and gives a train the threads left over (one train on two threads
/// uses both, as trace_train, and traces its reflection beside its gather); the result is
/// bit-identical for any thread count.
Expected<WaveField> trace_wave_field(const Scene& scene, unsigned threads = 1);
Expected<WaveField> trace_wave_field(const Scene& scene, const DwtSettings& settings, unsigned threads = 1);

}  // namespace houle
