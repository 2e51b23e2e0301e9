//! Impact with contact in dynamics: two identical blocks meeting across an X-FEM
//! interface, velocity formulation (Signorini–Moreau, seed eq. 7), Newmark average
//! acceleration; in 2D (below) and in 3D (hex8, `two_blocks_impact_across_an_xfem_interface_3d_hex8`).
//!
//! Geometry: a strip [0, 2.05] × [0, 0.05], quad4 NX × 1 (h = 2.05/NX), cut by a line
//! interface at x = 1.025 (mid-cell for odd NX): two blocks of length L = 1.025, no
//! supports.
//! Material: E = 1, ν = 0, ρ = 1, plane stress (1D waves, c = √(E/ρ) = 1). Initial
//! velocity ±v₀ towards each other, v₀ = 0.01 (projected with the enriched mass, the jump
//! held exactly); frictionless contact on the interface, lips touching at t = 0.
//! Reference (exact 1D solution, the same as a bar of length L against a rigid wall):
//! contact pressure ρ c v₀ = 0.01 for t ∈ (0, 2L/c = 2.05), then each block leaves with
//! its velocity reversed, −v₀ for the left one; the energy is kept.
//! Δt = h/(2c), t ∈ [0, 3].
//! The velocity law alone leaves the lips overlapping by ½ Δt ⟦v⟧ from the impact step on
//! (Newmark: u_{n+1} = u_n + Δt (v_n + v_{n+1})/2 with ⟦v_{n+1}⟧ = 0); the position
//! correction (`solve::position_correction`, the default) projects the displacements back
//! onto d_n ≥ 0 after that step, velocities kept.
//! Tolerances (issue 15 item 6), asserted at NX = 83 (h = 0.0247, Δt = 0.01235) in 2D and
//! 3D: no penetration beyond round-off at any step (largest overlap ≤ 1e-12 h; measured
//! ~1e-18); the last contact step within 2 Δt of 2L/c (measured 2.0377, one step early);
//! at most one open step inside the contact interval; the impulse Σ p_k Δt / (2L/c) within
//! 1% of ρ c v₀ (measured −0.94%) and the mean of the per-step pressures within 2%
//! (measured +0.26%: average acceleration makes the pressure alternate between steps about
//! its mean), and the pressure never changes sign during contact; rebound velocity (the
//! left block's momentum / its mass) within 3% of −v₀ (measured −1.89%; the issue's 1% is
//! reached by refinement, the third test: the contact ends early and the rebound error is
//! twice the impulse error, a discretisation effect); kinetic + strain energy after the
//! impact within 1% of before (measured 0.9908). At h = 0.05 (NX = 41) the contact ends 3
//! steps before 2L/c (the lips open at t = 2.0), impulse −1.58%, rebound −3.17%, energy
//! 0.99002; without the correction the lips, still overlapping by ½ Δt · 2v₀ when they open,
//! touch again at t = 2.025 (one more contact step: impulse −1.06%, rebound −2.11%, the
//! figures these tests asserted at h = 0.05 before the correction).

mod common;

use fissure::solve::dynamics::{project_field, solve_time_steps, InitialState};
use fissure::solve::observe::Silent;
use fissure::solve::report::SolveOptions;

const CASE: &str = r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.05, 0.05]
divisions = [NX, 1]

[[materials]]
E = 1.0
nu = 0.0
density = 1.0

[[cracks]]
name = "interface"
shape = "line"
point = [1.025, 0.0]
normal = [1.0, 0.0]

[cracks.contact]
friction = 0.0

[dynamics]
dt = DT
end_time = 3.0
"#;

/// The same blocks in 3D: the box [0, 2.05] × [0, 0.05] × [0, 0.05], hex8 NX × 1 × 1, cut by
/// the plane interface x = 1.025 (ν = 0: c = √(E/ρ) = 1 as in 2D).
const CASE_3D: &str = r#"[mesh]
generator = "box"
cell = "hex8"
upper = [2.05, 0.05, 0.05]
divisions = [NX, 1, 1]

[[materials]]
E = 1.0
nu = 0.0
density = 1.0

