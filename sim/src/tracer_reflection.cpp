// The reflected wave's front: seeded where the incident wave's rays ended on reflecting walls.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "houle/sim/dispersion.hpp"
#include "train_tracer.hpp"

namespace houle::detail {
namespace {

// Only rays that end on a wall, with samples, seed a reflected wave.
bool seeds_reflection(std::uint8_t flags, std::size_t samples) noexcept {
  return (flags & ray_flag::hit_wall) && samples > 0;
}

}  // namespace

// Where a train's output rays ended, for trace_reflection: as TrainTracer::ray_ends() has them.
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

TrainTracer::TrainTracer(const Scene& scene, std::size_t train, const DwtSettings& set, const std::vector<RayEnd>& ends,
                         double omega, double dx, double dy, double dphi, ThreadPool* pool)
    : scene_(scene), set_(set), floor_(scene.floor), train_index_(train), train_(scene.trains[train]), pool_(pool) {
  init_medium();
  reflected_ = true;
  front_ = reflected_front(ends, omega, dx, dy, dphi);
  set_step(dphi);
}

std::vector<RayEnd> TrainTracer::ray_ends() const {
  std::vector<RayEnd> ends(order_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const Ray& r = rays_[std::size_t(order_[i])];
    if (!seeds_reflection(r.flags, r.samples.count)) continue;
    const StagedSample& s = r.samples.last->at[(r.samples.count - 1) % SampleChunk::size];
    ends[i] = RayEnd{true, s.x, s.y, s.theta, s.phase, s.time, s.amplitude};
  }
  return ends;
}

// Seeds of the reflected wave: the end points of `incident`'s rays that hit a wall
// with alpha > 0, in reverse order (the mirror image reverses left and right), mirrored about the
// wall's normal there, with amplitude alpha A and the incident phase and time (phase continuous).
// A cut (an entry on "land": a dead ray with no samples) separates seeds whose incident rays were
// not neighbours on the same wall, so no tube joins them.
Front TrainTracer::reflected_front(const std::vector<RayEnd>& ends, double omega, double dx, double dy,
                                   double dphi) const {
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
bool TrainTracer::wall_of(double x, double y, std::uint32_t& wall) const noexcept {
  double best = std::numeric_limits<double>::infinity();
  for (const Capsule& c : capsules_) {
    const double ex = c.bx - c.ax, ey = c.by - c.ay, len2 = ex * ex + ey * ey;
    const double t = len2 > 0.0 ? std::clamp(((x - c.ax) * ex + (y - c.ay) * ey) / len2, 0.0, 1.0) : 0.0;
    const double d = std::fabs(dist(x - c.ax - t * ex, y - c.ay - t * ey) - c.radius);
    if (d < best) best = d, wall = c.wall;
  }
  return best < 1e-6;
}

}  // namespace houle::detail
