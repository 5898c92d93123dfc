#include "input_file.hpp"

#include <filesystem>

namespace houle::cli {

Expected<std::uintmax_t> regular_file_size(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (ec) return Error{path, ec.message()};
  if (!std::filesystem::is_regular_file(st)) return Error{path, "not a regular file"};
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path, ec.message()};
  return size;
}

}  // namespace houle::cli
