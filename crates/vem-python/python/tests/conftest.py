"""Shared helpers: the repository's scenes and the `vem` command the numbers are compared with."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[4]
SCENES = ROOT / "crates" / "vem-cli" / "scenes"


@pytest.fixture(scope="session")
def scenes() -> pathlib.Path:
    return SCENES


@pytest.fixture(scope="session")
def vem_bin() -> pathlib.Path:
    """The `vem` command (scripts/python-test.sh builds it and sets VEM_BIN)."""
    path = pathlib.Path(os.environ.get("VEM_BIN", ROOT / "target" / "release" / "vem"))
    if not path.exists():
        pytest.fail(f"the vem command is not built at {path}: run scripts/python-test.sh")
    return path
