#include "houle/sim/sea_surface.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>

#include "houle/runtime/assert.hpp"
#include "houle/runtime/thread_pool.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "carrier_march.hpp"
#include "dispersion_table.hpp"
#include "parabolic_model.hpp"
#include "ray_walls.hpp"

namespace houle {
namespace {

using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * pi;
// sqrt(Q^2 + L^2) stays below this so that the first-order trochoid never folds (docs/physics.md 3.1: J > 0).
constexpr double max_fold = 0.9;
// Depth used where the floor is at or above still water (the wave is gone there anyway): keeps the
// dispersion relation and coth(kh) finite.
constexpr double min_depth = 1e-3;
// Splat weights below this count as no sample.
constexpr double min_weight = 1e-9;

/// Fold and lean per metre of amplitude of a train of steepness q and wavenumber k over depth h
/// (train_grid.hpp: Q = q k A coth kh, L = Q e^{-kh}).
void shape(double q, double k, double h, double& fold, double& lean) {
  const double kh = k * std::max(h, min_depth);
  fold = q * k / std::tanh(kh);
  lean = fold * std::exp(-kh);
}

// Straight crests upstream of the domain, in the tracer's convention: phase 0 on the wavefront
// through the domain's most upstream corner.
void set_far_field(TrainGrid& g, const Scene& scene, const WaveRays& rays, double steepness, double depth_at_entry) {
  const Domain& d = scene.domain;
  const double corners[4][2] = {{d.x_min, d.y_min}, {d.x_max, d.y_min}, {d.x_min, d.y_max}, {d.x_max, d.y_max}};
  double upstream = INFINITY;
  for (const auto& c : corners) upstream = std::min(upstream, rays.direction_x * c[0] + rays.direction_y * c[1]);
  double k, a, h = depth_at_entry;
  if (rays.analytic) {
    k = rays.analytic_k;
    a = rays.analytic_amplitude;
  } else {
    h = std::max(depth_at_entry, min_depth);
    k = linear_wave(rays.omega, h).k;
    a = rays.amplitude0 * shoaling_coefficient(k * h);
  }
  g.far_kx = float(k * rays.direction_x);
  g.far_ky = float(k * rays.direction_y);
  g.far_amplitude = float(a);
  double fold, lean;
  shape(steepness, k, h, fold, lean);
  const double norm = std::hypot(fold, lean) * a;
  const double scale = norm > max_fold ? max_fold / norm : 1.0;
  g.far_fold = float(fold * scale);
  g.far_lean = float(lean * scale);
  g.far_offset = k * upstream - rays.phase0;
}

struct GridGeometry {
  double x0, y0, cell;
  std::size_t nx, ny;
  double x(std::size_t n) const noexcept { return x0 + double(n % nx) * cell; }
  double y(std::size_t n) const noexcept { return y0 + double(n / nx) * cell; }
};

/// One ray family (the incident rays of a train, or a reflected wave) resampled onto the grid. Each
/// sample is extrapolated to the node along its wave vector and tent-weighted; the complex amplitude
/// is kept relative to the far field's phase psi at the node (any continuous reference would do) so
/// that samples of different phases add as waves. Normalised per family: where a family's rays thin
/// out, its amplitude does not fade. The family's phase at a node is the least extrapolated phase of
/// the samples there (the first branch to arrive where rays crossed: a mean of two branches' phases
/// would be neither, and jumps as the samples change), with that sample's wave vector. A sample does
/// not reach nodes across a wall (the two faces of a thin wall see different waves).
struct FamilyField {
  std::vector<double> weight, phase, re, im, kx, ky;

