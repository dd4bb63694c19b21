#!/usr/bin/env python3
"""Full mode against base on walks of the SPD scenes: an orbit and a dolly for each.

For each scene of ../shared/scenes/spd/ named by --scenes, two camera paths made from
the scene's own view: an orbit (1 degree a frame about the view's up axis through 'at')
and a dolly (the eye moves 1% of its distance to 'at' towards it each frame). Each walk
runs in base and in full mode at the same moment, one thread each, one per core, cores
swapped each round (as perf/pair.py does). The figure is base's total time over full's, the
speed-up: per round the geometric mean of its two pairs (which cancels a difference
between the cores, perf/pair.py), and the median over the rounds. A speed-up under 1 is a
walk full mode loses.

    perf/spd/bench.py                      # 5 scenes x 2 paths, 640x480, 16 frames
    perf/spd/bench.py --scenes mount-s4 --paths orbit --size 320x240 --rounds 1

Writes perf/results/spd.json and perf/results/spd.md. Skips (exit 0) without ../shared.
"""
import argparse
import json
import math
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import ROOT, orbit_path, view_of  # noqa: E402
from pair import figure, start  # noqa: E402

SPD = os.path.join(ROOT, "..", "shared", "scenes", "spd")


def dolly_path(scene, frames, out):
    """The eye moves towards 'at' by 1% of its distance a frame."""
    v = view_of(scene)
    f, a, u = v["from"], v["at"], v["up"]
    with open(out, "w") as o:
        for k in range(frames):
            s = 1.0 - 0.01 * k
            p = [a[i] + (f[i] - a[i]) * s for i in range(3)]
            o.write("%g %g %g  %g %g %g  %g %g %g  %g\n" % (*p, *a, *u, v["angle"]))


def walk_cmd(exe, scene, path, size, mode, extra):
    return "%s walk %s --path %s --size %s --threads 1 --mode %s %s" % (exe, scene, path, size, mode, extra)


def pair(ca, cb, cpus):
    """Runs the two commands at once, each on its own core; their 'total X ms' figures."""
    pa, pb = start(ca, cpus[0]), start(cb, cpus[1] if len(cpus) > 1 else None)
    oa, ob = pa.communicate()[0], pb.communicate()[0]
    if pa.returncode or pb.returncode:
        raise SystemExit("spd/bench.py: a walk failed:\n%s\n%s" % (oa[-2000:], ob[-2000:]))
    return figure(oa, "total"), figure(ob, "total")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default="balls-s3,teapot-s6,rings-s3,mount-s4,gears-s2")
    ap.add_argument("--paths", default="orbit,dolly")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=1, help="rounds of two pairs (cores swapped)")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--flags", default="", help="extra flags for the full-mode walks")
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "spd"))
    a = ap.parse_args()
    if not os.path.isdir(SPD):
        print("spd/bench.py: no ../shared/scenes/spd: skipped")
        return 0
    cpus = sorted(os.sched_getaffinity(0))
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for name in a.scenes.split(","):
            scene = os.path.join(SPD, name + ".nff")
            for kind in a.paths.split(","):
                path = os.path.join(d, "%s-%s.path" % (name, kind))
                (orbit_path if kind == "orbit" else dolly_path)(scene, a.frames, path)
                cb = walk_cmd(a.exe, scene, path, a.size, "base", "")
                cf = walk_cmd(a.exe, scene, path, a.size, "full", a.flags)
                ratios, rounds = [], []
                for r in range(a.rounds):
                    for swap in (0, 1):
                        order = cpus if not swap else list(reversed(cpus))
                        tb, tf = pair(cb, cf, order)
                        ratios.append(tb / tf)
                    rounds.append(math.sqrt(ratios[-1] * ratios[-2]))
                row = {"scene": name, "path": kind, "speedup": statistics.median(rounds),
                       "smallest": min(ratios), "largest": max(ratios), "pairs": len(ratios)}
                rows.append(row)
                print("%-10s %-6s full %.3fx base (%.3f-%.3f, %d pairs)" %
                      (name, kind, row["speedup"], row["smallest"], row["largest"], row["pairs"]), flush=True)
    sp = [r["speedup"] for r in rows]
    summary = {"size": a.size, "frames": a.frames, "flags": a.flags, "walks": rows,
               "median": statistics.median(sp), "lowest": min(sp)}
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out + ".json", "w") as f:
        json.dump(summary, f, indent=1)
    with open(a.out + ".md", "w") as f:
        f.write("# SPD walks: full mode against base\n\n")
        f.write("| scene | path | full / base speed-up | range |\n|---|---|---:|---|\n")
        for r in rows:
            f.write("| %s | %s | %.2fx | %.2f-%.2f |\n" % (r["scene"], r["path"], r["speedup"], r["smallest"],
                                                          r["largest"]))
        f.write("\nmedian %.2fx, lowest %.2fx (%s, %d frames, `perf/spd/bench.py`)\n" %
                (summary["median"], summary["lowest"], a.size, a.frames))
    print("median %.3fx, lowest %.3fx; wrote %s.json and .md" % (summary["median"], summary["lowest"], a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
