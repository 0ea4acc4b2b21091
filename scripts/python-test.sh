#!/usr/bin/env bash
# Installs the Python package `vemcontact` into target/python-venv
# (scripts/install-python-package.sh) and runs its tests (crates/vem-python/python/tests): the
# package's numbers against Hertz's solution, the patch test's exact state and the `vem`
# command's own outputs of the same scenes. .ci/run runs the same two steps.
#
# Usage: scripts/python-test.sh [--profile PROFILE] [PYTEST_ARGS...]
#   --profile test: the quicker build of scripts/install-python-package.sh (default release).
set -euo pipefail
cd "$(dirname "$0")/.."
profile=release
if [ "${1:-}" = "--profile" ]; then
    profile="${2:?--profile needs a cargo profile (release, test)}"
    shift 2
fi
python=$(scripts/install-python-package.sh --profile "$profile" | tail -n 1)
# The test profile builds into target/debug.
bin_dir=$profile
[ "$profile" = "test" ] || [ "$profile" = "dev" ] && bin_dir=debug
VEM_BIN="$PWD/target/$bin_dir/vem" "$python" -m pytest -q crates/vem-python/python/tests "$@"
