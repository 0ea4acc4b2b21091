#!/usr/bin/env python3
"""Writes the meshio fixtures of vem-mesh's VTK readers (crates/vem-mesh/tests/data/vtk/meshio-*)
and, beside each, FILE.json: the points, cells and cell data as meshio reads the file back. The
Rust test crates/vem-mesh/tests/vtk.rs reads the same files with vem-mesh and compares. Run it
in the venv of scripts/install-vtu-check.sh when the fixtures change:

    "$(scripts/install-vtu-check.sh | tail -n 1)" scripts/vtk-fixtures.py [--check]

With --check nothing is written: exits 1 if a committed JSON differs from what meshio reads now.

The mesh: a unit square cut into a pentagon, a triangle and a quadrangle (polygons of mixed
sizes, one of them listed clockwise as some writers do), with its boundary as line cells whose
"gmsh:physical" cell data numbers the parts, named by field data as meshio writes Gmsh's
physical groups: 1 "bottom", 2 "sides", 3 "top".
"""
import json
import pathlib
import sys

import meshio
import numpy

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "crates" / "vem-mesh" / "tests" / "data" / "vtk"


def mesh():
    points = numpy.array([
        [0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0],
        [1.0, 0.5, 0.0], [1.0, 1.0, 0.0], [0.5, 1.0, 0.0],
        [0.0, 1.0, 0.0], [0.0, 0.5, 0.0], [0.5, 0.5, 0.0],
        [0.1234567890123456789, 0.0, 0.0],
    ])
    # Point 9 lies on the bottom edge between 0 and 1: the pentagon 0 9 1 8 7 has a hanging
    # node, allowed by the virtual element method.
    cells = [
        ("polygon", numpy.array([[0, 9, 1, 8, 7]])),
        ("triangle", numpy.array([[1, 2, 3], [1, 3, 8]])),
        # Clockwise on purpose: the reader turns it.
        ("quad", numpy.array([[8, 5, 4, 3], [7, 8, 5, 6]])),
        ("line", numpy.array([[0, 9], [9, 1], [1, 2], [2, 3], [3, 4], [6, 7], [7, 0], [4, 5], [5, 6]])),
    ]
    physical = [
        numpy.array([0]), numpy.array([0, 0]), numpy.array([0, 0]),
        numpy.array([1, 1, 1, 2, 2, 2, 2, 3, 3]),
    ]
    temperature = points[:, 0] * 2.0 - points[:, 1] / 3.0
    return meshio.Mesh(
        points,
        cells,
        point_data={"temperature": temperature},
        cell_data={"gmsh:physical": physical},
        field_data={"bottom": numpy.array([1, 1]), "sides": numpy.array([2, 1]),
                    "top": numpy.array([3, 1])},
    )


# (file name, writer arguments)
FIXTURES = [
    ("meshio-ascii.vtu", {"file_format": "vtu", "binary": False}),
    ("meshio-zlib.vtu", {"file_format": "vtu", "binary": True, "compression": "zlib"}),
    ("meshio-base64.vtu", {"file_format": "vtu", "binary": True, "compression": None}),
    ("meshio-ascii-51.vtk", {"file_format": "vtk", "binary": False}),
    ("meshio-binary-51.vtk", {"file_format": "vtk", "binary": True}),
    ("meshio-ascii-42.vtk", {"file_format": "vtk42", "binary": False}),
]


def describe(path):
    """What meshio reads from `path`: points, cells in order, cell data, point data."""
    read = meshio.read(path)
    cells = []
    physical = []
    for k, block in enumerate(read.cells):
        for row in block.data:
            cells.append([block.type, [int(p) for p in row]])
        if "gmsh:physical" in read.cell_data:
            physical.extend(int(v) for v in read.cell_data["gmsh:physical"][k])
    return {
        "points": [[float(x) for x in p] for p in read.points],
        "cells": cells,
        "gmsh:physical": physical,
        "temperature": [float(x) for x in read.point_data["temperature"]],
    }


def main(argv):
    check = "--check" in argv
    OUT.mkdir(parents=True, exist_ok=True)
    differ = []
    for name, arguments in FIXTURES:
        path = OUT / name
        if not check:
            meshio.write(path, mesh(), **arguments)
        text = json.dumps(describe(path), indent=1) + "\n"
        target = path.with_suffix(path.suffix + ".json")
        if check:
            if not target.exists() or target.read_text() != text:
                differ.append(target)
        else:
            target.write_text(text)
    if differ:
        for target in differ:
            print(f"vtk-fixtures: {target} differs from what meshio {meshio.__version__} reads",
                  file=sys.stderr)
        return 1
    print(f"vtk-fixtures: {len(FIXTURES)} files {'agree' if check else 'written'} "
          f"(meshio {meshio.__version__})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
