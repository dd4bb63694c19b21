#!/usr/bin/env python3
"""Speed against accuracy (issue 7): the bounded-error system and the alternatives a user
might pick instead, on the same engine, over the same walkthroughs.

Per scene, one camera path, every method with `--verify` (the error of every pixel against
the Whitted radiance, whitted.md 6): frame time relative to `--mode base` measured in the
same run (base walks interleaved with the others), and the error actually measured: max,
99.9th percentile and mean over the walk, and pixels over 0.05. Methods:
  full        the bounded-error system, one point per epsilon (--eps);
  upsample    the base tracer at 1/K resolution, bilinear (--upsample K);
  reuse       last frame's pixels reprojected without error control, each for at most N
              frames (--reuse-age N; a render-cache-like baseline);
  lightfield  fixed-depth linetrees interpolated without the error predicate (--lf-depth D).
Writes a Markdown table per scene, the raw JSON, and (gnuplot) a chart per scene: time
against the largest error, the 99.9th percentile and the pixels over epsilon side by side,
each point labelled with its setting.

    perf/accuracy/bench.py [SCENE ...] [--frames 20] [--size 400x300] [--threads N]
                           [--eps 0.005,...,0.5] [--upsample 2,3,4,6] [--reuse-age 1,2,4,8,32]
                           [--lf-depth 3,4,5,6] [--exe build/epsray] [--out perf/results/accuracy.md]
    perf/accuracy/bench.py --replot perf/results/accuracy.json    # redraw the charts only
Default scenes: scenes/artroom.nff on its walk (scenes/paths/artroom-walk.path), and, when
../shared is present, the SPD scenes balls-s3 and teapot-s6 on a slow orbit of their view.
"""
import argparse
import json
import math
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SPD = os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd")
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import gnuplot, gp_text, orbit_path, run_walk  # noqa: E402

NOMINAL_EPS = 0.05  # the baselines have no epsilon: "over" counts pixels over this one


def walk(exe, scene, path, size, threads, mode, eps, extra=()):
    flags = ["--mode", mode, "--size", size, "--eps", eps, "--threads", threads] + list(extra)
    return run_walk(exe, scene, path, flags + (["--verify"] if mode != "base" else []))["frames"]


def summary(frames, base_ms):
    v = [f["verify"] for f in frames]
    n = sum(sum(f["pixels"].values()) for f in frames)
    return {"ratio": statistics.median(f["ms"] for f in frames) / base_ms,
            "max": max(x["max_rel_err"] for x in v), "p999": max(x["p999_rel_err"] for x in v),
            "mean": statistics.fmean(x["mean_rel_err"] for x in v), "over": sum(x["violations"] for x in v),
            "fast": sum(f["pixels"]["fast"] for f in frames) / n, "interp": sum(f["pixels"]["interp"] for f in frames) / n}


