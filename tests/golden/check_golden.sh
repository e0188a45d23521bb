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
fi
