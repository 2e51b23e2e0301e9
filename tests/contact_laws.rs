//! The contact laws on the same unknowns (issue 13): the stabilised Lagrangian against the
//! augmented Lagrangian, and the initial gap.

mod common;

use common::contact::{inclined_crack, solve_contact_text};

/// Block `[0, 20]²` cut by the flat interface y = 10.5 (mid-element), E = 100, ν = 0,
/// quad4 10 × 10, bottom clamped, top displaced by (0, −1e-6).
fn block(contact: &str) -> String {
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [20.0, 20.0]\ndivisions = [10, 10]\n[[materials]]\nE = 100.0\nnu = 0.0\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [0.0, -1e-6]\n[[cracks]]\nname = \"iface\"\nshape = \"line\"\npoint = [0.0, 10.5]\nnormal = [0.0, 1.0]\n[cracks.contact]\n{contact}\n"
    )
}

/// Contact patch test for the stabilised Lagrangian (seed eq. 6; Taylor & Papadopoulos
/// 1991). Geometry: the 20 × 20 block cut at y = 10.5, quad4 10 × 10 (h = 2). Material
/// E = 100, ν = 0. Loads: bottom clamped, top displaced by −1e-6. Reference: uniform stress
/// σ_yy = E·(−1e-6)/20 = −5e-6, so λ = −5e-6 at every point (the λ = −5 with
/// E = 1e8). The stabilisation vanishes where d_n = 0, so it must not perturb the answer:
/// tolerance 1e-10 relative for κ_n from 1e-3·E/h to 1e3·E/h, with μ = 0 and μ = 0.3.
#[test]
fn stabilised_patch_test_lambda_exact_for_every_kappa() {
    let (e, h) = (100.0, 2.0);
    for mu in [0.0, 0.3] {
        for k in [1e-3, 1.0, 1e3] {
            let kappa = k * e / h;
            let r = solve_contact_text(&block(&format!(
                "friction = {mu}\nmethod = \"stabilised\"\nkappa_n = {kappa}\nkappa_t = {}",
                k / h
            )))
            .expect("solves");
            assert!(!r.lambda.is_empty());
            for l in &r.lambda {
                assert!((l / -5e-6 - 1.0).abs() < 1e-10, "κ_n = {kappa}, μ = {mu}: λ = {l}");
            }
            let c = r.steps[0].contact.as_ref().unwrap();
            assert_eq!(c.active, c.points, "every point in contact");
        }
    }
}

/// The initial gap g₀ (every method): the same block with the lips apart by g₀ = 4e-7 and
/// the top moved by −1e-6. Reference (1D): the gap closes after a shortening of 4e-7, the
/// rest 6e-7 strains the block, σ_yy = −100·6e-7/20 = −3e-6, so λ = −3e-6 at every point,
/// and the opening after closure is ⟦u⟧·n = −g₀. Tolerance 1e-9 relative.
#[test]
fn initial_gap_closes_then_carries_the_rest_of_the_load() {
    for method in ["augmented_lagrangian", "stabilised"] {
        let r = solve_contact_text(&block(&format!("method = \"{method}\"\ninitial_gap = 4e-7"))).expect("solves");
        for (l, (j, n)) in r.lambda.iter().zip(r.jump.iter().zip(&r.normal)) {
            assert!((l / -3e-6 - 1.0).abs() < 1e-9, "{method}: λ = {l}");
            let opening = j[0] * n[0] + j[1] * n[1];
            assert!((opening / -4e-7 - 1.0).abs() < 1e-9, "{method}: opening {opening}");
        }
    }
}

/// The closed 45° frictional crack of tests/contact_friction_cracks.rs (plate [−2, 2]²,
/// crack 2a = 0.4 at 45°, E = 1, ν = 0.3, σ = 1 compression, quad4 81 × 81) with μ = 0 and
/// μ = 0.3. Reference: the augmented Lagrangian on the same mesh. The stabilisation
/// (κ_n = E/h, κ_τ = 1/h) does not perturb the solution: |K_II| and the pressure at every
/// point agree to 1e-8 (relative to the mean pressure and to |K_II|).
#[test]
fn stabilised_matches_augmented_lagrangian_on_the_closed_inclined_crack() {
    for mu in [0.0, 0.3] {
        let al = solve_contact_text(&inclined_crack(mu, 81, "")).expect("AL solves");
        let st = solve_contact_text(&inclined_crack(mu, 81, "method = \"stabilised\"\n")).expect("stabilised solves");
        let p_mean = al.lambda.iter().map(|l| l.abs()).sum::<f64>() / al.lambda.len() as f64;
        let worst = al.lambda.iter().zip(&st.lambda).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / p_mean;
        println!("μ = {mu}: pressure difference {worst:.2e}");
        assert!(worst < 1e-8, "μ = {mu}: pressure differs by {worst:.2e}");
        for (a, s) in al.sifs[0].iter().zip(&st.sifs[0]) {
            let (ka, ks) = (a.k2.abs(), s.k2.abs());
            println!("μ = {mu}: |K_II| {ka} vs {ks}");
            assert!(((ks - ka) / ka).abs() < 1e-8, "μ = {mu}: |K_II| {ka} vs {ks}");
        }
    }
}
