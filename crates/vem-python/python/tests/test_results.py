"""The package's numbers against independent expectations: Hertz's solution, the patch test's
exact state, the `vem` command's run of the same scene file, linearity along a history."""

import csv
import math
import subprocess
import sys
import threading
import time
import tomllib

import numpy as np
import pytest

import vemcontact as vc


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def hertz(scenes):
    return vc.load(scenes / "hertz.toml").solve()


@pytest.fixture(scope="module")
def patch(scenes):
    return vc.load(scenes / "patch.toml").solve()


def test_hertz_peak_pressure_and_half_width_against_hertz(hertz):
    """Hertz for a cylinder (R = 1) on a half-space, plane strain: E* = E / (2 (1 - nu^2)),
    a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a), with P the load the clamp on the disc's top
    carries. Tolerances as the Rust test of the same scene: 4 % for the nodal peak, 1 % for
    the consistent one, 6 % for the half-width (read from node positions, spacing 0.01)."""
    E, nu, R = 100.0, 0.3, 1.0
    e_star = E / (2.0 * (1.0 - nu**2))
    P = np.linalg.norm(hertz.body("disc").reactions["top"])
    a = math.sqrt(4.0 * P * R / (math.pi * e_star))
    p0 = 2.0 * P / (math.pi * a)
    pair = hertz.pairs[0]
    assert pair.pressure.max() == pytest.approx(p0, rel=0.04)
    assert pair.consistent_pressure.max() == pytest.approx(p0, rel=0.01)
    # Equilibrium: the normal forces carry the clamp's load (the normals are the block's).
    np.testing.assert_array_equal(pair.normals, np.tile([0.0, -1.0], (len(pair), 1)))
    assert pair.normal_force.sum() == pytest.approx(P, rel=1e-9)
    # The contact zone: the nodes in contact span about 2a, centred under the disc.
    active = pair.positions[pair.normal_force > 0.0, 0]
    assert active.max() - active.min() == pytest.approx(2.0 * a, rel=0.12)
    assert abs(active.mean()) < 0.1 * a
    # The library's own comparison reports the same P and p0.
    report = hertz.summary["contact"]["hertz"][0]
    assert report["load"] == pytest.approx(P, rel=1e-9)
    assert report["peak_pressure"] == pytest.approx(p0, rel=1e-9)
    assert report["computed_peak_pressure"] == pair.pressure.max()
    # Frictionless and converged: no friction, no slip, KKT residuals small.
    assert not pair.friction.any() and not pair.slip.any()
    assert set(pair.status) <= {"open", "contact"}
    assert hertz.report["status"] == "converged"
    assert hertz.report["iterations"] > 0
    assert hertz.report["residuals"]["max_penetration"] < 1e-8
    # Gaps: closed where the force acts (complementarity), open where none does.
    gap = pair.gap
    assert np.all(gap[pair.normal_force > 0.0] < 1e-9)
    np.testing.assert_allclose(gap, pair.initial_gap - pair.normal_jump)


def test_patch_scene_reproduces_the_uniform_state(patch):
    """Two blocks, non-matching meshes, uniform pressure p = 2 on top: the exact solution is
    linear, so the discrete one is exact: contact pressure p at every node, sigma_yy = -p and
    sigma_xx = sigma_xy = 0 in every element, u_x = eps_xx x on the upper block's top."""
    p, nu, E = 2.0, 0.3, 200.0
    pair = patch.pairs[0]
    assert len(pair) > 0
    np.testing.assert_allclose(pair.pressure, p, atol=1e-9)
    assert pair.status == ["contact"] * len(pair)
    assert pair.normal_resultant == pytest.approx(p * 1.0, abs=1e-9)
    for body in patch.bodies:
        s = body.stress
        assert s.shape == (len(body.cells), 3, 3)
        np.testing.assert_allclose(s[:, 1, 1], -p, atol=1e-8)
        np.testing.assert_allclose(s[:, 0, 0], 0.0, atol=1e-8)
        np.testing.assert_allclose(s[:, 0, 1], 0.0, atol=1e-8)
        # Plane strain: sigma_zz = nu (sigma_xx + sigma_yy).
        np.testing.assert_allclose(s[:, 2, 2], -nu * p, atol=1e-8)
        assert body.displacement.shape == body.vertices.shape
    upper = patch.body("upper")
    eps_xx = p * nu * (1.0 + nu) / E
    x, u = upper.vertices, upper.displacement
    top = np.isclose(x[:, 1], 0.5)
    np.testing.assert_allclose(u[top, 0], eps_xx * x[top, 0], atol=1e-9)
    # The cells index the vertices: the offsets and the lists agree.
    offsets, connectivity = upper.cell_offsets, upper.cell_connectivity
    assert offsets[-1] == len(connectivity)
    np.testing.assert_array_equal(np.concatenate(upper.cells), connectivity)


