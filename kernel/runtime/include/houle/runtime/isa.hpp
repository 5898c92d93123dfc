// Instruction sets houle's kernels are compiled for, and the one chosen at start-up.
#pragma once
#include <cstddef>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace houle {

/// One value per row of houle/runtime/isa_list.inc. Values are stable: they are the HOULE_ISA_ID of
/// each per-ISA object (cmake/HouleIsa.cmake).
enum class Isa : std::uint8_t {
#define HOULE_ISA(enum_name, id, name, width, family, flags) enum_name = id,
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
};

/// Every ISA houle knows, compiled or not, in id order.
inline constexpr std::array all_isas = {
#define HOULE_ISA(enum_name, id, name, width, family, flags) Isa::enum_name,
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
};

/// Their names, comma-separated ("scalar, sse4.2, ..."), for messages and help texts.
inline constexpr std::string_view isa_names = std::string_view(
#define HOULE_ISA(enum_name, id, name, width, family, flags) ", " name
#include "houle/runtime/isa_list.inc"
#undef HOULE_ISA
).substr(2);

/// The name column of isa_list.inc ("sse4.2" for Isa::sse4_2).
std::string_view isa_name(Isa isa) noexcept;
std::optional<Isa> parse_isa(std::string_view name) noexcept;
/// Floats per batch.
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
