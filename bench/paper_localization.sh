#!/usr/bin/env bash
# The protocol of the string-matching localization paper (González-Buesa & Campos, Section III) on the
# simulator's rooms, ground-floor and white-hall surveys and on their union (the "global environment"):
# panoramas -> fingerprints (map points = database, test points = queries) -> match-strings with
# algorithms A1, A2, B, C, printed beside the paper's Tables I and V-VII. Beyond the paper: the cyclic
# variants, queries with an unknown heading (each query string rotated by a random offset, fixed seed),
# and a sequence of three consecutive test points instead of one.
#
#   bench/paper_localization.sh [OUT_DIR]        (SEQTOPO=path/to/seqtopo, SEED=1 to override)
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
SEQTOPO=${SEQTOPO:-$here/../build/release/src/seqtopo}
SEED=${SEED:-1}
out=${1:-paper-localization-out}
command -v jq >/dev/null || { echo "paper_localization.sh: needs jq" >&2; exit 1; }
[ -x "$SEQTOPO" ] || { echo "paper_localization.sh: no seqtopo at $SEQTOPO (set SEQTOPO=...)" >&2; exit 1; }
mkdir -p "$out"

# --- data: simulate, fingerprint -------------------------------------------------------------------
for env in rooms ground-floor white-hall; do
  d=$out/$env
  mkdir -p "$d"
  "$SEQTOPO" simulate --scenario "$env" --seed "$SEED" --no-images --out "$d/sim" 2>/dev/null
  "$SEQTOPO" fingerprint "$d/sim/panoramas" --positions "$d/sim/points.csv" --role map --out "$d/db.tsv" 2>/dev/null
  "$SEQTOPO" fingerprint "$d/sim/panoramas" --positions "$d/sim/points.csv" --role test --out "$d/queries.tsv" 2>/dev/null
  cp "$d/sim/adjacency.csv" "$d/adjacency.csv"
done
# Global environment: both buildings in one database; ids prefixed, the white hall moved 1 km away so
# the closest map point of a test point is always in its own building.
g=$out/global
mkdir -p "$g"
merge() {  # merge FILE: prefix ids, shift white-hall x
  awk -F'\t' -v OFS='\t' 'FNR == 1 {p = (FILENAME ~ /white-hall/) ? "wh-" : "gf-"} /^#/ {next}
    {$1 = p $1; if (NF >= 4 && p == "wh-") $3 = $3 + 1000; if (NF >= 5) $5 = p $5; print}' \
    "$out/ground-floor/$1" "$out/white-hall/$1" > "$g/$1"
}
merge db.tsv
merge queries.tsv
{ echo "test_id,map_id"
  awk -F, 'FNR == 1 {p = (FILENAME ~ /white-hall/) ? "wh-" : "gf-"; next} {print p $1 "," p $2}' \
    "$out/ground-floor/adjacency.csv" "$out/white-hall/adjacency.csv"; } > "$g/adjacency.csv"
# Unknown heading: each query string rotated by a random offset (as if the panorama started elsewhere).
for env in rooms ground-floor white-hall global; do
  awk -F'\t' -v OFS='\t' -v seed="$SEED" 'BEGIN {srand(seed)} /^#/ {print; next}
    {n = length($2); if (n > 1) {r = int(rand() * n); $2 = substr($2, r + 1) substr($2, 1, r)} print}' \
    "$out/$env/queries.tsv" > "$out/$env/queries-turned.tsv"
done

# --- runs -------------------------------------------------------------------------------------------
a2_preset() { case $1 in rooms) echo A2-rooms ;; ground-floor) echo A2-ground-floor ;; white-hall) echo A2-white-hall ;; *) echo A2-global ;; esac; }
algo_args() {  # algo_args ENV ALG
  case $2 in A1) echo "--algorithm A --preset A1" ;; A2) echo "--algorithm A --preset $(a2_preset "$1")" ;; *) echo "--algorithm $2" ;; esac
}
run() {  # run ENV VARIANT ALG [extra args]; writes OUT/ENV/VARIANT-ALG/metrics.json
  local env=$1 variant=$2 alg=$3
  shift 3
  local queries=$out/$env/queries.tsv
  case $variant in turned*) queries=$out/$env/queries-turned.tsv ;; esac
  # shellcheck disable=SC2046
  "$SEQTOPO" match-strings --db "$out/$env/db.tsv" --queries "$queries" --adjacency "$out/$env/adjacency.csv" \
    $(algo_args "$env" "$alg") "$@" --out "$out/$env/$variant-$alg" >/dev/null 2>&1
}
for env in rooms ground-floor white-hall global; do
  for alg in A1 A2 B C; do
    run "$env" paper "$alg"
    run "$env" cyclic "$alg" --cyclic
    run "$env" turned "$alg"
    run "$env" turned-cyclic "$alg" --cyclic
    run "$env" sequence "$alg" --window 3
  done
