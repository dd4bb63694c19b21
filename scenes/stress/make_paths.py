#!/usr/bin/env python3
"""Writes the camera paths of the stress scenes (scenes/stress/paths/*.path, whitted.md
section 8). Deterministic; rerun after changing the motion.

Every stress scene keeps its objects within a few units of the origin, so one set of
paths serves them all. The camera circles the origin at radius 6, 1.2 units up, looking
at (0, 0.5, 0):

  smooth     9 frames, 2.5 degrees of orbit per frame: the case reprojection is for.
  backwards  9 frames backing away from the origin along the view direction (radius 4 to
             8): every frame uncovers new pixels along the image border.
  fast-turn  8 frames standing still and turning 25 degrees per frame, left then right:
             most of each frame was outside the last one.
  teleport   7 frames jumping between unrelated viewpoints (front, right, above, behind,
             close up, low, front again): nothing carries over.

Scene-specific paths: the scaled scenes (tiny-scale.nff, huge-scale.nff) get the same
four paths with every length multiplied by 1e-4 and 1e4 (tiny-*.path, huge-*.path); the
camera stands on the floor plane of on-surface.nff (y = 1.2) in every generic path
except teleport, which is why that scene needs nothing of its own.
"""
import math
import os

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paths")
R, EYE_Y = 6.0, 1.2
AT = (0.0, 0.5, 0.0)


def orbit(deg, radius=R, y=EYE_Y):
    a = math.radians(deg)
    return (round(radius * math.sin(a), 9), y, round(radius * math.cos(a), 9))


def smooth():
    return [(orbit(-10 + 2.5 * k), AT, 40) for k in range(9)]


def backwards():
    frames = []
    for k in range(9):
        d = 4.0 + 0.5 * k
        f = orbit(15, d, 0.5 + (EYE_Y - 0.5) * d / R)  # along the line from AT through the orbit point
        frames.append((f, AT, 40))
    return frames


def fast_turn():
    eye = orbit(0)
    frames = []
    for yaw in (0, 25, 50, 75, 50, 25, 0, -25):
        a = math.radians(yaw)
        d = (-math.sin(a), (AT[1] - EYE_Y) / R, -math.cos(a))  # yaw 0 looks at the origin
        frames.append((eye, tuple(eye[i] + d[i] for i in range(3)), 40))
    return frames


def teleport():
    return [
        (orbit(0), AT, 40),
        (orbit(90), AT, 40),
        ((0.3, 7.0, 0.4), AT, 40),
        (orbit(180), AT, 40),
        (orbit(35, 2.6, 0.9), AT, 30),
        (orbit(-60, 5.0, 0.15), AT, 50),
        (orbit(0), AT, 40),
    ]


def write(name, frames, scale, what):
    lines = ["# epsray camera path (whitted.md section 8): from  at  up  angle",
             "# %s; made by scenes/stress/make_paths.py" % what]
    for f, a, angle in frames:
        nums = [c * scale for c in f] + [c * scale for c in a]
        lines.append("%s  %s  0 1 0  %g" % (" ".join("%.9g" % v for v in nums[:3]),
                                             " ".join("%.9g" % v for v in nums[3:]), angle))
    with open(os.path.join(HERE, name), "w") as out:
        out.write("\n".join(lines) + "\n")


PATHS = {"smooth": smooth, "backwards": backwards, "fast-turn": fast_turn, "teleport": teleport}

if __name__ == "__main__":
    os.makedirs(HERE, exist_ok=True)
    for name, make in PATHS.items():
        write(name + ".path", make(), 1.0, name)
        write("tiny-" + name + ".path", make(), 1e-4, name + ", lengths times 1e-4 for tiny-scale.nff")
        write("huge-" + name + ".path", make(), 1e4, name + ", lengths times 1e4 for huge-scale.nff")
