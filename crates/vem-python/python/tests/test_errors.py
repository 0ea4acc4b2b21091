"""Bad input raises the package's exceptions, naming the key path (and, for a file, the line
and column), never a panic."""

import math

import numpy as np
import pytest

import vemcontact as vc

GOOD = {
    "body": [{
        "name": "block",
        "mesh": {"family": "quads", "rectangle": [[0, 0], [1, 1]], "n": 2},
        "material": {"E": 1.0, "nu": 0.3, "plane": "strain"},
        "dirichlet": [{"part": "bottom", "x": 0.0, "y": 0.0}],
    }],
}


def bad(**change):
    import copy
    d = copy.deepcopy(GOOD)
    for path, value in change.items():
        *head, last = path.split("__")
        target = d
        for key in head:
            target = target[int(key)] if key.isdigit() else target[key]
        target[last] = value
    return d


def test_an_unknown_key_names_its_path():
    d = bad()
    d["body"][0]["mesh"] = {"familly": "quads", "rectangle": [[0, 0], [1, 1]], "n": 2}
    with pytest.raises(vc.SceneError) as e:
        vc.from_dict(d)
    assert e.value.key_path == "body[0].mesh.familly"
    assert e.value.path == ["body", 0, "mesh", "familly"]
    assert "familly" in e.value.message
    assert str(e.value).startswith("body[0].mesh.familly: ")
    assert e.value.line is None and e.value.file is None
    assert isinstance(e.value, ValueError)


def test_a_checked_value_names_its_path():
    """Names are checked when the scene is read, materials when it is built."""
    d = bad()
    d["contact"] = [{"body": "nobody", "part": "bottom",
                     "obstacle": {"line": {"point": [0, 0], "normal": [0, 1]}}}]
    with pytest.raises(vc.SceneError) as e:
        vc.from_dict(d)
    assert e.value.key_path == "contact[0].body"
    assert "nobody" in e.value.message and "block" in e.value.message
    scene = vc.from_dict(bad(body__0__material={"E": 1.0, "nu": 0.7, "plane": "strain"}))
    with pytest.raises(vc.SceneError) as e:
        scene.solve()
    assert e.value.key_path == "body[0].material"
    assert "0.7" in e.value.message


def test_a_wrong_type_and_a_non_finite_number_name_their_paths():
    with pytest.raises(vc.SceneError) as e:
        vc.from_dict(bad(body__0__material={"E": "stiff", "nu": 0.3, "plane": "strain"}))
    assert e.value.key_path.startswith("body[0].material")
    with pytest.raises(vc.SceneError) as e:
        vc.from_dict(bad(body__0__material={"E": math.nan, "nu": 0.3, "plane": "strain"}))
    assert e.value.key_path == "body[0].material.E"
    assert "finite" in e.value.message
    with pytest.raises(vc.SceneError) as e:
        vc.from_dict({"body": [{"name": object()}]})
    assert e.value.key_path == "body[0].name"


def test_numpy_values_are_taken():
    d = bad(body__0__mesh={"family": "quads", "rectangle": np.array([[0.0, 0.0], [1.0, 1.0]]),
                           "n": np.int64(2)})
    assert vc.from_dict(d).body_names == ["block"]


def test_an_unknown_part_is_found_when_building():
    d = bad()
    d["contact"] = [{"body": "block", "part": "botom", "obstacle": {"line": {"point": [0, 0], "normal": [0, 1]}}}]
    scene = vc.from_dict(d)
    with pytest.raises(vc.SceneError) as e:
        scene.solve()
    assert e.value.key_path == "contact[0].part"
    assert "bottom" in e.value.message  # the parts that exist are listed


def test_a_file_error_names_file_line_column_and_key_path(tmp_path):
    text = (
        '[[body]]\nname = "block"\n'
        'mesh = { family = "quads", rectangle = [[0, 0], [1, 1]], n = 2 }\n'
        'material = { E = 1.0, nu = 0.3, plane = "strian" }\n'
    )
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(vc.SceneError) as e:
        vc.load(path)
    err = e.value
    assert err.file == str(path)
    assert err.line == 4
    assert err.key_path.startswith("body[0].material")
    assert str(err).startswith(f"{path}:4:")
    # The same text from a string: the same place.
    with pytest.raises(vc.SceneError) as e:
        vc.loads(text, path="inline.toml")
    assert (e.value.line, e.value.column) == (err.line, err.column)
    assert str(e.value).startswith("inline.toml:4:")


def test_an_unknown_key_in_a_file():
    text = '[[body]]\nname = "a"\nmesh = { familly = "quads" }\n'
    with pytest.raises(vc.SceneError) as e:
        vc.loads(text)
    assert e.value.key_path == "body[0].mesh.familly"
    assert (e.value.line, e.value.column) == (3, 10)


def test_a_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        vc.load(tmp_path / "missing.toml")


def test_a_solve_without_support_is_a_solve_error():
    d = bad()
    del d["body"][0]["dirichlet"]
    d["body"][0]["body_force"] = [0.0, 1.0]
    d["contact"] = [{"body": "block", "part": "bottom", "obstacle": {"line": {"point": [0, 0], "normal": [0, 1]}}}]
    with pytest.raises(vc.SolveError) as e:
        vc.from_dict(d).solve()
    assert "no support" in str(e.value)
    assert isinstance(e.value, vc.SceneError)


def test_writing_into_a_folder_of_other_files_is_refused(tmp_path):
    result = vc.from_dict(GOOD).solve()
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(vc.OutputError):
        result.write(tmp_path)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_titles_and_reprs(scenes):
    text = ('[[body]]\nname = "a"\nmesh = { family = "quads", rectangle = [[0, 0], [1, 1]], n = 2 }\n'
            'material = { E = 1.0, nu = 0.3, plane = "strain" }\n')
    assert vc.loads(text).title == "scene"
    assert vc.loads(text, path="plate.toml").title == "plate"
    assert vc.from_dict(GOOD).title == "scene"
    scene = vc.load(scenes / "patch.toml")
    assert scene.title.startswith("Contact patch test")
    assert repr(scene).startswith("Scene(title='Contact patch test")
    assert scene.body_names == ["upper", "lower"] and scene.n_contacts == 1
