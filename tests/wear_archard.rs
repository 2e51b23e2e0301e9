//! Archard wear in the contact gap (issue 14): the wear field on the lips against closed
//! forms of the Archard law ẇ = (k/H)|λ||v_τ|, with the implicit and the staggered
//! couplings, and the bad inputs of `[cracks.contact.wear]`.
//!
//! Every case is the block [0, 8] × [−0.5, 0.5] (quad4 32 × 4, h = 0.25) cut through by the
//! flat interface y = 0.35 (inside a cell), E = 1, ν = 0 (plane strain), bottom clamped, top
//! driven along x by a prescribed displacement, sides free. The friction traction μp on
//! the interface and the drive at the top make a couple that the free sides balance by a
//! pressure varying along the interface, by a fraction of order 6μH/W (H the height above
//! the interface, W the width; measured: 1.3μ for H = 0.4, W = 2). Archard's wear does not
//! involve μ, so the closed forms are checked with μ = 2e-6 on this wide block with a thin
//! top (H = 0.15, W = 8): pressure and slip are then uniform to ~3e-7 relative. (Smaller
//! μ, 1e-6, makes the first linear solve of the step fail its residual check, with or
//! without wear.)
//! (Uniform shear tractions on the sides would balance the couple at any μ, but a face
//! load on the cell faces the interface crosses does not reach the enriched unknowns, so
//! they cannot be applied exactly there.)

mod common;

use fissure::case::{Case, CaseError};
use serde_json::Value;
use std::path::Path;

/// The block with contact `contact` (TOML lines of `[cracks.contact]`, its wear table
/// included), top lines `top` and `steps` load steps with factors 1..=steps (t counts the
/// steps) or k/steps (`unit_t`).
fn block(contact: &str, top: &str, steps: usize, unit_t: bool) -> String {
    let factors: Vec<String> = (1..=steps)
        .map(|k| if unit_t { format!("{:.17e}", k as f64 / steps as f64) } else { format!("{k}") })
        .collect();
    format!(
        r#"[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.5]
upper = [8.0, 0.5]
divisions = [32, 4]

[[materials]]
E = 1.0
nu = 0.0

[[dirichlet]]
group = "bottom"
components = ["x", "y"]

{top}

[steps]
factors = [{factors}]

[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.35]
normal = [0.0, 1.0]

[cracks.contact]
{contact}
"#,
        factors = factors.join(", ")
    )
}

