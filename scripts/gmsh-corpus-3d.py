#!/usr/bin/env python3
"""Writes the corpus of 3D .msh files that vem-mesh's polyhedral reader is compared on with
Gmsh's own reader (crates/vem-mesh/tests/data/gmsh-corpus-3d). The files are committed; this
script is run by hand when the corpus changes, followed by scripts/gmsh-reference.py for the
expected JSON:

    target/gmsh-venv/bin/python scripts/gmsh-corpus-3d.py
    target/gmsh-venv/bin/python scripts/gmsh-reference.py crates/vem-mesh/tests/data/gmsh-corpus-3d

The corpus covers the four volume element types (tetrahedra, hexahedra, prisms, pyramids), MSH
4.1 and 2.2, ASCII and binary, node and element tags out of order and with gaps, physical
surfaces as boundary parts (names with spaces), a physical surface spanning two surfaces, and
unnamed geometry left out of the groups. Every model is the unit cube [0, 1]^3 (the hybrid one
split at x = 1/2), so the Rust test can check volumes and side areas.
"""
import pathlib
import random

import gmsh

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "crates" / "vem-mesh" / "tests" / "data" / "gmsh-corpus-3d"
SIDES = ["left", "right", "front", "back", "bottom", "top"]


def box_sides(volume):
    """The six sides of the box volume, in the order of SIDES, found by their centres."""
    targets = [(0, 0.5, 0.5), (1, 0.5, 0.5), (0.5, 0, 0.5), (0.5, 1, 0.5), (0.5, 0.5, 0),
               (0.5, 0.5, 1)]
    boundary = [abs(t) for _, t in gmsh.model.getBoundary([(3, volume)], oriented=False)]
    sides = []
    for target in targets:
        for surface in boundary:
            centre = gmsh.model.occ.getCenterOfMass(2, surface)
            if all(abs(c - t) < 1e-9 for c, t in zip(centre, target)):
                sides.append(surface)
                break
    return sides


def named_sides(sides, volumes):
    for k, (name, surface) in enumerate(zip(SIDES, sides)):
        gmsh.model.addPhysicalGroup(2, [surface], 11 + k, name)
    gmsh.model.addPhysicalGroup(3, volumes, 1, "body")


def tetrahedra():
    """The unit cube meshed by tetrahedra."""
    gmsh.model.add("tetrahedra")
    box = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    named_sides(box_sides(box), [box])
    gmsh.model.mesh.setSize(gmsh.model.getEntities(0), 0.6)
    gmsh.model.mesh.generate(3)


def hexahedra():
    """The unit cube as 3 x 3 x 3 transfinite hexahedra."""
    gmsh.model.add("hexahedra")
    box = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    for _, curve in gmsh.model.getEntities(1):
        gmsh.model.mesh.setTransfiniteCurve(curve, 4)
    for _, surface in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(surface)
        gmsh.model.mesh.setRecombine(2, surface)
    gmsh.model.mesh.setTransfiniteVolume(box)
    named_sides(box_sides(box), [box])
    gmsh.model.mesh.generate(3)


def prisms():
    """A unit square of triangles extruded in three layers: prisms. Bottom and top in one group
    named "bottom and top", the four lateral sides in "sides"."""
    gmsh.model.add("prisms")
    g = gmsh.model.geo
    p = [g.addPoint(x, y, 0, 0.4) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1)]]
    lines = [g.addLine(p[k], p[(k + 1) % 4]) for k in range(4)]
    square = g.addPlaneSurface([g.addCurveLoop(lines)])
    extruded = g.extrude([(2, square)], 0, 0, 1, [3], recombine=True)
    g.synchronize()
    top, volume = extruded[0][1], extruded[1][1]
    lateral = [tag for dim, tag in extruded[2:] if dim == 2]
    gmsh.model.addPhysicalGroup(2, [square, top], 5, "bottom and top")
    gmsh.model.addPhysicalGroup(2, lateral, 6, "sides")
    gmsh.model.addPhysicalGroup(3, [volume], 1, "body")
    gmsh.model.mesh.generate(3)


