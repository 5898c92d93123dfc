// Instruction sets houle's kernels are compiled for, and the one chosen at start-up.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace houle {

/// Values are stable: they are the HOULE_ISA_ID of each per-ISA object (cmake/HouleIsa.cmake).
enum class Isa : std::uint8_t { scalar = 0, sse4_2 = 1, avx2 = 2, avx512 = 3, neon64 = 4, neon = 5 };

/// "scalar", "sse4.2", "avx2", "avx512", "neon64", "neon".
std::string_view isa_name(Isa isa) noexcept;
std::optional<Isa> parse_isa(std::string_view name) noexcept;
/// Floats per batch: 1, 4, 8, 16, 4, 4.
std::size_t isa_width(Isa isa) noexcept;
/// Compiled into this build.
bool isa_compiled(Isa isa) noexcept;
/// Compiled and runnable on this CPU (CPUID with OS support on x86, HWCAP on ARMv7).
bool isa_supported(Isa isa) noexcept;
/// Every supported ISA, best first; scalar is always last.
std::span<const Isa> supported_isas() noexcept;

/// The ISA all dispatched kernels use, chosen once: the environment variable HOULE_ISA when it names
/// a supported ISA, otherwise the best supported one.
Isa active_isa() noexcept;
/// Empty when HOULE_ISA is unset or was honoured; otherwise why it was ignored (for frontends to report).
std::string_view isa_override_error() noexcept;

}  // namespace houle
