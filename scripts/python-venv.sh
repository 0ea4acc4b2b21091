#!/usr/bin/env bash
# Creates (once) a virtual environment and installs the pinned PyPI packages it lacks: the one
# venv recipe of the scripts that need Python packages (install-vtu-check.sh,
# install-python-package.sh).
#
# Usage: scripts/python-venv.sh NAME VENV_DIR PACKAGE==VERSION...
#   NAME names the calling script in error messages.
# Prints the path of the venv's python on its last line.
set -euo pipefail
name="$1"
venv="$2"
shift 2
python="${PYTHON:-python3}"

if ! command -v "$python" >/dev/null; then
    echo "$name: $python not found; install Python 3 (apt-get install python3 python3-venv)" >&2
    exit 1
fi
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv" || {
        echo "$name: cannot create a virtual environment in $venv (apt-get install python3-venv?)" >&2
        exit 1
    }
fi
installed=$("$venv/bin/python" -m pip freeze 2>/dev/null || true)
missing=()
for package in "$@"; do
    grep -qix "$package" <<<"$installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
    if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        --timeout 60 --retries 2 "${missing[@]}"; then
        echo "$name: pip could not install ${missing[*]} (is PyPI reachable?)" >&2
        exit 1
    fi
fi
echo "$venv/bin/python"
