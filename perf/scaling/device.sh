#!/bin/bash
# Thread scaling on a lent many-core machine (issue 5), in two steps:
#   perf/scaling/device.sh pack [OLD]  here: copies build/epsray (and OLD, another build to
#                                 compare with, as .dev/epsray0), their shared libraries
#                                 (glibc too: the other machine's may differ) and two SPD
#                                 scenes into .dev/ (add /.dev/ to .git/info/exclude; carry it)
#   perf/scaling/device.sh run    there: where a frame's time goes at all threads
#                                 (sched_ab.py: rows per tile, tile orders, OLD), then the
#                                 scaling sweep; results under $OUT
#   perf/scaling/device.sh pipeline there: full mode at N workers against --pipeline at N
#                                 and N-1 workers (the reprojection thread makes N), then
#                                 the machine's own ceiling (N one-thread base walks at
#                                 once against one alone), then the scaling sweep, 3 reps
#   perf/scaling/device.sh ceiling there: base and full on all threads as a share of the
#                                 machine's own limit, N one-thread walks at once
#                                 (perf/scaling/ceiling.py, 2 reps); results under $OUT
#   perf/scaling/device.sh extras there: N one-thread walks at once against one alone,
#                                 thread time on 1 and N threads, the art-room walk at all
#                                 threads, and the reprojection methods at N and N-1 threads
set -euo pipefail
cd "$(dirname "$0")/../.."
E=.dev/epsray SIZE=${SIZE:-640x480}  # SIZE=96x72 for a dry run here
# K one-thread walks of the art-room orbit at once in MODE: the median of the processes'
# median frame ms, and their spread (what the machine itself loses with all cores busy).
at_once() {
  python3 -c "import sys; sys.path.insert(0,'perf'); from common import orbit_path; orbit_path('scenes/artroom.nff', 16, '/tmp/orbit.path')"
  rm -f /tmp/c*.json
  for i in $(seq "$2"); do $E walk scenes/artroom.nff --path /tmp/orbit.path --mode "$1" --size "$SIZE" --threads 1 --quiet --stats /tmp/c$i.json & done; wait
  python3 -c "
import json,statistics as st,sys
m=[st.median(f['ms'] for f in json.load(open(p))['frames'][1:]) for p in sys.argv[2:]]
print('%s, %d one-thread walks at once: median of per-process median frame ms %.1f (min %.1f max %.1f)' % (sys.argv[1], len(m), st.median(m), min(m), max(m)))" "$1" /tmp/c*.json
}
# The scaling sweep over 1..N threads with REPS repetitions: sweep N REPS.
sweep() {
  python3 perf/scaling/bench.py --exe $E --threads 1,2,4,8,12,$1 --frames 16 --reps "$2" --size "$SIZE" \
    --out "$OUT/scaling.md" scenes/artroom.nff .dev/spd/balls-s3.nff .dev/spd/teapot-s6.nff | tee "$OUT/scaling.log"
}
case "${1:-}" in
pack)
  rm -rf .dev && mkdir -p .dev/lib .dev/spd
  cp build/epsray .dev/epsray.bin
  if [ -n "${2:-}" ]; then
    cp "$2" .dev/epsray0.bin
    printf '%s\n' '#!/bin/sh' 'd=$(cd "$(dirname "$0")" && pwd)' \
      'exec "$d/lib/ld-linux-x86-64.so.2" --library-path "$d/lib" "$d/epsray0.bin" "$@"' > .dev/epsray0
    chmod +x .dev/epsray0
  fi
  for l in $(ldd build/epsray | awk '/=>/{print $3}') /lib64/ld-linux-x86-64.so.2; do cp -L "$l" .dev/lib/; done
  cp ../shared/scenes/spd/balls-s3.nff ../shared/scenes/spd/teapot-s6.nff .dev/spd/
  printf '%s\n' '#!/bin/sh' 'd=$(cd "$(dirname "$0")" && pwd)' \
    'exec "$d/lib/ld-linux-x86-64.so.2" --library-path "$d/lib" "$d/epsray.bin" "$@"' > .dev/epsray
  chmod +x .dev/epsray && .dev/epsray info ;;
run)
  export PYTHONUNBUFFERED=1
  n=$(nproc)
  { $E info; grep -H . /sys/kernel/mm/transparent_hugepage/{enabled,defrag}; } | tee "$OUT/info.log"
  v=(--variant rows1=$E,--tile-rows,1 --variant rows2=$E,--tile-rows,2 --variant default=$E
     --variant rows4=$E,--tile-rows,4 --variant rows6=$E,--tile-rows,6 --variant rows8=$E,--tile-rows,8
     --variant scan=$E,--tile-order,scan)
  [ -x .dev/epsray0 ] && v=(--variant old=.dev/epsray0 "${v[@]}")
  python3 perf/scaling/sched_ab.py --threads "$n" --reps 3 "${v[@]}" --out "$OUT/sched$n.md" | tail -12
  sweep "$n" 2 ;;
pipeline)
  export PYTHONUNBUFFERED=1
  n=$(nproc)
  $E info | tee "$OUT/info.log"
  python3 perf/scaling/sched_ab.py --threads "$n" --reps 3 --size "$SIZE" --modes full --variant default=$E \
    --variant pipeline=$E,--pipeline --variant pipeline-1=$E,--pipeline,--threads,$((n - 1)) --out "$OUT/pipeline$n.md" | tail -5
  for k in 1 "$n" 1; do at_once base "$k"; done | tee "$OUT/ceiling.log"
  sweep "$n" 3 ;;
ceiling)
  export PYTHONUNBUFFERED=1
  python3 perf/scaling/ceiling.py --exe $E --spd .dev/spd --reps 2 --out "$OUT/ceiling.md" ;;
extras)
  export PYTHONUNBUFFERED=1
  n=$(nproc)
  $E info | tee "$OUT/concurrent.log"
  for mode in base full; do for k in 1 $((n / 2)) $n 1; do at_once $mode "$k"; done; done | tee -a "$OUT/concurrent.log"
  for mode in base full; do for t in 1 "$n"; do
    $E walk scenes/artroom.nff --path /tmp/orbit.path --mode $mode --size "$SIZE" --threads "$t" --quiet --stats /tmp/$mode$t.json
    python3 -c "
import json,statistics as st
fr=json.load(open('/tmp/$mode$t.json'))['frames'][1:]
print('$mode $t threads: frame ms %.1f, thread time ms %.1f' % (st.median(f['ms'] for f in fr), st.median(sum(f['path_ms'].values()) for f in fr)))"
  done; done | tee -a "$OUT/concurrent.log"
  python3 perf/walk/bench.py --exe $E --threads "$n" --reps 3 --out "$OUT/walk$n.md" | tail -12
  # Pipelining pays with a core to spare: all cores shading against one left to the pipeline.
  # (Exact only: OSMesa is loaded at run time and its libLLVM is too large to carry.)
  for t in "$n" $((n - 1)); do
    python3 perf/reproject/bench.py --exe $E --threads "$t" --reps 3 --methods exact --out "$OUT/reproject$t.md" | tail -5
  done ;;
*) echo "usage: perf/scaling/device.sh pack [OLD]|run|pipeline|ceiling|extras" >&2; exit 2 ;;
esac
