#!/usr/bin/env bash
# ThreadSanitizer run over lumar's threaded paths (issue 16): the prefetching and
# reconnecting capture sources, the detection worker, the status file and config reload, and
# `lumar run` itself in the integration tests that drive it with signals and reloads (its
# capture prefetch, detection worker and reload watcher threads). Builds build-tsan/
# (-DLUMAR_SANITIZE=thread) on first use; a data race fails the test that ran into it (TSan's
# exit code 66), with the report in the test's output or in lumar's log.
#   scripts/tsan.sh [ctest regex]
# tests/tsan.supp lists what TSan may ignore: third-party code only, each with its reason.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${LUMAR_TSAN_BUILD:-$root/build-tsan}
regex=${1:-'PrefetchingSource|ReconnectingSource|DetectionWorker|StatusFile|RunCommand|RunReload|RunNotify|slow_pacing|fault_campaign'}
if [ ! -f "$build/CMakeCache.txt" ]; then
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMAR_SANITIZE=thread "${launcher[@]}"
fi
cmake --build "$build" --target lumar capture_tests app_tests cli_tests slow_pacing_tests -j"${JOBS:-2}"
export TSAN_OPTIONS="suppressions=$root/tests/tsan.supp second_deadlock_stack=1 history_size=4 ${TSAN_OPTIONS:-}"
start=$(date +%s)
rc=0
ctest --test-dir "$build" -R "$regex" --output-on-failure -j1 || rc=$?
echo "tsan.sh: $(( $(date +%s) - start )) s of tests, ctest exit $rc"
exit $rc
