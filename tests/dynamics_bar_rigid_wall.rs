//! The classic 1D Signorini impact in dynamics: an elastic bar against a rigid wall across
//! an X-FEM interface (issue 15 item 6, first bullet), velocity formulation, Newmark
//! average acceleration.
//!
//! Geometry: a strip [0, 1.05] × [0, h], quad4 n × 1 (h = 1.05/n), cut by a line interface
//! at x = L = 1.05 − h/2 (the middle of the last column of cells): the bar is
//! [0, L] × [0, h], the wall the `+` side of the last column, held rigidly at zero by a
//! lip condition (`[[dirichlet]]` with `crack` and `lip = "+"`, Lagrange multipliers).
//! Material: E = 1, ν = 0, ρ = 1, plane stress (1D waves, c = 1). Initial velocity v₀ =
//! 0.01 towards the wall on the bar (projected with the enriched mass: the jump at the
//! interface is exact), 0 on the wall; frictionless contact, lips touching at t = 0.
//! Δt = h/(2c), t ∈ [0, 2.6].
//! Reference (exact 1D solution; GetFEM's demo_dynamic_contact_1D set-up, Doyen, Ern &
//! Piperno, SIAM J. Sci. Comput. 33 (2011) 223–249): contact pressure ρ c v₀ = 0.01 for
//! t ∈ (0, 2L/c), then the bar leaves with velocity −v₀; the energy is kept.
//! Figures: contact duration (the last step in contact), the mean pressure as the impulse
//! Σ p_k Δt over the steps in contact divided by the exact duration 2L/c, the rebound
//! velocity as the bar's momentum / mass at the end (the momentum from the mass kernel's
//! projection of the bar's indicator), kinetic + strain energy at the end against t = 0,
//! and the largest overlap of the lips.
//! The position correction (`solve::position_correction`, the default with the velocity
//! formulation) projects the displacements back onto the lips' non-penetration after the
//! impact step, which the velocity law alone leaves overlapping by ½ Δt v₀.
//! Asserted (issue 15 item 6; `common::dynamics::check_velocity_form_bar`): at n = 21 and
//! 42, no penetration beyond round-off at any step (largest overlap ≤ 1e-12 h; measured
//! 8.0e-19, 6.2e-19), at most one open step inside the contact interval (measured 0, 1), no
//! sign change of the pressure, kinetic + strain energy at the end within 1% of t = 0
//! (measured 0.99002, 0.99078), kinetic + strain + contact work constant to 1e-9, and both
//! errors smaller at n = 42 than at n = 21; at n = 42 also the last contact step within
//! 2 Δt of 2L/c (measured one step early), the impulse-based mean pressure within 1% of
//! ρ c v₀ (measured −0.94%) and the rebound velocity within 3% of −v₀ (measured −1.89%).
//! At n = 21 (h = 0.05, the two-block test's mesh and Δt: the same figures) the contact
//! ends 3 steps before 2L/c (last contact step 1.975: the lips open at t = 2.0), the
//! impulse is −1.58% and the rebound −3.17%: not asserted against the tolerances
//! there. Without the correction the lips, still overlapping by ½ Δt v₀ when they open at
//! t = 2.0, touch again at 2.025 on the gap law (one more contact step, impulse −1.06%,
//! rebound −2.11%, energy 0.9939: the figures this test asserted before the correction);
//! the correction removes that late contact, so the figures above are the velocity law's
//! own. Where the energy goes (docs/contact-algorithms.md, "Position correction"): the
//! impact step's velocity law stops the lips' mass at once (1.4% of the energy at n = 21,
//! the trapezoidal contact work of that step), the release step gives 0.4% back.
//!
//! Formerly a known failure: the run stopped at the release (t = 2.0) with the Newton
//! loop's relative correction stalling near 1e-3 (near 1 in the quasi-static analogue) —
//! not a singular system but its measure: the
//! lip condition's multipliers of the wall, which carries nothing once every point is open,
//! are of round-off size, and their round-off corrections were measured against themselves.
//! The Dirichlet and relation multipliers are now measured against a floor of the force
//! scale (`solve::newton::reaction_floor`); the quasi-static reproduction is
//! `block_pulled_off_a_lip_held_wall_opens_with_zero_pressure_and_translates_freely`
//! (tests/lip_conditions_and_relations.rs). Run with `cargo test --release --test
//! dynamics_bar_rigid_wall -- --nocapture` for the figures.

