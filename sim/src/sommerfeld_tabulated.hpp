// The Sommerfeld modulus for the ray tracer's K' knots (tracer_k_factor.cpp): the field of
// houle::sommerfeld_field with the tabulated Fresnel auxiliary function. Internal to houle_sim.
#pragma once

namespace houle::detail {

/// |sommerfeld_field(k_r, theta, theta0, alpha)| within 1e-7, several times cheaper (the Fresnel part
/// from fresnel_aux_tabulated), from the two terms' Fresnel arguments v1 = s cos((theta - theta0) / 2)
/// and v2 = s cos((theta + theta0) / 2), s = sqrt(4 k r / pi); the second term only where alpha != 0.
double sommerfeld_modulus_at(double v1, double v2, double alpha) noexcept;

/// An upper bound on the modulus of one Sommerfeld term (alpha = 0, any v1): the lit side's first
/// fringe, 1.1705 (tests/sim/test_fresnel_integrals.cpp scans for it). So |F| <= bound (1 + alpha).
inline constexpr double sommerfeld_term_bound = 1.171;

}  // namespace houle::detail