[[cracks]]
name = "interface"
shape = "plane"
point = [1.025, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]

[cracks.contact]
friction = 0.0

[dynamics]
dt = DT
end_time = 3.0
"#;

/// The mesh of the asserted impact (h = 0.0247) and its time step Δt = h/(2c).
const NX: usize = 83;

fn dt_of(nx: usize) -> f64 {
    2.05 / nx as f64 / 2.0
}

#[test]
fn two_blocks_impact_across_an_xfem_interface_velocity_formulation() {
    let f = two_blocks(CASE, NX, dt_of(NX), true);
    eprintln!("{NX} cells: {f:?}");
}

/// The impact of the first test in 3D (issue 15 item 6, "2D and 3D"): the blocks on hex8
/// 83 × 1 × 1 (h = 0.0247), the plane interface x = 1.025, the same material, velocities,
/// Δt = h/(2c) and end time; reference: the same exact 1D solution (pressure ρ c v₀ = 0.01
/// for 2L/c = 2.05, velocities exchanged, energy kept). Asserted with the 2D test's
/// tolerances (the header: no penetration beyond round-off at any step, with the position
/// correction). Measured: the 2D figures (contact until 2.0377, mean of the per-step
/// pressures +0.26%, impulse −0.94%, rebound −1.89%, energy 0.9908): with ν = 0 and one
/// cell across, the hex8 blocks are the quad4 blocks extruded, so the figures are also
/// asserted equal to the 2D run's to 1e-9 relative.
#[test]
fn two_blocks_impact_across_an_xfem_interface_3d_hex8() {
    let f = two_blocks(CASE_3D, NX, dt_of(NX), true);
    eprintln!("hex8 {NX} × 1 × 1: {f:?}");
    let g = two_blocks(CASE, NX, dt_of(NX), false);
    let pairs = [(f.0, g.0), (f.1, g.1), (f.2, g.2), (f.3, g.3), (f.4, g.4)];
    for (k, (a, b)) in pairs.into_iter().enumerate() {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "figure {k}: 3D {a} against 2D {b}");
    }
}

/// Refinement of the impact above (with the position correction): quad4 nx × 1 with
/// nx = 41, 83, 125, 167, 209 (h = 2.05/nx, the interface x = 1.025 in the middle of a
/// cell), Δt = h/(2c) (Courant 0.5 kept).
/// Measured (h = 0.05 / 0.0247 / 0.0164 / 0.0123 / 0.0098): last contact step 1.975 /
/// 2.0377 / 2.0418 / 2.0316 / 2.0353 (2L/c = 2.05); impulse Σ p_k Δt over the contact
/// steps / (2L/c) −1.58% / −0.94% / −0.74% / −0.54% / −0.47%; rebound velocity (the left
/// block's momentum / mass after the impact) −3.17% / −1.89% / −1.48% / −1.08% / −0.93%;
/// kinetic + strain energy after / before 0.9900 / 0.9908 / 0.9954 / 0.9971 / 0.9976.
/// The impulse and the rebound errors are one discretisation effect: the contact ends one
/// step early (the discrete wave front is smeared over a few cells), the momentum change
/// is the impulse (rebound error ≈ twice the impulse error), and what is missing of the
/// rebound stays in the blocks as vibration. Asserted: the issue's 1% on the
/// impulse-based mean pressure from h = 0.0247 on and on the rebound velocity at
/// h = 0.0098, and that both errors decrease at every refinement.
#[test]
fn two_blocks_impact_refined_pressure_and_rebound_within_one_percent() {
    let (v0, p_exact) = (0.01, 0.01);
    let runs: Vec<(usize, Figures)> =
        [41, 83, 125, 167, 209].into_iter().map(|nx| (nx, two_blocks(CASE, nx, dt_of(nx), false))).collect();
    for (nx, f) in &runs {
        eprintln!(
            "h = {:.4}: contact until {:.4}, mean over steps {:.6} ({:+.2}%), impulse / (2L/c) {:.6} ({:+.2}%), rebound {:.6} ({:+.2}%), energy {:.5}",
            2.05 / *nx as f64,
            f.0,
            f.1,
            100.0 * (f.1 / p_exact - 1.0),
            f.2,
            100.0 * (f.2 / p_exact - 1.0),
            f.3,
            100.0 * (f.3 / -v0 - 1.0),
            f.4
        );
    }
    let err_p = |f: &Figures| (f.2 / p_exact - 1.0).abs();
    let err_v = |f: &Figures| (f.3 / -v0 - 1.0).abs();
    for w in runs.windows(2) {
        assert!(err_p(&w[1].1) < err_p(&w[0].1), "the pressure error does not decrease");
        assert!(err_v(&w[1].1) < err_v(&w[0].1), "the rebound error does not decrease");
    }
    assert!(runs[1..].iter().all(|r| err_p(&r.1) < 0.01), "impulse-based mean pressure");
    assert!(err_v(&runs[4].1) < 0.01, "rebound velocity {}", runs[4].1 .3);
}

