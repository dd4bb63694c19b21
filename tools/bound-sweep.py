#!/usr/bin/env python3
"""Hunt for error-bound violations with random camera walks (stdlib only).

For each scene the script reads the view (from/at/up/angle) and a rough cloud of
geometry points (sphere centres and extremes, cone ends, polygon and patch vertices,
box corners, disk centres; the native transforms are applied), then writes K random
walks of F frames each: a camera that starts somewhere unusual (orbiting, inside the
bounding box, close up to a surface, behind the scene, near the scene's own view)
looking at geometry, and moves like an interactive user (small per-frame translation
and turn, now and then a fast turn). Every walk is rendered with

    epsray walk SCENE --path P --mode M --eps E --size WxH --verify --threads 2 --stats S

for each mode and eps; the per-frame verify fields of the stats give the largest
relative error and the pixels over eps. One line per run, then a summary. A run with
pixels over eps prints its reproducer command and keeps its path file (others are
deleted). Exit status 1 if any run had pixels over eps or the renderer exited nonzero,
0 otherwise.

    python3 tools/bound-sweep.py --scenes scenes/artroom.nff scenes/tests/*.nff \\
        --walks 4 --frames 8 --size 240x180 --eps 0.01 0.05 0.2 --modes interp full \\
        --seed 1 --exe build/epsray --keep-dir /tmp/sweep/keep

`--flags "..."` adds epsray flags to every walk (e.g. `--reproject osmesa --pipeline`).
`--far-eyes F` pushes a share F of the walks 10^2-10^5 times farther back through a
telephoto lens.
"""
import argparse, json, math, os, random, subprocess, sys, time


def sub(a, b): return [a[i] - b[i] for i in range(3)]
def add(a, b): return [a[i] + b[i] for i in range(3)]
def mul(a, s): return [x * s for x in a]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def norm(a): return math.sqrt(dot(a, a))
def unit(a): n = norm(a); return [x / n for x in a] if n > 0 else [0.0, 0.0, 1.0]
def mat_vec(m, v): return [dot(m[i], v) for i in range(3)]
def mat_mul(a, b): return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rot(axis, deg):
    """Rotation matrix about a unit-normalised axis (right-hand rule)."""
    x, y, z = unit(axis); c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg)); t = 1 - c
    return [[t*x*x + c, t*x*y - s*z, t*x*z + s*y], [t*x*y + s*z, t*y*y + c, t*y*z - s*x],
            [t*x*z - s*y, t*y*z + s*x, t*z*z + c]]


