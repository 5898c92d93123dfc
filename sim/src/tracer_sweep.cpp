// The sweep: every step's passes over the wavefront (advance, tubes and amplitudes, insertion).
// The per-ray work of a step is the hot path: it lives in this one translation unit (with the inline
// helpers of train_tracer.hpp) so that the compiler inlines it as it did when the tracer was one file.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "clip_line.hpp"
#include "train_tracer.hpp"

namespace houle::detail {
namespace {

constexpr int max_insertion_passes = 16;   // per step; each pass halves the widest tube
// A front this large shares pass A between two lanes where rays curve: a curved step (RK4 with
// depth lookups, a few thousand instructions) far outweighs moving the ray's state between cores and
// back, which a straight step (a few dozen) does not (Fig. 4 on two lanes: 8.1 ms shared, 5.9 ms
// unshared).
constexpr std::size_t shared_pass_min_rays = 64;
constexpr std::size_t shared_chunk_rays = 16;  // what a lane takes at a time

}  // namespace

// The train's rays, all ended, in order_ as they will be output.
void TrainTracer::sweep() {
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

std::size_t TrainTracer::estimate_samples() const noexcept {
  const Domain& d = scene_.domain;
  const double across = dist(d.x_max - d.x_min, d.y_max - d.y_min);
  const double per_ray = across / set_.step + 2.0;
  return std::size_t(4.0 * double(front_.entries.size()) * per_ray) + 1024;
}

double TrainTracer::chord_event_near(const RayState& a, const RayState& b, double depth_b, double travel,
                                     double& clear, Stop& why) const noexcept {
  double u = 2.0;
  if (travel < clear) {
    clear -= travel;
  } else {
    // Most chords are nowhere near a wall: one box test instead of one per capsule.
    const bool near_walls = std::max(a.x, b.x) >= walls_box_.x_min && std::min(a.x, b.x) <= walls_box_.x_max &&
                            std::max(a.y, b.y) >= walls_box_.y_min && std::min(a.y, b.y) <= walls_box_.y_max;
    if (near_walls) {
      const WallHit hit = first_wall_hit(capsules_, a.x, a.y, b.x, b.y);
      if (hit.hit) u = hit.u, why = Stop::wall;
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
double TrainTracer::clearance(double x, double y) const noexcept {
  const Domain& d = scene_.domain;
  double c = std::min(std::min(x - d.x_min, d.x_max - x), std::min(y - d.y_min, d.y_max - y));
  if (!capsules_.empty()) {
    const double dx = std::max(std::max(walls_box_.x_min - x, x - walls_box_.x_max), 0.0);
    const double dy = std::max(std::max(walls_box_.y_min - y, y - walls_box_.y_max), 0.0);
    c = std::min(c, std::max(dx, dy));
  }
  return std::max(0.0, c * (1.0 - 1e-9) - 1e-9);
}

// move_ray within the sweep: a ray that ends gets its end point as an off-grid sample, shoaled over
// the partial step, its tube widening as over the last full step (in proportion to the phase).
bool TrainTracer::advance_ray(Lane& lane, std::int32_t id, double dphi) {
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
void TrainTracer::step(std::int32_t j) {
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
  // B: tubes, caustics and amplitudes on this wavefront. Without insertion (C) the tubes of D are
  // those of B, and D rides along.
  const bool inserts = main_.widest > set_.insertion_distance;
  update_amplitudes(!inserts);
  if (!inserts) return;
  // C: insertion where live neighbours are too far apart.
  for (int pass = 0; pass < max_insertion_passes && insert_rays(j); ++pass) measure_tubes();
  // D: remember this wavefront's tubes for the next step; mark sound tubes for tessellation.
  for (std::size_t i = 0; i < order_.size(); ++i) record_tube(i);
}

// Pass A over order_[lo, hi). The pairs are measured in a loop of their own, whose iterations are
// independent: the long sqrt and division of each spacing then overlap (within one loop with the
// advance they were on the critical path of every ray).
void TrainTracer::advance_front(Lane& lane, std::int32_t j, std::size_t lo, std::size_t hi) {
  for (std::size_t i = lo; i < hi; ++i) {
    if (i + 2 < hi) prefetch_ray(order_[i + 2]);
    advance_on_step(lane, order_[i], j);
  }
  measure_pairs(lane, lo, hi);
}

// order_ visits rays_ out of order, which the hardware cannot follow: the passes fetch a ray's
// hot lines two rays ahead.
void TrainTracer::prefetch_ray(std::int32_t id) const noexcept {
  const auto* p = reinterpret_cast<const char*>(&rays_[std::size_t(id)]);
  for (std::size_t b = 0; b < 4 * 64; b += 64) __builtin_prefetch(p + b, 1);
}

void TrainTracer::merge_side_lane() {
  main_.stats += side_.stats;
  main_.widest = std::max(main_.widest, side_.widest);
  main_.any_alive = main_.any_alive || side_.any_alive;
  main_.truncated = main_.truncated || side_.truncated;
  side_.stats = DwtStats{};
  side_.widest = 0.0;
  side_.any_alive = side_.truncated = false;
}

void TrainTracer::advance_on_step(Lane& lane, std::int32_t id, std::int32_t j) {
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

// Every pass of a step visits every ray in order_, and dead rays pile up in it. A dead ray between
// two dead neighbours can take no further part: it has no tube and never gets a new neighbour (rays are inserted only next to a live one). Such rays leave order_ and follow
// their predecessor in the output.
void TrainTracer::drop_inert_rays() {
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
void TrainTracer::follow(std::int32_t p, std::int32_t d) {
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
bool TrainTracer::pose_on_step(const Ray& r, double phi_j, Pose& p) const noexcept {
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
double TrainTracer::spacing(const Pose& a, const Pose& b) noexcept {
  const double mx = a.cos_t + b.cos_t, my = a.sin_t + b.sin_t;
  const double n2 = mx * mx + my * my;
  if (!(n2 > 1e-24)) return -1.0;  // opposite directions: treat as crossed
  return ((b.x - a.x) * -my + (b.y - a.y) * mx) / std::sqrt(n2);
}

// Spacing of every neighbour pair in order_ that has a pose on this wavefront (NaN otherwise); pair_real_ marks pairs of two live rays (only those may insert or be tessellated).
void TrainTracer::measure_tubes() {
  begin_tubes();
  measure_pairs(main_, 0, order_.size());
}

// The pairs within order_[lo, hi). The widest is kept in a register: through lane.widest, which
// the pair arrays' stores might alias, every pair's sqrt and division waited for the last one's.
void TrainTracer::measure_pairs(Lane& lane, std::size_t lo, std::size_t hi) {
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
void TrainTracer::begin_tubes() {
  const std::size_t n = order_.size();
  pair_sigma_.assign(n, std::numeric_limits<double>::quiet_NaN());
  pair_real_.assign(n, 0);
  main_.widest = 0.0;
}

// Pair (i, i + 1), whose rays have poses pa and pb on this wavefront.
// Returns its spacing if it is real, else 0 (what the widest real spacing starts from).
double TrainTracer::measure_pair(std::size_t i, const Pose& pa, const Pose& pb) {
  const Ray& a = rays_[std::size_t(order_[i])];
  const Ray& b = rays_[std::size_t(order_[i + 1])];
  const double sigma = spacing(pa, pb);
  const bool real = live_on_step(a) && live_on_step(b);
  pair_sigma_[i] = sigma;
  pair_real_[i] = real;
  return real ? sigma : 0.0;
}

// Tubes, caustics and amplitudes on this wavefront in one pass: pair (i, i + 1) is classified just
// before ray i, which needs it and pair (i - 1, i); with `record`, ray i's tube is recorded after.
void TrainTracer::update_amplitudes(bool record) {
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
TrainTracer::PairTube TrainTracer::classify_pair(std::size_t i) {
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
  if (!persisted || a.fresh || b.fresh) return t;
  return PairTube{a.tube_sigma, sigma, true, false};  // uncrossed then and now: both widths > 0
}

// Ray order_[i]'s tube to the next.
void TrainTracer::record_tube(std::size_t i) {
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
  a.tube_crossed = crossed;
  if (!crossed && pair_real_[i] && on_grid_sample(a) && on_grid_sample(b)) a.latest->flags |= sample_flag::tube_next;
}

// A ray's latest sample is on the phase grid (false without one: the sample cap refused it).
bool TrainTracer::on_grid_sample(const Ray& r) noexcept {
  return r.latest && !(r.latest->flags & sample_flag::off_grid);
}

}  // namespace houle::detail
