"""Scenes built in Python: the keys of a scene file (docs/scenes.md) as calls.

A :class:`SceneBuilder` holds the same dict that :func:`vemcontact.from_dict` reads, so a
scene built here is checked by the same code, with the same errors at the same key paths,
as a scene file::

    import vemcontact as vc

    s = vc.SceneBuilder(title="block on a line", solver=vc.solver("exact", tolerance=1e-13))
    block = s.add_body("block", vc.generated("voronoi", [[0, 0], [2, 1]], n=6, seed=3),
                       vc.isotropic(E=100.0, nu=0.3))
    block.dirichlet("left", x=0.0).traction("top", pressure=0.01)
    s.add_contact(block, "bottom", obstacle=vc.line([0, 0], [0, 1]))
    result = s.solve()
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Sequence, Union

from . import _native

Number = Union[int, float]
Value = Union[Number, str]  # a number or an expression of x, y, z, t
Curve = Sequence[Sequence[Number]]


def _keys(**keys: Any) -> Dict[str, Any]:
    """The keys given (those left at ``None`` are left out)."""
    return {k: v for k, v in keys.items() if v is not None}


# Meshes --------------------------------------------------------------------------------


def generated(
    family: str,
    rectangle: Optional[Sequence[Sequence[Number]]] = None,
    n: Optional[int] = None,
    seed: Optional[int] = None,
    *,
    box: Optional[Sequence[Sequence[Number]]] = None,
    parts: Optional[Sequence[Dict[str, Any]]] = None,
) -> Dict[str, Any]:
    """A generated mesh: ``family`` (``names()["mesh_families"]``: "quads", "triangles",
    "hexagons", "voronoi", ...) on ``rectangle = [[x0, y0], [x1, y1]]``, or a family of
    ``names()["mesh_families_3d"]`` ("hexahedra", "tetrahedra", "voronoi", ...) on ``box =
    [[x0, y0, z0], [x1, y1, z1]]``, with about ``n`` cells across (left out in the plane with
    ``accuracy`` or ``target_error``); ``parts`` cuts further boundary parts out by boxes
    (:func:`part_box`)."""
    return _keys(
        family=family,
        rectangle=None if rectangle is None else [list(p) for p in rectangle],
        box=None if box is None else [list(p) for p in box],
        n=n,
        seed=seed,
        parts=None if parts is None else list(parts),
    )


def part_box(name: str, box: Sequence[Sequence[Number]], of: Optional[str] = None) -> Dict[str, Any]:
    """A boundary part cut out of a mesh's boundary: the edges (faces in space) whose vertices
    all lie in ``box = [[x0, y0], [x1, y1]]`` (``[[x0, y0, z0], [x1, y1, z1]]``), among those
    of the part ``of`` when given (the key ``parts`` of a mesh)."""
    return _keys(name=name, of=of, box=[list(p) for p in box])


def inline(
    vertices: Any,
    polygons: Optional[Sequence[Sequence[int]]] = None,
    *,
    offsets: Optional[Sequence[int]] = None,
    connectivity: Optional[Sequence[int]] = None,
    polyhedra: Optional[Sequence[Sequence[Sequence[int]]]] = None,
    parts: Optional[Dict[str, Any]] = None,
    boxes: Optional[Sequence[Dict[str, Any]]] = None,
) -> Dict[str, Any]:
    """A mesh given inline, as a body's ``mesh`` in a scene: ``vertices`` (n x 2 with
    polygons, n x 3 with polyhedra; numpy arrays or lists) and the cells, either ``polygons``
    (vertex loops, counter-clockwise) or ``offsets`` with ``connectivity`` (polygon k is
    ``connectivity[offsets[k]:offsets[k + 1]]``), or ``polyhedra`` (each a list of face loops,
    outward). ``parts`` names boundary parts: ``{"bottom": edges}`` with edges as vertex pairs
    (k x 2) in the plane, ``{"left": faces}`` with faces as vertex loops in space; ``boxes``
    cuts further parts out by boxes (:func:`part_box`). The mesh is validated when the scene
    is built (or by :func:`vemcontact.mesh`): an error names the polygon and the vertex, at
    its key (``polygons[3]``)."""
    import numpy as np

    points = np.asarray(vertices, dtype=float)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise ValueError(f"vertices: an (n, 2) or (n, 3) array is expected, not shape {points.shape}")
    given = [polygons is not None, offsets is not None or connectivity is not None, polyhedra is not None]
    if sum(given) != 1:
        raise ValueError("give the cells as `polygons`, as `offsets` with `connectivity`, or as `polyhedra`")
    description: Dict[str, Any] = {"vertices": points.tolist()}
    if polyhedra is not None:
        description["polyhedra"] = [[[int(v) for v in face] for face in cell] for cell in polyhedra]
    elif polygons is not None:
        description["polygons"] = [[int(v) for v in polygon] for polygon in polygons]
    else:
        if offsets is None or connectivity is None:
            raise ValueError("`offsets` and `connectivity` go together")
        offsets = np.asarray(offsets, dtype=np.int64)
        connectivity = np.asarray(connectivity, dtype=np.int64)
        if offsets.ndim != 1 or len(offsets) < 1 or offsets[0] != 0 or offsets[-1] != len(connectivity) or np.any(np.diff(offsets) < 0):
            raise ValueError(
                "offsets: must start at 0, increase and end at len(connectivity) "
                f"= {len(connectivity)} (one entry per polygon plus one)"
            )
        description["polygons"] = [connectivity[a:b].tolist() for a, b in zip(offsets[:-1], offsets[1:])]
    if parts:
        key = "part_faces" if polyhedra is not None else "part_edges"
        if key == "part_edges":
            description[key] = {name: np.asarray(edges, dtype=np.int64).reshape(-1, 2).tolist() for name, edges in parts.items()}
        else:
            description[key] = {name: [[int(v) for v in face] for face in faces] for name, faces in parts.items()}
    if boxes:
        description["parts"] = list(boxes)
    return description


def mesh_file(path: Union[str, os.PathLike], part_names: Optional[Dict[int, str]] = None) -> Dict[str, Any]:
    """A mesh file (.msh, .vtu, .vtk, .txt, .poly), relative to the scene's base folder;
    ``part_names`` names the part numbers of a VTK file's line cells."""
    names = None if part_names is None else {str(k): v for k, v in part_names.items()}
    return _keys(file=os.fspath(path), part_names=names)


