#!/usr/bin/env bash
# Installs every build, test and run-time dependency of seqtopo from Debian's archive.
# Idempotent: packages already present are skipped by apt. Uses sudo when not run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libopencv-dev libeigen3-dev libceres-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libssl-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  emboss libedlib-dev libparasail-dev graphviz
  libfaiss-dev libopenmpi-dev openmpi-bin
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib python3-pip python3-venv python3-pil
  chromium chromium-driver python3-selenium ccache clang-format
  # Fuzzing (scripts/fuzz.sh): Debian's clang and its libFuzzer and sanitizer runtimes.
  clang libclang-rt-14-dev
  libjs-d3
  # Bags (the recording module): ROS 1 through librosbag and the message libraries, ROS 2 .db3 through SQLite,
  # MCAP chunks through zstd and lz4, a bag folder's metadata.yaml through libyaml.
  librosbag-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libsqlite3-dev libzstd-dev liblz4-dev libyaml-dev
  # Test-only: ROS 1 test bags written by Debian's python3-rosbag (tests/recording).
  python3-rosbag python3-sensor-msgs python3-nav-msgs python3-geometry-msgs
)
# Test-only: the ROS 2 test bags are written by npm packages (tests/recording/package.json), which the tests
# install into the build folder with npm. Debian's nodejs and npm unless a Node.js with npm is already there.
if ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
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
