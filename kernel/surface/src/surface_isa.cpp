// Compiled once per ISA (HOULE_ISA_ID set by cmake/HouleIsa.cmake) and once without it (scalar).
#define HOULE_ISA_SOURCE
#include "houle/simd/dispatch.hpp"
#include "camera_impl.hpp"
#include "capillary_impl.hpp"
#include "gerstner_impl.hpp"
#include "march_impl.hpp"
#include "surface_bounds_impl.hpp"
#include "train_grid_impl.hpp"
#include "surface_table.hpp"

namespace houle::detail {
namespace {
template <class A>
constexpr SurfaceTable make_surface_table() {
  return {&camera_row_rays<A>, &gerstner_eval<A>, &capillary_eval<A>, &march_rays<A>, &surface_column_stats<A>, &train_grid_eval<A>,
          &train_grid_eval_filtered<A>};
}
}  // namespace
}  // namespace houle::detail

HOULE_DEFINE_ISA_TABLE(houle::detail::SurfaceTable, houle::detail::make_surface_table)
