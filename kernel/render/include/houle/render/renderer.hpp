// The renderer: a filled SurfaceFrame (plus capillary noise) and a camera in, a linear-RGB Framebuffer
// out (paper section 4, eq. 10-12; docs/rendering.md 3, 4.4, 5.4, 6).
//
// Per pixel and sample (eq. 10 with the sea as the special case, docs/rendering.md 3.1):
//   * the primary ray is intersected with the scene's objects (boxes, spheres and the floor grid where
//     it rises above the sea's slab: land, beach) for t_max, then marched against the sea up to it;
//   * a sea hit is shaded with the exact Fresnel split (eq. 11) of its eq. 8 normal:
//       I = K_r I_r + K_t I_t + glint,
//     I_r the reflected ray's radiance (objects, diffusely lit, or the baked sky), the glint the sun's
//     analytic lobe (sky.hpp sun_glint) widened by the slope variance of the capillary octaves the LOD
//     dropped at that pixel, and I_t eq. 12 along the refracted ray: K I_object + (1 - K) I_sea, with
//     K = e^{-a(lambda) d} per wavelength through the WaterColourLut (or its RGB approximation), and
//     I_sea alone when the refracted ray finds nothing;
//   * an object hit is k_d C (I_a (1 + N_z) / 2 + I_sun (N.L) visibility): diffuse only (k_s = 0);
//   * a ray that finds nothing sees the sky.
// A camera under the sea sees the surface from below (total internal reflection outside Snell's
// window, optics.hpp), objects and the floor through the water between, and I_sea beyond.
//
// Units: linear sRGB relative radiance with the scene's white = a white Lambertian surface lit by the
// sun at normal incidence (colour.hpp's convention). The sky model's kcd/m^2 are converted with the
// sun's illuminance (a Kasten-Young air mass and Rayleigh + Angstrom aerosol optical depths for the
// turbidity); the sun's glint is pi x sun_glint in these units; I_sea is the WaterColourLut's I_sea
// (luminance 0.1 of a white object) times the light a horizontal surface receives.
//
// Simplifications, on purpose (the real-time budget): secondary rays do not test the sea again, so a
// reflected ray never meets another wave (one pointing below the horizon has its z clamped to
// `min_reflected_dz` and is renormalised, docs/rendering.md 3.3); objects are diffuse; light reaching
// underwater objects is the flat-sea refraction of the sun attenuated along depth / cos(theta_sun,water)
// (docs/rendering.md 3.4's refinement) and is shadowed by objects only, not by the waves; sky light on
// objects is the horizontal sky irradiance weighted by (1 + N_z) / 2.
//
// Per shot: the primary rays' object and floor hits, and the colour of what they meet off the sea
// (without moving objects), are kept per pixel and sample from one frame to the next while the camera
// does not change, and used where they are the frame's own bits (docs/rendering.md 2.4).
//
// Threads: a persistent pool made by create() (no thread is started per frame); rows are claimed one
// at a time by whichever thread is free, and every row is computed the same way whatever thread takes
// it, so the image is identical for any thread count. render() allocates nothing and never fails; no
// NaN or Inf reaches the framebuffer (non-finite samples are written as 0 and counted in
// last_counters()).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/render/colour.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/render/framebuffer.hpp"
#include "houle/surface/march.hpp"
#include "houle/surface/surface_frame.hpp"

