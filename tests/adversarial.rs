//! A generator of adversarial inputs, run through the `fissure` binary as a user would:
//! families of case values (negative, zero, huge, NaN and infinite numbers, formulas that
//! divide by zero), truncated meshes, crack placements against nodes, edges and the
//! boundary, and contact parameters over 12 orders of magnitude. For each input the
//! outcome must be one of:
//! - a clean error: exit 2 (case) or 1 (solve, with `summary.json` saying `failed`), and
//!   a message naming the key, crack or field the input's family expects;
//! - a result: exit 0, every figure of `summary.json` finite, and the input's reference
//!   check within its stated tolerance.
//!
//! Panics, aborts (a signal), hangs (the time limit) and wrong answers are failures.
//! Inputs that fail for a reason owned by another item of issue 11 are listed in
//! [`KNOWN`] with the item: they are counted and printed, never hidden, and do not fail
//! the test; a known failure that passes is reported so that the list can shrink.
//!
//! `cargo test --release --test adversarial -- --nocapture` runs the fast part and prints
//! the tally; `-- --ignored` adds the long randomised part (docs/reliability.md).

#[path = "common/cli.rs"]
mod cli;

use serde_json::Value;
use std::time::Duration;

const LIMIT: Duration = Duration::from_secs(180);

/// Inputs whose failure belongs to another item of issue 11 (input name, item): a name
/// ending in `*` matches every input that starts with the rest, one starting with `*`
/// every input that ends with the rest.
const KNOWN: &[(&str, &str)] = &[
    // Empty: items 1, 7 and 14 (`*/start_outside`, `*/start_on_boundary`,
    // `degenerate_formula`, `unit/threshold_huge`) pass since their fixes.
];

fn is_known(name: &str) -> Option<&'static str> {
    KNOWN
        .iter()
        .find(|(p, _)| match (p.strip_prefix('*'), p.strip_suffix('*')) {
            (Some(tail), _) => name.ends_with(tail),
            (_, Some(head)) => name.starts_with(head),
            _ => name == *p,
        })
        .map(|k| k.1)
}

type Reference = Box<dyn Fn(&Value) -> Result<(), String>>;

struct Input {
    family: &'static str,
    name: String,
    text: String,
    /// Words one of which a clean error must contain (the key, crack or field).
    names: Vec<&'static str>,
    /// `None`: the input must give an error; `Some`: a result is allowed and checked.
    reference: Option<Reference>,
    /// An error is not acceptable (valid input): only a result passes.
    must_solve: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Verdict {
    CleanError,
    Result,
    Failure,
}

fn judge(input: &Input, o: &cli::Outcome) -> (Verdict, String) {
    if o.timed_out {
        return (Verdict::Failure, format!("hang (killed after {LIMIT:?})"));
    }
    if o.stderr.contains("panicked") {
        return (Verdict::Failure, format!("panic: {}", o.stderr.trim()));
    }
    let Some(code) = o.code else { return (Verdict::Failure, format!("abort (signal): {}", o.stderr.trim())) };
    match code {
        0 => {
            let Some(s) = &o.summary else { return (Verdict::Failure, "exit 0 without summary.json".into()) };
            if s["status"] != "ok" {
                return (Verdict::Failure, format!("exit 0 with status {}", s["status"]));
            }
            let bad = cli::non_finite_figures(s);
            if !bad.is_empty() {
                return (Verdict::Failure, format!("non-finite figures reported ok: {bad:?}"));
            }
            match &input.reference {
                None => (Verdict::Failure, "a result where an error was expected".into()),
                Some(r) => match r(s) {
                    Ok(()) => (Verdict::Result, String::new()),
                    Err(m) => (Verdict::Failure, format!("wrong answer: {m}")),
                },
            }
        }
        1 | 2 => {
            let msg = o.stderr.trim().to_string();
            if !msg.contains("error:") {
                return (Verdict::Failure, format!("exit {code} without an error message: {msg}"));
            }
            if code == 1 && !o.stderr.contains("check") && o.summary.as_ref().is_none_or(|s| s["status"] != "failed") {
                return (Verdict::Failure, format!("exit 1 without summary.json status failed: {msg}"));
            }
            if input.must_solve {
                return (Verdict::Failure, format!("valid input refused: {msg}"));
            }
            if input.names.iter().any(|w| msg.contains(w)) {
                (Verdict::CleanError, msg)
            } else {
                (Verdict::Failure, format!("error naming none of {:?}: {msg}", input.names))
            }
        }
        c => (Verdict::Failure, format!("exit {c}: {}", o.stderr.trim())),
    }
}

fn num(s: &Value, path: &[&str]) -> f64 {
    let mut v = s;
    for p in path {
        v = match p.parse::<usize>() {
            Ok(i) => &v[i],
            Err(_) => &v[*p],
        };
    }
    v.as_f64().unwrap_or(f64::NAN)
}

fn last_step(s: &Value) -> &Value {
    s["steps"].as_array().and_then(|a| a.last()).unwrap_or(&Value::Null)
}

// ---------------------------------------------------------------------------------------
// Family 1: case values on a plate in tension.

/// Plate [0, 2] × [0, 1], quad4 8 × 4, plane strain, left edge clamped, traction
/// (σ, 0) on the right edge.
fn plate(e: &str, nu: &str, traction: &str, mesh: &str, extra: &str) -> String {
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\n{mesh}\n\n[[materials]]\nE = {e}\nnu = {nu}\n\n[[dirichlet]]\ngroup = \"left\"\ncomponents = [\"x\", \"y\"]\n\n[[traction]]\ngroup = \"right\"\nvalue = [{traction}, 0.0]\n{extra}"
    )
}

