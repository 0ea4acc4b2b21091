"""Contact of elastic bodies with the lowest-order virtual element method.

The package reads the scenes of the ``vem`` command (docs/scenes.md) from a TOML file, a
TOML text or a Python dict, or builds them call by call (:class:`SceneBuilder`); solves
them with the library (the GIL released); and gives the results as numpy arrays::

    import vemcontact as vc

    result = vc.load("crates/vem-cli/scenes/hertz.toml").solve()
    pair = result.pairs[0]
    print(pair.pressure.max(), result.report["iterations"])
    result.write("out/hertz")  # the vem command's VTU, CSV, SVG and JSON files

Errors are :class:`SceneError` (with the key path, and the file, line and column of a
scene file), :class:`SolveError` and :class:`OutputError`; the warnings of a run are
issued as :class:`SceneWarning` and listed in ``Result.warnings``.
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

from . import _native
from ._errors import OutputError, SceneError, SceneWarning, SolveError
from ._native import BodyResult, ContactPair, Result, Scene, Step
from .builder import (
    Body,
    SceneBuilder,
    circle,
    element,
    generated,
    isotropic,
    lame,
    law,
    line,
    mesh_file,
    polyline,
    solver,
)

__all__ = [
    "Body",
    "BodyResult",
    "ContactPair",
    "OutputError",
    "Result",
    "Scene",
    "SceneBuilder",
    "SceneError",
    "SceneWarning",
    "SolveError",
    "Step",
    "circle",
    "element",
    "from_dict",
    "generated",
    "isotropic",
    "lame",
    "law",
    "line",
    "load",
    "loads",
    "mesh_file",
    "polyline",
    "solve",
    "solver",
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
