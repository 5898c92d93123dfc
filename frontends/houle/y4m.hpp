// YUV4MPEG2 (y4m) streams: the frames as 8-bit BT.709 Y'CbCr in limited ("TV") range, behind a header
// that states the size, the frame rate, the chroma subsampling and the range, so that a reader
// (ffmpeg -i -, ffprobe, mpv, x264) needs no options. The Y'CbCr comes from the same tone-mapped
// sRGB codes as --raw rgb24 (docs/rendering.md 6).
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace houle::cli {

/// 4:4:4 keeps a chroma sample per pixel; 4:2:0 one per 2 x 2 pixels, their mean (centred, as JPEG and
/// ffmpeg's yuvj420p site it: C420jpeg).
enum class Y4mChroma : std::uint8_t { c444, c420 };
std::optional<Y4mChroma> parse_y4m_chroma(std::string_view name) noexcept;  ///< "444", "420"

/// The stream header line, e.g. "YUV4MPEG2 W640 H360 F30:1 Ip A1:1 C420jpeg XCOLORRANGE=LIMITED\n".
/// ffmpeg reads XCOLORRANGE, and no header line of 96 bytes or more ("Header too large"): the
/// longest houle writes (16384 x 16384 at F987654321:1000000) is 80. y4m has no key for the matrix
/// that ffmpeg reads: the stream is BT.709, which its users tag on the output (README).
std::string y4m_header(int width, int height, double fps, Y4mChroma chroma);

/// Bytes of one frame's planes (Y', then Cb, then Cr), without the "FRAME\n" line.
std::size_t y4m_frame_bytes(int width, int height, Y4mChroma chroma) noexcept;

/// One frame's planes from rgb24 codes (width x height x 3 bytes, top row first): Y' = 16 + 219 E'y,
/// Cb = 128 + 224 (E'b - E'y) / 1.8556, Cr = 128 + 224 (E'r - E'y) / 1.5748 with E'y = 0.2126 E'r +
/// 0.7152 E'g + 0.0722 E'b (BT.709) and E' = code / 255, rounded to nearest; for 4:2:0 the chroma of
/// a 2 x 2 block's pixels (those inside the image at an odd edge) is averaged before rounding.
void y4m_from_rgb24(std::span<const std::byte> rgb, int width, int height, Y4mChroma chroma, std::span<std::byte> out) noexcept;

}  // namespace houle::cli