/// (last contact time, mean of the per-step pressures, impulse Σ p Δt over the contact
/// steps / (2L/c), rebound velocity, energy after / before, largest overlap of the lips
/// over the run).
type Figures = (f64, f64, f64, f64, f64, f64);

/// The impact on `template` (2D quad4 nx × 1 or 3D hex8 nx × 1 × 1) with time step dt,
/// with the assertions of the header when `asserts`.
fn two_blocks(template: &str, nx: usize, dt: f64, asserts: bool) -> Figures {
    let (v0, len, c, rho) = (0.01, 1.025, 1.0, 1.0);
    let text = template.replace("NX", &nx.to_string()).replace("DT", &dt.to_string());
    let (case, mesh) = common::dynamics::build(&text, "blocks.toml");
    let (model, contact) = common::dynamics::model_and_contact(&case, &mesh);
    let contact = contact.expect("contact");
    let scheme = case.dynamics.as_ref().unwrap().scheme;
    let options = SolveOptions {
        position_correction: case.dynamics.as_ref().unwrap().position_correction,
        mass: case.dynamics.as_ref().unwrap().mass,
        ..SolveOptions::default()
    };
    let field = |_c: usize, x: [f64; 3]| Some([if x[0] < 1.025 { v0 } else { -v0 }, 0.0, 0.0]);
    let v_init = project_field(&model, &field, &options).unwrap();
    let initial = InitialState { u: vec![], v: v_init };
    // The left block's momentum is bᵀ v with b_k = ∫ ρ ψ_k 1_left (the mass kernel's
    // projection load of the left block's indicator).
    let rho_v = vec![rho];
    let indicator = |_c: usize, x: [f64; 3]| Some([if x[0] < 1.025 { 1.0 } else { 0.0 }, 0.0, 0.0]);
    let b = common::dynamics::momentum_weights_of(&model, &rho_v, &indicator, options.mass);
    let dim = mesh.dim;
    let mass_left = rho * len * 0.05f64.powi(dim as i32 - 1);
    let left: Vec<(usize, f64)> = (0..mesh.n_nodes())
        .filter(|&n| mesh.nodes[n][0] <= 0.95 + 1e-9)
        .map(|n| (n, if mesh.nodes[n][0] == 0.0 || (mesh.nodes[n][0] - 0.95).abs() < 1e-9 { 0.5 } else { 1.0 }))
        .collect();
    let weight: f64 = left.iter().map(|l| l.1).sum();
    struct Row {
        t: f64,
        active: usize,
        lambda: f64,
        opening: f64,
        v_left: f64,
        momentum: f64,
        energy: f64,
    }
    let mut rows = vec![];
    solve_time_steps(&model, Some(&contact), &options, &scheme, &initial, &Silent, &mut |s| {
        let m = s.motion.as_ref().unwrap();
        let rep = s.report.contact.as_ref();
        let vals = fissure::contact::state::point_values(&model, &contact.points, None, s.contact_state, s.u);
        let opening = vals.iter().map(|p| p.jump[0]).fold(f64::INFINITY, f64::min);
        let v_left = left.iter().map(|&(n, w)| w * m.velocity[dim * n]).sum::<f64>() / weight;
        let momentum = b.iter().zip(m.velocity).map(|(b, v)| b * v).sum::<f64>();
        rows.push(Row {
            t: m.time,
            active: rep.map_or(0, |r| r.active),
            lambda: rep.map_or(0.0, |r| 0.5 * (r.lambda_min + r.lambda_max)),
            opening,
            v_left,
            momentum,
            energy: m.energies.kinetic + m.energies.strain,
        });
        Ok(())
    })
    .unwrap();
    let contact_rows: Vec<&Row> = rows.iter().skip(1).filter(|r| r.active > 0).collect();
    let last = contact_rows.last().unwrap().t;
    let duration = 2.0 * len / c;
    eprintln!("contact until t = {last} (2L/c = {duration})");
    let p_mean = -contact_rows.iter().map(|r| r.lambda).sum::<f64>() / contact_rows.len() as f64;
    let p_impulse = -contact_rows.iter().map(|r| r.lambda * dt).sum::<f64>() / duration;
    let end = rows.last().unwrap();
    let rebound = end.momentum / mass_left;
    let e0 = rows[0].energy;
    let worst = rows.iter().map(|r| -r.opening).fold(0.0, f64::max);
    let figures = (last, p_mean, p_impulse, rebound, end.energy / e0, worst);
    if !asserts {
        return figures;
    }
    assert!((last - duration).abs() <= 2.0 * dt + 1e-12, "contact ends at {last}, 2L/c = {duration}");
    // Contact is one interval: every step up to the last contact step is in contact.
    let open: Vec<f64> = rows.iter().skip(1).filter(|r| r.active == 0 && r.t < last).map(|r| r.t).collect();
    eprintln!("open steps inside the contact interval: {open:?}");
    assert!(open.len() <= 1, "contact is not one interval: open at {open:?}");
    let p_exact = rho * c * v0;
    eprintln!("mean pressure {p_mean:.6} against ρ c v0 = {p_exact}; impulse / (2L/c) {p_impulse:.6}");
    assert!((p_mean / p_exact - 1.0).abs() < 0.02, "mean pressure {p_mean}");
    assert!((p_impulse / p_exact - 1.0).abs() < 0.01, "impulse-based mean pressure {p_impulse}");
    assert!(contact_rows.iter().all(|r| r.lambda < 0.0), "the pressure changes sign during contact");
    eprintln!("rebound velocity {rebound:.6} against {} (nodal mean {:.6})", -v0, end.v_left);
    assert!((rows[0].momentum / mass_left / v0 - 1.0).abs() < 1e-12, "initial momentum");
    assert!((rebound / -v0 - 1.0).abs() < 0.03, "rebound velocity {rebound}");
    eprintln!("energy after {:.6e}, before {e0:.6e}", end.energy);
    assert!((end.energy / e0 - 1.0).abs() < 0.01, "energy {} against {e0}", end.energy);
    let h = 2.05 / nx as f64;
    eprintln!("largest overlap {worst:.3e} (1e-12 h = {:.1e}; ½ Δt ⟦v⟧ = {:.3e})", 1e-12 * h, 0.5 * dt * 2.0 * v0);
    assert!(worst <= 1e-12 * h, "overlap {worst} beyond round-off");
    figures
}

