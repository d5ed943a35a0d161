#!/usr/bin/env bash
# Installs the dependencies, builds the release preset and runs every test (unit + verification),
# then builds the mpi preset (the program and its MPI tests) and runs those on 1 to 4 processes.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release "$@"
cmake --preset mpi
cmake --build --preset mpi --target talus talus_mpi_tests
ctest --preset mpi "$@"
