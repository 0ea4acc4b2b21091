#!/usr/bin/env python3
"""Reads the outputs of `vem run` with meshio and VTK (independent readers) and checks them
against the run's own contact.csv: every VTU file of the collection results.pvd opens in both,
each interface dataset has a point per row of its contact table (contact.csv, or
contact_NNNN.csv of a load history's step) with the same values, and every body
file has its displacement. Exits non-zero on any difference.

Usage: PYTHON scripts/check-outputs.py OUT_DIR   (PYTHON from scripts/install-vtu-check.sh)
"""
import csv
import pathlib
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy


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
    print(f"check-outputs: {len(datasets)} datasets of {out} agree "
          f"(VTK {vtk.vtkVersion.GetVTKVersion()}, meshio {meshio.__version__})")


if __name__ == "__main__":
    main()
