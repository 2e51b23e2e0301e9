//! Contact pressure of closed 3D cracks that slide, against the uniform pressure of the
//! remote compression, near the fronts included (issue 17, item 2;
//! `docs/contact-algorithms.md`, "3D sliding cracks: the pressure near the fronts").
//!
//! Tests: the penny crack closed by compression (pointwise) and sheared (ring averages),
//! the through crack of a slab under compression and shear (pointwise, the 3D covering
//! default), and that default's node budget; the raw multipliers pointwise with the
//! local-projection stabilisation (`multiplier_stabilisation`) on the sliding penny and the
//! slab.
//!
//! Diagnostics (ignored; `cargo test --release --test contact_pressure_3d -- --ignored
//! --nocapture NAME`):
//! - `diag_penny`: the pressure profile of the penny crack of
//!   `examples/penny_crack_contact_3d.toml` against the distance to the front, for `DIAG_R`
//!   (tip radius, default 0.25; `default` for none), `DIAG_MU` (friction, default 0),
//!   `DIAG_TAU` (shear, default 0.5), `DIAG_MESH` (mesh file, default
//!   `meshes/penny_block.msh`) and `DIAG_EXTRA` (case text appended after the crack's
//!   contact table, `\n` for new lines);
//! - `diag_slab`: the same for the slab, `DIAG_R` (default 0.2), `DIAG_MU`, `DIAG_N`,
//!   `DIAG_NZ`, `DIAG_T` (thickness, default 0.1), `DIAG_FACES=strain` (u_z = 0 on both
//!   faces instead of free faces), `DIAG_EXTRA` (as for the penny), with the pressure per z
//!   and the SIFs;
//! - `diag_penny_count`: the tip radius and enriched node counts for `DIAG_R` (a
//!   comma-separated list), without solving.
mod common;

use common::contact::{solve_contact_text, ContactRun};
use common::penny_block::{penny_block, penny_block_mesh, PENNY_DISC};
use fissure::contact::recovery::{Recovery, RECOVERY_CELLS};
use std::time::Instant;

const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The penny crack closed by σ and sheared by τ (the loads of the example), friction `mu`,
/// on `mesh`, tip radius `tip` (`None`: the default).
fn penny_contact(mesh: &str, sigma: f64, tau: f64, mu: f64, tip: Option<f64>) -> String {
    let loads = format!(
        "[[traction]]\ngroup = \"front\"\nvalue = [{tau}, 0.0, {ms}]\n[[traction]]\ngroup = \"back\"\nvalue = [{mt}, 0.0, {sigma}]\n\
         [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, {tau}]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, {mt}]",
        ms = -sigma,
        mt = -tau
    );
    let text = penny_block(mesh, &loads, PENNY_DISC);
    let text = match tip {
        Some(r) => text.replace("tip_radius = 0.25\n", &format!("tip_radius = {r}\n")),
        None => text.replace("tip_radius = 0.25\n", ""),
    };
    text + &format!("[cracks.contact]\nfriction = {mu}\n")
}

/// Pressure / `p_ref` − 1 per contact point, with its distance `d` to the front.
struct Profile {
    d: Vec<f64>,
    err: Vec<f64>,
    w: Vec<f64>,
}

impl Profile {
    fn of(r: &ContactRun, p_ref: f64, dist: impl Fn([f64; 3]) -> f64) -> Self {
        Profile {
            d: r.x.iter().map(|&x| dist(x)).collect(),
            err: r.lambda.iter().map(|l| -l / p_ref - 1.0).collect(),
            w: r.weight.clone(),
        }
    }
    /// The same for the pressure recovered from the run's multipliers ([`recovered`]).
    fn recovered(r: &ContactRun, p_ref: f64, dist: impl Fn([f64; 3]) -> f64) -> Self {
        Profile {
            d: r.x.iter().map(|&x| dist(x)).collect(),
            err: recovered(r).iter().map(|p| p / p_ref - 1.0).collect(),
            w: r.weight.clone(),
        }
    }
    /// The signed extremes (min, max) of the error over the points with d in [lo, hi).
    fn range(&self, lo: f64, hi: f64) -> (f64, f64, usize) {
        let mut out = (f64::INFINITY, f64::NEG_INFINITY, 0);
        for (d, e) in self.d.iter().zip(&self.err) {
            if *d >= lo && *d < hi {
                out = (out.0.min(*e), out.1.max(*e), out.2 + 1);
            }
        }
        out
    }
    /// The weighted mean error over the points with d in [lo, hi) (the ring's force).
    fn mean(&self, lo: f64, hi: f64) -> f64 {
        let (mut f, mut a) = (0.0, 0.0);
        for ((d, e), w) in self.d.iter().zip(&self.err).zip(&self.w) {
            if *d >= lo && *d < hi {
                f += e * w;
                a += w;
            }
        }
        f / a
    }
    fn print(&self, label: &str) {
        let bands = [0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 1.01];
        let mut s = String::new();
        for w in bands.windows(2) {
            let (lo, hi, n) = self.range(w[0], w[1]);
            let m = self.mean(w[0], w[1]);
            s += &format!(
                " [{:.2},{:.2}) {:+.2}%..{:+.2}% mean {:+.2}% ({n});",
                w[0],
                w[1],
                100.0 * lo,
                100.0 * hi,
                100.0 * m
            );
        }
        let rings: Vec<String> = (0..10)
            .map(|k| {
                format!("{:+.2}", 100.0 * self.mean(0.1 * k as f64, 0.1 * (k + 1) as f64 + 0.01 * f64::from(k == 9)))
            })
            .collect();
        s += &format!("\n  ring averages (0.1 a, %): {}", rings.join(" "));
        let (lo, hi, n) = self.range(0.1, 10.0);
        let (alo, ahi, an) = self.range(-1.0, 10.0);
        eprintln!(
            "{label}: all {:+.2}%..{:+.2}% ({an}); d ≥ 0.1: {:+.2}%..{:+.2}% ({n})\n  bands:{s}",
            100.0 * alo,
            100.0 * ahi,
            100.0 * lo,
            100.0 * hi
        );
    }
}

