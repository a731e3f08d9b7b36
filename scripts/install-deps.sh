#!/usr/bin/env bash
# Installs every build, run and test dependency of lumar from Debian 12 packages; with
# --build-only, just what building and running lumar needs (no test tools, no QEMU). Idempotent: packages already present are left alone. Works as root or through sudo.
set -euo pipefail

# What building and running lumar needs (scripts/demo.sh installs only these: --build-only).
build_packages=(
  build-essential cmake ninja-build pkg-config git
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev
  libglm-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-calib3d-dev
  libapriltag-dev
  libtinygltf-dev nlohmann-json3-dev libstb-dev libwebp-dev
  libmeshoptimizer-dev
  libdraco-dev # KHR_draco_mesh_compression glTF models (optional: LUMAR_WITH_DRACO)
  libturbojpeg0-dev
  libcamera-dev
  libtomlplusplus-dev
  libcli11-dev # the command line (daemon/cli/lumar_command_line.cpp)
  libcairo2-dev # lumar markers: PDF, SVG and PNG pages (daemon/markers)
  libx11-dev # the preview window (gles_renderer/window), on EGL's X11 platform
  libxext-dev # the preview window's MIT-SHM presentation on a software rasteriser
  libwayland-dev wayland-protocols libxkbcommon-dev # the preview window on Wayland (optional: LUMAR_WITH_WAYLAND)
  libfreetype-dev fonts-dejavu-core # the overlay's font, rasterised at build time (gles_renderer/overlay)
  libsystemd-dev
  glslang-tools
)
# What the test suite needs on top.
test_packages=(
  dpkg-dev file # scripts/check-deb.sh: the Debian package and its Depends
  libopencv-imgcodecs-dev # tests only: they read and write images with OpenCV
  libopencv-contrib-dev # optional: the ArUco column of lumar-bench-tracking
  v4l-utils # v4l2-compliance and v4l2-ctl against the virtual camera
  libgtest-dev googletest
  clang-format
  poppler-utils # pdftoppm: the markers test renders the PDF it prints
  xvfb xauth # the preview window tests run their own X server
  weston # the Wayland preview window's tests run a headless weston
  qemu-system-x86 busybox-static cpio # scripts/virtual-board.sh: the virtual board system test
  python3-matplotlib # scripts/soak.sh: the soak's PNG plot (without it, an SVG)
)
packages=("${build_packages[@]}")
[ "${1:-}" = "--build-only" ] || packages+=("${test_packages[@]}")

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
