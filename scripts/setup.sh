#!/usr/bin/env bash
# Installs every Debian 12 package ishibashi needs to build, test and benchmark.
# Safe to run again: when everything is already installed it returns at once.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config     # toolchain
  clang libomp-dev libclang-rt-14-dev  # the compiler CMakeLists.txt prefers, its OpenMP and sanitizers
  libeigen3-dev                        # linear algebra (engine)
  libcgal-dev libgmp-dev libmpfr-dev   # polyhedral geometry and validation (geometry)
  libvtk9-dev                          # ParaView output and its read-back tests (io)
  libtomlplusplus-dev libcli11-dev libfmt-dev   # scenario files, command line, formatting
  nlohmann-json3-dev                   # summary.json
  libspectra-dev                       # sparse eigensolver (modal analysis)
  libgtest-dev libgmock-dev libbenchmark-dev    # tests and benchmarks
  python3-matplotlib python3-vtk9 python3-pil  # the study's report: figures, snapshots from the .vtu, GIFs
  libopenmpi-dev openmpi-bin           # sweeps across machines (mpirun)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
