#!/usr/bin/env bash
# Quick start, command 2: install what is missing, build (Release), and run the
# whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
cd build
ctest -j2 --output-on-failure
