// The parabolic model (parabolic_model.hpp; the method and its choices: docs/physics.md 10).
#include "parabolic_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/dispersion.hpp"
#include "clip_line.hpp"
#include "dispersion_table.hpp"
#include "pade_factors.hpp"
#include "ray_walls.hpp"

namespace houle::detail {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * pi;
// The propagator's [3/3] Pade factors: at 8 steps per wavelength their error per step is 5e-4 for
// waves 60 deg off the march and 2e-5 at 40 deg (docs/physics.md 10.2). Its branch cut is turned by
// 0.1 rad so that evanescent waves (X < -1: what walls, land and the row ends scatter across the
// grid) decay, by 12-21 % a step, instead of travelling on unchanged; the approximant is then scaled so
// that no propagating wave grows (it would by 1e-9 a step near X = 0.19).
constexpr int propagator_order = 3;
constexpr double propagator_rotation = 0.1;
// The amplitude transforms (1 + X)^(+-1/4) are [2/2] approximants with their branch cut rotated by
// 45 deg (relative error 4e-3 for waves up to 40 deg off the march, 1.1e-2 at 60 deg): unrotated,
// their poles fall inside the spectrum of X's evanescent part. A [3/3] rotated by 30 deg is ten times
// as exact but amplifies evanescent waves 1.4 times more: on the plane beach it did worse.
constexpr int transform_order = 2;
constexpr double transform_rotation = pi / 4.0;
// Margins beside the domain, across the march, in wavelengths: the open ends of the rows lie there,
// away from the domain, where what crosses them is one wave leaving (docs/physics.md 10.2).
constexpr double pad_wavelengths = 2.0;
// Dally, Dean & Dalrymple (1985): a broken wave's energy flux decays at kappa / h towards that of the
// stable height Gamma h.
constexpr double dally_kappa = 0.15, dally_stable = 0.4;
constexpr double min_depth = 1e-3;  // m: the depth the dispersion relation sees at or above still water

double clamp_to(double v, double lo, double hi) { return std::min(std::max(v, lo), hi); }

struct Grid {
  double dx, dy;   // march direction
  double mx, my;   // across it (dir turned left)
  double s_lo, s_hi;
  double n0, dn;
  std::size_t columns;
  double sigma;                        // rad of the reference wave per step
  double resolved_wavelength;          // m
  double k_max;                        // rad/m: the reference wavenumber never exceeds it
  std::uint64_t rows_bound;
};

Grid make_grid(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& t) {
  const Domain& d = scene.domain;
  const WaveModel& wm = scene.wave_model;
  Grid g{};
  g.dx = t.dir_x;
  g.dy = t.dir_y;
  g.mx = -t.dir_y;
  g.my = t.dir_x;
  double n_lo = INFINITY, n_hi = -INFINITY;
  g.s_lo = INFINITY;
  g.s_hi = -INFINITY;
  for (const double x : {d.x_min, d.x_max}) {
    for (const double y : {d.y_min, d.y_max}) {
      g.s_lo = std::min(g.s_lo, g.dx * x + g.dy * y);
      g.s_hi = std::max(g.s_hi, g.dx * x + g.dy * y);
      n_lo = std::min(n_lo, g.mx * x + g.my * y);
      n_hi = std::max(n_hi, g.mx * x + g.my * y);
    }
  }
  // The shortest wavelength worth resolving: where the deep-water wave would already break, or where
  // waves end (dry_depth), or the floor's shallowest water if it is deeper. Shallower water is surf,
  // whose height the breaking model sets.
  const double breaking_depth = 2.0 * t.amplitude0 / scene.dwt.breaker_index;
  const double h_res = std::max({t.dry_depth, breaking_depth, floor.min_depth_bound(d), min_depth});
  const double k_res = std::max(linear_wave(t.omega, h_res).k, t.k_far);
  g.k_max = k_res;
  g.resolved_wavelength = two_pi / k_res;
  g.dn = g.resolved_wavelength / wm.points_per_wavelength;
  g.sigma = two_pi / wm.steps_per_wavelength;
  const double pad = pad_wavelengths * two_pi / t.k_far;
  const auto size = [&] {
    g.columns = std::size_t(std::ceil((n_hi - n_lo + 2.0 * pad) / g.dn)) + 1;
    g.rows_bound = std::uint64_t(std::ceil((g.s_hi - g.s_lo) * k_res / g.sigma)) + 2;
  };
  size();
  const double nodes = double(g.rows_bound) * double(g.columns);
  if (nodes > double(max_parabolic_nodes)) {
    // Coarser in both directions alike, the steps to a quarter wavelength at most (beyond it the
    // propagator's error grows fast) and the rest across the rows; the resolved wavelength says what
    // is left.
    const double scale = std::sqrt(nodes / double(max_parabolic_nodes)) * 1.001;
    const double step_scale = std::min(scale, (pi / 2.0) / g.sigma);
    g.sigma *= step_scale;
    g.dn *= scale * scale / step_scale;
    g.resolved_wavelength = g.dn * wm.points_per_wavelength;
    size();
  }
  g.n0 = n_lo - pad;
  return g;
}

/// The walls as the waves meet them: each segment clipped to the domain, and where a wall leaves the
/// domain (or ends within its thickness of the edge) a straight continuation beyond it, as every wall
/// that reaches the domain's edge is taken to continue (docs/scenes.md, walls).
std::vector<Capsule> march_walls(const Scene& scene, double reach) {
  const Domain& d = scene.domain;
  std::vector<Capsule> out;
  const std::vector<Capsule> all = wall_capsules(scene.walls);
  const auto near_edge = [&](double x, double y, double r) {
    return x - d.x_min <= r || d.x_max - x <= r || y - d.y_min <= r || d.y_max - y <= r;
  };
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Capsule& c = all[i];
    const double ex = c.bx - c.ax, ey = c.by - c.ay, len = std::hypot(ex, ey);
    double t0, t1;
    if (len <= 0.0 || !clip_line(d, c.ax, c.ay, ex, ey, t0, t1)) continue;
    t0 = std::max(t0, 0.0);
    t1 = std::min(t1, 1.0);
    if (t0 > t1) continue;
    const double ux = ex / len, uy = ey / len;
    Capsule in = c;
    in.ax = c.ax + t0 * ex;
    in.ay = c.ay + t0 * ey;
    in.bx = c.ax + t1 * ex;
    in.by = c.ay + t1 * ey;
    out.push_back(in);
    const bool first = i == 0 || all[i - 1].wall != c.wall, last = i + 1 == all.size() || all[i + 1].wall != c.wall;
    if (t0 > 0.0 || (first && near_edge(in.ax, in.ay, c.radius))) {
      out.push_back({in.ax, in.ay, in.ax - reach * ux, in.ay - reach * uy, c.radius, c.wall});
    }
    if (t1 < 1.0 || (last && near_edge(in.bx, in.by, c.radius))) {
      out.push_back({in.bx, in.by, in.bx + reach * ux, in.by + reach * uy, c.radius, c.wall});
    }
  }
  return out;
}

