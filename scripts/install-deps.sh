#!/usr/bin/env bash
# Installs lightbench's build, test and plotting dependencies from Debian 12's
# packages. Safe to re-run: it installs only what is missing.
set -euo pipefail

packages=(
  build-essential cmake git
  libembree-dev libtbb-dev libflann-dev libopenexr-dev libglm-dev
  libopenmesh-dev libyaml-cpp-dev libcli11-dev libpng-dev libpugixml-dev
  libopenimageio-dev  # texture and environment-map images: JPEG, PNG, TGA, HDR, PFM, EXR
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-matplotlib python3-numpy
  nlohmann-json3-dev pybind11-dev python3-dev  # meta.json, the Python package
  python3-pandas python3-pytest                # lightbench.load_run, its tests
  chromium                                      # the report viewer's headless check
  clang libclang-rt-14-dev  # libFuzzer + sanitizers for scripts/fuzz.sh
  libopenmpi-dev openmpi-bin  # mpirun -np N lightbench run (optional build: -DLIGHTBENCH_MPI)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
