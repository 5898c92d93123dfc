#include "toml_ascii.hpp"

#include <cstdint>
#include <cstdio>

namespace houle::cli {
namespace {

// One UTF-8 code point at text[i]: its value and length, or length 0 if the bytes are not UTF-8
// (truncated, overlong, a surrogate or beyond U+10FFFF).
struct CodePoint {
  char32_t value = 0;
  std::size_t length = 0;
};
CodePoint decode(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  const std::size_t n = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 0;
  if (n == 0 || lead >= 0xF8 || i + n > text.size()) return {};
  char32_t c = lead & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return {};
    c = (c << 6) | (byte(i + k) & 0x3F);
  }
  const char32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (c < smallest[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return {};
  return {c, n};
}

std::string escape(char32_t c) {
  char buf[12];
  if (c <= 0xFFFF) std::snprintf(buf, sizeof buf, "\\u%04X", unsigned(c));
  else std::snprintf(buf, sizeof buf, "\\U%08X", unsigned(c));
  return buf;
}

enum class State { normal, comment, basic, multiline_basic, literal, multiline_literal };

}  // namespace

Expected<std::string> toml_ascii(std::string_view text, const std::string& name) {
  std::string out;
  out.reserve(text.size());
  State state = State::normal;
  std::uint32_t line = 1, column = 1;
  auto fail = [&](const std::string& what) {
    return Error{name + ":" + std::to_string(line) + ":" + std::to_string(column), what};
  };
  auto starts = [&](std::size_t i, std::string_view s) { return text.substr(i, s.size()) == s; };
  for (std::size_t i = 0; i < text.size();) {
    const char ch = text[i];
    if (static_cast<unsigned char>(ch) >= 0x80) {
      const CodePoint cp = decode(text, i);
      if (cp.length == 0) return fail("invalid UTF-8 (a scene file is UTF-8 text)");
      switch (state) {
        case State::comment: out += '?'; break;
        case State::basic:
        case State::multiline_basic: out += escape(cp.value); break;
        case State::literal:
        case State::multiline_literal:
          return fail("a non-ASCII character in a literal string: write it in a basic string \"...\"");
        case State::normal: return fail("a non-ASCII character outside a string or comment");
      }
      i += cp.length;
      ++column;
      continue;
    }
    std::size_t take = 1;  // ASCII bytes copied as they are
    switch (state) {
      case State::normal:
        if (ch == '#') state = State::comment;
        else if (starts(i, "\"\"\"")) state = State::multiline_basic, take = 3;
        else if (ch == '"') state = State::basic;
        else if (starts(i, "'''")) state = State::multiline_literal, take = 3;
        else if (ch == '\'') state = State::literal;
        break;
      case State::comment:
        if (ch == '\n') state = State::normal;
        break;
      case State::basic:
        if (ch == '\\' && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) < 0x80 && text[i + 1] != '\n') take = 2;
        else if (ch == '"' || ch == '\n') state = State::normal;
        break;
      case State::multiline_basic:
        if (ch == '\\' && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) < 0x80) take = 2;
        else if (starts(i, "\"\"\"")) state = State::normal, take = 3;
        break;
      case State::literal:
        if (ch == '\'' || ch == '\n') state = State::normal;
        break;
      case State::multiline_literal:
        if (starts(i, "'''")) state = State::normal, take = 3;
        break;
    }
    for (std::size_t k = 0; k < take; ++k) {
      if (text[i + k] == '\n') ++line, column = 1;
      else ++column;
    }
    out.append(text.substr(i, take));
    i += take;
  }
  return out;
}

}  // namespace houle::cli
