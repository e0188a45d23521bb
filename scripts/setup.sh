#!/usr/bin/env bash
# Installs seqtopo's dependencies from Debian's archive.
#   scripts/setup.sh          what building and running seqtopo needs (the library, the command line, the Python
#                             module with pip): compilers, CMake, the libraries, graphviz and D3 for the report;
#   scripts/setup.sh --test   that plus what the tests, benchmarks and CI need (GoogleTest, Google Benchmark, the
#                             reference aligners, MPI, Chromium for the report test, clang for fuzzing, the tools
#                             that write test bags); scripts/test.sh runs it.
# Idempotent: packages already present are skipped by apt. Uses sudo when not run as root.
set -euo pipefail

with_tests=0
case "${1:-}" in
  "") ;;
  --test) with_tests=1 ;;
  *) echo "usage: scripts/setup.sh [--test]" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libpng-dev libjpeg-dev libeigen3-dev libceres-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libssl-dev zlib1g-dev libfaiss-dev
  # The map's topology.svg (graphviz's dot) and the report's interactive views (D3, inlined into report.html).
  graphviz libjs-d3
  # Bags (the recording module): ROS 1 through librosbag and the message libraries, ROS 2 .db3 through SQLite,
  # MCAP chunks through zstd and lz4 (and zlib's CRC-32), a bag folder's metadata.yaml through libyaml.
  librosbag-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libsqlite3-dev libzstd-dev liblz4-dev
  libyaml-dev
  # The Python module (pip install .).
  python3-dev pybind11-dev python3-numpy python3-pip python3-venv
)
test_packages=(
  git ccache clang-format
  libgtest-dev libgmock-dev libbenchmark-dev
  # References the tests and benchmarks compare with; seqtopo-mpi (built by the test preset).
  emboss libedlib-dev libparasail-dev libopenmpi-dev openmpi-bin
  python3-pytest python3-matplotlib python3-pil python3-tqdm
  # The report opened in headless Chromium (tests/browser).
  chromium chromium-driver python3-selenium
  # Fuzzing (scripts/fuzz.sh): Debian's clang and its libFuzzer and sanitizer runtimes.
  clang libclang-rt-14-dev
  # ROS 1 test bags written by Debian's python3-rosbag (tests/recording).
  python3-rosbag python3-sensor-msgs python3-nav-msgs python3-geometry-msgs
)
if [ "$with_tests" -eq 1 ]; then
  packages+=("${test_packages[@]}")
  # The ROS 2 test bags are written by npm packages (tests/recording/package.json), which the tests install into
  # the build folder with npm. Debian's nodejs and npm unless a Node.js with npm is already there.
  if ! command -v npm >/dev/null 2>&1; then
    packages+=(nodejs npm)
  fi
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
echo "setup: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
