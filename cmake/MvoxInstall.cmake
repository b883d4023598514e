# `cmake --install`: the libraries, their headers, a CMake package (find_package(mvox CONFIG),
# with a version file) and a pkg-config file for the core.
#
#   find_package(mvox 0.1 CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE mvox::core)   # or mvox::sim, mvox::host
#
# The core needs GLM only. mvox::host, when it was built, is installed too (it needs libjpeg,
# libpng and zlib), with the modules that link libtiff, OpenCV and GDCM in PREFIX/lib/mvox,
# loaded when a run needs them: a program linking mvox::host never links any of those.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(mvox_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/mvox)

install(TARGETS mvox_core EXPORT mvoxCoreTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${MVOX_CORE_PUBLIC_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mvox)
install(EXPORT mvoxCoreTargets NAMESPACE mvox:: DESTINATION ${mvox_package_dir})

install(TARGETS mvox_sim EXPORT mvoxSimTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sim/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mvox-sim
        FILES_MATCHING PATTERN "*.h")
install(EXPORT mvoxSimTargets NAMESPACE mvox:: DESTINATION ${mvox_package_dir})

if(TARGET mvox_host)
  install(TARGETS mvox_host EXPORT mvoxHostTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  # The host's headers keep their folders (read/, write/, ...); the command line's are its own.
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mvox-host
          FILES_MATCHING PATTERN "*.h" PATTERN "cli" EXCLUDE)
  install(EXPORT mvoxHostTargets NAMESPACE mvox:: DESTINATION ${mvox_package_dir})
  # The modules that link libtiff, OpenCV and GDCM, where module_loader.cpp looks for them.
  install(TARGETS ${MVOX_MODULES} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/mvox)
endif()
if(TARGET mvox)
  install(TARGETS mvox RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET mvox-mpi)
  install(TARGETS mvox-mpi RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mvoxConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/mvoxConfig.cmake
                              INSTALL_DESTINATION ${mvox_package_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mvoxConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mvoxConfig.cmake ${PROJECT_BINARY_DIR}/mvoxConfigVersion.cmake
        DESTINATION ${mvox_package_dir})

configure_file(${PROJECT_SOURCE_DIR}/cmake/mvox-core.pc.in ${PROJECT_BINARY_DIR}/mvox-core.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/mvox-core.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
