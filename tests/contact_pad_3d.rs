//! A round pad pressed and slid on a 3D X-FEM interface: the cases where the 3D contact
//! loops failed while the 2D ones ran (issue 14 item 6, the 3D wear example; issue 11's
//! open 3D friction failures): pressed into an asperity layer and slid in the same step,
//! and (ignored, open) rubbed through a step whose tangential increment is zero (the top
//! of a fretting cycle).

#[path = "common/cli.rs"]
mod cli;

use std::time::Duration;

const MU: f64 = 0.5;

/// The pad case: box [0, 2] × [0, 0.6] × [0, 1], hex8 with `divisions`, an X-FEM
/// interface plane y = 0.25 (inside a cell layer), E = 1, ν = 0.3, bottom clamped; the top
/// nodes within 0.34 of (1, 0.6, 0.5) (the pad) moved by (`x`, −0.003, 0), the rest of the
/// top free; μ = 0.5, augmented Lagrangian; `extra` appended to `[cracks.contact]`.
fn pad_case(divisions: &str, x: &str, steps: usize, extra: &str) -> String {
    format!(
        "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [0.0, 0.0, 0.0]\nupper = [2.0, 0.6, 1.0]\ndivisions = {divisions}\n\
         [[materials]]\nE = 1.0\nnu = 0.3\n\
         [[sets]]\nname = \"pad\"\nkind = \"nodes\"\non = \"y - 0.6\"\ninside = \"sqrt((x - 1) * (x - 1) + (z - 0.5) * (z - 0.5)) - 0.34\"\n\
         [[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\", \"z\"]\n\
         [[dirichlet]]\ngroup = \"pad\"\ncomponents = [\"x\", \"y\", \"z\"]\nvalues = [\"{x}\", \"-0.003 + 0 * t\", \"0 * t\"]\n\
         [steps]\ncount = {steps}\n[output]\nvtu = false\nplots = false\n\
         [[cracks]]\nname = \"interface\"\nshape = \"plane\"\npoint = [0.0, 0.25, 0.0]\nnormal = [0.0, 1.0, 0.0]\n\
         [cracks.contact]\nfriction = {MU}\n{extra}"
    )
}

/// Per step: (|R_τ|/|R_y| of the pad, stick points, friction passes, warnings of the run).
fn run(name: &str, text: &str, steps: usize) -> (Vec<(f64, u64, u64)>, Vec<String>) {
    let o = cli::fissure("contact_pad_3d", name, text, false, Duration::from_secs(600));
    assert_eq!(o.code, Some(0), "{name}: {}", o.stderr);
    let s = o.summary.expect("summary.json");
    assert_eq!(s["status"], "ok", "{name}");
    let st = s["steps"].as_array().unwrap();
    assert_eq!(st.len(), steps, "{name}");
    let rows = st
        .iter()
        .map(|st| {
            let r = &st["reactions"]["pad"];
            let (rx, ry, rz) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap(), r[2].as_f64().unwrap());
            let c = &st["contact"];
            (rx.hypot(rz) / ry.abs(), c["stick"].as_u64().unwrap(), c["iterations"]["friction"].as_u64().unwrap())
        })
        .collect();
    let warnings = s["warnings"].as_array().unwrap().iter().filter_map(|w| w.as_str().map(String::from)).collect();
    (rows, warnings)
}

/// Coulomb on the pad's reaction where every contact point slides (no stick point):
/// |R_τ| = μ|R_y|. Tolerance 1e-2 relative: the friction acts at the closed points only and
/// the weak contact law leaves 1.4–2% of the normal force at open points or as tension
/// (the run's "carried at open points" warning, `run::STRAY_NORMAL_FORCE`), and the
/// Coulomb tie |Λ| = 1 holds per multiplier packet (`contact::state::COULOMB_TIE`, 1e-2);
/// measured 0.4980–0.5007 on this pad. Never above μ by more than that, at any step.
fn assert_coulomb(name: &str, rows: &[(f64, u64, u64)]) -> usize {
    let mut gross = 0;
    for (k, &(ratio, stick, _)) in rows.iter().enumerate() {
        assert!(ratio <= MU * (1.0 + 1e-2), "{name} step {}: |R_τ|/|R_y| = {ratio} above μ", k + 1);
        if stick == 0 {
            gross += 1;
            assert!((ratio - MU).abs() <= 1e-2 * MU, "{name} step {}: gross slip with |R_τ|/|R_y| = {ratio}", k + 1);
        }
    }
    gross
}

