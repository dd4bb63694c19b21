#!/usr/bin/env bash
# Side-by-side timing of epsray's base Whitted tracer against Tachyon.
#
#   perf/tachyon/compare.sh [options] [SCENE ...]
#
# SCENE: a name in the scene directory (balls-s3) or a path to an .nff file;
# default: every *.nff of the scene directory.
#
# Options:
#   -d DIR     scene directory (default: <repo>/../shared/scenes/spd)
#   -s WxH     image size for both renderers (default 512x512)
#   -t N       threads for both renderers (default: nproc)
#   -r R       timed repetitions per renderer and scene (default 3)
#   -w N       untimed warm-up runs per renderer and scene (default 1)
#   -o FILE    Markdown output (default: <repo>/perf/results/tachyon.md);
#              the raw runs go next to it as tachyon-runs.csv
#   -k DIR     keep the converted scenes and the images in DIR
#   --spec M   Tachyon highlight model: blinn (default; N.H as whitted.md)
#              or phong (R.V, -shade_phong; same cost)
#   --epsray P, --tachyon P   the executables (default build/epsray and
#              tachyon from PATH)
#
# Each scene is converted once with nff2tachyon.py at the chosen size, then
# the two renderers run interleaved (the order alternates between
# repetitions): epsray `render SCENE --mode base --size S --threads T --png
# OUT --stats OUT.json`, Tachyon `-res W H -numthreads T -aasamples 0
# -raydepth 5 -fullshade -shade_blinn -o OUT.png -format PNG`. Both write a
# PNG so both pay for one image encode. Recorded per run: the wall time of
# the whole process (bash $EPOCHREALTIME around it), epsray's stats
# total_ms and frames[0].ms, Tachyon's self-reported parse, preprocessing
# (acceleration structure) and ray tracing times. The table gives medians.
#
# "internal" ratio = Tachyon (preprocessing + ray tracing) / epsray
# total_ms (contract.md: the whole run without start-up and file writing;
# it includes epsray's BVH build, as Tachyon's preprocessing is its grid
# build). "wall" ratio = whole-process wall times, which include parsing
# (Tachyon parses the converted .dat, epsray the .nff) and the PNG encode.
set -u -o pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

scene_dir="$root/../shared/scenes/spd"
size=512x512
threads=$(nproc)
reps=3
warmup=1
out_md="$root/perf/results/tachyon.md"
keep=""
spec=blinn
epsray="$root/build/epsray"
tachyon=$(command -v tachyon || echo /usr/bin/tachyon)
scenes=()

die() { echo "compare.sh: $*" >&2; exit 2; }

while [ $# -gt 0 ]; do
  case "$1" in
    -d) scene_dir=$2; shift 2 ;;
    -s) size=$2; shift 2 ;;
    -t) threads=$2; shift 2 ;;
    -r) reps=$2; shift 2 ;;
    -w) warmup=$2; shift 2 ;;
    -o) out_md=$2; shift 2 ;;
    -k) keep=$2; shift 2 ;;
    --spec) spec=$2; shift 2 ;;
    --epsray) epsray=$2; shift 2 ;;
    --tachyon) tachyon=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) die "unknown option $1 (try --help)" ;;
    *) scenes+=("$1"); shift ;;
  esac
done

[[ $size =~ ^([0-9]+)x([0-9]+)$ ]] || die "size must be WxH, got '$size'"
W=${BASH_REMATCH[1]}; H=${BASH_REMATCH[2]}
[[ $threads =~ ^[1-9][0-9]*$ ]] || die "bad thread count '$threads'"
[[ $reps =~ ^[1-9][0-9]*$ ]] || die "bad repetition count '$reps'"
[[ $warmup =~ ^[0-9]+$ ]] || die "bad warm-up count '$warmup'"
case "$spec" in blinn|phong) ;; *) die "--spec must be blinn or phong" ;; esac

if [ ! -x "$tachyon" ]; then
  die "tachyon not found (apt-get install tachyon)"
fi
have_epsray=1
if [ ! -x "$epsray" ]; then
  echo "compare.sh: $epsray not built; timing Tachyon only" >&2
  have_epsray=0
fi