mod common;

use common::dynamics::bar_impact as impact;
use common::dynamics::bar_impact_at as impact_at;
use common::dynamics::bar_impact_with as impact_with;
use common::dynamics::check_velocity_form_bar;

#[test]
fn bar_against_a_rigid_wall_velocity_formulation_matches_the_exact_impact() {
    let v0 = 0.01;
    let mut errors = vec![];
    for n in [21, 42] {
        let f = impact(n, v0, "");
        errors.push(check_velocity_form_bar(&f, n, v0));
    }
    assert!(errors[1].0 < errors[0].0 && errors[1].1 < errors[0].1, "no gain under refinement: {errors:?}");
}

/// Issue 15's bar against a rigid wall with the velocity formulation and Newmark average
/// acceleration, without penetration: the first test's set-up at n = 42 (h = 0.025,
/// Δt = 0.0125), with the position correction (the default) and without it
/// (`[dynamics] position_correction = false`). Reference: the exact 1D impact (the
/// header). Asserted with the correction: no penetration beyond round-off at any step
/// (largest overlap ≤ 1e-12 h; measured 6.2e-19), the last contact step within 2 Δt of
/// 2L/c (measured one step early), the impulse-based mean pressure within 1% of ρ c v₀
/// (measured −0.94%), the rebound velocity within 3% of −v₀ (measured −1.89%), kinetic +
/// strain after / before within 1% (measured 0.9908), no sign change of the pressure, and
/// the correction's work booked (kinetic + strain + contact work constant to 1e-9).
/// Without it the lips overlap by ½ Δt v₀ from the impact step on (asserted to 1e-9
/// relative): the correction is what removes it.
#[test]
fn bar_against_a_rigid_wall_does_not_penetrate_with_the_position_correction() {
    let (n, v0) = (42, 0.01);
    let f = impact(n, v0, "");
    check_velocity_form_bar(&f, n, v0);
    let off = impact(n, v0, "position_correction = false");
    eprintln!("without the correction: largest overlap {:.3e}, energy ratio {:.5}", off.overlap, off.energy_ratio);
    assert!((off.overlap / (0.5 * off.dt * v0) - 1.0).abs() < 1e-9, "overlap without the correction {}", off.overlap);
}

/// The bar of the first test at n = 200 (h = 0.00525, Δt = h/(2c), t ∈ [0, 2.6]: 1 040
/// steps of 804 dofs), where the contact factor is condensed onto the crack unknowns (at
/// n = 21 and 42 the system is too small and the plain LDLᵀ is used). Formerly a known
/// failure: the first step's Newton loop stopped after 30 iterations at the relative
/// correction 0.0335, each correction the same (the deferred interior solve did not bring
/// the lip condition's multiplier rows up to date); the corrections now solve the whole
/// system when there are Dirichlet or relation multipliers. Reference and tolerances: the
/// first test's (exact 1D impact: duration 2L/c, pressure ρ c v₀, rebound −v₀, energy
/// kept), at this mesh the 1% on the impulse-based pressure and the rebound
/// (measured −0.30%, −0.60%; energy 0.99871; no penetration beyond round-off, overlap
/// ≤ 1e-12 h, measured below 1e-18). The contact duration is asserted within 1%
/// of 2L/c (measured: the last contact step 2.0869 against 2.0947, −0.37%): the issue's
/// "within 2 time steps" is not met at this mesh (3 steps early, the discrete wave front
/// smeared over more steps at Courant 0.5; two open steps inside the interval, not
/// asserted).
#[test]
fn bar_against_a_rigid_wall_condensed_factor_at_n_200() {
    let (v0, p_exact) = (0.01, 0.01);
    let f = impact(200, v0, "");
    eprintln!(
        "n = 200: contact until {:.4} (2L/c = {:.4}), open steps inside {}, mean pressure {:+.3}%, rebound {:+.3}%, energy ratio {:.5}",
        f.last_contact,
        f.duration,
        f.open_inside,
        100.0 * (f.p_mean / p_exact - 1.0),
        100.0 * (f.rebound / -v0 - 1.0),
        f.energy_ratio
    );
    assert!((f.last_contact / f.duration - 1.0).abs() < 0.01, "duration");
    assert!(!f.sign_changes, "the pressure changes sign during contact");
    assert!((f.p_mean / p_exact - 1.0).abs() < 0.01, "mean pressure {}", f.p_mean);
    assert!((f.rebound / -v0 - 1.0).abs() < 0.01, "rebound velocity {}", f.rebound);
    assert!((f.energy_ratio - 1.0).abs() < 0.01, "energy ratio {}", f.energy_ratio);
    assert!(f.overlap <= 1e-12 * 1.05 / 200.0, "overlap {}", f.overlap);
}

