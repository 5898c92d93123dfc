#include "render_options.hpp"

#include <cctype>
#include <filesystem>

namespace houle::cli {
namespace {

// Frame numbers go into %d file names (int); a run is at most max_frames long.
constexpr long long max_frames = 10'000'000, max_frame_number = 2147483647;

// "z,normal,alpha,sea" (any of them, in any order) into `aovs`.
void take_aovs(Args& args, std::string_view list, FrameAovs& aovs) {
  while (true) {
    const auto comma = list.find(',');
    const std::string_view name = list.substr(0, comma);
    bool* flag = name == "z" ? &aovs.depth : name == "normal" ? &aovs.normal : name == "alpha" ? &aovs.alpha : name == "sea" ? &aovs.sea : nullptr;
    if (!flag) {
      args.fail("--aov expects a list of z, normal, alpha and sea (e.g. z,normal), got '" + std::string(name) + "'");
      return;
    }
    *flag = true;
    if (comma == std::string_view::npos) return;
    list.remove_prefix(comma + 1);
  }
}

bool is_exr(const std::string& pattern) {
  std::string ext = std::filesystem::path(pattern).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".exr";
}

}  // namespace

std::optional<std::pair<long, long>> parse_frames(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos) {
    const auto n = parse_int(text);
    if (!n || *n < 1 || *n > max_frames) return std::nullopt;
    return std::pair<long, long>{0, long(*n) - 1};
  }
  const auto a = parse_int(text.substr(0, colon)), b = parse_int(text.substr(colon + 1));
  if (!a || !b || *a < 0 || *b < *a || *b > max_frame_number || *b - *a >= max_frames) return std::nullopt;
  return std::pair<long, long>{long(*a), long(*b)};
}

RenderOptions take_render_options(Args& args) {
  RenderOptions o;
  if (auto v = args.value("--frames")) {
    const auto f = parse_frames(*v);
    if (!f) args.fail(std::string("--frames expects ") + frames_expected + ", got '" + *v + "'");
    else o.first = f->first, o.last = f->second;
  }
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
  o.y4m = args.value("--y4m");
  if (auto v = args.value("--y4m-chroma")) {
    const auto c = parse_y4m_chroma(*v);
    if (!c) args.fail("--y4m-chroma expects 444 or 420, got '" + *v + "'");
    else if (!o.y4m) args.fail("--y4m-chroma is for --y4m");
    else o.y4m_chroma = *c;
  }
  if (auto v = args.value("--aov")) take_aovs(args, *v, o.aovs);
  if (auto v = args.value("--pixel-format")) {
    const auto f = parse_pixel_format(*v);
    if (!f) args.fail("--pixel-format expects rgb24, rgba, bgra or rgbf32, got '" + *v + "'");
    else o.format = *f;
  }
  if (auto v = args.value("--exposure")) {
    const auto e = parse_double(*v);
    if (!e || *e <= 0.0) args.fail("--exposure expects a number > 0, got '" + *v + "'");
    else o.exposure = float(*e);
  }
  o.skip_existing = args.flag("--skip-existing");
  o.realtime = args.flag("--realtime");
  o.quiet = args.flag("--quiet");
  o.verbose = args.flag("--verbose");
  if (o.raw && !o.default_out) args.fail("--out and --raw exclude each other");
  if (o.y4m && (o.raw || !o.default_out)) args.fail(std::string("--y4m and ") + (o.raw ? "--raw" : "--out") + " exclude each other");
  if (o.y4m && o.format) args.fail("--pixel-format is for --raw: --y4m writes 8-bit Y'CbCr (see --y4m-chroma)");
  if ((o.aovs.depth || o.aovs.normal || o.aovs.alpha || o.aovs.sea) && (o.raw || o.y4m || !is_exr(o.out))) {
    args.fail("--aov needs EXR images (--out NAME%04d.exr): " +
              std::string(o.raw ? "--raw frames" : o.y4m ? "--y4m streams" : "'" + o.out + "'") + " have no place for extra channels");
  }
  if (!o.raw && o.format && *o.format != PixelFormat::rgbf32) {
    args.fail("--pixel-format " + std::string(pixel_format_name(*o.format)) +
              " is for --raw; images take their format from the --out extension (rgbf32 asks for 32-bit floats)");
  }
  if (o.y4m && *o.y4m == "-" && o.skip_existing) args.fail("--skip-existing needs a file: it cannot skip frames of standard output");
  if (o.raw && *o.raw == "-" && o.skip_existing) args.fail("--skip-existing needs a file: it cannot skip frames of standard output");
  return o;
}

}  // namespace houle::cli
