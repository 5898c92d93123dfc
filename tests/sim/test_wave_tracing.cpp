// Dynamic Wave Tracing against oracles (docs/physics.md 8.4-8.11): straight rays on a flat bottom, Snell
// and shoaling on a planar beach, the insertion invariant, flux conservation, caustics behind a shoal,
// the shoreline and breaking, walls and the domain edge, determinism, and the paper's Fig. 4 scene
// (geometric optics: diffraction is the sea surface's, tests/sim/test_sea_surface.cpp).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <span>
#include <vector>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/wave_rays.hpp"
#include "angles.hpp"
#include "beach_scene.hpp"

namespace {

using houle::Scene;
using houle::WaveRays;
namespace rf = houle::ray_flag;
namespace sf = houle::sample_flag;
using houle_test::pi;

WaveRays trace(const Scene& s, std::size_t train = 0, houle::DwtStats* stats = nullptr) {
  auto r = houle::trace_train(s, train, s.dwt, stats);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().field + ": " + r.error().message);
  return r.ok() ? std::move(r).value() : WaveRays{};
}

bool all_finite(const WaveRays& w) {
  for (const auto* v : {&w.x, &w.y, &w.theta, &w.k, &w.amplitude, &w.phase, &w.time}) {
    for (double d : *v) {
      if (!std::isfinite(d)) return false;
    }
  }
  return true;
}

// Perpendicular spacing of ray b's sample sb from ray a's sample sa across their mean direction.
double spacing(const WaveRays& w, std::size_t sa, std::size_t sb) {
  const double mx = std::cos(w.theta[sa]) + std::cos(w.theta[sb]), my = std::sin(w.theta[sa]) + std::sin(w.theta[sb]);
  const double n = std::hypot(mx, my);
  return ((w.x[sb] - w.x[sa]) * -my + (w.y[sb] - w.y[sa]) * mx) / n;
}

// Sample pairs (this ray, its neighbour) joined by a sound tube on step j.
std::vector<std::pair<std::size_t, std::size_t>> tubes_on_step(const WaveRays& w, std::int32_t j) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    const std::int64_t a = w.sample_at_step(r, j);
    if (a < 0 || !(w.sample_flags[std::size_t(a)] & sf::tube_next)) continue;
    const std::int64_t q = w.next_on_step(r, j);
    EXPECT_GE(q, 0);
    if (q >= 0) out.emplace_back(std::size_t(a), std::size_t(w.sample_at_step(std::size_t(q), j)));
  }
  return out;
}

std::int32_t last_step(const WaveRays& w) {
  std::int32_t last = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    last = std::max<std::int32_t>(last, w.first_step[r] + std::int32_t(w.sample_begin[r + 1] - w.sample_begin[r]));
  }
  return last;
}

Scene flat_scene() {
  Scene s;
  s.domain = {0.0, 0.0, 200.0, 100.0};
  s.floor.base.depth = 8.0;
  houle::WaveTrain t;
  t.direction_deg = 30.0;
  t.period = 5.0;
  t.amplitude = 0.3;
  s.trains = {t};
  s.dwt.analytic_shortcut = false;  // trace even though the effect plan would not
  return s;
}

using houle_test::beach_scene;

Scene shoal_scene(double height) {
  Scene s;
  s.domain = {0.0, 0.0, 300.0, 300.0};
  s.floor.base.depth = 10.0;
  s.floor.shoals.push_back(houle::Shoal{{150.0, 100.0}, 40.0, 40.0, 0.0, height});
  houle::WaveTrain t;
  t.direction_deg = 90.0;
  t.period = 6.0;
  t.amplitude = 0.1;
  s.trains = {t};
  s.dwt.step = 1.0;
  s.dwt.insertion_distance = 2.0;
  s.camera.position = {150.0, -20.0, 5.0};
  return s;
}

// ---- Effect plan -------------------------------------------------------------------------------

TEST(WaveTracing, EffectPlanSkipsRaysAndDiffraction) {
  // Flat water, no walls: straight crests, analytic phase, no rays at all.
  Scene flat = flat_scene();
  flat.dwt.analytic_shortcut = true;
  EXPECT_FALSE(houle::train_needs_rays(flat, 0));
  EXPECT_FALSE(houle::scene_has_pierheads(flat));
  houle::DwtStats stats;
  const WaveRays w = trace(flat, 0, &stats);
  EXPECT_TRUE(w.analytic);
  EXPECT_EQ(w.ray_count(), 0u);
  EXPECT_EQ(stats.rays, 0u);
  EXPECT_EQ(stats.samples, 0u);
  EXPECT_NEAR(w.analytic_k, houle::linear_wave(w.omega, 8.0).k, 1e-12);
  // Deep everywhere despite a shoal (30 m under the crest, L0 = 3.9 m): also analytic.
  Scene deep = flat;
  deep.trains[0].period = 1.6;
  deep.floor.base.depth = 40.0;
  deep.floor.shoals.push_back(houle::Shoal{{100, 50}, 20, 20, 0, 10});
  EXPECT_FALSE(houle::train_needs_rays(deep, 0));
  // A beach needs rays; without walls there is no diffraction work.
  const Scene beach = beach_scene(60.0, 1.0);
  EXPECT_TRUE(houle::train_needs_rays(beach, 0));
  EXPECT_FALSE(houle::scene_has_pierheads(beach));
  trace(beach, 0, &stats);
  EXPECT_GT(stats.rays, 0u);
  // A wall with a pierhead in the water: diffraction work exists (the sea surface's: test_effect_plan.cpp).
  EXPECT_TRUE(houle::scene_has_pierheads(houle::paper_fig4()));
  Scene off = houle::paper_fig4();
  off.dwt.diffraction = false;
  EXPECT_FALSE(houle::scene_has_pierheads(off));
}

