#!/usr/bin/env python3
"""Fault campaign against a running `lumar run` (issue 16); scripts/fault-campaign.sh runs it.

lumar runs on the fake camera (320x240, 10 fps) with a glTF object, a calibration file, an
environment .hdr and status.json, all copied into a scratch folder. The faults below are
injected one after the other; after each the campaign asserts that
  - the process is alive and frames keep coming (status.json's frame count advances),
  - the log has a line naming the file at fault (for the faults lumar must report),
  - status.json names the fault while it lasts (config: "rejected: FILE...") where it can
    be written,
  - after the good file returns, the configuration is "ok" again and frames flow,
and measures the recovery time: from the good state's return (or the fault's injection, for
faults lumar rides through) to status.json saying so with frames advancing. At the end a
SIGTERM in the middle of a reload must stop lumar with exit 0. Prints the table of faults.

Camera faults (--camera, or --camera-only) run `lumar run` against the user-space virtual V4L2
camera (tests/vcam's liblumar_vcam.so, preloaded), one process per fault because the camera
reads its faults when it is opened: unplugged after 1.5 s of every connection (and back at
once), a 5 s stall 15 s into each connection (longer than camera.timeout_ms = 2000), 1 %
corrupt MJPEG frames, and short frames (every 50th YUYV frame half-filled). lumar runs under
a stand-in for systemd's notify socket (NOTIFY_SOCKET, WATCHDOG_USEC=200000), so each STATUS=
and WATCHDOG=1 is seen with its time: the outage's STATUS= must name the fault, and the
recovery time is from it to the first WATCHDOG=1 after it (frames presented again). Each must
also log a line naming the fault, stay alive, keep status.json's frames advancing afterwards,
and stop with exit 0 on SIGTERM. The preload cannot run under the sanitizers' runtimes
(tests/integration/v4l2/CMakeLists.txt).
SIGUSR1 is not sent: lumar does not handle it (its default action ends a process, as for any
daemon that does not claim it).

  fault_campaign.py --lumar BINARY [--rounds N] [--limit S] [--keep DIR]
                    [--camera | --camera-only] [--vcam LIBRARY]
Exit status 0 when every assertion held."""
import argparse
import json
import os
import random
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CALIBRATION = """%YAML:1.0
---
image_width: 320
image_height: 240
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 228.50368, 0., 159.5, 0., 228.50368, 119.5, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0., 0., 0., 0., 0. ]
"""


def scene(model="box.glb", size=0.1, width=320, seed=1):
    return f"""[camera]
width = {width}
height = 240
fps = 10
seed = {seed}
calibration = "calib.yaml"

[[markers]]
id = 0
size = 0.16

[[objects]]
name = "box"
model = "{model}"
marker = 0
size = {size}

[environment]
hdr = "env.hdr"

[output]
path = "out.png"
status_path = "status/status.json"
"""


class Died(Exception):
    pass


