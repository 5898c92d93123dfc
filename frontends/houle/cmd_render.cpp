#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <unistd.h>

#include "cli.hpp"
#include "commands.hpp"
#include "frame_writer.hpp"
#include "houle/sim/animation.hpp"
#include "scene_source.hpp"

namespace houle::cli {
namespace {

constexpr const char* help = R"(usage: houle render [SCENE] [options]

Renders an animation of SCENE (the built-in coast without one) to an image sequence or raw frames.

options:
  --frames A:B | N        frames A to B inclusive, or the first N (default 0:47); frame n is at n / fps s;
                          at most 10000000 frames, numbered below 2^31
  --fps F                 frames per second of scene time (default 30)
  --size WxH              image size (default 640x360; each side at most 16384, at most 64 Mpixels)
  --quality Q             draft, realtime (default) or film
  --threads N             render threads (default 2)
  --out PATTERN           image sequence through OpenImageIO, one %d-style frame number in the name
                          (default frames/%04d.png); .png/.jpg/.tif are 8-bit sRGB, .exr linear half float
  --raw PATH|-            raw frames, tightly packed, top row first, to a file or standard output
  --pixel-format F        raw pixel format: rgb24 (default), rgba8, bgra8 (sRGB) or rgbf32 (linear)
  --exposure E            multiplies the linear image before tone mapping (default 1)
  --realtime              pace output to --fps (live preview pipelines)
  --quiet, --verbose      no progress line / per-frame stage times on stderr

raw frames into ffmpeg:
  houle render --frames 240 --raw - | ffmpeg -f rawvideo -pix_fmt rgb24 -s 640x360 -r 30 -i - out.mp4
Ctrl-C (or SIGTERM, SIGHUP) stops after the current frame; every frame written is complete.)";

// The signal that stopped the run (0: none). Terminal hang-ups and service managers stop a render
// the way Ctrl-C does, so that no frame is left half written.
std::atomic<int> interrupted{0};
extern "C" void on_stop_signal(int sig) { interrupted = sig; }

struct Options {
  long first = 0, last = 47;
  double fps = 30.0;
  int width = 640, height = 360;
  QualityPreset quality = QualityPreset::realtime;
  unsigned threads = 2;
  std::string out = "frames/%04d.png";
  bool default_out = true;
  std::optional<std::string> raw;
  PixelFormat format = PixelFormat::rgb24;
  float exposure = 1.0f;
  bool realtime = false, quiet = false, verbose = false;
};

// Frame numbers go into %d file names (int); a run is at most max_frames long.
constexpr long long max_frames = 10'000'000, max_frame_number = 2147483647;

bool parse_frames(const std::string& v, Options& o) {
  const auto colon = v.find(':');
  if (colon == std::string::npos) {
    const auto n = parse_int(v);
    if (!n || *n < 1 || *n > max_frames) return false;
    o.first = 0;
    o.last = long(*n) - 1;
    return true;
  }
  const auto a = parse_int(v.substr(0, colon)), b = parse_int(v.substr(colon + 1));
  if (!a || !b || *a < 0 || *b < *a || *b > max_frame_number || *b - *a >= max_frames) return false;
  o.first = long(*a);
  o.last = long(*b);
  return true;
}

}  // namespace