// ---- Flat bottom (docs/physics.md 8.4) ------------------------------------------------------------------

TEST(WaveTracing, FlatBottomStraightRaysConstantAmplitudeNoInsertion) {
  const Scene s = flat_scene();
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  ASSERT_GT(w.ray_count(), 100u);
  EXPECT_EQ(stats.inserted_rays, 0u);
  EXPECT_EQ(stats.crossings, 0u);
  EXPECT_TRUE(all_finite(w));
  const houle::LinearWave lw = houle::linear_wave(w.omega, 8.0);
  const double a = 0.3 * houle::shoaling_coefficient(lw.kh);
  const double theta = 30.0 * pi / 180.0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    const std::size_t b = w.sample_begin[r];
    for (std::size_t i = b; i < w.sample_begin[r + 1]; ++i) {
      EXPECT_NEAR(w.theta[i], theta, 1e-15);
      // On the ray's line through its first sample (tolerance: rounding of ~100 m coordinates).
      EXPECT_NEAR(-(w.x[i] - w.x[b]) * std::sin(theta) + (w.y[i] - w.y[b]) * std::cos(theta), 0.0, 1e-9);
      EXPECT_NEAR(w.amplitude[i] / a, 1.0, 1e-12);
      EXPECT_NEAR(w.k[i] / lw.k, 1.0, 1e-12);
    }
    EXPECT_TRUE(w.flags[r] & rf::left_domain);
  }
  // Constant spacing between neighbours on every wavefront.
  double expected = -1.0, worst = 0.0;
  for (std::int32_t j = 0; j <= last_step(w); ++j) {
    for (const auto& [a0, b0] : tubes_on_step(w, j)) {
      const double sg = spacing(w, a0, b0);
      if (expected < 0.0) expected = sg;
      worst = std::max(worst, std::fabs(sg - expected));
    }
  }
  EXPECT_GT(expected, 0.0);
  EXPECT_LT(expected, s.dwt.insertion_distance);
  EXPECT_LT(worst, 1e-9);
  // Equal-phase steps: on-grid sample j has phase j * phase_step exactly.
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    for (std::int32_t j = w.first_step[r]; j < w.first_step[r] + 5; ++j) {
      const std::int64_t i = w.sample_at_step(r, j);
      if (i >= 0) {
        EXPECT_EQ(w.phase[std::size_t(i)], double(j) * w.phase_step);
      }
    }
  }
}

// ---- Planar beach: Snell and shoaling (docs/physics.md 8.5) -------------------------------------------

void check_snell_and_shoaling(double step) {
  const Scene s = beach_scene(60.0, step);
  const houle::Bathymetry floor(s.floor);
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  ASSERT_GT(w.ray_count(), 50u);
  EXPECT_TRUE(all_finite(w));
  EXPECT_EQ(stats.broken_rays, 0u);
  EXPECT_GT(stats.inserted_rays, 0u);  // refraction towards the normal spreads the rays
  double worst_snell = 0.0, worst_amp = 0.0, worst_amp_edge = 0.0;
  std::size_t checked = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    // Tolerances: each ray's first (partial) step crosses the kink between the uniform water assumed
    // outside the domain and the slope inside; the chord between neighbours there is not quite the
    // tube width (1.5e-5 measured, then constant along the ray: 3e-5 allowed). The two outermost rays
    // have a tube on one side only, so nothing averages it (8e-5 measured: 1e-4 allowed).
    const bool edge = r == 0 || r + 1 == w.ray_count();
    const std::size_t b = w.sample_begin[r], e = w.sample_begin[r + 1];
    if (b == e) continue;
    // theta from +x; the contour normal is +y, so sin(angle from the normal) = cos(theta).
    const houle::LinearWave w0 = houle::linear_wave(w.omega, floor.depth(w.x[b], w.y[b]));
    const double q0 = std::cos(w.theta[b]) / w0.c;
    for (std::size_t i = b; i < e; ++i) {
      const double h = floor.depth(w.x[i], w.y[i]);
      const houle::LinearWave wi = houle::linear_wave(w.omega, h);
      worst_snell = std::max(worst_snell, std::fabs(std::cos(w.theta[i]) / wi.c / q0 - 1.0));
      // A = A_first Ks/Ks_first sqrt(cos a_first / cos a), cos a = sin theta.
      const double expected = w.amplitude[b] * houle::shoaling_coefficient(wi.kh) / houle::shoaling_coefficient(w0.kh) *
                              std::sqrt(std::sin(w.theta[b]) / std::sin(w.theta[i]));
      (edge ? worst_amp_edge : worst_amp) = std::max(edge ? worst_amp_edge : worst_amp, std::fabs(w.amplitude[i] / expected - 1.0));
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000u);
  EXPECT_LT(worst_snell, 1e-6) << "step " << step;
  EXPECT_LT(worst_amp, 3e-5) << "step " << step;
  EXPECT_LT(worst_amp_edge, 1e-4) << "step " << step;
  std::printf("planar beach, step %.2f m: %zu samples, sin(a)/C conserved to %.2e, A vs A0 Ks Kr to %.2e (front's "
              "edge rays %.2e)\n", step, checked, worst_snell, worst_amp, worst_amp_edge);
}