/// The bar of the first test (n = 42: h = 0.025, Δt = h/(2c) = 0.0125) against the wall
/// through a penalty spring: `method = "penalty"`, κ_n = 10 (stress/length; a spring of
/// stiffness κ_n·A on the bar's end, A = h), the displacement gap (the penalty's only
/// formulation), t ∈ [0, 3].
/// Reference (exact, 1D waves): until the wave reflected at the bar's free end comes back
/// (t < 2L/c) the bar's end is a dashpot of impedance ρc per unit area, so the overlap δ
/// of the spring follows dδ/dt = v₀ − κ_n δ/(ρc) and the contact pressure is
/// p(t) = ρ c v₀ (1 − exp(−t/τ)), τ = ρc/κ_n = 0.1 (8 time steps): a spring rising to the
/// hard contact's ρ c v₀ (the first test's pressure) in a few τ. The spring is elastic and
/// Newmark average acceleration keeps the energy of a linear system: once the bar has left
/// the spring, its kinetic + strain energy is the initial one.
/// Asserted: over the steps with t ≤ 0.9 · 2L/c (the discrete reflected wave, smeared over
/// a few cells, reaches the end a little before 2L/c: +3% at 2L/c − 5Δt) the largest
/// |p − p_exact| within 1% of ρ c v₀ (measured 0.39%) and the mean of p/p_exact over
/// t ∈ [τ, 0.9 · 2L/c] within 0.1% of 1 (measured 0.99999); the bar released before the end
/// (measured: last contact step 2.2375) with zero pressure at the end; the rebound velocity
/// (momentum / mass) within 1.5% of −v₀ (measured −0.55%: the rest stays as vibration);
/// kinetic + strain energy at the end within 1% of t = 0 (measured 1.00013); no sign change
/// of the pressure. Printed with `--nocapture`.
#[test]
fn bar_against_a_wall_through_a_penalty_spring_follows_the_exact_spring_impact() {
    let (v0, kappa, rho_c) = (0.01, 10.0, 1.0);
    let tau = rho_c / kappa;
    let f = impact_with(42, v0, "", &format!("method = \"penalty\"\nkappa_n = {kappa}"), 3.0);
    let exact = |t: f64| rho_c * v0 * (1.0 - (-t / tau).exp());
    // The discrete reflected wave is smeared over a few cells: it reaches the end a little
    // before 2L/c (the pressure is 3% above the exact one at 2L/c − 5Δt).
    let early: Vec<&(f64, f64)> = f.history.iter().filter(|(t, _)| *t <= 0.9 * f.duration).collect();
    let worst = early.iter().map(|(t, p)| (p - exact(*t)).abs()).fold(0.0, f64::max) / (rho_c * v0);
    let plateau: Vec<f64> = early.iter().filter(|(t, _)| *t >= tau).map(|(t, p)| p / exact(*t)).collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    eprintln!(
        "penalty κ_n = {kappa}: largest |p − p_exact| / ρcv₀ {worst:.4} over {} steps, mean p/p_exact {mean:.5} over {}, \
         contact until {:.4} (2L/c = {:.4}), energy ratio {:.5}, rebound {:.6}, last pressure {:.3e}",
        early.len(),
        plateau.len(),
        f.last_contact,
        f.duration,
        f.energy_ratio,
        f.rebound,
        f.history.last().unwrap().1
    );
    for (t, p) in early.iter().step_by(8) {
        eprintln!("  t = {t:.4}: p = {p:.6e}, exact {:.6e}", exact(*t));
    }
    assert!(worst < 0.01, "pressure history: {worst}");
    assert!((f.rebound / -v0 - 1.0).abs() < 0.015, "rebound velocity {}", f.rebound);
    assert!((mean - 1.0).abs() < 1e-3, "mean p / p_exact {mean}");
    assert!(f.last_contact < 3.0 - 4.0 * f.dt, "the bar is still on the spring at {}", f.last_contact);
    assert!(f.history.last().unwrap().1 == 0.0, "pressure at the end");
    assert!(!f.sign_changes, "the pressure changes sign during contact");
    assert!((f.energy_ratio - 1.0).abs() < 0.01, "energy ratio {}", f.energy_ratio);
}

