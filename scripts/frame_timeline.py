#!/usr/bin/env python3
"""Where a frame's cores sit idle: `lumar bench` under perf, phase by phase (issue 18).

On a software rasteriser the frame is two kinds of work: this process's render thread binds
state and bins draws, llvmpipe's threads rasterise the scenes it has flushed. A core is idle
when the render thread works alone (nothing flushed to rasterise) or waits while the
rasteriser finishes a scene on one thread. This script puts uprobes on the renderer's stage
entry points, records every context switch of the machine for a few seconds of a running
`lumar bench`, and prints per frame and phase (the last stage entered by the render thread):
wall time, idle core time, time the render thread ran alone, and the rasteriser's core time.

Needs root (uprobes, system-wide sched_switch) and `perf` (Debian: linux-perf). Numbers are
per frame, in ms. A development tool: not run by the tests.

  sudo python3 scripts/frame_timeline.py --config daemon/assets/scenes/car.toml [--binary build/lumar]
      [--seconds 3] [--frame N]   (--frame: print that frame's segments instead of the phases)
"""
import argparse
import collections
import os
import re
import subprocess
import sys
import tempfile
import time

# Stage entry points (mangled-name prefixes) and the phase each starts. MeshPass::draw runs in
# several phases (cube faces, the frame) and does not start one.
PROBES = [
    ("step", "_ZN5lumar8Pipeline4stepE"),
    ("shadows", "_ZN5lumar10ShadowPass6renderE"),
    ("bg_upload", "_ZN5lumar14BackgroundPass10uploadIntoE"),
    ("bg_draw", "_ZN5lumar14BackgroundPass12drawUploadedE"),
    ("camera_upload", "_ZN5lumar11CameraImage13uploadReducedE"),
    ("phantom_depth", "_ZN5lumar12PhantomDepth6renderE"),
    ("probes", "_ZN5lumar17EnvironmentProbes6updateE"),
    ("mirror", "_ZNK5lumar11IblPipeline17renderMirrorSlotsE"),
    ("probe_faces", "_ZN5lumar17EnvironmentProbes13drawProbeFaceE"),
    ("sh", "_ZNK5lumar11IblPipeline14projectSHSlotsE"),
    ("sh_sums", "_ZNK5lumar11IblPipeline10sumSamplesE"),
    ("derived_maps", "_ZNK5lumar11IblPipeline11renderFacesE"),
    ("receivers", "_ZN5lumar10ShadowPass13drawReceiversE"),
    # Only with lens effects on; without, the frame's meshes count under "receivers".
    ("frame_meshes", "_ZNK5lumar11LensEffects12beginVirtualE"),
    ("lens", "_ZN5lumar11LensEffects11applyCulledE"),
    ("lens_readback", "_ZN5lumar11LensEffects18readRadianceHalvedE"),
    ("lens_composite", "_ZN5lumar11LensEffects9compositeE"),
    ("readback", "_ZN5lumar13FrameReadback4readE"),
]
EVENT = re.compile(r"\s*(\S.*?)\s+(\d+)\s+\[(\d+)\]\s+(\d+\.\d+):\s+(\S+):\s*(.*)$")


def run(command, **kwargs):
    return subprocess.run(command, check=True, text=True, capture_output=True, **kwargs)


def add_probes(binary):
    subprocess.run(["perf", "probe", "-d", "probe_lumar:*"], capture_output=True)
    symbols = run(["nm", binary]).stdout.split("\n")
    for index, (_, prefix) in enumerate(PROBES):
        name = next((line.split()[2] for line in symbols if re.search(r" [tT] " + prefix, line)), None)
        if name is None:
            sys.exit(f"{binary}: no symbol {prefix}*")
        run(["perf", "probe", "-x", binary, "-a", f"p{index}={name}"])


