//! Archard wear in 3D under large sliding (issue 14 on 3D lips and the 3D pairs of issue
//! 16): the `+` lip of a 3D interface and the master face of a 3D contact pair carry a
//! nodal wear field (`src/contact/lip_wear.rs`, `MasterWear::nodal`), the slave side's wear
//! moves with its points.
//!
//! (a) `interface_block_*`: a box [0, 2] × [−0.5, 0.5] × [0, 0.3], hex8 20 × 7 × 3
//! (h = 0.1 along x), cut by the flat X-FEM interface y = 0 (through (1, 0, 0.15), normal
//! exactly (0, 1, 0), inside a cell layer); `+` lip the upper block's (the master), `−` lip
//! the lower block's (the slave points); `sliding = "large"`, `vertex` integration; E = 1,
//! ν = 0; bottom clamped; top pressed by −0.002 n (p = E·0.002/1 = 0.002) at step 0, then
//! slid by 0.05 per step along x for 4 steps (0.2 = 2 cells); μ = 0.5. Wear k/H = 0.002,
//! split 0.3 on the `+` lip; both couplings.
//! Reference (Archard 1953 at constant pressure): in the window x ∈ [0.5, 1.5], where both
//! lips stay in contact all the time, each lip wears (k/H)·share·p̄·S, S the slip (measured,
//! 0.2 less the shear of the first sliding step) and p̄ the points' ⟨−λ⟩₊ averaged over the
//! window and the steps. Measured: the slave points' area mean 1.2e-5 from it and the + lip's
//! nodal field's 1.6e-4 (tolerance 1%), the + lip's over the slave's in the split's ratio to
//! 1.7e-4 (tolerance 0.5%); the pressure −λ from 1.0025p to 1.0105p at the last step, the
//! slave points' wear from 0.992 to 1.004 of the plateau. The + lip's nodal field (on the
//! mesh nodes of the cut cells, `MasterWear::cell_nodal`), averaged over strips 2h wide
//! along the slide, is uniform to 0.18% (tolerance 2%). The worn volume Σ A w⁻ (slave
//! points) + Σ_a A_a w⁺_a (the nodal field, A_a the lumped areas) equals (k/H)·W_f/μ (W_f
//! the friction work Σ A ∫μ|λ||dslip|) to 1e-6 (measured 7.8e-16: the shape-function
//! weights of a deposit sum to 1), and the + lip's share is `split` to 1e-6.
//! (The interface was tilted to the normal (−0.03, 1, −0.02) until the pairing of the slave
//! points on the lateral faces z = 0 and 0.3 was fixed (`contact::pairing::EDGE_REACH`):
//! with the normal along y the geometry loop did not settle. Tilted, the pressure ran from
//! 0.32p to 1.4p at the last step and the slave's mean wear was 4.1% low; not analysed
//! further (the tilt's lateral press, 4e-4 h, is above the former off-the-lip tolerance of
//! 1e-6 h, so one lateral face's points may have been off the lip).)
//!
//! (b) `pair_punch_*`: a short punch slid along a longer base through a 3D contact pair.
//! Base `base` = [0, 3] × [−0.2, 0] × [0, 0.4] (hex8 30 × 2 × 2, h = 0.1, E = 100, ν = 0,
//! bottom clamped); punch `punch` = [0, 0.6] × [0, 0.3] × [0, 0.4] (hex8 5 × 3 × 2,
//! h = 0.12: non-matching faces, E = 1, ν = 0), its top pressed by u_y = −0.003
//! (p ≈ 0.01) at step 0 then slid by 0.1 per step for 12 steps (D = 1.2); slave =
//! `punch.bottom`, master = `base.top`, μ = 0.3, `sliding = "large"`, `gauss`. Wear
//! k/H = 0.002, split 0.3 on the master face. Reference: a base point X wears
//! (k/H)·split·p·(the distance the punch slid while over it): a trapezoid in X, rising from
//! 0 at X = a₀ to the plateau (k/H)·split·p·L_p (L_p = 0.6) at a₀ + L_p, flat to a₀ + D,
//! back to 0 at a₀ + D + L_p (a₀ the punch's left end once pressed and sheared). The
//! punch's own face wears (k/H)(1 − split)·p·S. μ is small (0.05) and the punch thin so
//! that the friction's moment leaves the pressure nearly uniform (±7% measured); the
//! references take the run's own pressures. Checked: each punch point against its own
//! pressure history, (k/H)(1 − split)·Σ_k p_k Δs_k, to 1% (measured 2.3e-5); the base's
//! nodal depths against the steps' deposits (each step's (k/H)·split·p̄_k·Δs_k under the
//! punch's end position [a_k, a_k + L_p], averaged over each node's hat function, half-width
//! h = 0.1), within 6% of the plateau (measured 3.5%: the punch's pressure varies along it
//! and the slave points integrate each hat approximately); the plateau's mean within 2% of
//! (k/H)·split·p̄·L_p (measured +0.8%); the volume to 1e-6 (measured 2e-16); and the pair's
//! wear figures (summary.json `steps[].contact_pairs[].wear`) equal to the run's.
//!
//! (c) hostile: (a) in SI units (E = 2e11 Pa, k/H = 0.002/2e11 Pa⁻¹, so the depths are the
//! same) gives the same depths on both lips to 1e-6 of the largest depth.

