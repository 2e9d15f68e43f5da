#!/usr/bin/env bash
# Quick start, command 1: install what is missing, build (Release), and run the
# main job — for now, render the default scene (the Cornell box).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
mkdir -p out
./build/lightbench render scenes/cornell-box.yaml --spp 64 -o out/cornell-box.exr
echo
echo "Image: out/cornell-box.exr (32-bit float OpenEXR), preview out/cornell-box.png,"
echo "configuration out/cornell-box.config.yaml"
