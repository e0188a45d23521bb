#!/usr/bin/env bash
# Installs the dependencies, builds seqtopo and runs the main job on the bundled corridor data.
# Extra arguments are passed to `seqtopo map`. The report lands in seqtopo-out/report.html.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target seqtopo
exec build/release/src/seqtopo align --a data/examples/walk_a.fa --b data/examples/walk_b.fa --match 2 --mismatch -1 --gap 1 --max-alignments 5 "$@"
