#!/usr/bin/env bash
# Installs every Talus dependency from Debian's archive (Debian 12). Idempotent.
# Nothing is downloaded from anywhere else and nothing is vendored.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  clang clang-format libclang-rt-14-dev libomp-dev
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev zlib1g-dev
  liblzma-dev                    # the frames' LZMA compression (VTK's vtkLZMADataCompressor)
  libgtest-dev libgmock-dev libbenchmark-dev
  libgdal-dev                    # terrain rasters and footprints (GeoTIFF, ESRI ASCII, GeoJSON, shapefile)
  python3-numpy python3-matplotlib python3-meshio
  python3-vtk9                   # VTK's own reader, in the run-folder test
  python3-rasterio               # the hazard maps' GeoTIFFs: their test and tools/plot_maps.py
  chromium                       # the verification report's browser test
  libopenmpi-dev openmpi-bin     # the mpi preset: domain decomposition over processes
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -q
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
