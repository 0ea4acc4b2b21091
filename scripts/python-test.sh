#!/usr/bin/env bash
# Installs the Python package `vemcontact` into target/python-venv
# (scripts/install-python-package.sh) and runs its tests (crates/vem-python/python/tests): the
# package's numbers against Hertz's solution, the patch test's exact state and the `vem`
# command's own outputs of the same scenes. .ci/run runs the same two steps.
#
# Usage: scripts/python-test.sh [PYTEST_ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
python=$(scripts/install-python-package.sh | tail -n 1)
VEM_BIN="$PWD/target/release/vem" "$python" -m pytest -q crates/vem-python/python/tests "$@"