TEST(WaveTracing, PlanarBeachConservesSnellAndFollowsShoaling) {
  check_snell_and_shoaling(1.0);
  check_snell_and_shoaling(0.25);  // converged: the same invariants at any step
}

// ---- Insertion (docs/physics.md 8.7) ------------------------------------------------------------------

TEST(WaveTracing, InsertionKeepsNeighboursWithinBmaxAndBetweenParents) {
  const Scene s = shoal_scene(3.0);
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  ASSERT_GT(stats.inserted_rays, 0u);
  const double b_max = s.dwt.insertion_distance;
  double widest = 0.0;
  std::size_t tubes = 0;
  for (std::int32_t j = 0; j <= last_step(w); ++j) {
    for (const auto& [a, b] : tubes_on_step(w, j)) {
      widest = std::max(widest, spacing(w, a, b));
      ++tubes;
    }
  }
  EXPECT_GT(tubes, 10000u);
  EXPECT_LE(widest, b_max * (1.0 + 1e-12));
  std::size_t children = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    if (w.parent_a[r] < 0) continue;
    const std::size_t pa = std::size_t(w.parent_a[r]), pb = std::size_t(w.parent_b[r]);
    EXPECT_LT(pa, r);
    EXPECT_GT(pb, r);
    const std::int32_t j = w.first_step[r];
    const std::int64_t c = w.sample_at_step(r, j), a = w.sample_at_step(pa, j), b = w.sample_at_step(pb, j);
    if (c < 0 || a < 0 || b < 0) continue;
    // Midpoint of the parents on the same wavefront, amplitude between theirs.
    EXPECT_NEAR(w.x[std::size_t(c)], 0.5 * (w.x[std::size_t(a)] + w.x[std::size_t(b)]), 1e-9);
    EXPECT_NEAR(w.y[std::size_t(c)], 0.5 * (w.y[std::size_t(a)] + w.y[std::size_t(b)]), 1e-9);
    EXPECT_EQ(w.phase[std::size_t(c)], w.phase[std::size_t(a)]);
    EXPECT_EQ(w.phase[std::size_t(c)], w.phase[std::size_t(b)]);
    const double lo = std::min(w.amplitude[std::size_t(a)], w.amplitude[std::size_t(b)]);
    const double hi = std::max(w.amplitude[std::size_t(a)], w.amplitude[std::size_t(b)]);
    EXPECT_GE(w.amplitude[std::size_t(c)], lo * (1.0 - 1e-12));
    EXPECT_LE(w.amplitude[std::size_t(c)], hi * (1.0 + 1e-12));
    ++children;
  }
  EXPECT_GT(children, 0u);
}

TEST(WaveTracing, EnergyFluxConservedOnASmoothBottom) {
  // A gentle shoal: rays bend, converge over it and spread behind it (insertions). The flux is
  // compared on every wavefront up to the first crossing, if any (beyond it rays no longer bound tubes).
  const Scene s = shoal_scene(1.5);
  const houle::Bathymetry floor(s.floor);
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  ASSERT_GT(stats.inserted_rays, 0u);
  std::int32_t first_crossing = last_step(w);
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    for (std::size_t i = w.sample_begin[r]; i < w.sample_begin[r + 1]; ++i) {
      if (w.sample_flags[i] & sf::crossed) {
        first_crossing = std::min(first_crossing, w.first_step[r] + std::int32_t(i - w.sample_begin[r]));
        break;
      }
    }
  }
  ASSERT_GT(first_crossing, 200);  // past the shoal (y = 60..140 m) and well beyond
  // Sum over sound tubes of (A^2 Cg at both ends, averaged) x spacing, per wavefront.
  auto flux = [&](std::int32_t j) {
    double f = 0.0;
    auto e = [&](std::size_t i) {
      return w.amplitude[i] * w.amplitude[i] * houle::linear_wave(w.omega, floor.depth(w.x[i], w.y[i])).cg;
    };
    for (const auto& [a, b] : tubes_on_step(w, j)) f += 0.5 * (e(a) + e(b)) * spacing(w, a, b);
    return f;
  };
  const double f0 = flux(1);
  double worst = 0.0;
  for (std::int32_t j = 10; j < std::min(first_crossing, last_step(w) - 2); j += 5) {
    worst = std::max(worst, std::fabs(flux(j) / f0 - 1.0));
  }
  EXPECT_LT(worst, 0.03);
  std::printf("energy flux across wavefronts over a shoal: max deviation %.3f %%\n", 100.0 * worst);
}

// ---- Caustics: circular shoal (docs/physics.md 8.6) ----------------------------------------------------

