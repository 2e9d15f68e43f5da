#!/usr/bin/env bash
# Regenerates what the docs list from the code (issue 39), after adding or
# changing an integrator: docs/integrators.md (every integrator's keys) and
# each list of integrators between
#   <!-- integrators SPEC --> … <!-- /integrators -->
# in README.md and docs/*.md (SPEC: --names, --with P or --without P; see
# integrators/registry_docs.h). Needs a build (./build/lightbench).
# tests/integrators/registry_keys_test.cpp fails until these are current.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=./build/lightbench
[ -x "$bin" ] || { echo "error: $bin not built (cmake --build build -j2)" >&2; exit 2; }
tmp=$(mktemp docs/.integrators.md.XXXXXX)
trap 'rm -f "$tmp"' EXIT
"$bin" integrators --markdown > "$tmp"
chmod --reference=docs/integrators.md "$tmp"
mv "$tmp" docs/integrators.md
for f in README.md docs/*.md; do
  tmp=$(mktemp "$(dirname "$f")/.update-docs.XXXXXX")
  "$bin" integrators --fill-lists < "$f" > "$tmp"
  if cmp -s "$f" "$tmp"; then
    rm -f "$tmp"
  else
    chmod --reference="$f" "$tmp"
    mv "$tmp" "$f"
    echo "updated $f"
  fi
done
