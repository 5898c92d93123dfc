// libFuzzer target: any bytes into the TOML scene parser (frontends/houle/scene_file.cpp). It must
// return a scene or an error naming "file:line:column" and a field; never crash, hang or leak.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > houle::cli::max_scene_file_bytes) return -1;  // load_scene_file refuses these unread
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // Height map images resolve against a folder that does not exist: image decoding is not fuzzed here.
  const houle::Expected<houle::Scene> scene = houle::cli::parse_scene(text, "fuzz.toml", "/nonexistent");
  if (!scene && (scene.error().field.rfind("fuzz.toml:", 0) != 0 || scene.error().message.empty())) __builtin_trap();
  return 0;
}
