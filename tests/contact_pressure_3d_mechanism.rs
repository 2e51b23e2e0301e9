//! The mechanism of the raw 3D contact-pressure oscillation of sliding cracks, on small
//! boxes where a run takes seconds (issue 17 item 2; `docs/contact-algorithms.md`, "3D
//! contact pressure pointwise: the mechanism and the stabilised multipliers").
//!
//! Diagnostic (ignored; `cargo test --release --test contact_pressure_3d_mechanism --
//! --ignored --nocapture diag_box`): a disc crack of radius 1 in the plane z = z0 of the
//! box [−2, 2]³ (symmetric about the crack plane for z0 = 0, so the slip puts no normal
//! stress on it: the pressure is σ everywhere; an odd number of divisions puts the crack
//! in the middle of a cell layer), closed by σ and sheared by τ in the
//! x–z plane, μ = 0 unless `DIAG_MU`. Environment: `DIAG_CELL` (`hex8`, `tet4`), `DIAG_N`
//! (divisions), `DIAG_Z0` (crack offset in cells), `DIAG_MESH` (a Gmsh file instead of the
//! generator: the box [−2, 2]³, crack at z = 0), `DIAG_SIGMA` (σ, default 1), `DIAG_TAU`
//! (τ/σ, default 0.5), `DIAG_GRAD` (g: the compression σ(1 + g x), the reference pressure
//! too, since the compression's field is linear and the crack closed), `DIAG_NU` (Poisson's ratio, default 0.3), `DIAG_TIP` (tip radius, default 0.3), `DIAG_EXTRA` (keys appended to
//! the crack's contact table, `\n` for new lines).
mod common;

use common::contact::{solve_contact_text, ContactRun};
use std::time::Instant;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key).ok().map_or(default, |v| v.parse().ok().unwrap_or_else(|| panic!("{key}")))
}

/// The disc crack of radius 1 at z = z0 in the box [−2, 2]³, closed by σ and
/// sheared by τ (σ units), on the generator's `cell` mesh n³ or on the Gmsh file `mesh`.
#[allow(clippy::too_many_arguments)]
fn box_disc(
    cell: &str,
    n: usize,
    z0: f64,
    mesh: Option<&str>,
    sigma: f64,
    tau: f64,
    mu: f64,
    tip: f64,
    extra: &str,
) -> String {
    let (lo, hi) = (-2.0, 2.0);
    let mesh = match mesh {
        Some(f) => format!("[mesh]\nfile = \"{f}\"\n"),
        None => format!(
            "[mesh]\ngenerator = \"box\"\ncell = \"{cell}\"\nlower = [-2.0, -2.0, {lo}]\nupper = [2.0, 2.0, {hi}]\ndivisions = [{n}, {n}, {n}]\n"
        ),
    };
    let t = tau * sigma;
    format!(
        "{mesh}[[materials]]\nE = 1.0\nnu = {nu}\n\
         [[sets]]\nname = \"p1\"\non = \"abs(x+2) + abs(y+2) + abs(z-({lo}))\"\n[[sets]]\nname = \"p2\"\non = \"abs(x-2) + abs(y+2) + abs(z-({lo}))\"\n\
         [[sets]]\nname = \"p3\"\non = \"abs(x+2) + abs(y-2) + abs(z-({lo}))\"\n\
         [[dirichlet]]\ngroup = \"p1\"\ncomponents = [\"x\", \"y\", \"z\"]\n[[dirichlet]]\ngroup = \"p2\"\ncomponents = [\"y\", \"z\"]\n\
         [[dirichlet]]\ngroup = \"p3\"\ncomponents = [\"z\"]\n\
         [[traction]]\ngroup = \"front\"\nvalue = [{t}, 0.0, \"-{sigma}*(1 + {g}*x)\"]\n[[traction]]\ngroup = \"back\"\nvalue = [{mt}, 0.0, \"{sigma}*(1 + {g}*x)\"]\n\
         [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, {t}]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, {mt}]\n\
         [[cracks]]\nname = \"disc\"\nshape = \"disc\"\ncentre = [0.0, 0.0, {z0}]\nnormal = [0.0, 0.0, 1.0]\nradius = 1.0\n\
         tip_radius = {tip}\nsif_radius = 0.3\n[cracks.contact]\nfriction = {mu}\n{extra}",
        mt = -t,
        g = env_or("DIAG_GRAD", 0.0),
        nu = env_or("DIAG_NU", 0.3),
    )
}