/// X = diag(d) + off * (second difference across the open links): link j joins columns j and j + 1.
/// Beyond each end a ghost node holds `ghost` times the end node's value: 1 closes the end (no
/// flux), e^{i l dn} lets a wave of lateral wavenumber l through it.
struct RowOperator {
  const cplx* d;  // complex where the wave is damped (breaking)
  const std::uint8_t* open;
  double off;
  std::size_t n;
  cplx ghost_first = 1.0, ghost_last = 1.0;
};

/// v <- (1 + b X)^-1 (1 + a X) v by the Thomas algorithm (I + b X with X real symmetric and b not
/// real has no singular leading block, so no pivoting is needed; open ends only add to X's imaginary
/// part, on the absorbing side). `w` holds n scratch values.
void apply_factor(const RowOperator& x, cplx a, cplx b, cplx* v, cplx* w) {
  const std::size_t n = x.n;
  if (n == 0) return;
  const auto link = [&](std::size_t j) { return x.open[j] ? x.off : 0.0; };  // j < n - 1
  // The diagonal of X: d, minus the open links, plus the ghosts' share at the ends.
  const auto diagonal = [&](std::size_t j) {
    const double left = j > 0 ? link(j - 1) : 0.0, right = j + 1 < n ? link(j) : 0.0;
    cplx value = x.d[j] - left - right;
    if (j == 0) value += x.off * (x.ghost_first - 1.0);
    if (j + 1 == n) value += x.off * (x.ghost_last - 1.0);
    return value;
  };
  // r = (1 + a X) v, written over w.
  for (std::size_t j = 0; j < n; ++j) {
    cplx xv = diagonal(j) * v[j];
    if (j > 0) xv += link(j - 1) * v[j - 1];
    if (j + 1 < n) xv += link(j) * v[j + 1];
    w[j] = v[j] + a * xv;
  }
  // Solve (1 + b X) v = w: forward elimination keeps the modified super-diagonal in v.
  cplx prev_c = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double left = j > 0 ? link(j - 1) : 0.0, right = j + 1 < n ? link(j) : 0.0;
    const cplx lower = b * left, diag = 1.0 + b * diagonal(j), upper = b * right;
    const cplx denom = diag - lower * prev_c;
    const cplx c = upper / denom;
    w[j] = (w[j] - (j > 0 ? lower * w[j - 1] : cplx(0.0))) / denom;
    v[j] = c;
    prev_c = c;
  }
  for (std::size_t j = n; j-- > 0;) {
    if (j + 1 < n) w[j] -= v[j] * w[j + 1];
  }
  std::copy(w, w + n, v);
}

