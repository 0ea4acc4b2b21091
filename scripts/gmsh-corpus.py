#!/usr/bin/env python3
"""Writes the corpus of .msh files that vem-mesh's reader is compared on with Gmsh's own reader
(crates/vem-mesh/tests/data/gmsh-corpus). The files are committed; this script is run by hand
when the corpus changes, followed by scripts/gmsh-reference.py for the expected JSON:

    target/gmsh-venv/bin/python scripts/gmsh-corpus.py
    target/gmsh-venv/bin/python scripts/gmsh-reference.py

The corpus covers MSH 4.1 and 2.2, ASCII and binary, node and element tags out of order and with
gaps, several node and element blocks in any order, physical names (with spaces), mixed triangles
and quadrangles, and a file without physical groups.
"""
import pathlib
import random
import struct

import gmsh

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "crates" / "vem-mesh" / "tests" / "data" / "gmsh-corpus"


def square(size=0.3):
    """The unit square with its four sides and its surface as named physical groups."""
    gmsh.model.add("square")
    occ = gmsh.model.geo
    points = [occ.addPoint(x, y, 0, size) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1)]]
    lines = [occ.addLine(points[k], points[(k + 1) % 4]) for k in range(4)]
    surface = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    occ.synchronize()
    for name, line, tag in zip(["bottom", "right", "top", "left"], lines, [11, 12, 13, 14]):
        gmsh.model.addPhysicalGroup(1, [line], tag, name)
    gmsh.model.addPhysicalGroup(2, [surface], 21, "body")
    gmsh.model.mesh.generate(2)


def mixed():
    """Two surfaces side by side: transfinite quadrangles and triangles; names with spaces."""
    gmsh.model.add("mixed")
    g = gmsh.model.geo
    p = [g.addPoint(x, y, 0, 0.35) for x, y in [(0, 0), (0.5, 0), (1, 0), (1, 1), (0.5, 1), (0, 1)]]
    bottom_left, bottom_right = g.addLine(p[0], p[1]), g.addLine(p[1], p[2])
    right = g.addLine(p[2], p[3])
    top_right, top_left = g.addLine(p[3], p[4]), g.addLine(p[4], p[5])
    left, middle = g.addLine(p[5], p[0]), g.addLine(p[1], p[4])
    quads = g.addPlaneSurface([g.addCurveLoop([bottom_left, middle, top_left, left])])
    triangles = g.addPlaneSurface([g.addCurveLoop([bottom_right, right, top_right, -middle])])
    for curve, n in [(bottom_left, 3), (top_left, 3), (middle, 5), (left, 5)]:
        g.mesh.setTransfiniteCurve(curve, n)
    g.mesh.setTransfiniteSurface(quads)
    g.mesh.setRecombine(2, quads)
    probe = g.addPoint(2, 0.5, 0)
    g.synchronize()
    gmsh.model.addPhysicalGroup(1, [bottom_left, bottom_right], 5, "contact zone")
    gmsh.model.addPhysicalGroup(1, [left], 7, "left side")
    gmsh.model.addPhysicalGroup(0, [probe], 3, "probe")
    gmsh.model.addPhysicalGroup(2, [quads, triangles], 9, "body")
    gmsh.model.mesh.generate(2)


def plain():
    """The unit disc without physical groups: Gmsh saves every element."""
    gmsh.model.add("plain")
    gmsh.model.occ.addDisk(0, 0, 0, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.4)
    gmsh.model.mesh.generate(2)
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


def reverse_blocks(source, target):
    """Rewrites an MSH 4.1 ASCII file with its node and element blocks in reverse order and the
    nodes of each block in reverse order (tags out of order inside a block)."""
    lines = (OUT / source).read_text().splitlines()
    out = []
    i = 0
    while i < len(lines):
        line = lines[i]
        out.append(line)
        i += 1
        if line not in ("$Nodes", "$Elements"):
            continue
        header = lines[i]
        out.append(header)
        i += 1
        n_blocks = int(header.split()[0])
        blocks = []
        for _ in range(n_blocks):
            block_header = lines[i].split()
            count = int(block_header[3])
            i += 1
            if line == "$Nodes":
                tags = lines[i:i + count]
                coords = lines[i + count:i + 2 * count]
                i += 2 * count
                body = tags[::-1] + coords[::-1]
            else:
                body = lines[i:i + count][::-1]
                i += count
            blocks.append([" ".join(block_header)] + body)
        for block in reversed(blocks):
            out.extend(block)
    (OUT / target).write_text("\n".join(out) + "\n")


