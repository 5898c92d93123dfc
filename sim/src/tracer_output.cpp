// The tracer's runs and their output: the staged samples gathered into one WaveRays block per train.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include "train_tracer.hpp"

namespace houle::detail {

WaveRays TrainTracer::run(DwtStats& stats) {
  sweep();
  return finish(stats, [] {});
}

WaveRays TrainTracer::run_reflecting(DwtStats& stats, WaveRays& reflected, DwtStats& reflected_stats) {
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

// The output, and `also` run beside the gather on the second lane when there is one (the first
// task it takes), or after it.
template <class Also>
WaveRays TrainTracer::finish(DwtStats& stats, const Also& also) {
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
  const std::size_t at_flags = layout.add<std::uint8_t>(ns);
  std::shared_ptr<std::byte[]> block = layout.allocate();
  double* arrays[n_doubles];
  for (std::size_t i = 0; i < n_doubles; ++i) arrays[i] = BulkLayout::at<double>(block.get(), at[i]);
  auto* flags = BulkLayout::at<std::uint8_t>(block.get(), at_flags);
  out.x = {arrays[0], ns};
  out.y = {arrays[1], ns};
  out.theta = {arrays[2], ns};
  out.k = {arrays[3], ns};
  out.amplitude = {arrays[4], ns};
  out.phase = {arrays[5], ns};
  out.time = {arrays[6], ns};
  out.sample_flags = {flags, ns};
  // Per ray, its chunks into the output block, front to back; on two lanes, runs of rays of about
  // equal sample counts are taken from both ends (what a ray's output is does not depend on the
  // lane that writes it).
  const Gather g{arrays, flags};
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
    pool_->for_ranges(runs + 1, 1, [&](std::size_t c, std::size_t, unsigned) {
      if (c == runs) also();
      else gather(out, g, bound[c], bound[c + 1]);
    });
  } else {
    gather(out, g, 0, nr);
    also();
  }
  out.sample_storage = std::move(block);
  out.first_step.resize(nr);
  out.flags.resize(nr);
  out.parent_a.resize(nr);
  out.parent_b.resize(nr);
  for (std::size_t i = 0; i < nr; ++i) {
    const Ray& r = rays_[std::size_t(order_[i])];
    out.first_step[i] = r.first_step >= 0 ? r.first_step : 0;
    out.flags[i] = r.flags;
    out.parent_a[i] = r.parent_a >= 0 ? rank[std::size_t(r.parent_a)] : -1;
    out.parent_b[i] = r.parent_b >= 0 ? rank[std::size_t(r.parent_b)] : -1;
  }
  // An incident trace whose rays only seed the carrier loses nothing to a cap (reflected traces are
  // never marched: their rays are their wave).
  const bool carrier_only = marched_ && rays_only_seed_the_carrier(scene_, set_);
  main_.stats.truncated = !carrier_only && (main_.stats.truncated || main_.truncated);
  stats = main_.stats;
  return out;
}

// The staged samples of rays order_[lo, hi) into the output.
void TrainTracer::gather(const WaveRays& out, const Gather& g, std::size_t lo, std::size_t hi) const {
  // Local pointers: the byte stores of the flags could alias g's, which the compiler would
  // otherwise reload for every sample.
  double *const x = g.arrays[0], *const y = g.arrays[1], *const theta = g.arrays[2], *const k = g.arrays[3];
  double *const amplitude = g.arrays[4], *const phase = g.arrays[5], *const time = g.arrays[6];
  std::uint8_t* const flags = g.flags;
  for (std::size_t i = lo; i < hi; ++i) {
    const Ray& r = rays_[std::size_t(order_[i])];
    std::size_t t = out.sample_begin[i];
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
      t += n;
    }
  }
}

}  // namespace houle::detail
