# `cmake --install` gives headers, libraries and houleConfig.cmake, so another project can
# find_package(houle) and link houle::kernel / houle::sim (tests/consumer checks it).
include(CMakePackageConfigHelpers)

foreach(dir kernel/runtime/include/houle kernel/surface/include/houle kernel/render/include/houle sim/include/houle)
  if(EXISTS ${PROJECT_SOURCE_DIR}/${dir})
    install(DIRECTORY ${dir} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endforeach()
set(_targets "")
foreach(t houle_kernel houle_surface_isa houle_render_isa houle_sim houle_sim_isa)
  if(TARGET ${t})
    list(APPEND _targets ${t})
  endif()
endforeach()
install(TARGETS ${_targets}
  EXPORT houleTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT houleTargets NAMESPACE houle:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/houle)

configure_package_config_file(cmake/houleConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/houleConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/houle)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/houleConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/houleConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/houleConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/houle)
