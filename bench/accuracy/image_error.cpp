#include "image_error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace houle::accuracy {
namespace {

/// Displayed values in [0, 1]: the tone map, then the sRGB curve, not rounded to 8 bits (rounding
/// would put a floor of ~1e-3 under every error: single code steps flipping).
std::vector<float> displayed(const Framebuffer& fb) {
  std::vector<float> d(fb.rgb.size());
  const ToneMap tm{};
  for (std::size_t i = 0; i < d.size(); i += 3) {
    const LinearRgb t = tone_map({fb.rgb[i], fb.rgb[i + 1], fb.rgb[i + 2]}, tm);
    for (std::size_t k = 0; k < 3; ++k) {
      const double c = k == 0 ? t.r : k == 1 ? t.g : t.b;
      d[i + k] = float(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
    }
  }
  return d;
}

/// Separable Gaussian blur (sigma 1.5, radius 5, clamped at the edges), as in Wang et al. 2004.
std::vector<double> blur(const std::vector<double>& v, int w, int h) {
  constexpr int radius = 5;
  std::array<double, 2 * radius + 1> k{};
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += k[std::size_t(i + radius)] = std::exp(-double(i * i) / (2.0 * 1.5 * 1.5));
  for (double& x : k) x /= sum;
  std::vector<double> tmp(v.size()), out(v.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -radius; i <= radius; ++i) s += k[std::size_t(i + radius)] * v[std::size_t(y * w + std::clamp(x + i, 0, w - 1))];
      tmp[std::size_t(y * w + x)] = s;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -radius; i <= radius; ++i) s += k[std::size_t(i + radius)] * tmp[std::size_t(std::clamp(y + i, 0, h - 1) * w + x)];
      out[std::size_t(y * w + x)] = s;
    }
  }
  return out;
}

}  // namespace

ImageError image_error(const Framebuffer& a, const Framebuffer& b) {
  const std::vector<float> da = displayed(a), db = displayed(b);
  double se = 0.0;
  for (std::size_t i = 0; i < da.size(); ++i) se += double(da[i] - db[i]) * double(da[i] - db[i]);
  ImageError e;
  e.rmse = std::sqrt(se / double(std::max<std::size_t>(da.size(), 1)));

  const int w = a.width, h = a.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  for (std::size_t p = 0; p < n; ++p) {
    x[p] = 0.2126 * da[3 * p] + 0.7152 * da[3 * p + 1] + 0.0722 * da[3 * p + 2];
    y[p] = 0.2126 * db[3 * p] + 0.7152 * db[3 * p + 1] + 0.0722 * db[3 * p + 2];
    xx[p] = x[p] * x[p];
    yy[p] = y[p] * y[p];
    xy[p] = x[p] * y[p];
  }
  const std::vector<double> mx = blur(x, w, h), my = blur(y, w, h), sxx = blur(xx, w, h), syy = blur(yy, w, h),
                            sxy = blur(xy, w, h);
  constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double ssim = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    const double vx = sxx[p] - mx[p] * mx[p], vy = syy[p] - my[p] * my[p], cxy = sxy[p] - mx[p] * my[p];
    ssim += ((2.0 * mx[p] * my[p] + c1) * (2.0 * cxy + c2)) /
            ((mx[p] * mx[p] + my[p] * my[p] + c1) * (vx + vy + c2));
  }
  e.dssim = std::max(0.0, 1.0 - ssim / double(std::max<std::size_t>(n, 1)));
  return e;
}

Framebuffer downsample(const Framebuffer& fb, int factor) {
  Framebuffer out(fb.width / factor, fb.height / factor);
  const float inv = 1.0f / float(factor * factor);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        float s = 0.0f;
        for (int j = 0; j < factor; ++j) {
          for (int i = 0; i < factor; ++i) s += fb.rgb[(std::size_t(y * factor + j) * std::size_t(fb.width) + std::size_t(x * factor + i)) * 3 + std::size_t(c)];
        }
        out.rgb[(std::size_t(y) * std::size_t(out.width) + std::size_t(x)) * 3 + std::size_t(c)] = s * inv;
      }
    }
  }
  return out;
}

}  // namespace houle::accuracy