void apply(const PadeFactors& f, const RowOperator& x, cplx* v, cplx* w) {
  const std::size_t pairs = std::max(f.num.size(), f.den.size());
  for (std::size_t i = 0; i < pairs; ++i) {
    apply_factor(x, i < f.num.size() ? f.num[i] : cplx(0.0), i < f.den.size() ? f.den[i] : cplx(0.0), v, w);
  }
  for (std::size_t j = 0; j < x.n; ++j) v[j] *= f.scale;
}

/// The ghost factor of an open row end from the end node and its neighbour: the wave there, taken as
/// one plane wave, continues beyond the end (e^{i l dn}). A wave that would come in through the end
/// (or none) closes it instead: nothing enters from outside, and X's imaginary part stays on the
/// absorbing side, so the march never grows.
cplx open_end(cplx end, cplx inner) {
  if (std::abs(end) == 0.0 || std::abs(inner) == 0.0) return 1.0;
  const cplx ratio = end / inner;
  const cplx ghost = ratio / std::abs(ratio);
  return ghost.imag() > 0.0 ? ghost : cplx(1.0);
}

/// One row of the march grid: the floor and the walls across it.
struct Row {
  std::vector<double> depth, k, p;  // m, rad/m (linear), C Cg (m^2/s^2)
  std::vector<std::uint8_t> wet;    // water, outside every wall
  std::vector<std::uint8_t> open;   // per link j (columns j, j + 1): no wall between them
  std::vector<std::uint8_t> reached;  // the march from the previous row does not cross a wall
};

}  // namespace

std::size_t ParabolicField::row_before(double sp) const noexcept {
  const std::size_t r = std::size_t(std::upper_bound(s.begin(), s.end(), sp) - s.begin());
  return std::clamp<std::size_t>(r, 1, s.size() - 1) - 1;
}

double ParabolicField::reference_turn(std::size_t r, double fs, double reference) const noexcept {
  return std::remainder(phase[r] + (phase[r + 1] - phase[r]) * fs - reference, two_pi);
}

double entry_depth(const Scene& scene, const Bathymetry& floor, double dir_x, double dir_y) noexcept {
  const Domain& d = scene.domain;
  const double cx = 0.5 * (d.x_min + d.x_max) - dir_x * 0.5 * (d.x_max - d.x_min);
  const double cy = 0.5 * (d.y_min + d.y_max) - dir_y * 0.5 * (d.y_max - d.y_min);
  return floor.depth(std::clamp(cx, d.x_min, d.x_max), std::clamp(cy, d.y_min, d.y_max));
}

