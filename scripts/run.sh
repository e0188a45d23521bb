#!/usr/bin/env bash
# Installs the dependencies, builds seqtopo and runs the main job on the bundled corridor data.
# Extra arguments are passed to `seqtopo map`. The report lands in seqtopo-out/report.html.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target seqtopo
exec build/release/src/seqtopo map "$@"
