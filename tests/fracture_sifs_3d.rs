//! Stress intensity factors along 3D crack fronts against published references.
//! Material: E = 1, ν = 0.3; remote stress σ = 1.

mod common;

use common::fracture::{feddersen, penny_case, slab, solve_text};
use std::f64::consts::PI;

/// Through-thickness centre crack in a slab with plane-strain constraints, against the 2D
/// value. Geometry: slab [−5, 5] × [−10, 10] × [0, 0.5] (hex8, 81 × 161 × 2 cells), crack
/// 2a = 2 along y = 0 through the whole thickness (a rectangle crack wider than the slab,
/// so the fronts are the lines x = ±1 and the parts of the front outside the body are
/// ignored). Loads: σ = 1 on y = ±10; u_z = 0 on z = 0 and z = 0.5 (plane strain).
/// Reference: the 2D plane-strain value, K_I = σ√(πa)·F(a/b) with Feddersen's F(0.2)
/// (Tada handbook), which the 2D test reproduces to 0.2%. Tolerance 2% at every front point;
/// K_II and K_III below 1e-3 σ√(πa).
#[test]
fn through_crack_slab_plane_strain_k1_matches_2d_within_2pct() {
    let text = &slab(5.0);
    let r = solve_text(text);
    let reference = PI.sqrt() * feddersen(0.2);
    assert!(r.sifs[0].len() >= 2, "both fronts");
    for s in &r.sifs[0] {
        let err = s.k1 / reference - 1.0;
        eprintln!(
            "front point {:?}: K_I {:.5} ({:+.3}%), K_II {:.1e}, K_III {:.1e}",
            s.x,
            s.k1,
            100.0 * err,
            s.k2,
            s.k3
        );
        assert!(err.abs() < 2e-2, "{:.3}%", 100.0 * err);
        assert!(s.k2.abs() < 1e-3 * reference && s.k3.abs() < 1e-3 * reference);
    }
}

/// Penny-shaped crack under remote tension (Sneddon 1946; Tada handbook): a disc of radius
/// a = 1 in the plane z = 0 at the centre of the block [−5, 5]³ (side 10a), Gmsh tet4 mesh
/// meshes/penny_block.msh graded to 0.09 at the front. Load σ = 1 on z = ±5; rigid modes
/// removed by three corner points. Reference: K_I = 2σ√(a/π) along the whole front
/// (infinite body). Tolerance 3% at every front point (K_II, K_III below 2% of K_I).
/// Domain radius 0.25 (≈ 2.8 front cells), tip enrichment radius 0.25.
#[test]
fn penny_crack_k1_within_3pct_along_the_front() {
    let text = penny_case("[[traction]]\ngroup = \"front\"\nvalue = [0.0, 0.0, 1.0]\n[[traction]]\ngroup = \"back\"\nvalue = [0.0, 0.0, -1.0]");
    let r = solve_text(&text);
    let reference = 2.0 / PI.sqrt();
    let pts = &r.sifs[0];
    assert!(pts.len() >= 16, "points along the front: {}", pts.len());
    let mut worst = 0.0f64;
    for s in pts {
        let rho = (s.x[0] * s.x[0] + s.x[1] * s.x[1]).sqrt();
        // Points lie on the discrete front (chords of the circle within cells): h²/(8a) ≈ 1e-3.
        assert!((rho - 1.0).abs() < 2e-3 && s.x[2].abs() < 1e-9, "front point off the circle: {:?}", s.x);
        let err = s.k1 / reference - 1.0;
        worst = worst.max(err.abs());
        assert!(s.k2.abs() < 0.02 * reference && s.k3.abs() < 0.02 * reference, "K_II {} K_III {}", s.k2, s.k3);
    }
    let mean = pts.iter().map(|s| s.k1).sum::<f64>() / pts.len() as f64;
    eprintln!(
        "penny: {} points, mean K_I {:.5} ({:+.2}%), worst {:.2}%",
        pts.len(),
        mean,
        100.0 * (mean / reference - 1.0),
        100.0 * worst
    );
    assert!(worst < 3e-2, "worst front point {:.2}%", 100.0 * worst);
}

