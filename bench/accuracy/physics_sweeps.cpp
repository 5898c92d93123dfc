// The physics knobs, measured where an exact or a much finer answer exists:
// - Dynamic Wave Tracing step and insertion distance on the built-in coast (refraction over the
//   beach, shoaling, the jetty's diffraction): the resampled sea (realtime's sea_cell) against the
//   one traced with the knob 8x (step) or 4x (insertion) finer, as RMS height in m over the domain
//   at a few times and RMS amplitude per train in m; the time is the trace (one thread).
// - The wave model (rays, or the parabolic model at several resolutions) against the laboratory
//   measurements of Berkhoff, Booy & Radder (1982): RMS of H/H0 over the 208 points and the worst
//   section's RMS; the time is the whole build (trace and sea surface, one thread).
// - Diffraction models against the exact Sommerfeld solution (itself checked against scipy to 2e-15,
//   diffraction.hpp): mean and max |K - K_exact| over r/L in [0.5, 10], every angle; ns per
//   coefficient. The float A&S path (sommerfeld_field_fg, the candidate for a float kernel) is a
//   fourth point.
// - Sea-state components (docs/physics.md 2.9) on the built-in coast with a JONSWAP sea instead of its
//   trains: the Hs map (4 sqrt(sum |B|^2 / 2) over the trains, on a 1 m lattice of the domain) of N
//   components against the one of 256, RMS and max in m; the time is the scene build and the
//   frame's surface fill (realtime, 2 threads), which grow with N.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "houle/sim/animation.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
#include "berkhoff_shoal.hpp"
#include "sweep.hpp"

namespace houle::accuracy {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double pi = 3.14159265358979323846;

// ---- Dynamic Wave Tracing ------------------------------------------------------------------------

struct Traced {
  SeaSurface sea;
  double trace_ms;  ///< median over the runs
  bool truncated;
};

Traced trace(const Scene& scene, const DwtSettings& dwt, int runs) {
  std::vector<double> ms;
  Expected<WaveField> f = Error{"", ""};
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    f = trace_wave_field(scene, dwt, 1);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!f) fail(f.error());
  }
  Expected<SeaSurface> sea = SeaSurface::build(scene, f.value(), quality_preset(QualityPreset::realtime).sea_cell);
  if (!sea) fail(sea.error());
  return {std::move(sea.value()), median(ms), f.value().stats.truncated};
}

struct SurfaceError {
  double height_m = 0.0;     ///< RMS height difference
  double amplitude = 0.0;    ///< RMS of A - A_ref (m) over the surface's trains (reflected ones included)
};

/// Over a 1 m lattice of the domain (land included: both are 0 there), at three times.
SurfaceError surface_error(SeaSurface& a, SeaSurface& ref, const Scene& scene) {
  std::vector<float> x, y;
  for (double py = scene.domain.y_min + 0.5; py < scene.domain.y_max; py += 1.0) {
    for (double px = scene.domain.x_min + 0.5; px < scene.domain.x_max; px += 1.0) x.push_back(float(px)), y.push_back(float(py));
  }
  const std::size_t n = x.size();
  std::vector<float> ha(n), hr(n), g1(n), g2(n);
  double se = 0.0, sa = 0.0;
  std::size_t na = 0;
  for (double t : {0.0, 2.7, 5.9}) {
    a.set_time(t);
    ref.set_time(t);
    a.eval(x.data(), y.data(), n, ha.data(), g1.data(), g2.data());
    ref.eval(x.data(), y.data(), n, hr.data(), g1.data(), g2.data());
    for (std::size_t i = 0; i < n; ++i) se += double(ha[i] - hr[i]) * double(ha[i] - hr[i]);
  }
  // Wall reflection adds trains (with no deep-water amplitude of their own, so no relative one).
  const std::size_t trains = std::min(a.trains().size(), ref.trains().size());
  for (std::size_t tr = 0; tr < trains; ++tr) {
    for (std::size_t i = 0; i < n; ++i) {
      const double d = double(a.probe(tr, x[i], y[i]).amplitude) - double(ref.probe(tr, x[i], y[i]).amplitude);
      sa += d * d;
      ++na;
    }
  }
  return {std::sqrt(se / double(3 * n)), std::sqrt(sa / double(std::max<std::size_t>(na, 1)))};
}

struct DwtKnob {
  const char* name;
  std::vector<double> values;  ///< least accurate first
  double reference;
  double DwtSettings::*field;
};

