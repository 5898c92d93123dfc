// Ray insertion (docs/physics.md 2.4): a ray between live neighbours that have drifted farther apart
// than the insertion distance, and the new rays' places in the wavefront's order.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "train_tracer.hpp"

namespace houle::detail {

// pending_ is in order of `after` (insert_rays walks the front in order).
void TrainTracer::apply_insertions() {
  merged_.clear();
  std::size_t p = 0;
  for (std::size_t i = 0; i < order_.size(); ++i) {
    merged_.push_back(order_[i]);
    for (; p < pending_.size() && pending_[p].after == i; ++p) merged_.push_back(pending_[p].id);
  }
  order_.swap(merged_);
  pending_.clear();
}

// One pass over the wavefront: a ray between every sound live pair farther apart than b_max.
bool TrainTracer::insert_rays(std::int32_t j) {
  const double b_max = set_.insertion_distance;
  if (!(main_.widest > b_max)) return false;
  for (std::size_t i = 0; i + 1 < order_.size(); ++i) {
    if (!pair_real_[i] || !(pair_sigma_[i] > b_max)) continue;  // not two live rays, or close enough
    const std::int32_t ia = order_[i], ib = order_[i + 1];
    if (rays_[std::size_t(ia)].crossed_with == ib) continue;  // never between crossed rays (docs/physics.md 2.4)
    if (marched_ && rays_.size() >= marched_budget_) continue;  // the carrier march fills the gaps
    if (rays_.size() >= set_.max_rays) {
      ++main_.stats.insertions_refused;
      main_.truncated = true;
      continue;
    }
    const std::int32_t id = insert_midpoint(ia, ib, j);
    ++main_.stats.inserted_rays;
    pending_.push_back(Pending{i, id});
  }
  if (pending_.empty()) return false;
  apply_insertions();
  return true;
}

// A ray between two live neighbours on the current wavefront (docs/physics.md 2.4): midpoint, bisecting
// direction, mean amplitude; flags only where both parents share them.
std::int32_t TrainTracer::insert_midpoint(std::int32_t ia, std::int32_t ib, std::int32_t j) {
  const std::int32_t id = std::int32_t(rays_.size());
  rays_.emplace_back();
  ++main_.stats.rays;
  Ray& r = rays_.back();
  const Ray& a = rays_[std::size_t(ia)];
  const Ray& b = rays_[std::size_t(ib)];
  r.parent_a = ia;
  r.parent_b = ib;
  r.flags = std::uint8_t(a.flags & b.flags & ray_flag::broken);
  const double x = 0.5 * (a.st.x + b.st.x), y = 0.5 * (a.st.y + b.st.y);
  const double theta = std::atan2(a.sin_t + b.sin_t, a.cos_t + b.cos_t);
  r.st = RayState{x, y, theta, grid_phase(j), 0.5 * (a.st.s + b.st.s), 0.5 * (a.st.tau + b.st.tau)};
  r.sync_direction();
  const double hx = a.home_x + b.home_x, hy = a.home_y + b.home_y, h = std::hypot(hx, hy);
  if (h > 0.0) r.home_x = hx / h, r.home_y = hy / h;
  r.first_step = j;
  r.joined = true;
  r.fresh = true;
  const bool in_wall = !capsules_.empty() && wall_blocks(capsules_, x, y, x, y);
  if (in_wall || !(floor_.depth(x, y) > h_min_)) {
    // The parents straddle a wall or a spit of land: the new ray is a cut, with no samples.
    r.alive = false;
    r.joined = false;
    r.flags |= ray_flag::dead | (in_wall ? ray_flag::hit_wall : ray_flag::reached_shore);
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

}  // namespace houle::detail
