#!/usr/bin/env python3
"""Writes scenes/paths/artroom-long.path: 1000 frames around the art room at the paper's
walking speed (17 m in 400 frames), on an ellipse about the room's middle, looking along the
way with the gaze swinging +-40 degrees every 150 frames: 1.4 laps, so the walk returns to
cells it left long before (what a memory budget evicts). Deterministic."""
import math
import os

STEP = 17.0 / 400
CX, CZ, RX, RZ = 0.0, -6.5, 3.5, 6.0  # the room spans x -6..6, z -16..3
lines = ["# epsray camera path (whitted.md section 8): from  at  up  angle",
         "# made by scenes/paths/make_artroom_long.py"]
t = 0.0
for k in range(1000):
    x, z = CX + RX * math.cos(t), CZ + RZ * math.sin(t)
    dx, dz = -RX * math.sin(t), RZ * math.cos(t)  # the ellipse's tangent
    speed = math.hypot(dx, dz)
    yaw = math.atan2(dx, dz) + math.radians(40) * math.sin(2 * math.pi * k / 150)
    at = (x + math.sin(yaw), 1.5, z + math.cos(yaw))
    lines.append("%.5f %.5f %.5f  %.5f %.5f %.5f  0 1 0  55" % (x, 1.7, z, *at))
    t += STEP / speed
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "artroom-long.path")
with open(out, "w") as f:
    f.write("\n".join(lines) + "\n")
