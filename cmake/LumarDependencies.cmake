# Every dependency is a Debian 12 package (scripts/install-deps.sh installs them all) found
# through its CMake package or pkg-config.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(glm REQUIRED CONFIG)
find_package(nlohmann_json REQUIRED CONFIG)
find_package(TinyGLTF REQUIRED CONFIG)
find_package(tomlplusplus REQUIRED CONFIG)
# The command line (daemon/cli/lumar_command_line.cpp); header-only, Debian 12 has 2.1.2.
find_package(CLI11 REQUIRED CONFIG)
# Mesh simplification for the environment maps' stand-ins; Debian 12 has 0.18.
find_package(meshoptimizer REQUIRED CONFIG)

pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
pkg_check_modules(GLESV2 REQUIRED IMPORTED_TARGET glesv2)
pkg_check_modules(APRILTAG REQUIRED IMPORTED_TARGET apriltag)
pkg_check_modules(SYSTEMD REQUIRED IMPORTED_TARGET libsystemd)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
pkg_check_modules(WEBP REQUIRED IMPORTED_TARGET libwebp) # EXT_texture_webp images
# The KMS display sink: DRM/KMS modesetting (libdrm) and scan-out buffers for EGL (GBM).
pkg_check_modules(LIBDRM REQUIRED IMPORTED_TARGET libdrm)
pkg_check_modules(GBM REQUIRED IMPORTED_TARGET gbm)
# The preview window (gles_renderer/window): Xlib, with EGL's X11 platform.
pkg_check_modules(X11 REQUIRED IMPORTED_TARGET x11)
# Printable markers (daemon/markers): PDF, SVG and PNG pages; Debian 12 has 1.16.
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)
# MJPEG cameras (decode) and the virtual camera's MJPEG output (encode); Debian 12 has 2.1.5.
pkg_check_modules(TURBOJPEG REQUIRED IMPORTED_TARGET libturbojpeg)
# libcamera cameras (CSI sensors behind an ISP; UVC through its uvcvideo pipeline); Debian 12
# has 0.0.3. Its headers are included as system headers: their warnings are not ours to fail
# the build on (-Wpedantic -Wshadow -Werror).
pkg_check_modules(LIBCAMERA REQUIRED IMPORTED_TARGET libcamera)
set_target_properties(PkgConfig::LIBCAMERA PROPERTIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${LIBCAMERA_INCLUDE_DIRS}")

# Debian ships OpenCV's CMake package only with the all-modules libopencv-dev (which drags
# in VTK, Qt and more); we need four modules, so find them one by one.
include(FindOpenCVModules)

find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

# Compressed glTF geometry (gles_renderer/assets/gltf_compression.h), each decoder optional:
# without one, a model that requires its extension is refused with a message naming it.
# KHR_draco_mesh_compression: Debian 12 has libdraco-dev 1.5.5.
find_package(draco CONFIG QUIET)
option(LUMAR_WITH_DRACO "Decode KHR_draco_mesh_compression glTF models (libdraco-dev)" ${draco_FOUND})
if(LUMAR_WITH_DRACO AND NOT draco_FOUND)
  message(FATAL_ERROR "LUMAR_WITH_DRACO is ON but libdraco-dev is not installed (scripts/install-deps.sh)")
endif()
# EXT_meshopt_compression: meshoptimizer's decoder (the library is required above anyway).
option(LUMAR_WITH_MESHOPT_DECODER "Decode EXT_meshopt_compression glTF models (libmeshoptimizer-dev)" ON)
