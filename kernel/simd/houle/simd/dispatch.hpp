// Per-ISA function tables. A module declares a table struct of function pointers, defines
// `make_table<A>()` in a source compiled once per ISA (cmake: houle_add_isa_library), and looks the
// table up once; calls then go through a plain pointer, never through a new dispatch.
#pragma once
#include "houle/runtime/assert.hpp"
#include "houle/runtime/isa.hpp"
#include "houle/simd/simd.hpp"

namespace houle::simd {

/// Defined (specialised) in the object compiled for ISA I.
template <class Table, Isa I>
const Table& isa_table() noexcept;

/// The table for `isa`, which must be supported (the public entries taking an Isa say so).
template <class Table>
const Table& table_for(Isa isa) noexcept {
  HOULE_ASSERT(isa_supported(isa), "an ISA this build and CPU support (isa_supported)");
  switch (isa) {
#if HOULE_HAVE_ISA_1
    case Isa::sse4_2: return isa_table<Table, Isa::sse4_2>();
#endif
#if HOULE_HAVE_ISA_2
    case Isa::avx2: return isa_table<Table, Isa::avx2>();
#endif
#if HOULE_HAVE_ISA_3
    case Isa::avx512: return isa_table<Table, Isa::avx512>();
#endif
#if HOULE_HAVE_ISA_4
    case Isa::neon64: return isa_table<Table, Isa::neon64>();
#endif
#if HOULE_HAVE_ISA_5
    case Isa::neon: return isa_table<Table, Isa::neon>();
#endif
    default: return isa_table<Table, Isa::scalar>();
  }
}

/// The table for active_isa(), looked up on first use.
template <class Table>
const Table& active_table() noexcept {
  static const Table& table = table_for<Table>(active_isa());
  return table;
}

}  // namespace houle::simd

// In a per-ISA source: HOULE_ISA_ID (0 when unset: the scalar build of the same file) selects the
// architecture tag `houle::simd::IsaArch` and the Isa value `houle::simd::this_isa`.
#ifdef HOULE_ISA_SOURCE
#ifndef HOULE_ISA_ID
#define HOULE_ISA_ID 0
#endif
namespace houle::simd {
inline constexpr Isa this_isa = static_cast<Isa>(HOULE_ISA_ID);
#if HOULE_ISA_ID == 0
using IsaArch = scalar;
#elif HOULE_ISA_ID == 1
using IsaArch = xsimd::sse4_2;
#elif HOULE_ISA_ID == 2
using IsaArch = xsimd::fma3<xsimd::avx2>;
#elif HOULE_ISA_ID == 3
using IsaArch = xsimd::avx512bw;
#elif HOULE_ISA_ID == 4
using IsaArch = xsimd::neon64;
#elif HOULE_ISA_ID == 5
using IsaArch = xsimd::neon;
#endif
}  // namespace houle::simd
/// Defines the table of module `Table` for this object's ISA from `make<IsaArch>()`.
#define HOULE_DEFINE_ISA_TABLE(Table, make)                                              \
  template <>                                                                            \
  const Table& houle::simd::isa_table<Table, houle::simd::this_isa>() noexcept {         \
    static constexpr Table table = make<houle::simd::IsaArch>();                         \
    return table;                                                                        \
  }
#endif