/// Extremes and area-weighted RMS of p/σ − 1 over the points with d = 1 − r in [lo, hi).
/// With `rho` > 0, of the traction the bulk feels, −(λ − ρ d_n), in place of −λ.
fn band(r: &ContactRun, sigma: f64, lo: f64, hi: f64, rho: f64) -> (f64, f64, f64, usize) {
    let (mut mn, mut mx, mut s2, mut w, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0, 0);
    for (((x, l), wt), dn) in r.x.iter().zip(&r.lambda).zip(&r.weight).zip(&r.d_n) {
        let d = 1.0 - x[0].hypot(x[1]);
        if d >= lo && d < hi {
            let e = -(l - rho * dn) / (sigma * (1.0 + env_or("DIAG_GRAD", 0.0) * x[0])) - 1.0;
            mn = mn.min(e);
            mx = mx.max(e);
            s2 += wt * e * e;
            w += wt;
            n += 1;
        }
    }
    (mn, mx, (s2 / w).sqrt(), n)
}

#[test]
#[ignore]
fn diag_box() {
    let cell = std::env::var("DIAG_CELL").unwrap_or_else(|_| "hex8".into());
    let n: usize = env_or("DIAG_N", 20);
    let h = 4.0 / n as f64;
    let z0 = env_or("DIAG_Z0", 0.0) * h;
    let mesh = std::env::var("DIAG_MESH").ok();
    let sigma: f64 = env_or("DIAG_SIGMA", 1.0);
    let tau: f64 = env_or("DIAG_TAU", 0.5);
    let mu: f64 = env_or("DIAG_MU", 0.0);
    let tip: f64 = env_or("DIAG_TIP", 0.3);
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let t = Instant::now();
    let r = solve_contact_text(&box_disc(&cell, n, z0, mesh.as_deref(), sigma, tau, mu, tip, &extra))
        .unwrap_or_else(|e| panic!("{e:?}"));
    let open = r.contact.iter().filter(|c| !**c).count();
    let mut s = format!(
        "box {cell} n={n} z0={z0:.4} mesh={mesh:?} σ={sigma} τ/σ={tau} grad={} μ={mu} tip={tip} extra={extra:?}: {:.1} s, {} points, {} packets, {open} open\n",
        env_or("DIAG_GRAD", 0.0),
        t.elapsed().as_secs_f64(),
        r.x.len(),
        r.multipliers
    );
    for (lo, hi) in [(0.0, 0.1), (0.1, 0.3), (0.3, 0.5), (0.5, 1.01), (0.1, 1.01)] {
        let (mn, mx, rms, k) = band(&r, sigma, lo, hi, 0.0);
        let (gmn, gmx, grms, _) = band(&r, sigma, lo, hi, 1.0 / r.h);
        s += &format!(
            "  d in [{lo:.1},{hi:.2}): {:+.2}% .. {:+.2}%, rms {:.2}% ({k}); λ − (E/h) d_n: {:+.2}% .. {:+.2}%, rms {:.2}%\n",
            100.0 * mn,
            100.0 * mx,
            100.0 * rms,
            100.0 * gmn,
            100.0 * gmx,
            100.0 * grms
        );
    }
    eprint!("{s}");
    if let Ok(f) = std::env::var("DIAG_LOG") {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(f).expect("DIAG_LOG");
        f.write_all(s.as_bytes()).expect("DIAG_LOG");
    }
}

/// The bulk's normal stress at the contact points of `diag_box`'s case, from each side of
/// the cut cell (σ_nn⁺, σ_nn⁻ of the enriched displacement there), against σ: how well the
/// bulk itself carries the pressure where the multipliers oscillate.
/// Per contact point: d, and the errors of −λ, −σ_nn⁺, −σ_nn⁻ and their mean.
type StressRow = (f64, f64, f64, f64, f64);

