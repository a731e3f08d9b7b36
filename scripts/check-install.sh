#!/usr/bin/env bash
# Installs a build into a scratch DESTDIR and checks the layout works: the binary finds its
# assets, renders the built-in default, and the installed /etc configuration is valid.
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
         "$dest$prefix/share/lumar/env/venice_sunset_1k.hdr" "$dest$prefix/lib/systemd/system/lumar.service"; do
  [ -e "$f" ] || { echo "missing after install: ${f#"$dest"}"; exit 1; }
done
"$bin" render --frames 2 --out "$dest/frame.png" --log-level warn
# The installed configuration names installed assets; check it against the scratch tree.
sed "s|\"$prefix/share/lumar/|\"$dest$prefix/share/lumar/|" "$config" >"$dest/lumar.toml"
"$bin" check-config "$dest/lumar.toml"
echo "install layout ok"
