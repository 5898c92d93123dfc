// Sea-floor height maps from image files (any format OpenImageIO reads; 8- or 16-bit grey is usual).
#pragma once
#include <cstdint>
#include <string>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene_keys.hpp"  // HeightMapFile: how grey levels become depths

namespace houle::cli {

/// Images wider or taller than this many pixels are refused up front.
inline constexpr int max_height_map_side = 8192;
/// Files larger than this are refused before reading: 8192x8192 RGBA floats fit.
inline constexpr std::uintmax_t max_height_map_bytes = std::uintmax_t(1) << 31;

/// The image at `path` (how.file resolved against the scene file's directory) as a height map.
Expected<HeightMap> load_height_map(const std::string& path, const HeightMapFile& how);

}  // namespace houle::cli
