#!/usr/bin/env bash
# The README's plain install build, with CMake's default generator (Unix Makefiles), not the
# Ninja our scripts use: Make does not create the folders of a custom command's outputs and
# orders steps differently, so a build that only ever ran under Ninja can break there.
# Configures a scratch tree exactly as README.md "Installing" says, builds the lumar target,
# installs it into a scratch DESTDIR and renders a frame with the installed binary.
# Usage: scripts/check-plain-build.sh WORK_DIR
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
work=$1
jobs=$(nproc 2>/dev/null || echo 2)
rm -rf "$work"
mkdir -p "$work"
# Build type None (no optimisation, no debug information): this check is about the generator,
# and unoptimised code compiles in about half the time of the release build's.
cmake -S "$top" -B "$work/build" -G "Unix Makefiles" -DCMAKE_INSTALL_PREFIX=/usr -DLUMAR_BUILD_TESTS=OFF \
      -DCMAKE_BUILD_TYPE=None >"$work/configure.log"
generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$work/build/CMakeCache.txt")
[ "$generator" = "Unix Makefiles" ] || { echo "plain build: configured with '$generator'"; exit 1; }
cmake --build "$work/build" -j "$jobs" --target lumar >"$work/build.log" 2>&1 || { tail -n 30 "$work/build.log"; exit 1; }
DESTDIR="$work/root" cmake --install "$work/build" >/dev/null
"$work/root/usr/bin/lumar" render --frames 1 --out "$work/frame.png" --log-level warn
[ -s "$work/frame.png" ] || { echo "plain build: the installed lumar wrote no frame"; exit 1; }
echo "plain build ok: Unix Makefiles built and installed lumar"
