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

/// Wear with the asperity layer under constant pressure (seed eq. 5 with Archard): the
/// block of the module doc, lips coincident (g₀ = 0) with a layer of thickness a = 1e-3
/// (pre-crushed by a at rest, so the layer opens the lips until it balances the load),
/// top pressed by the traction p = 1e-3 and slid along x by 0.01 per step for 5 steps,
/// μ = 2e-6, k/H = 0.5, split 0.3 on `+`. Two layers, one on each side of the crush limit
/// p* = κa²: κ = 2e3 (p* = 2e-3 > p: the layer alone carries p, crush δ = √(p/κ) < a, the
/// hard contact is open, λ = 0) and κ = 500 (p* = 5e-4 < p: the layer is crushed flat,
/// d_n = 0, and the hard contact carries −λ = p − κa² = 5e-4). Reference: Archard at
/// constant pressure with the total normal pressure p_total = −λ + κ⟨d_n + a⟩₊² = p (the
/// equilibrium of the top block, whatever the share of the layer): w⁺ = 0.3·(k/H)·p·s,
/// w⁻ = 0.7·(k/H)·p·s at every point, s = 0.05 − μpH/G the slip (H = 1, G = 1/2), and the
/// worn volume Σ w_p (w⁺ + w⁻) = (k/H)·W_f/μ. Tolerance: 5e-6 relative per point (the
/// friction couple makes the pressure vary by ~3e-7, module doc; the penalty law's
/// pressure is the same total), 1e-9 on the volume against the work (the same points and
/// values). With either coupling and every method; the regime is asserted (layer only:
/// λ = 0 and κδ² = p to 5e-6; crushed: |d_n| < 1e-9·a and −λ = p − κa² to 1e-5 (penalty:
/// −λ + κδ² = p)). Before this, the wear used the hard contact's λ only: zero wear in the
/// first regime, half of it in the second.
#[test]
fn asperity_layer_wear_uses_the_total_pressure_on_both_sides_of_the_crush_limit() {
    let (p, mu, ds, n, c, split, a) = (1e-3, 2e-6, 0.01, 5usize, 0.5, 0.3, 1e-3);
    let slip = ds * n as f64 - mu * p / 0.5 * 1.0;
    let top = format!(
        "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = \"{ds}*t\"\n\n[[traction]]\ngroup = \"top\"\nvalue = [\"0*t\", \"-{p} + 0*t\"]"
    );
    for (kappa, crushed) in [(2e3, false), (500.0, true)] {
        for method in ["augmented_lagrangian", "stabilised", "penalty"] {
            for coupling in ["implicit", "staggered"] {
                let contact = format!(
                    "friction = {mu}\nmethod = \"{method}\"\n[cracks.contact.asperity]\nthickness = {a}\nstiffness = {kappa}\n[cracks.contact.wear]\ncoefficient = {c}\nsplit = {split}\ncoupling = \"{coupling}\""
                );
                let tag = format!("κ = {kappa}, {method}, {coupling}");
                let r = common::contact::solve_contact_text(&block(&contact, &top, n, false))
                    .unwrap_or_else(|e| panic!("{tag}: {e:?}"));
                assert!(!r.lambda.is_empty());
                let reference = c * p * slip;
                let (mut volume, mut work) = (0.0, 0.0);
                for k in 0..r.lambda.len() {
                    let crush = r.d_n[k] + a;
                    let layer = kappa * crush.max(0.0).powi(2);
                    let total = -r.lambda[k] + layer;
                    assert!((total / p - 1.0).abs() < 5e-6, "{tag}: total pressure {total:.9e}");
                    if crushed {
                        if method != "penalty" {
                            assert!(r.d_n[k].abs() < 1e-9 * a, "{tag}: d_n = {:.3e}", r.d_n[k]);
                            assert!(
                                (-r.lambda[k] / (p - kappa * a * a) - 1.0).abs() < 1e-5,
                                "{tag}: λ = {}",
                                r.lambda[k]
                            );
                        } else {
                            assert!(r.lambda[k] < 0.0, "{tag}: the hard contact carries part");
                        }
                    } else {
                        assert!(r.lambda[k] == 0.0 || r.lambda[k].abs() < 1e-12 * p, "{tag}: λ = {}", r.lambda[k]);
                        assert!(crush < a && (layer / p - 1.0).abs() < 5e-6, "{tag}: crush {crush:.6e}");
                    }
                    let [wp, wm] = r.wear[k];
                    assert!(
                        (wp / (split * reference) - 1.0).abs() < 5e-6,
                        "{tag}: w+ {wp:.9e}, ref {:.9e}",
                        split * reference
                    );
                    assert!(
                        (wm / ((1.0 - split) * reference) - 1.0).abs() < 5e-6,
                        "{tag}: w- {wm:.9e}, ref {:.9e}",
                        (1.0 - split) * reference
                    );
                    volume += r.weight[k] * (wp + wm);
                    work += r.weight[k] * r.frictional_work[k];
                }
                assert!((volume / (c * work / mu) - 1.0).abs() < 1e-9, "{tag}: volume {volume:.9e}, W_f {work:.9e}");
                assert!((work / (mu * p * slip * 8.0) - 1.0).abs() < 5e-6, "{tag}: W_f {work:.9e}");
            }
        }
    }
}

