#include "houle/render/framebuffer.hpp"

#include <array>
#include <cmath>
#include <cstring>

#include "houle/runtime/assert.hpp"

namespace houle {
namespace {

// ffmpeg's -pix_fmt names, so a pipe's two ends say the same; houle's earlier rgba8 and bgra8 stay
// accepted.
constexpr std::array<std::string_view, 4> format_names = {"rgb24", "rgba", "bgra", "rgbf32"};
constexpr std::array<std::string_view, 4> format_aliases = {"rgb24", "rgba8", "bgra8", "rgbf32"};
constexpr std::array<std::size_t, 4> format_bytes = {3, 4, 4, 12};

double encode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055; }
double decode(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }

// code k is right for linear values in [threshold[k-1], threshold[k]); the table gives, for each of
// 4096 uniform slots, the code at the slot's start, so at most one boundary lies inside a slot
// after the first few (their spacing exceeds the slot width above code ~10; below, slots hold
// several boundaries, hence the small loop).
struct Srgb8Table {
  std::array<float, 256> threshold{};  // linear value where code k+1 starts; last = +inf
  std::array<std::uint8_t, 4097> start{};
  Srgb8Table() {
    for (int k = 0; k < 255; ++k) {
      // The smallest float whose exact encoding rounds to k + 1; the decoded guess may be an ulp off.
      float t = float(decode((k + 0.5) / 255.0));
      while (encode(t) * 255.0 >= k + 0.5) t = std::nextafter(t, 0.0f);
      while (encode(t) * 255.0 < k + 0.5) t = std::nextafter(t, 2.0f);
      threshold[k] = t;
    }
    threshold[255] = INFINITY;
    int code = 0;
    for (int i = 0; i <= 4096; ++i) {
      const float v = float(i) / 4096.0f;
      while (v >= threshold[code]) ++code;
      start[i] = std::uint8_t(code);
    }
  }
};
const Srgb8Table& srgb8_table() {
  static const Srgb8Table t;
  return t;
}

}  // namespace

std::string_view pixel_format_name(PixelFormat f) noexcept {
  HOULE_ASSERT(std::size_t(f) < format_names.size(), "pixel_format_name: one of the PixelFormat values");
  return format_names[std::size_t(f)];
}

std::optional<PixelFormat> parse_pixel_format(std::string_view name) noexcept {
  for (std::size_t i = 0; i < format_names.size(); ++i) {
    if (format_names[i] == name || format_aliases[i] == name) return PixelFormat(i);
  }
  return std::nullopt;
}

std::size_t bytes_per_pixel(PixelFormat f) noexcept {
  HOULE_ASSERT(std::size_t(f) < format_bytes.size(), "bytes_per_pixel: one of the PixelFormat values");
  return format_bytes[std::size_t(f)];
}

float tone_map(float linear, const ToneMap& tm) noexcept {
  const float x = linear * tm.exposure;
  constexpr float knee = 0.8f, room = 1.0f - knee;
  if (!(x > knee)) return x > 0.0f ? x : 0.0f;  // NaN and negatives go to black
  return knee + room * (1.0f - std::exp(-(x - knee) / room));
}

std::uint8_t srgb8_from_linear(float v) noexcept {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  const Srgb8Table& t = srgb8_table();
  int code = t.start[int(v * 4096.0f)];
  while (v >= t.threshold[code]) ++code;
  return std::uint8_t(code);
}

void encode_frame(const Framebuffer& fb, const ToneMap& tm, PixelFormat f, std::span<std::byte> out) noexcept {
  const std::size_t n = std::size_t(fb.width) * std::size_t(fb.height);
  HOULE_ASSERT(fb.width >= 0 && fb.height >= 0 && fb.rgb.size() == 3 * n, "encode_frame: width * height * 3 floats in fb.rgb");
  HOULE_ASSERT(out.size() == bytes_per_pixel(f) * n, "encode_frame: bytes_per_pixel(f) * width * height bytes in out");
  if (f == PixelFormat::rgbf32) {
    std::memcpy(out.data(), fb.rgb.data(), n * 12);
    return;
  }
  const std::size_t bpp = bytes_per_pixel(f);
  const bool bgr = f == PixelFormat::bgra8;
  auto* o = reinterpret_cast<std::uint8_t*>(out.data());
  for (std::size_t i = 0; i < n; ++i, o += bpp) {
    const float* p = &fb.rgb[3 * i];
    const std::uint8_t r = srgb8_from_linear(tone_map(p[0], tm)), g = srgb8_from_linear(tone_map(p[1], tm)),
                       b = srgb8_from_linear(tone_map(p[2], tm));
    o[0] = bgr ? b : r;
    o[1] = g;
    o[2] = bgr ? r : b;
    if (bpp == 4) o[3] = 255;
  }
}

}  // namespace houle