  template <class Keep>
  void splat(const GridGeometry& g, const TrainGrid& far, const WaveRays& rays, Keep&& keep, double radius,
             const std::vector<detail::Capsule>& walls) {
    const std::size_t nodes = g.nx * g.ny;
    for (std::vector<double>* v : {&weight, &re, &im, &kx, &ky}) v->assign(nodes, 0.0);
    phase.assign(nodes, INFINITY);
    const int reach = int(std::ceil(radius / g.cell));
    const double fkx = far.far_kx, fky = far.far_ky;
    double wall_radius = 0.0;
    for (const detail::Capsule& c : walls) wall_radius = std::max(wall_radius, c.radius);
    const double near_wall = radius + g.cell + wall_radius;
    // Per column of a sample's footprint, its tent weight and the phase the sample's wave gains from
    // the footprint's first column: the same in every row, so worked out once per sample (the splat
    // is most of a train's resampling after the carrier's march).
    std::vector<double> tent_x(std::size_t(2 * reach)), advance_x(std::size_t(2 * reach));
    for (std::size_t r = 0; r < rays.ray_count(); ++r) {
      if (!keep(r)) continue;
      for (std::size_t s = rays.sample_begin[r]; s < rays.sample_begin[r + 1]; ++s) {
        const double sx = rays.x[s], sy = rays.y[s];
        const bool check_walls = std::any_of(walls.begin(), walls.end(), [&](const detail::Capsule& c) {
          return detail::point_segment_dist2(sx, sy, c) < near_wall * near_wall;
        });
        const double gx = (sx - g.x0) / g.cell, gy = (sy - g.y0) / g.cell;
        const int ci = int(std::floor(gx)), cj = int(std::floor(gy));
        const int i0 = std::max(0, ci - reach + 1), i1 = std::min(int(g.nx) - 1, ci + reach);
        const int j0 = std::max(0, cj - reach + 1), j1 = std::min(int(g.ny) - 1, cj + reach);
        if (i0 > i1 || j0 > j1) continue;
        const double ksx = rays.k[s] * std::cos(rays.theta[s]), ksy = rays.k[s] * std::sin(rays.theta[s]);
        const double a = rays.amplitude[s];
        // Phase at node (i0, j0) relative to psi there, and its steps per node along x and y.
        const double nx0 = g.x0 + i0 * g.cell, ny0 = g.y0 + j0 * g.cell;
        const double phi0 = rays.phase[s] + ksx * (nx0 - sx) + ksy * (ny0 - sy);
        const double rel0 = phi0 - (fkx * nx0 + fky * ny0 - far.far_offset);
        const cplx z0 = std::polar(a, rel0), step_x = std::polar(1.0, (ksx - fkx) * g.cell),
                   step_y = std::polar(1.0, (ksy - fky) * g.cell);
        for (int i = i0; i <= i1; ++i) {
          tent_x[std::size_t(i - i0)] = 1.0 - std::fabs(i - gx) * g.cell / radius;
          advance_x[std::size_t(i - i0)] = ksx * (i - i0) * g.cell;
        }
        cplx row = z0;
        for (int j = j0; j <= j1; ++j, row *= step_y) {
          const double wy = 1.0 - std::fabs(j - gy) * g.cell / radius;
          if (wy <= 0.0) continue;
          const double advance_y = ksy * (j - j0) * g.cell;
          cplx z = row;
          for (int i = i0; i <= i1; ++i, z *= step_x) {
            const double wx = tent_x[std::size_t(i - i0)];
            if (wx <= 0.0) continue;
            const std::size_t n = std::size_t(j) * g.nx + std::size_t(i);
            if (check_walls && detail::wall_blocks(walls, sx, sy, g.x(n), g.y(n))) continue;
            const double w = wx * wy;
            weight[n] += w;
            re[n] += w * z.real();
            im[n] += w * z.imag();
            const double at_node = phi0 + advance_x[std::size_t(i - i0)] + advance_y;
            if (at_node < phase[n]) {
              phase[n] = at_node;
              kx[n] = ksx;
              ky[n] = ksy;
            }
          }
        }
      }
    }
    for (std::size_t n = 0; n < nodes; ++n) {
      if (weight[n] <= min_weight) continue;
      const double inv = 1.0 / weight[n];
      re[n] *= inv;
      im[n] *= inv;
    }
  }
  bool covers(std::size_t n) const noexcept { return weight[n] > min_weight; }
};

/// A pierhead as one train sees it: the incident wave there and the breakwater frame it defines.
struct Pierhead {
  detail::PierheadSite site;
  BreakwaterFrame frame;
  double amplitude, phase, k, depth;  ///< incident A_M (m), phi_M (rad), k_M (rad/m), h_M (m)
  double shadow_x, shadow_y;         ///< unit direction of the incident shadow line from M
  double mirror_x, mirror_y;         ///< unit direction of the reflected wave's shadow line from M
};

/// A pierhead's diffracted wave travels out from M along straight lines (it is not refracted: docs/
/// physics.md 9): per direction, its optical distance (the integral of k ds, through the depths it
/// crosses) and how far it goes before land or a wall stops it.
class RadialTable {
 public:
  /// Along each direction from M the grid's nearest nodes give the wavenumber (0 on land) and the
  /// depth, every `step` m.
  RadialTable(const Pierhead& p, const GridGeometry& g, const std::vector<float>& depths, const std::vector<float>& wavenumber,
              bool uniform, const std::vector<detail::Capsule>& walls, double h_min, double r_max, double step)
      : step_(step), uniform_(uniform), k_m_(p.k), samples_(std::size_t(std::ceil(r_max / step)) + 2),
        reach_(angles, float(r_max + step)) {
    if (!uniform_) phase_.assign(angles * samples_, 0.0f);
    // The segment that ends at M is the semi-infinite wall of the solution: no line from M crosses
    // it. The wall's other segments and other walls stop the wave.
    std::vector<detail::Capsule> others;
    for (const detail::Capsule& c : walls) {
      const bool own = c.wall == p.site.wall && ((c.ax == p.site.x && c.ay == p.site.y) || (c.bx == p.site.x && c.by == p.site.y));
      if (!own) others.push_back(c);
    }
    const double start = 1e-3;
    for (std::size_t a = 0; a < angles; ++a) {
      const double c = std::cos(two_pi * double(a) / angles), s = std::sin(two_pi * double(a) / angles);
      const detail::WallHit hit = detail::first_wall_hit(others, p.site.x + start * c, p.site.y + start * s,
                                                         p.site.x + r_max * c, p.site.y + r_max * s);
      double reach = hit.hit ? start + hit.u * (r_max - start) : r_max + step;
      if (!uniform_) {
        float* phase = &phase_[a * samples_];
        double sum = 0.0, k_last = k_m_;
        for (std::size_t i = 1; i < samples_ && double(i - 1) * step < reach; ++i) {
          const double r = double(i) * step;
          const long ni = std::lround((p.site.x + r * c - g.x0) / g.cell), nj = std::lround((p.site.y + r * s - g.y0) / g.cell);
          double k = k_last;
          if (ni >= 0 && nj >= 0 && ni < long(g.nx) && nj < long(g.ny)) {
            const std::size_t n = std::size_t(nj) * g.nx + std::size_t(ni);
            if (!(depths[n] > h_min)) reach = std::min(reach, r);
            k = wavenumber[n] > 0.0f ? double(wavenumber[n]) : k_last;
          }
          sum += 0.5 * (k_last + k) * step;
          k_last = k;
          phase[i] = float(sum);
        }
      }
      reach_[a] = float(reach);
    }
  }
  /// Optical distance to (dx, dy) from M, or false where the wave does not go.
  bool optical_distance(double dx, double dy, double r, double& k_r) const noexcept {
    double u = std::atan2(dy, dx) / two_pi * angles;
    if (u < 0.0) u += angles;
    const std::size_t a0 = std::size_t(u) % angles, a1 = (a0 + 1) % angles;
    const double t = u - std::floor(u);
    if (r > double(t < 0.5 ? reach_[a0] : reach_[a1])) return false;
    if (uniform_) {
      k_r = k_m_ * r;
      return true;
    }
    const double v = std::min(r / step_, double(samples_ - 1) - 1e-9);
    const std::size_t i = std::size_t(v);
    const double w = v - double(i);
    const auto at = [&](std::size_t a) {
      const float* phase = &phase_[a * samples_];
      return double(phase[i]) + (double(phase[i + 1]) - double(phase[i])) * w;
    };
    k_r = at(a0) + (at(a1) - at(a0)) * t;
    return true;
  }

