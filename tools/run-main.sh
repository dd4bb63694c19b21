#!/usr/bin/env bash
# The main job: set up, render the built-in art room, then walk through it (reprojection
# and interpolants, 60 frames at the paper's speed), and print summaries. Extra arguments
# go to the still render.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
mkdir -p out
build/epsray render scenes/artroom.nff --mode base --png out/artroom.png --pfm out/artroom.pfm \
  --stats out/artroom.json "$@"
build/epsray walk scenes/artroom.nff --path scenes/paths/artroom-walk.path --mode full --eps 0.05 \
  --out-dir out/walk --png --stats out/walk.json