/// Pressurised penny crack (Sneddon 1946): the block and mesh of the previous test without
/// remote load, pressure p = 1 on both crack faces. Reference K_I = 2p√(a/π) (infinite body).
/// Tolerance 3% at every front point. Exercises the crack-face traction term of the 3D
/// interaction integral (a cut-off keeps the far side of the front out of each point's
/// face integral: without it K_I came out 1.7× too large).
#[test]
fn pressurised_penny_crack_k1_within_3pct_along_the_front() {
    let text = penny_case("") + "pressure = 1.0\n";
    let r = solve_text(&text);
    let reference = 2.0 / PI.sqrt();
    let worst = r.sifs[0].iter().map(|s| (s.k1 / reference - 1.0).abs()).fold(0.0, f64::max);
    let mean = r.sifs[0].iter().map(|s| s.k1).sum::<f64>() / r.sifs[0].len() as f64;
    eprintln!(
        "pressurised penny: mean K_I {mean:.4} ({:+.2}%), worst {:.2}%",
        100.0 * (mean / reference - 1.0),
        100.0 * worst
    );
    assert!(worst < 3e-2, "worst {:.2}%", 100.0 * worst);
}

/// Penny-shaped crack under pure shear (Kassir & Sih 1966; Tada handbook): the block, mesh
/// and crack of the tension test (a = 1 in z = 0, block [−5, 5]³, tet4 graded to 0.09 at
/// the front, E = 1, ν = 0.3, tip enrichment radius 0.25), no contact. Load: σ_xz = τ = 0.5
/// (traction ±τ along x on z = ±5, ±τ along z on x = ±5). Reference (infinite body), with φ
/// the polar angle of the front point from the x axis:
/// K_II = 4τ√(a/π)/(2 − ν) cos φ, K_III = 4(1 − ν)τ√(a/π)/(2 − ν) sin φ — Kassir & Sih's
/// K_III with the sign of fissure's frame (e3 = e1 × n = −e_φ on this front), K_I = 0.
/// Checked at the domain radii 0.15 and 0.5: at every front point K_II and K_III within 5% of
/// their amplitudes (the curvature terms of the interaction integral matter here: without
/// them K_II came out 7% and 23% low, |K_III| 15% and 36% low at these radii), |K_I| below
/// 1% of the K_II amplitude. Measured worst errors (K_II / K_III): 1.4% / 2.7% at 0.15,
/// 2.8% / 3.3% at 0.5 (without the 3D blending ramp of `src/enrich/mod.rs`: 3.5% / 3.0%
/// and 2.8% / 3.2%).
#[test]
fn penny_crack_under_shear_k2_k3_within_5pct_of_kassir_sih() {
    let tau = 0.5;
    let nu = 0.3;
    let k2_amp = 4.0 * tau / PI.sqrt() / (2.0 - nu);
    let k3_amp = (1.0 - nu) * k2_amp;
    let load = "[[traction]]\ngroup = \"front\"\nvalue = [0.5, 0.0, 0.0]\n[[traction]]\ngroup = \"back\"\nvalue = [-0.5, 0.0, 0.0]\n\
                [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, 0.5]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, -0.5]";
    for radius in [0.15, 0.5] {
        let text = penny_case(load).replace("sif_radius = 0.25", &format!("sif_radius = {radius}"));
        let r = solve_text(&text);
        let pts = &r.sifs[0];
        assert!(pts.len() >= 10, "points along the front: {}", pts.len());
        let (mut w2, mut w3) = (0.0f64, 0.0f64);
        for s in pts {
            let phi = s.x[1].atan2(s.x[0]);
            let e2 = (s.k2 - k2_amp * phi.cos()) / k2_amp;
            let e3 = (s.k3 - k3_amp * phi.sin()) / k3_amp;
            w2 = w2.max(e2.abs());
            w3 = w3.max(e3.abs());
            assert!(s.k1.abs() < 0.01 * k2_amp, "K_I {} at {:?}", s.k1, s.x);
        }
        eprintln!(
            "penny under shear, radius {radius}: {} points, worst K_II {:.2}%, worst K_III {:.2}% (of the amplitudes)",
            pts.len(),
            100.0 * w2,
            100.0 * w3
        );
        assert!(w2 < 0.05 && w3 < 0.05, "radius {radius}: K_II {:.2}%, K_III {:.2}%", 100.0 * w2, 100.0 * w3);
    }
}

