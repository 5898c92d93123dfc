// Compiled once per ISA (HOULE_ISA_ID set by cmake/HouleIsa.cmake) and once without it (scalar).
#define HOULE_ISA_SOURCE
#include "houle/simd/dispatch.hpp"
#include "dispersion_impl.hpp"
#include "sim_table.hpp"

namespace houle::detail {
namespace {
template <class A>
constexpr SimTable make_sim_table() {
  return {&dispersion_k_batch<A>};
}
}  // namespace
}  // namespace houle::detail

HOULE_DEFINE_ISA_TABLE(houle::detail::SimTable, houle::detail::make_sim_table)