/// The contact tangent's factor is kept from one time step to the next (issue 15 item 8:
/// no refactorisation while the statuses do not change). The impact of the first test
/// (quad4 41 × 1, frictionless, velocity formulation, Δt = 0.025, 120 steps).
/// Derivation of the count: the effective matrix K + M/(β Δt²) and ρ_n are the same at
/// every step, and a frictionless point's tangent depends on its contact status only, so
/// a factor is computed when a Newton loop starts with a status set other than the one of
/// the factor the solver holds: at the first step (no factor yet), then once after each
/// active-set iteration that changed a status (without friction and without a 2-cycle,
/// every active-set iteration after a step's first follows exactly one change). Hence
/// Σ factorisations over the steps = 1 + Σ_k (active-set iterations of step k − 1), and a
/// step with one active-set iteration (no status change) factorises nothing and makes two
/// solves (the exact Newton step and the correction that confirms it). Before the factor
/// was carried, every step factorised (one per active-set iteration): 120 factorisations
/// at least. Also: the end-of-step contact sets change at most as often as that count
/// says, and the factor is computed at most 1 + 2 × (their changes) times here (each
/// change seen at a step's end took one active-set iteration, none took more).
/// The position correction (after the impact step only: the one step whose lips overlap)
/// solves on its own system K + ε M/(β Δt²), which it factorises at its first use: one
/// factorisation more per correction whose statuses differ from its carried factor's, here
/// exactly one, counted in the impact step's report. So Σ factorisations = 1 + Σ_k
/// (active-set iterations of step k − 1) + 1, with one corrected step.
#[test]
fn two_blocks_impact_refactorises_only_when_a_contact_status_changes() {
    let text = CASE.replace("NX", "41").replace("DT", "0.025");
    let (case, mesh) = common::dynamics::build(&text, "blocks.toml");
    let (model, contact) = common::dynamics::model_and_contact(&case, &mesh);
    let contact = contact.expect("contact");
    let scheme = case.dynamics.as_ref().unwrap().scheme;
    let options = SolveOptions::default();
    let v0 = 0.01;
    let field = |_c: usize, x: [f64; 3]| Some([if x[0] < 1.025 { v0 } else { -v0 }, 0.0, 0.0]);
    let v_init = project_field(&model, &field, &options).unwrap();
    let initial = InitialState { u: vec![], v: v_init };
    // Per step ≥ 1: (factorisations, linear solves, active-set iterations, contact set).
    let mut rows: Vec<(usize, usize, usize, Vec<bool>)> = vec![];
    let mut start: Vec<bool> = vec![];
    let mut corrected = vec![];
    solve_time_steps(&model, Some(&contact), &options, &scheme, &initial, &Silent, &mut |s| {
        let m = s.motion.as_ref().unwrap();
        if m.position_correction > 0.0 {
            corrected.push(s.report.index);
        }
        let set: Vec<bool> = s.contact_state.iter().map(|p| p.contact).collect();
        match s.report.contact.as_ref() {
            Some(rep) => rows.push((s.report.factorizations, s.report.linear_solves, rep.active_set, set)),
            None => start = set,
        }
        Ok(())
    })
    .unwrap();
    let factorisations: usize = rows.iter().map(|r| r.0).sum();
    let status_changes: usize = rows.iter().map(|r| r.2 - 1).sum();
    let mut previous = &start;
    let mut set_changes = 0;
    for r in &rows {
        set_changes += usize::from(&r.3 != previous);
        previous = &r.3;
    }
    let quiet: Vec<&(usize, usize, usize, Vec<bool>)> = rows.iter().skip(1).filter(|r| r.2 == 1).collect();
    eprintln!(
        "{} steps: {factorisations} factorisations, {status_changes} active-set iterations with a change, \
         {set_changes} changes of the end-of-step contact set, {} steps without a change",
        rows.len(),
        quiet.len()
    );
    eprintln!("position corrections after the steps {corrected:?}");
    assert_eq!(corrected, vec![1], "the correction runs after the impact step only");
    assert_eq!(factorisations, 2 + status_changes, "factorisations against 1 + status changes + 1 correction");
    assert!(set_changes <= status_changes, "{set_changes} set changes, {status_changes} status changes");
    assert!(factorisations <= 2 + 2 * set_changes, "{factorisations} factorisations, {set_changes} set changes");
    assert!(quiet.len() >= rows.len() / 2, "most steps change no status: {} of {}", quiet.len(), rows.len());
    for r in &quiet {
        assert_eq!((r.0, r.1), (0, 2), "a step without status change: (factorisations, solves)");
    }
}

