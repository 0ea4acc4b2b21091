"""Meshes from numpy arrays and meshio, the registries' names, the studies, Ctrl-C, the wheel's
stable ABI and results in space, each checked against an independent expectation: the patch
test's exact state, identical arrays after a round trip, the `vem` command's own lists, the
theorem's rate, the uniform state of a block in space."""

import importlib.metadata
import os
import re
import signal
import subprocess
import threading

import numpy as np
import pytest

import vemcontact as vc

# The unit square cut into three quadrilaterals around the interior vertex 4 = (0.5, 0.4);
# vertices 5 = (0.5, 0) and 6 = (0, 0.6) lie on the sides.
POINTS = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.4], [0.5, 0], [0, 0.6]], dtype=float)
POLYGONS = [[0, 5, 4, 6], [5, 1, 2, 4], [4, 2, 3, 6]]
PARTS = {"left": [[3, 6], [6, 0]], "bottom": [[0, 5], [5, 1]], "right": [[1, 2]], "top": [[2, 3]]}


def square_scene(mesh):
    s = vc.SceneBuilder(title="patch from arrays")
    body = s.add_body("square", mesh, vc.isotropic(E=100.0, nu=0.3, plane="stress"))
    body.dirichlet("left", x=0.0).dirichlet("bottom", y=0.0).traction("right", value=[2.0, 0.0])
    return s


def check_uniform_tension(result, sigma=2.0, E=100.0, nu=0.3):
    """Plane stress, sigma_xx = sigma: eps_xx = sigma / E, eps_yy = -nu sigma / E, linear u."""
    body = result.body("square")
    x, y = body.vertices.T
    np.testing.assert_allclose(body.displacement[:, 0], sigma / E * x, atol=1e-12)
    np.testing.assert_allclose(body.displacement[:, 1], -nu * sigma / E * y, atol=1e-12)
    np.testing.assert_allclose(body.stress[:, 0, 0], sigma, atol=1e-10)
    np.testing.assert_allclose(body.stress[:, 1, 1], 0.0, atol=1e-10)
    np.testing.assert_allclose(body.stress[:, 0, 1], 0.0, atol=1e-10)
    np.testing.assert_allclose(body.reactions["left"], [-sigma, 0.0], atol=1e-10)


def test_patch_test_on_a_mesh_from_arrays_polygons_and_offsets():
    """The same mesh given as polygons and as offsets + connectivity reproduces the uniform
    state to 1e-10, and the mesh comes back as given."""
    by_polygons = vc.inline(POINTS, POLYGONS, parts=PARTS)
    offsets = np.cumsum([0] + [len(p) for p in POLYGONS])
    by_offsets = vc.inline(POINTS, offsets=offsets, connectivity=np.concatenate(POLYGONS), parts=PARTS)
    assert by_polygons == by_offsets
    result = square_scene(by_offsets).solve()
    check_uniform_tension(result)
    body = result.body("square")
    np.testing.assert_array_equal(body.vertices, POINTS)
    np.testing.assert_array_equal(body.cell_offsets, offsets)
    np.testing.assert_array_equal(body.cell_connectivity, np.concatenate(POLYGONS))
    np.testing.assert_array_equal(body.mesh.parts["right"], [[1, 2]])
    # The summary says where the mesh came from.
    assert "given inline" in result.summary["bodies"][0]["mesh"]


def test_a_bad_mesh_from_arrays_names_the_cell_and_vertex():
    bad = [[0, 5, 4, 6], [5, 1, 9, 4], [4, 2, 3, 6]]
    with pytest.raises(vc.SceneError) as e:
        vc.mesh(vc.inline(POINTS, bad))
    assert e.value.key_path == "polygons[1]"
    assert "polygon 1" in str(e.value) and "vertex 9" in str(e.value)
    with pytest.raises(vc.SceneError) as e:
        square_scene(vc.inline(POINTS, [[0, 5, 4, 6], [5, 1, 2, 4], [6, 3, 2, 4]], parts=PARTS)).build().solve()
    assert e.value.key_path == "body[0].mesh.polygons[2]"
    assert "polygon" in str(e.value)
    with pytest.raises(vc.SceneError) as e:
        vc.mesh(vc.inline([[0, 0], [1, 0], [0, 1]], [[0, 2, 1]]))
    assert e.value.key_path == "polygons[0]" and "clockwise" in str(e.value)
    with pytest.raises(vc.SceneError) as e:
        vc.mesh(vc.inline(POINTS, POLYGONS, parts={"bottom": [[5, 4]]}))
    assert e.value.key_path == "part_edges.bottom"


