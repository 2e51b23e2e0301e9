//! Large-sliding benchmark: the cost of one pairing (deformed master lip, its BVH, the
//! narrow-band projection of every slave point) and the geometry loop's share of whole
//! large-sliding runs.
//!
//! Run: `cargo bench --bench sliding` (all rows) or `cargo bench --bench sliding -- pair-3d`.
//!
//! Rows:
//! - `pair-2d`, `pair-3d`: a through interface (2D: the line y = 0 across a quad4 strip of
//!   50 000 × 3 cells, two facets per cut cell; 3D: the plane z = 0 across a hex8 slab of
//!   120 × 120 × 3 cells) with the `+` side translated rigidly by 2.5 cells along the
//!   interface (standard dofs d on the + nodes, Heaviside dofs d/2). Gauss contact points.
//!   Rows `pair-2d-1`, `pair-3d-1` keep one contact point per facet (as many points as
//!   master facets: 1e5 against 1e5 in 2D). The time is the best of 5 calls of `contact::pairing::pair` (all of it: deforming the
//!   master facets, building the BVH, projecting every point), with rayon on 2 threads.
//! - `run-2d`, `run-3d`: the sliding blocks of `tests/large_sliding.rs` with `vertex`
//!   contact integration (2D: 120 × 21 quad4,
//!   10 slide steps; 3D: 10 × 10 × 7 hex8, 5 slide steps), whole solve: the time spent in
//!   the geometry loop (pairing, plus the pattern rebuilds and symbolic analyses it causes)
//!   against the total.

use fissure::case::resolve::{build_contact, build_mesh, build_model};
use fissure::case::Case;
use fissure::contact::pairing::{pair, PairingOptions};
use fissure::enrich::EnrichKind;
use fissure::run::solve_model_recorded;
use fissure::solve::statics::SolveOptions;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
#[path = "../tests/common/sliding.rs"]
mod sliding_cases;
use common::peak_rss_mb;

