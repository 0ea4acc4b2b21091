#!/usr/bin/env python3
"""Reads every FILE.vtu of a folder with VTK's own XML reader (vtkXMLUnstructuredGridReader) and
with meshio, and compares points, cells and arrays with FILE.json written beside it by
vem-mesh (crates/vem-mesh/examples/vtu_samples.rs): values bit for bit, cell types, array types
and numbers of components. Files whose JSON says "meshio": false (poly-lines, polyhedra: meshio
does not read them) are checked with VTK only; where the JSON gives a "volume", VTK's own cell
volumes (vtkCellSizeFilter) must be positive and add up to it (to "volume_tolerance", relative,
1e-10 by default). A .pvd file in the folder is
checked too: every dataset it names exists and VTK reads it.

    cargo run --release -p vem-mesh --example vtu_samples -- target/vtu-check
    "$(scripts/install-vtu-check.sh | tail -n 1)" scripts/check-vtu.py target/vtu-check

Exits 1 on any difference, naming the file, the array and the first differing entry.
"""
import json
import pathlib
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy

VTK_TYPE_NAMES = {
    vtk.VTK_DOUBLE: "Float64",
    vtk.VTK_INT: "Int32",
    vtk.VTK_LONG_LONG: "Int64",
    vtk.VTK_ID_TYPE: "Int64",
    vtk.VTK_UNSIGNED_CHAR: "UInt8",
}
if hasattr(vtk, "VTK_TYPE_INT64"):
    VTK_TYPE_NAMES[vtk.VTK_TYPE_INT64] = "Int64"
MESHIO_TYPES = {1: "vertex", 3: "line", 5: "triangle", 7: "polygon", 9: "quad", 10: "tetra"}
NUMPY_TYPE_NAMES = {"float64": "Float64", "int32": "Int32", "int64": "Int64", "uint8": "UInt8"}


class Mismatch(Exception):
    pass


def same(what, expected, actual):
    """Exact equality of two arrays of numbers (floats bit for bit)."""
    expected = numpy.asarray(expected)
    actual = numpy.asarray(actual).reshape(expected.shape) if numpy.asarray(actual).size == expected.size else numpy.asarray(actual)
    if expected.shape != actual.shape:
        raise Mismatch(f"{what}: shape {actual.shape}, expected {expected.shape}")
    if expected.dtype.kind == "f" or actual.dtype.kind == "f":
        equal = numpy.array_equal(expected.astype(numpy.float64).view(numpy.int64),
                                  actual.astype(numpy.float64).view(numpy.int64))
    else:
        equal = numpy.array_equal(expected.astype(numpy.int64), actual.astype(numpy.int64))
    if not equal:
        flat_e, flat_a = expected.ravel(), actual.ravel()
        k = next(i for i in range(flat_e.size) if not (flat_e[i] == flat_a[i]))
        raise Mismatch(f"{what}: entry {k} is {flat_a[k]!r}, expected {flat_e[k]!r}")


def check_vtk(path, expected):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise Mismatch(f"VTK could not read it (error code {reader.GetErrorCode()})")
    grid = reader.GetOutput()
    n_points = len(expected["points"])
    if grid.GetNumberOfPoints() != n_points:
        raise Mismatch(f"VTK: {grid.GetNumberOfPoints()} points, expected {n_points}")
    if n_points:
        same("VTK: points", numpy.array(expected["points"], dtype=float),
             vtk_to_numpy(grid.GetPoints().GetData()))
    cells = grid.GetCells()
    same("VTK: connectivity", expected["connectivity"], vtk_to_numpy(cells.GetConnectivityArray()))
    same("VTK: offsets", expected["offsets"], vtk_to_numpy(cells.GetOffsetsArray()))
    types = grid.GetCellTypes() if hasattr(grid, "GetCellTypes") else None
    if not isinstance(types, vtk.vtkDataArray):
        types = grid.GetCellTypesArray()
    same("VTK: types", expected["types"], vtk_to_numpy(types))
    for c, t in enumerate(expected["types"]):
        if t == 42:
            # The faces of a polyhedron, as VTK hands them out: a face stream.
            ids = vtk.vtkIdList()
            grid.GetFaceStream(c, ids)
            stream = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
            start = 0 if c == 0 else max([o for o in expected["face_offsets"][:c] if o >= 0], default=0)
            same(f"VTK: faces of cell {c}", expected["faces"][start:expected["face_offsets"][c]], stream)
    if expected.get("volume") is not None:
        # VTK's own cell volumes (its polyhedra triangulate their faces themselves).
        sizes = vtk.vtkCellSizeFilter()
        sizes.SetInputData(grid)
        sizes.ComputeVertexCountOff()
        sizes.ComputeLengthOff()
        sizes.ComputeAreaOff()
        sizes.ComputeVolumeOn()
        sizes.Update()
        volumes = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
        if not (volumes > 0).all():
            raise Mismatch(f"VTK: cell {int(numpy.argmin(volumes))} has volume {volumes.min()!r}")
        tolerance = expected.get("volume_tolerance", 1e-10)
        if abs(volumes.sum() - expected["volume"]) > tolerance * expected["volume"]:
            raise Mismatch(f"VTK: the cells' volumes add up to {volumes.sum()!r}, "
                           f"expected {expected['volume']!r}")
    for group, data in [("point_data", grid.GetPointData()), ("cell_data", grid.GetCellData())]:
        for array in expected[group]:
            found = data.GetArray(array["name"])
            if found is None:
                raise Mismatch(f"VTK: no {group} array '{array['name']}'")
            type_name = VTK_TYPE_NAMES.get(found.GetDataType(), found.GetDataTypeAsString())
            if type_name != array["type"]:
                raise Mismatch(f"VTK: {group} '{array['name']}' is {type_name}, expected {array['type']}")
            if found.GetNumberOfComponents() != array["components"]:
                raise Mismatch(f"VTK: {group} '{array['name']}' has {found.GetNumberOfComponents()} "
                               f"components, expected {array['components']}")
            same(f"VTK: {group} '{array['name']}'", array["values"], vtk_to_numpy(found).ravel())