def test_generated_meshes_by_name_as_arrays():
    """A generated mesh is the scene's: a body on the same family, n and seed solves on the
    same vertices; its parts are the sides; its area is the rectangle's."""
    mesh = vc.generate("voronoi", [[0, 0], [2, 1]], n=6, seed=3)
    assert mesh.dimension == 2 and set(mesh.parts) == {"bottom", "right", "top", "left"}
    v = mesh.vertices
    area = 0.0
    for cell in mesh.cells:
        p = v[cell]
        area += 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    assert area == pytest.approx(2.0, rel=1e-12)
    again = vc.mesh(mesh.to_dict())
    np.testing.assert_array_equal(again.vertices, mesh.vertices)
    np.testing.assert_array_equal(again.cell_connectivity, mesh.cell_connectivity)
    scene = vc.from_dict({"body": [{"name": "a", "mesh": vc.generated("voronoi", [[0, 0], [2, 1]], 6, 3),
                                    "material": vc.isotropic(1.0, 0.3),
                                    "dirichlet": [{"part": "bottom", "x": 0, "y": 0}]}]})
    np.testing.assert_array_equal(scene.solve().body("a").vertices, mesh.vertices)
    block = vc.generate("hexahedra", box=[[0, 0, 0], [1, 1, 1]], n=2)
    assert (block.dimension, block.n_cells, block.n_vertices) == (3, 8, 27)
    assert all(len(cell) == 6 for cell in block.cells)


def test_meshio_round_trip_keeps_points_cells_and_parts(tmp_path):
    meshio = pytest.importorskip("meshio")
    mesh = vc.generate("voronoi", [[0, 0], [1, 1]], n=5, seed=2)
    m = mesh.to_meshio()
    back = vc.from_meshio(m)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.cell_offsets, mesh.cell_offsets)
    np.testing.assert_array_equal(back.cell_connectivity, mesh.cell_connectivity)
    for name, edges in mesh.parts.items():
        np.testing.assert_array_equal(back.parts[name], edges)
    # Through a file meshio writes and reads (VTU; parts are not kept by VTU, so given again).
    path = tmp_path / "mesh.vtu"
    meshio.write(path, m)
    read = vc.from_meshio(meshio.read(path), parts={k: v for k, v in mesh.parts.items()})
    np.testing.assert_array_equal(read.vertices, mesh.vertices)
    np.testing.assert_array_equal(read.cell_connectivity, mesh.cell_connectivity)
    # A mesh in space: hexahedra as meshio cells become polyhedra of the same volume.
    cube = vc.generate("hexahedra", box=[[0, 0, 0], [1, 1, 1]], n=2)
    back = vc.from_meshio(cube.to_meshio())
    np.testing.assert_array_equal(back.vertices, cube.vertices)
    assert [sorted(map(tuple, c)) for c in back.cells] == [sorted(map(tuple, c)) for c in cube.cells]
    assert set(back.parts) == set(cube.parts)
    hexahedra = meshio.Mesh(cube.vertices, [("hexahedron", _hexahedra_of(cube))])
    assert vc.from_meshio(hexahedra).n_cells == 8


def _hexahedra_of(cube):
    """The 2 x 2 x 2 cells of the unit cube in VTK's hexahedron order, from the vertices."""
    v = cube.vertices
    index = {tuple(np.round(p * 2).astype(int)): k for k, p in enumerate(v)}
    cells = []
    for i in range(2):
        for j in range(2):
            for k in range(2):
                corner = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
                cells.append([index[(i + a, j + b, k + c)] for a, b, c in corner])
    return np.array(cells)


