#!/usr/bin/env python3
"""Thread scaling as a share of the machine's own limit (issue 28's scaling target).

A machine with N cores does not run one thread N times as fast: cores share caches,
memory bandwidth and clocks. Its own limit is what N independent one-thread walks get
done when they run at once. For each walk and mode this script times, interleaved over
R repetitions:

  T1     one one-thread walk alone
  Tonce  N one-thread walks started at once (the median of their times)
  TN     one walk on N threads

and reports the speedup T1 / TN, the machine's limit N T1 / Tonce, and the share of the
limit reached, (T1 / TN) / (N T1 / Tonce) = Tonce / (N TN): the walk's throughput on N
threads over that of N single-thread processes. Times are each walk's total_ms (every
frame, the cold first one included), medians over the repetitions. A second table says
where the last N-thread run's time went: its first frame, the tile phases, the
reprojection, the work after the tiles, and what lies outside the frames.

    perf/scaling/ceiling.py [--exe build/epsray] [--threads N] [--reps 2] [--out FILE.md]
        [--walk NAME,SCENE,PATH,SIZE ...]
Default walks: the art room's walk at 800x600, and 16-frame orbits at 640x480 of
balls-s3 and teapot-s6 where present (../shared/scenes/spd or --spd).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import orbit_path  # noqa: E402


def total_ms(procs, keep=None):
    """Waits for `epsray walk` processes; their total_ms, in order (keep: the last stats)."""
    out = []
    for p, stats in procs:
        if p.wait() != 0:
            sys.exit("ceiling: a walk failed (exit %d)" % p.returncode)
        with open(stats) as f:
            d = json.load(f)
        out.append(d["total_ms"])
        if keep is not None:
            keep[:] = [d]
    return out


def breakdown(d):
    """Where an N-thread walk's total_ms went, in ms."""
    fr = d["frames"]
    ms = sum(f["ms"] for f in fr)
    shade = sum(f["sched"]["shade_ms"] for f in fr)
    waits = sum(f["sched"]["join_ms"] + f["sched"]["tail_ms"] for f in fr)
    rp = sum(f.get("reproject_ms", 0) for f in fr)
    after = sum(f["sched"]["after_ms"] for f in fr)
    probe = sum(f.get("probe", {}).get("ms", 0) for f in fr)
    return (d["total_ms"], fr[0]["ms"], statistics.median(f["ms"] for f in fr[1:]) if len(fr) > 1 else 0, shade, waits,
            rp, after, probe, ms - shade - rp - after - probe, d["total_ms"] - ms)


def start(exe, w, mode, threads, stats):
    name, scene, path, size = w
    cmd = [exe, "walk", scene, "--path", path, "--size", size, "--mode", mode, "--threads", str(threads),
           "--quiet", "--stats", stats]
    return subprocess.Popen(cmd), stats


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--reps", type=int, default=2)
    ap.add_argument("--modes", default="base,full")
    ap.add_argument("--spd", default=os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd"))
    ap.add_argument("--walk", action="append", default=[], help="NAME,SCENE,PATH,SIZE")
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "ceiling.md"))
    a = ap.parse_args()
    n = a.threads
    tmp = tempfile.mkdtemp()
    walks = [tuple(s.split(",")) for s in a.walk]
    if not walks:
        art = os.path.join(ROOT, "scenes", "artroom.nff")
        walks.append(("artroom walk", art, os.path.join(ROOT, "scenes", "paths", "artroom-walk.path"), "800x600"))
        for name, scene in [("balls-s3", os.path.join(a.spd, "balls-s3.nff")),
                            ("teapot-s6", os.path.join(a.spd, "teapot-s6.nff"))]:
            if os.path.exists(scene):
                path = os.path.join(tmp, name + ".path")
                orbit_path(scene, 16, path)
                walks.append((name + " orbit", scene, path, "640x480"))
    info = subprocess.run([a.exe, "info"], capture_output=True, text=True).stdout.strip()
    rows, parts = [], []
    for w in walks:
        for mode in a.modes.split(","):
            t1, tonce, tn, last = [], [], [], []
            for r in range(a.reps):
                t1 += total_ms([start(a.exe, w, mode, 1, os.path.join(tmp, "a.json"))])
                ms = total_ms([start(a.exe, w, mode, 1, os.path.join(tmp, "c%d.json" % i)) for i in range(n)])
                tonce.append(statistics.median(ms))
                tn += total_ms([start(a.exe, w, mode, n, os.path.join(tmp, "n.json"))], last)
            T1, Tonce, TN = (statistics.median(v) for v in (t1, tonce, tn))
            row = (w[0], w[3], mode, T1, Tonce, TN, T1 / TN, n * T1 / Tonce, Tonce / (n * TN))
            rows.append(row)
            parts.append((w[0], mode) + breakdown(last[0]))
            print("%s %s %s: T1 %.0f ms, %d at once %.0f ms, %d threads %.0f ms; speedup %.2f, limit %.2f, share %.3f"
                  % (row[:3] + (T1, n, Tonce, n, TN) + row[6:]), flush=True)
    lines = ["# Thread scaling against the machine's limit (%d threads, %d rep(s), total ms; %s)" %
             (n, a.reps, time.strftime("%Y-%m-%d %H:%M")), "", "Machine (`epsray info`):", "", "```", info, "```", "",
             "| walk | size | mode | T1 ms | %d at once ms | %d threads ms | speedup | limit | share |" % (n, n),
             "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    lines += ["| %s | %s | %s | %.0f | %.0f | %.1f | %.2f | %.2f | %.3f |" % r for r in rows]
    lines += ["", "Where the last %d-thread run's time went (ms): the whole walk, its first frame, its median frame" % n,
              "after that; summed over frames, the tile phases (of which the threads' waits before their first",
              "tile and after their last), the reprojection, the work after the tiles, the probes, the rest of",
              "the frames; and what lies outside the frames (the world's and linetrees' set-up).", "",
              "| walk | mode | total | frame 0 | median frame | tiles | waits | reproject | after | probe | rest | outside |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    lines += ["| %s | %s | " % p[:2] + " | ".join("%.1f" % v for v in p[2:]) + " |" for p in parts]
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", a.out)


if __name__ == "__main__":
    main()
