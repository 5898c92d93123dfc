// Dynamic Wave Tracing: the wavefront sweep (see wave_rays.hpp for the method and its choices).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "houle/runtime/bulk_memory.hpp"
#include "houle/runtime/thread_pool.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/wave_rays.hpp"
#include "clip_line.hpp"
#include "ray_step.hpp"
#include "ray_walls.hpp"
#include "sommerfeld_tabulated.hpp"

namespace houle {
namespace detail {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double fan_spacing = pi / 8.0;   // rad between a fan's first rays (refined by insertion)
constexpr int max_insertion_passes = 16;   // per step; each pass halves the widest tube
// A front this large shares pass A between two lanes where rays curve: a curved step (RK4 with
// depth lookups, a few thousand instructions) far outweighs moving the ray's state between cores and
// back, which a straight step (a few dozen) does not (Fig. 4 on two lanes: 8.1 ms shared, 5.9 ms
// unshared).
constexpr std::size_t shared_pass_min_rays = 64;
constexpr std::size_t shared_chunk_rays = 16;  // what a lane takes at a time

// ---- The train's entry front, shared by dwt_bound and the tracer -------------------------------

struct Entry {
  double x = 0.0, y = 0.0;  // where the ray enters the domain, m
  double phi = 0.0;         // rad, k_entry * distance from the upstream wavefront
  double tau = 0.0;         // s
  double theta = 0.0;       // rad, direction of travel
  double amplitude = 0.0;   // m, a_geo at the entry point
  LocalWave wave{};
  bool water = false;       // false: the entry point is land (or shallower than h_min)
};

struct Front {
  double omega = 0.0, k0 = 0.0, l0 = 0.0;
  double dx = 1.0, dy = 0.0;   // direction of travel
  double h_min = 0.0;
  double dphi = 0.0;           // phase step
  double k_ref = 0.0;
  std::vector<Entry> entries;  // in order across the front (increasing to the left)
};

Medium make_medium(const Scene& scene, const Bathymetry& floor, double omega, double h_min) {
  Medium m;
  m.floor = &floor;
  m.omega = omega;
  m.k0 = deep_water_wavenumber(omega);
  m.h_eval_min = 0.5 * h_min;
  m.uniform = floor.uniform();
  if (m.uniform) m.uniform_wave = wave_from_depth(m, scene.floor.base.depth);
  m.ds_max = 0.25 * floor.length_scale();
  return m;
}

Front make_front(const Scene& scene, std::size_t train, const DwtSettings& set, const Medium& medium) {
  Front f;
  const WaveTrain& t = scene.trains[train];
  f.omega = train_omega(t);
  f.k0 = deep_water_wavenumber(f.omega);
  f.l0 = two_pi / f.k0;
  const Point2 dir = train_direction(t);
  f.dx = dir.x;
  f.dy = dir.y;
  f.h_min = std::max(set.min_depth, set.min_depth_wavelengths * f.l0);
  const double lx = -f.dy, ly = f.dx;  // left of the direction of travel
  const Domain& d = scene.domain;
  double a_min = std::numeric_limits<double>::infinity(), c_lo = a_min, c_hi = -a_min;
  for (double x : {d.x_min, d.x_max}) {
    for (double y : {d.y_min, d.y_max}) {
      a_min = std::min(a_min, x * f.dx + y * f.dy);
      c_lo = std::min(c_lo, x * lx + y * ly);
      c_hi = std::max(c_hi, x * lx + y * ly);
    }
  }
  double width = c_hi - c_lo;
  if (set.front_width > 0.0 && set.front_width < width) {
    const double mid = 0.5 * (c_lo + c_hi);
    c_lo = mid - 0.5 * set.front_width;
    width = set.front_width;
  }
  // Automatic count: spacing strictly below b_max, so a flat bottom needs no insertion at all.
  const std::size_t n = set.initial_rays > 0
                            ? set.initial_rays
                            : std::max<std::size_t>(2, std::size_t(std::floor(width / set.insertion_distance)) + 1);
  f.entries.resize(n);
  f.k_ref = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    // Rays centred in n equal strips of the front, so none runs exactly along a domain edge.
    const double c = c_lo + (double(i) + 0.5) * width / double(n);
    const double px = a_min * f.dx + c * lx, py = a_min * f.dy + c * ly;
    double t0 = 0.0, t1 = 0.0;
    Entry& e = f.entries[i];
    if (!clip_line(d, px, py, f.dx, f.dy, t0, t1)) continue;
    e.x = px + t0 * f.dx;
    e.y = py + t0 * f.dy;
    const double h = medium.floor->depth(e.x, e.y);
    if (!(h > f.h_min)) continue;
    e.wave = wave_at(medium, e.x, e.y);
    e.water = true;
    e.phi = e.wave.k * t0;
    e.tau = t0 / e.wave.cg;
    e.theta = std::atan2(f.dy, f.dx);
    e.amplitude = t.amplitude * e.wave.ks;
    f.k_ref = std::min(f.k_ref, e.wave.k);
  }
  if (std::isfinite(f.k_ref)) f.dphi = f.k_ref * set.step;
  return f;
}

double path_limit(const Domain& d) noexcept { return 4.0 * ((d.x_max - d.x_min) + (d.y_max - d.y_min)); }

double dist(double x, double y) noexcept { return std::sqrt(x * x + y * y); }  // no need for hypot's range care

// ---- Diffraction coefficients ---------------------------------------------------------------------

// K' of one of the paper's models at r/L, theta in the breakwater frame (the exact model is
// evaluated from its Fresnel arguments in the tracer: TrainTracer::k_factor).
double coefficient(DiffractionModel model, double r_over_l, double theta, double theta0, double alpha) {
  const auto d = diffraction(model, r_over_l, theta, theta0, alpha);
  return d.ok() ? d->K : 1.0;
}

// K' varies over half a wavelength or more along a ray (faster near the pierhead), so it is computed
// exactly at knots along each ray at most knot_spacing() apart and interpolated in between.
// Undiffracted samples take the incident-only coefficient where v (docs/physics.md 4.4, pi/2 convention)
// is below band_end, blended to 1 from band_start.
constexpr double band_start = 4.0, band_end = 8.0;

// A knot whose exact K' is left to the gather (k_exact < 0 never holds a coefficient).
constexpr double pending_knot = -1.0;
bool knot_pending(double k_exact) noexcept { return !(k_exact >= 0.0); }  // NaN at run ends too

// ---- The tracer --------------------------------------------------------------------------------

// One sample as the sweep builds it. Samples with a diffraction coefficient hold a_geo in
// `amplitude`, their breaking limit in a_break and, at knots, the exact K' in k_exact (pending_knot
// until it is computed, NaN elsewhere); K' is applied after the sweep.
struct StagedSample {
  double x, y, theta, k, amplitude, phase, time, a_break, k_exact;
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
  std::size_t wall_rays = 0;  // rays flagged hit_wall
  double widest = 0.0;        // the largest pair_sigma_ of a real pair on this wavefront
  bool any_alive = false;
  bool truncated = false;
  std::vector<double> k_scratch, a_scratch;  // gather(): one ray's k_exact and a_break
  std::vector<double> path_scratch;           // apply_diffraction(): path lengths along a run
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
  bool fresh = false;            // born complete on this step (fans, insertions): nothing to update
  bool tube_crossed = false;
  bool has_knot = false;         // knot_* hold the last knot along this ray
  std::uint8_t flags = 0;
  std::int32_t family = -1;      // fan index, or -1 for the incident wave
  std::int32_t crossed_with = -1;  // this step: the next ray it is found crossed with
  double a_geo = 0.0;            // m, amplitude from shoaling and tube width (no K', capped)
  double a_prev = 0.0, cg_prev = 0.0;  // at the previous sample
  double width_ratio = 1.0;      // b_prev / b over the last full step (for a final partial step)
  double clear = 0.0;            // m of path from st free of walls and the domain's edge (chord_event)
  std::int32_t tube_next = -1;   // the tube to the next ray in order, as of the last completed step
  // Line 2: that tube, the samples, the last knot (path length s and spacing to the next).
  double tube_sigma = 0.0;       // perpendicular spacing, m
  double tube_b = 0.0;           // width used for amplitude (sigma, or sigma / d in a fan)
  StagedSample* latest = nullptr;  // in samples; null before the first (or if the cap refused it)
  ChunkList samples;             // in a lane's SampleStore: appended to on every step
  double knot_s = 0.0, knot_gap = 0.0;
  // Lines 3-4: the wave at st (its hot fields first; aligned where pointers are 4 bytes).
  alignas(64) LocalWave w{};
  // The last knot's K' (NaN while pending: then knot_sample holds it, to be computed in the gather
  // unless a cap needs it first).
  double knot_k = 1.0;
  StagedSample* knot_sample = nullptr;
  // Cold: ends, lineage.
  std::uint32_t wall = 0;        // the wall it hit (when hit_wall)
  double hit_x = 0.0, hit_y = 0.0;
  double theta0 = 0.0;           // direction at birth
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
static_assert(offsetof(Ray, alive) == 64 && offsetof(Ray, tube_sigma) == 128 && offsetof(Ray, w) == 192,
              "Ray's hot fields are in its first four lines");

struct Fan {
  PierheadSite site{};
  BreakwaterFrame frame{};
  double phi_m = 0.0, tau_m = 0.0;  // incident phase and time at M
  double a_m = 0.0;                 // incident amplitude at M
  LocalWave wave_m{};
  double ox = 0.0, oy = 0.0;        // start of the fan's rays
  double phi_o = 0.0, tau_o = 0.0;
  double theta0 = 0.0;              // incidence in the breakwater frame
  double v_scale = 0.0;             // sqrt(4 k / pi): v = v_scale sqrt(r) cos((theta - theta0) / 2)
  double d0x = 0.0, d0y = 0.0;      // world unit vector at angle theta0 in the frame (towards the waves' origin)
  double cos_theta0 = 1.0, sin_theta0 = 0.0;
  double cos_half_theta0 = 1.0, sin_half_theta0 = 0.0;
};

enum class Stop : std::uint8_t { none, wall, domain, shore, turned };

// Only rays that end on a wall, with samples, and are not DIFFRACTED seed a reflected wave.
bool seeds_reflection(std::uint8_t flags, std::size_t samples) noexcept {
  return (flags & ray_flag::hit_wall) && !(flags & ray_flag::diffracted) && samples > 0;
}

// Where a ray ended, if it seeds the reflected wave: its last sample, with its final amplitude.
struct RayEnd {
  bool on_wall = false;
  double x = 0.0, y = 0.0, theta = 0.0, phase = 0.0, time = 0.0, amplitude = 0.0;
};

// The same from a train's output.
std::vector<RayEnd> ray_ends(const WaveRays& in) {
  std::vector<RayEnd> ends(in.ray_count());
  for (std::size_t q = 0; q < in.ray_count(); ++q) {
    const std::size_t end = in.sample_begin[q + 1];
    if (!seeds_reflection(in.flags[q], end - in.sample_begin[q])) continue;
    const std::size_t s = end - 1;
    ends[q] = RayEnd{true, in.x[s], in.y[s], in.theta[s], in.phase[s], in.time[s], in.amplitude[s]};
  }
  return ends;
}

class TrainTracer {
 public:
  // The incident train, from its entry front, on the caller's thread and the lanes of `pool` (none,
  // or a pool of two: see train_pool()).
  TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, ThreadPool* pool)
      : scene_(scene), set_(set), floor_(scene.floor), train_index_(train), train_(scene.trains[train]), pool_(pool) {
    init_medium();
    front_ = make_front(scene, train, set, medium_);
    set_step(front_.dphi);
    if (set.diffraction) sites_ = pierhead_sites(scene, floor_, h_min_);
    site_used_.assign(sites_.size(), false);
    sites_left_ = sites_.size();
    if (set.diffraction_model == DiffractionModel::exact) {
      // Where a_geo times this bound is within the breaking limit, no cap can bind and the sweep
      // needs no K' (finalize). A fan's K' has two terms; a lit-band sample's is a product of one
      // blend of a term towards 1 per fan.
      double alpha = 0.0;
      for (const Wall& w : scene.walls) alpha = std::max(alpha, w.reflection);
      k_bound_ = std::max(sommerfeld_term_bound * (1.0 + alpha),
                          std::pow(sommerfeld_term_bound, double(sites_.size())));
    }
  }
  // The train's reflected wave, seeded where its rays ended on reflecting walls (ray_ends(), with the
  // incident wave's omega, direction of entry and phase step).
  TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, const std::vector<RayEnd>& ends, double omega,
              double dx, double dy, double dphi, ThreadPool* pool)
      : scene_(scene), set_(set), floor_(scene.floor), train_index_(train), train_(scene.trains[train]), pool_(pool) {
    init_medium();
    reflected_ = true;
    front_ = reflected_front(ends, omega, dx, dy, dphi);
    set_step(dphi);
  }