int cmd_render(std::span<char* const> argv) {
  Args args("render", argv);
  if (args.flag("--help")) {
    std::puts(help);
    return 0;
  }
  Options o;
  if (auto v = args.value("--frames"); v && !parse_frames(*v, o)) args.fail("--frames expects A:B (0 <= A <= B < 2^31, at most 10000000 frames) or a count N in 1..10000000, got '" + *v + "'");
  if (auto v = args.value("--fps")) {
    const auto f = parse_double(*v);
    if (!f || *f <= 0.0 || *f > 1000.0) args.fail("--fps expects a number in (0, 1000], got '" + *v + "'");
    else o.fps = *f;
  }
  if (auto v = args.value("--size")) {
    const auto s = parse_size(*v);
    if (!s) args.fail(std::string("--size expects ") + size_expected + ", got '" + *v + "'");
    else o.width = s->first, o.height = s->second;
  }
  take_quality(args, o.quality);
  take_threads(args, o.threads);
  if (auto v = args.value("--out")) o.out = *v, o.default_out = false;
  o.raw = args.value("--raw");
  if (auto v = args.value("--pixel-format")) {
    const auto f = parse_pixel_format(*v);
    if (!f) args.fail("--pixel-format expects rgb24, rgba8, bgra8 or rgbf32, got '" + *v + "'");
    else o.format = *f;
  }
  if (auto v = args.value("--exposure")) {
    const auto e = parse_double(*v);
    if (!e || *e <= 0.0) args.fail("--exposure expects a number > 0, got '" + *v + "'");
    else o.exposure = float(*e);
  }
  o.realtime = args.flag("--realtime");
  o.quiet = args.flag("--quiet");
  o.verbose = args.flag("--verbose");
  const std::vector<std::string> positionals = args.rest();
  if (!args.failed() && o.raw && !o.default_out) args.fail("--out and --raw exclude each other");
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  // The output is checked before the scene is built, and opened after: a refused scene leaves an
  // existing output untouched.
  if (const std::optional<Error> e = o.raw ? check_raw_output(*o.raw) : check_image_output(o.out, o.default_out)) {
    std::fprintf(stderr, "houle render: %s: %s\n", e->field.c_str(), e->message.c_str());
    return 2;
  }
  std::optional<Scene> scene = scene_from_args(positionals, "render");
  if (!scene) return 2;

  Expected<Animation> anim = Animation::create(*scene, quality_preset(o.quality), std::uint32_t(o.width),
                                               std::uint32_t(o.height), o.threads);
  if (!anim) {
    std::fprintf(stderr, "houle render: %s: %s: %s\n", scene_name(positionals).c_str(), anim.error().field.c_str(),
                 anim.error().message.c_str());
    return 2;
  }
  if (!o.raw && o.default_out) std::filesystem::create_directories("frames");
  Expected<std::unique_ptr<FrameWriter>> writer =
      o.raw ? make_raw_writer(*o.raw, o.format, o.width, o.height) : make_image_writer(o.out, o.width, o.height);
  if (!writer) {
    std::fprintf(stderr, "houle render: %s: %s\n", writer.error().field.c_str(), writer.error().message.c_str());
    return 2;
  }
  const bool progress = !o.quiet && ::isatty(2);
  if (o.verbose) std::fprintf(stderr, "houle render: scene built in %.1f ms\n", anim->build_ms());

  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_stop_signal);
  Framebuffer fb(o.width, o.height);
  const ToneMap tm{o.exposure};
  const auto start = std::chrono::steady_clock::now();
  const long total = o.last - o.first + 1;
  long done = 0;
  for (long n = o.first; n <= o.last && !interrupted; ++n, ++done) {
    anim->render(double(n) / o.fps, fb);
    if (o.realtime) std::this_thread::sleep_until(start + std::chrono::duration<double>(double(done + 1) / o.fps));
    const WriteStatus st = writer.value()->write(fb, tm, n);
    if (st == WriteStatus::failed) {
      std::fprintf(stderr, "%shoule render: %s\n", progress ? "\n" : "", writer.value()->error().c_str());
      return 1;
    }
    if (st == WriteStatus::closed) {
      if (!o.quiet) std::fprintf(stderr, "%shoule render: output closed by its reader after %ld frames\n", progress ? "\n" : "", done);
      return 0;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.verbose) {
      const AnimationTimes& t = anim->last_times();
      std::fprintf(stderr, "frame %ld: surface %.2f ms, noise %.2f ms, march %.2f ms, shade %.2f ms, render %.2f ms\n", n,
                   t.surface_ms, t.noise_ms, t.render.march_ms, t.render.shade_ms, t.render.total_ms);
    } else if (progress) {
      const double fps = double(done + 1) / elapsed;
      std::fprintf(stderr, "\rframe %ld (%ld/%ld)  %.1f fps  ETA %.0f s   ", n, done + 1, total, fps,
                   double(total - done - 1) / fps);
    }
  }
  if (progress) std::fputc('\n', stderr);
  if (interrupted) {
    std::fprintf(stderr, "houle render: interrupted after %ld complete frames\n", done);
    return 128 + interrupted;  // as the shell reports a process the signal ended
  }
  if (!o.quiet && !o.raw) {
    std::fprintf(stderr, "houle render: %ld frames written to %s\n", done, o.out.c_str());
  }
  return 0;
}

}  // namespace houle::cli
