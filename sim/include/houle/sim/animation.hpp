// A scene ready to animate: everything built once per scene (traced wave rays, the resampled sea,
// the sea floor grid, the renderer's tables and threads, the per-frame surface buffers), then one call
// per frame. Frame n is a pure function of (scene, quality, size, time): nothing carried between
// frames changes the image.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/render/framebuffer.hpp"
#include "houle/render/renderer.hpp"
#include "houle/surface/surface_frame.hpp"
#include "houle/sim/floating_objects.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {

/// Named points of the accuracy/time trade (docs/accuracy.md): each sets every knob below.
enum class QualityPreset : std::uint8_t { draft, realtime, film };
std::string_view quality_name(QualityPreset q) noexcept;
std::optional<QualityPreset> parse_quality(std::string_view name) noexcept;

struct Quality {
  RenderQuality render{};
  SurfaceFrameConfig surface{};
  float sea_cell = 0.5f;  ///< m, resampling grid of traced trains (SeaSurface::build)
};
Quality quality_preset(QualityPreset q) noexcept;

/// The renderer's view of a scene: the sea floor as a height grid, walls as stone blocks, objects
/// (floating ones at rest on still water: Animation moves them), sun, sky and water.
RenderScene make_render_scene(const Scene& scene);

/// Per-stage times of the last frame, ms.
struct AnimationTimes {
  double surface_ms = 0.0;  ///< per-frame retessellation: the sea's grids at time t
  double noise_ms = 0.0;    ///< capillary frame
  FrameTimes render{};      ///< march / intersect / shade / total
};

class Animation {
 public:
  /// Traces the scene's waves and allocates everything. `threads` (>= 1) are used for tracing and
  /// rendering; the images do not depend on it.
  static Expected<Animation> create(const Scene& scene, const Quality& quality, std::uint32_t width,
                                    std::uint32_t height, unsigned threads);

  /// Renders the frame at `time_s` into `out` (width x height), seen by the camera at that time (a
  /// moving camera: camera_path.hpp), the floating objects posed on the sea at that time. No heap
  /// allocation after the first frame.
  void render(double time_s, Framebuffer& out) noexcept;

  const AnimationTimes& last_times() const noexcept { return times_; }
  const WaveField& waves() const noexcept { return *waves_; }
  const Renderer& renderer() const noexcept { return renderer_; }
  /// The camera of the last frame (before any: of time 0).
  const Camera& camera() const noexcept { return camera_; }
  double build_ms() const noexcept { return build_ms_; }
  /// The build's cost as estimated once the rays were traced (build_cost.hpp), checked then.
  const BuildCost& build_cost() const noexcept { return cost_; }
  /// Frames that built a capillary noise frame: 0 when the effect plan skips the noise.
  std::uint64_t noise_frames() const noexcept { return noise_frames_; }

 private:
  Animation(Renderer renderer, SurfaceFrame surface) : renderer_(std::move(renderer)), surface_(std::move(surface)) {}

  std::unique_ptr<WaveField> waves_;
  std::unique_ptr<SeaSurface> sea_;
  Renderer renderer_;
  SurfaceFrame surface_;
  Camera camera_{};
  std::vector<FloatingObject> floating_;
  double float_bound_ = 0.0;  ///< m, the sea's height bound: no floating object heaves beyond it
  ViewCamera view_;  ///< the scene's camera, with its keys when it moves (camera_path.hpp)
  std::uint32_t width_ = 0, height_ = 0;
  void set_camera(double time_s) noexcept;
  std::optional<CapillaryParams> noise_params_;
  CapillaryFrame noise_{};
  AnimationTimes times_{};
  double build_ms_ = 0.0;
  BuildCost cost_{};
  std::uint64_t noise_frames_ = 0;
};

}  // namespace houle
