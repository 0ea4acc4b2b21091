#!/usr/bin/env bash
# Builds the Python package `vemcontact` (crates/vem-python) as a wheel with maturin and installs
# it into a virtual environment (by default target/python-venv, with maturin, numpy and pytest,
# pinned), as a user would install it. Also builds the `vem` command (release) that the
# package's tests compare with.
#
# Usage: scripts/install-python-package.sh [VENV_DIR]
# Prints the path of the venv's python on its last line.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-target/python-venv}"
python=$(scripts/python-venv.sh install-python-package "$venv" \
    maturin==1.16.0 numpy==2.4.6 pytest==9.2.0 | tail -n 1)

# The `vem` command the tests compare with, built together with the package's library: rust-numpy
# and PyO3 change the features of a few shared dependencies (num-complex, matrixmultiply, syn),
# so the command built alone would not share its libraries with the wheel's build. Built
# together (as .ci/run builds them), the wheel's build below compiles only PyO3 and the
# package's own crate.
cargo build --release -p vem-cli -p vem-python >&2
# The wheel, for the venv's Python, in release; then installed as a user would install it.
wheels=target/python-wheels
rm -rf "$wheels"
"$venv/bin/maturin" build --release --quiet --interpreter "$python" \
    --manifest-path crates/vem-python/Cargo.toml --out "$wheels" >&2
"$python" -m pip install --quiet --disable-pip-version-check --no-deps \
    --force-reinstall "$wheels"/vemcontact-*.whl >&2
echo "$python"
