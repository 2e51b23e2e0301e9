//! Solving a cracked case given as text and computing its SIFs.

use fissure::case::{resolve, Case};
use fissure::post::sif::{crack_sifs, SifOptions, SifPoint};
use fissure::run::solve_model;
use fissure::solve::statics::SolveOptions;
use std::path::Path;

/// What a fracture run gives back.
pub struct FractureRun {
    /// SIFs per crack at the last step.
    pub sifs: Vec<Vec<SifPoint>>,
    pub dofs: usize,
    pub nodes: usize,
}

/// Parses, solves and computes the SIFs of every crack (pressure on faces included).
pub fn solve_text(text: &str) -> FractureRun {
    let case = Case::parse(text, Path::new("case.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mesh = resolve::build_mesh(&case).unwrap_or_else(|e| panic!("{e}"));
    let model = resolve::build_model(&case, &mesh).unwrap_or_else(|e| panic!("{e}"));
    let (report, sols) = solve_model(&model, &SolveOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let u = sols.last().expect("a step");
    let t = *model.load_factors.last().unwrap();
    let sifs = (0..model.cracks.len())
        .map(|k| {
            let p = model.crack_pressure[k].clone();
            let facets = &model.cracks[k].cut.facets;
            let tr = move |fi: usize, x: [f64; 3]| {
                let pv = p.as_ref().map_or(0.0, |p| p.eval_load(x, t));
                let n = facets[fi].normal;
                [pv * n[0], pv * n[1], pv * n[2]]
            };
            let opts = SifOptions { radius: case.cracks[k].sif_radius };
            crack_sifs(&model, k, u, Some(&tr), &opts)
        })
        .collect();
    FractureRun { sifs, dofs: report.dofs.n_total(), nodes: mesh.n_nodes() }
}

/// Crack opening [[u]]·n at the midpoints of every facet of crack 0, sorted by x.
pub fn openings(text: &str) -> Vec<([f64; 3], f64)> {
    use fissure::enrich::basis::{field_at, CellBasis, Evaluator};
    let case = Case::parse(text, Path::new("case.toml")).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &mesh).unwrap();
    let (_, sols) = solve_model(&model, &SolveOptions::default()).unwrap();
    let u = sols.last().unwrap();
    let ev = Evaluator { mesh: &mesh, enr: &model.enrichment, cracks: &model.cracks };
    let mut out = vec![];
    let mut b = CellBasis::default();
    for f in &model.cracks[0].cut.facets {
        b.build(&mesh, &model.enrichment, f.cell);
        let mut v = vec![0.0; b.len()];
        let mut g = vec![[0.0; 3]; b.len()];
        let k = f.vertices_ref.len() as f64;
        let mut xi = [0.0; 3];
        for p in &f.vertices_ref {
            for i in 0..3 {
                xi[i] += p[i] / k;
            }
        }
        let pi = ev.eval(f.cell, &b, &xi, Some(1), &mut v, &mut g).unwrap();
        let (up, _) = field_at(mesh.dim, &b, &v, &g, u);
        ev.eval(f.cell, &b, &xi, Some(-1), &mut v, &mut g).unwrap();
        let (um, _) = field_at(mesh.dim, &b, &v, &g, u);
        let o: f64 = (0..3).map(|i| (up[i] - um[i]) * f.normal[i]).sum();
        out.push((pi.x, o));
    }
    out.sort_by(|a, b| a.0[0].partial_cmp(&b.0[0]).unwrap());
    out
}

/// A plate [x0, x1] × [y0, y1] of quad4 (or tri3) cells, E = 1, ν = 0.3 (plane strain),
/// held by two corner points (rigid modes only), plus `extra` case text.
pub fn plate(cell: &str, lo: [f64; 2], hi: [f64; 2], div: [usize; 2], extra: &str) -> String {
    format!(
        r#"
[mesh]
generator = "rectangle"
cell = "{cell}"
lower = [{x0}, {y0}]
upper = [{x1}, {y1}]
divisions = [{nx}, {ny}]
[[materials]]
E = 1.0
nu = 0.3
[[sets]]
name = "pin"
on = "abs(x-({x0})) + abs(y-({y0}))"
[[sets]]
name = "roller"
on = "abs(x-({x1})) + abs(y-({y0}))"
[[dirichlet]]
group = "pin"
components = ["x", "y"]
[[dirichlet]]
group = "roller"
components = ["y"]
{extra}
"#,
        x0 = lo[0],
        y0 = lo[1],
        x1 = hi[0],
        y1 = hi[1],
        nx = div[0],
        ny = div[1]
    )
}

/// Tension σ = 1 on the top and bottom edges.
pub const TENSION: &str =
    "[[traction]]\ngroup = \"top\"\nvalue = [0.0, 1.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, -1.0]\n";

/// Feddersen's finite-width factor for a centre crack (Tada, Paris & Irwin):
/// [1 − 0.025 (a/b)² + 0.06 (a/b)⁴] √sec(πa/2b).
pub fn feddersen(a_over_b: f64) -> f64 {
    let r = a_over_b;
    (1.0 - 0.025 * r * r + 0.06 * r.powi(4)) * (1.0 / (std::f64::consts::PI * r / 2.0).cos()).sqrt()
}

/// The Paris-law cycles of a centre crack in a plate of half-width `b` (Feddersen's F):
/// ∫ da / (C (F σ √(πa))^m) from `a0` to `a1` at σ = 1, Simpson's rule on 20 000 intervals.
pub fn feddersen_cycles(a0: f64, a1: f64, b: f64, c: f64, m: f64) -> f64 {
    let k = |a: f64| (std::f64::consts::PI * a).sqrt() * feddersen(a / b);
    let n = 20000;
    let h = (a1 - a0) / n as f64;
    (0..n)
        .map(|i| {
            let a = a0 + i as f64 * h;
            h / 6.0 * (1.0 / (c * k(a).powf(m)) + 4.0 / (c * k(a + 0.5 * h).powf(m)) + 1.0 / (c * k(a + h).powf(m)))
        })
        .sum()
}

/// The penny-crack block of meshes/penny_block.msh ([`super::penny_block`]) with the disc
/// crack of radius 1 in z = 0 and `extra` case text (loads, options) before it.
pub fn penny_case(extra: &str) -> String {
    use super::penny_block::{penny_block, penny_block_mesh, PENNY_DISC};
    penny_block(&penny_block_mesh(), extra, PENNY_DISC)
}

/// The through-crack slab of `tests/fracture_sifs_3d.rs` and `tests/crack_geometry_guards.rs`
/// (hex8, [−5, 5] × [−10, 10] × [0, 0.5], 81 × 161 × 2 cells, u_z = 0 on both faces z = 0
/// and z = 0.5, σ = 1 on y = ±10) with a rectangle crack 2a = 2 in y = 0 whose half-width
/// along z is `hz` around z = 0.25.
pub fn slab(hz: f64) -> String {
    format!(
        r#"
[mesh]
generator = "box"
cell = "hex8"
lower = [-5.0, -10.0, 0.0]
upper = [5.0, 10.0, 0.5]
divisions = [81, 161, 2]
[[materials]]
E = 1.0
nu = 0.3
[[sets]]
name = "pin"
on = "abs(x+5) + abs(y+10)"
[[sets]]
name = "roller"
on = "abs(x-5) + abs(y+10)"
[[dirichlet]]
group = "pin"
components = ["x", "y"]
[[dirichlet]]
group = "roller"
components = ["y"]
[[dirichlet]]
group = "front"
components = ["z"]
[[dirichlet]]
group = "back"
components = ["z"]
[[traction]]
group = "top"
value = [0.0, 1.0, 0.0]
[[traction]]
group = "bottom"
value = [0.0, -1.0, 0.0]
[[cracks]]
name = "through"
shape = "rectangle"
centre = [0.0, 0.0, 0.25]
normal = [0.0, 1.0, 0.0]
axis_u = [1.0, 0.0, 0.0]
half_lengths = [1.0, {hz}]
tip_radius = 0.3
sif_radius = 0.5
"#
    )
}
