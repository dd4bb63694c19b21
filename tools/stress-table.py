#!/usr/bin/env python3
"""Walks the stress scenes (scenes/stress/, issue 8) along their camera paths with --verify
and prints the Markdown table of docs/stress.md: per walk, the share of pixels each path
produced (fast = span-filled, interp = interpolated, base = traced), the largest relative
error and the pixels over epsilon, summed over the frames.

    tools/stress-table.py [--epsray build/epsray] [--size 128x96] [--threads N]

Exit status 1 when any walk fails or any pixel is over epsilon. The rows are the walks
tests/test_stress.cpp runs (same scenes, paths, modes, epsilons and size).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRESS = os.path.join(ROOT, "scenes", "stress")

# (scene, path, mode, eps[, size, min cell pixels]): the walks of tests/test_stress.cpp.
WALKS = [
    ("grazing", "smooth", "full", 0.05),
    ("grazing", "smooth", "full", 0.05, "192x144", 2),
    ("grazing", "fast-turn", "full", 0.05),
    ("grazing", "teleport", "interp", 0.05),
    ("tir-glass", "smooth", "full", 0.05),
    ("tir-glass", "backwards", "full", 0.05),
    ("tir-glass", "teleport", "interp", 0.05),
    ("subpixel", "smooth", "full", 0.05),
    ("subpixel", "backwards", "full", 0.05),
    ("subpixel", "fast-turn", "interp", 0.05),
    ("shiny", "smooth", "full", 0.05),
    ("shiny", "teleport", "full", 0.05),
    ("many-lights", "smooth", "full", 0.05),
    ("many-lights", "teleport", "interp", 0.05),
    ("behind", "smooth", "full", 0.05),
    ("behind", "smooth", "interp", 0.05),
    ("behind", "backwards", "full", 0.05),
    ("behind", "fast-turn", "full", 0.05),
    ("behind", "teleport", "full", 0.05),
    ("inside", "smooth", "full", 0.05),
    ("inside", "teleport", "full", 0.05),
    ("on-surface", "smooth", "full", 0.05),
    ("on-surface", "smooth", "full", 0.05, "192x144", 2),
    ("on-surface", "fast-turn", "full", 0.05),
    ("on-surface", "backwards", "interp", 0.05),
    ("tiny-scale", "tiny-smooth", "full", 0.05),
    ("tiny-scale", "tiny-teleport", "full", 0.05),
    ("tiny-scale", "tiny-backwards", "interp", 0.05),
    ("tiny-scale", "tiny-smooth", "full", 0.05, "192x144", 2),
    ("huge-scale", "huge-smooth", "full", 0.05),
    ("huge-scale", "huge-smooth", "full", 0.05, "192x144", 2),
    ("huge-scale", "huge-teleport", "full", 0.05),
    ("huge-scale", "huge-backwards", "interp", 0.05),
    ("behind", "smooth", "full", 1e-6),
    ("tir-glass", "teleport", "interp", 1e-6),
    ("behind", "smooth", "full", 10),
    ("subpixel", "smooth", "interp", 10),
    ("shiny", "teleport", "full", 10),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--epsray", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--size", default="128x96")
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()

    print("| scene | path | mode | eps | size | frames | fast | interp | base | with per-pixel rays | max rel. error | "
          "over eps |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    bad = False
    with tempfile.TemporaryDirectory() as tmp:
        for scene, path, mode, eps, *extra in WALKS:
            size = extra[0] if extra else a.size
            label = size + (" (cells >= %d px)" % extra[1] if extra else "")
            stats = os.path.join(tmp, "stats.json")
            cmd = [a.epsray, "walk", os.path.join(STRESS, scene + ".nff"),
                   "--path", os.path.join(STRESS, "paths", path + ".path"),
                   "--mode", mode, "--eps", repr(eps), "--size", size, "--verify", "--quiet",
                   "--stats", stats]
            if extra:
                cmd += ["--min-cell-pixels", str(extra[1])]
            if a.threads:
                cmd += ["--threads", str(a.threads)]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                bad = True
                print("| %s | %s | %s | %g | %s | exit %d: %s ||||||| " % (scene, path, mode, eps, label, r.returncode,
                                                                      r.stderr.strip().replace("|", "/")))
                continue
            with open(stats) as f:
                frames = json.load(f)["frames"]
            px = {k: sum(fr["pixels"][k] for fr in frames) for k in ("fast", "interp", "base")}
            total = sum(px.values())
            deferred = sum(fr.get("deferred_pixels", 0) for fr in frames)
            err = max(fr["verify"]["max_rel_err"] for fr in frames)
            over = sum(fr["verify"]["violations"] for fr in frames)
            bad |= over > 0
            print("| %s | %s | %s | %g | %s | %d | %.1f%% | %.1f%% | %.1f%% | %.1f%% | %.2g | %d |" % (
                scene, path, mode, eps, label, len(frames), 100.0 * px["fast"] / total,
                100.0 * px["interp"] / total, 100.0 * px["base"] / total, 100.0 * deferred / total, err, over))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
