// Dynamic Wave Tracing: the wavefront sweep of one train (see wave_rays.hpp for the method and its
// choices). TrainTracer's members are defined by topic, each file named after what it holds:
//   tracer_front.cpp       the entry front and the initial rays
//   tracer_sweep.cpp       the sweep: each step's passes (advance, tubes, amplitudes), the hot path, in
//                          one translation unit so that the compiler inlines it as one
//   tracer_insertion.cpp   rays inserted where neighbours drift apart
//   tracer_reflection.cpp  the reflected wave, seeded where rays ended on walls
//   tracer_output.cpp      the runs and the gather into WaveRays
// wave_tracing.cpp holds the entry points (trace_train, trace_reflection, trace_wave_field, dwt_bound).
// Internal to houle_sim.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "houle/runtime/bulk_memory.hpp"
#include "houle/runtime/thread_pool.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/wave_rays.hpp"
#include "ray_step.hpp"
#include "ray_walls.hpp"

namespace houle::detail {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();
// Rays a train the parabolic model marches may have, per initial ray (docs/physics.md 10.6): the
// shipped scenes insert 1.5-2 per initial ray; over 1,024 random shoals, bars and channels insertion
// went on to dwt.max_rays, 127 per initial ray, and the trace stopped there.
constexpr std::size_t marched_ray_factor = 8;

// Where the parabolic model marches the field and no wall reflects, a train's rays only seed the
// carrier phase: a cap that stops them leaves nothing missing, since the carrier march fills the
// phase beyond them (docs/physics.md 10.6).
inline bool rays_only_seed_the_carrier(const Scene& scene, const DwtSettings& set) noexcept {
  return scene_wave_model(scene).kind == WaveModelKind::parabolic &&
         !(set.reflection && scene_has_reflecting_walls(scene));
}

// ---- The train's entry front, shared by dwt_bound and the tracer -------------------------------

struct Entry {
  double x = 0.0, y = 0.0;  // where the ray enters the domain, m
  double phi = 0.0;         // rad, k_entry * distance from the upstream wavefront
  double tau = 0.0;         // s
  double theta = 0.0;       // rad, direction of travel
  double amplitude = 0.0;   // m, a_geo at the entry point
  LocalWave wave{};
  bool water = false;       // false: the entry point is land (or shallower than h_min), or behind a wall
  bool behind_wall = false;  // a wall beyond the domain's edge shadows the entry point
};

struct Front {
  double omega = 0.0, k0 = 0.0, l0 = 0.0;
  double dx = 1.0, dy = 0.0;   // direction of travel
  double h_min = 0.0;
  double dphi = 0.0;           // phase step
  double k_ref = 0.0;
  std::vector<Entry> entries;  // in order across the front (increasing to the left)
};

Medium make_medium(const Scene& scene, const Bathymetry& floor, double omega, double h_min);
Front make_front(const Scene& scene, std::size_t train, const DwtSettings& set, const Medium& medium);

inline double path_limit(const Domain& d) noexcept { return 4.0 * ((d.x_max - d.x_min) + (d.y_max - d.y_min)); }

inline double dist(double x, double y) noexcept { return std::sqrt(x * x + y * y); }  // no need for hypot's range care

// ---- The tracer --------------------------------------------------------------------------------

// One sample as the sweep builds it.
struct StagedSample {
  double x, y, theta, k, amplitude, phase, time;
  std::uint8_t flags;
};

// Samples are staged per ray in chunks of consecutive samples of one ray; a ray points to its latest
// sample, which the sweep still amends (amplitude, flags). The gather at the end then copies runs
// per ray, and only chunks in use are ever touched (bulk_memory.hpp: first touches cost).
struct alignas(64) SampleChunk {
  static constexpr std::uint32_t size = 32;
  StagedSample at[size];
  SampleChunk* next;  // the ray's next chunk, or null
};

// A ray's chunks, first to last (the last one partly filled).
struct ChunkList {
  SampleChunk* first = nullptr;
  SampleChunk* last = nullptr;
  std::uint32_t count = 0;  // samples
};

// Chunks in slabs of equal size, none of which moves once allocated.
class SampleStore {
 public:
  // Sizes the slabs for about `samples` samples (before the first append).
  void reserve(std::size_t samples) { slab_chunks_ = std::max(slab_chunks_, samples / SampleChunk::size + 64); }
  // A new last sample of `list`.
  StagedSample& append(ChunkList& list) {
    const std::uint32_t slot = list.count % SampleChunk::size;
    if (slot == 0) {
      SampleChunk* c = new_chunk();
      c->next = nullptr;
      (list.last ? list.last->next : list.first) = c;
      list.last = c;
    }
    ++list.count;
    if (slot + 1 < SampleChunk::size) {
      // The ray's next sample, written on the next step: its lines are fetched meanwhile (the
      // hardware sees no stream in one sample per ray per step).
      const auto* next = reinterpret_cast<const char*>(&list.last->at[slot + 1]);
      __builtin_prefetch(next, 1);
      __builtin_prefetch(next + sizeof(StagedSample) - 1, 1);
    }
    return list.last->at[slot];
  }