#[test]
#[ignore]
fn diag_box_stress() {
    use fissure::case::{resolve, Case};
    use fissure::contact::state::point_values;
    use fissure::enrich::basis::{field_at, CellBasis, Evaluator};
    use fissure::run::solve_model_recorded;
    use fissure::solve::statics::SolveOptions;
    let cell = std::env::var("DIAG_CELL").unwrap_or_else(|_| "hex8".into());
    let n: usize = env_or("DIAG_N", 20);
    let h = 4.0 / n as f64;
    let z0 = env_or("DIAG_Z0", 0.0) * h;
    let mesh = std::env::var("DIAG_MESH").ok();
    let tau: f64 = env_or("DIAG_TAU", 0.5);
    let tip: f64 = env_or("DIAG_TIP", 0.3);
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let text = box_disc(&cell, n, z0, mesh.as_deref(), 1.0, tau, 0.0, tip, &extra);
    let case = Case::parse(&text, std::path::Path::new("case.toml")).unwrap();
    let m = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &m).unwrap();
    let setup = resolve::build_contact(&case, &model).unwrap().expect("contact");
    let (_, rec) = solve_model_recorded(&model, Some(&setup), &SolveOptions::default()).unwrap();
    let u = &rec.last().unwrap().u;
    let pts = &setup.points;
    let vals = point_values(&model, pts, None, &rec.last().unwrap().contact_state, u);
    let ev = Evaluator { mesh: &m, enr: &model.enrichment, cracks: &model.cracks };
    let mut basis = CellBasis::default();
    let (mut v, mut g) = (vec![], vec![]);
    let mut rows = vec![];
    for (p, pv) in pts.points.iter().zip(&vals) {
        basis.build(&m, &model.enrichment, p.cell);
        v.resize(basis.len(), 0.0);
        g.resize(basis.len(), [0.0; 3]);
        let mat = &model.materials[model.cell_material[p.cell] as usize];
        let mut snn = [0.0; 2];
        for (s, side) in [1i8, -1].iter().enumerate() {
            ev.eval(p.cell, &basis, &p.xi, Some(*side), &mut v, &mut g).unwrap();
            let (_, gu) = field_at(3, &basis, &v, &g, u);
            let mut eps = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    eps[i][j] = 0.5 * (gu[i][j] + gu[j][i]);
                }
            }
            let st = mat.stress(model.analysis, &eps);
            let nn = p.normal;
            snn[s] = (0..3).map(|i| (0..3).map(|j| nn[i] * st[i][j] * nn[j]).sum::<f64>()).sum();
        }
        rows.push((
            1.0 - p.x[0].hypot(p.x[1]),
            -pv.lambda - 1.0,
            -snn[0] - 1.0,
            -snn[1] - 1.0,
            -0.5 * (snn[0] + snn[1]) - 1.0,
        ));
    }
    let mut s = format!("box stress {cell} n={n} mesh={mesh:?} τ={tau} tip={tip} extra={extra:?}\n");
    for (lo, hi) in [(0.0, 0.1), (0.1, 0.3), (0.3, 0.5), (0.5, 1.01), (0.1, 1.01)] {
        let sel: Vec<_> = rows.iter().filter(|r| r.0 >= lo && r.0 < hi).collect();
        let rng =
            |f: &dyn Fn(&StressRow) -> f64| sel.iter().fold((9.0f64, -9.0f64), |a, r| (a.0.min(f(r)), a.1.max(f(r))));
        let (a, b, c, d) = (rng(&|r| r.1), rng(&|r| r.2), rng(&|r| r.3), rng(&|r| r.4));
        s += &format!(
            "  [{lo:.1},{hi:.2}) −λ {:+.2}..{:+.2}%  −σnn⁺ {:+.2}..{:+.2}%  −σnn⁻ {:+.2}..{:+.2}%  mean {:+.2}..{:+.2}%\n",
            100.0 * a.0,
            100.0 * a.1,
            100.0 * b.0,
            100.0 * b.1,
            100.0 * c.0,
            100.0 * c.1,
            100.0 * d.0,
            100.0 * d.1
        );
    }
    eprint!("{s}");
    if let Ok(f) = std::env::var("DIAG_LOG") {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(f).expect("DIAG_LOG");
        f.write_all(s.as_bytes()).expect("DIAG_LOG");
    }
}

