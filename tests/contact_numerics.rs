//! Contact numerics that must not depend on the numbers' scale: the unit system, the ratio
//! of the stiffness to the load.

mod common;

use common::contact::solve_contact_text;
use std::f64::consts::PI;

/// The closed 45° crack of `tests/contact_friction_cracks.rs` (plate [−2L, 2L]², crack
/// 2a = 0.4L at 45° centred at (0.0123L, 0.0071L), quad4 81 × 81, ν = 0.3, plane strain,
/// μ = 0.3, tip radius 0.05L, SIF radius 0.06L) compressed by σ = 5e-9 E (steel, E = 2e11 Pa,
/// under 1 kPa), written in five unit systems: SI (L = 1e-3 m, E = 2e11 Pa), mm–N–MPa
/// (L = 1, E = 2e5), and both scaled by 1e±6. Reference: the run in mm–N–MPa. Tolerance:
/// λ/σ at every contact point and K/(σ√L) at both tips equal to 1e-8, same statuses and
/// the same iteration counts (friction, active set, Newton). Before the Newton correction
/// was measured per block of unknowns (displacements, λ, Λ, reactions) the counts differed
/// between unit systems (7, 8, 9 Newton iterations).
#[test]
fn contact_is_invariant_to_the_unit_system() {
    let case = |l: f64, e: f64| {
        let b = 45f64.to_radians();
        let (c, s, a) = (b.cos(), b.sin(), 0.2);
        let ctr = [0.0123, 0.0071];
        let sig = 5e-9 * e;
        format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [{lo:e}, {lo:e}]\nupper = [{hi:e}, {hi:e}]\ndivisions = [81, 81]\n[[materials]]\nE = {e:e}\nnu = 0.3\n[[sets]]\nname = \"pin\"\non = \"abs(x + {hi:e}) + abs(y + {hi:e})\"\n[[sets]]\nname = \"roller\"\non = \"abs(x - {hi:e}) + abs(y + {hi:e})\"\n[[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, {ms:e}]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, {sig:e}]\n[[cracks]]\nname = \"c\"\nshape = \"segment\"\na = [{ax:e}, {ay:e}]\nb = [{bx:e}, {by:e}]\ntip_radius = {tr:e}\nsif_radius = {sr:e}\n[cracks.contact]\nfriction = 0.3\n",
            lo = -2.0 * l,
            hi = 2.0 * l,
            ms = -sig,
            ax = (ctr[0] - a * c) * l,
            ay = (ctr[1] - a * s) * l,
            bx = (ctr[0] + a * c) * l,
            by = (ctr[1] + a * s) * l,
            tr = 0.05 * l,
            sr = 0.06 * l,
        )
    };
    let run = |l: f64, e: f64| {
        let r = solve_contact_text(&case(l, e)).unwrap_or_else(|err| panic!("L = {l:e}, E = {e:e}: {err}"));
        let sig = 5e-9 * e;
        let c = r.steps[0].contact.clone().unwrap();
        let lam: Vec<f64> = r.lambda.iter().map(|x| x / sig).collect();
        let k: Vec<[f64; 2]> = r.sifs[0].iter().map(|t| [t.k1 / (sig * l.sqrt()), t.k2 / (sig * l.sqrt())]).collect();
        (lam, k, r.status.clone(), (c.friction, c.active_set, c.newton))
    };
    let reference = run(1.0, 2e5);
    let k0 = (PI * 0.2).sqrt();
    eprintln!(
        "mm–N–MPa: K_II/σ√(πa) {:?}, counts {:?}",
        reference.1.iter().map(|k| k[1] / k0).collect::<Vec<_>>(),
        reference.3
    );
    for (l, e) in [(1e-3, 2e11), (1e-6, 2e-1), (1e6, 2e11), (1e-9, 2e5), (1e3, 2e17)] {
        let r = run(l, e);
        let dl = r.0.iter().zip(&reference.0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        let dk =
            r.1.iter().zip(&reference.1).map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs())).fold(0.0, f64::max);
        eprintln!("L = {l:e}, E = {e:e}: max |Δλ/σ| {dl:.1e}, max |ΔK/σ√L| {dk:.1e}, counts {:?}", r.3);
        assert_eq!(r.2, reference.2, "L = {l:e}, E = {e:e}: statuses differ");
        assert_eq!(r.3, reference.3, "L = {l:e}, E = {e:e}: iteration counts differ");
        assert!(dl < 1e-8, "L = {l:e}, E = {e:e}: λ/σ differs by {dl:e}");
        assert!(dk < 1e-8, "L = {l:e}, E = {e:e}: K/σ√L differs by {dk:e}");
    }
}