@pytest.mark.parametrize("name", ["patch", "hertz"])
def test_same_numbers_as_the_vem_command(name, scenes, vem_bin, tmp_path):
    """The `vem` command run on the same file in its own process: its contact.csv (shortest
    round-trip numbers) equals the package's arrays exactly, its summary the package's."""
    out = tmp_path / "cli"
    subprocess.run([str(vem_bin), "run", str(scenes / f"{name}.toml"), "--out", str(out)],
                   check=True, capture_output=True)
    rows = read_csv(out / "contact.csv")
    result = vc.load(scenes / f"{name}.toml").solve()
    pairs = result.pairs
    positions = np.concatenate([p.positions for p in pairs])
    column = lambda key: np.array([float(r[key]) for r in rows])
    assert len(rows) == len(positions)
    np.testing.assert_array_equal(column("x"), positions[:, 0])
    np.testing.assert_array_equal(column("y"), positions[:, 1])
    for key, attr in [("initial_gap", "initial_gap"), ("normal_jump", "normal_jump"),
                      ("normal_force", "normal_force"), ("pressure", "pressure"),
                      ("consistent_pressure", "consistent_pressure"),
                      ("friction_force", "friction"), ("slip", "tangential_slip")]:
        np.testing.assert_array_equal(column(key), np.concatenate([getattr(p, attr) for p in pairs]), key)
    assert [r["status"] for r in rows] == sum((p.status for p in pairs), [])
    import json
    summary = json.loads((out / "summary.json").read_text())
    assert summary["contact"]["report"]["iterations"] == result.report["iterations"]
    assert summary["contact"]["resultants"] == result.summary["contact"]["resultants"]
    for cli_body, body in zip(summary["bodies"], result.bodies):
        assert cli_body["strain_energy"] == body.strain_energy
        assert cli_body["max_displacement"] == np.linalg.norm(body.displacement, axis=1).max()
        assert cli_body["max_von_mises"] == body.von_mises.max()
    # And the package's own files are the command's: the same writer.
    mine = tmp_path / "py"
    files = result.write(mine)
    assert (mine / "contact.csv").read_text() == (out / "contact.csv").read_text()
    assert {f.name for f in files} >= {"contact.csv", "summary.json", "interface.vtu"}


def test_write_keeps_the_kinds_and_the_encoding_asked_for(scenes, tmp_path):
    """`write(dir, files=..., vtu_encoding=...)`: fewer kinds of files with the same contents,
    the .vtu files as text holding the computed values bit for bit; the keywords hold for
    that call only."""
    meshio = pytest.importorskip("meshio")
    result = vc.load(scenes / "signorini.toml").solve()
    full = {f.name for f in result.write(tmp_path / "full")}
    assert {"block.vtu", "contact.csv", "deformed.svg", "summary.json"} <= full
    tables = result.write(tmp_path / "csv", files=["csv"])
    assert sorted(f.name for f in tables) == ["contact.csv", "summary.json"]
    assert (tmp_path / "csv" / "contact.csv").read_text() == (tmp_path / "full" / "contact.csv").read_text()
    text = result.write(tmp_path / "ascii", files=["vtu"], vtu_encoding="ascii")
    assert sorted(f.name for f in text) == ["block.vtu", "interface.vtu", "results.pvd", "summary.json"]
    assert 'format="ascii"' in (tmp_path / "ascii" / "block.vtu").read_text()
    grid = meshio.read(tmp_path / "ascii" / "block.vtu")
    np.testing.assert_array_equal(grid.point_data["displacement"][:, :2], result.body("block").displacement)
    assert {f.name for f in result.write(tmp_path / "again")} == full
    assert b'encoding="raw"' in (tmp_path / "again" / "block.vtu").read_bytes()
    with pytest.raises(ValueError, match="ascii"):
        result.write(tmp_path / "bad", vtu_encoding="asci")
    with pytest.raises(ValueError, match="pictures"):
        result.write(tmp_path / "bad", files=["png"])
    with pytest.raises(TypeError, match="list of kinds"):
        result.write(tmp_path / "bad", files="csv")
    with pytest.raises(TypeError, match="list of kinds"):
        block_on_line().set_output(files="csv")
    # The same settings as the scene's keys, through the builder.
    built = block_on_line().set_output(files=["vtu"], vtu_encoding="compressed").solve()
    names = sorted(f.name for f in built.write(tmp_path / "built"))
    assert names == ["block.vtu", "interface.vtu", "results.pvd", "summary.json"]
    assert b'compressor="vtkZLibDataCompressor"' in (tmp_path / "built" / "block.vtu").read_bytes()


