// houle_accuracy: the accuracy/time sweeps of docs/accuracy.md as two CSV files. scripts/accuracy
// runs it and turns the CSV into the plots and tables of the doc; --smoke runs every path cheaply
// (a ctest entry, so the program cannot rot; no test depends on its numbers).
#include <cstdio>
#include <cstring>
#include <string>

#include "sweep.hpp"

namespace {

void usage() {
  std::puts(R"(usage: houle_accuracy [--knobs FILE] [--presets FILE] [--size WxH] [--frames N] [--repeats N] [--only KNOB] [--base PRESET] [--smoke]

Sweeps every accuracy knob of the built-in coast (and the wave-tracing knobs, the diffraction models)
one at a time and writes FILE (default accuracy.csv): knob, value, presets using it, time, error.
--presets FILE also times draft / realtime / film at 640x360 and 1280x720 and measures their error
at 640x360 against a brute-force render. --size is the image knobs' size (default 320x180); --only
sweeps one knob (its name as in the CSV, e.g. surface.levels); --base sets the other image knobs
to draft, realtime (default) or film.)");
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

}  // namespace

int main(int argc, char** argv) {
  houle::accuracy::Options o;
  std::string knobs_path = "accuracy.csv", presets_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--help") {
      usage();
      return 0;
    } else if (a == "--smoke") {
      o.smoke = true;
    } else if (a == "--knobs" && has_value) {
      knobs_path = argv[++i];
    } else if (a == "--base" && has_value && houle::parse_quality(argv[i + 1])) {
      o.base = *houle::parse_quality(argv[++i]);
    } else if (a == "--only" && has_value) {
      o.only = argv[++i];
    } else if (a == "--presets" && has_value) {
      presets_path = argv[++i];
    } else if (a == "--size" && has_value && std::sscanf(argv[i + 1], "%ux%u", &o.width, &o.height) == 2 &&
               o.width > 0 && o.height > 0) {
      ++i;
    } else if (a == "--frames" && has_value && std::sscanf(argv[i + 1], "%d", &o.frames) == 1 && o.frames > 0) {
      ++i;
    } else if (a == "--repeats" && has_value && std::sscanf(argv[i + 1], "%d", &o.timing_repeats) == 1 &&
               o.timing_repeats > 0) {
      ++i;
    } else {
      std::fprintf(stderr, "houle_accuracy: unexpected argument '%s'\n", a.c_str());
      usage();
      return 2;
    }
  }
  if (o.smoke) {
    o.width = 64, o.height = 36, o.frames = 1, o.timing_repeats = 1, o.base = houle::QualityPreset::draft;
  }

  std::vector<houle::accuracy::Row> rows = houle::accuracy::sweep_physics_knobs(o);
  for (auto& r : houle::accuracy::sweep_image_knobs(o)) rows.push_back(std::move(r));
  std::FILE* f = std::fopen(knobs_path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "houle_accuracy: cannot write %s\n", knobs_path.c_str());
    return 1;
  }
  std::fprintf(f, "knob,value,presets,time,time_what,frame_ms,error,error_what,error2,error2_what,reference\n");
  for (const auto& r : rows) {
    std::fprintf(f, "%s,%.9g,%s,%.6g,%s,%.6g,%.6g,%s,%.6g,%s,%s\n", r.knob.c_str(), r.value, quoted(r.presets).c_str(),
                 r.time, quoted(r.time_what).c_str(), r.frame_ms, r.error, quoted(r.error_what).c_str(), r.error2,
                 quoted(r.error2_what).c_str(), quoted(r.reference).c_str());
  }
  std::fclose(f);

  if (!presets_path.empty()) {
    const auto presets = houle::accuracy::measure_presets(o);
    std::FILE* p = std::fopen(presets_path.c_str(), "w");
    if (!p) {
      std::fprintf(stderr, "houle_accuracy: cannot write %s\n", presets_path.c_str());
      return 1;
    }
    std::fprintf(p, "preset,width,height,frame_ms,surface_ms,noise_ms,march_ms,intersect_ms,shade_ms,rmse,dssim\n");
    for (const auto& r : presets) {
      std::fprintf(p, "%s,%u,%u,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", r.preset.c_str(), r.width, r.height,
                   r.frame_ms, r.surface_ms, r.noise_ms, r.march_ms, r.intersect_ms, r.shade_ms, r.rmse,
                   r.dssim);
    }
    std::fclose(p);
  }
  return 0;
}
