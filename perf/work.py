#!/usr/bin/env python3
"""Two epsray commands compared by the work they do, counted, not timed.

pair.py's ratios on this project's 2-core VM spread by 20-40% between pairs minutes apart,
so a change worth 2-5% cannot be seen there in any number of rounds one can wait for.
This script runs each command under valgrind's cachegrind, which counts the instructions
executed and simulates the caches: the same command gives the same counts on any day and
under any load. An epsray walk or render gets `--threads 1` and `--tile-order scan` where
it names neither (and a walk `--quiet`), so that which thread builds a cell, and in what
order, cannot move the counts.

The figure compared is cachegrind's own rough cost estimate,
    est = Ir + 10 (D1 misses + I1 misses) + 100 LL misses,
(the weights of kcachegrind's cycle estimate, less its branch term), beside the plain
instruction count Ir. Neither is time: a division, a square root or a mispredicted branch
counts as one instruction. So a figure from here says which of two variants does less; pair.py, or a
quiet machine, says whether the clock agrees. Under valgrind a command runs about 60x
slower: choose small sizes and short paths (400x300 and 15 frames take about a minute).

    perf/work.py \\
        --a "build/epsray walk scenes/artroom.nff --path P --size 400x300 --mode base" \\
        --b "build/epsray walk scenes/artroom.nff --path P --size 400x300 --mode full"

Both commands run at once, one per core; the counts do not depend on that.
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

FIELDS = {
    "Ir": r"I\s+refs:\s+([0-9,]+)",
    "I1": r"I1\s+misses:\s+([0-9,]+)",
    "D1": r"D1\s+misses:\s+([0-9,]+)",
    "LL": r"LL misses:\s+([0-9,]+)",
}


def with_defaults(cmd):
    words = shlex.split(cmd)
    if words and os.path.basename(words[0]) == "epsray" and len(words) > 1 and words[1] in ("walk", "render"):
        if "--threads" not in words:
            words += ["--threads", "1"]
        if "--tile-order" not in words:
            words += ["--tile-order", "scan"]
        if "--quiet" not in words and words[1] == "walk":
            words += ["--quiet"]
    return words


def start(words, out_file):
    vg = ["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--cachegrind-out-file=" + out_file]
    return subprocess.Popen(vg + words, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def counts(text, label):
    out = {}
    for name, pattern in FIELDS.items():
        m = re.search(pattern, text)
        if not m:
            raise SystemExit("work.py: %s: valgrind printed no %s count:\n%s" % (label, name, text[-2000:]))
        out[name] = int(m.group(1).replace(",", ""))
    out["est"] = out["Ir"] + 10 * (out["D1"] + out["I1"]) + 100 * out["LL"]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True, help="the reference command")
    ap.add_argument("--b", required=True, help="the command compared with it")
    ap.add_argument("--keep", metavar="DIR",
                    help="keep the two cachegrind.out files in DIR (a.out, b.out) for cg_annotate")
    a = ap.parse_args()
    if not shutil.which("valgrind"):
        print("work.py: valgrind is not installed (apt-get install valgrind)", file=sys.stderr)
        return 2
    if a.keep:
        os.makedirs(a.keep, exist_ok=True)
        return compare(a, a.keep)
    with tempfile.TemporaryDirectory(prefix="epsray-work-") as folder:
        return compare(a, folder)


def compare(a, folder):
    cmds = {"A": with_defaults(a.a), "B": with_defaults(a.b)}
    procs = {k: start(w, os.path.join(folder, k.lower() + ".out")) for k, w in cmds.items()}
    res = {}
    for k, p in procs.items():
        text = p.communicate()[0]
        if p.returncode:
            for q in procs.values():
                if q.poll() is None:
                    q.kill()
            raise SystemExit("work.py: command %s failed (rc %d):\n%s" % (k, p.returncode, text[-2000:]))
        res[k] = counts(text, k)
    for k in ("A", "B"):
        print("%s: %s" % (k, " ".join(shlex.quote(w) for w in cmds[k])))
        r = res[k]
        print("   Ir {:,}  D1 misses {:,}  LL misses {:,}  est {:,}".format(r["Ir"], r["D1"], r["LL"], r["est"]))
    print("B / A: est %.4f, Ir %.4f" % (res["B"]["est"] / res["A"]["est"], res["B"]["Ir"] / res["A"]["Ir"]))
    if a.keep:
        print("cachegrind files: %s/a.out, %s/b.out (cg_annotate FILE)" % (folder, folder))
    return 0


if __name__ == "__main__":
    sys.exit(main())