/// The first test's bar (n = 42) with `method = "stabilised"` (velocity formulation): in
/// contact the stabilised law is the augmented Lagrangian with the penalty term κ_n d_n
/// added, which vanishes where the law holds (d_n = 0), so the answer is the augmented
/// Lagrangian's (docs/contact-algorithms.md, "Contact laws"). Reference: the first test's
/// run with the augmented Lagrangian; asserted: the same contact steps, the per-step
/// pressures within 1e-6 ρ c v₀ (measured 2.5e-13), the energy ratio within 1e-8, and
/// the first test's checks at n = 42 against the exact impact (duration within 2 Δt,
/// impulse-based pressure within 1%, rebound within 3%) and no penetration (≤ 1e-12 h).
#[test]
fn bar_against_a_rigid_wall_stabilised_law_matches_the_augmented_lagrangian() {
    let (v0, p_exact) = (0.01, 0.01);
    let al = impact(42, v0, "");
    let st = impact_with(42, v0, "", "method = \"stabilised\"", 2.6);
    let diff = al.history.iter().zip(&st.history).map(|(a, b)| (a.1 - b.1).abs()).fold(0.0, f64::max);
    eprintln!(
        "stabilised against augmented Lagrangian: largest pressure difference {:.3e} ρcv₀, contact until {} / {}, energy {} / {}",
        diff / p_exact,
        st.last_contact,
        al.last_contact,
        st.energy_ratio,
        al.energy_ratio
    );
    assert_eq!(al.history.len(), st.history.len());
    assert_eq!(st.last_contact, al.last_contact, "contact duration");
    assert!(diff <= 1e-6 * p_exact, "pressure histories differ by {diff}");
    assert!((st.energy_ratio - al.energy_ratio).abs() < 1e-8, "energy");
    assert!((st.last_contact - st.duration).abs() <= 2.0 * st.dt + 1e-12, "duration");
    assert!(!st.sign_changes, "the pressure changes sign during contact");
    assert!((st.p_mean / p_exact - 1.0).abs() < 0.01, "mean pressure {}", st.p_mean);
    assert!((st.rebound / -v0 - 1.0).abs() < 0.03, "rebound velocity {}", st.rebound);
    assert!(st.overlap <= 1e-12 * 1.05 / 42.0, "overlap {}", st.overlap);
}

