#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "cli.hpp"
#include "commands.hpp"
#include "frame_files.hpp"
#include "frame_writer.hpp"
#include "houle/sim/animation.hpp"
#include "houle/sim/build_cost.hpp"
#include "render_options.hpp"
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
  --threads N             render threads (default: the machine's hardware threads); frames are the
                          same for any count
  --out PATTERN           image sequence through OpenImageIO, one %d-style frame number in the name
                          (default frames/%04d.png; its folder is made): .png/.jpg/.tif are 8-bit sRGB,
                          .exr linear half float, .hdr linear float (extensions in any case);
                          EXR headers hold the camera (worldToCamera, worldToNDC), framesPerSecond,
                          Software, houle:frame and houle:time (s); no date: a frame's file is the
                          same bytes on every render
  --aov LIST              EXR only: channels beside R, G, B from z, normal, alpha, sea: Z (32-bit, m
                          along the view axis to the first surface, inf for none), N.X N.Y N.Z (its
                          world-space normal, facing the camera), A (share of the pixel's samples that
                          meet something: 0 for sky), sea (share that meet the sea surface)
  --raw PATH|-            raw frames, tightly packed, top row first, to a file or standard output
  --y4m PATH|-            a YUV4MPEG2 stream (for ffmpeg -i -, ffprobe, mpv, x264: the header gives the
                          size and rate): BT.709 Y'CbCr in limited range (XCOLORRANGE=LIMITED) from
                          the tone-mapped sRGB frames
  --y4m-chroma 420|444    chroma subsampling of --y4m: 420 (default; one chroma sample per 2x2 pixels,
                          centred) or 444
  --pixel-format F        raw pixel format, ffmpeg's names: rgb24 (default), rgba, bgra (sRGB; rgba8 and
                          bgra8 too) or rgbf32 (linear floats); with --out only rgbf32, for linear
                          32-bit float images (.tif/.tiff as float TIFF, .exr in full float)
  --exposure E            multiplies the linear image before tone mapping (default: the scene's,
                          fixed from its sun and sky); EXR and HDR files and rgbf32 stay linear
  --skip-existing         restart a stopped run: render only the frames whose --out file is missing,
                          or nothing if the --raw file exists (which is then written whole, under a
                          temporary name until its last frame); temporary files that a killed run
                          left (NAME.tmpPID) are removed. One run per frame range at a time
  --realtime              pace output to --fps (live preview pipelines); frames late for their time
                          are counted, the first warned of, the count given at the end
  --quiet, --verbose      no progress and summary lines / per-frame stage times on stderr

Progress goes to stderr: one updated line on a terminal, else a line a second; a last line gives
the frames, the elapsed time and the mean frame rate.

into ffmpeg, as raw frames or as a y4m stream that says its own size and rate:
  houle render --frames 240 --raw - | ffmpeg -f rawvideo -pix_fmt rgb24 -s 640x360 -r 30 -i - -pix_fmt yuv420p out.mp4
  houle render --frames 240 --y4m - | ffmpeg -i - -colorspace bt709 -color_primaries bt709 -color_trc bt709 out.mp4
Ctrl-C, SIGTERM (a Slurm job cancelled or out of time) or SIGHUP stops after the current frame; every
frame written is complete. houle farm spreads a frame range over many machines.)";

// The signal that stopped the run (0: none). Terminal hang-ups and service managers stop a render
// the way Ctrl-C does, so that no frame is left half written.
std::atomic<int> interrupted{0};
extern "C" void on_stop_signal(int sig) { interrupted = sig; }

// "1:02:03" (h:mm:ss), with tenths of a second if asked.
std::string clock_text(double seconds, bool tenths) {
  const double s = std::max(seconds, 0.0);
  const long whole = tenths ? long(s) : std::lround(s);
  char buf[48];
  if (tenths) std::snprintf(buf, sizeof buf, "%ld:%02ld:%04.1f", whole / 3600, whole / 60 % 60, s - double(whole / 60 * 60));
  else std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", whole / 3600, whole / 60 % 60, whole % 60);
  return buf;
}

}  // namespace

