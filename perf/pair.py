#!/usr/bin/env python3
"""Two epsray commands timed at the same moment, one per core, to compare them on a noisy machine.

On a shared VM the speed of the whole machine drifts by tens of percent from one minute
to the next, so two runs made one after the other differ by more than most changes do.
Run at the same time, each pinned to its own core (give each `--threads 1`), both see the
same drift; swapping the cores every round cancels a difference between the cores. Each
pair gives a ratio B / A of a figure both print ("median frame X ms" or "total X ms");
the median over the pairs is printed, with the smallest and largest.

Where one core runs s times slower than the other, a round's two pairs give r s and r / s:
their geometric mean is r exactly, while the median over pairs lands between them, at
r (s + 1/s) / 2 (5.7% high for s = 1.4, as this VM's cores have been). So each round's
geometric mean is printed too, with how far apart the cores ran in it (both commands'
times on one core over the other's, geometrically averaged), and the median over the
rounds' geometric means is the answer to quote.

    perf/pair.py --rounds 3 --metric median \\
        --a "build/epsray walk scenes/artroom.nff --path P --threads 1 --mode base" \\
        --b "build/epsray walk scenes/artroom.nff --path P --threads 1 --mode full"

Measured on this project's 2-core VM: A against itself gave ratios from 0.92 to 1.02
(median of four 0.97), where runs one after the other moved by up to 40%.
"""
import argparse
import math
import os
import re
import shlex
import statistics
import subprocess
import sys


def figure(text, metric):
    m = re.search(r"median frame ([0-9.]+) ms" if metric == "median" else r"total ([0-9.]+) ms", text)
    if not m:
        raise SystemExit("pair.py: the command printed no '%s' figure:\n%s" % (metric, text[-2000:]))
    return float(m.group(1))


def start(cmd, cpu):
    pin = (lambda: os.sched_setaffinity(0, {cpu})) if cpu is not None else None
    return subprocess.Popen(shlex.split(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            preexec_fn=pin)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True, help="the reference command")
    ap.add_argument("--b", required=True, help="the command compared with it")
    ap.add_argument("--rounds", type=int, default=3, help="rounds of two pairs (cores swapped)")
    ap.add_argument("--metric", choices=["median", "total"], default="median",
                    help="median: 'median frame X ms' (walk); total: 'total X ms'")
    a = ap.parse_args()
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        print("pair.py: one core only: the commands run one after the other", file=sys.stderr)
    ratios, rounds, apart = [], [], []
    for r in range(a.rounds):
        times = {}
        for swap in (0, 1):
            ca, cb = (cpus[swap], cpus[1 - swap]) if len(cpus) >= 2 else (None, None)
            if ca is None:
                outs = [start(c, None).communicate()[0] for c in (a.a, a.b)]
            else:
                pa, pb = start(a.a, ca), start(a.b, cb)
                outs = [pa.communicate()[0], pb.communicate()[0]]
                if pa.returncode or pb.returncode:
                    raise SystemExit("pair.py: a command failed:\n%s\n%s" % (outs[0][-2000:], outs[1][-2000:]))
            fa, fb = figure(outs[0], a.metric), figure(outs[1], a.metric)
            ratios.append(fb / fa)
            times[swap] = (fa, fb)
            print("round %d, A on cpu %s: A %.1f ms, B %.1f ms, B / A %.3f" % (r, ca, fa, fb, fb / fa))
        (a0, b1), (a1, b0) = times[0], times[1]  # swap 0: A on the first core, B on the second
        rounds.append(math.sqrt(ratios[-1] * ratios[-2]))
        apart.append(math.sqrt((a1 / a0) * (b1 / b0)))
    print("B / A: median %.3f, smallest %.3f, largest %.3f over %d pairs" %
          (statistics.median(ratios), min(ratios), max(ratios), len(ratios)))
    print("B / A by round (geometric mean of its two pairs): median %.3f, smallest %.3f, largest %.3f over %d "
          "rounds; the second core's times over the first's: %s" %
          (statistics.median(rounds), min(rounds), max(rounds), len(rounds), " ".join("%.2f" % x for x in apart)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
