//! Command-line overrides (`--set KEY=VALUE`) and sweeps (`fissure sweep`).
//!
//! Reference: the contract in docs/case-format.md, "Command-line overrides and sweeps":
//! an overridden value is validated exactly like one written in the file; errors in it
//! name the override; other errors keep the case file's own line; a sweep writes one
//! folder per value and `sweep.csv` with one row per value.
//!
//! The sweep test reproduces the μ sweep of examples/inclined_crack_friction_2d.toml on a
//! coarser mesh: plate [−2, 2]², crack 2a = 0.4 at β = 45°, E = 1, ν = 0.3, plane strain,
//! compression σ = 1. Reference (closed form, infinite plate):
//! |K_II| = σ√(πa)(sinβ cosβ − μ cos²β) while the faces slip (μ < tan β = 1), 0 once they
//! stick; K_I ≈ 0 (closed crack). Tolerance: 4% of σ√(πa)·½ on the 81 × 81 mesh (the
//! example's 161 × 161 mesh is within 1.1% of the finite-plate value 0.2801).

mod common;

use fissure::case::overrides::Override;
use fissure::case::{resolve, Case, CaseError};
use fissure::sweep::SweepPlan;
use std::path::{Path, PathBuf};
use std::process::Command;

const CASE: &str = r#"[parameters]
load = 1.0

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [4, 2]

[[materials]]
E = 100.0
nu = 0.25

[[dirichlet]]
group = "left"
components = ["x", "y"]

[[traction]]
group = "right"
value = ["load", 0.0]
"#;

const CRACK: &str = r#"
[[cracks]]
name = "c"
shape = "segment"
a = [0.5, 0.5]
b = [1.5, 0.5]

[cracks.contact]
friction = 0.3
"#;

fn sets(args: &[&str]) -> Vec<Override> {
    args.iter().map(|a| Override::parse(a).unwrap_or_else(|e| panic!("{a}: {e}"))).collect()
}

fn parse_with(text: &str, args: &[&str]) -> Result<Case, CaseError> {
    Case::parse_with(text, Path::new("case.toml"), &sets(args))
}

#[test]
fn overrides_set_numbers_strings_and_new_keys() {
    let text = format!("{CASE}{CRACK}");
    let case = parse_with(
        &text,
        &["cracks.0.contact.friction=0.6", "parameters.load=2", "mesh.divisions=[8, 4]", "cracks.0.name=main"],
    )
    .unwrap();
    assert_eq!(case.cracks[0].contact.as_ref().unwrap().friction, 0.6);
    assert_eq!(case.parameters["load"], 2.0);
    assert_eq!(case.cracks[0].name, "main");
    match case.mesh {
        fissure::case::MeshSource::Generated { divisions, .. } => assert_eq!(divisions, [8, 4, 1]),
        _ => panic!("generated mesh"),
    }
    // A key the file does not have yet (here a new parameter used by a formula).
    let case = parse_with(CASE, &["parameters.p=3", "traction.0.value=[\"p\", 0]"]).unwrap();
    assert_eq!(case.parameters["p"], 3.0);
    // A bare word is a string: a formula or a choice.
    let case = parse_with(&text, &["cracks.0.contact.lbb=vital_vertex"]).unwrap();
    assert_eq!(case.cracks[0].contact.as_ref().unwrap().lbb, fissure::contact::multipliers::LbbStrategy::VitalVertex);
}

#[test]
fn a_wrong_type_in_an_override_names_the_override() {
    let text = format!("{CASE}{CRACK}");
    let e = parse_with(&text, &["cracks.0.contact.friction=abc"]).unwrap_err();
    assert_eq!(e.to_string(), "--set cracks.0.contact.friction=abc: expected a number, found a string");
    assert_eq!(e.key, "cracks[0].contact.friction");
    assert_eq!(e.line, None);
    let e = parse_with(&text, &["materials.0.nu=0.7"]).unwrap_err();
    assert!(e.to_string().starts_with("--set materials.0.nu=0.7: Poisson's ratio"), "{e}");
    let e = parse_with(&text, &["parameters.load=[1, 2]"]).unwrap_err();
    assert!(e.to_string().starts_with("--set parameters.load=[1, 2]: a parameter must be a number"), "{e}");
}