def test_a_solved_body_to_meshio():
    pytest.importorskip("meshio")
    result = square_scene(vc.inline(POINTS, POLYGONS, parts=PARTS)).solve()
    m = result.to_meshio("square")
    np.testing.assert_allclose(m.point_data["displacement"][:, :2], result.body("square").displacement)
    stress = np.concatenate([block for block in m.cell_data["stress"]])
    np.testing.assert_allclose(stress[: len(POLYGONS), 0], 2.0, atol=1e-10)


def test_registry_names_are_what_the_command_accepts(tmp_path, vem_bin):
    """Each list is the one the `vem` command prints when it refuses an unknown name."""
    names = vc.names()
    assert vc.solvers() == names["solvers"] and "condensed" in names["solvers"]
    assert vc.elements() == names["elements"] and vc.accuracy_presets() == names["accuracy_presets"]

    def refused(**keys):
        scene = {"body": [{"name": "a", "mesh": vc.generated("quads", [[0, 0], [1, 1]], 2),
                           "material": vc.isotropic(1.0, 0.3),
                           "dirichlet": [{"part": "bottom", "x": 0, "y": 0}]}]}
        for key, value in keys.items():
            if key == "element":
                scene["body"][0]["element"] = value
            else:
                scene[key] = value
        path = tmp_path / "scene.toml"
        path.write_text(_toml(scene))
        run = subprocess.run([str(vem_bin), "check", str(path)], capture_output=True, text=True)
        assert run.returncode != 0
        return run.stderr

    for key, listed in [("solver", "solvers"), ("element", "elements"), ("accuracy", "accuracy_presets")]:
        message = refused(**{key: "nonesuch"})
        for name in names[listed]:
            assert re.search(rf"\b{re.escape(name)}\b", message), (name, message)
        # Every listed name is accepted.
        for name in names[listed]:
            if listed == "elements" and name == "p1":
                continue  # the linear triangle needs triangles
            vc.from_dict(_scene_with(key, name))


def _scene_with(key, name):
    scene = {"body": [{"name": "a", "mesh": vc.generated("quads", [[0, 0], [1, 1]], 2),
                       "material": vc.isotropic(1.0, 0.3)}]}
    if key == "element":
        scene["body"][0]["element"] = name
    else:
        scene[key] = name
    return scene


def _toml(value, prefix=""):
    """A scene dict as TOML (the few types the scenes above use)."""
    import json
    lines, tables = [], []
    for key, v in value.items():
        if isinstance(v, list) and v and isinstance(v[0], dict):
            tables.append((key, v))
        else:
            lines.append(f"{key} = {json.dumps(v) if not isinstance(v, dict) else _inline(v)}")
    for key, items in tables:
        for item in items:
            lines.append(f"[[{prefix}{key}]]")
            lines.append(_toml(item, prefix=f"{prefix}{key}."))
    return "\n".join(lines)


def _inline(d):
    import json
    return "{ " + ", ".join(f"{k} = {_inline(v) if isinstance(v, dict) else json.dumps(v)}" for k, v in d.items()) + " }"


def test_a_quick_convergence_study_shows_the_theorem_rates():
    """E1 on quads: first order in E_grad and E_a, second in E_0 (Theorem 4.1)."""
    study = vc.convergence_study("E1", "quads", sizes=[4, 8, 16])
    rows = study["rows"]
    np.testing.assert_array_equal(rows["n"], [4, 8, 16])
    assert np.all(np.diff(rows["e_grad"]) < 0)
    rate = np.polyfit(np.log(rows["h"]), np.log(rows["e_grad"]), 1)[0]
    assert rate == pytest.approx(study["rates"]["grad"], abs=1e-9)
    assert 0.9 < rate < 1.2
    assert study["rates"]["l2"] > 1.8 and study["verdict"]["passed"]
    plan = vc.convergence_plan(quick=True, cases=["M1"])
    assert [p["pairing"] for p in plan][:2] == ["quads/quads", "quads/quads*3"]
    assert plan[0]["sizes"] == [8, 16, 32]
    with pytest.raises(ValueError, match="nonesuch"):
        vc.convergence_study("nonesuch", "quads")


