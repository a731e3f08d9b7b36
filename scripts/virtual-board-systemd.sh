#!/usr/bin/env bash
# The systemd virtual board (a manual system check, not a ctest; several minutes): installs
# lumar's .deb with apt into a fresh minimal Debian 12 (debootstrap), enables lumar.service,
# boots that system with Debian's kernel and its real systemd under qemu-system-x86_64 (TCG)
# and checks in the guest (tests/system/virtual-board-systemd-guest.sh) that the unit, with
# all its hardening, runs lumar on Mesa's llvmpipe:
#   enabled        lumar.service is enabled
#   active         it becomes active (Type=notify: READY=1 after the first frame)
#   status-text    `systemctl show -p StatusText` carries lumar's STATUS=
#   status-json    /run/lumar/status.json exists and another user can read it
#   reload         `systemctl reload lumar` makes lumar log "reloaded", same process
#   still-running  still active 10 s later, no restart (the watchdog is fed)
#   stop           `systemctl stop` ends it with Result=success
#   journal        no seccomp kills, EPERM/EACCES or failures in the unit's or kernel's journal
# and prints `systemd-analyze security lumar` from the guest.
#
#   scripts/virtual-board-systemd.sh [--build DIR | --deb FILE] [--cache DIR]
#                                    [--kernel-cache DIR] [--timeout S] [--keep]
#
#   --build DIR         a built lumar tree: its package is made with `cpack -G DEB` (default: build)
#   --deb FILE          use this lumar_*.deb instead
#   --cache DIR         debootstrap tarball, apt's downloaded packages, kernel, images, run logs
#                       (default: BUILD/virtual-board-systemd; also LUMAR_VIRTUAL_BOARD_SYSTEMD_CACHE)
#   --kernel-cache DIR  where the Debian kernel package is (or is fetched to) extracted, the
#                       layout scripts/virtual-board.sh uses (default: CACHE/kernel); e.g.
#                       BUILD/virtual-board/kernel to share that test's download
#   --timeout S         how long the VM may run (default 900)
#   --keep              keep the run directory (console log, disk image) even when all pass
#
# Exit status: 0 every check passed, 1 a check or the VM failed, 2 bad usage or missing tools.
# Needs root (debootstrap, chroot, file ownership in the image), debootstrap, qemu-system-x86,
# busybox-static, cpio, e2fsprogs, and network access the first time (the Debian mirror).
# A rerun reuses the debootstrap tarball and apt's packages (no network), rebuilding only the
# image with the current .deb.
set -euo pipefail

top=$(cd "$(dirname "$0")/.." && pwd)
build=$top/build
deb=""
cache=${LUMAR_VIRTUAL_BOARD_SYSTEMD_CACHE:-}
kernel_cache=""
timeout_s=900
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --deb) deb=$2; shift 2 ;;
    --cache) cache=$2; shift 2 ;;
    --kernel-cache) kernel_cache=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "virtual-board-systemd: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

