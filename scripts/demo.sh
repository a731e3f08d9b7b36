#!/usr/bin/env bash
# Installs dependencies, builds lumar and renders the built-in demo (fake camera, shipped
# model and HDR environment, headless) to out/demo.png and out/demo.y4m.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
bash "$top/scripts/install-deps.sh" --build-only
# Only the lumar binary, without the tests' packages and targets: scripts/test.sh switches the
# tests on in the same tree.
LUMAR_BUILD_TARGET=lumar bash "$top/scripts/build.sh" -DLUMAR_BUILD_TESTS=OFF
mkdir -p "$top/out"
"$top/build/lumar" render --frames 90 --out "$top/out/demo.png" --out "$top/out/demo.y4m"
echo "demo: look at $top/out/demo.png (last frame) and $top/out/demo.y4m (3 s video, e.g. 'mpv out/demo.y4m' or 'ffplay out/demo.y4m')"
