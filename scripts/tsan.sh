#!/usr/bin/env bash
# ThreadSanitizer run over lumar's threaded paths (issue 16), exactly as reported in the notes:
#  1. builds build-tsan/ (-DLUMAR_SANITIZE=thread, -O1 -g1, ccache, -j${JOBS:-2}) with only the targets
#     that run threads: capture_tests (PrefetchingSource's capture thread in its three modes,
#     ReconnectingSource under it), tracking_tests (HelperThread, the tracker's parallel window
#     search), app_tests (DetectionWorker, the status file) and lumar;
#  2. runs those tests' threaded suites (ctest regex below);
#  3. runs `lumar run` on the shipped scene's fake camera (640x480 at 15 fps: capture prefetch
#     just in time, the detection worker, the tracker's helper thread, the render loop, the
#     config watcher) for RUN_S seconds, then RELOADS times edits the file and runs RUN_S
#     seconds again, in turn: [tracking] by the edit alone (the config watcher's inotify; the
#     tracker and its worker are replaced), [tracking] with a SIGHUP, [camera]'s fps (a new
#     scene: camera, capture thread, GL context); stops it with SIGTERM. Fails when fewer
#     reloads than edits were logged.
# A data race fails the run: TSan's exit code 66 for a test, a "WARNING: ThreadSanitizer" line
# in lumar's log for the run (its log is kept in build-tsan/tsan-run/). The V4L2 and libcamera
# sources are not run: the virtual camera's LD_PRELOAD cannot follow TSan's runtime, and there
# is no camera here.
#   scripts/tsan.sh [ctest regex]        environment: LUMAR_TSAN_BUILD, JOBS, RUN_S (default 8),
#                                        RELOADS (default 2), TESTS=0 (only lumar and its run)
# tests/tsan.supp lists what TSan may ignore: third-party code only, each with its reason.
# The suite runs a smaller part of this on every build: ctest label `tsan` (tests/tsan) rebuilds
# only the threaded classes, their tests and `lumar run`'s loop with TSan (about 2 minutes), and
# runs that loop through its reloads; this script instruments all of lumar, the libraries those
# threads call included (the renderer, the config, the tracking), and runs the shipped scene.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${LUMAR_TSAN_BUILD:-$root/build-tsan}
regex=${1:-'PrefetchingSource|ReconnectingSource|DetectionWorker|HelperThread|TrackedPoses|StatusFile'}
run_s=${RUN_S:-8}
reload_count=${RELOADS:-2}
targets=(capture_tests tracking_tests app_tests lumar)
[ "${TESTS:-1}" != 0 ] || targets=(lumar)
if [ ! -f "$build/CMakeCache.txt" ]; then
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  # -O1 and line tables only (-g1): all a TSan report needs, and lumar's 237 build steps took
  # 22 min at -j2 beside a load of 7-13 (2 cores, ccache cold).
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMAR_SANITIZE=thread -DLUMAR_WERROR=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    "${launcher[@]}"
fi
for target in "${targets[@]}"; do
  cmake --build "$build" --target "$target" -j"${JOBS:-2}"
done
export TSAN_OPTIONS="suppressions=$root/tests/tsan.supp second_deadlock_stack=1 history_size=4 ${TSAN_OPTIONS:-}"
start=$(date +%s)
rc=0
if [ "${TESTS:-1}" != 0 ]; then
  ctest --test-dir "$build" -R "$regex" --output-on-failure -j1 || rc=$?
  echo "tsan.sh: $(($(date +%s) - start)) s of tests, ctest exit $rc"
fi

# `lumar run` with a reload, in a scratch copy of the shipped scene (its relative paths kept).
work=$build/tsan-run
rm -rf "$work"
mkdir -p "$work"
for entry in "$root"/daemon/assets/*/; do
  ln -s "$entry" "$work/$(basename "$entry")"
done
# The shipped calibration is for 1280x720, which lumar refuses for a 640x480 camera: the run
# uses the ideal camera lumar assumes without one.
sed -e 's/^width = 1280 /width = 640 /' -e 's/^height = 720/height = 480/' -e 's/^fps = 30.0 /fps = 15.0 /' \
  -e 's|^calibration = |# calibration = |' \
  -e 's|^\[output\]|[output]\nstatus_path = "status.json"|' "$root/daemon/assets/lumar.toml" >"$work/scene.toml"
run_start=$(date +%s)
"$build/lumar" run --config "$work/scene.toml" >"$work/lumar.log" 2>&1 &
pid=$!
frames() { sed -n 's/.*"frames":\([0-9]*\).*/\1/p' "$work/status.json" 2>/dev/null || true; }
for _ in $(seq 1 600); do # the first frame: GL and the detector start slowly under TSan
  [ -n "$(frames)" ] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.5
done
if ! kill -0 "$pid" 2>/dev/null; then # refused the scene or crashed: nothing to wait for
  tail -n 5 "$work/lumar.log" >&2
  echo "tsan.sh: lumar run ended before its first frame; log $work/lumar.log" >&2
  exit 1
fi
sleep "$run_s"
toggle() { # toggle KEY A B: KEY's value A becomes B and B becomes A (sed -i renames a new file over the old one, as editors do)
  sed -i -e "s/^$1 = $2 /$1 = @ /" -e "s/^$1 = $3 /$1 = $2 /" -e "s/^$1 = @ /$1 = $3 /" "$work/scene.toml"
}
sed -i 's/^filter_beta = 40.0$/filter_beta = 40.0 /' "$work/scene.toml"
for i in $(seq 1 "$reload_count"); do
  case $((i % 3)) in
    1) toggle filter_beta 40.0 30.0 ;;                                    # the watcher alone
    2) toggle filter_beta 40.0 30.0 && kill -HUP "$pid" 2>/dev/null || true ;; # and a SIGHUP
    0) toggle fps 15.0 12.0 ;; # [camera]: a new camera, GL context and everything else
  esac
  # Under TSan a reload takes 7-33 s (load 12): the next edit waits for this one's reload, or
  # the watcher would rightly merge the two and the count below would fall short.
  for _ in $(seq 1 360); do
    [ "$(grep -c "reloaded" "$work/lumar.log" || true)" -ge "$i" ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.5
  done
  sleep "$run_s"
done
before=$(frames)
kill -TERM "$pid" 2>/dev/null || true
run_rc=0
wait "$pid" || run_rc=$?
races=$(grep -c "WARNING: ThreadSanitizer" "$work/lumar.log" || true)
reloads=$(grep -c "reloaded" "$work/lumar.log" || true)
echo "tsan.sh: lumar run $(($(date +%s) - run_start)) s, ${before:-0} frames, $reloads reload line(s)," \
  "exit $run_rc, $races TSan report(s); log $work/lumar.log"
if [ "$run_rc" -ne 0 ] || [ "$races" -ne 0 ] || [ -z "$before" ] || [ "$reloads" -lt "$reload_count" ]; then
  rc=1
fi
exit $rc
