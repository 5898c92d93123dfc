// Per-ISA function tables. A module declares a table struct of function pointers, defines
// `make_table<A>()` in a source compiled once per ISA (cmake: houle_add_isa_library), and looks the
// table up once; calls then go through a plain pointer, never through a new dispatch.
#pragma once
#include <cstdint>

#include "houle/runtime/assert.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/simd/simd.hpp"

// Bit `id` is set for each ISA compiled into this build (cmake/HouleIsa.cmake).
#ifndef HOULE_COMPILED_ISA_MASK
#error "HOULE_COMPILED_ISA_MASK is set by cmake/HouleIsa.cmake (target houle_compiled_isas)"
#endif

namespace houle::simd {

/// houle::isa_compiled as a constant, for the dispatch below.
inline constexpr bool compiled_in(Isa isa) {
  return ((std::uint32_t{HOULE_COMPILED_ISA_MASK} >> static_cast<unsigned>(isa)) & 1u) != 0;
}

/// Defined (specialised) in the object compiled for ISA I.
template <class Table, Isa I>
const Table& isa_table() noexcept;

/// The table for `isa`, which must be supported (the public entries taking an Isa say so).
template <class Table>
const Table& table_for(Isa isa) noexcept {
  HOULE_ASSERT(isa_supported(isa), "an ISA this build and CPU support (isa_supported)");
  switch (isa) {
    // The tables of ISAs not compiled into this build are never named: they are not defined.
#define HOULE_ISA(enum_name, id, name, width, family, flags)                           \
  case Isa::enum_name:                                                                   \
    if constexpr (compiled_in(Isa::enum_name)) return isa_table<Table, Isa::enum_name>(); \
    break;
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
  }
  return isa_table<Table, Isa::scalar>();
}

/// The table for active_isa(), looked up on first use.
template <class Table>
const Table& active_table() noexcept {
  static const Table& table = table_for<Table>(active_isa());
  return table;
}

/// The architecture tag of each ISA's kernels: here, not in isa_list.inc, as the runtime has no SIMD.
/// Every row of the list must have one (checked below, in each per-ISA object).
template <Isa I>
struct isa_arch;
template <>
struct isa_arch<Isa::scalar> {
  using type = scalar;
};
#if HOULE_SIMD_BATCHES
template <>
struct isa_arch<Isa::sse4_2> {
  using type = xsimd::sse4_2;
};
template <>
struct isa_arch<Isa::avx2> {
  using type = xsimd::fma3<xsimd::avx2>;
};
template <>
struct isa_arch<Isa::avx512> {
  using type = xsimd::avx512bw;
};
template <>
struct isa_arch<Isa::neon64> {
  using type = xsimd::neon64;
};
template <>
struct isa_arch<Isa::neon> {
  using type = xsimd::neon;
};
template <Isa I>
concept has_isa_arch = requires { typename isa_arch<I>::type; };
#define HOULE_ISA(enum_name, id, name, width, family, flags) \
  static_assert(has_isa_arch<Isa::enum_name>, "isa_list.inc: no isa_arch for " name);
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
#endif

}  // namespace houle::simd

// In a per-ISA source: HOULE_ISA_ID (0 when unset: the scalar build of the same file) selects the
// architecture tag `houle::simd::IsaArch` and the Isa value `houle::simd::this_isa`.
#ifdef HOULE_ISA_SOURCE
#ifndef HOULE_ISA_ID
#define HOULE_ISA_ID 0
#endif
namespace houle::simd {
inline constexpr Isa this_isa = static_cast<Isa>(HOULE_ISA_ID);
using IsaArch = typename isa_arch<this_isa>::type;
#define HOULE_ISA(enum_name, id, name, floats, family, flags) \
  static_assert(this_isa != Isa::enum_name || width<IsaArch> == (floats), "isa_list.inc: width of " name);
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
}  // namespace houle::simd
/// Defines the table of module `Table` for this object's ISA from `make<IsaArch>()`.
#define HOULE_DEFINE_ISA_TABLE(Table, make)                                              \
  template <>                                                                            \
  const Table& houle::simd::isa_table<Table, houle::simd::this_isa>() noexcept {         \
    static constexpr Table table = make<houle::simd::IsaArch>();                         \
    return table;                                                                        \
  }
#endif
