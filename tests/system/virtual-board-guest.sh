#!/bin/sh
# The virtual board test's steps inside the guest (run by the initramfs's /init from the
# host's run directory, mounted over 9p as the current directory). Each step prints
# "LUMAR-VB: step NAME ok" or "LUMAR-VB: step NAME FAILED: why" and leaves its logs and
# results here for the host, which judges the images (virtual_board_check). A step that
# shows something on screen asks the host for a screendump ("LUMAR-VB: screendump NAME") and
# waits for NAME.done.
status=0
ok() { echo "LUMAR-VB: step $1 ok"; }
failed() { echo "LUMAR-VB: step $1 FAILED: $2"; status=1; }
uptime_s() { cut -d' ' -f1 /proc/uptime; }
# Runs `lumar run --config /tmp/NAME.toml --frames FRAMES` (its [output] path must be
# /tmp/NAME.png) and leaves NAME.log and NAME.png here for the host, saying how long it took;
# on failure shows the log's tail and returns non-zero.
still() { # NAME FRAMES
  t0=$(uptime_s)
  if lumar run --config "/tmp/$1.toml" --frames "$2" >"$1.log" 2>&1 && cp "/tmp/$1.png" "$1.png"; then
    echo "$1: $2 frames in $(awk -v a="$t0" -v b="$(uptime_s)" 'BEGIN { printf "%.1f", b - a }') s (lumar run, start to exit)"
    return 0
  fi
  tail -8 "$1.log"
  return 1
}

# --- probe: vivid's capture node with its formats, and the DRM device ------------------------
lumar probe >probe.txt 2>&1
sed 's/^/probe| /' probe.txt
if ! grep -q '^  /dev/video0: .*(driver vivid' probe.txt; then
  failed probe "vivid's /dev/video0 not listed"
elif ! grep -q '^    YUYV ' probe.txt; then
  failed probe "no YUYV format listed"
elif ! grep -q '^  /dev/dri/card0' probe.txt; then
  failed probe "no DRM device listed"
else
  ok probe
fi

# --- capture: vivid through V4L2 into a headless still ----------------------------------------
cat >/tmp/capture.toml <<'EOF'
board = "qemu-virtual-board"
[output]
path = "/tmp/capture.png"
EOF
if still capture 60; then
  ok capture
else
  failed capture "lumar run failed (capture.log)"
fi

# --- KMS: lumar run presenting on the DRM device, checked by the host's screendump ----------
# Starts lumar with CONFIG, waits until it has shown FRAMES frames (its status file), asks the
# host for a screendump, then stops lumar with SIGTERM and expects a clean exit.
present() { # NAME CONFIG FRAMES
  name=$1
  rm -f /tmp/status.json
  lumar run --config "$2" >"$name.log" 2>&1 &
  pid=$!
  frames=0
  for _ in $(seq 600); do
    kill -0 "$pid" 2>/dev/null || break
    frames=$(sed -n 's/.*"frames":\([0-9]*\).*/\1/p' /tmp/status.json 2>/dev/null)
    [ "${frames:-0}" -ge "$3" ] && break
    sleep 0.2
  done
  if ! kill -0 "$pid" 2>/dev/null; then
    wait "$pid"
    code=$?
    tail -5 "$name.log"
    failed "$name" "lumar run exited early with status $code ($name.log)"
    return
  fi
  if [ "${frames:-0}" -lt "$3" ]; then
    kill -TERM "$pid"; wait "$pid"
    failed "$name" "only ${frames:-0} frames shown in 120 s"
    return
  fi
  cp /tmp/status.json "$name.status.json"
  echo "LUMAR-VB: screendump $name"
  for _ in $(seq 600); do
    [ -e "$name.done" ] && break
    sleep 0.1
  done
  kill -TERM "$pid"
  wait "$pid"
  code=$?
  if [ ! -e "$name.done" ]; then
    failed "$name" "the host took no screendump"
  elif [ "$code" != 0 ]; then
    tail -5 "$name.log"
    failed "$name" "lumar run exited with status $code after SIGTERM ($name.log)"
  else
    echo "$name: $(cat "$name.status.json")"
    ok "$name"
  fi
}

if [ "$(cat kms)" = 1 ]; then
  # vivid's YCbCr frames converted in the renderer (zero-copy where EGL imports vivid's
  # dmabufs), shown through atomic commits.
  cat >/tmp/kms-bars.toml <<'EOF'
