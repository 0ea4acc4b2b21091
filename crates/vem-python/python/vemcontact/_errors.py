"""The package's exception and warning classes."""

from __future__ import annotations

from typing import List, Optional, Union


class SceneError(ValueError):
    """A scene that cannot be read, checked or built.

    ``str(error)`` is the message the ``vem`` command prints: for a scene file
    ``file:line:column: message`` followed by the line and a caret, for a dict
    ``key.path: message``.

    Attributes:
        key_path: the key at fault as written, ``"contact[0].law.friction_bound"``
            (``""`` for the whole scene).
        path: the same as a list of keys (str) and indices (int).
        message: what is wrong, without the place.
        file, line, column: for a scene read from TOML, where (1-based); ``None``
            otherwise, or where the file has no place for the key.
    """

    def __init__(
        self,
        text: str,
        key_path: str = "",
        path: Optional[List[Union[str, int]]] = None,
        message: Optional[str] = None,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
    ) -> None:
        super().__init__(text)
        self.key_path = key_path
        self.path = list(path or [])
        self.message = text if message is None else message
        self.file = file
        self.line = line
        self.column = column


class SolveError(SceneError):
    """A scene that was built but whose solve failed (a contact without support, a
    solver that did not converge, ...); ``key_path`` names the setting at fault where
    there is one, ``""`` otherwise. A subclass of :class:`SceneError`."""


class OutputError(OSError):
    """Output files that could not be written (``Result.write``)."""

    def __init__(self, text: str, directory: object = None) -> None:
        super().__init__(text)
        self.directory = directory


class SceneWarning(UserWarning):
    """What a converged answer's user should know: a solver's or the model's warning (a
    contact zone cut short, an element far outside the mesh assumptions, a locking
    element near incompressibility) or a key of an earlier version of the format."""
