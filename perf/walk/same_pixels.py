#!/usr/bin/env python3
"""Each path of a walk against the same pixels traced by base mode's code.

`epsray walk --base-cost` traces every pixel again by base mode's code right after the
frame's own path shades it, and adds that time under the path that served the pixel
(stats `base_code_ms` beside `path_ms`, `deferred_ms`, `span_ms`). The average base pixel
is the wrong yardstick for a path whose pixels are not average (traced pixels lie where
the scene is dear), so this table sets each path against its own pixels: pixels, the
path's thread time, base's code on them, and the ratio. Frames from --first on (frame 0
builds most of the walk's cells).

The two traces of a pixel share the core's caches, each running warm from the other:
the base column sums to somewhat more than a base walk's own thread time (1.11 on the
art-room walk), and the ratios move by up to 0.1 between a quiet machine and a loaded
one. Read them as where a walk's paths stand, not as a speed-up.

    perf/walk/same_pixels.py [--scene scenes/artroom.nff] [--path scenes/paths/artroom-walk.path]
                             [--size 800x600] [--eps 0.05] [--first 1] [--exe build/epsray]
                             [--out perf/results/same-pixels.md]
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import add_walk_arguments, run_walk  # noqa: E402


def table(frames):
    """Rows (path, pixels, full ms, base-code ms) summed over frames."""
    def total(key, sub=None):
        return sum(f[key][sub] if sub else f[key] for f in frames)

    px = {k: total("pixels", k) for k in ("fast", "interp", "base")}
    ms = {k: total("path_ms", k) for k in ("fast", "interp", "base")}
    bc = {k: total("base_code_ms", k) for k in ("fast", "interp", "base", "deferred", "span")}
    dpx, dms = total("deferred_pixels"), total("deferred_ms")
    spx, sms = total("span_pixels"), total("span_ms")
    rows = [
        ("traced", px["base"], ms["base"], bc["base"]),
        ("interpolated (builds included)", px["interp"], ms["interp"], bc["interp"]),
        ("with per-pixel rays", dpx, dms, bc["deferred"]),
        ("fast or interpolated, nothing deferred, not span-filled",
         px["fast"] + px["interp"] - dpx - spx, ms["fast"] + ms["interp"] - dms - sms,
         bc["fast"] + bc["interp"] - bc["deferred"] - bc["span"]),
        ("span-filled", spx, sms, bc["span"]),
        ("all paths", sum(px.values()), sum(ms.values()), bc["fast"] + bc["interp"] + bc["base"]),
    ]
    reproject = total("reproject_ms")
    return rows, reproject


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_walk_arguments(ap, "same-pixels.md")
    ap.add_argument("--eps", type=float, default=0.05)
    ap.add_argument("--mode", default="full")
    ap.add_argument("--first", type=int, default=1, help="first frame counted (default 1: the cold frame left out)")
    a = ap.parse_args()
    stats = run_walk(a.exe, a.scene, a.path, ["--mode", a.mode, "--size", a.size, "--eps", a.eps, "--threads", 1,
                                              "--tile-order", "scan", "--base-cost"])
    frames = stats["frames"][a.first:]
    if not frames:
        sys.exit("no frames from --first %d on" % a.first)
    rows, reproject = table(frames)
    lines = ["# %s, %s, %s mode, eps %g, frames %d-%d, one thread: each path against base's code on its pixels"
             % (os.path.basename(a.scene), a.size, a.mode, a.eps, a.first, a.first + len(frames) - 1), "",
             "| path | pixels | the path's time | base's code on the same pixels | path / base |",
             "|---|---:|---:|---:|---:|"]
    for name, n, t, b in rows:
        lines.append("| %s | %.2f M | %.0f ms | %.0f ms | %s |" % (name, n / 1e6, t, b, "%.2f" % (t / b) if b > 0 else "-"))
    all_t, all_b = rows[-1][2], rows[-1][3]
    lines += ["", "Reprojection besides: %.0f ms; paths and reprojection against base's code: %.3f."
              % (reproject, (all_t + reproject) / all_b if all_b > 0 else float("nan")),
              "", "Command: `%s`" % " ".join(stats.get("command", []))]
    text = "\n".join(lines) + "\n"
    print(text, end="")
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write(text)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