/// A block pressed by a fixed traction p onto a base and pushed sideways by a prescribed
/// displacement of its top: mesh [0, 1] × [−0.5, 0.5], quad4 20 × 21 (h = 0.05; the
/// interface y = 0 crosses the middle of a row of cells), base y < 0, block y > 0, both
/// E = 1, ν = 0.3, plane strain; bottom clamped; top: u_x = 0.001 t, traction (0, −p) at
/// every step t = 1 … 10; interface: a `line` crack with Coulomb friction μ = 0.5, small
/// sliding, default ρ_n and ρ_τ. For E/p = 1e2 the block sticks (the shear needed to slide,
/// μp, exceeds what u_x = 0.01 gives); for E/p = 1e4 and 1e6 it slides from the first
/// step and its trailing edge lifts off (the tangential force's moment, μH > W/6).
/// Reference (statics, Coulomb): once the block slides, the clamped bottom's reaction
/// satisfies |R_x| = μ |R_y| (R_y = p × width); while any point sticks, |R_x| ≤ μ |R_y|. Tolerance: 1e-4 relative. Before ρ_τ followed the
/// threshold (ρ_n/(μ|λ̄|), `CrackLaw::rho_t_at`) the stick/slip statuses chattered and
/// E/p = 1e4 failed in the friction loop at step 1 (E/p = 1e3 at step 5).
#[test]
fn sliding_block_obeys_coulomb_for_every_stiffness_to_load_ratio() {
    for e_over_p in [1e2, 1e3, 1e4, 1e6] {
        let p = 1.0 / e_over_p;
        let text = format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [1.0, 0.5]\ndivisions = [20, 21]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = 0.001\n[[traction]]\ngroup = \"top\"\nvalue = [\"0\", \"{mp:e} + 0 * t\"]\n[steps]\nfactors = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n",
            mp = -p
        );
        let r = solve_contact_text(&text).unwrap_or_else(|err| panic!("E/p = {e_over_p:e}: {err}"));
        for (k, s) in r.steps.iter().enumerate() {
            let c = s.contact.as_ref().unwrap();
            // Reactions per Dirichlet group: [bottom, top]; the clamped bottom carries the
            // whole normal load (the top holds only u_x).
            let bottom = s.reactions[0];
            let ratio = bottom[0].abs() / bottom[1];
            eprintln!(
                "E/p = {e_over_p:e} step {}: |R_x|/|R_y| {ratio:.6}, {} stick {} slip of {} ({:?} passes/AS/Newton)",
                k + 1,
                c.stick,
                c.slip,
                c.points,
                (c.friction, c.active_set, c.newton)
            );
            assert!((bottom[1] / p - 1.0).abs() < 1e-6, "E/p = {e_over_p:e}: R_y {}", bottom[1]);
            if c.stick == 0 {
                assert!(
                    (ratio - 0.5).abs() < 0.5e-4,
                    "E/p = {e_over_p:e} step {}: sliding with |R_x|/|R_y| {ratio}",
                    k + 1
                );
            } else {
                assert!(ratio <= 0.5 * (1.0 + 1e-4), "E/p = {e_over_p:e} step {}: |R_x|/|R_y| {ratio} above μ", k + 1);
            }
        }
        let last = r.steps.last().unwrap().contact.as_ref().unwrap();
        if e_over_p >= 1e4 {
            assert_eq!(last.stick, 0, "E/p = {e_over_p:e}: the block slides");
        }
        if e_over_p <= 1e2 {
            assert_eq!(last.slip, 0, "E/p = {e_over_p:e}: the block sticks");
        }
    }
}

/// The sliding block of [`sliding_block_obeys_coulomb_for_every_stiffness_to_load_ratio`]
/// (E/p = 1e4: it slides from the first step) on a base E_b times stiffer than the block:
/// [0, 1] × [−0.5, 0.5], quad4 20 × 21 (the interface y = 0 runs through the middle of a
/// row of cells), block y > 0 with E = 1, base y < 0 with E_b (a `[[sets]]` of cells
/// `inside = "y"`, which also takes the cut row, whose centroids lie on y = 0), ν = 0.3,
/// plane strain, p = 1e-4, μ = 0.5, u_x = 0.001 t at the top, t = 1 … 10. Reference
/// (statics, Coulomb): the clamped bottom carries R_y = p·W; while every contact point
/// slides, |R_x| = μ R_y. Tolerance: R_y to 1e-6; |R_x|/R_y within 1e-3 of μ, and the same
/// ratio for every contrast to 1e-5 (measured 2026-11-26: 0.5003188 at 1e3, 0.5003158 at
/// 1e5 and 1e6; 0.499975 with one material: the 6.4e-4 excess is that of a base whose
/// cut cells are stiffer than the block's, i.e. of the weak, per-packet contact law with
/// different stiffness on each side, not of the contrast's size). Before each side of a cut
/// cell took its own side's material (`physics::side_materials`) the cut row was all E_b:
/// E_b = 1e3 failed in the active-set loop (statuses in a 3-cycle) and 1e6 as a "singular"
/// LDLᵀ; before the solver's residual check weighed each row by its stiffness, 1e5 and 1e6
/// still failed as "singular" (relative residual 5e-6 and 3.5e-5 in ‖Ax − b‖/‖b‖).
#[test]
fn sliding_on_a_base_stiffer_by_1e3_to_1e6_obeys_coulomb() {
    let p = 1e-4;
    let mut ratios = vec![];
    for e_b in [1e3, 1e4, 1e5, 1e6] {
        let text = format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [1.0, 0.5]\ndivisions = [20, 21]\n[[sets]]\nname = \"base\"\nkind = \"cells\"\ninside = \"y\"\n[[materials]]\nE = 1.0\nnu = 0.3\n[[materials]]\ngroup = \"base\"\nE = {e_b:e}\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = 0.001\n[[traction]]\ngroup = \"top\"\nvalue = [\"0\", \"{mp:e} + 0 * t\"]\n[steps]\nfactors = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n",
            mp = -p
        );
        let r = solve_contact_text(&text).unwrap_or_else(|err| panic!("E_b = {e_b:e}: {err}"));
        for (k, (s, pts)) in r.steps.iter().zip(&r.history).enumerate() {
            let c = s.contact.as_ref().unwrap();
            let bottom = s.reactions[0];
            let ratio = bottom[0].abs() / bottom[1];
            let tension: f64 = pts.iter().filter(|q| q.lambda > 0.0).map(|q| q.weight * q.lambda).sum();
            eprintln!(
                "E_b = {e_b:e} step {}: |R_x|/R_y {ratio:.7}, {} stick {} slip of {} ({:?} passes/AS/Newton), tension {:.2e} of p",
                k + 1,
                c.stick,
                c.slip,
                c.points,
                (c.friction, c.active_set, c.newton),
                tension / p
            );
            assert!((bottom[1] / p - 1.0).abs() < 1e-6, "E_b = {e_b:e}: R_y {}", bottom[1]);
            assert_eq!(c.stick, 0, "E_b = {e_b:e} step {}: the block slides", k + 1);
            assert!((ratio - 0.5).abs() < 0.5e-3, "E_b = {e_b:e} step {}: |R_x|/R_y {ratio}", k + 1);
            ratios.push(ratio);
        }
    }
    let (lo, hi) = ratios.iter().fold((f64::MAX, f64::MIN), |(a, b), &r| (a.min(r), b.max(r)));
    assert!(hi - lo < 0.5e-5, "the ratio depends on the contrast: {lo} to {hi}");
}