ParabolicTrain parabolic_train(const Scene& scene, const Bathymetry& floor, std::size_t train) noexcept {
  const WaveTrain& w = scene.trains[train];
  const Point2 dir = train_direction(w);
  ParabolicTrain t;
  t.omega = train_omega(w);
  t.dir_x = dir.x;
  t.dir_y = dir.y;
  t.amplitude0 = w.amplitude;
  t.k_far = linear_wave(t.omega, std::max(entry_depth(scene, floor, dir.x, dir.y), min_depth)).k;
  t.dry_depth = std::max(scene.dwt.min_depth, scene.dwt.min_depth_wavelengths * two_pi / deep_water_wavenumber(t.omega));
  return t;
}

std::uint64_t parabolic_nodes(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& train) {
  const Grid g = make_grid(scene, floor, train);
  return g.rows_bound * g.columns;
}

ParabolicWork parabolic_work(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& train) {
  const Grid g = make_grid(scene, floor, train);
  const Domain& d = scene.domain;
  const double k0 = deep_water_wavenumber(train.omega);
  // The march's step is sigma over the row's mean wavenumber (its wet nodes', at most k_max), so
  // its rows are the integral of that mean over s, over sigma: sampled on a coarse lattice here.
  constexpr int along = 128, across = 64;
  const double span_s = g.s_hi - g.s_lo, span_n = double(g.columns - 1) * g.dn;
  double expected_rows = 2.0;
  for (int a = 0; a < along; ++a) {
    const double s = g.s_lo + (double(a) + 0.5) / along * span_s;
    double sum = 0.0;
    int wet = 0;
    for (int c = 0; c < across; ++c) {
      const double n = g.n0 + (double(c) + 0.5) / across * span_n;
      const double x = s * g.dx + n * g.mx, y = s * g.dy + n * g.my;
      const double h = floor.depth(clamp_to(x, d.x_min, d.x_max), clamp_to(y, d.y_min, d.y_max));
      if (!(h > train.dry_depth)) continue;
      const double hh = std::max(h, min_depth);
      sum += kh_from_table(k0 * hh) / hh;
      ++wet;
    }
    const double kbar = std::min(wet > 0 ? sum / wet : train.k_far, g.k_max);
    expected_rows += kbar * span_s / along / g.sigma;
  }
  ParabolicWork w;
  w.nodes = std::min(g.rows_bound, std::uint64_t(std::ceil(expected_rows))) * g.columns;

  const double span = (g.s_hi - g.s_lo) + double(g.columns) * g.dn;
  const std::vector<Capsule> walls = march_walls(scene, 2.0 * span);
  // Rows are at least sigma / k_max apart (rows_bound counts them so) and at most sigma / k0 (the
  // mean wavenumber is never below deep water's); the last may end that far past s_hi.
  const double rows_per_m = double(g.rows_bound) / std::max(g.s_hi - g.s_lo, g.dn);
  const double last_step = g.sigma / k0;
  // Every row looks at the walls that start before it; the rows a wall spans test the nodes across
  // its extent, grown by its radius and a node each side (march_parabolic's fill_row).
  double tests = double(g.rows_bound) * double(walls.size());
  for (const Capsule& c : walls) {
    const double sa = g.dx * c.ax + g.dy * c.ay, sb = g.dx * c.bx + g.dy * c.by;
    const double na = g.mx * c.ax + g.my * c.ay, nb = g.mx * c.bx + g.my * c.by;
    const double s0 = std::max(std::min(sa, sb) - c.radius, g.s_lo);
    const double s1 = std::min(std::max(sa, sb) + c.radius, g.s_hi + last_step);
    if (!(s0 <= s1)) continue;
    const double rows = std::min(double(g.rows_bound), (s1 - s0) * rows_per_m + 2.0);
    const double columns = std::min(double(g.columns), (std::abs(nb - na) + 2.0 * c.radius) / g.dn + 5.0);
    tests += 3.0 * rows * columns;
  }
  w.wall_tests = tests < 0x1p60 ? std::uint64_t(tests) : std::uint64_t(1) << 60;
  return w;
}