 private:
  static constexpr std::size_t angles = 2048;
  double step_;
  bool uniform_;
  double k_m_;
  std::size_t samples_;
  std::vector<float> phase_;  ///< angles x samples: optical distance at r = i step
  std::vector<float> reach_;  ///< per direction, m
};

/// A pierhead seen from one node.
struct PierheadView {
  BreakwaterPolar polar;
  bool reached = false;    ///< the diffracted wave gets here (no land or wall on the way)
  double k_r = 0.0;        ///< rad, optical distance from M
  double amplitude = 0.0;  ///< m, the incident amplitude at M shoaled to the node
};

/// The incident wave at M from the incident family's nodes around it (M itself is on the wall),
/// extrapolated along their wave vectors; false if no incident ray came near M (it is in the shadow
/// of another structure or on land: no diffraction there, one order only).
bool incident_at(const GridGeometry& g, const FamilyField& inc, double mx, double my, double radius,
                 double& amplitude, double& phase, double& kx, double& ky) {
  const int reach = int(std::ceil(2.0 * radius / g.cell));
  const int ci = int(std::floor((mx - g.x0) / g.cell)), cj = int(std::floor((my - g.y0) / g.cell));
  double w_sum = 0.0, a = 0.0, p = 0.0, qx = 0.0, qy = 0.0;
  for (int j = std::max(0, cj - reach); j <= std::min(int(g.ny) - 1, cj + reach); ++j) {
    for (int i = std::max(0, ci - reach); i <= std::min(int(g.nx) - 1, ci + reach); ++i) {
      const std::size_t n = std::size_t(j) * g.nx + std::size_t(i);
      if (!inc.covers(n)) continue;
      const double dx = mx - g.x(n), dy = my - g.y(n);
      const double w = 1.0 / (std::hypot(dx, dy) + g.cell);
      w_sum += w;
      a += w * std::hypot(inc.re[n], inc.im[n]);
      p += w * (inc.phase[n] + inc.kx[n] * dx + inc.ky[n] * dy);
      qx += w * inc.kx[n];
      qy += w * inc.ky[n];
    }
  }
  if (w_sum <= 0.0 || !(a > 0.0)) return false;
  amplitude = a / w_sum;
  phase = p / w_sum;
  kx = qx / w_sum;
  ky = qy / w_sum;
  return std::hypot(kx, ky) > 0.0;
}

// Where a semi-infinite wall's geometric optics ends (s1 < 0, s2 < 0 in diffraction.hpp); the masks
// and the diffracted waves must decide a point on a shadow line alike.
bool in_shadow(const BreakwaterPolar& p) noexcept { return p.theta - p.theta0 > pi; }
bool beyond_reflection(const BreakwaterPolar& p) noexcept { return p.theta + p.theta0 > pi; }

/// Distance from P to the half-line from M along (dx, dy), if P lies beyond M along it; else +inf.
double from_half_line(double px, double py, double mx, double my, double dx, double dy) noexcept {
  const double along = (px - mx) * dx + (py - my) * dy;
  return along > 0.0 ? std::fabs((px - mx) * dy - (py - my) * dx) : INFINITY;
}

}  // namespace

/// The per-node arrays one train's resampling works in, one set per thread of the build, sized by
/// the first train it resamples and refilled, not reallocated, for the next: fresh arrays per train
/// cost the buoy scene's 32 trains a third of the build in page faults and zeroing. resample()
/// refills each before it reads it, so a train's grid does not depend on the trains the thread did
/// before (nor on which thread took it).
struct SeaSurface::ResampleScratch {
  FamilyField incident;
  std::vector<FamilyField> reflections;  ///< as many as the most reflected waves of a train so far
  std::vector<float> wavenumber, kh_at;
  std::vector<cplx> sums;
  std::vector<std::uint8_t> has_wave, near_wall;
  std::vector<double> carrier, carrier_kx, carrier_ky, reference, magnitude;
  std::vector<std::uint32_t> queue;
  detail::CarrierMarchScratch march;
};

Expected<SeaSurface> SeaSurface::build(const Scene& scene, const WaveField& field, float cell, SeaParts parts,
                                       unsigned threads) {
  if (!(cell > 0.0f)) return Error{"cell", "a resampling cell > 0 m"};
  if (field.trains.size() != scene.trains.size()) return Error{"field", "one traced train per scene train"};
  const std::size_t count = field.trains.size();
  if (count > TrainGridFrame::max_trains) {
    return Error{"trains", "at most " + std::to_string(TrainGridFrame::max_trains) + " wave trains, got " + std::to_string(count)};
  }
  for (const ReflectedWave& r : field.reflections) {
    if (r.train >= count) return Error{"field", "a reflected wave of a train the scene has"};
  }
  SeaSurface s;
  s.parts_ = parts;
  const Bathymetry floor(scene.floor);
  const Domain& d = scene.domain;
  s.trains_.resize(count);
  s.grids_.resize(count);
  std::vector<std::size_t> traced;
  std::vector<float> b_max(count, 0.0f);
  for (std::size_t t = 0; t < count; ++t) {
    const WaveRays& rays = field.trains[t];
    TrainField& f = s.trains_[t];
    TrainGrid& g = s.grids_[t];
    s.amplitude0_.push_back(float(scene.trains[t].amplitude));
    f.omega = rays.omega;
    f.phase = scene.trains[t].phase;
    set_far_field(g, scene, rays, scene.trains[t].steepness, detail::entry_depth(scene, floor, rays.direction_x, rays.direction_y));
    b_max[t] = g.far_amplitude;
    if (rays.analytic) continue;
    const double nx = std::ceil((d.x_max - d.x_min) / cell) + 1, ny = std::ceil((d.y_max - d.y_min) / cell) + 1;
    if (!(nx * ny < 2147483648.0)) return Error{"cell", "a resampling grid of fewer than 2^31 nodes over the domain"};
    g.origin_x = float(d.x_min);
    g.origin_y = float(d.y_min);
    g.cell = cell;
    g.nx = std::uint32_t(nx);
    g.ny = std::uint32_t(ny);
    traced.push_back(t);
  }
  // The floor under the grid, shared by every traced train; then the trains, each on its own (on
  // up to `threads` threads: a train's grid depends on nothing but its own rays).
  std::vector<float> depths;
  if (!traced.empty()) {
    const TrainGrid& g = s.grids_[traced.front()];
    depths.resize(std::size_t(g.nx) * g.ny);
    for (std::size_t n = 0; n < depths.size(); ++n) {
      depths[n] = float(floor.depth(double(g.origin_x) + double(n % g.nx) * cell, double(g.origin_y) + double(n / g.nx) * cell));
    }
  }
  std::vector<DiffractionWork> work(count);
  std::unique_ptr<detail::ThreadPool> pool;
  if (threads > 1 && traced.size() > 1) {
    Expected<std::unique_ptr<detail::ThreadPool>> made = detail::ThreadPool::create(std::min(threads, unsigned(traced.size())));
    if (!made) return made.error();
    pool = std::move(made).value();
  }
  std::vector<ResampleScratch> scratch(pool ? pool->size() : 1);
  const auto resample_trains = [&](std::size_t begin, std::size_t end, unsigned lane) noexcept {
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t t = traced[i];
      std::vector<const WaveRays*> reflected;
      for (const ReflectedWave& r : field.reflections) {
        if (r.train == t) reflected.push_back(&r.rays);
      }
      b_max[t] = s.resample(t, scene, floor, depths, field.trains[t], reflected, parts, work[t], scratch[lane]);
    }
  };
  if (pool) {
    pool->for_ranges(traced.size(), 1, resample_trains);
  } else {
    resample_trains(0, traced.size(), 0);
  }
  for (std::size_t t = 0; t < count; ++t) {
    s.height_bound_ += b_max[t];
    s.diffraction_work_.pierheads += work[t].pierheads;
    s.diffraction_work_.evaluations += work[t].evaluations;
  }
  s.frame_.count = std::uint32_t(s.grids_.size());
  s.frame_.trains = s.grids_.data();
  s.set_time(0.0);
  return s;
}

