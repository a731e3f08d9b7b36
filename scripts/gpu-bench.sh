#!/bin/bash
# The GPU figures of issue 18: `lumar bench --replay` on the car scene (daemon/assets/scenes/
# car.toml) at 1280x720 and 1920x1080, without and with the lens effects, on a machine with a GPU
# but neither lumar's build dependencies nor a network (the device machines lent to some
# sessions: NVIDIA's driver, EGL through libglvnd, root, no apt). Two steps:
#
#   scripts/gpu-bench.sh pack [BUNDLE]
#       Here, after a build (LUMAR_BUILD_DIR, default build): the stripped binary and the
#       shared libraries it loads, but glibc's, libstdc++'s and the GL ones (the GPU
#       machine's own, or libglvnd's), in BUNDLE/lumar.tar.xz, and libglvnd's Debian packages
#       (EGL, GLES, and the GLX that OpenCV's core links) in BUNDLE/deb. BUNDLE defaults to
#       .gpubench (ignored by git): ~17 MB, which travels with a copy of this tree.
#   scripts/gpu-bench.sh run [BUNDLE] [OUT]
#       There, in that copy's root: unpacks the bundle into a temporary folder, installs
#       libglvnd where the machine lacks a part of it (root), points it at NVIDIA's EGL
#       vendor file where there is one, prints `lumar probe`'s EGL part, and writes one `lumar bench
#       --json` per scene and size into OUT (default gpu-bench-out), then a table of them.
#       On a machine without a GPU it measures what EGL offers (llvmpipe), which checks the
#       bundle. FRAMES (default 600) sets the frames measured per run.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
command=${1:-}
bundle=${2:-$root/.gpubench}

