//! A semi-elliptical surface crack grown in fatigue (issue 21, item 7, "3D,
//! semi-elliptical surface crack"): its aspect ratio a/c against the cycles, against the
//! Newman–Raju-based integration of the Paris law at the deepest and the surface points.
//!
//! Geometry (`meshes/surface_crack_growth.geo`): plate x ∈ [−5, 5] (width 2b = 10),
//! y ∈ [−5, 5] (height 2h = 10, the load direction), z ∈ [0, 5] (thickness t = 5); crack
//! in the plane y = 0 on the face z = t, initial depth a0 = 0.6 and half-length c0 = 1
//! (a/c = 0.6, a/t = 0.12, c/b = 0.2): an `elliptic_disc` centred at (0, 0, t) with
//! semi-axes (c0, a0), half of it outside the plate. The mesh is tet4 of size hf over the
//! half elliptic disc of semi-axes (1.55, 1.2) thickened by 0.25 (where the front passes),
//! growing to 0.8 away. Material E = 1, ν = 0.3. Load: σ = 1 on y = ±h, R = 0; three
//! corner points of the face z = 0 hold the rigid-body motions. Paris law
//! da/dN = C ΔK^m with C = 1e-3, m = 3 (units of E = σ = 1); increments of Δa_max at the
//! point of largest ΔK, the others by (ΔK/ΔK_max)^m.
//!
//! Reference: the two-degree-of-freedom integration of the Paris law used with the
//! Newman–Raju equation since Newman & Raju (1981) (e.g. Newman, J. C. Jr. & Raju, I. S.,
//! "Prediction of fatigue crack-growth patterns and lives in three-dimensional cracked
//! bodies", ICF6, 1984; the NASGRO surface-crack model): the front stays a semi-ellipse,
//! da/dN = C ΔK_A^m at the deepest point A (φ = 90°) and dc/dN = C ΔK_C^m at the surface
//! point C (φ = 0), here by fourth-order Runge–Kutta in steps of 0.05 cycles from
//! (a0, c0). K from Newman, J. C. Jr. & Raju, I. S., "An empirical stress-intensity factor
//! equation for the surface crack", Eng. Fract. Mech. 15 (1981) 185–192, tension,
//! a/c ≤ 1:
//!
//! ```text
//! K = σ √(π a / Q) F(a/c, a/t, c/b, φ)
//! Q   = 1 + 1.464 (a/c)^1.65
//! F   = [M1 + M2 (a/t)² + M3 (a/t)⁴] g f_φ f_w
//! M1  = 1.13 − 0.09 (a/c)
//! M2  = −0.54 + 0.89 / (0.2 + a/c)
//! M3  = 0.5 − 1 / (0.65 + a/c) + 14 (1 − a/c)^24
//! g   = 1 + [0.1 + 0.35 (a/t)²] (1 − sin φ)²
//! f_φ = [(a/c)² cos²φ + sin²φ]^¼
//! f_w = [sec(π c / (2b) · √(a/t))]^½
//! ```
//!
//! From (0.6, 1) the deepest point grows faster (K_C/K_A = 0.86 at a/c = 0.6) and a/c rises
//! towards the ratio near 0.8 where K_A ≈ K_C: 0.692 at N = 100, 0.763 at N = 200.
//!
//! Measured: a and c of each entry are the semi-axes of the ellipse
//! (x/c)² + ((t − z)/a)² = 1 fitted (least squares in 1/c², 1/a²) to its SIF points, and
//! its cycles `steps[e].cracks[0].growth.cycles`; the reference a/c is the integration's
//! at those cycles. Tolerance (the issue's): |a/c / (a/c)_NR − 1| ≤ 5% at every entry.
//! How fissure treats the front ends (docs/conventions.md, "Crack growth"): the front is
//! the loop of the initial ellipse, its outer half outside the plate; the points whose
//! SIF domain is cut by the face (closer to it than sif_radius) are not trusted, and their
//! K_eq and that of the front ends on the face are the linear extrapolation along the
//! front of the K_eq inside.
//!
//! The CI test (`surface_crack_fatigue_grows_towards_newman_raju_shape_coarse`, the
//! committed coarse mesh `meshes/surface_crack_growth_coarse.msh`, hf = 0.15) runs two
//! increments of 0.15 and checks the ends of the front stay on the face and the shape moves the
//! right way (a/c up, towards the reference); the study (ignored; it generates the hf = 0.1
//! mesh with gmsh) runs four increments of 0.1 and checks the 5%.
//!
//! Measured (2026-11-27, release, load 7–11): coarse, 28.6 s, a/c 0.604, 0.682, 0.745
//! against 0.600, 0.693, 0.753 (worst −1.56%); study (26 811 dofs, 53 s), a/c 0.601,
//! 0.661, 0.711, 0.753, 0.786 against 0.600, 0.664, 0.713, 0.750, 0.778 (worst +1.14%).
//! a and c themselves fall 8–9% behind the integration at the same cycles (K_I is 2–3%
//! below Newman–Raju all along the front on these meshes, −6 to −9% in the rate; a bias
//! uniform along the front leaves a/c alone): not checked. docs/performance.md,
//! "Crack growth (issue 21)".

