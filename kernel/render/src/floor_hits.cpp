// The dispatched floor hits of secondary rays (templates in floor_hits_impl.hpp).
#include "floor_hits.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

namespace {
void check_rays(const FloorGridView& f, const FloorRays& in, std::size_t n, const FloorHits& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.ox != nullptr && in.oy != nullptr && in.oz != nullptr && in.dx != nullptr &&
                          in.dy != nullptr && in.dz != nullptr && in.t_max != nullptr && out.t != nullptr &&
                          out.nx != nullptr && out.ny != nullptr && out.nz != nullptr && out.left != nullptr && out.objects != nullptr),
               "floor_hits: n floats in every array");
  HOULE_ASSERT(f.nx == 0 || (f.z != nullptr && f.cell_max != nullptr && f.nx >= 1 && f.ny >= 1),
               "floor_hits: a floor of 1 x 1 samples or more, or none");
}
}  // namespace

void floor_hits(const FloorGridView& f, const ObjectBounds& b, const FloorRays& in, std::size_t n, FloorHits out) noexcept {
  check_rays(f, in, n, out);
  simd::active_table<RenderTable>().floor_hits_batch(f, b, in, n, out);
}

void floor_hits(Isa isa, const FloorGridView& f, const ObjectBounds& b, const FloorRays& in, std::size_t n,
                FloorHits out) noexcept {
  check_rays(f, in, n, out);
  simd::table_for<RenderTable>(isa).floor_hits_batch(f, b, in, n, out);
}

}  // namespace houle::detail
