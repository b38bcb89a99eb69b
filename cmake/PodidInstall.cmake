include(CMakePackageConfigHelpers)
get_property(podid_modules GLOBAL PROPERTY PODID_MODULES)
install(TARGETS ${podid_modules} podid EXPORT podidTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET podid_cli)
  install(TARGETS podid_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(EXPORT podidTargets NAMESPACE podid::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/podid)
configure_package_config_file(cmake/podidConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/podidConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/podid)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/podidConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/podidConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/podidConfigVersion.cmake ${CMAKE_CURRENT_SOURCE_DIR}/cmake/FindMETIS.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/podid)
