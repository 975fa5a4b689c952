# Install rules and the Debian package. The installed tree is the build
# folder's layout: bin/plcrun, lib/libsoftplc-*.so, include/plc/...,
# lib/cmake/softplc/ (the CMake package), share/softplc/cell-template/.
include(CMakePackageConfigHelpers)

get_property(PLC_SDK_TARGETS GLOBAL PROPERTY PLC_SDK_TARGETS)
get_property(PLC_SDK_INCLUDE_DIRS GLOBAL PROPERTY PLC_SDK_INCLUDE_DIRS)
set(PLC_CMAKE_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/softplc)

install(TARGETS plcrun RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
# The other tools: the HMI bridge's process (plcrun starts it from beside
# itself), the HMI client and the simulated DeviceNet slaves.
foreach(tool plchmi plcctl dnslave)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  endif()
endforeach()
install(TARGETS ${PLC_SDK_TARGETS} EXPORT softplcTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(dir ${PLC_SDK_INCLUDE_DIRS})
  install(DIRECTORY ${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT runtime)
endforeach()
install(EXPORT softplcTargets NAMESPACE softplc:: DESTINATION ${PLC_CMAKE_PACKAGE_DIR}
        COMPONENT runtime)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/softplcConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/softplcConfig.cmake
                              INSTALL_DESTINATION ${PLC_CMAKE_PACKAGE_DIR}
                              PATH_VARS CMAKE_INSTALL_BINDIR CMAKE_INSTALL_INCLUDEDIR)
# The ABI version (plc/abi.hpp) guards the binary interface; the package
# version says which runtime a project asks for.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/softplcConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/softplcConfig.cmake
              ${PROJECT_BINARY_DIR}/softplcConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/softplc_cell_library.cmake
        DESTINATION ${PLC_CMAKE_PACKAGE_DIR} COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/runtime/plcrun/cell-template/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/softplc/cell-template COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/docs/config.md DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT runtime)

# cpack -G DEB (from the build folder): softplc_<version>_<arch>.deb.
set(CPACK_PACKAGE_NAME softplc)
set(CPACK_PACKAGE_VENDOR "softplc")
set(CPACK_PACKAGE_CONTACT "softplc developers <dev@softplc.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Soft-PLC runtime, FB library and SDK for cell projects")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
# Run-time libraries from the Debian archive (dpkg-shlibdeps finds them),
# and what a cell project needs to build against the headers.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# plcsweep (bin/plcsweep) is Python: campaign files need python3-yaml.
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libboost-dev (>= 1.74), cmake (>= 3.25), g++ (>= 4:12), python3, python3-yaml")
# The cell template's test uses GoogleTest; plcsweep's report matplotlib,
# its Dask executor (and a machine that is a Dask worker) python3-distributed.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS
    "libgtest-dev, ninja-build, python3-matplotlib, python3-distributed")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
include(CPack)