/// Penny-shaped crack closed by compression and sheared, with Coulomb friction (the set-up
/// of examples/penny_crack_contact_3d.toml): the block, mesh and crack of the tension test
/// (a = 1 in z = 0, block [−5, 5]³, tet4 graded to 0.09 at the front, E = 1, ν = 0.3, tip
/// enrichment radius 0.25, domain radius 0.25), contact on the crack faces with μ = 0.2
/// (vital-edge multipliers, Gauss integration). Loads: compression σ = 1 (∓1 along z on
/// z = ±5) plus the shear τ = 0.5 of the previous test. Since τ > μσ the lips slide along x
/// everywhere. Reference (Kassir & Sih 1966, infinite body, uniform frictional sliding):
/// the effective shear τ − μσ = 0.3 in the K_II and K_III of the previous test, K_I = 0.
/// Tolerances: every contact point in contact and slipping, the friction semi-multiplier a
/// unit vector along +x at every point (|Λ − e_x| < 1e-3: it opposes the slip through
/// λ < 0) and τ1 = e_x on every facet; K_II and K_III within 5% of their amplitudes at
/// every front point, |K_I| below 3% of the K_II amplitude. Measured: all 12 928 points
/// slip, ||Λ| − 1| ≤ 5e-6, |Λ_y| ≤ 0.011; worst K_II 1.60% (mean −0.14%), worst K_III
/// 3.21% (mean −0.02%), |K_I| ≤ 0.90% over the 25 front points (without the 3D blending
/// ramp: 1.15%, 2.08%, 1.97%). Those are with `multiplier_stabilisation = 0` (the default); with
/// γ₀ = 10: worst K_II 1.64% (mean −0.14%), K_III 3.22% (mean
/// −0.02%), |K_I| ≤ 0.82%, ||Λ| − 1| ≤ 5.5e-6, |Λ_y| ≤ 0.011.
/// Before the tangent basis was chosen per crack, τ1 was e_x on about half of the facets
/// and e_y on the others (the facet normals of this flat crack carry round-off in x and
/// y, and the axis was picked per facet), so the packets' Λ components mixed two frames:
/// |Λ| 0.74–1.0, 841 points reported sticking, and K_II 9–17%, |K_III| 13–24% above the
/// reference.
#[test]
fn closed_penny_crack_sliding_with_friction_k2_k3_within_5pct_of_kassir_sih() {
    let (tau, mu, sigma, nu) = (0.5, 0.2, 1.0, 0.3);
    let k2_amp = 4.0 * (tau - mu * sigma) / PI.sqrt() / (2.0 - nu);
    let k3_amp = (1.0 - nu) * k2_amp;
    let load = "[[traction]]\ngroup = \"front\"\nvalue = [0.5, 0.0, -1.0]\n[[traction]]\ngroup = \"back\"\nvalue = [-0.5, 0.0, 1.0]\n\
                [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, 0.5]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, -0.5]";
    let text = penny_case(load) + "[cracks.contact]\nfriction = 0.2\n";
    let r = common::contact::solve_contact_text(&text).unwrap_or_else(|e| panic!("{e:?}"));
    let n = r.status.len();
    let slip = r.status.iter().filter(|s| **s == fissure::contact::law::Status::Slip).count();
    assert_eq!(slip, n, "slipping points: {slip} of {n}");
    let (mut worst_norm, mut worst_y) = (0.0f64, 0.0f64);
    for (l, t) in r.big_lambda.iter().zip(&r.tangent) {
        assert!((t[0] - 1.0).abs() < 1e-12, "τ1 {t:?}");
        assert!(l[0] > 0.0, "Λ {l:?}");
        worst_norm = worst_norm.max(((l[0] * l[0] + l[1] * l[1]).sqrt() - 1.0).abs());
        worst_y = worst_y.max(l[1].abs());
    }
    eprintln!("||Λ| − 1| ≤ {worst_norm:.2e}, |Λ_y| ≤ {worst_y:.2e}");
    assert!(worst_norm < 1e-3 && worst_y < 0.05, "||Λ| − 1| up to {worst_norm:.2e}, |Λ_y| up to {worst_y:.2e}");
    let pts = &r.sifs[0];
    assert!(pts.len() >= 10, "points along the front: {}", pts.len());
    let (mut w1, mut w2, mut w3, mut m2, mut m3) = (0.0f64, 0.0f64, 0.0f64, 0.0, 0.0);
    for s in pts {
        let phi = s.x[1].atan2(s.x[0]);
        let e2 = (s.k2 - k2_amp * phi.cos()) / k2_amp;
        let e3 = (s.k3 - k3_amp * phi.sin()) / k3_amp;
        w1 = w1.max(s.k1.abs() / k2_amp);
        w2 = w2.max(e2.abs());
        w3 = w3.max(e3.abs());
        m2 += e2 / pts.len() as f64;
        m3 += e3 / pts.len() as f64;
    }
    eprintln!(
        "penny with friction: {n} points slipping; {} front points, worst K_II {:.2}% (mean {:+.2}%), worst K_III {:.2}% (mean {:+.2}%), |K_I| ≤ {:.2}% (of the amplitudes)",
        pts.len(),
        100.0 * w2,
        100.0 * m2,
        100.0 * w3,
        100.0 * m3,
        100.0 * w1
    );
    assert!(w2 < 0.05 && w3 < 0.05, "K_II {:.2}%, K_III {:.2}%", 100.0 * w2, 100.0 * w3);
    assert!(w1 < 0.03, "K_I {:.2}%", 100.0 * w1);
}