/// The sliding block of [`sliding_block_obeys_coulomb_for_every_stiffness_to_load_ratio`]
/// with one material (E = 1, ν = 0.3) and the traction ramped with the load factor
/// (p = 1e-4·t, u_x = 0.001·t, t = 1 … 10): a proportional problem, so every step should
/// give the same |R_x|/R_y = μ = 0.5 (measured 0.4999745). At step 2 the loops end on another
/// active set (57 closed points instead of 54), whose multiplier carries 1.92% of the
/// normal force at open points or as tension at closed ones, and |R_x|/R_y = 0.5066: 1.3%
/// above μ (docs/reliability.md, "Stiffness contrast across an interface"). Reference
/// behaviour: that step, and only that one, is reported in `summary.json` `warnings`
/// (a share of stray normal force above 1%; the other steps carry 0.29%).
#[test]
fn a_step_whose_multiplier_carries_normal_force_at_open_points_is_reported() {
    let text = "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [1.0, 0.5]\ndivisions = [20, 21]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = 0.001\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, -1e-4]\n[steps]\nfactors = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n";
    let s = common::run_cli("contact_numerics", "stray_normal_force", text);
    let warnings: Vec<&str> = s["warnings"].as_array().unwrap().iter().filter_map(|w| w.as_str()).collect();
    let stray: Vec<&&str> = warnings.iter().filter(|w| w.contains("of the normal force")).collect();
    assert_eq!(stray.len(), 1, "{warnings:?}");
    assert!(stray[0].starts_with("step 2: crack 'interface': 1.9"), "{}", stray[0]);
    for (k, step) in s["steps"].as_array().unwrap().iter().enumerate() {
        let r = &step["reactions"]["bottom"];
        let ratio = r[0].as_f64().unwrap().abs() / r[1].as_f64().unwrap();
        if k == 1 {
            assert!(ratio > 0.5 * 1.01, "step 2: |R_x|/R_y {ratio}: the spurious state is gone, update the test");
        } else {
            assert!((ratio - 0.5).abs() < 0.5e-4, "step {}: |R_x|/R_y {ratio}", k + 1);
        }
    }
}

/// Issue 11 item 9, the symptom reported: on the closed 45° crack of
/// `common::contact::inclined_crack` (plate [−2, 2]², quad4 41 × 41, E = 1, μ = 0.3,
/// compression σ = 1, E/h = 10.25) `rho_n = 1e4` (976 E/h) let the pointwise gap (a few
/// 1e-5, the weak per-packet law) outweigh λ in the status test λ − ρ_n d_n: two points next
/// to tip b opened under a multiplier of −0.46 (90% of the largest pressure, 0.5 exact) and
/// K_II at b was 17% off (−0.2962 for −0.2528; docs/reliability.md, "Contact numerics").
/// The law now augments with the gap projected on the multiplier packets above E/h
/// (`CrackLaw::rho_projected`), and no point opens there: the premise of this test is kept
/// with the pointwise law, which the developer's switch `FISSURE_POINTWISE_AUGMENTATION`
/// restores. Reference behaviour: with that switch the step is reported in `summary.json`
/// `warnings` naming the crack and the share (≥ 80%; the threshold is 25%, the sliding
/// block's open-zone edge carries 3.3%); the projected law at the same `rho_n` and the
/// default ρ_n give no such warning, with every point closed.
#[test]
fn points_opened_under_a_compressive_multiplier_are_reported() {
    let cases = [
        ("large_rho_n_pointwise", "rho_n = 1e4\n", true, &[("FISSURE_POINTWISE_AUGMENTATION", "1")][..]),
        ("large_rho_n", "rho_n = 1e4\n", false, &[][..]),
        ("default_rho_n", "", false, &[][..]),
    ];
    for (name, extra, warned, env) in cases {
        let s =
            common::run_cli_with_env("contact_numerics", name, &common::contact::inclined_crack(0.3, 41, extra), env);
        let warnings: Vec<&str> = s["warnings"].as_array().unwrap().iter().filter_map(|w| w.as_str()).collect();
        let w = warnings.iter().find(|w| w.contains("open points carry a compressive multiplier"));
        assert_eq!(w.is_some(), warned, "{name}: {warnings:?}");
        if let Some(w) = w {
            assert!(w.starts_with("step 1: crack 'c':"), "{w}");
            let share: f64 = w.split("up to ").nth(1).and_then(|t| t.split('%').next()).unwrap().parse().unwrap();
            assert!(share >= 80.0, "{w}");
        } else {
            let c = &s["steps"][0]["contact"];
            assert_eq!(c["active"], c["points"], "{name}: every point closed");
        }
    }
}

