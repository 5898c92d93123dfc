// Sea-floor height maps from image files (any format OpenImageIO reads; 8- or 16-bit grey is usual).
#pragma once
#include <string>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"

namespace houle::cli {

/// How grey levels become depths: linear from black (0) to white (1). The image's top row is the
/// north edge (largest y); pixel centres are `cell` metres apart, the bottom-left one at `origin`.
struct HeightMapImage {
  Point2 origin{};
  double cell = 1.0;
  double depth_at_black = 20.0;  ///< m
  double depth_at_white = -2.0;  ///< m (negative: land)
};

/// Images larger than this many pixels are refused up front.
inline constexpr std::size_t max_height_map_pixels = std::size_t(8192) * 8192;

Expected<HeightMap> load_height_map(const std::string& path, const HeightMapImage& how);

}  // namespace houle::cli
