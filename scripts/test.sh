#!/usr/bin/env bash
# Installs the dependencies of building and testing (scripts/setup.sh --test), builds seqtopo (Release, warnings
# as errors) and runs the whole test suite.
# Usage: scripts/test.sh [release|sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
scripts/setup.sh --test
cmake --workflow --preset "$preset"
