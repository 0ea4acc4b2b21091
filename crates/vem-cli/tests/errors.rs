//! Bad scenes give errors that say where and what: file, line and column of the offending
//! key (from the TOML parser, or from the check of a name against the meshes), the parts that
//! exist for an unknown part, the bodies for an unknown body. Never a panic. The binary
//! prints them and exits with a failure code.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::file_names;

use vem_cli::{CliError, Model, Scene};

/// A generated block "a" with the parts left, right, bottom, top.
const BLOCK: &str = r#"
[[body]]
name = "a"
mesh = { family = "quads", rectangle = [[0, 0], [1, 1]], n = 4 }
material = { E = 1.0, nu = 0.3, plane = "strain" }
"#;

/// Parses and builds `text` as the scene `bad.toml`; returns the error.
fn error_of(text: &str) -> CliError {
    match Scene::parse("bad.toml", text).and_then(|scene| Model::build(&scene)) {
        Ok(_) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Line and column of the first occurrence of `needle` in `text` (1-based).
fn position_of(text: &str, needle: &str) -> (usize, usize) {
    let start = text.find(needle).expect("needle in text");
    let line = text[..start].matches('\n').count() + 1;
    let column = start - text[..start].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// Checks that `error` is a scene error at the position of `needle` whose message contains
/// every one of `words`, and that its display starts with `bad.toml:line:column:`.
fn assert_located(error: &CliError, text: &str, needle: &str, words: &[&str]) {
    let (line, column) = position_of(text, needle);
    let at = error
        .location()
        .unwrap_or_else(|| panic!("no location: {error}"));
    assert_eq!((at.line, at.column), (line, column), "{error}");
    let shown = error.to_string();
    assert!(
        shown.starts_with(&format!("bad.toml:{line}:{column}: ")),
        "{shown}"
    );
    for word in words {
        assert!(shown.contains(word), "'{word}' missing from: {shown}");
    }
}

#[test]
fn misspelt_key_is_located_and_lists_the_keys() {
    let text = BLOCK.replace("family =", "familly =");
    let e = error_of(&text);
    assert_located(
        &e,
        &text,
        "familly",
        &["unknown field `familly`", "`family`", "`file`"],
    );
}

#[test]
fn wrong_type_is_located() {
    let text = BLOCK.replace("E = 1.0", "E = \"soft\"");
    let e = error_of(&text);
    assert_located(&e, &text, "\"soft\"", &["invalid type", "f64"]);
}

#[test]
fn syntax_error_is_located() {
    let text = "[[body]]\nname = \"a\nmesh = 1\n";
    let e = error_of(text);
    let at = e.location().unwrap();
    assert_eq!(at.line, 2, "{e}");
    assert!(e.to_string().starts_with("bad.toml:2:"), "{e}");
}

#[test]
fn unknown_variant_lists_the_choices() {
    let text = BLOCK.replace("\"strain\"", "\"strian\"");
    let e = error_of(&text);
    assert_located(&e, &text, "\"strian\"", &["`strain`", "`stress`"]);
}

#[test]
fn unknown_output_kinds_list_the_choices() {
    let text = format!("{BLOCK}\n[output]\nvtu_encoding = \"asci\"\n");
    let e = error_of(&text);
    assert_located(
        &e,
        &text,
        "\"asci\"",
        &["`binary`", "`compressed`", "`ascii`"],
    );
    let text = format!("{BLOCK}\n[output]\nfiles = [\"csv\", \"png\"]\n");
    let e = error_of(&text);
    assert_located(&e, &text, "\"png\"", &["`vtu`", "`csv`", "`pictures`"]);
}

#[test]
fn unknown_part_lists_the_parts() {
    let text = format!("{BLOCK}\n[[body.dirichlet]]\npart = \"botom\"\ny = 0.0\n");
    let e = error_of(&text);
    assert_located(
        &e,
        &text,
        "\"botom\"",
        &[
            "no boundary part named 'botom'",
            "['left', 'right', 'bottom', 'top']",
        ],
    );
}

#[test]
fn unknown_contact_part_lists_the_parts() {
    let text = format!(
        "{BLOCK}\n[[contact]]\nbody = \"a\"\npart = \"base\"\nobstacle = {{ line = {{ point = [0, 0], normal = [0, 1] }} }}\n"
    );
    let e = error_of(&text);
    assert_located(&e, &text, "\"base\"", &["'base'", "'bottom'"]);
}

#[test]
fn unknown_body_lists_the_bodies() {
    let text = format!(
        "{BLOCK}\n[[contact]]\nbody = \"a\"\npart = \"bottom\"\nother_body = \"b\"\nother_part = \"top\"\n"
    );
    let e = error_of(&text);
    assert_located(&e, &text, "\"b\"", &["no body named 'b'", "['a']"]);
}

#[test]
fn a_repeated_contact_pair_is_an_error() {
    let pair = "[[contact]]\nbody = \"a\"\npart = \"bottom\"\nobstacle = { line = { point = [0, 0], normal = [0, 1] } }\n";
    let text = format!(
        "{BLOCK}\n{pair}\n{}",
        pair.replace("contact]]", "contact]] ")
    );
    let e = error_of(&text);
    assert_located(
        &e,
        &text,
        "[[contact]] ",
        &["repeats contact[0]", "body 'a' part 'bottom'"],
    );
}

#[test]
fn law_settings_must_match_the_law() {
    let base = format!(
        "{BLOCK}\n[[contact]]\nbody = \"a\"\npart = \"bottom\"\nobstacle = {{ line = {{ point = [0, 0], normal = [0, 1] }} }}\n"
    );
    let text = format!("{base}law = \"tresca\"\n");
    assert_located(
        &error_of(&text),
        &text,
        "\"tresca\"",
        &["law 'tresca'", "missing field `friction_bound`"],
    );
    let text = format!("{base}coefficient = 0.3\n");
    assert_located(
        &error_of(&text),
        &text,
        "0.3\n",
        &["`coefficient` does not apply to law = \"frictionless\""],
    );
    let text = format!("{base}penalty = {{ factor = 10.0 }}\n");
    assert_located(
        &error_of(&text),
        &text,
        "{ factor",
        &[
            "solver 'condensed'",
            "unknown field `penalty`",
            "expected one of `tolerance`, `max_iterations`, `interface`",
        ],
    );
}

#[test]
fn inadmissible_values_are_located() {
    let text = BLOCK.replace("nu = 0.3", "nu = 0.7");
    assert_located(
        &error_of(&text),
        &text,
        "{ E = 1.0",
        &["body 'a'", "Poisson's ratio nu = 0.7"],
    );
    let text = BLOCK.replace("E = 1.0, nu = 0.3", "E = 1.0, lambda = 2.0");
    assert_located(
        &error_of(&text),
        &text,
        "{ E = 1.0",
        &["`E` and `nu`, or as `lambda` and `mu`"],
    );
    let text = BLOCK.replace("n = 4 }", "n = 0 }");
    let e = error_of(&text);
    assert!(e.to_string().contains("size n = 0"), "{e}");
}

#[test]
fn missing_mesh_file_names_the_file() {
    let text = BLOCK.replace(
        "{ family = \"quads\", rectangle = [[0, 0], [1, 1]], n = 4 }",
        "{ file = \"nowhere.msh\" }",
    );
    let e = error_of(&text);
    assert_located(&e, &text, "\"nowhere.msh\"", &["nowhere.msh"]);
}

#[test]
fn a_floating_body_is_reported_when_solved() {
    let text = format!("{BLOCK}traction = [{{ part = \"top\", value = [0.0, -1.0] }}]\n");
    let scene = Scene::parse("bad.toml", text).unwrap();
    let e = Model::build(&scene).unwrap().solve().unwrap_err();
    assert!(e.to_string().contains("not held"), "{e}");
}

fn write_scene(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vem-cli-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn vem(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_vem"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn the_binary_prints_the_located_error_and_fails() {
    let text = format!("{BLOCK}\n[[body.dirichlet]]\npart = \"botom\"\ny = 0.0\n");
    let path = write_scene("unknown_part.toml", &text);
    for command in ["check", "run"] {
        let output = vem(&[command, path.to_str().unwrap()]);
        assert!(!output.status.success());
        let stderr = String::from_utf8(output.stderr).unwrap();
        let (line, column) = position_of(&text, "\"botom\"");
        let expected = format!("error: {}:{line}:{column}: ", path.display());
        assert!(stderr.starts_with(&expected), "{stderr}");
        assert!(stderr.contains("'bottom'"), "{stderr}");
    }
}

#[test]
fn the_binary_checks_a_scene_and_explains_itself() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/signorini.toml");
    let output = vem(&["check", scene.to_str().unwrap()]);
    assert!(output.status.success());
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(stdout.contains("gamma (A1)"), "{stdout}");
    assert!(stdout.contains("against a rigid line"), "{stdout}");
    assert!(stdout.contains("no tangential rows"), "{stdout}");
    let help = String::from_utf8(vem(&["--help"]).stdout).unwrap();
    for command in ["run", "check", "mesh"] {
        assert!(help.contains(command), "{help}");
    }
    let run_help = String::from_utf8(vem(&["run", "--help"]).stdout).unwrap();
    assert!(run_help.contains("contact.csv") && run_help.contains("summary.json"));
}

#[test]
fn the_binary_writes_the_files_and_encoding_asked_for() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/signorini.toml");
    let scene = scene.to_str().unwrap();
    let out = std::env::temp_dir().join(format!("vem-cli-files-{}", std::process::id()));
    let out = out.to_str().unwrap();
    let output = vem(&[
        "run",
        scene,
        "--out",
        out,
        "--files",
        "vtu,csv",
        "--vtu-encoding",
        "ascii",
    ]);
    assert!(output.status.success(), "{output:?}");
    assert_eq!(
        file_names(Path::new(out)),
        [
            "block.vtu",
            "contact.csv",
            "interface.vtu",
            "results.pvd",
            "summary.json"
        ]
    );
    let block = std::fs::read_to_string(Path::new(out).join("block.vtu")).unwrap();
    assert!(block.contains("format=\"ascii\""));
    // `none` with another kind, an unknown kind, an unknown encoding: refused, nothing written.
    for (args, status, words) in [
        (
            ["--files", "vtu,none"],
            1,
            "cannot be given with other kinds",
        ),
        (
            ["--files", "vtu,png"],
            2,
            "expected one of `vtu`, `csv`, `pictures` or `none`",
        ),
        (
            ["--vtu-encoding", "zlib"],
            2,
            "expected one of `binary`, `compressed`, `ascii`",
        ),
    ] {
        let output = vem(&[&["run", scene, "--out", out][..], &args[..]].concat());
        assert_eq!(output.status.code(), Some(status), "{args:?}");
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert!(stderr.contains(words), "{stderr}");
    }
    assert_eq!(file_names(Path::new(out)).len(), 5);
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn the_binary_generates_a_mesh() {
    let out = std::env::temp_dir().join(format!("vem-cli-mesh-{}", std::process::id()));
    let output = vem(&[
        "mesh",
        "--family",
        "hexagons",
        "--n",
        "5",
        "--rect",
        "0,0,2,1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{output:?}");
    assert!(out.join("hexagons-5.vtu").is_file() && out.join("hexagons-5.svg").is_file());
    let output = vem(&["mesh", "--family", "pentagons"]);
    assert!(!output.status.success());
    assert!(String::from_utf8(output.stderr)
        .unwrap()
        .contains("pentagons"));
}

#[test]
fn a_gmsh_file_converts_with_its_parts() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hertz_disc.msh");
    let out = std::env::temp_dir().join(format!("vem-cli-convert-{}", std::process::id()));
    let report = vem_cli::convert_mesh(&file, &out).unwrap();
    assert_eq!(report.parts, ["arc", "top"]);
    assert!(out.join("hertz_disc.vtu").is_file() && out.join("hertz_disc.svg").is_file());
    // The half-disc of radius 1: area pi / 2 up to the polygonal arc.
    let mesh = vem_mesh::io::read_gmsh(&file).unwrap();
    let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
    assert!((area - std::f64::consts::FRAC_PI_2).abs() < 2e-3, "{area}");
    assert_eq!(report.polygons, mesh.n_polygons());
}

#[test]
fn values_the_library_rejects_are_located_at_their_key() {
    // Checked by the library (interface options, Dirichlet data when the body is built, load
    // values when it is assembled), located by the scene.
    let contact = "[[contact]]\nbody = \"a\"\npart = \"bottom\"\nobstacle = { line = { point = [0, 0], normal = [0, 1] } }\n";
    let text = format!("{BLOCK}\n{contact}max_distance = -1.0\n");
    assert_located(
        &error_of(&text),
        &text,
        "-1.0\n",
        &["max_distance = -1", "positive and finite"],
    );
    // Non-finite values are refused where they are written.
    let text = format!("{BLOCK}dirichlet = [{{ part = \"left\", x = nan }}]\n");
    assert_located(
        &error_of(&text),
        &text,
        "nan }",
        &["`body[0].dirichlet[0].x` = nan", "must be finite"],
    );
    let text = format!(
        "{BLOCK}dirichlet = [{{ part = \"bottom\", x = 0.0, y = 0.0 }}]\ntraction = [{{ part = \"top\", pressure = inf }}]\n"
    );
    assert_located(
        &error_of(&text),
        &text,
        "inf }",
        &["`body[0].traction[0].pressure` = inf", "must be finite"],
    );
}
