#!/bin/sh
# The checks of the systemd virtual board (scripts/virtual-board-systemd.sh), run inside the
# guest by lumar-vbs-check.service once the boot reached multi-user.target: lumar.service as
# installed by the .deb, started by the real systemd with all its hardening, against Mesa's
# llvmpipe. Prints "LUMAR-VBS: PASS NAME" or "LUMAR-VBS: FAIL NAME: why" per check for the
# host, then "LUMAR-VBS: done", and powers the guest off.
export SYSTEMD_PAGER='' SYSTEMD_COLORS=0 LC_ALL=C.UTF-8
timeout_s=${1:-600}
pass() { echo "LUMAR-VBS: PASS $1"; }
fail() { echo "LUMAR-VBS: FAIL $1: $2"; }
uptime_s() { cut -d' ' -f1 /proc/uptime; }
prop() { systemctl show lumar -p "$1" --value; }
section() { echo "----- $* -----"; }

echo "LUMAR-VBS: checks start at uptime $(uptime_s) s"
systemctl is-enabled lumar >/dev/null 2>&1 && pass enabled || fail enabled "lumar.service is $(systemctl is-enabled lumar 2>&1)"

# --- active: Type=notify, so active means lumar sent READY=1 (after its first frame) --------
state=$(systemctl is-active lumar)
waited=0
while [ "$state" != active ] && [ "$waited" -lt "$timeout_s" ]; do
  case "$state" in failed) break ;; esac
  sleep 1
  waited=$((waited + 1))
  state=$(systemctl is-active lumar)
done
if [ "$state" = active ]; then
  start=$(prop ExecMainStartTimestampMonotonic)
  ready=$(prop ActiveEnterTimestampMonotonic)
  echo "LUMAR-VBS: active at uptime $(uptime_s) s; ExecStart to READY=1 in" \
    "$(awk -v a="$start" -v b="$ready" 'BEGIN { printf "%.1f", (b - a) / 1e6 }') s;" \
    "restarts $(prop NRestarts)"
  pass active
else
  fail active "lumar.service is '$state' after ${waited} s (Result=$(prop Result), restarts $(prop NRestarts))"
fi

# --- STATUS= and the status file -----------------------------------------------------------
# lumar sends STATUS= once a second's frames are counted: under TCG a few frames later.
for _ in $(seq 180); do
  text=$(prop StatusText)
  [ -n "$text" ] && break
  sleep 1
done
if [ -n "$text" ]; then
  echo "LUMAR-VBS: StatusText=$text"
  pass status-text
else
  fail status-text "StatusText is empty"
fi
for _ in $(seq 30); do
  [ -s /run/lumar/status.json ] && break
  sleep 1
done
if [ -s /run/lumar/status.json ] && su nobody -s /bin/sh -c 'cat /run/lumar/status.json' >/tmp/status.json 2>&1 &&
   grep -q '"frames"' /tmp/status.json; then
  echo "LUMAR-VBS: $(ls -l /run/lumar/status.json)"
  echo "LUMAR-VBS: status.json $(head -c 400 /tmp/status.json)"
  pass status-json
else
  ls -la /run/lumar 2>&1
  fail status-json "/run/lumar/status.json missing or unreadable by another user: $(head -c 200 /tmp/status.json 2>/dev/null)"
fi

# --- reload: ExecReload sends SIGHUP, lumar logs "reloaded" ----------------------------------
pid_before=$(prop MainPID)
if systemctl reload lumar; then
  found=0
  for _ in $(seq 60); do
    if journalctl -u lumar -b --no-pager -o cat | grep -q 'reloaded'; then found=1; break; fi
    sleep 1
  done
  if [ "$found" = 1 ] && [ "$(systemctl is-active lumar)" = active ] && [ "$(prop MainPID)" = "$pid_before" ]; then
    echo "LUMAR-VBS: $(journalctl -u lumar -b --no-pager -o cat | grep 'reloaded' | tail -1)"
    pass reload
  else
    fail reload "no 'reloaded' in the journal, or lumar restarted (pid $pid_before -> $(prop MainPID), $(systemctl is-active lumar))"
  fi
else
  fail reload "systemctl reload lumar failed"
fi

# Let it run a little longer under the watchdog before judging the journal.
sleep 10
[ "$(systemctl is-active lumar)" = active ] && [ "$(prop NRestarts)" = 0 ] && pass still-running ||
  fail still-running "lumar.service is $(systemctl is-active lumar), restarts $(prop NRestarts), Result=$(prop Result)"

# --- stop: SIGTERM, a clean exit ------------------------------------------------------------
systemctl stop lumar
result=$(prop Result)
status=$(prop ExecMainStatus)
[ "$result" = success ] && pass stop || fail stop "Result=$result ExecMainStatus=$status"

# --- the journal: no seccomp kills, no denied syscalls or devices ---------------------------
section "journalctl -u lumar"
journalctl -u lumar -b --no-pager -o short-monotonic | tail -n 60
section "end of journal"
# SystemCallFilter kills with SIGSYS (the kernel's audit type=1326 names the syscall); a
# filtered-with-errno call or a denied device shows up as EPERM/EACCES in lumar's messages.
bad=$( { journalctl -u lumar -b --no-pager -o cat |
    grep -Ei 'seccomp|SIGSYS|Bad system call|core-dump|dumped core|Operation not permitted|Permission denied|EPERM|EACCES|Failed|Watchdog timeout|status=2[0-9][0-9]/'
  journalctl -k -b --no-pager -o cat | grep -Ei 'type=1326|lumar.*(denied|segfault)'; } || true)
if [ -z "$bad" ]; then
  pass journal
else
  echo "$bad" | sed 's/^/LUMAR-VBS: journal| /'
  fail journal "suspicious lines in the journal (above)"
fi

section "systemctl cat lumar"
systemctl cat lumar --no-pager 2>&1 | grep -E '^(# /|WatchdogSec|TimeoutStartSec|ExecReload)'
section "systemd-analyze security lumar"
systemd-analyze security --no-pager lumar 2>&1
section "end of security"
echo "LUMAR-VBS: security $(systemd-analyze security --no-pager lumar 2>&1 | sed -n 's/.*Overall exposure level for lumar.service: *//p')"
echo "LUMAR-VBS: done uptime $(uptime_s) s"
systemctl poweroff --no-block