# Materials -----------------------------------------------------------------------------


def isotropic(E: Number, nu: Number, plane: str = "strain") -> Dict[str, Any]:
    """An isotropic material by Young's modulus and Poisson's ratio; ``plane`` is
    "strain" or "stress"."""
    return {"E": E, "nu": nu, "plane": plane}


def lame(lam: Number, mu: Number, plane: str = "strain") -> Dict[str, Any]:
    """An isotropic material by its Lamé parameters (``lambda``, ``mu``)."""
    return {"lambda": lam, "mu": mu, "plane": plane}


# Obstacles, laws, solvers --------------------------------------------------------------


def line(point: Sequence[Number], normal: Sequence[Number]) -> Dict[str, Any]:
    """A rigid half-plane bounded by the line through ``point``; ``normal`` points out of
    it, towards the body."""
    return {"line": {"point": list(point), "normal": list(normal)}}


def circle(centre: Sequence[Number], radius: Number) -> Dict[str, Any]:
    """A rigid disc; the body lies outside it."""
    return {"circle": {"centre": list(centre), "radius": radius}}


def polyline(points: Sequence[Sequence[Number]]) -> Dict[str, Any]:
    """A rigid polyline; the obstacle lies to the right of the direction of travel."""
    return {"polyline": [list(p) for p in points]}


def plane(point: Sequence[Number], normal: Sequence[Number]) -> Dict[str, Any]:
    """In space: a rigid half-space bounded by the plane through ``point``; ``normal`` points
    out of it, towards the body."""
    return {"plane": {"point": list(point), "normal": list(normal)}}


def sphere(centre: Sequence[Number], radius: Number) -> Dict[str, Any]:
    """In space: a rigid ball; the body lies outside it."""
    return {"sphere": {"centre": list(centre), "radius": radius}}


