#include "houle/runtime/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace houle::detail {

void assert_failed(const char* file, int line, const char* condition, const char* message) noexcept {
  std::fprintf(stderr, "%s:%d: houle contract violated: %s (%s)\n", file, line, message, condition);
  std::fflush(stderr);
  std::abort();
}

}  // namespace houle::detail
