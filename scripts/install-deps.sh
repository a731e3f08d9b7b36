#!/usr/bin/env bash
# Installs every build, run and test dependency of lumar from Debian 12 packages.
# Idempotent: packages already present are left alone. Works as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  dpkg-dev file
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev
  libglm-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-calib3d-dev
  libopencv-imgcodecs-dev # tests only: they read and write images with OpenCV
  libapriltag-dev
  libopencv-contrib-dev # optional: the ArUco column of lumar-bench-tracking
  libtinygltf-dev nlohmann-json3-dev libstb-dev
  libmeshoptimizer-dev
  libturbojpeg0-dev v4l-utils
  libcamera-dev
  libtomlplusplus-dev
  libcli11-dev # the command line (daemon/cli/lumar_command_line.cpp)
  libsystemd-dev
  libgtest-dev googletest
  glslang-tools
  clang-format
  qemu-system-x86 busybox-static cpio # scripts/virtual-board.sh: the virtual board system test
)

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