/// The wear figures of every step of a run's summary.
fn wear_steps(summary: &Value) -> Vec<Value> {
    summary["steps"].as_array().unwrap().iter().map(|s| s["contact"]["wear"].clone()).collect()
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// Constant pressure under load control. Geometry and material: the block of the module
/// doc. Load: traction p = 1e-3 pressing the top, top slid along x by 0.01 per step for 5
/// steps (0.01·t), μ = 2e-6. Reference: the interface slides from the first step with
/// λ = −p, slip s = 0.01·N − γH (γ = μp/G the shear strain of both blocks, G = E/2,
/// H = 1), and the pressure does not change with the wear (load control): w = (k/H)·p·s
/// uniform (Archard 1953, integrated at constant p). Tolerance 1e-6 relative on the mean
/// depth w⁺ + w⁻ against (k/H)·p·s and on the largest against (k/H)·max|λ|·s (the
/// pressure varies by the friction couple: asserted uniform within 5e-6, measured 1.9e-6),
/// with either coupling and k/H given as
/// `coefficient` or as `k` and `hardness` (split 0.3), for the augmented Lagrangian, the
/// stabilised and the penalty law (whose λ = −κ_n⟨d_n^w⟩₊ is −p at equilibrium too); the
/// frictional work is
/// W_f = μ p s · W (1e-6) and the worn volume (k/H)·W_f/μ (1e-9: the same points and
/// values); wear_history.csv has one row per step with the same figures. With μ = 0.3
/// (the pressure then varies by ±8% along the interface) the worn volume is still
/// (k/H)·W_f/μ to 1e-9.
#[test]
fn constant_pressure_wear_is_k_over_h_times_p_times_slip_with_either_coupling() {
    let (p, mu, ds, n) = (1e-3, 2e-6, 0.01, 5usize);
    let slip = ds * n as f64 - mu * p / 0.5 * 1.0;
    let top = format!(
        "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = \"{ds}*t\"\n\n[[traction]]\ngroup = \"top\"\nvalue = [\"0*t\", \"-{p} + 0*t\"]"
    );
    for (method, wear, coefficient) in [
        ("augmented_lagrangian", "coefficient = 0.5\ncoupling = \"implicit\"", 0.5),
        ("augmented_lagrangian", "coefficient = 0.5\ncoupling = \"staggered\"", 0.5),
        ("augmented_lagrangian", "k = 2e-3\nhardness = 4e-3\nsplit = 0.3", 0.5),
        ("stabilised", "coefficient = 0.5", 0.5),
        ("penalty", "coefficient = 0.5", 0.5),
        ("penalty", "coefficient = 0.5\ncoupling = \"staggered\"", 0.5),
    ] {
        let contact = format!("friction = {mu}\nmethod = \"{method}\"\n[cracks.contact.wear]\n{wear}");
        let text = block(&contact, &top, n, false);
        let name = format!("constant_pressure_{method}_{}", wear.len());
        let summary = common::run_cli("wear_archard", &name, &text);
        let steps = wear_steps(&summary);
        assert_eq!(steps.len(), n);
        let last = &steps[n - 1];
        let c = &summary["steps"][n - 1]["contact"];
        for key in ["lambda_min", "lambda_max"] {
            assert!((num(c, key) / -p - 1.0).abs() < 5e-6, "{key}: {c}");
        }
        let p_max = -num(c, "lambda_min");
        for (key, reference) in [("mean", coefficient * p * slip), ("max", coefficient * p_max * slip)] {
            let w = num(last, key);
            assert!((w / reference - 1.0).abs() < 1e-6, "{method}, {wear}: {key} {w:.9e}, reference {reference:.9e}");
        }
        let work = num(last, "frictional_work");
        assert!((work / (mu * p * slip * 8.0) - 1.0).abs() < 1e-6, "W_f {work}");
        let volume = num(last, "volume");
        assert!((volume / (coefficient * work / mu) - 1.0).abs() < 1e-9, "volume {volume}, W_f {work}");
        // The history next to summary.json: a header and one row per step.
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("wear_archard").join(&name);
        let csv = std::fs::read_to_string(dir.join("wear_history.csv")).unwrap();
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows[0], "step,load_factor,max,mean,volume,frictional_work");
        assert_eq!(rows.len(), n + 1);
        let max: f64 = rows[n].split(',').nth(2).unwrap().parse().unwrap();
        assert!((max / num(last, "max") - 1.0).abs() < 1e-11);
        // The lips' VTU carries the wear arrays.
        let vtu = std::fs::read_to_string(dir.join(format!("{name}_crack_step0005.vtu"))).unwrap();
        for array in ["wear_plus", "wear_minus", "wear_total"] {
            assert!(vtu.contains(&format!("Name=\"{array}\"")), "{array}");
        }
    }
    let contact = "friction = 0.3\n[cracks.contact.wear]\ncoefficient = 0.5";
    let summary = common::run_cli("wear_archard", "constant_pressure_mu_0_3", &block(contact, &top, n, false));
    let last = &wear_steps(&summary)[n - 1];
    let (volume, work) = (num(last, "volume"), num(last, "frictional_work"));
    assert!((volume / (0.5 * work / 0.3) - 1.0).abs() < 1e-9, "μ = 0.3: volume {volume}, W_f {work}");
}