def hybrid():
    """The unit cube cut at x = 1/2: hexahedra on the left, tetrahedra on the right, pyramids
    where the tetrahedra meet the hexahedra's quadrangles."""
    gmsh.model.add("hybrid")
    occ = gmsh.model.occ
    left = occ.addBox(0, 0, 0, 0.5, 1, 1)
    right = occ.addBox(0.5, 0, 0, 0.5, 1, 1)
    occ.fragment([(3, left)], [(3, right)])
    occ.synchronize()
    left_surfaces = [abs(t) for _, t in gmsh.model.getBoundary([(3, left)], oriented=False)]
    left_curves = set()
    for surface in left_surfaces:
        for _, c in gmsh.model.getBoundary([(2, surface)], oriented=False):
            left_curves.add(abs(c))
    for curve in left_curves:
        gmsh.model.mesh.setTransfiniteCurve(curve, 3)
    for surface in left_surfaces:
        gmsh.model.mesh.setTransfiniteSurface(surface)
        gmsh.model.mesh.setRecombine(2, surface)
    gmsh.model.mesh.setTransfiniteVolume(left)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.35)
    # The outer sides: x = 0 of the left box, x = 1 of the right box, and the others split in two.
    boundary = set()
    for volume in (left, right):
        for _, t in gmsh.model.getBoundary([(3, volume)], oriented=False):
            boundary.add(abs(t))
    def at(axis, value):
        found = []
        for surface in sorted(boundary):
            xmin, ymin, zmin, xmax, ymax, zmax = gmsh.model.getBoundingBox(2, surface)
            lo, hi = [(xmin, xmax), (ymin, ymax), (zmin, zmax)][axis]
            if abs(lo - value) < 1e-6 and abs(hi - value) < 1e-6:
                found.append(surface)
        return found
    groups = [("x = 0", at(0, 0.0)), ("x = 1", at(0, 1.0)), ("y = 0", at(1, 0.0)),
              ("y = 1", at(1, 1.0)), ("z = 0", at(2, 0.0)), ("z = 1", at(2, 1.0))]
    for k, (name, surfaces) in enumerate(groups):
        gmsh.model.addPhysicalGroup(2, surfaces, 21 + k, name)
    gmsh.model.addPhysicalGroup(3, [left, right], 2, "body")
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 1e22)


def shuffle_tags(seed):
    """Gives nodes and elements new tags: a random order with gaps."""
    rng = random.Random(seed)
    tags, _, _ = gmsh.model.mesh.getNodes()
    new = rng.sample(range(1, 10 * len(tags)), len(tags))
    gmsh.model.mesh.renumberNodes([int(t) for t in tags], new)
    element_tags = []
    for dim, entity in gmsh.model.getEntities():
        _, etags, _ = gmsh.model.mesh.getElements(dim, entity)
        for block in etags:
            element_tags.extend(int(t) for t in block)
    new = rng.sample(range(1, 10 * len(element_tags)), len(element_tags))
    gmsh.model.mesh.renumberElements(element_tags, new)


def save(name, version, binary):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(str(OUT / name))


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    gmsh.initialize(["gmsh"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    tetrahedra()
    for version, tag in [(4.1, "41"), (2.2, "22")]:
        save(f"box_tetrahedra_{tag}.msh", version, False)
        save(f"box_tetrahedra_{tag}_binary.msh", version, True)
    shuffle_tags(5)
    save("box_tetrahedra_shuffled_41.msh", 4.1, False)
    gmsh.model.remove()
    hexahedra()
    save("box_hexahedra_41.msh", 4.1, False)
    save("box_hexahedra_22_binary.msh", 2.2, True)
    gmsh.model.remove()
    prisms()
    save("box_prisms_41_binary.msh", 4.1, True)
    save("box_prisms_22.msh", 2.2, False)
    gmsh.model.remove()
    hybrid()
    save("box_hybrid_41.msh", 4.1, False)
    save("box_hybrid_22.msh", 2.2, False)
    shuffle_tags(6)
    save("box_hybrid_shuffled_41_binary.msh", 4.1, True)
    gmsh.finalize()


if __name__ == "__main__":
    main()