/// The checksum that identifies the bulk matrix of a carried factor changes with any value
/// (a one-ulp change, a sign, two values swapped), so a changed ρ, Δt or scheme
/// coefficient (a changed effective matrix) drops the carried factor.
#[test]
fn carried_factor_checksum_changes_with_any_value_of_the_matrix() {
    use fissure::solve::setup::values_checksum;
    let k: Vec<f64> = (0..1000).map(|i| 1.0 + (i as f64 * 0.37).sin()).collect();
    let base = values_checksum(&k);
    assert_eq!(base, values_checksum(&k.clone()));
    let mut ulp = k.clone();
    ulp[500] = f64::from_bits(ulp[500].to_bits() + 1);
    let mut sign = k.clone();
    sign[3] = -sign[3];
    sign[7] = -sign[7];
    let mut swap = k.clone();
    swap.swap(10, 11);
    let scaled: Vec<f64> = k.iter().map(|x| x * (1.0 + 1e-15)).collect();
    for (what, v) in [("one ulp", &ulp), ("two signs", &sign), ("a swap", &swap), ("scaled", &scaled)] {
        assert_ne!(values_checksum(v), base, "{what}");
    }
}

/// Issue 15 item 6, second bullet, every tolerance at once: the two blocks of the first
/// test (geometry, material, ±v₀, the exact 1D reference in the header: Doyen, Ern &
/// Piperno, SIAM J. Sci. Comput. 33 (2011) 223–249) at NX = 41 (h = 0.05, Δt = h/(2c) =
/// 0.025), in 2D (quad4 41 × 1) and 3D (hex8 41 × 1 × 1), with the redistributed mass
/// (`[dynamics] mass = "redistributed"`: Khenous, Laborde & Renard, Eur. J. Mech.
/// A/Solids 27 (2008) 918–932; the Heaviside dofs of the cut cells carry no mass),
/// velocity formulation, Newmark average acceleration, the position correction on.
/// Asserted in 2D and 3D (the header's checks, then the issue's tolerances): the last
/// contact step within 2 Δt of 2L/c (measured 2.025 against 2.05, one step early), the
/// impulse-based mean pressure within 1% of ρ c v₀ (measured −0.354%), the rebound
/// velocity within 1% of −v₀ (measured −0.709%), kinetic + strain energy after the impact
/// within 1% of before (measured 0.99748), no penetration beyond round-off (largest
/// overlap ≤ 1e-12 h; measured 2e-18 h in 2D, 1e-17 h in 3D); 3D equal to 2D to 1e-9
/// relative (ν = 0, one cell across). The consistent mass at this mesh ends the contact
/// 3 steps early with the rebound −3.17% (asserted beyond 1% here). At NX = 83 the
/// redistributed mass gives −0.768% / −1.537% / 0.99747 (impulse / rebound / energy, one
/// step early): the rebound misses 1% there (docs/contact-algorithms.md, "Mass
/// redistribution").
#[test]
fn two_blocks_impact_redistributed_mass_meets_every_tolerance_2d_and_3d_at_h_0_05() {
    let (v0, p_exact, nx) = (0.01, 0.01, 41);
    let red = |t: &str| t.replace("end_time = 3.0", "end_time = 3.0\nmass = \"redistributed\"");
    let dt = dt_of(nx);
    let f2 = two_blocks(&red(CASE), nx, dt, true);
    let f3 = two_blocks(&red(CASE_3D), nx, dt, true);
    for (what, f) in [("2D", f2), ("3D", f3)] {
        eprintln!(
            "{what}, redistributed mass, NX = {nx}: contact until {:.4} ({:.1} steps early), impulse {:+.3}%, rebound \
             {:+.3}%, energy {:.5}, largest overlap {:.2e} h",
            f.0,
            (2.05 - f.0) / dt,
            100.0 * (f.2 / p_exact - 1.0),
            100.0 * (f.3 / -v0 - 1.0),
            f.4,
            f.5 / (2.05 / nx as f64)
        );
    }
    assert_every_impact_tolerance(f2, f3, nx, dt);
    let consistent = two_blocks(CASE, nx, dt, false);
    assert!((consistent.3 / -v0 - 1.0).abs() > 0.01, "the consistent mass meets the rebound too");
}

