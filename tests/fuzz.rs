//! Fuzzing by property-based generators (proptest): the case reader, the formula parser,
//! the Gmsh reader and the cut of one cell by arbitrary level sets never panic, and the
//! cut partitions the cell. `cargo fuzz` needs a nightly toolchain, which this project
//! does not require: proptest on stable is the tool (docs/reliability.md).
//!
//! Each target runs a few hundred cases in CI; the `#[ignore]`d `long_*` tests run
//! `FISSURE_FUZZ_CASES` cases (default 100 000) and print the executions reached:
//! `cargo test --release --test fuzz -- --ignored --nocapture`.

use fissure::case::{resolve, Case, MeshSource};
use fissure::cut::{cut_crack, CutOptions};
use fissure::element::CellType;
use fissure::formula::Formula;
use fissure::levelset::NodalLevelSets;
use fissure::mesh::{gmsh::parse_msh, Cell, Mesh};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

fn long_cases() -> u32 {
    std::env::var("FISSURE_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(100_000)
}

/// Runs `check` on `cases` generated values; panics (with proptest's shrunk input) on
/// the first failure; prints the executions and the time.
fn fuzz<S: Strategy>(name: &str, cases: u32, strategy: S, check: impl Fn(S::Value) -> Result<(), TestCaseError>)
where
    S::Value: std::fmt::Debug,
{
    let start = Instant::now();
    let config = Config { cases, failure_persistence: None, max_shrink_iters: 2000, ..Config::default() };
    let mut runner = TestRunner::new(config);
    // Shrinking re-runs a panicking case many times: print proptest's summary only.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let executions = std::sync::atomic::AtomicUsize::new(0);
    let result = runner.run(&strategy, |v| {
        executions.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        check(v)
    });
    std::panic::set_hook(hook);
    eprintln!(
        "fuzz {name}: {} executions (shrinking included) in {:.1} s",
        executions.into_inner(),
        start.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("fuzz {name}: {e}");
    }
}

// ---------------------------------------------------------------------------------------
// Formula parser.

const TOKENS: [&str; 44] = [
    "x",
    "y",
    "z",
    "t",
    "a",
    "E",
    "PI",
    "π",
    "1",
    "0",
    "2.5",
    "1e308",
    "1e-308",
    "2.5e3",
    ".5",
    "5.",
    "+",
    "-",
    "*",
    "/",
    "^",
    "(",
    ")",
    "sin",
    "sqrt",
    "ln",
    "exp",
    "abs",
    "atan",
    " ",
    "e",
    "#",
    "1e",
    "--",
    "**",
    "(-",
    "0/0",
    "ä",
    "_",
    "99999999999999999999999",
    "1e400",
    "E1",
    "x2",
    ",",
];

fn formula_strategy() -> impl Strategy<Value = String> {
    prop::collection::vec(0..TOKENS.len(), 0..24).prop_map(|v| v.into_iter().map(|i| TOKENS[i]).collect())
}

fn check_formula(src: String) -> Result<(), TestCaseError> {
    let params = BTreeMap::from([("a".to_string(), 2.0), ("E".to_string(), 1e7)]);
    if let Ok(f) = Formula::parse(&src, &params) {
        for p in [[0.0, 0.0, 0.0], [1e300, -1e300, 0.5], [f64::MIN_POSITIVE, 1.0, -1.0]] {
            let _ = f.eval(p, 0.5);
        }
        // The parameter E is never Euler's number.
        if src.trim() == "E" {
            prop_assert_eq!(f.eval([0.0; 3], 0.0), 1e7);
        }
    }
    Ok(())
}

#[test]
fn formula_parser_never_panics() {
    fuzz("formula", 2000, formula_strategy(), check_formula);
}

#[test]
#[ignore]
fn long_formula_parser_never_panics() {
    fuzz("formula", long_cases(), formula_strategy(), check_formula);
}

// ---------------------------------------------------------------------------------------
// Case reader: a valid case damaged line by line.

const CASE: &str = r#"[parameters]
p = 2.0
E = 1e7

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [8, 4]

[[sets]]
name = "mid"
on = "x - 1"
tolerance = 0.3

[[materials]]
E = 100.0
nu = 0.3

[[dirichlet]]
group = "left"
components = ["x", "y"]

[[traction]]
group = "right"
value = ["p * y", 0.0]

[[cracks]]
name = "c"
shape = "segment"
a = [0.7, 0.5]
b = [1.3, 0.5]

[cracks.contact]
friction = 0.3

[steps]
count = 2

[solver]
linear = "ldlt"
"#;

const VALUES: [&str; 26] = [
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e308",
    "1e-308",
    "\"\"",
    "\"x/0\"",
    "\"0/0\"",
    "[]",
    "[100000, 100000]",
    "[0, 0]",
    "true",
    "\"sqrt(-1)\"",
    "{}",
    "[[1]]",
    "\"ä\"",
    "9223372036854775807",
    "-9223372036854775808",
    "1.5",
    "[1.0]",
    "\"+\"",
    "[1.0, 2.0, 3.0, 4.0]",
    "\"E * PI\"",
    "[\"nan\", 1]",
];

#[derive(Debug, Clone)]
enum Edit {
    DeleteLine(prop::sample::Index),
    Value(prop::sample::Index, usize),
    DuplicateLine(prop::sample::Index),
    Truncate(prop::sample::Index),
    Byte(prop::sample::Index, u8),
}

fn edit_strategy() -> impl Strategy<Value = Vec<Edit>> {
    let one = prop_oneof![
        any::<prop::sample::Index>().prop_map(Edit::DeleteLine),
        (any::<prop::sample::Index>(), 0..VALUES.len()).prop_map(|(i, v)| Edit::Value(i, v)),
        any::<prop::sample::Index>().prop_map(Edit::DuplicateLine),
        any::<prop::sample::Index>().prop_map(Edit::Truncate),
        (any::<prop::sample::Index>(), any::<u8>()).prop_map(|(i, b)| Edit::Byte(i, b)),
    ];
    prop::collection::vec(one, 1..4)
}

fn apply(edits: &[Edit]) -> String {
    let mut lines: Vec<String> = CASE.lines().map(String::from).collect();
    let mut text = String::new();
    for e in edits {
        match e {
            Edit::DeleteLine(i) => {
                lines.remove(i.index(lines.len()));
            }
            Edit::Value(i, v) => {
                let k = i.index(lines.len());
                if let Some((key, _)) = lines[k].split_once(" = ") {
                    lines[k] = format!("{key} = {}", VALUES[*v]);
                }
            }
            Edit::DuplicateLine(i) => {
                let k = i.index(lines.len());
                lines.insert(k, lines[k].clone());
            }
            Edit::Truncate(_) | Edit::Byte(..) => {}
        }
        if lines.is_empty() {
            lines.push(String::new());
        }
    }
    text.push_str(&lines.join("\n"));
    let mut bytes = text.into_bytes();
    for e in edits {
        match e {
            Edit::Truncate(i) => bytes.truncate(i.index(bytes.len() + 1)),
            Edit::Byte(i, b) if !bytes.is_empty() => {
                let k = i.index(bytes.len());
                bytes[k] = *b;
            }
            _ => {}
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

fn check_case(edits: Vec<Edit>) -> Result<(), TestCaseError> {
    let text = apply(&edits);
    let Ok(case) = Case::parse(&text, Path::new("fuzz.toml")) else { return Ok(()) };
    // Resolve small models only (the memory guard refuses the absurd ones, tested elsewhere).
    if let MeshSource::Generated { divisions, .. } = &case.mesh {
        if divisions.iter().map(|&d| d as f64 + 1.0).product::<f64>() > 2e4 {
            return Ok(());
        }
    }
    let Ok(mesh) = resolve::build_mesh(&case) else { return Ok(()) };
    let Ok(model) = resolve::build_model(&case, &mesh) else { return Ok(()) };
    let _ = resolve::build_contact(&case, &model);
    Ok(())
}

/// Found by the case-reader fuzzer: `count = 9223372036854775807` in `[steps]` aborted on
/// a capacity overflow; it is now an error naming `steps.count`.
#[test]
fn absurd_step_count_is_an_error_not_an_abort() {
    let text = CASE.replace("count = 2", "count = 9223372036854775807");
    let e = Case::parse(&text, Path::new("fuzz.toml")).unwrap_err();
    assert_eq!(e.key, "steps.count", "{e}");
}

#[test]
fn case_reader_never_panics() {
    fuzz("case reader", 300, edit_strategy(), check_case);
}

#[test]
#[ignore]
fn long_case_reader_never_panics() {
    fuzz("case reader", long_cases() / 10, edit_strategy(), check_case);
}

// ---------------------------------------------------------------------------------------
// Gmsh reader: bundled meshes with bytes overwritten, inserted, removed, or cut short.

fn mesh_bytes(name: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes").join(name)).unwrap()
}

const MESHES: [&str; 4] = ["block.msh", "block_binary.msh", "old_format_v22.msh", "plate_with_hole_binary.msh"];

fn msh_strategy() -> impl Strategy<Value = (usize, Vec<(prop::sample::Index, u8, u8)>, Option<prop::sample::Index>)> {
    (
        0..MESHES.len(),
        prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<u8>()), 1..8),
        proptest::option::weighted(0.2, any::<prop::sample::Index>()),
    )
}

fn check_msh(
    (which, edits, cut): (usize, Vec<(prop::sample::Index, u8, u8)>, Option<prop::sample::Index>),
    files: &[Vec<u8>],
) -> Result<(), TestCaseError> {
    let mut b = files[which].clone();
    for (i, op, v) in edits {
        let k = i.index(b.len());
        match op {
            0 => b[k] = v,
            1 => b.insert(k, v),
            _ => {
                b.remove(k);
            }
        }
    }
    if let Some(c) = cut {
        b.truncate(c.index(b.len()));
    }
    if let Ok(mesh) = parse_msh(&b, MESHES[which]) {
        let _ = mesh.validate();
    }
    Ok(())
}

#[test]
fn gmsh_reader_never_panics() {
    let files: Vec<Vec<u8>> = MESHES.iter().map(|m| mesh_bytes(m)).collect();
    fuzz("gmsh reader", 200, msh_strategy(), |v| check_msh(v, &files));
}

#[test]
#[ignore]
fn long_gmsh_reader_never_panics() {
    let files: Vec<Vec<u8>> = MESHES.iter().map(|m| mesh_bytes(m)).collect();
    fuzz("gmsh reader", long_cases() / 10, msh_strategy(), |v| check_msh(v, &files));
}

// ---------------------------------------------------------------------------------------
// The cut of one cell by arbitrary nodal level sets: any magnitudes (1e-300 to 1e300),
// exact zeros, exact ties. Property: no panic; the sub-cells partition the reference
// cell (Σ reference measures = the cell's, 1e-10 relative); each facet has 2 (2D) or 3
// (3D) vertices.

fn one_cell(kind: CellType) -> Mesh {
    let nodes: Vec<[f64; 3]> = match kind {
        CellType::Tri3 => vec![[0.1, -0.2, 0.0], [1.3, 0.1, 0.0], [0.4, 0.9, 0.0]],
        CellType::Quad4 => vec![[0.0, 0.0, 0.0], [2.0, 0.2, 0.0], [1.7, 1.5, 0.0], [-0.2, 1.1, 0.0]],
        CellType::Tet4 => vec![[0.0, 0.1, 0.0], [1.2, 0.0, 0.1], [0.2, 0.9, -0.1], [0.1, 0.2, 1.1]],
        CellType::Hex8 => vec![
            [0.0, 0.0, 0.0],
            [1.1, 0.1, 0.05],
            [1.2, 1.0, -0.1],
            [-0.1, 0.9, 0.1],
            [0.1, -0.1, 1.0],
            [1.0, 0.05, 1.2],
            [1.1, 1.1, 0.9],
            [0.05, 1.0, 1.1],
        ],
    };
    let idx: Vec<usize> = (0..nodes.len()).collect();
    Mesh { dim: kind.dim(), nodes, cells: vec![Cell::new(kind, &idx)], ..Default::default() }
}

fn level_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1.0f64..1.0,
        Just(0.0),
        Just(-0.0),
        (-1.0f64..1.0, -300i32..300).prop_map(|(m, e)| m * 10f64.powi(e)),
        Just(f64::MIN_POSITIVE),
        Just(-f64::MIN_POSITIVE),
        Just(1e-300),
        Just(1e300),
    ]
}

