//! The whole-system factor kept across contact iterations (`src/solve/faer/kept.rs`): on a
//! contact system that the condensed factor does not take, a new contact tangent that
//! differs in few contact columns is solved by GMRES preconditioned by the previous factor
//! instead of a new numeric factorisation. Each test switches the path through the
//! environment (`FISSURE_KEPT_FACTOR`, read at each analysis) and runs the two variants one
//! after the other, holding [`ENV`] so that the tests do not switch it under each other.

mod common;
use common::contact::solve_contact_text;
use common::sliding::blocks;
use std::sync::Mutex;

/// Held by each test while it sets `FISSURE_KEPT_FACTOR` and runs (the tests of a file run
/// in parallel threads of one process, which share the environment).
static ENV: Mutex<()> = Mutex::new(());

/// Sliding blocks of `tests/large_sliding.rs` ([0, 6] × [−0.5, 0.5], quad4 120 × 21, E = 1,
/// ν = 0, bottom clamped, top driven by u = (0.03 t, −0.002), μ = 0.5, large sliding,
/// `nodes` integration, 4 steps). Large sliding marks every primal unknown as varying, so
/// the contact system is never condensed: the plain LDLᵀ (968 crack unknowns, 242
/// multipliers). Reference: the same run with the kept factor switched off
/// (`FISSURE_KEPT_FACTOR=0`), which factorises at every new contact tangent; the run with it
/// keeps the factor with an unlimited budget (`FISSURE_KEPT_FACTOR=1`: by the predicted cost
/// this small model's factorisation is worth too few Krylov iterations to keep).
/// Assertions: the same Newton factorisation calls (the loops do not change), numeric
/// factorisations down from all of them (29, measured) to at most all but 4 (16 measured:
/// 13 tangents kept, 40 GMRES solves, 48 iterations; the tangents that change every contact
/// column by as much as the entries are refactorised, `WHOLE_CHANGE`), some solves by GMRES; the contact pressure and Λ at every point, and the reactions of
/// every step, equal to the run without it within 1e-9 relative to their largest value
/// (the loops' Newton tolerance is 1e-8 relative; both solves reach ~1e-14).
#[test]
fn sliding_blocks_large_sliding_kept_factor_fewer_factorisations_same_answer() {
    let _env = ENV.lock().unwrap_or_else(|p| p.into_inner());
    let top = r#"[[dirichlet]]
group = "top"
components = ["x", "y"]
values = ["0.03 * t", "-0.002 + 0 * t"]"#;
    let text = blocks(0.5, top, 4, "nodes");
    std::env::set_var("FISSURE_KEPT_FACTOR", "0");
    let off = solve_contact_text(&text).expect("solves without the kept factor");
    std::env::set_var("FISSURE_KEPT_FACTOR", "1");
    let on = solve_contact_text(&text).expect("solves with the kept factor");
    std::env::remove_var("FISSURE_KEPT_FACTOR");
    let sum = |run: &common::contact::ContactRun, f: &dyn Fn(&fissure::solve::backend::CondensedCounts) -> usize| {
        run.steps.iter().filter_map(|s| s.contact.as_ref().and_then(|c| c.kept)).map(|c| f(&c)).sum::<usize>()
    };
    let calls = |run: &common::contact::ContactRun| run.steps.iter().map(|s| s.factorizations).sum::<usize>();
    let (numeric_off, numeric_on) = (sum(&off, &|c| c.factorizations), sum(&on, &|c| c.factorizations));
    let (reused_on, krylov_on) = (sum(&on, &|c| c.reused), sum(&on, &|c| c.krylov_solves));
    println!(
        "factorisation calls {} / {}; numeric factorisations off {numeric_off}, on {numeric_on}; kept {reused_on}, \
         GMRES solves {krylov_on}, iterations {}",
        calls(&off),
        calls(&on),
        sum(&on, &|c| c.krylov_iterations)
    );
    assert_eq!(calls(&off), calls(&on), "the loops take the same path");
    assert_eq!(numeric_off, calls(&off), "switched off, every new tangent is factorised");
    assert!(numeric_off >= 25, "the case factorises often: {numeric_off}");
    assert!(numeric_on + 4 <= numeric_off, "kept factor: {numeric_on} numeric factorisations of {numeric_off}");
    assert!(reused_on >= 4 && krylov_on >= 4, "kept {reused_on}, GMRES solves {krylov_on}");
    let close = |a: &[f64], b: &[f64], what: &str| {
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-9 * scale, "{what}: differ by {diff:e} (largest {scale:e})");
    };
    close(&on.lambda, &off.lambda, "λ");
    let lam = |r: &common::contact::ContactRun| r.big_lambda.iter().map(|l| l[0]).collect::<Vec<f64>>();
    close(&lam(&on), &lam(&off), "Λ");
    let reactions = |r: &common::contact::ContactRun| r.reactions.iter().flatten().copied().collect::<Vec<f64>>();
    close(&reactions(&on), &reactions(&off), "reactions");
}

