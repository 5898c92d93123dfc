# Instruction sets compiled for this target. Each SIMD kernel source is compiled once per ISA with
# that ISA's flags; the baseline code picks one at start-up (kernel/runtime/src/isa.cpp).
# The ISAs, their ids (houle::Isa, HOULE_ISA_ID), flags and processor families are the rows of
# kernel/runtime/include/houle/runtime/isa_list.inc, read here as HOULE_ISA_ID_<isa>, HOULE_ISA_FLAGS_<isa>.
set(_houle_isa_list ${PROJECT_SOURCE_DIR}/kernel/runtime/include/houle/runtime/isa_list.inc)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_houle_isa_list})
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(_houle_family x86_64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64)$")
  set(_houle_family aarch64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^arm")
  set(_houle_family arm)
else()
  set(_houle_family none)
endif()
set(HOULE_SIMD_ISAS "")
file(STRINGS ${_houle_isa_list} _houle_rows REGEX "^HOULE_ISA\\(")
foreach(row IN LISTS _houle_rows)
  if(NOT row MATCHES "^HOULE_ISA\\(([a-z0-9_]+), ([0-9]+), \"[^\"]+\", [0-9]+, ([a-z0-9_]+), \"([^\"]*)\"\\)$")
    message(FATAL_ERROR "${_houle_isa_list}: cannot read the row '${row}'")
  endif()
  set(isa ${CMAKE_MATCH_1})
  set(HOULE_ISA_ID_${isa} ${CMAKE_MATCH_2})
  separate_arguments(HOULE_ISA_FLAGS_${isa} UNIX_COMMAND "${CMAKE_MATCH_4}")
  if(CMAKE_MATCH_3 STREQUAL _houle_family AND NOT HOULE_FORCE_SCALAR)
    list(APPEND HOULE_SIMD_ISAS ${isa})
  endif()
endforeach()
# gcc 12 reports false -W(maybe-)uninitialized inside avx512fintrin.h (its _mm512_undefined_* idiom),
# the latter only with the sanitizers on. (clang, for the fuzz targets, has no such option.)
list(APPEND HOULE_ISA_FLAGS_avx512 $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized> -Wno-uninitialized)

# A build may leave out kernels to save CI time: the asan preset leaves out AVX-512 (compiled under
# ASan it was a minute of CI; the release stage tests it against the scalar reference), the fuzz
# preset keeps AVX2 alone (its targets check the model, not each ISA).
set(HOULE_SKIP_ISAS "" CACHE STRING "SIMD kernels not to build (e.g. avx512); the rest still dispatch at run time")
if(HOULE_SKIP_ISAS)
  list(REMOVE_ITEM HOULE_SIMD_ISAS ${HOULE_SKIP_ISAS})
endif()
message(STATUS "houle: SIMD kernels for: scalar ${HOULE_SIMD_ISAS}")

# Internal: the list of compiled ISAs (for the runtime's dispatch), and the SIMD layer.
add_library(houle_compiled_isas INTERFACE)
# Bit <id> for each ISA compiled in; scalar (id 0) always is.
math(EXPR _houle_mask "1 << ${HOULE_ISA_ID_scalar}")
foreach(isa IN LISTS HOULE_SIMD_ISAS)
  math(EXPR _houle_mask "${_houle_mask} | (1 << ${HOULE_ISA_ID_${isa}})")
endforeach()
target_compile_definitions(houle_compiled_isas INTERFACE HOULE_COMPILED_ISA_MASK=${_houle_mask})
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
