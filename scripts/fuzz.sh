#!/usr/bin/env bash
# Runs one libFuzzer target (tests/fuzz) for SECONDS:
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]
# TARGET: config board_profile material_sidecar gltf hdr calibration y4m mjpeg v4l2_frame v4l2_driver
# fake_camera.
# Builds build-fuzz/ (clang 14, -DLUMAR_FUZZ=ON: ASan, UBSan, coverage) on first use, seeds a
# working corpus from tests/fuzz/seeds/TARGET.txt and tests/fuzz/regressions/TARGET/, and
# leaves crashes in build-fuzz/fuzz-artifacts/TARGET/. A crash found becomes a regression
# input: copy it into tests/fuzz/regressions/TARGET/ and fix the loader (the suite's
# fuzz_smoke_TARGET replays it). Environment: LUMAR_FUZZ_BUILD (build folder), JOBS, MAX_LEN,
# BUILD=0 (run the target as built: while another fuzz.sh or a build uses the folder's ninja).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 2 ]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
target=$1
seconds=$2
shift 2
if [ ! -f "$root/tests/fuzz/seeds/$target.txt" ]; then
  echo "fuzz.sh: no fuzz target '$target' (see tests/fuzz/seeds/)" >&2
  exit 2
fi
build=${LUMAR_FUZZ_BUILD:-$root/build-fuzz}
if [ ! -f "$build/CMakeCache.txt" ]; then
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMAR_FUZZ=ON \
    -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 "${launcher[@]}"
fi
[ "${BUILD:-1}" = 0 ] || cmake --build "$build" --target "fuzz_$target" -j"${JOBS:-2}"

corpus=$build/fuzz-corpus/$target
artifacts=$build/fuzz-artifacts/$target
mkdir -p "$corpus" "$artifacts"
while read -r seed; do
  [ -n "$seed" ] || continue
  if [ -d "$root/$seed" ]; then
    find "$root/$seed" -type f -exec cp -n {} "$corpus/" \;
  else
    cp -n "$root/$seed" "$corpus/"
  fi
done <"$root/tests/fuzz/seeds/$target.txt"
find "$root/tests/fuzz/regressions/$target" -type f -exec cp -n {} "$corpus/" \;

case $target in
  config | board_profile | material_sidecar | fake_camera) dict=(-dict="$root/tests/fuzz/dict/toml.dict") ;;
  gltf) dict=(-dict="$root/tests/fuzz/dict/gltf.dict") ;;
  calibration) dict=(-dict="$root/tests/fuzz/dict/yaml.dict") ;;
  *) dict=() ;;
esac
# Targets write each input to a scratch file (the loaders take paths): in memory that is
# about 12 times faster than on this disk (calibration: 3,000 against 250 runs a second).
if [ -z "${TMPDIR:-}" ] && [ -w /dev/shm ]; then
  export TMPDIR=/dev/shm
fi
# -timeout: an input that takes 10 s is a stall (the issue's hangs); -rss_limit_mb: what a
# small appliance has.
"$build/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -max_len="${MAX_LEN:-65536}" -timeout=10 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/" "${dict[@]}" "$@" "$corpus"
