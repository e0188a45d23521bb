#!/usr/bin/env bash
# Installs what running needs (scripts/setup.sh, no test tools), builds the command line and runs the main job on
# the bundled corridor data. Extra arguments are passed to `seqtopo map`. The report lands in seqtopo-out/report.html.
# The build folder is build/run (the `run` preset: no tests, benchmarks, Python module or MPI), or build/release
# when scripts/test.sh has configured it already, so that a developer's tree is not built twice.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
preset=run
[ -f build/release/CMakeCache.txt ] && preset=release
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" --target seqtopo
exec "build/$preset/src/seqtopo" map "$@"
