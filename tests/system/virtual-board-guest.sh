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
t0=$(uptime_s)
if lumar run --config /tmp/capture.toml --frames 60 >capture.log 2>&1 && cp /tmp/capture.png capture.png; then
  echo "capture: 60 frames in $(awk -v a="$t0" -v b="$(uptime_s)" 'BEGIN { printf "%.1f", b - a }') s (lumar run, start to exit)"
  ok capture
else
  tail -5 capture.log
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
exit "$status"