done

# --- tables -----------------------------------------------------------------------------------------
pct() { jq -r ".$2.$3_percent // empty" "$1" | awk '{printf "%5.1f", $1}'; }
declare -A paper
paper[rooms]="83.3 93.3 73.3 80 | 96.7 96.7 90 90 | 3.3 3.3 10 10"
paper[ground-floor]="68.2 90.9 54.5 50 | 95.5 90.9 72.7 81.8 | 4.5 9.1 27.3 18.2 | 52.3 85.0 37.5 38.9 | 71.4 85.0 75.0 83.3 | 28.6 15.0 25.0 16.7"
paper[white-hall]="61.1 77.8 61.1 38.9 | 83.3 88.9 77.8 77.8 | 16.7 11.1 22.2 22.2 | 60.0 75.0 50.0 35.7 | 73.3 87.5 78.6 71.4 | 26.7 12.5 21.4 28.6"
paper[global]="60.0 75.0 50.0 35.0 | 85.0 77.5 75.0 70.0 | 15.0 22.5 25.0 30.0 | 47.1 83.9 43.3 39.3 | 70.6 87.1 80.0 85.7 | 29.4 12.9 20.0 14.3"
declare -A title
title[rooms]="Table I - rooms test (10 map points, 30 test points)"
title[ground-floor]="Table V - ground floor test (21 map points, 22 test points)"
title[white-hall]="Table VI - white hall test (15 map points, 18 test points)"
title[global]="Table VII - global environment test (36 map points, 40 test points)"

rows() {  # rows ENV: the metric rows of the environment's table
  if [ "$1" = rooms ]; then
    echo "Exact topological exact"; echo "Correct topological correct"; echo "Wrong topological wrong"
  else
    echo "Top._exact topological exact"; echo "Top._correct topological correct"; echo "Top._wrong topological wrong"
    echo "Geom._exact geometric exact"; echo "Geom._correct geometric correct"; echo "Geom._wrong geometric wrong"
  fi
}
for env in rooms ground-floor white-hall global; do
  echo
  echo "${title[$env]}: ours (paper) [%]"
  printf '%-14s' ""; for alg in A1 A2 B C; do printf '%-17s' "Alg. $alg"; done; echo
  IFS='|' read -r -a published <<< "${paper[$env]}"
  i=0
  while read -r label kind field; do
    read -r -a p <<< "${published[$i]}"
    printf '%-14s' "${label//_/ }"
    j=0
    for alg in A1 A2 B C; do
      printf '%-17s' "$(pct "$out/$env/paper-$alg/metrics.json" "$kind" "$field") ($(printf '%5.1f' "${p[$j]}"))"
      j=$((j + 1))
    done
    echo
    i=$((i + 1))
  done < <(rows "$env")
done

echo
echo "Beyond the paper: topological exact / correct, geometric exact / correct [%]"
for env in rooms ground-floor white-hall global; do
  echo
  echo "$env"
  printf '%-26s' ""; for alg in A1 A2 B C; do printf '%-27s' "Alg. $alg"; done; echo
  for variant in paper cyclic turned turned-cyclic sequence; do
    case $variant in
      paper) label="one fingerprint" ;; cyclic) label="cyclic" ;; turned) label="unknown heading" ;;
      turned-cyclic) label="unknown heading, cyclic" ;; sequence) label="3 consecutive points" ;;
    esac
    printf '%-26s' "$label"
    for alg in A1 A2 B C; do
      f=$out/$env/$variant-$alg/metrics.json
      printf '%-27s' "$(pct "$f" topological exact)/$(pct "$f" topological correct)  $(pct "$f" geometric exact)/$(pct "$f" geometric correct)"
    done
    echo
  done
done