 private:
  SampleChunk* new_chunk() {
    if (used_ == slab_chunks_ || blocks_.empty()) {
      BulkLayout layout;
      const std::size_t at = layout.add<SampleChunk>(slab_chunks_);
      blocks_.push_back(layout.allocate());
      slab_ = BulkLayout::at<SampleChunk>(blocks_.back().get(), at);
      used_ = 0;
    }
    return slab_ + used_++;
  }
  std::vector<std::shared_ptr<std::byte[]>> blocks_;
  SampleChunk* slab_ = nullptr;  // the last slab, of which used_ chunks are taken
  std::size_t slab_chunks_ = 64, used_ = 0;
};

// What the worker of a pass writes besides the rays and pairs it owns.
struct Lane {
  SampleStore samples;
  DwtStats stats{};
  double widest = 0.0;        // the largest pair_sigma_ of a real pair on this wavefront
  bool any_alive = false;
  bool truncated = false;
};

// Fields are grouped so that a step touches four of a ray's lines (the ones prefetch_ray fetches):
// pose; wavefront state and amplitude; tube and samples; the wave's first half. Cold fields last.
struct alignas(64) Ray {
  // Line 0: motion and pose (pass A, tubes).
  RayState st{};
  double cos_t = 1.0, sin_t = 0.0;  // of st.theta
  // Line 1: state on the wavefront (every pass), amplitude.
  bool alive = true;             // not ended (pending rays are alive)
  bool entering = false;         // an initial ray that has not reached the domain: outside it, on a
                                 // straight path in uniform water, it still bounds its neighbours' tubes
  bool joined = false;           // has reached the phase grid
  bool joined_now = false;       // its first on-grid sample is this step's
  bool fresh = false;            // inserted on this step, complete: nothing to update
  bool tube_crossed = false;
  std::uint8_t flags = 0;
  std::int32_t crossed_with = -1;  // this step: the next ray it is found crossed with
  double a_geo = 0.0;            // m, amplitude from shoaling and tube width (capped)
  double a_prev = 0.0, cg_prev = 0.0;  // at the previous sample
  double width_ratio = 1.0;      // b_prev / b over the last full step (for a final partial step)
  double clear = 0.0;            // m of path from st free of walls and the domain's edge (chord_event)
  std::int32_t tube_next = -1;   // the tube to the next ray in order, as of the last completed step
  // Line 2: that tube and the samples.
  double tube_sigma = 0.0;       // perpendicular spacing, m
  StagedSample* latest = nullptr;  // in samples; null before the first (or if the cap refused it)
  ChunkList samples;             // in a lane's SampleStore: appended to on every step
  double home_x = 1.0, home_y = 0.0;  // the direction the ray set out in (turned_back)
  // Lines 3-4: the wave at st (its hot fields first; aligned where pointers are 4 bytes).
  alignas(64) LocalWave w{};
  // Cold: lineage.
  std::int32_t first_step = -1;
  std::int32_t parent_a = -1, parent_b = -1;
  // Rays dropped from the sweep that follow this one in the output, first to last (drop_inert_rays),
  // linked by dropped_next.
  std::int32_t dropped_first = -1, dropped_last = -1, dropped_next = -1;