  WaveRays run(DwtStats& stats) {
    sweep();
    return finish(stats, [] {});
  }

  // run(), and the wave reflected where this one's rays ended (trace_reflection of its result). On
  // two lanes in uniform water the reflected wave is traced on the second, beside this one's gather;
  // where rays curve, after it on both (its large fronts share their steps).
  WaveRays run_reflecting(DwtStats& stats, WaveRays& reflected, DwtStats& reflected_stats) {
    sweep();
    const std::vector<RayEnd> ends = ray_ends();
    auto trace = [&](ThreadPool* pool) {
      TrainTracer r(scene_, train_index_, set_, ends, medium_.omega, front_.dx, front_.dy, front_.dphi, pool);
      reflected = r.run(reflected_stats);
      reflected_stats.reflected_rays = reflected_stats.rays;
    };
    if (medium_.uniform) return finish(stats, [&] { trace(nullptr); });
    WaveRays out = finish(stats, [] {});
    trace(pool_);
    return out;
  }

  // Where every ray ended, in output order (after the sweep): what a reflected wave starts from.
  std::vector<RayEnd> ray_ends() {
    std::vector<RayEnd> ends(order_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) {
      Ray& r = rays_[std::size_t(order_[i])];
      if (!seeds_reflection(r.flags, r.samples.count)) continue;
      StagedSample& s = r.samples.last->at[(r.samples.count - 1) % SampleChunk::size];
      double a = s.amplitude;
      if (s.flags & sample_flag::diffraction) {
        // As apply_diffraction will have it: exact K' at the end of a run (kept for it).
        if (knot_pending(s.k_exact)) s.k_exact = k_factor(main_, r.family, s.x, s.y, s.phase);
        a = std::min(a * s.k_exact, s.a_break);
      }
      ends[i] = RayEnd{true, s.x, s.y, s.theta, s.phase, s.time, a};
    }
    return ends;
  }

 private:
  // The train's rays, all ended, in order_ as they will be output.
  void sweep() {
    if (!(front_.dphi > 0.0)) return;  // the whole front is on land
    main_.samples.reserve(std::min<std::size_t>(set_.max_samples, estimate_samples()));
    if (pool_) side_.samples.reserve(std::min<std::size_t>(set_.max_samples, estimate_samples()) / 2);
    rays_.reserve(std::min<std::size_t>(set_.max_rays, 4 * front_.entries.size() + 64));

    start_front();
    std::int64_t j = first_step_;
    const std::int64_t last_step = first_step_ + std::int64_t(path_max_ * max_k() / front_.dphi) + 2;
    while (main_.any_alive && !main_.truncated && j <= last_step) {
      step(std::int32_t(j));
      ++main_.stats.steps;
      if (j % 8 == 0) drop_inert_rays();  // dead rays pile up slowly: a pass now and then keeps up
      ++j;
    }
    if (main_.any_alive) {
      // A cap stopped the sweep: whatever is still running ends here.
      main_.truncated = true;
      for (Ray& r : rays_) {
        if (r.alive) r.alive = false, r.flags |= ray_flag::dead | ray_flag::truncated;
      }
    }
    // The dropped rays back in place.
    merged_.clear();
    for (std::int32_t id : order_) {
      merged_.push_back(id);
      for (std::int32_t d = rays_[std::size_t(id)].dropped_first; d >= 0; d = rays_[std::size_t(d)].dropped_next) {
        merged_.push_back(d);
      }
    }
    order_.swap(merged_);
  }
  // ---- setup ----

  void init_medium() {
    const double omega = train_omega(train_);
    const double l0 = two_pi / deep_water_wavenumber(omega);
    h_min_ = std::max(set_.min_depth, set_.min_depth_wavelengths * l0);
    medium_ = make_medium(scene_, floor_, omega, h_min_);
    capsules_ = wall_capsules(scene_.walls);
    for (const Capsule& c : capsules_) {
      walls_box_.x_min = std::min(walls_box_.x_min, std::min(c.ax, c.bx) - c.radius);
      walls_box_.x_max = std::max(walls_box_.x_max, std::max(c.ax, c.bx) + c.radius);
      walls_box_.y_min = std::min(walls_box_.y_min, std::min(c.ay, c.by) - c.radius);
      walls_box_.y_max = std::max(walls_box_.y_max, std::max(c.ay, c.by) + c.radius);
    }
    path_max_ = path_limit(scene_.domain);
  }

  void set_step(double dphi) noexcept {
    if (!medium_.uniform) return;
    uniform_a_break_ = breaking_limit(medium_.uniform_wave);
    medium_.step_dphi = dphi;
    medium_.step_ds = dphi / medium_.uniform_wave.k;
    medium_.step_dtau = medium_.step_ds / medium_.uniform_wave.cg;
  }

  // Seeds of the reflected wave: the end points of `incident`'s undiffracted rays that hit a wall
  // with alpha > 0, in reverse order (the mirror image reverses left and right), mirrored about the
  // wall's normal there, with amplitude alpha A and the incident phase and time (phase continuous).
  // A cut (an entry on "land": a dead ray with no samples) separates seeds whose incident rays were
  // not neighbours on the same wall, so no tube joins them.
  Front reflected_front(const std::vector<RayEnd>& ends, double omega, double dx, double dy, double dphi) const {
    Front f;
    f.omega = omega;
    f.k0 = deep_water_wavenumber(omega);
    f.l0 = two_pi / f.k0;
    f.dx = dx;
    f.dy = dy;
    f.h_min = h_min_;
    f.dphi = dphi;
    f.k_ref = dphi / set_.step;
    std::int64_t previous_wall = -1;  // wall of the last seed, -1 after a cut
    for (std::size_t q = ends.size(); q-- > 0;) {
      const RayEnd& end = ends[q];
      std::uint32_t wall = 0;
      Entry e;
      double nx = 0.0, ny = 0.0;
      if (end.on_wall) {
        e.x = end.x;
        e.y = end.y;
        e.water = wall_of(e.x, e.y, wall) && scene_.walls[wall].reflection > 0.0 && end.amplitude > 0.0 &&
                  wall_normal(capsules_, wall, e.x, e.y, nx, ny);
        if (e.water) {
          const double tx = std::cos(end.theta), ty = std::sin(end.theta);
          const double dn = tx * nx + ty * ny;
          e.theta = std::atan2(ty - 2.0 * dn * ny, tx - 2.0 * dn * nx);
          e.phi = end.phase;
          e.tau = end.time;
          e.amplitude = scene_.walls[wall].reflection * end.amplitude;
          e.wave = wave_at(medium_, e.x, e.y);
        }
      }
      if (!e.water) {
        if (previous_wall >= 0) f.entries.push_back(Entry{});
        previous_wall = -1;
        continue;
      }
      if (previous_wall >= 0 && previous_wall != std::int64_t(wall)) f.entries.push_back(Entry{});
      f.entries.push_back(e);
      previous_wall = wall;
    }
    return f;
  }

  // The wall whose surface (x, y) lies on: the nearest capsule.
  bool wall_of(double x, double y, std::uint32_t& wall) const noexcept {
    double best = std::numeric_limits<double>::infinity();
    for (const Capsule& c : capsules_) {
      const double ex = c.bx - c.ax, ey = c.by - c.ay, len2 = ex * ex + ey * ey;
      const double t = len2 > 0.0 ? std::clamp(((x - c.ax) * ex + (y - c.ay) * ey) / len2, 0.0, 1.0) : 0.0;
      const double d = std::fabs(dist(x - c.ax - t * ex, y - c.ay - t * ey) - c.radius);
      if (d < best) best = d, wall = c.wall;
    }
    return best < 1e-6;
  }

  double max_k() const noexcept {
    // The shortest waves are at h_min: no ray has more phase per metre.
    return wave_from_depth(medium_, h_min_).k;
  }

  std::size_t estimate_samples() const noexcept {
    const Domain& d = scene_.domain;
    const double across = dist(d.x_max - d.x_min, d.y_max - d.y_min);
    const double per_ray = across / set_.step + 2.0;
    return std::size_t(4.0 * double(front_.entries.size()) * per_ray) + 1024;
  }