/// Issue 11 item 9, the fix: K_II does not depend on `rho_n`. The closed 45° crack of
/// `common::contact::inclined_crack` (plate [−2, 2]², quad4 41 × 41, crack 2a = 0.4 at 45°,
/// E = 1, ν = 0.3, plane strain, μ = 0.3, compression σ = 1 on the top and bottom edges;
/// E/h = 10.25, 24 contact points on 6 multiplier packets), solved with `rho_n` = 0.1, 1,
/// 10, 100, 1e3 and 1e4 × E/h. Reference: the run with the default ρ_n = E/h (K_II at the
/// tips a and b −0.2006, −0.2526 on this mesh; σ√(πa)(sinβ cosβ − μ cos²β) ≈ 0.277 in an
/// infinite plate, reached at 161 × 161). Tolerance: K_II at both tips within 0.5% of the
/// reference at every `rho_n`, every point closed. Measured (2026-11-27): −0.20065, −0.25253
/// at 0.1 E/h and −0.20064, −0.25258 from 1 to 1e4 E/h (equal to 5 digits above E/h: the
/// part of ρ_n above E/h augments the gap projected on the packets, which vanishes at the
/// converged closed state). The pointwise law of before (developer's switch
/// `FISSURE_POINTWISE_AUGMENTATION`) gave −0.2962 at b at 976 E/h (+17%, two points
/// opened): checked here to fail the same tolerance, so the test can fail.
#[test]
fn closed_45_degree_crack_k_ii_does_not_depend_on_rho_n() {
    let e_over_h = 41.0 / 4.0;
    let k_ii = |name: &str, factor: Option<f64>, env: &[(&str, &str)]| {
        let extra = factor.map_or(String::new(), |f| format!("rho_n = {:e}\n", f * e_over_h));
        let s =
            common::run_cli_with_env("contact_numerics", name, &common::contact::inclined_crack(0.3, 41, &extra), env);
        let step = &s["steps"][0];
        let c = &step["contact"];
        let front = step["cracks"][0]["front"].as_array().unwrap();
        let k: Vec<f64> = front.iter().map(|p| p["KII"].as_f64().unwrap()).collect();
        (k, c["active"] == c["points"])
    };
    let (reference, closed) = k_ii("rho_n_default", None, &[]);
    assert_eq!(reference.len(), 2);
    assert!(closed, "default ρ_n: every point closed");
    let within = |k: &[f64]| k.iter().zip(&reference).all(|(k, r)| ((k - r) / r).abs() < 5e-3);
    for factor in [0.1, 1.0, 10.0, 100.0, 1e3, 1e4] {
        let (k, closed) = k_ii(&format!("rho_n_{factor:e}"), Some(factor), &[]);
        eprintln!("rho_n = {factor:e} E/h: K_II {k:?} (reference {reference:?}), every point closed: {closed}");
        assert!(closed, "rho_n = {factor:e} E/h: a point opened");
        assert!(within(&k), "rho_n = {factor:e} E/h: K_II {k:?}, reference {reference:?}");
    }
    let (k, _) = k_ii("rho_n_1e3_pointwise", Some(976.0 / 1.0), &[("FISSURE_POINTWISE_AUGMENTATION", "1")]);
    assert!(!within(&k), "the pointwise law at 976 E/h drifts: K_II {k:?}, reference {reference:?}");
}

/// A block held sideways only by friction: mesh [0, 2] × [−0.5, 0.25], quad4 40 × 16, E = 1,
/// ν = 0.3, plane strain; bottom clamped; the top loaded by the traction (q, −p), p = 1e-3,
/// nothing else holding the block above the interface y = 0 (a `line` crack, μ = 0.5,
/// default `initial_threshold = 0`). The frictionless first pass is singular (the block's
/// horizontal motion is free); it is redone with every contact point stuck. Reference
/// (statics): for q = 0.25 p < μp the block sticks, the bottom's reaction is (−q W, p W)
/// with W = 2. Tolerance 1e-9 relative; every point sticks. For q = 0.6 p > μp no static
/// equilibrium exists: the run must fail (not report a solution), with a message saying
/// that friction cannot hold the part.
#[test]
fn a_body_held_sideways_only_by_friction_is_solved_from_a_bonded_first_pass() {
    let case = |q: f64| {
        format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [2.0, 0.25]\ndivisions = [40, 16]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[traction]]\ngroup = \"top\"\nvalue = [{q:e}, -1e-3]\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n"
        )
    };
    let p = 1e-3;
    let r = solve_contact_text(&case(0.25 * p)).expect("the block sticks");
    let c = r.steps[0].contact.as_ref().unwrap();
    let bottom = r.steps[0].reactions[0];
    eprintln!("q = 0.25p: {c:?}; bottom reaction {bottom:?}");
    assert_eq!(c.stick, c.points, "every point sticks");
    assert!((bottom[0] / (-0.25 * p * 2.0) - 1.0).abs() < 1e-9, "R_x {}", bottom[0]);
    assert!((bottom[1] / (p * 2.0) - 1.0).abs() < 1e-9, "R_y {}", bottom[1]);
    let err = solve_contact_text(&case(0.6 * p)).err().expect("no equilibrium when q > μp");
    let msg = err.to_string();
    eprintln!("q = 0.6p: {msg}");
    assert!(msg.contains("exceeds μ times the normal load"), "{msg}");
}

