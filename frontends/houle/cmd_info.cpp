#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/effect_plan.hpp"
#include "houle/sim/scene_geometry.hpp"
#include "houle/sim/sea_surface.hpp"
#include "scene_source.hpp"

namespace houle::cli {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
template <class T>
std::size_t bytes(std::span<const T> v) {
  return v.size_bytes();
}

// Heap bytes held by one train's rays.
std::size_t ray_bytes(const WaveRays& w) {
  return bytes(w.sample_begin) + bytes(w.first_step) + bytes(w.flags) + bytes(w.parent_a) + bytes(w.parent_b) +
         bytes(w.x) + bytes(w.y) + bytes(w.theta) + bytes(w.k) + bytes(w.amplitude) + bytes(w.phase) + bytes(w.time) +
         bytes(w.sample_flags);
}

// Islands listed one by one, at most (a noisy height map can make thousands).
constexpr std::size_t max_island_warnings = 5;

// What in the scene the tracer handles poorly, one sentence each.
std::vector<std::string> scene_warnings(const Scene& s) {
  std::vector<std::string> out;
  char buf[512];
  const std::vector<Island> islands = find_islands(s);
  for (std::size_t i = 0; i < std::min(islands.size(), max_island_warnings); ++i) {
    const Island& is = islands[i];
    const char* why = "(land rising through the surface inside the domain, clear of its edges): rays passing either side "
                      "cross again in its lee, where the sea averages the two branches instead of adding them, so the "
                      "waves there may be too low; check them with houle probe";
    if (is.low.x == is.high.x && is.low.y == is.high.y) {
      std::snprintf(buf, sizeof buf, "an island at (%.1f, %.1f) m %s", is.low.x, is.low.y, why);
    } else {
      std::snprintf(buf, sizeof buf, "an island from (%.1f, %.1f) to (%.1f, %.1f) m %s", is.low.x, is.low.y, is.high.x,
                    is.high.y, why);
    }
    out.emplace_back(buf);
  }
  if (islands.size() > max_island_warnings) {
    out.push_back(std::to_string(islands.size() - max_island_warnings) + " more islands");
  }
  for (const EdgePierhead& p : pierheads_near_edge(s)) {
    std::snprintf(buf, sizeof buf,
                  "walls[%zu] ends in the water at (%.1f, %.1f) m, %.2f m from the domain's edge, within a wavelength "
                  "(%.2f m, train %zu): waves pass between it and the edge, and diffract round it",
                  p.wall, p.end.x, p.end.y, p.edge_distance, p.wavelength, p.train);
    out.emplace_back(buf);
  }
  return out;
}

const char* yes(bool b) { return b ? "yes" : "no"; }
const char* json_bool(bool b) { return b ? "true" : "false"; }

}  // namespace

