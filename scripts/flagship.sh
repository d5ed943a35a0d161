#!/usr/bin/env bash
# Installs the dependencies, builds the release preset and runs the flagship example, then plots it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
case_file=${1:-cases/examples/block_on_floor.toml}
out=runs/$(basename "$case_file" .toml)
build/release/talus run "$case_file" --out "$out"
/usr/bin/python3 tools/plot_run.py "$out" --field stress_yy
echo "results in $out (open $out/particles.pvd in ParaView; plots in $out/plots)"
