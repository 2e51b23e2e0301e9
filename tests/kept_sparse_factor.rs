//! The whole-system factor kept across contact iterations (`src/solve/faer/kept.rs`): on a
//! contact system that the condensed factor does not take, a new contact tangent that
//! differs in few contact columns is solved by GMRES preconditioned by the previous factor
//! instead of a new numeric factorisation. One test (it switches the path off through the
//! environment, read at each analysis, so it runs the two variants one after the other).

mod common;
use common::contact::solve_contact_text;
use common::sliding::blocks;

/// Sliding blocks of `tests/large_sliding.rs` ([0, 6] × [−0.5, 0.5], quad4 120 × 21, E = 1,
/// ν = 0, bottom clamped, top driven by u = (0.03 t, −0.002), μ = 0.5, large sliding,
/// `nodes` integration, 4 steps). Large sliding marks every primal unknown as varying, so
/// the contact system is never condensed: the plain LDLᵀ (968 crack unknowns, 242
/// multipliers). Reference: the same run with the kept factor switched off
/// (`FISSURE_SPARSE_REFACTOR`), which factorises at every new contact tangent.
/// Assertions: the same Newton factorisation calls (the loops do not change), numeric
/// factorisations down from all of them (29, measured) to at most all but 4 (22 measured),
/// some solves by GMRES; the contact pressure and Λ at every point, and the reactions of
/// every step, equal to the run without it within 1e-9 relative to their largest value
/// (the loops' Newton tolerance is 1e-8 relative; both solves reach ~1e-14).
#[test]
fn sliding_blocks_large_sliding_kept_factor_fewer_factorisations_same_answer() {
    let top = r#"[[dirichlet]]
group = "top"
components = ["x", "y"]
values = ["0.03 * t", "-0.002 + 0 * t"]"#;
    let text = blocks(0.5, top, 4, "nodes");
    std::env::set_var("FISSURE_SPARSE_REFACTOR", "1");
    let off = solve_contact_text(&text).expect("solves without the kept factor");
    std::env::remove_var("FISSURE_SPARSE_REFACTOR");
    let on = solve_contact_text(&text).expect("solves with the kept factor");
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
