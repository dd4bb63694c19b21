#!/usr/bin/env python3
"""Interpolants against the base tracer, side by side (issue 3's benchmark).

For each scene: one `--mode base` render and one `--mode interp --verify` render per
epsilon, interleaved, R repetitions each; medians of frame time. Reports the share of
pixels interpolated, max and 99.9th-percentile relative error, pixels over epsilon,
linetree memory, and the cost of an interpolated pixel relative to a traced one:
    c = (T_interp - n_base * t_px) / n_interp / t_px,   t_px = T_base / (W * H)
(base-traced pixels in interp mode are charged at the base rate; the rest of the
frame's time is the interpolate path: visibility ray, lookup, building, the predicate).

    perf/interp/bench.py [--size 800x600] [--eps 0.01,0.02,0.05,0.1,0.2] [--reps 1]
                         [--threads N] [--out perf/results/interp.md] [SCENE ...]
Default scenes: scenes/artroom.nff and, when present, a few of ../shared/scenes/spd.
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
DEFAULT_SPD = ["balls-s3", "teapot-s6", "rings-s3", "tetra-s4", "mount-s4"]


def render(exe, scene, mode, size, threads, eps=None, verify=False):
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "s.json")
        cmd = [exe, "render", scene, "--mode", mode, "--size", size, "--threads", str(threads),
               "--quiet", "--stats", stats]
        if eps is not None:
            cmd += ["--eps", str(eps)]
        if verify:
            cmd += ["--verify"]
        subprocess.run(cmd, check=True)
        with open(stats) as f:
            return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--size", default="800x600")
    ap.add_argument("--eps", default="0.01,0.02,0.05,0.1,0.2")
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "interp.md"))
    a = ap.parse_args()
    scenes = a.scenes or [os.path.join(ROOT, "scenes", "artroom.nff")] + [
        os.path.join(SPD, s + ".nff") for s in DEFAULT_SPD if os.path.exists(os.path.join(SPD, s + ".nff"))]
    eps_list = [float(e) for e in a.eps.split(",")]
    w, h = (int(v) for v in a.size.split("x"))
    rows = []
    for scene in scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        for eps in eps_list:
            tb, ti, last = [], [], None
            for _ in range(a.reps):  # interleaved: base, interp, base, interp, ...
                tb.append(render(a.exe, scene, "base", a.size, a.threads)["frames"][0]["ms"])
                last = render(a.exe, scene, "interp", a.size, a.threads, eps, verify=True)
                ti.append(last["frames"][0]["ms"])
            f = last["frames"][0]
            base_ms, interp_ms = statistics.median(tb), statistics.median(ti)
            n = w * h
            n_int, n_base = f["pixels"]["interp"], f["pixels"]["base"]
            t_px = base_ms / n
            cost = (interp_ms - n_base * t_px) / n_int / t_px if n_int else float("nan")
            rows.append((name, eps, base_ms, interp_ms, base_ms / interp_ms, n_int / n, cost,
                         f["verify"]["max_rel_err"], f["verify"]["p999_rel_err"], f["verify"]["violations"],
                         f["memory_bytes"] / 1e6))
            print("%-12s eps %-5g base %8.1f ms interp %8.1f ms speedup %5.2f interp %5.1f%% cost %6.2f "
                  "max %.4f p99.9 %.4f over %d mem %.1f MB" % (rows[-1][0], *rows[-1][1:4], rows[-1][4],
                                                            100 * rows[-1][5], *rows[-1][6:]), flush=True)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as out:
        out.write("# Interpolants vs base (%s, %d threads, %d rep(s), median frame ms; %s)\n\n" %
                  (a.size, a.threads, a.reps, time.strftime("%Y-%m-%d %H:%M")))
        out.write("| scene | eps | base ms | interp ms | base/interp | interpolated | cost of an interp pixel "
                  "(x traced) | max err | 99.9% err | pixels over eps | memory MB |\n")
        out.write("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        for r in rows:
            out.write("| %s | %g | %.1f | %.1f | %.2f | %.1f%% | %.2f | %.4f | %.4f | %d | %.1f |\n" %
                      (r[0], r[1], r[2], r[3], r[4], 100 * r[5], r[6], r[7], r[8], r[9], r[10]))
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