def law(name: str, **settings: Any) -> Union[str, Dict[str, Any]]:
    """A contact law by registry name with its settings: ``law("frictionless")``,
    ``law("tresca", friction_bound=0.05)``, ``law("coulomb", coefficient=0.3)``."""
    return dict(name=name, **settings) if settings else name


def solver(name: str, **settings: Any) -> Union[str, Dict[str, Any]]:
    """The contact solver by registry name with its settings: ``solver("condensed")``,
    ``solver("exact", tolerance=1e-12)``, ``solver("penalty", penalty={"factor": 1e4})``."""
    return dict(name=name, **settings) if settings else name


def element(name: str, **settings: Any) -> Union[str, Dict[str, Any]]:
    """An element by registry name with its settings: ``element("vem1-bbar")``,
    ``element("vem1", stabilisation="drecipe")``."""
    return dict(name=name, **settings) if settings else name


# Bodies and scenes ---------------------------------------------------------------------


class Body:
    """One body of a :class:`SceneBuilder`: its conditions are added by chained calls."""

    def __init__(self, description: Dict[str, Any]) -> None:
        self._d = description

    @property
    def name(self) -> str:
        """The body's name."""
        return self._d["name"]

    def dirichlet(
        self,
        part: str,
        x: Optional[Value] = None,
        y: Optional[Value] = None,
        curve: Optional[Curve] = None,
        z: Optional[Value] = None,
    ) -> "Body":
        """Prescribes ``u_x``, ``u_y`` and/or ``u_z`` (in space; numbers or expressions) on
        ``part``."""
        self._d.setdefault("dirichlet", []).append(_keys(part=part, x=x, y=y, z=z, curve=_curve(curve)))
        return self

    def traction(
        self,
        part: str,
        value: Optional[Sequence[Value]] = None,
        pressure: Optional[Number] = None,
        curve: Optional[Curve] = None,
    ) -> "Body":
        """A traction vector ``value = [gx, gy]`` or a normal ``pressure`` (positive
        compressive) on ``part``."""
        vector = None if value is None else list(value)
        self._d.setdefault("traction", []).append(
            _keys(part=part, value=vector, pressure=pressure, curve=_curve(curve))
        )
        return self

    def rigid_plate(
        self,
        part: str,
        resultant_x: Optional[Number] = None,
        resultant_y: Optional[Number] = None,
        curve: Optional[Curve] = None,
    ) -> "Body":
        """Moves ``part`` as a rigid plate that applies the given total force (force
        control)."""
        self._d.setdefault("rigid_plate", []).append(
            _keys(part=part, resultant_x=resultant_x, resultant_y=resultant_y, curve=_curve(curve))
        )
        return self

    def body_force(self, force: Sequence[Value], curve: Optional[Curve] = None) -> "Body":
        """A body force per unit area ``[fx, fy]`` (numbers or expressions)."""
        self._d["body_force"] = list(force)
        if curve is not None:
            self._d["body_force_curve"] = _curve(curve)
        return self

    def __repr__(self) -> str:
        return f"Body({self._d!r})"


def _curve(curve: Optional[Curve]) -> Optional[List[List[Number]]]:
    return None if curve is None else [list(p) for p in curve]


def _name(body: Union[str, Body]) -> str:
    return body.name if isinstance(body, Body) else body


