#!/usr/bin/env bash
# Regenerates what the docs list from the code (issue 39), after adding or
# changing an integrator: docs/integrators.md (every integrator's keys) and
# each list of integrators by property between
#   <!-- integrators --with PROPERTY --> … <!-- /integrators -->
# in README.md and docs/*.md. Needs a build (./build/lightbench).
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
  LIGHTBENCH="$bin" /usr/bin/python3 - "$f" <<'PY'
import os, re, subprocess, sys, tempfile
path = sys.argv[1]
text = open(path, encoding="utf-8").read()
def generated(m):
    line = subprocess.check_output([os.environ["LIGHTBENCH"], "integrators", "--with", m.group(1)], text=True).strip()
    return m.group(0)[: m.start(2) - m.start(0)] + line + "<!-- /integrators -->"
new = re.sub(r"<!-- integrators --with ([a-z]+) -->([^\n]*?)<!-- /integrators -->", generated, text)
if new != text:
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path) or ".", prefix=".update-docs.")
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        out.write(new)
    os.chmod(tmp, os.stat(path).st_mode & 0o777)
    os.replace(tmp, path)
    print("updated", path)
PY
done
