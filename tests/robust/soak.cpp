// Soak: renders many frames of the built-in coast with a floating buoy at a small size and checks what a
// long unattended run needs: no heap allocation and no resident-memory growth after warm-up, and
// frames equal, byte for byte, to a fresh Animation's render of the same time. The frame time's
// drift (median of the last tenth over the first tenth) is reported, never asserted.
//   houle_soak [--frames N] [--size WxH] [--quality Q] [--threads N]
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "houle/sim/animation.hpp"

namespace {

constexpr long warmup = 30;
constexpr long checkpoints = 4;     // frames kept and compared with fresh renders
constexpr long rss_slack = 256 << 10;  // bytes: page-granular noise (a stack page touched deeper)

// Resident set size from /proc/self/statm, read without allocating (the loop counts allocations).
long resident_bytes() {
  char buf[128] = {};
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  const ssize_t n = ::read(fd, buf, sizeof buf - 1);
  ::close(fd);
  long size = 0, resident = 0;
  if (n <= 0 || std::sscanf(buf, "%ld %ld", &size, &resident) != 2) return -1;
  return resident * ::sysconf(_SC_PAGESIZE);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool same(const houle::Framebuffer& a, const houle::Framebuffer& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  long frames = 600;
  int width = 64, height = 36;
  unsigned threads = 2;
  houle::QualityPreset preset = houle::QualityPreset::draft;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--frames") frames = std::max(std::atol(value.c_str()), warmup + checkpoints);
    else if (key == "--size" && std::sscanf(value.c_str(), "%dx%d", &width, &height) == 2) {}
    else if (key == "--threads") threads = unsigned(std::max(1, std::atoi(value.c_str())));
    else if (key == "--quality" && houle::parse_quality(value)) preset = *houle::parse_quality(value);
    else {
      std::fprintf(stderr, "usage: houle_soak [--frames N] [--size WxH] [--quality draft|realtime|film] [--threads N]\n");
      return 2;
    }
  }
  // The built-in coast with a buoy floating in view: its pose is computed and the renderer's moving
  // objects placed every frame, without allocation.
  houle::Scene scene = houle::builtin_coast();
  houle::Sphere buoy;
  buoy.center = {128.0, 120.0, 0.0};
  buoy.radius = 0.8;
  buoy.colour = {0.85f, 0.12f, 0.05f};
  buoy.floats = true;
  scene.spheres.push_back(buoy);
  const houle::Quality quality = houle::quality_preset(preset);
  auto make = [&] {
    houle::Expected<houle::Animation> a = houle::Animation::create(scene, quality, std::uint32_t(width), std::uint32_t(height), threads);
    if (!a) {
      std::fprintf(stderr, "houle_soak: %s: %s\n", a.error().field.c_str(), a.error().message.c_str());
      std::exit(2);
    }
    return std::move(a.value());
  };
  // Everything the comparison needs exists before the measured run starts.
  houle::Animation anim = make();
  std::vector<houle::Animation> fresh;
  std::vector<houle::Framebuffer> kept(checkpoints, houle::Framebuffer(width, height));
  std::vector<long> kept_at(checkpoints);
  for (long c = 0; c < checkpoints; ++c) {
    fresh.push_back(make());
    kept_at[c] = frames - 1 - c * (frames - warmup) / checkpoints;
  }
  houle::Framebuffer fb(width, height);
  std::vector<double> ms;
  ms.reserve(std::size_t(frames));

  auto frame_time = [](long n) { return double(n) / 30.0; };
  for (long n = 0; n < warmup; ++n) anim.render(frame_time(n), fb);
  const long rss_start = resident_bytes();
  long rss_max = rss_start, allocations = 0;
  {
    houle::test::AllocationCounter counter;
    for (long n = warmup; n < frames; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      anim.render(frame_time(n), fb);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      for (long c = 0; c < checkpoints; ++c) {
        if (n == kept_at[c]) kept[c].rgb = fb.rgb;  // same size: a copy, no allocation
      }
      if (n % 64 == 0) rss_max = std::max(rss_max, resident_bytes());
    }
    allocations = counter.count();
  }
  const long rss_end = resident_bytes();
  rss_max = std::max(rss_max, rss_end);

  long mismatches = 0;
  for (long c = 0; c < checkpoints; ++c) {
    fresh[std::size_t(c)].render(frame_time(kept_at[c]), fb);
    if (!same(fb, kept[std::size_t(c)])) {
      ++mismatches;
      std::printf("houle_soak: frame %ld differs from a fresh render at the same time\n", kept_at[c]);
    }
  }
  const std::size_t tenth = std::max<std::size_t>(1, ms.size() / 10);
  const double first = median({ms.begin(), ms.begin() + long(tenth)});
  const double last = median({ms.end() - long(tenth), ms.end()});
  std::printf("houle_soak: %ld frames (%ld warm-up) %dx%d %s, %u threads\n", frames, warmup, width, height,
              std::string(houle::quality_name(preset)).c_str(), threads);
  std::printf("houle_soak: resident memory after warm-up %.2f MiB, at the end %.2f MiB, peak %.2f MiB (growth %ld bytes)\n",
              double(rss_start) / 1048576.0, double(rss_end) / 1048576.0, double(rss_max) / 1048576.0, rss_max - rss_start);
  std::printf("houle_soak: heap allocations after warm-up %ld\n", allocations);
  std::printf("houle_soak: frames %ld, %ld, %ld, %ld equal a fresh render: %s\n", kept_at[0], kept_at[1], kept_at[2],
              kept_at[3], mismatches ? "no" : "yes");
  std::printf("houle_soak: frame time median first tenth %.3f ms, last tenth %.3f ms (drift %+.1f %%, not asserted)\n",
              first, last, 100.0 * (last / first - 1.0));
  const bool ok = rss_start > 0 && allocations == 0 && rss_max - rss_start <= rss_slack && mismatches == 0;
  std::printf("houle_soak: %s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
