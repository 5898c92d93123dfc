// Sizes of the tests' largest random sets. The cross builds' tests run under qemu, 20-50x slower
// than natively, where the full sets took minutes per test (the armhf stage alone was 10 minutes of
// CI): there they are cut to a quarter. The code paths, the seeds and every bound are the same; the
// native stages (release, asan, scalar) run the full sets.
#pragma once
#include <cstddef>

namespace houle::test {

#ifdef HOULE_TEST_UNDER_EMULATION
inline constexpr std::size_t emulation_divisor = 4;
#else
inline constexpr std::size_t emulation_divisor = 1;
#endif

/// n, or a quarter of it (rounded up) under emulation.
constexpr std::size_t emulation_scaled(std::size_t n) noexcept { return (n + emulation_divisor - 1) / emulation_divisor; }

}  // namespace houle::test