TEST(WaveTracing, CircularShoalIsSymmetricCrossesAndStaysCapped) {
  const Scene s = shoal_scene(7.0);  // crest 3 m under water: strong focusing, caustics behind
  const houle::Bathymetry floor(s.floor);
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  EXPECT_TRUE(all_finite(w));
  EXPECT_GT(stats.crossings, 0u);
  std::size_t crossed = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) crossed += (w.flags[r] & rf::crossed) ? 1 : 0;
  EXPECT_GT(crossed, 0u);
  // Capped: Kr <= 2.5 and the breaking limits.
  for (std::size_t i = 0; i < w.sample_count(); ++i) {
    const double h = floor.depth(w.x[i], w.y[i]);
    const houle::LinearWave lw = houle::linear_wave(w.omega, h);
    ASSERT_LE(w.amplitude[i], s.dwt.max_refraction_coefficient * 0.1 * houle::shoaling_coefficient(lw.kh) * (1 + 1e-9));
    ASSERT_LE(2.0 * w.amplitude[i], s.dwt.breaker_index * h * (1 + 1e-9));
  }
  // Mirror symmetry about x = 150 on every wavefront (the front is symmetric and so is the floor).
  double worst = 0.0;
  std::size_t compared = 0;
  for (std::int32_t j = 0; j <= last_step(w); j += 7) {
    std::vector<std::pair<double, double>> row;  // (x, A)
    for (std::size_t r = 0; r < w.ray_count(); ++r) {
      const std::int64_t i = w.sample_at_step(r, j);
      if (i >= 0) row.emplace_back(w.x[std::size_t(i)], w.amplitude[std::size_t(i)]);
    }
    std::sort(row.begin(), row.end());
    if (row.empty()) continue;
    for (std::size_t a = 0, b = row.size() - 1; a < b; ++a, --b) {
      worst = std::max({worst, std::fabs(row[a].first + row[b].first - 300.0), std::fabs(row[a].second - row[b].second)});
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_LT(worst, 1e-6);
  std::printf("circular shoal: %llu crossings, %zu crossed rays, mirror asymmetry %.1e\n",
              static_cast<unsigned long long>(stats.crossings), crossed, worst);
}

// ---- Shoreline and breaking (docs/physics.md 8.9) --------------------------------------------------------

Scene shore_scene(double amplitude) {
  Scene s;
  s.domain = {0.0, 0.0, 100.0, 300.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 8.0;
  s.floor.base.slope = 1.0 / 30.0;
  s.floor.base.shoreward_deg = 90.0;
  s.floor.base.shoreline = {0.0, 240.0};  // land beyond y = 240
  houle::WaveTrain t;
  t.direction_deg = 90.0;
  t.period = 7.0;
  t.amplitude = amplitude;
  s.trains = {t};
  s.dwt.step = 0.5;
  s.dwt.insertion_distance = 2.0;
  s.camera.position = {50.0, -10.0, 5.0};
  return s;
}

TEST(WaveTracing, RaysStopAtTheShorelineAndNeverExceedTheBreakingLimit) {
  double previous_breaking_depth = 0.0;
  // h_min = 0.01 L0 = 0.77 m here: the smallest wave still breaks before it.
  for (double a0 : {0.3, 0.6, 1.2, 2.4}) {
    const Scene s = shore_scene(a0);
    const houle::Bathymetry floor(s.floor);
    houle::DwtStats stats;
    const WaveRays w = trace(s, 0, &stats);
    EXPECT_TRUE(all_finite(w));
    EXPECT_GT(stats.reached_shore, 0u);
    EXPECT_GT(stats.broken_rays, 0u);
    for (std::size_t i = 0; i < w.sample_count(); ++i) {
      const double h = floor.depth(w.x[i], w.y[i]);
      ASSERT_GE(h, w.min_depth * (1 - 1e-9));  // nothing on land
      ASSERT_LE(2.0 * w.amplitude[i], s.dwt.breaker_index * h * (1 + 1e-12) + 1e-15);
    }
    // The middle ray: ends at h_min, breaks first at a depth that grows with the offshore height.
    const std::size_t r = w.ray_count() / 2;
    ASSERT_TRUE(w.flags[r] & rf::reached_shore);
    const std::size_t last = w.sample_begin[r + 1] - 1;
    EXPECT_NEAR(floor.depth(w.x[last], w.y[last]), w.min_depth, 1e-6);
    double breaking_depth = 0.0;
    for (std::size_t i = w.sample_begin[r]; i < w.sample_begin[r + 1]; ++i) {
      if (w.sample_flags[i] & sf::broken) {
        breaking_depth = floor.depth(w.x[i], w.y[i]);
        break;
      }
    }
    EXPECT_GT(breaking_depth, previous_breaking_depth) << "A0 " << a0;
    std::printf("plane beach 1:30, A0 = %.2f m: breaks at h = %.3f m (H/h = %.2f there)\n", a0, breaking_depth,
                s.dwt.breaker_index);
    previous_breaking_depth = breaking_depth;
  }
}

// ---- Walls and the domain edge (docs/physics.md 8.8) -------------------------------------------------------

TEST(WaveTracing, RaysEndFlaggedOnWallsAndAtTheDomainEdge) {
  Scene s = flat_scene();
  s.trains[0].direction_deg = 90.0;
  houle::Wall wall;
  wall.points = {{60.0, 40.0}, {140.0, 60.0}};  // a detached breakwater: two pierheads
  wall.thickness = 2.0;
  s.walls = {wall};
  s.dwt.diffraction = false;  // walls only
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  EXPECT_GT(stats.wall_hits, 0u);
  EXPECT_GT(stats.left_domain, 0u);
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    ASSERT_TRUE(w.flags[r] & rf::dead);
    const std::size_t last = w.sample_begin[r + 1] - 1;
    ASSERT_TRUE(w.sample_flags[last] & sf::off_grid);
    const double x = w.x[last], y = w.y[last];
    if (w.flags[r] & rf::hit_wall) {
      // On the capsule's surface: distance to the segment = half the thickness.
      const double ex = 80.0, ey = 20.0, t = std::clamp(((x - 60.0) * ex + (y - 40.0) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
      EXPECT_NEAR(std::hypot(x - 60.0 - t * ex, y - 40.0 - t * ey), 1.0, 1e-6);
      EXPECT_TRUE(x > 57.0 && x < 143.0);
    } else {
      EXPECT_TRUE(w.flags[r] & rf::left_domain);
      EXPECT_NEAR(y, 100.0, 1e-9);
    }
    // No tube is ever marked across a ray that has ended.
    for (std::size_t i = w.sample_begin[r]; i < w.sample_begin[r + 1]; ++i) {
      if (!(w.sample_flags[i] & sf::tube_next)) continue;
      ASSERT_LT(r + 1, w.ray_count());
      ASSERT_FALSE(w.sample_flags[i] & sf::off_grid);
    }
  }
}

TEST(WaveTracing, AWallBeyondTheEdgeShadowsTheEntryFront) {
  // A wall from (-10, 90) to (230, 90) runs out through the domain's west edge; waves travel at 30
  // degrees. The front entering through the west edge just north of the wall (y from 90 to 95.8 m)
  // lies in the wall's shadow: its straight path from upstream crosses the wall's stub outside the
  // domain. No incident sample may lie in the lee: north of the wall, between the shadow lines from
  // its two ends (1.5 m clear of them: the wall's half thickness and a margin).
  Scene s = flat_scene();  // waves towards 30 degrees
  s.domain = {0.0, 0.0, 320.0, 180.0};
  houle::Wall wall;
  wall.points = {{-10.0, 90.0}, {230.0, 90.0}};
  wall.thickness = 2.0;
  s.walls = {wall};
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  EXPECT_TRUE(all_finite(w));
  const double nx = -0.5, ny = std::sqrt(3.0) / 2.0;  // left of the direction of travel
  auto left_of = [&](double x, double y, double mx, double my) { return (x - mx) * nx + (y - my) * ny; };
  std::size_t in_lee = 0, lit_west = 0, shadowed = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    if ((w.flags[r] & rf::hit_wall) && w.sample_begin[r] == w.sample_begin[r + 1]) ++shadowed;
    for (std::size_t i = w.sample_begin[r]; i < w.sample_begin[r + 1]; ++i) {
      const double x = w.x[i], y = w.y[i];
      if (!(y > 91.5)) continue;
      const double from_west = left_of(x, y, -10.0, 90.0), from_east = left_of(x, y, 230.0, 90.0);
      if (from_west < -1.5 && from_east > 1.5) ++in_lee;
      if (from_west > 1.5 && x < 100.0) ++lit_west;
    }
  }
  EXPECT_EQ(in_lee, 0u);
  EXPECT_GT(lit_west, 1000u);  // west of the shadow line the front enters as before
  EXPECT_GT(shadowed, 0u);     // the entries behind the wall: dead, on the wall, without samples
  // A wall that stays inside the domain shadows nothing of the entry front.
  s.walls[0].points = {{10.0, 90.0}, {230.0, 90.0}};
  const WaveRays inside = trace(s);
  for (std::size_t r = 0; r < inside.ray_count(); ++r) {
    if (inside.flags[r] & rf::hit_wall) {
      EXPECT_GT(inside.sample_begin[r + 1], inside.sample_begin[r]);
    }
  }
}

// ---- Determinism (docs/physics.md 8.11) -----------------------------------------------------------------

template <class T>
std::vector<T> values(std::span<const T> v) {
  return {v.begin(), v.end()};
}

void expect_identical(const WaveRays& a, const WaveRays& b) {
  EXPECT_EQ(a.sample_begin, b.sample_begin);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.first_step, b.first_step);
  EXPECT_EQ(a.parent_a, b.parent_a);
  EXPECT_EQ(values(a.x), values(b.x));
  EXPECT_EQ(values(a.y), values(b.y));
  EXPECT_EQ(values(a.theta), values(b.theta));
  EXPECT_EQ(values(a.k), values(b.k));
  EXPECT_EQ(values(a.amplitude), values(b.amplitude));
  EXPECT_EQ(values(a.phase), values(b.phase));
  EXPECT_EQ(values(a.time), values(b.time));
  EXPECT_EQ(values(a.sample_flags), values(b.sample_flags));
}

TEST(WaveTracing, DeterministicAcrossRunsAndThreadCounts) {
  const Scene coast = houle::builtin_coast();
  const auto one = houle::trace_wave_field(coast, 1);
  const auto two = houle::trace_wave_field(coast, 2);
  const auto three = houle::trace_wave_field(coast, 3);
  const auto six = houle::trace_wave_field(coast, 6);  // each train on a worker and its second lane
  ASSERT_TRUE(one.ok() && two.ok() && three.ok() && six.ok());
  ASSERT_EQ(one->trains.size(), 3u);
  for (std::size_t t = 0; t < 3; ++t) {
    expect_identical(one->trains[t], two->trains[t]);
    expect_identical(one->trains[t], three->trains[t]);
    expect_identical(one->trains[t], six->trains[t]);
    EXPECT_TRUE(all_finite(one->trains[t]));
  }
  EXPECT_EQ(one->stats.samples, three->stats.samples);
  EXPECT_EQ(one->stats.samples, six->stats.samples);
  // The jetty reflects (alpha > 0): its reflected waves too.
  ASSERT_FALSE(one->reflections.empty());
  ASSERT_EQ(one->reflections.size(), two->reflections.size());
  ASSERT_EQ(one->reflections.size(), six->reflections.size());
  for (std::size_t i = 0; i < one->reflections.size(); ++i) {
    EXPECT_EQ(one->reflections[i].train, two->reflections[i].train);
    expect_identical(one->reflections[i].rays, two->reflections[i].rays);
    expect_identical(one->reflections[i].rays, six->reflections[i].rays);
    EXPECT_TRUE(all_finite(one->reflections[i].rays));
  }
  const WaveRays a = trace(houle::paper_fig4()), b = trace(houle::paper_fig4());
  expect_identical(a, b);
}

TEST(WaveTracing, OneTrainOnTwoThreadsIsBitIdentical) {
  // One train of the coast: its rays curve over the floor and the front is large, so steps share
  // their rays between two threads.
  Scene swell = houle::builtin_coast();
  swell.trains.resize(1);
  houle::DwtStats one_stats, two_stats, reflected_stats;
  const auto one = houle::trace_train(swell, 0, swell.dwt, &one_stats, 1);
  const auto two = houle::trace_train(swell, 0, swell.dwt, &two_stats, 2);
  ASSERT_TRUE(one.ok() && two.ok());
  EXPECT_EQ(one_stats.shared_steps, 0u);
  EXPECT_GT(two_stats.shared_steps, two_stats.steps / 2);
  expect_identical(one.value(), two.value());
  EXPECT_EQ(one_stats.samples, two_stats.samples);
  EXPECT_EQ(one_stats.wall_hits, two_stats.wall_hits);
  EXPECT_EQ(one_stats.broken_rays, two_stats.broken_rays);
  // Its reflection too, and the field (which traces the reflection from the sweep's own ends).
  const auto reflected = houle::trace_reflection(swell, 0, one.value(), swell.dwt, &reflected_stats, 2);
  ASSERT_TRUE(reflected.ok());
  EXPECT_GT(reflected_stats.shared_steps, 0u);
  const auto field = houle::trace_wave_field(swell, 2);
  ASSERT_TRUE(field.ok());
  ASSERT_EQ(field->reflections.size(), 1u);
  expect_identical(field->trains[0], one.value());
  expect_identical(field->reflections[0].rays, reflected.value());
}

TEST(WaveTracing, StraightRaysDoNotShareSteps) {
  // Fig. 4's flat bottom: a straight step costs less than moving a ray between cores, so the second
  // thread traces the reflected wave while the incident samples are gathered instead.
  const Scene fig4 = houle::paper_fig4();
  const auto one = houle::trace_wave_field(fig4, 1);
  const auto two = houle::trace_wave_field(fig4, 2);
  ASSERT_TRUE(one.ok() && two.ok());
  EXPECT_EQ(two->stats.shared_steps, 0u);
  ASSERT_EQ(one->reflections.size(), 1u);
  ASSERT_EQ(two->reflections.size(), 1u);
  expect_identical(one->trains[0], two->trains[0]);
  expect_identical(one->reflections[0].rays, two->reflections[0].rays);
  EXPECT_EQ(one->stats.samples, two->stats.samples);
  // As trace_reflection gives it from the incident output.
  const auto reflected = houle::trace_reflection(fig4, 0, one->trains[0], fig4.dwt);
  ASSERT_TRUE(reflected.ok());
  expect_identical(two->reflections[0].rays, reflected.value());
}

// ---- Caps and bounds ----------------------------------------------------------------------------------

TEST(WaveTracing, CapsBoundTheOutput) {
  Scene s = shoal_scene(3.0);
  s.wave_model.kind = houle::WaveModelKind::rays;  // a marched train's capped rays are no truncation
  const houle::DwtBound bound = houle::dwt_bound(s, 0, s.dwt);
  houle::DwtStats stats;
  WaveRays w = trace(s, 0, &stats);
  EXPECT_LE(w.ray_count(), bound.rays);
  EXPECT_LE(w.sample_count(), bound.samples);
  EXPECT_FALSE(stats.truncated);
  EXPECT_EQ(stats.samples, w.sample_count());
  s.dwt.max_rays = 200;
  w = trace(s, 0, &stats);
  EXPECT_LE(w.ray_count(), 200u);
  EXPECT_GT(stats.insertions_refused, 0u);
  EXPECT_TRUE(stats.truncated);
  s.dwt.max_samples = 5000;
  w = trace(s, 0, &stats);
  EXPECT_LE(w.sample_count(), 5000u);
  EXPECT_TRUE(stats.truncated);
  EXPECT_TRUE(all_finite(w));
}

// trace_wave_field refuses a truncated field by default and says which cap; dwt.on_cap = warn keeps it
// (truncated in the stats, which every command reports).
TEST(WaveTracing, ACapIsAnErrorUnlessTheSceneAllowsIt) {
  Scene s = shoal_scene(3.0);
  // With rays (a marched train's rays only seed the carrier: test_parabolic_model.cpp).
  s.wave_model.kind = houle::WaveModelKind::rays;
  ASSERT_TRUE(houle::trace_wave_field(s, 1).ok());
  s.dwt.max_samples = 5000;
  const auto refused = houle::trace_wave_field(s, 1);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "dwt.on_cap");
  EXPECT_NE(refused.error().message.find("dwt.max_samples (5000 samples)"), std::string::npos) << refused.error().message;
  s.dwt.max_samples = houle::DwtSettings{}.max_samples;
  s.dwt.max_rays = 200;
  const auto rays = houle::trace_wave_field(s, 1);
  ASSERT_FALSE(rays.ok());
  EXPECT_NE(rays.error().message.find("dwt.max_rays (200 rays)"), std::string::npos) << rays.error().message;
  s.dwt.on_cap = houle::OnCap::warn;
  const auto kept = houle::trace_wave_field(s, 1);
  ASSERT_TRUE(kept.ok());
  EXPECT_TRUE(kept->stats.truncated);
  EXPECT_GT(kept->stats.insertions_refused, 0u);
}