Expected<ParabolicField> march_parabolic(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& t) {
  if (!(t.omega > 0.0 && t.k_far > 0.0)) return Error{"trains", "a train with a period and a wavenumber > 0"};
  const Grid g = make_grid(scene, floor, t);
  const Domain& dom = scene.domain;
  const std::size_t nc = g.columns;
  const double k0 = deep_water_wavenumber(t.omega);
  const double gamma_b = scene.dwt.breaker_index;

  PadeFactors propagator =
      rotated_pade(propagator_series(g.sigma, propagator_rotation, 2 * propagator_order), propagator_rotation);
  double gain = 1.0;
  for (double x = -1.0; x <= 4.0; x += 1e-4) gain = std::max(gain, std::abs(propagator(x)));
  propagator.scale /= gain;
  const PadeFactors to_flux = rotated_pade(power_series(0.25, transform_rotation, 2 * transform_order), transform_rotation);
  const PadeFactors from_flux = rotated_pade(power_series(-0.25, transform_rotation, 2 * transform_order), transform_rotation);

  // Walls, by where they start along the march (each is tested only on the rows it can reach).
  const double span = (g.s_hi - g.s_lo) + double(nc) * g.dn;
  std::vector<Capsule> walls = march_walls(scene, 2.0 * span);
  const auto s_of = [&](double x, double y) { return g.dx * x + g.dy * y; };
  const auto n_of = [&](double x, double y) { return g.mx * x + g.my * y; };
  std::sort(walls.begin(), walls.end(), [&](const Capsule& a, const Capsule& b) {
    return std::min(s_of(a.ax, a.ay), s_of(a.bx, a.by)) - a.radius < std::min(s_of(b.ax, b.ay), s_of(b.bx, b.by)) - b.radius;
  });

  ParabolicField f;
  f.dir_x = g.dx;
  f.dir_y = g.dy;
  f.n0 = g.n0;
  f.dn = g.dn;
  f.columns = std::uint32_t(nc);
  f.resolved_wavelength = g.resolved_wavelength;
  f.s.reserve(std::size_t(g.rows_bound));
  f.phase.reserve(std::size_t(g.rows_bound));
  f.eta.reserve(std::size_t(g.rows_bound * nc));

  Row cur, next;
  for (Row* r : {&cur, &next}) {
    r->depth.resize(nc);
    r->k.resize(nc);
    r->p.resize(nc);
    r->wet.resize(nc);
    r->open.resize(nc);
    r->reached.resize(nc);
  }
  // Fills row `r` at s: depths (clamped to the domain outside it), the linear wave, and the walls on
  // the way from s_prev.
  const auto fill_row = [&](Row& r, double s, double s_prev) {
    for (std::size_t j = 0; j < nc; ++j) {
      const double n = g.n0 + double(j) * g.dn;
      const double x = s * g.dx + n * g.mx, y = s * g.dy + n * g.my;
      // Outside the domain the floor is that of its nearest point (a beach goes on along its shore).
      const double h = floor.depth(clamp_to(x, dom.x_min, dom.x_max), clamp_to(y, dom.y_min, dom.y_max));
      r.depth[j] = h;
      // kh by table (docs/physics.md 1.2): C = (g / omega) tanh kh, Cg = n C.
      const double hh = std::max(h, min_depth), kh = kh_from_table(k0 * hh), c = gravity / t.omega * std::tanh(kh);
      r.k[j] = kh / hh;
      r.p[j] = c * c * group_velocity_ratio(kh);
      r.wet[j] = h > 0.0;
      r.open[j] = 1;
      r.reached[j] = 1;
    }
    const double lo = std::min(s, s_prev), hi = std::max(s, s_prev);
    for (const Capsule& c : walls) {
      const double sa = s_of(c.ax, c.ay), sb = s_of(c.bx, c.by);
      if (std::min(sa, sb) - c.radius > hi) break;
      ++f.wall_tests;
      if (std::max(sa, sb) + c.radius < lo) continue;
      // The capsule's n-range within the strip [lo - radius, hi + radius].
      double ta = 0.0, tb = 1.0;
      if (sb != sa) {
        ta = ((lo - c.radius) - sa) / (sb - sa);
        tb = ((hi + c.radius) - sa) / (sb - sa);
        if (ta > tb) std::swap(ta, tb);
        ta = std::max(ta, 0.0);
        tb = std::min(tb, 1.0);
      }
      const double na = n_of(c.ax + ta * (c.bx - c.ax), c.ay + ta * (c.by - c.ay));
      const double nb = n_of(c.ax + tb * (c.bx - c.ax), c.ay + tb * (c.by - c.ay));
      const long j0 = std::max(0L, long(std::floor((std::min(na, nb) - c.radius - g.n0) / g.dn)) - 1);
      const long j1 = std::min(long(nc) - 1, long(std::ceil((std::max(na, nb) + c.radius - g.n0) / g.dn)) + 1);
      const std::span<const Capsule> one(&c, 1);
      f.wall_tests += 3 * std::uint64_t(std::max(0L, j1 - j0 + 1));
      for (long j = j0; j <= j1; ++j) {
        const double n = g.n0 + double(j) * g.dn;
        const double x = s * g.dx + n * g.mx, y = s * g.dy + n * g.my;
        if (point_segment_dist2(x, y, c) < c.radius * c.radius) r.wet[std::size_t(j)] = 0;
        if (s != s_prev && wall_blocks(one, s_prev * g.dx + n * g.mx, s_prev * g.dy + n * g.my, x, y)) {
          r.reached[std::size_t(j)] = 0;
        }
        if (j + 1 < long(nc)) {
          const double x1 = x + g.dn * g.mx, y1 = y + g.dn * g.my;
          if (wall_blocks(one, x, y, x1, y1)) r.open[std::size_t(j)] = 0;
        }
      }
    }
  };
  const auto mean_k = [&](const std::vector<double>& k, const Row& r) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t j = 0; j < nc; ++j) {
      if (r.wet[j] && r.depth[j] > t.dry_depth) {
        sum += k[j];
        ++count;
      }
    }
    // Capped so that the steps stay at least as long as at the resolved wavelength (the row count is
    // then bounded); surf-zone nodes with shorter waves see X > 0, where the propagator is as exact.
    return std::min(count ? sum / double(count) : t.k_far, g.k_max);
  };

  // The march's state: u = K^(1/2) sqrt(p) eta demodulated by Phi (its flux |u|^2 is the energy flux
  // across the row, docs/physics.md 10.1), the amplitude of the last row (for the amplitude-dependent
  // k) and the breaking columns.
  std::vector<cplx> u(nc), scratch(nc), out(nc);
  std::vector<double> amp(nc, 0.0), k_cur(nc), k_next(nc), decay(nc);
  std::vector<cplx> d(nc);
  std::vector<std::uint8_t> breaking(nc, 0), step_open(nc, 1);
  const auto nonlinear_k = [&](const Row& r, std::vector<double>& k) {
    for (std::size_t j = 0; j < nc; ++j) {
      k[j] = r.k[j];
      if (scene.wave_model.amplitude_dispersion && r.wet[j] && amp[j] > 0.0) {
        k[j] = amplitude_dispersion_k(t.omega, std::max(r.depth[j], min_depth), amp[j], r.k[j]);
      }
    }
  };
  const auto store = [&](double s, double phi) {
    f.s.push_back(s);
    f.phase.push_back(phi);
    for (std::size_t j = 0; j < nc; ++j) f.eta.push_back(std::complex<float>(out[j]));
  };

  // Row 0, upstream of the domain: the far field's plane wave, A0 shoaled to each node's depth.
  double s = g.s_lo, phi = t.k_far * g.s_lo - t.far_offset;
  fill_row(cur, s, s);
  for (std::size_t j = 0; j < nc; ++j) {
    const double kh = cur.k[j] * std::max(cur.depth[j], min_depth);
    out[j] = cur.wet[j] ? t.amplitude0 * shoaling_coefficient(kh) : 0.0;
    amp[j] = std::abs(out[j]);
  }
  nonlinear_k(cur, k_cur);
  {
    const double kbar = mean_k(k_cur, cur);
    for (std::size_t j = 0; j < nc; ++j) {
      d[j] = (k_cur[j] * k_cur[j] - kbar * kbar) / (kbar * kbar);
      u[j] = out[j] * std::sqrt(cur.p[j]);
    }
    apply(to_flux, {d.data(), cur.open.data(), 1.0 / (kbar * g.dn * kbar * g.dn), nc}, u.data(), scratch.data());
    for (std::size_t j = 0; j < nc; ++j) u[j] *= std::sqrt(kbar);
  }
  store(s, phi);

  while (s < g.s_hi && f.s.size() < g.rows_bound) {
    const double kbar = mean_k(k_cur, cur);
    const double ds = g.sigma / kbar;
    fill_row(next, s + ds, s);
    nonlinear_k(next, k_next);
    // The propagator over the step, with the mean of both rows' k^2, coupling two columns only where
    // no wall runs between them on either row (a wall crossing the rows obliquely is between
    // different columns on each). A broken wave loses energy flux at kappa / h (1 - (Gamma h / H)^2)
    // (Dally, Dean & Dalrymple 1985), which enters as an imaginary part of k^2, so that the damping
    // is smooth across the row (scaling nodes one by one scatters the field).
    // The rate is smoothed across the row (a binomial filter over 5 columns): where breaking starts
    // column by column, a rate that jumps between neighbours scatters the field into streaks.
    // Water shallower than dry_depth absorbs what reaches it, the more the shallower (a wave that
    // runs into nodes set to 0 row after row scatters off their staircase).
    for (std::size_t j = 0; j < nc; ++j) {
      decay[j] = 0.0;  // 1/m, of the amplitude
      const double h = std::max(0.5 * (cur.depth[j] + next.depth[j]), min_depth);
      if (breaking[j]) {
        const double stable = dally_stable * h / (2.0 * amp[j]);
        decay[j] = 0.5 * dally_kappa / h * (1.0 - stable * stable);
      }
      if (h < t.dry_depth) decay[j] += k_next[j] * (1.0 - h / t.dry_depth);
    }
    for (std::size_t j = 0; j < nc; ++j) {
      const auto at = [&](std::ptrdiff_t i) { return decay[std::size_t(std::clamp<std::ptrdiff_t>(i, 0, std::ptrdiff_t(nc) - 1))]; };
      const std::ptrdiff_t i = std::ptrdiff_t(j);
      const double smooth = (at(i - 2) + 4.0 * at(i - 1) + 6.0 * at(i) + 4.0 * at(i + 1) + at(i + 2)) / 16.0;
      const double k2 = 0.5 * (k_cur[j] * k_cur[j] + k_next[j] * k_next[j]);
      d[j] = cplx(k2 - kbar * kbar, 2.0 * std::sqrt(k2) * smooth) / (kbar * kbar);
      step_open[j] = cur.open[j] & next.open[j];
    }
    const RowOperator step{d.data(), step_open.data(), 1.0 / (kbar * g.dn * kbar * g.dn), nc,
                           open_end(u[0], u[1]), open_end(u[nc - 1], u[nc - 2])};
    apply(propagator, step, u.data(), scratch.data());
    for (std::size_t j = 0; j < nc; ++j) {
      if (!next.wet[j] || !next.reached[j]) u[j] = 0.0;
    }
    s += ds;
    phi += g.sigma;
    // The surface amplitude: eta = p^(-1/2) K^(-1/2) u.
    const double kbar_next = mean_k(k_next, next);
    for (std::size_t j = 0; j < nc; ++j) {
      d[j] = (k_next[j] * k_next[j] - kbar_next * kbar_next) / (kbar_next * kbar_next);
      out[j] = u[j];
    }
    apply(from_flux, {d.data(), next.open.data(), 1.0 / (kbar_next * g.dn * kbar_next * g.dn), nc}, out.data(),
          scratch.data());
    // A wave breaks where its height reaches gamma_b h and goes on breaking until it is down to the
    // stable height Gamma h (the sea surface caps what is left above gamma_b h, as for the rays).
    for (std::size_t j = 0; j < nc; ++j) {
      out[j] = next.wet[j] ? out[j] / std::sqrt(kbar_next * next.p[j]) : 0.0;
      amp[j] = std::abs(out[j]);
      const double h = std::max(next.depth[j], min_depth);
      breaking[j] = (breaking[j] || 2.0 * amp[j] > gamma_b * h) && 2.0 * amp[j] > dally_stable * h;
      f.broken += breaking[j];
    }
    store(s, phi);
    std::swap(cur, next);
    std::swap(k_cur, k_next);
  }
  return f;
}

}  // namespace houle::detail