def check_meshio(path, expected):
    mesh = meshio.read(path)
    same("meshio: points", numpy.array(expected["points"], dtype=float).reshape(-1, 3), mesh.points)
    # meshio groups consecutive cells of a type (polygons by their number of points).
    cells = []
    for block in mesh.cells:
        for row in block.data:
            cells.append((block.type, list(row)))
    offsets, connectivity = expected["offsets"], expected["connectivity"]
    wanted = [(MESHIO_TYPES[t], connectivity[offsets[c]:offsets[c + 1]])
              for c, t in enumerate(expected["types"])]
    for c, (ours, theirs) in enumerate(zip(wanted, cells)):
        if ours[0] != theirs[0] and not (ours[0] == "polygon" and theirs[0].startswith("polygon")):
            raise Mismatch(f"meshio: cell {c} is a {theirs[0]}, expected a {ours[0]}")
        same(f"meshio: cell {c}", ours[1], theirs[1])
    if len(cells) != len(wanted):
        raise Mismatch(f"meshio: {len(cells)} cells, expected {len(wanted)}")
    for group, data in [("point_data", mesh.point_data), ("cell_data", mesh.cell_data)]:
        for array in expected[group]:
            if array["name"] not in data:
                raise Mismatch(f"meshio: no {group} array '{array['name']}'")
            values = data[array["name"]]
            if group == "cell_data":
                values = numpy.concatenate([numpy.asarray(v) for v in values])
            values = numpy.asarray(values)
            type_name = NUMPY_TYPE_NAMES.get(str(values.dtype), str(values.dtype))
            if type_name != array["type"]:
                raise Mismatch(f"meshio: {group} '{array['name']}' is {type_name}, expected {array['type']}")
            components = 1 if values.ndim == 1 else values.shape[1]
            if components != array["components"]:
                raise Mismatch(f"meshio: {group} '{array['name']}' has {components} components, "
                               f"expected {array['components']}")
            same(f"meshio: {group} '{array['name']}'", array["values"], values.ravel())


def check_pvd(path):
    root = ET.parse(path).getroot()
    datasets = root.findall("./Collection/DataSet")
    if not datasets:
        raise Mismatch("no datasets")
    for d in datasets:
        target = path.parent / d.attrib["file"]
        if not target.exists():
            raise Mismatch(f"dataset '{d.attrib['file']}' does not exist")
        float(d.attrib["timestep"])
        int(d.attrib["part"])
    return len(datasets)


def main(argv):
    folder = pathlib.Path(argv[0]) if argv else pathlib.Path("target/vtu-check")
    files = sorted(folder.glob("*.vtu"))
    if not files:
        print(f"check-vtu: no .vtu files in {folder}", file=sys.stderr)
        return 1
    failed = 0
    checked = 0
    for path in files:
        description = path.with_suffix(".json")
        if not description.exists():
            print(f"check-vtu: {path}: no {description.name} beside it", file=sys.stderr)
            failed += 1
            continue
        expected = json.loads(description.read_text())
        try:
            check_vtk(path, expected)
            if expected["meshio"]:
                check_meshio(path, expected)
            checked += 1
        except Mismatch as e:
            print(f"check-vtu: {path}: {e}", file=sys.stderr)
            failed += 1
    for path in sorted(folder.glob("*.pvd")):
        try:
            check_pvd(path)
        except (Mismatch, ET.ParseError, KeyError, ValueError) as e:
            print(f"check-vtu: {path}: {e}", file=sys.stderr)
            failed += 1
    print(f"check-vtu: {checked} passed, {failed} failed (VTK {vtk.vtkVersion.GetVTKVersion()}, "
          f"meshio {meshio.__version__})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
