#!/usr/bin/env python3
"""Interpolants against the base tracer, side by side (issue 3's benchmark).

For each scene and epsilon, interleaved, R repetitions each: a `--mode base` walk and a
`--mode interp --verify` walk over a still camera (the scene's own view, 3 frames).
Frame 0 of the interp walk is cold (every interpolant is built); frames 1-2 are warm
(the linetrees of frame 0 are looked up, as when the viewer's camera rests). Reports the
share of pixels interpolated, max and 99.9th-percentile relative error, pixels over
epsilon, linetree memory, and the cost of a pixel on each path relative to a traced one,
from the thread time each path took (--stats path_ms):
    c_path = (path_ms[path] / n_path) / (base walk's path_ms / (W * H))
once for the cold frame (the interpolate path pays for building and proving cells) and
once for the warm ones (a visibility ray, a lookup and the interpolation), the warm one
also split between the pixels whose cell left lights or secondary rays to per-pixel rays
(--stats deferred_pixels, deferred_ms) and those with nothing deferred.
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import run_walk  # noqa: E402
SPD = os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd")
DEFAULT_SPD = ["balls-s3", "teapot-s6", "rings-s3", "tetra-s4", "mount-s4"]


def view_line(scene):
    """The scene's own camera as a path line (whitted.md 8): from, at, up, angle."""
    v = {"from": "0 0 0", "at": "0 0 -1", "up": "0 1 0", "angle": "45"}
    with open(scene) as f:
        for line in f:
            k = line.split()
            if k and k[0] in v:
                v[k[0]] = " ".join(k[1:4]) if k[0] != "angle" else k[1]
    return "%s  %s  %s  %s" % (v["from"], v["at"], v["up"], v["angle"])


def walk(exe, scene, mode, size, threads, eps=None, verify=False, frames=3):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "still.path")
        with open(path, "w") as f:
            f.write((view_line(scene) + "\n") * frames)
        flags = ["--mode", mode, "--size", size, "--threads", threads]
        flags += (["--eps", eps] if eps is not None else []) + (["--verify"] if verify else [])
        return run_walk(exe, scene, path, flags)


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
            tb, tc, tw, tpx, last = [], [], [], [], None
            for _ in range(a.reps):  # interleaved: base, interp, base, interp, ...
                b = walk(a.exe, scene, "base", a.size, a.threads)["frames"]
                tb += [f["ms"] for f in b]
                tpx += [f["path_ms"]["base"] for f in b]
                last = walk(a.exe, scene, "interp", a.size, a.threads, eps, verify=True)
                tc.append(last["frames"][0]["ms"])
                tw += [f["ms"] for f in last["frames"][1:]]
            f = last["frames"][0]
            base_ms, cold_ms, warm_ms = statistics.median(tb), statistics.median(tc), statistics.median(tw)
            base_px_ms = statistics.median(tpx)
            n = w * h
            n_int, n_base = f["pixels"]["interp"], f["pixels"]["base"]
            t_px = base_px_ms / n  # thread time of a traced pixel in the base walk

            def cost(frames, path):
                px = sum(g["pixels"][path] for g in frames)
                return sum(g["path_ms"][path] for g in frames) / px / t_px if px else float("nan")

            def split_cost(frames, deferring):
                """Warm interpolated pixels with per-pixel rays (deferring) or with none."""
                px = sum(g["deferred_pixels"] if deferring else g["pixels"]["interp"] - g["deferred_pixels"]
                         for g in frames)
                ms = sum(g["deferred_ms"] if deferring else g["path_ms"]["interp"] - g["deferred_ms"] for g in frames)
                return ms / px / t_px if px else float("nan")

            worst = max(last["frames"], key=lambda g: g["verify"]["max_rel_err"])["verify"]
            over = sum(g["verify"]["violations"] for g in last["frames"])
            rows.append((name, eps, base_ms, cold_ms, warm_ms, base_ms / warm_ms, n_int / n,
                         f.get("deferred_pixels", 0) / n, cost(last["frames"][:1], "interp"), cost(last["frames"][1:], "interp"),
                         split_cost(last["frames"][1:], False), split_cost(last["frames"][1:], True),
                         cost(last["frames"][1:], "base"), worst["max_rel_err"], f["verify"]["p999_rel_err"], over,
                         f["linetree_bytes"] / 1e6))
            print("%-12s eps %-5g base %7.1f ms cold %8.1f ms warm %7.1f ms base/warm %5.2f interp %5.1f%% "
                  "(per-pixel rays %5.1f%%) interp cost cold %6.2f warm %5.2f (nothing deferred %5.2f, per-pixel rays "
                  "%5.2f), traced %5.2f max %.4f p99.9 %.4f "
                  "over %d mem %.1f MB" % (*rows[-1][:6], 100 * rows[-1][6], 100 * rows[-1][7], *rows[-1][8:]),
                  flush=True)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as out:
        out.write("# Interpolants vs base (%s, %d threads, %d rep(s), median frame ms; %s)\n\n" %
                  (a.size, a.threads, a.reps, time.strftime("%Y-%m-%d %H:%M")))
        out.write("| scene | eps | base ms | interp cold ms | interp warm ms | base/warm | interpolated | "
                  "of which with per-pixel rays | cost of an interpolated pixel, cold | warm | warm, nothing deferred | "
                  "warm, with per-pixel rays | cost of a traced pixel in interp mode, warm | max err | 99.9% err | "
                  "pixels over eps | linetree MB |\n")
        out.write("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        for r in rows:
            out.write("| %s | %g | %.1f | %.1f | %.1f | %.2f | %.1f%% | %.1f%% | %.2f | %.2f | %.2f | %.2f | %.2f | %.4f | "
                      "%.4f | %d | %.1f |\n" % (r[0], r[1], r[2], r[3], r[4], r[5], 100 * r[6], 100 * r[7], *r[8:]))
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
