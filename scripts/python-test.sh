#!/usr/bin/env bash
# Builds the Python package `vemcontact` (crates/vem-python) as a wheel with maturin, installs it
# into a virtual environment (by default target/python-venv, with maturin, numpy and pytest,
# pinned) and runs its tests (crates/vem-python/python/tests). The tests compare the package's
# numbers with Hertz's solution, the patch test's exact state and the `vem` command's own
# outputs of the same scenes, so the command is built first (release, as CI builds it).
#
# Usage: scripts/python-test.sh [PYTEST_ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${VEM_PYTHON_VENV:-target/python-venv}"
python="${PYTHON:-python3}"
packages=(maturin==1.16.0 numpy==2.4.6 pytest==9.2.0)

if ! command -v "$python" >/dev/null; then
    echo "python-test: $python not found; install Python 3 (apt-get install python3 python3-venv)" >&2
    exit 1
fi
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv" || {
        echo "python-test: cannot create a virtual environment in $venv (apt-get install python3-venv?)" >&2
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
        echo "python-test: pip could not install ${missing[*]} (is PyPI reachable?)" >&2
        exit 1
    fi
fi

# The `vem` command the tests compare with, built together with the package's library: rust-numpy
# and PyO3 change the features of a few shared dependencies (num-complex, matrixmultiply, syn),
# so the command built alone would not share its libraries with the wheel's build. Built
# together (as .ci/run builds them), the wheel's build below compiles only PyO3 and the
# package's own crate.
cargo build --release -p vem-cli -p vem-python
# The wheel, for the venv's Python, in release; then installed as a user would install it.
wheels=target/python-wheels
rm -rf "$wheels"
"$venv/bin/maturin" build --release --quiet --interpreter "$venv/bin/python" \
    --manifest-path crates/vem-python/Cargo.toml --out "$wheels"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps \
    --force-reinstall "$wheels"/vemcontact-*.whl

VEM_BIN="$PWD/target/release/vem" "$venv/bin/python" -m pytest -q \
    crates/vem-python/python/tests "$@"
