# Install rules and the package configuration for find_package(unisph).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS unisph EXPORT unisphTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/unisph DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT unisphTargets NAMESPACE unisph:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/unisph)
configure_package_config_file(cmake/unisphConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/unisphConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/unisph)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/unisphConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/unisphConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/unisphConfigVersion.cmake
              cmake/UnisphKernelSources.cmake cmake/UnisphCudaDialect.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/unisph)
