// The frame the renderer writes (linear, scene-referred RGB) and its encodings for output.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "houle/render/colour.hpp"

namespace houle {

/// Per-pixel channels beside the image (arbitrary output variables, for compositing), each asked
/// for separately: one not asked for is an empty vector and costs the renderer nothing.
struct FrameAovs {
  bool depth = false, normal = false, alpha = false, sea = false;
};

/// Interleaved linear RGB floats, row-major, top row first, and the AOVs asked for, in the same
/// pixel order. Sized once; rendering never reallocates.
struct Framebuffer {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< width * height * 3
  /// m along the camera's forward axis (not along the ray) to the first surface met (sea, object or
  /// floor), the nearest of the pixel's samples; +inf where a sample meets none. width * height
  std::vector<float> depth;
  /// The first surface's unit world-space normal turned to face the camera, averaged over the
  /// pixel's samples (0 for a sample that meets none). width * height * 3, interleaved x, y, z
  std::vector<float> normal;
  /// The share of the pixel's samples that meet something: 0 where the sky is seen; under water
  /// every sample counts (the water is opaque). width * height
  std::vector<float> alpha;
  /// The share of the pixel's samples whose primary ray meets the sea surface (from above or below). width * height
  std::vector<float> sea;

  Framebuffer() = default;
  Framebuffer(int w, int h, FrameAovs aovs = {})
      : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.0f),
        depth(aovs.depth ? std::size_t(w) * std::size_t(h) : 0, 0.0f),
        normal(aovs.normal ? std::size_t(w) * std::size_t(h) * 3 : 0, 0.0f),
        alpha(aovs.alpha ? std::size_t(w) * std::size_t(h) : 0, 0.0f),
        sea(aovs.sea ? std::size_t(w) * std::size_t(h) : 0, 0.0f) {}
};

/// Tightly packed output formats. 8-bit ones are display-referred sRGB (tone-mapped, encoded);
/// rgbf32 is the linear framebuffer itself (for EXR-like use and for tests).
enum class PixelFormat : std::uint8_t { rgb24, rgba8, bgra8, rgbf32 };
/// ffmpeg's -pix_fmt name: rgb24, rgba, bgra; rgbf32 (linear floats, native byte order).
std::string_view pixel_format_name(PixelFormat f) noexcept;
/// The names above, and rgba8, bgra8 for rgba, bgra.
std::optional<PixelFormat> parse_pixel_format(std::string_view name) noexcept;
std::size_t bytes_per_pixel(PixelFormat f) noexcept;

/// The display transform (docs/rendering.md 4.5): scene-referred linear radiance times the exposure,
/// then a filmic curve on the luminance (Narkowicz's fit of the ACES curve with its asymptote put at 1:
/// a slight toe, highlights that roll off towards 1 and never reach it), the colour scaled with it and,
/// where its largest channel passes 0.8, desaturated towards white at the same luminance so that
/// channel rolls off into 1 (1 - e^-(m - 0.8)/0.2 above the knee) instead of clipping. Hue is kept; a
/// bright glint is a white core in a coloured halo, not a flat blob. NaN, infinite and negative values
/// go to black.
struct ToneMap {
  float exposure = 1.0f;
};
/// Display-referred linear sRGB, each channel in [0, 1].
LinearRgb tone_map(LinearRgb linear, const ToneMap& tm) noexcept;
/// The curve alone, on a luminance (>= 0): f(x) = x (2.43 x + 0.03) / (x (2.43 x + 0.59) + 0.14), below 1.
float filmic_curve(float luminance) noexcept;

/// Linear [0, 1] to the sRGB code value 0..255, correctly rounded (a table lookup plus one
/// comparison; equal to rounding the exact sRGB curve, tested over every float in [0, 1]).
std::uint8_t srgb8_from_linear(float linear) noexcept;

/// Encodes `fb` into `out` (bytes_per_pixel(f) * width * height bytes), alpha = 255.
void encode_frame(const Framebuffer& fb, const ToneMap& tm, PixelFormat f, std::span<std::byte> out) noexcept;

}  // namespace houle
