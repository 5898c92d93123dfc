// Floating boxes and spheres (`float = true`, docs/physics.md 2.10): each frame an object's pose
// follows the sea surface under it at that frame's time, and nothing else (frame n stays a pure
// function of n). At rest in still water it sits at its hydrostatic draft (the submerged volume is
// density / sea_water_density of the whole). In a frame, the surface heights at fixed samples of its
// still-water waterplane give the heave (their mean) and the pitch and roll (the least-squares plane
// through them): the object's vertical axis turns to the plane's normal and its waterplane centre
// rides on the plane, so the waterline sits at the draft below the local surface.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "houle/render/renderer.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

class SeaSurface;

/// The draft (m) of a floating sphere of radius r and density rho: the depth d of the cap
/// pi d^2 (3 r - d) / 3 that holds rho / sea_water_density of the sphere's volume.
double sphere_draft(double radius, double density) noexcept;
/// The draft of a floating box of height 2 half_z: 2 half_z rho / sea_water_density.
double box_draft(double half_z, double density) noexcept;

/// One floating object of a scene, ready for a pose per frame.
struct FloatingObject {
  static constexpr std::size_t samples = 16;  ///< waterplane samples
  bool box = false;
  std::size_t render_index = 0;  ///< into RenderScene::boxes or ::spheres
  double x = 0.0, y = 0.0;       ///< m, the waterplane's centre
  double yaw = 0.0;              ///< rad (boxes)
  double centre_above = 0.0;     ///< m, the centre's height above the waterplane at rest (negative: below)
  std::array<float, samples> dx{}, dy{};  ///< m, the samples' offsets from (x, y)
};

/// Where a floating object is in a frame.
struct FloatingPose {
  double heave = 0.0;                     ///< m, the waterplane centre's height
  std::array<double, 3> normal{0.0, 0.0, 1.0};  ///< the object's vertical axis (the plane's unit normal)
  std::array<double, 3> centre{};         ///< m
};

/// The scene's floating objects, boxes first; `first_box` is the render index of the scene's first
/// box (make_render_scene puts the walls' blocks before them).
std::vector<FloatingObject> floating_objects(const Scene& scene, std::size_t first_box);

/// The object's pose on `sea` at the time it was set last, its heave within +-bound (the sea's
/// height bound). No allocation.
FloatingPose floating_pose(const FloatingObject& object, const SeaSurface& sea, double bound) noexcept;

/// The renderer's pose of a floating box with that pose (its x axis the yaw turned into the plane).
BoxPose box_pose(const FloatingObject& object, const FloatingPose& pose) noexcept;

}  // namespace houle
