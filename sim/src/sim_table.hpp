// The sim module's per-ISA function table (see houle/simd/dispatch.hpp).
#pragma once
#include <cstddef>

namespace houle::detail {

struct SimTable {
  /// k[i] at depth[i] for deep-water wavenumber k0 (rad/m); see houle::dispersion_k_batch.
  void (*dispersion_k_batch)(float k0, const float* depth, std::size_t n, float* k) noexcept;
};

}  // namespace houle::detail
