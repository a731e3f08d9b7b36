#!/usr/bin/env bash
# Builds the Debian package from a build tree (cpack -G DEB) and checks it: the files and
# where they land, /etc/lumar/lumar.toml as a conffile, Depends covering every library the
# binary links (as dpkg -S attributes them) plus Mesa's EGL vendor, and that the package
# installs with dpkg into a scratch root whose binary accepts its own /etc configuration.
# Usage: scripts/check-deb.sh BUILD_DIR
set -euo pipefail
build=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "check-deb: $*"; exit 1; }

# cpack first builds the preinstall target (everything, unless the tree was configured with
# CMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON): run it on a built tree.
(cd "$build" && cpack -G DEB -B "$work/out" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(find "$work/out" -maxdepth 1 -name 'lumar_*.deb' | head -n 1)
[ -n "$deb" ] || fail "cpack made no lumar_*.deb"

# Contents: paths as dpkg will install them.
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$work/contents"
for f in /usr/bin/lumar /etc/lumar/lumar.toml /usr/lib/systemd/system/lumar.service \
         /usr/lib/tmpfiles.d/lumar.conf /usr/share/lumar/README.md \
         /usr/share/lumar/models/CesiumMilkTruck.glb /usr/share/lumar/env/venice_sunset_1k.hdr \
         /usr/share/lumar/calibration/fake_camera_1280x720.yaml /usr/share/lumar/scenes/ \
         /usr/share/lumar/board/README.md /usr/share/lumar/board/raspberry-pi-5.toml \
         /usr/share/lumar/board/imx8mp.toml /usr/share/lumar/board/x86-uvc.toml \
         /usr/share/lumar/board/qemu-virtual-board.toml; do
  grep -qxF "$f" "$work/contents" || fail "missing from the package: $f"
done
# Nothing may escape the prefix and /etc (a build-tree path or /usr/local would).
if stray=$(grep -v -E '^/$|^/(usr|etc)/|^/usr$|^/etc$' "$work/contents"); then
  fail "unexpected paths in the package: $stray"
fi

# Control: conffiles and Depends.
dpkg-deb -e "$deb" "$work/control"
[ "$(cat "$work/control/conffiles")" = "/etc/lumar/lumar.toml" ] || fail "conffiles: $(cat "$work/control/conffiles")"
depends=$(dpkg-deb -f "$deb" Depends)
[ -n "$depends" ] || fail "no Depends"
has_dep() { tr ',' '\n' <<<"$depends" | sed 's/^ *//; s/[ (].*//' | grep -qxF "$1"; }
needed=$(objdump -p "$build/lumar" | awk '$1 == "NEEDED" {print $2}')
[ -n "$needed" ] || fail "objdump found no NEEDED libraries in $build/lumar"
ldconfig -p >"$work/ldconfig"
owner() { dpkg -S "$1" 2>/dev/null | sed -n '1s/:.*//p' || true; }
for lib in $needed; do
  # The first path the loader would use for this name (no early exit: pipefail and SIGPIPE).
  path=$(awk -v l="$lib" '$1 == l && !found {print $NF; found = 1}' "$work/ldconfig")
  [ -n "$path" ] || fail "cannot find $lib"
  # dpkg knows a library by the path its package ships: the versioned file behind the
  # soname link, under /usr/lib or (libc6 on merged-/usr Debian 12) /lib.
  pkg=$(owner "$(realpath "$path")")
  [ -n "$pkg" ] || pkg=$(owner "$path")
  [ -n "$pkg" ] || fail "no package owns $path ($lib)"
  has_dep "$pkg" || fail "Depends lacks $pkg (for $lib): $depends"
done
for pkg in libegl-mesa0 libgl1-mesa-dri; do
  has_dep "$pkg" || fail "Depends lacks $pkg: $depends"
done

# Install into a scratch root (its own dpkg database; dependencies are the host's, so not
# checked; maintainer scripts run outside a chroot and skip their work under DPKG_ROOT).
root="$work/root"
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
touch "$root/var/lib/dpkg/status"
how="dpkg --root"
if ! dpkg --root="$root" --force-script-chrootless --force-depends --force-not-root --log=/dev/null \
     -i "$deb" >"$work/dpkg.log" 2>&1; then
  # Not permitted here (no root): unpack the files instead, which checks the same layout.
  cat "$work/dpkg.log"
  rm -rf "$root" && mkdir -p "$root"
  dpkg-deb -x "$deb" "$root"
  how="dpkg-deb -x"
fi
[ -x "$root/usr/bin/lumar" ] || fail "$how: no /usr/bin/lumar"
# The installed configuration names /usr/share/lumar; point it at the scratch root.
sed "s|\"/usr/share/lumar/|\"$root/usr/share/lumar/|" "$root/etc/lumar/lumar.toml" >"$work/lumar.toml"
"$root/usr/bin/lumar" check-config "$work/lumar.toml" >/dev/null || fail "installed binary rejects its /etc configuration"
"$root/usr/bin/lumar" check-config "$root/usr/share/lumar/board/x86-uvc.toml" >/dev/null || fail "installed board rejected"
echo "deb ok ($(basename "$deb"), $(wc -l <"$work/contents") entries, installed with $how)"
