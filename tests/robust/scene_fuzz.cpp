// The scene fuzzer: whatever `validate` accepts must build, render and probe (issue 22). Random
// scenes (scene_generator.hpp: every key within its range, extremes included) that validate are each
// run in a child process under a CPU-time and a memory bound: build the animation at draft quality,
// render one small frame, probe a few points; any refusal, crash, NaN or Inf, or a bound exceeded is
// a failure, and the scene is written as TOML (with its height map image) for a regression input.
//
//   houle_scene_fuzz [--seconds S] [--seed N] [--scenes N] [--keep DIR] [--cpu-seconds S] [--max-estimate S]
//                    [--memory-mib M]
//
// Bounds per scene: CPU time at most 3 times the build's estimate (build_cost.hpp) plus --cpu-seconds,
// peak resident memory at most --memory-mib (4.5 GiB). Scenes estimated over --max-estimate seconds
// are counted and skipped (the test suite's short run leaves them to scripts/fuzz-scenes).
//
// Scene i of a run is generate_scene(seed + i): `--seed S+i --scenes 1` runs it alone.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "houle/sim/animation.hpp"
#include "houle/sim/build_cost.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
#include "scene_generator.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  double seconds = 30.0;
  std::uint64_t seed = 1;
  std::uint64_t scenes = ~std::uint64_t(0);
  std::string keep;
  // Per scene: CPU seconds beyond its estimate (the child's may take `slack` times the estimate plus
  // this), the largest estimate run (longer ones are counted, not run), and the peak resident memory
  // (the build's 4 GiB limit and the process).
  double cpu_seconds = 10.0, slack = 3.0, max_estimate = 1e9;
  long memory_mib = 4608;
};

// What the child reports by its exit code.
enum Outcome : int { ok = 0, refused = 10, not_finite = 11, capped = 12 };

bool finite(float v) { return std::isfinite(v); }

// The resampling cell `houle probe` takes: the realtime quality's, or the draft's where that does not fit.
float probe_cell(const houle::Scene& scene) {
  const houle::Quality realtime = houle::quality_preset(houle::QualityPreset::realtime);
  if (houle::check_build_cost(houle::estimate_build_cost(scene, realtime, 0, 1), "")) return realtime.sea_cell;
  return houle::quality_preset(houle::QualityPreset::draft).sea_cell;
}

// Estimated CPU seconds of the child's work: the draft build and the probe's.
double estimated_seconds(const houle::Scene& scene) {
  houle::Quality q = houle::quality_preset(houle::QualityPreset::draft);
  const double build = houle::estimate_build_cost(scene, q, 48 * 27, 1).seconds();
  q.sea_cell = probe_cell(scene);
  return build + houle::estimate_build_cost(scene, q, 0, 1).seconds();
}

// In the child: the checks, then _exit with an Outcome.
[[noreturn]] void check_scene(const houle::Scene& scene) {
  constexpr std::uint32_t w = 48, h = 27;
  houle::Expected<houle::Animation> a =
      houle::Animation::create(scene, houle::quality_preset(houle::QualityPreset::draft), w, h, 1);
  if (!a) {
    // A trace that reached its cap fails when the scene says so (dwt.on_cap = "error"; validate warns of it).
    if (a.error().field == "dwt.on_cap" && scene.dwt.on_cap == houle::OnCap::error) std::_Exit(capped);
    std::fprintf(stderr, "build refused: %s: %s\n", a.error().field.c_str(), a.error().message.c_str());
    std::_Exit(refused);
  }
  houle::Framebuffer fb(w, h);
  a->render(3.7, fb);
  for (const float v : fb.rgb) {
    if (!finite(v)) {
      std::fprintf(stderr, "a pixel is not finite\n");
      std::_Exit(not_finite);
    }
  }
  // As `houle probe` does: the sea at the probe's cell, with its parts, at a few points in and around the domain.
  houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 1);
  if (!field) {
    std::fprintf(stderr, "probe's trace refused: %s: %s\n", field.error().field.c_str(), field.error().message.c_str());
    std::_Exit(refused);
  }
  const float cell = probe_cell(scene);
  houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), cell, houle::SeaParts::keep, 1);
  if (!sea) {
    std::fprintf(stderr, "probe's sea refused: %s: %s\n", sea.error().field.c_str(), sea.error().message.c_str());
    std::_Exit(refused);
  }
  sea->set_time(1e5);
  const houle::Domain& d = scene.domain;
  for (const double u : {-0.1, 0.3, 0.5, 0.9, 1.1}) {
    const float x = float(d.x_min + u * (d.x_max - d.x_min)), y = float(d.y_min + (1.0 - u) * (d.y_max - d.y_min));
    float ht = 0, gx = 0, gy = 0;
    sea->eval(&x, &y, 1, &ht, &gx, &gy);
    bool ok = finite(ht) && finite(gx) && finite(gy);
    for (std::size_t t = 0; t < scene.trains.size(); ++t) {
      const houle::TrainProbe p = sea->probe(t, x, y);
      for (const float v : {p.amplitude, p.relative_amplitude, p.diffraction, p.wavelength, p.direction_deg, p.phase,
                            p.incident, p.diffracted, p.reflected}) {
        ok = ok && finite(v);
      }
    }
    if (!ok) {
      std::fprintf(stderr, "probe at (%g, %g) is not finite\n", double(x), double(y));
      std::_Exit(not_finite);
    }
  }
  std::_Exit(ok);
}

