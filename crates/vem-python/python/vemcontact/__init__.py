"""Contact of elastic bodies with the lowest-order virtual element method.

The package reads the scenes of the ``vem`` command (docs/scenes.md) from a TOML file, a
TOML text or a Python dict, or builds them call by call (:class:`SceneBuilder`); solves
them with the library (the GIL released); and gives the results as numpy arrays::

    import vemcontact as vc

    result = vc.load("crates/vem-cli/scenes/hertz.toml").solve()
    pair = result.pairs[0]
    print(pair.pressure.max(), result.report["iterations"])
    result.write("out/hertz")  # the vem command's VTU, CSV, SVG and JSON files

Meshes come from numpy arrays (:func:`inline`), the project's generators (:func:`generate`)
or meshio (:func:`from_meshio`); :func:`names` lists the registries' names; the convergence
and trade-off studies run from here (:func:`convergence_study`, :func:`tradeoff_study`).
Ctrl-C interrupts a solve (``KeyboardInterrupt``).

Errors are :class:`SceneError` (with the key path, and the file, line and column of a
scene file), :class:`SolveError` and :class:`OutputError`; the warnings of a run are
issued as :class:`SceneWarning` and listed in ``Result.warnings``.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Optional, Union

from . import _native
from ._errors import OutputError, SceneError, SceneWarning, SolveError
from ._native import BodyResult, ContactPair, Mesh, Result, Scene, Step
from ._meshio import from_meshio
from .builder import (
    Body,
    SceneBuilder,
    circle,
    element,
    generated,
    inline,
    isotropic,
    lame,
    law,
    line,
    mesh_file,
    part_box,
    plane,
    polyline,
    sphere,
    solver,
)
from .studies import convergence_study, convergence_plan, tradeoff_study

__all__ = [
    "Body",
    "BodyResult",
    "ContactPair",
    "Mesh",
    "OutputError",
    "Result",
    "Scene",
    "SceneBuilder",
    "SceneError",
    "SceneWarning",
    "SolveError",
    "Step",
    "accuracy_presets",
    "circle",
    "convergence_plan",
    "convergence_study",
    "element",
    "elements",
    "from_dict",
    "from_meshio",
    "generate",
    "generated",
    "inline",
    "isotropic",
    "lame",
    "law",
    "line",
    "load",
    "loads",
    "mesh",
    "mesh_file",
    "names",
    "part_box",
    "plane",
    "polyline",
    "sphere",
    "solve",
    "solver",
    "solvers",
    "tradeoff_study",
]


def load(path: Union[str, os.PathLike]) -> Scene:
    """Reads and checks the scene file (TOML) at ``path``; mesh files are relative to
    its folder. Raises :class:`SceneError` with ``file``, ``line``, ``column`` and
    ``key_path``."""
    return _native.load(os.fspath(path))


def loads(text: str, path: Optional[Union[str, os.PathLike]] = None) -> Scene:
    """Reads and checks a scene from TOML text; ``path`` names it in errors and its
    folder is where mesh files are looked up."""
    return _native.loads(text, None if path is None else os.fspath(path))


def from_dict(scene: Mapping[str, Any], base: Optional[Union[str, os.PathLike]] = None) -> Scene:
    """Reads and checks a scene from a dict of a scene file's keys (lists, numbers,
    strings; numpy arrays and paths are taken too). Raises :class:`SceneError` naming the
    key path (``body[0].mesh.n``)."""
    return _native.from_dict(scene, None if base is None else os.fspath(base))


def solve(
    scene: Union[Scene, SceneBuilder, Mapping[str, Any], str, os.PathLike],
    memory_limit_gib: Optional[float] = None,
) -> Result:
    """Solves a scene given as a :class:`Scene`, a :class:`SceneBuilder`, a dict or the
    path of a scene file."""
    if isinstance(scene, SceneBuilder):
        scene = scene.build()
    elif isinstance(scene, Mapping):
        scene = from_dict(scene)
    elif isinstance(scene, (str, os.PathLike)):
        scene = load(scene)
    return scene.solve(memory_limit_gib)


def mesh(description: Mapping[str, Any], base: Optional[Union[str, os.PathLike]] = None) -> Mesh:
    """The mesh of a body's ``mesh`` description (:func:`generated`, :func:`mesh_file`,
    :func:`inline`), built and validated as a scene builds it, with its boundary parts.
    Raises :class:`SceneError` at the key path in ``description`` (``polygons[3]``) with the
    message of the library naming the cell and the vertex."""
    return _native.mesh(description, None if base is None else os.fspath(base))


def generate(
    family: str,
    rectangle: Optional[Any] = None,
    n: Optional[int] = None,
    seed: Optional[int] = None,
    *,
    box: Optional[Any] = None,
) -> Mesh:
    """A mesh of the project's families: ``family`` of ``names()["mesh_families"]`` on a
    ``rectangle = [[x0, y0], [x1, y1]]`` or of ``names()["mesh_families_3d"]`` on a ``box =
    [[x0, y0, z0], [x1, y1, z1]]``, about ``n`` cells across, ``seed`` for the random
    families (default 1): the same mesh a scene generates. Its parts are the sides
    ("bottom", "right", "top", "left"; in space also "front", "back")."""
    if n is None:
        raise TypeError("generate() needs the size n (about n cells across)")
    return mesh(generated(family, rectangle, n, seed, box=box))


def names() -> Dict[str, List[str]]:
    """The names the scenes accept, read from the library's registries: ``solvers``,
    ``elements``, ``laws``, ``accuracy_presets``, ``mesh_families`` (of a rectangle) and
    ``mesh_families_3d`` (of a box)."""
    return _native.names()


def solvers() -> List[str]:
    """The contact solvers' names (a scene's ``solver``)."""
    return names()["solvers"]


def elements() -> List[str]:
    """The elements' names (a body's ``element``)."""
    return names()["elements"]


def accuracy_presets() -> List[str]:
    """The accuracy presets' names (a scene's ``accuracy``)."""
    return names()["accuracy_presets"]
