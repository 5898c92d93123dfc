// Test entry point: says which ISA the dispatched kernels use, so every CI log shows it.
#include <gtest/gtest.h>

#include <cstdio>

#include "houle/runtime/isa.hpp"

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (!houle::isa_override_error().empty()) {
    std::fprintf(stderr, "houle: %.*s\n", int(houle::isa_override_error().size()), houle::isa_override_error().data());
    return 2;
  }
  std::printf("houle: active ISA %.*s; supported:", int(houle::isa_name(houle::active_isa()).size()),
              houle::isa_name(houle::active_isa()).data());
  for (houle::Isa isa : houle::supported_isas()) std::printf(" %.*s", int(houle::isa_name(isa).size()), houle::isa_name(isa).data());
  std::printf("\n");
  return RUN_ALL_TESTS();
}
