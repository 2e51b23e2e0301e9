//! Bad case files give a clear error naming the key and the line, never a panic.
//! Reference: the case-file contract in docs/case-format.md. Each test writes a small
//! case, changes one thing, and checks the message (key path and 1-based line).

use fissure::case::{resolve, Case, CaseError};
use std::path::Path;
use std::process::Command;

const GOOD: &str = r#"[mesh]
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
value = [1.0, "0.1*y"]
"#;

fn parse(text: &str) -> Result<Case, CaseError> {
    Case::parse(text, Path::new("case.toml"))
}

fn resolve_err(text: &str) -> CaseError {
    let case = parse(text).expect("parses");
    let mesh = resolve::build_mesh(&case).expect("mesh");
    resolve::build_model(&case, &mesh).expect_err("must fail")
}

#[test]
fn good_case_reads_and_resolves() {
    let case = parse(GOOD).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &mesh).unwrap();
    assert_eq!(model.dirichlet.len(), 2 * 3);
}

#[test]
fn missing_key_names_the_key_and_the_table_line() {
    let e = parse(&GOOD.replace("nu = 0.25\n", "")).unwrap_err();
    assert_eq!(e.key, "materials[0].nu");
    assert_eq!(e.line, Some(7));
    assert!(e.to_string().contains("case.toml:7: key 'materials[0].nu': missing key 'nu'"), "{e}");
}

#[test]
fn unknown_key_is_an_error_with_its_line() {
    let e = parse(&GOOD.replace("nu = 0.25", "nu = 0.25\nyoung = 3.0")).unwrap_err();
    assert_eq!(e.key, "materials[0].young");
    assert_eq!(e.line, Some(10));
    assert!(e.message.contains("unknown key 'young'"), "{e}");
    let top = parse(&format!("{GOOD}\n[solverr]\nlinear = \"lu\"\n")).unwrap_err();
    assert_eq!(top.key, "solverr");
    assert!(top.line.is_some());
}

#[test]
fn wrong_type_names_expected_and_found() {
    let e = parse(&GOOD.replace("E = 100.0", "E = \"hard\"")).unwrap_err();
    assert_eq!(e.key, "materials[0].E");
    assert_eq!(e.line, Some(8));
    assert!(e.message.contains("expected a number, found a string"), "{e}");
    let e2 = parse(&GOOD.replace("divisions = [4, 2]", "divisions = 4")).unwrap_err();
    assert_eq!((e2.key.as_str(), e2.line), ("mesh.divisions", Some(5)));
}

#[test]
fn bad_formula_shows_the_formula_and_line() {
    let e = parse(&GOOD.replace("\"0.1*y\"", "\"0.1*y +* 2\"")).unwrap_err();
    assert_eq!(e.key, "traction[0].value");
    assert_eq!(e.line, Some(17));
    assert!(e.message.contains("0.1*y +* 2"), "{e}");
    let e2 = parse(&GOOD.replace("\"0.1*y\"", "\"0.1*w\"")).unwrap_err();
    assert!(e2.message.contains("unknown variable 'w'"), "{e2}");
}

#[test]
fn unknown_group_lists_the_available_ones() {
    let e = resolve_err(&GOOD.replace("group = \"left\"", "group = \"lefft\""));
    assert_eq!(e.key, "dirichlet[0].group");
    assert_eq!(e.line, Some(11));
    assert!(e.message.contains("unknown group 'lefft'") && e.message.contains("left, right"), "{e}");
}

#[test]
fn invalid_values_and_choices_are_rejected() {
    for (from, to, key) in [
        ("nu = 0.25", "nu = 0.5", "materials[0].nu"),
        ("E = 100.0", "E = -1.0", "materials[0].E"),
        ("cell = \"quad4\"", "cell = \"hex8\"", "mesh.cell"),
        ("components = [\"x\", \"y\"]", "components = [\"x\", \"w\"]", "dirichlet[0].components"),
        ("upper = [2.0, 1.0]", "upper = [2.0]", "mesh.upper"),
    ] {
        let e = parse(&GOOD.replace(from, to)).unwrap_err();
        assert_eq!(e.key, key, "{e}");
        assert!(e.line.is_some(), "{e}");
    }
    let z = resolve_err(&GOOD.replace("components = [\"x\", \"y\"]", "components = [\"z\"]"));
    assert!(z.message.contains("does not exist in a 2D model"), "{z}");
    let toml = parse("[mesh\nfile = 1").unwrap_err();
    assert!(toml.message.contains("not valid TOML") && toml.line == Some(1), "{toml}");
}

