//! A plane stress pulse meeting a closed frictionless crack normal to it (issue 15 item 6,
//! "wave through a closed crack"): a compressive pulse crosses with no reflection, a
//! tensile pulse opens the crack and is reflected. Velocity formulation (Signorini–Moreau,
//! seed eq. 7), Newmark average acceleration.
//!
//! Geometry: a strip [0, 3.25] × [0, 0.025], quad4 130 × 1 (h = 0.025), cut by a line
//! interface at x = 1.0125 (the middle of cell 40) normal to the strip; lips touching
//! (initial_gap 0), zero initial displacement and velocity, no supports.
//! Material: E = 1, ν = 0, ρ = 1, plane stress (1D waves, c = √(E/ρ) = 1).
//! Pulse: a traction along x on the end x = 0, ±σ₀ sin²(π t/T) for t ∈ [0, T], 0 after,
//! σ₀ = 0.01, T = 1 (40 cell transit times): `+` pushes (compressive pulse), `−` pulls
//! (tensile pulse). Δt = h/(2c) = 0.0125, t ∈ [0, 2.8]: the front reaches the far end
//! x = 3.25 after the window, so nothing comes back from it.
//! Monitors: the mean x velocity of the two nodes at x = 1.5 (beyond the crack; the pulse
//! crosses it for t ∈ [1.5, 2.5]) and at x = 0.25 (before it: the incident pulse for
//! t ∈ [0.25, 1.25], read over [0, 1.6]; a reflection from the crack for t ∈ [1.775,
//! 2.775], read over [1.65, 2.8]).
//! Reference (1D waves): the particle velocity of a plane pulse is σ/(ρc), amplitude
//! v₀ = σ₀/(ρc) = 0.01. A closed frictionless interface normal to the pulse transmits a
//! compressive pulse whole (the lips stay in contact and move together, under the pulse's
//! pressure, peak σ₀); a tensile one cannot cross it (the lips open: the `−` part ends at
//! a free face, which reflects the pulse whole and moves at twice the particle velocity
//! meanwhile, so the lips end apart by 2 ∫ σ/(ρc) dt = σ₀ T/(ρc) = 0.01; the `+` part
//! stays at rest).
//! Tolerances (issue 15 item 6), with the figures measured: compressive, the peak
//! transmitted velocity within 2% of the same strip without the crack (the same mesh and
//! Δt, so the same discrete dispersion; measured −0.12%) and of v₀ (−0.06%), any
//! reflection below 2% of v₀ (0.79%), the largest contact pressure within 2% of σ₀
//! (+1.1%); tensile, the peak transmitted velocity below 2% of v₀ (0.57%), the reflection's
//! peak within 2% of the incident one (+0.67%), the final opening within 2% of σ₀ T/(ρc)
//! (+0.05%).
//! What is left in the "transmitted" and "reflected" figures is the discrete dispersion of
//! average acceleration with the consistent mass: short waves run ahead of the front, a
//! ripple of alternating sign whose compressive lobes a closed crack passes on. With a
//! half-sine of T = 0.5 (a kink at t = 0) the ripple was 4.5% of v₀ and the tensile
//! pulse's "transmission" 4.6%; the smooth sin² pulse twice as long brings it below 1%.
//! Run with `cargo test --release --test dynamics_wave_through_crack -- --nocapture`
//! for the figures.

mod common;

use fissure::solve::dynamics::{solve_time_steps, InitialState};
use fissure::solve::observe::Silent;
use fissure::solve::report::SolveOptions;

const STRIP: &str = r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [3.25, 0.025]
divisions = [130, 1]

[[materials]]
E = 1.0
nu = 0.0
density = 1.0

[[traction]]
group = "left"
value = ["SIGN 0.01 * sin(PI * t / 1.0)^2 * (1 + signum(1.0 - t)) / 2", 0.0]

[dynamics]
dt = 0.0125
end_time = 2.8
"#;

const CRACK: &str = r#"
[[cracks]]
name = "interface"
shape = "line"
point = [1.0125, 0.0]
normal = [1.0, 0.0]

[cracks.contact]
friction = 0.0
formulation = "velocity"
"#;

/// The velocity histories at the monitors and the crack's behaviour.
struct Run {
    /// (time, mean x velocity at x = 0.5, mean x velocity at x = 1.5).
    rows: Vec<(f64, f64, f64)>,
    /// Steps with contact points active, most compressive λ, largest and smallest normal
    /// opening over the run (0 without a crack).
    active_steps: usize,
    lambda_min: f64,
    opening_max: f64,
    opening_min: f64,
}