/// The bar of the first test (n = 42: h = 0.025, Δt = h/(2c) = 0.0125, L = 1.05 − h/2)
/// against the lip-held wall through a damped asperity layer: augmented Lagrangian with
/// `initial_gap = a` and `[cracks.contact.asperity]` thickness a = 0.004, stiffness
/// κ = 2500 (stress/length²), damping c_n = 500 (stress·time/length²), on the displacement
/// gap (the default with a layer); t ∈ [0, 3]. The layer's traction is
/// κδ² + c_n δ δ̇ with δ = d_n + a its crush and δ̇ the normal relative velocity (the
/// scheme's velocity at the end of each step). The lips start a apart, so the layer is
/// unloaded at t = 0, and its crush stays below a (δ∞ = √(ρ c v₀/κ) = a/2): the hard
/// contact never closes.
/// Reference (exact 1D waves, as for the penalty spring above): until the wave reflected at
/// the free end returns (t < 2L/c) the bar's end is a dashpot of impedance ρc, so
/// p = ρc (v₀ − δ̇) = κδ² + c_n δ δ̇, i.e. δ̇ = (ρ c v₀ − κδ²)/(ρc + c_n δ), δ(0) = 0,
/// integrated here by RK4 (100 substeps per Δt). Measured: the pressure on the bar over
/// each step from its momentum, p = −(P_{k+1} − P_k)/(Δt h) (average acceleration: the mean
/// of the contact forces at the step's two ends), against the mean of the reference at the
/// two ends. Asserted over the steps ending at t ≤ 0.9 · 2L/c (the discrete reflected wave
/// arrives a little early, as for the penalty spring): the largest difference within 1.5% of
/// ρ c v₀ for the damped layer (measured: see the output) and for the same layer
/// without damping against its own reference (c_n = 0); the damped and undamped
/// references differ by more than 10% of ρ c v₀ somewhere in that window, so the damping
/// is measured (a damping on the change of d_n over a step instead of the velocity, as in
/// statics, would be Δt = 0.0125 times too weak here). Also: the bar leaves the layer
/// before t = 3 and, with damping, ends with less kinetic + strain energy than at t = 0,
/// the loss being the contact forces' work (`contact_work`, which holds the layer's
/// dissipation; kinetic + strain + contact work at the end within 1e-9 of the initial
/// energy, the energy balance of average acceleration); without damping the layer is
/// elastic and the energy after release is the initial one within 1%.
#[test]
fn bar_against_a_wall_through_a_damped_asperity_layer_follows_the_wave_solution() {
    let (v0, rho_c, kappa, a) = (0.01, 1.0, 2500.0, 0.004);
    let mut refs = vec![];
    for c_n in [500.0, 0.0] {
        let keys = format!(
            "initial_gap = {a}\n[cracks.contact.asperity]\nthickness = {a}\nstiffness = {kappa}\ndamping = {c_n}"
        );
        let f = impact_with(42, v0, "", &keys, 3.0);
        let h = 1.05 / 42.0;
        // The reference δ(t), p(t) at the step times.
        let rate = |d: f64| (rho_c * v0 - kappa * d * d) / (rho_c + c_n * d);
        let sub = 100;
        let hs = f.dt / sub as f64;
        let mut delta = 0.0;
        let mut p_ref = vec![0.0];
        for _ in 1..f.momentum.len() {
            for _ in 0..sub {
                let k1 = rate(delta);
                let k2 = rate(delta + 0.5 * hs * k1);
                let k3 = rate(delta + 0.5 * hs * k2);
                let k4 = rate(delta + hs * k3);
                delta += hs * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
            }
            p_ref.push(kappa * delta * delta + c_n * delta * rate(delta));
        }
        let mut worst: f64 = 0.0;
        let mut steps = 0;
        for k in 0..f.momentum.len() - 1 {
            let (t1, p1) = (f.momentum[k + 1].0, f.momentum[k + 1].1);
            if t1 > 0.9 * f.duration {
                break;
            }
            let p = -(p1 - f.momentum[k].1) / (f.dt * h);
            let exact = 0.5 * (p_ref[k] + p_ref[k + 1]);
            worst = worst.max((p - exact).abs() / (rho_c * v0));
            steps += 1;
            if k % 16 == 0 {
                eprintln!("  c_n = {c_n}: t = {t1:.4}: p = {p:.6e}, exact {exact:.6e}");
            }
        }
        let released = f.layer_history.iter().rev().find(|r| r.1 > 0.0).map_or(0.0, |r| r.0);
        eprintln!(
            "asperity layer c_n = {c_n}: largest |p − p_exact| / ρcv₀ {worst:.4} over {steps} steps, last step in the layer {released:.4} \
             (2L/c = {:.4}), kinetic + strain at the end / t = 0 {:.6}, (kinetic + strain + contact work) / E0 − 1 = {:.2e}, \
             rebound {:.6}",
            f.duration,
            f.energy_ratio,
            f.balance_end - 1.0,
            f.rebound
        );
        assert!(worst < 0.015, "c_n = {c_n}: pressure history {worst}");
        assert!(released < 3.0 - 4.0 * f.dt, "c_n = {c_n}: still in the layer at {released}");
        assert!((f.balance_end - 1.0).abs() < 1e-9, "c_n = {c_n}: energy balance {}", f.balance_end);
        if c_n > 0.0 {
            assert!(f.energy_ratio < 0.99, "c_n = {c_n}: no energy dissipated ({})", f.energy_ratio);
        } else {
            assert!((f.energy_ratio - 1.0).abs() < 0.01, "elastic layer: energy ratio {}", f.energy_ratio);
        }
        refs.push(p_ref);
    }
    let apart = refs[0].iter().zip(&refs[1]).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / (rho_c * v0);
    eprintln!("damped and undamped references differ by up to {apart:.4} ρcv₀");
    assert!(apart > 0.1, "the damping is not measured: {apart}");
}

