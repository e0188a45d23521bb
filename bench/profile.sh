#!/usr/bin/env bash
# Where `seqtopo map` spends its time on the 3,600 Nordland frames (summer then winter in one folder): the
# stage times it prints, then perf's hottest functions (self time) and the pipeline's calls (with children).
# BENCHMARK.md ("The whole map job") keeps the result next to the before/after table.
# Usage: bench/profile.sh BUILD_DIR [NORDLAND_DIR]   (needs perf: Debian's linux-perf)
set -euo pipefail
build=${1:?usage: bench/profile.sh BUILD_DIR [NORDLAND_DIR]}
nordland=${2:-$(dirname "$0")/../../shared/data/nordland-64x32}
out=${OUT:-profile-out}
seqtopo="$build/src/seqtopo"
command -v perf >/dev/null || { echo "bench/profile.sh: perf not found (apt-get install linux-perf)" >&2; exit 1; }

. "$(dirname "$0")/nordland_folder.sh"
nordland_folder "$nordland" "$out"
frames="$out/frames"

rm -rf "$out/map"
# DWARF call graphs: the build has no frame pointers.
perf record -q --call-graph dwarf,16384 -F 499 -o "$out/perf.data" \
  "$seqtopo" map "$frames" --ground-truth "$out/poses.csv" --gt-radius 2 --out "$out/map" 2>&1 | grep -E "done in|wrote"
echo
echo "## hottest functions (self)"
perf report -i "$out/perf.data" --no-children --sort dso,symbol --stdio -g none 2>/dev/null |
  grep -E '^ +[0-9]' | head -25 | cut -c1-150
echo
echo "## seqtopo's calls (with what they call)"
perf report -i "$out/perf.data" --children --sort symbol --stdio -g none 2>/dev/null |
  grep -E '^ +[0-9].*seqtopo::' | grep -v 'cli::\|lambda\|_Function_handler\|_Invoker' | head -30 | cut -c1-150