def chart(name, rows, png, dat, caption=""):
    """Time against error, one series per method, each point labelled with its setting
    (eps, K, age, depth): three panels, the largest error, the 99.9th percentile and the
    pixels over epsilon, with one key below them, off the data."""
    methods = [m for m in ("full", "upsample", "reuse", "lightfield") if any(r["method"] == m for r in rows)]
    knob = {"full": "eps %g", "upsample": "K %d", "reuse": "age %d", "lightfield": "depth %d"}
    with open(dat, "w") as f:
        for m in methods:
            f.write("# %s: param ratio max p999 mean over label\n" % m)
            for r in sorted((r for r in rows if r["method"] == m), key=lambda r: r["param"]):
                # Log axes: errors floored at 1e-6; no pixel over is drawn at 0.5, the tic labelled 0.
                f.write("%g %g %g %g %g %g \"%s\"\n" % (
                    r["param"], r["ratio"], max(r["max"], 1e-6), max(r["p999"], 1e-6), max(r["mean"], 1e-6),
                    r["over"] if r["over"] > 0 else 0.5, knob[m] % r["param"]))
            f.write("\n\n")
    title = {"full": "bounded error (eps)", "upsample": "base at 1/K, upsampled", "reuse": "pixel reuse, no control",
             "lightfield": "fixed-depth interpolation, no predicate"}

    def series(col, with_titles):
        return ", ".join(
            "'%s' index %d using %d:2 with linespoints lw 2 lc %d pt %d title %s, "
            "'' index %d using %d:2:7 with labels offset char 0.6,0.6 left font ',8' tc lt %d notitle" %
            (dat, i, col, i + 1, i + 5, gp_text(title[m]) if with_titles else "''", i, col, i + 1)
            for i, m in enumerate(methods)) + ", 1 with lines dt 2 lc 'gray' notitle"

    def panel(k, col, xlabel, ptitle, extra=""):
        return ("set origin %g,0.1; set size 0.333,0.84; set title %s; set xlabel %s; %s plot %s; " %
                (k / 3, gp_text(ptitle), gp_text(xlabel), extra, series(col, False)))
    # The key: a plot of nothing across the bottom, so it never covers a point.
    key = ("set origin 0,0; set size 1,0.1; unset title; unset xlabel; unset ylabel; unset tics; unset border; "
           "unset grid; unset logscale; set xrange [0:1]; set yrange [0:1]; set key center center horizontal "
           "maxrows 1 width 1; plot " + ", ".join("NaN with linespoints lw 2 lc %d pt %d title %s" %
                                                  (i + 1, i + 5, gp_text(title[m])) for i, m in enumerate(methods)) +
           ", NaN with lines dt 2 lc 'gray' title 'base tracer (time 1)'; ")
    script = ("set terminal pngcairo noenhanced size 1800,640; set output '%s'; set multiplot title %s; "
              "unset key; set logscale x; set grid; set ylabel 'frame time / base (median frame, same run)'; "
              "set yrange [0:*]; " % (png, gp_text("%s: frame time against measured error%s" % (name, caption))) +
              panel(0, 3, "largest relative error (measured against Whitted)", "largest error") +
              panel(1, 4, "99.9th percentile of the relative error", "99.9th percentile error") +
              panel(2, 6, "pixels over epsilon, all frames (baselines: over %g)" % NOMINAL_EPS, "pixels over epsilon",
                    "set xtics add ('0' 0.5); set xrange [0.3:*];") +
              key + "unset multiplot")
    gnuplot(script, png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--path", help="camera path for the first scene (default: the art room's walk)")
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--size", default="400x300")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--eps", default="0.005,0.01,0.02,0.05,0.1,0.2,0.5")
    ap.add_argument("--upsample", default="2,3,4,6")
    ap.add_argument("--reuse-age", default="1,2,4,8,32")
    ap.add_argument("--lf-depth", default="3,4,5,6")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "accuracy.md"))
    ap.add_argument("--replot", metavar="JSON", help="redraw the charts of an earlier run's accuracy.json "
                    "beside --out, without walking anything")
    a = ap.parse_args()
    out_base = os.path.splitext(a.out)[0]
    if a.replot:
        with open(a.replot) as f:
            raw = json.load(f)
        os.makedirs(os.path.dirname(a.out), exist_ok=True)
        for name, run in raw.items():
            chart(name, run["rows"], out_base + "-" + name + ".png", out_base + "-" + name + ".dat")
        return 0
    scenes = a.scenes or [os.path.join(ROOT, "scenes", "artroom.nff")] + [
        os.path.join(SPD, s + ".nff") for s in ("balls-s3", "teapot-s6") if os.path.exists(os.path.join(SPD, s + ".nff"))]
    runs = [("full", float(e), ["--eps", e]) for e in a.eps.split(",")]
    runs += [("upsample", int(k), ["--upsample", k]) for k in a.upsample.split(",") if k]
    runs += [("reuse", int(n), ["--reuse-age", n]) for n in a.reuse_age.split(",") if n]
    runs += [("lightfield", int(d), ["--lf-depth", d]) for d in a.lf_depth.split(",") if d]
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    text = ["# Speed against accuracy (%s, %d frames, %d threads; %s)" % (a.size, a.frames, a.threads,
                                                                        time.strftime("%Y-%m-%d %H:%M")), "",
            "Frame time is the median over the walk relative to `--mode base` in the same run; errors are "
            "whitted.md 6's, over every pixel of every frame; 'over' counts pixels over eps (full) or over %g "
            "(the baselines have no bound)." % NOMINAL_EPS, ""]
    raw = {}
    with tempfile.TemporaryDirectory() as d:
        for si, scene in enumerate(scenes):
            name = os.path.splitext(os.path.basename(scene))[0]
            path = os.path.join(d, name + ".path")
            if si == 0 and (a.path or name == "artroom"):
                src = a.path or os.path.join(ROOT, "scenes", "paths", "artroom-walk.path")
                with open(src) as s, open(path, "w") as o:
                    o.writelines([l for l in s if l.strip() and not l.lstrip().startswith("#")][:a.frames])
            else:
                orbit_path(scene, a.frames, path)
            base_ms, rows = [], []
            for i, (method, param, extra) in enumerate(runs):
                if i % 4 == 0:  # base interleaved: every fourth run, and once at the end
                    base_ms += [f["ms"] for f in walk(a.exe, scene, path, a.size, a.threads, "base", 0)]
                eps = param if method == "full" else NOMINAL_EPS
                frames = walk(a.exe, scene, path, a.size, a.threads, method, eps, extra)
                rows.append(dict(method=method, param=param, frames=frames))
            base_ms += [f["ms"] for f in walk(a.exe, scene, path, a.size, a.threads, "base", 0)]
            med = statistics.median(base_ms)
            for r in rows:
                r.update(summary(r.pop("frames"), med))
                print("%-10s %-10s %-6g time %5.2f  max %9.4g  99.9%% %9.4g  mean %8.4g  over %d" %
                      (name, r["method"], r["param"], r["ratio"], r["max"], r["p999"], r["mean"], r["over"]), flush=True)
            raw[name] = {"base_median_ms": med, "rows": rows}
            text += ["## %s (base median %.1f ms a frame)" % (name, med), "",
                     "![%s](%s)" % (name, os.path.basename(out_base) + "-" + name + ".png"), "",
                     "| method | setting | time / base | max error | 99.9th pct | mean | over | fast | interp |",
                     "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
            knob = {"full": "eps %g", "upsample": "K %d", "reuse": "age %d", "lightfield": "depth %d"}
            text += ["| %s | %s | %.2f | %.4g | %.4g | %.4g | %d | %.1f%% | %.1f%% |" %
                     (r["method"], knob[r["method"]] % r["param"], r["ratio"], r["max"], r["p999"], r["mean"], r["over"],
                      100 * r["fast"], 100 * r["interp"]) for r in rows]
            text.append("")
            with open(a.out, "w") as f:  # after every scene: a run cut short keeps what it measured
                f.write("\n".join(text) + "\n")
            with open(out_base + ".json", "w") as f:
                json.dump(raw, f, indent=1)
            chart(name, rows, out_base + "-" + name + ".png", out_base + "-" + name + ".dat",
                  " (%d frames, %s, %d threads)" % (a.frames, a.size, a.threads))
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
