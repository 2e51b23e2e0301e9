//! The friction thresholds a step starts from with wear (issue 14, the wear bench's floors):
//! extrapolated from the last two converged steps (`solve::threshold_start`, the default
//! with wear) against the last step's (`FISSURE_THRESHOLD_START=previous`).
//!
//! Case: the wear bench's platen (`benches/wear.rs`) on a coarser mesh, as in
//! `tests/wear_provisional_passes.rs`: the layer [0, 4] × [−0.5, 0.5] (quad4 40 × 80) cut
//! by the flat interface y = 0.27, E = 1, ν = 0, bottom clamped, top pressed down by 0.002
//! at step 1 and slid along x by 0.005 per step for 7 more steps, μ = 0.5, the augmented
//! Lagrangian (whose threshold keeps the fixed point), Archard k/H = 1 (split 0.5). The
//! wear moves the pressure by ~5e-3 relative per step, steadily: from the last step's
//! thresholds the fixed point takes 5–7 passes a step.

mod common;

use serde_json::Value;

/// The platen ([`common::contact::wear_platen`], 8 steps) with the wear `coupling`;
/// `plain`: the plain sparse factor of the whole system (the bench's 1e5 row's path), else
/// the default (condensed here).
fn platen(coupling: &str, plain: bool) -> String {
    let solver = if plain { "[solver]\ncondense = false\n" } else { "" };
    common::contact::wear_platen(8, solver, "", coupling)
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// The per-step friction passes of `steps[].contact.iterations`.
fn passes(summary: &Value) -> Vec<u64> {
    summary["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["contact"]["iterations"]["friction"].as_u64().unwrap())
        .collect()
}

/// The largest relative difference over the steps of the wear figures (max, mean, volume,
/// frictional work), of the pressure range (λ min, max) and of the top's reaction, each
/// relative to its own scale.
fn difference(a: &Value, b: &Value) -> f64 {
    let (sa, sb) = (a["steps"].as_array().unwrap(), b["steps"].as_array().unwrap());
    assert_eq!(sa.len(), sb.len());
    let mut worst = 0.0f64;
    let mut rel = |x: f64, y: f64, scale: f64| worst = worst.max((x - y).abs() / scale.max(f64::MIN_POSITIVE));
    for (x, y) in sa.iter().zip(sb) {
        let (cx, cy) = (&x["contact"], &y["contact"]);
        for key in ["max", "mean", "volume", "frictional_work"] {
            let (wx, wy) = (num(&cx["wear"], key), num(&cy["wear"], key));
            rel(wx, wy, wy.abs());
        }
        let lam = num(cy, "lambda_min").abs();
        rel(num(cx, "lambda_min"), num(cy, "lambda_min"), lam);
        rel(num(cx, "lambda_max"), num(cy, "lambda_max"), lam);
        let (rx, ry) = (&x["reactions"]["top"], &y["reactions"]["top"]);
        let scale = (0..2).map(|k| ry[k].as_f64().unwrap().abs()).fold(0.0, f64::max);
        for k in 0..2 {
            rel(rx[k].as_f64().unwrap(), ry[k].as_f64().unwrap(), scale);
        }
    }
    worst
}

/// Extrapolated starting thresholds give the same wear and pressure as the last step's
/// thresholds, in fewer friction passes. Case: the module doc's platen, staggered and
/// implicit wear on the plain factor, staggered on the default (condensed) one.
/// Reference: the same run with `FISSURE_THRESHOLD_START=previous`. Tolerance: every
/// step's wear figures (max, mean, volume, frictional work), λ min and max (relative to
/// the largest pressure) and the top's reaction (relative to its largest component) to
/// 1e-5: both runs stop their fixed points at `tol_friction` = 1e-6 on the thresholds'
/// relative change, from different starts, so their thresholds differ at that order (the
/// contraction ≈ 0.2 a pass bounds the distance to the fixed point by ~1.3 × 1e-6), and
/// the wear and tractions follow the thresholds linearly. Counts: from step 5 on (the
/// extrapolation needs two sliding steps, 2 and 3, and to have beaten the last step's
/// start once, in step 4) at least 2 passes fewer a step with staggered wear and at least
/// 1 with implicit, and fewer over the run in every case.
#[test]
fn extrapolated_thresholds_give_the_same_wear_and_pressure_in_fewer_passes() {
    for (coupling, plain, fewer) in [("staggered", true, 2), ("implicit", true, 1), ("staggered", false, 2)] {
        let tag = format!("{coupling}, {}", if plain { "plain" } else { "condensed" });
        let name = format!("{coupling}_{}", if plain { "plain" } else { "condensed" });
        let text = platen(coupling, plain);
        let new = common::run_cli("wear_threshold_start", &format!("{name}_extrapolated"), &text);
        let old = common::run_cli_with_env(
            "wear_threshold_start",
            &format!("{name}_previous"),
            &text,
            &[("FISSURE_THRESHOLD_START", "previous")],
        );
        assert_eq!(new["linear_solver"]["condensed"], Value::Bool(!plain), "{tag}: the factor");
        let diff = difference(&new, &old);
        let (pn, po) = (passes(&new), passes(&old));
        eprintln!("{tag}: figures differ by {diff:.2e} relative; friction passes {pn:?} against {po:?}");
        assert!(diff <= 1e-5, "{tag}: figures differ by {diff:.2e} relative (tolerance 1e-5)");
        assert!(pn.iter().sum::<u64>() < po.iter().sum::<u64>(), "{tag}: passes {pn:?} against {po:?}");
        for k in 4..pn.len() {
            assert!(pn[k] + fewer <= po[k], "{tag}: step {}: passes {pn:?} against {po:?}", k + 1);
        }
    }
}
