#!/usr/bin/env bash
# Installs the dependencies, builds the release preset, runs the flagship case (the Vaiont landslide,
# three bodies with thermal pressurization of the clay layer and the reservoir as a water body, 4 m
# particle spacing: about 3 minutes on 2 cores after the build), prints its headline figures and
# plots it (a Vaiont case also with tools/plot_vaiont.py: the deposit, and the wave).
# Another case: scripts/flagship.sh CASE.toml [talus run options...] (the paper's dry model:
# cases/vaiont/three_bodies.toml)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
case_file=${1:-cases/vaiont/three_bodies_reservoir.toml}
shift || true
out=runs/$(basename "$case_file" .toml)
# The script owns runs/<case>: a re-run empties it first (talus refuses a non-empty folder).
build/release/talus run "$case_file" --out "$out" --overwrite "$@"
/usr/bin/python3 -c "import json; r = json.load(open('$out/summary.json'))['results']; print('results:', json.dumps(r, indent=2))"
/usr/bin/python3 tools/plot_run.py "$out" --field body
case "$case_file" in
  *vaiont/three_bodies*|*vaiont/five_bodies*|*vaiont/rigid_boundary.toml|*vaiont/rigid_boundary_wet*|*vaiont/rigid_boundary_reservoir*)
    /usr/bin/python3 tools/plot_vaiont.py "$out" ;;
esac
echo "results in $out (open $out/particles.pvd in ParaView; plots in $out/plots)"