pack() {
  local build=${LUMAR_BUILD_DIR:-$root/build}
  local binary=$build/lumar
  [ -x "$binary" ] || { echo "gpu-bench: no $binary: build first (scripts/build.sh)" >&2; exit 2; }
  local stage
  stage=$(mktemp -d)
  trap 'rm -rf "$stage"' RETURN
  mkdir -p "$stage/lib" "$bundle/deb"
  strip -o "$stage/lumar" "$binary"
  # Every library the loader resolves, but those a Linux machine with a GL driver has of its
  # own (glibc, the C++ runtime a newer release keeps compatible, libglvnd's dispatch that
  # the driver plugs into).
  ldd "$binary" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | while read -r name path; do
    case "$name" in
      libc.so.* | libm.so.* | libpthread.so.* | libdl.so.* | librt.so.* | ld-linux* | libstdc++.so.* | libgcc_s.so.*) ;;
      libEGL.so.* | libGLESv2.so.* | libGLdispatch.so.* | libGLX.so.* | libGL.so.* | libOpenGL.so.*) ;;
      *) cp -L "$path" "$stage/lib/$name" ;;
    esac
  done
  tar -C "$stage" -cJf "$bundle/lumar.tar.xz" lumar lib
  rm -f "$bundle"/deb/*.deb
  local sandbox=()
  [ "$(id -u)" != 0 ] || sandbox=(-o APT::Sandbox::User=root) # root downloads into its own folder
  (cd "$bundle/deb" && apt-get "${sandbox[@]}" download libegl1 libgles2 libglvnd0 libglx0 libgl1 libopengl0 >/dev/null)
  echo "gpu-bench: $(du -sh "$bundle" | cut -f1) in $bundle ($(find "$stage/lib" -type f | wc -l) libraries," \
    "$(find "$bundle/deb" -name '*.deb' | wc -l) packages)"
}

# car.toml with absolute paths, at WIDTH x HEIGHT, the lens effects on or off. Its calibration
# is the committed fake_camera_1280x720.yaml; at other sizes the fake camera runs without one,
# on its own intrinsics (defaultIntrinsics(), core/camera_model.h: the same 70-degree camera,
# principal point at the centre, which that file holds for 1280x720).
write_config() {
  local width=$1 height=$2 lens=$3 out=$4
  local assets=$root/daemon/assets
  local size="width = $width\nheight = $height"
  local calibration="s#^calibration = .*#&\n$size#"
  [ "${width}x${height}" = 1280x720 ] || calibration="s#^calibration = .*#$size#"
  sed -e "s#\"\.\./#\"$assets/#g" -e "$calibration" "$assets/scenes/car.toml" >"$out"
  if [ "$lens" = on ]; then
    printf '\n[rendering.lens]\nenabled = true\n' >>"$out"
  fi
}

run() {
  local out=$1
  [ -f "$bundle/lumar.tar.xz" ] || { echo "gpu-bench: no $bundle/lumar.tar.xz: run 'scripts/gpu-bench.sh pack' first" >&2; exit 2; }
  local work
  work=$(mktemp -d)
  trap 'rm -rf "$work"' RETURN
  tar -C "$work" -xJf "$bundle/lumar.tar.xz"
  local missing=
  for soname in libEGL.so.1 libGLESv2.so.2 libGLX.so.0 libGL.so.1 libOpenGL.so.0 libGLdispatch.so.0; do
    ldconfig -p | grep -q "^[[:space:]]*$soname " || missing="$missing $soname"
  done
  if [ -n "$missing" ]; then
    [ "$(id -u)" = 0 ] || { echo "gpu-bench: no$missing here, and installing libglvnd needs root" >&2; exit 1; }
    for package in "$bundle"/deb/*.deb; do dpkg -x "$package" /; done
    ldconfig
  fi
  if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ]; then
    for vendor in /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json /usr/share/glvnd/egl_vendor.d/10_nvidia.json; do
      if [ -f "$vendor" ]; then
        export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
        break
      fi
    done
  fi
  local lumar=$work/lumar
  export LD_LIBRARY_PATH=$work/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  mkdir -p "$out"
  # What renders here: the EGL platform, GL's renderer and extensions (a failed probe still
  # leaves the benches to say more).
  "$lumar" probe >"$work/probe.txt" 2>&1 || echo "gpu-bench: lumar probe failed ($?)"
  sed -n '/^EGL/,$p' "$work/probe.txt" | tee "$out/probe.txt"
  local frames=${FRAMES:-600}
  for size in 1280x720 1920x1080; do
    local width=${size%x*} height=${size#*x}
    for lens in off on; do
      local name=car_${size}_lens-$lens
      write_config "$width" "$height" "$lens" "$work/$name.toml"
      echo "== $name ($frames frames, replay)"
      # One run failing (a driver's limit at one size, say) leaves the others to run.
      "$lumar" bench --config "$work/$name.toml" --replay --frames "$frames" --no-profile --json \
        --log-level warn >"$out/$name.json" || { echo "gpu-bench: $name failed ($?)"; rm -f "$out/$name.json"; }
    done
  done
  python3 - "$out" <<'EOF'
import glob, json, os, sys
rows = []
for path in sorted(glob.glob(os.path.join(sys.argv[1], "car_*.json"))):
    r = json.load(open(path))
    frame = r.get("frame_ms", {})
    latency = r.get("latency_ms", {})
    rows.append((os.path.basename(path)[:-5], r.get("fps"), frame.get("p50"), frame.get("p99"),
                 latency.get("p50"), latency.get("p99"), r.get("peak_rss_mb")))
print("| run | fps | frame p50 / p99 ms | latency p50 / p99 ms | peak MiB |")
print("|---|---|---|---|---|")
for name, fps, f50, f99, l50, l99, peak in rows:
    print(f"| {name} | {fps} | {f50} / {f99} | {l50} / {l99} | {peak} |")
EOF
}

case "$command" in
  pack) pack ;;
  run) run "${3:-$root/gpu-bench-out}" ;;
  *) echo "usage: scripts/gpu-bench.sh pack [BUNDLE] | run [BUNDLE] [OUT]" >&2; exit 2 ;;
esac