const MESH: &str = "upper = [2.0, 1.0]\ndivisions = [8, 4]";

/// The reference of the plate: the solution is linear in σ/E, so max |u| = u₁ σ/E with
/// u₁ the value for σ = E = 1 (measured by the same code on the same mesh, exact
/// scaling), to 1e-6 relative.
fn plate_reference(u1: f64, sigma: f64, e: f64) -> Reference {
    Box::new(move |s| {
        let u = num(last_step(s), &["max_displacement"]);
        let expected = u1 * sigma / e;
        if (u - expected).abs() <= 1e-6 * expected.abs() {
            Ok(())
        } else {
            Err(format!("max |u| = {u:e}, expected {expected:e} (σ/E scaling)"))
        }
    })
}

fn case_values(u1: f64) -> Vec<Input> {
    let mut v = vec![];
    let err = |name: &str, text: String, names: Vec<&'static str>| Input {
        family: "case values",
        name: name.into(),
        text,
        names,
        reference: None,
        must_solve: false,
    };
    for (name, e) in
        [("e_zero", "0.0"), ("e_negative", "-1.0"), ("e_nan", "nan"), ("e_inf", "inf"), ("e_string", "\"1e7\"")]
    {
        v.push(err(name, plate(e, "0.3", "1.0", MESH, ""), vec!["'materials[0].E'"]));
    }
    for (name, nu) in [("nu_half", "0.5"), ("nu_minus_one", "-1.0"), ("nu_nan", "nan"), ("nu_big", "1e300")] {
        v.push(err(name, plate("1.0", nu, "1.0", MESH, ""), vec!["'materials[0].nu'"]));
    }
    // Extreme but valid: a result within the scaling reference, or a clean error naming
    // the non-finite field.
    for (name, e, sigma) in [
        ("e_tiny", 1e-300, 1.0),
        ("e_huge", 1e300, 1.0),
        ("e_tiny_load_tiny", 1e-300, 1e-300),
        ("load_huge", 1.0, 1e300),
        ("load_tiny", 1.0, 1e-300),
        ("steel_si", 2.1e11, 1e3),
        ("nu_nearly_half", 1.0, 1.0),
    ] {
        let nu = if name == "nu_nearly_half" { "0.4999999" } else { "0.3" };
        let mut i = err(
            name,
            plate(&format!("{e:e}"), nu, &format!("{sigma:e}"), MESH, ""),
            vec!["non-finite", "linear solve"],
        );
        if name != "nu_nearly_half" {
            i.reference = Some(plate_reference(u1, sigma, e));
        } else {
            i.reference = Some(Box::new(|_| Ok(())));
        }
        v.push(i);
    }
    for (name, t, names) in [
        ("load_div_zero", "\"1/0\"", vec!["load", "traction"]),
        ("load_nan", "\"sqrt(-1)\"", vec!["load", "traction"]),
        ("load_inf", "inf", vec!["load", "traction"]),
        ("load_bad_formula", "\"1 +* x\"", vec!["traction[0].value"]),
        ("load_unknown_variable", "\"q*x\"", vec!["unknown variable 'q'"]),
    ] {
        v.push(err(name, plate("1.0", "0.3", t, MESH, ""), names));
    }
    for (name, mesh) in [
        ("divisions_zero", "upper = [2.0, 1.0]\ndivisions = [0, 4]"),
        ("divisions_negative", "upper = [2.0, 1.0]\ndivisions = [-1, 4]"),
        ("divisions_absurd", "upper = [2.0, 1.0]\ndivisions = [1000000000, 1000000000]"),
        ("divisions_absurd_3", "upper = [2.0, 1.0]\ndivisions = [9223372036854775807, 1]"),
        ("upper_below_lower", "upper = [0.0, 1.0]\ndivisions = [8, 4]"),
        ("upper_nan", "upper = [nan, 1.0]\ndivisions = [8, 4]"),
    ] {
        v.push(err(name, plate("1.0", "0.3", "1.0", mesh, ""), vec!["mesh.divisions", "mesh.upper"]));
    }
    for (name, mesh, scale) in [
        ("domain_tiny", "upper = [2e-200, 1e-200]\ndivisions = [8, 4]", 1e-200),
        ("domain_huge", "upper = [2e200, 1e200]\ndivisions = [8, 4]", 1e200),
        ("one_cell_high", "upper = [2.0, 1.0]\ndivisions = [1, 1]", f64::NAN),
    ] {
        let mut i = err(name, plate("1.0", "0.3", "1.0", mesh, ""), vec!["non-finite", "linear solve", "mesh"]);
        i.reference = Some(if scale.is_nan() {
            Box::new(|_| Ok(()))
        } else {
            // Displacements scale with the size: max |u| = u₁ × size.
            plate_reference(u1 * scale, 1.0, 1.0)
        });
        v.push(i);
    }
    for (name, extra, names) in [
        ("steps_nan", "[steps]\nfactors = [nan]\n", vec!["steps.factors"]),
        ("steps_zero", "[steps]\ncount = 0\n", vec!["steps.count"]),
        (
            "dirichlet_nan",
            "[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"y\"]\nvalue = \"0/0\"\n",
            vec!["Dirichlet value"],
        ),
        ("group_unknown", "[[dirichlet]]\ngroup = \"nowhere\"\ncomponents = [\"y\"]\n", vec!["dirichlet[1].group"]),
        ("typo_key", "[solver]\nlinaer = \"lu\"\n", vec!["did you mean 'linear'"]),
        ("parameter_e", "[parameters]\nE = \"x\"\n", vec!["parameters.E"]),
    ] {
        v.push(err(name, plate("1.0", "0.3", "1.0", MESH, extra), names));
    }
    // x/y on the edge x = 2 is infinite at y = 0 only, where no quadrature point lies: a
    // finite result (any), or an error naming the load.
    let mut i = err("load_x_over_y", plate("1.0", "0.3", "\"x/y\"", MESH, ""), vec!["load", "traction"]);
    i.reference = Some(Box::new(|_| Ok(())));
    v.push(i);
    // A huge load factor: a result within the scaling reference, or the guard.
    let mut i = err("steps_huge", plate("1.0", "0.3", "1.0", MESH, "[steps]\nfactors = [1e300]\n"), vec!["non-finite"]);
    i.reference = Some(plate_reference(u1, 1e300, 1.0));
    v.push(i);
    v
}

