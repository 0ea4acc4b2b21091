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
python=$(scripts/python-venv.sh install-vtu-check "$venv" meshio==5.3.5 vtk==9.7.2 numpy==2.4.6 |
    tail -n 1)
check="import meshio, vtk, numpy"
if ! "$python" -c "$check" >/dev/null 2>&1; then
    if command -v apt-get >/dev/null; then
        echo "install-vtu-check: vtk does not import; installing its system libraries" >&2
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq >/dev/null
        apt-get install -y -qq libgl1 libx11-6 libxrender1 libxext6 libxcursor1 libxft2 \
            libxinerama1 libglu1-mesa libfontconfig1 >/dev/null
    fi
fi
if ! error=$("$python" -c "$check" 2>&1); then
    echo "install-vtu-check: meshio or vtk still does not import:" >&2
    echo "$error" >&2
    exit 1
fi
echo "$python"
