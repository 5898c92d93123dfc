#include "houle/sim/animation.hpp"
#include "houle/sim/camera_path.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/effect_plan.hpp"
#include "houle/sim/floating_objects.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include "houle/runtime/assert.hpp"
#include "houle/sim/bathymetry.hpp"
#include "parabolic_model.hpp"

namespace houle {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

constexpr std::array<std::string_view, 3> quality_names = {"draft", "realtime", "film"};

}  // namespace

std::string_view quality_name(QualityPreset q) noexcept {
  HOULE_ASSERT(std::size_t(q) < quality_names.size(), "quality_name: one of the QualityPreset values");
  return quality_names[std::size_t(q)];
}

std::optional<QualityPreset> parse_quality(std::string_view name) noexcept {
  for (std::size_t i = 0; i < quality_names.size(); ++i) {
    if (quality_names[i] == name) return QualityPreset(i);
  }
  return std::nullopt;
}

Quality quality_preset(QualityPreset q) noexcept {
  Quality r;
  switch (q) {
    case QualityPreset::draft:
      r.render.march.refine_iterations = 0;
      r.render.shadows = false;
      r.surface.levels = 7;
      r.surface.cells = 128;
      r.surface.finest_cell = 0.5f;
      r.sea_cell = 1.0f;
      break;
    case QualityPreset::realtime:
      break;  // the defaults of every knob
    case QualityPreset::film:
      r.render.march.step_fraction = 0.1f;
      // The hit distance is at float resolution after 4 iterations; more only cost evaluations
      // (docs/accuracy.md, "Root refinement").
      r.render.march.refine_iterations = 4;
      r.render.samples_per_pixel = 8;
      r.surface.levels = 8;
      r.surface.cells = 512;
      r.surface.finest_cell = 0.125f;
      r.sea_cell = 0.25f;
      break;
  }
  return r;
}

Expected<Animation> Animation::create(const Scene& scene_in, const Quality& quality, std::uint32_t width,
                                      std::uint32_t height, unsigned threads) {
  HOULE_ASSERT(threads >= 1, "Animation::create: threads >= 1");
  const auto t0 = Clock::now();
  Expected<Scene> scene = validate(scene_in);
  if (!scene) return scene.error();
  const Scene& s = scene.value();
  if (Expected<void> fits = check_build_cost(estimate_build_cost(s, quality, std::uint64_t(width) * height, threads),
                                             "at this quality and size");
      !fits) {
    return fits.error();
  }

  Expected<Camera> camera = make_camera(camera_params(camera_pose(s.camera, 0.0), width, height));
  if (!camera) return Error{"camera", camera.error().message};

  // The tracer and the noise follow the same plan (train_needs_rays, pierheads, capillary amplitude);
  // the renderer gets its skipped stages switched off.
  const EffectPlan plan = plan_effects(s, quality);
  Expected<WaveField> waves = trace_wave_field(s, std::max(threads, 1u));
  if (!waves) return waves.error();
  // Before the sea's grids, the most of the build: again, with the rays as traced.
  const BuildCost cost = estimate_build_cost(s, quality, std::uint64_t(width) * height, threads, &waves.value());
  if (Expected<void> fits = check_build_cost(cost, "at this quality and size, with the rays as traced"); !fits) {
    return fits.error();
  }
  Expected<SeaSurface> sea = SeaSurface::build(s, waves.value(), quality.sea_cell, SeaParts::drop, std::max(threads, 1u));
  if (!sea) return sea.error();
  Expected<SurfaceFrame> surface = SurfaceFrame::create(quality.surface);
  if (!surface) return Error{"quality.surface", surface.error().message};
  // The trains' fields at the frame's nodes are read from the grids once per level layout (docs/design.md 3).
  surface->keep_static(sea->sample_keep_floats());
  // A floating object goes no further than the sea's height bound up or down, and its centre swings
  // by less than 1.5 times its height above the waterplane as it tilts.
  RenderScene render_scene = make_render_scene(s);
  if (plan.surf) render_scene.surf = sea.value().surf_map(s);
  render_scene.sea_height_bound = sea->height_bound();
  std::vector<FloatingObject> floating = floating_objects(s, render_scene.boxes.size() - s.boxes.size());
  const double float_bound = double(sea->height_bound());
  for (const FloatingObject& f : floating) {
    const float motion = float(float_bound + 1.5 * std::abs(f.centre_above)) + 0.01f;
    (f.box ? render_scene.boxes[f.render_index].motion : render_scene.spheres[f.render_index].motion) = motion;
  }
  Expected<Renderer> renderer = Renderer::create(render_scene, width, height, planned_quality(plan, quality).render, threads);
  if (!renderer) return Error{"render", renderer.error().message};

  Animation a(std::move(renderer.value()), std::move(surface.value()));
  a.floating_ = std::move(floating);
  a.float_bound_ = float_bound;
  a.waves_ = std::make_unique<WaveField>(std::move(waves.value()));
  a.sea_ = std::make_unique<SeaSurface>(std::move(sea.value()));
  a.camera_ = camera.value();
  a.view_ = s.camera;
  a.width_ = width;
  a.height_ = height;
  if (plan.capillary_noise) {
    CapillaryParams p;
    p.amplitude = float(s.capillary.amplitude);
    p.base_wavelength = float(s.capillary.base_wavelength);
    p.lacunarity = float(s.capillary.lacunarity);
    p.max_octaves = s.capillary.max_octaves;
    p.animation_rate = float(s.capillary.time_scale);
    Expected<CapillaryFrame> probe = make_capillary_frame(p, 0.0);
    if (!probe) return Error{"capillary", probe.error().message};
    a.noise_params_ = p;
  }
  a.cost_ = cost;
  a.build_ms_ = ms_since(t0);
  return a;
}