/// Issue 15 item 6, first bullet, every tolerance at once: the first test's bar at n = 21
/// (h = 0.05, Δt = h/(2c) = 0.025, t ∈ [0, 2.6]; geometry, material, loads and the exact
/// 1D reference of Doyen, Ern & Piperno in the header) with the redistributed mass
/// (`[dynamics] mass = "redistributed"`: the mass redistribution method of Khenous,
/// Laborde & Renard, Eur. J. Mech. A/Solids 27 (2008) 918–932, the lips' Heaviside dofs
/// without mass, `physics::inertia`), velocity formulation, Newmark average acceleration,
/// the position correction on (the default).
/// Asserted together (the tolerances): the last contact step within 2 Δt of 2L/c
/// (measured one step early: 2.025 against 2.05), the impulse-based mean pressure within
/// 1% of ρ c v₀ (measured −0.354%), the rebound velocity within 1% of −v₀ (measured
/// −0.709%), kinetic + strain energy after the impact within 1% of before (measured
/// 0.99748), no penetration beyond round-off at any step (largest overlap ≤ 1e-12 h;
/// measured 2.3e-17 h); also contact in one interval without an open step, no sign change
/// of the pressure, kinetic + strain + contact work constant to 1e-9.
/// The same bar with the consistent mass (the first test) misses two of them here (3 steps
/// early, rebound −3.17%: asserted beyond 1%, the redistribution is what makes the
/// difference). Without the position correction the figures are the same (the velocity law
/// decides them) but the lips overlap by ½ Δt v₀ (asserted to 1e-9 relative).
/// With the displacement formulation (the gap law at every step, Khenous et al.'s setting)
/// the redistributed mass removes the chatter of the consistent one (there: 56 open steps,
/// energy ×13.5): asserted with the same five tolerances (measured: 2 steps early, −0.216%,
/// −0.432%, energy 1.00395, overlap 8e-19 h).
/// Not every mesh meets the 1% on the rebound (docs/contact-algorithms.md, "Mass
/// redistribution": n = 11 … 23 and from n = 81 on do, n = 25 … 79 miss it by up to 0.62%;
/// at n = 42 −1.54%), so at n = 42 the other four and a rebound within 2% are asserted.
#[test]
fn bar_against_a_rigid_wall_redistributed_mass_meets_every_impact_tolerance_at_n_21() {
    let (v0, p_exact) = (0.01, 0.01);
    let all_five = |f: &common::dynamics::BarFigures, n: usize, rebound_tol: f64, what: &str| {
        let h = 1.05 / n as f64;
        eprintln!(
            "{what}, n = {n}: contact until {:.4} (2L/c = {:.4}, {:.1} steps early), open steps inside {}, mean pressure \
             {:+.3}%, rebound {:+.3}%, energy ratio {:.5}, largest overlap {:.2e} h, balance {:.1e}",
            f.last_contact,
            f.duration,
            (f.duration - f.last_contact) / f.dt,
            f.open_inside,
            100.0 * (f.p_mean / p_exact - 1.0),
            100.0 * (f.rebound / -v0 - 1.0),
            f.energy_ratio,
            f.overlap / h,
            f.balance_end - 1.0
        );
        assert!((f.last_contact - f.duration).abs() <= 2.0 * f.dt + 1e-12, "{what}: duration {}", f.last_contact);
        assert!((f.p_mean / p_exact - 1.0).abs() < 0.01, "{what}: mean pressure {}", f.p_mean);
        assert!((f.rebound / -v0 - 1.0).abs() < rebound_tol, "{what}: rebound velocity {}", f.rebound);
        assert!((f.energy_ratio - 1.0).abs() < 0.01, "{what}: energy ratio {}", f.energy_ratio);
        assert!(f.overlap <= 1e-12 * h, "{what}: overlap {}", f.overlap);
        assert_eq!(f.open_inside, 0, "{what}: contact is not one interval");
        assert!(!f.sign_changes, "{what}: the pressure changes sign during contact");
        assert!((f.balance_end - 1.0).abs() < 1e-9, "{what}: total energy {}", f.balance_end);
    };
    let red = "mass = \"redistributed\"";
    let f = impact(21, v0, red);
    all_five(&f, 21, 0.01, "redistributed mass, velocity formulation");
    let consistent = impact(21, v0, "");
    assert!((consistent.rebound / -v0 - 1.0).abs() > 0.01, "the consistent mass meets the rebound too");
    let off = impact(21, v0, &format!("{red}\nposition_correction = false"));
    assert!((off.overlap / (0.5 * off.dt * v0) - 1.0).abs() < 1e-9, "overlap without the correction {}", off.overlap);
    assert_eq!(off.last_contact, f.last_contact, "the correction changes the contact duration");
    assert!((off.rebound / f.rebound - 1.0).abs() < 1e-3, "the correction changes the rebound");
    let disp = impact_with(21, v0, red, "formulation = \"displacement\"", 2.6);
    all_five(&disp, 21, 0.01, "redistributed mass, displacement formulation");
    let f42 = impact(42, v0, red);
    all_five(&f42, 42, 0.02, "redistributed mass, velocity formulation");
}

