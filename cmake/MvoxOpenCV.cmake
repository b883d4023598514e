# Imported targets opencv::core, opencv::imgproc, opencv::imgcodecs, visible in every directory,
# and opencv::highgui only when it is installed: it brings Qt, so mvox never links it and only the
# optional live window module (src/live_window/) does.
# Debian ships OpenCVConfig.cmake only with the all-modules package libopencv-dev, which pulls in
# VTK, Qt and the rest; we install just the modules we use and find them directly.
find_package(OpenCV QUIET COMPONENTS core imgproc imgcodecs)
if(OpenCV_FOUND)
  foreach(module core imgproc imgcodecs)
    if(NOT TARGET opencv::${module})
      add_library(opencv::${module} INTERFACE IMPORTED GLOBAL)
      target_link_libraries(opencv::${module} INTERFACE opencv_${module})
    endif()
  endforeach()
  if(TARGET opencv_highgui AND NOT TARGET opencv::highgui)
    add_library(opencv::highgui INTERFACE IMPORTED GLOBAL)
    target_link_libraries(opencv::highgui INTERFACE opencv_highgui)
  endif()
  return()
endif()

find_path(MVOX_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
foreach(module core imgproc imgcodecs)
  find_library(MVOX_OPENCV_${module}_LIBRARY opencv_${module} REQUIRED)
  if(NOT TARGET opencv::${module})
    add_library(opencv::${module} UNKNOWN IMPORTED GLOBAL)
    set_target_properties(opencv::${module} PROPERTIES
      IMPORTED_LOCATION "${MVOX_OPENCV_${module}_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${MVOX_OPENCV_INCLUDE_DIR}")
  endif()
endforeach()

# Optional: libopencv-highgui-dev, needed only for --show's window.
find_library(MVOX_OPENCV_highgui_LIBRARY opencv_highgui)
if(MVOX_OPENCV_highgui_LIBRARY AND EXISTS "${MVOX_OPENCV_INCLUDE_DIR}/opencv2/highgui.hpp")
  if(NOT TARGET opencv::highgui)
    add_library(opencv::highgui UNKNOWN IMPORTED GLOBAL)
    set_target_properties(opencv::highgui PROPERTIES
      IMPORTED_LOCATION "${MVOX_OPENCV_highgui_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${MVOX_OPENCV_INCLUDE_DIR}")
  endif()
else()
  message(STATUS "OpenCV highgui not found (libopencv-highgui-dev): no window for --show")
endif()
