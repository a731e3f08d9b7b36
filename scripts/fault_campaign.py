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

Not injected here (they need the virtual V4L2 camera, see tests/integration/v4l2): camera
unplug, stalls, corrupt and short frames. SIGUSR1 is not sent: lumar does not handle it (its
default action ends a process, as for any daemon that does not claim it).

  fault_campaign.py --lumar BINARY [--rounds N] [--limit S] [--keep DIR]
Exit status 0 when every assertion held."""
import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
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


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lumar", default=os.path.join(ROOT, "build", "lumar"))
    parser.add_argument("--rounds", type=int, default=1, help="repeat the fault sequence (the long campaign)")
    parser.add_argument("--limit", type=float, default=30.0, help="seconds a reaction or recovery may take")
    parser.add_argument("--keep", help="work in this folder and keep it")
    args = parser.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="lumar-faults-")
    os.makedirs(os.path.join(work, "status"), exist_ok=True)
    shutil.copy(os.path.join(ROOT, "tests", "data", "models", "BoxTextured.glb"), os.path.join(work, "box.glb"))
    shutil.copy(os.path.join(ROOT, "daemon", "assets", "env", "venice_sunset_1k.hdr"), os.path.join(work, "env.hdr"))
    with open(os.path.join(work, "calib.yaml"), "w") as f:
        f.write(CALIBRATION)
    with open(os.path.join(work, "scene.toml"), "w") as f:
        f.write(scene())
    c = Campaign(os.path.abspath(args.lumar), work, args.limit)
    started = time.monotonic()
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
    if not args.keep and not c.failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if c.failures else 0


if __name__ == "__main__":
    sys.exit(main())
