#!/usr/bin/env bash
# Fault campaign against a running `lumar run` (issue 16): broken, half-written and deeply
# nested configs, a config naming a missing model, a truncated model, a broken calibration, a
# deleted environment map, a full disk and an unwritable folder under status.json, a SIGHUP
# storm, and SIGTERM during a reload; lumar must keep running on its last good configuration,
# log a line naming each file, and recover when the good file returns (scripts/fault_campaign.py
# says exactly what is asserted). Prints a table of fault -> recovery time. --camera adds the
# camera faults against the virtual V4L2 camera (unplug and return, a 5 s stall, 1 % corrupt
# MJPEG frames, short frames; needs the lumar_vcam target built), --camera-only runs just those.
#   scripts/fault-campaign.sh [--rounds N] [--limit S] [--keep DIR] [--lumar BINARY]
#                             [--camera | --camera-only] [--vcam LIBRARY]
# The suite runs one round (ctest -L fault: fault_campaign about a minute, fault_campaign_camera
# about two); the long campaign is e.g.
#   scripts/fault-campaign.sh --rounds 20 --camera
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
exec python3 "$root/scripts/fault_campaign.py" "$@"