/// Displacement-controlled pressing: the column of height L = 1 (the block of the module
/// doc), E = 1, top held at u_y = −U (U = 1e-3) and slid along x by S = 1 over the run
/// (u_x = t, t = k/N), μ = 2e-6. Reference: the wear relieves
/// the column, p = E(U − w)/L, so dw/ds = (k/H)E(U − w)/L and
/// w(s) = U(1 − exp(−(k/H)E s/L)) (issue 14), with k/H = 0.1 (a = (k/H)E S/L = 0.1) and s
/// the slip, S − μ p H/G. Asserted: the implicit coupling (backward Euler in s) within 0.5%
/// at 20 steps (expected 0.24%); the staggered one (forward Euler) converges at first order
/// in the step count: rates between 10, 20, 40, 80 steps within 1 ± 0.1 (measured 1.005,
/// 1.002, 1.001); its error at 80 steps below 0.1% (measured 0.06%). Measured implicit
/// error at 20 steps: −0.237%, backward Euler's (1 + a/N)^−N against e^−a.
#[test]
fn displacement_controlled_wear_follows_the_exponential_implicit_within_half_percent_staggered_first_order() {
    let (u, mu, c, e, l) = (1e-3, 2e-6, 0.1, 1.0, 1.0);
    let run = |coupling: &str, n: usize| {
        let contact = format!("friction = {mu}\n[cracks.contact.wear]\ncoefficient = {c}\ncoupling = \"{coupling}\"");
        let top =
            format!("[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [\"t\", \"-{u} + 0*t\"]");
        let summary =
            common::run_cli("wear_archard", &format!("pressing_{coupling}_{n}"), &block(&contact, &top, n, true));
        let w = num(&wear_steps(&summary)[n - 1], "mean");
        let p = e * (u - w) / l;
        let s = 1.0 - mu * p * 1.0 / 0.5;
        let reference = u * (1.0 - (-c * e * s / l).exp());
        let newton = summary["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["contact"]["iterations"]["newton"].as_u64().unwrap())
            .max()
            .unwrap();
        ((w - reference) / reference, newton)
    };
    let (implicit, newton) = run("implicit", 20);
    assert!(implicit.abs() < 5e-3, "implicit at 20 steps: relative error {implicit:.3e}");
    // The pressure–wear coupling is in the tangent: a handful of Newton iterations per step
    // (measured at most 8, over the friction passes).
    assert!(newton <= 12, "implicit: {newton} Newton iterations in a step");
    let errors: Vec<f64> = [10, 20, 40, 80].iter().map(|&n| run("staggered", n).0).collect();
    for k in 0..3 {
        let rate = (errors[k] / errors[k + 1]).abs().log2();
        assert!(
            (rate - 1.0).abs() < 0.1,
            "staggered rate {rate:.3} between {} and {} steps: errors {errors:?}",
            10 << k,
            20 << k
        );
    }
    assert!(errors[3].abs() < 1e-3, "staggered at 80 steps: {:.3e}", errors[3]);
}

/// No wear without frictional sliding. The block of the module doc, k/H = 0.5, 3 steps,
/// both couplings: (a) μ = 0, top pressed by p = 1e-3 and slid by 0.01 per step (the
/// lips slide without friction); (b) μ = 0.3, top pressed and not slid (every point
/// sticks); (c) μ = 0.3, top lifted by 1e-3 and slid (the face opens: no contact).
/// Reference: zero wear and zero frictional work (Archard with the frictional work
/// μ|λ||dslip|: none of the three dissipates); tolerance: exactly 0.
#[test]
fn no_friction_no_slip_or_an_open_face_gives_no_wear() {
    let press = |slide: &str| {
        format!("[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = \"{slide}\"\n\n[[traction]]\ngroup = \"top\"\nvalue = [\"0*t\", \"-1e-3 + 0*t\"]")
    };
    let lift = "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [\"0.01*t\", \"1e-3 + 0*t\"]"
        .to_string();
    for coupling in ["implicit", "staggered"] {
        for (what, mu, top) in
            [("frictionless", 0.0, press("0.01*t")), ("stuck", 0.3, press("0*t")), ("open", 0.3, lift.clone())]
        {
            let contact =
                format!("friction = {mu}\n[cracks.contact.wear]\ncoefficient = 0.5\ncoupling = \"{coupling}\"");
            let summary =
                common::run_cli("wear_archard", &format!("zero_{what}_{coupling}"), &block(&contact, &top, 3, false));
            for (k, w) in wear_steps(&summary).iter().enumerate() {
                for key in ["max", "mean", "volume", "frictional_work"] {
                    assert_eq!(num(w, key), 0.0, "{what}, {coupling}, step {}: {key}", k + 1);
                }
            }
            let c = &summary["steps"][2]["contact"];
            match what {
                "open" => assert_eq!(c["active"], 0, "{c}"),
                "stuck" => assert_eq!(c["stick"], c["points"], "{c}"),
                _ => assert_eq!(c["slip"], c["points"], "{c}"),
            }
        }
    }
}

fn parse(text: &str) -> Result<Case, CaseError> {
    Case::parse(text, Path::new("case.toml"))
}

/// Bad input of `[cracks.contact.wear]` (issue 14): each gives an error naming the key and
/// its line (never a panic): zero or negative coefficient, hardness ≤ 0, split outside
/// [0, 1], k without hardness, both coefficient and k, an unknown coupling, wear on a
/// crack without contact, and wear with [dynamics] or the implicit
/// coupling with the asperity layer (not available).
#[test]
fn bad_wear_input_names_the_key_and_the_line() {
    let top = "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [\"0.01*t\", \"-1e-3 + 0*t\"]";
    let case = |wear: &str| block(&format!("friction = 0.3\n[cracks.contact.wear]\n{wear}"), top, 2, false);
    let good = case("coefficient = 0.5");
    parse(&good).expect("the good case reads");
    let line_of = |text: &str, needle: &str| text.lines().position(|l| l.starts_with(needle)).map(|i| i + 1);
    for (wear, key, needle, says) in [
        ("coefficient = 0.0", "cracks[0].contact.wear.coefficient", "coefficient", "must be positive"),
        ("coefficient = -2.0", "cracks[0].contact.wear.coefficient", "coefficient", "must be positive"),
        ("k = 0.1\nhardness = 0.0", "cracks[0].contact.wear.hardness", "hardness", "must be positive"),
        ("k = 0.1\nhardness = -3.0", "cracks[0].contact.wear.hardness", "hardness", "must be positive"),
        ("coefficient = 0.5\nsplit = 1.5", "cracks[0].contact.wear.split", "split", "in [0, 1]"),
        ("coefficient = 0.5\nsplit = -0.1", "cracks[0].contact.wear.split", "split", "in [0, 1]"),
        ("k = 0.1", "cracks[0].contact.wear.k", "k =", "needs hardness"),
        ("coefficient = 0.5\nk = 0.1\nhardness = 2.0", "cracks[0].contact.wear.k", "k =", "not both"),
        ("coefficient = 0.5\ncoupling = \"explicit\"", "cracks[0].contact.wear.coupling", "coupling", "implicit"),
        ("split = 0.5", "cracks[0].contact.wear.coefficient", "[cracks.contact.wear]", "missing key 'coefficient'"),
    ] {
        let text = case(wear);
        let e = parse(&text).expect_err(wear);
        assert_eq!(e.key, key, "{wear}: {e}");
        assert_eq!(e.line, line_of(&text, needle), "{wear}: {e}");
        assert!(e.message.contains(says), "{wear}: {e}");
    }
    // Wear on a crack without contact: the wear table alone.
    let text = good.replace("[cracks.contact]\nfriction = 0.3\n", "");
    let e = parse(&text).expect_err("wear without contact");
    assert_eq!(e.key, "cracks[0].contact.wear", "{e}");
    assert!(e.message.contains("without contact") && e.line.is_some(), "{e}");
    // Not available: the implicit coupling with the asperity layer, dynamics (large
    // sliding is, in 2D: tests/wear_large_sliding.rs, which also checks the 3D refusal).
    let large = good.replace("friction = 0.3\n", "friction = 0.3\nsliding = \"large\"\n");
    parse(&large).expect("large sliding in 2D");
    let asperity = good
        .replace("friction = 0.3\n", "friction = 0.3\n[cracks.contact.asperity]\nthickness = 1e-4\nstiffness = 1e6\n");
    let e = parse(&asperity).expect_err("implicit with asperity");
    assert_eq!(e.key, "cracks[0].contact.wear", "{e}");
    assert!(e.message.contains("staggered"), "{e}");
    parse(&asperity.replace("coefficient = 0.5", "coefficient = 0.5\ncoupling = \"staggered\""))
        .expect("staggered with asperity");
    let dynamics = format!(
        "{}\n[dynamics]\ndt = 0.1\nsteps = 2\n",
        good.replace("[steps]\nfactors = [1, 2]\n", "").replace("nu = 0.0\n", "nu = 0.0\ndensity = 1.0\n")
    );
    let e = parse(&dynamics).expect_err("dynamics");
    assert_eq!(e.key, "cracks[0].contact.wear", "{e}");
    assert!(e.message.contains("dynamic"), "{e}");
}

/// A wear depth beyond the cell size stops the run with an error naming the crack and the
/// step, and keeps the steps before it on disk. The constant-pressure block (p = 1e-3,
/// μ = 2e-6, top slid by 0.0095 per step) with k/H = 5e3, all on the + lip, implicit
/// coupling: each step wears 5e3·1e-3·0.0095 = 0.0475, so the depth passes h = 0.25 at
/// step 6.
/// (The staggered coupling is unstable here: a step's wear, 0.05, is 50 times the elastic
/// shortening p·L/E it relieves; docs/contact-algorithms.md, "Wear".)
#[test]
fn wear_deeper_than_a_cell_stops_naming_crack_and_step_and_keeps_the_good_steps() {
    let top = "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = \"0.0095*t\"\n\n[[traction]]\ngroup = \"top\"\nvalue = [\"0*t\", \"-1e-3 + 0*t\"]";
    let text = block("friction = 2e-6\n[cracks.contact.wear]\ncoefficient = 5e3\nsplit = 1.0", top, 8, false);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("wear_archard");
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("too_deep.toml");
    std::fs::write(&case, &text).unwrap();
    let out = dir.join("too_deep");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_fissure"))
        .args(["run", case.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("step 6") && stderr.contains("crack 'interface'") && stderr.contains("wear depth"),
        "{stderr}"
    );
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert_eq!(summary["steps"].as_array().unwrap().len(), 5);
    assert!(out.join("too_deep_crack_step0005.vtu").exists());
    assert!(!out.join("too_deep_crack_step0006.vtu").exists());
}