/// The stencils of the local-projection stabilisation (`contact::points::Stencil`) on the
/// unstructured tet4 mesh of the penny crack (`meshes/penny_block.msh`, disc a = 1 in
/// z = 0, `multiplier_stabilisation = 10`): every packet with points has one, and its
/// defect δ_j = Σ_k s_k λ_k vanishes for multipliers linear in the crack plane (λ_k the
/// linear field at the packet centroids Σ w ψ x / Σ w ψ, to 1e-9 of the field's range), so
/// the stabilisation keeps a uniform or linear pressure; it does not vanish for
/// multipliers alternating between packets (the oscillation it damps: some |δ_j| > 0.5).
#[test]
fn stabilisation_stencils_vanish_on_linear_multipliers() {
    use fissure::case::{resolve, Case};
    let text = common::penny_block::penny_block(
        &common::penny_block::penny_block_mesh(),
        "[[traction]]\ngroup = \"front\"\nvalue = [0.0, 0.0, -1.0]",
        common::penny_block::PENNY_DISC,
    ) + "[cracks.contact]\nmultiplier_stabilisation = 10\n";
    let case = Case::parse(&text, std::path::Path::new("c.toml")).unwrap();
    let m = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &m).unwrap();
    let setup = resolve::build_contact(&case, &model).unwrap().expect("contact");
    let pts = &setup.points;
    let n = pts.cracks[0].space.n_unknowns;
    let (mut area, mut centre) = (vec![0.0; n], vec![[0.0; 3]; n]);
    for p in &pts.points {
        for &(j, c) in &p.terms {
            if c > 0.0 {
                area[j as usize] += p.weight * c;
                (0..3).for_each(|i| centre[j as usize][i] += p.weight * c * p.x[i]);
            }
        }
    }
    let used = area.iter().filter(|a| **a > 0.0).count();
    assert_eq!(pts.stencils.len(), used, "one stencil per packet with points");
    let linear = |k: u32| {
        let (a, c) = (area[k as usize], centre[k as usize]);
        1.0 + 0.3 * c[0] / a - 0.2 * c[1] / a
    };
    let alternating = |k: u32| if k % 2 == 0 { 1.0 } else { -1.0 };
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for st in &pts.stencils {
        assert!(st.terms.len() >= 3, "packet {}: a stencil of {} packets", st.unknown, st.terms.len());
        worst = worst.max(st.terms.iter().map(|&(k, s)| s * linear(k)).sum::<f64>().abs());
        largest = largest.max(st.terms.iter().map(|&(k, s)| s * alternating(k)).sum::<f64>().abs());
    }
    eprintln!("{} stencils: |δ| ≤ {worst:.2e} on a linear field, up to {largest:.2} on an alternating one", used);
    assert!(worst < 1e-9, "linear multipliers: |δ| up to {worst:.2e}");
    assert!(largest > 0.5, "alternating multipliers: |δ| at most {largest:.2}");
}

/// `multiplier_stabilisation` in a case file: a negative value, or the key on a law without
/// multipliers (`method = "penalty"`), is an error naming the key.
#[test]
fn multiplier_stabilisation_key_errors_name_the_key() {
    use fissure::case::Case;
    for extra in ["multiplier_stabilisation = -1\n", "method = \"penalty\"\nmultiplier_stabilisation = 1\n"] {
        let text = box_disc("hex8", 4, 0.0, None, 1.0, 0.0, 0.0, 0.3, extra);
        let e = Case::parse(&text, std::path::Path::new("c.toml")).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains("multiplier_stabilisation"), "{extra:?}: {e}");
    }
}

/// The stabilisation in 2D: the closed 45° crack of `tests/contact_friction_cracks.rs`
/// (`common::contact::inclined_crack`, tip radius 0.05, reference pressure 0.5σ, |K_II| of
/// GetFEM 0.4001 at μ = 0 and 0.2801 at μ = 0.3) on the meshes `DIAG_N` (comma-separated,
/// default 121,181) with γ₀ = `DIAG_G` (comma-separated, default 0,10), μ = `DIAG_MU`.
#[test]
#[ignore]
fn diag_inclined_2d() {
    let mu: f64 = env_or("DIAG_MU", 0.0);
    let getfem = if mu == 0.0 { 0.4001 } else { 0.2801 };
    let ns = std::env::var("DIAG_N").unwrap_or_else(|_| "121,181".into());
    let gs = std::env::var("DIAG_G").unwrap_or_else(|_| "0,10".into());
    let mut s = String::new();
    for n in ns.split(',') {
        for g in gs.split(',') {
            let text =
                common::contact::inclined_crack(mu, n.parse().unwrap(), &format!("multiplier_stabilisation = {g}\n"));
            let r = solve_contact_text(&text).unwrap_or_else(|e| panic!("{e:?}"));
            let (lo, hi) =
                r.lambda.iter().fold((9.0f64, -9.0f64), |a, l| (a.0.min(-l / 0.5 - 1.0), a.1.max(-l / 0.5 - 1.0)));
            let k2: Vec<String> =
                r.sifs[0].iter().map(|p| format!("{:+.3}%", 100.0 * (p.k2.abs() / getfem - 1.0))).collect();
            s += &format!(
                "inclined 2D n={n} γ₀={g} μ={mu}: pressure {:+.2}%..{:+.2}%, K_II {k2:?}\n",
                100.0 * lo,
                100.0 * hi
            );
        }
    }
    eprint!("{s}");
    if let Ok(f) = std::env::var("DIAG_LOG") {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(f).expect("DIAG_LOG");
        f.write_all(s.as_bytes()).expect("DIAG_LOG");
    }
}
