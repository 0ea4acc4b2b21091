//! Bad input and a hostile environment: never a panic, a hang, an overflow or a silently
//! different model. Standard output closed or full; arrays of the wrong length; numbers out of
//! range or overflowing; meshes larger than the memory limit; outputs written as a set (all
//! or nothing) with the temporaries of killed runs removed; an initial overlap and a contact
//! that holds nothing named with their gaps.

mod common;

use std::fs;
use std::path::PathBuf;
use std::process::{Command, Stdio};

use common::file_names;

use vem_cli::{CliError, Model, Scene};

/// The frictionless Signorini block on the rigid line y = 0 (uniform pressure p = 0.5).
const SIGNORINI: &str = r#"
[[body]]
name = "block"
mesh = { family = "quads", rectangle = [[0, 0], [2, 1]], n = 4 }
material = { E = 100.0, nu = 0.3, plane = "strain" }

[[body.dirichlet]]
part = "left"
x = 0.0

[[body.traction]]
part = "top"
pressure = 0.5

[[contact]]
body = "block"
part = "bottom"
obstacle = { line = { point = [0.0, 0.0], normal = [0.0, 1.0] } }
"#;

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vem-cli-bad-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Parses and builds `text` as `bad.toml`; returns the error.
fn error_of(text: &str) -> CliError {
    match Scene::parse("bad.toml", text).and_then(|scene| Model::build(&scene)) {
        Ok(_) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Checks that `error` is located on the line of `needle` and says every one of `words`.
fn assert_at(error: &CliError, text: &str, needle: &str, words: &[&str]) {
    let start = text.find(needle).expect("needle in text");
    let line = text[..start].matches('\n').count() + 1;
    let at = error
        .location()
        .unwrap_or_else(|| panic!("no location: {error}"));
    assert_eq!(at.line, line, "{error}");
    let shown = error.to_string();
    for word in words {
        assert!(shown.contains(word), "'{word}' missing from: {shown}");
    }
}

/// The Signorini scene with `from` replaced by `to` (which must occur).
fn signorini_with(from: &str, to: &str) -> String {
    assert!(SIGNORINI.contains(from), "{from}");
    SIGNORINI.replacen(from, to, 1)
}

#[test]
fn arrays_of_the_wrong_length_are_refused_at_their_line() {
    let cases = [
        (
            "pressure = 0.5",
            "value = [1.0, 2.0, 3.0]",
            "[1.0, 2.0, 3.0]",
            "3 entries",
        ),
        (
            "[[0, 0], [2, 1]]",
            "[[0, 0], [2, 1], [3, 3]]",
            "[[0, 0], [2, 1], [3, 3]]",
            "3 entries",
        ),
        (
            "[[0, 0], [2, 1]]",
            "[[0, 0, 0], [2, 1]]",
            "[[0, 0, 0]",
            "3 entries",
        ),
        (
            "point = [0.0, 0.0]",
            "point = [0.0]",
            "point = [0.0]",
            "1 entries",
        ),
        (
            "normal = [0.0, 1.0]",
            "normal = [0.0, 1.0, 0.0]",
            "normal = [0.0, 1.0, 0.0]",
            "3 entries",
        ),
    ];
    for (from, to, needle, words) in cases {
        let text = signorini_with(from, to);
        let e = error_of(&text);
        assert_at(&e, &text, needle, &[words, "exactly 2"]);
    }
    // The body force and a polyline: the same rule.
    let text = signorini_with(
        "[[body.dirichlet]]",
        "body_force = [0.0, -1.0, 5.0]\n[[body.dirichlet]]",
    );
    assert_at(&error_of(&text), &text, "body_force", &["3 entries"]);
    let text = signorini_with(
        "line = { point = [0.0, 0.0], normal = [0.0, 1.0] }",
        "polyline = [[3, 0], [1, 0, 7], [-1, 0]]",
    );
    assert_at(&error_of(&text), &text, "polyline", &["3 entries"]);
}

#[test]
fn numbers_out_of_range_are_refused_with_key_and_line() {
    let cases = [
        (
            "E = 100.0",
            "E = 1e308",
            "E = 1e308",
            "`body[0].material.E` = 1e308",
        ),
        ("E = 100.0", "E = 1e155", "material", "out of range"),
        (
            "E = 100.0, nu = 0.3",
            "lambda = 1.7976931348623157e308, mu = 1.0",
            "lambda = 1.79",
            "`body[0].material.lambda`",
        ),
        // Keys are located at their value, also inside a table entry (`[[body.traction]]`).
        (
            "pressure = 0.5",
            "pressure = 1e300",
            "pressure = 1e300",
            "`body[0].traction[0].pressure`",
        ),
        (
            "pressure = 0.5",
            "pressure = nan",
            "pressure = nan",
            "must be finite",
        ),
        (
            "[2, 1]]",
            "[2, 1e200]]",
            "rectangle",
            "`body[0].mesh.rectangle[1][1]`",
        ),
        (
            "x = 0.0",
            "x = inf",
            "x = inf",
            "`body[0].dirichlet[0].x` = inf",
        ),
        (
            "point = [0.0, 0.0]",
            "point = [0.0, -1e-200]",
            "obstacle",
            "`contact[0].obstacle.line.point[1]`",
        ),
    ];
    for (from, to, needle, words) in cases {
        let text = signorini_with(from, to);
        let e = error_of(&text);
        assert_at(&e, &text, needle, &[words]);
    }
    // A Hertz radius of f64::MAX, a picture 1e300 pixels wide.
    let text = format!("{SIGNORINI}hertz = {{ radius = 1.7976931348623157e308 }}\n");
    assert_at(
        &error_of(&text),
        &text,
        "hertz",
        &["`contact[0].hertz.radius`", "out of range"],
    );
    let text = format!("{SIGNORINI}\n[output]\nwidth = 1e300\n");
    assert_at(&error_of(&text), &text, "width", &["at most 20000"]);
    // The limits themselves are accepted: 1e100 and 1e-100.
    let text = signorini_with("pressure = 0.5", "pressure = 1e-100");
    Scene::parse("ok.toml", text).unwrap();
}

#[test]
fn overflowing_material_says_so_once() {
    // Each number in range, their combination overflowing is refused by the library with
    // one "invalid material" (the element layer's reason, not doubled).
    let text = signorini_with("E = 100.0, nu = 0.3", "lambda = 1e100, mu = -1e100");
    let shown = error_of(&text).to_string();
    assert_eq!(shown.matches("invalid material").count(), 1, "{shown}");
    assert!(shown.contains("mu = -1e100"), "{shown}");
}

#[test]
fn meshes_beyond_the_memory_limit_are_refused_before_generation() {
    // quads n = 7000 on a square: 4.9e7 cells (an abort on a failed allocation before).
    let text = signorini_with("[[0, 0], [2, 1]], n = 4", "[[0, 0], [1, 1]], n = 7000");
    let text = format!("{text}\n[limits]\nmemory_gib = 64\n");
    let e = error_of(&text);
    assert_at(
        &e,
        &text,
        "mesh =",
        &[
            "49000000 polygons",
            "needs about",
            "64.0 GiB",
            "[limits] memory_gib",
        ],
    );
    // The same scene within a (generous) limit of the command line is only counted, not
    // built: a small limit refuses even the 4 x 2 block.
    let small = Scene::parse("small.toml", SIGNORINI)
        .unwrap()
        .with_memory_limit(
            vem_cli::resources::MemoryLimit::try_from_gib(
                1e-6,
                vem_cli::resources::LimitOrigin::CommandLine,
            )
            .unwrap(),
        );
    let shown = Model::build(&small).unwrap_err().to_string();
    assert!(shown.contains("--memory-limit"), "{shown}");
    // A tall rectangle with Voronoi n = 9: 8.1e6 cells, refused at once (not minutes).
    let text = signorini_with(
        "family = \"quads\", rectangle = [[0, 0], [2, 1]]",
        "family = \"voronoi\", rectangle = [[0, 0], [1, 1e5]]",
    )
    .replace("n = 4", "n = 9");
    let e = error_of(&text);
    assert_at(&e, &text, "mesh =", &["8100000 cells"]);
}

/// Runs the binary with `args`, standard output to `stdout`; returns the exit code and the
/// standard error.
fn vem(args: &[&str], stdout: Stdio) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_vem"))
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn closed_or_full_standard_output_is_no_panic() {
    let dir = scratch("stdout");
    let scene = dir.join("s.toml");
    fs::write(&scene, SIGNORINI).unwrap();
    let scene = scene.to_str().unwrap();
    // A reader that went away (`vem check s.toml | head -0`): quiet success.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vem"))
        .args(["check", scene])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // A full disk: an error naming standard output, exit code 1.
    if let Ok(full) = fs::OpenOptions::new().write(true).open("/dev/full") {
        let (code, stderr) = vem(&["check", scene], Stdio::from(full));
        assert_eq!(code, Some(1), "{stderr}");
        assert!(
            stderr.contains("cannot write to standard output"),
            "{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // The command line's memory limit, and its refusal of nonsense.
    let (code, stderr) = vem(
        &[
            "mesh",
            "--family",
            "quads",
            "--n",
            "18",
            "--rect",
            "0,0,1,1e5",
            "--memory-limit",
            "1",
        ],
        Stdio::null(),
    );
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("32400000 polygons") && stderr.contains("--memory-limit"),
        "{stderr}"
    );
    let (code, stderr) = vem(&["check", scene, "--memory-limit=-3"], Stdio::null());
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("memory limit -3 GiB"), "{stderr}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn outputs_are_replaced_as_a_set_and_stale_temporaries_removed() {
    let dir = scratch("atomic");
    let scene = dir.join("s.toml");
    fs::write(&scene, SIGNORINI).unwrap();
    let out = dir.join("out");
    // An earlier run's folder with a file this run does not write, and the temporaries of a
    // killed run (a process id above the kernel's largest never runs).
    fs::create_dir(&out).unwrap();
    fs::write(out.join("other.vtu"), "old").unwrap();
    fs::write(out.join("summary.json"), "{}").unwrap();
    fs::write(out.join(".block.vtu.4194399.0.tmp"), "half").unwrap();
    fs::create_dir(dir.join(".out.4194399.2.tmp")).unwrap();
    fs::write(dir.join(".out.4194399.2.tmp/block.vtu"), "half").unwrap();
    let (outcome, files) = vem_cli::run(&scene, Some(&out)).unwrap();
    let expected = [
        "block.vtu",
        "contact.csv",
        "deformed.svg",
        "interface.vtu",
        "pressure.svg",
        "results.pvd",
        "summary.json",
    ];
    assert_eq!(file_names(&out), expected);
    assert_eq!(files.len(), expected.len());
    assert!(files.iter().all(|f| f.parent() == Some(out.as_path())));
    assert_eq!(file_names(&dir), ["out", "s.toml"]);
    // The summary on disk is this run's.
    let summary = fs::read_to_string(out.join("summary.json")).unwrap();
    let written: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert_eq!(
        written["contact"]["nodes"],
        serde_json::to_value(outcome.summary.contact.as_ref().unwrap().nodes).unwrap()
    );
    // A run that fails leaves the earlier result as it was and no temporary.
    let before = fs::read(out.join("summary.json")).unwrap();
    let pulled = dir.join("pulled.toml");
    fs::write(&pulled, signorini_with("pressure = 0.5", "pressure = -0.5")).unwrap();
    assert!(vem_cli::run(&pulled, Some(&out)).is_err());
    assert_eq!(fs::read(out.join("summary.json")).unwrap(), before);
    assert_eq!(file_names(&dir), ["out", "pulled.toml", "s.toml"]);
    // A folder holding anything a run does not write is refused, not replaced.
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let refused = vem_cli::run(&scene, Some(&out)).unwrap_err().to_string();
    assert!(refused.contains("notes.txt"), "{refused}");
    assert!(out.join("notes.txt").exists());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn overlap_is_a_warning_and_no_support_names_the_gaps() {
    let dir = scratch("overlap");
    // The line 0.1 above the bottom: every node overlaps by 0.1, solved as an interference
    // fit; the contact pressure is then set by the imposed overlap, not by p.
    let scene = dir.join("overlap.toml");
    fs::write(
        &scene,
        signorini_with("point = [0.0, 0.0]", "point = [0.0, 0.1]"),
    )
    .unwrap();
    let (outcome, _) = vem_cli::run(&scene, Some(&dir.join("out"))).unwrap();
    let contact = outcome.summary.contact.as_ref().unwrap();
    let warning = contact
        .warnings
        .iter()
        .find(|w| w.starts_with("initial overlap"))
        .unwrap_or_else(|| panic!("{:?}", contact.warnings));
    assert!(
        warning.contains("5 of 5 interface nodes") && warning.contains("-1.000e-1"),
        "{warning}"
    );
    // Frictionless nodes in contact are labelled so.
    assert_eq!(contact.nodes.contact, 5);
    assert_eq!(contact.nodes.slip, 0);
    // Pulled away from the line, held sideways only: the contact holds nothing.
    let scene = dir.join("pulled.toml");
    fs::write(&scene, signorini_with("pressure = 0.5", "pressure = -0.5")).unwrap();
    let e = vem_cli::run(&scene, Some(&dir.join("out2"))).unwrap_err();
    let shown = e.to_string();
    assert!(
        shown.contains("body 'block' part 'bottom' against a rigid line")
            && shown.contains("no support")
            && shown.contains("initial gaps from 0.000e0 to 0.000e0 at its 5 nodes"),
        "{shown}"
    );
    // The solver's own words follow, once.
    assert_eq!(shown.matches("unbounded energy").count(), 1, "{shown}");
    fs::remove_dir_all(&dir).unwrap();
}
