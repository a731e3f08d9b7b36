#!/usr/bin/env bash
# Configures and builds lumar into build/ (or $LUMAR_BUILD_DIR). Extra arguments go to cmake.
# With LUMAR_BUILD_TARGET set (e.g. lumar) only that target and what it needs are built.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUMAR_BUILD_DIR:-$top/build}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S "$top" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMAR_WERROR=ON "$@" >/dev/null
cmake --build "$build" -j "$jobs" ${LUMAR_BUILD_TARGET:+--target "$LUMAR_BUILD_TARGET"}
