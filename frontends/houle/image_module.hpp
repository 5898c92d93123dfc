// Image files go through OpenImageIO in a module, houle_image_io.so, loaded on first use. Linked
// into the command, OpenImageIO and the ~260 shared libraries it pulls in took 0.33 s to load and
// relocate at every start (0.6 s under AddressSanitizer), and most runs (raw frames into a pipe,
// info, probe, validate, bench) never read or write an image.
#pragma once
#include <cstddef>

#include "houle/runtime/expected.hpp"

namespace houle::cli {

/// How write_rgb stores pixels (an int across the module's C interface).
enum ImageStorage : int { srgb8 = 0, linear_half = 1, linear_float = 2 };

/// The module's C interface (image_module_oiio.cpp). Each function returns 0 on success; otherwise
/// it writes a NUL-terminated message of at most error_size bytes to `error` and returns non-zero.
struct ImageModule {
  /// Whether OpenImageIO has a writer for files named like `name` (it goes by the extension).
  int (*can_write)(const char* name, char* error, std::size_t error_size);
  /// Writes a width x height RGB image to `path` in the format `format_name` picks: `pixels` are
  /// linear floats stored as `storage` says (ImageStorage), else sRGB bytes (PNG at zlib level 1).
  int (*write_rgb)(const char* path, const char* format_name, int width, int height, int storage, const void* pixels,
                   char* error, std::size_t error_size);
  /// Reads the first channel of the image at `path` as floats in [0, 1] into the buffer that
  /// `allocate(context, width, height)` returns for its size (row 0 is the image's top row); returns 2
  /// without an error message if `allocate` returns null.
  int (*read_first_channel)(const char* path, void* context, float* (*allocate)(void* context, int width, int height),
                            char* error, std::size_t error_size);
};

/// The module, loaded by the first call from beside the executable or from its installed place; an
/// error saying where it looked and why it failed otherwise.
Expected<const ImageModule*> image_module();

}  // namespace houle::cli
