#!/usr/bin/env bash
# Installs the dependencies, builds the release preset and runs every test (unit + verification).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release "$@"