def record(args, folder):
    data = os.path.join(folder, "perf.data")
    bench = subprocess.Popen([args.binary, "bench", "--config", args.config, "--replay", "--frames", "100000",
                              "--no-profile"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(args.warmup)
        run(["perf", "record", "-a", "-o", data, "-e", "sched:sched_switch", "-e", "probe_lumar:*", "--",
             "sleep", str(args.seconds)])
    finally:
        bench.kill()
        bench.wait()
        subprocess.run(["perf", "probe", "-d", "probe_lumar:*"], capture_output=True)
    return run(["perf", "script", "-i", data, "-F", "comm,tid,cpu,time,event,trace"]).stdout


def analyse(text, args):
    events = []
    for line in text.split("\n"):
        m = EVENT.match(line)
        if m:
            events.append((float(m.group(4)), int(m.group(3)), int(m.group(2)), m.group(5), m.group(6)))
    events.sort()
    render = next((e[2] for e in events if e[3] == "probe_lumar:p0"), None)
    if render is None:
        sys.exit("no frame was recorded")
    names = {}
    for e in events:
        if e[3] == "sched:sched_switch":
            m = re.search(r"next_comm=(.*?) next_pid=(\d+)", e[4])
            names[int(m.group(2))] = m.group(1)
    cpus = len({e[1] for e in events})
    # Whole frames only: from the first frame's start to the last one's.
    steps = [e[0] for e in events if e[3] == "probe_lumar:p0" and e[2] == render]
    if len(steps) < 2:
        sys.exit("fewer than two frame starts were recorded")
    running, phase, previous = {}, "?", events[0][0]
    wall, idle, alone, raster = (collections.Counter() for _ in range(4))
    segments, frames = [], 0
    for t, cpu, tid, event, rest in events:
        span = t - previous
        if len(running) == cpus and span > 0 and steps[0] <= previous and t <= steps[-1]:
            busy = [p for p in running.values() if p != 0]
            rasterising = sum(1 for p in busy if names.get(p, "").startswith("llvmpipe"))
            wall[phase] += span
            idle[phase] += (cpus - len(busy)) * span
            alone[phase] += span if busy == [render] else 0.0
            raster[phase] += rasterising * span
            if frames == args.frame:
                state = ("R" if render in busy else ".") + str(rasterising) + "-" * (cpus - len(busy))
                segments.append((previous, span, state, phase))
        if event == "sched:sched_switch":
            running[cpu] = int(re.search(r"next_pid=(\d+)", rest).group(1))
        elif event.startswith("probe_lumar:p") and tid == render:
            index = int(event.split(":p")[1])
            if index == 0:
                frames += 1
            phase = PROBES[index][0]
        previous = t
    if args.frame is not None:
        start = segments[0][0] if segments else 0.0
        print("ms from the frame's start, length, R = render thread running, digit = rasteriser threads, - = an idle core")
        merged = []
        for t, span, state, name in segments:
            if merged and merged[-1][2:] == [state, name]:
                merged[-1][1] += span
            else:
                merged.append([t, span, state, name])
        for t, span, state, name in merged:
            if span >= 5e-5:
                print(f"{(t - start) * 1e3:8.2f} {span * 1e3:6.2f} {state:3} {name}")
        return
    frames = len(steps) - 1
    print(f"{frames} frames, {cpus} cores; ms per frame")
    print(f"{'phase':15} {'wall':>7} {'idle':>7} {'alone':>7} {'raster':>7}")
    for name, _ in PROBES:
        print(f"{name:15} {wall[name] * 1e3 / frames:7.2f} {idle[name] * 1e3 / frames:7.2f} "
              f"{alone[name] * 1e3 / frames:7.2f} {raster[name] * 1e3 / frames:7.2f}")
    print(f"{'total':15} {sum(wall.values()) * 1e3 / frames:7.2f} {sum(idle.values()) * 1e3 / frames:7.2f} "
          f"{sum(alone.values()) * 1e3 / frames:7.2f} {sum(raster.values()) * 1e3 / frames:7.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--config", required=True)
    parser.add_argument("--binary", default="build/lumar")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--warmup", type=float, default=9.0, help="seconds before recording (start-up)")
    parser.add_argument("--frame", type=int, help="print the segments of this recorded frame")
    args = parser.parse_args()
    args.binary = os.path.abspath(args.binary)
    add_probes(args.binary)
    with tempfile.TemporaryDirectory() as folder:
        analyse(record(args, folder), args)


if __name__ == "__main__":
    main()