namespace houle {

/// A box oriented about z: its local axes are the world's x and y turned by yaw_rad (counter-clockwise
/// seen from above) and z.
/// `motion` > 0 makes it a moving box (Renderer::move_box): its centre stays within `motion` of
/// `center` on each axis, in any orientation.
struct RenderBox {
  std::array<float, 3> center{};       ///< m
  std::array<float, 3> half_extent{};  ///< m, each > 0, along the local axes
  float yaw_rad = 0.0f;
  LinearRgb colour{0.5f, 0.5f, 0.5f};  ///< diffuse reflectance k_d C, each channel in [0, 1]
  float motion = 0.0f;                 ///< m >= 0; 0: it never moves
};

/// `motion` > 0 makes it a moving sphere (Renderer::move_sphere), as for a box.
struct RenderSphere {
  std::array<float, 3> center{};  ///< m
  float radius = 1.0f;            ///< m, > 0
  LinearRgb colour{0.5f, 0.5f, 0.5f};  ///< diffuse reflectance, each channel in [0, 1]
  float motion = 0.0f;            ///< m >= 0; 0: it never moves
};

/// Where a moving box is in a frame: its centre and its local axes in world coordinates (unit and
/// orthogonal; a box at rest has x and y turned by its yaw, and z up).
struct BoxPose {
  std::array<float, 3> center{};
  std::array<std::array<float, 3>, 3> axes{{{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}}};
};

/// The sea floor and land as a height grid built once per scene: z (m) of the ground, negative under
/// the still sea. Sample (i, j) sits at (origin_x + i cell, origin_y + j cell) and is z[j nx + i];
/// the ground between samples is bilinear, and outside the grid it is the nearest edge sample's z
/// (the edges extend to infinity). nx = ny = 0: no floor at all (open sea, bottomless).
struct FloorGrid {
  float origin_x = 0.0f, origin_y = 0.0f;  ///< m
  float cell = 1.0f;                       ///< m, > 0
  std::uint32_t nx = 0, ny = 0;
  std::vector<float> z;                    ///< nx * ny finite values, m
  LinearRgb sand{0.55f, 0.5f, 0.4f};       ///< diffuse reflectance of the ground
};

/// Where waves break, built once per scene (docs/rendering.md 3.7): per node of a grid (node (i, j) at
/// (origin_x + i cell, origin_y + j cell), element j nx + i), how much foam the sea carries there, in
/// [0, 1], the direction the breaking waves travel (unit, or 0 at the toes of walls, where foam
/// lines the crests whatever their direction) and their amplitude (m). Bilinear between nodes, 0
/// outside. nx = ny = 0: nothing breaks, and the renderer does no work for it.
struct SurfMap {
  float origin_x = 0.0f, origin_y = 0.0f, cell = 1.0f;  ///< m
  std::uint32_t nx = 0, ny = 0;
  std::vector<float> foam, dir_x, dir_y, amplitude;  ///< nx * ny each
};

struct RenderScene {
  FloorGrid floor;
  SurfMap surf;
  std::vector<RenderBox> boxes;
  std::vector<RenderSphere> spheres;
  std::array<float, 3> sun_direction{0.0f, 0.5f, 0.8660254f};  ///< towards the sun (normalised on use)
  float turbidity = 3.0f;               ///< Preetham sky, in [1.7, 10]
  /// 1/m at 440 nm, added to pure water's absorption as coloured dissolved organic matter
  /// (a_g(lambda) = a_g(440) e^{-0.014 (lambda - 440)}, colour.hpp water_absorption), >= 0.
  float water_extra_absorption = 0.0f;
  float sea_dominant_wavelength_nm = 490.0f;  ///< I_sea's dominant wavelength (the paper's table), in [380, 780]
  /// m: |height| of every frame's sea surface, the capillary noise aside, stays within this (inf:
  /// unknown). A frame within it cuts the primary rays' floor walks at a height that does not move
  /// with the waves, so that a still camera's primary hits are found once per shot (docs/rendering.md 2.4).
  float sea_height_bound = std::numeric_limits<float>::infinity();
};

/// Accuracy knobs (docs/design.md 5: explicit).
struct RenderQuality {
  MarchQuality march{};
  int samples_per_pixel = 1;       ///< 1, 4 or 8, at fixed sub-pixel positions (averaged)
  bool spectral_absorption = true;  ///< eq. 12 per wavelength (WaterColourLut), else three exponentials
  bool shadows = true;              ///< shadow rays from lit points (and the glint) towards the sun
  bool reflect_objects = true;      ///< reflected sea rays test the objects; else sky only
};

/// Wall-clock time of the last render() (steady_clock). The stages run interleaved row by row on every
/// thread: a stage's figure is the time the threads spent in it, summed and divided by the thread count.
struct FrameTimes {
  double march_ms = 0.0;      ///< march_rays against the sea
  double intersect_ms = 0.0;  ///< primary rays and their object / floor intersections (t_max)
  double shade_ms = 0.0;      ///< Fresnel, secondary rays, sky, water colour, supersample averaging
  double total_ms = 0.0;      ///< the whole call
};

/// What the last render() saw, in samples (pixels x samples per pixel).
struct RenderCounters {
  std::uint64_t sea = 0;        ///< primary ray met the sea surface (from above or below)
  std::uint64_t object = 0;     ///< primary ray met an object or the floor first
  std::uint64_t sky = 0;        ///< primary ray met nothing (the sky, or I_sea under water)
  std::uint64_t nonfinite = 0;  ///< samples whose colour was NaN or Inf (written as 0): should stay 0
  std::uint64_t reused = 0;     ///< samples whose object and floor hit the last frame's camera had found
  std::uint64_t kept_colour = 0;  ///< samples off the sea whose colour an earlier frame of the still camera had shaded
};

/// What render() writes: the image, or a debugging view.
enum class RenderView : std::uint8_t {
  shaded = 0,           ///< eq. 10
  sea_reflectance = 1,  ///< K_r of the primary sea hit in all three channels (0 elsewhere)
};

class Renderer {
 public:
  /// Bytes of primary hits and colours kept per pixel and sample for a still camera, and the most
  /// kept: an image x samples over it keeps none and intersects and shades every frame.
  static constexpr std::size_t kept_hit_bytes = 41, max_kept_bytes = std::size_t(256) << 20;
  /// The reflected sea ray's minimum z after clamping (see the file comment).
  static constexpr float min_reflected_dz = 0.01f;
  /// m: refracted and under-water rays that meet nothing within this see I_sea.
  static constexpr float underwater_reach = 1000.0f;

