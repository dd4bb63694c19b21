#!/usr/bin/env python3
"""Random scenes for bound sweeps (stdlib only).

The bound must hold on scenes nobody wrote, not only on the test scenes and the SPD set.
This writes N random scenes in the native superset: every primitive kind (spheres, open
and capped cones and cylinders, boxes, disks, convex and concave polygons, patches with
vertex normals), materials from matte to mirror and glass (ior above and below 1, so
total internal reflection both ways), checker and image textures, plain and coloured
lights, an explicit ambient now and then, and nested transforms. Primitives run from 2% to
50% of the scene's scale, so large and small ones meet. Lit diffuse radiance is
kept near or below 1 (scene-format.md), some scenes push past it. With --hard H, each
primitive comes with probability H with a configuration where methods fail: coplanar
overlapping polygons, nested glass, a light inside glass or just above a disk, slivers,
interpenetrating solids, a plane seen edge on.

    python3 tools/random-scene.py --count 20 --seed 1 --out /tmp/rs
    python3 tools/bound-sweep.py --scenes /tmp/rs/*.nff --walks 2 --frames 8 --size 160x120

The scenes are a pure function of --seed, --count and --hard (--paths: the same scenes,
plus a camera path each).
"""
import argparse, math, os, random

TEXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scenes", "textures")


def vec(v): return " ".join("%.9g" % x for x in v)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def material(rng):
    kind = rng.choice(["matte", "matte", "shiny", "shiny", "mirror", "glass", "glass-low"])
    c = [rng.uniform(0.2, 1) for _ in range(3)]
    kd = {"matte": rng.uniform(0.4, 0.9), "shiny": rng.uniform(0.3, 0.7), "mirror": rng.uniform(0, 0.3),
          "glass": rng.uniform(0, 0.2), "glass-low": rng.uniform(0, 0.2)}[kind]
    ks = {"matte": rng.choice([0, 0, rng.uniform(0, 0.1)]), "shiny": rng.uniform(0.05, 0.5),
          "mirror": rng.uniform(0.5, 0.95), "glass": rng.uniform(0.05, 0.3), "glass-low": rng.uniform(0.05, 0.3)}[kind]
    shine = rng.choice([0, rng.uniform(1, 10), rng.uniform(10, 100), rng.uniform(100, 1000)])
    t = rng.uniform(0.4, 0.9) if kind.startswith("glass") else 0
    ior = rng.uniform(1.1, 2.4) if kind == "glass" else (rng.uniform(0.5, 0.95) if kind == "glass-low" else 1)
    return "f %s %.4g %.4g %.4g %.4g %.4g" % (vec(c), kd, ks, shine, t, ior)


def texture(rng, tex_dir):
    """A texture line for the next primitives (mostly none); images named from tex_dir."""
    if rng.random() < 0.75:
        return "texture none"
    s = rng.uniform(0.1, 3)
    if rng.random() < 0.5:
        a = [rng.uniform(0, 1) for _ in range(3)]
        b = [rng.uniform(0, 1) for _ in range(3)]
        return "texture checker %s %s %.4g %.4g" % (vec(a), vec(b), s, s * rng.uniform(0.5, 2))
    name = rng.choice(sorted(f for f in os.listdir(TEXTURES) if f.endswith(".png")))
    return "texture image %s %.4g %.4g" % (os.path.join(tex_dir, name), s, s * rng.uniform(0.5, 2))


def point(rng, r):
    return [rng.uniform(-r, r), rng.uniform(0, r), rng.uniform(-r, r)]


def polygon(rng, centre, size, concave):
    """A planar polygon around centre: a random plane, vertices counter-clockwise in it."""
    n = unit([rng.gauss(0, 1) for _ in range(3)])
    a = unit([n[1], -n[0], 0] if abs(n[2]) < 0.9 else [0, n[2], -n[1]])
    b = [n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]]
    k = rng.randint(5, 9) if concave else rng.randint(3, 6)
    angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(k))
    # Keep the first two edges at a proper angle (scene-format.md's check).
    angles[0], angles[1] = 0.0, 2 * math.pi / k
    angles[2:] = sorted(max(x, angles[1] + 0.2) for x in angles[2:])
    pts = []
    for j, t in enumerate(angles):
        r = size * (rng.uniform(0.3, 1) if concave and j % 2 and j > 2 else 1)
        pts.append([centre[i] + r * (math.cos(t) * a[i] + math.sin(t) * b[i]) for i in range(3)])
    return n, pts


