// Distances in units in the last place, for comparing SIMD paths with the scalar reference.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace houle::test {

/// Ordered integer image of a float: adjacent floats differ by 1, -0 == +0.
inline std::int64_t float_order(float x) {
  std::int32_t i;
  std::memcpy(&i, &x, sizeof i);
  return i < 0 ? std::int64_t(std::numeric_limits<std::int32_t>::min()) - i : i;
}

/// Number of representable floats between a and b; a huge value if either is NaN.
inline std::int64_t ulp_distance(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::int64_t>::max();
  const std::int64_t d = float_order(a) - float_order(b);
  return d < 0 ? -d : d;
}

/// |a - b| in units of the float spacing at `scale` (> 0), rounded up: 0 only when a == b. Used where
/// outputs come from cancellation, so that a value near zero is judged against its natural size.
inline std::int64_t ulps_of_scale(float a, float b, float scale) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::int64_t>::max();
  const double spacing = double(std::nextafter(scale, std::numeric_limits<float>::infinity())) - double(scale);
  return std::int64_t(std::ceil(std::fabs(double(a) - double(b)) / spacing));
}

}  // namespace houle::test