  /// Everything is allocated here: per-thread scratch, the kept primary hits, the sky table, the water
  /// colour table, the floor's block bounds and a pool of `threads` workers counting the caller (0 means 1). Fails on an
  /// invalid scene, quality, size or when a thread cannot be started.
  static Expected<Renderer> create(const RenderScene& scene, std::uint32_t width, std::uint32_t height,
                                   const RenderQuality& quality, unsigned threads);

  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  ~Renderer();

  /// One frame into `out`, which must be sized width x height beforehand, seen by `camera`, which
  /// must have this renderer's width and height: otherwise a build with HOULE_ASSERTS aborts with a
  /// message, and a release build writes nothing. `noise` may be null
  /// (no capillary ripples); its level at each hit sets the glint's extra roughness with
  /// `noise_params`, or with noise->params when that is null. No heap allocation; deterministic.
  void render(const SurfaceFrame& surface, const CapillaryFrame* noise, const CapillaryParams* noise_params,
              const Camera& camera, Framebuffer& out, RenderView view = RenderView::shaded) noexcept;

  /// Places moving box `box` (an index into RenderScene::boxes, with motion > 0) or moving sphere
  /// `sphere` for the next render(): its centre is clamped to within its motion of where the scene
  /// put it. The primary hits kept for a still camera are not used where a ray meets a moving object
  /// now or met it when they were kept, so a frame is the one a fresh renderer gives. No allocation.
  void move_box(std::size_t box, const BoxPose& pose) noexcept;
  void move_sphere(std::size_t sphere, const std::array<float, 3>& center) noexcept;

  /// SurfaceFrame::fill on this renderer's threads (the per-frame retessellation shares them with
  /// render()): `sampler` must allow concurrent calls. The frame is the same as fill() gives.
  void fill_surface(SurfaceFrame& surface, SurfaceSampler sampler, void* context) noexcept;

  /// The exposure (ToneMap::exposure) this scene's sun and sky ask for, fixed per scene so that frame n
  /// stays a pure function of the scene and n (docs/rendering.md 4.5).
  float display_exposure() const noexcept;

  const FrameTimes& last_times() const noexcept;
  const RenderCounters& last_counters() const noexcept;
  std::uint32_t width() const noexcept;
  std::uint32_t height() const noexcept;
  unsigned threads() const noexcept;

  struct Impl;

 private:
  explicit Renderer(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace houle