void sweep_dwt(const Options& o, std::vector<Row>& rows) {
  const Scene coast = builtin_coast();
  const int runs = o.smoke ? 1 : 3;
  const DwtKnob knobs[] = {
      {"dwt.step", {1.6, 0.8, 0.4, 0.2, 0.1}, 0.05, &DwtSettings::step},
      {"dwt.insertion_distance", {4.0, 2.0, 1.0, 0.5}, 0.25, &DwtSettings::insertion_distance},
  };
  for (const DwtKnob& k : knobs) {
    if (!o.only.empty() && o.only != k.name) continue;
    DwtSettings d = coast.dwt;
    d.*k.field = o.smoke ? k.values[1] : k.reference;
    Traced ref = trace(coast, d, 1);
    std::fprintf(stderr, "%s: reference %g (%.0f ms%s)\n", k.name, d.*k.field, ref.trace_ms,
                 ref.truncated ? ", truncated" : "");
    const std::size_t n = o.smoke ? 1 : k.values.size();
    for (std::size_t i = 0; i < n; ++i) {
      d.*k.field = k.values[i];
      Traced t = trace(coast, d, runs);
      const SurfaceError e = surface_error(t.sea, ref.sea, coast);
      Row r;
      r.knob = k.name;
      r.value = k.values[i];
      r.presets = k.values[i] == coast.dwt.*k.field ? "all (scene default)" : "";
      r.time = t.trace_ms;
      r.time_what = "trace_wave_field, 1 thread (ms)";
      r.error = e.height_m;
      r.error_what = "RMS height (m)";
      r.error2 = e.amplitude;
      r.error2_what = "RMS amplitude (m)";
      char ref_text[96];
      std::snprintf(ref_text, sizeof ref_text, "trace at %g m%s, built-in coast", o.smoke ? k.values[1] : k.reference,
                    ref.truncated ? " (truncated)" : "");
      r.reference = ref_text;
      std::fprintf(stderr, "  %g: %.1f ms, %.4f m, amplitude %.4f m%s\n", k.values[i], t.trace_ms, e.height_m, e.amplitude,
                   t.truncated ? " (truncated)" : "");
      rows.push_back(std::move(r));
    }
  }
}

// ---- Wave model on the elliptic shoal --------------------------------------------------------------