int cmd_render(std::span<char* const> argv) {
  Args args("render", argv);
  if (args.flag("--help")) {
    std::puts(help);
    return 0;
  }
  const RenderOptions o = take_render_options(args);
  const std::vector<std::string> positionals = args.rest();
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  const std::optional<std::string> stream = o.raw ? o.raw : o.y4m;  // frames into one file or a pipe
  if (stream && *stream == "-" && ::isatty(1)) {
    std::fprintf(stderr, "houle render: standard output is a terminal: pipe the frames into a program (e.g. ffmpeg) "
                         "or give a file\n");
    return 2;
  }
  // The output is checked before the scene is built, and opened after: a refused scene leaves an
  // existing output untouched.
  if (Expected<void> ok = stream ? check_raw_output(*stream) : check_image_output(o.out, o.format == PixelFormat::rgbf32); !ok) {
    std::fprintf(stderr, "houle render: %s: %s\n", ok.error().field.c_str(), ok.error().message.c_str());
    return 2;
  }
  // What is left to do: every frame, or with --skip-existing those not yet on disk.
  FrameRuns todo{{o.first, o.last}};
  if (o.skip_existing) {
    std::vector<std::string> stale;
    if (stream) {
      if (std::filesystem::exists(*stream)) todo.clear();
      stale = temp_files_of(*stream);
    } else if (Expected<std::string> name = format_frame_name(o.out, o.first); !name) {
      std::fprintf(stderr, "houle render: %s: %s\n", name.error().field.c_str(), name.error().message.c_str());
      return 2;
    } else {
      SequenceOnDisk on_disk = scan_sequence(o.out, o.first, o.last);
      todo = std::move(on_disk.missing);
      stale = std::move(on_disk.temp_files);
    }
    std::error_code ec;
    for (const std::string& f : stale) std::filesystem::remove(f, ec);
    if (!stale.empty() && !o.quiet) {
      std::fprintf(stderr, "houle render: removed %zu temporary file%s that a stopped run left\n", stale.size(),
                   stale.size() == 1 ? "" : "s");
    }
    if (todo.empty()) {
      // Before the scene is built: a resubmitted farm task with nothing to do ends at once.
      if (!o.quiet) std::fprintf(stderr, "houle render: frames %ld:%ld already complete in %s\n", o.first, o.last,
                                 (stream ? *stream : o.out).c_str());
      return 0;
    }
  }
  std::optional<Scene> scene = scene_from_args(positionals, "render");
  if (!scene) return 2;

  if (o.verbose) {
    const BuildCost cost = estimate_build_cost(*scene, quality_preset(o.quality), std::uint64_t(o.width) * o.height, o.threads);
    const auto mib = [](std::uint64_t b) { return double(b) / 1048576.0; };
    std::fprintf(stderr,
                 "houle render: estimated build: %.0f MiB at the peak (rays %.0f, sea grids %.0f, floor %.0f, image %.0f, "
                 "program %.0f), %.1f s of CPU (tracing %.1f, sea grids %.1f, floor and walls %.1f), %llu samples\n",
                 mib(cost.bytes()), mib(cost.rays), mib(cost.sea), mib(cost.floor), mib(cost.image), mib(cost.program),
                 cost.seconds(), cost.trace_s, cost.sea_s, cost.floor_s, (unsigned long long)cost.samples);
  }
  Expected<Animation> anim = Animation::create(*scene, quality_preset(o.quality), std::uint32_t(o.width),
                                               std::uint32_t(o.height), o.threads);
  if (!anim) {
    std::fprintf(stderr, "houle render: %s: %s: %s\n", scene_name(positionals).c_str(), anim.error().field.c_str(),
                 anim.error().message.c_str());
    return 2;
  }
  warn_if_truncated("render", scene_name(positionals), anim.value().waves());
  Expected<std::unique_ptr<FrameWriter>> writer =
      o.raw   ? make_raw_writer(*o.raw, o.format.value_or(PixelFormat::rgb24), o.width, o.height, o.skip_existing)
      : o.y4m ? make_y4m_writer(*o.y4m, o.width, o.height, o.fps, o.y4m_chroma, o.skip_existing)
              : make_image_writer(o.out, o.width, o.height, o.format == PixelFormat::rgbf32, {o.fps, anim->camera(), o.aovs});
  if (!writer) {
    std::fprintf(stderr, "houle render: %s: %s\n", writer.error().field.c_str(), writer.error().message.c_str());
    return 2;
  }
  const bool progress = !o.quiet, live = progress && ::isatty(2);  // live: one line redrawn with \r
  if (o.verbose) {
    const BuildCost& c = anim->build_cost();
    std::fprintf(stderr, "houle render: estimated once traced: %.0f MiB at the peak, %.1f s of CPU after the trace, %llu samples\n",
                 double(c.bytes()) / 1048576.0, c.seconds(), (unsigned long long)c.samples);
    std::fprintf(stderr, "houle render: scene built in %.1f ms, exposure %.4g%s\n", anim->build_ms(),
                 o.exposure.value_or(anim->renderer().display_exposure()), o.exposure ? " (--exposure)" : " (the scene's)");
  }

  // From here on a stop ends the run after a complete frame (and a --raw file written whole is removed).
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_stop_signal);
  Framebuffer fb(o.width, o.height, o.aovs);
  const ToneMap tm{o.exposure.value_or(anim->renderer().display_exposure())};
  const auto start = std::chrono::steady_clock::now();
  const long total = count_frames(todo), skipped = o.last - o.first + 1 - total;
  long done = 0, late = 0;  // late: --realtime frames written after their time
  double last_line = 0.0;
  // " in 0:00:01.3 (3.1 fps)": the run so far.
  const auto summary = [&] {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char buf[96];
    std::snprintf(buf, sizeof buf, " in %s (%.1f fps)", clock_text(elapsed, true).c_str(),
                  elapsed > 0.0 ? double(done) / elapsed : 0.0);
    return std::string(buf);
  };
  for (const auto& [run_first, run_last] : todo) {
    for (long n = run_first; n <= run_last && !interrupted; ++n, ++done) {
      anim->render(double(n) / o.fps, fb);
      if (o.realtime) {
        const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(double(done + 1) / o.fps));
        if (std::chrono::steady_clock::now() > due) {
          if (late++ == 0 && !o.quiet) {
            std::fprintf(stderr, "%shoule render: warning: --realtime: frame %ld is late (rendering is slower than %g fps)\n",
                         live ? "\n" : "", n, o.fps);
          }
        } else {
          std::this_thread::sleep_until(due);
        }
      }
      const WriteStatus st = writer.value()->write(fb, tm, n);
      if (st == WriteStatus::failed) {
        std::fprintf(stderr, "%shoule render: %s\n", live ? "\n" : "", writer.value()->error().c_str());
        return 1;
      }
      if (st == WriteStatus::closed) {
        if (!o.quiet) {
          std::fprintf(stderr, "%shoule render: output closed by its reader after %ld frames%s\n", live ? "\n" : "", done,
                       summary().c_str());
        }
        return 0;
      }
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (o.verbose) {
        const AnimationTimes& t = anim->last_times();
        std::fprintf(stderr, "frame %ld: surface %.2f ms, noise %.2f ms, march %.2f ms, shade %.2f ms, render %.2f ms\n", n,
                     t.surface_ms, t.noise_ms, t.render.march_ms, t.render.shade_ms, t.render.total_ms);
      } else if (live || (progress && (done == 0 || elapsed - last_line >= 1.0))) {
        // A log (not a terminal) gets a line a second, not one per frame.
        last_line = elapsed;
        const double fps = double(done + 1) / elapsed;
        std::fprintf(stderr, "%sframe %ld (%ld/%ld)  %.1f fps  ETA %s%s", live ? "\r" : "", n, done + 1, total, fps,
                     clock_text(double(total - done - 1) / fps, false).c_str(), live ? "   " : "\n");
      }
    }
  }
  if (live) std::fputc('\n', stderr);
  if (interrupted) {
    std::fprintf(stderr, "houle render: interrupted after %ld complete frames%s%s\n", done, summary().c_str(),
                 stream && o.skip_existing ? " (not kept: with --skip-existing a --raw file is written whole)" : "");
    return 128 + interrupted;  // as the shell reports a process the signal ended
  }
  if (writer.value()->finish() == WriteStatus::failed) {
    std::fprintf(stderr, "houle render: %s\n", writer.value()->error().c_str());
    return 1;
  }
  if (!o.quiet) {
    const std::string to = !stream ? o.out : *stream == "-" ? "standard output" : *stream;
    std::fprintf(stderr, "houle render: %ld frames written to %s%s", done, to.c_str(), summary().c_str());
    if (skipped > 0) std::fprintf(stderr, " (%ld already complete, skipped)", skipped);
    if (late > 0) std::fprintf(stderr, " (%ld late for --realtime)", late);
    std::fputc('\n', stderr);
  }
  return 0;
}

}  // namespace houle::cli