def test_a_quick_tradeoff_agrees_across_converged_settings():
    """M1 at n = 8: every converged setting of the quick study solves the same discrete
    problem, so their errors agree with the exact solver's to the settings' tolerances; the
    errors fall with n."""
    rows = vc.tradeoff_study(cases=["M1"], sizes=[4, 8], settings=["reference", "exact", "draft"])
    assert list(rows["setting"]) == ["reference", "exact", "draft"] * 2
    assert all(s == "Converged" for s in rows["status"])
    e = rows["e_grad"].reshape(2, 3)
    assert e[0, 0] == pytest.approx(e[0, 1], rel=1e-6)
    assert e[0, 2] == pytest.approx(e[0, 1], rel=1e-2)
    assert np.all(e[1] < e[0])
    with pytest.raises(ValueError, match="unknown solver"):
        vc.tradeoff_study(cases=["M1"], sizes=[4], settings=["nonesuch"])


def test_ctrl_c_interrupts_a_long_run(scenes):
    """SIGINT sent from a timer thread during a run (10^4 Voronoi cells: about 0.5 s on a
    quiet machine, 3 s on a loaded one; the waiting thread looks for signals every 50 ms) raises
    KeyboardInterrupt in the caller, and the package solves again afterwards. The worker
    finishes the stage under way (the build) and stops before the solve. Python's own SIGINT
    handler is installed for the test: a process started in the background by a shell without
    job control inherits SIGINT ignored, and Python then installs none."""
    scene = vc.from_dict({"body": [{"name": "a", "mesh": vc.generated("voronoi", [[0, 0], [1, 1]], 100, 1),
                                    "material": vc.isotropic(1.0, 0.3),
                                    "dirichlet": [{"part": "bottom", "x": 0, "y": 0}],
                                    "traction": [{"part": "top", "value": [0, -1]}]}]})
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            scene.solve()
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    check_uniform_tension(square_scene(vc.inline(POINTS, POLYGONS, parts=PARTS)).solve())


def test_the_wheel_is_one_stable_abi_wheel():
    """The extension is built for the stable ABI of CPython 3.9 and later (abi3)."""
    wheel = importlib.metadata.distribution("vemcontact").read_text("WHEEL")
    tags = [line.split(":", 1)[1].strip() for line in wheel.splitlines() if line.startswith("Tag:")]
    assert tags and all(re.match(r"cp39-abi3-", tag) for tag in tags), tags
    assert vc._native.__file__.endswith(".abi3.so") or vc._native.__file__.endswith(".pyd")


def test_a_block_in_space_gives_its_uniform_state_as_arrays(scenes):
    """block3d.toml: sigma_xx = 0.5, sigma_zz = -0.2, every other component 0; u linear;
    the reactions balance the loads; the arrays are (n, 3)."""
    result = vc.load(scenes / "block3d.toml").solve()
    body = result.body("block")
    assert body.dimension == 3
    assert body.vertices.shape[1] == 3 and body.displacement.shape == body.vertices.shape
    expected = np.zeros((3, 3))
    expected[0, 0], expected[2, 2] = 0.5, -0.2
    np.testing.assert_allclose(body.stress, np.broadcast_to(expected, body.stress.shape), atol=1e-10)
    E, nu = 100.0, 0.3
    strain = np.array([0.5 + 0.2 * nu, -nu * (0.5 - 0.2), -0.2 - 0.5 * nu]) / E
    np.testing.assert_allclose(body.displacement, body.vertices * strain, atol=1e-12)
    # Reactions: the left face holds the pull 0.5 x area 1, the bottom the pressure 0.2 x 2.
    np.testing.assert_allclose(body.reactions["left"][0], -0.5, atol=1e-10)
    np.testing.assert_allclose(body.reactions["bottom"][2], 0.4, atol=1e-10)
    assert len(body.cells) == body.mesh.n_cells == len(body.stress)
    assert result.pairs == []


