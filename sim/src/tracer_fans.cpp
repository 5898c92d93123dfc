// Diffraction fans ([GL98] 2.2.1): where the front passes a pierhead, DIFFRACTED rays spread from it
// into the shadow, each traced up to the current wavefront.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "train_tracer.hpp"

namespace houle::detail {
namespace {

constexpr double fan_spacing = pi / 8.0;   // rad between a fan's first rays (refined by insertion)

}  // namespace

// True if a fan was inserted into order_.
bool TrainTracer::spawn_fans(std::int32_t j) {
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
bool TrainTracer::try_spawn(std::size_t s, std::int32_t live_id, std::int32_t dead_id, int side, std::size_t pos,
                            std::int32_t j) {
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
std::int32_t TrainTracer::trace_diffracted(std::int32_t fan, double psi, std::int32_t j, double a_target,
                                           std::int32_t pa, std::int32_t pb) {
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

}  // namespace houle::detail
