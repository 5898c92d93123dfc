// Dynamic Wave Tracing: the wavefront sweep (see wave_rays.hpp for the method and its choices).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/wave_rays.hpp"
#include "ray_step.hpp"
#include "ray_walls.hpp"

namespace houle {
namespace detail {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;
constexpr double fan_spacing = pi / 8.0;   // rad between a fan's first rays (refined by insertion)
constexpr int max_insertion_passes = 16;   // per step; each pass halves the widest tube

// ---- The train's entry front, shared by dwt_bound and the tracer -------------------------------

struct Entry {
  double x = 0.0, y = 0.0;  // where the ray enters the domain, m
  double phi = 0.0;         // rad, k_entry * distance from the upstream wavefront
  double tau = 0.0;         // s
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

// Parameter range [t0, t1] of the line p + t d inside the rectangle (Liang-Barsky); false if it misses.
bool clip_line(const Domain& d, double px, double py, double dx, double dy, double& t0, double& t1) noexcept {
  t0 = -std::numeric_limits<double>::infinity();
  t1 = std::numeric_limits<double>::infinity();
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {px - d.x_min, d.x_max - px, py - d.y_min, d.y_max - py};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double r = q[i] / p[i];
      if (p[i] < 0.0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  return t0 <= t1;
}

Medium make_medium(const Scene& scene, const Bathymetry& floor, double omega, double h_min) {
  Medium m;
  m.floor = &floor;
  m.omega = omega;
  m.k0 = deep_water_wavenumber(omega);
  m.h_eval_min = 0.5 * h_min;
  m.uniform = floor.uniform();
  if (m.uniform) m.uniform_wave = wave_from_depth(m, scene.floor.base.depth, 0.0);
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
  const std::size_t n = set.initial_rays > 0
                            ? set.initial_rays
                            : std::max<std::size_t>(2, std::size_t(std::ceil(width / set.insertion_distance)));
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
    e.wave = wave_at(medium, e.x, e.y, 0.0);
    e.water = true;
    e.phi = e.wave.k * t0;
    e.tau = t0 / e.wave.cg;
    f.k_ref = std::min(f.k_ref, e.wave.k);
  }
  if (std::isfinite(f.k_ref)) f.dphi = f.k_ref * set.step;
  return f;
}

double path_limit(const Domain& d) noexcept { return 4.0 * ((d.x_max - d.x_min) + (d.y_max - d.y_min)); }

// ---- The tracer --------------------------------------------------------------------------------

struct Ray {
  RayState st{};
  LocalWave w{};                 // the wave at st
  double a_geo = 0.0;            // m, amplitude from shoaling and tube width (no K', capped)
  double a_prev = 0.0, cg_prev = 0.0;  // at the previous sample
  std::int32_t family = -1;      // fan index, or -1 for the incident wave
  double theta0 = 0.0;           // direction at birth
  std::int32_t parent_a = -1, parent_b = -1;
  std::uint8_t flags = 0;
  std::int32_t first_step = -1;
  bool alive = true;             // not ended (pending rays are alive)
  bool joined = false;           // has reached the phase grid
  bool joined_now = false;       // its first on-grid sample is this step's
  bool fresh = false;            // born complete on this step (fans): nothing to update
  std::uint32_t last_sample = 0;
  std::uint32_t wall = 0;        // the wall it hit (when hit_wall)
  double hit_x = 0.0, hit_y = 0.0;
  // The tube to the next ray in order, as of the last completed step.
  std::int32_t tube_next = -1;
  double tube_sigma = 0.0;       // perpendicular spacing, m
  double tube_b = 0.0;           // width used for amplitude (sigma, or sigma / d in a fan)
  bool tube_crossed = false;
  std::int32_t crossed_with = -1;  // this step: next ray it is found crossed with
};

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
};

// Samples in the order they are produced; sorted per ray at the end.
struct SampleStore {
  std::vector<double> x, y, theta, k, amplitude, phase, time;
  std::vector<std::uint8_t> flags;
  std::vector<std::int32_t> ray;
  void reserve(std::size_t n) {
    for (auto* v : {&x, &y, &theta, &k, &amplitude, &phase, &time}) v->reserve(n);
    flags.reserve(n);
    ray.reserve(n);
  }
  std::size_t size() const noexcept { return x.size(); }
};

// One candidate event on a chord, for the stop callback.
enum class Stop : std::uint8_t { none, wall, domain, shore };

class TrainTracer {
 public:
  TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set)
      : scene_(scene), set_(set), floor_(scene.floor), train_(scene.trains[train]) {
    const double omega = train_omega(train_);
    const double l0 = two_pi / deep_water_wavenumber(omega);
    h_min_ = std::max(set.min_depth, set.min_depth_wavelengths * l0);
    medium_ = make_medium(scene, floor_, omega, h_min_);
    front_ = make_front(scene, train, set, medium_);
    capsules_ = wall_capsules(scene.walls);
    if (set.diffraction) sites_ = pierhead_sites(scene, floor_, h_min_);
    site_used_.assign(sites_.size(), false);
    path_max_ = path_limit(scene.domain);
  }

