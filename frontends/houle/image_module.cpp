#include "image_module.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace houle::cli {
namespace {

constexpr const char* module_file = "houle_image_io.so";

// The directory of the running executable ("" if unknown).
std::filesystem::path executable_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

Expected<const ImageModule*> load() {
  // Beside the executable in a build tree; HOULE_MODULE_DIR (relative to the installed bin dir) once installed.
  const std::filesystem::path dir = executable_dir();
  std::string tried;
  for (const std::filesystem::path& candidate : {dir / module_file, dir / HOULE_MODULE_DIR / module_file}) {
    std::error_code ec;
    if (!std::filesystem::exists(candidate, ec)) {
      tried += (tried.empty() ? "" : ", ") + candidate.lexically_normal().string();
      continue;
    }
    void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) return Error{candidate.string(), std::string("cannot load the image module: ") + dlerror()};
    using Entry = const ImageModule* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, "houle_image_module"));
    if (!entry) return Error{candidate.string(), "not a houle image module (no houle_image_module)"};
    return entry();
  }
  return Error{module_file, "the image module (OpenImageIO) is not installed; looked at " + tried +
                                "; --raw needs no module"};
}

}  // namespace

Expected<const ImageModule*> image_module() {
  static const Expected<const ImageModule*> module = load();
  return module;
}

}  // namespace houle::cli
