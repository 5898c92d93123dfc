#include "houle/render/framebuffer.hpp"

#include <algorithm>
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

float filmic_curve(float x) noexcept {
  if (!(x > 0.0f)) return 0.0f;  // NaN too
  if (!(x < 1e6f)) return 1.0f;  // +inf; the curve is 1 to float precision long before
  const float f = x * (2.43f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
  return f < 1.0f ? f : 1.0f;
}

LinearRgb tone_map(LinearRgb c, const ToneMap& tm) noexcept {
  const auto clean = [&](float v) { return v > 0.0f && v < 3e38f ? v * tm.exposure : 0.0f; };  // NaN, inf, < 0: 0
  c = {clean(c.r), clean(c.g), clean(c.b)};
  const float y = luminance(c);
  if (!(y > 0.0f) || !(y < 3e38f)) return {0.0f, 0.0f, 0.0f};
  const float y_out = filmic_curve(y), k = y_out / y;
  c = {c.r * k, c.g * k, c.b * k};
  // The largest channel rolls off above a knee (the shape of the old per-channel shoulder), the colour
  // mixed with the grey of the same luminance to follow it: saturated highlights go towards white
  // instead of flattening one channel at 1.
  constexpr float knee = 0.8f, room = 1.0f - knee;
  const float m = std::max(c.r, std::max(c.g, c.b));
  if (m > knee && m > y_out) {
    const float target = knee + room * (1.0f - std::exp(-(m - knee) / room));
    const float keep = std::max(target - y_out, 0.0f) / (m - y_out);
    c = {y_out + (c.r - y_out) * keep, y_out + (c.g - y_out) * keep, y_out + (c.b - y_out) * keep};
  }
  const auto unit = [](float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); };
  return {unit(c.r), unit(c.g), unit(c.b)};
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
    const LinearRgb d = tone_map({p[0], p[1], p[2]}, tm);
    const std::uint8_t r = srgb8_from_linear(d.r), g = srgb8_from_linear(d.g), b = srgb8_from_linear(d.b);
    o[0] = bgr ? b : r;
    o[1] = g;
    o[2] = bgr ? r : b;
    if (bpp == 4) o[3] = 255;
  }
}

}  // namespace houle