  WaveRays run(DwtStats& stats) {
    WaveRays out;
    out.omega = medium_.omega;
    out.direction_x = front_.dx;
    out.direction_y = front_.dy;
    out.amplitude0 = train_.amplitude;
    out.phase_step = front_.dphi;
    out.min_depth = h_min_;
    if (!(front_.dphi > 0.0)) return finish(out, stats);  // the whole front is on land

    samples_.reserve(std::min<std::size_t>(set_.max_samples, estimate_samples()));
    rays_.reserve(std::min<std::size_t>(set_.max_rays, 4 * front_.entries.size() + 64));

    start_front();
    std::int64_t j = first_step_;
    const std::int64_t last_step = first_step_ + std::int64_t(path_max_ * max_k() / front_.dphi) + 2;
    while (any_alive_ && !truncated_ && j <= last_step) {
      step(std::int32_t(j));
      ++stats_.steps;
      ++j;
    }
    if (any_alive_) {
      // A cap stopped the sweep: whatever is still running ends here.
      truncated_ = true;
      for (Ray& r : rays_) {
        if (r.alive) r.alive = false, r.flags |= ray_flag::dead | ray_flag::truncated;
      }
    }
    return finish(out, stats);
  }

 private:
  // ---- setup ----

  double max_k() const noexcept {
    // The shortest waves are at h_min: no ray has more phase per metre.
    return wave_from_depth(medium_, h_min_, 0.0).k;
  }

  std::size_t estimate_samples() const noexcept {
    const Domain& d = scene_.domain;
    const double across = std::hypot(d.x_max - d.x_min, d.y_max - d.y_min);
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
      ++stats_.initial_rays;
      ++stats_.rays;
      if (!e.water) {
        // Enters on land: a cut in the front, with no samples.
        r.alive = false;
        r.flags = ray_flag::dead | ray_flag::reached_shore;
        ++stats_.reached_shore;
        continue;
      }
      r.st = RayState{e.x, e.y, std::atan2(front_.dy, front_.dx), e.phi, 0.0, e.tau};
      r.theta0 = r.st.theta;
      r.w = e.wave;
      r.a_geo = train_.amplitude * shoaling_coefficient(e.wave.kh);
      r.cg_prev = r.w.cg;
      any_alive_ = true;
      const std::int64_t js = grid_step_at_or_after(e.phi);
      first_step_ = std::min(first_step_, js);
      write_sample(id, r.st, r.w, on_grid(e.phi) ? 0 : sample_flag::off_grid);
      finalize(id, rays_[std::size_t(id)].last_sample);
    }
    if (first_step_ == std::numeric_limits<std::int64_t>::max()) first_step_ = 0;
  }

  double grid_phase(std::int64_t j) const noexcept { return double(j) * front_.dphi; }
  bool on_grid(double phi) const noexcept {
    const double j = std::round(phi / front_.dphi);
    return grid_phase(std::int64_t(j)) == phi;
  }
  std::int64_t grid_step_at_or_after(double phi) const noexcept {
    std::int64_t j = std::int64_t(std::ceil(phi / front_.dphi));
    while (grid_phase(j) < phi) ++j;
    while (j > 0 && grid_phase(j - 1) >= phi) --j;
    return j;
  }

  // ---- samples ----

  void write_sample(std::int32_t id, const RayState& st, const LocalWave& w, std::uint8_t flags) {
    if (samples_.size() >= set_.max_samples) {
      truncated_ = true;
      return;
    }
    samples_.x.push_back(st.x);
    samples_.y.push_back(st.y);
    samples_.theta.push_back(st.theta);
    samples_.k.push_back(w.k);
    samples_.amplitude.push_back(0.0);
    samples_.phase.push_back(st.phi);
    samples_.time.push_back(st.tau);
    samples_.flags.push_back(flags);
    samples_.ray.push_back(id);
    rays_[std::size_t(id)].last_sample = std::uint32_t(samples_.size() - 1);
    ++stats_.samples;
  }

