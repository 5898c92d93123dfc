// The surf map's packing and the dispatched foam cover (templates in foam_impl.hpp).
#include "foam.hpp"

#include <limits>
#include <utility>

#include "houle/render/renderer.hpp"
#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

SurfView PackedSurf::view() const noexcept {
  return {nodes.empty() ? nullptr : nodes.front().data(), origin_x, origin_y, cell, float(nx - 1), float(ny - 1),
          std::int32_t(nx)};
}

bool surf_map_fits(std::uint32_t nx, std::uint32_t ny) noexcept {
  return std::uint64_t(nx) * ny * 4 <= std::uint64_t(std::numeric_limits<std::int32_t>::max());
}

PackedSurf pack(const SurfMap& m) {
  HOULE_ASSERT(surf_map_fits(m.nx, m.ny), "pack: a surf map of at most 2^29 nodes");
  std::vector<std::array<float, 4>> nodes;
  nodes.reserve(m.foam.size());
  for (std::size_t n = 0; n < m.foam.size(); ++n) nodes.push_back({m.foam[n], m.dir_x[n], m.dir_y[n], m.amplitude[n]});
  return {m.origin_x, m.origin_y, m.cell, m.nx, m.ny, std::move(nodes)};
}

namespace {
void check_foam(const SurfView& m, const FoamInput& in, std::size_t n, const float* cover) noexcept {
  HOULE_ASSERT(n == 0 || (in.side != nullptr && in.x != nullptr && in.y != nullptr && in.z != nullptr &&
                          in.gx != nullptr && in.gy != nullptr && in.t != nullptr && cover != nullptr),
               "foam_cover: n floats in every array");
  HOULE_ASSERT(m.nodes != nullptr && m.nx >= 2 && m.u_end >= 1.0f && m.v_end >= 1.0f, "foam_cover: a surf map of 2 x 2 nodes or more");
}
}  // namespace

void foam_cover(const SurfView& m, const FoamInput& in, std::size_t n, float pixel_angle, float* cover) noexcept {
  check_foam(m, in, n, cover);
  simd::active_table<RenderTable>().foam_cover_batch(m, in, n, pixel_angle, cover);
}

void foam_cover(Isa isa, const SurfView& m, const FoamInput& in, std::size_t n, float pixel_angle, float* cover) noexcept {
  check_foam(m, in, n, cover);
  simd::table_for<RenderTable>(isa).foam_cover_batch(m, in, n, pixel_angle, cover);
}

}  // namespace houle::detail
