#!/usr/bin/env python3
"""Convert one NFF scene (Eric Haines' SPD format) to Tachyon's scene language.

Usage:
    nff2tachyon.py SCENE.nff [-o OUT.dat] [--size WxH] [--depth 5]
                   [--cones cylinder|tris] [--cone-segments 16] [--no-frustum]

Purpose: a *timing* comparison of epsray's base Whitted tracer with Tachyon
(Debian package `tachyon`) on the same geometry, lights and view. Tachyon's
own NFF reader is not used because it is unfaithful (it ignores `angle`,
mirrors the image, gives every light full intensity and draws it as a white
sphere, ignores Shine and ior). Python 3 standard library only.

How each NFF feature maps (whitted.md is the reference model):

* Handedness. Tachyon builds its camera's right vector as up x view, i.e. it
  is left-handed; NFF (and epsray) use r = view x up. Every x coordinate
  (points, normals, camera vectors, lights) is negated, which mirrors the
  world so Tachyon's image comes out the right way round. A mirror also
  reverses every polygon's winding, so each triangle is written as
  (v0, v2, v1): Tachyon's STRI turns its interpolated normal towards the
  viewer by the winding's normal (v1-v0) x (v2-v0), the same rule as
  whitted.md's "entering" test, and that needs the winding to agree with
  the (mirrored) vertex normals again; without the swap smooth patches
  would be shaded from the wrong side.
* Camera. CENTER = from, VIEWDIR = normalize(at - from), UPDIR = up (Tachyon
  orthogonalises it itself). Tachyon samples pixel column c (0-based, from
  the left) at image-plane coordinate left + (c+1)*(right-left)/W and row r
  (0-based, from the *bottom*) at bottom + (r+1)*(top-bottom)/H, on a plane
  at distance 1 (checked with one-pixel-wide test triangles on Tachyon
  0.99b6). whitted.md puts pixel centres at (x - (W-1)/2)*s and
  ((H-1)/2 - y)*s with s = 2 tan(angle/2) / (H-1). So a FRUSTUM of
  left = -(W+1)/2*s, right = (W-1)/2*s, bottom = -(H+1)/2*s,
  top = (H-1)/2*s gives the very same eye rays. ZOOM = 0.5/tan(angle/2) is
  written too (the parser needs it; the frustum overrides it). With
  --no-frustum only ZOOM is used: field of view off by H/(H-1) and the
  image shifted by half a pixel.
* Resolution: the NFF `resolution` unless --size overrides it. The frustum
  depends on it, so pass the final size here (and the same -res to tachyon,
  or none).
* RAYDEPTH 5 (--depth): Tachyon gives eye rays depth RAYDEPTH and spawns a
  secondary ray only while depth > 1, so 5 means five levels counting the
  eye ray, as whitted.md's Dmax = 5. ANTIALIASING 0.
* Lights: `l x y z` -> LIGHT RAD 0 (invisible point light), COLOR =
  sqrt(N)/(2N) grey, N = number of lights; `l x y z r g b` keeps its colour.
  No attenuation (Tachyon's default).
* Ambient: Tachyon has no scene ambient, only a per-texture AMBIENT
  coefficient multiplied by the surface colour, so AMBIENT = A * Kd with
  A = sqrt(N)/(2N) (0 without lights) reproduces whitted.md's A * Kd * C.
* Material `f r g b Kd Ks Shine T ior` -> one TEXDEF per distinct `f`:
  COLOR r g b, DIFFUSE Kd, SPECULAR Ks (Tachyon's SPECULAR is the mirror
  reflection weight, exactly Ks * L(reflected)), PHONG PLASTIC Ks
  PHONG_SIZE Shine when Ks > 0 and Shine > 0 (a PLASTIC highlight is
  light colour * Ks * pow(N.H, Shine) when rendered with -shade_blinn, the
  half-vector model of whitted.md; -shade_phong uses R.V instead, same
  cost), OPACITY 1 - T. Tachyon cannot refract: a transparent surface
  passes the ray straight on, weighted by T (= 1 - OPACITY), and `ior` is
  ignored; its shadows through transparent surfaces are filtered by the
  opacity (-shadow_filter_on, default) where whitted.md blocks them fully.
* Background `b r g b` -> BACKGROUND r g b.
* Sphere `s` -> SPHERE (|R|; Tachyon's shading normal always faces the ray).
* Cone/cylinder `c` (open, no caps) -> FCYLINDER BASE APEX RAD (open too)
  when r0 == r1. Tachyon has no cone primitive. For r0 != r1 (only SPD
  `tree` has them: tapering branches) the default (--cones cylinder) is an
  FCYLINDER of the mean radius (|r0| + |r1|) / 2: one analytic quadric
  against one, which keeps the *amount of geometry* (object count, BVH
  size, intersection cost class) equal; silhouettes differ slightly.
  --cones tris writes a triangulated frustum instead (--cone-segments side
  quads, 2 smooth STRIs each, normals of the true cone).
* Polygon `p n`: triangles -> TRI; convex polygons -> fan of TRIs;
  concave ones (SPD gears: 144-vertex faces) -> ear clipping in the
  polygon's plane. Tachyon triangles are double-sided, like NFF polygons.
  Degenerate (zero-area) triangles are dropped.
* Patch `pp n`: the same triangulation, as STRI with the vertex normals
  (a fan of a convex n-gon is exactly whitted.md's interpolation).

The first lines of the output are '#' comments with the counts (read by
compare.sh): "# nff_primitives N" and "# tachyon_objects M".
"""

