# Instruction sets compiled for this target. Each SIMD kernel source is compiled once per ISA with
# that ISA's flags; the baseline code picks one at start-up (kernel/runtime/src/isa.cpp).
# The numeric ids must match houle::Isa in kernel/runtime/include/houle/runtime/isa.hpp.
set(HOULE_ISA_ID_scalar 0)
set(HOULE_ISA_ID_sse4_2 1)
set(HOULE_ISA_ID_avx2 2)
set(HOULE_ISA_ID_avx512 3)
set(HOULE_ISA_ID_neon64 4)
set(HOULE_ISA_ID_neon 5)

set(HOULE_ISA_FLAGS_sse4_2 -msse4.2)
set(HOULE_ISA_FLAGS_avx2 -mavx2 -mfma)
# gcc 12 reports false -W(maybe-)uninitialized inside avx512fintrin.h (its _mm512_undefined_* idiom),
# the latter only with the sanitizers on. (clang, for the fuzz targets, has no such option.)
set(HOULE_ISA_FLAGS_avx512 -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx512vl -mfma
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized> -Wno-uninitialized)
set(HOULE_ISA_FLAGS_neon64 "")
# The armhf baseline (Debian: VFPv3-D16) has no NEON; only the NEON kernels may use it.
set(HOULE_ISA_FLAGS_neon -mfpu=neon-vfpv4)

if(HOULE_FORCE_SCALAR)
  set(HOULE_SIMD_ISAS "")
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(HOULE_SIMD_ISAS sse4_2 avx2 avx512)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64)$")
  set(HOULE_SIMD_ISAS neon64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^arm")
  set(HOULE_SIMD_ISAS neon)
else()
  set(HOULE_SIMD_ISAS "")
endif()
# A build may leave out kernels it can never run: the asan preset leaves out AVX-512, which the CI
# machines lack (compiled under ASan it was a minute of CI for a kernel no test could reach).
set(HOULE_SKIP_ISAS "" CACHE STRING "SIMD kernels not to build (e.g. avx512); the rest still dispatch at run time")
if(HOULE_SKIP_ISAS)
  list(REMOVE_ITEM HOULE_SIMD_ISAS ${HOULE_SKIP_ISAS})
endif()
message(STATUS "houle: SIMD kernels for: scalar ${HOULE_SIMD_ISAS}")

# Internal: the list of compiled ISAs (for the runtime's dispatch), and the SIMD layer.
add_library(houle_compiled_isas INTERFACE)
if(HOULE_FORCE_SCALAR)
  target_compile_definitions(houle_compiled_isas INTERFACE HOULE_FORCE_SCALAR=1)
endif()
foreach(isa IN LISTS HOULE_SIMD_ISAS)
  target_compile_definitions(houle_compiled_isas INTERFACE HOULE_HAVE_ISA_${HOULE_ISA_ID_${isa}}=1)
endforeach()
add_library(houle_simd INTERFACE)
target_include_directories(houle_simd INTERFACE $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/kernel/simd>)
target_link_libraries(houle_simd INTERFACE houle_headeronly houle_options houle_runtime_headers houle_compiled_isas)

# houle_add_isa_library(<name> <deps> <source>...): a static library holding <source> compiled once per
# SIMD ISA, with HOULE_ISA_ID set. <deps> is the INTERFACE target that gives the parent room's sources
# their include paths (their own headers and the floors below), so the ISA objects can include no
# more than the room's baseline code can. Link the library PRIVATE and *after* the baseline objects:
# inline functions that are not templated on the ISA are emitted in every object, and the linker keeps
# the first copy it loads, so a baseline caller could otherwise end up in an AVX2-compiled copy (SIGILL
# on older CPUs). tests/check_isa_leaks.sh guards this.
function(houle_add_isa_library name deps)
  add_library(${name} STATIC)
  foreach(isa IN LISTS HOULE_SIMD_ISAS)
    add_library(${name}_${isa} OBJECT ${ARGN})
    target_compile_definitions(${name}_${isa} PRIVATE HOULE_ISA_ID=${HOULE_ISA_ID_${isa}})
    target_compile_options(${name}_${isa} PRIVATE ${HOULE_ISA_FLAGS_${isa}})
    target_link_libraries(${name}_${isa} PRIVATE ${deps} houle_simd houle_warnings)
    target_sources(${name} PRIVATE $<TARGET_OBJECTS:${name}_${isa}>)
  endforeach()
  if(NOT HOULE_SIMD_ISAS)
    target_sources(${name} PRIVATE ${PROJECT_SOURCE_DIR}/cmake/empty.cpp)
  endif()
  string(REPLACE "houle_" "" export_name ${name})
  set_target_properties(${name} PROPERTIES LINKER_LANGUAGE CXX EXPORT_NAME ${export_name})
endfunction()