#[path = "common/cli.rs"]
mod cli;
#[path = "common/newman_raju.rs"]
mod newman_raju;

use cli::fissure;
use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Duration;

const T: f64 = 5.0;
const B: f64 = 5.0;
const A0: f64 = 0.6;
const C0: f64 = 1.0;
const PARIS_C: f64 = 1e-3;
const PARIS_M: f64 = 3.0;

/// Newman–Raju K (σ = 1, tension, a/c ≤ 1) at the parametric angle `phi` of this plate.
fn newman_raju(a: f64, c: f64, phi: f64) -> f64 {
    newman_raju::k1(a, c, T, B, phi)
}

/// (a, c) at `cycles` by the Newman–Raju Paris integration from (A0, C0) (RK4, dN = 0.05).
fn reference(cycles: f64) -> (f64, f64) {
    let rate = |a: f64, c: f64| {
        (PARIS_C * newman_raju(a, c, 0.5 * PI).powf(PARIS_M), PARIS_C * newman_raju(a, c, 0.0).powf(PARIS_M))
    };
    let (mut a, mut c, mut n) = (A0, C0, 0.0);
    let dn: f64 = 0.05;
    while n < cycles {
        let h = dn.min(cycles - n);
        let k1 = rate(a, c);
        let k2 = rate(a + 0.5 * h * k1.0, c + 0.5 * h * k1.1);
        let k3 = rate(a + 0.5 * h * k2.0, c + 0.5 * h * k2.1);
        let k4 = rate(a + h * k3.0, c + h * k3.1);
        a += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        c += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        n += h;
    }
    (a, c)
}

fn case(mesh: &Path, radius: f64, increment: f64, steps: usize) -> String {
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
[output]
vtu = false
[[cracks]]
name = "surface"
shape = "elliptic_disc"
centre = [0.0, 0.0, {T}]
normal = [0.0, 1.0, 0.0]
major_axis = [1.0, 0.0, 0.0]
semi_axes = [{C0}, {A0}]
tip_radius = {radius}
sif_radius = {radius}
[propagation]
increment = {increment}
steps = {steps}
[propagation.fatigue]
C = {PARIS_C}
m = {PARIS_M}
"#,
        mesh = mesh.display()
    )
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// One entry: cycles, fitted (a, c), the SIF points (x, z), and the fit's largest
/// residual |(x/c)² + (d/a)² − 1|.
struct Entry {
    cycles: f64,
    a: f64,
    c: f64,
    points: Vec<(f64, f64)>,
    residual: f64,
}

/// The ellipse (x/c)² + (d/a)² = 1, d = t − z, through the points by least squares in
/// (u, v) = (1/c², 1/a²).
fn fit(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let (mut sxx, mut sxy, mut syy, mut bx, mut by) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(x, z) in points {
        let (p, q) = (x * x, (T - z).powi(2));
        sxx += p * p;
        sxy += p * q;
        syy += q * q;
        bx += p;
        by += q;
    }
    let det = sxx * syy - sxy * sxy;
    let u = (bx * syy - by * sxy) / det;
    let v = (sxx * by - sxy * bx) / det;
    let residual = points.iter().map(|&(x, z)| (x * x * u + (T - z).powi(2) * v - 1.0).abs()).fold(0.0, f64::max);
    (1.0 / v.sqrt(), 1.0 / u.sqrt(), residual)
}

