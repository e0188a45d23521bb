#!/usr/bin/env bash
# The measurements of BENCHMARK.md ("Mapping at scale" and "Sparse versus exact on Nordland").
# Usage: bench/scale.sh BUILD_DIR [NORDLAND_DIR]   (BUILD_DIR: a Release build with the benchmarks)
set -euo pipefail
build=${1:?usage: bench/scale.sh BUILD_DIR [NORDLAND_DIR]}
nordland=${2:-$(dirname "$0")/../../shared/data/nordland-64x32}
out=${OUT:-scale-out}
mkdir -p "$out"
seqtopo="$build/src/seqtopo"

"$seqtopo" bench scale --sizes 1000,3000,10000 --sparse-sizes 0 --threads 2 --out "$out/dense.json"
"$seqtopo" bench scale --sizes 0 --sparse-sizes 1000,10000,100000,1000000 --threads 2 --out "$out/sparse.json"
# Minutes on two free cores.
"$seqtopo" bench scale --sizes 100000 --sparse-sizes 0 --threads 2 --no-similarity-pass --out "$out/dense100k.json"

# Nordland summer then winter as one folder of 3,600 frames; frame k of either season sits at (k mod 1800, 0).
. "$(dirname "$0")/nordland_folder.sh"
nordland_folder "$nordland" "$out/nordland"
frames="$out/nordland/frames"
"$seqtopo" map "$frames" --ground-truth "$out/nordland/poses.csv" --gt-radius 2 --out "$out/nordland/map"
"$build/bench/bench_sparse_nordland" "$nordland" "$out/nordland/map/loop_closures.csv"