/// Issue 15 item 6, first bullet, every tolerance at once at n = 42 (h = 0.025): the bar of
/// the first test (geometry, material, loads, the exact 1D reference of Doyen, Ern &
/// Piperno in the header) with the redistributed mass (Khenous, Laborde & Renard 2008) and
/// Δt = h/(√2 c), velocity formulation, Newmark average acceleration, position correction
/// on, t ∈ [0, 2.6]. Courant 1/√2 is where the leading phase errors of the consistent mass
/// of linear elements (ω_h = c k (1 + (kh)²/24 + …), waves too fast) and of the
/// trapezoidal rule (Ω = ω (1 − (ω Δt)²/12 + …), too slow) cancel: (kh)²/24 = (c k Δt)²/12
/// (docs/contact-algorithms.md, "Mass redistribution"); at Courant ½ the discrete
/// reflected wave arrives with a dispersive train whose tensile part the unilateral law
/// cuts off, the impulse deficit behind the rebound's error.
/// Asserted together: the last contact step within 2 Δt of 2L/c (measured 0.62 Δt after
/// it: 2L/c is not a multiple of Δt), the impulse-based mean pressure within 1% of ρ c v₀
/// (measured −0.357%), the rebound within 1% of −v₀ (measured −0.715%), kinetic + strain
/// energy after within 1% of before (measured 0.99676), no penetration beyond round-off
/// (overlap ≤ 1e-12 h; measured below 1e-16 h), one contact interval, no sign change, the total
/// energy constant to 1e-9; and the same five at n = 84 (measured +0.83 steps, −0.230%,
/// −0.460%, 0.99807). Measured for comparison at this Courant number: the consistent mass
/// gives −0.500% / −1.000% / 0.99316 at n = 42 (the rebound on the tolerance), the
/// displacement formulation with the redistributed mass −0.342% / −0.684% / 1.00030.
#[test]
fn bar_against_a_rigid_wall_redistributed_mass_at_courant_one_over_root_two_meets_every_tolerance_at_n_42() {
    let (v0, p_exact) = (0.01, 0.01);
    for n in [42, 84] {
        let h = 1.05 / n as f64;
        let f = impact_at(n, v0, "mass = \"redistributed\"", "", 2.6, std::f64::consts::FRAC_1_SQRT_2);
        eprintln!(
            "Courant 1/√2, redistributed mass, n = {n}: contact until {:.4} (2L/c = {:.4}, {:+.2} steps), open steps \
             inside {}, mean pressure {:+.3}%, rebound {:+.3}%, energy ratio {:.5}, largest overlap {:.2e} h",
            f.last_contact,
            f.duration,
            (f.last_contact - f.duration) / f.dt,
            f.open_inside,
            100.0 * (f.p_mean / p_exact - 1.0),
            100.0 * (f.rebound / -v0 - 1.0),
            f.energy_ratio,
            f.overlap / h
        );
        assert!((f.last_contact - f.duration).abs() <= 2.0 * f.dt + 1e-12, "n = {n}: duration {}", f.last_contact);
        assert!((f.p_mean / p_exact - 1.0).abs() < 0.01, "n = {n}: mean pressure {}", f.p_mean);
        assert!((f.rebound / -v0 - 1.0).abs() < 0.01, "n = {n}: rebound velocity {}", f.rebound);
        assert!((f.energy_ratio - 1.0).abs() < 0.01, "n = {n}: energy ratio {}", f.energy_ratio);
        assert!(f.overlap <= 1e-12 * h, "n = {n}: overlap {}", f.overlap);
        assert_eq!(f.open_inside, 0, "n = {n}: contact is not one interval");
        assert!(!f.sign_changes, "n = {n}: the pressure changes sign during contact");
        assert!((f.balance_end - 1.0).abs() < 1e-9, "n = {n}: total energy {}", f.balance_end);
    }
}
