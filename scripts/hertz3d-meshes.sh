#!/usr/bin/env bash
# Meshes the Hertz scene in space (crates/vem-cli/scenes/hertz3d_{ball,block}.geo) with
# tetrahedra at any size with Gmsh's Python wheel (installed by scripts/install-gmsh.sh into
# target/gmsh-venv): the mesh size H_CONTACT within 0.15 of the contact point, H far from it.
#
# Usage: scripts/hertz3d-meshes.sh H_CONTACT H BALL_OUT BLOCK_OUT
#   (writes BALL_OUT.msh and BLOCK_OUT.msh, MSH 4.1)
# The committed meshes of crates/vem-cli/scenes/hertz3d.toml:
#   scripts/hertz3d-meshes.sh 0.02 0.25 crates/vem-cli/scenes/hertz3d_ball crates/vem-cli/scenes/hertz3d_block
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 4 ]; then
    sed -n '2,9p' "$0" >&2
    exit 2
fi
python=$(scripts/install-gmsh.sh | tail -n 1)
mkdir -p "$(dirname "$3")" "$(dirname "$4")"
mesh() { # GEO OUT H_CONTACT H
    "$python" - "$1" "$2" "$3" "$4" <<'PY'
import re, sys
import gmsh
geo, out, h_contact, h = sys.argv[1:5]
text = open(geo).read()
text = re.sub(r"^h_contact = [0-9.]+;", f"h_contact = {h_contact};", text, flags=re.M)
text = re.sub(r"^h = [0-9.]+;", f"h = {h};", text, flags=re.M)
with open(out + ".tmp.geo", "w") as f:
    f.write(text)
gmsh.initialize()
gmsh.option.setNumber("General.Verbosity", 1)
gmsh.open(out + ".tmp.geo")
gmsh.model.mesh.generate(3)
gmsh.model.mesh.optimize("Netgen")
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(out + ".msh")
gmsh.finalize()
PY
    rm -f "$2.tmp.geo"
}
mesh crates/vem-cli/scenes/hertz3d_ball.geo "$3" "$1" "$2"
mesh crates/vem-cli/scenes/hertz3d_block.geo "$4" "$1" "$2"
echo "wrote $3.msh and $4.msh"