import argparse
import math
import sys


class NFFError(Exception):
    pass


# ----------------------------------------------------------------------------
# small vector helpers
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = norm(a)
    if n == 0.0:
        raise NFFError("zero-length vector")
    return (a[0] / n, a[1] / n, a[2] / n)


def mirror(p):
    """Negate x: fixes Tachyon's left-handed camera (see module docstring)."""
    return (-p[0], p[1], p[2])


def fmt(x):
    s = "%.9g" % x
    return "0" if s == "-0" else s


def fmtv(v):
    return "%s %s %s" % (fmt(v[0]), fmt(v[1]), fmt(v[2]))


# ----------------------------------------------------------------------------
# triangulation
def newell_normal(pts):
    nx = ny = nz = 0.0
    n = len(pts)
    for i in range(n):
        x0, y0, z0 = pts[i]
        x1, y1, z1 = pts[(i + 1) % n]
        nx += (y0 - y1) * (z0 + z1)
        ny += (z0 - z1) * (x0 + x1)
        nz += (x0 - x1) * (y0 + y1)
    return (nx, ny, nz)


def project2d(pts):
    """Project a planar 3-D polygon onto the coordinate plane most parallel to
    it; returns 2-D points whose orientation follows the Newell normal's
    sign on the dropped axis."""
    n = newell_normal(pts)
    ax = max(range(3), key=lambda k: abs(n[k]))
    i, j = [(1, 2), (2, 0), (0, 1)][ax]
    return [(p[i], p[j]) for p in pts]