/// An open crack with contact and friction: the inclined crack of
/// `tests/contact_friction_cracks.rs` (quad4 41 × 41, μ = 0.3) under tension σ = 1 instead of
/// compression, `max_friction = 1`. Every point opens, so friction has nothing to do: the
/// friction loop must end after its first pass (it used to chase round-off multipliers,
/// λ ≈ 1e-185, for 11 passes, so `max_friction = 10` failed a run with no contact).
/// Reference: no point in contact, λ = 0. Tolerance: |λ| < 1e-12 σ.
#[test]
fn an_open_crack_with_friction_needs_one_friction_pass() {
    let text = common::contact::inclined_crack(0.3, 41, "")
        .replace("value = [0.0, -1.0]", "value = [0.0, 1.0]#")
        .replace("value = [0.0, 1.0]\n", "value = [0.0, -1.0]\n")
        .replace("value = [0.0, 1.0]#", "value = [0.0, 1.0]")
        + "[contact_solver]\nmax_friction = 1\n";
    let r = solve_contact_text(&text).expect("one friction pass suffices");
    let c = r.steps[0].contact.as_ref().unwrap();
    eprintln!("{c:?}");
    assert_eq!(c.active, 0, "the crack opens");
    assert_eq!(c.friction, 1);
    assert!(r.lambda.iter().all(|l| l.abs() < 1e-12), "λ {:?}", r.lambda);
}

/// A loop that reaches its cap reports its own measure, not the Newton correction: on the
/// closed 45° crack (quad4 41 × 41, μ = 0.3), `max_friction = 1` stops the friction loop
/// (which needs 3–4 passes) with the relative change of the thresholds (1 on the first
/// pass: the thresholds go from 0 to λ), and `start_closed = false` with
/// `max_active_set = 1` stops the active-set loop with the number of statuses that changed
/// (every point closes).
#[test]
fn a_capped_loop_reports_its_own_measure() {
    let friction =
        solve_contact_text(&(common::contact::inclined_crack(0.3, 41, "") + "[contact_solver]\nmax_friction = 1\n"))
            .err()
            .expect("one friction pass is not enough")
            .to_string();
    eprintln!("{friction}");
    assert!(friction.contains("friction threshold loop did not converge in 1 iterations (last relative change of the friction thresholds 1.00e0)"), "{friction}");
    let active = solve_contact_text(
        &(common::contact::inclined_crack(0.3, 41, "start_closed = false\n")
            + "[contact_solver]\nmax_active_set = 1\n"),
    )
    .err()
    .expect("one active-set iteration is not enough")
    .to_string();
    eprintln!("{active}");
    assert!(
        active.contains("active set loop did not converge in 1 iterations (")
            && active.contains("statuses still changing"),
        "{active}"
    );
}

/// `integration = "nodes"` and `"vertex"` on a crack with a front: the nodal rules do not
/// integrate the √r jump near the front. Case: the closed 45° crack of
/// `common::contact::inclined_crack` (σ = 1, 2a = 0.4, μ = 0.3, quad4 41 × 41). Reference:
/// the pressure is σ cos²45° = 0.5 on the whole crack (Gauss, the default, gives it to 1e-3
/// on 161 × 161); the nodal rules are off by several percent near the tips (measured in
/// docs/reliability.md), so the run must say so: a warning naming the crack and the rule,
/// and none with `gauss`.
#[test]
fn nodal_contact_rules_on_a_crack_with_a_front_are_reported() {
    for (rule, warned) in [("nodes", true), ("vertex", true), ("gauss", false)] {
        let text = common::contact::inclined_crack(0.3, 41, &format!("integration = \"{rule}\"\n"));
        let s = common::run_cli("contact_numerics", &format!("nodal_rule_{rule}"), &text);
        let warnings: Vec<String> =
            s["warnings"].as_array().unwrap().iter().map(|w| w.as_str().unwrap().to_string()).collect();
        let hit = warnings.iter().any(|w| w.contains("crack 'c'") && w.contains(&format!("integration = \"{rule}\"")));
        assert_eq!(hit, warned, "{rule}: warnings {warnings:?}");
    }
}

