// The sand's colour at a row of floor hits, a packet at a time (templates in sand_impl.hpp).
#pragma once
#include <cstddef>

#include "houle/render/colour.hpp"
#include "houle/runtime/isa.hpp"

namespace houle::detail {

/// One row of floor hits: on_sand > 0 where a pixel's ray meets the floor, at (x, y, z), with the
/// pixel's footprint there (m); those four are not read elsewhere (any value will do).
struct SandInput {
  const float* on_sand;
  const float *x, *y, *z, *footprint;
};
struct SandOutput {
  float *r, *g, *b;
};
/// The sand of dry reflectance `dry` at each hit (sand_at in sand_impl.hpp), 0 where on_sand <= 0.
void sand_albedo(const LinearRgb& dry, const SandInput& in, std::size_t n, SandOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void sand_albedo(Isa isa, const LinearRgb& dry, const SandInput& in, std::size_t n, SandOutput out) noexcept;

}  // namespace houle::detail
