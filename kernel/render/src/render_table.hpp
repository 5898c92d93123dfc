// The render room's per-ISA function table (see houle/simd/dispatch.hpp).
#pragma once
#include <cstddef>

#include "houle/render/optics.hpp"

namespace houle::detail {

struct RenderTable {
  void (*fresnel_batch)(const float*, float, float*, std::size_t) noexcept;
  void (*reflect_refract_batch)(const ReflectRefractInput&, std::size_t, float, float, ReflectRefractOutput) noexcept;
};

}  // namespace houle::detail
