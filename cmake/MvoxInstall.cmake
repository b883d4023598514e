# `cmake --install`: the libraries, their headers, a CMake package (find_package(mvox CONFIG),
# with a version file) and a pkg-config file for the core.
#
#   find_package(mvox 0.1 CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE mvox::core)   # or mvox::sim, mvox::host
#
# The core needs GLM only. mvox::host, when it was built, is installed too, with the modules that
# find OpenCV and GDCM the way this build did; its package then finds them as well.
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
  install(FILES ${PROJECT_SOURCE_DIR}/cmake/MvoxOpenCV.cmake ${PROJECT_SOURCE_DIR}/cmake/MvoxGDCM.cmake
          DESTINATION ${mvox_package_dir})
endif()
if(TARGET mvox)
  install(TARGETS mvox RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET mvox_live_window)
  # Beside the executable, where LiveWindow looks first (src/picture/live_window.h).
  install(TARGETS mvox_live_window LIBRARY DESTINATION ${CMAKE_INSTALL_BINDIR})
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
