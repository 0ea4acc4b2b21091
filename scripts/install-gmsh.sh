#!/usr/bin/env bash
# Installs Gmsh's Python API (the `gmsh` wheel from PyPI) into a virtual environment, by default
# target/gmsh-venv, and checks that it imports. The wheel links against a few X11/OpenGL
# libraries that a minimal Debian lacks; they are installed with apt-get when missing. The version
# is pinned: the committed reference JSON was generated with it.
#
# Usage: scripts/install-gmsh.sh [VENV_DIR]
# Prints the path of the venv's python on its last line.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-target/gmsh-venv}"
python="${PYTHON:-python3}"
version=4.15.2

if ! command -v "$python" >/dev/null; then
    echo "install-gmsh: $python not found; install Python 3 (apt-get install python3 python3-venv)" >&2
    exit 1
fi
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv" || {
        echo "install-gmsh: cannot create a virtual environment in $venv (apt-get install python3-venv?)" >&2
        exit 1
    }
fi
# pip's metadata tells the installed version without loading the library.
if [ "$("$venv/bin/python" -m pip show gmsh 2>/dev/null | sed -n 's/^Version: //p')" != "$version" ]; then
    if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        --timeout 60 --retries 2 "gmsh==$version"; then
        echo "install-gmsh: pip could not install the gmsh wheel (is PyPI reachable?)" >&2
        exit 1
    fi
fi
# The wheel's shared library needs these at load time (not for meshing without a GUI).
if ! "$venv/bin/python" -c "import gmsh" >/dev/null 2>&1; then
    if command -v apt-get >/dev/null; then
        echo "install-gmsh: the gmsh module does not import; installing its system libraries" >&2
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq >/dev/null
        apt-get install -y -qq libglu1-mesa libxft2 libxinerama1 libxcursor1 libxrender1 \
            libxfixes3 libgl1 libx11-6 libfontconfig1 >/dev/null
    fi
fi
if ! error=$("$venv/bin/python" -c "import gmsh" 2>&1); then
    echo "install-gmsh: the gmsh module still does not import:" >&2
    echo "$error" >&2
    exit 1
fi
echo "$venv/bin/python"
