#!/usr/bin/env bash
# Simulated worlds with ground truth, mapped and scored: `seqtopo simulate` then `seqtopo map` for every
# mapping scenario, and one table of loop-closure, topology and metric accuracy from the metrics.json files.
#
#   bench/worlds.sh [OUT_DIR]            # default build/worlds; seeds 1 to 5
#   SEQTOPO=path/to/seqtopo SEEDS="3" SCENARIOS="figure-eight zigzag" MAP_ARGS="--preset paper" \
#     SIM_ARGS="--lighting-change 0" bench/worlds.sh
# One row per seed and scenario, then the mean and the worst case of each scenario over the seeds (worst: the
# lowest F1 and ARI, the most missed and spurious junctions, the most false closures). MAP_ARGS is empty by
# default: `seqtopo map` sees 360-degree panoramas and chooses its descriptors for them. REUSE_SIM=1 keeps
# worlds already simulated in OUT_DIR (the simulator is deterministic per seed).
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$here/build/worlds}"
seqtopo="${SEQTOPO:-$(ls -t "$here"/build/*/src/seqtopo 2>/dev/null | head -1)}"
seeds="${SEEDS:-${SEED:-1 2 3 4 5}}"
scenarios="${SCENARIOS:-figure-eight corridor-reverse nested-loops zigzag aliasing}"
map_args="${MAP_ARGS:-}"
sim_args="${SIM_ARGS:-}"
[[ -x "$seqtopo" ]] || { echo "worlds.sh: no seqtopo binary (set SEQTOPO)" >&2; exit 1; }
mkdir -p "$out"

for seed in $seeds; do
  for s in $scenarios; do
    sim="$out/seed$seed/$s/sim"
    map="$out/seed$seed/$s/map"
    echo "== seed $seed: $s" >&2
    if [[ "${REUSE_SIM:-0}" != 1 || ! -f "$sim/simulation.json" ]]; then
      # shellcheck disable=SC2086
      "$seqtopo" simulate --scenario "$s" --seed "$seed" --no-images --out "$sim" $sim_args
    fi
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$seqtopo" map "$sim/panoramas" --out "$map" --odometry "$sim/odometry.csv" \
      --ground-truth "$sim/ground_truth.png" --gt-places "$sim/places.csv" --gt-poses "$sim/poses.csv" $map_args
    python3 -c 'import sys,time; print(f"{float(sys.argv[2]) - float(sys.argv[1]):.1f}")' "$start" "$(date +%s.%N)" \
      > "$out/seed$seed/$s/map_seconds.txt"
  done
done

python3 - "$out" "$seeds" $scenarios <<'PY'
import json, sys, os
out, seeds, names = sys.argv[1], sys.argv[2].split(), sys.argv[3:]
head = ["seed", "scenario", "frames", "tp/fp/fn", "precision", "recall", "F1", "AUC", "R@100P", "SeqSLAM F1",
        "ARI", "false/missed merges", "junctions t/f/m", "spurious", "vetoed", "ATE odo", "ATE ekf", "ATE pg", "map s"]
def f(v, d=3):
    return "-" if v is None else (f"{v:.{d}f}" if isinstance(v, float) else str(v))
def load(path):
    return json.load(open(path)) if os.path.exists(path) else {}
def table(head, rows):
    cells = [head] + [[f(v) for v in r] for r in rows]
    widths = [max(len(c[i]) for c in cells) for i in range(len(head))]
    print("| " + " | ".join(h.ljust(w) for h, w in zip(head, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for c in cells[1:]:
        print("| " + " | ".join(v.ljust(w) for v, w in zip(c, widths)) + " |")
rows, per = [], {s: [] for s in names}
for seed in seeds:
    for s in names:
        base_dir = os.path.join(out, f"seed{seed}", s)
        sim = load(os.path.join(base_dir, "sim", "simulation.json"))
        m = load(os.path.join(base_dir, "map", "metrics.json"))
        lc, topo, met, base = m.get("loop_closure", {}), m.get("topology", {}), m.get("metric", {}), m.get("baseline", {})
        vetoed = len(load(os.path.join(base_dir, "map", "alignments.json")).get("rejected_by_odometry", []))
        spath = os.path.join(base_dir, "map_seconds.txt")
        secs = open(spath).read().strip() if os.path.exists(spath) else "-"
        jt, jf, jm = (topo.get(k) for k in ("junctions_true", "junctions_found", "junctions_matched"))
        spurious = None if jf is None or jm is None else max(0, jf - jm)
        per[s].append({"f1": lc.get("f1"), "ari": topo.get("adjusted_rand_index"), "missed": None if jt is None else jt - jm,
                       "spurious": spurious, "fp": lc.get("fp")})
        rows.append([seed, s, sim.get("frames"), "/".join(f(lc.get(k)) for k in ("tp", "fp", "fn")), lc.get("precision"),
                     lc.get("recall"), lc.get("f1"), lc.get("auc"), lc.get("recall_at_100_precision"), base.get("f1"),
                     topo.get("adjusted_rand_index"), "/".join(f(topo.get(k)) for k in ("false_merges", "missed_merges")),
                     "/".join(f(v) for v in (jt, jf, jm)), spurious, vetoed, met.get("ate_odometry"), met.get("ate_ekf"),
                     met.get("ate_pose_graph"), secs])
table(head, rows)
print()
summary = []
for s in names:
    v = per[s]
    def values(key):
        return [x[key] for x in v if x[key] is not None]
    def mean(key):
        xs = values(key)
        return sum(xs) / len(xs) if xs else None
    def worst(key, low):
        xs = values(key)
        return (min(xs) if low else max(xs)) if xs else None
    summary.append([s, len(v), mean("f1"), worst("f1", True), mean("ari"), worst("ari", True), worst("missed", False),
                    mean("spurious"), worst("spurious", False), worst("fp", False)])
table(["scenario", "seeds", "F1 mean", "F1 worst", "ARI mean", "ARI worst", "junctions missed (worst)",
       "spurious junctions mean", "spurious (worst)", "false closures (worst)"], summary)
PY
