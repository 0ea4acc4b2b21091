#!/usr/bin/env bash
# Builds the Python package `vemcontact` (crates/vem-python) as a wheel with maturin and installs
# it into a virtual environment (by default target/python-venv, with maturin, numpy, pytest and meshio,
# pinned), as a user would install it. Also builds the `vem` command (same profile) that the
# package's tests compare with.
#
# Usage: scripts/install-python-package.sh [--profile PROFILE] [VENV_DIR]
#   --profile test builds the package and the command with the optimised test profile (into
#   target/debug, shared with `cargo test`): quicker to build while iterating; the default is
#   release, as users install it. The wheel is one stable-ABI (abi3) wheel for CPython 3.9 and
#   later.
# Prints the path of the venv's python on its last line.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=release
if [ "${1:-}" = "--profile" ]; then
    profile="${2:?--profile needs a cargo profile (release, test)}"
    shift 2
fi
venv="${1:-target/python-venv}"
cargo_profile=$profile
if [ "$profile" = "test" ]; then
    # maturin builds the library with `cargo rustc`, which compiles a test harness under the
    # test profile: the dev profile with the test profile's settings instead, whose libraries
    # are those of `cargo test` (both build into target/debug).
    cargo_profile=dev
    export CARGO_PROFILE_DEV_OPT_LEVEL=3 CARGO_PROFILE_DEV_DEBUG=false
fi
python=$(scripts/python-venv.sh install-python-package "$venv" \
    maturin==1.16.0 numpy==2.4.6 pytest==9.2.0 meshio==5.3.5 | tail -n 1)

# The `vem` command the tests compare with, built together with the package's library: rust-numpy
# and PyO3 change the features of a few shared dependencies (num-complex, matrixmultiply, syn),
# so the command built alone would not share its libraries with the wheel's build. Built
# together (as .ci/run builds them), the wheel's build below compiles only PyO3 and the
# package's own crate.
cargo build --profile "$cargo_profile" -p vem-cli -p vem-python >&2
# The wheel, for the venv's Python, in the profile chosen; then installed as a user would install it.
wheels=target/python-wheels
rm -rf "$wheels"
"$venv/bin/maturin" build --profile "$cargo_profile" --quiet --interpreter "$python" \
    --manifest-path crates/vem-python/Cargo.toml --out "$wheels" >&2
"$python" -m pip install --quiet --disable-pip-version-check --no-deps \
    --force-reinstall "$wheels"/vemcontact-*.whl >&2
echo "$python"
