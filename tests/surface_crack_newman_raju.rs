//! K_I along a semi-elliptical surface crack in a plate under remote tension, against the
//! Newman–Raju (1981) equation (issue 17, item 3).
//!
//! Geometry (`meshes/surface_crack_plate.geo`): plate x ∈ [−5, 5] (width 2b = 10),
//! y ∈ [−5, 5] (height 2h = 10, the load direction), z ∈ [0, 5] (thickness t = 5); crack in
//! the plane y = 0 on the face z = t, depth a = 1, half-length c = 1: a `elliptic_disc`
//! centred at (0, 0, t) with semi-axes (c, a), half of it outside the plate (ignored by
//! fissure). Front: x = c cos φ, z = t − a sin φ, φ ∈ [0, π] the parametric angle (φ = 0, π
//! at the free surface, φ = π/2 at the deepest point). a/c = 1, a/t = 0.2, c/b = 0.2.
//! Material E = 1, ν = 0.3. Load: traction σ = 1 on y = ±h; three corner points of the
//! face z = 0 hold the rigid-body motions (no other support). Full plate, no symmetry
//! plane: a symmetry plane x = 0 crossed by the crack would hold only the standard dofs
//! (Dirichlet conditions act on the standard part, `docs/conventions.md`), and y = 0 is the
//! crack itself.
//!
//! Reference: Newman, J. C. Jr. & Raju, I. S., "An empirical stress-intensity factor
//! equation for the surface crack", Eng. Fract. Mech. 15 (1981) 185–192 (also NASA
//! TM-83200, 1981), equations for tension, a/c ≤ 1:
//!
//! ```text
//! K = σ √(π a / Q) F(a/c, a/t, c/b, φ)
//! Q   = 1 + 1.464 (a/c)^1.65                           (shape factor, ellipse perimeter)
//! F   = [M1 + M2 (a/t)² + M3 (a/t)⁴] g f_φ f_w
//! M1  = 1.13 − 0.09 (a/c)
//! M2  = −0.54 + 0.89 / (0.2 + a/c)
//! M3  = 0.5 − 1 / (0.65 + a/c) + 14 (1 − a/c)^24
//! g   = 1 + [0.1 + 0.35 (a/t)²] (1 − sin φ)²
//! f_φ = [(a/c)² cos²φ + sin²φ]^¼
//! f_w = [sec(π c / (2b) · √(a/t))]^½                    (finite width)
//! ```
//!
//! Here Q = 2.464 and K(90°) = 1.1891, K(18°) = 1.2538 (σ = 1, a = 1). Newman and Raju
//! state the equation within ±5% of their finite-element results (Raju & Newman 1979) for
//! 0 < a/c ≤ 1, a/t < 0.8, c/b < 0.5. The case chosen is where it is most reliable: a
//! shallow (a/t = 0.2) semicircular crack in a wide plate (c/b = 0.2, f_w = 1.005), where
//! the back face and the width barely matter (M2, M3 terms 0.8% of F), the equation
//! matches their finite-element values to about 1–2%, and other independent solutions
//! of the semicircular surface crack agree with it to the same order; larger a/t and a/c
//! far from 1 lean more on the fit.
//!
//! Points compared: the SIF points of the front whose parametric angle
//! φ = atan2((t − z)/a, x/c) lies in [18°, 162°], the inner 80% of the front's parametric
//! range (the points nearer the free surface are printed, not checked: there the 3D
//! corner singularity makes K fall towards the surface, which the equation does not
//! model, and the SIF domain, of radius 0.25, is cut by the face). Tolerance: 3% at every
//! such point (the issue's figure); K_II and K_III below 1% of the reference.
//!
//! Mesh `meshes/surface_crack_plate.msh`: tet4 graded to 0.09 at the front (5390 nodes);
//! tip_radius = sif_radius = 0.25. Measured (release, 2 cores at load 10): 27 408 dofs, 41 s
//! wall (16 s CPU), 11 points checked, worst −1.96% at φ = 62.3°, mean −1.13%; the two
//! points outside (φ = 6.9°, 173.1°) are −4.5% and −4.7%.
//!
//! Refinement (`surface_crack_refinement_study`, ignored: needs gmsh on the PATH), the worst
//! and mean error over the points of [18°, 162°]:
//!
//! | front size hf | radius | dofs | points | worst | mean |
//! |---|---|---|---|---|---|
//! | 0.2 (`surface_crack_plate_coarse.msh`, the example's) | 0.4 | 7 803 | 6 | −3.14% | −2.42% |
//! | 0.09 (`surface_crack_plate.msh`, this test) | 0.25 | 27 408 | 11 | −1.96% | −1.16% |
//! | 0.06 (gmsh, hd = 0.08) | 0.25 | 62 586 | 11 | −1.53% | −0.92% |
//!
//! The points near 20° and 160° approach the equation with refinement (−0.6% → −0.3/−0.5%)
//! while the deepest point stays at −1.4/−1.5%: a difference of the order of the
//! equation's own fit to its finite-element data, not a mesh error (`docs/performance.md`,
//! "Semi-elliptical surface crack").

