#!/usr/bin/env bash
# The measurements of docs/online.md: `seqtopo map --online` on the bundled corridor, on Nordland summer + winter
# (3,600 frames) and on synthetic routes of 3,600 and 10^5 descriptors (`seqtopo bench scale --write-route`):
# online and offline loop-closure F1, revisit detection delay, per-frame time (median, 99th percentile) and peak
# memory. A benchmark, not a test: it prints what it measured.
# Usage: bench/online.sh BUILD_DIR [NORDLAND_DIR]   (BUILD_DIR: a Release build)
set -euo pipefail
build=${1:?usage: bench/online.sh BUILD_DIR [NORDLAND_DIR]}
here=$(cd "$(dirname "$0")" && pwd)
nordland=${2:-$here/../../shared/data/nordland-64x32}
out=${OUT:-online-out}
mkdir -p "$out"
seqtopo="$build/src/seqtopo"
corridor="$here/../data/rtabmap-corridor"

report() {  # name folder: the online.json figures and the peak memory of the run
  python3 - "$1" "$2/online.json" "$2.time" <<'PY'
import json, re, sys
name, summary, timing = sys.argv[1:4]
s = json.load(open(summary))
rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(timing).read())
line = f"{name}: {s['frames']} frames, per frame median {1e3 * s['frame_seconds']['median']:.2f} ms, " \
       f"p99 {1e3 * s['frame_seconds']['p99']:.2f} ms, max {1e3 * s['frame_seconds']['max']:.2f} ms"
if rss:
    line += f", peak memory {int(rss.group(1)) / 1024:.0f} MB"
if "metrics" in s:
    m = s["metrics"]
    line += f"; online P {m['precision']:.3f} R {m['recall']:.3f} F1 {m['f1']:.3f}"
if "offline_metrics" in s:
    line += f"; offline F1 {s['offline_metrics']['f1']:.3f}"
print(line)
PY
}

run() {  # name folder args...
  local name=$1 dir=$2
  shift 2
  /usr/bin/time -v "$seqtopo" map "$@" --online --out "$dir" > "$dir.events.txt" 2> "$dir.time"
  report "$name" "$dir"
}

run corridor "$out/corridor" "$corridor" --ground-truth "$corridor/ground_truth.bmp"
python3 "$here/online_agreement.py" "$out/corridor"

# Nordland summer then winter as one folder of 3,600 frames (as bench/scale.sh); frame k of either season at (k mod 1800, 0).
. "$(dirname "$0")/nordland_folder.sh"
nordland_folder "$nordland" "$out/nordland"
frames="$out/nordland/frames"
run nordland "$out/nordland/map" "$frames" --ground-truth "$out/nordland/poses.csv" --gt-radius 2
python3 "$here/online_agreement.py" "$out/nordland/map"
python3 "$here/online_delay.py" "$out/nordland/map/events.jsonl" "$out/nordland/poses.csv" 2 10

for n in 3600 100000; do
  route="$out/route$n"
  rm -rf "$route"
  "$seqtopo" bench scale --sizes $n --write-route "$route" 2> /dev/null
  run "synthetic $n" "$out/synthetic$n" "$route/descriptors.npy" --no-offline-outputs --ground-truth "$route/poses.csv" \
    --gt-radius 2
  python3 "$here/online_delay.py" "$out/synthetic$n/events.jsonl" "$route/poses.csv" 2 10
done