/// A small sliding penny crack (the loads of `examples/penny_crack_contact_3d.toml` on a
/// coarse box): block [−2.5, 2.5]³, hex8 10 × 10 × 11 (the crack plane z = 0 between node
/// layers), E = 1, ν = 0.3, three corner points holding the rigid modes, disc crack a = 1 in
/// z = 0 (tip radius 0.5), σ = 1 across it and τ = 0.5 in the x–z plane, Coulomb μ = 0.2
/// (every point slides). Its crack block is more than 1/20 of the unknowns: the plain LDLᵀ
/// of the whole saddle point, the kept factor's case. Reference: the same run with the kept
/// factor switched off (`FISSURE_KEPT_FACTOR=0`: a numeric factorisation at every new
/// contact tangent); the run with it keeps the factor by the same rule with an unlimited
/// budget (`FISSURE_KEPT_FACTOR=1`: this small model's factorisation is worth too few Krylov
/// iterations to keep by the predicted cost). Both runs start the first friction pass from
/// the sliding statuses the law gives (no stick predictor with a kept factor in 3D,
/// `solve::contact_loops`), so the first friction tangent is a change of every friction
/// row from the frictionless one, refactorised in both (`kept.rs`, `WHOLE_CHANGE`).
/// Assertions: the loops take the same path (the same factorisation calls and Newton
/// iterations: 4 and 8 measured); numeric factorisations 1 or 2 with the factor kept (2
/// measured: the frictionless tangent and the first friction tangent, the least the nested
/// loops allow) against all 4 calls without it; GMRES solves (at least 2; measured 5) of at
/// most 16 iterations each on average (measured 36 in all, 7.2 a solve); the pressure, Λ and K_I, K_II, K_III at every front point equal to
/// the switched-off run's within 1e-9 relative to their largest value, the reactions within
/// 1e-9 of the applied force σ·25 (they balance to round-off: ~1e-13).
#[test]
fn sliding_penny_kept_factor_fewer_factorisations_same_lambda_and_k() {
    let _env = ENV.lock().unwrap_or_else(|p| p.into_inner());
    let text = common::contact::small_sliding_penny_case("");
    std::env::set_var("FISSURE_KEPT_FACTOR", "0");
    let off = solve_contact_text(&text).expect("solves without the kept factor");
    std::env::set_var("FISSURE_KEPT_FACTOR", "1");
    let on = solve_contact_text(&text).expect("solves with the kept factor");
    std::env::remove_var("FISSURE_KEPT_FACTOR");
    assert!(!off.condensed, "the plain LDLᵀ of the saddle point");
    let sum = |run: &common::contact::ContactRun, f: &dyn Fn(&fissure::solve::backend::CondensedCounts) -> usize| {
        run.steps.iter().filter_map(|s| s.contact.as_ref().and_then(|c| c.kept)).map(|c| f(&c)).sum::<usize>()
    };
    let calls = |run: &common::contact::ContactRun| run.steps.iter().map(|s| s.factorizations).sum::<usize>();
    let newton = |run: &common::contact::ContactRun| {
        run.steps.iter().filter_map(|s| s.contact.as_ref()).map(|c| c.newton).sum::<usize>()
    };
    let (numeric_off, numeric_on) = (sum(&off, &|c| c.factorizations), sum(&on, &|c| c.factorizations));
    let (solves_on, iterations_on) = (sum(&on, &|c| c.krylov_solves), sum(&on, &|c| c.krylov_iterations));
    println!(
        "{} points; factorisation calls {} / {}, Newton {} / {}; numeric factorisations off {numeric_off}, on \
         {numeric_on}; kept {}, GMRES solves {solves_on}, iterations {iterations_on}",
        on.lambda.len(),
        calls(&off),
        calls(&on),
        newton(&off),
        newton(&on),
        sum(&on, &|c| c.reused)
    );
    assert_eq!((calls(&off), newton(&off)), (calls(&on), newton(&on)), "the loops take the same path");
    assert_eq!(numeric_off, calls(&off), "switched off, every new tangent is factorised");
    assert!(
        (1..=2).contains(&numeric_on) && numeric_off >= 4,
        "kept factor: {numeric_on} numeric factorisations of {numeric_off}"
    );
    assert!(solves_on >= 2 && iterations_on <= 16 * solves_on, "GMRES: {solves_on} solves, {iterations_on} iterations");
    let close_to = |a: &[f64], b: &[f64], floor: f64, what: &str| {
        let scale = b.iter().fold(floor, |m, v| m.max(v.abs()));
        let diff = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-9 * scale, "{what}: differ by {diff:e} (largest {scale:e})");
    };
    let close = |a: &[f64], b: &[f64], what: &str| close_to(a, b, 0.0, what);
    close(&on.lambda, &off.lambda, "λ");
    let lam = |r: &common::contact::ContactRun| r.big_lambda.iter().flatten().copied().collect::<Vec<f64>>();
    close(&lam(&on), &lam(&off), "Λ");
    let reactions = |r: &common::contact::ContactRun| r.reactions.iter().flatten().copied().collect::<Vec<f64>>();
    close_to(&reactions(&on), &reactions(&off), 25.0, "reactions");
    let k = |r: &common::contact::ContactRun| {
        r.sifs.iter().flatten().flat_map(|p| [p.k1, p.k2, p.k3]).collect::<Vec<f64>>()
    };
    close(&k(&on), &k(&off), "K");
}