// ---------------------------------------------------------------------------------------
// Family 2: truncated and damaged meshes.

fn meshes() -> Vec<Input> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let tmp = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("adversarial_meshes");
    std::fs::create_dir_all(&tmp).unwrap();
    let mut v = vec![];
    for name in ["block.msh", "block_binary.msh", "plate_with_hole.msh"] {
        let b = std::fs::read(dir.join(name)).unwrap();
        for frac in [0.0, 0.05, 0.3, 0.5, 0.7, 0.95, 0.999] {
            let cut = ((b.len() as f64) * frac) as usize;
            let path = tmp.join(format!("{frac}_{name}"));
            std::fs::write(&path, &b[..cut]).unwrap();
            let text = format!("[mesh]\nfile = \"{}\"\n\n[[materials]]\nE = 1.0\nnu = 0.3\n", path.display());
            v.push(Input {
                family: "truncated meshes",
                name: format!("{name}@{frac}"),
                text,
                names: vec!["mesh.file"],
                reference: None,
                must_solve: false,
            });
        }
    }
    v
}

// ---------------------------------------------------------------------------------------
// Family 3: crack placements. Plate [0, 4] × [0, 2], quad4 16 × 8 (h = 0.25), plane
// strain, E = 1, ν = 0.3, σ = 1 on top and bottom, held by two corner points; an edge
// crack from the left side at height y_c with its tip at (a, y_c). Reference: the same
// plate with a `half_line` crack with the same tip (the formulation the docs verify),
// K_I within 2%.