  // Diffraction coefficient, breaking caps and flags for sample `s` of ray `id` (whose a_geo is the
  // geometric amplitude there); may dissipate a_geo.
  void finalize(std::int32_t id, std::uint32_t s) {
    Ray& r = rays_[std::size_t(id)];
    if (s >= samples_.size() || samples_.ray[s] != id) return;  // the sample cap refused it
    const double x = samples_.x[s], y = samples_.y[s];
    double K = 1.0;
    std::uint8_t flags = samples_.flags[s];
    if (r.family >= 0) {
      const Fan& f = fans_[std::size_t(r.family)];
      const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
      // Optical distance from M (physics.md 4.7): the phase gained since M, in wavelengths.
      const double r_over_l = std::max(0.0, (samples_.phase[s] - f.phi_m) / two_pi);
      const double theta = p.kind == BreakwaterPointKind::on_structure ? two_pi : p.theta;
      const auto d = diffraction(set_.diffraction_model, r_over_l, theta, f.theta0, f.site.reflection);
      if (d.ok()) K = d->K;
      flags |= sample_flag::diffraction;
      ++stats_.diffraction_evaluations;
    } else {
      for (const Fan& f : fans_) {
        // Undiffracted rays near a shadow line: the incident-only coefficient |G(s1)| (they carry no
        // reflected wave), blended to 1 from v = 4 to 8 so that nothing jumps at the band's edge.
        const BreakwaterPolar p = breakwater_polar(f.frame, x, y);
        if (p.theta > pi + f.theta0) continue;  // not this pierhead's lit side
        const double v = f.v_scale * std::sqrt(p.r) * std::cos(0.5 * (p.theta - f.theta0));
        if (v >= 8.0) continue;
        const auto d = diffraction(set_.diffraction_model, p.r_over_L, p.theta, f.theta0, 0.0);
        ++stats_.diffraction_evaluations;
        if (!d.ok()) continue;
        const double t = std::clamp((v - 4.0) / 4.0, 0.0, 1.0);
        const double blend = t * t * (3.0 - 2.0 * t);
        K *= d->K + (1.0 - d->K) * blend;
        flags |= sample_flag::diffraction;
      }
    }
    // Breaking: H <= gamma_b h (depth-limited) and H <= 0.142 L tanh kh (Miche), as amplitudes.
    const double L = two_pi / r.w.k;
    const double a_break = std::min(0.5 * set_.breaker_index * r.w.h, 0.071 * L * std::tanh(r.w.kh));
    double a = r.a_geo * K;
    if (a > a_break) {
      a = a_break;
      if (K > 0.0) r.a_geo = a_break / K;  // the excess is dissipated, not carried on
      flags |= sample_flag::broken;
      if (!(r.flags & ray_flag::broken)) ++stats_.broken_rays;
      r.flags |= ray_flag::broken;
    }
    samples_.amplitude[s] = a;
    samples_.flags[s] = flags;
  }

  // ---- stepping ----