def parse_scene(path):
    """Return (view dict, list of geometry points). Rough: only what a camera needs."""
    view = {"from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0], "angle": 45.0}
    pts, M, T, stack = [], [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0], []
    xf = lambda p: add(mat_vec(M, p), T)
    lines = [l.split("#")[0].split() for l in open(path, errors="replace")]
    lines = [l for l in lines if l]
    i = 0
    while i < len(lines):
        w, i = lines[i], i + 1
        k, n = w[0], w[1:]
        try:
            f = [float(x) for x in n]
        except ValueError:
            f = []
        if k in ("from", "at", "up"): view[k] = f[:3]
        elif k == "angle": view[k] = f[0]
        elif k == "s":
            r = abs(f[3]) * math.sqrt(abs(M[0][0]**2 + M[1][0]**2 + M[2][0]**2))
            c = xf(f[:3]); pts.append(c)
            pts += [add(c, [r * (a == j) * sg for j in range(3)]) for a in range(3) for sg in (1, -1)]
        elif k in ("c", "cc"): pts += [xf(f[0:3]), xf(f[4:7])]
        elif k == "box": pts += [xf([f[(m >> j & 1) * 3 + j] for j in range(3)]) for m in range(8)]
        elif k == "disk": pts.append(xf(f[:3]))
        elif k in ("p", "pp") and f:
            for _ in range(int(f[0])):
                pts.append(xf([float(x) for x in lines[i][:3]])); i += 1
        elif k == "push": stack.append((M, T))
        elif k == "pop" and stack: M, T = stack.pop()
        elif k == "translate": T = xf(f[:3])
        elif k == "rotate": M = mat_mul(M, rot(f[:3], f[3]))
        elif k == "scale": M = [[x * f[0] for x in r] for r in M]
    return view, pts


def make_walk(rng, view, pts, frames):
    """One walk: list of (from, at, up, angle), and the name of its start strategy."""
    q = lambda j, f: sorted(p[j] for p in pts)[int(f * (len(pts) - 1))]  # robust box: huge floors
    lo = [q(j, 0.02) for j in range(3)] if pts else add(view["at"], [-1] * 3)  # do not dominate it
    hi = [q(j, 0.98) for j in range(3)] if pts else add(view["at"], [1] * 3)
    ctr, diag = mul(add(lo, hi), 0.5), max(norm(sub(hi, lo)), 1e-9)
    pick = lambda: rng.choice(pts) if pts else ctr
    jit = lambda p, s: add(p, [rng.gauss(0, s) for _ in range(3)])
    kind = rng.choice(["orbit", "orbit", "inside", "close", "close", "scene", "behind", "far"])
    target = jit(pick(), 0.02 * diag)
    if kind == "orbit":
        eye = add(ctr, mul(unit([rng.gauss(0, 1) for _ in range(3)]), diag * rng.uniform(0.3, 0.9)))
    elif kind == "inside":
        eye = [rng.uniform(lo[j], hi[j]) for j in range(3)]
    elif kind == "close":  # within a few percent of the scene size from a surface point
        eye = jit(target, diag * 10 ** rng.uniform(-3.5, -1))
        target = jit(pick(), 0.02 * diag) if rng.random() < 0.5 else jit(target, 0.05 * diag)
    elif kind == "scene":
        eye = jit(view["from"], 0.05 * norm(sub(view["from"], view["at"])))
        target = jit(view["at"], 0.05 * diag)
    elif kind == "behind":  # opposite the scene's own camera
        eye = add(ctr, mul(sub(ctr, view["from"]), rng.uniform(0.3, 1.2)))
    else:
        eye = add(ctr, mul(unit([rng.gauss(0, 1) for _ in range(3)]), diag * rng.uniform(1, 4)))
    if norm(sub(target, eye)) < 1e-6 * diag: target = add(eye, [0, 0, -diag])
    fwd, dist = unit(sub(target, eye)), max(norm(sub(target, eye)), 1e-4 * diag)
    up0 = unit(view["up"])
    angle = rng.choice([rng.uniform(25, 75)] * 4 + [rng.uniform(5, 20), rng.uniform(90, 150)])
    speed = diag * (10 ** rng.uniform(-3, -1.3)) * (0.1 if kind == "close" else 1)
    vel = mul(unit([rng.gauss(0, 1) for _ in range(3)]), speed)
    yaw_rate, pitch_rate, roll = rng.gauss(0, 2.5), rng.gauss(0, 1.0), rng.gauss(0, 8) if rng.random() < 0.3 else 0
    out = []
    for k in range(frames):
        up = mat_vec(rot(fwd, roll), up0)
        if norm(cross(fwd, up)) < 1e-3: up = [1, 0, 0] if abs(fwd[0]) < 0.9 else [0, 0, 1]
        out.append((eye, add(eye, mul(fwd, dist)), up, angle))
        eye = add(add(eye, vel), mul(fwd, speed * rng.gauss(0, 0.5)))
        yaw = yaw_rate + (rng.choice([-1, 1]) * rng.uniform(15, 35) if rng.random() < 0.12 else 0)
        fwd = unit(mat_vec(rot(up0, yaw), fwd))
        side = cross(fwd, up0)
        if norm(side) > 1e-3 and abs(dot(fwd, up0)) < 0.97: fwd = unit(mat_vec(rot(side, pitch_rate), fwd))
        vel = add(mul(vel, 0.8), mul(unit([rng.gauss(0, 1) for _ in range(3)]), 0.2 * speed))
    return out, kind


def push_back(walk, rng):
    """The same walk through a telephoto lens from 10^2 to 10^5 times as far back along each
    frame's view, the view angle shrunk to frame the same region at the target (an eye
    thousands of scene sizes away once broke the float reference: docs/stress.md, far eyes)."""
    s = 10 ** rng.uniform(2, 5)
    out = []
    for fr, at, up, ang in walk:
        fwd = sub(at, fr)
        half = math.radians(ang) / 2
        out.append((sub(at, mul(fwd, s)), at, up, math.degrees(2 * math.atan(math.tan(half) / s))))
    return out


def write_path(fn, walk, note):
    with open(fn, "w") as f:
        f.write("# bound-sweep walk (%s): from  at  up  angle\n" % note)
        for fr, at, up, ang in walk:
            f.write("  ".join(" ".join("%.9g" % x for x in v) for v in (fr, at, up)) + "  %.6g\n" % ang)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", nargs="+", required=True)
    ap.add_argument("--walks", type=int, default=4)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--size", default="240x180")
    ap.add_argument("--eps", nargs="+", default=["0.01", "0.05", "0.2"])
    ap.add_argument("--modes", nargs="+", default=["interp", "full"])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--exe", default="build/epsray")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=900)
    ap.add_argument("--keep-dir", default="/tmp/bound-sweep")
    ap.add_argument("--flags", default="", help="more epsray flags for every walk, e.g. '--reproject osmesa --pipeline'")
    ap.add_argument("--far-eyes", type=float, default=0.0,
                    help="share of walks pushed 10^2-10^5 times farther back through a telephoto lens "
                         "(drawn from a second generator, so the walks of a seed are otherwise unchanged)")
    a = ap.parse_args()
    os.makedirs(a.keep_dir, exist_ok=True)
    rng, t0 = random.Random(a.seed), time.time()
    far_rng = random.Random(a.seed * 7919 + 1)
    nruns = nframes = 0; bad, worst = [], {}
    for scene in a.scenes:
        view, pts = parse_scene(scene)
        base = os.path.splitext(os.path.basename(scene))[0]
        for w in range(a.walks):
            walk, kind = make_walk(rng, view, pts, a.frames)
            if a.far_eyes > 0 and far_rng.random() < a.far_eyes:
                walk, kind = push_back(walk, far_rng), "tele-" + kind
            pf = os.path.abspath(os.path.join(a.keep_dir, "%s-s%d-w%d.path" % (base, a.seed, w)))
            write_path(pf, walk, "%s, seed %d, walk %d, start %s" % (scene, a.seed, w, kind))
            keep = False
            for mode in a.modes:
                for eps in a.eps:
                    st = os.path.join(a.keep_dir, "stats.json")
                    if os.path.exists(st): os.remove(st)
                    cmd = [a.exe, "walk", scene, "--path", pf, "--mode", mode, "--eps", eps, "--size", a.size,
                           "--verify", "--threads", str(a.threads)] + a.flags.split()
                    t = time.time()
                    try:
                        r = subprocess.run(cmd + ["--stats", st], capture_output=True, text=True, timeout=a.timeout)
                        rc, err = r.returncode, r.stderr.strip().splitlines()[-1:] if r.stderr.strip() else []
                    except subprocess.TimeoutExpired:
                        rc, err = "timeout", []
                    nruns += 1; over, mx, fo, acc, npx = 0, 0.0, [], 0, 1
                    if rc == 0:
                        for fr in json.load(open(st))["frames"]:
                            v, px = fr["verify"], fr["pixels"]; nframes += 1; mx = max(mx, v["max_rel_err"])
                            acc += px["fast"] + px["interp"]; npx += sum(px.values())
                            if v["violations"]: over += v["violations"]; fo.append(fr["index"])
                    key = (mode, eps); worst[key] = max(worst.get(key, 0.0), mx / float(eps))
                    line = "%-14s w%-2d %-6s %-6s eps %-5s max %.5f over %-5d acc %3d%% %5.1fs rc %s" % (
                        base, w, kind, mode, eps, mx, over, 100 * acc // npx, time.time() - t, rc)
                    if over or rc != 0:
                        keep = True
                        line += "  FRAMES %s %s\n    repro: %s" % (fo, " ".join(err), " ".join(cmd))
                        bad.append(line)
                    print(line, flush=True)
            if not keep: os.remove(pf)
    print("\nsummary: %d scenes, %d walks x %d frames, %d runs, %d verified frames, %.0f s" % (
        len(a.scenes), len(a.scenes) * a.walks, a.frames, nruns, nframes, time.time() - t0))
    for (mode, eps), r in sorted(worst.items()):
        print("  %-6s eps %-5s worst max_err/eps %.3f" % (mode, eps, r))
    print("%d failing runs" % len(bad))
    for l in bad: print(l)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
