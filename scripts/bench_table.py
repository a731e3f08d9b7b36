#!/usr/bin/env python3
"""Issue 18's table: `lumar bench` on the car scene's variants, builds interleaved and repeated.

Runs every scene (car, car with bloom, camera+hdr with bloom: replayed; car and car with bloom:
live fake camera) with each build in turn, REPS times over, and prints one Markdown table of
medians: fps, frame time, capture-to-present latency, CPU per frame and peak resident memory.
The scenes are daemon/assets/scenes/car.toml with its paths made absolute, written to a
temporary folder. This machine is shared: compare builds within one run, never across runs,
and read the load column.

  python3 scripts/bench_table.py --reps 3 base=/tmp/lumar.old new=build/lumar
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "daemon", "assets", "scenes", "car.toml")

# (name, text appended to car.toml, replay)
LENS = "\n[rendering.lens]\nenabled = true\n"
VARIANTS = [
    ("car, replay", "", True),
    ("car +bloom, replay", LENS, True),
    ("camera+hdr +bloom, replay", LENS, True),
    ("car, live", "", False),
    ("car +bloom, live", LENS, False),
]


def write_scenes(folder):
    text = open(SCENE, encoding="utf-8").read()
    # Paths in car.toml are relative to it: "../models/x.glb" and the like.
    text = re.sub(r'"\.\./', '"' + os.path.join(ROOT, "daemon", "assets") + "/", text)
    camera = text.replace("[environment]\n", '[environment]\nsource = "camera+hdr"\n', 1)
    camera = camera.replace("[rendering]\n", "[rendering]\nphantoms_show_camera = true\n", 1)
    paths = []
    for index, (name, extra, _) in enumerate(VARIANTS):
        path = os.path.join(folder, f"scene{index}.toml")
        with open(path, "w", encoding="utf-8") as out:
            out.write((camera if name.startswith("camera") else text) + extra)
        paths.append(path)
    return paths


def bench(binary, scene, replay, frames):
    command = [binary, "bench", "--config", scene, "--frames", str(frames), "--no-profile", "--json"]
    if replay:
        command.append("--replay")
    load = float(open("/proc/loadavg", encoding="ascii").read().split()[0])
    result = json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)
    return {"fps": result["fps"], "p50": result["frame_ms"]["p50"], "p99": result["frame_ms"]["p99"],
            "lat50": result["latency_ms"]["p50"], "lat99": result["latency_ms"]["p99"],
            "cpu": result["cpu_ms_per_frame"], "peak": result["peak_rss_mb"], "load": load}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("builds", nargs="+", help="NAME=PATH of a lumar binary, first the base")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--frames", type=int, default=200)
    args = parser.parse_args()
    builds = [tuple(b.split("=", 1)) for b in args.builds]
    results = {}
    with tempfile.TemporaryDirectory() as folder:
        scenes = write_scenes(folder)
        for rep in range(args.reps):
            for (name, _, replay), scene in zip(VARIANTS, scenes):
                for build, path in builds:
                    run = bench(os.path.abspath(path), scene, replay, args.frames)
                    results.setdefault((name, build), []).append(run)
                    print(f"rep {rep + 1} | {name} | {build}: {run['fps']:.2f} fps, CPU {run['cpu']:.1f} ms, "
                          f"load {run['load']:.2f}", flush=True)

    def median(runs, key):
        return statistics.median(run[key] for run in runs)

    names = " / ".join(build for build, _ in builds)
    print(f"\n| scene | fps ({names}) | runs | p50 / p99 ms | latency p50 / p99 ms | CPU ms/frame | peak MiB |")
    print("|---|---|---|---|---|---|---|")
    for name, _, _ in VARIANTS:
        cells = {key: [] for key in ("fps", "runs", "frame", "latency", "cpu", "peak")}
        for build, _ in builds:
            runs = results[(name, build)]
            cells["fps"].append(f"{median(runs, 'fps'):.2f}")
            cells["runs"].append(" ".join(f"{run['fps']:.1f}" for run in runs))
            cells["frame"].append(f"{median(runs, 'p50'):.1f} / {median(runs, 'p99'):.1f}")
            cells["latency"].append(f"{median(runs, 'lat50'):.1f} / {median(runs, 'lat99'):.1f}")
            cells["cpu"].append(f"{median(runs, 'cpu'):.2f}")
            cells["peak"].append(f"{median(runs, 'peak'):.1f}")
        print(f"| {name} | " + " | ".join(" → ".join(cells[key]) for key in cells) + " |")
    loads = [run["load"] for runs in results.values() for run in runs]
    print(f"\nload (1-minute average before each run) {min(loads):.2f}-{max(loads):.2f}; medians of {args.reps}")


if __name__ == "__main__":
    main()