#[test]
fn an_unknown_key_in_an_override_names_the_override() {
    let text = format!("{CASE}{CRACK}");
    let e = parse_with(&text, &["cracks.0.contact.frictio=0.3"]).unwrap_err();
    assert!(e.to_string().starts_with("--set cracks.0.contact.frictio=0.3: unknown key 'frictio'"), "{e}");
    // An unknown table: the reader stops at the table the override created.
    let e = parse_with(&text, &["solverr.linear=lu"]).unwrap_err();
    assert!(e.to_string().starts_with("--set solverr.linear=lu: unknown key 'solverr'"), "{e}");
    // Entries that do not exist, and paths through values.
    let e = parse_with(&text, &["cracks.3.name=x"]).unwrap_err();
    assert_eq!(e.to_string(), "--set cracks.3.name=x: there is no cracks.3: cracks has 1 entries (0..0)");
    let e = parse_with(&text, &["cracks.first.name=x"]).unwrap_err();
    assert!(e.to_string().contains("cracks is an array: give an entry index"), "{e}");
    let e = parse_with(&text, &["mesh.cell.kind=x"]).unwrap_err();
    assert_eq!(e.to_string(), "--set mesh.cell.kind=x: mesh.cell is a string, not a table");
    let e = parse_with(&text, &["cracks.0=x"]).unwrap_err();
    assert!(e.to_string().contains("cracks.0 is a table: give one of its keys"), "{e}");
    // Malformed arguments.
    assert!(Override::parse("friction").unwrap_err().to_string().contains("expected KEY=VALUE"));
    assert!(Override::parse("a..b=1").is_err());
    assert!(Override::parse("a=").is_err());
}

#[test]
fn errors_found_after_reading_name_the_override_or_keep_the_file_line() {
    // A group that does not exist is found when the model is built.
    let case = parse_with(CASE, &["dirichlet.0.group=nowhere"]).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    let e = case.attribute(resolve::build_model(&case, &mesh).unwrap_err());
    assert!(e.to_string().starts_with("--set dirichlet.0.group=nowhere: "), "{e}");
    // An error of the file itself keeps the file's line, although the override added a
    // key (a line) above it.
    let bad = CASE.replace("nu = 0.25", "nu = 0.25\nyoung = 3.0");
    let e = Case::parse(&bad, Path::new("case.toml")).unwrap_err();
    assert_eq!(e.line, Some(13));
    let e = parse_with(&bad, &["parameters.p=3", "model.analysis=plane_stress"]).unwrap_err();
    assert_eq!(e.key, "materials[0].young");
    assert_eq!(e.line, Some(13), "{e}");
    assert!(e.to_string().starts_with("case.toml:13: key 'materials[0].young'"), "{e}");
}

#[test]
fn overrides_keep_the_rest_of_every_example_as_written() {
    // Replacing a value with itself leaves each example's text unchanged, so the file's
    // line numbers stay right in errors.
    for entry in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let case = Case::parse(&text, &path).unwrap();
        let again =
            Case::parse_with(&text, &path, &sets(&[&format!("materials.0.E={:?}", case.materials[0].material.young)]))
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(again.materials[0].material.young, case.materials[0].material.young);
    }
}

#[test]
fn a_sweep_needs_one_list_of_numbers() {
    let text = format!("{CASE}{CRACK}");
    let plan = |args: &[&str]| SweepPlan::new(&text, sets(args));
    let p = plan(&["cracks.0.contact.friction=[0, 0.3, 1.1]", "mesh.divisions=[8, 4]"]).unwrap();
    assert_eq!(p.values, vec![0.0, 0.3, 1.1]);
    assert_eq!(p.fixed.len(), 1, "a list on a key that holds a list is a plain override");
    assert_eq!(p.folder(1), "friction=0.3");
    assert_eq!(p.overrides(2).last().unwrap().to_string(), "--set cracks.0.contact.friction=1.1");
    let e = plan(&["cracks.0.contact.friction=[0, a]"]).unwrap_err();
    assert!(e.to_string().contains("a list of numbers"), "{e}");
    let e = plan(&["cracks.0.contact.lbb=[\"none\", \"vital_edge\"]"]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "--set cracks.0.contact.lbb=[\"none\", \"vital_edge\"]: a sweep takes a list of numbers; '\"none\"' is not a number"
    );
    let e = plan(&["cracks.0.contact.friction=0.3"]).unwrap_err();
    assert!(e.to_string().contains("no swept key"), "{e}");
    let e = plan(&["cracks.0.contact.friction=[0, 1]", "parameters.load=[1, 2]"]).unwrap_err();
    assert!(e.to_string().contains("one swept key at a time"), "{e}");
    let e = plan(&["cracks.0.contact.friction=[]"]).unwrap_err();
    assert!(e.to_string().contains("empty"), "{e}");
}

