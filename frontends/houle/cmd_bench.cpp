#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/sim/animation.hpp"
#include "frame_writer.hpp"
#include "scene_source.hpp"

namespace houle::cli {
namespace {

struct Distribution {
  double median = 0, p90 = 0, p99 = 0, max = 0;
};
Distribution distribution(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))]; };
  return {at(0.5), at(0.9), at(0.99), v.back()};
}

// The CPU's name as /proc/cpuinfo gives it (x86's "model name"; ARM kernels give "Hardware" or "Model"
// at best), or "unknown".
std::string host_cpu() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  for (const char* key : {"model name", "Hardware", "Model"}) {
    in.clear();
    in.seekg(0);
    while (std::getline(in, line)) {
      const auto colon = line.find(':');
      if (line.rfind(key, 0) == 0 && colon != std::string::npos) {
        const auto start = line.find_first_not_of(" \t", colon + 1);
        if (start != std::string::npos) return line.substr(start);
      }
    }
  }
  return "unknown";
}

// Now, in UTC: "2026-12-05T11:40:00Z".
std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }
double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double sum = 0.0;
  for (const double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / double(v.size() - 1));
}

// Google Benchmark's JSON (what its tools/compare.py reads): per stage, one entry per frame as a
// repetition of one iteration (run_type "iteration"), then the mean, median and stddev aggregates, all
// in ms. houle times wall clock only: cpu_time repeats real_time.
std::string gbench_json(const std::string& context, const std::string& prefix,
                        std::span<const std::pair<const char*, const std::vector<double>*>> stages) {
  std::string out = "{\n  \"context\": " + context + ",\n  \"benchmarks\": [";
  char buf[512];
  bool first = true;
  for (std::size_t family = 0; family < stages.size(); ++family) {
    const std::vector<double>& v = *stages[family].second;
    const std::string name = json_string(prefix + stages[family].first);
    const auto entry = [&](const char* run_type, const std::string& entry_name, const char* aggregate, long index, double ms) {
      std::snprintf(buf, sizeof buf,
                    "%s\n    {\"name\": %s, \"family_index\": %zu, \"per_family_instance_index\": 0, \"run_name\": %s, "
                    "\"run_type\": \"%s\", \"repetitions\": %zu, \"repetition_index\": %ld, \"threads\": 1, "
                    "%s\"iterations\": 1, \"real_time\": %.6f, \"cpu_time\": %.6f, \"time_unit\": \"ms\"}",
                    first ? "" : ",", entry_name.c_str(), family, name.c_str(), run_type, v.size(), index, aggregate, ms, ms);
      out += buf;
      first = false;
    };
    for (std::size_t i = 0; i < v.size(); ++i) entry("iteration", name, "", long(i), v[i]);
    const double med = distribution(v).median, avg = mean(v), sd = stddev(v);
    for (const auto& [agg, value] : {std::pair{"mean", avg}, std::pair{"median", med}, std::pair{"stddev", sd}}) {
      const std::string agg_name = json_string(prefix + stages[family].first + "_" + agg);
      const std::string field = std::string("\"aggregate_name\": \"") + agg + "\", \"aggregate_unit\": \"time\", ";
      entry("aggregate", agg_name, field.c_str(), -1, value);
    }
  }
  return out + "\n  ]\n}\n";
}

}  // namespace