/// The pressure recovered at every contact point (`contact::recovery`: the local linear fit of
/// −λ over `RECOVERY_CELLS` cells; the run's `h` is the crack's cell size, one crack).
fn recovered(r: &ContactRun) -> Vec<f64> {
    let pts = (0..r.x.len()).map(|i| (r.x[i], r.weight[i], -r.lambda[i])).collect();
    let rec = Recovery::new(3, RECOVERY_CELLS * r.h, pts);
    r.x.iter().zip(&r.normal).map(|(x, n)| rec.at(*x, *n).expect("points in the window")).collect()
}

/// Penny-shaped crack closed by compression alone: no slip. Geometry and mesh of
/// `examples/penny_crack_contact_3d.toml` (a = 1 in z = 0, block [−5, 5]³, tet4 graded to
/// 0.09 at the front, `meshes/penny_block.msh`), E = 1, ν = 0.3, tip radius 0.25, μ = 0.
/// Load: σ = 1 (∓1 along z on z = ±5). Reference: the lips transmit the remote stress,
/// pressure −λ = σ at every contact point (the crack changes nothing). Tolerances: every
/// point in contact; |p/σ − 1| ≤ 1% at every point farther than 0.1 a from the front (one
/// front-cell layer, 0.09, plus a margin: the front cells are excluded as in 2D, their
/// multipliers sit on the singular field) and ≤ 2% in the front cells. Measured: ≤ 0.71%
/// beyond 0.1 a, −1.41%..+1.16% in the front cells, ≤ 0.02% beyond 0.3 a.
#[test]
fn penny_crack_closed_by_compression_pressure_within_1pct_beyond_the_front_cells() {
    // γ₀ = 0: the raw multipliers without the stabilisation (the 3D default since
    // 2026-11-28), whose figures the header gives.
    let r = solve_contact_text(
        &(penny_contact(&penny_block_mesh(), 1.0, 0.0, 0.0, Some(0.25)) + "multiplier_stabilisation = 0\n"),
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert!(r.contact.iter().all(|c| *c), "every point in contact");
    let p = Profile::of(&r, 1.0, |x| 1.0 - x[0].hypot(x[1]));
    p.print("penny, σ alone");
    let (lo, hi, n) = p.range(0.1, 10.0);
    assert!(n > 1000, "points beyond 0.1 a: {n}");
    assert!(lo > -0.01 && hi < 0.01, "beyond 0.1 a: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
    let (lo, hi, _) = p.range(-1.0, 0.1);
    assert!(lo > -0.02 && hi < 0.02, "front cells: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
}

/// Penny-shaped crack closed by compression and sheared: the loads of
/// `examples/penny_crack_contact_3d.toml` (σ = 1 across the crack, τ = 0.5 in the x–z
/// plane) with μ = 0 and with the example's μ = 0.2 (τ > μσ: every point slides along x).
/// Geometry, mesh and material of the previous test, tip radius 0.25. Reference: pressure
/// −λ = σ everywhere (the slip, antisymmetric about the crack plane, puts no normal stress
/// on it; Kassir & Sih's sliding penny). Tolerances: every point in contact; the pressure
/// averaged over each ring of width 0.1 a (weighted by the contact points' areas: the
/// normal force the ring transmits) within 1% of σ (measured ≤ 0.36% at μ = 0, ≤ 0.22% at
/// μ = 0.2); pointwise within 12% at μ = 0 (measured −10.9% … +11.0%,
/// largest at 0.2–0.4 a from the front where the tip-enriched zone ends, ±5.5% in the
/// middle of the disc) and 8% at μ = 0.2 (measured −6.5% … +6.6%: the effective shear
/// τ − μσ is 0.3). The issue's 1% pointwise is not met (`docs/contact-algorithms.md`, "3D
/// sliding cracks: the pressure near the fronts"); the bounds keep the oscillation from
/// growing.
#[test]
fn sliding_penny_crack_ring_averaged_pressure_within_1pct() {
    for (mu, pointwise) in [(0.0, 0.12), (0.2, 0.08)] {
        // γ₀ = 0: the raw multipliers without the stabilisation, as the header says.
        let r = solve_contact_text(
            &(penny_contact(&penny_block_mesh(), 1.0, 0.5, mu, Some(0.25)) + "multiplier_stabilisation = 0\n"),
        )
        .unwrap_or_else(|e| panic!("{e:?}"));
        assert!(r.contact.iter().all(|c| *c), "μ = {mu}: every point in contact");
        let p = Profile::of(&r, 1.0, |x| 1.0 - x[0].hypot(x[1]));
        p.print(&format!("sliding penny, μ = {mu}"));
        for k in 0..10 {
            let (lo, hi) = (0.1 * k as f64, 0.1 * (k + 1) as f64);
            let m = p.mean(lo, if k == 9 { 1.01 } else { hi });
            assert!(m.abs() < 0.01, "μ = {mu}, ring {lo:.2}–{hi:.2} a from the front: mean {:+.2}%", 100.0 * m);
        }
        let (lo, hi, _) = p.range(-1.0, 10.0);
        assert!(lo > -pointwise && hi < pointwise, "μ = {mu}: pointwise {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
    }
}

/// With `DIAG_DUMP=FILE`, writes every contact point (x, y, z, −λ, weight, slip, its first
/// multiplier packet) as CSV for offline analysis.
fn dump(r: &ContactRun) {
    let Ok(file) = std::env::var("DIAG_DUMP") else { return };
    let mut s = String::from("x,y,z,p,w,sx,sy,sz,packet,npk\n");
    let last = r.history.last().expect("a step");
    for (i, x) in r.x.iter().enumerate() {
        let j = r.material_jump[i];
        let t = &last[i].terms;
        let pk = t.iter().max_by(|a, b| a.1.partial_cmp(&b.1).unwrap()).map_or(u32::MAX, |t| t.0);
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            x[0],
            x[1],
            x[2],
            -r.lambda[i],
            r.weight[i],
            j[0],
            j[1],
            j[2],
            pk,
            t.len()
        );
    }
    std::fs::write(&file, s).expect("DIAG_DUMP");
}

/// The pressure recovered from the multipliers (`contact::recovery`: at each point the
/// local linear fit of −λ, weighted by the points' areas and a tricube kernel, over a window
/// of three cells) of the sliding penny crack of `examples/penny_crack_contact_3d.toml`:
/// geometry, mesh, material and loads of the previous test (a = 1, tet4 0.09 at the front,
/// σ = 1, τ = 0.5), tip radius 0.25, μ = 0 and the example's μ = 0.2 (every point slides).
/// Reference: pressure σ uniform (Kassir & Sih's sliding penny: the slip, antisymmetric
/// about the crack plane, puts no normal stress on it). Tolerances: the recovered pressure
/// within 1% of σ at every contact point farther than 0.1 a from the front (one front-cell
/// layer and a margin, as the other tests here; the raw multipliers there are ±11% at
/// μ = 0, `docs/contact-algorithms.md`, "3D contact pressure pointwise: the recovered
/// pressure") and within 3% in the front cells; the raw ring averages (0.1 a wide) within
/// 0.5% and the recovered ones within 0.5%.
#[test]
fn sliding_penny_crack_recovered_pressure_within_1pct_beyond_the_front_cells() {
    for mu in [0.0, 0.2] {
        // γ₀ = 0: the raw multipliers without the stabilisation, as the header says.
        let r = solve_contact_text(
            &(penny_contact(&penny_block_mesh(), 1.0, 0.5, mu, Some(0.25)) + "multiplier_stabilisation = 0\n"),
        )
        .unwrap_or_else(|e| panic!("{e:?}"));
        assert!(r.contact.iter().all(|c| *c), "μ = {mu}: every point in contact");
        let dist = |x: [f64; 3]| 1.0 - x[0].hypot(x[1]);
        let raw = Profile::of(&r, 1.0, dist);
        let rec = Profile::recovered(&r, 1.0, dist);
        raw.print(&format!("sliding penny, μ = {mu}"));
        rec.print("  recovered");
        let (lo, hi, n) = rec.range(0.1, 10.0);
        assert!(n > 1000, "points beyond 0.1 a: {n}");
        assert!(lo > -0.01 && hi < 0.01, "μ = {mu}, recovered beyond 0.1 a: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
        let (lo, hi, _) = rec.range(-1.0, 0.1);
        assert!(
            lo > -0.03 && hi < 0.03,
            "μ = {mu}, recovered in the front cells: {:+.2}%..{:+.2}%",
            100.0 * lo,
            100.0 * hi
        );
        for k in 0..10 {
            let (lo, hi) = (0.1 * k as f64, if k == 9 { 1.01 } else { 0.1 * (k + 1) as f64 });
            let (m, mr) = (raw.mean(lo, hi), rec.mean(lo, hi));
            assert!(
                m.abs() < 0.005 && mr.abs() < 0.005,
                "μ = {mu}, ring {lo:.2}–{hi:.2}: raw {:+.2}%, recovered {:+.2}%",
                100.0 * m,
                100.0 * mr
            );
        }
    }
}

#[test]
#[ignore]
fn diag_penny() {
    let tip = match std::env::var("DIAG_R").as_deref() {
        Ok("default") => None,
        Ok(r) => Some(r.parse().expect("DIAG_R")),
        Err(_) => Some(0.25),
    };
    let mu: f64 = std::env::var("DIAG_MU").map(|m| m.parse().expect("DIAG_MU")).unwrap_or(0.0);
    let mesh = std::env::var("DIAG_MESH").unwrap_or_else(|_| penny_block_mesh());
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let tau: f64 = std::env::var("DIAG_TAU").map(|m| m.parse().expect("DIAG_TAU")).unwrap_or(0.5);
    let text = penny_contact(&mesh, 1.0, tau, mu, tip) + &extra;
    let t = Instant::now();
    let r = solve_contact_text(&text).unwrap_or_else(|e| panic!("{e:?}"));
    let p = Profile::of(&r, 1.0, |x| 1.0 - x[0].hypot(x[1]));
    p.print(&format!(
        "penny tip {tip:?} μ = {mu} τ = {tau} ({:.1} s, {} points)",
        t.elapsed().as_secs_f64(),
        r.x.len()
    ));
    Profile::recovered(&r, 1.0, |x| 1.0 - x[0].hypot(x[1])).print("  recovered");
    dump(&r);
}

/// The closed 45° crack of `tests/contact_friction_cracks.rs` extruded into a slab: plate
/// [−2, 2]² × [0, `t`], hex8 n × n × `nz`, E = 1, ν = 0.3, free faces z = 0 and z = t (one
/// corner point holds z) or, with `plane_strain`, u_z = 0 on both (the face nodes' enriched
/// z unknowns are held too, `physics::held_faces`: the lips no longer slide along z on the
/// faces; see `tests/dirichlet_on_cut_faces.rs`), traction −1 on y = 2 and +1
/// on y = −2 (σ = 1 compression), the lines x = ±2, y = −2 holding the in-plane modes; a through-thickness rectangle
/// crack 2a = 0.4 at 45° centred at (0.0123, 0.0071), wider than the slab along z (its
/// fronts are the two lines at the ends of the 45° segment). Tip radius `tip` (`None`:
/// the default), domain radius 0.06, friction `mu`.
fn slab_45(n: usize, nz: usize, t: f64, mu: f64, tip: Option<f64>, plane_strain: bool) -> String {
    let b = 45f64.to_radians();
    let (c, s) = (b.cos(), b.sin());
    let tip = tip.map_or(String::new(), |r| format!("tip_radius = {r}\n"));
    format!(
        "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [-2.0, -2.0, 0.0]\nupper = [2.0, 2.0, {t}]\ndivisions = [{n}, {n}, {nz}]\n\
         [[materials]]\nE = 1.0\nnu = 0.3\n\
         [[sets]]\nname = \"pin\"\non = \"abs(x+2) + abs(y+2)\"\n[[sets]]\nname = \"roller\"\non = \"abs(x-2) + abs(y+2)\"\n\
         [[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n\
         {faces}\
         [[traction]]\ngroup = \"top\"\nvalue = [0.0, -1.0, 0.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, 1.0, 0.0]\n\
         [[cracks]]\nname = \"c\"\nshape = \"rectangle\"\ncentre = [0.0123, 0.0071, {zc}]\nnormal = [{nx}, {c}, 0.0]\naxis_u = [{c}, {s}, 0.0]\n\
         half_lengths = [0.2, 5.0]\n{tip}sif_radius = 0.06\n[cracks.contact]\nfriction = {mu}\n",
        zc = 0.5 * t,
        nx = -s,
        faces = match plane_strain {
            // Plane strain: u_z = 0 on both faces (and the enriched z unknowns there).
            true => "[[dirichlet]]\ngroup = \"front\"\ncomponents = [\"z\"]\n[[dirichlet]]\ngroup = \"back\"\ncomponents = [\"z\"]\n",
            // Free faces: one point holds z.
            false => "[[sets]]\nname = \"pz\"\non = \"abs(x+2) + abs(y+2) + abs(z)\"\n[[dirichlet]]\ngroup = \"pz\"\ncomponents = [\"z\"]\n",
        },
    )
}

/// The closed 45° crack of `tests/contact_friction_cracks.rs` as a through crack of a slab
/// under compression and shear: plate [−2, 2]² × [0, 0.1], hex8 81 × 81 × 2 (a/h = 4), E = 1,
/// ν = 0.3, free faces z = 0 and z = 0.1 (one corner point holds z; the lines x = ±2,
/// y = −2 hold x, y and y), traction ∓1 on y = ±2 (σ = 1 compression); crack: a rectangle
/// 2a = 0.4 at 45° centred at (0.0123, 0.0071), through the thickness (its fronts are the
/// two lines at the ends of the 45° segment), `[cracks.contact]` with μ = 0 and μ = 0.3 and
/// no `tip_radius`: the 3D default covers the crack (radius a = 0.2, 2% of the nodes).
/// References: pressure σ cos²β = 0.5σ at every contact point, as in 2D: the slab and the
/// square are symmetric about the crack plane (up to the crack's 0.004 offset), so the
/// slip, which is antisymmetric, puts no normal stress on it; K_I = 0. Tolerances: every
/// point in contact; pressure within 1% of 0.5σ farther than one cell (0.049) from a front
/// (measured ≤ 0.44%, μ = 0 and 0.3) and within 2.5% in the front cells (measured 1.96%);
/// |K_I| < 1% of K_II; K_II within 5% of GetFEM's 2D value (0.4001, 0.2801; measured +4.3%,
/// +4.5%: a slab of thickness a/2 with free faces is not the 2D problem, and K_III =
/// ±0.11 (μ = 0) at the two front points, antisymmetric through the thickness as the
/// free-face coupling of modes II and III makes it: asserted to 2%). With two cell layers
/// (the former default) the pressure is 1.32% off beyond one cell and 2.79% overall, the
/// wave of `docs/contact-algorithms.md`, "Accuracy near the tips".
#[test]
fn slab_through_crack_under_compression_and_shear_pressure_within_1pct() {
    let h = 4.0 / 81.0;
    for (mu, getfem) in [(0.0, 0.4001), (0.3, 0.2801)] {
        // γ₀ = 0: the raw multipliers without the stabilisation, as the header says.
        let r = solve_contact_text(&(slab_45(81, 2, 0.1, mu, None, false) + "multiplier_stabilisation = 0\n"))
            .unwrap_or_else(|e| panic!("{e:?}"));
        assert!(r.contact.iter().all(|c| *c), "μ = {mu}: every point in contact");
        let p = Profile::of(&r, 0.5, |x| 0.2 - ((x[0] - 0.0123) * SQRT_HALF + (x[1] - 0.0071) * SQRT_HALF).abs());
        p.print(&format!("slab, μ = {mu}"));
        let (lo, hi, n) = p.range(h, 1.0);
        assert!(n > 100, "μ = {mu}: points beyond a cell from the fronts: {n}");
        assert!(lo > -0.01 && hi < 0.01, "μ = {mu}, beyond a cell: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
        let (lo, hi, _) = p.range(-1.0, 1.0);
        assert!(lo > -0.025 && hi < 0.025, "μ = {mu}, all: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
        let f = &r.sifs[0];
        assert_eq!(f.len(), 4, "μ = {mu}: two points on each of the two fronts");
        for s in f {
            assert!(s.k1.abs() < 0.01 * getfem, "μ = {mu}: K_I {} at {:?}", s.k1, s.x);
            assert!((s.k2.abs() / getfem - 1.0).abs() < 0.05, "μ = {mu}: K_II {} at {:?}", s.k2, s.x);
            // The partner through the thickness: same front, mirrored z.
            let m =
                f.iter().find(|t| (t.x[0] - s.x[0]).abs() < 1e-9 && (t.x[2] - (0.1 - s.x[2])).abs() < 1e-9).unwrap();
            // Antisymmetric to 2% of itself, or to 1% of K_II where K_III itself is that
            // small (since the free faces keep their mode-III term, 2026-11-28, K_III is
            // 0.003 here instead of ±0.11: `sif.rs`, "Faces the front ends on").
            let tol = (0.02 * s.k3.abs()).max(0.01 * getfem);
            assert!((s.k3 + m.k3).abs() < tol, "μ = {mu}: K_III {} and {}", s.k3, m.k3);
        }
    }
}

/// The pressure recovered from the multipliers (`contact::recovery`, as in the penny test
/// above) of the slab's through crack of the previous test (plate [−2, 2]² × [0, 0.1], hex8
/// 81 × 81 × 2, E = 1, ν = 0.3, free faces, σ = 1; crack 2a = 0.4 at 45°) with μ = 0 and the
/// former default tip zone of two cell layers (`tip_radius = 0.099`), whose edge crosses
/// the crack at 0.1 from each front: the raw pressure carries the wave there (−1.79% …
/// +2.79% at all points, +1.32% beyond 0.1 from the fronts; `docs/contact-algorithms.md`,
/// "3D contact pressure pointwise: the recovered pressure"). Reference: 0.5σ at every
/// point (σ cos²β, the slab symmetric about the crack plane). Tolerances: the recovered
/// pressure within 1% of 0.5σ at every contact point, the front cells included (measured
/// −0.27% … +0.81%), and within 0.5% beyond one cell (4/81) from the fronts (measured
/// −0.27% … +0.12% beyond 0.05).
#[test]
fn slab_through_crack_recovered_pressure_within_1pct_across_the_tip_zone_edge() {
    // γ₀ = 0: the raw multipliers without the stabilisation, as the header says.
    let r = solve_contact_text(&(slab_45(81, 2, 0.1, 0.0, Some(0.099), false) + "multiplier_stabilisation = 0\n"))
        .unwrap_or_else(|e| panic!("{e:?}"));
    assert!(r.contact.iter().all(|c| *c), "every point in contact");
    let dist = |x: [f64; 3]| 0.2 - ((x[0] - 0.0123) * SQRT_HALF + (x[1] - 0.0071) * SQRT_HALF).abs();
    Profile::of(&r, 0.5, dist).print("slab, two cell layers, μ = 0");
    let rec = Profile::recovered(&r, 0.5, dist);
    rec.print("  recovered");
    let (lo, hi, n) = rec.range(-1.0, 1.0);
    assert!(n == r.x.len(), "every point has a distance: {n}");
    assert!(lo > -0.01 && hi < 0.01, "recovered, all points: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
    let (lo, hi, _) = rec.range(4.0 / 81.0, 1.0);
    assert!(lo > -0.005 && hi < 0.005, "recovered beyond a cell: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
}

/// The 3D covering default and its node budget (`enrich::COVERING_NODE_SHARE`, a quarter of
/// the nodes), without solving. The slab of the previous test: radius = a = 0.2 (the
/// rectangle's smaller half-length). The penny of `examples/penny_crack_contact_3d.toml`
/// without `tip_radius` (covering would take in 6178 of its 12 088 nodes, 51%): two cell
/// layers, 0.245 (the mean edge of the front cells × 2). A disc a = 1.2 in the box
/// [−2, 2]³, hex8 8³, closed by σ = 1 (covering would take in over a quarter of the nodes)
/// run through the CLI: two layers, `steps[0].cracks[0].tip_radius` = 1.0 (cells of 0.5),
/// and a warning that names the crack.
#[test]
fn covering_tip_zone_is_the_3d_default_within_a_quarter_of_the_nodes() {
    use fissure::case::{resolve, Case};
    let radius = |text: &str| {
        let case = Case::parse(text, std::path::Path::new("c.toml")).unwrap();
        let m = resolve::build_mesh(&case).unwrap();
        let model = resolve::build_model(&case, &m).unwrap();
        let e = &model.enrichment;
        eprintln!("tip radius {:?}: {} tip nodes of {}", e.tip_radius, e.n_tip_nodes, m.n_nodes());
        (e.tip_radius[0], e.n_tip_nodes as f64 / m.n_nodes() as f64)
    };
    let (r, share) = radius(&slab_45(81, 2, 0.1, 0.0, None, false));
    assert!((r - 0.2).abs() < 1e-12 && share < 0.25, "slab: radius {r}, share {share}");
    let (r, share) = radius(&penny_contact(&penny_block_mesh(), 1.0, 0.5, 0.0, None));
    assert!(r > 0.2 && r < 0.3 && share < 0.25, "penny: radius {r}, share {share}");
    let text = "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [-2.0, -2.0, -2.0]\nupper = [2.0, 2.0, 2.0]\n\
                divisions = [8, 8, 8]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"back\"\n\
                components = [\"x\", \"y\", \"z\"]\n[[traction]]\ngroup = \"front\"\nvalue = [0.0, 0.0, -1.0]\n\
                [[cracks]]\nname = \"penny\"\nshape = \"disc\"\ncentre = [0.0, 0.0, 0.01]\nnormal = [0.0, 0.0, 1.0]\n\
                radius = 1.2\nsif_radius = 0.4\n[cracks.contact]\nfriction = 0.0\n";
    let s = common::run_cli("covering_3d", "box_penny", text);
    let w = s["warnings"].as_array().expect("warnings");
    assert!(
        w.iter().any(|w| w.as_str().is_some_and(|w| w.contains("crack 'penny': a tip enrichment covering the crack"))),
        "{w:?}"
    );
    let r_summary = s["steps"][0]["cracks"][0]["tip_radius"].as_f64().unwrap();
    assert!((r_summary - 1.0).abs() < 1e-9, "summary tip_radius {r_summary} (two cells of 0.5)");
}

#[test]
#[ignore]
fn diag_slab() {
    let tip = match std::env::var("DIAG_R").as_deref() {
        Ok("default") => None,
        Ok(r) => Some(r.parse().expect("DIAG_R")),
        Err(_) => Some(0.2),
    };
    let mu: f64 = std::env::var("DIAG_MU").map(|m| m.parse().expect("DIAG_MU")).unwrap_or(0.0);
    let n: usize = std::env::var("DIAG_N").map(|m| m.parse().expect("DIAG_N")).unwrap_or(81);
    let nz: usize = std::env::var("DIAG_NZ").map(|m| m.parse().expect("DIAG_NZ")).unwrap_or(2);
    let t = Instant::now();
    let th: f64 = std::env::var("DIAG_T").map(|m| m.parse().expect("DIAG_T")).unwrap_or(0.1);
    let strain = std::env::var("DIAG_FACES").is_ok_and(|f| f == "strain");
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let r = solve_contact_text(&(slab_45(n, nz, th, mu, tip, strain) + &extra)).unwrap_or_else(|e| panic!("{e:?}"));
    let ctr = [0.0123, 0.0071];
    let d = 0.5f64.sqrt();
    let p = Profile::of(&r, 0.5, |x| 0.2 - ((x[0] - ctr[0]) * d + (x[1] - ctr[1]) * d).abs());
    p.print(&format!(
        "slab {n}×{n}×{nz} tip {tip:?} μ = {mu} ({:.1} s, {} points)",
        t.elapsed().as_secs_f64(),
        r.x.len()
    ));
    Profile::recovered(&r, 0.5, |x| 0.2 - ((x[0] - ctr[0]) * d + (x[1] - ctr[1]) * d).abs()).print("  recovered");
    let mut zs: Vec<f64> = r.x.iter().map(|x| (x[2] * 1e4).round() / 1e4).collect();
    zs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    zs.dedup();
    for z in zs {
        let (lo, hi) =
            r.x.iter().zip(&r.lambda).filter(|(x, _)| (x[2] - z).abs() < 5e-5).fold((9.0f64, -9.0f64), |a, (_, l)| {
                let e = -l / 0.5 - 1.0;
                (a.0.min(e), a.1.max(e))
            });
        let uz = r
            .jump
            .iter()
            .zip(&r.x)
            .filter(|(_, x)| (x[2] - z).abs() < 5e-5)
            .map(|(j, _)| j[2].abs())
            .fold(0.0, f64::max);
        eprintln!("  z = {z:.4}: {:+.2}%..{:+.2}%, |[[u_z]]| ≤ {uz:.2e}", 100.0 * lo, 100.0 * hi);
    }
    for s in &r.sifs[0] {
        eprintln!("  front point {:?}: K_I {:+.4} K_II {:+.4} K_III {:+.4}", s.x, s.k1, s.k2, s.k3);
    }
}

/// Prints the enrichment of the penny for `DIAG_R` (and `DIAG_MESH`) without solving.
#[test]
#[ignore]
fn diag_penny_count() {
    use fissure::case::{resolve, Case};
    let mesh = std::env::var("DIAG_MESH").unwrap_or_else(|_| penny_block_mesh());
    for r in std::env::var("DIAG_R").unwrap_or_else(|_| "0.25".into()).split(',') {
        let tip = if r == "default" { None } else { Some(r.parse().expect("DIAG_R")) };
        let case = Case::parse(&penny_contact(&mesh, 1.0, 0.5, 0.0, tip), std::path::Path::new("c.toml")).unwrap();
        let m = resolve::build_mesh(&case).unwrap();
        let model = resolve::build_model(&case, &m).unwrap();
        let e = &model.enrichment;
        eprintln!(
            "tip {r}: radius {:?}, {} nodes, {} tip nodes, {} Heaviside nodes, {} dofs",
            e.tip_radius,
            m.n_nodes(),
            e.n_tip_nodes,
            e.n_heaviside_nodes,
            e.dofs.n_total()
        );
    }
}

/// The raw multipliers with the local-projection stabilisation (`[cracks.contact]
/// multiplier_stabilisation = 10`, `contact::kernel` stencil elements) on the sliding penny
/// crack of `examples/penny_crack_contact_3d.toml`: a = 1 in z = 0, block [−5, 5]³, tet4
/// graded to 0.09 at the front (`meshes/penny_block.msh`), E = 1, ν = 0.3, tip radius 0.25;
/// σ = 1 across the crack, τ = 0.5 in the x–z plane, μ = 0 and the example's μ = 0.2 (every
/// point slides). References: pressure −λ = σ at every contact point (Kassir & Sih's
/// sliding penny: the slip, antisymmetric about the crack plane, puts no normal stress on
/// it); K_II = 4τ_e√(a/π)/(2 − ν) cos φ, K_III = 4(1 − ν)τ_e√(a/π)/(2 − ν) sin φ with the
/// effective shear τ_e = τ − μσ, K_I = 0 (Kassir & Sih 1966). Tolerances: every point in
/// contact; the raw −λ within 1% of σ beyond 0.1 a (without the stabilisation −10.9 …
/// +11.0% at μ = 0; measured with it −0.30 … +0.32% at μ = 0, −0.20 … +0.19% at μ = 0.2) and
/// within 1.5% in the front cells (measured −0.63 … +0.55%); ring averages (0.1 a) within
/// 0.5%; K_II and K_III within 5% of their amplitudes and |K_I| within 3% of the K_II
/// amplitude at every front point, the bands of `tests/fracture_sifs_3d.rs` (measured worst
/// K_II, K_III, |K_I|: 1.48%, 2.98%, 0.62% at μ = 0; 1.64%, 3.22%, 0.82% at μ = 0.2, where
/// the unstabilised run of that file gives 1.60%, 3.21%, 0.90%).
#[test]
fn sliding_penny_crack_stabilised_multipliers_pressure_within_1pct_pointwise() {
    use std::f64::consts::PI;
    for mu in [0.0, 0.2] {
        let text = penny_contact(&penny_block_mesh(), 1.0, 0.5, mu, Some(0.25)) + "multiplier_stabilisation = 10\n";
        let r = solve_contact_text(&text).unwrap_or_else(|e| panic!("{e:?}"));
        assert!(r.contact.iter().all(|c| *c), "μ = {mu}: every point in contact");
        let p = Profile::of(&r, 1.0, |x| 1.0 - x[0].hypot(x[1]));
        p.print(&format!("sliding penny, stabilised multipliers, μ = {mu}"));
        let (lo, hi, n) = p.range(0.1, 10.0);
        assert!(n > 1000, "points beyond 0.1 a: {n}");
        assert!(lo > -0.01 && hi < 0.01, "μ = {mu}, beyond 0.1 a: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
        let (lo, hi, _) = p.range(-1.0, 0.1);
        assert!(lo > -0.015 && hi < 0.015, "μ = {mu}, front cells: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
        for k in 0..10 {
            let (lo, hi) = (0.1 * k as f64, if k == 9 { 1.01 } else { 0.1 * (k + 1) as f64 });
            let m = p.mean(lo, hi);
            assert!(m.abs() < 0.005, "μ = {mu}, ring {lo:.2}–{hi:.2}: {:+.2}%", 100.0 * m);
        }
        let (tau_e, nu) = (0.5 - mu, 0.3);
        let k2_amp = 4.0 * tau_e / PI.sqrt() / (2.0 - nu);
        let k3_amp = (1.0 - nu) * k2_amp;
        let (mut w1, mut w2, mut w3) = (0.0f64, 0.0f64, 0.0f64);
        for s in &r.sifs[0] {
            let phi = s.x[1].atan2(s.x[0]);
            w1 = w1.max(s.k1.abs() / k2_amp);
            w2 = w2.max(((s.k2 - k2_amp * phi.cos()) / k2_amp).abs());
            w3 = w3.max(((s.k3 - k3_amp * phi.sin()) / k3_amp).abs());
        }
        eprintln!(
            "  μ = {mu}: worst K_II {:.2}%, K_III {:.2}%, |K_I| {:.2}% of the amplitudes",
            100.0 * w2,
            100.0 * w3,
            100.0 * w1
        );
        assert!(r.sifs[0].len() >= 10, "front points: {}", r.sifs[0].len());
        assert!(w2 < 0.05 && w3 < 0.05 && w1 < 0.03, "μ = {mu}: K_II {w2:.4}, K_III {w3:.4}, K_I {w1:.4}");
    }
}

/// The raw multipliers with the local-projection stabilisation (`multiplier_stabilisation =
/// 10`) on the slab's through crack with the former default tip zone of two cell layers
/// (`tip_radius = 0.099`), whose edge crosses the crack 0.1 from each front: plate
/// [−2, 2]² × [0, 0.1], hex8 81 × 81 × 2, E = 1, ν = 0.3, free faces, σ = 1 compression,
/// crack 2a = 0.4 at 45°, μ = 0 (`slab_45`). Reference: 0.5σ at every point (σ cos²β, the
/// slab symmetric about the crack plane); K_II of GetFEM's 2D run, 0.4001. Tolerances: the
/// raw pressure within 0.5% of 0.5σ at every contact point, the front cells included
/// (without the stabilisation −1.79 … +2.79%; measured with it −0.30 … +0.18%); K_II within
/// 5% of 0.4001 at the four front points, as in the unstabilised slab test (measured
/// 0.4173, +4.3%, the same as without: a slab a/2 thick with free faces is not the 2D
/// problem).
#[test]
fn slab_through_crack_stabilised_multipliers_pressure_within_half_pct_across_the_tip_zone_edge() {
    let text = slab_45(81, 2, 0.1, 0.0, Some(0.099), false) + "multiplier_stabilisation = 10\n";
    let r = solve_contact_text(&text).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(r.contact.iter().all(|c| *c), "every point in contact");
    let dist = |x: [f64; 3]| 0.2 - ((x[0] - 0.0123) * SQRT_HALF + (x[1] - 0.0071) * SQRT_HALF).abs();
    let p = Profile::of(&r, 0.5, dist);
    p.print("slab, two cell layers, stabilised multipliers, μ = 0");
    let (lo, hi, n) = p.range(-1.0, 1.0);
    assert_eq!(n, r.x.len(), "every point has a distance");
    assert!(lo > -0.005 && hi < 0.005, "all points: {:+.2}%..{:+.2}%", 100.0 * lo, 100.0 * hi);
    assert_eq!(r.sifs[0].len(), 4, "two points on each of the two fronts");
    for s in &r.sifs[0] {
        assert!((s.k2.abs() / 0.4001 - 1.0).abs() < 0.05, "K_II {} at {:?}", s.k2, s.x);
    }
}
