#!/usr/bin/env bash
# seqtopo-mpi on 1 and 2 ranks over the synthetic route of `seqtopo bench scale` (docs/scaling.md, "Spreading
# the work over a cluster"): wall time of each, the per-stage summary lines, and a byte comparison of the
# two alignments.json.
# Usage: bench/mpi.sh BUILD_DIR [N]   (BUILD_DIR: a Release build with SEQTOPO_BUILD_MPI=ON; N default 100000)
set -euo pipefail
build=${1:?usage: bench/mpi.sh BUILD_DIR [N]}
n=${2:-100000}
out=${OUT:-mpi-out}
mkdir -p "$out"
# Offline, as root if need be, no binding (two ranks on two cores), no mpirun banners.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun_args=(--oversubscribe --bind-to none --mca btl self,vader --mca pml ob1 -q)

"$build/src/seqtopo" bench scale --sizes "$n" --write-route "$out"
for np in 1 2; do
  start=$(date +%s%N)
  mpirun "${mpirun_args[@]}" -np "$np" "$build/src/seqtopo-mpi" sparse "$out/descriptors.npy" \
    --out "$out/alignments-np$np.json" </dev/null
  end=$(date +%s%N)
  echo "np $np: $(( (end - start) / 1000000 )) ms wall (mpirun included)"
done
cmp "$out/alignments-np1.json" "$out/alignments-np2.json" && echo "alignments.json: identical for 1 and 2 ranks"
