#!/usr/bin/env bash
# Set up everything mat-hopper needs, idempotently:
#   - system libraries (when run as root on Debian/Ubuntu): OSMesa for
#     off-screen rendering, PostgreSQL for the distributed-optimizer tests,
#     Chromium for the test that opens the built book in a browser;
#   - a virtual environment in .venv with the pinned requirements
#     (environment.txt) and the package itself (editable).
# Re-running is cheap: the venv is rebuilt only when the pins change.
set -euo pipefail
cd "$(dirname "$0")/.."

PY=${PYTHON:-python3}
SYSTEM_PACKAGES="libosmesa6 libgl1 libglx-mesa0 postgresql chromium"

if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  missing=""
  for p in $SYSTEM_PACKAGES; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
  done
  if [ -n "$missing" ]; then
    echo "setup: installing system packages:$missing"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends $missing >/dev/null
  fi
else
  echo "setup: not root (or no apt-get): skipping system packages ($SYSTEM_PACKAGES)"
fi

stamp=.venv/.mat-hopper-setup
want=$(cat environment.txt pyproject.toml | sha256sum | cut -c1-16)
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
echo "setup: creating .venv with $($PY --version)"
[ -x .venv/bin/python ] || $PY -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -r environment.txt
.venv/bin/python -m pip install -q --no-deps -e .
echo "$want" > "$stamp"
echo "setup: done"