mod common;
use common::contact::{solve_contact_text, ContactRun};

const K_OVER_H: f64 = 0.002;
const SPLIT: f64 = 0.3;
const MU_PUNCH: f64 = 0.05;

/// The interface's unit normal (along y) and the slide direction (x projected on the
/// interface).
fn frame() -> ([f64; 3], [f64; 3]) {
    let n0 = [0.0, 1.0, 0.0];
    let l: f64 = n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2];
    let n = [n0[0] / l.sqrt(), n0[1] / l.sqrt(), n0[2] / l.sqrt()];
    let t0 = [1.0 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]];
    let lt = (t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]).sqrt();
    (n, [t0[0] / lt, t0[1] / lt, t0[2] / lt])
}

fn interface_block(young: f64, coupling: &str) -> String {
    let (n, t) = frame();
    let values: Vec<String> = (0..3).map(|i| format!("\"{:.12} + {:.12} * t\"", -0.002 * n[i], 0.05 * t[i])).collect();
    format!(
        r#"[mesh]
generator = "box"
cell = "hex8"
lower = [0.0, -0.5, 0.0]
upper = [2.0, 0.5, 0.3]
divisions = [20, 7, 3]
[[materials]]
E = {young:e}
nu = 0.0
[[dirichlet]]
group = "bottom"
components = ["x", "y", "z"]
[[dirichlet]]
group = "top"
components = ["x", "y", "z"]
values = [{}]
[steps]
factors = [0, 1, 2, 3, 4]
[[cracks]]
name = "interface"
shape = "plane"
point = [1.0, 0.0, 0.15]
normal = [{}, {}, {}]
[cracks.contact]
friction = 0.5
sliding = "large"
integration = "vertex"
[cracks.contact.wear]
coefficient = {:e}
split = {SPLIT}
coupling = "{coupling}"
"#,
        values.join(", "),
        n[0],
        n[1],
        n[2],
        K_OVER_H / young
    )
}

/// (mean, (max − min)/mean) of the depths.
fn spread(w: &[(f64, f64)]) -> (f64, f64) {
    let mean = w.iter().map(|q| q.1).sum::<f64>() / w.len() as f64;
    let (lo, hi) = w.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| (a.min(q.1), b.max(q.1)));
    (mean, (hi - lo) / mean)
}

/// The worn volume against (k/H)·W_f/μ, and the run's wear figures against the same sum.
fn check_volume(r: &ContactRun, mu: f64, what: &str) {
    let slave: f64 = (0..r.x.len()).map(|i| r.weight[i] * (r.wear[i][0] + r.wear[i][1])).sum();
    let master: f64 = r.master_nodal.iter().flatten().map(|m| m.1 * m.2).sum();
    let work: f64 = (0..r.x.len()).map(|i| r.weight[i] * r.frictional_work[i]).sum();
    let expected = K_OVER_H * work / mu;
    let rel = ((slave + master) / expected - 1.0).abs();
    println!(
        "{what}: volume {:e} (master share {:.9}), relative to (k/H) W_f/μ {rel:.1e}",
        slave + master,
        master / (slave + master)
    );
    assert!(rel < 1e-6, "{what}: volume {:e} vs {expected:e}", slave + master);
    assert!((master / (slave + master) - SPLIT).abs() < 1e-6, "{what}: master share {}", master / (slave + master));
    let w = r.wear_figures.expect("wear figures");
    assert!((w.volume / (slave + master) - 1.0).abs() < 1e-12, "{what}: summary volume {}", w.volume);
}

