#include "houle/runtime/isa.hpp"

#include <array>
#include <cstdlib>
#include <string>

#include "houle/runtime/assert.hpp"

#if defined(__arm__) && defined(__linux__)
#include <asm/hwcap.h>
#include <sys/auxv.h>
#endif

namespace houle {
namespace {

// Bit `id` is set for each ISA compiled into this build (cmake/HouleIsa.cmake).
#ifndef HOULE_COMPILED_ISA_MASK
#error "HOULE_COMPILED_ISA_MASK is set by cmake/HouleIsa.cmake (target houle_compiled_isas)"
#endif

struct IsaRow {
  Isa isa;
  std::string_view name;
  std::size_t width;
};
constexpr IsaRow rows[] = {
#define HOULE_ISA(enum_name, id, name, width, family, flags) {Isa::enum_name, name, width},
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
};
constexpr std::size_t isa_count = std::size(rows);

constexpr bool ids_are_row_indices() {
  for (std::size_t i = 0; i < isa_count; ++i) {
    if (static_cast<std::size_t>(rows[i].isa) != i) return false;
  }
  return true;
}
static_assert(ids_are_row_indices(), "isa_list.inc: the ids must be 0, 1, 2, ... in row order");
static_assert(isa_count <= 32, "HOULE_COMPILED_ISA_MASK has 32 bits");

bool cpu_has(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return true;
#if defined(__x86_64__) || defined(__i386__)
    // libgcc's checks include the OS's XGETBV support for the wider registers.
    case Isa::sse4_2: return __builtin_cpu_supports("sse4.2");
    case Isa::avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("fma");
#endif
#if defined(__aarch64__)
    case Isa::neon64: return true;  // Advanced SIMD is mandatory on AArch64
#endif
#if defined(__arm__) && defined(__linux__)
    case Isa::neon: return (getauxval(AT_HWCAP) & HWCAP_NEON) != 0;
#endif
    default: return false;
  }
}

struct Choice {
  std::array<Isa, isa_count> supported{};
  std::size_t supported_count = 0;
  Isa active = Isa::scalar;
  std::string override_error;
};

const Choice& choice() noexcept {
  static const Choice c = [] {
    Choice r;
    // Best first: the rows run from least to most preferred (isa_list.inc), and no CPU supports two
    // processor families.
    for (std::size_t i = isa_count; i-- > 0;) {
      if (isa_supported(rows[i].isa)) r.supported[r.supported_count++] = rows[i].isa;
    }
    r.active = r.supported[0];
    if (const char* env = std::getenv("HOULE_ISA"); env != nullptr && *env != '\0') {
      const std::optional<Isa> wanted = parse_isa(env);
      if (!wanted) {
        r.override_error = std::string("HOULE_ISA=") + env + " is not one of " + std::string(isa_names);
      } else if (!isa_supported(*wanted)) {
        r.override_error = std::string("HOULE_ISA=") + env + " is not " +
                           (isa_compiled(*wanted) ? "supported by this CPU" : "compiled into this build");
      } else {
        r.active = *wanted;
      }
    }
    return r;
  }();
  return c;
}

}  // namespace

std::string_view isa_name(Isa isa) noexcept {
  HOULE_ASSERT(static_cast<std::size_t>(isa) < isa_count, "isa_name: one of the Isa values");
  return rows[static_cast<std::size_t>(isa)].name;
}

std::optional<Isa> parse_isa(std::string_view name) noexcept {
  for (const IsaRow& row : rows) {
    if (row.name == name) return row.isa;
  }
  return std::nullopt;
}

std::size_t isa_width(Isa isa) noexcept {
  HOULE_ASSERT(static_cast<std::size_t>(isa) < isa_count, "isa_width: one of the Isa values");
  return rows[static_cast<std::size_t>(isa)].width;
}

bool isa_compiled(Isa isa) noexcept { return ((HOULE_COMPILED_ISA_MASK >> static_cast<unsigned>(isa)) & 1u) != 0; }

bool isa_supported(Isa isa) noexcept { return isa_compiled(isa) && cpu_has(isa); }

std::span<const Isa> supported_isas() noexcept {
  const Choice& c = choice();
  return {c.supported.data(), c.supported_count};
}

Isa active_isa() noexcept { return choice().active; }

std::string_view isa_override_error() noexcept { return choice().override_error; }

}  // namespace houle