class Campaign:
    def __init__(self, lumar, work, limit):
        self.lumar = lumar
        self.work = work
        self.limit = limit
        self.config = os.path.join(work, "scene.toml")
        self.log_path = os.path.join(work, "lumar.log")
        self.status_path = os.path.join(work, "status", "status.json")
        self.failures = []
        self.table = []  # (fault, file named in the log, lines, status named it, recovery s)

    # --- files -------------------------------------------------------------------------
    def write(self, name, data, replace=True):
        """Writes a file the way editors do (beside, renamed over) or in place."""
        path = os.path.join(self.work, name)
        mode = "wb" if isinstance(data, bytes) else "w"
        if replace:
            with open(path + ".new", mode) as f:
                f.write(data)
            os.replace(path + ".new", path)
        else:
            with open(path, mode) as f:
                f.write(data)

    def log(self):
        with open(self.log_path, errors="replace") as f:
            return f.read()

    def status(self):
        try:
            with open(self.status_path) as f:
                return json.load(f)
        except (OSError, ValueError):
            return None

    def frames(self):
        s = self.status()
        return s["frames"] if s else None

    # --- process -----------------------------------------------------------------------
    def start(self):
        self.log_file = open(self.log_path, "w")
        self.proc = subprocess.Popen([self.lumar, "run", "--config", self.config], stdout=self.log_file,
                                     stderr=subprocess.STDOUT, cwd=self.work)
        if not self.wait(lambda: (self.frames() or 0) >= 3, 120):
            raise SystemExit("fault_campaign: lumar did not start:\n" + self.log())

    def alive(self):
        return self.proc.poll() is None

    def wait(self, condition, limit):
        deadline = time.monotonic() + limit
        while time.monotonic() < deadline:
            if not self.alive():
                return False
            if condition():
                return True
            time.sleep(0.05)
        return False

    def frames_advance(self, limit):
        """True once status.json shows frames beyond those it shows now."""
        start = self.frames() or 0
        return self.wait(lambda: (self.frames() or 0) > start, limit)

    def check(self, ok, what):
        if not ok:
            self.failures.append(what)
            print(f"  FAIL: {what}", flush=True)
        return ok

    # --- one fault ---------------------------------------------------------------------
    def stop_if_dead(self, name):
        """A dead daemon fails every check after it: stop the campaign at the first death."""
        if not self.alive():
            tail = "\n".join(self.log().splitlines()[-3:])
            raise Died(f"{name}: lumar exited ({self.proc.returncode}); its log ends:\n{tail}")

    def fault(self, name, inject, restore, named, reload_signal=False, status_names=True, logged=True,
              status_frozen=False):
        """Injects a fault, checks lumar rides it out and says so, restores, checks recovery.
        status_frozen: the fault is status.json's own (it cannot move): lumar must stay up."""
        print(f"{name} ...", flush=True)
        log_before = len(self.log())
        inject()
        if reload_signal:
            self.proc.send_signal(signal.SIGHUP)
        lines = 0
        if logged:
            self.wait(lambda: named in self.log()[log_before:], self.limit)
            lines = sum(1 for line in self.log()[log_before:].splitlines() if named in line)
            self.check(lines >= 1, f"{name}: no log line names {named}")
        self.check(self.alive(), f"{name}: lumar died")
        said = None
        if status_names:
            said = self.wait(lambda: named in (self.status() or {}).get("config", ""), self.limit)
            self.check(said, f"{name}: status.json does not name {named}: {self.status()}")
        if status_frozen:
            time.sleep(2.0)
            self.check(self.alive(), f"{name}: lumar died")
        elif self.alive():
            self.check(self.frames_advance(self.limit), f"{name}: frames stopped during the fault")
        restored = time.monotonic()
        restore()
        if reload_signal:
            self.proc.send_signal(signal.SIGHUP)
        recovered = self.wait(lambda: (self.status() or {}).get("config") == "ok", self.limit) and \
            self.frames_advance(self.limit)
        recovery = time.monotonic() - restored
        self.check(recovered, f"{name}: no recovery within {self.limit} s: {self.status()}")
        self.check(self.alive(), f"{name}: lumar died after the restore")
        self.stop_if_dead(name)
        self.table.append((name, named if logged else "-", lines, "yes" if said else ("-" if said is None else "no"),
                           f"{recovery:.2f}" if recovered else "none"))

    def run(self, rounds):
        good = scene()
        glb = open(os.path.join(self.work, "box.glb"), "rb").read()
        hdr = open(os.path.join(self.work, "env.hdr"), "rb").read()
        rng = random.Random(16)
        for round_ in range(rounds):
            if rounds > 1:
                print(f"--- round {round_ + 1} of {rounds}", flush=True)
            garbage = bytes(rng.randrange(256) for _ in range(600))
            self.fault("config replaced by garbage", lambda: self.write("scene.toml", garbage),
                       lambda: self.write("scene.toml", good), "scene.toml")
            cut = good.index("size =") + 3  # mid-key: `siz` is an unknown key... then a bad line
            self.fault("config half-written in place",
                       lambda: self.write("scene.toml", good[:cut] + " = = \n", replace=False),
                       lambda: self.write("scene.toml", good, replace=False), "scene.toml")
            deep = "a = " + "[" * 10000 + "]" * 10000 + "\n"
            self.fault("config nested 10,000 deep", lambda: self.write("scene.toml", deep),
                       lambda: self.write("scene.toml", good), "scene.toml")
            self.fault("config naming a missing model", lambda: self.write("scene.toml", scene(model="missing.glb")),
                       lambda: self.write("scene.toml", good), "missing.glb")
            self.fault("valid edit (object size)", lambda: self.write("scene.toml", scene(size=0.15)),
                       lambda: self.write("scene.toml", good), "scene.toml", logged=True, status_names=False)
            self.fault("model truncated (SIGHUP)", lambda: self.write("box.glb", glb[: len(glb) // 2]),
                       lambda: self.write("box.glb", glb), "box.glb", reload_signal=True)
            self.fault("calibration broken (SIGHUP)", lambda: self.write("calib.yaml", "%YAML:1.0\n[[[[\x01"),
                       lambda: self.write("calib.yaml", CALIBRATION), "calib.yaml", reload_signal=True)
            self.fault("environment .hdr deleted (SIGHUP)", lambda: os.remove(os.path.join(self.work, "env.hdr")),
                       lambda: self.write("env.hdr", hdr), "env.hdr", reload_signal=True)
            partial = self.status_path + ".partial"
            # ENOSPC without a mount: the status file's scratch name made a link to /dev/full,
            # where every write fails with "No space left on device" (tmpfs needs root's mount).
            self.fault("status disk full (ENOSPC via /dev/full)", lambda: os.symlink("/dev/full", partial),
                       lambda: os.remove(partial), "status.json.partial", status_names=False,
                       status_frozen=True)
            status_dir = os.path.dirname(self.status_path)
            # The status folder gone and a file in its place: writes fail with ENOTDIR (root
            # ignores a read-only mode, so chmod would not fault here).
            def break_dir():
                shutil.rmtree(status_dir)
                open(status_dir, "w").close()

            def mend_dir():
                os.remove(status_dir)
                os.mkdir(status_dir)

            self.fault("status folder unwritable", break_dir, mend_dir, "status.json", status_names=False,
                       status_frozen=True)

            def storm():
                for _ in range(100):
                    self.proc.send_signal(signal.SIGHUP)
                    time.sleep(0.01)

            self.fault("SIGHUP storm (100 in a second)", storm, lambda: None, "reloaded", status_names=False)

    def sigterm_during_reload(self):
        """A [camera] change (the longest reload: new camera and GL context), SIGTERM at once."""
        print("SIGTERM during a reload ...", flush=True)
        self.write("scene.toml", scene(seed=7))
        self.proc.send_signal(signal.SIGHUP)
        time.sleep(0.05)
        sent = time.monotonic()
        self.proc.send_signal(signal.SIGTERM)
        try:
            rc = self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = None
        took = time.monotonic() - sent
        self.check(rc == 0, f"SIGTERM during a reload: exit {rc}")
        self.check("stopped after" in self.log(), "SIGTERM during a reload: no 'stopped after' line")
        self.table.append(("SIGTERM during a reload", "-", 0, "-", f"exit {rc} after {took:.2f} s"))


CAMERA_SCENE = """[camera]
source = "v4l2"
device = "/dev/video-lumar-test"
width = 640
height = 480
fps = 30
timeout_ms = 2000

[output]
path = "out.png"
status_path = "status/status.json"
"""

# (fault, the virtual camera's settings, what the log line and the outage's STATUS= name; None:
# lumar rides it through without an outage, so only the log names it).
CAMERA_FAULTS = [
    ("camera unplugged and back", {"LUMAR_VCAM_FAULT_UNPLUG_AT": "45"}, "unplugged", "unplugged"),
    # The camera's clock runs from STREAMON, and lumar's start (GL, detector) can take over
    # 10 s on a loaded machine, by when an early stall would be over: frame 450 is 15 s in.
    ("camera stalls 5 s", {"LUMAR_VCAM_FAULT_STALL_AT": "450", "LUMAR_VCAM_FAULT_STALL_MS": "5000"},
     "no frame for 2 s", "no frame for 2 s"),
    ("1 % corrupt frames (MJPEG)", {"LUMAR_VCAM_FORMATS": "MJPG", "LUMAR_VCAM_FAULT_CORRUPT_EVERY": "100"},
     "is corrupt", None),
    ("short frames (YUYV, every 50th)", {"LUMAR_VCAM_FORMATS": "YUYV", "LUMAR_VCAM_FAULT_SHORT_EVERY": "50"},
     "is corrupt", None),
]


class NotifySocket:
    """A datagram socket standing in for systemd's: every message with its arrival time."""

    def __init__(self, path):
        self.path = path
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.sock.bind(path)
        self.sock.settimeout(0.2)
        self.messages = []  # (monotonic time, text)
        self.lock = threading.Lock()
        self.running = True
        self.thread = threading.Thread(target=self.listen, daemon=True)
        self.thread.start()

    def listen(self):
        while self.running:
            try:
                data = self.sock.recv(4096)
            except socket.timeout:
                continue
            except OSError:
                return
            with self.lock:
                for line in data.decode(errors="replace").splitlines():
                    self.messages.append((time.monotonic(), line))

    def snapshot(self):
        with self.lock:
            return list(self.messages)

    def close(self):
        self.running = False
        self.thread.join()
        self.sock.close()
        os.unlink(self.path)


def camera_fault(name, env_fault, logged, outage, lumar, vcam, work, limit, table, failures):
    """One `lumar run` against the virtual camera with one fault; rows into table."""
    print(f"{name} ...", flush=True)
    run = os.path.join(work, "camera-" + str(len(table)))
    os.makedirs(os.path.join(run, "status"))
    with open(os.path.join(run, "scene.toml"), "w") as f:
        f.write(CAMERA_SCENE)
    notify = NotifySocket(os.path.join(run, "notify.sock"))
    env = dict(os.environ, LD_PRELOAD=vcam, LUMAR_VCAM_DEVICE="/dev/video-lumar-test",
               NOTIFY_SOCKET=notify.path, WATCHDOG_USEC="200000")
    env.pop("WATCHDOG_PID", None)
    env.update(env_fault)
    log_path = os.path.join(run, "lumar.log")
    status_path = os.path.join(run, "status", "status.json")
    log_file = open(log_path, "w")
    proc = subprocess.Popen([lumar, "run", "--config", "scene.toml"], stdout=log_file, stderr=subprocess.STDOUT,
                            cwd=run, env=env)

    def log():
        with open(log_path, errors="replace") as f:
            return f.read()

    def frames():
        try:
            with open(status_path) as f:
                return json.load(f)["frames"]
        except (OSError, ValueError, KeyError):
            return 0

    def wait(condition, seconds):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline and proc.poll() is None:
            if condition():
                return True
            time.sleep(0.05)
        return False

    ok = True

    def check(good, what):
        nonlocal ok
        if not good:
            failures.append(f"{name}: {what}")
            print(f"  FAIL: {name}: {what}", flush=True)
            ok = False
        return good

    started = time.monotonic()
    check(wait(lambda: frames() >= 3, limit), "no frames at start")
    check(wait(lambda: logged in log(), limit), f"no log line names '{logged}'")
    lines = [line for line in log().splitlines() if logged in line]
    # An outage: the STATUS= naming it, then frames again (the first WATCHDOG=1 after it).
    said = recovery = None
    if outage is not None:
        def recovered():
            messages = notify.snapshot()
            down = next((t for t, m in messages if m.startswith("STATUS=camera unavailable") and outage in m), None)
            up = next((t for t, m in messages if down is not None and t > down and m == "WATCHDOG=1"), None)
            return (down, up) if up is not None else None

        check(wait(lambda: recovered() is not None, limit), f"no STATUS= naming '{outage}' followed by frames")
        times = recovered()
        if times:
            said = True
            recovery = times[1] - times[0]
    check(proc.poll() is None, "lumar died")
    before = frames()
    check(wait(lambda: frames() > before, limit), "frames do not advance after the fault")
    proc.send_signal(signal.SIGTERM)
    try:
        rc = proc.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        proc.kill()
        rc = None
    log_file.close()
    notify.close()
    check(rc == 0, f"exit {rc} on SIGTERM")
    if not ok:
        print("  log ends:\n    " + "\n    ".join(log().splitlines()[-6:]), flush=True)
    first = lines[0].strip() if lines else "-"
    table.append((name, f"'{logged}': {first[:90]}", len(lines), "STATUS= yes" if said else "-",
                  f"{recovery:.2f}" if recovery is not None else ("rides through" if ok else "none"),
                  f"{time.monotonic() - started:.0f} s"))


def camera_campaign(lumar, vcam, work, limit):
    """Runs CAMERA_FAULTS; returns (table rows, failures)."""
    if not os.path.exists(vcam):
        return [], [f"no virtual camera at {vcam} (build the lumar_vcam target, or --vcam)"]
    table, failures = [], []
    for name, env_fault, logged, outage in CAMERA_FAULTS:
        camera_fault(name, env_fault, logged, outage, lumar, vcam, work, limit, table, failures)
    return table, failures


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lumar", default=os.path.join(ROOT, "build", "lumar"))
    parser.add_argument("--rounds", type=int, default=1, help="repeat the fault sequence (the long campaign)")
    parser.add_argument("--limit", type=float, default=30.0, help="seconds a reaction or recovery may take")
    parser.add_argument("--keep", help="work in this folder and keep it")
    parser.add_argument("--camera", action="store_true", help="also the camera faults (virtual V4L2 camera)")
    parser.add_argument("--camera-only", action="store_true", help="only the camera faults")
    parser.add_argument("--vcam", help="liblumar_vcam.so (default: beside --lumar, tests/vcam/)")
    args = parser.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="lumar-faults-")
    os.makedirs(os.path.join(work, "status"), exist_ok=True)
    shutil.copy(os.path.join(ROOT, "tests", "data", "models", "BoxTextured.glb"), os.path.join(work, "box.glb"))
    shutil.copy(os.path.join(ROOT, "daemon", "assets", "env", "venice_sunset_1k.hdr"), os.path.join(work, "env.hdr"))
    with open(os.path.join(work, "calib.yaml"), "w") as f:
        f.write(CALIBRATION)
    with open(os.path.join(work, "scene.toml"), "w") as f:
        f.write(scene())
    lumar = os.path.abspath(args.lumar)
    started = time.monotonic()
    failures = []
    if not args.camera_only:
        c = Campaign(lumar, work, args.limit)
        c.start()
        try:
            c.run(args.rounds)
            c.sigterm_during_reload()
        except Died as e:
            c.failures.append(str(e))
            print(f"  FAIL: {e}", flush=True)
        finally:
            if c.alive():
                c.proc.kill()
        print(f"\n| fault | log names | lines | status.json names it | recovery (s) |")
        print("|---|---|---|---|---|")
        for row in c.table:
            print("| " + " | ".join(str(x) for x in row) + " |")
        print(f"\n{len(c.table)} faults in {time.monotonic() - started:.0f} s, {len(c.failures)} failed assertion(s); "
              f"log {c.log_path}")
        failures += c.failures
    if args.camera or args.camera_only:
        camera_started = time.monotonic()
        vcam = args.vcam or os.path.join(os.path.dirname(lumar), "tests", "vcam", "liblumar_vcam.so")
        table, camera_failures = camera_campaign(lumar, os.path.abspath(vcam), work, args.limit)
        print("\n| camera fault | log line | lines | outage named | recovery (s) | run |")
        print("|---|---|---|---|---|---|")
        for row in table:
            print("| " + " | ".join(str(x) for x in row) + " |")
        print(f"\n{len(table)} camera faults in {time.monotonic() - camera_started:.0f} s, "
              f"{len(camera_failures)} failed assertion(s); logs under {work}")
        failures += camera_failures
    if not args.keep and not failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
