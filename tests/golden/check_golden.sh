#!/usr/bin/env bash
# Golden outputs of `seqtopo map`: the bundled corridor (and Nordland summer + winter as one folder of 3,600
# frames, when ../shared/data is there) mapped with the defaults must give exactly the files whose SHA-256 sums
# are checked in beside this script. A change of the map's behaviour shows here first; when it is meant, run
# the script with --update and say why in the commit.
# Usage: tests/golden/check_golden.sh SEQTOPO_BINARY SOURCE_DIR [--update]
set -euo pipefail
bin=$1
source=$2
update=${3:-}
here="$source/tests/golden"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
files=(map.json alignments.json loop_closures.csv metrics.json scores.npy similarity.npy topology.dot)

# The topology of a map.json: places, independent cycles (edges - places + components), junctions, dead ends;
# fails unless they are the expected ones (an independent count from the edge list, not the map's own).
topology() {  # map.json, places_min, places_max, cycles, junctions_max, dead_ends
  python3 - "$@" <<'PY'
import json, sys
path, lo, hi, cycles, junctions, dead_ends = sys.argv[1], *map(int, sys.argv[2:])
m = json.load(open(path))
places, edges = len(m["places"]), m["edges"]
parent = list(range(places))
def find(x):
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x
degree = [0] * places
for p, q in edges:
    parent[find(p)] = find(q)
    degree[p] += 1
    degree[q] += 1
components = len({find(x) for x in range(places)})
got = (places, len(edges) - places + components, len(m["junctions"]), sum(d >= 3 for d in degree), degree.count(1))
print(f"golden: {path}: {got[0]} places, {got[1]} independent cycles, {got[2]} junctions, {got[4]} dead ends")
ok = lo <= got[0] <= hi and got[1] == cycles and got[2] <= junctions and got[3] <= junctions and got[4] == dead_ends
sys.exit(0 if ok else 1)
PY
}

check() {  # name, then the map command's arguments
  local name=$1
  shift
  "$bin" map "$@" --out "$tmp/$name" --threads 2 >/dev/null 2>"$tmp/$name.log" || { cat "$tmp/$name.log"; exit 1; }
  (cd "$tmp/$name" && sha256sum "${files[@]}") >"$tmp/$name.sha256"
  if [ "$update" = "--update" ]; then
    cp "$tmp/$name.sha256" "$here/$name.sha256"
    echo "golden: updated $name"
  elif ! diff -u "$here/$name.sha256" "$tmp/$name.sha256"; then
    echo "golden: $name differs from tests/golden/$name.sha256 (the lines above)"
    exit 1
  else
    echo "golden: $name identical"
  fi
}

check corridor
# The corridor is one loop gone round about 1.1 times: one cycle of about 40 places, no branch.
topology "$tmp/corridor/map.json" 38 44 1 1 0 || { echo "golden: the corridor is not one cycle"; exit 1; }
nordland="$source/../shared/data/nordland-64x32"
if [ -d "$nordland" ]; then
  mkdir -p "$tmp/frames"
  k=0
  for season in summer winter; do
    for f in $(ls "$nordland/$season" | sort); do
      ln -s "$(realpath "$nordland/$season/$f")" "$tmp/frames/$(printf %04d $k).png"
      k=$((k + 1))
    done
  done
  { echo "index,x,y,theta"; for ((k = 0; k < 3600; k++)); do echo "$k,$((k % 1800)),0,0"; done; } >"$tmp/poses.csv"
  check nordland "$tmp/frames" --ground-truth "$tmp/poses.csv" --gt-radius 2
  # One path seen twice; as one folder, summer's last frame and winter's first are joined (one invented cycle).
  topology "$tmp/nordland/map.json" 1780 1820 1 0 0 || { echo "golden: Nordland is not one path seen twice"; exit 1; }
fi