void sweep_wave_model(const Options& o, std::vector<Row>& rows) {
  const std::vector<houle_test::BerkhoffPoint> points = houle_test::berkhoff_measurements(HOULE_TEST_DATA_DIR);
  if (points.empty()) fail({"berkhoff1982_sections.csv", "cannot read the measurements"});
  struct Variant {
    const char* name;
    double value;  ///< the CSV's value column: an index, named in `presets`
    WaveModelKind kind;
    double points_per_wavelength;
    bool amplitude_dispersion;
  };
  const Variant variants[] = {
      {"rays", 0, WaveModelKind::rays, 10.0, true},
      {"parabolic_linear", 1, WaveModelKind::parabolic, 10.0, false},
      {"parabolic_ppw4", 2, WaveModelKind::parabolic, 4.0, true},
      {"parabolic_ppw6", 3, WaveModelKind::parabolic, 6.0, true},
      {"parabolic", 4, WaveModelKind::parabolic, 10.0, true},
      {"parabolic_ppw16", 5, WaveModelKind::parabolic, 16.0, true},
  };
  const int runs = o.smoke ? 1 : 3;
  for (const Variant& v : variants) {
    if (o.smoke && v.kind == WaveModelKind::rays) continue;
    Scene scene = houle_test::berkhoff_scene(v.kind);
    scene.wave_model.points_per_wavelength = v.points_per_wavelength;
    scene.wave_model.amplitude_dispersion = v.amplitude_dispersion;
    std::vector<double> ms;
    Expected<SeaSurface> sea = Error{"", ""};
    for (int i = 0; i < runs; ++i) {
      const auto t0 = Clock::now();
      Expected<WaveField> f = trace_wave_field(scene, 1);
      if (!f) fail(f.error());
      sea = SeaSurface::build(scene, f.value(), quality_preset(QualityPreset::realtime).sea_cell);
      if (!sea) fail(sea.error());
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    double all = 0.0, worst_section = 0.0;
    for (int section = 1; section <= 8; ++section) {
      double sum = 0.0;
      int count = 0;
      for (const houle_test::BerkhoffPoint& p : points) {
        if (p.section != section) continue;
        const double e = sea.value().probe(0, float(p.x), float(p.y)).amplitude / houle_test::berkhoff_amplitude - p.relative;
        sum += e * e;
        ++count;
      }
      all += sum;
      if (count) worst_section = std::max(worst_section, std::sqrt(sum / count));
    }
    Row r;
    r.knob = "wave_model";
    r.value = v.value;
    r.presets = v.name;
    r.time = median(ms);
    r.time_what = "scene build, 1 thread (ms)";
    r.error = std::sqrt(all / double(points.size()));
    r.error_what = "RMS of H/H0";
    r.error2 = worst_section;
    r.error2_what = "worst section's RMS";
    r.reference = "Berkhoff, Booy & Radder (1982), 208 measured points on 8 sections (tests/data)";
    std::fprintf(stderr, "wave model %s: %.0f ms, RMS %.3f, worst section %.3f\n", v.name, r.time, r.error, worst_section);
    rows.push_back(std::move(r));
  }
}

// ---- Diffraction models --------------------------------------------------------------------------

struct Point {
  double r_over_L, theta;
};

void sweep_diffraction(const Options& o, std::vector<Row>& rows) {
  constexpr double theta0 = pi / 2, rigid = 1.0;
  std::vector<Point> pts(o.smoke ? 100 : 20000);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> rl(0.5, 10.0), th(1e-3, 2.0 * pi - 1e-3);
  for (Point& p : pts) p = {rl(rng), th(rng)};
  std::vector<double> exact(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) exact[i] = std::abs(sommerfeld_field(2.0 * pi * pts[i].r_over_L, pts[i].theta, theta0, rigid));

  struct Variant {
    const char* name;
    double value;  ///< the CSV's value column: an index, named in `presets`
    double (*k)(const Point&);
  };
  const Variant variants[] = {
      {"paper", 0, [](const Point& p) { return diffraction(DiffractionModel::paper, p.r_over_L, p.theta, theta0, rigid).value().K; }},
      {"paper_corrected", 1,
       [](const Point& p) { return diffraction(DiffractionModel::paper_corrected, p.r_over_L, p.theta, theta0, rigid).value().K; }},
      {"exact_float", 2,
       [](const Point& p) { return double(std::abs(sommerfeld_field_fg(2.0 * pi * p.r_over_L, p.theta, theta0, 1.0f))); }},
      {"exact", 3, [](const Point& p) { return diffraction(DiffractionModel::exact, p.r_over_L, p.theta, theta0, rigid).value().K; }},
  };
  for (const Variant& v : variants) {
    std::vector<double> ns;
    double mean = 0.0, worst = 0.0, sink = 0.0;
    for (int rep = 0; rep < (o.smoke ? 1 : 7); ++rep) {
      const auto t0 = Clock::now();
      for (const Point& p : pts) sink += v.k(p);
      ns.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(pts.size()));
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double d = std::abs(v.k(pts[i]) - exact[i]);
      mean += d;
      worst = std::max(worst, d);
    }
    if (!std::isfinite(sink)) std::fprintf(stderr, "diffraction %s: non-finite K\n", v.name);
    Row r;
    r.knob = "diffraction.model";
    r.value = v.value;
    r.presets = v.name;  // the model's name (the presets all use exact)
    r.time = median(ns);
    r.time_what = "per coefficient (ns)";
    r.error = mean / double(pts.size());
    r.error_what = "mean |K - K_exact|";
    r.error2 = worst;
    r.error2_what = "max |K - K_exact|";
    r.reference = "Sommerfeld (sommerfeld_field, double), rigid wall, normal incidence, r/L in [0.5, 10]";
    std::fprintf(stderr, "diffraction %s: %.1f ns, mean %.2e, max %.2e\n", v.name, median(ns), r.error, worst);
    rows.push_back(std::move(r));
  }
}

// ---- Sea-state components -----------------------------------------------------------------------

Scene coast_sea_state(std::uint32_t components) {
  Scene s = builtin_coast();
  s.trains.clear();
  SeaState sea;
  sea.significant_height = 0.8;
  sea.peak_period = 6.0;
  sea.direction_deg = 80.0;
  sea.spread_deg = 20.0;
  sea.components = components;
  s.sea_states = {sea};
  // Caps near what a component needs, so that the memory estimate admits 128 traced components.
  s.dwt.max_rays = 4096;
  s.dwt.max_samples = 131072;
  const Expected<Scene> valid = validate(s);
  if (!valid) fail(valid.error());
  return valid.value();
}

