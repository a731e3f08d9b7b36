#!/usr/bin/env bash
# Installs dependencies, builds lumar with warnings as errors and runs the whole test suite
# through ctest. With --sanitize it builds into build-asan/ with ASan and UBSan instead.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
bash "$top/scripts/install-deps.sh"
if [ "${1:-}" = "--sanitize" ]; then
  export LUMAR_BUILD_DIR=$top/build-asan
  bash "$top/scripts/build.sh" -DLUMAR_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
else
  export LUMAR_BUILD_DIR=$top/build
  bash "$top/scripts/build.sh"
fi
cd "$LUMAR_BUILD_DIR"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
