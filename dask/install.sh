#!/usr/bin/env bash
# Create (or reuse) the Python venv that runs dask/dask_bake.py.
#   dask/install.sh [VENV_DIR]        default: .venv-dask at the repo root
# Env: PYTHON (interpreter for the venv, default python3; 3.10+ needed by dask 2026.x).
# Installs dask[distributed] from PyPI only. Idempotent: a venv where
# `import dask.distributed` works at the pinned version is left as it is.
set -euo pipefail

DASK_VERSION="2026.8.0"
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${1:-$repo_root/.venv-dask}"
python="${PYTHON:-python3}"

ready() {
    [[ -x "$venv/bin/python" ]] && "$venv/bin/python" - "$DASK_VERSION" <<'PY' >/dev/null 2>&1
import sys
import dask, dask.distributed, distributed
sys.exit(0 if dask.__version__ == distributed.__version__ == sys.argv[1] else 1)
PY
}

if ready; then
    echo "dask $DASK_VERSION already in $venv"
    exit 0
fi

if [[ ! -x "$venv/bin/python" ]]; then
    "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    "dask[distributed]==$DASK_VERSION"

if ! ready; then
    echo "install.sh: dask.distributed $DASK_VERSION still not importable in $venv" >&2
    exit 1
fi
echo "dask $DASK_VERSION installed in $venv"
echo "run: $venv/bin/python $repo_root/dask/dask_bake.py --help"