fn edge_plate(crack: &str) -> String {
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [4.0, 2.0]\ndivisions = [16, 8]\n\n[[materials]]\nE = 1.0\nnu = 0.3\n\n[[sets]]\nname = \"pin\"\non = \"abs(x - 4) + abs(y)\"\n\n[[sets]]\nname = \"roller\"\non = \"abs(x - 4) + abs(y - 2)\"\n\n[[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"x\"]\n\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, 1.0]\n\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, -1.0]\n\n[[cracks]]\nname = \"c\"\n{crack}\n"
    )
}

fn k1_of(s: &Value) -> Vec<f64> {
    last_step(s)["cracks"][0]["front"]
        .as_array()
        .map(|f| f.iter().map(|p| p["KI"].as_f64().unwrap_or(f64::NAN)).collect())
        .unwrap_or_default()
}

fn crack_placements() -> Vec<Input> {
    let mut v = vec![];
    // (name, y_c, a, start of the segment): tip at a node, on an edge, inside a cell;
    // crack on a node line or between; segment start outside, on, or inside the boundary.
    let placements = [
        ("tip_in_cell", 1.06, 1.13),
        ("tip_on_node", 1.0, 1.0),
        ("tip_on_vertical_edge", 1.06, 1.0),
        ("tip_on_horizontal_edge", 1.0, 1.13),
        ("crack_on_node_line", 1.0, 1.13),
    ];
    for (pname, yc, a) in placements {
        let reference_text = edge_plate(&format!("shape = \"half_line\"\ntip = [{a}, {yc}]\ndirection = [1.0, 0.0]"));
        let reference = cli::fissure("adversarial", &format!("ref_{pname}"), &reference_text, false, LIMIT);
        let k_ref = reference.summary.as_ref().map(k1_of).and_then(|k| k.first().copied());
        for (sname, x0) in [("start_outside", -0.05), ("start_on_boundary", 0.0), ("start_inside", 0.01)] {
            let text = edge_plate(&format!("shape = \"segment\"\na = [{x0}, {yc}]\nb = [{a}, {yc}]"));
            let reference: Option<Reference> = k_ref.map(|k_ref| -> Reference {
                Box::new(move |s: &Value| {
                    let k = k1_of(s);
                    // The tip inside the plate; a front point at the boundary end is spurious.
                    let tips = k.len();
                    let k_tip = k.iter().copied().fold(f64::NAN, |m: f64, v| if m.is_nan() || v > m { v } else { m });
                    if tips == 1 && (k_tip - k_ref).abs() <= 0.02 * k_ref.abs() {
                        Ok(())
                    } else {
                        Err(format!("K_I {k:?} (front points {tips}), half_line reference {k_ref:.5}"))
                    }
                })
            });
            // A start inside the boundary leaves a ligament: a two-tip crack, its inner tip
            // near the half_line's only when the ligament is negligible; judged by error-free
            // finite output only.
            let (reference, must_solve) = if sname == "start_inside" {
                (Some(Box::new(|_: &Value| Ok(())) as Reference), true)
            } else {
                (reference, true)
            };
            v.push(Input {
                family: "crack placements",
                name: format!("{pname}/{sname}"),
                text,
                names: vec!["crack 'c'"],
                reference,
                must_solve,
            });
        }
    }
    for (name, crack) in [
        ("entirely_outside", "shape = \"segment\"\na = [5.0, 1.0]\nb = [6.0, 1.0]"),
        ("degenerate_formula", "shape = \"formula\"\nlsn = \"0*x\""),
        ("zero_length", "shape = \"segment\"\na = [1.0, 1.0]\nb = [1.0, 1.0]"),
        ("nan_end", "shape = \"segment\"\na = [nan, 1.0]\nb = [1.0, 1.0]"),
        // Through cracks without contact leaving a piece that the two points at x = 4 do
        // not hold (issue 11 item 13): the error names the crack and the free piece.
        ("through_segment_free_piece", "shape = \"segment\"\na = [1.03, 3.0]\nb = [1.03, -1.0]"),
        ("through_line_free_piece", "shape = \"line\"\npoint = [2.0, 1.03]\nnormal = [0.0, 1.0]"),
    ] {
        v.push(Input {
            family: "crack placements",
            name: name.into(),
            text: edge_plate(crack),
            names: vec!["crack 'c'", "cracks[0]"],
            reference: None,
            must_solve: false,
        });
    }
    v
}

