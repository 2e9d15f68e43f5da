#!/usr/bin/env bash
# Makes `import lightbench` work in Debian's /usr/bin/python3: writes a .pth
# file naming this checkout's build/python (where the build assembles the
# package) into the interpreter's site-packages (root) or user site (others).
# Like `pip install -e`, a rebuild is seen without reinstalling; no pip is
# needed (Debian 12's pip refuses system installs, PEP 668).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
PACKAGE_PARENT="$(pwd)/build/python"
[[ -f "$PACKAGE_PARENT/lightbench/__init__.py" ]] ||
  { echo "install-python: $PACKAGE_PARENT/lightbench is missing: build first (cmake --build build)" >&2; exit 2; }
if [[ $(id -u) -eq 0 ]]; then
  SITE=$("$PY" -c 'import site; print(site.getsitepackages()[0])')
else
  SITE=$("$PY" -c 'import site; print(site.getusersitepackages())')
fi
mkdir -p "$SITE"
printf '%s\n' "$PACKAGE_PARENT" >"$SITE/lightbench.pth.tmp"
mv "$SITE/lightbench.pth.tmp" "$SITE/lightbench.pth"
# Checked from another folder, as a user would import it.
(cd / && "$PY" -c 'import lightbench; print("install-python: lightbench", lightbench.__version__, "importable from", lightbench.__file__)')