float SeaSurface::resample(std::size_t t, const Scene& scene, const Bathymetry& floor, const std::vector<float>& depths,
                           const WaveRays& rays, const std::vector<const WaveRays*>& reflected, SeaParts parts,
                           DiffractionWork& work, ResampleScratch& scratch) {
  TrainField& f = trains_[t];
  TrainGrid& g = grids_[t];
  const GridGeometry geo{g.origin_x, g.origin_y, g.cell, g.nx, g.ny};
  const std::size_t nodes = geo.nx * geo.ny;
  const double radius = std::max({scene.dwt.step, scene.dwt.insertion_distance, 2.0 * double(g.cell)});
  const double steepness = scene.trains[t].steepness;
  const DiffractionModel model = scene.dwt.diffraction_model;
  // Geometric-optics edges are sharpened within this distance of a shadow line (the splat has
  // carried each family up to `radius` past its last ray).
  const double band = 2.0 * radius + 2.0 * double(g.cell);

  const std::vector<detail::Capsule> walls = detail::wall_capsules(scene.walls);
  const std::vector<detail::PierheadSite> sites =
      scene.dwt.diffraction ? detail::pierhead_sites(scene, floor, rays.min_depth) : std::vector<detail::PierheadSite>{};
  FamilyField& incident = scratch.incident;
  incident.splat(geo, g, rays, [](std::size_t) { return true; }, radius, walls);
  // The parabolic model's field replaces the incident rays and the pierheads' diffraction of the
  // incident wave (it diffracts by itself); the rays still seed the carrier, give the reflected waves
  // and K''s reference (docs/physics.md 10.6).
  std::optional<detail::ParabolicField> marched;
  if (scene_wave_model(scene).kind == WaveModelKind::parabolic) {
    detail::ParabolicTrain pt = detail::parabolic_train(scene, floor, t);
    pt.far_offset = g.far_offset;
    Expected<detail::ParabolicField> m = detail::march_parabolic(scene, floor, pt);
    HOULE_ASSERT(m.ok(), "SeaSurface: a traced train has a wave to march");
    marched = std::move(m).value();
    f.model = WaveModelKind::parabolic;
    f.model_nodes = std::uint64_t(marched->rows()) * marched->columns;
    f.resolved_wavelength = marched->resolved_wavelength;
  }
  // How far a node's march-grid corners may lie from it.
  double march_reach = 0.0;
  if (marched) {
    double ds = 0.0;
    for (std::size_t r = 1; r < marched->rows(); ++r) ds = std::max(ds, marched->s[r] - marched->s[r - 1]);
    march_reach = std::hypot(ds, marched->dn);
  }

  // The pierheads this train reaches, with the incident wave at each.
  std::vector<Pierhead> pierheads;
  {
    for (const detail::PierheadSite& site : sites) {
      Pierhead p{site, {}, 0.0, 0.0, 0.0, std::max(floor.depth(site.x, site.y), min_depth), 0, 0, 0, 0};
      double kx, ky;
      if (!incident_at(geo, incident, site.x, site.y, radius, p.amplitude, p.phase, kx, ky)) continue;
      p.k = std::hypot(kx, ky);
      const auto frame = make_breakwater_frame({site.x, site.y, site.ux, site.uy}, kx / p.k, ky / p.k, two_pi / p.k);
      if (!frame.ok()) continue;
      p.frame = frame.value();
      p.shadow_x = kx / p.k;
      p.shadow_y = ky / p.k;
      // The reflected wave's shadow line: the incident direction mirrored about the wall's line.
      const double along = p.shadow_x * site.ux + p.shadow_y * site.uy;
      p.mirror_x = 2.0 * along * site.ux - p.shadow_x;
      p.mirror_y = 2.0 * along * site.uy - p.shadow_y;
      pierheads.push_back(p);
    }
  }
  work.pierheads += pierheads.size();

  for (std::vector<float>* v : {&f.phi, &f.b_re, &f.b_im, &f.kx, &f.ky, &f.fold, &f.lean, &f.breaking}) v->assign(nodes, 0.0f);
  f.diffraction.assign(pierheads.empty() ? 0 : nodes, 0.0f);
  for (std::vector<float>* v : {&f.incident, &f.diffracted, &f.reflected}) v->assign(parts == SeaParts::keep ? nodes : 0, 0.0f);
  if (scratch.reflections.size() < reflected.size()) scratch.reflections.resize(reflected.size());
  const std::span<FamilyField> reflections(scratch.reflections.data(), reflected.size());
  for (std::size_t r = 0; r < reflected.size(); ++r) {
    // Rays reflected off a pierhead's rounded end would spray its reflection round the tip: the
    // diffracted wave is what goes there.
    const WaveRays& w = *reflected[r];
    const auto off_the_face = [&](std::size_t ray) {
      if (w.sample_begin[ray] == w.sample_begin[ray + 1]) return false;
      const double x = w.x[w.sample_begin[ray]], y = w.y[w.sample_begin[ray]];
      return std::none_of(sites.begin(), sites.end(), [&](const detail::PierheadSite& p) {
        return (x - p.x) * p.ux + (y - p.y) * p.uy < 0.0 && std::hypot(x - p.x, y - p.y) < 2.0 * p.radius + 1e-6;
      });
    };
    reflections[r].splat(geo, g, w, off_the_face, radius, walls);
  }

  // The local wave at every water node (kh by table, docs/physics.md 1.2; 0 on land). A node a hair
  // under water takes min_depth, as the breaking cap does: k ~ sqrt(k0 / h) would otherwise grow
  // without bound at the waterline (1e7 rad/m at h = 1e-16 m), and the carrier's phase with it.
  const double k0 = deep_water_wavenumber(rays.omega);
  std::vector<float>& wavenumber = scratch.wavenumber;
  std::vector<float>& kh_at = scratch.kh_at;
  wavenumber.assign(nodes, 0.0f);
  kh_at.assign(nodes, 0.0f);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (!(depths[n] > 0.0f)) continue;
    const double h = std::max(double(depths[n]), min_depth), kh = detail::kh_from_table(k0 * h);
    kh_at[n] = float(kh);
    wavenumber[n] = float(kh / h);
  }
  const auto breaking_limit = [&](std::size_t n) {
    const double h = std::max(double(depths[n]), min_depth), k = double(wavenumber[n]);
    return std::min(0.5 * scene.dwt.breaker_index * h, 0.071 * two_pi / k * std::tanh(double(kh_at[n])));
  };
  std::vector<RadialTable> radials;
  const double far_corner = std::hypot(double(geo.nx - 1) * geo.cell, double(geo.ny - 1) * geo.cell);
  for (const Pierhead& p : pierheads) {
    radials.emplace_back(p, geo, depths, wavenumber, floor.uniform(), walls, rays.min_depth, far_corner, 2.0 * double(g.cell));
  }

  // Pass 1, per node: everything of the train's frequency that arrives, summed relative to the far
  // field's phase psi; the incident rays' phase seeds the carrier where they are lit.
  std::vector<cplx>& sums = scratch.sums;
  sums.assign(nodes, 0.0);
  std::vector<std::uint8_t>& has_wave = scratch.has_wave;
  has_wave.assign(nodes, 0);
  std::vector<double>& carrier = scratch.carrier;
  std::vector<double>& carrier_kx = scratch.carrier_kx;
  std::vector<double>& carrier_ky = scratch.carrier_ky;
  std::vector<double>& reference = scratch.reference;
  carrier.assign(nodes, NAN);
  for (std::vector<double>* v : {&carrier_kx, &carrier_ky, &reference}) v->assign(nodes, 0.0);
  std::vector<PierheadView> views(pierheads.size());
  for (std::size_t n = 0; n < nodes; ++n) {
    const double x = geo.x(n), y = geo.y(n);
    const double psi = double(g.far_kx) * x + double(g.far_ky) * y - g.far_offset;
    const double depth = double(depths[n]);
    if (!(depth > 0.0)) continue;  // land: no wave, and the carrier does not cross it
    const double local_kh = double(kh_at[n]);
    // Where the rays stopped short of the shore nothing arrives here: the shoreline pass below.
    if (!(depth > rays.min_depth)) continue;
    // Each pierhead's frame at this node, the optical distance k r from it and its incident
    // amplitude shoaled from M to here.
    for (std::size_t q = 0; q < pierheads.size(); ++q) {
      const Pierhead& p = pierheads[q];
      PierheadView& v = views[q];
      v.polar = breakwater_polar(p.frame, x, y);
      v.k_r = p.k * v.polar.r;
      v.reached = radials[q].optical_distance(x - p.site.x, y - p.site.y, v.polar.r, v.k_r);
      v.amplitude = p.amplitude * shoaling_coefficient(local_kh) / shoaling_coefficient(p.k * p.depth);
    }
    // Pierhead q's geometric-optics plane wave, relative to psi (incident: sign -1, along the shadow
    // line; reflected: sign +1, along the mirror line).
    const auto plane_wave = [&](std::size_t q, double sign) {
      const Pierhead& p = pierheads[q];
      const PierheadView& v = views[q];
      const double phase = p.phase - v.k_r * std::cos(v.polar.theta + sign * v.polar.theta0);
      return v.amplitude * (sign < 0.0 ? 1.0 : p.site.reflection) * std::polar(1.0, phase - psi);
    };
    cplx incident_part = 0.0, reflected_part = 0.0, diffracted_part = 0.0;
    if (incident.covers(n)) reference[n] = std::hypot(incident.re[n], incident.im[n]);
    bool arrived = false;
    if (marched) {
      // No corner of the march grid across a wall from the node (the two faces of a thin wall see
      // different waves).
      const bool near = std::any_of(walls.begin(), walls.end(), [&](const detail::Capsule& c) {
        return detail::point_segment_dist2(x, y, c) < (march_reach + c.radius) * (march_reach + c.radius);
      });
      // Where the march has no wave next to the node (at the waterline, in a wall's lee corner), the
      // shoreline pass below carries the nearest wave there.
      const std::optional<cplx> v = marched->relative(x, y, psi, [&](double cx, double cy) {
        return near && detail::wall_blocks(walls, x, y, cx, cy);
      });
      incident_part = v.value_or(0.0);
      arrived = v.has_value();
    } else {
      // The incident rays, cut at every pierhead's shadow line. The last ray may pass up to a ray
      // spacing from M: where none reached near the line, the pierhead's plane wave fills the gap.
      bool lit = incident.covers(n);
      std::size_t fill = pierheads.size();
      for (std::size_t q = 0; q < pierheads.size(); ++q) {
        const Pierhead& p = pierheads[q];
        if (from_half_line(x, y, p.site.x, p.site.y, p.shadow_x, p.shadow_y) >= band) continue;
        if (in_shadow(views[q].polar)) {
          lit = false;
        } else if (!incident.covers(n)) {
          fill = q;
        }
      }
      if (lit) {
        incident_part += cplx(incident.re[n], incident.im[n]);
      } else if (fill < pierheads.size()) {
        incident_part += plane_wave(fill, -1.0);
      }
      arrived = lit || fill < pierheads.size();
    }
    // The reflected waves, cut and filled in the same way at their shadow lines (the exact model
    // diffracts them; the paper's models do not, and leave them as traced).
    bool reflection_covers = false;
    for (const FamilyField& r : reflections) {
      if (!r.covers(n)) continue;
      reflection_covers = true;
      bool beyond = false;
      for (std::size_t q = 0; q < pierheads.size() && model == DiffractionModel::exact; ++q) {
        const Pierhead& p = pierheads[q];
        if (p.site.reflection <= 0.0 || from_half_line(x, y, p.site.x, p.site.y, p.mirror_x, p.mirror_y) >= band) continue;
        if (beyond_reflection(views[q].polar)) beyond = true;
      }
      if (beyond) continue;
      reflected_part += cplx(r.re[n], r.im[n]);
      arrived = true;
    }
    for (std::size_t q = 0; q < pierheads.size() && model == DiffractionModel::exact && !reflection_covers; ++q) {
      const Pierhead& p = pierheads[q];
      if (p.site.reflection <= 0.0 || from_half_line(x, y, p.site.x, p.site.y, p.mirror_x, p.mirror_y) >= band) continue;
      if (beyond_reflection(views[q].polar)) continue;
      reflected_part += plane_wave(q, 1.0);
      arrived = true;
      break;
    }
    // Each pierhead's diffracted wave: the semi-infinite solution minus its geometric-optics part
    // (docs/physics.md 4.7), or a paper model's coefficient minus the incident wave. With the
    // parabolic model only the reflected wave's (Sommerfeld's solution is linear in alpha: its
    // alpha term), which the march does not carry; the paper's models diffract no reflected wave.
    for (std::size_t q = 0; q < pierheads.size(); ++q) {
      const Pierhead& p = pierheads[q];
      const PierheadView& v = views[q];
      if (!v.reached) continue;
      const double alpha = p.site.reflection;
      const cplx go1 = std::polar(1.0, -v.k_r * std::cos(v.polar.theta - v.polar.theta0));
      cplx d;
      if (marched) {
        if (model != DiffractionModel::exact || !(alpha > 0.0)) continue;
        d = sommerfeld_reflected(v.k_r, v.polar.theta, v.polar.theta0);
        if (!beyond_reflection(v.polar)) d -= std::polar(1.0, -v.k_r * std::cos(v.polar.theta + v.polar.theta0));
        d *= alpha;
      } else if (model == DiffractionModel::exact) {
        d = sommerfeld_field(v.k_r, v.polar.theta, v.polar.theta0, alpha);
        if (!in_shadow(v.polar)) d -= go1;
        if (!beyond_reflection(v.polar)) d -= alpha * std::polar(1.0, -v.k_r * std::cos(v.polar.theta + v.polar.theta0));
      } else {
        const auto sample = diffraction(model, v.k_r / two_pi, v.polar.theta, v.polar.theta0, alpha);
        if (!sample.ok()) continue;
        d = std::polar(sample->K, sample->phase);
        if (!in_shadow(v.polar)) d -= go1;
      }
      diffracted_part += v.amplitude * d * std::polar(1.0, p.phase - psi);
      arrived = true;
      ++work.evaluations;
    }
    // K' is against the incident wave without the structures: where its rays did not reach, the
    // nearest pierhead's incident amplitude shoaled to here.
    if (!incident.covers(n) && !pierheads.empty()) {
      std::size_t nearest = 0;
      for (std::size_t q = 1; q < pierheads.size(); ++q) {
        if (views[q].polar.r < views[nearest].polar.r) nearest = q;
      }
      reference[n] = views[nearest].amplitude;
    }
    sums[n] = incident_part + reflected_part + diffracted_part;
    if (parts == SeaParts::keep) {
      f.incident[n] = float(std::abs(incident_part));
      f.diffracted[n] = float(std::abs(diffracted_part));
      f.reflected[n] = float(std::abs(reflected_part));
    }
    has_wave[n] = arrived ? 1 : 0;
  }

  // The carrier: the train's first arrivals through the water (an eikonal solution: what the rays
  // follow where they do not cross, and continuous where they cross, end or are cut at a shadow
  // line), marched from where its rays enter the domain, round land and walls (no move of the
  // stencil crosses a wall).
  std::vector<std::uint8_t>& near_wall = scratch.near_wall;
  near_wall.assign(nodes, 0);
  for (const detail::Capsule& c : walls) {
    const double reach = c.radius + 2.5 * geo.cell;  // the stencil's longest move, and some
    const long i0 = std::max(0L, long(std::floor((std::min(c.ax, c.bx) - reach - geo.x0) / geo.cell)));
    const long i1 = std::min(long(geo.nx) - 1, long(std::ceil((std::max(c.ax, c.bx) + reach - geo.x0) / geo.cell)));
    const long j0 = std::max(0L, long(std::floor((std::min(c.ay, c.by) - reach - geo.y0) / geo.cell)));
    const long j1 = std::min(long(geo.ny) - 1, long(std::ceil((std::max(c.ay, c.by) + reach - geo.y0) / geo.cell)));
    for (long j = j0; j <= j1; ++j) {
      for (long i = i0; i <= i1; ++i) {
        const std::size_t n = std::size_t(j) * geo.nx + std::size_t(i);
        if (detail::point_segment_dist2(geo.x(n), geo.y(n), c) <= reach * reach) near_wall[n] = 1;
      }
    }
  }
  const auto crosses_wall = [&](std::size_t a, std::size_t b) {
    return detail::wall_blocks(walls, geo.x(a), geo.y(a), geo.x(b), geo.y(b));
  };
  for (std::size_t n = 0; n < nodes; ++n) {
    const std::size_t i = n % geo.nx, j = n / geo.nx;
    // An upstream edge node the incident rays reached: the far field's phase, as the tracer's entry.
    const bool upstream = (i == 0 && g.far_kx > 0.0f) || (i + 1 == geo.nx && g.far_kx < 0.0f) ||
                          (j == 0 && g.far_ky > 0.0f) || (j + 1 == geo.ny && g.far_ky < 0.0f);
    if (!upstream || !incident.covers(n) || !(wavenumber[n] > 0.0f)) continue;
    carrier[n] = double(g.far_kx) * geo.x(n) + double(g.far_ky) * geo.y(n) - g.far_offset;
    carrier_kx[n] = g.far_kx;
    carrier_ky[n] = g.far_ky;
  }
  detail::march_carrier(geo.nx, geo.ny, geo.cell, wavenumber, near_wall, crosses_wall, carrier, carrier_kx, carrier_ky,
                        scratch.march);

  // Pass 2: the sum relative to the carrier, capped by breaking (the waves that meet at a node
  // break as one: each ray is capped so, their sum and a diffracted wave shoaled into shallow water
  // need it too), and the shape.
  std::vector<double>& magnitude = scratch.magnitude;
  magnitude.assign(nodes, 0.0);
  // The probe's parts at node `to`: those at `from` times `scale` (breaking caps them with their sum).
  const auto scale_parts = [&](std::size_t from, std::size_t to, double scale) {
    if (parts != SeaParts::keep) return;
    for (std::vector<float>* part : {&f.incident, &f.diffracted, &f.reflected}) (*part)[to] = float(double((*part)[from]) * scale);
  };
  for (std::size_t n = 0; n < nodes; ++n) {
    const double x = geo.x(n), y = geo.y(n);
    const double psi = double(g.far_kx) * x + double(g.far_ky) * y - g.far_offset;
    if (!std::isfinite(carrier[n])) {
      carrier[n] = psi;
      carrier_kx[n] = g.far_kx;
      carrier_ky[n] = g.far_ky;
    }
    f.phi[n] = float(carrier[n]);
    f.kx[n] = float(carrier_kx[n]);
    f.ky[n] = float(carrier_ky[n]);
    if (!has_wave[n]) continue;
    const double h = std::max(double(depths[n]), min_depth);
    cplx b = sums[n] * std::polar(1.0, psi - carrier[n]);
    const double limit = breaking_limit(n);
    // Breaking: 1 where the wave is within 20 % of the cap (in the surf zone the tracer holds it there
    // and the resampling spreads it a little below), rising from 0 at 55 % of it.
    f.breaking[n] = float(std::clamp((std::abs(b) / limit - 0.55) / 0.25, 0.0, 1.0));
    if (std::abs(b) > limit) {
      const double cap = limit / std::abs(b);
      b *= cap;
      scale_parts(n, n, cap);
    }
    f.b_re[n] = float(b.real());
    f.b_im[n] = float(b.imag());
    magnitude[n] = std::abs(b);
    double fold, lean;
    shape(steepness, std::hypot(carrier_kx[n], carrier_ky[n]), h, fold, lean);
    f.fold[n] = float(fold);
    f.lean[n] = float(lean);
    if (!f.diffraction.empty()) f.diffraction[n] = reference[n] > 0.0 ? float(magnitude[n] / reference[n]) : 0.0f;
  }

  // Between the depth where the rays stop (h_min) and the waterline nothing was traced: the nearest
  // wave goes on there along its wave vector, its height capped by breaking, so it dies out at the
  // waterline instead of ending in a step (breadth first from the nodes with a wave: deterministic).
  std::vector<std::uint32_t>& queue = scratch.queue;
  queue.clear();
  for (std::size_t n = 0; n < nodes; ++n) {
    if (has_wave[n]) queue.push_back(std::uint32_t(n));
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t n = queue[head], i = n % geo.nx, j = n / geo.nx;
    const std::size_t around[4] = {i > 0 ? n - 1 : n, i + 1 < geo.nx ? n + 1 : n, j > 0 ? n - geo.nx : n,
                                   j + 1 < geo.ny ? n + geo.nx : n};
    for (std::size_t m : around) {
      // (With the parabolic model also the water nodes next to its waterline that its grid leaves out.)
      if (has_wave[m] || !(depths[m] > 0.0f) || (depths[m] > rays.min_depth && !marched)) continue;
      if (near_wall[m] && crosses_wall(n, m)) continue;
      has_wave[m] = 1;
      queue.push_back(std::uint32_t(m));
      // The wave keeps its direction; its phase advances by the mean k of both nodes; relative to
      // m's own carrier.
      const double h = double(depths[m]), k = std::hypot(double(f.kx[n]), double(f.ky[n]));
      const double limit = breaking_limit(m), k_m = double(wavenumber[m]);
      const double scale = magnitude[n] > limit ? limit / magnitude[n] : 1.0;
      const double ux = k > 0.0 ? double(f.kx[n]) / k : 0.0, uy = k > 0.0 ? double(f.ky[n]) / k : 0.0;
      const double along = ux * (geo.x(m) - geo.x(n)) + uy * (geo.y(m) - geo.y(n));
      const double turn = double(f.phi[n]) + 0.5 * (k + k_m) * along - double(f.phi[m]);
      const cplx b = cplx(f.b_re[n], f.b_im[n]) * scale * std::polar(1.0, turn);
      f.b_re[m] = float(b.real());
      f.b_im[m] = float(b.imag());
      magnitude[m] = magnitude[n] * scale;
      f.breaking[m] = scale < 1.0 ? 1.0f : f.breaking[n];
      double fold, lean;
      shape(steepness, std::hypot(double(f.kx[m]), double(f.ky[m])), h, fold, lean);
      f.fold[m] = float(fold);
      f.lean[m] = float(lean);
      if (!f.diffraction.empty()) f.diffraction[m] = float(double(f.diffraction[n]) * scale);
      scale_parts(n, m, scale);
    }
  }
  // The fold-free bound sqrt(Q^2 + L^2) <= max_fold holds for any bilinear mix of a cell's corners:
  // each node's fold and lean are scaled for the largest |B| of the cells around it.
  double b_max = g.far_amplitude;
  for (std::size_t n = 0; n < nodes; ++n) {
    const std::size_t i = n % geo.nx, j = n / geo.nx;
    double around = 0.0;
    for (std::size_t jj = j > 0 ? j - 1 : 0; jj <= std::min(j + 1, geo.ny - 1); ++jj) {
      for (std::size_t ii = i > 0 ? i - 1 : 0; ii <= std::min(i + 1, geo.nx - 1); ++ii) around = std::max(around, magnitude[jj * geo.nx + ii]);
    }
    b_max = std::max(b_max, magnitude[n]);
    const double norm = std::hypot(double(f.fold[n]), double(f.lean[n])) * around;
    if (norm > max_fold) {
      f.fold[n] = float(double(f.fold[n]) * max_fold / norm);
      f.lean[n] = float(double(f.lean[n]) * max_fold / norm);
    }
  }
  g.phi = f.phi.data();
  g.b_re = f.b_re.data();
  g.b_im = f.b_im.data();
  g.kx = f.kx.data();
  g.ky = f.ky.data();
  g.fold = f.fold.data();
  g.lean = f.lean.data();
  return float(b_max);
}

