#!/usr/bin/env bash
# Installs a build into a scratch DESTDIR and checks the layout works: the binary finds its
# assets, renders the built-in default, the installed /etc configuration is valid, the board
# profiles are installed, valid and found by name, and the tmpfiles.d entry is in place.
# Usage: scripts/check-install.sh BUILD_DIR
set -euo pipefail
build=$(realpath "$1")
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
DESTDIR="$dest" cmake --install "$build" >/dev/null
prefix=$(cmake -L -N "$build" | sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p')
bin="$dest$prefix/bin/lumar"
config=$(find "$dest" -path '*/lumar/lumar.toml' | head -n 1)
for f in "$bin" "$config" "$dest$prefix/share/lumar/models/CesiumMilkTruck.glb" \
         "$dest$prefix/share/lumar/env/venice_sunset_1k.hdr" "$dest$prefix/lib/systemd/system/lumar.service" \
         "$dest$prefix/lib/tmpfiles.d/lumar.conf" "$dest$prefix/share/lumar/board/README.md" \
         "$dest$prefix/share/lumar/board/"{raspberry-pi-5,imx8mp,x86-uvc,qemu-virtual-board}.toml; do
  [ -e "$f" ] || { echo "missing after install: ${f#"$dest"}"; exit 1; }
done
"$bin" render --frames 2 --out "$dest/frame.png" --log-level warn
# The installed configuration names installed assets; check it against the scratch tree.
sed "s|\"$prefix/share/lumar/|\"$dest$prefix/share/lumar/|" "$config" >"$dest/lumar.toml"
"$bin" check-config "$dest/lumar.toml"
for board in "$dest$prefix/share/lumar/board/"*.toml; do
  "$bin" check-config "$board" >/dev/null
done
# `board = "NAME"` resolves in the installed board directory: a shipped name is accepted, and
# an unknown one is reported with the installed path it was looked for at.
{ echo 'board = "x86-uvc"'; cat "$dest/lumar.toml"; } >"$dest/with-board.toml"
"$bin" check-config "$dest/with-board.toml" >/dev/null
{ echo 'board = "no-such-board"'; cat "$dest/lumar.toml"; } >"$dest/bad-board.toml"
if err=$("$bin" check-config "$dest/bad-board.toml" 2>&1); then
  echo "check-config accepted an unknown board"
  exit 1
fi
case "$err" in
  *"no board profile $dest$prefix/share/lumar/board/no-such-board.toml"*) ;;
  *) echo "unknown board not looked up in the installed board directory: $err"; exit 1 ;;
esac
echo "install layout ok"
