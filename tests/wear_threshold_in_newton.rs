//! The friction threshold with wear (issue 14, the wear bench's floors): the threshold in
//! the Newton loop (`[contact_solver] friction_threshold = "newton"`, the default of the
//! stabilised law) with either wear coupling, against the friction fixed point's wear.
//!
//! Every case is the wear bench's platen (`benches/wear.rs`) on a coarser mesh: the layer
//! [0, 4] × [−0.5, 0.5] (quad4 40 × 80, h = 0.1 × 0.0125) cut by the flat interface
//! y = 0.27 (inside a cell row), E = 1, ν = 0, bottom clamped, top pressed down by 0.002
//! at step 1 and slid along x by 0.005 per step for 5 more steps, μ = 0.5, Archard
//! k/H = 1 (split 0.5). The whole interface slides from step 2 on; the wear, 5e-3 of the
//! approach per step, moves the pressure by ~5e-3 relative per step, so the plain fixed
//! point takes 5–7 passes a step (measured with main's binary at 91fce3c: 7, 5–6, 6, 6, 6
//! passes in steps 2–6, either coupling and method), where the run without wear takes 1.
//! The factor is condensed (the crack block is small), so the threshold can follow the
//! Newton loop.

mod common;

use serde_json::Value;

/// Every run starts each step from the last step's friction thresholds: the fixed point's
/// 5–7 passes a step are of that start (the extrapolated start of the default takes 1–3
/// here: `tests/wear_threshold_start.rs`).
const LAST_THRESHOLDS: &[(&str, &str)] = &[("FISSURE_THRESHOLD_START", "previous")];

/// The platen ([`common::contact::wear_platen`], 6 steps) with `method`, the wear
/// `coupling` and the `friction_threshold` key (None: not given).
fn platen(method: &str, coupling: &str, threshold: Option<&str>) -> String {
    let solver = threshold.map_or(String::new(), |t| format!("[contact_solver]\nfriction_threshold = \"{t}\"\n"));
    common::contact::wear_platen(6, &solver, &format!("method = \"{method}\""), coupling)
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// Friction passes of every step.
fn passes(summary: &Value) -> Vec<usize> {
    summary["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["contact"]["iterations"]["friction"].as_u64().unwrap() as usize)
        .collect()
}

/// The wear figures of two runs agree to `tol` relative at every step (max, mean, worn
/// volume, frictional work).
fn same_wear(a: &Value, b: &Value, tol: f64, tag: &str) {
    let (sa, sb) = (a["steps"].as_array().unwrap(), b["steps"].as_array().unwrap());
    assert_eq!(sa.len(), sb.len(), "{tag}");
    for (k, (x, y)) in sa.iter().zip(sb).enumerate() {
        for key in ["max", "mean", "volume", "frictional_work"] {
            let (wx, wy) = (num(&x["contact"]["wear"], key), num(&y["contact"]["wear"], key));
            assert!((wx - wy).abs() <= tol * wy.abs(), "{tag}: step {} {key}: {wx:.12e} against {wy:.12e}", k + 1);
        }
    }
}

/// The threshold in the Newton loop with wear. Case: the module doc's platen, the
/// stabilised law (whose threshold follows the loop by default) and the augmented
/// Lagrangian with `friction_threshold = "newton"`, staggered and implicit wear.
/// Reference: the same case with `friction_threshold = "fixed_point"`, the plain fixed
/// point (the staggered wear is a constant of the step in the gap; the implicit wear
/// changes the normal law, not the threshold λ). Tolerance: the wear figures of every
/// step (max, mean, volume, frictional work) to 1e-6 relative, the friction tolerance's
/// order (measured 2.6e-7 staggered, 4.7e-8 implicit, 2026-11-27). Counts: 1 friction
/// pass a step with the threshold in the loop (asserted ≤ 2) and 5–6 Newton iterations in
/// steps 2–6 (asserted ≤ 8), against 5–7 passes (asserted ≥ 4) and 11–27 Newton
/// iterations with the fixed point.
#[test]
fn wear_with_the_threshold_in_the_newton_loop_gives_the_fixed_point_wear_in_fewer_passes() {
    for (method, key) in [("stabilised", None), ("augmented_lagrangian", Some("newton"))] {
        for coupling in ["staggered", "implicit"] {
            let tag = format!("{method} {coupling}");
            let name = format!("{method}_{coupling}");
            let live = common::run_cli_with_env(
                "wear_threshold_in_newton",
                &format!("{name}_newton"),
                &platen(method, coupling, key),
                LAST_THRESHOLDS,
            );
            let fixed = common::run_cli_with_env(
                "wear_threshold_in_newton",
                &format!("{name}_fixed"),
                &platen(method, coupling, Some("fixed_point")),
                LAST_THRESHOLDS,
            );
            assert_eq!(live["linear_solver"]["condensed"], Value::Bool(true), "{tag}: the condensed factor");
            same_wear(&live, &fixed, 1e-6, &tag);
            let (pl, pf) = (passes(&live), passes(&fixed));
            assert!(pl.iter().all(|&p| p <= 2), "{tag}: passes {pl:?} with the threshold in the loop");
            assert!(pf[1..].iter().all(|&p| p >= 4), "{tag}: passes {pf:?} with the fixed point");
            let newton = |s: &Value| -> Vec<u64> {
                s["steps"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|t| t["contact"]["iterations"]["newton"].as_u64().unwrap())
                    .collect()
            };
            let nl = newton(&live);
            assert!(nl[1..].iter().all(|&n| n <= 8), "{tag}: Newton iterations {nl:?} with the threshold in the loop");
        }
    }
}
