#!/usr/bin/env bash
# Test setup of tests/recording: installs the npm packages that write the ROS 2 test bags (package.json beside
# this script) into DEST/node_modules with the machine's npm. Test-only: seqtopo never needs them to build or
# run. Skips the install when the same package.json was installed before.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
dest="$1"
mkdir -p "$dest"
# The writer runs from beside its node_modules (ES modules resolve packages from the script's folder).
cp "$here/write_ros2_bag.mjs" "$dest/write_ros2_bag.mjs"
if [ -f "$dest/package.json" ] && cmp -s "$here/package.json" "$dest/package.json" && [ -d "$dest/node_modules/@mcap/core" ]; then
  echo "recording test tools: already installed in $dest"
  exit 0
fi
command -v npm >/dev/null || { echo "recording test tools: npm not found (Debian: apt-get install npm)" >&2; exit 1; }
cp "$here/package.json" "$dest/package.json"
cd "$dest"
npm install --no-audit --no-fund --no-package-lock --loglevel=error
echo "recording test tools: installed in $dest"
