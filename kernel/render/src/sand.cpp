// The dispatched sand colour (templates in sand_impl.hpp).
#include "sand.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

namespace {
void check_sand(const SandInput& in, std::size_t n, const SandOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.on_sand != nullptr && in.x != nullptr && in.y != nullptr && in.z != nullptr &&
                          in.footprint != nullptr && out.r != nullptr && out.g != nullptr && out.b != nullptr),
               "sand_albedo: n floats in every array");
}
}  // namespace

void sand_albedo(const LinearRgb& dry, const SandInput& in, std::size_t n, SandOutput out) noexcept {
  check_sand(in, n, out);
  simd::active_table<RenderTable>().sand_albedo_batch(dry, in, n, out);
}

void sand_albedo(Isa isa, const LinearRgb& dry, const SandInput& in, std::size_t n, SandOutput out) noexcept {
  check_sand(in, n, out);
  simd::table_for<RenderTable>(isa).sand_albedo_batch(dry, in, n, out);
}

}  // namespace houle::detail
