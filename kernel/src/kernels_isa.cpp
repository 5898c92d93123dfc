// Compiled once per ISA (HOULE_ISA_ID set by cmake/HouleIsa.cmake) and once without it (scalar).
#define HOULE_ISA_SOURCE
#include "houle/simd/dispatch.hpp"
#include "gerstner_impl.hpp"
#include "kernel_table.hpp"

namespace houle::detail {
namespace {
template <class A>
constexpr KernelTable make_kernel_table() {
  return {&gerstner_eval<A>};
}
}  // namespace
}  // namespace houle::detail

HOULE_DEFINE_ISA_TABLE(houle::detail::KernelTable, houle::detail::make_kernel_table)
