// The Sommerfeld modulus for the ray tracer's K' knots (wave_tracing.cpp): the field of
// houle::sommerfeld_field with the tabulated Fresnel auxiliary function. Internal to houle_sim.
#pragma once

namespace houle::detail {

/// |sommerfeld_field(k_r, theta, theta0, alpha)| (same arguments and ranges) within 1e-7, several
/// times cheaper: the Fresnel part from fresnel_aux_tabulated.
double sommerfeld_modulus_tabulated(double k_r, double theta, double theta0, double alpha) noexcept;

}  // namespace houle::detail
