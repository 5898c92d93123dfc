// The sea that houle probe and houle map read: the scene traced and resampled once, at the realtime
// quality's grid, each train's parts (incident, diffracted, reflected) kept for SeaSurface::probe.
#pragma once
#include <optional>
#include <string>

#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"

namespace houle::cli {

/// Positions are floats: 100 km out they still resolve 8 mm, a small fraction of the shortest
/// wavelength; at 1e9 m the resolution is 64 m and the height is noise, then inf and NaN. Points
/// farther than this outside the domain are refused.
inline constexpr double max_probe_distance = 100e3;  // m
/// How far (x, y) lies outside `d` (m; 0 inside).
double distance_outside(const Domain& d, double x, double y);

/// The sea of `scene` (called `name` in messages), or nothing after printing
/// "houle <command>: <name>: field: what" and setting `exit_code` (2: the scene is refused, 1: the
/// build failed). A trace stopped at a cap is warned of (warn_if_truncated).
std::optional<SeaSurface> build_probe_sea(const Scene& scene, const std::string& name, const char* command, int& exit_code);

}  // namespace houle::cli
