// Dynamic Wave Tracing's entry points (wave_rays.hpp): a scene's trains traced, each by a TrainTracer
// (train_tracer.hpp), with their reflected waves, on a worker each and a second lane where threads allow.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "houle/runtime/thread_pool.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_keys.hpp"
#include "houle/sim/wave_rays.hpp"
#include "ray_walls.hpp"
#include "train_tracer.hpp"

namespace houle {
namespace detail {
namespace {

Expected<Scene> checked(const Scene& scene, const DwtSettings& settings) {
  Scene copy = scene;
  copy.dwt = settings;
  return validate(std::move(copy));
}

// Effect plan: straight crests, analytic phase, no rays.
WaveRays analytic_rays(const Scene& scene, std::size_t train) {
  WaveRays out;
  const WaveTrain& t = scene.trains[train];
  out.omega = train_omega(t);
  const Point2 d = train_direction(t);
  out.direction_x = d.x;
  out.direction_y = d.y;
  out.amplitude0 = t.amplitude;
  out.analytic = true;
  const Bathymetry floor(scene.floor);
  const LinearWave w = linear_wave(out.omega, floor.uniform() ? scene.floor.base.depth : 1e9);
  out.analytic_k = w.k;
  out.analytic_amplitude = t.amplitude * shoaling_coefficient(w.kh);
  return out;
}

// The same, and `train` must be one of its trains.
Expected<Scene> checked(const Scene& scene, const DwtSettings& settings, std::size_t train) {
  if (train >= scene.trains.size()) {
    return Error{"trains", "an index below " + std::to_string(scene.trains.size()) + ", got " + std::to_string(train)};
  }
  return checked(scene, settings);
}

// A train's second lane: none on one thread, else a pool of two (the tracer shares its passes between
// two lanes at most).
Expected<std::unique_ptr<ThreadPool>> train_pool(unsigned threads) {
  if (threads < 2) return std::unique_ptr<ThreadPool>();
  return ThreadPool::create(2);
}

}  // namespace
}  // namespace detail

DwtStats& DwtStats::operator+=(const DwtStats& o) noexcept {
  rays += o.rays;
  initial_rays += o.initial_rays;
  inserted_rays += o.inserted_rays;
  samples += o.samples;
  steps += o.steps;
  crossings += o.crossings;
  broken_rays += o.broken_rays;
  wall_hits += o.wall_hits;
  left_domain += o.left_domain;
  reached_shore += o.reached_shore;
  turned_back += o.turned_back;
  reflected_rays += o.reflected_rays;
  insertions_refused += o.insertions_refused;
  shared_steps += o.shared_steps;
  truncated = truncated || o.truncated;
  return *this;
}

namespace {

// dwt.on_cap = "error": a trace that reached a cap stopped there, and the field beyond would be
// missing (zero) without anything in a render saying so.
Expected<void> untruncated(std::size_t train, const DwtStats& st, const DwtSettings& dwt) {
  if (!st.truncated) return {};
  const std::string which =
      st.rays >= dwt.max_rays || st.insertions_refused > 0
          ? "dwt.max_rays (" + std::to_string(dwt.max_rays) + " rays)"
          : st.samples >= dwt.max_samples ? "dwt.max_samples (" + std::to_string(dwt.max_samples) + " samples)"
                                          : "the path length a ray may travel";
  return Error{"dwt.on_cap", "train " + std::to_string(train) + "'s wave rays reached " + which +
                                 " and stopped, leaving the field beyond them empty: expected a larger cap, a "
                                 "larger dwt.step or dwt.insertion_distance, or on_cap = \"warn\" to accept it"};
}

}  // namespace

bool scene_has_pierheads(const Scene& scene) noexcept {
  if (!scene.dwt.diffraction || scene.walls.empty()) return false;
  const Bathymetry floor(scene.floor);
  // h_min is per train; the smallest possible (min_depth) keeps this a safe over-estimate.
  return !detail::pierhead_sites(scene, floor, scene.dwt.min_depth).empty();
}

bool scene_has_reflecting_walls(const Scene& scene) noexcept {
  if (!scene.dwt.reflection) return false;
  return std::any_of(scene.walls.begin(), scene.walls.end(), [](const Wall& w) { return w.reflection > 0.0; });
}

bool train_needs_rays(const Scene& scene, std::size_t train) noexcept {
  if (train >= scene.trains.size()) return false;
  const WaveTrain& t = scene.trains[train];
  if (!(t.amplitude > 0.0)) return false;
  if (!scene.walls.empty()) return true;
  const Bathymetry floor(scene.floor);
  if (floor.uniform()) return false;
  // Deep everywhere (h >= L0: kh >= 2 pi, C within 1e-5 of g / omega): no refraction worth a ray.
  const double l0 = 2.0 * std::numbers::pi / deep_water_wavenumber(train_omega(t));
  return !(floor.min_depth_bound(scene.domain) >= l0);
}

TrainModel scene_wave_model(const Scene& scene) noexcept {
  switch (scene.wave_model.kind) {
    case WaveModelKind::rays: return {WaveModelKind::rays, "wave_model.kind = \"rays\""};
    case WaveModelKind::parabolic: return {WaveModelKind::parabolic, "wave_model.kind = \"parabolic\""};
    case WaveModelKind::automatic: break;
  }
  const SeaFloor& f = scene.floor;
  if (!f.shoals.empty() || !f.bars.empty() || !f.channels.empty() || f.height_map) {
    return {WaveModelKind::parabolic,
            "auto: shoals, bars, channels or a height map make rays cross, where ray amplitudes are capped, not computed"};
  }
  return {WaveModelKind::rays, "auto: over a flat floor or a plane beach rays do not cross, and diffraction is exact"};
}

std::string_view wave_model_name(WaveModelKind kind) noexcept {
  switch (kind) {
    case WaveModelKind::rays: return "rays";
    case WaveModelKind::parabolic: return "parabolic";
    case WaveModelKind::automatic: return "auto";
  }
  return "?";
}

DwtBound dwt_bound(const Scene& scene, std::size_t train, const DwtSettings& settings) noexcept {
  DwtBound b;
  b.rays = settings.max_rays;
  b.samples = settings.max_samples;
  if (train >= scene.trains.size()) return b;
  const Bathymetry floor(scene.floor);
  const double omega = train_omega(scene.trains[train]);
  const double h_min = std::max(settings.min_depth, settings.min_depth_wavelengths * 2.0 * std::numbers::pi /
                                                        deep_water_wavenumber(omega));
  const detail::Medium m = detail::make_medium(scene, floor, omega, h_min);
  const detail::Front f = detail::make_front(scene, train, settings, m);
  if (!(f.dphi > 0.0)) return DwtBound{f.entries.size(), 0};
  // Every ray ends within the path limit; each step takes at least dphi / k(h_min) of path.
  const double steps = detail::path_limit(scene.domain) * detail::wave_from_depth(m, h_min).k / f.dphi + 4.0;
  const double worst = double(settings.max_rays) * steps;
  b.samples = std::size_t(std::min(double(settings.max_samples), worst));
  return b;
}

std::vector<Error> trace_cap_warnings(const Scene& scene) {
  std::vector<Error> warnings;
  const DwtSettings& d = scene.dwt;
  if (detail::rays_only_seed_the_carrier(scene, d)) return warnings;  // a cap leaves nothing missing
  const std::string likely = ": the trace is likely to stop there (an error unless dwt.on_cap = \"warn\")";
  for (std::size_t i = 0; i < scene.trains.size(); ++i) {
    if (d.analytic_shortcut && !train_needs_rays(scene, i)) continue;
    const FrontSize f = front_size(scene, i, d);
    const double steps = std::floor(f.length / d.step) + 1.0, samples = double(f.rays) * steps;
    const std::string train = "trains[" + std::to_string(i) + "]'s ";
    if (samples > double(d.max_samples)) {
      warnings.push_back(Error{"dwt.max_samples",
                               train + std::to_string(f.rays) + " initial rays cross the " +
                                   scene_keys::number_text(std::round(f.length * 1e3) / 1e3) + " m domain in " +
                                   scene_keys::number_text(steps) + " steps of dwt.step, about " +
                                   scene_keys::number_text(std::round(samples)) + " samples before any insertion, "
                                   "over this cap of " + std::to_string(d.max_samples) + likely});
    } else if (expected_trace_samples(scene, i) >= double(d.max_samples)) {
      warnings.push_back(Error{"dwt.max_samples",
                               train + "rays, with those that insertion adds where the floor refracts them apart, are "
                                       "expected to take more samples than this cap of " +
                                   std::to_string(d.max_samples) + likely});
    }
  }
  return warnings;
}

Expected<WaveRays> trace_train(const Scene& scene, std::size_t train, const DwtSettings& settings, DwtStats* stats,
                               unsigned threads) {
  auto valid = detail::checked(scene, settings, train);
  if (!valid.ok()) return valid.error();
  DwtStats local;
  DwtStats& st = stats ? *stats : local;
  st = DwtStats{};
  if (settings.analytic_shortcut && !train_needs_rays(scene, train)) return detail::analytic_rays(scene, train);
  auto pool = detail::train_pool(threads);
  if (!pool) return pool.error();
  detail::TrainTracer tracer(valid.value(), train, valid->dwt, pool->get());
  return tracer.run(st);
}

Expected<WaveRays> trace_reflection(const Scene& scene, std::size_t train, const WaveRays& incident,
                                    const DwtSettings& settings, DwtStats* stats, unsigned threads) {
  auto valid = detail::checked(scene, settings, train);
  if (!valid.ok()) return valid.error();
  DwtStats local;
  DwtStats& st = stats ? *stats : local;
  st = DwtStats{};
  WaveRays none;
  none.omega = incident.omega;
  none.direction_x = incident.direction_x;
  none.direction_y = incident.direction_y;
  none.amplitude0 = incident.amplitude0;
  none.phase_step = incident.phase_step;
  none.min_depth = incident.min_depth;
  if (!valid->dwt.reflection || incident.analytic || !scene_has_reflecting_walls(valid.value())) return none;
  auto pool = detail::train_pool(threads);
  if (!pool) return pool.error();
  detail::TrainTracer tracer(valid.value(), train, valid->dwt, detail::ray_ends(incident), incident.omega, incident.direction_x,
                             incident.direction_y, incident.phase_step, pool->get());
  WaveRays out = tracer.run(st);
  st.reflected_rays = st.rays;
  return out;
}

Expected<WaveField> trace_wave_field(const Scene& scene, unsigned threads) {
  return trace_wave_field(scene, scene.dwt, threads);
}

Expected<WaveField> trace_wave_field(const Scene& scene, const DwtSettings& settings, unsigned threads) {
  auto valid = detail::checked(scene, settings);
  if (!valid.ok()) return valid.error();
  const Scene& s = valid.value();
  const std::size_t n = s.trains.size();
  std::vector<WaveRays> incident(n), reflected(n);
  std::vector<DwtStats> stats(n), reflected_stats(n);
  const std::size_t workers = std::min<std::size_t>(std::max(1u, threads), n);
  const unsigned lanes = workers > 0 ? threads / unsigned(workers) : 1u;
  const bool reflects = s.dwt.reflection && scene_has_reflecting_walls(s);
  // Trains are independent and each is traced as trace_train, then trace_reflection, would trace it,
  // on a worker and that worker's second lane when there are threads for one: the result does not
  // depend on the thread count.
  auto pool = detail::ThreadPool::create(unsigned(workers));
  if (!pool) return pool.error();
  std::vector<std::unique_ptr<detail::ThreadPool>> second_lanes(workers);
  for (auto& lane : second_lanes) {
    auto p = detail::train_pool(lanes);
    if (!p) return p.error();
    lane = std::move(p.value());
  }
  // Worker w traces trains w, w + workers, ...: the first train (in the shipped scenes the longest
  // waves, the most work) and the last share a worker only when there are more trains than workers.
  pool.value()->for_ranges(workers, 1, [&](std::size_t first, std::size_t, unsigned lane) {
    for (std::size_t i = first; i < n; i += workers) {
      if (s.dwt.analytic_shortcut && !train_needs_rays(s, i)) {
        incident[i] = detail::analytic_rays(s, i);
        continue;
      }
      detail::TrainTracer tracer(s, i, s.dwt, second_lanes[lane].get());
      incident[i] = reflects ? tracer.run_reflecting(stats[i], reflected[i], reflected_stats[i]) : tracer.run(stats[i]);
    }
  });
  if (s.dwt.on_cap == OnCap::error) {
    for (std::size_t i = 0; i < n; ++i) {
      if (Expected<void> whole = untruncated(i, stats[i], s.dwt); !whole) return whole.error();
      if (Expected<void> whole = untruncated(i, reflected_stats[i], s.dwt); !whole) return whole.error();
    }
  }
  WaveField field;
  for (std::size_t i = 0; i < n; ++i) {
    field.trains.push_back(std::move(incident[i]));
    field.stats += stats[i];
    if (reflected[i].sample_count() > 0) {
      field.reflections.push_back(ReflectedWave{i, std::move(reflected[i])});
      field.stats += reflected_stats[i];
    }
  }
  return field;
}

}  // namespace houle
