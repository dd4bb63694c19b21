#!/usr/bin/env python3
"""Thread scaling (issue 5): the same walks on 1, 2, ... N threads.

For each scene and mode (base, interp, full), runs `epsray walk` over a short camera path
at each thread count, interleaved, R repetitions; reports the median frame time, the
speedup over one thread and the parallel efficiency, with the machine's hwloc topology
(`epsray info`), and draws speedup against threads (gnuplot, when installed).

    perf/scaling/bench.py [--threads 1,2,4,...] [--frames 12] [--size 640x480] [--reps 1]
                          [--exe build/epsray] [--out perf/results/scaling.md] [SCENE ...]
Default scenes: scenes/artroom.nff and, when present, ../shared/scenes/spd/balls-s3 and
teapot-s6; each walks 12 frames of a slow orbit around its own camera's target.
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
SPD = os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd")
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import gnuplot, gp_text, orbit_path, run_walk  # noqa: E402


def walk(exe, scene, path, mode, size, threads, pin, tile_rows=None):
    flags = ["--mode", mode, "--size", size, "--threads", threads] + (["--pin"] if pin else [])
    return run_walk(exe, scene, path, flags + (["--tile-rows", tile_rows] if tile_rows else []))


def report(a, info, rows):
    """Writes the Markdown table, and the chart where gnuplot is installed."""
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(os.path.splitext(a.out)[0] + ".json", "w") as f:
        json.dump({"size": a.size, "frames": a.frames, "reps": a.reps, "pin": a.pin, "tile_rows": a.tile_rows, "info": info, "rows": rows}, f)
    lines = ["# Thread scaling (%s, %d frames, %d rep(s), median frame ms%s; %s)" %
             (a.size, a.frames, a.reps, (", workers pinned" if a.pin else "") + (", %d-row tiles" % a.tile_rows if getattr(a, "tile_rows", None) else ""), time.strftime("%Y-%m-%d %H:%M")), "", "Machine (`epsray info`):", "",
             "```", info, "```", "",
             "| scene | mode | threads | frame ms | speedup | efficiency |", "|---|---|---:|---:|---:|---:|"]
    lines += ["| %s | %s | %d | %.1f | %.2f | %.2f |" % r for r in rows]
    text = "\n".join(lines) + "\n"
    with open(a.out, "w") as f:
        f.write(text)
    dat = os.path.splitext(a.out)[0] + ".dat"
    png = os.path.splitext(a.out)[0] + ".png"
    series = sorted({(r[0], r[1]) for r in rows})
    with open(dat, "w") as f:
        for name, mode in series:
            f.write("# %s %s\n" % (name, mode))
            for r in rows:
                if (r[0], r[1]) == (name, mode):
                    f.write("%d %.4f\n" % (r[2], r[4]))
            f.write("\n\n")
    # One colour per scene, one point and dash per mode.
    names = sorted({n for n, _ in series})
    kinds = {"base": (1, 7), "interp": (3, 4), "full": (2, 5)}
    plots = ", ".join("'%s' index %d with linespoints lw 2 lc %d dt %d pt %d title '%s %s'" %
                      (dat, i, names.index(n) + 1, kinds.get(m, (1, 1))[0], kinds.get(m, (1, 1))[1], n, m)
                      for i, (n, m) in enumerate(series))
    title = "Speedup over one thread (%s, %d frames, median frame%s)" % (
        a.size, a.frames, ", workers pinned" if a.pin else "")
    counts = sorted({r[2] for r in rows})
    top = 1.05 * max(counts + [1])
    script = ("set terminal pngcairo noenhanced size 900,600; set output '%s'; set title %s; "
              "set xlabel 'threads'; set ylabel 'speedup over 1 thread'; set xrange [0:%g]; set yrange [0:%g]; "
              "set xtics (%s); set key outside right; set grid; plot x title 'ideal' dashtype 2 lc 'gray', %s" %
              (png, gp_text(title), top, top, ", ".join(str(c) for c in counts), plots))
    gnuplot(script, png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--threads", default=None, help="comma list; default 1, 2, 4, ... up to the cores")
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--modes", default="base,interp,full")
    ap.add_argument("--pin", action="store_true", help="bind workers to cores (epsray --pin)")
    ap.add_argument("--tile-rows", type=int, help="rows per tile (default: epsray's, from the thread count)")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "scaling.md"))
    ap.add_argument("--replot", metavar="JSON", help="redraw the table and chart of an earlier run's JSON "
                    "(a run on a machine without gnuplot)")
    a = ap.parse_args()
    if a.replot:
        with open(a.replot) as f:
            r = json.load(f)
        a.size, a.frames, a.reps, a.pin, a.tile_rows = r["size"], r["frames"], r["reps"], r["pin"], r.get("tile_rows")
        report(a, r["info"], [tuple(x) for x in r["rows"]])
        print("wrote", a.out)
        return 0
    cores = os.cpu_count() or 1
    if a.threads:
        counts = [int(t) for t in a.threads.split(",")]
    else:
        counts, t = [], 1
        while t < cores:
            counts.append(t)
            t *= 2
        counts.append(cores)
    scenes = a.scenes or [os.path.join(ROOT, "scenes", "artroom.nff")] + [
        os.path.join(SPD, s + ".nff") for s in ("balls-s3", "teapot-s6") if os.path.exists(os.path.join(SPD, s + ".nff"))]
    modes = a.modes.split(",")
    info = subprocess.run([a.exe, "info"], capture_output=True, text=True).stdout.strip()
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for scene in scenes:
            path = os.path.join(d, "orbit.path")
            orbit_path(scene, a.frames, path)
            name = os.path.splitext(os.path.basename(scene))[0]
            for mode in modes:
                times = {t: [] for t in counts}
                for _ in range(a.reps):
                    for t in counts:  # interleaved over thread counts
                        times[t] += [f["ms"] for f in walk(a.exe, scene, path, mode, a.size, t, a.pin, a.tile_rows)["frames"]]
                med = {t: statistics.median(times[t]) for t in counts}
                for t in counts:
                    s = med[counts[0]] / med[t] * counts[0]
                    rows.append((name, mode, t, med[t], s, s / t))
                    print("%-10s %-6s %3d threads  %8.1f ms  speedup %5.2f  efficiency %4.2f" % rows[-1], flush=True)
                report(a, info, rows)  # after every series, so a run cut short keeps its rows
    report(a, info, rows)
    print("wrote", a.out, "(and .json; .png where gnuplot is installed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
