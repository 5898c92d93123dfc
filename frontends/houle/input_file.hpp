// Input files (scene files, height maps) are read only when they are regular files of bounded size:
// a device such as /dev/zero, a FIFO or a directory would make a read hang or never end.
#pragma once
#include <cstdint>
#include <string>

#include "houle/runtime/expected.hpp"

namespace houle::cli {

/// The size of the regular file at `path`; an error message (without the path) if it is missing or
/// not a regular file.
Expected<std::uintmax_t> regular_file_size(const std::string& path);

}  // namespace houle::cli
