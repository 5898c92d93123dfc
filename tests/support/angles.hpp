// pi and degrees for the tests: a `using` of these in each test file may repeat in a unity build,
// where a definition of its own in every file would not.
#pragma once
#include <numbers>

namespace houle_test {
inline constexpr double pi = std::numbers::pi;
inline constexpr double deg = pi / 180.0;  ///< radians per degree
}  // namespace houle_test