  void start_front() {
    first_step_ = std::numeric_limits<std::int64_t>::max();
    for (const Entry& e : front_.entries) {
      const std::int32_t id = std::int32_t(rays_.size());
      rays_.emplace_back();
      Ray& r = rays_.back();
      order_.push_back(id);
      ++main_.stats.initial_rays;
      ++main_.stats.rays;
      if (!e.water) {
        // Enters on land (or separates two walls' reflections): a cut in the front, with no samples.
        r.alive = false;
        r.flags = reflected_ ? ray_flag::dead : ray_flag::dead | ray_flag::reached_shore;
        if (!reflected_) ++main_.stats.reached_shore;
        continue;
      }
      r.st = RayState{e.x, e.y, e.theta, e.phi, 0.0, e.tau};
      r.sync_direction();
      r.theta0 = r.st.theta;
      r.w = e.wave;
      r.a_geo = e.amplitude;
      r.cg_prev = r.w.cg;
      r.entering = true;
      main_.any_alive = true;
      first_step_ = std::min(first_step_, grid_step_at_or_after(e.phi));
      write_sample(main_, id, r.st, r.w, on_grid(e.phi) ? std::uint8_t(0) : sample_flag::off_grid);
      finalize(main_, id);
    }
    if (first_step_ == std::numeric_limits<std::int64_t>::max()) first_step_ = 0;
  }

  double grid_phase(std::int64_t j) const noexcept { return double(j) * front_.dphi; }
  bool on_grid(double phi) const noexcept { return grid_phase(std::int64_t(std::round(phi / front_.dphi))) == phi; }
  std::int64_t grid_step_at_or_after(double phi) const noexcept {
    std::int64_t j = std::int64_t(std::ceil(phi / front_.dphi));
    while (grid_phase(j) < phi) ++j;
    while (grid_phase(j - 1) >= phi) --j;
    return j;
  }