mod common;

use common::fracture::solve_text;
use std::path::Path;

const A: f64 = 1.0;
const C: f64 = 1.0;
const T: f64 = 5.0;
const B: f64 = 5.0;

/// Newman–Raju K_I for tension (σ = 1) at the parametric angle `phi` (rad) of this crack.
fn newman_raju(phi: f64) -> f64 {
    common::newman_raju::k1(A, C, T, B, phi)
}

/// The case: the plate of `mesh` under σ = 1 with the surface crack, domain and tip
/// enrichment radius `radius`.
fn case(mesh: &Path, radius: f64) -> String {
    format!(
        r#"
[mesh]
file = "{mesh}"
[[materials]]
E = 1.0
nu = 0.3
[[sets]]
name = "p1"
on = "abs(x+5) + abs(y+5) + abs(z)"
[[sets]]
name = "p2"
on = "abs(x-5) + abs(y+5) + abs(z)"
[[sets]]
name = "p3"
on = "abs(x+5) + abs(y-5) + abs(z)"
[[dirichlet]]
group = "p1"
components = ["x", "y", "z"]
[[dirichlet]]
group = "p2"
components = ["y", "z"]
[[dirichlet]]
group = "p3"
components = ["z"]
[[traction]]
group = "top"
value = [0.0, 1.0, 0.0]
[[traction]]
group = "bottom"
value = [0.0, -1.0, 0.0]
[[cracks]]
name = "surface"
shape = "elliptic_disc"
centre = [0.0, 0.0, {T}]
normal = [0.0, 1.0, 0.0]
major_axis = [1.0, 0.0, 0.0]
semi_axes = [{C}, {A}]
tip_radius = {radius}
sif_radius = {radius}
"#,
        mesh = mesh.display()
    )
}

/// What one mesh gives over the checked points: (dofs, checked points as
/// (φ in degrees, K_I, reference), worst and mean relative error there).
struct Comparison {
    dofs: usize,
    checked: Vec<(f64, f64, f64)>,
    worst: f64,
    mean: f64,
}

