set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

# Options every houle target uses; never the user's global flags.
add_library(houle_options INTERFACE)
target_compile_features(houle_options INTERFACE cxx_std_20)
# gcc fuses a*b+c by default in C++ on targets with FMA; the results would differ between x86 and ARM
# and between the scalar and SIMD paths. Fusing is done explicitly where it is wanted.
# -fno-math-errno lets lrintf/sqrtf inline.
target_compile_options(houle_options INTERFACE -ffp-contract=off -fno-math-errno)
# Contract checks (houle/runtime/assert.hpp) in every houle target alike: Expected's accessors are
# inline, and a library and its tests must agree on them.
if(HOULE_ASSERTS)
  target_compile_definitions(houle_options INTERFACE HOULE_ENABLE_ASSERTS)
endif()

add_library(houle_warnings INTERFACE)
target_compile_options(houle_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough
  $<$<BOOL:${HOULE_WERROR}>:-Werror>)

if(HOULE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "HOULE_FUZZ needs clang (libFuzzer): configure with the fuzz preset")
  endif()
  set(HOULE_SANITIZE ON)
  # Coverage instrumentation everywhere; only the fuzz targets link libFuzzer's main.
  target_compile_options(houle_options INTERFACE -fsanitize=fuzzer-no-link)
endif()
if(HOULE_SANITIZE AND HOULE_TSAN)
  message(FATAL_ERROR "HOULE_SANITIZE and HOULE_TSAN exclude each other")
endif()
if(HOULE_TSAN)
  target_compile_options(houle_options INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(houle_options INTERFACE -fsanitize=thread)
endif()
if(HOULE_SANITIZE)
  target_compile_options(houle_options INTERFACE -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(houle_options INTERFACE -fsanitize=address,undefined)
endif()