// ---------------------------------------------------------------------------------------
// Family 4: contact parameters. Block [0, 1]², quad4 6 × 6, plane strain, cut by an
// interface at y = 0.53 with contact; bottom edge u_y = 0, left edge u_x = 0, top traction
// (0, −p). Reference: uniform σ_yy = −p, so λ = −p at every contact point (λ_min and
// λ_max) to 1e-5 relative, whatever ρ_n, friction and the unit system.

fn contact_block(e: f64, p: f64, contact: &str) -> String {
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [1.0, 1.0]\ndivisions = [6, 6]\n\n[[materials]]\nE = {e:e}\nnu = 0.3\n\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"y\"]\n\n[[dirichlet]]\ngroup = \"left\"\ncomponents = [\"x\"]\n\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, {mp:e}]\n\n[[cracks]]\nname = \"i\"\nshape = \"line\"\npoint = [0.5, 0.53]\nnormal = [0.0, 1.0]\n\n[cracks.contact]\n{contact}\n",
        mp = -p
    )
}

fn contact_reference(p: f64) -> Reference {
    Box::new(move |s| {
        let c = &last_step(s)["contact"];
        let (lo, hi) = (num(c, &["lambda_min"]), num(c, &["lambda_max"]));
        if (lo + p).abs() <= 1e-5 * p && (hi + p).abs() <= 1e-5 * p {
            Ok(())
        } else {
            Err(format!("λ in [{lo:e}, {hi:e}], expected {:e}", -p))
        }
    })
}

fn contact_parameters() -> Vec<Input> {
    let mut v = vec![];
    for (units, e, p) in [("unit", 1.0, 0.01), ("si_steel", 2.1e11, 1e3), ("mm_mpa", 2.1e5, 1e-3)] {
        for rho in [1e-6, 1e-3, 1.0, 1e3, 1e6] {
            for mu in [0.0, 0.5] {
                let contact = format!("friction = {mu}\nrho_n = {:e}\nrho_t = {:e}", rho * e, rho * e);
                v.push(Input {
                    family: "contact parameters",
                    name: format!("{units}/rho_{rho:e}/mu_{mu}"),
                    text: contact_block(e, p, &contact),
                    names: vec!["contact", "rho_n"],
                    reference: Some(contact_reference(p)),
                    must_solve: true,
                });
            }
        }
        for (name, extra) in [
            ("threshold_huge", "friction = 0.5\ninitial_threshold = 1e12"),
            ("integration_vertex", "friction = 0.5\nintegration = \"vertex\""),
            ("integration_nodes", "friction = 0.5\nintegration = \"nodes\""),
            ("start_open", "friction = 0.5\nstart_closed = false"),
        ] {
            v.push(Input {
                family: "contact parameters",
                name: format!("{units}/{name}"),
                text: contact_block(e, p, extra),
                names: vec!["contact"],
                reference: Some(contact_reference(p)),
                must_solve: true,
            });
        }
    }
    for (name, extra, names) in [
        ("rho_zero", "rho_n = 0.0", vec!["contact.rho_n"]),
        ("rho_nan", "rho_n = nan", vec!["contact.rho_n"]),
        ("friction_negative", "friction = -0.1", vec!["contact.friction"]),
        ("friction_inf", "friction = inf", vec!["contact.friction"]),
    ] {
        v.push(Input {
            family: "contact parameters",
            name: name.into(),
            text: contact_block(1.0, 0.01, extra),
            names,
            reference: None,
            must_solve: false,
        });
    }
    v
}