  // ---- samples ----

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
    *r.latest = StagedSample{st.x, st.y, st.theta, w.k, 0.0, st.phi, st.tau, 0.0,
                             std::numeric_limits<double>::quiet_NaN(), flags};
    ++lane.stats.samples;
  }

  // Does an undiffracted sample at (x, y) lie in some fan's lit-side band?
  bool in_band(double x, double y) const noexcept {
    for (const Fan& f : fans_) {
      // |v| = v_scale sqrt((r + p.d0) / 2), d0 the unit vector towards theta0: no atan2 needed to
      // see that a point is far from the shadow line (|v| >= band_end: outside the band either side).
      const double px = x - f.site.x, py = y - f.site.y;
      const double r = dist(px, py);
      if (f.v_scale * f.v_scale * 0.5 * (r + px * f.d0x + py * f.d0y) >= band_end * band_end) continue;
      // On the lit side cos((theta - theta0) / 2) >= 0, so that |v| is v and the point is in the band.
      if (!beyond_shadow_line(f, px, py)) return true;
    }
    return false;
  }

  // theta > pi + theta0 (breakwater_polar's angle, without its atan2): the point (px, py) from the
  // pierhead lies below the structure's line and counter-clockwise of the shadow line (direction
  // pi + theta0) in the breakwater frame.
  static bool beyond_shadow_line(const Fan& f, double px, double py) noexcept {
    const double u = px * f.frame.ux + py * f.frame.uy, v = px * f.frame.vx + py * f.frame.vy;
    return v < 0.0 && f.sin_theta0 * u - f.cos_theta0 * v > 0.0;
  }

  // The point (px, py) from fan f's pierhead in its breakwater frame: its distance r, and the
  // cosines of (theta -+ theta0) / 2, which give the Sommerfeld terms' Fresnel arguments. From
  // half-angle identities (no atan2 or cos): cos(theta / 2) = sign(v) sqrt((r + u) / 2r) and
  // sin(theta / 2) = sqrt((r - u) / 2r), each from whichever of r + u, r - u does not cancel
  // ((r + u)(r - u) = v^2). On the structure's line theta is 2 pi with `lee` (the fans' lee face),
  // else 0; at the pierhead, pi.
  struct HalfAngles {
    double r, minus, plus;
  };
  static HalfAngles half_angles(const Fan& f, double px, double py, bool lee) noexcept {
    const double u = px * f.frame.ux + py * f.frame.uy, v = px * f.frame.vx + py * f.frame.vy;
    const double r = std::sqrt(u * u + v * v);
    double c = 0.0, s = 1.0;  // cos and sin of theta / 2
    if (v == 0.0 && u > 0.0) {
      c = lee ? -1.0 : 1.0;
      s = 0.0;
    } else if (r > 0.0) {
      if (u >= 0.0) {
        c = std::sqrt((r + u) / (2.0 * r));
        s = std::fabs(v) / std::sqrt(2.0 * r * (r + u));
      } else {
        s = std::sqrt((r - u) / (2.0 * r));
        c = std::fabs(v) / std::sqrt(2.0 * r * (r - u));
      }
      if (v < 0.0) c = -c;
    }
    return {r, c * f.cos_half_theta0 + s * f.sin_half_theta0, c * f.cos_half_theta0 - s * f.sin_half_theta0};
  }

  // K' at a sample of a ray of `family` (-1: undiffracted) with phase phi. The exact model goes
  // straight to the Fresnel arguments (half_angles); the paper's models through their formulas.
  double k_factor(Lane& lane, std::int32_t family, double x, double y, double phi) {
    const bool exact = set_.diffraction_model == DiffractionModel::exact;
    if (family >= 0) {
      const Fan& f = fans_[std::size_t(family)];
      ++lane.stats.diffraction_evaluations;
      if (exact) {
        // k r with the optical distance from M (docs/physics.md 4.7): the phase gained since M.
        const double s = std::sqrt(4.0 / pi * std::max(0.0, phi - f.phi_m));
        const HalfAngles h = half_angles(f, x - f.site.x, y - f.site.y, true);
        return sommerfeld_modulus_at(s * h.minus, s * h.plus, f.site.reflection);
      }
      const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
      // Optical distance from M (docs/physics.md 4.7): the phase gained since M, in wavelengths.
      const double r_over_l = std::max(0.0, (phi - f.phi_m) / two_pi);
      // A sample exactly on the structure's line can only be on its lee face (fans start there).
      const double theta = p.kind == BreakwaterPointKind::on_structure ? two_pi : p.theta;
      return coefficient(set_.diffraction_model, r_over_l, theta, f.theta0, f.site.reflection);
    }
    double K = 1.0;
    for (const Fan& f : fans_) {
      // Undiffracted rays near a shadow line: the incident-only coefficient |G(s1)| (they carry no
      // reflected wave), blended to 1 from v = 4 to 8 so that nothing jumps at the band's edge.
      const double px = x - f.site.x, py = y - f.site.y;
      if (f.v_scale * f.v_scale * 0.5 * (dist(px, py) + px * f.d0x + py * f.d0y) >= band_end * band_end) continue;
      if (beyond_shadow_line(f, px, py)) continue;  // not this pierhead's lit side
      const HalfAngles h = half_angles(f, px, py, false);
      const double v = f.v_scale * std::sqrt(h.r) * h.minus;
      if (v >= band_end) continue;
      ++lane.stats.diffraction_evaluations;
      double kf = 0.0;
      if (exact) {
        kf = sommerfeld_modulus_at(v, 0.0, 0.0);
      } else {
        const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
        kf = coefficient(set_.diffraction_model, p.r_over_L, p.theta, f.theta0, 0.0);
      }
      const double t = std::clamp((v - band_start) / (band_end - band_start), 0.0, 1.0);
      K *= kf + (1.0 - kf) * (t * t * (3.0 - 2.0 * t));
    }
    return K;
  }

  // The largest amplitude the breaking caps allow: H <= gamma_b h and H <= 0.142 L tanh kh.
  double breaking_limit(const LocalWave& w) const noexcept {
    return std::min(0.5 * set_.breaker_index * w.h, 0.071 * two_pi / w.k * w.tanh_kh);
  }

  // How far along a ray K' may go between exact evaluations: a quarter wavelength, less near the
  // pierhead where K' changes faster (a third of the distance to it, at least L/64).
  double knot_spacing(std::int32_t family, double x, double y, double k) const noexcept {
    const double wavelength = two_pi / k;
    return std::clamp(distance_to_pierhead(family, x, y) / 3.0, wavelength / 64.0, wavelength / 4.0);
  }

  // Amplitude of ray id's latest sample from its a_geo, then the breaking caps H <= gamma_b h and
  // H <= 0.142 L tanh kh (the excess is dissipated from a_geo). Where a diffraction coefficient
  // applies, the caps use K' from the ray's last knot (a new knot when that is more than a knot
  // spacing back); the sample keeps a_geo and its limit, and gets interpolated K' and the caps
  // again after the sweep (apply_diffraction). A knot's exact K' is computed here only if a cap
  // could bind: otherwise the gather computes it, on both lanes when there are two.
  [[gnu::always_inline]] void finalize(Lane& lane, std::int32_t id) {
    Ray& r = rays_[std::size_t(id)];
    if (!r.latest) return;  // the sample cap refused it
    StagedSample& c = *r.latest;
    const double a_break = medium_.uniform ? uniform_a_break_ : breaking_limit(r.w);
    const double x = c.x, y = c.y;
    const bool diffracts = r.family >= 0 || (!fans_.empty() && in_band(x, y));
    double K = 1.0;
    if (diffracts) {
      c.flags |= sample_flag::diffraction;
      if (!r.has_knot || r.st.s - r.knot_s >= r.knot_gap || r.st.s < r.knot_s) {
        r.knot_k = std::numeric_limits<double>::quiet_NaN();
        r.knot_sample = &c;
        r.knot_s = r.st.s;
        r.knot_gap = knot_spacing(r.family, x, y, r.w.k);
        r.has_knot = true;
        c.k_exact = pending_knot;
      }
      c.amplitude = r.a_geo;
      c.a_break = a_break;
      if (r.a_geo * k_bound_ <= a_break) return;  // no cap can bind, whatever K' is
      if (std::isnan(r.knot_k)) {
        StagedSample& knot = *r.knot_sample;
        r.knot_k = knot.k_exact = k_factor(lane, r.family, knot.x, knot.y, knot.phase);
      }
      K = r.knot_k;
    }
    double a = r.a_geo * K;
    if (a > a_break) {
      a = a_break;
      if (K > 0.0) r.a_geo = a_break / K;
      c.flags |= sample_flag::broken;
      if (!(r.flags & ray_flag::broken)) ++lane.stats.broken_rays;
      r.flags |= ray_flag::broken;
    }
    c.amplitude = diffracts ? r.a_geo : a;
    c.a_break = a_break;
  }

  // ---- stepping ----

  // Where along the chord a -> b (0..1) the ray meets a wall, the domain's edge or the shoreline
  // (depth h_min), whichever comes first; > 1 if none. `clear` is a path length from a within which
  // the ray can meet neither a wall nor the domain's edge, kept up to date here: most chords skip
  // those tests.
  double chord_event(const RayState& a, const RayState& b, double depth_b, double& clear, Stop& why,
                     std::uint32_t& wall) const noexcept {
    why = Stop::none;
    // The path length is at least the chord's (RK4 sums the same positive weights for both).
    const double travel = b.s - a.s;
    if (travel < clear && depth_b > h_min_) {
      clear -= travel;  // most chords: inline, the rest out of line
      return 2.0;
    }
    return chord_event_near(a, b, depth_b, travel, clear, why, wall);
  }
  [[gnu::noinline]] double chord_event_near(const RayState& a, const RayState& b, double depth_b, double travel,
                                            double& clear, Stop& why, std::uint32_t& wall) const noexcept {
    double u = 2.0;
    if (travel < clear) {
      clear -= travel;
    } else {
      // Most chords are nowhere near a wall: one box test instead of one per capsule.
      const bool near_walls = std::max(a.x, b.x) >= walls_box_.x_min && std::min(a.x, b.x) <= walls_box_.x_max &&
                              std::max(a.y, b.y) >= walls_box_.y_min && std::min(a.y, b.y) <= walls_box_.y_max;
      if (near_walls) {
        const WallHit hit = first_wall_hit(capsules_, a.x, a.y, b.x, b.y);
        if (hit.hit) u = hit.u, why = Stop::wall, wall = hit.wall;
      }
      const Domain& d = scene_.domain;
      if (b.x < d.x_min || b.x > d.x_max || b.y < d.y_min || b.y > d.y_max) {
        double t0 = 0.0, t1 = 0.0;
        const double ex = clip_line(d, a.x, a.y, b.x - a.x, b.y - a.y, t0, t1) ? std::clamp(t1, 0.0, 1.0) : 0.0;
        if (ex < u) u = ex, why = Stop::domain;
      }
      clear = clearance(b.x, b.y);
    }
    if (depth_b <= h_min_) {
      // Bisection on the chord for depth = h_min (the floor is continuous).
      double lo = 0.0, hi = 1.0;
      if (floor_.depth(a.x, a.y) <= h_min_) hi = 0.0;
      for (int i = 0; i < 40 && hi - lo > 1e-12; ++i) {
        const double mid = 0.5 * (lo + hi);
        (floor_.depth(a.x + mid * (b.x - a.x), a.y + mid * (b.y - a.y)) <= h_min_ ? hi : lo) = mid;
      }
      if (hi < u) u = hi, why = Stop::shore;
    }
    return u;
  }

  // A lower bound on the distance from (x, y) to the domain's edge and to every wall (their box, by
  // the Chebyshev distance), less a margin for rounding; 0 outside the domain or inside the box.
  double clearance(double x, double y) const noexcept {
    const Domain& d = scene_.domain;
    double c = std::min(std::min(x - d.x_min, d.x_max - x), std::min(y - d.y_min, d.y_max - y));
    if (!capsules_.empty()) {
      const double dx = std::max(std::max(walls_box_.x_min - x, x - walls_box_.x_max), 0.0);
      const double dy = std::max(std::max(walls_box_.y_min - y, y - walls_box_.y_max), 0.0);
      c = std::min(c, std::max(dx, dy));
    }
    return std::max(0.0, c * (1.0 - 1e-9) - 1e-9);
  }

  // Moves ray `id` on by dphi. If it meets a wall, the domain's edge or the shoreline it stops there,
  // is flagged dead with the reason, and false is returned. Amplitudes are the caller's business.
  bool move_ray(Lane& lane, std::int32_t id, double dphi) {
    Ray& r = rays_[std::size_t(id)];
    Stop why = Stop::none;
    std::uint32_t wall = 0;
    auto stop = [&](const RayState& a, const RayState& b, double depth_b) {
      return chord_event(a, b, depth_b, r.clear, why, wall);
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
      ++lane.wall_rays;
      r.wall = wall;
      r.hit_x = r.st.x;
      r.hit_y = r.st.y;
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

  // An incident ray that refraction has turned against the train's direction of travel ends there
  // (docs/physics.md 2.6). Only a floor that changes within a wavelength turns a ray that far (round
  // an island or a steep shoal), where rays no longer describe the wave; what is scattered back is
  // small and mostly breaks on the shoal, and a scatterer must not change the sea upstream of it. The
  // parabolic models of the mild-slope equation drop the back-scattered wave for the same reason.
  // Fans spread into the lee by design and reflected waves travel back by design: both are exempt.
  bool turned_back(const Ray& r) const noexcept {
    return !reflected_ && r.family < 0 && r.cos_t * front_.dx + r.sin_t * front_.dy < 0.0;
  }

  // move_ray within the sweep: a ray that ends gets its end point as an off-grid sample, shoaled over
  // the partial step, its tube widening as over the last full step (in proportion to the phase).
  bool advance_ray(Lane& lane, std::int32_t id, double dphi) {
    const double phi0 = rays_[std::size_t(id)].st.phi;
    if (move_ray(lane, id, dphi)) return true;
    Ray& r = rays_[std::size_t(id)];
    const double u = std::clamp((r.st.phi - phi0) / front_.dphi, 0.0, 1.0);
    r.a_geo *= std::sqrt(r.cg_prev / r.w.cg * std::pow(r.width_ratio, u));
    const std::uint8_t crossed = (r.flags & ray_flag::crossed) ? sample_flag::crossed : std::uint8_t(0);
    write_sample(lane, id, r.st, r.w, std::uint8_t(sample_flag::off_grid | crossed));
    finalize(lane, id);
    return false;
  }

  // The passes over the wavefront, fused where nothing in between can change their result, so that a
  // step visits each ray's state fewer times.
  void step(std::int32_t j) {
    step_ = j;
    const double phi_j = grid_phase(j);
    main_.any_alive = false;
    // A: advance every live ray to this wavefront, and measure each pair once both are there. On a
    // large front of curving rays two lanes share the chunks of order_, unless the sample cap could
    // be reached on this step (where the rays refused would depend on the lanes' timing); the pairs
    // across chunks are measured after.
    begin_tubes();
    const std::size_t n = order_.size();
    if (pool_ && !medium_.uniform && n >= shared_pass_min_rays && main_.stats.samples + n <= set_.max_samples) {
      pool_->for_ranges(n, shared_chunk_rays, [&](std::size_t lo, std::size_t hi, unsigned lane) {
        advance_front(lane == 0 ? main_ : side_, j, lo, hi);
      });
      for (std::size_t i = shared_chunk_rays; i < n; i += shared_chunk_rays) {
        Pose pa{}, pb{};
        if (pose_on_step(rays_[std::size_t(order_[i - 1])], phi_j, pa) && pose_on_step(rays_[std::size_t(order_[i])], phi_j, pb)) {
          main_.widest = std::max(main_.widest, measure_pair(i - 1, pa, pb));
        }
      }
      merge_side_lane();
      ++main_.stats.shared_steps;
    } else {
      advance_front(main_, j, 0, n);
    }
    if (main_.truncated) return;
    // B: fans at pierheads the front has just passed (each site spawns once); they change order_.
    if (sites_left_ > 0 && main_.wall_rays > 0 && spawn_fans(j)) measure_tubes();  // a fan needs a ray that ended on a wall
    // C: tubes, caustics and amplitudes on this wavefront. Without insertion (D) the tubes of E are
    // those of C, and E rides along.
    const bool inserts = main_.widest > set_.insertion_distance;
    update_amplitudes(!inserts);
    if (!inserts) return;
    // D: insertion where live neighbours are too far apart.
    for (int pass = 0; pass < max_insertion_passes && insert_rays(j); ++pass) measure_tubes();
    // E: remember this wavefront's tubes for the next step; mark sound tubes for tessellation.
    for (std::size_t i = 0; i < order_.size(); ++i) record_tube(i);
  }

  // Pass A over order_[lo, hi). The pairs are measured in a loop of their own, whose iterations are
  // independent: the long sqrt and division of each spacing then overlap (within one loop with the
  // advance they were on the critical path of every ray).
  void advance_front(Lane& lane, std::int32_t j, std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      if (i + 2 < hi) prefetch_ray(order_[i + 2]);
      advance_on_step(lane, order_[i], j);
    }
    measure_pairs(lane, lo, hi);
  }

  // order_ visits rays_ out of order, which the hardware cannot follow: the passes fetch a ray's
  // hot lines two rays ahead.
  void prefetch_ray(std::int32_t id) const noexcept {
    const auto* p = reinterpret_cast<const char*>(&rays_[std::size_t(id)]);
    for (std::size_t b = 0; b < 4 * 64; b += 64) __builtin_prefetch(p + b, 1);
  }

  void merge_side_lane() {
    main_.stats += side_.stats;
    main_.wall_rays += side_.wall_rays;
    main_.widest = std::max(main_.widest, side_.widest);
    main_.any_alive = main_.any_alive || side_.any_alive;
    main_.truncated = main_.truncated || side_.truncated;
    side_.stats = DwtStats{};
    side_.wall_rays = 0;
    side_.widest = 0.0;
    side_.any_alive = side_.truncated = false;
  }

  void advance_on_step(Lane& lane, std::int32_t id, std::int32_t j) {
    const double phi_j = grid_phase(j);
    Ray& r = rays_[std::size_t(id)];
    r.joined_now = false;
    r.fresh = false;
    r.crossed_with = -1;
    if (!r.alive) return;
    lane.any_alive = true;
    r.a_prev = r.a_geo;
    r.cg_prev = r.w.cg;
    double dphi = front_.dphi;
    if (!r.joined) {
      if (r.st.phi > phi_j) return;  // enters later
      r.joined = r.joined_now = true;
      r.entering = false;
      r.first_step = j;
      if (r.st.phi == phi_j) return;  // its start sample is on this step already
      dphi = phi_j - r.st.phi;
    }
    if (!advance_ray(lane, id, dphi)) return;
    Ray& q = rays_[std::size_t(id)];
    q.st.phi = phi_j;
    if (q.st.s > path_max_) {
      q.alive = false;
      q.flags |= ray_flag::dead | ray_flag::truncated;
      lane.truncated = true;
      return;
    }
    write_sample(lane, id, q.st, q.w, (q.flags & ray_flag::crossed) ? sample_flag::crossed : std::uint8_t(0));
  }

  bool live_on_step(const Ray& r) const noexcept { return r.alive && r.joined; }

  // Every pass of a step visits every ray in order_, and dead rays pile up in it. A dead ray between
  // two dead neighbours can take no further part: it has no tube, spawns no fan, and never gets a
  // new neighbour (rays are inserted only next to a live one). Such rays leave order_ and follow
  // their predecessor in the output.
  void drop_inert_rays() {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < order_.size(); ++i) {
      const std::int32_t id = order_[i];
      if (kept > 0 && i + 1 < order_.size() && !rays_[std::size_t(id)].alive &&
          !rays_[std::size_t(order_[kept - 1])].alive && !rays_[std::size_t(order_[i + 1])].alive) {
        follow(order_[kept - 1], id);
        continue;
      }
      order_[kept++] = id;
    }
    order_.resize(kept);
  }

  // Ray d (and the rays that follow it) now follow ray p's followers in the output.
  void follow(std::int32_t p, std::int32_t d) {
    Ray& rd = rays_[std::size_t(d)];
    const std::int32_t tail = rd.dropped_last >= 0 ? rd.dropped_last : d;
    rd.dropped_next = rd.dropped_first;
    rd.dropped_first = rd.dropped_last = -1;
    Ray& rp = rays_[std::size_t(p)];
    (rp.dropped_last >= 0 ? rays_[std::size_t(rp.dropped_last)].dropped_next : rp.dropped_first) = d;
    rp.dropped_last = tail;
  }

  // Where a ray is on the current wavefront: its state if it is live there, or for an initial ray
  // still outside the domain the point of its straight entry path with that phase (the outside is
  // uniform water, where the wavefront is straight). False for anything else.
  struct Pose {
    double x, y, cos_t, sin_t;
  };
  // A neighbour pair's tube over the last step: widths then and now where it persisted soundly.
  struct PairTube {
    double b_prev = 0.0, b_now = 0.0;
    bool sound = false, crossed = false;
  };
  bool pose_on_step(const Ray& r, double phi_j, Pose& p) const noexcept {
    if (live_on_step(r)) {
      p = Pose{r.st.x, r.st.y, r.cos_t, r.sin_t};
      return true;
    }
    if (!r.alive || !r.entering || r.st.phi < phi_j) return false;
    const double back = (r.st.phi - phi_j) / r.w.k;
    p = Pose{r.st.x - r.cos_t * back, r.st.y - r.sin_t * back, r.cos_t, r.sin_t};
    return true;
  }

  // Perpendicular spacing of b from a across their mean direction (> 0 when b is to a's left).
  static double spacing(const Pose& a, const Pose& b) noexcept {
    const double mx = a.cos_t + b.cos_t, my = a.sin_t + b.sin_t;
    const double n2 = mx * mx + my * my;
    if (!(n2 > 1e-24)) return -1.0;  // opposite directions: treat as crossed
    return ((b.x - a.x) * -my + (b.y - a.y) * mx) / std::sqrt(n2);
  }

  // Tube width used for amplitude: sigma, or sigma / d (distance from the pierhead) within a fan.
  double tube_width(std::int32_t family, const Pose& a, const Pose& b, double sigma) const noexcept {
    if (family < 0) return sigma;
    // Distances from where the fan's rays start (the lee corner on a thick wall), so that a radial
    // fan on a flat bottom has sigma / d constant exactly.
    const Fan& f = fans_[std::size_t(family)];
    const double ax = a.x - f.ox, ay = a.y - f.oy, bx = b.x - f.ox, by = b.y - f.oy;
    const double d = 0.5 * (std::sqrt(ax * ax + ay * ay) + std::sqrt(bx * bx + by * by));
    return d > 0.0 ? sigma / d : 0.0;
  }

  // Spacing and tube width of every neighbour pair in order_ that has a pose on this wavefront (NaN
  // otherwise); pair_real_ marks pairs of two live rays (only those may insert or be tessellated).
  void measure_tubes() {
    begin_tubes();
    measure_pairs(main_, 0, order_.size());
  }

  // The pairs within order_[lo, hi). The widest is kept in a register: through lane.widest, which
  // the pair arrays' stores might alias, every pair's sqrt and division waited for the last one's.
  void measure_pairs(Lane& lane, std::size_t lo, std::size_t hi) {
    if (lo >= hi) return;
    const double phi_j = grid_phase(step_);
    Pose pa{}, pb{};
    bool has_a = pose_on_step(rays_[std::size_t(order_[lo])], phi_j, pa);
    double widest = lane.widest;
    for (std::size_t i = lo + 1; i < hi; ++i) {
      const bool has_b = pose_on_step(rays_[std::size_t(order_[i])], phi_j, pb);
      if (has_a && has_b) widest = std::max(widest, measure_pair(i - 1, pa, pb));
      pa = pb;
      has_a = has_b;
    }
    lane.widest = widest;
  }

  // No pair measured yet on this wavefront.
  void begin_tubes() {
    const std::size_t n = order_.size();
    pair_sigma_.assign(n, std::numeric_limits<double>::quiet_NaN());
    pair_width_.assign(n, 0.0);
    pair_real_.assign(n, 0);
    main_.widest = 0.0;
  }

  // Pair (i, i + 1), whose rays have poses pa and pb on this wavefront.
  // Returns its spacing if it is real, else 0 (what the widest real spacing starts from).
  double measure_pair(std::size_t i, const Pose& pa, const Pose& pb) {
    const Ray& a = rays_[std::size_t(order_[i])];
    const Ray& b = rays_[std::size_t(order_[i + 1])];
    const double sigma = spacing(pa, pb);
    const bool real = live_on_step(a) && live_on_step(b);
    pair_sigma_[i] = sigma;
    pair_width_[i] = tube_width(a.family, pa, pb, sigma);
    pair_real_[i] = real;
    return real ? sigma : 0.0;
  }

  // Tubes, caustics and amplitudes on this wavefront in one pass: pair (i, i + 1) is classified just
  // before ray i, which needs it and pair (i - 1, i); with `record`, ray i's tube is recorded after.
  void update_amplitudes(bool record) {
    const std::size_t n = order_.size();
    PairTube left{};
    for (std::size_t i = 0; i < n; ++i) {
      if (i + 2 < n) prefetch_ray(order_[i + 2]);
      const PairTube right = i + 1 < n ? classify_pair(i) : PairTube{};
      const std::int32_t id = order_[i];
      Ray& r = rays_[std::size_t(id)];
      if (live_on_step(r) && !r.fresh) {
        double w_prev = 0.0, w_now = 0.0;
        int tubes = 0;
        for (const PairTube& t : {left, right}) {
          if (t.sound) w_prev += t.b_prev, w_now += t.b_now, ++tubes;
        }
        // Energy flux A^2 Cg b is constant along the tube (docs/physics.md 2.3).
        const double ratio = tubes > 0 ? w_prev / w_now : 1.0;
        if (!r.joined_now) r.width_ratio = ratio;
        r.a_geo = r.a_prev * std::sqrt(r.cg_prev / r.w.cg * ratio);
        // Caustic cap: Kr <= Kr_max (docs/physics.md 2.5, cap 2).
        r.a_geo = std::min(r.a_geo, set_.max_refraction_coefficient * train_.amplitude * r.w.ks);
        if ((left.crossed || right.crossed) && r.latest) r.latest->flags |= sample_flag::crossed;
        finalize(main_, id);
      }
      if (record) record_tube(i);
      left = right;
    }
  }

  // The tube between order_[i] and order_[i + 1] over the last step; flags a caustic where the two
  // have just swapped sides.
  PairTube classify_pair(std::size_t i) {
    PairTube t{};
    const double sigma = pair_sigma_[i];
    if (std::isnan(sigma)) return t;
    Ray& a = rays_[std::size_t(order_[i])];
    Ray& b = rays_[std::size_t(order_[i + 1])];
    const bool persisted = a.tube_next == order_[i + 1];
    bool crossed = sigma <= 0.0;
    if (persisted) {
      if (!a.tube_crossed && a.tube_sigma > 0.0 && sigma <= 0.0) {
        // Neighbours swapped sides: a caustic between them (docs/physics.md 2.5).
        ++main_.stats.crossings;
        a.flags |= ray_flag::crossed;
        b.flags |= ray_flag::crossed;
      }
      crossed = a.tube_crossed || sigma <= 0.0;
    }
    if (crossed) {
      a.crossed_with = order_[i + 1];
      t.crossed = true;
      return t;
    }
    if (!persisted || a.family != b.family || a.fresh || b.fresh) return t;
    const double width = pair_width_[i];
    if (!(a.tube_b > 0.0) || !(width > 0.0)) return t;
    return PairTube{a.tube_b, width, true, false};
  }

  // ---- diffraction fans ----

  // True if a fan was inserted into order_.
  bool spawn_fans(std::int32_t j) {
    for (std::size_t i = 0; i + 1 < order_.size(); ++i) {
      for (int side : {+1, -1}) {
        // side +1: the dead ray is the next in order (to the live ray's left); -1: the previous.
        const std::int32_t live_id = side > 0 ? order_[i] : order_[i + 1];
        const std::int32_t dead_id = side > 0 ? order_[i + 1] : order_[i];
        const Ray& b = rays_[std::size_t(live_id)];
        const Ray& a = rays_[std::size_t(dead_id)];
        if (!live_on_step(b) || b.fresh || a.alive || !(a.flags & ray_flag::hit_wall)) continue;
        for (std::size_t s = 0; s < sites_.size(); ++s) {
          if (site_used_[s] || sites_[s].wall != a.wall) continue;
          if (try_spawn(s, live_id, dead_id, side, i, j)) break;
        }
      }
    }
    if (pending_.empty()) return false;
    apply_insertions();
    return true;
  }

  // [GL98] 2.2.1: ray `dead_id` ended on the wall of site s and its live neighbour `live_id` (R1)
  // has passed the site's pierhead M: a fan of DIFFRACTED rays from R1's direction to the wall's.
  bool try_spawn(std::size_t s, std::int32_t live_id, std::int32_t dead_id, int side, std::size_t pos, std::int32_t j) {
    const PierheadSite site = sites_[s];
    // Copies: rays_ grows while the fan is traced.
    const Ray b = rays_[std::size_t(live_id)];
    const Ray a = rays_[std::size_t(dead_id)];
    const double dx = b.cos_t, dy = b.sin_t;
    const double nx = -dy, ny = dx;  // b's left
    const double mx = site.x - b.st.x, my = site.y - b.st.y;
    const double lateral = side * (mx * nx + my * ny);  // > 0: M is on the dead ray's side
    const double hit_lateral = side * ((a.hit_x - b.st.x) * nx + (a.hit_y - b.st.y) * ny);
    if (!(lateral > 0.0) || lateral > hit_lateral + site.radius + 1e-9) return false;
    if (!(side * (site.ux * nx + site.uy * ny) > 0.0)) return false;  // the wall runs towards the dead ray
    if (mx * dx + my * dy > 0.0) return false;                          // R1 has not passed M yet
    // The fan sweeps from R1's direction towards the wall, through the shadow.
    const double theta_wall = std::atan2(site.uy, site.ux);
    double span = side * (theta_wall - b.st.theta);
    span -= two_pi * std::floor(span / two_pi);
    if (!(span > 1e-6 && span < pi)) return false;

    Fan f;
    f.site = site;
    f.wave_m = wave_at(medium_, site.x, site.y);
    const auto frame = make_breakwater_frame(Breakwater{site.x, site.y, site.ux, site.uy}, dx, dy, two_pi / f.wave_m.k);
    if (!frame.ok()) return false;
    f.frame = frame.value();
    f.theta0 = f.frame.theta0;
    f.v_scale = std::sqrt(4.0 * f.wave_m.k / pi);
    f.cos_theta0 = std::cos(f.theta0);
    f.sin_theta0 = std::sin(f.theta0);
    f.cos_half_theta0 = std::cos(0.5 * f.theta0);
    f.sin_half_theta0 = std::sin(0.5 * f.theta0);
    f.d0x = f.cos_theta0 * f.frame.ux + f.sin_theta0 * f.frame.vx;
    f.d0y = f.cos_theta0 * f.frame.uy + f.sin_theta0 * f.frame.vy;
    const double along = mx * dx + my * dy;  // <= 0: M is behind R1's wavefront position
    f.phi_m = b.st.phi + b.w.k * along;
    f.tau_m = b.st.tau + along / b.w.cg;
    f.a_m = b.a_prev * std::sqrt(b.cg_prev / f.wave_m.cg);
    // Thick walls: the rays start on the lee corner of the tip, so the ray along the lee face grazes it.
    const double lee_x = side > 0 ? site.uy : -site.uy, lee_y = side > 0 ? -site.ux : site.ux;
    const double off = site.radius * (1.0 + 1e-9);
    f.ox = site.x + off * lee_x;
    f.oy = site.y + off * lee_y;
    f.phi_o = f.phi_m + f.wave_m.k * off;
    f.tau_o = f.tau_m + off / f.wave_m.cg;
    const std::int32_t fan_index = std::int32_t(fans_.size());
    fans_.push_back(f);
    site_used_[s] = true;
    --sites_left_;
    ++main_.stats.fans;

    const int n = std::max(1, int(std::ceil(span / fan_spacing)));
    std::vector<std::int32_t> ids;
    for (int i = 0; i <= n; ++i) {
      if (rays_.size() >= set_.max_rays) {
        ++main_.stats.insertions_refused;
        main_.truncated = true;
        break;
      }
      const double psi = b.st.theta + side * span * double(i) / double(n);
      ids.push_back(trace_diffracted(fan_index, psi, j, -1.0, -1, -1));
    }
    // Between the live ray and the dead one, the ray parallel to R1 next to R1.
    if (side < 0) std::reverse(ids.begin(), ids.end());
    pending_.push_back(Pending{pos, std::move(ids)});
    return true;
  }

  // A DIFFRACTED ray of fan `fan` from its origin with direction psi, traced up to step j. With
  // a_target >= 0 its geometric amplitude is ramped (linearly in distance) to reach a_target at j.
  std::int32_t trace_diffracted(std::int32_t fan, double psi, std::int32_t j, double a_target, std::int32_t pa,
                                std::int32_t pb) {
    const Fan f = fans_[std::size_t(fan)];
    const std::int32_t id = std::int32_t(rays_.size());
    rays_.emplace_back();
    ++main_.stats.rays;
    ++main_.stats.diffracted_rays;
    {
      Ray& r = rays_.back();
      r.family = fan;
      r.theta0 = psi;
      r.parent_a = pa;
      r.parent_b = pb;
      r.flags = ray_flag::diffracted;
      r.st = RayState{f.ox, f.oy, psi, f.phi_o, 0.0, f.tau_o};
      r.sync_direction();
      r.w = wave_at(medium_, f.ox, f.oy);
      r.fresh = true;
    }
    const double phi_j = grid_phase(j);
    // Catch-up to step j: positions first (samples are written once their amplitudes are known).
    const double phi_o = rays_.back().st.phi;
    const bool start_on_grid = on_grid(phi_o);
    catch_.clear();
    catch_.push_back(CatchUp{rays_.back().st, rays_.back().w, start_on_grid ? std::uint8_t(0) : sample_flag::off_grid});
    const std::int64_t j_start = grid_step_at_or_after(phi_o);
    const std::int64_t j_next = start_on_grid ? j_start + 1 : j_start;  // first step to move to
    bool alive = true;
    for (std::int64_t jj = j_next; jj <= j; ++jj) {
      if (!move_ray(main_, id, grid_phase(jj) - rays_[std::size_t(id)].st.phi)) {
        alive = false;
        catch_.push_back(CatchUp{rays_[std::size_t(id)].st, rays_[std::size_t(id)].w, sample_flag::off_grid});
        break;
      }
      rays_[std::size_t(id)].st.phi = grid_phase(jj);
      catch_.push_back(CatchUp{rays_[std::size_t(id)].st, rays_[std::size_t(id)].w, 0});
    }
    // Amplitudes: shoaling along the ray (a fan's tube width grows like d on a flat bottom, which
    // eq. 7 cancels), ramped linearly in distance to the parents' mean when inserting.
    Ray& r = rays_[std::size_t(id)];
    const bool reached_j = alive && catch_.back().st.phi == phi_j;
    const double d_end = dist(catch_.back().st.x - f.ox, catch_.back().st.y - f.oy);
    const double a_end_shoaled = f.a_m * std::sqrt(f.wave_m.cg / catch_.back().w.cg);
    const double ramp = a_target >= 0.0 && reached_j && a_end_shoaled > 0.0 ? a_target / a_end_shoaled - 1.0 : 0.0;
    double a = f.a_m * std::sqrt(f.wave_m.cg / catch_.front().w.cg);
    double prev_factor = 1.0;
    for (std::size_t i = 0; i < catch_.size(); ++i) {
      const CatchUp& c = catch_[i];
      if (i > 0) a *= std::sqrt(catch_[i - 1].w.cg / c.w.cg);
      const double d = dist(c.st.x - f.ox, c.st.y - f.oy);
      const double factor = 1.0 + ramp * (d_end > 0.0 ? std::min(d / d_end, 1.0) : 1.0);
      a *= factor / prev_factor;
      prev_factor = factor;
      r.st = c.st;  // finalize() reads the ray's state at the sample
      r.w = c.w;
      r.a_geo = std::min(a, set_.max_refraction_coefficient * train_.amplitude * c.w.ks);
      write_sample(main_, id, c.st, c.w, c.flags);
      finalize(main_, id);
      a = r.a_geo;  // breaking may have dissipated some
    }
    r.st = catch_.back().st;
    r.sync_direction();
    r.w = catch_.back().w;
    r.a_prev = r.a_geo;
    r.cg_prev = r.w.cg;
    r.alive = alive;
    if (!alive) return id;
    main_.any_alive = true;
    if (reached_j) {
      // On this wavefront already, complete: joins the tubes from the next step.
      r.joined = true;
      r.first_step = std::int32_t(start_on_grid ? j_start : j_next);
    } else {
      // Starts ahead of this wavefront: the sweep picks it up when the front reaches its start.
      r.fresh = false;
    }
    return id;
  }

  // ---- insertion ----

  struct Pending {
    std::size_t after;               // insert after this position in order_
    std::vector<std::int32_t> ids;   // in order
  };

  void apply_insertions() {
    std::sort(pending_.begin(), pending_.end(), [](const Pending& a, const Pending& b) { return a.after < b.after; });
    merged_.clear();
    std::size_t p = 0;
    for (std::size_t i = 0; i < order_.size(); ++i) {
      merged_.push_back(order_[i]);
      for (; p < pending_.size() && pending_[p].after == i; ++p) merged_.insert(merged_.end(), pending_[p].ids.begin(), pending_[p].ids.end());
    }
    order_.swap(merged_);
    pending_.clear();
  }

  // One pass over the wavefront: a ray between every sound live pair farther apart than b_max.
  bool insert_rays(std::int32_t j) {
    const double b_max = set_.insertion_distance;
    if (!(main_.widest > b_max)) return false;
    for (std::size_t i = 0; i + 1 < order_.size(); ++i) {
      if (!pair_real_[i] || !(pair_sigma_[i] > b_max)) continue;  // not two live rays, or close enough
      const std::int32_t ia = order_[i], ib = order_[i + 1];
      const Ray& a = rays_[std::size_t(ia)];
      const Ray& b = rays_[std::size_t(ib)];
      if (a.crossed_with == ib) continue;  // never between crossed rays (docs/physics.md 2.4)
      if (rays_.size() >= set_.max_rays) {
        ++main_.stats.insertions_refused;
        main_.truncated = true;
        continue;
      }
      std::int32_t id;
      if (a.family >= 0 && a.family == b.family) {
        // A diffracted ray from the pierhead, bisecting its parents' starting directions.
        const double psi = std::atan2(std::sin(a.theta0) + std::sin(b.theta0), std::cos(a.theta0) + std::cos(b.theta0));
        const double target = 0.5 * (a.a_geo + b.a_geo);
        id = trace_diffracted(a.family, psi, j, target, ia, ib);
      } else {
        id = insert_midpoint(ia, ib, j);
      }
      ++main_.stats.inserted_rays;
      pending_.push_back(Pending{i, {id}});
    }
    if (pending_.empty()) return false;
    apply_insertions();
    return true;
  }

  // A ray between two live neighbours on the current wavefront (docs/physics.md 2.4): midpoint, bisecting
  // direction, mean amplitude; flags only where both parents share them.
  std::int32_t insert_midpoint(std::int32_t ia, std::int32_t ib, std::int32_t j) {
    const std::int32_t id = std::int32_t(rays_.size());
    rays_.emplace_back();
    ++main_.stats.rays;
    Ray& r = rays_.back();
    const Ray& a = rays_[std::size_t(ia)];
    const Ray& b = rays_[std::size_t(ib)];
    r.parent_a = ia;
    r.parent_b = ib;
    r.family = a.family == b.family ? a.family : -1;
    r.flags = std::uint8_t(a.flags & b.flags & ray_flag::broken);
    const double x = 0.5 * (a.st.x + b.st.x), y = 0.5 * (a.st.y + b.st.y);
    const double theta = std::atan2(a.sin_t + b.sin_t, a.cos_t + b.cos_t);
    r.st = RayState{x, y, theta, grid_phase(j), 0.5 * (a.st.s + b.st.s), 0.5 * (a.st.tau + b.st.tau)};
    r.sync_direction();
    r.theta0 = theta;
    r.first_step = j;
    r.joined = true;
    r.fresh = true;
    const bool in_wall = !capsules_.empty() && first_wall_hit(capsules_, x, y, x, y).hit;
    if (in_wall || !(floor_.depth(x, y) > h_min_)) {
      // The parents straddle a wall or a spit of land: the new ray is a cut, with no samples.
      r.alive = false;
      r.joined = false;
      r.flags |= ray_flag::dead | (in_wall ? ray_flag::hit_wall : ray_flag::reached_shore);
      if (in_wall) ++main_.wall_rays;
      return id;
    }
    r.w = wave_at(medium_, x, y);
    r.a_geo = 0.5 * (a.a_geo + b.a_geo);
    r.a_prev = r.a_geo;
    r.cg_prev = r.w.cg;
    write_sample(main_, id, r.st, r.w, 0);
    finalize(main_, id);
    main_.any_alive = true;
    return id;
  }

  // ---- tubes ----

  // Ray order_[i]'s tube to the next.
  void record_tube(std::size_t i) {
    const std::size_t n = order_.size();
    Ray& a = rays_[std::size_t(order_[i])];
    const double sigma = i + 1 < n ? pair_sigma_[i] : std::numeric_limits<double>::quiet_NaN();
    if (std::isnan(sigma)) {
      a.tube_next = -1;
      a.tube_crossed = false;
      return;
    }
    const std::int32_t next = order_[i + 1];
    const Ray& b = rays_[std::size_t(next)];
    const bool crossed = a.crossed_with == next || sigma <= 0.0;
    a.tube_next = next;
    a.tube_sigma = sigma;
    a.tube_b = crossed ? 0.0 : pair_width_[i];
    a.tube_crossed = crossed;
    if (!crossed && pair_real_[i] && on_grid_sample(a) && on_grid_sample(b)) a.latest->flags |= sample_flag::tube_next;
  }

  // A ray's latest sample is on the phase grid (false without one: the sample cap refused it).
  bool on_grid_sample(const Ray& r) noexcept {
    return r.latest && !(r.latest->flags & sample_flag::off_grid);
  }

  // ---- output ----

  // The output, and `also` run beside the gather on the second lane when there is one (the first
  // task it takes), or after it.
  template <class Also>
  WaveRays finish(DwtStats& stats, const Also& also) {
    WaveRays out;
    out.omega = medium_.omega;
    out.direction_x = front_.dx;
    out.direction_y = front_.dy;
    out.amplitude0 = train_.amplitude;
    out.phase_step = front_.dphi;
    out.min_depth = h_min_;
    const std::size_t nr = order_.size();
    std::vector<std::int32_t> rank(rays_.size(), -1);
    for (std::size_t i = 0; i < nr; ++i) rank[std::size_t(order_[i])] = std::int32_t(i);
    out.sample_begin.assign(nr + 1, 0);
    for (std::size_t i = 0; i < nr; ++i) out.sample_begin[i + 1] = out.sample_begin[i] + rays_[std::size_t(order_[i])].samples.count;
    const std::size_t ns = out.sample_begin[nr];
    BulkLayout layout;
    constexpr std::size_t n_doubles = 7;  // x, y, theta, k, amplitude, phase, time
    std::size_t at[n_doubles];
    for (std::size_t i = 0; i < n_doubles; ++i) at[i] = layout.add<double>(ns);
    const bool diffraction = !fans_.empty();
    const std::size_t at_flags = layout.add<std::uint8_t>(ns), at_k = layout.add<float>(diffraction ? ns : 0);
    std::shared_ptr<std::byte[]> block = layout.allocate();
    double* arrays[n_doubles];
    for (std::size_t i = 0; i < n_doubles; ++i) arrays[i] = BulkLayout::at<double>(block.get(), at[i]);
    auto* flags = BulkLayout::at<std::uint8_t>(block.get(), at_flags);
    float* coefficient = BulkLayout::at<float>(block.get(), at_k);
    out.x = {arrays[0], ns};
    out.y = {arrays[1], ns};
    out.theta = {arrays[2], ns};
    out.k = {arrays[3], ns};
    out.amplitude = {arrays[4], ns};
    out.phase = {arrays[5], ns};
    out.time = {arrays[6], ns};
    out.sample_flags = {flags, ns};
    if (diffraction) out.diffraction = {coefficient, ns};
    // Per ray, its chunks into the output block, front to back, with K' applied ray by ray; on two
    // lanes, runs of rays of about equal sample counts are taken from both ends (what a ray's
    // output is does not depend on the lane that writes it).
    const Gather g{arrays, flags, coefficient, diffraction};
    if (pool_) {
      constexpr std::size_t runs = 32;
      std::vector<std::size_t> bound(runs + 1, nr);
      bound[0] = 0;
      for (std::size_t c = 1; c < runs; ++c) {
        const std::uint32_t target = std::uint32_t(ns * c / runs);
        const auto past = std::lower_bound(out.sample_begin.begin(), out.sample_begin.end() - 1, target);
        bound[c] = std::size_t(past - out.sample_begin.begin());
        bound[c] = std::max(bound[c], bound[c - 1]);
      }
      pool_->for_ranges(runs + 1, 1, [&](std::size_t c, std::size_t, unsigned lane) {
        if (c == runs) also();
        else gather(lane == 0 ? main_ : side_, out, g, bound[c], bound[c + 1]);
      });
      merge_side_lane();
    } else {
      gather(main_, out, g, 0, nr);
      also();
    }
    out.sample_storage = std::move(block);
    out.first_step.resize(nr);
    out.flags.resize(nr);
    out.parent_a.resize(nr);
    out.parent_b.resize(nr);
    out.pierhead.resize(nr);
    for (std::size_t i = 0; i < nr; ++i) {
      const Ray& r = rays_[std::size_t(order_[i])];
      out.first_step[i] = r.first_step >= 0 ? r.first_step : 0;
      out.flags[i] = r.flags;
      out.parent_a[i] = r.parent_a >= 0 ? rank[std::size_t(r.parent_a)] : -1;
      out.parent_b[i] = r.parent_b >= 0 ? rank[std::size_t(r.parent_b)] : -1;
      out.pierhead[i] = r.family;
    }
    for (const Fan& f : fans_) {
      out.pierheads.push_back(WaveRays::Pierhead{f.site.x, f.site.y, f.ox, f.oy, f.site.wall, f.phi_m, f.a_m, f.wave_m.k});
    }
    main_.stats.truncated = main_.stats.truncated || main_.truncated;
    stats = main_.stats;
    return out;
  }

  // Where finish() writes the samples.
  struct Gather {
    double* const* arrays;  // x, y, theta, k, amplitude, phase, time
    std::uint8_t* flags;
    float* coefficient;     // K' (with diffraction)
    bool diffraction;
  };

  // The staged samples of rays order_[lo, hi) into the output, K' applied.
  void gather(Lane& lane, const WaveRays& out, const Gather& g, std::size_t lo, std::size_t hi) {
    // Local pointers: the byte stores of the flags could alias g's, which the compiler would
    // otherwise reload for every sample.
    double *const x = g.arrays[0], *const y = g.arrays[1], *const theta = g.arrays[2], *const k = g.arrays[3];
    double *const amplitude = g.arrays[4], *const phase = g.arrays[5], *const time = g.arrays[6];
    std::uint8_t* const flags = g.flags;
    for (std::size_t i = lo; i < hi; ++i) {
      const Ray& r = rays_[std::size_t(order_[i])];
      const std::size_t begin = out.sample_begin[i];
      if (g.diffraction) lane.k_scratch.resize(r.samples.count), lane.a_scratch.resize(r.samples.count);
      std::size_t t = begin;
      for (const SampleChunk* c = r.samples.first; c; c = c->next) {
        const SampleChunk& ch = *c;
        const std::size_t n = std::min<std::size_t>(SampleChunk::size, out.sample_begin[i + 1] - t);
        for (std::size_t q = 0; q < n; ++q) {
          const StagedSample& s = ch.at[q];
          x[t + q] = s.x;
          y[t + q] = s.y;
          theta[t + q] = s.theta;
          k[t + q] = s.k;
          amplitude[t + q] = s.amplitude;
          phase[t + q] = s.phase;
          time[t + q] = s.time;
          flags[t + q] = s.flags;
        }
        if (g.diffraction) {
          for (std::size_t q = 0; q < n; ++q) {
            lane.k_scratch[t - begin + q] = ch.at[q].k_exact;
            lane.a_scratch[t - begin + q] = ch.at[q].a_break;
          }
        }
        t += n;
      }
      if (!g.diffraction) continue;
      apply_diffraction(lane, out, amplitude, r.family, begin, out.sample_begin[i + 1]);
      for (std::size_t q = begin; q < t; ++q) {
        g.coefficient[q] = (flags[q] & sample_flag::diffraction) ? float(lane.k_scratch[q - begin]) : 1.0f;
      }
    }
  }

  // K' for one ray's samples that carry a diffraction coefficient (they hold a_geo): exact at the
  // knots the sweep left (and at both ends of each run of such samples), linear in path length in
  // between; then the breaking cap once more, so H <= gamma_b h holds whatever the interpolation did.
  // `out` holds the samples in ray order (its amplitudes are `amplitude`); the lane's k_scratch and
  // a_scratch hold the ray's staged k_exact and a_break, from `begin`.
  void apply_diffraction(Lane& lane, const WaveRays& out, double* amplitude, std::int32_t family, std::size_t begin,
                         std::size_t end) {
    auto k_exact = [&](std::size_t t) -> double& { return lane.k_scratch[t - begin]; };
    std::size_t i = begin;
    while (i < end) {
      if (!(out.sample_flags[i] & sample_flag::diffraction)) {
        ++i;
        continue;
      }
      std::size_t run_end = i;
      while (run_end < end && (out.sample_flags[run_end] & sample_flag::diffraction)) ++run_end;
      for (std::size_t e : {i, run_end - 1}) {
        double& K = k_exact(e);
        if (knot_pending(K)) K = k_factor(lane, family, out.x[e], out.y[e], out.phase[e]);
      }
      std::size_t last = i;
      double path = 0.0, path_last = 0.0;
      lane.path_scratch.resize(run_end - i);  // path length from sample i
      for (std::size_t t = i + 1; t < run_end; ++t) {
        path += dist(out.x[t] - out.x[t - 1], out.y[t] - out.y[t - 1]);
        lane.path_scratch[t - i] = path;
        double& K = k_exact(t);
        if (std::isnan(K)) continue;
        if (K == pending_knot) K = k_factor(lane, family, out.x[t], out.y[t], out.phase[t]);
        // Knot t: interpolate the samples since the previous knot.
        const double k_last = k_exact(last), k_t = K;
        for (std::size_t q = last + 1; q < t; ++q) {
          const double u = path > path_last ? (lane.path_scratch[q - i] - path_last) / (path - path_last) : 1.0;
          k_exact(q) = k_last + u * (k_t - k_last);
        }
        last = t;
        path_last = path;
      }
      for (std::size_t t = i; t < run_end; ++t) {
        amplitude[t] = std::min(amplitude[t] * k_exact(t), lane.a_scratch[t - begin]);
      }
      i = run_end;
    }
  }

  double distance_to_pierhead(std::int32_t family, double x, double y) const noexcept {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < fans_.size(); ++f) {
      if (family >= 0 && std::int32_t(f) != family) continue;
      best = std::min(best, dist(x - fans_[f].site.x, y - fans_[f].site.y));
    }
    return best;
  }

  struct CatchUp {
    RayState st;
    LocalWave w;
    std::uint8_t flags;
  };

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
  std::vector<PierheadSite> sites_;
  std::vector<bool> site_used_;
  std::size_t sites_left_ = 0;  // sites that have not spawned their fan yet
  std::vector<Fan> fans_;
  std::vector<Ray> rays_;
  std::vector<std::int32_t> order_, merged_;
  std::vector<Pending> pending_;
  std::vector<CatchUp> catch_;
  std::int32_t step_ = 0;  // the wavefront being processed
  std::vector<double> pair_sigma_, pair_width_;
  std::vector<std::uint8_t> pair_real_;
  Lane main_;  // the sweep's own
  Lane side_;  // the pool's second lane's, merged into main_ after each shared pass
  std::int64_t first_step_ = 0;
  double k_bound_ = inf;  // K' <= k_bound_ everywhere (finalize)
  double uniform_a_break_ = 0.0;  // breaking_limit() of a uniform floor
  bool reflected_ = false;  // tracing a reflected wave (seeded on walls, not from the entry front)
};