void keep_scene(const Options& o, std::uint64_t seed, const houle::Scene& s) {
  if (o.keep.empty()) return;
  std::filesystem::create_directories(o.keep);
  const std::string name = "scene_" + std::to_string(seed);
  std::ofstream(o.keep + "/" + name + ".toml") << "# houle_scene_fuzz --seed " << seed << " --scenes 1\n"
                                               << houle::test::scene_toml(s, name + ".pgm");
  if (s.floor.height_map) {
    double black = 0.0, white = 0.0;
    std::ofstream(o.keep + "/" + name + ".pgm") << houle::test::height_map_pgm(*s.floor.height_map, black, white);
  }
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--seconds") o.seconds = std::stod(v);
    else if (k == "--seed") o.seed = std::stoull(v);
    else if (k == "--scenes") o.scenes = std::stoull(v);
    else if (k == "--keep") o.keep = v;
    else if (k == "--cpu-seconds") o.cpu_seconds = std::stod(v);
    else if (k == "--max-estimate") o.max_estimate = std::stod(v);
    else if (k == "--memory-mib") o.memory_mib = std::stol(v);
    else return false;
  }
  return argc % 2 == 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr, "usage: houle_scene_fuzz [--seconds S] [--seed N] [--scenes N] [--keep DIR] [--cpu-seconds S] "
                         "[--max-estimate S] [--memory-mib M]\n");
    return 2;
  }
  std::printf("bounds per scene: %.0f x the estimated CPU time + %.0f s, %ld MiB resident (draft build, a 48x27 frame, "
              "5 probes)\n", o.slack, o.cpu_seconds, o.memory_mib);
  std::fflush(stdout);
  const auto t0 = Clock::now();
  std::uint64_t made = 0, too_large = 0, valid = 0, failures = 0, skipped = 0, caps = 0;
  double worst_time_ratio = 0.0;
  long peak_kib = 0;
  std::map<std::string, std::pair<int, std::string>> invalid;  // by the section validate blamed, to tune the generator
  double slowest = 0.0;
  for (std::uint64_t i = 0; i < o.scenes; ++i) {
    if (std::chrono::duration<double>(Clock::now() - t0).count() >= o.seconds) break;
    const std::uint64_t seed = o.seed + i;
    const houle::Scene scene = houle::test::generate_scene(seed);
    ++made;
    // What no scene file can hold (1 MiB, scene_file.hpp) is not a scene `validate` sees.
    if (houle::test::scene_toml(scene, "map.pgm").size() > (std::size_t(1) << 20)) {
      ++too_large;
      continue;
    }
    const auto v = houle::validate(scene);
    if (!v) {
      auto& [n, example] = invalid[v.error().field.substr(0, v.error().field.find_first_of(".["))];
      if (n++ == 0) example = v.error().field + ": " + v.error().message;
      continue;
    }
    ++valid;
    // What the commands build from: the validated scene (sea states expanded into their trains).
    const houle::Scene& checked = v.value();
    const double estimate = estimated_seconds(checked);
    if (estimate > o.max_estimate) {
      ++skipped;
      continue;
    }
    const double bound = o.slack * estimate + o.cpu_seconds;
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
      // The CPU bound kills (SIGXCPU) a build that runs too long; the address-space bound, twice the
      // resident bound (threads' stacks and reserved pages count), makes a runaway allocation fail.
      const rlimit cpu{rlim_t(std::ceil(bound)), rlim_t(std::ceil(bound)) + 1};
      const rlimit as{rlim_t(o.memory_mib) << 21, rlim_t(o.memory_mib) << 21};
      setrlimit(RLIMIT_CPU, &cpu);
      setrlimit(RLIMIT_AS, &as);
      check_scene(checked);
    }
    int status = 0;
    rusage usage{};
    wait4(pid, &status, 0, &usage);
    const double cpu = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                       1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    peak_kib = std::max(peak_kib, usage.ru_maxrss);
    slowest = std::max(slowest, cpu);
    std::string why;
    worst_time_ratio = std::max(worst_time_ratio, cpu / std::max(estimate, 0.01));
    if (WIFEXITED(status) && WEXITSTATUS(status) == capped) ++caps;
    if (WIFSIGNALED(status)) why = std::string("killed by ") + strsignal(WTERMSIG(status));
    else if (WEXITSTATUS(status) != ok && WEXITSTATUS(status) != capped) {
      why = WEXITSTATUS(status) == refused ? "refused after validating" : "not finite";
    }
    else if (usage.ru_maxrss > o.memory_mib * 1024) why = "over the memory bound (" + std::to_string(usage.ru_maxrss >> 10) + " MiB)";
    if (why.empty()) continue;
    ++failures;
    std::printf("FAIL seed %llu: %s (%.1f s CPU, estimated %.1f s; %ld MiB)\n", (unsigned long long)seed, why.c_str(), cpu,
                estimate, usage.ru_maxrss >> 10);
    keep_scene(o, seed, scene);
  }
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("%llu scenes in %.1f s (%.1f per second; %llu over a scene file's 1 MiB), %llu valid (%.1f per second; %llu estimated over %.0f s, not run; "
              "%llu stopped at a cap as their dwt.on_cap asked), %llu failures; slowest %.2f s CPU (at worst %.1f x its "
              "estimate), peak %ld MiB resident\n",
              (unsigned long long)made, elapsed, double(made) / elapsed, (unsigned long long)too_large, (unsigned long long)valid,
              double(valid) / elapsed, (unsigned long long)skipped, o.max_estimate, (unsigned long long)caps, (unsigned long long)failures, slowest,
              worst_time_ratio, peak_kib >> 10);
  for (const auto& [section, e] : invalid) std::printf("invalid: %d blamed on %s, e.g. %s\n", e.first, section.c_str(), e.second.c_str());
  return failures == 0 ? 0 : 1;
}