int cmd_info(std::span<char* const> argv) {
  Args args("info", argv);
  if (args.flag("--help")) {
    std::puts(R"(usage: houle info [SCENE] [--quality Q] [--threads N] [--json]

Describes a scene (the built-in coast without SCENE): domain, sea floor, wave trains, structures and
objects; the effect plan at quality Q (default realtime: which stages run); then builds it and
reports per train whether it is traced, its rays and samples, the reflected waves, the diffraction
the resampled sea computed (pierheads, and grid nodes x pierheads evaluated), the memory the rays and
the resampled sea hold, and the scene build time (tracing and resampling, N threads, default the
machine's hardware threads). --json prints the same facts as one JSON object.

Warns (a `warning:` line; "warnings" in JSON) when the scene has an island (land rising through
the surface inside the domain, clear of its edges; found on a grid of 1 m cells, coarser beyond
512 m) or a wall end in the water closer to the domain's edge than a wavelength of a traced train
(at the end's depth): waves pass the gap between it and the edge, which may not be what was meant;
and when the wave rays stopped at a cap (allowed by dwt.on_cap = "warn"; by default that is an error).)");
    return 0;
  }
  const bool json = args.flag("--json");
  const std::optional<SceneRun> run = take_scene_run(args, "info");
  if (!run) return 2;
  const Scene& s = run->scene;
  const QualityPreset quality = run->quality;
  const unsigned threads = run->threads;
  const Quality q = quality_preset(quality);
  const EffectPlan plan = plan_effects(s, q);
  const BuildCost cost = estimate_build_cost(s, q, 0, threads);
  if (const Expected<void> fits = check_build_cost(cost, "at this quality"); !fits) {
    std::fprintf(stderr, "houle info: %s: %s: %s\n", run->name.c_str(), fits.error().field.c_str(), fits.error().message.c_str());
    return 2;
  }
  std::vector<std::string> warnings = scene_warnings(s);

  const auto t0 = std::chrono::steady_clock::now();
  Expected<WaveField> field = trace_wave_field(s, threads);
  const double trace_ms = ms_since(t0);
  if (!field) {
    std::fprintf(stderr, "houle info: %s: %s: %s\n", run->name.c_str(), field.error().field.c_str(),
                 field.error().message.c_str());
    return 2;
  }
  if (field.value().stats.truncated) {
    warnings.push_back("the wave rays reached a cap (dwt.max_rays, dwt.max_samples or the path length) and stopped: "
                       "the field beyond them is empty (dwt.on_cap = \"warn\")");
  }
  const auto t1 = std::chrono::steady_clock::now();
  Expected<SeaSurface> sea = SeaSurface::build(s, field.value(), q.sea_cell, SeaParts::drop, threads);
  const double sea_ms = ms_since(t1);
  if (!sea) {
    std::fprintf(stderr, "houle info: %s\n", sea.error().message.c_str());
    return 1;
  }
  std::size_t rays_memory = 0, sea_memory = 0;
  for (const WaveRays& w : field->trains) rays_memory += ray_bytes(w);
  for (const ReflectedWave& r : field->reflections) rays_memory += ray_bytes(r.rays);
  for (const TrainField& f : sea->trains()) {
    sea_memory += bytes(f.phi) + bytes(f.b_re) + bytes(f.b_im) + bytes(f.kx) + bytes(f.ky) + bytes(f.fold) + bytes(f.lean);
  }
  const DwtStats& st = field->stats;
  const DiffractionWork& dw = sea->diffraction_work();
  const std::string& name = run->name;

  if (json) {
    std::printf("{\"scene\": %s, \"quality\": \"%s\", \"threads\": %u,\n", json_string(name).c_str(),
                quality_name(quality).data(), threads);
    std::printf(" \"domain\": [%g, %g, %g, %g], \"walls\": %zu, \"boxes\": %zu, \"spheres\": %zu,\n", s.domain.x_min,
                s.domain.y_min, s.domain.x_max, s.domain.y_max, s.walls.size(), s.boxes.size(), s.spheres.size());
    std::printf(" \"warnings\": [");
    for (std::size_t i = 0; i < warnings.size(); ++i) std::printf("%s%s", i ? ", " : "", json_string(warnings[i]).c_str());
    std::printf("],\n");
    std::printf(" \"plan\": {\"ray_tracing\": %s, \"wave_model\": \"%s\", \"wave_model_why\": %s, \"diffraction\": %s, "
                "\"wall_reflection\": %s, \"capillary_noise\": %s, "
                "\"refraction\": %s, \"specular\": %s, \"shadows\": %s, \"reflect_objects\": %s, \"surf\": %s},\n",
                json_bool(plan.ray_tracing), wave_model_name(plan.wave_model.kind).data(),
                json_string(std::string(plan.wave_model.why)).c_str(), json_bool(plan.diffraction), json_bool(plan.wall_reflection),
                json_bool(plan.capillary_noise), json_bool(plan.refraction), json_bool(plan.specular),
                json_bool(plan.shadows), json_bool(plan.reflect_objects), json_bool(plan.surf));
    std::printf(" \"trains\": [");
    for (std::size_t i = 0; i < s.trains.size(); ++i) {
      const WaveTrain& t = s.trains[i];
      const WaveRays& w = field->trains[i];
      const double omega = train_omega(t);
      const Point2 d = train_direction(t);
      const TrainField& f = sea->trains()[i];
      std::printf("%s\n  {\"period_s\": %.6g, \"deep_wavelength_m\": %.6g, \"amplitude_m\": %g, \"direction_deg\": %.6g, "
                  "\"traced\": %s, \"rays\": %zu, \"samples\": %zu, \"model\": \"%s\", \"march_nodes\": %llu, "
                  "\"resolved_wavelength_m\": %.6g}",
                  i ? "," : "", 2.0 * std::numbers::pi / omega, 2.0 * std::numbers::pi * 9.81 / (omega * omega),
                  t.amplitude, std::atan2(d.y, d.x) * 180.0 / std::numbers::pi, json_bool(plan.train_rays[i]),
                  w.ray_count(), w.sample_count(), wave_model_name(f.model).data(),
                  static_cast<unsigned long long>(f.model_nodes), f.resolved_wavelength);
    }
    std::printf("],\n \"reflections\": [");
    for (std::size_t i = 0; i < field->reflections.size(); ++i) {
      const ReflectedWave& r = field->reflections[i];
      std::printf("%s{\"train\": %zu, \"rays\": %zu, \"samples\": %zu}", i ? ", " : "", r.train, r.rays.ray_count(),
                  r.rays.sample_count());
    }
    std::printf("],\n \"totals\": {\"rays\": %llu, \"initial_rays\": %llu, \"inserted_rays\": %llu, "
                "\"reflected_rays\": %llu, \"samples\": %llu, \"steps\": %llu, "
                "\"crossings\": %llu, \"broken_rays\": %llu, \"turned_back\": %llu, \"shared_steps\": %llu, \"truncated\": %s},\n",
                static_cast<unsigned long long>(st.rays), static_cast<unsigned long long>(st.initial_rays),
                static_cast<unsigned long long>(st.inserted_rays), static_cast<unsigned long long>(st.reflected_rays),
                static_cast<unsigned long long>(st.samples), static_cast<unsigned long long>(st.steps),
                static_cast<unsigned long long>(st.crossings), static_cast<unsigned long long>(st.broken_rays),
                static_cast<unsigned long long>(st.turned_back), static_cast<unsigned long long>(st.shared_steps),
                json_bool(st.truncated));
    std::printf(" \"sea_diffraction\": {\"pierheads\": %zu, \"evaluations\": %llu},\n", dw.pierheads,
                static_cast<unsigned long long>(dw.evaluations));
    std::printf(" \"memory_bytes\": {\"rays\": %zu, \"sea_grid\": %zu},\n", rays_memory, sea_memory);
    std::printf(" \"estimate\": {\"peak_bytes\": %llu, \"cpu_seconds\": %.6g, \"samples\": %llu},\n",
                (unsigned long long)cost.bytes(), cost.seconds(), (unsigned long long)cost.samples);
    std::printf(" \"build_ms\": {\"trace\": %.3f, \"sea_surface\": %.3f, \"total\": %.3f}}\n", trace_ms, sea_ms,
                trace_ms + sea_ms);
    return 0;
  }

  std::printf("scene: %s\n", name.c_str());
  std::printf("domain: [%g, %g] x [%g, %g] m\n", s.domain.x_min, s.domain.x_max, s.domain.y_min, s.domain.y_max);
  std::printf("sea floor: %s, depth %g m; %zu shoals, %zu bars, %zu channels%s\n",
              s.floor.base.kind == FloorKind::flat ? "flat" : "planar beach", s.floor.base.depth, s.floor.shoals.size(),
              s.floor.bars.size(), s.floor.channels.size(), s.floor.height_map ? ", height map" : "");
  std::printf("trains: %zu\n", s.trains.size());
  for (std::size_t i = 0; i < s.trains.size(); ++i) {
    const WaveTrain& t = s.trains[i];
    const WaveRays& w = field->trains[i];
    const double omega = train_omega(t);
    const Point2 d = train_direction(t);
    const std::string origin = t.sea_state >= 0 ? ", of sea_states[" + std::to_string(t.sea_state) + "]" : "";
    std::printf("  [%zu] period %.3g s, deep-water wavelength %.4g m, amplitude %g m, towards %.1f deg%s\n", i,
                2.0 * std::numbers::pi / omega, 2.0 * std::numbers::pi * 9.81 / (omega * omega), t.amplitude,
                std::atan2(d.y, d.x) * 180.0 / std::numbers::pi, origin.c_str());
    if (plan.train_rays[i]) {
      std::printf("      traced: %zu rays, %zu samples\n", w.ray_count(), w.sample_count());
      const TrainField& f = sea->trains()[i];
      if (f.model == WaveModelKind::parabolic) {
        std::printf("      parabolic model: %llu march nodes, wavelengths down to %.3g m resolved\n",
                    static_cast<unsigned long long>(f.model_nodes), f.resolved_wavelength);
      }
    } else {
      std::printf("      analytic: straight crests, no rays\n");
    }
  }
  for (const ReflectedWave& r : field->reflections) {
    std::printf("  reflected wave of [%zu]: %zu rays, %zu samples\n", r.train, r.rays.ray_count(), r.rays.sample_count());
  }
  const auto floating = std::count_if(s.boxes.begin(), s.boxes.end(), [](const Box& b) { return b.floats; }) +
                        std::count_if(s.spheres.begin(), s.spheres.end(), [](const Sphere& b) { return b.floats; });
  std::printf("walls: %zu, boxes: %zu, spheres: %zu (%zu floating)\n", s.walls.size(), s.boxes.size(), s.spheres.size(),
              std::size_t(floating));
  for (const std::string& w : warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("capillary ripples: %s\n", s.capillary.amplitude > 0.0 ? "on" : "off");
  std::printf("effect plan (%s): ray tracing %s, diffraction %s, wall reflection %s, capillary noise %s, refraction %s, "
              "specular %s, shadows %s, object reflections %s, surf %s\n",
              quality_name(quality).data(), yes(plan.ray_tracing), yes(plan.diffraction), yes(plan.wall_reflection),
              yes(plan.capillary_noise), yes(plan.refraction), yes(plan.specular), yes(plan.shadows),
              yes(plan.reflect_objects), yes(plan.surf));
  std::printf("wave model: %s (%s)\n", wave_model_name(plan.wave_model.kind).data(), plan.wave_model.why.data());
  std::printf("rays: %llu (%llu initial, %llu inserted, %llu reflected), %llu samples, %llu wavefront steps (%llu shared "
              "by two lanes), %llu turned back by refraction%s\n",
              static_cast<unsigned long long>(st.rays), static_cast<unsigned long long>(st.initial_rays),
              static_cast<unsigned long long>(st.inserted_rays), static_cast<unsigned long long>(st.reflected_rays),
              static_cast<unsigned long long>(st.samples), static_cast<unsigned long long>(st.steps),
              static_cast<unsigned long long>(st.shared_steps), static_cast<unsigned long long>(st.turned_back),
              st.truncated ? " (TRUNCATED at a cap)" : "");
  std::printf("diffracted waves (sea surface): %zu (pierheads x trains), computed at %llu grid nodes in all\n",
              dw.pierheads, static_cast<unsigned long long>(dw.evaluations));
  std::printf("memory: rays %.2f MiB, sea grids %.2f MiB\n", double(rays_memory) / 1048576.0, double(sea_memory) / 1048576.0);
  std::printf("estimated before the build (a render adds its image and floor): %.0f MiB at the peak, %.1f s of CPU, %llu samples\n",
              double(cost.bytes()) / 1048576.0, cost.seconds(), (unsigned long long)cost.samples);
  std::printf("build time: %.2f ms (tracing %.2f ms, resampling %.2f ms, %u threads)\n", trace_ms + sea_ms, trace_ms, sea_ms,
              threads);
  return 0;
}

}  // namespace houle::cli