/// Issue 15 item 6, second bullet, every tolerance at once at NX = 83 (h = 0.0247): the two
/// blocks of the first test (reference: the exact 1D impact of the header, Doyen, Ern &
/// Piperno) in 2D (quad4 83 × 1) and 3D (hex8 83 × 1 × 1) with the redistributed mass
/// (Khenous, Laborde & Renard 2008) and Δt = h/(√2 c) (Courant 1/√2, where the leading
/// phase errors of the consistent mass and of the trapezoidal rule cancel:
/// docs/contact-algorithms.md, "Mass redistribution"), velocity formulation, Newmark
/// average acceleration, the position correction on.
/// Asserted in 2D and 3D (the header's checks, then the issue's tolerances): the last
/// contact step within 2 Δt of 2L/c, the impulse-based mean pressure within 1% of ρ c v₀,
/// the rebound velocity within 1% of −v₀, kinetic + strain energy after within 1% of
/// before, no penetration beyond round-off (≤ 1e-12 h); 3D equal to 2D to 1e-9 relative.
/// Measured (2D and 3D alike): the last contact step 2.0608, 0.62 Δt after 2L/c (not a
/// multiple of Δt), impulse −0.357%, rebound −0.715%, energy 0.99676, largest overlap
/// 2.2e-16 h; the mean of the per-step pressures −0.881% (the header's 2% on it holds).
/// The bar against a rigid wall at n = 42 gives the same figures
/// (tests/dynamics_bar_rigid_wall.rs).
#[test]
fn two_blocks_impact_redistributed_mass_at_courant_one_over_root_two_meets_every_tolerance_2d_and_3d_at_h_0_025() {
    let (v0, p_exact, nx) = (0.01, 0.01, NX);
    let red = |t: &str| t.replace("end_time = 3.0", "end_time = 3.0\nmass = \"redistributed\"");
    let dt = 2.05 / nx as f64 * std::f64::consts::FRAC_1_SQRT_2;
    let f2 = two_blocks(&red(CASE), nx, dt, true);
    let f3 = two_blocks(&red(CASE_3D), nx, dt, true);
    for (what, f) in [("2D", f2), ("3D", f3)] {
        eprintln!(
            "{what}, redistributed mass, Courant 1/√2, NX = {nx}: contact until {:.4} ({:+.2} steps), mean over the steps \
             {:+.3}%, impulse {:+.3}%, rebound {:+.3}%, energy {:.5}, largest overlap {:.2e} h",
            f.0,
            (f.0 - 2.05) / dt,
            100.0 * (f.1 / p_exact - 1.0),
            100.0 * (f.2 / p_exact - 1.0),
            100.0 * (f.3 / -v0 - 1.0),
            f.4,
            f.5 / (2.05 / nx as f64)
        );
    }
    assert_every_impact_tolerance(f2, f3, nx, dt);
}