/// The 45° through crack of a slab held in plane strain by u_z = 0 on both faces, against
/// the 2D plane-strain run of the same mesh; the front ends on the held faces, whose term
/// of the interaction integral this checks (`src/post/sif.rs`, "Faces the front ends on").
/// Geometry: plate [−2, 2]² (quad4 41 × 41 in 2D; hex8 41 × 41 × nz in 3D, thickness t),
/// crack 2a = 1 at 45° centred at (0.0123, 0.0071) (off the node lines), a through
/// rectangle in 3D. Material E = 1, ν = 0.3. Loads: σ_yy = 1 on y = ±2 (open crack, K_I
/// and K_II); x, y held at the corner (−2, −2), y at (2, −2); in 3D u_z = 0 on z = 0 and
/// z = t (enriched unknowns too, `physics::held_faces`). Tip radius 0.2, domain radius 0.2
/// (two cells): (nz, t) = (1, 0.4) and (2, 0.4), two front points on each front, (4, 0.8),
/// four. Reference: the 2D problem extruded (in-plane field uniform through the thickness,
/// u_z ≡ 0): K_I and K_II equal to the 2D run's, K_III = 0 at every front point.
/// Tolerances: |K_III| < 1e-3 |K_II| (measured ≤ 2.2e-4), K_I and K_II within 0.1% of
/// the 2D tip's at the same end (measured ≤ 0.075%). Without the held faces' term (they
/// were left out like free faces) K_III was ∓0.35 = 52% of K_II at nz = 1.
/// `[xfem] tip_degree = 12` (both runs): with the default 6 the 3D solve's own quadrature
/// of the tip cells (sub-tetrahedra, not symmetric in z) leaves the discrete in-plane field
/// not quite uniform through the thickness, and K_III = 3.9e-3 K_II at nz = 1 whatever the
/// SIF's quadrature (raising only the SIF's volume degree to 12 left 2.2e-3; raising the
/// solve's took it to 1.9e-4).
#[test]
fn plane_strain_slab_with_held_faces_has_no_k3() {
    let n = 41;
    // The solve's quadrature on tip-enriched cells (module doc of the test).
    let extra = "[xfem]\ntip_degree = 12\n";
    let b = 45f64.to_radians();
    let (c, s) = (b.cos(), b.sin());
    let common = "[[materials]]\nE = 1.0\nnu = 0.3\n\
         [[sets]]\nname = \"pin\"\non = \"abs(x+2) + abs(y+2)\"\n[[sets]]\nname = \"roller\"\non = \"abs(x-2) + abs(y+2)\"\n\
         [[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n";
    let two_d = format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [-2.0, -2.0]\nupper = [2.0, 2.0]\ndivisions = [{n}, {n}]\n\
         {common}[[traction]]\ngroup = \"top\"\nvalue = [0.0, 1.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, -1.0]\n\
         [[cracks]]\nname = \"c\"\nshape = \"segment\"\na = [{ax}, {ay}]\nb = [{bx}, {by}]\ntip_radius = 0.2\nsif_radius = 0.2\n{extra}",
        ax = 0.0123 - 0.5 * c,
        ay = 0.0071 - 0.5 * s,
        bx = 0.0123 + 0.5 * c,
        by = 0.0071 + 0.5 * s,
    );
    let r2 = solve_text(&two_d);
    for p in &r2.sifs[0] {
        eprintln!("2D tip {:?}: K_I {:+.6} K_II {:+.6}", p.x, p.k1, p.k2);
    }
    for (nz, t, points) in [(1, 0.4, 2), (2, 0.4, 2), (4, 0.8, 4)] {
        let three_d = format!(
            "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [-2.0, -2.0, 0.0]\nupper = [2.0, 2.0, {t}]\ndivisions = [{n}, {n}, {nz}]\n\
             {common}[[dirichlet]]\ngroup = \"front\"\ncomponents = [\"z\"]\n[[dirichlet]]\ngroup = \"back\"\ncomponents = [\"z\"]\n\
             [[traction]]\ngroup = \"top\"\nvalue = [0.0, 1.0, 0.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, -1.0, 0.0]\n\
             [[cracks]]\nname = \"c\"\nshape = \"rectangle\"\ncentre = [0.0123, 0.0071, {zc}]\nnormal = [{nx}, {c}, 0.0]\n\
             axis_u = [{c}, {s}, 0.0]\nhalf_lengths = [0.5, 5.0]\ntip_radius = 0.2\nsif_radius = 0.2\n{extra}",
            zc = 0.5 * t,
            nx = -s,
        );
        let r3 = solve_text(&three_d);
        assert_eq!(r3.sifs[0].len(), 2 * points, "nz = {nz}, t = {t}: {points} points on each front");
        for p in &r3.sifs[0] {
            // The 2D tip at the same end (the 2D frame's e2 is −n at the end a: K_II
            // compares in magnitude, K_I in value).
            let q = r2.sifs[0]
                .iter()
                .min_by(|a, b| {
                    (a.x[0] - p.x[0]).hypot(a.x[1] - p.x[1]).total_cmp(&(b.x[0] - p.x[0]).hypot(b.x[1] - p.x[1]))
                })
                .unwrap();
            let (e1, e2) = (p.k1 / q.k1 - 1.0, p.k2.abs() / q.k2.abs() - 1.0);
            eprintln!(
                "nz = {nz}, t = {t}: front point {:?}: K_I {:+.6} ({:+.4}%) K_II {:+.6} ({:+.4}%) K_III {:+.2e} ({:.1e} K_II)",
                p.x,
                p.k1,
                100.0 * e1,
                p.k2,
                100.0 * e2,
                p.k3,
                p.k3.abs() / q.k2.abs()
            );
            assert!(p.k3.abs() < 1e-3 * q.k2.abs(), "nz = {nz}, t = {t}: K_III {} against K_II {}", p.k3, q.k2);
            assert!(
                e1.abs() < 1e-3 && e2.abs() < 1e-3,
                "nz = {nz}, t = {t}: K_I {}, K_II {} against 2D {}, {}",
                p.k1,
                p.k2,
                q.k1,
                q.k2
            );
        }
    }
}

