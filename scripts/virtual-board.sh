#!/usr/bin/env bash
# The virtual board system test (DESIGN.md §7): boots Debian's own kernel under
# qemu-system-x86_64 (software emulation, no KVM) with busybox, lumar and its library closure
# (Mesa's llvmpipe through kms_swrast) in an initramfs, the vivid test camera and a bochs (or
# virtio-gpu) display, and runs lumar against the real kernel drivers:
#   probe     `lumar probe` lists vivid's capture node and the DRM device
#   capture   `lumar run` captures from vivid into a headless PNG: vivid's colour bars in order
#   kms-bars  `lumar run` presents vivid through KMS: the bars on screen (QEMU screendump)
#   kms-tags  `lumar run` presents the fake camera's tag scene through KMS: the virtual object
#             on screen where the ground-truth pose puts it
#   dmabuf-import  with vgem loaded (llvmpipe through kms_swrast on it, EGL_EXT_image_dma_buf_import):
#             gl_dmabuf_device_tests imports real dmabufs (vgem's dumb buffers) and draws them
#             like the uploaded planes; the texture is the buffer
#   dmabuf-camera  `lumar run` with vivid on that display: its dmabufs (another device's, which
#             kms_swrast cannot map) are refused up front, the bars still come out in order
#   libcamera `lumar run` with `source = "libcamera"` on vimc (built here for the guest's kernel)
#             through libcamera's vimc pipeline handler: its colour bars in order
# The kms-* steps run when this lumar accepts `[output] sink = "kms"`; before that the test
# stops after `capture` and exits 77 (skipped), so 0 always means every check passed.
#
#   scripts/virtual-board.sh [--build DIR] [--cache DIR] [--display bochs|virtio] [--no-kms]
#                            [--cold] [--keep]
#
#   --build DIR    a configured and built lumar tree with lumar and virtual_board_check
#                  (default: build)
#   --cache DIR    downloaded kernel, initramfs and run logs (default: BUILD/virtual-board;
#                  also LUMAR_VIRTUAL_BOARD_CACHE)
#   --display D    bochs: QEMU's standard VGA (bochs-drm, the default); virtio: virtio-vga
#   --no-kms       skip the kms-* steps even when the KMS sink is there (then exit 77)
#   --cold         start with an empty Mesa shader cache (the cache keeps llvmpipe's compiled
#                  shaders from one run to the next: compiling them under TCG takes longest)
#   --keep         keep the run directory (logs, screendumps) even when every check passes
#
# Exit status: 0 every check passed, 1 a check or the VM failed, 2 bad usage or missing tools,
# 77 the KMS checks were skipped (sink not available) after the others passed.
# Needs qemu-system-x86, busybox-static and cpio (scripts/install-deps.sh) and network access
# once, to fetch the kernel package into the cache.
set -euo pipefail

top=$(cd "$(dirname "$0")/.." && pwd)
build=$top/build
cache=${LUMAR_VIRTUAL_BOARD_CACHE:-}
display=bochs
keep=0
kms_wanted=1
cold=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --cache) cache=$2; shift 2 ;;
    --display) display=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    --no-kms) kms_wanted=0; shift ;;
    --cold) cold=1; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "virtual-board: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
build=$(realpath -e "$build" 2>/dev/null) || { echo "virtual-board: no build directory" >&2; exit 2; }
cache=$(realpath -m "${cache:-$build/virtual-board}")
case "$display" in
  bochs) qemu_display=(-vga std) ;;
  virtio) qemu_display=(-vga none -device virtio-vga) ;;
  *) echo "virtual-board: --display must be bochs or virtio" >&2; exit 2 ;;
esac

