// Image files go through OpenImageIO in a module, houle_image_io.so, loaded on first use. Linked
// into the command, OpenImageIO and the ~260 shared libraries it pulls in took 0.33 s to load and
// relocate at every start (0.6 s under AddressSanitizer), and most runs (raw frames into a pipe,
// info, probe, validate, bench) never read or write an image.
#pragma once
#include <cstddef>

#include "houle/runtime/expected.hpp"

namespace houle::cli {

/// How write_image stores a channel (an int across the module's C interface).
enum ImageStorage : int { srgb8 = 0, linear_half = 1, linear_float = 2 };

/// An image's channels, interleaved in `pixels`: floats, or bytes when every channel is srgb8.
struct ImageLayout {
  int width = 0, height = 0, channels = 0;
  const char* const* names = nullptr;  ///< `channels` names: "R", "G", "B", then e.g. "A", "Z", "N.X", "depth"
  const int* storage = nullptr;        ///< `channels` ImageStorage values
};

/// A header attribute, by OpenEXR's name and type (formats that have no place for one drop it).
struct ImageAttribute {
  enum Type : int { text = 0, integer = 1, real = 2, matrix44 = 3, rational = 4 };
  const char* name = nullptr;
  Type type = text;
  const char* string = nullptr;  ///< text
  double number = 0.0;           ///< real (a double in EXR)
  int ints[2] = {};              ///< integer; rational as numerator, denominator
  float floats[16] = {};         ///< matrix44 row by row, for row vectors (OpenEXR's convention: p' = p M)
};

/// The module's C interface (image_module_oiio.cpp). Each function returns 0 on success; otherwise
/// it writes a NUL-terminated message of at most error_size bytes to `error` and returns non-zero.
struct ImageModule {
  /// Whether OpenImageIO has a writer for files named like `name` (it goes by the extension).
  int (*can_write)(const char* name, char* error, std::size_t error_size);
  /// Writes the image `layout` describes to `path` in the format `format_name` picks (PNG at zlib
  /// level 1), with `attributes`, and nothing that changes from run to run (no date): the same
  /// pixels give the same bytes.
  int (*write_image)(const char* path, const char* format_name, const ImageLayout* layout, const void* pixels,
                     const ImageAttribute* attributes, int attribute_count, char* error, std::size_t error_size);
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
