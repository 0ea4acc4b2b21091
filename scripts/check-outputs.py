#!/usr/bin/env python3
"""Reads the outputs of `vem run` with meshio and VTK (independent readers) and checks them
against the run's own contact.csv: every VTU file of the collection results.pvd opens in both,
each interface dataset has a point per row of its contact table (contact.csv, or
contact_NNNN.csv of a load history's step) with the same values, and every body
file has its displacement, read alike by both, on as many cells in both (polyhedra, VTK type 42,
for a scene in space). Exits non-zero on any difference.

Usage: PYTHON scripts/check-outputs.py OUT_DIR   (PYTHON from scripts/install-vtu-check.sh)
"""
import csv
import pathlib
import sys
import xml.etree.ElementTree as ET

import meshio
import meshio.vtu._vtu as meshio_vtu
import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def _patched_parse_raw_binary(filename):
    """meshio 5.3.5's reader of raw appended VTU data, with one fix: it relabels each
    DataArray's offset in place (to the offset in its base64 copy) while it still looks arrays
    up by their raw offsets, so a later raw offset that equals an earlier array's new offset
    finds the wrong array ("cannot reshape", or a misread array). The files are valid (VTK and
    ParaView read them); here every array is looked up before any is relabelled."""
    import base64
    import re
    import zlib
    from xml.etree import ElementTree as ET

    raw = open(filename, "rb").read()
    start = re.search(re.compile(b'<AppendedData[^>]+(?:">)'), raw).end()
    stop = raw.find(b"</AppendedData>")
    root = ET.fromstring(raw[:start].decode() + raw[stop:].decode())
    data = raw[start:stop].split(b"_", 1)[1].rsplit(b"\n", 1)[0]
    dtype = meshio_vtu.vtu_to_numpy_type[root.get("header_type", "UInt32")].newbyteorder("<")
    root.find("AppendedData").set("encoding", "base64")
    by_offset = {}
    for tag in root.iter("DataArray"):
        if tag.get("offset") is not None:
            by_offset.setdefault(int(tag.get("offset")), []).append(tag)
    compressed = root.attrib.pop("compressor", None) is not None
    arrays, i = "", 0
    while i < len(data):
        for tag in by_offset[i]:
            tag.set("offset", str(len(arrays)))
        if compressed:
            blocks = int(numpy.frombuffer(data[i : i + dtype.itemsize], dtype)[0])
            header_bytes = (3 + blocks) * dtype.itemsize
            header = numpy.frombuffer(data[i : i + header_bytes], dtype)
            block, j = b"", 0
            for k in range(blocks):
                size = int(header[k + 3])
                block += zlib.decompress(data[i + header_bytes + j : i + header_bytes + j + size])
                j += size
            arrays += base64.b64encode(
                numpy.array([len(block)]).astype(dtype).tobytes() + block).decode()
            i += header_bytes + j
        else:
            size = int(numpy.frombuffer(data[i : i + dtype.itemsize], dtype)[0])
            arrays += base64.b64encode(data[i : i + size + dtype.itemsize]).decode()
            i += size + dtype.itemsize
    root.find("AppendedData").text = "_" + arrays
    return root


meshio_vtu._parse_raw_binary = _patched_parse_raw_binary

