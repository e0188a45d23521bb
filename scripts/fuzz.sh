#!/usr/bin/env bash
# Fuzzes seqtopo's readers with libFuzzer: the harnesses of tests/fuzz/ (npy, CSV, odometry CSV, places CSV,
# FASTA, strings files, --config files), built with Debian's clang under AddressSanitizer and
# UndefinedBehaviorSanitizer in build/fuzz, started from the seed corpus of tests/fuzz/make_corpus.py.
#
#   scripts/fuzz.sh [SECONDS_EACH]   # each harness for SECONDS_EACH seconds (default 20; CI smoke-runs 10)
#   scripts/fuzz.sh 300              # the longer run
#
# Prints one line per harness (executions, result) and exits non-zero when any harness reports a crash, a
# leak, undefined behaviour, a timeout (an input taking over 10 s) or running out of memory; the input that
# did it is kept in build/fuzz/artifacts/<harness>/ and the log in build/fuzz/logs/<harness>.log. Reproduce
# with `build/fuzz/fuzz_<harness> build/fuzz/artifacts/<harness>/crash-...`. Inputs that reached new code stay
# in build/fuzz/corpus/<harness>/ and are used by the next run.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-20}
if ! [[ "$seconds" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: scripts/fuzz.sh [SECONDS_EACH]" >&2
  exit 2
fi
start=$SECONDS
build=build/fuzz
harnesses=(npy csv odometry_csv places_csv fasta strings_file config_file png_jpeg)

generator=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
cmake -S tests/fuzz -B "$build" -DCMAKE_CXX_COMPILER="${FUZZ_CXX:-clang++}" "${generator[@]}" >/dev/null
cmake --build "$build" -j"${FUZZ_JOBS:-2}" >/dev/null
rm -rf "$build/seeds" "$build/artifacts" "$build/logs"
python3 tests/fuzz/make_corpus.py "$build/seeds"
mkdir -p "$build/logs"

export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
failed=()
for h in "${harnesses[@]}"; do
  mkdir -p "$build/corpus/$h" "$build/artifacts/$h"
  log=$build/logs/$h.log
  status=0
  "$build/fuzz_$h" "$build/corpus/$h" "$build/seeds/$h" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/artifacts/$h/" >"$log" 2>&1 || status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  result=ok
  if [ "$status" -ne 0 ]; then
    result="FAILED (exit $status): $(grep -m 1 -E 'ERROR:|runtime error:|==[0-9]+==' "$log" || tail -n 1 "$log")"
  elif grep -q -E 'runtime error:|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)' "$log"; then
    result="FAILED: $(grep -m 1 -E 'runtime error:|ERROR: ' "$log")"
  fi
  [ "$result" = ok ] || failed+=("$h")
  printf 'fuzz %-13s %10s executions in %s s: %s\n' "$h" "${runs:-?}" "$seconds" "$result"
done

elapsed=$((SECONDS - start))
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: ${#failed[@]} of ${#harnesses[@]} harnesses failed (${failed[*]}); logs in $build/logs, inputs in $build/artifacts ($elapsed s)" >&2
  exit 1
fi
echo "fuzz: all ${#harnesses[@]} harnesses ok ($elapsed s)"
