#!/usr/bin/env bash
# Quick start, command 1: install what is missing, build (Release), and run the
# main job — the default experiment, experiments/quickstart.yaml (about four
# minutes on 2 cores, its reference included) — after installing the Python
# package (scripts/install-python.sh). It ends by printing where the plot and
# report are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
bash scripts/install-python.sh
./build/lightbench run experiments/quickstart.yaml
