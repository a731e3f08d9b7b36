#!/usr/bin/env bash
# Fault campaign against a running `lumar run` (issue 16): broken, half-written and deeply
# nested configs, a config naming a missing model, a truncated model, a broken calibration, a
# deleted environment map, a full disk and an unwritable folder under status.json, a SIGHUP
# storm, and SIGTERM during a reload; lumar must keep running on its last good configuration,
# log a line naming each file, and recover when the good file returns (scripts/fault_campaign.py
# says exactly what is asserted). Prints a table of fault -> recovery time.
#   scripts/fault-campaign.sh [--rounds N] [--limit S] [--keep DIR] [--lumar BINARY]
# The suite runs one round (ctest -L fault, about a minute); the long campaign is e.g.
#   scripts/fault-campaign.sh --rounds 20
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
exec python3 "$root/scripts/fault_campaign.py" "$@"
