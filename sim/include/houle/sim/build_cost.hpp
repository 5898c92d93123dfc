// What building a scene will take, estimated before any of it is done (docs/design.md 7): the peak
// resident memory and the CPU time of Animation::create (tracing, the sea's grids, the floor grid,
// the renderer) at a quality and image size. Every command checks it first, and `validate` checks the
// cheapest build (draft quality) so that whatever validates builds.
#pragma once
#include <cstdint>
#include <string>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {

struct Quality;  // animation.hpp

struct BuildCost {
  /// Peak resident bytes, by part, at the build's stage where they peak (tracing, resampling or
  /// rendering; the parts of the other stages are 0): the traced rays (staged and gathered samples),
  /// the sea's grids (kept per traced train, and a resampling's scratch per thread), the floor (the
  /// renderer's grid, height map copies), the image (per-pixel buffers, kept primary hits, the surface
  /// frame) and the program itself (code, libraries, tables, threads' stacks).
  std::uint64_t rays = 0, sea = 0, floor = 0, image = 0, program = 0;
  /// CPU seconds on one core of the development machine (AMD EPYC, docs/design.md 7), by stage.
  double trace_s = 0.0, sea_s = 0.0, floor_s = 0.0;  ///< floor_s: the floor grid, the walls' blocks and the objects
  /// Samples the traced trains are expected to take (expected_trace_samples, and their reflected waves).
  std::uint64_t samples = 0;

  std::uint64_t bytes() const noexcept { return rays + sea + floor + image + program; }
  double seconds() const noexcept { return trace_s + sea_s + floor_s; }
};

/// The estimate for a valid scene built by Animation::create(scene, quality, pixels, threads). With
/// `traced` (the scene's traced waves), the rest of the build from there: the samples and rays are
/// those traced (the prediction misses rays inserted without end over a rough floor, which only the
/// caps bound), the tracing itself done.
BuildCost estimate_build_cost(const Scene& scene, const Quality& quality, std::uint64_t pixels, unsigned threads,
                              const WaveField* traced = nullptr);

/// The samples train `train` of a valid scene is expected to take (estimate_build_cost's prediction:
/// its initial rays marched straight, and the rays insertion adds where the floor refracts), at most
/// dwt.max_samples, which a train expected to reach that cap gets.
double expected_trace_samples(const Scene& scene, std::size_t train);

/// Builds longer than this (estimated CPU time at the cheapest quality) are refused by `validate`.
inline constexpr double max_build_seconds = 300.0;

/// An error naming the largest part and what to change when the estimate is over
/// scene_limits::max_animation_bytes or max_build_seconds; `what` names the build ("at draft
/// quality", "at this quality and size").
Expected<void> check_build_cost(const BuildCost& cost, const std::string& what);

}  // namespace houle