/// What: the pad pressed (0.003) into an asperity layer (thickness 1e-3 = `initial_gap`,
/// κ_a = 5e3: the layer carries κ_a a² = 5e-3 when crushed, about the pad's mean pressure)
/// and slid (0.002 along x) in the same first step, then slid on (0.002 per step), on hex8
/// 12 × 6 × 5 (h = 0.1–0.17). Reference: Coulomb on the pad's reaction once every point
/// slides ([`assert_coulomb`]); the loops converge with the friction passes within
/// [3, 12] per step (measured 9, 8, 7 with the layer's traction in the Newton loop's
/// threshold; before that 8, 8, 7 with step 1 accepted as stalled at a threshold change
/// of 1.4e-3, with its warning). No warning about the normal force at open points: the
/// layer carries the load, and its traction counts in the normal force of that check
/// (before, with λ alone, of round-off size, it reported 309% and 323%).
/// Before the fix step 1 failed in the Newton loop (30 iterations, the correction cycling
/// 5.636e-2 / 5.650e-2 after the status freeze): 7 points whose layer had separated at the
/// iterate but whose threshold λ̄ was still non-zero were reported open, so the freeze
/// skipped them and they flipped between stick and slip at every iteration
/// (`contact::state::freeze_statuses`). (The same case without the layer ran before and
/// runs now, step 1 stalled at 4.2e-3: about 60 points of the partial-slip ring flip
/// between stick and slip at every Newton iteration; not in this test, 60 s.)
#[test]
fn pad_pressed_into_an_asperity_layer_and_slid_in_one_step_converges() {
    let layer = "initial_gap = 0.001\n[cracks.contact.asperity]\nthickness = 0.001\nstiffness = 5000.0\n";
    let text = pad_case("[12, 6, 5]", "0.006 * t", 3, layer);
    let (rows, warnings) = run("pad_slid_layer", &text, 3);
    for (k, r) in rows.iter().enumerate() {
        assert!((3..=12).contains(&r.2), "step {}: {} friction passes", k + 1, r.2);
    }
    let gross = assert_coulomb("pad_slid_layer", &rows);
    assert!(gross >= 2, "the pad does not slide: {rows:?}");
    eprintln!("pad_slid_layer: {rows:?}\n{warnings:?}");
    assert!(!warnings.iter().any(|w| w.contains("of the normal force is carried at open points")), "{warnings:?}");
}

/// What: the pad rubbed by 0.01 sin(0.8πt) over 4 steps (hex8 10 × 4 × 5, no layer):
/// x = 0.0059, 0.0095, 0.0095, 0.0059: step 3 does not move the pad along the interface
/// (the top of a fretting cycle of 10 steps) and step 4 reverses. Reference: Coulomb on the
/// pad's reaction where every point slides ([`assert_coulomb`]); at step 3 nothing moves, so
/// the pad's tangential reaction stays that of step 2 (within 1e-2); friction passes within
/// [1, 12].
/// OPEN, ignored: step 3 fails in the active-set loop (30 iterations, 160 statuses
/// changing). Measured: the stuck solution of the stick predictor at that step has
/// |g_τ| = |Λ| > 2 at 166 of the 671 closed points and in (1.01, 2] at 395: with the
/// tangential multipliers on their restricted (vital-edge) space, the stuck Λ is far from
/// unit length pointwise although the previous step ended sliding, so the pointwise
/// stick/slip test flips hundreds of points at every Newton iteration. Keeping the points
/// on the Coulomb tie stuck after the predictor (tried) keeps 2 of them: no effect. A
/// stick/slip decision per multiplier packet (the candidate) would change nothing
/// (measured 2026-11-27 after each Newton loop of step 3): every touching point (665–671)
/// violates stick pointwise, |g_τ| > 2 at 356–551, and so does the λ̄-weighted mean of
/// g_τ over each of the 46 tangential packets, so the packet-majority status equals the
/// pointwise one at every point; the contact statuses also change at every active-set
/// iteration (3-cycle of 186/192/223 changes from iteration 7), and |Λ_j| > 1.01 at 13
/// of the 46 packets at the end of the sliding step 2 already. The 2D
/// pad (`fretting_pad_*`) survives the same step with a stall warning (209 Newton
/// iterations). The example `pad_fretting_wear_3d.toml` uses a stepping without it.
/// Tried 2026-11-28 and not kept (docs/reliability.md, "The lift-off edge at a large
/// rho_n, and the 3D step without tangential increment"): statuses per packet tested on
/// the packet's Λ_j and its stick row's slip (the packets alternate between all-slip and
/// half-stuck as the points do), and the open points' Λ row scaled down by 1e-6 (step 3
/// still fails, 147 statuses changing).
#[test]
#[ignore = "open: a step with zero tangential increment after sliding fails in 3D"]
fn pad_rubbed_through_a_step_without_tangential_increment_and_a_reversal() {
    let text = pad_case("[10, 4, 5]", "0.01 * sin(0.8 * PI * t)", 4, "");
    let (rows, warnings) = run("pad_fretting", &text, 4);
    for (k, r) in rows.iter().enumerate() {
        assert!((1..=12).contains(&r.2), "step {}: {} friction passes", k + 1, r.2);
    }
    assert_coulomb("pad_fretting", &rows);
    assert!((rows[2].0 - rows[1].0).abs() <= 1e-2 * MU, "step 3 moved: {rows:?}");
    eprintln!("pad_fretting: {rows:?}\n{warnings:?}");
}
