# Install the libraries, headers and a relocatable package config, so that an outside
# project can do find_package(Shore REQUIRED) and link shore::terrain, shore::water,
# shore::bullet (and shore::mesh, the meshes for rendering).
include(CMakePackageConfigHelpers)

install(TARGETS shore_core shore_threads shore_mesh shore_terrain shore_water shore_bullet
  EXPORT ShoreTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(_dir core mesh terrain water bullet)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${_dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()

set(SHORE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/Shore)
install(EXPORT ShoreTargets NAMESPACE shore:: DESTINATION ${SHORE_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ShoreConfig.cmake.in
  ${PROJECT_BINARY_DIR}/ShoreConfig.cmake INSTALL_DESTINATION ${SHORE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ShoreConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ShoreConfig.cmake ${PROJECT_BINARY_DIR}/ShoreConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/ShoreBullet.cmake
        DESTINATION ${SHORE_CMAKE_DIR})
