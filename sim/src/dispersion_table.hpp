// kh as a function of k0h by table, for the ray tracer's inner loop. Internal to houle_sim.
//
// x = kh is tabulated against u = sqrt(k0h) on [0, 5] (u is the natural variable: x ~ u in shallow
// water, x = u^2 in deep water) with exact derivatives, and interpolated by cubic Hermite: relative
// error below 1e-12 (tests/sim/test_dispersion.cpp), about ten times cheaper than Newton. Beyond
// k0h = 25, tanh kh = 1 to double precision and kh = k0h.
#pragma once

namespace houle::detail {

/// kh at y = k0h > 0 (0 for y <= 0 or NaN).
double kh_from_table(double y) noexcept;

}  // namespace houle::detail