def primitive(rng, r):
    kind = rng.choice(["s", "s", "c", "cc", "box", "disk", "p", "pconc", "pp"])
    size = r * math.exp(rng.uniform(math.log(0.02), math.log(0.5)))
    p = point(rng, r)
    if kind == "s":
        return ["s %s %.5g" % (vec(p), size * rng.choice([1, 1, 1, -1]))]
    if kind in ("c", "cc"):
        q = [p[i] + size * 2 * x for i, x in enumerate(unit([rng.gauss(0, 1) for _ in range(3)]))]
        r0 = size * rng.uniform(0.2, 1)
        r1 = rng.choice([r0, 0, size * rng.uniform(0.1, 1)])
        return ["%s %s %.5g %s %.5g" % (kind, vec(p), r0, vec(q), r1)]
    if kind == "box":
        q = [p[i] + size * rng.uniform(0.2, 2) for i in range(3)]
        return ["box %s %s" % (vec(p), vec(q))]
    if kind == "disk":
        return ["disk %s %s %.5g" % (vec(p), vec([rng.gauss(0, 1) for _ in range(3)]), size)]
    n, pts = polygon(rng, p, size * 2, kind == "pconc")
    if kind == "pp":
        out = ["pp %d" % len(pts)]
        for v in pts:
            vn = unit([n[i] + rng.uniform(-0.4, 0.4) for i in range(3)])
            out.append("%s %s" % (vec(v), vec(vn)))
        return out
    return ["p %d" % len(pts)] + [vec(v) for v in pts]


def hard_case(rng, r, tex_dir):
    """Configurations where methods fail: coincident and nested surfaces, a light inside
    glass or next to a surface, slivers, grazing planes."""
    kind = rng.choice(["coplanar", "nested-glass", "light-inside", "light-close", "sliver", "interpenetrate",
                       "grazing"])
    p = point(rng, r)
    size = r * rng.uniform(0.1, 0.5)
    if kind == "coplanar":  # two overlapping squares in one plane, different materials
        q = [p[0] + size * 0.5, p[1], p[2] + size * 0.3]
        sq = lambda c: ["p 4", vec([c[0] - size, c[1], c[2] - size]), vec([c[0] - size, c[1], c[2] + size]),
                        vec([c[0] + size, c[1], c[2] + size]), vec([c[0] + size, c[1], c[2] - size])]
        return [material(rng)] + sq(p) + [material(rng)] + sq(q)
    if kind == "nested-glass":
        ior = rng.uniform(1.1, 2)
        return ["f 1 1 1 0.05 0.2 50 0.8 %.4g" % ior, "s %s %.9g" % (vec(p), size),
                "f 1 1 1 0.05 0.2 50 0.8 %.4g" % (1 / ior if rng.random() < 0.5 else ior * 1.2),
                "s %s %.9g" % (vec(p), size * rng.uniform(0.3, 0.9))]
    if kind == "light-inside":
        return ["l %s 0.3 0.3 0.3" % vec(p), "f 1 1 1 0.1 0.1 20 0.8 1.5", "s %s %.9g" % (vec(p), size)]
    if kind == "light-close":
        return ["l %s 0.2 0.2 0.2" % vec([p[0], p[1] + size * 1e-3, p[2]]), material(rng),
                "disk %s 0 1 0 %.9g" % (vec(p), size)]
    if kind == "sliver":
        q = [p[0] + size, p[1] + size * 1e-3, p[2] + size * 0.5]
        return [material(rng), "box %s %s" % (vec(p), vec(q)),
                "cc %s %.9g %s %.9g" % (vec(p), size * 1e-3, vec([p[0], p[1] + size, p[2]]), size * 1e-3)]
    if kind == "interpenetrate":
        q = [p[0] + size * 0.7, p[1], p[2]]
        return [material(rng), "s %s %.9g" % (vec(p), size), material(rng), "s %s %.9g" % (vec(q), size),
                material(rng), "c %s %.9g %s %.9g" % (vec(p), size * 0.3, vec(q), size * 0.3)]
    # A wide plane, nearly level: seen almost edge on from eye height.
    g = 1.5 * r
    return [material(rng), texture(rng, tex_dir), "p 4", vec([p[0] - g, p[1], p[2] - g]),
            vec([p[0] - g, p[1] + 0.01 * r, p[2] + g]), vec([p[0] + g, p[1] + 0.01 * r, p[2] + g]),
            vec([p[0] + g, p[1], p[2] - g])]