Expected<Scene> checked(const Scene& scene, const DwtSettings& settings) {
  Scene copy = scene;
  copy.dwt = settings;
  return validate(std::move(copy));
}

// Effect plan: straight crests, analytic phase, no rays.
WaveRays analytic_rays(const Scene& scene, std::size_t train) {
  WaveRays out;
  const WaveTrain& t = scene.trains[train];
  out.omega = train_omega(t);
  const Point2 d = train_direction(t);
  out.direction_x = d.x;
  out.direction_y = d.y;
  out.amplitude0 = t.amplitude;
  out.analytic = true;
  const Bathymetry floor(scene.floor);
  const LinearWave w = linear_wave(out.omega, floor.uniform() ? scene.floor.base.depth : 1e9);
  out.analytic_k = w.k;
  out.analytic_amplitude = t.amplitude * shoaling_coefficient(w.kh);
  return out;
}

// The same, and `train` must be one of its trains.
Expected<Scene> checked(const Scene& scene, const DwtSettings& settings, std::size_t train) {
  if (train >= scene.trains.size()) {
    return Error{"trains", "an index below " + std::to_string(scene.trains.size()) + ", got " + std::to_string(train)};
  }
  return checked(scene, settings);
}

// A train's second lane: none on one thread, else a pool of two (the tracer shares its passes between
// two lanes at most).
Expected<std::unique_ptr<ThreadPool>> train_pool(unsigned threads) {
  if (threads < 2) return std::unique_ptr<ThreadPool>();
  return ThreadPool::create(2);
}

}  // namespace
}  // namespace detail

