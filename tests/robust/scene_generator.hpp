// Random scenes for the scene fuzzer (scene_fuzz.cpp): every key of the key table
// (sim/src/scene_keys.cpp) drawn within its range, extremes included, arrays from empty to their
// limits, then the few rules no single key's range states (scene.cpp) met most of the time, so that
// most scenes validate. A scene is a pure function of its seed.
#pragma once
#include <cstdint>
#include <string>

#include "houle/sim/scene.hpp"

namespace houle::test {

Scene generate_scene(std::uint64_t seed);

/// The scene as a TOML file docs/scenes.md describes, every key written; a height map is written
/// as a plain PGM image `map_file` beside it (its path relative to the scene file's folder).
std::string scene_toml(const Scene& scene, const std::string& map_file);
/// The height map as a plain PGM (grey levels 0..65535 spanning its depths) and the depths of black
/// and white that read it back.
std::string height_map_pgm(const HeightMap& map, double& depth_at_black, double& depth_at_white);

}  // namespace houle::test
