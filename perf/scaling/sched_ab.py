#!/usr/bin/env python3
"""Where a frame's wall time goes at N threads, for builds or flags side by side (issue 5).

Walks a slow orbit of a scene with each variant, interleaved, R repetitions, and reports
per mode the median frame ms, the thread time (the tiles' cycle counts summed over the
threads, `--stats` path_ms), the reprojection's wall time (full) and, where the build reports it (`--stats` sched), the tile
phase's wall time and the threads' mean wait before their first tile (join) and after
their last (tail), and the wall time after the tile phase (merging cells, eviction); with
--pipeline, the next frame's reprojection prepared ahead on its own thread (ahead) and what
the frame waited for it (ahead wait).

    perf/scaling/sched_ab.py --threads N [--reps 3] [--frames 16] [--size 640x480]
        [--modes base,full] [--scene scenes/artroom.nff] [--out FILE.md]
        --variant NAME=EXE[,FLAG,FLAG...] --variant ...
e.g. --variant scan=build/epsray,--tile-order,scan --variant cost=build/epsray
A FLAG env:KEY=VALUE sets an environment variable for that variant's runs instead, e.g.
env:GLIBC_TUNABLES=glibc.malloc.hugetlb=1 (malloc asks for transparent huge pages).
"""
import argparse
import json
import os
import statistics as st
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import orbit_path  # noqa: E402


def run_walk(exe, scene, path, flags, env):
    """`epsray walk` with --stats, in an environment with `env` added; returns the stats."""
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "s.json")
        subprocess.run([exe, "walk", scene, "--path", path, "--quiet", "--stats", stats] + [str(f) for f in flags],
                       check=True, env=dict(os.environ, **env))
        with open(stats) as f:
            return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--threads", type=int, required=True)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--modes", default="base,full")
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "artroom.nff"))
    ap.add_argument("--variant", action="append", required=True, help="NAME=EXE[,FLAG,...]")
    ap.add_argument("--out")
    a = ap.parse_args()
    variants = []
    for v in a.variant:
        name, _, rest = v.partition("=")
        exe, *flags = rest.split(",")
        env = dict(f[4:].split("=", 1) for f in flags if f.startswith("env:"))
        variants.append((name, exe, [f for f in flags if not f.startswith("env:")], env))
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "orbit.path")
        orbit_path(a.scene, a.frames, path)
        lines = ["# Scheduling at %d threads (%s, %s, %d frames of an orbit, %d interleaved reps; medians over frames 1..%d, then reps)" %
                 (a.threads, os.path.basename(a.scene), a.size, a.frames, a.reps, a.frames - 1), "",
                 "| mode | variant | frame ms | thread ms | thread ms / threads | reproject ms | tile phase ms | join ms | tail ms | after ms | ahead ms | ahead wait ms |",
                 "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for mode in a.modes.split(","):
            got = {name: [] for name, _, _, _ in variants}
            workers = {}
            for _ in range(a.reps):
                for name, exe, flags, env in variants:
                    s = run_walk(exe, a.scene, path, ["--mode", mode, "--size", a.size, "--threads", a.threads] + flags, env)
                    got[name].append(s["frames"][1:])
                    workers[name] = s.get("threads", a.threads)  # a variant may set its own --threads
            for name, _, _, _ in variants:
                def med(fn):
                    vals = [st.median(fn(f) for f in fr) for fr in got[name]]
                    return st.median(vals)
                ms, thread = med(lambda f: f["ms"]), med(lambda f: sum(f["path_ms"].values()))
                row = "| %s | %s | %.1f | %.1f | %.1f | %.1f |" % (mode, name, ms, thread, thread / workers[name],
                                                               med(lambda f: f.get("reproject_ms", 0)))
                if "sched" in got[name][0][0]:
                    row += " %.1f | %.2f | %.2f | %.2f |" % tuple(med(lambda f, k=k: f["sched"][k]) for k in ("shade_ms", "join_ms", "tail_ms", "after_ms"))
                else:
                    row += " | | | |"
                if "ahead_ms" in got[name][0][0]:  # --pipeline: reprojection prepared on its own thread
                    row += " %.1f | %.2f |" % (med(lambda f: f.get("ahead_ms", 0)), med(lambda f: f.get("ahead_wait_ms", 0)))
                else:
                    row += " | |"
                lines.append(row)
                print(row, flush=True)
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