fn strip_2d() -> String {
    r#"
[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.0015]
upper = [50.0, 0.0015]
divisions = [50000, 3]
[[materials]]
E = 1.0
nu = 0.0
[[dirichlet]]
group = "bottom"
components = ["x", "y"]
[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[cracks.contact]
sliding = "large"
"#
    .to_string()
}

fn slab_3d() -> String {
    r#"
[mesh]
generator = "box"
cell = "hex8"
lower = [0.0, 0.0, -0.015]
upper = [1.2, 1.2, 0.015]
divisions = [120, 120, 3]
[[materials]]
E = 1.0
nu = 0.0
[[dirichlet]]
group = "back"
components = ["x", "y", "z"]
[[cracks]]
name = "interface"
shape = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[cracks.contact]
sliding = "large"
"#
    .to_string()
}

/// Times one pairing of a case with the + side translated by `d`; with `one_per_facet`,
/// only the first contact point of each facet is kept (as many points as facets).
fn pair_row(name: &str, text: &str, d: [f64; 3], one_per_facet: bool) {
    let case = Case::parse(text, Path::new("bench.toml")).expect("case");
    let mesh = build_mesh(&case).expect("mesh");
    let model = build_model(&case, &mesh).expect("model");
    let mut setup = build_contact(&case, &model).expect("contact").expect("contact");
    if one_per_facet {
        let pts = &mut setup.points;
        let kept: Vec<_> = pts.facets.iter().map(|(_, _, r)| pts.points[r.start].clone()).collect();
        for (k, f) in pts.facets.iter_mut().enumerate() {
            f.2 = k..k + 1;
        }
        pts.points = kept;
    }
    let dim = mesh.dim;
    let n_total = model.enrichment.dofs.n_total() + setup.points.n_unknowns;
    let mut u = vec![0.0; n_total];
    let lsn = &model.cracks[0].levelsets.lsn;
    for n in 0..mesh.n_nodes() {
        if lsn[n] >= 0.0 {
            for i in 0..dim {
                u[n * dim + i] = d[i];
            }
        }
        for item in model.enrichment.node_items(n) {
            if item.kind == EnrichKind::Heaviside {
                for i in 0..dim {
                    u[item.first_dof as usize + i] = 0.5 * d[i];
                }
            }
        }
    }
    let opts = PairingOptions::default();
    let mut best = f64::INFINITY;
    let mut counts = Default::default();
    for _ in 0..5 {
        let clock = Instant::now();
        let p = pair(&mesh, &model.enrichment, &model.cracks, &setup.points, &u, &opts, &[]);
        best = best.min(clock.elapsed().as_secs_f64());
        counts = p.counts;
    }
    println!(
        "| {name:9} | {:>9} | {:>9} | {:>8.3} | {:>8} | {:>8} | {:>8.0} |",
        setup.points.points.len(),
        model.cracks[0].cut.facets.len(),
        best,
        counts.paired,
        counts.outside + counts.far + counts.failed,
        peak_rss_mb()
    );
}

/// A whole large-sliding run: (geometry loop s, total s, steps, geometry iterations).
fn run_row(name: &str, text: &str) {
    let case = Case::parse(text, Path::new("bench.toml")).expect("case");
    let mesh = build_mesh(&case).expect("mesh");
    let model = build_model(&case, &mesh).expect("model");
    let setup = build_contact(&case, &model).expect("contact").expect("contact");
    let clock = Instant::now();
    let (report, _) = solve_model_recorded(&model, Some(&setup), &SolveOptions::default()).expect("solves");
    let total = clock.elapsed().as_secs_f64();
    let t = report.timings;
    // The first pattern and symbolic analysis belong to any run; the geometry loop adds the
    // pairings and the rebuilds it triggers.
    let rebuilds: usize = report.steps.iter().filter_map(|s| s.contact.as_ref()).map(|c| c.pattern_rebuilds).sum();
    let geo_iters: usize = report.steps.iter().filter_map(|s| s.contact.as_ref()).map(|c| c.geometry).sum();
    let per_build = (t.pattern + t.symbolic) / (rebuilds + 1) as f64;
    let geometry = t.pairing + per_build * rebuilds as f64;
    println!(
        "| {name:8} | {:>7} | {:>5} | {:>8} | {:>8} | {:>8.3} | {:>8.3} | {:>8.3} | {:>7.1}% |",
        report.n_eq,
        report.steps.len(),
        geo_iters,
        rebuilds,
        t.pairing,
        geometry,
        total,
        100.0 * geometry / total
    );
}

/// The platen of the 2D sliding blocks: pressing by 0.002, moving by 0.03 per step.
const PLATEN_2D: &str = r#"[[dirichlet]]
group = "top"
components = ["x", "y"]
values = ["0.03 * t", "-0.002 + 0 * t"]"#;

fn main() {
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let filter: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let want = |name: &str| filter.is_empty() || filter.iter().any(|f| name.contains(f.as_str()));
    println!("Pairing (best of 5, rayon threads: {})", rayon::current_num_threads());
    println!("| row       | points    | facets    | pair s   | paired   | unpaired | peak MB  |");
    println!("|-----------|-----------|-----------|----------|----------|----------|----------|");
    if want("pair-2d") {
        pair_row("pair-2d", &strip_2d(), [0.0025, 0.0, 0.0], false);
        pair_row("pair-2d-1", &strip_2d(), [0.0025, 0.0, 0.0], true);
    }
    if want("pair-3d") {
        pair_row("pair-3d", &slab_3d(), [0.025, 0.0, 0.0], false);
        pair_row("pair-3d-1", &slab_3d(), [0.025, 0.0, 0.0], true);
    }
    println!();
    println!("Geometry loop share of whole large-sliding runs");
    println!("| row      | eqs     | steps | geo its  | rebuilds | pair s   | geom. s  | total s  | share    |");
    println!("|----------|---------|-------|----------|----------|----------|----------|----------|----------|");
    if want("run-2d") {
        run_row("run-2d", &sliding_cases::blocks(0.5, PLATEN_2D, 10, "vertex"));
    }
    if want("run-3d") {
        run_row("run-3d", &sliding_cases::inclined_plane_blocks("large", 0.16, 5, "vertex").0);
    }
}
