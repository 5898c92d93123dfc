// Scene text made ASCII before it reaches toml++. Debian's toml++ 3.3.0 reaches
// __builtin_unreachable() on some non-ASCII code points (U+00A1..U+0499 among them) where it looks
// for whitespace (marzer/tomlplusplus#190, #295; found by tests/fuzz): undefined behaviour on a
// user's file. So: inside basic strings ("..." and """...""") a non-ASCII character becomes its
// \uXXXX escape (the same string), inside comments it becomes '?' (comments are discarded), and
// anywhere else it is refused as TOML would refuse it, except in literal strings ('...'), refused
// too, with a hint: the parser could read them as something else after an earlier error.
#pragma once
#include <string>
#include <string_view>

#include "houle/runtime/expected.hpp"

namespace houle::cli {

/// `text` with only ASCII, or the first problem as {"name:line:column", what was expected}. Column
/// numbers of later errors on a line with an escaped character are off by the escapes' length.
Expected<std::string> toml_ascii(std::string_view text, const std::string& name);

}  // namespace houle::cli
