#include "height_map_image.hpp"

#if HOULE_WITH_OIIO
#include <OpenImageIO/imageio.h>
#endif

namespace houle::cli {

#if HOULE_WITH_OIIO
Expected<HeightMap> load_height_map(const std::string& path, const HeightMapImage& how) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return Error{path, "cannot open the height map image: " + OIIO::geterror()};
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 2 || spec.height < 2) return Error{path, "a height map needs at least 2x2 pixels"};
  if (std::size_t(spec.width) * std::size_t(spec.height) > max_height_map_pixels) {
    return Error{path, "height map of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                           " pixels is over the limit of 8192x8192"};
  }
  std::vector<float> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    return Error{path, "cannot read the height map image: " + in->geterror()};
  }
  HeightMap map;
  map.nx = std::uint32_t(spec.width);
  map.ny = std::uint32_t(spec.height);
  map.origin = how.origin;
  map.cell = how.cell;
  map.depth.resize(std::size_t(map.nx) * map.ny);
  // The first channel is the grey level; the image's first row is the north edge.
  for (std::uint32_t j = 0; j < map.ny; ++j) {
    for (std::uint32_t i = 0; i < map.nx; ++i) {
      const float v = pixels[(std::size_t(map.ny - 1 - j) * map.nx + i) * spec.nchannels];
      map.depth[std::size_t(j) * map.nx + i] = float(how.depth_at_black + (how.depth_at_white - how.depth_at_black) * v);
    }
  }
  return map;
}
#else
Expected<HeightMap> load_height_map(const std::string& path, const HeightMapImage&) {
  return Error{path, "this houle was built without OpenImageIO, so it cannot read height map images"};
}
#endif

}  // namespace houle::cli