/// Runs the case and reads every entry.
fn grow(name: &str, text: &str) -> Vec<Entry> {
    let o = fissure("surface_crack_fatigue", name, text, false, Duration::from_secs(3600));
    assert_eq!(o.code, Some(0), "{name}: {}", o.stderr);
    let s = o.summary.expect("summary.json");
    assert_eq!(s["status"], "ok", "{name}: {}", s["warnings"]);
    let warnings = s["warnings"].to_string();
    assert!(!warnings.contains("reached the boundary") && !warnings.contains("growth stopped"), "{warnings}");
    s["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            let crack = &e["cracks"][0];
            let points: Vec<(f64, f64)> =
                crack["front"].as_array().unwrap().iter().map(|p| (f(&p["x"][0]), f(&p["x"][2]))).collect();
            let (a, c, residual) = fit(&points);
            Entry { cycles: f(&crack["growth"]["cycles"]), a, c, points, residual }
        })
        .collect()
}

/// Prints the entries against the reference; returns the worst a/c error.
fn compare(name: &str, entries: &[Entry]) -> f64 {
    let mut worst = 0.0f64;
    for (k, e) in entries.iter().enumerate() {
        let (ra, rc) = reference(e.cycles);
        let err = (e.a / e.c) / (ra / rc) - 1.0;
        eprintln!(
            "{name} entry {k}: N = {:8.3}, a = {:.4} (NR {:.4}, {:+.2}%), c = {:.4} (NR {:.4}, {:+.2}%), a/c = {:.4} (NR {:.4}, {:+.2}%), {} points, fit residual {:.1e}",
            e.cycles,
            e.a,
            ra,
            100.0 * (e.a / ra - 1.0),
            e.c,
            rc,
            100.0 * (e.c / rc - 1.0),
            e.a / e.c,
            ra / rc,
            100.0 * err,
            e.points.len(),
            e.residual
        );
        if err.abs() > worst.abs() {
            worst = err;
        }
    }
    worst
}

/// Checks that hold on every mesh: both ends of the front reach the face (the SIF points
/// nearest it, on each side, within `near` of it and inside the plate), the crack grows at
/// both the deepest point and along the face at every entry, and a/c rises.
fn check_growth(entries: &[Entry], near: f64) {
    for (k, e) in entries.iter().enumerate() {
        assert!(e.points.iter().all(|p| p.1 <= T + 1e-9), "entry {k}: a point outside the plate");
        for side in [-1.0, 1.0] {
            let shallowest =
                e.points.iter().filter(|p| p.0 * side > 0.0).map(|p| T - p.1).fold(f64::INFINITY, f64::min);
            assert!(shallowest < near, "entry {k}: the front's end on side {side} is {shallowest} below the face");
        }
        // The front is a smooth half ellipse (the fit's largest residual).
        assert!(e.residual < 0.08, "entry {k}: fit residual {}", e.residual);
    }
    for (k, w) in entries.windows(2).enumerate() {
        assert!(w[1].cycles > w[0].cycles, "cycles at entry {}", k + 1);
        assert!(
            w[1].a > w[0].a && w[1].c > w[0].c,
            "entry {}: a {} → {}, c {} → {}",
            k + 1,
            w[0].a,
            w[1].a,
            w[0].c,
            w[1].c
        );
        assert!(w[1].a / w[1].c > w[0].a / w[0].c, "entry {}: a/c must rise", k + 1);
    }
}

fn mesh_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes").join(name)
}

/// CI: the coarse mesh (hf = 0.15, sif_radius 0.3), two increments of 0.15.
#[test]
fn surface_crack_fatigue_grows_towards_newman_raju_shape_coarse() {
    let entries = grow("coarse", &case(&mesh_path("surface_crack_growth_coarse.msh"), 0.3, 0.15, 2));
    assert_eq!(entries.len(), 3);
    let worst = compare("coarse", &entries);
    check_growth(&entries, 0.3);
    assert!(worst.abs() < 0.05, "worst a/c {:+.2}%", 100.0 * worst);
}

