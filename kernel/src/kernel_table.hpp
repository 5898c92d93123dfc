// The kernel module's per-ISA function table (see houle/simd/dispatch.hpp).
#pragma once
#include <cstddef>

#include "houle/kernel/gerstner.hpp"

namespace houle::detail {

struct KernelTable {
  void (*gerstner_eval)(const GerstnerFrame&, const float*, const float*, std::size_t, GerstnerOutput, int) noexcept;
};

}  // namespace houle::detail
