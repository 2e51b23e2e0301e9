//! Large sliding along a through interface and along a crack (formulation §7): the pairing
//! of the `−` lip with the `+` lip in the deformed configuration, the geometry loop, and
//! the force balance of Coulomb sliding.
//!
//! Blocks (2D tests): the rectangle [0, 6] × [−0.5, 0.5] (quad4, 120 × 21 cells, h = 0.05
//! along the interface) is cut by the through interface y = 0 (a `line` crack, in the
//! middle of a cell row): two blocks of height 0.5. E = 1, ν = 0 (so that pressing gives a uniform state, without Poisson
//! coupling), plane strain. Bottom edge clamped. Contact on the interface with large
//! sliding, vertex integration (the contact points are the multiplier nodes).
//!
//! Reference values are exact statics: while every contact point slides, the tangential
//! force is μ times the normal force (Coulomb), and away from the block ends a pressed
//! block carries the applied pressure uniformly.

mod common;
use common::contact::{solve_contact_text, ContactRun, PointRecord};
use fissure::contact::law::Status;

/// The two blocks with the top edge driven by `top` (TOML lines for the top edge).
fn blocks(mu: f64, top: &str, steps: usize) -> String {
    let factors: Vec<String> = (0..=steps).map(|k| format!("{k}")).collect();
    format!(
        r#"
[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.5]
upper = [6.0, 0.5]
divisions = [120, 21]

[[materials]]
E = 1.0
nu = 0.0

[[dirichlet]]
group = "bottom"
components = ["x", "y"]

{top}

[steps]
factors = [{factors}]

[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[cracks.contact]
friction = {mu}
sliding = "large"
integration = "vertex"
"#,
        factors = factors.join(", ")
    )
}

/// The mean gap of every multiplier packet whose points are all in contact, weighted by the
/// multiplier's basis function: g_j = Σ w c_j d_n / Σ w c_j (the quantity the contact law
/// sets to zero; between the packets the master lip is not matched node to node).
fn packet_gaps(points: &[PointRecord]) -> Vec<f64> {
    let n = points.iter().flat_map(|p| p.terms.iter().map(|t| t.0 as usize + 1)).max().unwrap_or(0);
    let mut num = vec![0.0; n];
    let mut den = vec![0.0; n];
    let mut all_in = vec![true; n];
    for p in points {
        for &(j, c) in &p.terms {
            let j = j as usize;
            if p.status == Status::Open {
                all_in[j] = false;
            }
            num[j] += p.weight * c * p.d_n;
            den[j] += p.weight * c;
        }
    }
    (0..n).filter(|&j| all_in[j] && den[j] > 0.0).map(|j| num[j] / den[j]).collect()
}

/// Whether a point is at least two block heights (1.0) from both ends of the contact zone
/// [0.03 k, 6] of step k.
fn away_from_ends(p: &PointRecord, k: usize) -> bool {
    p.x[0] >= 0.03 * k as f64 + 1.0 && p.x[0] <= 5.0
}

/// Step k's top-edge reaction.
fn top_reaction(run: &ContactRun, k: usize) -> [f64; 3] {
    // Dirichlet groups in case order: bottom, top.
    run.steps[k].reactions[1]
}

/// Block pressed by a rigid platen (top edge: u_y = −0.002), then the platen slides by
/// 0.03 per step for 10 steps (0.3 = 6 element lengths), μ = 0.5.
/// Reference: while sliding, |R_x| = μ |R_y| on the platen (Coulomb; within 1%); the
/// weighted gap of every fully active multiplier packet is below 1e-8 h (the
/// augmented-Lagrangian law is exact, not a penalty); at least two block heights from the
/// ends of the contact zone the pressure is uniform within 1%.
/// Measured: |R_x|/|R_y| = 0.50000 at every step, packet gaps ≤ 4e-19, pressure spread
/// ≤ 0.32%. (The pointwise gap between the multiplier nodes is not zero: the master lip's
/// nodes do not face the slave's once it has slid; it is ~1e-6 at the zone ends.)
#[test]
fn sliding_block_mu05_tangential_force_is_mu_times_normal_within_1pct() {
    let top = r#"[[dirichlet]]
group = "top"
components = ["x", "y"]
values = ["0.03 * t", "-0.002 + 0 * t"]"#;
    let run = solve_contact_text(&blocks(0.5, top, 10)).expect("solves");
    let h = 0.05;
    let mut worst_ratio = 0.0f64;
    for k in 1..run.steps.len() {
        let r = top_reaction(&run, k);
        let ratio = r[0].abs() / r[1].abs();
        worst_ratio = worst_ratio.max((ratio / 0.5 - 1.0).abs());
        let pts = &run.history[k];
        let gaps = packet_gaps(pts);
        let gmax = gaps.iter().fold(0.0f64, |a, g| a.max(g.abs()));
        assert!(gmax < 1e-8 * h, "step {k}: packet gap {gmax:e}");
        let mid: Vec<f64> = pts.iter().filter(|p| away_from_ends(p, k) && p.paired).map(|p| -p.lambda).collect();
        let mean = mid.iter().sum::<f64>() / mid.len() as f64;
        let spread = mid.iter().fold(0.0f64, |a, p| a.max((p / mean - 1.0).abs()));
        assert!(spread < 0.01, "step {k}: pressure spread {spread}");
        let slide = run.steps[k].contact.as_ref().unwrap();
        assert!(slide.stick <= 4, "step {k}: {} points stick", slide.stick);
        println!("step {k}: R = {r:?}, |Rx|/|Ry| = {ratio:.5}, packet gap {gmax:.1e}, pressure spread {spread:.2e}");
    }
    assert!(worst_ratio < 0.01, "tangential / normal force off μ by {worst_ratio}");
    // The slide really is large: the last step has unpaired points (slid off the master lip).
    let last = run.steps.last().unwrap().contact.as_ref().unwrap();
    let pairing = last.pairing.expect("large sliding reports its pairing");
    assert!(pairing.outside + pairing.far >= 10, "{pairing:?}");
    assert!(last.geometry >= 2 && last.geometry <= 10, "geometry iterations {}", last.geometry);
}

/// Block pressed by a uniform traction p = 0.001 on the part of its top edge that stays
/// above the lower block (reference x < 6 − 0.03 t, so that the load does not overhang) and
/// moved along by u_x = 0.03 t (6 element lengths over 10 steps), μ = 0. Reference: the
/// contact pressure equals p at every step within 1%, at least two block heights from the
/// ends of the contact zone, and the tangential reaction is zero. Measured: worst 0.55%.
#[test]
fn sliding_block_frictionless_pressure_equals_applied_pressure_every_step() {
    let top = r#"[[dirichlet]]
group = "top"
components = ["x"]
value = "0.03 * t"

[[traction]]
group = "top"
value = [0.0, "-0.0005 * (1 + signum(5.99999 - 0.03 * t - x))"]"#;
    let run = solve_contact_text(&blocks(0.0, top, 10)).expect("solves");
    for k in 0..run.steps.len() {
        let mid: Vec<f64> =
            run.history[k].iter().filter(|p| away_from_ends(p, k) && p.paired).map(|p| -p.lambda).collect();
        let worst = mid.iter().fold(0.0f64, |a, p| a.max((p / 0.001 - 1.0).abs()));
        println!("step {k}: {} points, worst pressure error {worst:.2e}", mid.len());
        assert!(worst < 0.01, "step {k}: pressure off by {worst}");
        let rx = top_reaction(&run, k)[0];
        assert!(rx.abs() < 1e-9, "step {k}: tangential reaction {rx}");
    }
}
