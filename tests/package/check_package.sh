#!/usr/bin/env bash
# seqtopo as other C++ projects use it:
#  1. `cmake --install` of this build into a fresh prefix; examples/cpp configured outside the tree with
#     find_package(seqtopo CONFIG), built, and every example run (02 maps the installed corridor data); the
#     installed command maps its installed demo data when given no input;
#  2. the same source configured with every optional dependency disabled and only the alignment engine asked for
#     (SEQTOPO_MODULES: the other modules are not compiled, which took most of this test's time): it still builds
#     with the standard library alone, installs, and a consumer of seqtopo::align builds and runs;
#  3. a middle subset, the mapping module and what it needs (no io, formats, images): the package config finds only
#     their third-party packages (derived from what the modules link), and a consumer of seqtopo::mapping builds and
#     runs.
# Usage: tests/package/check_package.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$source/examples/cpp" -B "$tmp/examples" "${generator[@]}" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-Wall -Wextra -Werror" >/dev/null
cmake --build "$tmp/examples" >/dev/null
"$tmp/examples/01_similarity_to_map"
"$tmp/examples/03_localize"
corridor="$tmp/prefix/share/seqtopo/rtabmap-corridor"
"$tmp/examples/02_images_to_map" "$corridor" "$corridor/ground_truth.bmp" "$tmp/corridor-map" 2>/dev/null
for f in map.json alignments.json report.html; do test -s "$tmp/corridor-map/$f"; done
# The installed command opens the installed codecs plugin: PREFIX/lib, found from PREFIX/libexec/seqtopo/. Given
# no input it maps the installed demo data, PREFIX/share/seqtopo/rtabmap-corridor, found the same way (not the
# source tree's copy, which an installed copy may not have).
LD_DEBUG=files "$tmp/prefix/bin/seqtopo" map --out "$tmp/cli-map" >/dev/null 2>"$tmp/ld.log"
test -s "$tmp/cli-map/map.json"
if ! grep -q "seqtopo map: $corridor<" "$tmp/cli-map/report.html"; then
  echo "the installed seqtopo did not map its own $corridor:"
  grep -o "<title>[^<]*" "$tmp/cli-map/report.html"
  exit 1
fi
if ! grep -q "file=$tmp/prefix/lib/libseqtopo_codecs.so " "$tmp/ld.log"; then
  echo "the installed seqtopo did not open $tmp/prefix/lib/libseqtopo_codecs.so:"
  grep "libseqtopo_codecs" "$tmp/ld.log" | head -3
  exit 1
fi

disabled=()
for p in OpenMP OpenCV Eigen3 Ceres CLI11 nlohmann_json fmt faiss OpenSSL; do
  disabled+=(-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON)
done
cmake -S "$source" -B "$tmp/minimal" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSEQTOPO_BUILD_TESTS=OFF \
  -DSEQTOPO_BUILD_BENCH=OFF -DSEQTOPO_BUILD_PYTHON=OFF -DSEQTOPO_BUILD_MPI=OFF -DSEQTOPO_MODULES=align \
  "${disabled[@]}" >"$tmp/minimal.log" 2>&1
cat "$tmp/minimal.log" | grep "seqtopo:" || true
grep -q "module align not built" "$tmp/minimal.log" && { echo "align was skipped"; exit 1; }
cmake --build "$tmp/minimal" >/dev/null
cmake --install "$tmp/minimal" --prefix "$tmp/minimal-prefix" >/dev/null
test -f "$tmp/minimal-prefix/lib/libseqtopo_align.a"
test ! -e "$tmp/minimal-prefix/lib/libseqtopo_image.a"
test ! -e "$tmp/minimal-prefix/lib/libseqtopo_strings.a"
cmake -S "$source/tests/package/align_only" -B "$tmp/align-only" "${generator[@]}" \
  -DCMAKE_PREFIX_PATH="$tmp/minimal-prefix" >/dev/null
cmake --build "$tmp/align-only" >/dev/null
"$tmp/align-only/align_only"
echo "package: examples and the standard-library-only engine built and ran"

cmake -S "$source" -B "$tmp/mapping" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSEQTOPO_BUILD_TESTS=OFF \
  -DSEQTOPO_BUILD_BENCH=OFF -DSEQTOPO_BUILD_PYTHON=OFF -DSEQTOPO_BUILD_MPI=OFF \
  "-DSEQTOPO_MODULES=align;similarity;significance;mapping" >"$tmp/mapping.log" 2>&1
cmake --build "$tmp/mapping" >/dev/null
cmake --install "$tmp/mapping" --prefix "$tmp/mapping-prefix" >/dev/null
test -f "$tmp/mapping-prefix/lib/libseqtopo_mapping.a"
test ! -e "$tmp/mapping-prefix/lib/libseqtopo_formats.a"
test ! -e "$tmp/mapping-prefix/lib/libseqtopo_io.a"
if grep -q "nlohmann_json\|OpenCV\|OpenSSL" "$tmp/mapping-prefix/lib/cmake/seqtopo/seqtopoConfig.cmake"; then
  echo "the mapping-only package looks up packages its modules do not link:"
  grep "find_dependency" "$tmp/mapping-prefix/lib/cmake/seqtopo/seqtopoConfig.cmake"
  exit 1
fi
cmake -S "$source/tests/package/mapping_only" -B "$tmp/mapping-only" "${generator[@]}" \
  -DCMAKE_PREFIX_PATH="$tmp/mapping-prefix" >/dev/null
cmake --build "$tmp/mapping-only" >/dev/null
"$tmp/mapping-only/mapping_only" >/dev/null
