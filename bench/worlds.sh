#!/usr/bin/env bash
# Simulated worlds with ground truth, mapped and scored: `seqtopo simulate` then `seqtopo map` for every
# mapping scenario, and one table of loop-closure, topology and metric accuracy from the metrics.json files.
#
#   bench/worlds.sh [OUT_DIR]            # default build/worlds
#   SEQTOPO=path/to/seqtopo SEED=3 SCENARIOS="figure-eight zigzag" MAP_ARGS="--preset paper" \
#     SIM_ARGS="--lighting-change 0" bench/worlds.sh
# The default MAP_ARGS fuse the joint histogram with the heading-invariant panorama signature: the robot
# records 360-degree panoramas, and several scenarios revisit paths in the opposite direction.
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$here/build/worlds}"
seqtopo="${SEQTOPO:-$(ls -t "$here"/build/*/src/seqtopo 2>/dev/null | head -1)}"
seed="${SEED:-1}"
scenarios="${SCENARIOS:-figure-eight corridor-reverse nested-loops zigzag aliasing}"
map_args="${MAP_ARGS:---descriptor joint-histogram,panorama}"
sim_args="${SIM_ARGS:-}"
[[ -x "$seqtopo" ]] || { echo "worlds.sh: no seqtopo binary (set SEQTOPO)" >&2; exit 1; }
mkdir -p "$out"

for s in $scenarios; do
  sim="$out/$s/sim"
  map="$out/$s/map"
  echo "== $s" >&2
  # shellcheck disable=SC2086
  "$seqtopo" simulate --scenario "$s" --seed "$seed" --no-images --out "$sim" $sim_args
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  "$seqtopo" map "$sim/panoramas" --out "$map" --odometry "$sim/odometry.csv" \
    --ground-truth "$sim/ground_truth.png" --gt-places "$sim/places.csv" --gt-poses "$sim/poses.csv" $map_args
  python3 -c 'import sys,time; print(f"{float(sys.argv[2]) - float(sys.argv[1]):.1f}")' "$start" "$(date +%s.%N)" \
    > "$map/seconds.txt"
done

python3 - "$out" $scenarios <<'PY'
import json, sys, os
out, names = sys.argv[1], sys.argv[2:]
head = ["scenario", "frames", "tp/fp/fn", "precision", "recall", "F1", "AUC", "R@100P", "SeqSLAM F1",
        "ARI", "false/missed merges", "junctions t/f/m", "vetoed", "ATE odo", "ATE ekf", "ATE pg", "map s"]
rows = []
def f(v, d=3):
    return "-" if v is None else (f"{v:.{d}f}" if isinstance(v, float) else str(v))
for s in names:
    sim = json.load(open(os.path.join(out, s, "sim", "simulation.json")))
    path = os.path.join(out, s, "map", "metrics.json")
    m = json.load(open(path)) if os.path.exists(path) else {}
    lc, topo, met, base = m.get("loop_closure", {}), m.get("topology", {}), m.get("metric", {}), m.get("baseline", {})
    apath = os.path.join(out, s, "map", "alignments.json")
    vetoed = len(json.load(open(apath)).get("rejected_by_odometry", [])) if os.path.exists(apath) else None
    secs = open(os.path.join(out, s, "map", "seconds.txt")).read().strip() if os.path.exists(os.path.join(out, s, "map", "seconds.txt")) else "-"
    rows.append([s, sim["frames"], "/".join(f(lc.get(k)) for k in ("tp", "fp", "fn")), lc.get("precision"), lc.get("recall"), lc.get("f1"), lc.get("auc"),
                 lc.get("recall_at_100_precision"), base.get("f1"), topo.get("adjusted_rand_index"),
                 "/".join(f(topo.get(k)) for k in ("false_merges", "missed_merges")),
                 "/".join(f(topo.get(k)) for k in ("junctions_true", "junctions_found", "junctions_matched")),
                 vetoed, met.get("ate_odometry"), met.get("ate_ekf"), met.get("ate_pose_graph"), secs])
cells = [head] + [[f(v) for v in r] for r in rows]
widths = [max(len(c[i]) for c in cells) for i in range(len(head))]
print("| " + " | ".join(h.ljust(w) for h, w in zip(head, widths)) + " |")
print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
for c in cells[1:]:
    print("| " + " | ".join(v.ljust(w) for v, w in zip(c, widths)) + " |")
PY
