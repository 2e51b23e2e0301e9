//! The θ-method on velocities (issue 15 item 2; the founding paper's finite-difference
//! scheme, seed: "schémas d'ordre 1 (θ schéma)", Jean–Moreau): u_{n+1} = u_n +
//! Δt ((1 − θ) v_n + θ v_{n+1}), M (v_{n+1} − v_n) = Δt (θ F_{n+1} + (1 − θ) F_n),
//! F = f − K u − contact forces (`[dynamics] scheme = "theta"`, `solve::time::Theta`).
//!
//! 1. Free cantilever (set-up of tests/dynamics_free_cantilever.rs: [0, 10] × [0, 1]
//!    clamped at x = 0, quad4 40 × 4, E = 1000, ν = 0.3, ρ = 1, plane stress, released
//!    from the Euler–Bernoulli tip-load shape, Δt = T₁/100, 620 steps), θ = ½: the
//!    trapezoidal rule, so the tolerances of average acceleration: first period within 1% of
//!    the modal T₁ (consistent-mass eigenproblem, `lowest_frequency`), total energy changing
//!    by less than 1e-8 of its initial value per step.
//! 2. The same cantilever with θ = 1 (backward Euler) and θ = ¾: the energy decreases at
//!    every step, and once the higher modes are damped out (from step 200: the second mode,
//!    ω₂ Δt ≈ 0.39, keeps less than 1e-6 of its energy) the energy ratio over steps
//!    200 → 400 is the first mode's (|λ|²)²⁰⁰, with the amplification factor of the θ-method
//!    on ẍ = −ω² x (Ω = ω₁ Δt): λ = (1 − i (1 − θ) Ω)/(1 + i θ Ω),
//!    |λ|² = (1 + (1 − θ)² Ω²)/(1 + θ² Ω²) (θ = 1: 1/(1 + Ω²); derivation: the step is
//!    (I + θ Ω J) z_{n+1} = (I − (1 − θ) Ω J) z_n on z = (ω u, v), J the rotation by π/2).
//!    Tolerance 1e-6 relative on the 200-step ratio (measured 6e-12 at θ = 1, 5e-8 at
//!    θ = ¾: the residue of the higher modes, which θ = ¾ damps more slowly).
//! 3. The bar against a rigid wall (tests/dynamics_bar_rigid_wall.rs, velocity formulation
//!    of the contact, Doyen–Ern–Piperno's exact solution) with θ = ½: the Newmark bar test's
//!    assertions (`common::dynamics::check_velocity_form_bar`: no penetration beyond
//!    round-off with the position correction, the tolerances at n = 42), at n = 21
//!    and 42. With θ = 1 the velocity law's impact-step overlap
//!    (1 − θ) Δt ⟦v⟧ vanishes: no penetration beyond round-off (1e-12 h), at the price of the
//!    bar's energy (backward Euler damps the wave; measured at n = 21: contact until exactly
//!    2L/c, mean pressure −8.8%, rebound −17.6%, kinetic + strain after / before 0.73;
//!    asserted only as a loss).
//!
//! Run with `cargo test --release --test dynamics_theta_method -- --nocapture` for the figures.

mod common;

use common::dynamics::{bar_impact, check_velocity_form_bar, free_cantilever};
use fissure::element::CellType;
use fissure::solve::time::{DynamicScheme, Theta};

fn theta(t: f64) -> impl Fn(f64) -> DynamicScheme {
    move |t1| DynamicScheme::Theta(Theta::new(t, t1 / 100.0, 620))
}

#[test]
fn theta_half_free_cantilever_conserves_energy_and_keeps_the_first_period() {
    let (period, t1, totals) = free_cantilever(CellType::Quad4, [40, 4], &theta(0.5));
    let err = period / t1 - 1.0;
    let e0 = totals[0];
    let drift = totals.windows(2).map(|w| (w[1] - w[0]).abs() / e0).fold(0.0, f64::max);
    eprintln!(
        "θ = 1/2: period {period:.6} against T1 {t1:.6} ({:+.3}%), largest energy change per step {drift:.2e}",
        100.0 * err
    );
    assert!(err.abs() < 0.01, "period {period} against {t1}");
    assert!(drift < 1e-8, "energy changes by {drift:.2e} per step");
}

#[test]
fn theta_above_half_dissipates_the_first_mode_by_its_amplification_factor() {
    for th in [1.0, 0.75] {
        let (_, t1, totals) = free_cantilever(CellType::Quad4, [40, 4], &theta(th));
        let decreasing = totals.windows(2).all(|w| w[1] < w[0]);
        let omega_dt = 2.0 * std::f64::consts::PI / t1 * (t1 / 100.0);
        let o2 = omega_dt * omega_dt;
        let lambda2 = (1.0 + (1.0 - th) * (1.0 - th) * o2) / (1.0 + th * th * o2);
        let expected = lambda2.powi(200);
        let measured = totals[400] / totals[200];
        let err = measured / expected - 1.0;
        eprintln!(
            "θ = {th}: energy strictly decreasing: {decreasing}; E(620)/E(0) = {:.5}; E(400)/E(200) = {measured:.8} \
             against (|λ|²)^200 = {expected:.8} ({err:+.2e})",
            totals[620] / totals[0]
        );
        assert!(decreasing, "θ = {th}: the energy does not decrease at every step");
        assert!(err.abs() < 1e-6, "θ = {th}: decay {measured} against {expected}");
    }
}

#[test]
fn bar_against_a_rigid_wall_theta_half_matches_the_exact_impact() {
    let v0 = 0.01;
    let mut errors = vec![];
    for n in [21, 42] {
        let f = bar_impact(n, v0, "scheme = \"theta\"\ntheta = 0.5");
        errors.push(check_velocity_form_bar(&f, n, v0));
    }
    assert!(errors[1].0 < errors[0].0 && errors[1].1 < errors[0].1, "no gain under refinement: {errors:?}");
}

#[test]
fn bar_against_a_rigid_wall_theta_one_does_not_penetrate() {
    let (n, v0) = (21, 0.01);
    let f = bar_impact(n, v0, "scheme = \"theta\"\ntheta = 1.0");
    let h = 1.05 / n as f64;
    eprintln!(
        "θ = 1, n = {n}: contact until {:.4} (2L/c = {:.4}), open steps inside {}, sign change {}, mean pressure {:+.3}%, \
         rebound {:+.3}%, energy ratio {:.5}, largest overlap {:.3e}",
        f.last_contact,
        f.duration,
        f.open_inside,
        f.sign_changes,
        100.0 * (f.p_mean / 0.01 - 1.0),
        100.0 * (f.rebound / -v0 - 1.0),
        f.energy_ratio,
        f.overlap,
    );
    assert!(f.overlap <= 1e-12 * h, "overlap {}", f.overlap);
    assert!(f.energy_ratio < 1.0, "energy ratio {}", f.energy_ratio);
}
