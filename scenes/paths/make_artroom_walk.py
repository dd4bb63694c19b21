#!/usr/bin/env python3
"""Writes scenes/paths/artroom-walk.path: 60 frames through the art room at the paper's
speed (section 8.2: crossing the room's 17 m takes 400 frames, a full turn 150 frames),
in mixed directions: forward, turning left while moving, backing up, turning right,
sidestepping. Deterministic; rerun after changing the motion."""
import math
import os

STEP = 17.0 / 400          # metres per frame
TURN = 2 * math.pi / 150   # radians per frame
pos = [-2.7, 1.7, 1.4]
yaw = math.atan2(0.9 - pos[0], -(-10 - pos[2]))  # towards the scene's own 'at', from -z
pitch = math.atan2(1.2 - 1.7, math.hypot(0.9 + 2.7, -10 - 1.4))

# (frames, forward step, sideways step, turn) per segment
segments = [(15, 1, 0, 0), (12, 1, 0, 1), (10, -1, 0, 0), (13, 0, 0, -1), (10, 0, 1, 0)]
lines = ["# epsray camera path (whitted.md section 8): from  at  up  angle",
         "# made by scenes/paths/make_artroom_walk.py"]
for frames, fwd, side, turn in segments:
    for _ in range(frames):
        d = [math.sin(yaw) * math.cos(pitch), math.sin(pitch), -math.cos(yaw) * math.cos(pitch)]
        right = [math.cos(yaw), 0, math.sin(yaw)]
        at = [pos[i] + d[i] for i in range(3)]
        lines.append("%.5f %.5f %.5f  %.5f %.5f %.5f  0 1 0  55" % (*pos, *at))
        pos = [pos[i] + STEP * (fwd * d[i] + side * right[i]) for i in range(3)]
        pos[1] = 1.7
        yaw += TURN * turn
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "artroom-walk.path")
with open(out, "w") as f:
    f.write("\n".join(lines) + "\n")
