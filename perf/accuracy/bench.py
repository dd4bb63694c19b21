#!/usr/bin/env python3
"""Speed against accuracy (issue 7, first part): one walkthrough at many epsilons.

For each epsilon, a `--mode full --verify` walk and a `--mode base` walk of the same path,
side by side; reports the median frame time relative to base and the error actually
measured against the Whitted radiance (max and 99.9th percentile over the walk, pixels
over epsilon), and charts time against error (gnuplot, when installed).

    perf/accuracy/bench.py [--scene scenes/artroom.nff] [--path scenes/paths/artroom-walk.path]
                           [--frames 20] [--size 400x300] [--eps 0.005,0.01,...,0.5]
                           [--exe build/epsray] [--out perf/results/accuracy.md]
Not yet here: the alternatives of issue 7 (upsampled base, uncontrolled reprojection,
interpolation without the predicate) on the same axes.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def walk(exe, scene, path, mode, size, eps, verify):
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "s.json")
        cmd = [exe, "walk", scene, "--path", path, "--mode", mode, "--size", size, "--eps", str(eps), "--quiet",
               "--stats", stats]
        if verify:
            cmd.append("--verify")
        subprocess.run(cmd, check=True)
        with open(stats) as f:
            return json.load(f)["frames"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "artroom.nff"))
    ap.add_argument("--path", default=os.path.join(ROOT, "scenes", "paths", "artroom-walk.path"))
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--size", default="400x300")
    ap.add_argument("--eps", default="0.005,0.01,0.02,0.05,0.1,0.2,0.5")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "accuracy.md"))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "walk.path")
        with open(a.path) as src, open(path, "w") as dst:
            lines = [l for l in src if l.strip() and not l.lstrip().startswith("#")]
            dst.writelines(lines[:a.frames])
        for eps in [float(e) for e in a.eps.split(",")]:
            base = walk(a.exe, a.scene, path, "base", a.size, eps, False)  # interleaved with full
            full = walk(a.exe, a.scene, path, "full", a.size, eps, True)
            ratio = statistics.median(f["ms"] for f in full) / statistics.median(f["ms"] for f in base)
            worst = max(f["verify"]["max_rel_err"] for f in full)
            p999 = max(f["verify"]["p999_rel_err"] for f in full)
            over = sum(f["verify"]["violations"] for f in full)
            px = {k: sum(f["pixels"][k] for f in full) for k in ("fast", "interp", "base")}
            n = sum(px.values())
            rows.append((eps, ratio, worst, p999, over, px["fast"] / n, px["interp"] / n))
            print("eps %-6g full/base time %5.2f  max err %.4f  99.9%% %.4f  over %d  fast %4.1f%%  interp %4.1f%%" %
                  (eps, ratio, worst, p999, over, 100 * rows[-1][5], 100 * rows[-1][6]), flush=True)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    text = ["# Speed against accuracy: %s, %d frames of %s, %s; %s" %
            (os.path.basename(a.scene), a.frames, os.path.basename(a.path), a.size, time.strftime("%Y-%m-%d %H:%M")),
            "", "| eps | full / base frame time | max error | 99.9th pct error | pixels over eps | fast | interp |",
            "|---:|---:|---:|---:|---:|---:|---:|"]
    text += ["| %g | %.2f | %.4f | %.4f | %d | %.1f%% | %.1f%% |" % (r[0], r[1], r[2], r[3], r[4], 100 * r[5], 100 * r[6])
             for r in rows]
    with open(a.out, "w") as f:
        f.write("\n".join(text) + "\n")
    print("wrote", a.out)
    if shutil.which("gnuplot"):
        dat, png = os.path.splitext(a.out)[0] + ".dat", os.path.splitext(a.out)[0] + ".png"
        with open(dat, "w") as f:
            for r in rows:
                f.write("%g %g %g %g\n" % (r[0], r[1], r[2], r[3]))
        script = ("set terminal pngcairo size 800,600; set output '%s'; set logscale x; set grid; "
                  "set xlabel 'relative error (measured against Whitted)'; set ylabel 'frame time / base'; "
                  "set key left top; plot '%s' using 3:2 with linespoints title 'max error', "
                  "'%s' using 4:2 with linespoints title '99.9th percentile', "
                  "'%s' using 1:2 with points pt 6 title 'epsilon (the bound)'" % (png, dat, dat, dat))
        if subprocess.run(["gnuplot", "-e", script]).returncode == 0:
            print("wrote", png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
