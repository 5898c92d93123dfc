// The dispatched floor hits of rays into the water (templates in water_floor_impl.hpp).
#include "water_floor.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

namespace {
void check_water(const WaterFloorView& f, const WaterRays& in, std::size_t n, const WaterHits& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.ox != nullptr && in.oy != nullptr && in.oz != nullptr && in.dx != nullptr &&
                          in.dy != nullptr && in.dz != nullptr && in.t_max != nullptr && out.t != nullptr &&
                          out.nx != nullptr && out.ny != nullptr && out.nz != nullptr && out.left != nullptr),
               "water_floor: n floats in every array");
  HOULE_ASSERT(f.nx == 0 || (f.z != nullptr && f.cell_max != nullptr && f.nx >= 1 && f.ny >= 1),
               "water_floor: a floor of 1 x 1 samples or more, or none");
}
}  // namespace

void water_floor(const WaterFloorView& f, const WaterRays& in, std::size_t n, WaterHits out) noexcept {
  check_water(f, in, n, out);
  simd::active_table<RenderTable>().water_floor_batch(f, in, n, out);
}

void water_floor(Isa isa, const WaterFloorView& f, const WaterRays& in, std::size_t n, WaterHits out) noexcept {
  check_water(f, in, n, out);
  simd::table_for<RenderTable>(isa).water_floor_batch(f, in, n, out);
}

}  // namespace houle::detail
