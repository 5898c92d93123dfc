// A moving camera: where it is at any time, from the scene's camera keys (docs/scenes.md,
// [[camera.keys]]). Position, look-at point and field of view are each a cubic Hermite curve through
// the keys with Catmull-Rom tangents (the neighbouring keys' difference over their time apart,
// one-sided at the ends), so they move smoothly (C1) and pass through every key at its time; the
// field of view is kept between the two keys' values around it. Outside the keys' times the camera
// stands at the first or last key. A pure function of time: frame n does not depend on the frames
// rendered before it.
#pragma once
#include "houle/surface/camera.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

struct CameraPose {
  Point3 position{}, look_at{};
  double vertical_fov_deg = 50.0;
};

/// The camera at time_s: the still camera without keys, else the keys' curves. No allocation.
CameraPose camera_pose(const ViewCamera& camera, double time_s) noexcept;

/// The renderer's camera for a pose (an image of width x height pixels).
CameraParams camera_params(const CameraPose& pose, std::uint32_t width, std::uint32_t height) noexcept;

}  // namespace houle
