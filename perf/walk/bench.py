#!/usr/bin/env python3
"""Walkthroughs: full (reprojection + interpolants) against base and interp (issue 4).

Runs `epsray walk` over a camera path in each mode, interleaved, R repetitions, and
reports per mode: median frame time and its ratio to base measured in the same run, the
share of pixels per path, the relative cost of each path as in the paper's Table 1
(thread time per pixel of the path, over the thread time per pixel of the base walk),
the reprojection time per frame, linetree memory over the walk, and (from one --verify
walk) the max error and pixels over epsilon.

    perf/walk/bench.py [--scene scenes/artroom.nff] [--path scenes/paths/artroom-walk.path]
                       [--size 800x600] [--eps 0.05] [--reps 1] [--threads N]
                       [--exe build/epsray] [--out perf/results/walk.md]
"""
import argparse
import os
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import add_walk_arguments, gnuplot, gp_text, run_walk  # noqa: E402


def walk(exe, scene, path, mode, size, threads, eps, verify=False, budget=0):
    flags = ["--mode", mode, "--size", size, "--threads", threads, "--eps", eps] + (["--verify"] if verify else [])
    flags += ["--memory-mb", budget] if budget else []
    return run_walk(exe, scene, path, flags)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_walk_arguments(ap, "walk.md")
    ap.add_argument("--eps", type=float, default=0.05)
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--memory-mb", type=float, default=24,
                    help="also run full mode under this linetree budget (issue 4: under 25 MB); 0: not")
    a = ap.parse_args()
    modes = ["base", "interp", "full"]
    budgeted = "full, %g MB" % a.memory_mb
    if a.memory_mb:
        modes.append(budgeted)
    runs = {m: [] for m in modes}
    for _ in range(a.reps):  # interleaved: base, interp, full, base, ...
        for m in modes:
            budget = a.memory_mb if m == budgeted else 0
            runs[m].append(walk(a.exe, a.scene, a.path, m.split(",")[0], a.size, a.threads, a.eps, budget=budget))
    checked = walk(a.exe, a.scene, a.path, "full", a.size, a.threads, a.eps, verify=True)

    def frames(m):
        return [f for r in runs[m] for f in r["frames"]]

    med = {m: statistics.median(f["ms"] for f in frames(m)) for m in modes}
    w, h = (int(v) for v in a.size.split("x"))
    base_px_ms = statistics.median(f["path_ms"]["base"] for f in frames("base")) / (w * h)
    n_frames = len(runs["base"][0]["frames"])
    lines = []
    lines.append("# Walkthrough: %s, %d frames of %s, %s, eps %g, %d threads, %d rep(s); %s\n" %
                 (os.path.basename(a.scene), n_frames, os.path.basename(a.path), a.size, a.eps, a.threads, a.reps,
                  time.strftime("%Y-%m-%d %H:%M")))
    lines.append("| mode | median frame ms | base / mode | fast | interp | base-traced | with per-pixel rays | "
                 "cost fast | cost interp | cost base | cost of fast + interp, nothing deferred | "
                 "with per-pixel rays | span-filled | cost span-filled | reprojection ms | "
                 "linetree MB (first / middle / last) | linetree MB, largest of frames 0-29 | building cells, share of thread time |")
    lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|")
    for m in modes:
        fs = frames(m)
        px = {k: sum(f["pixels"][k] for f in fs) for k in ("fast", "interp", "base")}
        tm = {k: sum(f["path_ms"][k] for f in fs) for k in ("fast", "interp", "base")}
        allpx = sum(px.values())
        cost = {k: (tm[k] / px[k] / base_px_ms if px[k] else float("nan")) for k in px}
        mem = [f["linetree_bytes"] / 1e6 for f in runs[m][0]["frames"]]
        rep = statistics.median(f.get("reproject_ms", 0) for f in fs)
        deferred = sum(f.get("deferred_pixels", 0) for f in fs)
        # The fast and interp pixels split by whether their cell left rays to each pixel.
        d_ms = sum(f.get("deferred_ms", 0) for f in fs)
        rest_px = px["fast"] + px["interp"] - deferred
        c_rest = (tm["fast"] + tm["interp"] - d_ms) / rest_px / base_px_ms if rest_px else float("nan")
        c_def = d_ms / deferred / base_px_ms if deferred else float("nan")
        # Fast pixels filled in screen space along spans (span_fill.h), and their cost.
        span = sum(f.get("span_pixels", 0) for f in fs)
        c_span = sum(f.get("span_ms", 0) for f in fs) / span / base_px_ms if span else float("nan")
        # Building interpolants, paid by the pixels that first reach the cells (interp and base paths).
        build = sum(f.get("build_ms", 0) for f in fs) / (sum(tm.values()) or 1)
        lines.append("| %s | %.1f | %.2f | %.1f%% | %.1f%% | %.1f%% | %.1f%% | %.3f | %.2f | %.2f | %.2f | %.2f | %.1f%% | "
                     "%.3f | %.1f | %.1f / %.1f / %.1f | %.1f | %.1f%% |" %
                     (m, med[m], med["base"] / med[m], 100 * px["fast"] / allpx, 100 * px["interp"] / allpx,
                      100 * px["base"] / allpx, 100 * deferred / allpx, cost["fast"], cost["interp"], cost["base"],
                      c_rest, c_def, 100 * span / allpx, c_span, rep, mem[0], mem[len(mem) // 2], mem[-1],
                      max(mem[:30]), 100 * build))
    worst = max(f["verify"]["max_rel_err"] for f in checked["frames"])
    over = sum(f["verify"]["violations"] for f in checked["frames"])
    lines.append("")
    lines.append("Costs are thread time per pixel of each path over thread time per pixel of the base walk "
                 "(the paper's Table 1: fast 0.022, interpolate and build 0.84-1.33, base 1).")
    lines.append("Verified full walk: max relative error %.4f, %d pixels over eps %g in %d frames." %
                 (worst, over, a.eps, len(checked["frames"])))
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as out:
        out.write(text)
    print("wrote", a.out)
    figure12(runs, os.path.splitext(a.out)[0], a.scene, a.path, a.size, budgeted if a.memory_mb else None)
    return 0


def figure12(runs, base, scene, path, size, budgeted=None):
    """The paper's Figure 12 for our walk: per frame, the frame time of each mode, the share
    of full mode's pixels on each path, and full mode's linetree memory, unbounded and under
    the budget when one ran (the first repetition)."""
    dat, png = base + "-frames.dat", base + "-frames.png"
    b, i, f = (runs[m][0]["frames"] for m in ("base", "interp", "full"))
    fb = runs[budgeted][0]["frames"] if budgeted else f
    with open(dat, "w") as out:
        out.write("# frame base_ms interp_ms full_ms fast%% interp%% base%% full_memory_MB budgeted_memory_MB\n")
        for k in range(len(f)):
            px = f[k]["pixels"]
            n = sum(px.values()) or 1
            out.write("%d %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f\n" % (
                k, b[k]["ms"], i[k]["ms"], f[k]["ms"], 100 * px["fast"] / n, 100 * px["interp"] / n,
                100 * px["base"] / n, f[k]["linetree_bytes"] / 1e6, fb[k]["linetree_bytes"] / 1e6))
    title = gp_text("Figure 12: %s along %s, %s, frame by frame" % (os.path.basename(scene), os.path.basename(path), size))
    script = (
        "set terminal pngcairo noenhanced size 900,960; set output '%s'; set multiplot layout 3,1 title %s;"
        "set grid; set key outside right; set lmargin 10; set rmargin 30; set xrange [0:*];"
        "set title 'frame time per mode'; set ylabel 'frame ms'; set yrange [0:*];"
        "plot '%s' u 1:2 w l lw 2 t 'base', '' u 1:3 w l lw 2 t 'interp', '' u 1:4 w l lw 2 t 'full';"
        "set title 'full mode: where its pixels came from'; set ylabel 'pixels (%%)'; set yrange [0:100];"
        "plot '%s' u 1:($5+$6+$7) w filledcurves x1 t 'base-traced', "
        "'' u 1:($5+$6) w filledcurves x1 t 'interpolated', '' u 1:5 w filledcurves x1 t 'fast (reprojected)';"
        "set title 'full mode: linetree memory'; set yrange [0:*]; set xlabel 'frame'; set ylabel 'linetrees MB';"
        "plot '%s' u 1:8 w l lw 2 t 'unbounded'%s; unset multiplot" % (
            png, title, dat, dat, dat, ", '' u 1:9 w l lw 2 t %s" % gp_text(budgeted) if budgeted else ""))
    gnuplot(script, png)


if __name__ == "__main__":
    sys.exit(main())
