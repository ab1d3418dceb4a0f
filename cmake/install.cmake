# Installing latticedyn as a library: `cmake --install build --prefix P` puts the static libraries,
# the headers (P/include/latticedyn/<layer>/*.hpp), the `latticedyn` program, a CMake package
# (find_package(latticedyn), target latticedyn::latticedyn) and a pkg-config file in place.
include(CMakePackageConfigHelpers)

# Everything a program needs, in one target: every layer (the driver's simulation flow and the
# facade, api/simulator.hpp, on top).
add_library(latticedyn_library INTERFACE)
target_link_libraries(latticedyn_library INTERFACE latticedyn_api)
set_target_properties(latticedyn_library PROPERTIES EXPORT_NAME latticedyn)
add_library(latticedyn::latticedyn ALIAS latticedyn_library)

set(_layers latticedyn_core latticedyn_control latticedyn_elements latticedyn_assembly latticedyn_timestepping latticedyn_io
            latticedyn_driver latticedyn_api)
install(TARGETS ${_layers} latticedyn_library latticedyn_options latticedyn_metis
        EXPORT latticedynTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS latticedyn RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(layer core control elements assembly timestepping io drivers api)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/latticedyn/${layer}
          FILES_MATCHING PATTERN "*.hpp")
endforeach()

set(_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/latticedyn)
install(EXPORT latticedynTargets NAMESPACE latticedyn:: DESTINATION ${_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/latticedynConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/latticedynConfig.cmake INSTALL_DESTINATION ${_cmake_dir})
# 0.x: a minor version may change the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/latticedynConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/latticedynConfig.cmake ${PROJECT_BINARY_DIR}/latticedynConfigVersion.cmake
        DESTINATION ${_cmake_dir})

# pkg-config: the libraries in link order, the dependencies by their own .pc files.
set(LATTICEDYN_PC_ARCH "")
if(LATTICEDYN_ARCH)
  set(LATTICEDYN_PC_ARCH "-march=${LATTICEDYN_ARCH}")
endif()
# The way up from <libdir>/pkgconfig to the prefix ("../.." for lib/pkgconfig).
string(REGEX REPLACE "[^/]+" ".." LATTICEDYN_PC_UP "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
configure_file(${PROJECT_SOURCE_DIR}/cmake/latticedyn.pc.in ${PROJECT_BINARY_DIR}/latticedyn.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/latticedyn.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