def _patched_polyhedron_cells_from_data(offsets, faces, faceoffsets, cell_data_raw):
    """meshio 5.3.5's reader of polyhedra (VTK type 42), with two fixes. It shapes every
    DataArray by its NumberOfComponents attribute, so the `faces`, `faceoffsets` and `offsets`
    streams, which VTK writes with NumberOfComponents="1" as any single-component array, come in
    as columns (n x 1) and its loop over them fails ("only integer scalar arrays can be converted
    to a scalar index"): they are flattened here. And it groups the cells into blocks by their
    number of vertices in order of first appearance but their cell data in increasing order of
    that number, so the data of a block can be another block's ("Incompatible cell data"): here
    both are grouped by the same key in the same (increasing) order. VTK and ParaView read the
    files as written."""
    offsets, faces, faceoffsets = (numpy.ravel(a) for a in (offsets, faces, faceoffsets))
    sizes = numpy.diff(numpy.hstack((0, offsets)))
    starts = numpy.append([0], faceoffsets[:-1])
    cells, cell_data = {}, {}
    for size in numpy.unique(sizes):
        items = numpy.where(sizes == size)[0]
        block = []
        for c in items:
            at, cell = starts[c] + 1, []
            for _ in range(int(faces[starts[c]])):
                n = int(faces[at])
                cell.append(numpy.array(faces[at + 1 : at + 1 + n], dtype=int))
                at += n + 1
            block.append(cell)
        cells[f"polyhedron{size}"] = block
        for name, values in cell_data_raw.items():
            cell_data.setdefault(name, []).append(values[items])
    return cells, cell_data


meshio_vtu._polyhedron_cells_from_data = _patched_polyhedron_cells_from_data


def vtk_read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        raise SystemExit(f"check-outputs: VTK reads no point from {path}")
    return grid


def main():
    out = pathlib.Path(sys.argv[1])
    datasets = [d.attrib for d in ET.parse(out / "results.pvd").getroot().iter("DataSet")]
    if not datasets:
        raise SystemExit("check-outputs: results.pvd lists no dataset")
    columns = ["initial_gap", "normal_jump", "normal_force", "pressure", "consistent_pressure"]
    for d in datasets:
        path = out / d["file"]
        mesh = meshio.read(path)
        grid = vtk_read(path)
        if len(mesh.points) != grid.GetNumberOfPoints():
            raise SystemExit(f"check-outputs: {path}: meshio and VTK disagree on the points")
        if d["name"] == "interface":
            # interface.vtu against contact.csv, interface_NNNN.vtu against contact_NNNN.csv.
            table = out / d["file"].replace("interface", "contact").replace(".vtu", ".csv")
            rows = list(csv.DictReader(open(table)))
            if len(mesh.points) != len(rows):
                raise SystemExit(f"check-outputs: {path}: {len(mesh.points)} points, "
                                 f"{len(rows)} rows in contact.csv")
            for name in columns:
                expected = numpy.array([float(r[name]) for r in rows])
                for reader, values in [("meshio", numpy.ravel(mesh.point_data[name])),
                                       ("VTK", vtk_to_numpy(grid.GetPointData().GetArray(name)))]:
                    if not numpy.array_equal(values, expected):
                        raise SystemExit(f"check-outputs: {path}: {reader} reads '{name}' "
                                         f"unlike {table.name}")
        elif "displacement" not in mesh.point_data:
            raise SystemExit(f"check-outputs: {path}: no displacement")
        else:
            by_vtk = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
            by_meshio = numpy.asarray(mesh.point_data["displacement"])
            if by_meshio.shape != by_vtk.shape or not numpy.array_equal(by_meshio, by_vtk):
                raise SystemExit(f"check-outputs: {path}: meshio and VTK read the displacement "
                                 "differently")
            cells = sum(len(block.data) for block in mesh.cells)
            if cells != grid.GetNumberOfCells():
                raise SystemExit(f"check-outputs: {path}: meshio reads {cells} cells, VTK "
                                 f"{grid.GetNumberOfCells()}")
            polyhedra = sum(1 for k in range(grid.GetNumberOfCells()) if grid.GetCellType(k) == 42)
            if polyhedra and (polyhedra != cells or by_vtk.shape[1] != 3):
                raise SystemExit(f"check-outputs: {path}: a body in space is all polyhedra "
                                 "with a displacement of 3 components")
    print(f"check-outputs: {len(datasets)} datasets of {out} agree "
          f"(VTK {vtk.vtkVersion.GetVTKVersion()}, meshio {meshio.__version__})")


if __name__ == "__main__":
    main()