def test_a_dict_gives_the_same_answer_as_its_file(scenes):
    """The file read by Python's own TOML reader into a dict, then by `from_dict`: the same
    scene, the same numbers to the last bit."""
    with open(scenes / "patch.toml", "rb") as f:
        d = tomllib.load(f)
    from_dict = vc.from_dict(d, base=scenes).solve()
    from_file = vc.load(scenes / "patch.toml").solve()
    for a, b in zip(from_dict.bodies, from_file.bodies):
        np.testing.assert_array_equal(a.displacement, b.displacement)
        np.testing.assert_array_equal(a.stress, b.stress)
    np.testing.assert_array_equal(from_dict.pairs[0].pressure, from_file.pairs[0].pressure)
    # The scene's own dict reads back into the same scene.
    again = vc.from_dict(vc.load(scenes / "patch.toml").to_dict(), base=scenes).solve()
    np.testing.assert_array_equal(again.pairs[0].pressure, from_file.pairs[0].pressure)


def block_on_line(p=0.01, history=None):
    s = vc.SceneBuilder(title="block on a line", solver=vc.solver("exact", tolerance=1e-13))
    block = s.add_body("block", vc.generated("voronoi", [[0, 0], [2, 1]], n=6, seed=3),
                       vc.isotropic(E=100.0, nu=0.3))
    block.dirichlet("left", x=0.0).traction("top", pressure=p)
    s.add_contact(block, "bottom", obstacle=vc.line([0, 0], [0, 1]))
    if history is not None:
        s.set_history(steps=history)
    return s


def test_a_built_scene_is_the_block_of_the_library_example():
    """A uniform pressure p on a block on a rigid line: the contact pressure is p at every
    node and the resultant p times the width (the library's own example, built in Python)."""
    s = block_on_line()
    d = s.to_dict()
    assert d["contact"][0]["obstacle"] == {"line": {"point": [0, 0], "normal": [0, 1]}}
    result = s.solve()
    pair = result.pairs[0]
    np.testing.assert_allclose(pair.pressure, 0.01, rtol=1e-6)
    assert pair.normal_resultant == pytest.approx(0.02, rel=1e-6)
    assert result.summary["contact"]["model"]["tangential_rows"] == 0
    assert result.steps == []
    assert "block on a line" in repr(result) and "pairs=1" in repr(result)
    assert repr(pair).startswith("ContactPair(index=0")
    assert "Scene(title='block on a line'" in repr(s.build())


def test_every_step_of_a_history():
    """Frictionless contact has no memory: each step is the static problem at its load, and
    elasticity is linear, so the steps at factors 0.5 and 1 differ by the factor 2."""
    result = block_on_line(history=[0.5, 1.0]).solve()
    steps = result.steps
    assert [s.time for s in steps] == [1.0, 2.0]
    half, full = steps[0], steps[1]
    np.testing.assert_allclose(half.pairs[0].pressure, 0.005, rtol=1e-6)
    np.testing.assert_allclose(2.0 * half.pairs[0].normal_force, full.pairs[0].normal_force, rtol=1e-6)
    np.testing.assert_allclose(2.0 * half.bodies[0].displacement, full.bodies[0].displacement,
                               rtol=1e-6, atol=1e-12)
    np.testing.assert_array_equal(full.pairs[0].pressure, result.pairs[0].pressure)
    assert half.report["status"] == "converged"


def test_warnings_are_python_warnings_and_a_list():
    """A pair with no node in contact (the gap never closes) is a warning of the model."""
    s = vc.SceneBuilder(title="apart")
    block = s.add_body("block", vc.generated("quads", [[0, 0], [1, 0.5]], n=4),
                       vc.isotropic(E=10.0, nu=0.3))
    block.dirichlet("top", x=0.0, y=0.0).body_force([0.0, -0.01])
    s.add_contact(block, "bottom", obstacle=vc.line([0, -1], [0, 1]))
    with pytest.warns(vc.SceneWarning) as caught:
        result = s.solve()
    assert result.warnings
    assert [str(w.message) for w in caught] == result.warnings
    assert not result.pairs[0].normal_force.any()


def test_the_gil_is_released_while_solving(scenes):
    """A Python thread runs while the scene is solved. The interpreter's forced switches are
    put off (switch interval 60 s), so the watching thread gets the GIL only when the main
    thread gives it up: while a solve that holds the GIL runs, it would see nothing."""
    scene = vc.load(scenes / "hertz.toml")
    state = {"solving": False, "seen": 0}
    done = threading.Event()

    def watcher():
        while not done.is_set():
            if state["solving"]:
                state["seen"] += 1
            time.sleep(0.0005)  # gives up the GIL

    interval = sys.getswitchinterval()
    sys.setswitchinterval(60.0)
    thread = threading.Thread(target=watcher)
    thread.start()
    try:
        state["solving"] = True
        scene.solve()
        state["solving"] = False
    finally:
        done.set()
        thread.join()
        sys.setswitchinterval(interval)
    assert state["seen"] > 0