/// The study: the hf = 0.1 mesh made by gmsh (sif_radius 0.25), four increments of 0.1
/// (a from 0.6 to about 1.0); a/c within 5% of the Newman–Raju integration at every entry.
#[test]
#[ignore]
fn surface_crack_fatigue_aspect_ratio_within_5pct_of_newman_raju_integration() {
    let dir = std::env::temp_dir().join(format!("fissure_surface_fatigue_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = dir.join("surface_crack_growth.msh");
    let ok = std::process::Command::new("gmsh")
        .args(["-3", "-format", "msh41", "-nt", "1"])
        .arg(mesh_path("surface_crack_growth.geo"))
        .arg("-o")
        .arg(&mesh)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    assert!(ok, "gmsh failed or is not on the PATH");
    let t = std::time::Instant::now();
    let entries = grow("fine", &case(&mesh, 0.25, 0.1, 4));
    eprintln!("fine: {:.1} s", t.elapsed().as_secs_f64());
    assert_eq!(entries.len(), 5);
    let worst = compare("fine", &entries);
    check_growth(&entries, 0.25);
    assert!(worst.abs() < 0.05, "worst a/c {:+.2}%", 100.0 * worst);
}

/// Study (issue 21, the cycles): does the K bias near the deepest point shrink with the
/// mesh? The initial crack (a0 = 0.6, c0 = 1, sif_radius = tip_radius = 0.3 on every
/// mesh) solved once on `meshes/surface_crack_growth.geo` at front sizes hf = 0.15 (the
/// committed coarse mesh), 0.1 and 0.075 (made by gmsh); K_I at the deepest SIF point
/// (largest parametric angle φ) against Newman–Raju at that φ. Measured (2026-11-27,
/// load 12): 0.9508 (13 086 dofs, φ = 81°), 0.9641 (25 557, φ = 81°), 0.9658 (46 464,
/// φ = 90°): the bias shrinks, from −4.9% to −3.4%, and slower at each refinement (the
/// domain radius is held at 0.3, not scaled with hf; Newman–Raju itself is a fit within
/// about ±5% of the finite-element K it was drawn from). Checked: the ratio rises at each
/// refinement.
#[test]
#[ignore]
fn surface_crack_deepest_point_k_bias_against_newman_raju_shrinks_with_the_front_size() {
    let dir = std::env::temp_dir().join(format!("fissure_surface_bias_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut ratios = vec![];
    for hf in [0.15, 0.1, 0.075] {
        let mesh = if hf == 0.15 {
            mesh_path("surface_crack_growth_coarse.msh")
        } else {
            let mesh = dir.join(format!("surface_crack_growth_{hf}.msh"));
            let ok = std::process::Command::new("gmsh")
                .args(["-3", "-format", "msh41", "-nt", "1", "-setnumber", "hf", &hf.to_string()])
                .arg(mesh_path("surface_crack_growth.geo"))
                .arg("-o")
                .arg(&mesh)
                .output()
                .map(|o| o.status.success())
                .unwrap_or(false);
            assert!(ok, "gmsh failed or is not on the PATH");
            mesh
        };
        let text = case(&mesh, 0.3, 0.1, 1);
        let text = text.split("[propagation]").next().unwrap();
        let o = fissure("surface_crack_bias", &format!("hf{hf}"), text, false, Duration::from_secs(3600));
        assert_eq!(o.code, Some(0), "hf {hf}: {}", o.stderr);
        let s = o.summary.expect("summary.json");
        let front = s["steps"][0]["cracks"][0]["front"].as_array().unwrap().clone();
        let (phi, ratio) = front
            .iter()
            .map(|p| {
                let (x, z) = (f(&p["x"][0]), f(&p["x"][2]));
                let phi = ((T - z) / A0).atan2(x.abs() / C0);
                (phi, f(&p["KI"]) / newman_raju(A0, C0, phi))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap();
        eprintln!("hf {hf}: {} dofs, K_I / K_NR at φ = {:.1}°: {ratio:.4}", s["dofs"]["total"], phi.to_degrees());
        ratios.push(ratio);
    }
    assert!(ratios.windows(2).all(|w| w[1] > w[0]), "the bias does not shrink: {ratios:?}");
}