def test_the_contact_patch_test_in_space_from_a_dict():
    """Two stacked blocks in space on non-matching meshes (hexahedra 3^3 on tetrahedra 4^3),
    moduli 100 and 300, on rollers, the upper top moved down by d = 0.01: the uniform pressure
    sigma = d / (1/E1 + 1/E2) at every interface node to 1e-10, the nodal forces adding up to
    sigma times the interface's area 1, the arrays (k, 3)."""
    d = 0.01
    rollers = [{"part": "left", "x": 0.0}, {"part": "front", "y": 0.0}]
    scene = vc.from_dict({
        "body": [
            {"name": "upper", "mesh": {"family": "hexahedra", "box": [[0, 0, 0], [1, 1, 1]], "n": 3},
             "material": {"E": 100.0, "nu": 0.3},
             "dirichlet": rollers + [{"part": "top", "z": -d}]},
            {"name": "lower", "mesh": {"family": "tetrahedra", "box": [[0, 0, -1], [1, 1, 0]], "n": 4},
             "material": {"E": 300.0, "nu": 0.3},
             "dirichlet": rollers + [{"part": "bottom", "z": 0.0}]},
        ],
        "contact": [{"body": "upper", "part": "bottom", "other_body": "lower", "other_part": "top"}],
    })
    result = scene.solve()
    sigma = d / (1.0 / 100.0 + 1.0 / 300.0)
    [pair] = result.pairs
    assert pair.dimension == 3
    assert pair.positions.shape == (len(pair), 3) and pair.normals.shape == (len(pair), 3)
    np.testing.assert_allclose(pair.pressure, sigma, rtol=1e-10)
    np.testing.assert_allclose(pair.consistent_pressure, sigma, rtol=1e-10)
    np.testing.assert_allclose(pair.normals, np.tile([0.0, 0.0, -1.0], (len(pair), 1)), atol=1e-12)
    assert pair.tributary.sum() == pytest.approx(1.0, rel=1e-12)
    assert pair.normal_force.sum() == pytest.approx(sigma, rel=1e-10)
    assert set(pair.status) == {"contact"}
    with pytest.raises(AttributeError, match="friction_force"):
        pair.friction
    # The summary's resultant, and the bodies solved with the interface nodes inserted.
    assert result.summary["contact"]["resultants"]["normal"] == pytest.approx(sigma, rel=1e-10)
    assert result.body("upper").dimension == 3


def test_the_worked_hertz_example_from_arrays_matches_hertz():
    """docs/python.md's example (examples/hertz_arrays.py): an indenter meshed from arrays
    with a circular bottom of radius 1 pressed into a generated block. Hertz for the load the
    pair carries: the peak pressure within 3 %, the contact width within two node spacings
    (0.02) of 2a, zero pressure beyond."""
    import importlib.util
    import pathlib

    path = pathlib.Path(__file__).resolve().parents[1] / "examples" / "hertz_arrays.py"
    spec = importlib.util.spec_from_file_location("hertz_arrays", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    result = example.solve()
    pair = result.pairs[0]
    P, a, p0 = example.hertz(pair)
    assert P > 0 and result.report["status"] == "converged"
    assert pair.pressure.max() == pytest.approx(p0, rel=0.03)
    assert pair.consistent_pressure.max() == pytest.approx(p0, rel=0.03)
    active = pair.positions[pair.normal_force > 0, 0]
    assert abs((active.max() - active.min()) - 2 * a) < 2 * 0.02
    assert np.all(pair.pressure[np.abs(pair.positions[:, 0]) > a + 0.04] == 0.0)
    # Equilibrium: the clamp on the indenter's top carries the contact load.
    assert -result.body("indenter").reactions["top"][1] == pytest.approx(P, rel=1e-8)