void Animation::set_camera(double time_s) noexcept {
  if (view_.keys.empty()) return;
  CameraParams p = camera_params(camera_pose(view_, time_s), width_, height_);
  // The curves may pass through their own look-at point: that instant takes the nearest key's view
  // (each key is a valid camera), so that make_camera cannot fail here (nor allocate its error).
  if (p.position == p.look_at) {
    const auto nearest = std::min_element(view_.keys.begin(), view_.keys.end(), [&](const CameraKey& a, const CameraKey& b) {
      return std::abs(a.time - time_s) < std::abs(b.time - time_s);
    });
    p = camera_params(camera_pose(view_, nearest->time), width_, height_);
  }
  if (Expected<Camera> c = make_camera(p)) camera_ = c.value();
}

void Animation::render(double time_s, Framebuffer& out) noexcept {
  HOULE_ASSERT(out.width == int(renderer_.width()) && out.height == int(renderer_.height()),
               "Animation::render: a framebuffer of the animation's width x height");
  set_camera(time_s);
  auto t0 = Clock::now();
  sea_->set_time(time_s);
  for (const FloatingObject& f : floating_) {
    const FloatingPose p = floating_pose(f, *sea_, float_bound_);
    if (f.box) {
      renderer_.move_box(f.render_index, box_pose(f, p));
    } else {
      renderer_.move_sphere(f.render_index, {float(p.centre[0]), float(p.centre[1]), float(p.centre[2])});
    }
  }
  // Every ray the renderer marches over the sea starts at the camera and samples within the frame's
  // slab: the sea's height bound (which bounds every node) widened by the noise's (the marcher's
  // octave bounds sum to it within a ten-thousandth).
  const float sea_bound = float(float_bound_ * 1.001 + 0.01);
  const float noise_bound =
      noise_params_ ? capillary_height_bound(*noise_params_, capillary_top_level(*noise_params_)) : 0.0f;
  const float slab = sea_bound + noise_bound * 1.01f + 0.01f;
  surface_.begin_frame(camera_.position[0], camera_.position[1]);
  surface_.restrict_to_view(camera_, -slab, slab);
  surface_.set_viewer(camera_);  // and its pixels set what the nodes can hold
  renderer_.fill_surface(surface_, &SeaSurface::sample, sea_.get());
  HOULE_ASSERT(surface_.view().global.h_min >= -sea_bound && surface_.view().global.h_max <= sea_bound,
               "Animation::render: the sea within its height bound");
  times_.surface_ms = ms_since(t0);
  t0 = Clock::now();
  const CapillaryFrame* noise = nullptr;
  if (noise_params_) {
    // Validated in create(): the only failure left would be a non-finite time.
    if (Expected<CapillaryFrame> f = make_capillary_frame(*noise_params_, time_s)) {
      noise_ = f.value();
      noise = &noise_;
      ++noise_frames_;
      surface_.set_noise_bounds(noise_bound, capillary_slope_bound(*noise_params_, capillary_top_level(*noise_params_)));
    }
  }
  times_.noise_ms = ms_since(t0);
  renderer_.render(surface_, noise, noise ? &*noise_params_ : nullptr, camera_, out);
  times_.render = renderer_.last_times();
}

}  // namespace houle