log() { echo "virtual-board-systemd: $*"; }
die() { echo "virtual-board-systemd: $*" >&2; exit "${2:-1}"; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

[ "$(id -u)" = 0 ] || die "needs root (debootstrap, chroot, root-owned files in the image)" 2
for tool in debootstrap qemu-system-x86_64 busybox cpio mke2fs dpkg-deb apt-get chroot; do
  command -v "$tool" >/dev/null || die "$tool not found (apt-get install debootstrap qemu-system-x86 busybox-static cpio e2fsprogs)" 2
done
ldd "$(command -v busybox)" >/dev/null 2>&1 && die "busybox is not statically linked (package busybox-static)" 2
if [ -z "$deb" ]; then
  build=$(realpath -e "$build" 2>/dev/null) || die "no build directory $build" 2
fi
cache=$(realpath -m "${cache:-$build/virtual-board-systemd}")
kernel_cache=$(realpath -m "${kernel_cache:-$cache/kernel}")
mkdir -p "$cache"
started=$(now)

# --- The package ----------------------------------------------------------------------------
if [ -z "$deb" ]; then
  log "cpack -G DEB in $build"
  rm -rf "$cache/deb"
  (cd "$build" && cpack -G DEB -B "$cache/deb" >"$cache/cpack.log" 2>&1) || { cat "$cache/cpack.log"; die "cpack failed"; }
  deb=$(find "$cache/deb" -maxdepth 1 -name 'lumar_*_amd64.deb' | head -n 1)
  [ -n "$deb" ] || die "cpack made no lumar_*_amd64.deb"
fi
deb=$(realpath -e "$deb") || die "no package $deb" 2
log "package $(basename "$deb"): Depends: $(dpkg-deb -f "$deb" Depends)"

# --- Kernel: Debian's linux-image package (as scripts/virtual-board.sh fetches it) ----------
kernel_package=$(find "$kernel_cache" -maxdepth 2 -name extracted -path '*/linux-image-*-amd64/*' -printf '%h\n' 2>/dev/null |
  xargs -rn1 basename | sort -V | tail -1)
if [ -z "$kernel_package" ]; then
  kernel_package=$(apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*-amd64\)$/\1/p' | head -1 || true)
  [ -n "$kernel_package" ] || die "cannot find the bookworm kernel package (apt-cache depends linux-image-amd64)" 2
  kdir=$kernel_cache/$kernel_package
  log "fetching $kernel_package"
  rm -rf "$kdir"
  mkdir -p "$kdir/deb"
  (cd "$kdir/deb" && apt-get download "$kernel_package") || die "apt-get download $kernel_package failed"
  dpkg-deb -x "$kdir"/deb/*.deb "$kdir/root"
  rm -rf "$kdir/deb"
  busybox depmod -b "$kdir/root" "${kernel_package#linux-image-}"
  touch "$kdir/extracted"
fi
kver=${kernel_package#linux-image-}
kdir=$kernel_cache/$kernel_package
vmlinuz=$kdir/root/boot/vmlinuz-$kver
moddir=$kdir/root/lib/modules/$kver
[ -f "$vmlinuz" ] && [ -f "$moddir/modules.dep" ] || die "$kdir: incomplete kernel tree (delete it to refetch)"

# --- Debian 12 base system: debootstrap once, kept as a tarball --------------------------------
suite=bookworm
mirror=${LUMAR_DEBIAN_MIRROR:-http://deb.debian.org/debian}
include=systemd,systemd-sysv,udev,dbus,kmod
base=$cache/debian-$suite-$(echo "$include" | sha256sum | cut -c1-8).tar
if [ ! -f "$base" ]; then
  log "debootstrap --variant=minbase $suite ($include)"
  t0=$(now)
  tmp=$cache/debootstrap.tmp
  rm -rf "$tmp"
  debootstrap --variant=minbase --include="$include" "$suite" "$tmp" "$mirror" >"$cache/debootstrap.log" 2>&1 ||
    { tail -20 "$cache/debootstrap.log"; die "debootstrap failed ($cache/debootstrap.log)"; }
  # The security and update suites too, as on an installed system; lists fetched now so a
  # rerun needs no network.
  cat >"$tmp/etc/apt/sources.list" <<EOF
deb $mirror $suite main
deb $mirror $suite-updates main
deb http://deb.debian.org/debian-security $suite-security main
EOF
  cp /etc/resolv.conf "$tmp/etc/resolv.conf"
  chroot "$tmp" apt-get update >"$cache/apt-update.log" 2>&1 || { cat "$cache/apt-update.log"; die "apt-get update in the chroot failed"; }
  chroot "$tmp" apt-get clean
  tar -C "$tmp" -cf "$base.partial" .
  mv "$base.partial" "$base"
  rm -rf "$tmp"
  log "base system $(du -m "$base" | cut -f1) MB in $(since "$t0") s"
fi

# --- The system under test: the base, lumar installed with apt, configured, enabled ----------
run=$cache/run
root=$run/root
# A run killed while the chroot's bind mounts were up must not take /dev with it.
{ grep -F " $run/" /proc/mounts || true; } | cut -d' ' -f2 | sort -r | while read -r m; do umount "$m" || true; done
grep -qF " $run/" /proc/mounts && die "$run: still mounted inside, not deleting it"
rm -rf "$run"
mkdir -p "$root"
t0=$(now)
tar -C "$root" -xf "$base"
archives=$cache/apt-archives
mkdir -p "$archives/partial" "$root/var/cache/apt/archives"
chroot_mounts=()
umount_chroot() {
  local i
  for ((i = ${#chroot_mounts[@]} - 1; i >= 0; i--)); do umount "${chroot_mounts[i]}" 2>/dev/null || true; done
  chroot_mounts=()
}
trap umount_chroot EXIT
for m in proc sys dev; do
  mount --bind "/$m" "$root/$m"
  chroot_mounts+=("$root/$m")
done
# apt's downloads survive in the cache: a rerun installs the same packages offline.
mount --bind "$archives" "$root/var/cache/apt/archives"
chroot_mounts+=("$root/var/cache/apt/archives")
cp "$deb" "$root/tmp/lumar.deb"
cp /etc/resolv.conf "$root/etc/resolv.conf"
# No service starts inside the chroot (there is no systemd running there anyway).
printf '#!/bin/sh\nexit 101\n' >"$root/usr/sbin/policy-rc.d"
chmod 755 "$root/usr/sbin/policy-rc.d"
# Depends alone must be enough: no Recommends.
if ! chroot "$root" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends /tmp/lumar.deb \
     >"$run/apt-install.log" 2>&1; then
  tail -30 "$run/apt-install.log"
  die "apt-get install ./lumar.deb failed in the chroot ($run/apt-install.log)"
fi
log "apt-get install ./$(basename "$deb"): $(grep -cE '^(Setting up|Unpacking) ' "$run/apt-install.log" || true) unpack/setup steps in $(since "$t0") s"
grep -q '^ii  lumar ' <(chroot "$root" dpkg -l lumar) || die "lumar not installed (dpkg -l)"
umount_chroot
trap - EXIT
rm -f "$root/usr/sbin/policy-rc.d" "$root/tmp/lumar.deb"

# The kernel's modules, for udev (bochs for the display, and whatever else the VM shows it).
mkdir -p "$root/lib/modules"
cp -a "$moddir" "$root/lib/modules/"
chroot "$root" depmod "$kver"

# The configuration: the shipped default (fake camera, headless output) plus the status file.
conf=$root/etc/lumar/lumar.toml
grep -q '^# status_path = "/run/lumar/status.json"' "$conf" || die "$conf: no commented status_path to enable"
sed -i 's|^# status_path = "/run/lumar/status.json"|status_path = "/run/lumar/status.json"|' "$conf"
grep -q '^sink = "headless"' "$conf" || die "$conf: the output is not headless"
# (The status file's directory exists only once systemd made the RuntimeDirectory.)
mkdir "$root/run/lumar"
chroot "$root" /usr/bin/lumar check-config /etc/lumar/lumar.toml >/dev/null || die "lumar check-config rejects $conf"
rmdir "$root/run/lumar"

# Under TCG the guest runs llvmpipe some 30 times slower than a board's CPU: a frame can take
# longer than the unit's 10 s watchdog and the 90 s start timeout. This VM's own allowance;
# the unit is otherwise the package's, unchanged.
mkdir -p "$root/etc/systemd/system/lumar.service.d"
cat >"$root/etc/systemd/system/lumar.service.d/virtual-board.conf" <<EOF
[Service]
WatchdogSec=120s
TimeoutStartSec=600s
EOF

# The checks run as a service once the boot is done, on the serial console.
install -m 755 "$top/tests/system/virtual-board-systemd-guest.sh" "$root/usr/local/sbin/lumar-vbs-check"
cat >"$root/etc/systemd/system/lumar-vbs-check.service" <<EOF
[Unit]
Description=lumar systemd virtual board checks
After=lumar.service
[Service]
Type=oneshot
ExecStart=/usr/local/sbin/lumar-vbs-check $((timeout_s / 2))
StandardOutput=tty
StandardError=tty
TTYPath=/dev/ttyS0
[Install]
WantedBy=multi-user.target
EOF
echo '/dev/vda / ext4 rw,noatime 0 0' >"$root/etc/fstab"
echo lumar-vbs >"$root/etc/hostname"
: >"$root/etc/machine-id"
# Nothing interactive on the console the checks print to; no timers that would start apt.
chroot "$root" systemctl enable lumar.service lumar-vbs-check.service >/dev/null 2>&1
chroot "$root" systemctl mask serial-getty@ttyS0.service getty@tty1.service apt-daily.timer \
  apt-daily-upgrade.timer >/dev/null 2>&1
chroot "$root" systemctl set-default multi-user.target >/dev/null 2>&1
[ "$(chroot "$root" systemctl is-enabled lumar.service)" = enabled ] || die "systemctl enable lumar failed"

# The disk image (ext4 from the directory) and the initramfs that mounts it.
image=$run/root.ext4
size_mb=$(($(du -sm "$root" | cut -f1) + 512))
mke2fs -q -t ext4 -L lumar-root -d "$root" "$image" "${size_mb}M"
initramfs=$run/initramfs.cpio
iroot=$run/initramfs
mkdir -p "$iroot"/{usr/bin,usr/sbin,usr/lib,proc,sys,dev,newroot}
ln -s usr/bin "$iroot/bin"; ln -s usr/sbin "$iroot/sbin"; ln -s usr/lib "$iroot/lib"
cp "$(command -v busybox)" "$iroot/usr/bin/busybox"
for applet in $(busybox --list); do
  [ -e "$iroot/usr/bin/$applet" ] || ln -s busybox "$iroot/usr/bin/$applet"
done
install -m 755 "$top/tests/system/virtual-board-systemd-init.sh" "$iroot/init"
for m in virtio_pci virtio_blk crc32c_generic ext4; do
  line=$(grep -E "(^|/)${m}\\.ko:" "$moddir/modules.dep") || die "module $m not in $moddir"
  for f in ${line/:/}; do
    mkdir -p "$iroot/lib/modules/$kver/$(dirname "$f")"
    cp "$moddir/$f" "$iroot/lib/modules/$kver/$f"
  done
done
cp "$moddir"/modules.{order,builtin} "$iroot/lib/modules/$kver/"
busybox depmod -b "$iroot" "$kver"
(cd "$iroot" && find . | LC_ALL=C sort | cpio -o -H newc --quiet) >"$initramfs"
rm -rf "$root" "$iroot"
log "image $(du -m "$image" | cut -f1) MB (ext4, ${size_mb} MB), initramfs ready in $(since "$t0") s"

# --- Boot -------------------------------------------------------------------------------------
serial=$run/serial.log
log "booting $kernel_package with systemd (TCG)"
boot_started=$(now)
qemu-system-x86_64 -accel tcg -m 2G -smp 2 -nodefaults -no-reboot \
  -vga std -display none \
  -kernel "$vmlinuz" -initrd "$initramfs" \
  -append "console=ttyS0 quiet panic=-1 systemd.show_status=error" \
  -drive file="$image",format=raw,if=virtio \
  -serial file:"$serial" \
  >"$run/qemu.log" 2>&1 &
qemu=$!
trap 'kill "$qemu" 2>/dev/null || true' EXIT
boot_s=""
while kill -0 "$qemu" 2>/dev/null; do
  if [ -z "$boot_s" ] && grep -q '^LUMAR-VBS: checks start' "$serial" 2>/dev/null; then
    boot_s=$(since "$boot_started")
    log "checks started in the guest after $boot_s s"
  fi
  if [ "$(since "$boot_started" | cut -d. -f1)" -ge "$timeout_s" ]; then
    log "the VM ran past ${timeout_s} s; stopping it"
    break
  fi
  sleep 0.5
done
kill "$qemu" 2>/dev/null || true
wait "$qemu" 2>/dev/null || true
run_s=$(since "$boot_started")

# --- Results ----------------------------------------------------------------------------------
tr -d '\r' <"$serial" >"$run/console.txt"
log "guest console:"
sed 's/^/  | /' "$run/console.txt"
failed=0
for check in enabled active status-text status-json reload still-running stop journal; do
  if grep -q "^LUMAR-VBS: PASS $check\$" "$run/console.txt"; then
    echo "PASS $check"
  else
    echo "FAIL $check: $(sed -n "s/^LUMAR-VBS: FAIL $check: //p" "$run/console.txt" | head -1)"
    failed=1
  fi
done
grep -q '^LUMAR-VBS: done' "$run/console.txt" || { echo "FAIL guest: the checks did not finish"; failed=1; }
log "$(grep '^LUMAR-VBS: active at' "$run/console.txt" | sed 's/^LUMAR-VBS: //' || true)"
log "systemd-analyze security: $(sed -n 's/^LUMAR-VBS: security //p' "$run/console.txt")"
log "boot to checks ${boot_s:-?} s, VM run ${run_s} s, total $(since "$started") s"
if [ "$failed" != 0 ]; then
  log "FAILED (console log in $run/console.txt)"
  exit 1
fi
[ "$keep" = 1 ] || rm -rf "$run"
log "all checks passed"
