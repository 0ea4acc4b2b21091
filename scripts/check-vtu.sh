#!/usr/bin/env bash
# The VTU writer against independent readers: installs meshio and VTK in a venv
# (scripts/install-vtu-check.sh), writes sample files in every encoding with a JSON description
# beside each (crates/vem-mesh/examples/vtu_samples.rs), and reads them back with meshio and with
# VTK's XML reader (scripts/check-vtu.py). Exits non-zero on any difference.
#
# Usage: scripts/check-vtu.sh [OUT_DIR]   (default target/vtu-check)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-target/vtu-check}"
python=$(scripts/install-vtu-check.sh | tail -n 1)
rm -rf "$out"
cargo run --quiet --release -p vem-mesh --example vtu_samples -- "$out"
"$python" scripts/check-vtu.py "$out"
