#include <cstdio>
#include "houle/kernel/isa.hpp"
int main() { std::printf("houle %s (%s)\n", HOULE_VERSION, houle::isa_name(houle::active_isa()).data()); }