DwtStats& DwtStats::operator+=(const DwtStats& o) noexcept {
  rays += o.rays;
  initial_rays += o.initial_rays;
  inserted_rays += o.inserted_rays;
  diffracted_rays += o.diffracted_rays;
  samples += o.samples;
  steps += o.steps;
  fans += o.fans;
  diffraction_evaluations += o.diffraction_evaluations;
  crossings += o.crossings;
  broken_rays += o.broken_rays;
  wall_hits += o.wall_hits;
  left_domain += o.left_domain;
  reached_shore += o.reached_shore;
  turned_back += o.turned_back;
  reflected_rays += o.reflected_rays;
  insertions_refused += o.insertions_refused;
  shared_steps += o.shared_steps;
  truncated = truncated || o.truncated;
  return *this;
}

bool scene_has_pierheads(const Scene& scene) noexcept {
  if (!scene.dwt.diffraction || scene.walls.empty()) return false;
  const Bathymetry floor(scene.floor);
  // h_min is per train; the smallest possible (min_depth) keeps this a safe over-estimate.
  return !detail::pierhead_sites(scene, floor, scene.dwt.min_depth).empty();
}

bool scene_has_reflecting_walls(const Scene& scene) noexcept {
  if (!scene.dwt.reflection) return false;
  return std::any_of(scene.walls.begin(), scene.walls.end(), [](const Wall& w) { return w.reflection > 0.0; });
}

