// How far a rendered frame is from a reference, as a viewer sees it: both go through the default
// display transform (tone map, sRGB curve) before they are compared.
#pragma once
#include "houle/render/framebuffer.hpp"

namespace houle::accuracy {

struct ImageError {
  double rmse = 0.0;   ///< root mean square over pixels and channels of the displayed values in [0, 1]
  double dssim = 0.0;  ///< 1 - SSIM of the displayed luma (Gaussian window, sigma 1.5 px; 0 = identical)
};

/// `a` and `b` must have the same size.
ImageError image_error(const Framebuffer& a, const Framebuffer& b);

/// Box filter by an integer factor (linear values averaged): a reference rendered at factor x the
/// size becomes a supersampled reference at the size compared.
Framebuffer downsample(const Framebuffer& fb, int factor);

}  // namespace houle::accuracy
