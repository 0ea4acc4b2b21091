#!/usr/bin/env python3
"""Writes the Gmsh meshes that the reading speed of vem-mesh is measured on (docs/benchmarks.md,
"Reading and writing meshes"): the Hertz indenter of tests/data/half_disc.geo (a half-disc of
radius 1 refined towards its bottom point) at several sizes, each saved as MSH 4.1 and 2.2,
ASCII and binary, by Gmsh itself:

    target/gmsh-venv/bin/python scripts/mesh-bench.py [OUT] [--sizes 6,60,300]

OUT defaults to target/mesh-bench. --sizes are the approximate sizes in MB of the MSH 4.1 ASCII
files. Files named hertz-<MB>MB-<version>-<ascii|binary>.msh; existing files are kept (delete
them to regenerate). Then:

    cargo run --release -p vem-mesh --example io_speed -- target/mesh-bench/*.msh
"""
import math
import pathlib
import sys

import gmsh

ROOT = pathlib.Path(__file__).resolve().parent.parent

# Bytes of an MSH 4.1 ASCII file per node of this mesh (measured: about 2 triangles per node).
BYTES_PER_NODE = 95.0
# Nodes of the mesh at scale 1 (h = 0.05, h_contact = 0.01, as in half_disc.geo).
NODES_AT_SCALE_1 = 1033


def half_disc(scale):
    """The geometry and size field of tests/data/half_disc.geo, sizes divided by `scale`."""
    gmsh.model.add("hertz")
    g = gmsh.model.geo
    h, h_contact = 0.05 / scale, 0.01 / scale
    centre = g.addPoint(0, 1, 0, h)
    left = g.addPoint(-1, 1, 0, h)
    bottom = g.addPoint(0, 0, 0, h_contact)
    right = g.addPoint(1, 1, 0, h)
    arc_left = g.addCircleArc(left, centre, bottom)
    arc_right = g.addCircleArc(bottom, centre, right)
    top = g.addLine(right, left)
    surface = g.addPlaneSurface([g.addCurveLoop([arc_left, arc_right, top])])
    g.synchronize()
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [bottom])
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_contact)
    field.setNumber(threshold, "SizeMax", h)
    field.setNumber(threshold, "DistMin", 0.02)
    field.setNumber(threshold, "DistMax", 0.4)
    field.setAsBackgroundMesh(threshold)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    # Delaunay: the fastest 2D algorithm of Gmsh for millions of triangles.
    gmsh.option.setNumber("Mesh.Algorithm", 5)
    gmsh.model.addPhysicalGroup(1, [arc_left, arc_right], 1, "arc")
    gmsh.model.addPhysicalGroup(1, [top], 2, "top")
    gmsh.model.addPhysicalGroup(2, [surface], 3, "body")
    gmsh.model.mesh.generate(2)


def main(argv):
    sizes = [6, 60, 300]
    rest = []
    i = 0
    while i < len(argv):
        if argv[i] == "--sizes":
            sizes = [int(s) for s in argv[i + 1].split(",")]
            i += 2
        else:
            rest.append(argv[i])
            i += 1
    out = pathlib.Path(rest[0]) if rest else ROOT / "target" / "mesh-bench"
    out.mkdir(parents=True, exist_ok=True)
    gmsh.initialize(["gmsh"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        for mb in sizes:
            names = [(f"hertz-{mb}MB-{tag}-{kind}.msh", version, kind == "binary")
                     for version, tag in [(4.1, "41"), (2.2, "22")]
                     for kind in ["ascii", "binary"]]
            if all((out / name).exists() for name, _, _ in names):
                continue
            nodes = mb * 1e6 / BYTES_PER_NODE
            half_disc(math.sqrt(nodes / NODES_AT_SCALE_1))
            for name, version, binary in names:
                gmsh.option.setNumber("Mesh.MshFileVersion", version)
                gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
                gmsh.write(str(out / name))
                size = (out / name).stat().st_size
                print(f"mesh-bench: {out / name}: {size / 1e6:.1f} MB")
            gmsh.model.remove()
    finally:
        gmsh.finalize()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