fn fissure(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fissure")).args(args).output().expect("fissure runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fissure_overrides_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn cli_check_and_sweep_reject_bad_overrides_with_exit_2() {
    let dir = scratch("cli_errors");
    let case = dir.join("case.toml");
    std::fs::write(&case, format!("{CASE}{CRACK}")).unwrap();
    let c = case.to_str().unwrap();
    let out = fissure(&["check", c, "--set", "cracks.0.contact.friction=abc"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("error: --set cracks.0.contact.friction=abc: expected a number, found a string"), "{err}");
    let out = fissure(&["check", c, "--set", "cracks.0.contact.friction=0.5", "--set", "parameters.load=2"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let out = fissure(&["run", c, "--set", "nokey=1", "--out", dir.join("o").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--set nokey=1: unknown key 'nokey'"));
    // Every value is validated before the first solve.
    let out = fissure(&["sweep", c, "--set", "materials.0.nu=[0.3, 0.6]", "--out", dir.join("s").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--set materials.0.nu=0.6: Poisson's ratio"));
    assert!(!dir.join("s").join("nu=0.3").exists(), "nothing solved before the error");
    let out = fissure(&["sweep", c, "--set", "cracks.0.shape=[1, 2]", "--out", dir.join("s").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--set cracks.0.shape=1: expected a string"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn friction_sweep_of_the_inclined_crack_follows_the_closed_form_k2() {
    let dir = scratch("sweep");
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/inclined_crack_friction_2d.toml");
    let out = dir.join("out");
    let run = fissure(&[
        "sweep",
        example.to_str().unwrap(),
        "--set",
        "cracks.0.contact.friction=[0, 0.3, 0.6, 1.1]",
        "--set",
        "mesh.divisions=[81, 81]",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap_or_else(|| panic!("column {name} in {head:?}"));
    assert_eq!(head[0], "cracks.0.contact.friction");
    assert_eq!(&head[1..3], &["status", "dir"]);
    assert_eq!(*head.last().unwrap(), "error");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4);
    let sigma_sqrt_pi_a = (std::f64::consts::PI * 0.2f64).sqrt();
    for (row, mu) in rows.iter().zip([0.0, 0.3, 0.6, 1.1]) {
        assert_eq!(row[0].parse::<f64>().unwrap(), mu);
        assert_eq!(row[1], "ok");
        assert!(out.join(row[2]).join("summary.json").exists(), "one folder per value: {}", row[2]);
        let reference = sigma_sqrt_pi_a * (0.5 - mu * 0.5f64).max(0.0);
        for tip in 0..2 {
            let k2: f64 = row[col(&format!("inclined.tip{tip}.KII"))].parse().unwrap();
            let k1: f64 = row[col(&format!("inclined.tip{tip}.KI"))].parse().unwrap();
            assert!(
                (k2.abs() - reference).abs() < 0.04 * 0.5 * sigma_sqrt_pi_a,
                "mu = {mu}, tip {tip}: |K_II| = {k2}, closed form {reference}"
            );
            assert!(k1.abs() < 0.04 * 0.5 * sigma_sqrt_pi_a, "mu = {mu}: K_I = {k1}");
        }
        let active: usize = row[col("contact.active")].parse().unwrap();
        let points: usize = row[col("contact.points")].parse().unwrap();
        let (stick, slip): (usize, usize) =
            (row[col("contact.stick")].parse().unwrap(), row[col("contact.slip")].parse().unwrap());
        assert_eq!(active, points, "the crack stays closed");
        if mu < 1.0 {
            assert_eq!(slip, points, "mu = {mu}: every point slips");
        } else {
            assert_eq!(stick, points, "mu = {mu}: every point sticks");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
