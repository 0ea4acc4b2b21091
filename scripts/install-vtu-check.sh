#!/usr/bin/env bash
# Installs the independent VTK readers that scripts/check-vtu.py compares vem-mesh's files with:
# meshio and VTK's Python wheel (with numpy), pinned, into a virtual environment, by default
# target/vtu-check-venv, and checks that they import. VTK's wheel needs a few X11/OpenGL libraries
# at import time that a minimal Debian lacks; they are installed with apt-get when missing.
#
# Usage: scripts/install-vtu-check.sh [VENV_DIR]
# Prints the path of the venv's python on its last line.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-target/vtu-check-venv}"
python="${PYTHON:-python3}"
packages=(meshio==5.3.5 vtk==9.7.2 numpy==2.4.6)

if ! command -v "$python" >/dev/null; then
    echo "install-vtu-check: $python not found; install Python 3 (apt-get install python3 python3-venv)" >&2
    exit 1
fi
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv" || {
        echo "install-vtu-check: cannot create a virtual environment in $venv (apt-get install python3-venv?)" >&2
        exit 1
    }
fi
installed=$("$venv/bin/python" -m pip freeze 2>/dev/null || true)
missing=()
for package in "${packages[@]}"; do
    grep -qix "$package" <<<"$installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
    if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        --timeout 60 --retries 2 "${missing[@]}"; then
        echo "install-vtu-check: pip could not install ${missing[*]} (is PyPI reachable?)" >&2
        exit 1
    fi
fi
check="import meshio, vtk, numpy"
if ! "$venv/bin/python" -c "$check" >/dev/null 2>&1; then
    if command -v apt-get >/dev/null; then
        echo "install-vtu-check: vtk does not import; installing its system libraries" >&2
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq >/dev/null
        apt-get install -y -qq libgl1 libx11-6 libxrender1 libxext6 libxcursor1 libxft2 \
            libxinerama1 libglu1-mesa libfontconfig1 >/dev/null
    fi
fi
if ! error=$("$venv/bin/python" -c "$check" 2>&1); then
    echo "install-vtu-check: meshio or vtk still does not import:" >&2
    echo "$error" >&2
    exit 1
fi
echo "$venv/bin/python"