#[test]
fn interface_block_3d_large_sliding_each_lip_wears_archard_and_keeps_the_worn_volume() {
    for coupling in ["implicit", "staggered"] {
        let r = solve_contact_text(&interface_block(1.0, coupling)).expect("solves");
        assert_eq!(r.master_nodal.len(), 1, "the + lip's nodal field");
        assert!(r.wear.iter().all(|w| w[0] == 0.0), "{coupling}: w+ kept at the slave points");
        check_volume(&r, 0.5, coupling);
        let (n, _) = frame();
        let slip = |j: [f64; 3]| {
            let jn = j[0] * n[0] + j[1] * n[1] + j[2] * n[2];
            (0..3).map(|k| (j[k] - jn * n[k]).powi(2)).sum::<f64>().sqrt()
        };
        let win = |x: f64| (0.5..=1.5).contains(&x);
        let mid: Vec<usize> = (0..r.x.len()).filter(|&i| win(r.x[i][0]) && r.weight[i] > 0.0).collect();
        let area: f64 = mid.iter().map(|&i| r.weight[i]).sum();
        let s = mid.iter().map(|&i| slip(r.material_jump[i]) * r.weight[i]).sum::<f64>() / area;
        // The slide of each step (the first less the shear γ it builds up).
        let gamma = 0.05 * 4.0 - s;
        let ds = |k: usize| if k == 1 { 0.05 - gamma } else { 0.05 };
        let steps = r.history.len();
        // Each slave point: Archard with its own pressure history ⟨−λ⟩₊.
        let own = |i: usize| -> f64 { (1..steps).map(|k| (-r.history[k][i].lambda).max(0.0) * ds(k)).sum() };
        let mut sum_w = 0.0;
        for &i in &mid {
            sum_w += r.weight[i] * r.wear[i][1];
        }
        let p = mid.iter().map(|&i| own(i) * r.weight[i]).sum::<f64>() / area / s;
        let (lo, hi) =
            mid.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &i| (a.min(-r.lambda[i]), b.max(-r.lambda[i])));
        let plateau = [K_OVER_H * SPLIT * p * s, K_OVER_H * (1.0 - SPLIT) * p * s];
        let (wlo, whi) =
            mid.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &i| (a.min(r.wear[i][1]), b.max(r.wear[i][1])));
        println!(
            "{coupling}: mean pressure ⟨−λ⟩₊ over the steps {p:.6e} (E·0.002 = 2e-3; last step −λ from {lo:.3e} to {hi:.3e}), S = {s:.6}"
        );
        println!(
            "{coupling} slave: area mean {:.6} of (k/H)(1 − split) p̄ S, points from {:.3} to {:.3} of it",
            sum_w / area / plateau[1],
            wlo / plateau[1],
            whi / plateau[1]
        );
        assert!((p / 0.002 - 1.0).abs() < 0.03, "{coupling}: mean pressure {p:e}");
        assert!(
            (sum_w / area / plateau[1] - 1.0).abs() < 0.01,
            "{coupling}: slave mean {:e} vs {:e}",
            sum_w / area,
            plateau[1]
        );
        // The + lip: its nodes' area-weighted mean over the window, and over strips 2h wide
        // (the field is the deposit averaged over each node's hat, 2h wide).
        let nodes: Vec<&([f64; 3], f64, f64)> = r.master_nodal[0].iter().filter(|m| win(m.0[0]) && m.1 > 0.0).collect();
        let mean_of = |lo: f64, hi: f64| -> f64 {
            let sel: Vec<_> = nodes.iter().filter(|m| m.0[0] >= lo && m.0[0] < hi).collect();
            sel.iter().map(|m| m.1 * m.2).sum::<f64>() / sel.iter().map(|m| m.1).sum::<f64>()
        };
        let mean = mean_of(0.5, 1.5 + 1e-9);
        let strips: Vec<f64> = (0..5).map(|k| mean_of(0.5 + 0.2 * k as f64, 0.7 + 0.2 * k as f64 + 1e-9)).collect();
        let (slo, shi) = strips.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
        println!(
            "{coupling} + lip: {} nodes, area mean {:.6} of (k/H) split p̄ S, strips {:?} of it (spread {:.2e})",
            nodes.len(),
            mean / plateau[0],
            strips.iter().map(|v| format!("{:.4}", v / plateau[0])).collect::<Vec<_>>(),
            (shi - slo) / mean
        );
        assert!((mean / plateau[0] - 1.0).abs() < 0.01, "{coupling}: + lip mean {mean:e} vs {:e}", plateau[0]);
        // Both lips saw the same pressure and slip there: their means in the ratio of the
        // split.
        let ratio = (mean / SPLIT) / (sum_w / area / (1.0 - SPLIT));
        println!("{coupling}: (w⁺/split)/(w⁻/(1 − split)) over the window {ratio:.6}");
        assert!((ratio - 1.0).abs() < 0.005, "{coupling}: lips' ratio {ratio}");
        assert!((shi - slo) / mean < 0.02, "{coupling}: + lip strips {strips:?}");
    }
}