log() { echo "virtual-board: $*"; }
die() { echo "virtual-board: $*" >&2; exit "${2:-1}"; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

lumar=$build/lumar
checker=$build/tests/system/virtual_board_check
dmabuf_tests=$build/tests/gl/gl_dmabuf_device_tests
[ -x "$lumar" ] || die "$lumar not built (ninja -C $build lumar)" 2
[ -x "$checker" ] || die "$checker not built (ninja -C $build virtual_board_check)" 2
[ -x "$dmabuf_tests" ] || die "$dmabuf_tests not built (ninja -C $build gl_dmabuf_device_tests)" 2
for tool in qemu-system-x86_64 busybox cpio dpkg-deb apt-get ldd strip; do
  command -v "$tool" >/dev/null || die "$tool not found (scripts/install-deps.sh)" 2
done
# The initramfs has no C library of its own for busybox: it must be the static build.
ldd "$(command -v busybox)" >/dev/null 2>&1 && die "busybox is not statically linked (package busybox-static)" 2
mkdir -p "$cache"
started=$(now)

# --- Kernel: Debian's linux-image package, fetched once into the cache ----------------------
# The newest bookworm kernel the linux-image-amd64 metapackage points at; offline, whatever
# the cache already holds.
kernel_package=$(apt-cache depends linux-image-amd64 2>/dev/null |
  sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*-amd64\)$/\1/p' | head -1 || true)
if [ -z "$kernel_package" ]; then
  kernel_package=$(find "$cache/kernel" -maxdepth 1 -name 'linux-image-*-amd64' -printf '%f\n' 2>/dev/null |
    sort -V | tail -1)
  [ -n "$kernel_package" ] || die "cannot find the bookworm kernel package (apt-cache depends linux-image-amd64)" 2
fi
kver=${kernel_package#linux-image-}
kdir=$cache/kernel/$kernel_package
if [ ! -e "$kdir/extracted" ]; then
  log "fetching $kernel_package"
  rm -rf "$kdir"
  mkdir -p "$kdir/deb"
  (cd "$kdir/deb" && apt-get download "$kernel_package" >/dev/null 2>&1) ||
    (cd "$kdir/deb" && apt-get download "$kernel_package") || die "apt-get download $kernel_package failed"
  dpkg-deb -x "$kdir"/deb/*.deb "$kdir/root"
  rm -rf "$kdir/deb"
  # The package ships no modules.dep (the postinst runs depmod); busybox's depmod writes the
  # modules.dep that busybox's modprobe reads in the guest.
  busybox depmod -b "$kdir/root" "$kver"
  touch "$kdir/extracted"
fi
vmlinuz=$kdir/root/boot/vmlinuz-$kver
moddir=$kdir/root/lib/modules/$kver
if [ ! -f "$vmlinuz" ] || [ ! -f "$moddir/modules.dep" ]; then
  die "$kdir: incomplete kernel tree (delete it to refetch)"
fi

# --- vimc and libcamera's IPA: a camera libcamera drives, for the libcamera step ------------
# Debian's kernel leaves vimc (the virtual media-controller camera, which libcamera's vimc
# pipeline handler drives) unbuilt, so the module is built here, once, for exactly this kernel:
# its headers and kbuild packages, and vimc's directory from the matching kernel source
# package. libcamera-ipa holds the vimc IPA module the pipeline handler loads.
vimc=$kdir/vimc
if [ ! -e "$vimc/built" ]; then
  log "building the vimc module for $kver (once)"
  t0=$(now)
  rm -rf "$vimc"
  mkdir -p "$vimc/deb" "$vimc/root" "$vimc/src"
  series=$(echo "$kver" | cut -d. -f1-2)                  # 6.1
  common=${kver%-*}-common                                # 6.1.0-57-common
  ipa_version=$(dpkg-query -W -f='${Version}' libcamera0.0.3 2>/dev/null || true)
  packages=("linux-headers-$kver" "linux-headers-$common" "linux-kbuild-$series" "linux-source-$series"
            "libcamera-ipa${ipa_version:+=$ipa_version}")
  (cd "$vimc/deb" && apt-get download "${packages[@]}" >/dev/null 2>&1) ||
    (cd "$vimc/deb" && apt-get download "${packages[@]}") || die "apt-get download ${packages[*]} failed"
  for deb in "$vimc"/deb/linux-headers-*.deb "$vimc"/deb/linux-kbuild-*.deb "$vimc"/deb/libcamera-ipa_*.deb; do
    dpkg-deb -x "$deb" "$vimc/root"
  done
  dpkg-deb --fsys-tarfile "$vimc"/deb/linux-source-*.deb |
    tar -xO "./usr/src/linux-source-$series.tar.xz" |
    tar -xJ -C "$vimc/src" --strip-components=5 "linux-source-$series/drivers/media/test-drivers/vimc"
  # The headers' Makefile includes the common tree by its installed path; point it here.
  headers=$vimc/root/usr/src/linux-headers-$kver
  sed -i "s#^include /usr/src/#include $vimc/root/usr/src/#" "$headers/Makefile"
  make -s -C "$headers" M="$vimc/src" CONFIG_VIDEO_VIMC=m modules >"$vimc/build.log" 2>&1 ||
    { cat "$vimc/build.log"; die "building vimc.ko failed"; }
  rm -rf "$vimc/deb"
  touch "$vimc/built"
  log "vimc.ko built in $(since "$t0") s"
fi

# --- Initramfs: busybox, the needed modules, lumar installed with its library closure --------
# Rebuilt when lumar, its installed files, this script or the kernel change. Left
# uncompressed: under TCG the kernel unpacks a compressed one more slowly than QEMU loads the
# plain file.
stamp=$( {
  sha256sum "$lumar" "$dmabuf_tests" "$vimc/src/vimc.ko" "$0" "$top/tests/system/virtual-board-init.sh"
  find "$top/board" "$top/daemon/assets" -type f -print0 | sort -z | xargs -0 sha256sum
  echo "$kver"
} | sha256sum | cut -c1-16)
initramfs=$cache/initramfs-$stamp.cpio
if [ ! -f "$initramfs" ]; then
  log "building the initramfs"
  t0=$(now)
  rm -f "$cache"/initramfs-*.cpio*
  root=$cache/rootfs
  rm -rf "$root"
  mkdir -p "$root"/{usr/bin,usr/sbin,usr/lib,usr/lib64,proc,sys,dev,tmp,run,mnt/host,etc}
  ln -s usr/bin "$root/bin"; ln -s usr/sbin "$root/sbin"
  ln -s usr/lib "$root/lib"; ln -s usr/lib64 "$root/lib64"

  cp "$(command -v busybox)" "$root/usr/bin/busybox"
  for applet in $(busybox --list); do
    [ -e "$root/usr/bin/$applet" ] || ln -s busybox "$root/usr/bin/$applet"
  done
  cp "$top/tests/system/virtual-board-init.sh" "$root/init"
  chmod 755 "$root/init"

  # Modules: the drivers and everything modules.dep says they need.
  # vimc's own dependencies (its modinfo "depends=") come from the kernel's tree.
  vimc_depends=$(strings "$vimc/src/vimc.ko" | sed -n 's/^depends=//p' | tr ',' ' ')
  wanted="vivid bochs virtio-gpu vgem virtio_pci 9pnet_virtio 9p $vimc_depends"
  mods=()
  for m in $wanted; do
    pattern=${m//[-_]/[-_]}
    line=$(grep -E "(^|/)${pattern}\\.ko:" "$moddir/modules.dep") || die "module $m not in $moddir"
    # shellcheck disable=SC2206
    mods+=(${line/:/})
  done
  for f in $(printf '%s\n' "${mods[@]}" | sort -u); do
    mkdir -p "$root/lib/modules/$kver/$(dirname "$f")"
    cp "$moddir/$f" "$root/lib/modules/$kver/$f"
  done
  mkdir -p "$root/lib/modules/$kver/extra"
  cp "$vimc/src/vimc.ko" "$root/lib/modules/$kver/extra/"
  cp "$moddir"/modules.{order,builtin} "$root/lib/modules/$kver/"
  busybox depmod -b "$root" "$kver"

  # lumar as `cmake --install` lays it out (bin, share/lumar with models and board profiles).
  DESTDIR=$cache/install cmake --install "$build" --prefix /usr >/dev/null
  cp -a "$cache/install/usr/." "$root/usr/"
  rm -rf "$cache/install"
  strip --strip-debug "$root/usr/bin/lumar"
  cp "$dmabuf_tests" "$root/usr/bin/"
  strip --strip-debug "$root/usr/bin/$(basename "$dmabuf_tests")"

  # Mesa: GBM, EGL through glvnd, and the one megadriver file llvmpipe is in (kms_swrast for
  # GBM on a dumb-buffer KMS device, swrast for surfaceless).
  libdir=/usr/lib/x86_64-linux-gnu
  mkdir -p "$root$libdir/dri" "$root/usr/share/glvnd/egl_vendor.d"
  cp "$libdir/dri/kms_swrast_dri.so" "$root$libdir/dri/"
  ln -s kms_swrast_dri.so "$root$libdir/dri/swrast_dri.so"
  cp /usr/share/glvnd/egl_vendor.d/50_mesa.json "$root/usr/share/glvnd/egl_vendor.d/"
  elves=("$lumar" "$dmabuf_tests" "$libdir/dri/kms_swrast_dri.so" "$libdir/libEGL_mesa.so.0" "$libdir/libgbm.so.1")
  for elf in "${elves[@]}"; do
    ldd "$elf" | awk '/=> \// { print $3 } /^[ \t]*\/.*ld-linux/ { print $1 }'
  done | sort -u | while read -r lib; do
    # The library under the name the loader looks for (its SONAME path), symlinks resolved.
    [ -e "$root$lib" ] || { mkdir -p "$root$(dirname "$lib")"; cp -L "$lib" "$root$lib"; }
  done
  # libcamera's IPA modules (with their signatures and proxies) and their configuration files.
  cp -a "$vimc/root/usr/lib/x86_64-linux-gnu/libcamera" "$root$libdir/"
  mkdir -p "$root/usr/share/libcamera"
  cp -a "$vimc/root/usr/share/libcamera/ipa" "$root/usr/share/libcamera/"
  for lib in "$libdir/libEGL_mesa.so.0" "$libdir/libgbm.so.1"; do
    [ -e "$root$lib" ] || cp -L "$lib" "$root$lib"
  done

  log "root file system $(du -sm "$root" | cut -f1) MB ($(du -sm "$root/usr/lib" | cut -f1) MB libraries)"
  (cd "$root" && find . | LC_ALL=C sort | cpio -o -H newc --quiet) >"$initramfs.partial"
  mv "$initramfs.partial" "$initramfs"
  rm -rf "$root"
  log "initramfs $(du -m "$initramfs" | cut -f1) MB built in $(since "$t0") s"
fi

# --- Run directory: shared with the guest over 9p ---------------------------------------------
run=$cache/run
rm -rf "$run"
mkdir -p "$run/share"
share=$run/share
cp "$top/tests/system/virtual-board-guest.sh" "$share/guest.sh"

# Does this lumar have the KMS sink? Then the guest runs the KMS steps too.
printf 'board = "qemu-virtual-board"\n[output]\nsink = "kms"\n' >"$run/kms-probe.toml"
if [ "$kms_wanted" = 0 ]; then
  kms=0
  log "KMS: the kms-* steps are skipped (--no-kms)"
elif "$lumar" check-config "$run/kms-probe.toml" >/dev/null 2>&1; then
  kms=1
else
  kms=0
  log "KMS: this lumar has no [output] sink = \"kms\" yet; the kms-* steps are skipped"
fi
echo "$kms" >"$share/kms"

# The tag scene: one fake-camera frame played in a loop, and the configuration that shows the
# object on it; the checker renders the frame (it knows its ground truth).
cp "$top/tests/system/virtual-board-tags.toml" "$share/tags.toml"
cp "$top/tests/data/models/BoxTextured.glb" "$share/"
cp "$top/daemon/assets/env/venice_sunset_1k.hdr" "$share/"
"$checker" scene "$share/tags.toml" >/dev/null 2>&1 || "$checker" scene "$share/tags.toml"

# llvmpipe's shader cache, carried from run to run through the share (the guest copies it to
# and from its tmpfs: Mesa maps its index file, which 9p cannot share).
shader_cache=$cache/mesa-shader-cache
[ "$cold" = 1 ] && rm -rf "$shader_cache"
[ -d "$shader_cache" ] && cp -a "$shader_cache" "$share/mesa-shader-cache"

# --- Boot ------------------------------------------------------------------------------------
serial=$run/serial.log
mkfifo "$run/monitor.in" "$run/monitor.out"
cat "$run/monitor.out" >"$run/monitor.log" &
monitor_reader=$!
log "booting $kernel_package ($display display, TCG)"
boot_started=$(now)
qemu-system-x86_64 -accel tcg -m 2G -smp 2 -nodefaults -no-reboot \
  "${qemu_display[@]}" -display none \
  -kernel "$vmlinuz" -initrd "$initramfs" \
  -append "console=ttyS0 quiet panic=-1 lumar.display=$display" \
  -virtfs local,path="$share",mount_tag=host,security_model=none,id=host \
  -serial file:"$serial" -monitor pipe:"$run/monitor" \
  >"$run/qemu.log" 2>&1 &
qemu=$!
cleanup() {
  kill "$qemu" 2>/dev/null || true
  kill "$monitor_reader" 2>/dev/null || true
}
trap cleanup EXIT

# Serve the guest's screendump requests ("LUMAR-VB: screendump NAME" on the serial console):
# dump the screen to NAME.ppm, wait until the file is whole, and answer with NAME.done in the
# share, which the guest waits for before it stops lumar.
timeout_s=${LUMAR_VIRTUAL_BOARD_TIMEOUT:-600}
served=" "
boot_s=""
while kill -0 "$qemu" 2>/dev/null; do
  if [ -z "$boot_s" ] && grep -q '^LUMAR-VB: userspace' "$serial" 2>/dev/null; then
    boot_s=$(since "$boot_started")
    log "user space after $boot_s s"
  fi
  for name in $(sed -n 's/^LUMAR-VB: screendump \([a-z0-9-]*\)\r\{0,1\}$/\1/p' "$serial" 2>/dev/null); do
    case "$served" in *" $name "*) continue ;; esac
    served="$served$name "
    echo "screendump $run/$name.ppm" >"$run/monitor.in"
    for _ in $(seq 100); do
      if [ -s "$run/$name.ppm" ]; then
        dims=$(head -c 20 "$run/$name.ppm" | tr '\n' ' ' | awk '{ print $2 * $3 * 3 }')
        header=$(head -c 20 "$run/$name.ppm" | head -n 3 | wc -c)
        [ "$(stat -c %s "$run/$name.ppm")" -ge $((dims + header)) ] && break
      fi
      sleep 0.1
    done
    log "screendump $name: $(head -c 20 "$run/$name.ppm" | head -n 2 | tail -1 | tr ' ' 'x')"
    touch "$share/$name.done"
  done
  if [ "$(since "$boot_started" | cut -d. -f1)" -ge "$timeout_s" ]; then
    log "the VM ran past ${timeout_s} s; stopping it"
    break
  fi
  sleep 0.2
done
wait "$qemu" 2>/dev/null || true
run_s=$(since "$boot_started")
if [ -d "$share/mesa-shader-cache" ]; then
  rm -rf "$shader_cache"
  cp -a "$share/mesa-shader-cache" "$shader_cache"
fi

# --- Results ---------------------------------------------------------------------------------
tr -d '\r' <"$serial" >"$run/console.txt"
log "guest console:"
grep -v '^LUMAR-VB: screendump' "$run/console.txt" | sed 's/^/  | /'
failed=0
step() { grep -q "^LUMAR-VB: step $1 ok" "$run/console.txt"; }
png_size() { # WIDTHxHEIGHT from a PNG's IHDR (big-endian at bytes 16-23)
  od -An -tu1 -j16 -N8 "$1" | awk '{ printf "%dx%d", $1 * 16777216 + $2 * 65536 + $3 * 256 + $4, $5 * 16777216 + $6 * 65536 + $7 * 256 + $8 }'
}
check() { # NAME COMMAND...: run a host-side check and report it
  local name=$1; shift
  if "$@" >"$run/$name.check" 2>&1; then
    log "$name: ok: $(tail -1 "$run/$name.check")"
  else
    log "$name: FAILED"; sed 's/^/  /' "$run/$name.check"; failed=1
  fi
}
grep -q '^LUMAR-VB: done' "$run/console.txt" || { log "the guest did not finish"; failed=1; }
for s in probe capture; do step "$s" || { log "step $s failed in the guest"; failed=1; }; done
if [ -f "$share/capture.png" ]; then
  check capture-bars "$checker" bars "$share/capture.png" --camera 640x480
else
  log "capture: no capture.png came back"; failed=1
fi
if [ "$kms" = 1 ]; then
  for s in kms-bars kms-tags; do step "$s" || { log "step $s failed in the guest"; failed=1; }; done
  if [ -f "$run/kms-bars.ppm" ]; then
    check screen-bars "$checker" bars "$run/kms-bars.ppm" --camera 640x480
  else
    log "kms-bars: no screendump"; failed=1
  fi
  if [ -f "$run/kms-tags.ppm" ]; then
    check screen-tags "$checker" object "$run/kms-tags.ppm" "$share/tags.toml"
  else
    log "kms-tags: no screendump"; failed=1
  fi
fi
for s in dmabuf-import dmabuf-camera libcamera; do step "$s" || { log "step $s failed in the guest"; failed=1; }; done
if [ -f "$share/dmabuf-camera.png" ]; then
  check dmabuf-camera-bars "$checker" bars "$share/dmabuf-camera.png" --camera 640x480
else
  log "dmabuf-camera: no dmabuf-camera.png came back"; failed=1
fi
if [ -f "$share/libcamera.png" ]; then
  # libcamera settles the size with vimc (multiples of 6): the still is the camera frame.
  check libcamera-bars "$checker" bars "$share/libcamera.png" --camera "$(png_size "$share/libcamera.png")"
else
  log "libcamera: no libcamera.png came back"; failed=1
fi

log "boot to user space ${boot_s:-?} s, VM run ${run_s} s, total $(since "$started") s"
if [ "$failed" != 0 ]; then
  log "FAILED (logs in $run)"
  exit 1
fi
[ "$keep" = 1 ] || rm -rf "$run"
if [ "$kms" != 1 ]; then
  log "probe and capture checks passed; KMS checks skipped"
  exit 77
fi
log "all checks passed"