/// Runs every input, prints one line per input and the tally, and returns the
/// unexpected failures.
fn run_all(inputs: Vec<Input>) -> Vec<String> {
    let mut tally: std::collections::BTreeMap<(&str, Verdict), usize> = Default::default();
    let mut failures = vec![];
    let mut known_seen = vec![];
    for (k, input) in inputs.iter().enumerate() {
        let o = cli::fissure("adversarial", &format!("in{k}"), &input.text, false, LIMIT);
        let (verdict, note) = judge(input, &o);
        let known = is_known(&input.name);
        let label = match (verdict, known) {
            (Verdict::Failure, Some(item)) => {
                known_seen.push(input.name.clone());
                format!("KNOWN ({item})")
            }
            (Verdict::Failure, None) => {
                failures.push(format!("{} / {}: {note}", input.family, input.name));
                "FAIL".to_string()
            }
            (_, Some(item)) => format!("passes (listed as known, {item})"),
            (v, None) => format!("{v:?}"),
        };
        *tally.entry((input.family, verdict)).or_default() += 1;
        eprintln!("{:<20} {:<40} {label:<24} {}", input.family, input.name, note.lines().next().unwrap_or(""));
    }
    eprintln!("\ntally (family, verdict: count):");
    for ((f, v), n) in &tally {
        eprintln!("  {f:<20} {v:?}: {n}");
    }
    eprintln!("known failures (other items of issue 11): {}", known_seen.len());
    failures
}

fn unit_plate_displacement() -> f64 {
    let o = cli::fissure("adversarial", "unit_plate", &plate("1.0", "0.3", "1.0", MESH, ""), false, LIMIT);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    num(last_step(o.summary.as_ref().unwrap()), &["max_displacement"])
}

/// The fast part: every family, deterministic inputs.
#[test]
fn adversarial_inputs_give_a_clean_error_or_a_checked_result() {
    let u1 = unit_plate_displacement();
    let mut inputs = case_values(u1);
    inputs.extend(meshes());
    inputs.extend(crack_placements());
    inputs.extend(contact_parameters());
    let failures = run_all(inputs);
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

/// The long part: random combinations of the case values, crack placements and contact
/// parameters (a fixed-seed generator, `FISSURE_ADVERSARIAL_CASES` inputs, default 300).
#[test]
#[ignore]
fn long_random_adversarial_inputs() {
    let n: usize = std::env::var("FISSURE_ADVERSARIAL_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300);
    let u1 = unit_plate_displacement();
    let mut rng = 0x9e3779b97f4a7c15u64;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut inputs = vec![];
    for k in 0..n {
        match k % 3 {
            0 => {
                let e = 10f64.powf(-300.0 + 600.0 * next());
                let sigma = 10f64.powf(-300.0 + 600.0 * next());
                let mut i = Input {
                    family: "random values",
                    name: format!("E={e:.3e} sigma={sigma:.3e}"),
                    text: plate(&format!("{e:e}"), "0.3", &format!("{sigma:e}"), MESH, ""),
                    names: vec!["non-finite", "linear solve", "load"],
                    reference: None,
                    must_solve: false,
                };
                i.reference = Some(plate_reference(u1, sigma, e));
                inputs.push(i);
            }
            1 => {
                let (yc, a) = (0.6 + 0.8 * next(), 0.6 + 1.0 * next());
                let x0 = -0.3 + 0.6 * next();
                inputs.push(Input {
                    family: "random cracks",
                    name: format!("a=[{x0:.4},{yc:.4}] tip=[{a:.4},{yc:.4}]"),
                    text: edge_plate(&format!("shape = \"segment\"\na = [{x0}, {yc}]\nb = [{a}, {yc}]")),
                    names: vec!["crack 'c'"],
                    reference: Some(Box::new(|_| Ok(()))),
                    must_solve: true,
                });
            }
            _ => {
                let e = 10f64.powf(-6.0 + 18.0 * next());
                let p = e * 10f64.powf(-9.0 + 7.0 * next());
                let rho = e * 10f64.powf(-6.0 + 12.0 * next());
                let mu = next();
                inputs.push(Input {
                    family: "random contact",
                    name: format!("E={e:.3e} p={p:.3e} rho={rho:.3e} mu={mu:.2}"),
                    text: contact_block(e, p, &format!("friction = {mu}\nrho_n = {rho:e}\nrho_t = {rho:e}")),
                    names: vec!["contact"],
                    reference: Some(contact_reference(p)),
                    must_solve: true,
                });
            }
        }
    }
    let failures = run_all(inputs);
    eprintln!("{} failures:\n{}", failures.len(), failures.join("\n"));
    assert!(failures.is_empty());
}
