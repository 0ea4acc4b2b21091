#!/usr/bin/env bash
# Meshes the Hertz scene (crates/vem-cli/scenes/hertz_{disc,block}.geo) at any size with Gmsh's
# Python wheel (installed by scripts/install-gmsh.sh into target/gmsh-venv): the contact mesh
# size H_CONTACT near the contact point, the far sizes H_DISC and H_BLOCK.
#
# Usage: scripts/hertz-meshes.sh H_CONTACT H_DISC H_BLOCK DISC_OUT BLOCK_OUT
#   (writes DISC_OUT.msh and BLOCK_OUT.msh, MSH 4.1)
# Example (about 10^5 unknowns, the load-history benchmark of docs/benchmarks.md):
#   scripts/hertz-meshes.sh 0.002 0.0125 0.039 target/fretting/disc_1e5 target/fretting/block_1e5
# BLOCK_GEO=crates/vem-cli/scenes/hertz_block_triangles.geo meshes the block with triangles.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 5 ]; then
    sed -n '2,11p' "$0" >&2
    exit 2
fi
python=$(scripts/install-gmsh.sh | tail -n 1)
mkdir -p "$(dirname "$4")" "$(dirname "$5")"
mesh() { # GEO OUT H_CONTACT H
    "$python" - "$1" "$2" "$3" "$4" <<'PY'
import re, sys
import gmsh
geo, out, h_contact, h = sys.argv[1:5]
text = open(geo).read()
text = re.sub(r"^h_contact = [0-9.]+;", f"h_contact = {h_contact};", text, flags=re.M)
text = re.sub(r"^h = [0-9.]+;", f"h = {h};", text, flags=re.M)
with open(out + ".geo", "w") as f:
    f.write(text)
gmsh.initialize()
gmsh.option.setNumber("General.Verbosity", 1)
gmsh.open(out + ".geo")
gmsh.model.mesh.generate(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(out + ".msh")
gmsh.finalize()
PY
    rm -f "$2.geo"
}
mesh crates/vem-cli/scenes/hertz_disc.geo "$4" "$1" "$2"
mesh "${BLOCK_GEO:-crates/vem-cli/scenes/hertz_block.geo}" "$5" "$1" "$3"
echo "wrote $4.msh and $5.msh"
