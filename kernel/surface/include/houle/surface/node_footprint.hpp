// What a node of the per-frame surface can hold: a wave shorter than the node spacing or than the
// viewer's pixel footprint there would alias into moiré, so the trains fade out of the height and
// gradient before that and their slopes go into the glint's roughness (docs/rendering.md 5.5).
#pragma once

namespace houle {

/// The sampling a SurfaceFrame fill asks for at a run of nodes: the level's node spacing and, when
/// a viewer is set (SurfaceFrame::set_viewer), the footprint of its pixels on the mean sea plane.
struct NodeFootprint {
  float cell = 0.0f;         ///< m, node spacing of the level filled (0: no grid limit)
  float pixel_angle = 0.0f;  ///< rad, the viewer's pixel angle (Camera::pixel_angle); 0: no viewer
  float eye_x = 0.0f, eye_y = 0.0f;  ///< m, the viewer's ground point
  float eye_height = 0.0f;           ///< m, the viewer above the mean sea plane (either sign)
};

/// The weight in [0, 1] of a wave of wave vector (kx, ky) rad/m at (x, y) under `footprint`: 1 while
/// its wavelength spans at least two pixel footprints (measured along the wave vector: the footprint is
/// the pixel's ellipse on the plane, stretched along the view by 1 / sin(grazing)) and four cells,
/// falling with a smoothstep to 0 at one footprint or two cells. The scalar value of what the
/// train-grid kernels compute per lane (train_grid_impl.hpp).
float node_wave_weight(const NodeFootprint& footprint, float x, float y, float kx, float ky) noexcept;

}  // namespace houle