/// The worn depth of a column pressed through the asperity layer alone, displacement
/// controlled (the implicit coupling's series compliance with the layer, whose pressure
/// falls as the lips wear). The block of the module doc (column height L = 1, E = 1), lips
/// apart by g₀ = a = 2e-3 with a layer of thickness a and stiffness κ = 1e3, top held at
/// u_y = −U (U = 1e-3) and slid along x by S = 1 over the run (u_x = t, t = k/N), μ = 2e-6,
/// k/H = 0.2. Reference (closed form): the layer's crush δ = U − w − pL/E with p = κδ²
/// stays below a (δ₀ = 6.18e-4), and dw/ds = (k/H)κδ² with dw = −(1 + 2κLδ/E)dδ gives
/// s(δ) = [(1/δ − 1/δ₀) − (2κL/E) ln(δ/δ₀)]/((k/H)κ), solved for δ at the slip s = S − μpH/G
/// and w = U − δ − κLδ²/E. Asserted, for the augmented Lagrangian and the penalty law (the
/// hard contact stays open: the same law): the implicit coupling (backward Euler in s)
/// within 0.5% at 20 steps (measured −0.26%) with at most 2 more Newton iterations in a
/// step than the staggered run, whose steps do not see their own wear (the layer's
/// dependence on the wear is in the implicit tangent; measured 18 against 17: the layer's
/// quadratic law itself takes 10 to 17 iterations a step, with or without wear), and the
/// staggered one (forward Euler) at first order in the step count, rates between 10, 20,
/// 40, 80 steps within 1 ± 0.1.
#[test]
fn asperity_layer_wear_under_displacement_control_follows_the_closed_form() {
    let (u, mu, c, e, l, a, kappa): (f64, f64, f64, f64, f64, f64, f64) = (1e-3, 2e-6, 0.2, 1.0, 1.0, 2e-3, 1e3);
    let delta_of_w = |w: f64| (-(e / l) + ((e / l).powi(2) + 4.0 * kappa * (e / l) * (u - w)).sqrt()) / (2.0 * kappa);
    let d0 = delta_of_w(0.0);
    let s_of = |d: f64| ((1.0 / d - 1.0 / d0) - 2.0 * kappa * l / e * (d / d0).ln()) / (c * kappa);
    let reference = |s: f64| {
        // δ(s) by Newton on s(δ) = s (s decreasing in δ).
        let mut d = d0;
        for _ in 0..100 {
            let f = s_of(d) - s;
            let df = -(1.0 / (d * d) + 2.0 * kappa * l / (e * d)) / (c * kappa);
            d -= f / df;
        }
        u - d - kappa * l * d * d / e
    };
    for method in ["augmented_lagrangian", "penalty"] {
        let run = |coupling: &str, n: usize| {
            let contact = format!(
                "friction = {mu}\nmethod = \"{method}\"\ninitial_gap = {a}\n[cracks.contact.asperity]\nthickness = {a}\nstiffness = {kappa}\n[cracks.contact.wear]\ncoefficient = {c}\ncoupling = \"{coupling}\""
            );
            let top = format!(
                "[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [\"t\", \"-{u} + 0*t\"]"
            );
            let r = common::contact::solve_contact_text(&block(&contact, &top, n, true))
                .unwrap_or_else(|err| panic!("{method}, {coupling}, {n}: {err:?}"));
            let area: f64 = r.weight.iter().sum();
            let w = r.weight.iter().zip(&r.wear).map(|(wt, w)| wt * (w[0] + w[1])).sum::<f64>() / area;
            let d = delta_of_w(w);
            assert!(d < a && r.lambda.iter().all(|l| l.abs() < 1e-12), "{method}: the layer alone carries the load");
            let p = kappa * d * d;
            let s = 1.0 - mu * p / 0.5;
            let reference = reference(s);
            let newton = r.steps.iter().map(|st| st.contact.as_ref().unwrap().newton).max().unwrap();
            ((w - reference) / reference, newton)
        };
        let (implicit, newton) = run("implicit", 20);
        let (_, newton_staggered) = run("staggered", 20);
        println!("{method}: implicit at 20 steps {implicit:.3e}, Newton iterations in a step at most {newton} (staggered {newton_staggered})");
        assert!(implicit.abs() < 5e-3, "{method}: implicit at 20 steps: relative error {implicit:.3e}");
        assert!(
            newton <= newton_staggered + 2,
            "{method}: implicit: {newton} Newton iterations in a step, staggered {newton_staggered}"
        );
        let errors: Vec<f64> = [10, 20, 40, 80].iter().map(|&n| run("staggered", n).0).collect();
        println!("{method}: staggered errors {errors:?}");
        for k in 0..3 {
            let rate = (errors[k] / errors[k + 1]).abs().log2();
            assert!((rate - 1.0).abs() < 0.1, "{method}: staggered rate {rate:.3}: errors {errors:?}");
        }
    }
}

fn parse(text: &str) -> Result<Case, CaseError> {
    Case::parse(text, Path::new("case.toml"))
}

/// Bad input of `[cracks.contact.wear]` (issue 14): each gives an error naming the key and
/// its line (never a panic): zero or negative coefficient, hardness ≤ 0, split outside
/// [0, 1], k without hardness, both coefficient and k, an unknown coupling, wear on a
/// crack without contact, and wear with [dynamics] (not available); wear with the
/// asperity layer reads with either coupling.
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
    // Available: either coupling with the asperity layer. Not available: dynamics (large
    // sliding is, in 2D: tests/wear_large_sliding.rs, which also checks the 3D refusal).
    let large = good.replace("friction = 0.3\n", "friction = 0.3\nsliding = \"large\"\n");
    parse(&large).expect("large sliding in 2D");
    let asperity = good
        .replace("friction = 0.3\n", "friction = 0.3\n[cracks.contact.asperity]\nthickness = 1e-4\nstiffness = 1e6\n");
    parse(&asperity).expect("implicit with asperity");
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