class SceneBuilder:
    """A scene built call by call; :meth:`to_dict` is the dict of a scene file's keys,
    :meth:`build` checks it into a :class:`vemcontact.Scene`, :meth:`solve` solves it."""

    def __init__(
        self,
        title: Optional[str] = None,
        solver: Optional[Union[str, Dict[str, Any]]] = None,
        accuracy: Optional[str] = None,
        target_error: Optional[float] = None,
    ) -> None:
        self._d: Dict[str, Any] = _keys(
            title=title, solver=solver, accuracy=accuracy, target_error=target_error
        )
        self._bodies: List[Body] = []

    def add_body(
        self,
        name: str,
        mesh: Union[Dict[str, Any], "_native.Mesh"],
        material: Dict[str, Any],
        element: Optional[Union[str, Dict[str, Any]]] = None,
    ) -> Body:
        """Adds a body (see :func:`generated`, :func:`mesh_file`, :func:`inline`, a
        :class:`vemcontact.Mesh`, :func:`isotropic`) and returns it for its conditions."""
        if hasattr(mesh, "to_dict") and not isinstance(mesh, dict):
            mesh = mesh.to_dict()
        body = Body(_keys(name=name, mesh=mesh, material=material, element=element))
        self._d.setdefault("body", []).append(body._d)
        self._bodies.append(body)
        return body

    def add_contact(
        self,
        body: Union[str, Body],
        part: str,
        *,
        other_body: Optional[Union[str, Body]] = None,
        other_part: Optional[str] = None,
        obstacle: Optional[Dict[str, Any]] = None,
        law: Optional[Union[str, Dict[str, Any]]] = None,
        normal: Optional[str] = None,
        imposed_gap: Optional[Value] = None,
        max_distance: Optional[Number] = None,
        hertz_radius: Optional[Number] = None,
    ) -> "SceneBuilder":
        """A contact pair: ``part`` of ``body`` against ``other_part`` of ``other_body``
        or against a rigid ``obstacle`` (:func:`line`, :func:`circle`, :func:`polyline`)."""
        self._d.setdefault("contact", []).append(
            _keys(
                body=_name(body),
                part=part,
                other_body=None if other_body is None else _name(other_body),
                other_part=other_part,
                obstacle=obstacle,
                law=law,
                normal=normal,
                imposed_gap=imposed_gap,
                max_distance=max_distance,
                hertz=None if hertz_radius is None else {"radius": hertz_radius},
            )
        )
        return self

    def set_solver(self, name: str, **settings: Any) -> "SceneBuilder":
        """The contact solver of every pair (see :func:`solver`)."""
        self._d["solver"] = dict(name=name, **settings) if settings else name
        return self

    def set_history(
        self,
        steps: Optional[Sequence[Number]] = None,
        times: Optional[Sequence[Number]] = None,
        end: Optional[Number] = None,
        increments: Optional[int] = None,
    ) -> "SceneBuilder":
        """A load history: load factors ``steps``, or ``times``, or ``end`` with
        ``increments`` (then every condition follows its ``curve``)."""
        self._d["history"] = _keys(
            steps=None if steps is None else list(steps),
            times=None if times is None else list(times),
            end=end,
            increments=increments,
        )
        return self

    def set_output(
        self,
        magnification: Optional[Number] = None,
        width: Optional[Number] = None,
        length_unit: Optional[str] = None,
        stress_unit: Optional[str] = None,
        vtu_encoding: Optional[str] = None,
        files: Optional[Sequence[str]] = None,
    ) -> "SceneBuilder":
        """The `[output]` table (replaced as a whole): the pictures' displacement
        magnification, width in pixels and units; the encoding of the .vtu files ("binary",
        "compressed", "ascii") and the kinds of files written besides summary.json (a list of
        some of "vtu", "csv", "pictures")."""
        if isinstance(files, str):
            raise TypeError(f'files: give a list of kinds, e.g. ["{files}"], not the string {files!r}')
        self._d["output"] = _keys(
            magnification=magnification,
            width=width,
            length_unit=length_unit,
            stress_unit=stress_unit,
            vtu_encoding=vtu_encoding,
            files=None if files is None else list(files),
        )
        return self

    def to_dict(self) -> Dict[str, Any]:
        """The scene as the dict of a scene file's keys."""
        import copy

        return copy.deepcopy(self._d)

    def build(self, base: Optional[Union[str, os.PathLike]] = None) -> "_native.Scene":
        """The checked scene; mesh files are looked up from ``base`` (default: the current
        folder). Raises :class:`vemcontact.SceneError` at the key path at fault."""
        return _native.from_dict(self._d, None if base is None else os.fspath(base))

    def solve(self, base: Optional[Union[str, os.PathLike]] = None, memory_limit_gib: Optional[float] = None) -> "_native.Result":
        """Builds and solves (see :meth:`vemcontact.Scene.solve`)."""
        return self.build(base).solve(memory_limit_gib)

    def __repr__(self) -> str:
        return f"SceneBuilder({self._d!r})"
