# Finds the OpenCV modules lumar uses from Debian's per-module -dev packages and defines the
# imported target lumar::opencv.
find_path(OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
set(_lumar_opencv_libs)
foreach(module core imgproc calib3d imgcodecs)
  find_library(OPENCV_${module}_LIBRARY NAMES opencv_${module} REQUIRED)
  list(APPEND _lumar_opencv_libs ${OPENCV_${module}_LIBRARY})
endforeach()
add_library(lumar_opencv INTERFACE)
target_include_directories(lumar_opencv SYSTEM INTERFACE ${OPENCV_INCLUDE_DIR})
target_link_libraries(lumar_opencv INTERFACE ${_lumar_opencv_libs})
add_library(lumar::opencv ALIAS lumar_opencv)
message(STATUS "OpenCV modules: ${_lumar_opencv_libs}")