#[test]
fn cli_reports_errors_with_exit_codes_and_no_panic() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("case_errors");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, GOOD.replace("E = 100.0", "E = true")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fissure")).arg("check").arg(&bad).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("bad.toml:8: key 'materials[0].E'") && !err.contains("panicked"), "{err}");

    // Under-constrained: only x held on the left edge.
    let under = dir.join("under.toml");
    std::fs::write(&under, GOOD.replace("components = [\"x\", \"y\"]", "components = [\"x\"]")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fissure"))
        .arg("run")
        .arg(&under)
        .arg("--out")
        .arg(dir.join("under"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("under-constrained") && err.contains("translation along y"), "{err}");
    let summary = std::fs::read_to_string(dir.join("under/summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"failed\""), "{summary}");

    let good = dir.join("good.toml");
    std::fs::write(&good, GOOD).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fissure")).arg("check").arg(&good).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// Cracks with impossible input: each error names the crack and the key, with its line.
#[test]
fn bad_cracks_are_errors_naming_the_crack() {
    let crack = |body: &str| format!("{GOOD}\n[[cracks]]\nname = \"c1\"\n{body}");
    // Entirely outside the mesh (the plate is [0, 2] × [0, 1]).
    let e = resolve_err(&crack("shape = \"segment\"\na = [5.0, 5.0]\nb = [6.0, 5.0]\n"));
    assert!(e.message.contains("crack 'c1'") && e.message.contains("outside the mesh"), "{e}");
    assert_eq!(e.key, "cracks[0].shape");
    assert_eq!(e.line, Some(19), "the line of the crack's table");
    // Impossible parameters.
    for (body, what) in [
        ("shape = \"segment\"\na = [0.5, 0.5]\nb = [0.5, 0.5]\n", "segment"),
        ("shape = \"ellipse\"\ncentre = [1.0, 0.5]\nsemi_axes = [-0.2, 0.1]\n", "ellipse"),
        ("shape = \"line\"\npoint = [1.0, 0.5]\nnormal = [0.0, 0.0]\n", "normal"),
    ] {
        let e = parse(&crack(body)).unwrap_err();
        assert!(e.message.contains("crack 'c1'") && e.key.starts_with("cracks[0]"), "{what}: {e}");
        assert!(e.line.is_some());
    }
    // A 3D shape in a 2D model.
    let e = resolve_err(&crack("shape = \"disc\"\ncentre = [1.0, 0.5, 0.0]\nnormal = [0.0, 1.0, 0.0]\nradius = 0.2\n"));
    assert!(e.message.contains("crack 'c1'") && e.message.contains("2D"), "{e}");
    // A formula that does not parse: the formula, the position and the line.
    let e = parse(&crack("shape = \"formula\"\nlsn = \"y - 0.5 +* x\"\nlst = \"x - 1\"\n")).unwrap_err();
    assert_eq!((e.key.as_str(), e.line), ("cracks[0].lsn", Some(22)));
    assert!(e.message.contains("\"y - 0.5 +* x\"") && e.message.contains("at character 10"), "{e}");
    // Unknown key in a crack table.
    let e = parse(&crack("shape = \"segment\"\na = [0.5, 0.5]\nb = [1.5, 0.5]\nradius = 2.0\n")).unwrap_err();
    assert_eq!(e.key, "cracks[0].radius");
    // Two cracks with the same name.
    let e = parse(&format!(
        "{}\n[[cracks]]\nname = \"c1\"\nshape = \"line\"\npoint = [0.0, 0.2]\nnormal = [0.0, 1.0]\n",
        crack("shape = \"line\"\npoint = [0.0, 0.5]\nnormal = [0.0, 1.0]\n")
    ))
    .unwrap_err();
    assert!(e.message.contains("two cracks are named 'c1'"), "{e}");
}

/// Contact options: a negative Coulomb coefficient, a non-positive augmentation, an
/// unknown option or an unknown loop setting are errors naming the key and its line;
/// contact on a crack that cuts no cell is an error naming the crack.
#[test]
fn bad_contact_options_are_errors_naming_the_key() {
    let crack =
        "[[cracks]]\nname = \"c1\"\nshape = \"line\"\npoint = [0.0, 0.55]\nnormal = [0.0, 1.0]\n[cracks.contact]\n";
    let base = GOOD.replace("[[traction]]\ngroup = \"right\"\nvalue = [1.0, \"0.1*y\"]\n", "");
    for (opt, key) in [
        ("friction = -0.1", "cracks[0].contact.friction"),
        ("rho_n = 0.0", "cracks[0].contact.rho_n"),
        ("rho_t = -2.0", "cracks[0].contact.rho_t"),
        ("lbb = \"vital\"", "cracks[0].contact.lbb"),
        ("integration = \"lobatto\"", "cracks[0].contact.integration"),
        ("frictoin = 0.3", "cracks[0].contact.frictoin"),
        ("sliding = \"huge\"", "cracks[0].contact.sliding"),
    ] {
        let e = parse(&format!("{base}\n{crack}{opt}\n")).unwrap_err();
        assert_eq!(e.key, key, "{e}");
        assert!(e.line.is_some(), "{e}");
    }
    let e = parse(&format!("{base}\n{crack}\n[contact_solver]\nmax_newton = 0\n")).unwrap_err();
    assert_eq!(e.key, "contact_solver.max_newton");
    let e = parse(&format!("{base}\n{crack}\n[contact_solver]\nalgorithm = \"fast\"\n")).unwrap_err();
    assert_eq!(e.key, "contact_solver.algorithm");
    let e = parse(&format!("{base}\n{crack}\n[contact_solver]\nmax_geometry = 0\n")).unwrap_err();
    assert_eq!(e.key, "contact_solver.max_geometry");
    let e = parse(&format!("{base}\n{crack}\n[contact_solver]\ntol_geometry = -1.0\n")).unwrap_err();
    assert_eq!(e.key, "contact_solver.tol_geometry");
    let e = parse(&format!("{base}\n{crack}\n[solver]\ncondense = \"yes\"\n")).unwrap_err();
    assert_eq!(e.key, "solver.condense");
    assert!(e.line.is_some(), "{e}");
    // A crack outside the mesh with contact: the crack is named.
    let outside = crack.replace("[0.0, 0.55]", "[0.0, 5.0]");
    let e = resolve_err(&format!("{base}\n{outside}friction = 0.2\n"));
    assert!(e.message.contains("crack 'c1'"), "{e}");
    // A valid contact case checks and solves through the CLI.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("contact_ok");
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("ok.toml");
    std::fs::write(&f, format!("{base}\n{crack}friction = 0.2\n")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fissure")).arg("check").arg(&f).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// `[solver] backend = "petsc"` in a build without the cargo feature `petsc`: a case
/// error at the key's line naming the feature and the build command (exit 2 from the
/// CLI); with the feature it reads. `[solver.petsc]` keys are checked either way.
#[test]
fn petsc_backend_without_the_feature_names_the_feature_and_the_build_command() {
    let text = format!("{GOOD}\n[solver]\nbackend = \"petsc\"\n");
    let line = text.lines().position(|l| l.starts_with("backend")).unwrap() + 1;
    match (parse(&text), cfg!(feature = "petsc")) {
        (Err(e), false) => {
            assert_eq!(e.key, "solver.backend");
            assert_eq!(e.line, Some(line));
            assert!(e.message.contains("feature `petsc`") && e.message.contains("--features petsc"), "{e}");
        }
        (Ok(case), true) => assert_eq!(case.solver.backend.name(), "petsc"),
        (Err(e), true) => panic!("refused with the feature: {e}"),
        (Ok(_), false) => panic!("read without the feature"),
    }
    let faer = parse(&format!("{GOOD}\n[solver]\nbackend = \"faer\"\n")).unwrap();
    assert_eq!(faer.solver.backend.name(), "faer");
    let e = parse(&format!("{GOOD}\n[solver]\nbackend = \"faer\"\n[solver.petsc]\nksp = \"cg\"\n")).unwrap_err();
    assert!(e.message.contains("backend = \"petsc\""), "{e}");
    let e = parse(&format!("{GOOD}\n[solver]\nbackend = \"petsc\"\n[solver.petsc]\nrtol = 2.0\n")).unwrap_err();
    assert_eq!(e.key, "solver.petsc.rtol");
    let e = parse(&format!("{GOOD}\n[solver]\nbackend = \"petsc\"\n[solver.petsc]\noptions = \"ksp_monitor\"\n"))
        .unwrap_err();
    assert!(e.message.contains("start with '-'"), "{e}");
    let e = parse(&format!("{GOOD}\n[solver]\nbackend = \"petsc\"\n[solver.petsc]\nkps = \"cg\"\n")).unwrap_err();
    assert!(e.message.contains("unknown key 'kps'"), "{e}");
}
