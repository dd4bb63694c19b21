#!/usr/bin/env bash
# The whole benchmark suite (issue 7), one command on a fresh machine:
#   perf/run-suite.sh [--quick]
# Installs what is missing and builds (tools/setup.sh), then runs every benchmark into
# perf/results/ (ignored by git): speed against accuracy with the baselines, the walkthrough
# (Table 1 and Figure 12), still-frame interpolation, thread scaling on this machine's cores,
# the 1000-frame memory-budget walk, the Tachyon comparison and the micro-benchmarks; each writes its Markdown, raw JSON/CSV
# and PNG charts, and perf/results/report.md gathers them with the machine's topology.
# About half an hour on a 2-core machine (the sum of its parts); --quick (smaller frames,
# fewer settings) took 2 min 12 s.
# Do not run it beside a build or the tests: the ratios are side by side, but the noise is not.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
tools/setup.sh
cmake --build build -j"$(nproc)" --target epsray_micro >/dev/null
R=perf/results
mkdir -p "$R"
exe=build/epsray
log() { printf '\n== %s (%s)\n' "$1" "$(date +%H:%M:%S)"; }

if ((quick)); then
  acc=(--frames 8 --size 200x150 --eps 0.01,0.05,0.2 --upsample 2,4 --reuse-age 2,8 --lf-depth 4,5)
  walk=(--size 400x300) reproject=(--size 400x300 --reps 1) interp=(--size 400x300 --eps 0.05)
  spd=(--size 320x240 --frames 8 --paths orbit)
  scale=(--frames 4 --size 320x240)
  memory=(--frames 100 --size 200x150 --budgets 16)
  tachyon=(-r 1) micro=(--benchmark_filter=whitted)
else
  acc=() walk=() reproject=() interp=() spd=() scale=() memory=() tachyon=(-r 3) micro=()
fi

log "speed against accuracy, with the baselines"
python3 perf/accuracy/bench.py --exe "$exe" --out "$R/accuracy.md" "${acc[@]}"
log "walkthrough: Table 1 and Figure 12"
python3 perf/walk/bench.py --exe "$exe" --out "$R/walk.md" "${walk[@]}"
log "SPD walks: full against base"
python3 perf/spd/bench.py --exe "$exe" --out "$R/spd" "${spd[@]}"
log "reprojection methods and pipelining"
python3 perf/reproject/bench.py --exe "$exe" --out "$R/reproject.md" "${reproject[@]}"
log "still frames: interpolation"
python3 perf/interp/bench.py --exe "$exe" --out "$R/interp.md" "${interp[@]}"
log "thread scaling on this machine"
python3 perf/scaling/bench.py --exe "$exe" --out "$R/scaling.md" "${scale[@]}"
log "memory budget over a long walk"
python3 perf/memory/bench.py --exe "$exe" --out "$R/memory.md" "${memory[@]}"
log "Tachyon"
if command -v tachyon >/dev/null; then
  perf/tachyon/compare.sh "${tachyon[@]}" -o "$R/tachyon.md" || echo "tachyon comparison failed; the report goes on"
fi
log "micro-benchmarks"
build/perf/epsray_micro --benchmark_out="$R/micro.json" --benchmark_out_format=json "${micro[@]}" >"$R/micro.txt"

# The report: every part's Markdown in one file, charts linked beside their tables.
{
  echo "# epsray benchmark report ($(date '+%Y-%m-%d %H:%M'))"
  echo
  echo "Made by \`perf/run-suite.sh${1:+ $1}\` at commit $(git rev-parse --short HEAD 2>/dev/null || echo '?')."
  echo
  echo '```'
  "$exe" info
  echo '```'
  for part in accuracy walk spd reproject interp scaling memory tachyon; do
    [ -f "$R/$part.md" ] || continue
    echo
    sed 's/^# /## /' "$R/$part.md"
    for png in "$R/$part"*.png; do
      [ -f "$png" ] || continue
      grep -q "$(basename "$png")" "$R/$part.md" || printf '\n![%s](%s)\n' "$(basename "$png" .png)" "$(basename "$png")"
    done
  done
  echo
  echo "## Micro-benchmarks (one thread)"
  echo
  echo '```'
  cat "$R/micro.txt"
  echo '```'
} >"$R/report.md"
log "wrote $R/report.md"
ls "$R"
