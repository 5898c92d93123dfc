// Contract checks for debug builds: HOULE_ASSERT(cond, "what must hold") states a precondition of a
// public entry (a size that must match, a pointer that must not be null, an index in range). With
// HOULE_ENABLE_ASSERTS defined (CMake option HOULE_ASSERTS: the dev, asan, tsan and fuzz presets) a
// failed check prints file:line, the condition and the message to stderr and aborts, so a wrong call
// stops where it is made. Otherwise the check compiles to nothing and the condition is not evaluated:
// release code is what it would be without it. A caller's bad input is an Error (expected.hpp); an
// assertion is for a call that breaks the documented contract, which no input file can cause.
#pragma once

namespace houle::detail {
/// Prints "file:line: houle contract violated: message (condition)" to stderr and aborts. Out of line
/// (kernel/runtime/src/assert.cpp) so that no per-ISA object holds a copy the linker could pick.
[[noreturn]] void assert_failed(const char* file, int line, const char* condition, const char* message) noexcept;
}  // namespace houle::detail

#if defined(HOULE_ENABLE_ASSERTS)
#define HOULE_ASSERT(cond, message) \
  ((cond) ? static_cast<void>(0) : ::houle::detail::assert_failed(__FILE__, __LINE__, #cond, message))
#else
// sizeof keeps the names in the check used (no unused-variable warnings) without evaluating them.
#define HOULE_ASSERT(cond, message) static_cast<void>(sizeof(!(cond)) + sizeof(message))
#endif