/// (c) Hostile units: E = 2e11 (SI) with k/H = 0.002/2e11 wears both lips as E = 1 does.
#[test]
fn interface_block_3d_wear_in_si_units_gives_the_same_depths() {
    let a = solve_contact_text(&interface_block(1.0, "staggered")).expect("solves");
    let b = solve_contact_text(&interface_block(2e11, "staggered")).expect("solves");
    let depths = |r: &ContactRun| -> Vec<f64> {
        r.wear.iter().map(|w| w[1]).chain(r.master_nodal[0].iter().map(|m| m.2)).collect()
    };
    let (da, db) = (depths(&a), depths(&b));
    assert_eq!(da.len(), db.len());
    let scale = da.iter().fold(0.0f64, |m, &w| m.max(w));
    let worst = da.iter().zip(&db).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    println!("largest depth {scale:e}, largest difference {worst:e}");
    assert!(scale > 0.0 && worst < 1e-6 * scale, "SI depths differ by {worst:e} of {scale:e}");
}

fn punch(coupling: &str) -> String {
    let factors: Vec<String> = (0..=12).map(|k| k.to_string()).collect();
    format!(
        r#"[mesh]
[[mesh.parts]]
name = "base"
generator = "box"
cell = "hex8"
lower = [0.0, -0.2, 0.0]
upper = [3.0, 0.0, 0.4]
divisions = [30, 2, 2]
[[mesh.parts]]
name = "punch"
generator = "box"
cell = "hex8"
lower = [0.0, 0.0, 0.0]
upper = [0.6, 0.1, 0.4]
divisions = [5, 1, 2]
[[materials]]
group = "base"
E = 100.0
nu = 0.0
[[materials]]
group = "punch"
E = 1.0
nu = 0.0
[[dirichlet]]
group = "base.bottom"
components = ["x", "y", "z"]
[[dirichlet]]
group = "punch.top"
components = ["x", "y", "z"]
values = ["0.1 * t", "-0.001 + 0 * t", "0"]
[steps]
factors = [{}]
[[contact_pairs]]
name = "punch"
slave = "punch.bottom"
master = "base.top"
friction = {MU_PUNCH}
sliding = "large"
integration = "gauss"
[contact_pairs.wear]
coefficient = {K_OVER_H}
split = {SPLIT}
coupling = "{coupling}"
"#,
        factors.join(", ")
    )
}

