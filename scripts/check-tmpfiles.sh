#!/usr/bin/env bash
# Checks systemd/lumar.tmpfiles: systemd-tmpfiles applies it cleanly in a scratch root and
# creates /run/lumar as root:root 0755. Debian 12's systemd 252 has no --dry-run, so the file
# is applied with --root (nothing outside the scratch directory is touched); every line it
# cannot parse makes it exit non-zero (65). A deliberately broken copy must fail, so the
# check is known to catch errors.
# Usage: scripts/check-tmpfiles.sh
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
conf="$top/systemd/lumar.tmpfiles"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mkdir "$work/root"
if ! out=$(systemd-tmpfiles --root="$work/root" --create "$conf" 2>&1) || [ -n "$out" ]; then
  echo "systemd-tmpfiles --create: ${out:-failed}"
  exit 1
fi
made=$(stat -c '%F %a %U:%G' "$work/root/run/lumar" 2>/dev/null || echo "nothing")
if [ "$made" != "directory 755 root:root" ]; then
  echo "/run/lumar: expected 'directory 755 root:root', found '$made'"
  exit 1
fi

# The same file with its mode mangled: systemd-tmpfiles must reject it.
sed 's|^d /run/lumar 0755|d /run/lumar 07x5|' "$conf" >"$work/broken.conf"
cmp -s "$conf" "$work/broken.conf" && { echo "could not break the file: its 'd /run/lumar 0755' line changed?"; exit 1; }
mkdir "$work/root2"
if systemd-tmpfiles --root="$work/root2" --create "$work/broken.conf" >/dev/null 2>&1; then
  echo "systemd-tmpfiles accepted a broken file: the check proves nothing"
  exit 1
fi
echo "tmpfiles ok"