void SeaSurface::set_time(double time_s) noexcept {
  double tau[TrainGridFrame::max_trains];
  for (std::size_t t = 0; t < trains_.size(); ++t) tau[t] = trains_[t].omega * time_s - trains_[t].phase;
  set_train_grid_time(frame_, tau);
}

void SeaSurface::eval(const float* x, const float* y, std::size_t n, float* height, float* grad_x,
                      float* grad_y) const noexcept {
  train_grid_eval(frame_, x, y, n, {height, grad_x, grad_y});
}

TrainProbe SeaSurface::probe(std::size_t train, float x, float y) const noexcept {
  HOULE_ASSERT(train < trains_.size(), "SeaSurface::probe: a train of the scene");
  const TrainGrid& g = grids_[train];
  const TrainGridFields l = train_grid_fields(g, x, y);
  // Bilinear, as the kernel interpolates the other fields, at the nearest point of the grid (off it
  // the edge's wave goes on); `outside` without the field.
  const float gx = std::clamp((x - g.origin_x) / g.cell, 0.0f, float(g.nx - 1));
  const float gy = std::clamp((y - g.origin_y) / g.cell, 0.0f, float(g.ny - 1));
  const auto at = [&](const std::vector<float>& q, float outside) {
    if (q.empty() || g.nx < 2 || std::isnan(gx) || std::isnan(gy)) return outside;
    const std::size_t i = std::min(std::size_t(gx), std::size_t(g.nx) - 2), j = std::min(std::size_t(gy), std::size_t(g.ny) - 2);
    const float u = gx - float(i), v = gy - float(j);
    const std::size_t n00 = j * g.nx + i;
    return (q[n00] * (1.0f - u) + q[n00 + 1] * u) * (1.0f - v) + (q[n00 + g.nx] * (1.0f - u) + q[n00 + g.nx + 1] * u) * v;
  };
  const TrainField& f = trains_[train];
  const float k = std::sqrt(l.kx * l.kx + l.ky * l.ky);
  TrainProbe p;
  p.amplitude = std::hypot(l.b_re, l.b_im);
  p.relative_amplitude = amplitude0_[train] > 0.0f ? p.amplitude / amplitude0_[train] : 0.0f;
  p.wavelength = k > 0.0f ? float(two_pi) / k : 0.0f;
  p.direction_deg = float(std::atan2(l.ky, l.kx) * 180.0 / pi);
  p.phase = float(std::remainder(double(l.phi) + std::atan2(double(l.b_im), double(l.b_re)) - double(frame_.time_phase[train]), two_pi));
  p.diffraction = at(f.diffraction, 1.0f);
  if (parts_ == SeaParts::keep) {
    // An analytic train is its far field: all incident.
    p.incident = at(f.incident, p.amplitude);
    p.diffracted = at(f.diffracted, 0.0f);
    p.reflected = at(f.reflected, 0.0f);
  }
  return p;
}

void SeaSurface::sample(void* context, const SurfaceSamples& s) noexcept {
  HOULE_ASSERT(context != nullptr, "SeaSurface::sample: a SeaSurface as the context");
  // The frame's nodes hold only the waves their footprint resolves (docs/rendering.md 5.5).
  train_grid_eval(static_cast<const SeaSurface*>(context)->frame_, s.x, s.y, s.n, s.footprint,
                  {s.height, s.grad_x, s.grad_y}, s.slope_variance, {s.keep, s.kept});
}

}  // namespace houle
