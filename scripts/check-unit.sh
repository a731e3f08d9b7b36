#!/usr/bin/env bash
# Checks systemd/lumar.service: `systemd-analyze verify` clean (with ExecStart pointed at the
# given lumar binary) and `systemd-analyze security` exposure at or below 2.0 ("SAFE"/"OK").
# Usage: scripts/check-unit.sh path/to/lumar
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
lumar=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed "s|/usr/bin/lumar|$lumar|" "$top/systemd/lumar.service" >"$work/lumar.service"
cd "$work"
out=$(systemd-analyze verify "$work/lumar.service" 2>&1 || true)
if [ -n "$out" ]; then
  echo "systemd-analyze verify: $out"
  exit 1
fi
systemd-analyze security --offline=yes --threshold=20 "$work/lumar.service" | tail -n 1
