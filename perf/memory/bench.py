#!/usr/bin/env python3
"""Memory budget over a long walk (issue 8): the 1000 frames of scenes/paths/artroom-long.path
in full mode with no budget and with `--memory-mb M` budgets, and a base walk, side by side.
Reports per run: linetree memory per frame (largest, last), the process's peak, the median
frame time against base and against no budget, and the share of pixels per path; charts
memory and frame time per frame, both from zero (gnuplot).

    perf/memory/bench.py [--budgets 64,25] [--frames 1000] [--size 400x300] [--eps 0.05]
                         [--exe build/epsray] [--out perf/results/memory.md]
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import gnuplot, gp_text, run_walk  # noqa: E402


def walk(exe, path, size, eps, mode, budget):
    flags = ["--mode", mode, "--size", size, "--eps", eps] + (["--memory-mb", budget] if budget else [])
    return run_walk(exe, os.path.join(ROOT, "scenes", "artroom.nff"), path, flags)


def chart(runs, budgets, base, caption):
    """Linetree memory and frame time per frame, one line per budget; both axes from zero,
    the budgets drawn as dashed lines, the keys outside the plots."""
    dat, png = base + ".dat", base + ".png"
    with open(dat, "w") as f:
        for b, r in runs:
            f.write("# budget %g\n" % b)
            for k, fr in enumerate(r["frames"]):
                f.write("%d %.3f %.3f\n" % (k, fr["linetree_bytes"] / 1e6, fr["ms"]))
            f.write("\n\n")
    names = ["no budget"] + ["--memory-mb %g" % b for b in budgets[1:]]
    mem = ", ".join("'%s' index %d u 1:2 w l lw 2 lc %d t %s" % (dat, i, i + 1, gp_text(n)) for i, n in enumerate(names))
    mem += "".join(", %g w l dt 2 lc %d t %s" % (b, i + 2, gp_text("budget %g MB" % b)) for i, b in enumerate(budgets[1:]))
    tms = ", ".join("'%s' index %d u 1:3 w l lc %d t %s" % (dat, i, i + 1, gp_text(n)) for i, n in enumerate(names))
    script = ("set terminal pngcairo noenhanced size 1000,760; set output '%s'; set multiplot layout 2,1 title %s; "
              "set grid; set key outside right; set rmargin 28; set xrange [0:*]; "
              "set title 'linetree memory (linetree_bytes)'; set ylabel 'MB'; set yrange [0:*]; plot %s; "
              "set title 'frame time'; set xlabel 'frame'; set ylabel 'frame ms'; set yrange [0:*]; plot %s; "
              "unset multiplot" % (png, gp_text("Memory budget: " + caption), mem, tms))
    gnuplot(script, png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budgets", default="64,25")
    ap.add_argument("--frames", type=int, default=1000)
    ap.add_argument("--size", default="400x300")
    ap.add_argument("--eps", type=float, default=0.05)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "memory.md"))
    a = ap.parse_args()
    budgets = [0] + [float(b) for b in a.budgets.split(",") if b]
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "long.path")
        with open(os.path.join(ROOT, "scenes", "paths", "artroom-long.path")) as s, open(path, "w") as o:
            o.writelines([l for l in s if l.strip() and not l.lstrip().startswith("#")][:a.frames])
        base = walk(a.exe, path, a.size, a.eps, "base", 0)
        runs = [(b, walk(a.exe, path, a.size, a.eps, "full", b)) for b in budgets]
    base_ms = statistics.median(f["ms"] for f in base["frames"])
    free_ms = statistics.median(f["ms"] for f in runs[0][1]["frames"])
    lines = ["# Memory budget: %d frames of artroom-long.path, %s, full mode, eps %g; %s" %
             (len(base["frames"]), a.size, a.eps, time.strftime("%Y-%m-%d %H:%M")), "",
             "| budget | linetrees MB, largest | last | process peak MB | median frame ms | / base | / no budget | fast | interp | traced |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for b, r in runs:
        fs = r["frames"]
        mem = [f["linetree_bytes"] / 1e6 for f in fs]
        n = sum(sum(f["pixels"].values()) for f in fs)
        px = {k: sum(f["pixels"][k] for f in fs) / n for k in ("fast", "interp", "base")}
        ms = statistics.median(f["ms"] for f in fs)
        lines.append("| %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %.1f%% | %.1f%% | %.1f%% |" % (
            "%g MB" % b if b else "none", max(mem), mem[-1], r["peak_memory_bytes"] / 1e6, ms, ms / base_ms,
            ms / free_ms, 100 * px["fast"], 100 * px["interp"], 100 * px["base"]))
    lines += ["", "Base walk: median frame %.1f ms. 'linetrees MB' is the stats' linetree_bytes (linetrees, "
              "interpolants, shared samples and ray trees); the process peak is the resident set's high-water mark." % base_ms]
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write(text)
    chart(runs, budgets, os.path.splitext(a.out)[0], "%d frames of artroom-long.path, %s, full mode, eps %g" % (
        len(base["frames"]), a.size, a.eps))
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