#[test]
fn pair_punch_3d_slid_along_a_base_wears_a_trapezoid_proportional_to_the_time_under_it() {
    let r = solve_contact_text(&punch("implicit")).expect("solves");
    assert_eq!(r.master_nodal.len(), 1, "the master face's nodal field");
    let n = r.x.len();
    let live: Vec<usize> = (0..n).filter(|&i| r.weight[i] > 0.0).collect();
    let area: f64 = live.iter().map(|&i| r.weight[i]).sum();
    // The punch's mean pressure and slide at each step (its bottom lags its top by the
    // shear γ = μp̄H_p/G from the first sliding step on).
    let steps = r.history.len();
    let pk: Vec<f64> =
        (0..steps).map(|k| live.iter().map(|&i| -r.history[k][i].lambda * r.weight[i]).sum::<f64>() / area).collect();
    let gamma = MU_PUNCH * pk[1] * 0.1 / 0.5;
    let a = |k: usize| if k == 0 { 0.0 } else { 0.1 * k as f64 - gamma };
    let (pmin, pmax) =
        live.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &i| (a.min(-r.lambda[i]), b.max(-r.lambda[i])));
    println!("p̄ = {:.6e} (last step: min {pmin:.4e}, max {pmax:.4e}), γ = {gamma:.2e}", pk[steps - 1]);
    // The punch's face: each point (k/H)(1 − split) Σ_k p_k Δs_k with its own pressures.
    let mut worst_slave: f64 = 0.0;
    for &i in &live {
        let e: f64 =
            (1..steps).map(|k| -r.history[k][i].lambda * (a(k) - a(k - 1))).sum::<f64>() * K_OVER_H * (1.0 - SPLIT);
        worst_slave = worst_slave.max((r.wear[i][1] / e - 1.0).abs());
    }
    println!("punch face: worst |w⁻ − (k/H)(1 − split) Σ p Δs| {worst_slave:.2e} relative");
    assert!(worst_slave < 0.01, "punch face off its own pressure history by {worst_slave:e}");
    // The base: each step deposits (k/H)·split·p_k·Δs_k under the punch's end position
    // [a_k, a_k + L_p]; a vertex's depth is that averaged over its hat function (half-width
    // h = 0.1 along x, cut at the base's ends). Summed over the steps: the trapezoid of the
    // time under the punch, rounded over ±h at its kinks.
    let (lp, h, len) = (0.6, 0.1, 3.0);
    let hat_cdf = |c: f64, x: f64| -> f64 {
        // ∫_{-∞}^{x} of the hat centred at c (unnormalised, cut to [0, len]).
        let part = |u: f64| -> f64 {
            let d = (u - c) / h;
            if d <= -1.0 {
                0.0
            } else if d <= 0.0 {
                0.5 * (1.0 + d).powi(2)
            } else if d <= 1.0 {
                1.0 - 0.5 * (1.0 - d).powi(2)
            } else {
                1.0
            }
        };
        part(x.clamp(0.0, len)) - part(0.0)
    };
    let fraction = |c: f64, lo: f64, hi: f64| (hat_cdf(c, hi) - hat_cdf(c, lo)) / hat_cdf(c, len);
    let expected = |x: f64| -> f64 {
        (1..steps).map(|k| pk[k] * (a(k) - a(k - 1)) * fraction(x, a(k), a(k) + lp)).sum::<f64>() * K_OVER_H * SPLIT
    };
    let plateau = K_OVER_H * SPLIT * pk[steps - 1] * lp;
    let mut nodes: Vec<(f64, f64)> = r.master_nodal[0].iter().map(|m| (m.0[0], m.2)).collect();
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut worst: f64 = 0.0;
    let mut xs: Vec<f64> = nodes.iter().map(|q| q.0).collect();
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    for &x in &xs {
        let w: Vec<f64> = nodes.iter().filter(|q| (q.0 - x).abs() < 1e-9).map(|q| q.1).collect();
        let e = expected(x);
        for v in &w {
            worst = worst.max((v - e).abs() / plateau);
        }
        if x <= 2.0 {
            println!(
                "X {x:.2}: w+ {:.4} of the plateau (mean over z), expected {:.4}",
                w.iter().sum::<f64>() / w.len() as f64 / plateau,
                e / plateau
            );
        }
    }
    let flat: Vec<(f64, f64)> =
        nodes.iter().filter(|q| q.0 >= lp + 2.0 * h && q.0 <= a(steps - 1) - h).copied().collect();
    let (mean, sp) = spread(&flat);
    println!("plateau: {} vertices, {:.6} of (k/H) split p̄ L_p, spread {sp:.2e}; worst |w − expected| {worst:.4} of the plateau", flat.len(), mean / plateau);
    assert!(flat.len() >= 6, "{} plateau vertices", flat.len());
    assert!((mean / plateau - 1.0).abs() < 0.02, "plateau {mean:e} vs {plateau:e}");
    assert!(worst < 0.06, "the base's depth is {worst:.4} of the plateau off the trapezoid");
    check_volume(&r, MU_PUNCH, "punch");
    // The pair's own figures (summary.json's steps[].contact_pairs[].wear) are the run's.
    let each = r.wear_figures_each[0].expect("the pair's wear figures");
    let all = r.wear_figures.expect("wear figures");
    assert!((each.volume - all.volume).abs() <= 1e-14 * all.volume && each.max == all.max, "{each:?} vs {all:?}");
}
