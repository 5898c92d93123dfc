// The options of `houle render`, parsed in one place: the render command reads them, and `houle farm`
// checks the options it hands to each array task with the same rules and messages.
#pragma once
#include <optional>
#include <string>

#include "cli.hpp"
#include "houle/render/framebuffer.hpp"
#include "houle/sim/animation.hpp"
#include "y4m.hpp"

namespace houle::cli {

struct RenderOptions {
  long first = 0, last = 47;
  double fps = 30.0;
  int width = 640, height = 360;
  QualityPreset quality = QualityPreset::realtime;
  unsigned threads = default_threads();
  std::string out = "frames/%04d.png";
  bool default_out = true;
  std::optional<std::string> raw;
  std::optional<std::string> y4m;        ///< a YUV4MPEG2 stream (y4m.hpp) to a file or "-"
  Y4mChroma y4m_chroma = Y4mChroma::c420;
  FrameAovs aovs;                        ///< EXR channels beside R, G, B (--aov)
  std::optional<PixelFormat> format;  ///< raw: default rgb24; images: only rgbf32 (32-bit float files)
  std::optional<float> exposure;  ///< none: the scene's (Renderer::display_exposure)
  bool skip_existing = false;
  bool realtime = false, quiet = false, verbose = false;
};

/// Takes every `houle render` option from `args` (positionals stay); a bad value or a bad
/// combination fails `args` with the message `houle render` prints.
RenderOptions take_render_options(Args& args);

/// "0:23" -> {0, 23}; "N" -> {0, N - 1}; nothing outside the limits --frames states.
std::optional<std::pair<long, long>> parse_frames(std::string_view text);
inline constexpr const char* frames_expected =
    "A:B (0 <= A <= B < 2^31, at most 10000000 frames) or a count N in 1..10000000";

}  // namespace houle::cli
