# Every dependency comes from a Debian package. Each work-around below names the packaging bug it avoids.
find_package(Threads REQUIRED)

# GLM and xsimd are header-only. Cross builds cannot find their host configs (the find root is the
# target sysroot), so they use the host headers through a private symlink folder: never
# -isystem /usr/include, which would put the host's libc headers ahead of the target's.
if(NOT CMAKE_CROSSCOMPILING)
  find_package(glm CONFIG QUIET)
  find_package(xsimd 8 CONFIG QUIET)
endif()
add_library(houle_headeronly INTERFACE)
if(TARGET glm::glm AND TARGET xsimd)
  # xsimd 8.1's exported target links a library "xtl" that Debian 12 does not ship.
  set_property(TARGET xsimd PROPERTY INTERFACE_LINK_LIBRARIES "")
  target_link_libraries(houle_headeronly INTERFACE glm::glm xsimd)
else()
  set(_hdr ${CMAKE_BINARY_DIR}/host-headers)
  file(MAKE_DIRECTORY ${_hdr})
  foreach(d glm xsimd)
    if(NOT EXISTS /usr/include/${d})
      message(FATAL_ERROR "/usr/include/${d} is missing: run scripts/setup")
    endif()
    file(CREATE_LINK /usr/include/${d} ${_hdr}/${d} SYMBOLIC)
  endforeach()
  target_include_directories(houle_headeronly SYSTEM INTERFACE $<BUILD_INTERFACE:${_hdr}>)
endif()
# GLM >= 1.0 refuses gtx headers without this; 0.9.9.8 only warns.
target_compile_definitions(houle_headeronly INTERFACE GLM_ENABLE_EXPERIMENTAL GLM_FORCE_XYZW_ONLY)

if(HOULE_WITH_OIIO AND NOT CMAKE_CROSSCOMPILING)
  find_package(OpenImageIO 2.4 CONFIG REQUIRED)
  # OIIO 2.4.7's export lists /usr/include/opencv4, which is absent unless OpenCV's headers are installed.
  foreach(t OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
    get_target_property(inc ${t} INTERFACE_INCLUDE_DIRECTORIES)
    set(keep "")
    foreach(i IN LISTS inc)
      if(EXISTS "${i}")
        list(APPEND keep "${i}")
      endif()
    endforeach()
    set_target_properties(${t} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${keep}")
  endforeach()
  find_package(tomlplusplus CONFIG QUIET)
else()
  set(HOULE_WITH_OIIO OFF)
endif()

if(HOULE_BUILD_TESTS)
  if(CMAKE_CROSSCOMPILING)
    # Debian ships GoogleTest's source; the host's libgtest cannot link into a foreign binary.
    set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
    set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
    add_subdirectory(/usr/src/googletest ${CMAKE_BINARY_DIR}/_googletest EXCLUDE_FROM_ALL SYSTEM)
  else()
    find_package(GTest CONFIG REQUIRED)
  endif()
  include(GoogleTest)
endif()

if(HOULE_BUILD_BENCH)
  if(CMAKE_CROSSCOMPILING)
    set(HOULE_BUILD_BENCH OFF)   # Debian ships no benchmark source; qemu timings mean nothing anyway
  else()
    find_package(benchmark CONFIG REQUIRED)
  endif()
endif()
