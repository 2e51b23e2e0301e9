//! The friction fixed point's provisional intermediate passes with wear (issue 14, the wear
//! bench's floors on the plain factor): `[contact_solver] intermediate_passes =
//! "provisional"` (the default) against `"confirmed"` (every pass's Newton loop to
//! `tol_newton`).
//!
//! Every case is the wear bench's platen (`benches/wear.rs`) on a coarser mesh: the layer
//! [0, 4] × [−0.5, 0.5] (quad4 40 × 80, h = 0.1 × 0.0125) cut by the flat interface
//! y = 0.27 (inside a cell row), E = 1, ν = 0, bottom clamped, top pressed down by 0.002
//! at step 1 and slid along x by 0.005 per step for 5 more steps, μ = 0.5, the augmented
//! Lagrangian (the default law, whose threshold keeps the fixed point), Archard k/H = 1
//! (split 0.5). The wear moves the pressure by ~5e-3 relative per step, so the fixed point
//! takes 5–7 passes a step from step 2 on. `[solver] condense = false` puts the run on the
//! plain sparse LDLᵀ of the whole system (the bench's 1e5 row's path); the default
//! (condensed here) is checked too.

mod common;

use fissure::case::Case;
use serde_json::Value;
use std::path::Path;

/// Every run starts each step from the last step's friction thresholds: the 5–7 passes a
/// step of that start are what the provisional passes are measured on (the extrapolated
/// start of the default takes 1–3 here: `tests/wear_threshold_start.rs`).
const LAST_THRESHOLDS: &[(&str, &str)] = &[("FISSURE_THRESHOLD_START", "previous")];

/// The platen ([`common::contact::wear_platen`], 6 steps) with the wear `coupling`,
/// `intermediate_passes` and, when `plain`, the plain factor.
fn platen(coupling: &str, passes: &str, plain: bool) -> String {
    let solver = if plain { "[solver]\ncondense = false\n" } else { "" };
    common::contact::wear_platen(
        6,
        &format!("{solver}[contact_solver]\nintermediate_passes = \"{passes}\"\n"),
        "",
        coupling,
    )
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// A per-step count of `steps[].contact`: `iterations.<key>` or `<key>`.
fn counts(summary: &Value, key: &str) -> Vec<u64> {
    summary["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let c = &s["contact"];
            c["iterations"][key].as_u64().or_else(|| c[key].as_u64()).unwrap_or_else(|| panic!("{key} in {c}"))
        })
        .collect()
}

/// The largest relative difference over the steps of the wear figures (max, mean, volume,
/// frictional work) of two runs.
fn wear_difference(a: &Value, b: &Value) -> f64 {
    let (sa, sb) = (a["steps"].as_array().unwrap(), b["steps"].as_array().unwrap());
    assert_eq!(sa.len(), sb.len());
    let mut worst = 0.0f64;
    for (x, y) in sa.iter().zip(sb) {
        for key in ["max", "mean", "volume", "frictional_work"] {
            let (wx, wy) = (num(&x["contact"]["wear"], key), num(&y["contact"]["wear"], key));
            worst = worst.max((wx - wy).abs() / wy.abs().max(f64::MIN_POSITIVE));
        }
    }
    worst
}

/// Provisional intermediate passes give the confirmed passes' wear in fewer linear solves.
/// Case: the module doc's platen, staggered and implicit wear, on the plain factor and
/// (staggered) on the default condensed one. Reference: the same run with
/// `intermediate_passes = "confirmed"`. Tolerances: the wear figures of every step (max,
/// mean, volume, frictional work) to 1e-8 relative with staggered wear (each pass's step
/// is exact on the frozen statuses, so both runs make the same passes: their thresholds
/// are the same to round-off, asserted equal pass counts); to 1e-6 with implicit wear
/// (the friction tolerance's order: a provisional pass of the implicit coupling's
/// nonlinear Newton loop is one modified-Newton step, so the passes' thresholds differ
/// and only the accepted fixed points agree, each to `tol_friction` = 1e-6). Counts: fewer
/// linear solves over the run with provisional passes (staggered: one solve fewer in every
/// intermediate pass, at least 3 fewer a step in steps 2–6 where the fixed point takes
/// 5–7 passes).
#[test]
fn provisional_intermediate_passes_give_the_confirmed_passes_wear_in_fewer_solves() {
    for (coupling, plain, tol) in [("staggered", true, 1e-8), ("implicit", true, 1e-6), ("staggered", false, 1e-8)] {
        let tag = format!("{coupling}, {}", if plain { "plain" } else { "condensed" });
        let name = format!("{coupling}_{}", if plain { "plain" } else { "condensed" });
        let prov = common::run_cli_with_env(
            "wear_provisional_passes",
            &format!("{name}_prov"),
            &platen(coupling, "provisional", plain),
            LAST_THRESHOLDS,
        );
        let conf = common::run_cli_with_env(
            "wear_provisional_passes",
            &format!("{name}_conf"),
            &platen(coupling, "confirmed", plain),
            LAST_THRESHOLDS,
        );
        assert_eq!(prov["linear_solver"]["condensed"], Value::Bool(!plain), "{tag}: the factor");
        let diff = wear_difference(&prov, &conf);
        eprintln!("{tag}: wear figures differ by {diff:.2e} relative");
        assert!(diff <= tol, "{tag}: wear figures differ by {diff:.2e} relative (tolerance {tol:.0e})");
        let (sp, sc) = (counts(&prov, "linear_solves"), counts(&conf, "linear_solves"));
        let (fp, fc) = (counts(&prov, "friction"), counts(&conf, "friction"));
        eprintln!("{tag}: solves {sp:?} against {sc:?}, friction passes {fp:?} against {fc:?}");
        assert!(sp.iter().sum::<u64>() < sc.iter().sum::<u64>(), "{tag}: solves {sp:?} against {sc:?}");
        if coupling == "staggered" {
            assert_eq!(fp, fc, "{tag}: the same passes");
            for k in 1..sp.len() {
                assert!(sp[k] + 3 <= sc[k], "{tag}: step {}: solves {sp:?} against {sc:?}", k + 1);
            }
        }
    }
}

/// `intermediate_passes` takes `provisional` or `confirmed`; anything else is an error
/// naming the key and its line.
#[test]
fn bad_intermediate_passes_names_the_key_and_the_line() {
    let good = platen("staggered", "confirmed", false);
    Case::parse(&good, Path::new("case.toml")).expect("confirmed reads");
    let text = good.replace("\"confirmed\"", "\"sometimes\"");
    let e = Case::parse(&text, Path::new("case.toml")).expect_err("an unknown choice");
    assert_eq!(e.key, "contact_solver.intermediate_passes", "{e}");
    assert_eq!(e.line, text.lines().position(|l| l.starts_with("intermediate_passes")).map(|i| i + 1), "{e}");
    assert!(e.message.contains("provisional"), "{e}");
}