  // Where along the chord a -> b (0..1) the ray meets a wall, the domain's edge or the shoreline
  // (depth h_min), whichever comes first; > 1 if none.
  double chord_event(const RayState& a, const RayState& b, Stop& why, std::uint32_t& wall) const noexcept {
    double u = 2.0;
    why = Stop::none;
    const WallHit hit = first_wall_hit(capsules_, a.x, a.y, b.x, b.y);
    if (hit.hit) u = hit.u, why = Stop::wall, wall = hit.wall;
    const Domain& d = scene_.domain;
    if (b.x < d.x_min || b.x > d.x_max || b.y < d.y_min || b.y > d.y_max) {
      double t0 = 0.0, t1 = 0.0;
      const double ex = clip_line(d, a.x, a.y, b.x - a.x, b.y - a.y, t0, t1) ? std::clamp(t1, 0.0, 1.0) : 0.0;
      if (ex < u) u = ex, why = Stop::domain;
    }
    if (!medium_.uniform && floor_.depth(b.x, b.y) <= h_min_) {
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

  // Moves ray `id` on by dphi. If it meets a wall, the domain's edge or the shoreline it stops there,
  // is flagged dead with the reason, and false is returned. Amplitudes are the caller's business.
  bool move_ray(std::int32_t id, double dphi) {
    Ray& r = rays_[std::size_t(id)];
    Stop why = Stop::none;
    std::uint32_t wall = 0;
    auto stop = [&](const RayState& a, const RayState& b) { return chord_event(a, b, why, wall); };
    if (!advance(medium_, r.st, r.w, dphi, stop)) return true;
    r.alive = false;
    r.flags |= ray_flag::dead;
    if (why == Stop::wall) {
      r.flags |= ray_flag::hit_wall;
      r.wall = wall;
      r.hit_x = r.st.x;
      r.hit_y = r.st.y;
      ++stats_.wall_hits;
    } else if (why == Stop::domain) {
      r.flags |= ray_flag::left_domain;
      ++stats_.left_domain;
    } else {
      r.flags |= ray_flag::reached_shore;
      ++stats_.reached_shore;
    }
    return false;
  }

  // move_ray within the sweep: a ray that ends gets its end point as an off-grid sample, shoaled over
  // the partial step with its tube width unchanged.
  bool advance_ray(std::int32_t id, double dphi) {
    if (move_ray(id, dphi)) return true;
    Ray& r = rays_[std::size_t(id)];
    r.a_geo *= std::sqrt(r.cg_prev / r.w.cg);
    const std::uint8_t crossed = (r.flags & ray_flag::crossed) ? sample_flag::crossed : std::uint8_t(0);
    write_sample(id, r.st, r.w, std::uint8_t(sample_flag::off_grid | crossed));
    finalize(id, r.last_sample);
    return false;
  }

  void step(std::int32_t j) {
    const double phi_j = grid_phase(j);
    any_alive_ = false;
    // A: advance every live ray to this wavefront.
    for (std::int32_t id : order_) {
      Ray& r = rays_[std::size_t(id)];
      r.joined_now = false;
      r.fresh = false;
      r.crossed_with = -1;
      if (!r.alive) continue;
      any_alive_ = true;
      r.a_prev = r.a_geo;
      r.cg_prev = r.w.cg;
      double dphi = front_.dphi;
      if (!r.joined) {
        if (r.st.phi > phi_j) continue;  // enters later
        r.joined = r.joined_now = true;
        r.first_step = j;
        if (r.st.phi == phi_j) continue;  // its start sample is on this step already
        dphi = phi_j - r.st.phi;
      }
      if (!advance_ray(id, dphi)) continue;
      Ray& q = rays_[std::size_t(id)];
      q.st.phi = phi_j;
      if (q.st.s > path_max_) {
        q.alive = false;
        q.flags |= ray_flag::dead | ray_flag::truncated;
        truncated_ = true;
        continue;
      }
      write_sample(id, q.st, q.w, (q.flags & ray_flag::crossed) ? sample_flag::crossed : std::uint8_t(0));
    }
    if (truncated_) return;
    // B: fans at pierheads the front has just passed.
    if (!sites_.empty()) spawn_fans(j);
    // C: tubes, caustics and amplitudes on this wavefront.
    update_amplitudes();
    // D: insertion where live neighbours are too far apart.
    for (int pass = 0; pass < max_insertion_passes; ++pass) {
      if (!insert_rays(j)) break;
    }
    // E: remember this wavefront's tubes for the next step; mark sound tubes for tessellation.
    record_tubes();
  }

  bool live_on_step(const Ray& r) const noexcept { return r.alive && r.joined; }

  // Perpendicular spacing of b from a across their mean direction (> 0 when b is to a's left).
  static double spacing(const Ray& a, const Ray& b) noexcept {
    double mx = std::cos(a.st.theta) + std::cos(b.st.theta), my = std::sin(a.st.theta) + std::sin(b.st.theta);
    const double n = std::hypot(mx, my);
    if (!(n > 1e-12)) return -1.0;  // opposite directions: treat as crossed
    mx /= n;
    my /= n;
    return (b.st.x - a.st.x) * -my + (b.st.y - a.st.y) * mx;
  }

  // Tube width used for amplitude: sigma, or sigma / d (distance from the pierhead) within a fan.
  double tube_width(const Ray& a, const Ray& b, double sigma) const noexcept {
    if (a.family < 0) return sigma;
    const Fan& f = fans_[std::size_t(a.family)];
    const double d = 0.5 * (std::hypot(a.st.x - f.site.x, a.st.y - f.site.y) + std::hypot(b.st.x - f.site.x, b.st.y - f.site.y));
    return d > 0.0 ? sigma / d : 0.0;
  }

  void update_amplitudes() {
    const std::size_t n = order_.size();
    pair_ok_.assign(n, 0);
    pair_b_prev_.assign(n, 0.0);
    pair_b_now_.assign(n, 0.0);
    pair_crossed_.assign(n, 0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      Ray& a = rays_[std::size_t(order_[i])];
      Ray& b = rays_[std::size_t(order_[i + 1])];
      if (!live_on_step(a) || !live_on_step(b)) continue;
      const double sigma = spacing(a, b);
      const bool persisted = a.tube_next == order_[i + 1];
      bool crossed = sigma <= 0.0;
      if (persisted) {
        if (!a.tube_crossed && a.tube_sigma > 0.0 && sigma <= 0.0) {
          ++stats_.crossings;
          a.flags |= ray_flag::crossed;
          b.flags |= ray_flag::crossed;
        }
        crossed = a.tube_crossed || sigma <= 0.0;
      }
      if (crossed) {
        a.crossed_with = order_[i + 1];
        pair_crossed_[i] = 1;
        continue;
      }
      if (!persisted || a.family != b.family || a.fresh || b.fresh) continue;
      const double width = tube_width(a, b, sigma);
      if (!(a.tube_b > 0.0) || !(width > 0.0)) continue;
      pair_ok_[i] = 1;
      pair_b_prev_[i] = a.tube_b;
      pair_b_now_[i] = width;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t id = order_[i];
      Ray& r = rays_[std::size_t(id)];
      if (!live_on_step(r) || r.fresh) continue;
      double w_prev = 0.0, w_now = 0.0;
      int tubes = 0;
      bool crossed = false;
      if (i > 0) {
        if (pair_ok_[i - 1]) w_prev += pair_b_prev_[i - 1], w_now += pair_b_now_[i - 1], ++tubes;
        crossed = crossed || pair_crossed_[i - 1];
      }
      if (i + 1 < n) {
        if (pair_ok_[i]) w_prev += pair_b_prev_[i], w_now += pair_b_now_[i], ++tubes;
        crossed = crossed || pair_crossed_[i];
      }
      // Energy flux A^2 Cg b is constant along the tube (physics.md 2.3).
      const double ratio = tubes > 0 && !r.joined_now ? w_prev / w_now : 1.0;
      r.a_geo = r.a_prev * std::sqrt(r.cg_prev / r.w.cg * ratio);
      // Caustic cap: Kr <= Kr_max (physics.md 2.5, cap 2).
      r.a_geo = std::min(r.a_geo, set_.max_refraction_coefficient * train_.amplitude * shoaling_coefficient(r.w.kh));
      if (crossed) samples_.flags[r.last_sample] |= sample_flag::crossed;
      finalize(id, r.last_sample);
    }
  }

  // ---- diffraction fans ----

  void spawn_fans(std::int32_t j) {
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
    if (!pending_.empty()) apply_insertions();
  }

  bool try_spawn(std::size_t s, std::int32_t live_id, std::int32_t dead_id, int side, std::size_t pos, std::int32_t j) {
    const PierheadSite site = sites_[s];
    // Copies: rays_ grows while the fan is traced.
    const Ray b = rays_[std::size_t(live_id)];
    const Ray a = rays_[std::size_t(dead_id)];
    const double dx = std::cos(b.st.theta), dy = std::sin(b.st.theta);
    const double nx = -dy, ny = dx;  // b's left
    const double mx = site.x - b.st.x, my = site.y - b.st.y;
    const double lateral = side * (mx * nx + my * ny);  // > 0: M is on the dead ray's side
    const double hit_lateral = side * ((a.hit_x - b.st.x) * nx + (a.hit_y - b.st.y) * ny);
    if (!(lateral > 0.0) || lateral > hit_lateral + site.radius + 1e-9) return false;
    if (!(side * (site.ux * nx + site.uy * ny) > 0.0)) return false;  // the wall runs towards the dead ray
    if (mx * dx + my * dy > 0.0) return false;                          // b has not passed M yet
    // The fan sweeps from b's direction towards the wall, through the shadow.
    const double theta_wall = std::atan2(site.uy, site.ux);
    double span = side * (theta_wall - b.st.theta);
    span = span - two_pi * std::floor(span / two_pi);
    if (!(span > 1e-6 && span < pi)) return false;

    Fan f;
    f.site = site;
    f.wave_m = wave_at(medium_, site.x, site.y, b.w.kh);
    const auto frame = make_breakwater_frame(Breakwater{site.x, site.y, site.ux, site.uy}, dx, dy, two_pi / f.wave_m.k);
    if (!frame.ok()) return false;
    f.frame = frame.value();
    f.theta0 = f.frame.theta0;
    f.v_scale = std::sqrt(4.0 * f.wave_m.k / pi);
    const double along = mx * dx + my * dy;  // <= 0: M is behind b's wavefront position
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
    ++stats_.fans;

    const int n = std::max(1, int(std::ceil(span / fan_spacing)));
    std::vector<std::int32_t> ids;
    for (int i = 0; i <= n; ++i) {
      if (rays_.size() >= set_.max_rays) {
        ++stats_.insertions_refused;
        truncated_ = true;
        break;
      }
      const double psi = b.st.theta + side * span * double(i) / double(n);
      ids.push_back(trace_diffracted(fan_index, psi, j, -1.0, -1, -1));
    }
    // Between the live ray and the dead one: the ray parallel to b next to b.
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
    ++stats_.rays;
    ++stats_.diffracted_rays;
    {
      Ray& r = rays_.back();
      r.family = fan;
      r.theta0 = psi;
      r.parent_a = pa;
      r.parent_b = pb;
      r.flags = ray_flag::diffracted;
      r.st = RayState{f.ox, f.oy, psi, f.phi_o, 0.0, f.tau_o};
      r.w = wave_at(medium_, f.ox, f.oy, f.wave_m.kh);
      r.a_geo = f.a_m * std::sqrt(f.wave_m.cg / r.w.cg);
      r.cg_prev = r.w.cg;
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
      if (!move_ray(id, grid_phase(jj) - rays_[std::size_t(id)].st.phi)) {
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
    const double d_end = std::hypot(catch_.back().st.x - f.site.x, catch_.back().st.y - f.site.y);
    const double a_end_shoaled = f.a_m * std::sqrt(f.wave_m.cg / catch_.back().w.cg);
    const double ramp = a_target >= 0.0 && reached_j && a_end_shoaled > 0.0 ? a_target / a_end_shoaled - 1.0 : 0.0;
    double a = f.a_m * std::sqrt(f.wave_m.cg / catch_.front().w.cg);
    double prev_factor = 1.0;
    for (std::size_t i = 0; i < catch_.size(); ++i) {
      const CatchUp& c = catch_[i];
      if (i > 0) a *= std::sqrt(catch_[i - 1].w.cg / c.w.cg);
      const double d = std::hypot(c.st.x - f.site.x, c.st.y - f.site.y);
      const double factor = 1.0 + ramp * (d_end > 0.0 ? std::min(d / d_end, 1.0) : 1.0);
      a *= factor / prev_factor;
      prev_factor = factor;
      r.w = c.w;
      r.a_geo = std::min(a, set_.max_refraction_coefficient * train_.amplitude * shoaling_coefficient(c.w.kh));
      write_sample(id, c.st, c.w, c.flags);
      finalize(id, r.last_sample);
      a = r.a_geo;  // breaking may have dissipated some
    }
    r.st = catch_.back().st;
    r.w = catch_.back().w;
    r.a_prev = r.a_geo;
    r.cg_prev = r.w.cg;
    r.alive = alive;
    if (!alive) return id;
    any_alive_ = true;
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
    std::vector<std::int32_t> merged;
    merged.reserve(order_.size() + 64);
    std::size_t p = 0;
    for (std::size_t i = 0; i < order_.size(); ++i) {
      merged.push_back(order_[i]);
      for (; p < pending_.size() && pending_[p].after == i; ++p) merged.insert(merged.end(), pending_[p].ids.begin(), pending_[p].ids.end());
    }
    order_.swap(merged);
    pending_.clear();
  }

  bool insert_rays(std::int32_t j) {
    const double b_max = set_.insertion_distance;
    for (std::size_t i = 0; i + 1 < order_.size(); ++i) {
      const std::int32_t ia = order_[i], ib = order_[i + 1];
      const Ray& a = rays_[std::size_t(ia)];
      const Ray& b = rays_[std::size_t(ib)];
      if (!live_on_step(a) || !live_on_step(b)) continue;
      const double sigma = spacing(a, b);
      if (!(sigma > b_max)) continue;
      if (a.crossed_with == ib || (a.tube_next == ib && a.tube_crossed)) continue;
      if (rays_.size() >= set_.max_rays) {
        ++stats_.insertions_refused;
        truncated_ = true;
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
      ++stats_.inserted_rays;
      pending_.push_back(Pending{i, {id}});
    }
    if (pending_.empty()) return false;
    apply_insertions();
    return true;
  }

  // A ray between two live neighbours on the current wavefront (physics.md 2.4).
  std::int32_t insert_midpoint(std::int32_t ia, std::int32_t ib, std::int32_t j) {
    const std::int32_t id = std::int32_t(rays_.size());
    rays_.emplace_back();
    ++stats_.rays;
    Ray& r = rays_.back();
    const Ray& a = rays_[std::size_t(ia)];
    const Ray& b = rays_[std::size_t(ib)];
    r.parent_a = ia;
    r.parent_b = ib;
    r.family = a.family == b.family ? a.family : -1;
    r.flags = std::uint8_t(a.flags & b.flags & (ray_flag::broken | ray_flag::diffracted));
    if (r.family < 0) r.flags &= std::uint8_t(~ray_flag::diffracted);
    const double x = 0.5 * (a.st.x + b.st.x), y = 0.5 * (a.st.y + b.st.y);
    const double theta = std::atan2(std::sin(a.st.theta) + std::sin(b.st.theta), std::cos(a.st.theta) + std::cos(b.st.theta));
    r.st = RayState{x, y, theta, grid_phase(j), 0.5 * (a.st.s + b.st.s), 0.5 * (a.st.tau + b.st.tau)};
    r.theta0 = theta;
    r.first_step = j;
    r.joined = true;
    r.fresh = true;
    const bool in_wall = first_wall_hit(capsules_, x, y, x, y).hit;
    if (in_wall || !(floor_.depth(x, y) > h_min_)) {
      // The parents straddle a wall or a spit of land: the new ray is a cut, with no samples.
      r.alive = false;
      r.joined = false;
      r.flags |= ray_flag::dead | (in_wall ? ray_flag::hit_wall : ray_flag::reached_shore);
      return id;
    }
    r.w = wave_at(medium_, x, y, 0.5 * (a.w.kh + b.w.kh));
    r.a_geo = 0.5 * (a.a_geo + b.a_geo);
    r.a_prev = r.a_geo;
    r.cg_prev = r.w.cg;
    write_sample(id, r.st, r.w, 0);
    finalize(id, rays_[std::size_t(id)].last_sample);
    any_alive_ = true;
    return id;
  }

  // ---- tubes ----

  void record_tubes() {
    const std::size_t n = order_.size();
    for (std::size_t i = 0; i < n; ++i) {
      Ray& a = rays_[std::size_t(order_[i])];
      const std::int32_t next = i + 1 < n ? order_[i + 1] : -1;
      if (next < 0 || !live_on_step(a) || !live_on_step(rays_[std::size_t(next)])) {
        a.tube_next = -1;
        a.tube_crossed = false;
        continue;
      }
      const Ray& b = rays_[std::size_t(next)];
      const double sigma = spacing(a, b);
      const bool crossed = a.crossed_with == next || sigma <= 0.0;
      a.tube_next = next;
      a.tube_sigma = sigma;
      a.tube_b = crossed ? 0.0 : tube_width(a, b, sigma);
      a.tube_crossed = crossed;
      if (!crossed && a.last_sample < samples_.size() && samples_.ray[a.last_sample] == order_[i] &&
          b.last_sample < samples_.size() && !(samples_.flags[a.last_sample] & sample_flag::off_grid) &&
          !(samples_.flags[b.last_sample] & sample_flag::off_grid)) {
        samples_.flags[a.last_sample] |= sample_flag::tube_next;
      }
    }
  }

  // ---- output ----

  WaveRays finish(WaveRays& out, DwtStats& stats) {
    const std::size_t nr = order_.size();
    std::vector<std::int32_t> rank(rays_.size(), -1);
    for (std::size_t i = 0; i < nr; ++i) rank[std::size_t(order_[i])] = std::int32_t(i);
    out.sample_begin.assign(nr + 1, 0);
    for (std::size_t s = 0; s < samples_.size(); ++s) ++out.sample_begin[std::size_t(rank[std::size_t(samples_.ray[s])]) + 1];
    for (std::size_t i = 0; i < nr; ++i) out.sample_begin[i + 1] += out.sample_begin[i];
    const std::size_t ns = samples_.size();
    out.x.resize(ns);
    out.y.resize(ns);
    out.theta.resize(ns);
    out.k.resize(ns);
    out.amplitude.resize(ns);
    out.phase.resize(ns);
    out.time.resize(ns);
    out.sample_flags.resize(ns);
    std::vector<std::uint32_t> cursor(out.sample_begin.begin(), out.sample_begin.end() - 1);
    for (std::size_t s = 0; s < ns; ++s) {
      const std::size_t d = cursor[std::size_t(rank[std::size_t(samples_.ray[s])])]++;
      out.x[d] = samples_.x[s];
      out.y[d] = samples_.y[s];
      out.theta[d] = samples_.theta[s];
      out.k[d] = samples_.k[s];
      out.amplitude[d] = samples_.amplitude[s];
      out.phase[d] = samples_.phase[s];
      out.time[d] = samples_.time[s];
      out.sample_flags[d] = samples_.flags[s];
    }
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
    stats_.truncated = stats_.truncated || truncated_;
    stats = stats_;
    return std::move(out);
  }

  struct CatchUp {
    RayState st;
    LocalWave w;
    std::uint8_t flags;
  };

  const Scene& scene_;
  const DwtSettings& set_;
  Bathymetry floor_;
  const WaveTrain& train_;
  double h_min_ = 0.0, path_max_ = 0.0;
  Medium medium_{};
  Front front_{};
  std::vector<Capsule> capsules_;
  std::vector<PierheadSite> sites_;
  std::vector<bool> site_used_;
  std::vector<Fan> fans_;
  std::vector<Ray> rays_;
  std::vector<std::int32_t> order_;
  std::vector<Pending> pending_;
  std::vector<CatchUp> catch_;
  std::vector<std::uint8_t> pair_ok_, pair_crossed_;
  std::vector<double> pair_b_prev_, pair_b_now_;
  SampleStore samples_;
  DwtStats stats_{};
  std::int64_t first_step_ = 0;
  bool any_alive_ = false;
  bool truncated_ = false;
};

Expected<Scene> checked(const Scene& scene, const DwtSettings& settings) {
  Scene copy = scene;
  copy.dwt = settings;
  return validate(std::move(copy));
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
  insertions_refused += o.insertions_refused;
  truncated = truncated || o.truncated;
  return *this;
}

bool scene_has_pierheads(const Scene& scene) noexcept {
  if (!scene.dwt.diffraction || scene.walls.empty()) return false;
  const Bathymetry floor(scene.floor);
  // h_min is per train; the smallest possible (min_depth) keeps this a safe over-estimate.
  return !detail::pierhead_sites(scene, floor, scene.dwt.min_depth).empty();
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
  const double steps = detail::path_limit(scene.domain) * detail::wave_from_depth(m, h_min, 0.0).k / f.dphi + 4.0;
  const double worst = double(settings.max_rays) * steps;
  b.samples = std::size_t(std::min(double(settings.max_samples), worst));
  return b;
}

Expected<WaveRays> trace_train(const Scene& scene, std::size_t train, const DwtSettings& settings, DwtStats* stats) {
  auto valid = detail::checked(scene, settings);
  if (!valid.ok()) return valid.error();
  if (train >= scene.trains.size()) {
    return Error{"trains", "an index below " + std::to_string(scene.trains.size()) + ", got " + std::to_string(train)};
  }
  DwtStats local;
  DwtStats& st = stats ? *stats : local;
  st = DwtStats{};
  if (!train_needs_rays(scene, train)) {
    // Effect plan: straight crests, analytic phase, no rays.
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
  detail::TrainTracer tracer(valid.value(), train, valid->dwt);
  return tracer.run(st);
}

Expected<WaveField> trace_wave_field(const Scene& scene, unsigned threads) {
  return trace_wave_field(scene, scene.dwt, threads);
}

Expected<WaveField> trace_wave_field(const Scene& scene, const DwtSettings& settings, unsigned threads) {
  auto valid = detail::checked(scene, settings);
  if (!valid.ok()) return valid.error();
  const std::size_t n = scene.trains.size();
  std::vector<std::optional<Expected<WaveRays>>> results(n);
  std::vector<DwtStats> stats(n);
  auto work = [&](std::size_t first, std::size_t step) {
    for (std::size_t i = first; i < n; i += step) results[i].emplace(trace_train(valid.value(), i, settings, &stats[i]));
  };
  const std::size_t workers = std::min<std::size_t>(std::max(1u, threads), n);
  if (workers <= 1) {
    work(0, 1);
  } else {
    // Trains are independent and each is traced sequentially: the result does not depend on the
    // thread count.
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(work, t, workers);
    work(0, workers);
    for (std::thread& t : pool) t.join();
  }
  WaveField field;
  for (std::size_t i = 0; i < n; ++i) {
    if (!results[i]->ok()) return results[i]->error();
    field.trains.push_back(std::move(*results[i]).value());
    field.stats += stats[i];
  }
  return field;
}

}  // namespace houle
