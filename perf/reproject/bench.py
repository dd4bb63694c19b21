#!/usr/bin/env python3
"""Reprojection methods (issues 4 and 5): exact per-pixel ownership against OSMesa, each
with and without pipelining (`--pipeline`: the next frame prepared on a thread of its own).

Walks the same path in full mode with the four variants, interleaved, R repetitions, and
reports per variant: the median frame time, the reprojection time left on the critical
path, the time the pipelined preparation took on its own thread and how long the frame
then waited for it (what did not overlap), and the fast pixels over the walk.

    perf/reproject/bench.py [--scene scenes/artroom.nff] [--path scenes/paths/artroom-walk.path]
                            [--size 800x600] [--threads 2] [--reps 3] [--methods exact,osmesa]
                            [--exe build/epsray]
                            [--out perf/results/reproject.md]
"""
import argparse
import os
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import add_walk_arguments, run_walk  # noqa: E402

VARIANTS = [("exact", []), ("exact, pipelined", ["--pipeline"]), ("osmesa", ["--reproject", "osmesa"]),
            ("osmesa, pipelined", ["--reproject", "osmesa", "--pipeline"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_walk_arguments(ap, "reproject.md")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--methods", default="exact,osmesa",
                    help="which reprojection methods, each with and without --pipeline (exact where OSMesa is absent)")
    a = ap.parse_args()
    variants = [(name, flags) for name, flags in VARIANTS if name.split(",")[0] in a.methods.split(",")]
    runs = {name: [] for name, _ in variants}
    for _ in range(a.reps):
        for name, flags in variants:  # interleaved: each repetition sees the machine alike
            runs[name].append(run_walk(a.exe, a.scene, a.path, ["--mode", "full", "--size", a.size, "--threads",
                                                                a.threads, "--eps", 0.05] + flags)["frames"][1:])
    med = statistics.median
    lines = ["# Reprojection methods (%s, %s, %d threads, %d rep(s); %s)" %
             (os.path.basename(a.scene), a.size, a.threads, a.reps, time.strftime("%Y-%m-%d %H:%M")), "",
             "| variant | frame ms (per rep) | reprojection on the critical path ms | prepared ahead ms | waited ms | "
             "fast pixels |", "|---|---:|---:|---:|---:|---:|"]
    base = None
    for name, _ in variants:
        reps = runs[name]
        ms = [med(f["ms"] for f in r) for r in reps]
        base = base or med(ms)
        lines.append("| %s | %.1f (%s; %.3f of exact) | %.1f | %.1f | %.2f | %d |" % (
            name, med(ms), " ".join("%.1f" % x for x in ms), med(ms) / base,
            med(med(f["reproject_ms"] for f in r) for r in reps), med(med(f.get("ahead_ms", 0) for f in r) for r in reps),
            med(med(f.get("ahead_wait_ms", 0) for f in r) for r in reps), sum(f["pixels"]["fast"] for f in reps[0])))
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