TEST(WaveTracing, RejectsInvalidInput) {
  Scene s = houle::paper_fig4();
  EXPECT_FALSE(houle::trace_train(s, 1, s.dwt).ok());
  houle::DwtSettings bad = s.dwt;
  bad.step = -1.0;
  const auto r = houle::trace_train(s, 0, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "dwt.step");
  s.trains[0].period = 0.0;
  EXPECT_FALSE(houle::trace_wave_field(s).ok());
}

// ---- The paper's Fig. 4 ---------------------------------------------------------------------------------

double cpu_ms() { return 1000.0 * double(std::clock()) / CLOCKS_PER_SEC; }

TEST(WaveTracing, PaperFig4Scene) {
  // Geometric optics only: on the flat bottom every sample carries the incident amplitude A0 Ks
  // exactly (no diffraction coefficient near the shadow line, relative tolerance 1e-12), rays that
  // meet the wall end on it, and none reaches its lee (x < 50 m, north of the wall's lee face).
  const Scene s = houle::paper_fig4();
  houle::DwtStats stats;
  const double c0 = cpu_ms();
  const auto t0 = std::chrono::steady_clock::now();
  const WaveRays w = trace(s, 0, &stats);
  const auto t1 = std::chrono::steady_clock::now();
  const double c1 = cpu_ms();
  EXPECT_TRUE(all_finite(w));
  EXPECT_FALSE(stats.truncated);
  EXPECT_EQ(stats.rays, stats.initial_rays + stats.inserted_rays);
  const double a = s.trains[0].amplitude * houle::shoaling_coefficient(houle::linear_wave(w.omega, 10.0).kh);
  std::size_t on_wall = 0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    for (std::size_t i = w.sample_begin[r]; i < w.sample_begin[r + 1]; ++i) {
      ASSERT_NEAR(w.amplitude[i], a, 1e-12 * a);
      ASSERT_FALSE(w.x[i] < 50.0 && w.y[i] > 50.5 + 1e-9) << "a sample in the lee at (" << w.x[i] << ", " << w.y[i] << ")";
    }
    if (w.flags[r] & rf::hit_wall) {
      ++on_wall;
      // On the wall's surface: 0.5 m (half its thickness) from the segment y = 50, x <= 50.
      const std::size_t last = w.sample_begin[r + 1] - 1;
      EXPECT_NEAR(std::hypot(std::max(w.x[last] - 50.0, 0.0), w.y[last] - 50.0), 0.5, 1e-6);
      EXPECT_LT(w.y[last], 50.0);
    }
  }
  EXPECT_GT(on_wall, 30u);
  std::printf("Fig. 4: %llu rays (%llu initial, %llu inserted), %llu samples, %zu rays on the wall; "
              "build %.2f ms wall, %.2f ms CPU\n",
              static_cast<unsigned long long>(stats.rays), static_cast<unsigned long long>(stats.initial_rays),
              static_cast<unsigned long long>(stats.inserted_rays), static_cast<unsigned long long>(stats.samples), on_wall,
              std::chrono::duration<double, std::milli>(t1 - t0).count(), c1 - c0);
  // The alternative reading of the paper: a 69 m front at exactly 1 m spacing (docs/physics.md 2.1).
  Scene narrow = s;
  narrow.dwt.front_width = 69.0 + 1.0;
  houle::DwtStats ns;
  trace(narrow, 0, &ns);
  std::printf("Fig. 4 with a 70 m front (70 rays 1 m apart): %llu rays, %llu samples\n",
              static_cast<unsigned long long>(ns.rays), static_cast<unsigned long long>(ns.samples));
}

