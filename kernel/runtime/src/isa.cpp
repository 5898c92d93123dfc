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

constexpr std::array<std::string_view, 6> names = {"scalar", "sse4.2", "avx2", "avx512", "neon64", "neon"};
constexpr std::array<std::size_t, 6> widths = {1, 4, 8, 16, 4, 4};
// Best first.
constexpr std::array<Isa, 6> preference = {Isa::avx512, Isa::avx2, Isa::sse4_2, Isa::neon64, Isa::neon, Isa::scalar};

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
  std::array<Isa, 6> supported{};
  std::size_t supported_count = 0;
  Isa active = Isa::scalar;
  std::string override_error;
};

const Choice& choice() noexcept {
  static const Choice c = [] {
    Choice r;
    for (Isa isa : preference) {
      if (isa_supported(isa)) r.supported[r.supported_count++] = isa;
    }
    r.active = r.supported[0];
    if (const char* env = std::getenv("HOULE_ISA"); env != nullptr && *env != '\0') {
      const std::optional<Isa> wanted = parse_isa(env);
      if (!wanted) {
        r.override_error = std::string("HOULE_ISA=") + env + " is not one of scalar, sse4.2, avx2, avx512, neon64, neon";
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
  HOULE_ASSERT(static_cast<std::size_t>(isa) < names.size(), "isa_name: one of the Isa values");
  return names[static_cast<std::size_t>(isa)];
}

std::optional<Isa> parse_isa(std::string_view name) noexcept {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<Isa>(i);
  }
  return std::nullopt;
}

std::size_t isa_width(Isa isa) noexcept {
  HOULE_ASSERT(static_cast<std::size_t>(isa) < widths.size(), "isa_width: one of the Isa values");
  return widths[static_cast<std::size_t>(isa)];
}

bool isa_compiled(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return true;
#if HOULE_HAVE_ISA_1
    case Isa::sse4_2: return true;
#endif
#if HOULE_HAVE_ISA_2
    case Isa::avx2: return true;
#endif
#if HOULE_HAVE_ISA_3
    case Isa::avx512: return true;
#endif
#if HOULE_HAVE_ISA_4
    case Isa::neon64: return true;
#endif
#if HOULE_HAVE_ISA_5
    case Isa::neon: return true;
#endif
    default: return false;
  }
}

bool isa_supported(Isa isa) noexcept { return isa_compiled(isa) && cpu_has(isa); }

std::span<const Isa> supported_isas() noexcept {
  const Choice& c = choice();
  return {c.supported.data(), c.supported_count};
}

Isa active_isa() noexcept { return choice().active; }

std::string_view isa_override_error() noexcept { return choice().override_error; }

}  // namespace houle
