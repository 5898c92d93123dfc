// The image knobs and the presets, on the built-in coast animated by houle::Animation exactly as
// `houle render` does. One knob varies, the others stay at `realtime`; its reference is the same
// render with that knob well beyond `film` (samples per pixel: 8 at twice the size, box-filtered),
// so each curve shows that knob's own discretisation error. The presets are compared with one
// brute-force render (film's knobs pushed further, twice the size, 8 samples per pixel).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"
#include "image_error.hpp"
#include "sweep.hpp"

namespace houle::accuracy {
namespace {

constexpr QualityPreset presets[] = {QualityPreset::draft, QualityPreset::realtime, QualityPreset::film};

/// s of animation time of compared frame i: spread over the trains' periods so no single wave
/// phase decides a curve.
double frame_time(int i) { return 0.5 + 1.3 * double(i); }

struct Rendered {
  std::vector<Framebuffer> frames;  ///< frame_time(0 .. frames - 1)
  /// ms per frame index: the fastest of the repeats (the machine is shared: the least disturbed run
  /// is the best estimate of the cost), so medians over frames see each frame's content once.
  std::vector<double> frame, surface, noise, march, intersect, shade;
};

void keep_fastest(std::vector<double>& v, std::size_t i, double ms) {
  if (i >= v.size()) v.push_back(ms);
  else v[i] = std::min(v[i], ms);
}

/// Renders frames 0 .. frames - 1 `repeats` times after one warm-up frame (first-frame work stays
/// out of the timings); keeps the first pass's images (every pass gives the same ones).
Rendered render(const Scene& scene, const Quality& q, std::uint32_t w, std::uint32_t h, int frames, int repeats,
                unsigned threads) {
  Expected<Animation> a = Animation::create(scene, q, w, h, threads);
  if (!a) fail(a.error());
  Framebuffer fb(static_cast<int>(w), static_cast<int>(h));
  a->render(frame_time(0), fb);
  Rendered r;
  for (int rep = 0; rep < repeats; ++rep) {
    for (int i = 0; i < frames; ++i) {
      a->render(frame_time(i), fb);
      const AnimationTimes& t = a->last_times();
      const auto f = std::size_t(i);
      keep_fastest(r.frame, f, t.surface_ms + t.noise_ms + t.render.total_ms);
      keep_fastest(r.surface, f, t.surface_ms);
      keep_fastest(r.noise, f, t.noise_ms);
      keep_fastest(r.march, f, t.render.march_ms);
      keep_fastest(r.intersect, f, t.render.intersect_ms);
      keep_fastest(r.shade, f, t.render.shade_ms);
      if (rep == 0) r.frames.push_back(fb);
    }
  }
  return r;
}

/// Reference frames: rendered at `scale` x the size and box-filtered back.
std::vector<Framebuffer> reference(const Scene& scene, const Quality& q, std::uint32_t w, std::uint32_t h, int scale,
                                   const Options& o) {
  Rendered r = render(scene, q, w * std::uint32_t(scale), h * std::uint32_t(scale), o.frames, 1, o.threads);
  if (scale > 1) {
    for (Framebuffer& f : r.frames) f = downsample(f, scale);
  }
  return r.frames;
}

/// Errors over all compared frames: RMSE pooled over every pixel, 1 - SSIM averaged.
ImageError error(const std::vector<Framebuffer>& frames, const std::vector<Framebuffer>& ref) {
  ImageError e;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const ImageError f = image_error(frames[i], ref[i]);
    e.rmse += f.rmse * f.rmse;
    e.dssim += f.dssim;
  }
  const double n = double(std::max<std::size_t>(frames.size(), 1));
  return {std::sqrt(e.rmse / n), e.dssim / n};
}

/// Which stages a knob changes: its time is the sum of their medians.
enum class Cost { march, shade, render, noise_render, frame };

struct ImageKnob {
  const char* name;
  Cost cost;
  std::vector<double> values;  ///< least accurate first
  double reference;
  int reference_scale;                     ///< 2: the reference is rendered at twice the size
  double (*get)(const Quality&);           ///< the preset's value; null for scene knobs
  void (*set)(Scene&, Quality&, double);
};

const std::vector<ImageKnob>& image_knobs() {
  static const std::vector<ImageKnob> k = {
      {"march.step_fraction", Cost::march, {1.0, 0.5, 0.25, 0.1, 0.05}, 0.01, 1,
       [](const Quality& q) { return double(q.render.march.step_fraction); },
       [](Scene&, Quality& q, double v) {
         q.render.march.step_fraction = float(v);
         q.render.march.max_steps = 1 << 16;  // fine steps must not run out before the far sea
       }},
      {"march.refine_iterations", Cost::march, {0, 1, 2, 4, 8}, 24, 1,
       [](const Quality& q) { return double(q.render.march.refine_iterations); },
       [](Scene&, Quality& q, double v) { q.render.march.refine_iterations = int(v); }},
      {"render.samples_per_pixel", Cost::render, {1, 4, 8}, 8, 2,
       [](const Quality& q) { return double(q.render.samples_per_pixel); },
       [](Scene&, Quality& q, double v) { q.render.samples_per_pixel = int(v); }},
      {"render.spectral_absorption", Cost::shade, {0, 1}, 1, 1,
       [](const Quality& q) { return q.render.spectral_absorption ? 1.0 : 0.0; },
       [](Scene&, Quality& q, double v) { q.render.spectral_absorption = v != 0.0; }},
      {"capillary.max_octaves", Cost::noise_render, {0, 2, 4, 6}, 8, 1, nullptr,
       [](Scene& s, Quality&, double v) { s.capillary.max_octaves = int(v); }},
      {"surface.cells", Cost::frame, {64, 128, 256}, 512, 1,
       [](const Quality& q) { return double(q.surface.cells); },
       [](Scene&, Quality& q, double v) { q.surface.cells = std::uint32_t(v); }},
      {"surface.finest_cell", Cost::frame, {1.0, 0.5, 0.25}, 0.125, 1,
       [](const Quality& q) { return double(q.surface.finest_cell); },
       [](Scene&, Quality& q, double v) { q.surface.finest_cell = float(v); }},
      {"surface.levels", Cost::frame, {5, 6, 7, 8}, 10, 1, [](const Quality& q) { return double(q.surface.levels); },
       [](Scene&, Quality& q, double v) { q.surface.levels = std::uint32_t(v); }},
      {"sea_cell", Cost::frame, {2.0, 1.0, 0.5}, 0.25, 1, [](const Quality& q) { return double(q.sea_cell); },
       [](Scene&, Quality& q, double v) { q.sea_cell = float(v); }},
  };
  return k;
}

std::string presets_using(const ImageKnob& k, double v) {
  std::string s;
  if (!k.get) return s;
  for (QualityPreset p : presets) {
    if (k.get(quality_preset(p)) == v) s += (s.empty() ? "" : " ") + std::string(quality_name(p));
  }
  return s;
}

std::string format_value(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

/// What each effect of the built-in coast costs a frame and what leaving it out changes in the image:
/// each variant switches one off, against the coast with all of them (the effect plan switches them
/// off by itself in scenes that do not call for them: docs/design.md).
void sweep_effects(const Options& o, std::vector<Row>& rows) {
  struct Variant {
    const char* name;
    void (*set)(Scene&, Quality&);
  };
  const Variant variants[] = {
      {"all effects", [](Scene&, Quality&) {}},
      {"no capillary ripples", [](Scene& s, Quality&) { s.capillary.amplitude = 0.0; }},
      {"no shadows", [](Scene&, Quality& q) { q.render.shadows = false; }},
      {"no object reflections", [](Scene&, Quality& q) { q.render.reflect_objects = false; }},
      {"no jetty (diffraction, wall reflection, its shadow)", [](Scene& s, Quality&) { s.walls.clear(); }},
  };
  const Scene coast = builtin_coast();
  const Quality base = quality_preset(o.base);
  std::vector<Framebuffer> ref;
  const std::size_t n = o.smoke ? 2 : std::size(variants);
  for (std::size_t i = 0; i < n; ++i) {
    Scene s = coast;
    Quality q = base;
    variants[i].set(s, q);
    const Rendered r = render(s, q, o.width, o.height, o.frames, o.timing_repeats, o.threads);
    if (i == 0) ref = r.frames;
    const ImageError e = error(r.frames, ref);
    Row row;
    row.knob = "effects";
    row.value = double(i);
    row.presets = variants[i].name;
    row.time = median(r.frame);
    row.time_what = "whole frame (ms)";
    row.frame_ms = row.time;
    row.error = e.rmse;
    row.error_what = "image RMSE";
    row.error2 = e.dssim;
    row.error2_what = "1 - SSIM";
    row.reference = "the built-in coast with all its effects, " + std::to_string(o.width) + "x" +
                    std::to_string(o.height) + ", " + std::string(quality_name(o.base));
    std::fprintf(stderr, "effects: %s: %.2f ms, RMSE %.5f, 1-SSIM %.5f\n", variants[i].name, row.time, e.rmse, e.dssim);
    rows.push_back(std::move(row));
  }
}

}  // namespace

std::vector<Row> sweep_image_knobs(const Options& o) {
  const Scene coast = builtin_coast();
  // Smoke: every knob's cheapest setting against its second one (from `draft`, see main).
  const Quality base = quality_preset(o.base);
  std::vector<Row> rows;
  for (const ImageKnob& k : image_knobs()) {
    if (!o.only.empty() && o.only != k.name) continue;
    const double ref_value = o.smoke ? k.values[1] : k.reference;
    const int ref_scale = o.smoke ? 1 : k.reference_scale;
    Scene ref_scene = coast;
    Quality ref_quality = base;
    k.set(ref_scene, ref_quality, ref_value);
    const std::vector<Framebuffer> ref = reference(ref_scene, ref_quality, o.width, o.height, ref_scale, o);
    std::fprintf(stderr, "%s: reference %g\n", k.name, ref_value);
    const std::size_t n = o.smoke ? 1 : k.values.size();
    for (std::size_t i = 0; i < n; ++i) {
      Scene s = coast;
      Quality q = base;
      k.set(s, q, k.values[i]);
      const Rendered r = render(s, q, o.width, o.height, o.frames, o.timing_repeats, o.threads);
      const ImageError e = error(r.frames, ref);
      Row row;
      row.knob = k.name;
      row.value = k.values[i];
      row.presets = presets_using(k, k.values[i]);
      const double render_ms = median(r.march) + median(r.intersect) + median(r.shade);
      switch (k.cost) {
        case Cost::march:
          row.time = median(r.march), row.time_what = "march (ms)";
          break;
        case Cost::shade:
          row.time = median(r.shade), row.time_what = "shade (ms)";
          break;
        case Cost::render:
          row.time = render_ms, row.time_what = "march + intersect + shade (ms)";
          break;
        case Cost::noise_render:
          row.time = median(r.noise) + render_ms, row.time_what = "noise + march + intersect + shade (ms)";
          break;
        case Cost::frame:
          row.time = median(r.frame), row.time_what = "whole frame (ms)";
          break;
      }
      row.frame_ms = median(r.frame);
      row.error = e.rmse;
      row.error_what = "image RMSE";
      row.error2 = e.dssim;
      row.error2_what = "1 - SSIM";
      row.reference = format_value(ref_value) + (ref_scale > 1 ? " at 2x size, box-filtered" : "") + ", " +
                      std::to_string(o.width) + "x" + std::to_string(o.height) + ", other knobs " +
                      std::string(quality_name(o.base));
      std::fprintf(stderr, "  %g: %.2f ms, RMSE %.5f, 1-SSIM %.5f\n", k.values[i], row.time, e.rmse, e.dssim);
      rows.push_back(std::move(row));
    }
  }
  if (o.only.empty() || o.only == "effects") sweep_effects(o, rows);
  return rows;
}

std::vector<PresetRow> measure_presets(const Options& o) {
  const Scene coast = builtin_coast();
  struct Size {
    std::uint32_t w, h;
  };
  const std::vector<Size> sizes = o.smoke ? std::vector<Size>{{o.width, o.height}}
                                          : std::vector<Size>{{640, 360}, {1280, 720}};
  // The brute-force reference at the first size: film's knobs pushed further, at twice the size with
  // 8 samples per pixel (32 per compared pixel); film's own surface grid at twice its density.
  Quality brute = quality_preset(QualityPreset::film);
  if (!o.smoke) {
    brute.render.march.step_fraction = 0.05f;
    brute.render.march.refine_iterations = 16;
    brute.render.march.max_steps = 1 << 16;
    brute.surface.cells = 1024;
    brute.surface.finest_cell = 0.0625f;
    brute.sea_cell = 0.125f;
  }
  const std::vector<Framebuffer> ref = reference(coast, brute, sizes[0].w, sizes[0].h, o.smoke ? 1 : 2, o);
  std::fprintf(stderr, "presets: reference rendered\n");
  std::vector<PresetRow> rows;
  for (QualityPreset p : presets) {
    for (std::size_t si = 0; si < sizes.size(); ++si) {
      const Size sz = sizes[si];
      // The costliest case (film at 1280x720, seconds a frame) is timed on one pass.
      const int repeats = sz.w > 640 ? 1 : o.timing_repeats;
      const Rendered r = render(coast, quality_preset(p), sz.w, sz.h, o.frames, repeats, o.threads);
      PresetRow row;
      row.preset = std::string(quality_name(p));
      row.width = sz.w, row.height = sz.h;
      row.frame_ms = median(r.frame);
      row.surface_ms = median(r.surface);
      row.noise_ms = median(r.noise);
      row.march_ms = median(r.march);
      row.intersect_ms = median(r.intersect);
      row.shade_ms = median(r.shade);
      if (si == 0) {
        const ImageError e = error(r.frames, ref);
        row.rmse = e.rmse, row.dssim = e.dssim;
      }
      std::fprintf(stderr, "%s %ux%u: %.1f ms, RMSE %.5f\n", row.preset.c_str(), sz.w, sz.h, row.frame_ms, row.rmse);
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

}  // namespace houle::accuracy