# the scene list
if [ ${#scenes[@]} -eq 0 ]; then
  if [ ! -d "$scene_dir" ]; then
    echo "compare.sh: scene directory $scene_dir not found; nothing to do" >&2
    exit 0
  fi
  shopt -s nullglob
  scenes=("$scene_dir"/*.nff)
  shopt -u nullglob
  if [ ${#scenes[@]} -eq 0 ]; then
    echo "compare.sh: no .nff files in $scene_dir; nothing to do" >&2
    exit 0
  fi
else
  for i in "${!scenes[@]}"; do
    s=${scenes[$i]}
    if [ ! -f "$s" ]; then
      if [ -f "$scene_dir/$s.nff" ]; then s="$scene_dir/$s.nff"
      elif [ -f "$scene_dir/$s" ]; then s="$scene_dir/$s"
      else die "scene $s not found (looked in $scene_dir)"; fi
    fi
    scenes[$i]=$s
  done
fi

work=$(mktemp -d /tmp/epsray-tachyon.XXXXXX)
cleanup() { rm -rf "$work"; }
trap cleanup EXIT
if [ -n "$keep" ]; then mkdir -p "$keep" || die "cannot create $keep"; fi
mkdir -p "$(dirname "$out_md")" || die "cannot create $(dirname "$out_md")"
runs_csv="$(dirname "$out_md")/tachyon-runs.csv"

now() {
  if [ -n "${EPOCHREALTIME:-}" ]; then echo "${EPOCHREALTIME/,/.}"
  else date +%s.%N; fi
}

tflags=(-res "$W" "$H" -numthreads "$threads" -aasamples 0 -raydepth 5
        -fullshade "-shade_$spec")

# run_epsray NFF PNG JSON LOG -> prints "wall total_ms frame_ms" or "fail"
run_epsray() {
  local t0 t1 rc
  t0=$(now)
  "$epsray" render "$1" --mode base --size "$size" --threads "$threads" \
    --png "$2" --stats "$3" >"$4" 2>&1
  rc=$?
  t1=$(now)
  if [ $rc -ne 0 ]; then echo fail; return; fi
  python3 - "$3" "$t0" "$t1" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
wall = float(sys.argv[3]) - float(sys.argv[2])
print("%.6f %.3f %.3f" % (wall, d["total_ms"], d["frames"][0]["ms"]))
EOF
}

# run_tachyon DAT PNG LOG -> prints "wall parse_s preproc_s trace_s" or "fail"
run_tachyon() {
  local t0 t1 rc
  t0=$(now)
  "$tachyon" "$1" "${tflags[@]}" -o "$2" -format PNG >"$3" 2>&1
  rc=$?
  t1=$(now)
  if [ $rc -ne 0 ] || grep -qiE 'parse error|aborting|syntax error' "$3" \
     || [ ! -s "$2" ]; then
    echo fail; return
  fi
  awk -v t0="$t0" -v t1="$t1" '
    /Scene Parsing Time:/  { parse = $4 }
    /Preprocessing Time:/  { pre = $3 }
    /Ray Tracing Time:/    { trace = $4 }
    END { printf "%.6f %s %s %s\n", t1 - t0, parse, pre, trace }' "$3"
}

# warn if the executable is rebuilt while we time it
epsray_stamp() { stat -c '%Y %s' "$epsray" 2>/dev/null; }
stamp0=$(epsray_stamp)
load0=$(cut -d' ' -f1 /proc/loadavg)

echo "scene,nff_primitives,tachyon_objects,rep,renderer,wall_s,epsray_total_ms,epsray_frame_ms,tachyon_parse_s,tachyon_preproc_s,tachyon_trace_s" >"$runs_csv"

for nff in "${scenes[@]}"; do
  name=$(basename "$nff" .nff)
  dat="$work/$name.dat"
  if ! python3 "$here/nff2tachyon.py" "$nff" --size "$size" -o "$dat" 2>"$work/conv.log"; then
    echo "compare.sh: $name: conversion failed: $(cat "$work/conv.log")" >&2
    continue
  fi
  prims=$(awk '/^# nff_primitives/ { print $3; exit }' "$dat")
  tobjs=$(awk '/^# tachyon_objects/ { print $3; exit }' "$dat")
  epng="$work/$name.epsray.png"; tpng="$work/$name.tachyon.png"
  ejson="$work/$name.json"

  for ((i = 0; i < warmup; i++)); do
    [ $have_epsray = 1 ] && run_epsray "$nff" "$epng" "$ejson" "$work/e.log" >/dev/null
    run_tachyon "$dat" "$tpng" "$work/t.log" >/dev/null
  done

  printf '%-14s' "$name" >&2
  for ((r = 1; r <= reps; r++)); do
    # alternate the order so neither renderer always runs on a "warm" or
    # "tired" machine
    if (( r % 2 )); then order="e t"; else order="t e"; fi
    for who in $order; do
      if [ "$who" = e ]; then
        [ $have_epsray = 1 ] || continue
        res=$(run_epsray "$nff" "$epng" "$ejson" "$work/e.log")
        if [ "$res" = fail ]; then
          echo "compare.sh: $name: epsray failed: $(tail -n 3 "$work/e.log")" >&2
          echo "$name,$prims,$tobjs,$r,epsray,fail,,,,," >>"$runs_csv"
          continue
        fi
        read -r wall tot fr <<<"$res"
        echo "$name,$prims,$tobjs,$r,epsray,$wall,$tot,$fr,,," >>"$runs_csv"
        printf ' e%.3f' "$wall" >&2
      else
        res=$(run_tachyon "$dat" "$tpng" "$work/t.log")
        if [ "$res" = fail ]; then
          echo "compare.sh: $name: tachyon failed: $(tail -n 5 "$work/t.log")" >&2
          echo "$name,$prims,$tobjs,$r,tachyon,fail,,,,," >>"$runs_csv"
          continue
        fi
        read -r wall tp tpre ttr <<<"$res"
        echo "$name,$prims,$tobjs,$r,tachyon,$wall,,,$tp,$tpre,$ttr" >>"$runs_csv"
        printf ' t%.3f' "$wall" >&2
      fi
    done
  done
  echo >&2
  if [ -n "$keep" ]; then
    cp "$dat" "$keep/" 2>/dev/null
    [ -f "$epng" ] && cp "$epng" "$keep/"
    [ -f "$tpng" ] && cp "$tpng" "$keep/"
  fi
done

if [ $have_epsray = 1 ] && [ "$(epsray_stamp)" != "$stamp0" ]; then
  echo "compare.sh: WARNING: $epsray changed during the run; rerun for clean numbers" >&2
  rebuilt=" (WARNING: the executable was rebuilt during the run)"
else
  rebuilt=""
fi

cpu=$(awk -F': *' '/^model name/ { print $2; exit }' /proc/cpuinfo)
tpkg=$(dpkg-query -W -f '${Version}' tachyon 2>/dev/null || echo "?")
erev=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "uncommitted")
if [ -n "$(git -C "$root" status --porcelain -- engine sched cli 2>/dev/null)" ]; then
  erev="$erev+dirty"
fi

python3 - "$runs_csv" "$out_md" <<EOF
import csv, statistics, sys
runs = list(csv.DictReader(open(sys.argv[1])))
order, rows = [], {}
for r in runs:
    if r["scene"] not in rows:
        order.append(r["scene"])
        rows[r["scene"]] = {"prims": r["nff_primitives"],
                            "tobjs": r["tachyon_objects"],
                            "e": [], "et": [], "t": [], "tt": []}
    d = rows[r["scene"]]
    if r["wall_s"] == "fail":
        continue
    if r["renderer"] == "epsray":
        d["e"].append(float(r["wall_s"]))
        d["et"].append(float(r["epsray_total_ms"]) / 1000.0)
    else:
        d["t"].append(float(r["wall_s"]))
        d["tt"].append(float(r["tachyon_preproc_s"]) + float(r["tachyon_trace_s"]))

med = lambda v: statistics.median(v) if v else None
f3 = lambda x: "n/a" if x is None else "%.3f" % x
f2 = lambda x: "n/a" if x is None else "%.2f" % x

lines = []
lines.append("# epsray (base) vs Tachyon")
lines.append("")
lines.append("Machine: $(nproc) hardware threads, $cpu; threads used: $threads; "
             "1-min load average before the run: $load0 (other work on the machine skews the times).  ")
lines.append("Image $size, one sample per pixel, ray depth 5; median of $reps "
             "interleaved runs each (after $warmup warm-up).  ")
lines.append("epsray $erev (\`render --mode base\`)$rebuilt; Tachyon $tpkg (Debian), "
             "\`-aasamples 0 -raydepth 5 -fullshade -shade_$spec\`, "
             "scenes converted by perf/tachyon/nff2tachyon.py.  ")
lines.append("wall: whole process (parse, build, render, PNG write); internal: "
             "epsray stats total_ms vs Tachyon preprocessing + ray tracing.  ")
lines.append("ratio > 1: epsray is faster.")
lines.append("")
lines.append("| scene | primitives | Tachyon objects | epsray wall s | epsray internal s "
             "| Tachyon wall s | Tachyon internal s | Tachyon/epsray wall "
             "| Tachyon/epsray internal |")
lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
rw, ri = [], []
for s in order:
    d = rows[s]
    e, et, t, tt = med(d["e"]), med(d["et"]), med(d["t"]), med(d["tt"])
    q = t / e if e and t else None
    qi = tt / et if et and tt else None
    if q is not None: rw.append(q)
    if qi is not None: ri.append(qi)
    lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |"
                 % (s, d["prims"], d["tobjs"], f3(e), f3(et), f3(t), f3(tt),
                    f2(q), f2(qi)))
lines.append("| **median ratio** | | | | | | | **%s** | **%s** |"
             % (f2(med(rw)), f2(med(ri))))
lines.append("")
text = "\n".join(lines)
print(text)
open(sys.argv[2], "w").write(text)
EOF
echo "wrote $out_md and $runs_csv" >&2