fn cut_strategy() -> impl Strategy<Value = (usize, Vec<f64>, Option<Vec<f64>>)> {
    (0usize..4, prop::collection::vec(level_value(), 8), proptest::option::of(prop::collection::vec(level_value(), 8)))
}

fn check_cell_cut((k, n, t): (usize, Vec<f64>, Option<Vec<f64>>)) -> Result<(), TestCaseError> {
    let kind = [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8][k];
    let m = one_cell(kind);
    let nn = kind.n_nodes();
    let ls = NodalLevelSets { lsn: n[..nn].to_vec(), lst: t.map(|t| t[..nn].to_vec()) };
    let Ok(cut) = cut_crack(&m, &ls, &CutOptions::default()) else { return Ok(()) };
    for cc in &cut.cut_cells {
        let total: f64 = cc.subcells.iter().map(|s| s.reference_measure()).sum();
        let parent = kind.reference_measure();
        prop_assert!((total - parent).abs() <= 1e-10 * parent, "{kind:?}: sub-cells {total} vs {parent}");
    }
    for f in &cut.facets {
        prop_assert_eq!(f.vertices.len(), kind.dim());
        prop_assert!(f.vertices.iter().flatten().all(|v| v.is_finite()), "facet {:?}", f.vertices);
    }
    Ok(())
}

#[test]
fn cut_of_one_cell_never_panics_and_partitions_it() {
    fuzz("cell cut", 500, cut_strategy(), check_cell_cut);
}

#[test]
#[ignore]
fn long_cut_of_one_cell_never_panics_and_partitions_it() {
    fuzz("cell cut", long_cases(), cut_strategy(), check_cell_cut);
}
