"""Meshes to and from meshio (an optional dependency: ``pip install meshio``).

A mesh in the plane goes to meshio as its polygons ("triangle", "quad" or "polygon" blocks,
one block per run of cells with the same number of vertices, so that the order of the cells
is kept) with ``z = 0`` points; its boundary parts as "line" blocks named by ``cell_sets``. A
mesh in space goes as "polyhedron" blocks (each cell a list of outward face loops), its parts
as "polygon"/"triangle"/"quad" face blocks named by ``cell_sets``. From meshio, standard
volume cells (tetra, hexahedron, wedge, pyramid) become polyhedra whose faces are oriented
outward, and boundary parts are read from ``cell_sets`` or Gmsh's physical groups
(``cell_data["gmsh:physical"]`` with ``field_data``).
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence

import numpy as np

#: Faces (vertex loops, VTK numbering) of the standard volume cells; their orientation is
#: fixed afterwards (outward, by the cell's centroid).
_VOLUME_FACES = {
    "tetra": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    "hexahedron": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
    "wedge": [[0, 2, 1], [3, 4, 5], [0, 1, 4, 3], [1, 2, 5, 4], [2, 0, 3, 5]],
    "pyramid": [[0, 3, 2, 1], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
}
_SURFACE_TYPES = ("triangle", "quad", "polygon")


def _meshio():
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            "vemcontact's meshio conversion needs the package meshio: pip install meshio"
        ) from e
    return meshio


def _blocks_by_size(cells: Sequence[Any], name_of) -> List[tuple]:
    """Consecutive runs of cells with the same size, as (type, data) blocks."""
    blocks: List[tuple] = []
    for cell in cells:
        size = len(cell)
        if blocks and blocks[-1][0] == name_of(size) and blocks[-1][2] == size:
            blocks[-1][1].append(cell)
        else:
            blocks.append((name_of(size), [cell], size))
    return [(kind, data) for kind, data, _ in blocks]


def _polygon_type(size: int) -> str:
    return {3: "triangle", 4: "quad"}.get(size, "polygon")


def mesh_to_meshio(mesh, point_data=None, cell_data=None):
    """``mesh`` (a :class:`vemcontact.Mesh`) as a ``meshio.Mesh``; ``point_data`` and
    ``cell_data`` (per cell of the mesh) are attached to its cell blocks."""
    meshio = _meshio()
    vertices = np.asarray(mesh.vertices)
    if mesh.dimension == 2:
        points = np.column_stack([vertices, np.zeros(len(vertices))])
        cells = [np.asarray(c, dtype=np.int64) for c in mesh.cells]
        blocks = [(kind, np.array(data, dtype=np.int64)) for kind, data in _blocks_by_size(cells, _polygon_type)]
        part_blocks = [("line", np.asarray(edges, dtype=np.int64).reshape(-1, 2)) for edges in mesh.parts.values()]
    else:
        points = vertices
        cells = [[np.asarray(f, dtype=np.int64) for f in cell] for cell in mesh.cells]
        sizes = [len(np.unique(np.concatenate(cell))) for cell in cells]
        blocks = []
        for cell, size in zip(cells, sizes):
            kind = f"polyhedron{size}"
            if blocks and blocks[-1][0] == kind:
                blocks[-1][1].append(cell)
            else:
                blocks.append((kind, [cell]))
        part_blocks = []
        for faces in mesh.parts.values():
            faces = [np.asarray(f, dtype=np.int64) for f in faces]
            sizes = {len(f) for f in faces}
            if len(sizes) == 1:
                part_blocks.append((_polygon_type(sizes.pop()), np.array(faces)))
            else:
                part_blocks.append(("polygon", faces))
    n_blocks = len(blocks)
    cell_sets = {}
    for k, name in enumerate(mesh.parts):
        sets = [np.zeros(0, dtype=np.int64)] * (n_blocks + len(part_blocks))
        sets[n_blocks + k] = np.arange(len(part_blocks[k][1]), dtype=np.int64)
        cell_sets[name] = sets
    data = {}
    for name, values in (cell_data or {}).items():
        values = np.asarray(values)
        per_block = []
        start = 0
        for _, block in blocks:
            per_block.append(values[start : start + len(block)])
            start += len(block)
        for _, block in part_blocks:
            per_block.append(np.full((len(block),) + values.shape[1:], np.nan))
        data[name] = per_block
    return meshio.Mesh(
        points,
        blocks + part_blocks,
        point_data=dict(point_data or {}),
        cell_data=data,
        cell_sets=cell_sets,
    )


def body_to_meshio(body):
    """A solved body (:class:`vemcontact.BodyResult`) as a ``meshio.Mesh``: the mesh solved
    with the point data ``displacement`` and the cell data ``stress`` (m x 3 x 3 flattened to
    m x 9) and ``von_mises``."""
    displacement = np.asarray(body.displacement)
    if body.dimension == 2:
        displacement = np.column_stack([displacement, np.zeros(len(displacement))])
    stress = np.asarray(body.stress).reshape(-1, 9)
    return mesh_to_meshio(
        body.mesh,
        point_data={"displacement": displacement},
        cell_data={"stress": stress, "von_mises": np.asarray(body.von_mises)},
    )


def _outward(points: np.ndarray, faces: List[List[int]]) -> List[List[int]]:
    """The faces of a convex cell oriented outward (away from its centroid)."""
    centre = points[np.unique(np.concatenate(faces))].mean(axis=0)
    oriented = []
    for face in faces:
        p = points[face]
        normal = np.zeros(3)
        for i in range(len(face)):
            normal += np.cross(p[i], p[(i + 1) % len(face)])
        if np.dot(normal, p.mean(axis=0) - centre) < 0:
            face = face[::-1]
        oriented.append([int(v) for v in face])
    return oriented


def from_meshio(mesh, parts: Optional[Dict[str, Any]] = None, dimension: Optional[int] = None):
    """A :class:`vemcontact.Mesh` from a ``meshio.Mesh`` (read from any format meshio reads):
    its volume cells (tetra, hexahedron, wedge, pyramid, polyhedron) make a mesh in space,
    else its surface cells (triangle, quad, polygon) a mesh in the plane (points with z = 0,
    or two coordinates). Boundary parts come from ``cell_sets`` and Gmsh's physical groups
    over the boundary cells (lines in the plane, faces in space), or from ``parts`` (name ->
    edges or faces). The mesh is validated by the library: errors name the cell and the
    vertex (:class:`vemcontact.SceneError`)."""
    from . import _native
    from .builder import inline

    points = np.asarray(mesh.points, dtype=float)
    kinds = [block.type for block in mesh.cells]
    volume = any(k in _VOLUME_FACES or k.startswith("polyhedron") for k in kinds)
    if dimension is None:
        dimension = 3 if volume else 2
    if dimension == 2:
        if points.shape[1] == 3:
            if np.any(points[:, 2] != points[0, 2]):
                raise ValueError("a mesh in the plane needs points with one z (its surface cells are not planar)")
            points = points[:, :2]
        cell_kinds = _SURFACE_TYPES
        boundary_kinds = ("line",)
    else:
        cell_kinds = tuple(_VOLUME_FACES)
        boundary_kinds = _SURFACE_TYPES
    cells: List[Any] = []
    found_parts: Dict[str, List[Any]] = {}
    boundary_of_block: Dict[int, List[Any]] = {}
    for b, block in enumerate(mesh.cells):
        if block.type in cell_kinds and dimension == 2:
            cells.extend([list(map(int, c)) for c in block.data])
        elif dimension == 3 and (block.type in cell_kinds or block.type.startswith("polyhedron")):
            if block.type.startswith("polyhedron"):
                cells.extend([[list(map(int, f)) for f in cell] for cell in block.data])
            else:
                faces = _VOLUME_FACES[block.type]
                for c in np.asarray(block.data):
                    cells.append(_outward(points, [[int(c[i]) for i in face] for face in faces]))
        elif block.type in boundary_kinds:
            boundary_of_block[b] = [list(map(int, c)) for c in block.data]
    for name, sets in (mesh.cell_sets or {}).items():
        for b, indices in enumerate(sets):
            if b in boundary_of_block and indices is not None and len(indices) > 0:
                found_parts.setdefault(name, []).extend(boundary_of_block[b][int(i)] for i in indices)
    physical = (mesh.cell_data or {}).get("gmsh:physical")
    if physical is not None and mesh.field_data:
        names = {int(tag): name for name, (tag, dim) in ((n, v[:2]) for n, v in mesh.field_data.items())}
        for b, tags in enumerate(physical):
            if b not in boundary_of_block:
                continue
            for cell, tag in zip(boundary_of_block[b], tags):
                if int(tag) in names:
                    found_parts.setdefault(names[int(tag)], []).append(cell)
    if parts is not None:
        found_parts.update(parts)
    if dimension == 2:
        description = inline(points, polygons=cells, parts=found_parts or None)
    else:
        description = inline(points, polyhedra=cells, parts=found_parts or None)
    return _native.mesh(description)
