// The accuracy/time sweeps (docs/accuracy.md): one knob varied at a time, the others fixed, each
// setting measured for its error against a reference and for the time it costs.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "houle/sim/animation.hpp"
#include <vector>

namespace houle::accuracy {

struct Options {
  std::uint32_t width = 320, height = 180;  ///< px, the image knobs' sweep size
  int frames = 3;          ///< animation times compared with the reference (and timed)
  int timing_repeats = 3;  ///< each frame is rendered this many times; its fastest time counts
  unsigned threads = 2;
  bool smoke = false;      ///< one cheap setting per knob at a tiny size: exercises every path
  std::string only;        ///< non-empty: sweep this knob alone (e.g. "surface.levels")
  QualityPreset base = QualityPreset::realtime;  ///< the image knobs' other knobs (smoke: draft)
};

/// One measured setting of one knob.
struct Row {
  std::string knob;        ///< e.g. "march.step_fraction"
  double value = 0.0;      ///< the setting
  std::string presets;     ///< presets that use this value ("draft realtime"), space-separated
  double time = 0.0;       ///< what the knob costs (`time_what` says what and in which unit)
  std::string time_what;
  double frame_ms = 0.0;   ///< median whole frame (image knobs; 0 otherwise)
  double error = 0.0;      ///< primary error (`error_what`)
  std::string error_what;
  double error2 = 0.0;     ///< secondary error (`error2_what`)
  std::string error2_what;
  std::string reference;   ///< what the errors are measured against
};

/// Per-stage medians of a preset at one size, and its error against the brute-force reference.
struct PresetRow {
  std::string preset;
  std::uint32_t width = 0, height = 0;
  double frame_ms = 0.0;  ///< median over the frames of each frame's fastest repeat
  double surface_ms = 0.0, noise_ms = 0.0, march_ms = 0.0, intersect_ms = 0.0, shade_ms = 0.0;
  double rmse = -1.0, dssim = -1.0;  ///< -1: not measured at this size
};

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The sweeps run on valid built-in scenes: a failure is a bug to report, not a result.
[[noreturn]] inline void fail(const Error& e) {
  std::fprintf(stderr, "houle_accuracy: %s: %s\n", e.field.c_str(), e.message.c_str());
  std::exit(1);
}

/// Quality knobs of houle::Quality and the scene's capillary octaves, rendered (image error).
std::vector<Row> sweep_image_knobs(const Options& o);
/// Dynamic Wave Tracing step and insertion distance (surface error in m against a fine trace), and
/// the diffraction models against the exact Sommerfeld solution.
std::vector<Row> sweep_physics_knobs(const Options& o);
/// draft / realtime / film at 640x360 and 1280x720 (only the sweep size in smoke mode).
std::vector<PresetRow> measure_presets(const Options& o);

}  // namespace houle::accuracy