int cmd_bench(std::span<char* const> argv) {
  Args args("bench", argv);
  if (args.flag("--help")) {
    std::puts(R"(usage: houle bench [SCENE] [--frames N] [--warmup N] [--size WxH] [--quality Q] [--threads N]
                   [--json] [--gbench-json FILE]

Renders N frames (default 100) of SCENE (the built-in coast without one) after N warm-up frames
(default 5), without writing them, and reports the frame time's median, p90, p99 and maximum, with
the per-stage split (surface retessellation, noise, march, intersect, shade), the scene build time, the
share of primary rays whose object and floor hit was kept from the frame before (a still camera) and
how busy the render threads were (their mean busy time over the render's wall time: the rest is its
setup and the wait for the last row).
--threads N: render threads (default: the machine's hardware threads).

  --json              the report as JSON on standard output, schema 1 (README, "houle bench --json"):
                      {"schema": 1, "context": {houle_version, isa, threads, host_cpu, date, scene,
                      size, quality, frames, warmup}, "build_ms", "primary_reused", "render_busy",
                      "stages_ms": {STAGE: {median, p90, p99, max}}}
  --gbench-json FILE  also writes Google Benchmark's JSON format to FILE, for its tools/compare.py:
                      per stage (SCENE/WxH/QUALITY/STAGE) every frame as a repetition, then mean,
                      median and stddev, in ms (cpu_time = real_time: houle times wall clock))");
    return 0;
  }
  long frames = 100, warmup = 5;
  int width = 640, height = 360;
  if (auto v = args.value("--frames")) {
    const auto n = parse_int(*v);
    if (!n || *n < 1 || *n > 10'000'000) args.fail("--frames expects a count in 1..10000000, got '" + *v + "'");
    else frames = long(*n);
  }
  if (auto v = args.value("--warmup")) {
    const auto n = parse_int(*v);
    if (!n || *n < 0 || *n > 10000) args.fail("--warmup expects a count in 0..10000, got '" + *v + "'");
    else warmup = long(*n);
  }
  if (auto v = args.value("--size")) {
    const auto s = parse_size(*v);
    if (!s) args.fail(std::string("--size expects ") + size_expected + ", got '" + *v + "'");
    else width = s->first, height = s->second;
  }
  const bool json = args.flag("--json");
  const std::optional<std::string> gbench = args.value("--gbench-json");
  const std::optional<SceneRun> run = take_scene_run(args, "bench");
  if (!run) return 2;
  if (gbench) {  // checked before the scene is built (seconds, for a large one)
    if (Expected<void> ok = check_raw_output(*gbench); !ok) {
      std::fprintf(stderr, "houle bench: --gbench-json %s: %s\n", ok.error().field.c_str(), ok.error().message.c_str());
      return 2;
    }
  }
  const QualityPreset quality = run->quality;
  const unsigned threads = run->threads;
  Expected<Animation> anim = Animation::create(run->scene, quality_preset(quality), std::uint32_t(width),
                                               std::uint32_t(height), threads);
  if (!anim) {
    std::fprintf(stderr, "houle bench: %s: %s: %s\n", run->name.c_str(), anim.error().field.c_str(),
                 anim.error().message.c_str());
    return 2;
  }
  warn_if_truncated("bench", run->name, anim.value().waves());
  Framebuffer fb(width, height);
  std::vector<double> total, surface, noise, march, intersect, shade, busy;
  std::uint64_t samples = 0, reused = 0;
  for (long n = 0; n < warmup + frames; ++n) {
    const auto t0 = std::chrono::steady_clock::now();
    anim->render(double(n) / 30.0, fb);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (n < warmup) continue;
    const AnimationTimes& t = anim->last_times();
    total.push_back(ms);
    surface.push_back(t.surface_ms);
    noise.push_back(t.noise_ms);
    march.push_back(t.render.march_ms);
    intersect.push_back(t.render.intersect_ms);
    shade.push_back(t.render.shade_ms);
    // The stages are the render threads' mean busy times.
    busy.push_back(t.render.total_ms > 0.0 ? (t.render.march_ms + t.render.intersect_ms + t.render.shade_ms) / t.render.total_ms : 0.0);
    const RenderCounters& c = anim->renderer().last_counters();
    samples += c.sea + c.object + c.sky;
    reused += c.reused;
  }
  const std::pair<const char*, Distribution> rows[] = {
      {"frame", distribution(total)},   {"surface", distribution(surface)},     {"noise", distribution(noise)},
      {"march", distribution(march)},   {"intersect", distribution(intersect)}, {"shade", distribution(shade)}};
  const char* isa = isa_name(active_isa()).data();
  const double share = samples > 0 ? double(reused) / double(samples) : 0.0;
  const double render_busy = distribution(busy).median;
  // The context both JSON forms carry.
  char context[1024];
  std::snprintf(context, sizeof context,
                "{\"houle_version\": \"%s\", \"isa\": \"%s\", \"threads\": %u, \"host_cpu\": %s, \"date\": \"%s\", "
                "\"scene\": %s, \"size\": [%d, %d], \"quality\": \"%s\", \"frames\": %ld, \"warmup\": %ld}",
                HOULE_VERSION, isa, threads, json_string(host_cpu()).c_str(), utc_now().c_str(), json_string(run->name).c_str(),
                width, height, quality_name(quality).data(), frames, warmup);
  if (gbench) {
    const std::pair<const char*, const std::vector<double>*> stages[] = {
        {"frame", &total}, {"surface", &surface}, {"noise", &noise}, {"march", &march}, {"intersect", &intersect}, {"shade", &shade}};
    const std::string prefix = run->name + "/" + std::to_string(width) + "x" + std::to_string(height) + "/" +
                               std::string(quality_name(quality)) + "/";
    // Google Benchmark's context names beside houle's.
    const std::string gbench_context = std::string(context, std::strlen(context) - 1) +
                                       ", \"executable\": \"houle bench\", \"num_cpus\": " + std::to_string(default_threads()) + "}";
    const std::string text = gbench_json(gbench_context, prefix, stages);
    std::FILE* f = std::fopen(gbench->c_str(), "wb");
    const bool ok = f != nullptr && std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (f == nullptr || std::fclose(f) != 0 || !ok) {
      std::fprintf(stderr, "houle bench: --gbench-json %s: cannot write\n", gbench->c_str());
      return 1;
    }
  }
  if (json) {
    std::printf("{\"schema\": 1, \"context\": %s, \"build_ms\": %.3f, \"primary_reused\": %.4f, \"render_busy\": %.4f, "
                "\"stages_ms\": {",
                context, anim->build_ms(), share, render_busy);
    for (std::size_t i = 0; i < std::size(rows); ++i) {
      const Distribution& d = rows[i].second;
      std::printf("%s\"%s\": {\"median\": %.3f, \"p90\": %.3f, \"p99\": %.3f, \"max\": %.3f}", i ? ", " : "", rows[i].first,
                  d.median, d.p90, d.p99, d.max);
    }
    std::printf("}}\n");
  } else {
    std::printf("%s, %dx%d, %s, %u threads, ISA %s: %ld frames after %ld warm-up; scene build %.1f ms\n",
                run->name.c_str(), width, height,
                quality_name(quality).data(), threads, isa, frames, warmup, anim->build_ms());
    std::printf("%-10s %9s %9s %9s %9s   (ms)\n", "stage", "median", "p90", "p99", "max");
    for (const auto& [name, d] : rows) std::printf("%-10s %9.2f %9.2f %9.2f %9.2f\n", name, d.median, d.p90, d.p99, d.max);
    std::printf("primary object and floor hits kept from the frame before: %.1f %%\n", 100.0 * share);
    std::printf("render threads busy: %.1f %% of the render's wall time (median)\n", 100.0 * render_busy);
  }
  return 0;
}

}  // namespace houle::cli
