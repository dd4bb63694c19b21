"""Helpers shared by the perf scripts: running `epsray walk` for its stats, and camera
paths made from a scene's own view."""
import json
import math
import os
import shutil
import subprocess
import tempfile


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def add_walk_arguments(ap, out):
    """The options of the benchmarks that walk the art room's path (walk/, reproject/):
    --scene, --path, --size, --exe, and --out, perf/results/OUT by default."""
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "artroom.nff"))
    ap.add_argument("--path", default=os.path.join(ROOT, "scenes", "paths", "artroom-walk.path"))
    ap.add_argument("--size", default="800x600")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "epsray"))
    ap.add_argument("--out", default=os.path.join(ROOT, "perf", "results", out))


def run_walk(exe, scene, path, flags):
    """`epsray walk SCENE --path PATH --quiet FLAGS...`; returns its --stats JSON."""
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "s.json")
        subprocess.run([exe, "walk", scene, "--path", path, "--quiet", "--stats", stats] + [str(f) for f in flags],
                       check=True)
        with open(stats) as f:
            return json.load(f)


def gnuplot(script, png):
    """Draws a chart with gnuplot when it is installed; True when `png` was written.
    The charts share one style: a title on every figure and panel, keys outside the
    plotting area, and value axes that start at zero unless they are logarithmic."""
    if not shutil.which("gnuplot"):
        return False
    ok = subprocess.run(["gnuplot", "-e", script]).returncode == 0
    if ok:
        print("wrote", png)
    return ok


def gp_text(s):
    """A string for a gnuplot script, in single quotes (a quote inside is doubled)."""
    return "'" + str(s).replace("'", "''") + "'"


def view_of(scene):
    v = {"from": [0, 0, 0], "at": [0, 0, -1], "up": [0, 1, 0], "angle": 45}
    with open(scene) as f:
        for line in f:
            k = line.split()
            if k and k[0] in ("from", "at", "up"):
                v[k[0]] = [float(x) for x in k[1:4]]
            elif k and k[0] == "angle":
                v["angle"] = float(k[1])
    return v


def orbit_path(scene, frames, out):
    """A slow turn about the view's up axis through 'at': about 1 degree a frame."""
    v = view_of(scene)
    f, a, u = v["from"], v["at"], v["up"]
    n = math.sqrt(sum(x * x for x in u)) or 1
    u = [x / n for x in u]
    rel = [f[i] - a[i] for i in range(3)]
    with open(out, "w") as o:
        for k in range(frames):
            t = math.radians(1.0 * k)
            # Rodrigues rotation of rel about u by t.
            d = sum(rel[i] * u[i] for i in range(3))
            cx = [u[1] * rel[2] - u[2] * rel[1], u[2] * rel[0] - u[0] * rel[2], u[0] * rel[1] - u[1] * rel[0]]
            r = [rel[i] * math.cos(t) + cx[i] * math.sin(t) + u[i] * d * (1 - math.cos(t)) for i in range(3)]
            p = [a[i] + r[i] for i in range(3)]
            o.write("%g %g %g  %g %g %g  %g %g %g  %g\n" % (*p, *a, *u, v["angle"]))