/// Issue 15's impact tolerances on the two blocks' figures (last contact step, mean of the
/// per-step pressures, impulse-based mean pressure, rebound, energy after / before,
/// largest overlap; `two_blocks`) in 2D and 3D (v₀ = ρ c v₀ = 0.01, 2L/c = 2.05): the last
/// contact step within 2 Δt of 2L/c, the impulse within 1% of ρ c v₀, the rebound within 1%
/// of −v₀, the energy within 1%, no overlap beyond 1e-12 h; and 3D equal to 2D to 1e-9.
fn assert_every_impact_tolerance(f2: Figures, f3: Figures, nx: usize, dt: f64) {
    let (v0, p_exact) = (0.01, 0.01);
    for (what, f) in [("2D", f2), ("3D", f3)] {
        assert!((f.0 - 2.05).abs() <= 2.0 * dt + 1e-12, "{what}: duration {}", f.0);
        assert!((f.2 / p_exact - 1.0).abs() < 0.01, "{what}: impulse-based mean pressure {}", f.2);
        assert!((f.3 / -v0 - 1.0).abs() < 0.01, "{what}: rebound {}", f.3);
        assert!((f.4 - 1.0).abs() < 0.01, "{what}: energy {}", f.4);
        assert!(f.5 <= 1e-12 * 2.05 / nx as f64, "{what}: overlap {}", f.5);
    }
    let pairs = [(f3.0, f2.0), (f3.1, f2.1), (f3.2, f2.2), (f3.3, f2.3), (f3.4, f2.4)];
    for (k, (a, b)) in pairs.into_iter().enumerate() {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "figure {k}: 3D {a} against 2D {b}");
    }
}