board = "qemu-virtual-board"
[camera]
convert = "gpu"
[output]
sink = "kms"
status_path = "/tmp/status.json"
EOF
  present kms-bars /tmp/kms-bars.toml 10
  # The tag scene: the same folder and model, so the configuration stays next to them. Shown
  # through the legacy KMS API (SetCrtc + PageFlip), the atomic path's fallback.
  { cat tags.toml; printf '\n[output]\nsink = "kms"\nkms_api = "legacy"\nstatus_path = "/tmp/status.json"\n'; } >tags-kms.toml
  present kms-tags tags-kms.toml 10
  grep -h 'KMS output\|dma-buf\|dmabuf\|zero-copy\|import' kms-bars.log kms-tags.log | sed 's/^/kms| /'
fi

# --- dmabuf: real dmabufs through EGL_EXT_image_dma_buf_import ------------------------------
# vgem gives llvmpipe a DRM device: Mesa's surfaceless display then runs kms_swrast on it and
# offers the dmabuf import. Loaded last, so the steps above render as they would without it.
if ! modprobe vgem; then
  failed dmabuf-import "modprobe vgem failed"
else
  # lumar's import path (dmabuf_image.h, the background pass) with buffers of the display's
  # own device, vgem's dumb buffers: every layout, matrix and range against the CPU converter.
  if gl_dmabuf_device_tests >dmabuf-import.log 2>&1 && grep -q '^\[  PASSED  \] 3 tests' dmabuf-import.log; then
    grep '^dmabuf import:' dmabuf-import.log
    ok dmabuf-import
  else
    grep -v '^\[ \|^$' dmabuf-import.log | tail -8
    failed dmabuf-import "the device import tests failed or skipped (dmabuf-import.log)"
  fi
  # vivid's buffers on that display: kms_swrast cannot map another device's dmabuf, so lumar
  # must refuse them up front and upload (Mesa 22.3 crashes on the first draw otherwise).
  cat >/tmp/dmabuf-camera.toml <<'EOF'
board = "qemu-virtual-board"
[camera]
convert = "gpu"
[output]
path = "/tmp/dmabuf-camera.png"
EOF
  if still dmabuf-camera 30; then
    grep -h 'dmabuf' dmabuf-camera.log | sed 's/^/dmabuf| /'
    if grep -q 'no dmabuf import (the EGL driver is kms_swrast' dmabuf-camera.log; then
      ok dmabuf-camera
    else
      failed dmabuf-camera "lumar did not refuse vivid's dmabufs on kms_swrast (dmabuf-camera.log)"
    fi
  else
    failed dmabuf-camera "lumar run failed with vivid on the vgem display (dmabuf-camera.log)"
  fi
fi

# --- libcamera: vimc through libcamera's vimc pipeline handler --------------------------------
# vimc (built by the host for this kernel) is a media-controller camera: sensor, debayer and
# scaler subdevices in front of a capture node, which libcamera configures end to end. Its
# sensor shows the same 75 % colour bars as vivid.
if ! modprobe vimc; then
  failed libcamera "modprobe vimc failed"
else
  for _ in $(seq 50); do [ -e /dev/media1 ] && break; sleep 0.1; done
  # libcamera lists only devices udev has initialised, i.e. that have a udev database entry;
  # this initramfs runs no udevd, so write the (empty) entries it would have.
  mkdir -p /run/udev/data
  for node in /sys/bus/media/devices/* /sys/class/video4linux/*; do
    [ -e "$node/dev" ] && : >"/run/udev/data/c$(cat "$node/dev")"
  done
  lumar probe >libcamera-probe.txt 2>&1
  sed -n '/^libcamera/,/^EGL/p' libcamera-probe.txt | sed '$d; s/^/libcamera-probe| /'
  # No board profile: the QEMU board's camera is vivid through V4L2 (YUYV first).
  cat >/tmp/libcamera.toml <<'EOF'
[camera]
source = "libcamera"
device = "auto"
format = "auto"
width = 640
height = 480
[camera.controls]
# Controls vimc does not have (it offers brightness, contrast, saturation): each must be
# reported and skipped, the stream must still run.
exposure_us = 8000
gain = 200
white_balance_k = 4000
power_line_hz = 50
[output]
path = "/tmp/libcamera.png"
EOF
  if still libcamera 30; then
    grep -h 'libcamera' libcamera.log | grep -v ' DEBUG ' | head -12 | sed 's/^/libcamera| /'
    if [ "$(grep -c 'has no .* control' libcamera.log)" -lt 3 ]; then
      failed libcamera "the controls vimc lacks were not reported (libcamera.log)"
    else
      ok libcamera
    fi
  else
    failed libcamera "lumar run with source = libcamera failed (libcamera.log)"
  fi
fi
exit "$status"