TEST(WaveTracing, TurningRaysConserveSnellAndEndCleanly) {
  // docs/physics.md 8.10: rays heading 5 degrees seaward along a beach's contours turn back towards the
  // shore where sin(angle from the normal) / C would exceed 1/C. Nothing stalls or goes non-finite,
  // cos(theta) / C (Snell on contours along x) is conserved through the turning point, theta changes
  // smoothly, and every ray ends.
  Scene s = beach_scene(-5.0, 1.0);
  s.domain = {0.0, 150.0, 2000.0, 450.0};  // 9 m deep at the southern edge, 1 m at the northern
  s.dwt.front_width = 60.0;
  const houle::Bathymetry floor(s.floor);
  houle::DwtStats stats;
  const WaveRays w = trace(s, 0, &stats);
  EXPECT_TRUE(all_finite(w));
  EXPECT_FALSE(stats.truncated);
  double worst_snell = 0.0, worst_turn = 0.0, min_theta = 0.0, max_theta = -1.0;
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    ASSERT_TRUE(w.flags[r] & rf::dead);
    const std::size_t b = w.sample_begin[r], e = w.sample_begin[r + 1];
    if (b == e) continue;
    const double q0 = std::cos(w.theta[b]) / houle::linear_wave(w.omega, floor.depth(w.x[b], w.y[b])).c;
    for (std::size_t i = b; i < e; ++i) {
      const double c = houle::linear_wave(w.omega, floor.depth(w.x[i], w.y[i])).c;
      worst_snell = std::max(worst_snell, std::fabs(std::cos(w.theta[i]) / c / q0 - 1.0));
      if (i > b) worst_turn = std::max(worst_turn, std::fabs(w.theta[i] - w.theta[i - 1]));
      min_theta = std::min(min_theta, w.theta[i]);
      max_theta = std::max(max_theta, w.theta[i]);
    }
  }
  EXPECT_LT(min_theta, -0.05);  // they did head seaward
  EXPECT_GT(max_theta, 0.0);    // and turned shoreward
  EXPECT_LT(worst_snell, 2.5e-6);  // "about 1e-6" (docs/physics.md 8.5); 1.3e-6 measured, at the turning point
  EXPECT_LT(worst_turn, 0.05);  // a few sub-steps of at most 0.05 rad each would show as more
  std::printf("turning rays: theta from %.3f to %.3f rad, cos(theta)/C conserved to %.1e, largest turn per step %.1e rad\n",
              min_theta, max_theta, worst_snell, worst_turn);
}