def shuffle_v2(source, target, seed):
    """Rewrites an MSH 2.2 ASCII file with node and element tags out of order and with gaps, and
    its nodes and elements listed in a random order (Gmsh's MSH 2 writer always numbers them
    1, 2, ...). Writes TARGET.msh (ASCII) and TARGET_binary.msh (binary, one element per group)."""
    rng = random.Random(seed)
    lines = (OUT / source).read_text().splitlines()
    head = lines[:lines.index("$Nodes")]
    nodes_at = lines.index("$Nodes")
    n_nodes = int(lines[nodes_at + 1])
    nodes = [line.split() for line in lines[nodes_at + 2:nodes_at + 2 + n_nodes]]
    elements_at = lines.index("$Elements")
    n_elements = int(lines[elements_at + 1])
    elements = [line.split() for line in lines[elements_at + 2:elements_at + 2 + n_elements]]
    node_tag = dict(zip([n[0] for n in nodes],
                        map(str, rng.sample(range(1, 10 * n_nodes), n_nodes))))
    element_tag = map(str, rng.sample(range(1, 10 * n_elements), n_elements))
    nodes = [[node_tag[n[0]]] + n[1:] for n in nodes]
    renamed = []
    for e, tag in zip(elements, element_tag):
        n_tags = int(e[2])
        renamed.append([tag] + e[1:3 + n_tags] + [node_tag[v] for v in e[3 + n_tags:]])
    rng.shuffle(nodes)
    rng.shuffle(renamed)
    text = head + ["$Nodes", str(n_nodes)] + [" ".join(n) for n in nodes] + ["$EndNodes"]
    text += ["$Elements", str(n_elements)] + [" ".join(e) for e in renamed] + ["$EndElements"]
    (OUT / f"{target}.msh").write_text("\n".join(text) + "\n")
    binary = bytearray()
    for line in head:
        binary += (line.replace("2.2 0 8", "2.2 1 8") + "\n").encode()
        if line.startswith("2.2 "):
            binary += struct.pack("<i", 1) + b"\n"
    binary += f"$Nodes\n{n_nodes}\n".encode()
    for n in nodes:
        binary += struct.pack("<iddd", int(n[0]), *map(float, n[1:4]))
    binary += f"\n$EndNodes\n$Elements\n{n_elements}\n".encode()
    for e in renamed:
        n_tags = int(e[2])
        binary += struct.pack("<iii", int(e[1]), 1, n_tags)
        binary += struct.pack(f"<{len(e) - 2}i", int(e[0]), *map(int, e[3:]))
    binary += b"\n$EndElements\n"
    (OUT / f"{target}_binary.msh").write_bytes(bytes(binary))


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    gmsh.initialize(["gmsh"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    square()
    for version, tag in [(4.1, "41"), (2.2, "22")]:
        save(f"square_{tag}.msh", version, False)
        save(f"square_{tag}_binary.msh", version, True)
    shuffle_tags(1)
    save("square_shuffled_41.msh", 4.1, False)
    save("square_shuffled_41_binary.msh", 4.1, True)
    gmsh.model.remove()
    mixed()
    save("mixed_41.msh", 4.1, False)
    save("mixed_22.msh", 2.2, False)
    save("mixed_22_binary.msh", 2.2, True)
    shuffle_tags(2)
    save("mixed_shuffled_41_binary.msh", 4.1, True)
    gmsh.model.remove()
    plain()
    save("plain_41.msh", 4.1, False)
    save("plain_22.msh", 2.2, False)
    gmsh.finalize()
    reverse_blocks("square_shuffled_41.msh", "square_reversed_blocks_41.msh")
    reverse_blocks("mixed_41.msh", "mixed_reversed_blocks_41.msh")
    shuffle_v2("square_22.msh", "square_shuffled_22", 3)
    shuffle_v2("mixed_22.msh", "mixed_shuffled_22", 4)


if __name__ == "__main__":
    main()