/// Hs (m) at each point of the 1 m lattice of the domain, from the scene's sea at `cell` m.
std::vector<double> hs_map(const Scene& scene, float cell, unsigned threads) {
  Expected<WaveField> field = trace_wave_field(scene, threads);
  if (!field) fail(field.error());
  Expected<SeaSurface> sea = SeaSurface::build(scene, field.value(), cell, SeaParts::drop, threads);
  if (!sea) fail(sea.error());
  std::vector<double> hs;
  for (double py = scene.domain.y_min + 0.5; py < scene.domain.y_max; py += 1.0) {
    for (double px = scene.domain.x_min + 0.5; px < scene.domain.x_max; px += 1.0) {
      double variance = 0.0;
      for (std::size_t t = 0; t < sea->trains().size(); ++t) {
        const double a = sea->probe(t, float(px), float(py)).amplitude;
        variance += 0.5 * a * a;
      }
      hs.push_back(4.0 * std::sqrt(variance));
    }
  }
  return hs;
}

void sweep_components(const Options& o, std::vector<Row>& rows) {
  const std::uint32_t reference = o.smoke ? 4 : 256;
  const float cell = quality_preset(QualityPreset::draft).sea_cell;
  const std::vector<double> ref = hs_map(coast_sea_state(reference), cell, o.threads);
  std::fprintf(stderr, "sea_state.components: reference %u\n", reference);
  const std::vector<std::uint32_t> counts = o.smoke ? std::vector<std::uint32_t>{2} : std::vector<std::uint32_t>{4, 8, 16, 24, 32, 48, 64, 128};
  const std::uint32_t scene_default = SeaState{}.components;
  for (std::uint32_t n : counts) {
    const Scene scene = coast_sea_state(n);
    const std::vector<double> hs = hs_map(scene, cell, o.threads);
    double se = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < hs.size(); ++i) {
      se += (hs[i] - ref[i]) * (hs[i] - ref[i]);
      worst = std::max(worst, std::abs(hs[i] - ref[i]));
    }
    // Build and frames at realtime: the fastest of the repeats per frame, the median over the frames.
    Expected<Animation> a = Animation::create(scene, quality_preset(QualityPreset::realtime), o.width, o.height, o.threads);
    if (!a) fail(a.error());
    Framebuffer fb(int(o.width), int(o.height));
    std::vector<double> frame, surface;
    for (int f = 0; f < o.frames; ++f) {
      double best_frame = INFINITY, best_surface = INFINITY;
      for (int k = 0; k < o.timing_repeats; ++k) {
        const auto t0 = Clock::now();
        a->render(0.7 + 1.3 * f, fb);
        best_frame = std::min(best_frame, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        best_surface = std::min(best_surface, a->last_times().surface_ms);
      }
      frame.push_back(best_frame);
      surface.push_back(best_surface);
    }
    Row r;
    r.knob = "sea_state.components";
    r.value = n;
    r.presets = n == scene_default ? "all (scene default)" : "";
    r.time = a->build_ms();
    r.time_what = "scene build, realtime (ms)";
    r.frame_ms = median(frame);
    r.error = std::sqrt(se / double(hs.size()));
    r.error_what = "RMS Hs (m)";
    r.error2 = worst;
    r.error2_what = "max |Hs - Hs_ref| (m)";
    char ref_text[128];
    std::snprintf(ref_text, sizeof ref_text, "%u components, built-in coast under Hs 0.8 m, Tp 6 s, spread 20 deg", reference);
    r.reference = ref_text;
    std::fprintf(stderr, "  %u: build %.0f ms, frame %.1f ms (surface %.1f ms), Hs RMS %.4f m, max %.4f m\n", n, r.time,
                 r.frame_ms, median(surface), r.error, worst);
    rows.push_back(std::move(r));
  }
}

}  // namespace

std::vector<Row> sweep_physics_knobs(const Options& o) {
  std::vector<Row> rows;
  if (o.only.empty() || o.only == "diffraction.model") sweep_diffraction(o, rows);
  if (o.only.empty() || o.only == "wave_model") sweep_wave_model(o, rows);
  sweep_dwt(o, rows);
  if (o.only.empty() || o.only == "sea_state.components") sweep_components(o, rows);
  return rows;
}

}  // namespace houle::accuracy