def cross2(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def signed_area2(p):
    s = 0.0
    n = len(p)
    for k in range(n):
        x0, y0 = p[k]
        x1, y1 = p[(k + 1) % n]
        s += x0 * y1 - x1 * y0
    return s


def is_convex(p, eps):
    """True if the (simple) 2-D polygon turns the same way at every vertex
    (collinear vertices allowed)."""
    n = len(p)
    sign = 0
    for k in range(n):
        c = cross2(p[k - 1], p[k], p[(k + 1) % n])
        if c > eps:
            if sign < 0:
                return False
            sign = 1
        elif c < -eps:
            if sign > 0:
                return False
            sign = -1
    return True


def ear_clip(p, eps):
    """Ear clipping of a simple 2-D polygon (convex or concave). Returns index
    triples in the polygon's own winding. O(n * reflex) per clipped ear."""
    n = len(p)
    order = list(range(n))
    flip = signed_area2(p) < 0
    if flip:
        order.reverse()          # work counter-clockwise
    nxt = {order[k]: order[(k + 1) % n] for k in range(n)}
    prv = {order[k]: order[k - 1] for k in range(n)}

    def convex(i):
        return cross2(p[prv[i]], p[i], p[nxt[i]]) > eps

    reflex = {i for i in order if not convex(i)}

    def inside(q, a, b, c):
        # closed triangle test (points on the boundary count as inside)
        return (cross2(a, b, q) >= -eps and cross2(b, c, q) >= -eps
                and cross2(c, a, q) >= -eps)

    def is_ear(i):
        a, b, c = prv[i], i, nxt[i]
        if i in reflex:
            return False
        pa, pb, pc = p[a], p[b], p[c]
        for r in reflex:
            if r == a or r == c:
                continue
            q = p[r]
            if q == pa or q == pb or q == pc:
                continue
            if inside(q, pa, pb, pc):
                return False
        return True

    tris = []
    remaining = n
    i = order[0]
    misses = 0
    while remaining > 3:
        a, c = prv[i], nxt[i]
        area = cross2(p[a], p[i], p[c])
        degenerate = abs(area) <= eps
        if degenerate or is_ear(i):
            if not degenerate:
                tris.append((a, i, c))
            nxt[a] = c
            prv[c] = a
            reflex.discard(i)
            remaining -= 1
            for v in (a, c):
                if v in reflex and convex(v):
                    reflex.discard(v)
            i = a
            misses = 0
            continue
        i = c
        misses += 1
        if misses > remaining:
            # Not a simple polygon (or numerical trouble): clip anyway so
            # that the geometry count stays right.
            a2, c2 = prv[i], nxt[i]
            tris.append((a2, i, c2))
            nxt[a2] = c2
            prv[c2] = a2
            reflex.discard(i)
            remaining -= 1
            i = a2
            misses = 0
    a, c = prv[i], nxt[i]
    if abs(cross2(p[a], p[i], p[c])) > eps:
        tris.append((a, i, c))
    if flip:
        tris = [(t[2], t[1], t[0]) for t in tris]
    return tris


def triangulate(pts):
    """Index triples covering the planar polygon pts (3-D)."""
    n = len(pts)
    if n == 3:
        return [(0, 1, 2)]
    p2 = project2d(pts)
    ext = max(max(abs(q[0] - p2[0][0]), abs(q[1] - p2[0][1])) for q in p2)
    eps = 1e-12 * ext * ext
    if is_convex(p2, eps):
        return [(0, k, k + 1) for k in range(1, n - 1)]
    return ear_clip(p2, eps)


# ----------------------------------------------------------------------------
# NFF reading
class Scene:
    def __init__(self):
        self.frm = (0.0, 0.0, 0.0)
        self.at = (0.0, 0.0, -1.0)
        self.up = (0.0, 1.0, 0.0)
        self.angle = 45.0
        self.res = (512, 512)
        self.background = (0.0, 0.0, 0.0)
        self.lights = []          # (pos, colour or None)
        self.materials = []       # (r, g, b, kd, ks, shine, t, ior)
        self.objects = []         # (kind, material index, data)
        self.nff_prims = 0


def read_nff(path):
    with open(path, "r", encoding="ascii", errors="replace") as fh:
        lines = fh.read().splitlines()
    sc = Scene()
    cur_mat = None            # index into sc.materials; None: default
    default_mat = (1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0)

    # token stream with line numbers; commands may continue on later lines
    toks = []
    for ln, line in enumerate(lines, 1):
        k = line.find("#")
        if k >= 0:
            line = line[:k]
        parts = line.split()
        if parts:
            toks.append((ln, parts))

    pos = 0               # index into toks
    col = 0               # index into toks[pos][1]

    def where():
        return "%s:%d" % (path, toks[min(pos, len(toks) - 1)][0])

    def rest_of_line():
        nonlocal pos, col
        ln, parts = toks[pos]
        r = parts[col:]
        pos += 1
        col = 0
        return r

    def numbers(k, what):
        """k numbers, from the rest of this line and following lines."""
        nonlocal pos, col
        out = []
        while len(out) < k:
            if pos >= len(toks):
                raise NFFError("%s: %s needs %d numbers" % (path, what, k))
            ln, parts = toks[pos]
            while col < len(parts) and len(out) < k:
                try:
                    out.append(float(parts[col]))
                except ValueError:
                    raise NFFError("%s:%d: %s: bad number %r"
                                   % (path, ln, what, parts[col]))
                col += 1
            if col >= len(parts):
                pos += 1
                col = 0
        return out

    def need_line_end():
        nonlocal pos, col
        if col != 0:
            pos += 1
            col = 0

    def material():
        if cur_mat is None:
            sc.materials.append(default_mat)
            return len(sc.materials) - 1
        return cur_mat

    while pos < len(toks):
        ln, parts = toks[pos]
        cmd = parts[col]
        col += 1
        if col >= len(parts):
            pos += 1
            col = 0
        if cmd == "v":
            need_line_end()
            continue
        if cmd in ("from", "at", "up"):
            v = tuple(numbers(3, cmd))
            setattr(sc, {"from": "frm", "at": "at", "up": "up"}[cmd], v)
        elif cmd == "angle":
            sc.angle = numbers(1, cmd)[0]
        elif cmd == "hither":
            numbers(1, cmd)
        elif cmd == "resolution":
            w, h = numbers(2, cmd)
            sc.res = (int(w), int(h))
        elif cmd == "b":
            sc.background = tuple(numbers(3, cmd))
        elif cmd == "l":
            if col == 0:
                raise NFFError("%s:%d: light needs 3 numbers" % (path, ln))
            vals = [float(x) for x in rest_of_line()]
            if len(vals) == 3:
                sc.lights.append((tuple(vals), None))
            elif len(vals) == 6:
                sc.lights.append((tuple(vals[:3]), tuple(vals[3:])))
            else:
                raise NFFError("%s:%d: light needs 3 or 6 numbers, got %d"
                               % (path, ln, len(vals)))
        elif cmd == "f":
            m = tuple(numbers(8, "f"))
            sc.materials.append(m)
            cur_mat = len(sc.materials) - 1
        elif cmd == "s":
            x, y, z, r = numbers(4, "sphere")
            sc.objects.append(("s", material(), ((x, y, z), r)))
            sc.nff_prims += 1
        elif cmd == "c":
            v = numbers(8, "cone")
            sc.objects.append(("c", material(),
                               (tuple(v[0:3]), v[3], tuple(v[4:7]), v[7])))
            sc.nff_prims += 1
        elif cmd in ("p", "pp"):
            n = int(numbers(1, cmd)[0])
            need_line_end()
            per = 3 if cmd == "p" else 6
            verts = []
            for _ in range(n):
                v = numbers(per, "polygon vertex")
                need_line_end()
                verts.append(v)
            if n < 3:
                raise NFFError("%s:%d: polygon with %d vertices" % (path, ln, n))
            sc.objects.append((cmd, material(), verts))
            sc.nff_prims += 1
        else:
            raise NFFError("%s:%d: unknown or unsupported NFF command %r"
                           % (path, ln, cmd))
    return sc


# ----------------------------------------------------------------------------
# Tachyon writing
def write_tachyon(sc, out, size, depth, cones, cone_segments, use_frustum,
                  source):
    W, H = size if size else sc.res
    if H < 2 or W < 1:
        raise NFFError("bad resolution %dx%d" % (W, H))
    nl = len(sc.lights)
    inten = math.sqrt(nl) / (2 * nl) if nl else 0.0
    ambient = inten                      # SPD convention, 0 without lights

    body = []
    emit = body.append
    counts = {"SPHERE": 0, "FCYLINDER": 0, "TRI": 0, "STRI": 0}

    # textures: one TEXDEF per distinct NFF material that is used
    used = sorted({o[1] for o in sc.objects})
    texname = {}
    for k in used:
        r, g, b, kd, ks, shine, t, ior = sc.materials[k]
        name = "m%d" % k
        texname[k] = name
        phong = ""
        if ks > 0 and shine > 0:
            phong = " PHONG PLASTIC %s PHONG_SIZE %s" % (fmt(ks), fmt(shine))
        emit("TEXDEF %s AMBIENT %s DIFFUSE %s SPECULAR %s OPACITY %s%s"
             " COLOR %s %s %s TEXFUNC 0"
             % (name, fmt(ambient * kd), fmt(kd), fmt(ks),
                fmt(max(0.0, 1.0 - t)), phong, fmt(r), fmt(g), fmt(b)))

    def tri(a, b, c, tex):
        if norm(cross(sub(b, a), sub(c, a))) == 0.0:
            return
        # b and c swapped: the mirror reverses the winding (see docstring)
        emit("TRI V0 %s V1 %s V2 %s %s"
             % (fmtv(mirror(a)), fmtv(mirror(c)), fmtv(mirror(b)), tex))
        counts["TRI"] += 1

    def stri(a, b, c, na, nb, nc, tex):
        if norm(cross(sub(b, a), sub(c, a))) == 0.0:
            return
        # b and c swapped: the mirror reverses the winding, and Tachyon
        # turns the interpolated normal to the viewer's side by the
        # winding's normal (v1-v0) x (v2-v0), as whitted.md does
        emit("STRI V0 %s V1 %s V2 %s N0 %s N1 %s N2 %s %s"
             % (fmtv(mirror(a)), fmtv(mirror(c)), fmtv(mirror(b)),
                fmtv(mirror(na)), fmtv(mirror(nc)), fmtv(mirror(nb)), tex))
        counts["STRI"] += 1

    for kind, mi, data in sc.objects:
        tex = texname[mi]
        if kind == "s":
            ctr, r = data
            emit("SPHERE CENTER %s RAD %s %s" % (fmtv(mirror(ctr)), fmt(abs(r)), tex))
            counts["SPHERE"] += 1
        elif kind == "c":
            base, r0, apex, r1 = data
            r0, r1 = abs(r0), abs(r1)
            if r0 == r1 or cones == "cylinder":
                emit("FCYLINDER BASE %s APEX %s RAD %s %s"
                     % (fmtv(mirror(base)), fmtv(mirror(apex)),
                        fmt(0.5 * (r0 + r1)), tex))
                counts["FCYLINDER"] += 1
            else:
                axis = sub(apex, base)
                h = norm(axis)
                a = normalize(axis)
                # any vector perpendicular to the axis
                t = (1.0, 0.0, 0.0) if abs(a[0]) < 0.9 else (0.0, 1.0, 0.0)
                e1 = normalize(cross(a, t))
                e2 = cross(a, e1)
                slope = (r0 - r1) / h     # normal tilts towards the apex
                ring = []
                for k in range(cone_segments):
                    ang = 2 * math.pi * k / cone_segments
                    d = add(scale(e1, math.cos(ang)), scale(e2, math.sin(ang)))
                    nrm = normalize(add(d, scale(a, slope)))
                    ring.append((add(base, scale(d, r0)),
                                 add(apex, scale(d, r1)), nrm))
                for k in range(cone_segments):
                    b0, t0, n0 = ring[k]
                    b1, t1, n1 = ring[(k + 1) % cone_segments]
                    stri(b0, b1, t1, n0, n1, n1, tex)
                    stri(b0, t1, t0, n0, n1, n0, tex)
        elif kind == "p":
            pts = [tuple(v) for v in data]
            for i, j, k in triangulate(pts):
                tri(pts[i], pts[j], pts[k], tex)
        elif kind == "pp":
            pts = [tuple(v[:3]) for v in data]
            nrm = [tuple(v[3:]) for v in data]
            for i, j, k in triangulate(pts):
                stri(pts[i], pts[j], pts[k], nrm[i], nrm[j], nrm[k], tex)

    nobj = sum(counts.values())
    w = out.write
    w("# converted by perf/tachyon/nff2tachyon.py from %s\n" % source)
    w("# nff_primitives %d\n" % sc.nff_prims)
    w("# tachyon_objects %d (%s)\n"
      % (nobj, ", ".join("%s %d" % kv for kv in counts.items())))
    w("# lights %d\n" % nl)
    w("BEGIN_SCENE\n")
    w("RESOLUTION %d %d\n" % (W, H))

    # camera (whitted.md section 1), mirrored in x
    wv = normalize(sub(sc.at, sc.frm))
    half = math.tan(math.radians(sc.angle) / 2.0)
    zoom = 0.5 / half
    w("CAMERA\n")
    w("  ZOOM %s\n" % fmt(zoom))
    w("  ASPECTRATIO 1.0\n")
    w("  ANTIALIASING 0\n")
    w("  RAYDEPTH %d\n" % depth)
    w("  CENTER %s\n" % fmtv(mirror(sc.frm)))
    w("  VIEWDIR %s\n" % fmtv(mirror(wv)))
    w("  UPDIR %s\n" % fmtv(mirror(sc.up)))
    if use_frustum:
        s = 2.0 * half / (H - 1)
        w("  FRUSTUM %s %s %s %s\n"
          % (fmt(-(W + 1) / 2.0 * s), fmt((W - 1) / 2.0 * s),
             fmt(-(H + 1) / 2.0 * s), fmt((H - 1) / 2.0 * s)))
    w("END_CAMERA\n")
    w("BACKGROUND %s\n" % fmtv(sc.background))
    for p, c in sc.lights:
        col = c if c is not None else (inten, inten, inten)
        w("LIGHT CENTER %s RAD 0 COLOR %s\n" % (fmtv(mirror(p)), fmtv(col)))
    for line in body:
        w(line)
        w("\n")
    w("END_SCENE\n")
    return nobj


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Convert an NFF scene to Tachyon's scene language.")
    ap.add_argument("scene", help="input .nff file")
    ap.add_argument("-o", "--output", help="output .dat file (default: stdout)")
    ap.add_argument("--size", help="WxH, overrides the NFF resolution")
    ap.add_argument("--depth", type=int, default=5,
                    help="RAYDEPTH (levels counting the eye ray; default 5)")
    ap.add_argument("--cones", choices=("cylinder", "tris"), default="cylinder",
                    help="cones with r0 != r1: FCYLINDER of mean radius "
                         "(default) or triangulated")
    ap.add_argument("--cone-segments", type=int, default=16)
    ap.add_argument("--no-frustum", action="store_true",
                    help="camera from ZOOM only (no exact pixel-centre match)")
    args = ap.parse_args(argv)

    size = None
    if args.size:
        try:
            w, h = args.size.lower().split("x")
            size = (int(w), int(h))
        except ValueError:
            ap.error("--size must be WxH")
    try:
        sc = read_nff(args.scene)
        if args.output:
            with open(args.output, "w") as out:
                n = write_tachyon(sc, out, size, args.depth, args.cones,
                                  args.cone_segments, not args.no_frustum,
                                  args.scene)
        else:
            n = write_tachyon(sc, sys.stdout, size, args.depth, args.cones,
                              args.cone_segments, not args.no_frustum,
                              args.scene)
    except (NFFError, OSError) as e:
        print("nff2tachyon: %s" % e, file=sys.stderr)
        return 2
    print("nff2tachyon: %s: %d NFF primitives -> %d Tachyon objects, %d lights"
          % (args.scene, sc.nff_prims, n, len(sc.lights)), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
