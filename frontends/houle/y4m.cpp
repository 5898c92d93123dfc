#include "y4m.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli.hpp"

namespace houle::cli {
namespace {

constexpr double kr = 0.2126, kb = 0.0722, kg = 1.0 - kr - kb;  // BT.709 luma weights

std::byte code(double v) { return std::byte(std::uint8_t(std::lround(std::fmin(std::fmax(v, 0.0), 255.0)))); }

}  // namespace

std::optional<Y4mChroma> parse_y4m_chroma(std::string_view name) noexcept {
  if (name == "444") return Y4mChroma::c444;
  if (name == "420") return Y4mChroma::c420;
  return std::nullopt;
}

std::string y4m_header(int width, int height, double fps, Y4mChroma chroma) {
  const auto [num, den] = frame_rate_ratio(fps);
  char buf[192];
  std::snprintf(buf, sizeof buf, "YUV4MPEG2 W%d H%d F%d:%d Ip A1:1 %s XCOLORRANGE=LIMITED\n", width, height, num, den,
                chroma == Y4mChroma::c444 ? "C444" : "C420jpeg");
  return buf;
}

std::size_t y4m_frame_bytes(int width, int height, Y4mChroma chroma) noexcept {
  const std::size_t luma = std::size_t(width) * std::size_t(height);
  if (chroma == Y4mChroma::c444) return 3 * luma;
  return luma + 2 * (std::size_t(width + 1) / 2) * (std::size_t(height + 1) / 2);
}

void y4m_from_rgb24(std::span<const std::byte> rgb, int width, int height, Y4mChroma chroma, std::span<std::byte> out) noexcept {
  const std::size_t w = std::size_t(width), h = std::size_t(height);
  // E'y, E'b - E'y and E'r - E'y of pixel (x, y), each in units of 1/255.
  const auto pixel = [&](std::size_t x, std::size_t y, double& ey, double& db, double& dr) {
    const std::byte* p = &rgb[3 * (y * w + x)];
    const double r = double(p[0]), g = double(p[1]), b = double(p[2]);
    ey = kr * r + kg * g + kb * b;
    db = b - ey;
    dr = r - ey;
  };
  constexpr double y_scale = 219.0 / 255.0, c_scale = 224.0 / 255.0, b_div = 2.0 * (1.0 - kb), r_div = 2.0 * (1.0 - kr);
  const bool sub = chroma == Y4mChroma::c420;
  const std::size_t cw = sub ? (w + 1) / 2 : w, ch = sub ? (h + 1) / 2 : h;
  std::byte* y_plane = out.data();
  std::byte* cb_plane = y_plane + w * h;
  std::byte* cr_plane = cb_plane + cw * ch;
  for (std::size_t y = 0; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) {
      double ey, db, dr;
      pixel(x, y, ey, db, dr);
      y_plane[y * w + x] = code(16.0 + y_scale * ey);
      if (!sub) {
        cb_plane[y * w + x] = code(128.0 + c_scale * db / b_div);
        cr_plane[y * w + x] = code(128.0 + c_scale * dr / r_div);
      }
    }
  }
  if (!sub) return;
  for (std::size_t cy = 0; cy < ch; ++cy) {
    for (std::size_t cx = 0; cx < cw; ++cx) {
      double sum_b = 0.0, sum_r = 0.0;
      int n = 0;
      for (std::size_t y = 2 * cy; y < std::min(2 * cy + 2, h); ++y) {
        for (std::size_t x = 2 * cx; x < std::min(2 * cx + 2, w); ++x) {
          double ey, db, dr;
          pixel(x, y, ey, db, dr);
          sum_b += db;
          sum_r += dr;
          ++n;
        }
      }
      cb_plane[cy * cw + cx] = code(128.0 + c_scale * sum_b / (n * b_div));
      cr_plane[cy * cw + cx] = code(128.0 + c_scale * sum_r / (n * r_div));
    }
  }
}

}  // namespace houle::cli