fn run(compressive: bool, cracked: bool) -> Run {
    let mut text = STRIP.replace("SIGN ", if compressive { "" } else { "-" });
    if cracked {
        text.push_str(CRACK);
    }
    let (case, mesh) = common::dynamics::build(&text, "wave.toml");
    let (model, contact) = common::dynamics::model_and_contact(&case, &mesh);
    assert_eq!(contact.is_some(), cracked);
    let scheme = case.dynamics.as_ref().unwrap().scheme;
    let options = SolveOptions::default();
    let at = |x: f64| -> Vec<usize> { (0..mesh.n_nodes()).filter(|&n| (mesh.nodes[n][0] - x).abs() < 1e-9).collect() };
    let (before, after) = (at(0.25), at(1.5));
    assert_eq!((before.len(), after.len()), (2, 2));
    let mean = |nodes: &[usize], v: &[f64]| nodes.iter().map(|&n| v[2 * n]).sum::<f64>() / nodes.len() as f64;
    let mut out = Run { rows: vec![], active_steps: 0, lambda_min: 0.0, opening_max: 0.0, opening_min: 0.0 };
    solve_time_steps(&model, contact.as_ref(), &options, &scheme, &InitialState::default(), &Silent, &mut |s| {
        let m = s.motion.as_ref().unwrap();
        out.rows.push((m.time, mean(&before, m.velocity), mean(&after, m.velocity)));
        if let (Some(c), Some(rep)) = (contact.as_ref(), s.report.contact.as_ref()) {
            if rep.active > 0 {
                out.active_steps += 1;
                out.lambda_min = out.lambda_min.min(rep.lambda_min);
            }
            let vals = fissure::contact::state::point_values(&model, &c.points, None, s.contact_state, s.u);
            for p in &vals {
                out.opening_max = out.opening_max.max(p.jump[0]);
                out.opening_min = out.opening_min.min(p.jump[0]);
            }
        }
        Ok(())
    })
    .unwrap();
    out
}

/// Peak |v| at a monitor (column 1: x = 0.5, 2: x = 1.5) over t ∈ [from, to].
fn peak(r: &Run, column: usize, from: f64, to: f64) -> f64 {
    r.rows
        .iter()
        .filter(|w| w.0 >= from && w.0 <= to)
        .map(|w| if column == 1 { w.1 } else { w.2 }.abs())
        .fold(0.0, f64::max)
}

#[test]
fn compressive_pulse_crosses_a_closed_crack_without_reflection() {
    let v0 = 0.01;
    let plain = run(true, false);
    let cracked = run(true, true);
    let reference = peak(&plain, 2, 0.0, 2.8);
    let transmitted = peak(&cracked, 2, 0.0, 2.8);
    let incident = peak(&cracked, 1, 0.0, 1.6);
    let reflected = peak(&cracked, 1, 1.65, 2.8);
    eprintln!(
        "compressive: incident {incident:.6}, transmitted {transmitted:.6} (no crack {reference:.6}, v0 {v0}): \
         {:+.3}% of the strip without crack, {:+.3}% of v0; reflected {reflected:.3e} ({:.3}% of v0); \
         {} steps in contact, λ min {:.6}, opening in [{:.3e}, {:.3e}]",
        100.0 * (transmitted / reference - 1.0),
        100.0 * (transmitted / v0 - 1.0),
        100.0 * reflected / v0,
        cracked.active_steps,
        cracked.lambda_min,
        cracked.opening_min,
        cracked.opening_max
    );
    // The pulse pushes the lips together: contact carries it, at about σ₀.
    assert!(cracked.active_steps > 0, "the crack never closed under the compressive pulse");
    assert!((-cracked.lambda_min / 0.01 - 1.0).abs() < 0.02, "largest contact pressure {}", -cracked.lambda_min);
    assert!(
        (transmitted / reference - 1.0).abs() < 0.02,
        "transmitted {transmitted} against {reference} without crack"
    );
    assert!((transmitted / v0 - 1.0).abs() < 0.02, "transmitted {transmitted} against σ0/(ρc) = {v0}");
    assert!(reflected < 0.02 * v0, "reflection {reflected} from a closed crack");
}

#[test]
fn tensile_pulse_opens_a_closed_crack_and_is_reflected() {
    let v0 = 0.01;
    let cracked = run(false, true);
    let transmitted = peak(&cracked, 2, 0.0, 2.8);
    let incident = peak(&cracked, 1, 0.0, 1.6);
    let reflected = peak(&cracked, 1, 1.65, 2.8);
    eprintln!(
        "tensile: incident {incident:.6}, transmitted {transmitted:.3e} ({:.3}% of v0), reflected {reflected:.6} \
         ({:+.3}% of the incident); {} steps in contact, opening in [{:.3e}, {:.6e}]",
        100.0 * transmitted / v0,
        100.0 * (reflected / incident - 1.0),
        cracked.active_steps,
        cracked.opening_min,
        cracked.opening_max
    );
    // The free lip moves at twice the particle velocity while the pulse reflects: it ends
    // apart by 2 ∫ σ/(ρc) dt = σ₀ T/(ρc) = 0.01.
    let opening = v0 * 1.0;
    assert!(
        (cracked.opening_max / opening - 1.0).abs() < 0.02,
        "largest opening {} against {opening}",
        cracked.opening_max
    );
    assert!(transmitted < 0.02 * v0, "transmitted {transmitted} through an open crack");
    assert!((reflected / incident - 1.0).abs() < 0.02, "reflected {reflected} against the incident {incident}");
}