/// The condensed contact factor on an ill-conditioned crack block gives the plain factor's
/// answer. Case: the closed 45° crack of `common::contact::inclined_crack` (σ = 1, 2a = 0.4,
/// μ = 0.3) on quad4 321 × 321 with `integration = "nodes"`, whose crack block is
/// ill-conditioned. Reference: the same case with `[solver] condense = false`. Tolerance: λ
/// range and K_II at both tips equal to 1e-10 relative, status ok. History: before the
/// fallback to the plain LDLᵀ the run failed as "singular"; with it, this case fell back
/// (the condensed solve reached a relative residual of ~1e-1, a warning named the step).
/// Since the multiplier rows of all-open packets leave the dense LBLᵀ of the crack block
/// (`CondensedFactor::factorize`), the condensed solve is accurate here and there is no
/// fallback (3e-13 from the plain answer, measured). No case of the suite triggers the
/// fallback any more (docs/reliability.md); the next test injects the failure instead.
#[test]
fn an_ill_conditioned_crack_block_gives_the_plain_factors_answer() {
    let text = common::contact::inclined_crack(0.3, 321, "integration = \"nodes\"\n");
    let condensed = common::run_cli("contact_numerics", "fallback_condensed", &text);
    let plain = common::run_cli("contact_numerics", "fallback_plain", &format!("{text}\n[solver]\ncondense = false\n"));
    assert_eq!(condensed["status"], "ok");
    let (a, b) = (&condensed["steps"][0], &plain["steps"][0]);
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-10 * y.abs().max(1e-12);
    for key in ["lambda_min", "lambda_max"] {
        let (x, y) = (a["contact"][key].as_f64().unwrap(), b["contact"][key].as_f64().unwrap());
        assert!(close(x, y), "{key}: {x} against {y}");
    }
    for (p, q) in a["cracks"][0]["front"].as_array().unwrap().iter().zip(b["cracks"][0]["front"].as_array().unwrap()) {
        let (x, y) = (p["KII"].as_f64().unwrap(), q["KII"].as_f64().unwrap());
        assert!(close(x, y), "K_II: {x} against {y}");
    }
}

/// A condensed contact solve that fails its residual check is redone with the plain LDLᵀ
/// of the whole system, and the run says so (issue 11: the recovery path, which no
/// ordinary case of the suite reaches since the decoupled rows of the crack block; see
/// the test above). The failure is injected with the developer's switch
/// `FISSURE_FAULT_CONDENSED_SOLVE`, which negates every dense solve of the condensed
/// factor, so the residual check itself must catch it. Case: the closed 45° crack of
/// `common::contact::inclined_crack` (σ = 1, 2a = 0.4, μ = 0.3, quad4 41 × 41).
/// Reference: the same case with `[solver] condense = false`. Tolerance: λ range and K_II
/// at both tips equal to 1e-10 relative (the same factorisation, the same loops), status
/// ok, one warning naming the step and the fallback; without the switch, no such warning.
#[test]
fn a_condensed_solve_that_fails_its_residual_check_falls_back_to_the_plain_factor() {
    let text = common::contact::inclined_crack(0.3, 41, "");
    let fallback = |s: &serde_json::Value| -> Vec<String> {
        s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|w| w.as_str())
            .filter(|w| w.contains("condensed contact factor lost accuracy"))
            .map(str::to_string)
            .collect()
    };
    let faulty = common::run_cli_with_env(
        "contact_numerics",
        "fault_condensed",
        &text,
        &[("FISSURE_FAULT_CONDENSED_SOLVE", "1")],
    );
    let normal = common::run_cli("contact_numerics", "fault_none", &text);
    let plain = common::run_cli("contact_numerics", "fault_plain", &format!("{text}\n[solver]\ncondense = false\n"));
    assert_eq!(faulty["status"], "ok");
    let w = fallback(&faulty);
    assert!(w.len() == 1 && w[0].starts_with("step 1:") && w[0].contains("plain LDLᵀ"), "warnings: {w:?}");
    assert!(fallback(&normal).is_empty(), "no fault, no fallback: {:?}", fallback(&normal));
    let (a, b) = (&faulty["steps"][0], &plain["steps"][0]);
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-10 * y.abs().max(1e-12);
    for key in ["lambda_min", "lambda_max"] {
        let (x, y) = (a["contact"][key].as_f64().unwrap(), b["contact"][key].as_f64().unwrap());
        assert!(close(x, y), "{key}: {x} against {y}");
    }
    let fronts = (a["cracks"][0]["front"].as_array().unwrap(), b["cracks"][0]["front"].as_array().unwrap());
    assert_eq!(fronts.0.len(), 2);
    for (p, q) in fronts.0.iter().zip(fronts.1) {
        let (x, y) = (p["KII"].as_f64().unwrap(), q["KII"].as_f64().unwrap());
        assert!(close(x, y), "K_II: {x} against {y}");
    }
}

/// A first-pass friction threshold far above every stress of the model gives the answer of
/// the default one (issue 11 item 14). Geometry and loads of the adversarial family
/// "contact parameters" (`tests/adversarial.rs`): block [0, 1]², quad4 6 × 6, E = 1,
/// ν = 0.3, plane strain, u_y = 0 on the bottom, u_x = 0 on the left, pressure p = 0.01 on
/// the top, a frictional interface (μ = 0.5) across it at y = 0.53. Reference: uniform
/// σ_yy = −p, so λ = −p at every contact point (1e-5 relative), and λ equal to the run with
/// the default threshold (0) to 1e-8 relative, for thresholds 1 (= E), 1e12 and 1e300.
/// Before: 1e12 failed as a singular matrix blaming the supports (the stick terms μλ̄ were
/// 1e12 times the stiffness); thresholds above the largest E now act as E.
#[test]
fn a_huge_initial_threshold_gives_the_answer_of_the_default_one() {
    let p = 0.01;
    let case = |extra: &str| {
        format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [1.0, 1.0]\ndivisions = [6, 6]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"y\"]\n[[dirichlet]]\ngroup = \"left\"\ncomponents = [\"x\"]\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, -{p}]\n[[cracks]]\nname = \"i\"\nshape = \"line\"\npoint = [0.5, 0.53]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n{extra}\n"
        )
    };
    let base = solve_contact_text(&case("")).expect("default threshold");
    assert!(!base.lambda.is_empty());
    for th in ["1.0", "1e12", "1e300"] {
        let r = solve_contact_text(&case(&format!("initial_threshold = {th}")))
            .unwrap_or_else(|e| panic!("initial_threshold = {th}: {e}"));
        assert_eq!(r.lambda.len(), base.lambda.len());
        for (l, l0) in r.lambda.iter().zip(&base.lambda) {
            assert!((l + p).abs() < 1e-5 * p, "initial_threshold = {th}: λ = {l}, expected {}", -p);
            assert!((l - l0).abs() < 1e-8 * p, "initial_threshold = {th}: λ = {l}, default {l0}");
        }
    }
}

