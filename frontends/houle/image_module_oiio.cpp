// The image module (image_module.hpp): OpenImageIO behind a C interface, built as houle_image_io.so.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <string>
#include <vector>

#include "image_module.hpp"

namespace {

int fail(const std::string& message, char* error, std::size_t error_size) {
  if (error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
  return 1;
}

int can_write(const char* name, char* error, std::size_t error_size) {
  if (OIIO::ImageOutput::create(name)) return 0;
  return fail(OIIO::geterror(), error, error_size);
}

int write_rgb(const char* path, const char* format_name, int width, int height, int storage, const void* pixels, char* error,
              std::size_t error_size) {
  const bool linear = storage != houle::cli::srgb8;
  OIIO::ImageSpec spec(width, height, 3,
                       storage == houle::cli::linear_half    ? OIIO::TypeDesc::HALF
                       : storage == houle::cli::linear_float ? OIIO::TypeDesc::FLOAT
                                                             : OIIO::TypeDesc::UINT8);
  // zlib level 1: PNG writing dominated frame time at the default 6 (docs/design.md 11: 45 vs 14 ms).
  spec.attribute("png:compressionLevel", 1);
  spec.attribute("oiio:ColorSpace", linear ? "Linear" : "sRGB");
  auto out = OIIO::ImageOutput::create(format_name);
  if (!out) return fail(OIIO::geterror(), error, error_size);
  bool ok = out->open(path, spec) && out->write_image(linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, pixels);
  ok = out->close() && ok;
  return ok ? 0 : fail(out->geterror(), error, error_size);
}

int read_first_channel(const char* path, void* context, float* (*allocate)(void*, int, int), char* error,
                       std::size_t error_size) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return fail("cannot open the image: " + OIIO::geterror(), error, error_size);
  const OIIO::ImageSpec& spec = in->spec();
  float* dst = allocate(context, spec.width, spec.height);
  if (!dst) return 2;
  std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    return fail("cannot read the image: " + in->geterror(), error, error_size);
  }
  for (std::size_t i = 0, n = std::size_t(spec.width) * std::size_t(spec.height); i < n; ++i) {
    dst[i] = pixels[i * std::size_t(spec.nchannels)];
  }
  return 0;
}

constexpr houle::cli::ImageModule module{can_write, write_rgb, read_first_channel};

}  // namespace

extern "C" __attribute__((visibility("default"))) const houle::cli::ImageModule* houle_image_module() {
  return &module;
}
