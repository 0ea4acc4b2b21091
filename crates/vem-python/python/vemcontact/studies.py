"""The project's verification studies from Python: the convergence study (`cargo xtask
convergence`, docs/convergence.md) and the solvers' speed-accuracy trade-off (`cargo xtask
tradeoff`, docs/tradeoff.md), run by the library (vem-verify) with the GIL released, their rows
as dicts of numpy arrays.

    import vemcontact as vc

    study = vc.convergence_study("E1", "quads", sizes=[4, 8, 16])
    print(study["rates"]["grad"], study["rows"]["e_grad"])
    rows = vc.tradeoff_study(cases=["M1"], sizes=[8, 16])
    print(rows["setting"], rows["e_grad"], rows["solve"])
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence

import numpy as np

from . import _native

__all__ = ["convergence_plan", "convergence_study", "tradeoff_study"]


def _columns(rows: List[Dict[str, Any]]) -> Dict[str, np.ndarray]:
    """A list of flat dicts as a dict of arrays (a key missing from a row is NaN or None)."""
    keys: List[str] = []
    for row in rows:
        for key in row:
            if key not in keys:
                keys.append(key)
    columns: Dict[str, np.ndarray] = {}
    for key in keys:
        values = [row.get(key) for row in rows]
        present = [v for v in values if v is not None]
        if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
            if all(isinstance(v, int) for v in present) and len(present) == len(values):
                columns[key] = np.array(values, dtype=np.int64)
            else:
                columns[key] = np.array([np.nan if v is None else v for v in values], dtype=float)
        else:
            columns[key] = np.array(values, dtype=object)
    return columns


def convergence_plan(quick: bool = True, cases: Optional[Sequence[str]] = None) -> List[Dict[str, Any]]:
    """The studies of the project's convergence run in the plane (the same plan as
    ``cargo xtask convergence [--quick]``): one dict ``{case, pairing, sizes}`` per study of
    the cases ``cases`` (default M1, M2, E1)."""
    return _native.convergence_plan(quick, None if cases is None else list(cases))


def convergence_study(
    case: str,
    pairing: str,
    sizes: Sequence[int] = (8, 16, 32),
    solver: Optional[str] = None,
    element: Optional[str] = None,
    seed: Optional[int] = None,
) -> Dict[str, Any]:
    """Runs the convergence study of ``case`` (a manufactured case: M1..M4, E1, E2, the patch
    tests PT0a, PT0b, PTC1, ...) on the mesh ``pairing`` ("quads/quads*3", "voronoi/quads";
    one family such as "quads" for a one-body case) at ``sizes``, with the contact
    ``solver`` (:func:`vemcontact.solvers`) and ``element`` (:func:`vemcontact.elements`).

    Returns the study as ``convergence.json`` holds it (``case``, ``law``, ``pairing``,
    ``rates``: the fitted rates of ``grad``, ``energy``, ``l2``; ``verdict``: ``passed`` and
    ``shortfalls``; ``records``: the library's record per size) with ``rows``: a dict of
    arrays, one entry per size, of ``n`` (body 1's), ``h``, ``dofs``, ``polygons``,
    ``vertices``, the relative errors ``e_grad`` (``E_grad / |u|_1``), ``e_a``, ``e_0`` and
    the seconds ``seconds``."""
    result = _native.convergence_study(case, pairing, [int(n) for n in sizes], solver, element, seed)
    rows = []
    for record in result["records"]:
        errors = record["errors"]
        row = {
            "n": record["n"][0],
            "h": record["h"],
            "dofs": record["dofs"],
            "polygons": record["polygons"],
            "vertices": record["vertices"],
            "seconds": sum(record["times"].values()),
        }
        row.update(_relative_errors(errors))
        if record.get("solver_iterations") is not None:
            row["iterations"] = record["solver_iterations"]
        rows.append(row)
    result["rows"] = _columns(rows)
    return result


def _relative_errors(errors: Dict[str, Any]) -> Dict[str, float]:
    """The relative errors of a record's ``ErrorNorms``."""
    def ratio(error: str, norm: str) -> float:
        e, n = errors[error], errors[norm]
        return e / n if n > 0 else e

    return {
        "e_grad": ratio("grad", "exact_grad"),
        "e_a": ratio("energy", "interpolant_energy"),
        "e_0": ratio("l2", "exact_l2"),
    }


def tradeoff_study(
    cases: Sequence[str] = ("M1", "M2"),
    pairing: str = "quads/quads",
    sizes: Sequence[int] = (8, 16, 32),
    settings: Optional[Sequence[str]] = None,
    element: Optional[str] = None,
    quick: bool = True,
) -> Dict[str, np.ndarray]:
    """The speed-accuracy trade-off of the contact solvers' settings on manufactured cases
    (the groups of ``cargo xtask tradeoff --quick`` with an exact solution): each case on
    ``pairing`` at each size is discretised once and solved with every setting (default:
    the quick or the full study's, labels such as "draft", "exact", "penalty@factor=1e6").

    Returns the rows as a dict of arrays, one entry per (case, size, setting): ``case``,
    ``pairing``, ``element``, ``n``, ``h``, ``setting``, ``solver``, ``status``, ``error``,
    ``unknowns``, ``contact_rows``, ``iterations``, the relative errors ``e_grad``, ``e_0``,
    ``e_a``, ``pressure_l2``, ``pressure_max``, ``resultant``, ``misclassified`` and the
    seconds ``mesh_generation``, ``discretisation``, ``solve``, ``errors``."""
    labels = list(settings) if settings is not None else _native.tradeoff_settings(quick)
    rows: List[Dict[str, Any]] = []
    for case in cases:
        for n in sizes:
            rows.extend(_native.tradeoff_group(case, pairing, int(n), labels, element))
    return _columns(rows)