  void sync_direction() noexcept {
    cos_t = std::cos(st.theta);
    sin_t = std::sin(st.theta);
  }
};
static_assert(offsetof(Ray, alive) == 64 && offsetof(Ray, tube_sigma) == 128 && offsetof(Ray, home_y) < 192 &&
                  offsetof(Ray, w) == 192,
              "Ray's hot fields are in its first four lines");

enum class Stop : std::uint8_t { none, wall, domain, shore, turned };

// Where a ray ended, if it seeds the reflected wave: its last sample, with its final amplitude.
struct RayEnd {
  bool on_wall = false;
  double x = 0.0, y = 0.0, theta = 0.0, phase = 0.0, time = 0.0, amplitude = 0.0;
};

// The same from a train's output.
std::vector<RayEnd> ray_ends(const WaveRays& in);

// One train's wave, incident or reflected, traced as a sweep of wavefronts.
class TrainTracer {
 public:
  // The incident train, from its entry front, on the caller's thread and the lanes of `pool` (none,
  // or a pool of two: see train_pool()).
  TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, ThreadPool* pool);
  // The train's reflected wave, seeded where its rays ended on reflecting walls (ray_ends(), with the
  // incident wave's omega, direction of entry and phase step).
  TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, const std::vector<RayEnd>& ends,
              double omega, double dx, double dy, double dphi, ThreadPool* pool);

  WaveRays run(DwtStats& stats);

  // run(), and the wave reflected where this one's rays ended (trace_reflection of its result). On
  // two lanes in uniform water the reflected wave is traced on the second, beside this one's gather;
  // where rays curve, after it on both (its large fronts share their steps).
  WaveRays run_reflecting(DwtStats& stats, WaveRays& reflected, DwtStats& reflected_stats);

  // Where every ray ended, in output order (after the sweep): what a reflected wave starts from.
  std::vector<RayEnd> ray_ends() const;

 private:
  // A ray's position and direction on the current wavefront (pose_on_step).
  struct Pose {
    double x, y, cos_t, sin_t;
  };
  // A neighbour pair's tube over the last step: widths then and now where it persisted soundly.
  struct PairTube {
    double b_prev = 0.0, b_now = 0.0;
    bool sound = false, crossed = false;
  };
  struct Pending {
    std::size_t after;  // insert after this position in order_
    std::int32_t id;
  };
  // Where finish() writes the samples.
  struct Gather {
    double* const* arrays;  // x, y, theta, k, amplitude, phase, time
    std::uint8_t* flags;
  };

  // ---- tracer_front.cpp ----
  void init_medium();
  void set_step(double dphi) noexcept;
  void start_front();

  // ---- tracer_reflection.cpp ----
  Front reflected_front(const std::vector<RayEnd>& ends, double omega, double dx, double dy, double dphi) const;
  bool wall_of(double x, double y, std::uint32_t& wall) const noexcept;

  // ---- tracer_sweep.cpp ----
  // Those declared inline are defined there, the only file that calls them: the compiler folds an
  // inline function into the step's loops, as it did all of these when the tracer was one file, but
  // keeps an external one out of line unless it is small. advance_on_step and advance_ray, the per-ray
  // step, it folded only as local functions called once: they are inlined by force (a call fewer per
  // ray per step).
  void sweep();
  inline std::size_t estimate_samples() const noexcept;
  [[gnu::noinline]] double chord_event_near(const RayState& a, const RayState& b, double depth_b, double travel,
                                            double& clear, Stop& why) const noexcept;
  inline double clearance(double x, double y) const noexcept;
  [[gnu::always_inline]] inline bool advance_ray(Lane& lane, std::int32_t id, double dphi);
  inline void step(std::int32_t j);
  inline void advance_front(Lane& lane, std::int32_t j, std::size_t lo, std::size_t hi);
  inline void prefetch_ray(std::int32_t id) const noexcept;
  void merge_side_lane();
  [[gnu::always_inline]] inline void advance_on_step(Lane& lane, std::int32_t id, std::int32_t j);
  inline void drop_inert_rays();
  inline void follow(std::int32_t p, std::int32_t d);
  inline bool pose_on_step(const Ray& r, double phi_j, Pose& p) const noexcept;
  static inline double spacing(const Pose& a, const Pose& b) noexcept;
  inline void measure_tubes();
  inline void measure_pairs(Lane& lane, std::size_t lo, std::size_t hi);
  inline void begin_tubes();
  inline double measure_pair(std::size_t i, const Pose& pa, const Pose& pb);
  inline void update_amplitudes(bool record);
  inline PairTube classify_pair(std::size_t i);
  inline void record_tube(std::size_t i);
  inline bool on_grid_sample(const Ray& r) noexcept;

  // ---- tracer_insertion.cpp ----
  void apply_insertions();
  bool insert_rays(std::int32_t j);
  std::int32_t insert_midpoint(std::int32_t ia, std::int32_t ib, std::int32_t j);

  // ---- tracer_output.cpp ----
  template <class Also>
  WaveRays finish(DwtStats& stats, const Also& also);
  void gather(const WaveRays& out, const Gather& g, std::size_t lo, std::size_t hi) const;

  // ---- What several of those files use, inline: the phase grid, samples and their caps, moving a ray ----

  double max_k() const noexcept {
    // The shortest waves are at h_min: no ray has more phase per metre.
    return wave_from_depth(medium_, h_min_).k;
  }

  double grid_phase(std::int64_t j) const noexcept { return double(j) * front_.dphi; }
  bool on_grid(double phi) const noexcept { return grid_phase(std::int64_t(std::round(phi / front_.dphi))) == phi; }
  std::int64_t grid_step_at_or_after(double phi) const noexcept {
    std::int64_t j = std::int64_t(std::ceil(phi / front_.dphi));
    while (grid_phase(j) < phi) ++j;
    while (grid_phase(j - 1) >= phi) --j;
    return j;
  }

  // On a shared pass, step() has made sure that the cap is not reached (side_ counts from 0).
  [[gnu::always_inline]] void write_sample(Lane& lane, std::int32_t id, const RayState& st, const LocalWave& w,
                                           std::uint8_t flags) {
    Ray& r = rays_[std::size_t(id)];
    if (lane.stats.samples >= set_.max_samples) {
      lane.truncated = true;
      r.latest = nullptr;
      return;
    }
    r.latest = &lane.samples.append(r.samples);
    *r.latest = StagedSample{st.x, st.y, st.theta, w.k, 0.0, st.phi, st.tau, flags};
    ++lane.stats.samples;
  }

  // The largest amplitude the breaking caps allow: H <= gamma_b h and H <= 0.142 L tanh kh.
  double breaking_limit(const LocalWave& w) const noexcept {
    return std::min(0.5 * set_.breaker_index * w.h, 0.071 * two_pi / w.k * w.tanh_kh);
  }

  // Amplitude of ray id's latest sample from its a_geo, then the breaking caps H <= gamma_b h and
  // H <= 0.142 L tanh kh (the excess is dissipated from a_geo).
  [[gnu::always_inline]] void finalize(Lane& lane, std::int32_t id) {
    Ray& r = rays_[std::size_t(id)];
    if (!r.latest) return;  // the sample cap refused it
    StagedSample& c = *r.latest;
    const double a_break = medium_.uniform ? uniform_a_break_ : breaking_limit(r.w);
    if (r.a_geo > a_break) {
      r.a_geo = a_break;
      c.flags |= sample_flag::broken;
      if (!(r.flags & ray_flag::broken)) ++lane.stats.broken_rays;
      r.flags |= ray_flag::broken;
    }
    c.amplitude = r.a_geo;
  }

  // Where along the chord a -> b (0..1) the ray meets a wall, the domain's edge or the shoreline
  // (depth h_min), whichever comes first; > 1 if none. `clear` is a path length from a within which
  // the ray can meet neither a wall nor the domain's edge, kept up to date here: most chords skip
  // those tests.
  double chord_event(const RayState& a, const RayState& b, double depth_b, double& clear, Stop& why) const noexcept {
    why = Stop::none;
    // The path length is at least the chord's (RK4 sums the same positive weights for both).
    const double travel = b.s - a.s;
    if (travel < clear && depth_b > h_min_) {
      clear -= travel;  // most chords: inline, the rest out of line
      return 2.0;
    }
    return chord_event_near(a, b, depth_b, travel, clear, why);
  }

  // Moves ray `id` on by dphi. If it meets a wall, the domain's edge or the shoreline it stops there,
  // is flagged dead with the reason, and false is returned. Amplitudes are the caller's business.
  bool move_ray(Lane& lane, std::int32_t id, double dphi) {
    Ray& r = rays_[std::size_t(id)];
    Stop why = Stop::none;
    auto stop = [&](const RayState& a, const RayState& b, double depth_b) {
      return chord_event(a, b, depth_b, r.clear, why);
    };
    bool ended = advance(medium_, r.st, r.w, dphi, r.cos_t, r.sin_t, stop);
    if (!medium_.uniform) {
      r.sync_direction();  // straight rays keep theta
      if (!ended && turned_back(r)) ended = true, why = Stop::turned;
    }
    if (!ended) return true;
    r.alive = false;
    r.flags |= ray_flag::dead;
    if (why == Stop::wall) {
      r.flags |= ray_flag::hit_wall;
      ++lane.stats.wall_hits;
    } else if (why == Stop::domain) {
      r.flags |= ray_flag::left_domain;
      ++lane.stats.left_domain;
    } else if (why == Stop::turned) {
      ++lane.stats.turned_back;
    } else {
      r.flags |= ray_flag::reached_shore;
      ++lane.stats.reached_shore;
    }
    return false;
  }

  // A ray that refraction has turned more than 90 degrees from the direction it set out in ends
  // there (docs/physics.md 2.6). Only a floor that changes within a wavelength turns a ray that far
  // (round an island or a steep shoal), where rays no longer describe the wave; what is scattered
  // back is small and mostly breaks on the shoal, and a scatterer must not change the sea upstream of
  // it. The parabolic models of the mild-slope equation drop the back-scattered wave for the same
  // reason. A reflected ray sets out from its wall, so it is held to its own direction there.
  static bool turned_back(const Ray& r) noexcept { return r.cos_t * r.home_x + r.sin_t * r.home_y < 0.0; }

  bool live_on_step(const Ray& r) const noexcept { return r.alive && r.joined; }

  const Scene& scene_;
  const DwtSettings& set_;
  Bathymetry floor_;
  std::size_t train_index_ = 0;
  const WaveTrain& train_;
  ThreadPool* pool_ = nullptr;  // a second lane, side_'s; lane 0 is the caller's, main_
  double h_min_ = 0.0, path_max_ = 0.0;
  Medium medium_{};
  Front front_{};
  std::vector<Capsule> capsules_;
  Domain walls_box_{inf, inf, -inf, -inf};  // holds every capsule (empty without walls)
  std::vector<Ray> rays_;
  std::vector<std::int32_t> order_, merged_;
  std::vector<Pending> pending_;
  std::int32_t step_ = 0;  // the wavefront being processed
  std::vector<double> pair_sigma_;
  std::vector<std::uint8_t> pair_real_;
  Lane main_;  // the sweep's own
  Lane side_;  // the pool's second lane's, merged into main_ after each shared pass
  std::int64_t first_step_ = 0;
  double uniform_a_break_ = 0.0;  // breaking_limit() of a uniform floor
  bool reflected_ = false;  // tracing a reflected wave (seeded on walls, not from the entry front)
  // The parabolic model marches this train's field: its incident rays only seed the carrier and the
  // walls' reflections, and insertion stops at marched_budget_ rays, which is not a truncation
  // (docs/physics.md 10.6).
  bool marched_ = false;
  std::size_t marched_budget_ = 0;
};

}  // namespace houle::detail
