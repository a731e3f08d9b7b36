#!/usr/bin/env bash
# Soak (issue 16): runs `lumar run` on the fake camera for MINUTES and samples, every INTERVAL
# seconds, the process' resident memory, open file descriptors, threads, the GL objects alive
# (textures, buffers, vertex arrays, framebuffers, renderbuffers, samplers, programs,
# shaders: status.json's gl_objects, a census of the context, gl/gl_census.h) and the daemon's
# own fps, frames and capture-to-present latency (status.json) into a CSV, then plots the
# curves (scripts/soak_plot.py: a PNG with matplotlib, Debian's python3-matplotlib; an SVG
# without) and prints whether RSS, fds, threads or GL objects grew after the warm-up (the
# first fifth of the run).
#   scripts/soak.sh MINUTES [--interval S] [--out DIR] [--config FILE] [--lumar BINARY]
#   scripts/soak.sh --minutes MINUTES [...]       (the same; the issue's spelling)
# Default scene: the fake camera at 320x240, 10 fps (cheap enough to run beside a build);
# --config runs any scene instead (its [output] is replaced by a status file in DIR).
# Exits 1 when lumar died, did not stop cleanly on SIGTERM, or fds/threads/GL objects grew.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = --minutes ] && [ $# -ge 2 ]; then
  shift
fi
if [ $# -lt 1 ] || ! [[ $1 =~ ^[0-9]+([.][0-9]+)?$ ]]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
minutes=$1
shift
interval=5
out=$root/build/soak
config=
lumar=${LUMAR:-$root/build/lumar}
while [ $# -gt 0 ]; do
  case $1 in
    --interval) interval=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --config) config=$2; shift 2 ;;
    --lumar) lumar=$2; shift 2 ;;
    *) echo "soak.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$lumar" ] || { echo "soak.sh: no lumar binary at $lumar (build it, or --lumar)" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd) # the config names it, and resolves relative paths from its own folder
if [ -n "$config" ]; then
  # The scene's own tables (its [output] dropped: a second one is a TOML error) beside it, so
  # its relative paths still resolve; removed at the end.
  scene=$(dirname "$config")/.soak-$$.toml
  awk '/^\[output\]/ { skip = 1; next } /^\[/ { skip = 0 } !skip' "$config" >"$scene"
else
  scene=$out/soak.toml
  printf '[camera]\nwidth = 320\nheight = 240\nfps = 10\n' >"$scene"
fi
printf '[output]\npath = "%s/soak.png"\nstatus_path = "%s/status.json"\n' "$out" "$out" >>"$scene"
csv=$out/soak.csv
gl_kinds="textures buffers vertex_arrays framebuffers renderbuffers samplers programs shaders"
echo "t_s,rss_kb,fds,threads,fps,frames,latency_p50_ms,latency_p99_ms$(printf ',gl_%s' $gl_kinds)" >"$csv"

"$lumar" run --config "$scene" >"$out/lumar.log" 2>&1 &
pid=$!
cleanup() {
  kill -TERM "$pid" 2>/dev/null || true
  [ -z "$config" ] || rm -f "$scene"
}
trap cleanup EXIT
start=$(date +%s.%N)
end=$(awk -v s="$start" -v m="$minutes" 'BEGIN { printf "%.0f", s + m * 60 }')
field() { # field NAME FILE: a number from status.json ("" when absent or null)
  sed -n "s/.*\"$1\":\([-0-9.]*\).*/\1/p" "$2" 2>/dev/null | head -1 || true
}
while [ "$(date +%s)" -lt "$end" ]; do
  sleep "$interval"
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "soak.sh: lumar died; its log:" >&2
    tail -20 "$out/lumar.log" >&2
    exit 1
  fi
  t=$(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN { printf "%.1f", n - s }')
  rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status")
  threads=$(awk '/^Threads:/ { print $2 }' "/proc/$pid/status")
  fds=$(ls "/proc/$pid/fd" | wc -l)
  status=$out/status.json
  p50=$(sed -n 's/.*"p50":\([-0-9.]*\).*/\1/p' "$status" 2>/dev/null | head -1 || true)
  p99=$(sed -n 's/.*"p99":\([-0-9.]*\).*/\1/p' "$status" 2>/dev/null | head -1 || true)
  gl=
  for kind in $gl_kinds; do gl="$gl,$(field "$kind" "$status")"; done
  echo "$t,$rss,$fds,$threads,$(field fps "$status"),$(field frames "$status"),$p50,$p99$gl" >>"$csv"
done
kill -TERM "$pid"
rc=0
wait "$pid" || rc=$?
trap - EXIT
[ -z "$config" ] || rm -f "$scene"
grep -q "stopped after" "$out/lumar.log" || rc=1
# A PNG where some python3 has matplotlib (Debian's /usr/bin/python3 with python3-matplotlib),
# else the standard library's SVG.
plot=$out/soak.svg
python=python3
for candidate in python3 /usr/bin/python3; do
  if "$candidate" -c 'import matplotlib' 2>/dev/null; then
    python=$candidate
    plot=$out/soak.png
    break
  fi
done
"$python" "$root/scripts/soak_plot.py" "$csv" "$plot" || rc=1
echo "soak.sh: lumar exited $rc; samples $csv, plot $plot"
[ "$rc" -eq 0 ]