/// `rho_n` far above E/h (issue 11 items 9 and 14). On the closed 45° crack of
/// `common::contact::inclined_crack` (plate [−2, 2]², quad4 41 × 41, E = 1, μ = 0.3,
/// h = 4/41, E/h = 10.25) the pointwise law stopped on an answer that depends on ρ_n
/// (measured, `docs/reliability.md`: K_II 17% off at 1e3 E/h, status ok; the projected
/// augmentation above E/h removed that, [`closed_45_degree_crack_k_ii_does_not_depend_on_rho_n`],
/// but the edge of a contact zone is still sensitive) and the solve failed from 1e7 E/h,
/// blaming the supports (`rho_n = 1e12`). Reference behaviour: `rho_n = 1e12`
/// (1e11 E/h) is refused when the model is built, the error naming the key
/// `cracks[0].contact.rho_n`, the line of `rho_n`, the ratio and the admissible bound (1e6 E/h);
/// `rho_n = 1e4` (976 E/h) is accepted with a warning naming the crack and `rho_n`; the
/// default (E/h) and `rho_n = 100` (9.8 E/h) give no such warning.
#[test]
fn a_rho_n_far_above_e_over_h_is_refused_and_a_large_one_is_reported() {
    use fissure::case::{resolve, Case};
    let text = |extra: &str| common::contact::inclined_crack(0.3, 41, extra);
    let case = Case::parse(&text("rho_n = 1e12\n"), std::path::Path::new("case.toml")).expect("parses");
    let mesh = resolve::build_mesh(&case).expect("mesh");
    let model = resolve::build_model(&case, &mesh).expect("model");
    let Err(e) = resolve::build_contact(&case, &model) else { panic!("rho_n = 1e12 must be refused") };
    assert_eq!(e.key, "cracks[0].contact.rho_n", "{e}");
    let rho_line = text("rho_n = 1e12\n").lines().position(|l| l.starts_with("rho_n")).map(|i| i + 1);
    assert_eq!(e.line, rho_line, "the line of rho_n: {e}");
    assert!(e.message.contains("crack 'c'") && e.message.contains("times E/h") && e.message.contains("1e6"), "{e}");
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("rho_n_range");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, extra, warned) in
        [("large", "rho_n = 1e4\n", true), ("default", "", false), ("moderate", "rho_n = 100.0\n", false)]
    {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text(extra)).unwrap();
        let report = fissure::run::check_case(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let w = report.warnings.iter().any(|w| w.contains("crack 'c'") && w.contains("rho_n"));
        assert_eq!(w, warned, "{name}: {:?}", report.warnings);
    }
}

/// A fixed `rho_t` so small that the stick/slip labels are wrong (found by a hostile-user
/// audit, 2026-11-28). On the closed 45° crack of `common::contact::inclined_crack` (plate
/// [−2, 2]², quad4 41 × 41, E = 1, μ = 0.3, every point sliding; h = 4/41) the answer does
/// not depend on ρ_τ (K_II −0.200636 / −0.252576 at ρ_τ = 1e-12, 1e-8, 1e-6 and 1,
/// measured), but at 1e-12 all 24 sliding points were reported stick, at 1e-8 13 of 24.
/// Reference behaviour: `check` warns (naming the crack and `rho_t`) below 1e-6/h
/// (`rho_t = 1e-8`), not at 1e-4 (1e-5/h) nor with the default; and at `rho_t = 1e-4` the
/// run reports every point sliding (0 stick), as with the default.
#[test]
fn a_tiny_fixed_rho_t_is_reported_and_a_small_one_labels_sliding_points_slip() {
    let text = |extra: &str| common::contact::inclined_crack(0.3, 41, extra);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("rho_t_labels");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, extra, warned) in
        [("tiny", "rho_t = 1e-8\n", true), ("small", "rho_t = 1e-4\n", false), ("default", "", false)]
    {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text(extra)).unwrap();
        let report = fissure::run::check_case(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let w = report.warnings.iter().any(|w| w.contains("crack 'c'") && w.contains("rho_t"));
        assert_eq!(w, warned, "{name}: {:?}", report.warnings);
    }
    let r = solve_contact_text(&text("rho_t = 1e-4\n")).expect("rho_t = 1e-4 solves");
    let stick = r.status.iter().filter(|s| matches!(s, fissure::contact::law::Status::Stick)).count();
    let slip = r.status.iter().filter(|s| matches!(s, fissure::contact::law::Status::Slip)).count();
    assert!(stick == 0 && slip > 0, "rho_t = 1e-4: {stick} points reported stick, {slip} slip");
}

