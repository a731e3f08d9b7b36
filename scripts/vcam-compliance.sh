#!/usr/bin/env bash
# Checks the virtual camera (tests/vcam, an LD_PRELOAD library) against the V4L2 tools that
# check kernel drivers: `v4l2-compliance -s` (every ioctl test plus MMAP streaming with no
# poll, select and epoll) and `v4l2-ctl --stream-mmap --stream-count=100`, once per pixel
# format it serves (the format offered first is the one streamed). Prints each tool's summary
# line and exits non-zero when any test fails or a stream comes short.
#
#   scripts/vcam-compliance.sh [BUILD_DIR]     (default: build; builds nothing itself)
#
# Needs v4l-utils (scripts/install-deps.sh) and a built lumar_vcam target.
set -euo pipefail

build_dir=${1:-build}
library=$(realpath -e "$build_dir/tests/vcam/liblumar_vcam.so" 2>/dev/null) || {
  echo "vcam-compliance: $build_dir/tests/vcam/liblumar_vcam.so not found (build the lumar_vcam target)" >&2
  exit 2
}
for tool in v4l2-compliance v4l2-ctl; do
  command -v "$tool" >/dev/null || { echo "vcam-compliance: $tool not found (package v4l-utils)" >&2; exit 2; }
done

# A node name the tools accept (/dev/videoN); nothing exists there, the library serves it.
device=/dev/video${LUMAR_VCAM_COMPLIANCE_MINOR:-63}
log_dir=$(mktemp -d)
trap 'rm -rf "$log_dir"' EXIT
failed=0

for format in YUYV NV12 MJPG GREY; do
  offered="$format,$(echo YUYV,NV12,MJPG,GREY | tr ',' '\n' | grep -vx "$format" | paste -sd,)"
  log="$log_dir/compliance-$format.txt"
  status=0
  env LD_PRELOAD="$library" LUMAR_VCAM_DEVICE="$device" LUMAR_VCAM_FORMATS="$offered" \
    v4l2-compliance -d "$device" -s >"$log" 2>&1 || status=$?
  summary=$(grep -E '^Total for ' "$log" | tail -1 || true)
  if [ -z "$summary" ]; then
    echo "v4l2-compliance $format: no summary (exit $status)"; tail -5 "$log"; failed=1
  else
    echo "v4l2-compliance $format: $summary"
    grep -E '^\s+fail: ' "$log" || true
    failures=$(sed -E 's/.*Failed: ([0-9]+).*/\1/' <<<"$summary")
    [ "$failures" = 0 ] && [ "$status" = 0 ] || failed=1
  fi

  # 30 fps, a camera's rate: at 120 fps a loaded 2-core machine (MJPEG encoding in the
  # device, the tool's own dequeueing) misses frames, as a real driver would drop them, and
  # the check below wants every sequence number.
  log="$log_dir/ctl-$format.txt"
  status=0
  env LD_PRELOAD="$library" LUMAR_VCAM_DEVICE="$device" LUMAR_VCAM_FORMATS="$offered" \
    v4l2-ctl -d "$device" --set-fmt-video=width=640,height=480,pixelformat="$format" --set-parm=30 \
    --stream-mmap --stream-count=100 --verbose >"$log" 2>&1 || status=$?
  frames=$(tr '\r' '\n' <"$log" | grep -c '^cap dqbuf' || true)
  last=$(tr '\r' '\n' <"$log" | grep '^cap dqbuf' | tail -1 | sed -E 's/.*seq: *([0-9]+).*/\1/')
  echo "v4l2-ctl $format: Total frames: $frames of 100, last sequence: ${last:-none}, exit status: $status"
  [ "$status" = 0 ] && [ "$frames" = 100 ] && [ "${last:-}" = 99 ] || failed=1
done

if [ "$failed" != 0 ]; then
  echo "vcam-compliance: FAILED"
  exit 1
fi
echo "vcam-compliance: all passed"
