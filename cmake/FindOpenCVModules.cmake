# Finds the OpenCV modules lumar uses from Debian's per-module -dev packages and defines the
# imported target lumar::opencv (plus lumar::opencv_imgcodecs for the tests, lumar::opencv_aruco
# for the tracking benchmark).
find_path(OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
set(_lumar_opencv_libs)
foreach(module core imgproc calib3d)
  find_library(OPENCV_${module}_LIBRARY NAMES opencv_${module} REQUIRED)
  list(APPEND _lumar_opencv_libs ${OPENCV_${module}_LIBRARY})
endforeach()
add_library(lumar_opencv INTERFACE)
target_include_directories(lumar_opencv SYSTEM INTERFACE ${OPENCV_INCLUDE_DIR})
target_link_libraries(lumar_opencv INTERFACE ${_lumar_opencv_libs})
add_library(lumar::opencv ALIAS lumar_opencv)
message(STATUS "OpenCV modules: ${_lumar_opencv_libs}")

# imgcodecs (image files) only for the tests and the tracking benchmark (bench/, never
# installed), which read and write images with OpenCV; lumar decodes with stb_image, so the
# binary and its package do not depend on imgcodecs' closure.
find_library(OPENCV_imgcodecs_LIBRARY NAMES opencv_imgcodecs REQUIRED)
add_library(lumar_opencv_imgcodecs INTERFACE)
target_link_libraries(lumar_opencv_imgcodecs INTERFACE lumar_opencv ${OPENCV_imgcodecs_LIBRARY})
add_library(lumar::opencv_imgcodecs ALIAS lumar_opencv_imgcodecs)

# Optional: OpenCV's contrib aruco module (Debian: libopencv-contrib-dev), only for the ArUco
# column of lumar-bench-tracking (bench/); without it that detector is skipped.
find_path(OPENCV_ARUCO_INCLUDE_DIR opencv2/aruco.hpp PATH_SUFFIXES opencv4)
find_library(OPENCV_aruco_LIBRARY NAMES opencv_aruco)
if(OPENCV_ARUCO_INCLUDE_DIR AND OPENCV_aruco_LIBRARY)
  add_library(lumar_opencv_aruco INTERFACE)
  target_link_libraries(lumar_opencv_aruco INTERFACE lumar_opencv ${OPENCV_aruco_LIBRARY})
  target_compile_definitions(lumar_opencv_aruco INTERFACE LUMAR_HAVE_ARUCO=1)
  add_library(lumar::opencv_aruco ALIAS lumar_opencv_aruco)
  message(STATUS "OpenCV aruco: ${OPENCV_aruco_LIBRARY}")
else()
  message(STATUS "OpenCV aruco: not found (lumar-bench-tracking skips the ArUco detector)")
endif()
