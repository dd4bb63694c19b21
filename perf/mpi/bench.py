#!/usr/bin/env python3
"""Walks over MPI ranks (issue 30, docs/mpi.md): strong scaling here, and a model for a cluster.

Scaling: `mpirun -np K epsray walk` in full mode, one thread per rank, K = 1 and 2
(--ranks), interleaved --reps times; the wall time of the whole mpirun (start-up, scene
and BVH on every rank, frames, the gathering) and the speed-up from 1 to 2 ranks, for the
art room's walk and an orbit of an SPD scene. Per segment of the 2-rank run, the
coherence lost at its cold start: over its first --window frames, the extra building
time (path_ms.build), eye rays and traced pixels against the same frames of the 1-rank
walk, which arrived there warm.

Model: one process walks scenes/paths/artroom-long.path (1,000 frames) at --model-size;
fresh processes walking --window frames from every --cold-every-th frame, against the
same frames of the whole walk, give a segment's cold start C. (A --keyframe walk gives
the cost of a restart inside one process, for --keyframe's price.) With the measured
frame costs m_k and the start-up S (wall time less the frames), the walk on K ranks takes
S + max over segments (C, but not for the segment at frame 0, + sum of m_k), for the
segments epsray itself chooses for K ranks (read from the stats of a tiny walk under
mpirun -np K). Speed-up: the one-rank time over that, for K = 2 .. 64; beside it, and
alone for K = 128 .. 512, the split balanced on the measured costs themselves.

    perf/mpi/bench.py [--exe build/epsray] [--mpirun mpirun] [--size 640x480] [--reps 1]
                      [--spd teapot-s6] [--model-size 320x240] [--no-scaling] [--no-model]
                      [--out perf/results/mpi.md]

Writes OUT (Markdown) and OUT with .json. Run it on a quiet machine: its timings are
wall times of whole jobs.
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
sys.path.insert(0, os.path.join(ROOT, "perf"))
from common import orbit_path, run_walk  # noqa: E402

MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def mpi_walk(a, ranks, scene, path, flags, size):
    """mpirun -np RANKS epsray walk ...: (wall seconds of the whole mpirun, its stats)."""
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "s.json")
        cmd = [a.mpirun, "-q", "--oversubscribe", "-np", str(ranks), a.exe, "walk", scene, "--path", path,
               "--size", size, "--quiet", "--stats", stats] + [str(f) for f in flags]
        t0 = time.monotonic()
        subprocess.run(cmd, check=True, env=MPI_ENV)
        wall = time.monotonic() - t0
        with open(stats) as f:
            return wall, json.load(f)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def coherence(one, two, window):
    """Per segment of the 2-rank walk: what its first `window` frames cost beyond the same
    frames of the 1-rank walk."""
    rows = []
    for first, last in two["machine"]["mpi"]["segments"]:
        if last < first:
            continue
        ks = range(first, min(last, first + window - 1) + 1)
        f1 = {f["index"]: f for f in one["frames"]}
        f2 = {f["index"]: f for f in two["frames"]}

        def total(fs, get):
            return sum(get(fs[k]) for k in ks)

        rows.append({
            "segment": [first, last], "frames": len(ks),
            "extra_build_ms": total(f2, lambda f: f["build_ms"]) - total(f1, lambda f: f["build_ms"]),
            "extra_eye_rays": total(f2, lambda f: f["rays"]["eye"]) - total(f1, lambda f: f["rays"]["eye"]),
            "extra_traced_pixels": total(f2, lambda f: f["pixels"]["base"]) - total(f1, lambda f: f["pixels"]["base"]),
            "extra_frame_ms": total(f2, lambda f: f["ms"]) - total(f1, lambda f: f["ms"]),
        })
    return rows


def scaling(a, lines, out):
    tmp = tempfile.mkdtemp()
    spd = os.path.join(ROOT, "..", "shared", "scenes", "spd", a.spd + ".nff")
    walks = [("art room", os.path.join(ROOT, "scenes", "artroom.nff"),
              os.path.join(ROOT, "scenes", "paths", "artroom-walk.path"))]
    if os.path.isfile(spd):
        orbit = os.path.join(tmp, a.spd + "-orbit.path")
        orbit_path(spd, a.orbit_frames, orbit)
        walks.append((a.spd + " orbit", spd, orbit))
    flags = ["--mode", "full", "--threads", 1]
    lines.append("## Strong scaling: full mode, %s, one thread per rank\n" % a.size)
    lines.append("| walk | frames | ranks | wall s (median of %d) | speed-up over 1 rank | best run s | speed-up, "
                 "best runs | load before |" % a.reps)
    lines.append("|---|---:|---:|---:|---:|---:|---:|---|")
    for name, scene, path in walks:
        runs = {k: [] for k in a.ranks}
        stats = {}
        loads = []
        for _ in range(a.reps):  # interleaved: 1, 2, 1, 2, ...
            for k in a.ranks:
                loads.append(load())
                wall, st = mpi_walk(a, k, scene, path, flags, a.size)
                runs[k].append(wall)
                stats[k] = st
        n = len(stats[a.ranks[0]]["frames"])
        t1 = statistics.median(runs[a.ranks[0]])
        entry = {"walk": name, "scene": os.path.relpath(scene, ROOT), "frames": n, "size": a.size, "runs": {},
                 "loads": loads}
        for k in a.ranks:
            t = statistics.median(runs[k])
            entry["runs"][str(k)] = {"wall_s": runs[k], "median_s": t, "speedup": t1 / t,
                                     "segments": stats[k]["machine"]["mpi"]["segments"],
                                     "frame_ms_sum": sum(f["ms"] for f in stats[k]["frames"])}
            b1, b = min(runs[a.ranks[0]]), min(runs[k])
            lines.append("| %s | %d | %d | %.2f | %.2f | %.2f | %.2f | %s |" % (name, n, k, t, t1 / t, b, b1 / b,
                                                                            loads[a.ranks.index(k)]))
        if len(a.ranks) > 1:
            entry["coherence"] = coherence(stats[a.ranks[0]], stats[a.ranks[-1]], a.window)
        out["scaling"].append(entry)
    lines.append("")
    lines.append("Coherence lost at each segment's cold start (%d ranks against 1): the segment's first %d "
                 "frames against the same frames walked warm.\n" % (a.ranks[-1], a.window))
    lines.append("| walk | segment | extra building ms | extra eye rays | extra traced pixels | extra frame ms |")
    lines.append("|---|---|---:|---:|---:|---:|")
    for e in out["scaling"]:
        for r in e.get("coherence", []):
            lines.append("| %s | %d-%d | %.1f | %d | %d | %.1f |" % (e["walk"], r["segment"][0], r["segment"][1],
                                                                    r["extra_build_ms"], r["extra_eye_rays"],
                                                                    r["extra_traced_pixels"], r["extra_frame_ms"]))
    lines.append("")
    shutil.rmtree(tmp, ignore_errors=True)


def segments_for(a, ranks, scene, path):
    """The segments epsray picks for `ranks` ranks (a walk of 2x2 frames in base mode)."""
    _, st = mpi_walk(a, ranks, scene, path, ["--mode", "base", "--threads", 1], "2x2")
    return st["machine"]["mpi"]["segments"]


def ideal_largest(m, cold, ranks):
    """The largest segment cost of the best contiguous split of the measured frame costs m
    into `ranks` segments, each but the first paying `cold` (a bisection on the bound with a
    greedy fill): what balancing on the true costs, which no estimate sees, would give."""
    def segments_needed(bound):
        count, cost = 1, 0.0
        for k, x in enumerate(m):
            if cost + x > bound and k > 0:
                count, cost = count + 1, cold
            cost += x
            if cost > bound:
                return ranks + 1
        return count
    lo, hi = 0.0, sum(m) + cold * ranks
    for _ in range(100):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if segments_needed(mid) <= ranks else (mid, hi)
    return hi


def model(a, lines, out):
    scene = os.path.join(ROOT, "scenes", "artroom.nff")
    path = os.path.join(ROOT, "scenes", "paths", "artroom-long.path")
    flags = ["--mode", "full", "--threads", 1, "--size", a.model_size]
    t0 = time.monotonic()
    plain = run_walk(a.exe, scene, path, flags)
    wall1 = time.monotonic() - t0
    keyed = run_walk(a.exe, scene, path, flags + ["--keyframe", a.keyframe])
    m = [f["ms"] for f in plain["frames"]]
    mk = [f["ms"] for f in keyed["frames"]]
    n = len(m)
    cams = [l for l in open(path) if l.strip() and not l.startswith("#")]
    # A segment's cold start in a process of its own, as a rank makes it: the path's frames
    # from s walked by a fresh process, against the same frames arrived at warm.
    extras = []
    with tempfile.TemporaryDirectory() as d:
        for s0 in range(a.cold_every, n, a.cold_every):
            sub = os.path.join(d, "from%d.path" % s0)
            with open(sub, "w") as f:
                f.writelines(cams[s0:s0 + a.window])
            cold_run = run_walk(a.exe, scene, sub, flags)
            extras.append(sum(f["ms"] for f in cold_run["frames"]) - sum(m[s0:s0 + a.window]))
    cold = statistics.median(extras)
    # A keyframe's restart inside one process (--keyframe): its first frames against the plain walk's.
    restarts = [sum(mk[k:k + a.window]) - sum(m[k:k + a.window]) for k in range(a.keyframe, n, a.keyframe)]
    restart = statistics.median(restarts)
    startup_s = max(0.0, wall1 - sum(m) / 1000)
    lines.append("## Model: %d frames of artroom-long.path at %s, full mode, one thread per rank\n" %
                 (n, a.model_size))
    lines.append("Measured in one process: frames %.1f ms median (sum %.1f s), the first %.1f ms; start-up and "
                 "writing %.2f s. A segment's cold start, in a process of its own, costs %.1f ms more over its first "
                 "%d frames than arriving there warm (median of %d starts, every %d frames; spread %.1f to %.1f ms). "
                 "A --keyframe %d restart inside the process costs %.1f ms (median of %d; spread %.1f to %.1f ms).\n" %
                 (statistics.median(m), sum(m) / 1000, m[0], startup_s, cold, a.window, len(extras), a.cold_every,
                  min(extras), max(extras), a.keyframe, restart, len(restarts), min(restarts), max(restarts)))
    lines.append("| ranks | frames per rank (largest) | predicted wall s | speed-up | efficiency | "
                 "balanced on measured costs: wall s | speed-up | efficiency |")
    lines.append("|---:|---:|---:|---:|---:|---:|---:|---:|")
    t1 = startup_s + sum(m) / 1000
    rows = []
    for k in a.model_ranks:
        segs = segments_for(a, k, scene, path)
        worst = 0.0
        for first, last in segs:
            if last < first:
                continue
            ms = sum(m[first:last + 1]) + (cold if first > 0 else 0.0)
            worst = max(worst, ms)
        t = startup_s + worst / 1000
        ti = startup_s + ideal_largest(m, cold, k) / 1000
        rows.append({"ranks": k, "segments": segs, "predicted_s": t, "speedup": t1 / t, "efficiency": t1 / t / k,
                     "largest_segment": max(l - f + 1 for f, l in segs), "ideal_s": ti, "ideal_speedup": t1 / ti})
        lines.append("| %d | %d | %.2f | %.1f | %.0f%% | %.2f | %.1f | %.0f%% |" % (
            k, rows[-1]["largest_segment"], t, t1 / t, 100 * t1 / t / k, ti, t1 / ti, 100 * t1 / ti / k))
    # Beyond the ranks run: the balanced split alone (no epsray run needed).
    for k in a.ideal_ranks:
        ti = startup_s + ideal_largest(m, cold, k) / 1000
        rows.append({"ranks": k, "ideal_s": ti, "ideal_speedup": t1 / ti})
        lines.append("| %d | %d | | | | %.2f | %.1f | %.0f%% |" % (k, -(-n // k), ti, t1 / ti, 100 * t1 / ti / k))
    # Where it stops paying: the first K whose doubling gains under 25%, and the first
    # K under 50% efficiency.
    def stops(key):
        """The first K whose doubling gains under 25%, and the first K under 50% efficiency."""
        rs = [r for r in rows if key in r]
        double = next((rs[i + 1]["ranks"] for i in range(len(rs) - 1)
                       if rs[i + 1][key] < 1.25 * rs[i][key]), None)
        half = next((r["ranks"] for r in rs if r[key] / r["ranks"] < 0.5), None)
        return double, half
    stop, half = stops("speedup")
    istop, ihalf = stops("ideal_speedup")
    lines.append("")
    lines.append("With epsray's segments, efficiency falls under 50%% at %s ranks, and doubling the ranks gains under "
                 "25%% from %s. Balanced on the measured costs: under 50%% at %s ranks, doubling gains under 25%% "
                 "from %s ranks." % (half or "more than %d" % a.model_ranks[-1], stop or "more than %d" % a.model_ranks[-1],
                                     ihalf, istop))
    lines.append("")
    out["model"] = {"size": a.model_size, "frames": n, "frame_ms": m, "keyframe": a.keyframe, "keyed_frame_ms": mk,
                    "cold_extra_ms": cold, "cold_extras_ms": extras, "keyframe_restart_ms": restart,
                    "keyframe_restarts_ms": restarts, "startup_s": startup_s, "one_rank_s": t1,
                    "rows": rows, "stops_paying_at": stop, "half_efficiency_at": half,
                    "ideal_stops_paying_at": istop, "ideal_half_efficiency_at": ihalf}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--mpirun", default=shutil.which("mpirun") or "mpirun")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--spd", default="teapot-s6")
    ap.add_argument("--orbit-frames", type=int, default=60)
    ap.add_argument("--window", type=int, default=5, help="frames after a cold start counted as its cost")
    ap.add_argument("--model-size", default="320x240")
    ap.add_argument("--keyframe", type=int, default=50, help="the --keyframe walk: a restart every N frames")
    ap.add_argument("--cold-every", type=int, default=50, help="a cold segment start measured every N frames")
    ap.add_argument("--model-ranks", type=int, nargs="+", default=[2, 4, 8, 16, 32, 64])
    ap.add_argument("--ideal-ranks", type=int, nargs="*", default=[128, 256, 512],
                    help="ranks modelled on the balanced split alone")
    ap.add_argument("--no-scaling", action="store_true")
    ap.add_argument("--no-model", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", "mpi.md"))
    a = ap.parse_args()
    info = subprocess.run([a.exe, "info"], capture_output=True, text=True, check=True).stdout
    lines = ["# Walks over MPI ranks; %s" % time.strftime("%Y-%m-%d %H:%M"), ""]
    lines += ["    " + l for l in info.strip().splitlines()]
    lines.append("")
    lines.append("Load average (1, 5, 15 min) at the start: %s." % load())
    lines.append("")
    out = {"info": info, "load_at_start": load(), "scaling": []}
    if not a.no_scaling:
        scaling(a, lines, out)
    if not a.no_model:
        model(a, lines, out)
    lines.append("Load average at the end: %s." % load())
    out["load_at_end"] = load()
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write(text)
    with open(os.path.splitext(a.out)[0] + ".json", "w") as f:
        json.dump(out, f, indent=1)
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
