# Install rules and the CMake package, included by the top-level
# CMakeLists.txt after every target exists, only when HEDRA_INSTALL is on.
#
# Layout (GNUInstallDirs): headers in include/hedra/<library>/, static or
# shared libraries in lib/, the package (hedraConfig.cmake, its version file
# and hedraTargets.cmake) in lib/cmake/hedra/, hedra.pc in lib/pkgconfig/. Each library <name> is the
# target hedra_<name> with public headers in <name>/include/, exported as
# hedra::<name> (its EXPORT_NAME), so adding one is adding its name below.
# Private build-only helpers (hedra_warnings) are linked through
# $<BUILD_INTERFACE:...> and never appear in the export.
include(CMakePackageConfigHelpers)

set(HEDRA_INSTALLED_LIBRARIES hull collision)

set(HEDRA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/hedra
    CACHE STRING "Where to install hedra's CMake package files, relative to the prefix")

foreach(_library IN LISTS HEDRA_INSTALLED_LIBRARIES)
  install(TARGETS hedra_${_library} EXPORT hedraTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${_library}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()

install(EXPORT hedraTargets NAMESPACE hedra:: DESTINATION ${HEDRA_INSTALL_CMAKEDIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/hedraConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/hedraConfig.cmake
                              INSTALL_DESTINATION ${HEDRA_INSTALL_CMAKEDIR})
# 0.x releases may break the API between minor versions.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hedraConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hedraConfig.cmake ${PROJECT_BINARY_DIR}/hedraConfigVersion.cmake
        DESTINATION ${HEDRA_INSTALL_CMAKEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The pkg-config file, for builds without CMake (`pkg-config --cflags --libs
# hedra`): lib/pkgconfig/hedra.pc, its prefix found from its own place
# (${pcfiledir}) so the install can move. Libraries in link order (collision
# needs hull); Eigen's flags come through `Requires: eigen3`.
set(HEDRA_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH HEDRA_PC_PREFIX_FROM_PCDIR /prefix/${HEDRA_PKGCONFIG_DIR} /prefix)
string(REGEX REPLACE "/$" "" HEDRA_PC_PREFIX_FROM_PCDIR "${HEDRA_PC_PREFIX_FROM_PCDIR}")
set(HEDRA_PC_CFLAGS "")
if(HEDRA_ENABLE_ASSERTS)
  set(HEDRA_PC_CFLAGS " -DHEDRA_ENABLE_ASSERTS")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/hedra.pc.in ${PROJECT_BINARY_DIR}/hedra.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/hedra.pc DESTINATION ${HEDRA_PKGCONFIG_DIR})
