#include "height_map_image.hpp"

#include <vector>

#if HOULE_WITH_OIIO
#include "image_module.hpp"
#include "input_file.hpp"
#endif

namespace houle::cli {

#if HOULE_WITH_OIIO
namespace {

// The module's read target: the first channel, refused beyond the size limits.
struct Pixels {
  int width = 0, height = 0;
  std::vector<float> grey;
  static float* allocate(void* context, int width, int height) {
    auto& p = *static_cast<Pixels*>(context);
    p.width = width;
    p.height = height;
    if (width < 2 || height < 2 || width > max_height_map_side || height > max_height_map_side) return nullptr;
    p.grey.resize(std::size_t(width) * std::size_t(height));
    return p.grey.data();
  }
};

}  // namespace

Expected<HeightMap> load_height_map(const std::string& path, const HeightMapFile& how) {
  const Expected<std::uintmax_t> size = regular_file_size(path);
  if (!size) return Error{path, "height map: cannot open the image: " + size.error().message};
  if (size.value() > max_height_map_bytes) {
    return Error{path, "height map file of " + std::to_string(size.value()) + " bytes is over the limit of " +
                           std::to_string(max_height_map_bytes)};
  }
  Expected<const ImageModule*> module = image_module();
  if (!module) return module.error();
  Pixels pixels;
  char message[512] = "";
  const int status = module.value()->read_first_channel(path.c_str(), &pixels, &Pixels::allocate, message, sizeof message);
  if (status == 2 && (pixels.width < 2 || pixels.height < 2)) return Error{path, "a height map needs at least 2x2 pixels"};
  if (status == 2) {
    return Error{path, "height map of " + std::to_string(pixels.width) + "x" + std::to_string(pixels.height) +
                           " pixels is over the limit of " + std::to_string(max_height_map_side) + "x" +
                           std::to_string(max_height_map_side)};
  }
  if (status != 0) return Error{path, std::string("height map: ") + message};
  HeightMap map;
  map.nx = std::uint32_t(pixels.width);
  map.ny = std::uint32_t(pixels.height);
  map.origin = how.origin;
  map.cell = how.cell;
  map.mode = how.mode;
  map.depth.resize(std::size_t(map.nx) * map.ny);
  // The grey level; the image's first row is the north edge.
  for (std::uint32_t j = 0; j < map.ny; ++j) {
    for (std::uint32_t i = 0; i < map.nx; ++i) {
      const float v = pixels.grey[std::size_t(map.ny - 1 - j) * map.nx + i];
      map.depth[std::size_t(j) * map.nx + i] = float(how.depth_at_black + (how.depth_at_white - how.depth_at_black) * v);
    }
  }
  return map;
}
#else
Expected<HeightMap> load_height_map(const std::string& path, const HeightMapFile&) {
  return Error{path, "this houle was built without OpenImageIO, so it cannot read height map images"};
}
#endif

}  // namespace houle::cli