TEST(WaveTracing, RaysDoNotDependOnTheDiffractionSettings) {
  // Diffraction is the sea surface's: the rays, and their reflected wave, are the same whichever
  // model is chosen and with diffraction off.
  const Scene fig4 = houle::paper_fig4();
  const auto base = houle::trace_wave_field(fig4);
  ASSERT_TRUE(base.ok());
  ASSERT_EQ(base->reflections.size(), 1u);
  for (int variant = 0; variant < 3; ++variant) {
    Scene s = fig4;
    if (variant == 0) s.dwt.diffraction_model = houle::DiffractionModel::paper;
    if (variant == 1) s.dwt.diffraction_model = houle::DiffractionModel::paper_corrected;
    if (variant == 2) s.dwt.diffraction = false;
    const auto f = houle::trace_wave_field(s);
    ASSERT_TRUE(f.ok());
    expect_identical(f->trains[0], base->trains[0]);
    ASSERT_EQ(f->reflections.size(), 1u);
    expect_identical(f->reflections[0].rays, base->reflections[0].rays);
  }
}

TEST(WaveTracing, BuiltinCoastIsFiniteAndSound) {
  const Scene s = houle::builtin_coast();
  const houle::Bathymetry floor(s.floor);
  const auto field = houle::trace_wave_field(s, 2);
  ASSERT_TRUE(field.ok());
  const houle::DwtStats& st = field->stats;
  EXPECT_FALSE(st.truncated);
  for (std::size_t t = 0; t < field->trains.size(); ++t) {
    const WaveRays& w = field->trains[t];
    EXPECT_TRUE(all_finite(w));
    for (std::size_t i = 0; i < w.sample_count(); ++i) {
      const double h = floor.depth(w.x[i], w.y[i]);
      ASSERT_GE(h, w.min_depth * (1 - 1e-9));
      ASSERT_LE(2.0 * w.amplitude[i], s.dwt.breaker_index * h * (1 + 1e-12) + 1e-15);
    }
  }
  std::printf("builtin coast: %llu rays (%llu inserted), %llu samples, %llu crossings, %llu broken, "
              "%llu at the shore, %llu on walls\n",
              static_cast<unsigned long long>(st.rays), static_cast<unsigned long long>(st.inserted_rays),
              static_cast<unsigned long long>(st.samples),
              static_cast<unsigned long long>(st.crossings), static_cast<unsigned long long>(st.broken_rays),
              static_cast<unsigned long long>(st.reached_shore), static_cast<unsigned long long>(st.wall_hits));
}

}  // namespace