bool train_needs_rays(const Scene& scene, std::size_t train) noexcept {
  if (train >= scene.trains.size()) return false;
  const WaveTrain& t = scene.trains[train];
  if (!(t.amplitude > 0.0)) return false;
  if (!scene.walls.empty()) return true;
  const Bathymetry floor(scene.floor);
  if (floor.uniform()) return false;
  // Deep everywhere (h >= L0: kh >= 2 pi, C within 1e-5 of g / omega): no refraction worth a ray.
  const double l0 = 2.0 * std::numbers::pi / deep_water_wavenumber(train_omega(t));
  return !(floor.min_depth_bound(scene.domain) >= l0);
}

DwtBound dwt_bound(const Scene& scene, std::size_t train, const DwtSettings& settings) noexcept {
  DwtBound b;
  b.rays = settings.max_rays;
  b.samples = settings.max_samples;
  if (train >= scene.trains.size()) return b;
  const Bathymetry floor(scene.floor);
  const double omega = train_omega(scene.trains[train]);
  const double h_min = std::max(settings.min_depth, settings.min_depth_wavelengths * 2.0 * std::numbers::pi /
                                                        deep_water_wavenumber(omega));
  const detail::Medium m = detail::make_medium(scene, floor, omega, h_min);
  const detail::Front f = detail::make_front(scene, train, settings, m);
  if (!(f.dphi > 0.0)) return DwtBound{f.entries.size(), 0};
  // Every ray ends within the path limit; each step takes at least dphi / k(h_min) of path.
  const double steps = detail::path_limit(scene.domain) * detail::wave_from_depth(m, h_min).k / f.dphi + 4.0;
  const double worst = double(settings.max_rays) * steps;
  b.samples = std::size_t(std::min(double(settings.max_samples), worst));
  return b;
}