def orbit_path(eye, at, angle, what):
    """8 frames orbiting `at` by 3 degrees a frame while closing in by 3% a frame, then 2
    frames turning 20 degrees each on the spot: reprojection's case, then its failure."""
    lines = ["# epsray camera path (whitted.md section 8): from  at  up  angle", "# " + what]
    dx, dz = eye[0] - at[0], eye[2] - at[2]
    for k in range(10):
        a = math.radians(3 * min(k, 7))
        s = 0.97 ** min(k, 7)
        e = [at[0] + s * (dx * math.cos(a) - dz * math.sin(a)), at[1] + s * (eye[1] - at[1]),
             at[2] + s * (dx * math.sin(a) + dz * math.cos(a))]
        t = [at[i] - e[i] for i in range(3)]
        if k > 7:  # turn the view direction about the vertical through the eye
            b = math.radians(20 * (k - 7))
            t = [t[0] * math.cos(b) - t[2] * math.sin(b), t[1], t[0] * math.sin(b) + t[2] * math.cos(b)]
        lines.append("%s  %s  0 1 0  %.4g" % (vec(e), vec([e[i] + t[i] for i in range(3)]), angle))
    return "\n".join(lines) + "\n"


def scene(rng, index, hard, tex_dir):
    """The scene's text and its camera path's."""
    r = rng.choice([1.0, 10.0, 0.05, 300.0])  # the scene's scale
    out = ["# random scene %d (tools/random-scene.py), scale %g" % (index, r)]
    eye = [rng.uniform(-2, 2) * r, rng.uniform(0.3, 2) * r, rng.uniform(2, 4) * r]
    angle = rng.uniform(30, 70)
    out += ["v", "from %s" % vec(eye), "at %s" % vec([0, 0.3 * r, 0]), "up 0 1 0",
            "angle %.3g" % angle, "hither 0.01", "resolution 160 120"]
    out.append("b %s" % vec([rng.uniform(0, 0.3) for _ in range(3)]))
    nl = rng.randint(1, 4)
    coloured = rng.random() < 0.5
    for _ in range(nl):
        pos = [rng.uniform(-3, 3) * r, rng.uniform(0.5, 4) * r, rng.uniform(-3, 3) * r]
        if coloured:
            out.append("l %s %s" % (vec(pos), vec([rng.uniform(0.1, 0.8) / nl for _ in range(3)])))
        else:
            out.append("l %s" % vec(pos))
    if rng.random() < 0.4:
        out.append("ambient %s" % vec([rng.uniform(0, 0.3) for _ in range(3)]))
    # A ground, often textured: most scenes have one and its shadows and reflections matter.
    if rng.random() < 0.8:
        out += [material(rng), texture(rng, tex_dir)]
        g = 3 * r
        if rng.random() < 0.5:
            out += ["p 4", vec([-g, 0, -g]), vec([-g, 0, g]), vec([g, 0, g]), vec([g, 0, -g])]
        else:
            out += ["box %s %s" % (vec([-g, -0.1 * r, -g]), vec([g, 0, g]))]
    depth = 0
    for _ in range(rng.randint(4, 24)):
        roll = rng.random()
        if roll < 0.12 and depth < 4:
            out += ["push", "translate %s" % vec(point(rng, 0.3 * r)),
                    "rotate %s %.4g" % (vec([rng.gauss(0, 1) or 1 for _ in range(3)]), rng.uniform(-180, 180))]
            if rng.random() < 0.3:
                out.append("scale %.4g" % rng.uniform(0.5, 1.5))
            depth += 1
        elif roll < 0.2 and depth > 0:
            out.append("pop")
            depth -= 1
        if rng.random() < 0.6:
            out.append(material(rng))
            out.append(texture(rng, tex_dir))
        out += primitive(rng, r)
        if rng.random() < hard:
            out += hard_case(rng, r, tex_dir)
    out += ["pop"] * depth
    return "\n".join(out) + "\n", orbit_path(eye, [0, 0.3 * r, 0], float("%.3g" % angle), out[0][2:])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--count", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--hard", type=float, default=0.15, help="chance per primitive of a hard case as well")
    ap.add_argument("--out", required=True)
    ap.add_argument("--paths", action="store_true", help="also write SCENE.path: an orbit, then a fast turn")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    tex_dir = os.path.relpath(TEXTURES, a.out)  # scene files resolve it against their folder
    rng = random.Random(a.seed)
    for i in range(a.count):
        name = os.path.join(a.out, "random-s%d-%02d" % (a.seed, i))
        text, path = scene(rng, i, a.hard, tex_dir)
        with open(name + ".nff", "w") as f:
            f.write(text)
        if a.paths:
            with open(name + ".path", "w") as f:
                f.write(path)


if __name__ == "__main__":
    main()