/// Solves the plate on `mesh`, prints every front point against Newman–Raju and checks
/// that the points lie on the front ellipse and that K_II, K_III stay small.
fn compare(mesh: &Path, radius: f64) -> Comparison {
    let r = solve_text(&case(mesh, radius));
    let pts = &r.sifs[0];
    let mut rows: Vec<(f64, f64, f64)> = vec![];
    for s in pts {
        let [x, y, z] = s.x;
        // On the front: y = 0 and (x/c)² + ((t − z)/a)² = 1 up to the chords of the
        // discrete front within its cells (h²/(8a) ≈ 1e-3 at h = 0.09).
        let rho = ((x / C).powi(2) + ((T - z) / A).powi(2)).sqrt();
        assert!(y.abs() < 1e-9 && (rho - 1.0).abs() < 5e-3, "front point off the ellipse: {:?}", s.x);
        assert!(z <= T + 1e-9, "front point outside the plate: {:?}", s.x);
        let phi = ((T - z) / A).atan2(x / C);
        let reference = newman_raju(phi);
        eprintln!(
            "φ = {:6.2}°: K_I {:.4}, Newman–Raju {:.4} ({:+.2}%), K_II {:+.1e}, K_III {:+.1e}",
            phi.to_degrees(),
            s.k1,
            reference,
            100.0 * (s.k1 / reference - 1.0),
            s.k2,
            s.k3
        );
        if (18.0..=162.0).contains(&phi.to_degrees()) {
            assert!(
                s.k2.abs() < 0.01 * reference && s.k3.abs() < 0.01 * reference,
                "K_II {} K_III {} at φ = {:.1}°",
                s.k2,
                s.k3,
                phi.to_degrees()
            );
            rows.push((phi.to_degrees(), s.k1, reference));
        }
    }
    let errs: Vec<f64> = rows.iter().map(|&(_, k, r)| k / r - 1.0).collect();
    let worst = errs.iter().copied().fold(0.0f64, |w, e| if e.abs() > w.abs() { e } else { w });
    let mean = errs.iter().sum::<f64>() / errs.len().max(1) as f64;
    Comparison { dofs: r.dofs, checked: rows, worst, mean }
}

fn mesh_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes").join(name)
}

#[test]
fn surface_crack_plate_k1_within_3pct_of_newman_raju_over_the_inner_80pct() {
    let c = compare(&mesh_path("surface_crack_plate.msh"), 0.25);
    eprintln!(
        "surface crack: {} dofs, {} points in [18°, 162°], worst {:+.2}%, mean {:+.2}%",
        c.dofs,
        c.checked.len(),
        100.0 * c.worst,
        100.0 * c.mean
    );
    assert!(c.checked.len() >= 9, "points in [18°, 162°]: {:?}", c.checked);
    // Both halves of the front are checked, and the deepest region.
    assert!(c.checked.iter().any(|p| p.0 < 45.0) && c.checked.iter().any(|p| p.0 > 135.0));
    assert!(c.checked.iter().any(|p| (p.0 - 90.0).abs() < 15.0));
    assert!(c.worst.abs() < 0.03, "worst point {:+.2}%", 100.0 * c.worst);
}

/// The refinement table of the header: the coarse and the committed mesh, and a finer one
/// made by gmsh from `meshes/surface_crack_plate.geo` (hf = 0.06, hd = 0.08).
#[test]
#[ignore]
fn surface_crack_refinement_study() {
    let dir = std::env::temp_dir().join(format!("fissure_surface_crack_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fine = dir.join("surface_crack_plate_fine.msh");
    let ok = std::process::Command::new("gmsh")
        .args(["-3", "-format", "msh41", "-nt", "1", "-setnumber", "hf", "0.06", "-setnumber", "hd", "0.08"])
        .arg(mesh_path("surface_crack_plate.geo"))
        .arg("-o")
        .arg(&fine)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    assert!(ok, "gmsh failed or is not on the PATH");
    let rows = [
        ("0.2", mesh_path("surface_crack_plate_coarse.msh"), 0.4),
        ("0.09", mesh_path("surface_crack_plate.msh"), 0.25),
        ("0.06", fine, 0.25),
    ];
    let mut table = vec![];
    for (hf, mesh, radius) in rows {
        let t = std::time::Instant::now();
        let c = compare(&mesh, radius);
        table.push(format!(
            "| {hf} | {radius} | {} | {} | {:+.2}% | {:+.2}% | {:.1} s |",
            c.dofs,
            c.checked.len(),
            100.0 * c.worst,
            100.0 * c.mean,
            t.elapsed().as_secs_f64()
        ));
        assert!(c.worst.abs() < 0.035, "hf {hf}: worst {:+.2}%", 100.0 * c.worst);
    }
    eprintln!("| hf | radius | dofs | points | worst | mean | time |");
    for row in table {
        eprintln!("{row}");
    }
}