Expected<WaveRays> trace_train(const Scene& scene, std::size_t train, const DwtSettings& settings, DwtStats* stats,
                               unsigned threads) {
  auto valid = detail::checked(scene, settings, train);
  if (!valid.ok()) return valid.error();
  DwtStats local;
  DwtStats& st = stats ? *stats : local;
  st = DwtStats{};
  if (settings.analytic_shortcut && !train_needs_rays(scene, train)) return detail::analytic_rays(scene, train);
  auto pool = detail::train_pool(threads);
  if (!pool) return pool.error();
  detail::TrainTracer tracer(valid.value(), train, valid->dwt, pool->get());
  return tracer.run(st);
}

Expected<WaveRays> trace_reflection(const Scene& scene, std::size_t train, const WaveRays& incident,
                                    const DwtSettings& settings, DwtStats* stats, unsigned threads) {
  auto valid = detail::checked(scene, settings, train);
  if (!valid.ok()) return valid.error();
  DwtStats local;
  DwtStats& st = stats ? *stats : local;
  st = DwtStats{};
  WaveRays none;
  none.omega = incident.omega;
  none.direction_x = incident.direction_x;
  none.direction_y = incident.direction_y;
  none.amplitude0 = incident.amplitude0;
  none.phase_step = incident.phase_step;
  none.min_depth = incident.min_depth;
  if (!valid->dwt.reflection || incident.analytic || !scene_has_reflecting_walls(valid.value())) return none;
  auto pool = detail::train_pool(threads);
  if (!pool) return pool.error();
  detail::TrainTracer tracer(valid.value(), train, valid->dwt, detail::ray_ends(incident), incident.omega, incident.direction_x,
                             incident.direction_y, incident.phase_step, pool->get());
  WaveRays out = tracer.run(st);
  st.reflected_rays = st.rays;
  return out;
}

Expected<WaveField> trace_wave_field(const Scene& scene, unsigned threads) {
  return trace_wave_field(scene, scene.dwt, threads);
}

Expected<WaveField> trace_wave_field(const Scene& scene, const DwtSettings& settings, unsigned threads) {
  auto valid = detail::checked(scene, settings);
  if (!valid.ok()) return valid.error();
  const Scene& s = valid.value();
  const std::size_t n = s.trains.size();
  std::vector<WaveRays> incident(n), reflected(n);
  std::vector<DwtStats> stats(n), reflected_stats(n);
  const std::size_t workers = std::min<std::size_t>(std::max(1u, threads), n);
  const unsigned lanes = workers > 0 ? threads / unsigned(workers) : 1u;
  const bool reflects = s.dwt.reflection && scene_has_reflecting_walls(s);
  // Trains are independent and each is traced as trace_train, then trace_reflection, would trace it,
  // on a worker and that worker's second lane when there are threads for one: the result does not
  // depend on the thread count.
  auto pool = detail::ThreadPool::create(unsigned(workers));
  if (!pool) return pool.error();
  std::vector<std::unique_ptr<detail::ThreadPool>> second_lanes(workers);
  for (auto& lane : second_lanes) {
    auto p = detail::train_pool(lanes);
    if (!p) return p.error();
    lane = std::move(p.value());
  }
  // Worker w traces trains w, w + workers, ...: the first train (in the shipped scenes the longest
  // waves, the most work) and the last share a worker only when there are more trains than workers.
  pool.value()->for_ranges(workers, 1, [&](std::size_t first, std::size_t, unsigned lane) {
    for (std::size_t i = first; i < n; i += workers) {
      if (s.dwt.analytic_shortcut && !train_needs_rays(s, i)) {
        incident[i] = detail::analytic_rays(s, i);
        continue;
      }
      detail::TrainTracer tracer(s, i, s.dwt, second_lanes[lane].get());
      incident[i] = reflects ? tracer.run_reflecting(stats[i], reflected[i], reflected_stats[i]) : tracer.run(stats[i]);
    }
  });
  WaveField field;
  for (std::size_t i = 0; i < n; ++i) {
    field.trains.push_back(std::move(incident[i]));
    field.stats += stats[i];
    if (reflected[i].sample_count() > 0) {
      field.reflections.push_back(ReflectedWave{i, std::move(reflected[i])});
      field.stats += reflected_stats[i];
    }
  }
  return field;
}

}  // namespace houle
