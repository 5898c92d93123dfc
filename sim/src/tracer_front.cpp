// The train's entry front, shared by dwt_bound and the tracer, and the tracer's set-up: its medium,
// the walls' box, and the initial rays on their first samples.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "houle/sim/dispersion.hpp"
#include "clip_line.hpp"
#include "train_tracer.hpp"

namespace houle::detail {

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

namespace {

// The domain as the train sees it: along its direction of travel from a_min to a_max, across it
// (to the left) the front from c_lo, `width` wide, with `rays` initial rays.
struct FrontSpan {
  double a_min = inf, a_max = -inf, c_lo = inf, width = 0.0;
  std::size_t rays = 0;
};

FrontSpan front_span(const Domain& d, double dx, double dy, const DwtSettings& set) {
  const double lx = -dy, ly = dx;  // left of the direction of travel
  FrontSpan s;
  double c_hi = -inf;
  for (double x : {d.x_min, d.x_max}) {
    for (double y : {d.y_min, d.y_max}) {
      s.a_min = std::min(s.a_min, x * dx + y * dy);
      s.a_max = std::max(s.a_max, x * dx + y * dy);
      s.c_lo = std::min(s.c_lo, x * lx + y * ly);
      c_hi = std::max(c_hi, x * lx + y * ly);
    }
  }
  s.width = c_hi - s.c_lo;
  if (set.front_width > 0.0 && set.front_width < s.width) {
    const double mid = 0.5 * (s.c_lo + c_hi);
    s.c_lo = mid - 0.5 * set.front_width;
    s.width = set.front_width;
  }
  // Automatic count: spacing strictly below b_max, so a flat bottom needs no insertion at all
  // (validate refuses a count over dwt.max_rays; the clamp keeps the conversion defined).
  const double automatic = std::min(std::floor(s.width / set.insertion_distance) + 1.0, 0x1p40);
  s.rays = set.initial_rays > 0 ? set.initial_rays : std::max<std::size_t>(2, std::size_t(automatic));
  return s;
}

}  // namespace

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
  const FrontSpan span = front_span(d, f.dx, f.dy, set);
  const double a_min = span.a_min, c_lo = span.c_lo, width = span.width;
  const std::size_t n = span.rays;
  f.entries.resize(n);
  f.k_ref = std::numeric_limits<double>::infinity();
  // The sea outside the domain is open, but a wall that runs out beyond its edge shadows the part of
  // the front behind it: an entry whose straight path from well upstream (a domain diagonal back)
  // crosses a wall is dead. Only walls reaching the edge can lie on such a path.
  std::vector<Capsule> outside;
  for (const Capsule& c : wall_capsules(scene.walls)) {
    if (std::min(c.ax, c.bx) - c.radius <= d.x_min || std::max(c.ax, c.bx) + c.radius >= d.x_max ||
        std::min(c.ay, c.by) - c.radius <= d.y_min || std::max(c.ay, c.by) + c.radius >= d.y_max) {
      outside.push_back(c);
    }
  }
  const double upstream = dist(d.x_max - d.x_min, d.y_max - d.y_min);
  for (std::size_t i = 0; i < n; ++i) {
    // Rays centred in n equal strips of the front, so none runs exactly along a domain edge.
    const double c = c_lo + (double(i) + 0.5) * width / double(n);
    const double px = a_min * f.dx + c * lx, py = a_min * f.dy + c * ly;
    double t0 = 0.0, t1 = 0.0;
    Entry& e = f.entries[i];
    if (!clip_line(d, px, py, f.dx, f.dy, t0, t1)) continue;
    e.x = px + t0 * f.dx;
    e.y = py + t0 * f.dy;
    if (!outside.empty() && wall_blocks(outside, e.x - upstream * f.dx, e.y - upstream * f.dy, e.x, e.y)) {
      e.behind_wall = true;
      continue;
    }
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

TrainTracer::TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, ThreadPool* pool)
    : scene_(scene), set_(set), floor_(scene.floor), train_index_(train), train_(scene.trains[train]), pool_(pool) {
  init_medium();
  front_ = make_front(scene, train, set, medium_);
  set_step(front_.dphi);
  marched_ = scene_wave_model(scene).kind == WaveModelKind::parabolic;
  marched_budget_ = marched_ray_factor * front_.entries.size();
}

void TrainTracer::init_medium() {
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

void TrainTracer::set_step(double dphi) noexcept {
  if (!medium_.uniform) return;
  uniform_a_break_ = breaking_limit(medium_.uniform_wave);
  medium_.step_dphi = dphi;
  medium_.step_ds = dphi / medium_.uniform_wave.k;
  medium_.step_dtau = medium_.step_ds / medium_.uniform_wave.cg;
}

void TrainTracer::start_front() {
  first_step_ = std::numeric_limits<std::int64_t>::max();
  for (const Entry& e : front_.entries) {
    const std::int32_t id = std::int32_t(rays_.size());
    rays_.emplace_back();
    Ray& r = rays_.back();
    order_.push_back(id);
    ++main_.stats.initial_rays;
    ++main_.stats.rays;
    if (!e.water) {
      // Enters on land or behind a wall (or separates two walls' reflections): a cut in the front,
      // with no samples.
      r.alive = false;
      if (e.behind_wall) {
        r.flags = ray_flag::dead | ray_flag::hit_wall;
        ++main_.stats.wall_hits;
      } else {
        r.flags = reflected_ ? ray_flag::dead : ray_flag::dead | ray_flag::reached_shore;
        if (!reflected_) ++main_.stats.reached_shore;
      }
      continue;
    }
    r.st = RayState{e.x, e.y, e.theta, e.phi, 0.0, e.tau};
    r.sync_direction();
    r.home_x = r.cos_t;
    r.home_y = r.sin_t;
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

}  // namespace houle::detail

namespace houle {

FrontSize front_size(const Scene& scene, std::size_t train, const DwtSettings& settings) noexcept {
  const Point2 dir = train_direction(scene.trains[train]);
  const detail::FrontSpan s = detail::front_span(scene.domain, dir.x, dir.y, settings);
  return {s.width, s.a_max - s.a_min, s.rays, {s.a_min * dir.x - s.c_lo * dir.y, s.a_min * dir.y + s.c_lo * dir.x}};
}

}  // namespace houle
