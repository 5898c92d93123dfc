#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/sim/animation.hpp"
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

}  // namespace

int cmd_bench(std::span<char* const> argv) {
  Args args("bench", argv);
  if (args.flag("--help")) {
    std::puts(R"(usage: houle bench [SCENE] [--frames N] [--warmup N] [--size WxH] [--quality Q] [--threads N] [--json]

Renders N frames (default 100) of SCENE (the built-in coast without one) after N warm-up frames
(default 5), without writing them, and reports the frame time's median, p90, p99 and maximum, with
the per-stage split (surface retessellation, noise, march, intersect, shade), the scene build time and
the share of primary rays whose object and floor hit was kept from the frame before (a still camera).
--threads N: render threads (default: the machine's hardware threads).)");
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
  const std::optional<SceneRun> run = take_scene_run(args, "bench");
  if (!run) return 2;
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
  std::vector<double> total, surface, noise, march, intersect, shade;
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
    const RenderCounters& c = anim->renderer().last_counters();
    samples += c.sea + c.object + c.sky;
    reused += c.reused;
  }
  const std::pair<const char*, Distribution> rows[] = {
      {"frame", distribution(total)},   {"surface", distribution(surface)},     {"noise", distribution(noise)},
      {"march", distribution(march)},   {"intersect", distribution(intersect)}, {"shade", distribution(shade)}};
  const char* isa = isa_name(active_isa()).data();
  const double share = samples > 0 ? double(reused) / double(samples) : 0.0;
  if (json) {
    std::printf("{\"scene\": \"%s\", \"size\": [%d, %d], \"quality\": \"%s\", \"threads\": %u, \"isa\": \"%s\", \"frames\": %ld, "
                "\"build_ms\": %.3f, \"primary_reused\": %.4f, \"stages_ms\": {",
                run->name.c_str(), width, height,
                quality_name(quality).data(), threads, isa, frames, anim->build_ms(), share);
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
  }
  return 0;
}

}  // namespace houle::cli