/// An edge through crack (`half_plane`, front x = 0.3, plane y = 1/32) in the slab
/// [0, 1] × [−1, 1] × [0, 0.25] with free faces z = 0, 0.25, hex8 16 × 32 × 8, σ = 1 on
/// y = ±1, held by three corner points against the rigid modes in two ways (the second
/// lets the body take another rigid rotation), E = 1, ν = 0 and ν = 0.3. Reference: K_III
/// = 0 by symmetry (the field is plane strain for ν = 0), asserted |K_III| < 1e-3 K_I at
/// every front point, and K_I the same for both supports to 1e-5 (measured 1.4e-6 at
/// ν = 0.3: the supports' discrete fields differ by more than a rigid motion). Found by a hostile-user
/// audit (2026-11-28): K_III = ±0.1766 (11% of K_I) with one set of supports, ±0.005 with
/// the other, status ok: the mode-III face term of the interaction integral (σ^aux_α3
/// u_α,1 on a free face the front ends on) was left out, and it is what makes the domain
/// integral blind to a rigid rotation. Measured now ≤ 4e-5.
#[test]
fn through_crack_k3_is_zero_whatever_rigid_rotation_the_supports_allow() {
    let case = |nu: f64, second: &str| {
        format!(
            "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [0.0, -1.0, 0.0]\nupper = [1.0, 1.0, 0.25]\ndivisions = [16, 32, 8]\n\
             [[materials]]\nE = 1.0\nnu = {nu}\n\
             [[sets]]\nname = \"p0\"\non = \"abs(x) + abs(y + 1) + abs(z)\"\n\
             [[sets]]\nname = \"p1\"\non = \"{second}\"\n\
             [[sets]]\nname = \"p2\"\non = \"abs(x) + abs(y + 1) + abs(z - 0.25)\"\n\
             [[dirichlet]]\ngroup = \"p0\"\ncomponents = [\"x\", \"y\", \"z\"]\n\
             [[dirichlet]]\ngroup = \"p1\"\ncomponents = {}\n\
             [[dirichlet]]\ngroup = \"p2\"\ncomponents = [\"x\", \"y\"]\n\
             [[traction]]\ngroup = \"top\"\nvalue = [0.0, 1.0, 0.0]\n\
             [[traction]]\ngroup = \"bottom\"\nvalue = [0.0, -1.0, 0.0]\n\
             [[cracks]]\nname = \"c\"\nshape = \"half_plane\"\npoint_on_front = [0.3, 0.03125, 0.0]\n\
             normal = [0.0, 1.0, 0.0]\ndirection = [1.0, 0.0, 0.0]\n",
            if second.contains("x - 1") { "[\"y\", \"z\"]" } else { "[\"x\"]" }
        )
    };
    for nu in [0.0, 0.3] {
        let mut k1 = vec![];
        for second in ["abs(x - 1) + abs(y + 1) + abs(z)", "abs(x) + abs(y - 1) + abs(z)"] {
            let r = solve_text(&case(nu, second));
            let pts = &r.sifs[0];
            assert!(!pts.is_empty());
            for p in pts {
                eprintln!("ν = {nu}, supports {second}: {:?} K_I {:.6} K_III {:.2e}", p.x, p.k1, p.k3);
                assert!(p.k3.abs() < 1e-3 * p.k1.abs(), "ν = {nu}, {second}: K_III {} vs K_I {}", p.k3, p.k1);
            }
            k1.push(pts.iter().map(|p| p.k1).collect::<Vec<_>>());
        }
        for (a, b) in k1[0].iter().zip(&k1[1]) {
            assert!((a / b - 1.0).abs() < 1e-5, "ν = {nu}: K_I {a} vs {b}");
        }
    }
}