/// The sliding block of [`sliding_block_obeys_coulomb_for_every_stiffness_to_load_ratio`]
/// at E/p = 1e4 (quad4 20 × 21, E = 1, ν = 0.3, plane strain, p = 1e-4, μ = 0.5,
/// u_x = 0.001 t at the top, t = 1 … 10; it slides from step 1 and its trailing edge lifts
/// off) with `rho_n` = 1e6 and 2.04e7, 4.9e4 and 1.0e6 times E/h = 20.488 (the largest the
/// run accepts). Reference: the default ρ_n's answer (Coulomb, |R_x| = μ R_y while every
/// point slides: 0.499975 on 54 closed points) and Coulomb itself. Tolerance: |R_x|/R_y
/// within 1e-4 relative of μ at every step (measured 0.49999992 and 0.4999999961); the
/// closed points within 8 of the default's (one multiplier packet of the straight
/// interface holds 8 points; measured 52 against 54); every point slides; the active-set
/// iterations of a step within [2, 40] (measured 31 at step 1, 2 and 10 at the later ones).
/// Before the active-set loop closed cycles longer than 2, both failed at step 1 with "30
/// iterations, 1 status still changing": 4 edge points cycled with period 4 (4, 2, 1, 1
/// changes), which the 2-cycle rule did not catch.
/// OPEN, ignored (2026-11-28): closing cycles of any period made this pass, but the same
/// rule ended the first step of `contact_scales.rs`'s steel block (started from a
/// threshold far above its pressure) on |R_x|/R_y = 0.532 for μ = 0.5 with status ok, so
/// it was withdrawn; at these ρ_n the loop fails again, naming ρ_n as the likely cause
/// (`a_contact_loop_failing_at_a_rho_n_far_above_e_over_h_blames_rho_n`).
#[test]
#[ignore = "open: a longer status cycle at a rho_n far above E/h fails the active-set loop"]
fn sliding_block_at_a_rho_n_up_to_1e6_e_over_h_gives_the_defaults_answer() {
    let text = |extra: &str| {
        format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [1.0, 0.5]\ndivisions = [20, 21]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = 0.001\n[[traction]]\ngroup = \"top\"\nvalue = [\"0\", \"-1e-4 + 0 * t\"]\n[steps]\nfactors = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\n{extra}"
        )
    };
    let closed = |r: &common::contact::ContactRun| r.steps.last().unwrap().contact.as_ref().unwrap().active;
    let default = solve_contact_text(&text("")).unwrap_or_else(|e| panic!("default: {e}"));
    for rho in ["1e6", "2.04e7"] {
        let r = solve_contact_text(&text(&format!("rho_n = {rho}\n"))).unwrap_or_else(|e| panic!("rho_n = {rho}: {e}"));
        for (k, s) in r.steps.iter().enumerate() {
            let c = s.contact.as_ref().unwrap();
            let ratio = s.reactions[0][0].abs() / s.reactions[0][1];
            eprintln!(
                "rho_n = {rho} step {}: |R_x|/R_y {ratio:.9}, {} closed, {} stick ({:?} passes/AS/Newton)",
                k + 1,
                c.active,
                c.stick,
                (c.friction, c.active_set, c.newton)
            );
            assert!((ratio - 0.5).abs() <= 0.5e-4, "rho_n = {rho} step {}: |R_x|/R_y {ratio}", k + 1);
            assert_eq!(c.stick, 0, "rho_n = {rho} step {}: the block slides", k + 1);
            assert!(
                (2..=40).contains(&c.active_set),
                "rho_n = {rho} step {}: {} active-set iterations",
                k + 1,
                c.active_set
            );
        }
        let (a, b) = (closed(&r), closed(&default));
        assert!(a.abs_diff(b) <= 8, "rho_n = {rho}: {a} closed points, the default {b}");
    }
}

/// The failure message of a contact loop at a ρ_n far above E/h names ρ_n as the likely
/// cause and the value that works. Case: the sliding block of
/// [`sliding_block_at_a_rho_n_up_to_1e6_e_over_h_gives_the_defaults_answer`] with
/// `rho_n = 1e6` (4.9e4 E/h) and `max_active_set = 3` (it needs 31 in step 1), run as a
/// user runs it (`run::run_case`). Reference behaviour: the run fails with the active-set
/// loop's message followed by the crack, its ρ_n as a multiple of E/h, "likely cause", and
/// the default E/h and the 100 E/h bound; with `rho_n = 100` (4.9 E/h) the same cap fails
/// without that advice (ρ_n is not the cause there).
#[test]
fn a_contact_loop_failing_at_a_rho_n_far_above_e_over_h_blames_rho_n() {
    use fissure::run::{run_case, RunOptions};
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("rho_n_blamed");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, rho, blamed) in [("large", "1e6", true), ("moderate", "100.0", false)] {
        let text = format!(
            "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [1.0, 0.5]\ndivisions = [20, 21]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\"]\nvalue = 0.001\n[[traction]]\ngroup = \"top\"\nvalue = [\"0\", \"-1e-4 + 0 * t\"]\n[steps]\nfactors = [1]\n[output]\nvtu = false\nplots = false\n[contact_solver]\nmax_active_set = 3\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n[cracks.contact]\nfriction = 0.5\nrho_n = {rho}\n"
        );
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let Err(err) = run_case(&path, &dir.join(name), &RunOptions::default()) else {
            panic!("{name}: 3 active-set iterations are not enough")
        };
        let err = err.to_string();
        eprintln!("{name}: {err}");
        assert!(err.contains("active set loop did not converge in 3 iterations"), "{err}");
        let advice = err.contains("crack 'interface' has rho_n")
            && err.contains("times E/h = 2.0488e1")
            && err.contains("likely cause")
            && err.contains("remove rho_n")
            && err.contains("100 E/h");
        assert_eq!(advice, blamed, "{name}: {err}");
    }
}
