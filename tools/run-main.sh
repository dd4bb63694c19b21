#!/usr/bin/env bash
# The main job: set up, then render the built-in art room and print a summary.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
mkdir -p out
build/epsray render scenes/artroom.nff --mode base --png out/artroom.png --pfm out/artroom.pfm \
  --stats out/artroom.json "$@"
