#!/usr/bin/env python3
"""Reads every .msh file of a corpus folder with Gmsh's own reader (its Python API) and writes,
beside each FILE.msh, FILE.json: the nodes, elements and physical groups as Gmsh reads them.

The Rust test crates/vem-mesh/tests/gmsh_corpus.rs compares vem-mesh's reader with these files.
Run it in the venv that scripts/install-gmsh.sh creates:

    target/gmsh-venv/bin/python scripts/gmsh-reference.py [--check] [FOLDER]

FOLDER defaults to crates/vem-mesh/tests/data/gmsh-corpus. With --check nothing is written: the
script exits 1 if any committed JSON differs from what Gmsh reads now.
"""
import json
import pathlib
import sys

import gmsh

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT = ROOT / "crates" / "vem-mesh" / "tests" / "data" / "gmsh-corpus"


def describe(path):
    """The nodes, elements and physical groups of one file, as Gmsh's API returns them."""
    gmsh.clear()
    gmsh.open(str(path))
    tags, coords, _ = gmsh.model.mesh.getNodes(-1, -1, False, False)
    nodes = sorted(
        [int(t), float(coords[3 * i]), float(coords[3 * i + 1]), float(coords[3 * i + 2])]
        for i, t in enumerate(tags)
    )
    elements = []
    for dim, entity in gmsh.model.getEntities():
        types, element_tags, node_tags = gmsh.model.mesh.getElements(dim, entity)
        for element_type, etags, enodes in zip(types, element_tags, node_tags):
            n = len(enodes) // max(len(etags), 1)
            for k, tag in enumerate(etags):
                elements.append(
                    [int(tag), int(element_type), int(dim), int(entity),
                     [int(v) for v in enodes[k * n:(k + 1) * n]]]
                )
    elements.sort()
    groups = []
    for dim, tag in gmsh.model.getPhysicalGroups():
        entities = sorted(int(e) for e in gmsh.model.getEntitiesForPhysicalGroup(dim, tag))
        groups.append([int(dim), int(tag), gmsh.model.getPhysicalName(dim, tag), entities])
    groups.sort()
    return {"nodes": nodes, "elements": elements, "physical_groups": groups}


def render(data):
    """JSON with one node, element or group per line (short diffs); floats as Python repr."""
    lines = ["{"]
    for i, key in enumerate(["nodes", "elements", "physical_groups"]):
        lines.append(f'  "{key}": [')
        rows = [json.dumps(row) for row in data[key]]
        lines.extend("    " + row + ("," if k + 1 < len(rows) else "") for k, row in enumerate(rows))
        lines.append("  ]" + ("," if i < 2 else ""))
    lines.append("}")
    return "\n".join(lines) + "\n"


def main(argv):
    check = "--check" in argv
    folders = [a for a in argv if a != "--check"]
    folder = pathlib.Path(folders[0]) if folders else DEFAULT
    files = sorted(folder.glob("*.msh"))
    if not files:
        print(f"gmsh-reference: no .msh files in {folder}", file=sys.stderr)
        return 1
    gmsh.initialize(["gmsh"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    differ = []
    try:
        for path in files:
            text = render(describe(path))
            target = path.with_suffix(".json")
            if check:
                if not target.exists() or target.read_text() != text:
                    differ.append(target)
            else:
                target.write_text(text)
    finally:
        gmsh.finalize()
    if differ:
        for target in differ:
            print(f"gmsh-reference: {target} differs from what Gmsh {gmsh.__version__} reads; "
                  "regenerate with scripts/gmsh-reference.py", file=sys.stderr)
        return 1
    print(f"gmsh-reference: {len(files)} files {'agree' if check else 'written'} "
          f"(Gmsh {gmsh.__version__})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
