//! Crack growth benchmark: the cost of one growth increment, split by phase, beside one
//! static solve of the same model (issue 21, item 9).
//!
//! Run: `cargo bench --bench growth` (both rows) or `cargo bench --bench growth -- 2d-centre-1e5`
//! (one row). Each row runs in a child process.
//!
//! Rows:
//! - `2d-centre-1e5`: the centre crack of `benches/xfem.rs` (2a = 2 in the plate
//!   [−5, 5] × [−10, 10], quad4 157 × 315, about 1e5 dofs, E = 1, ν = 0.3, plane strain,
//!   σ = 1 on top and bottom, tip radius 0.3, SIF radius 0.5) grown by 20 increments of
//!   Δa = 0.1 at both tips (maximum hoop stress, p = 2): a from 1 to 3.
//! - `3d-penny-1e5`: the penny crack of `benches/xfem.rs` (a = 1 in the block [−5, 5]³,
//!   the finer tet4 mesh, about 1e5 dofs, tip and SIF radius 0.25) grown by 5 increments
//!   of Δa = 0.1 (a from 1 to 1.5).
//!
//! Each increment runs the stages of the growth loop (`run::growth`) with the library's
//! own pieces, as `benches/xfem.rs` does for one solve: geometry (the criterion, the new
//! segment or strip, the body checks, the grown crack's explicit shape), model (materials,
//! loads and conditions: `build_model` without the cracks), level sets (sampling, snap,
//! check), cut, enrichment, pattern and ordering (the sparsity pattern and the symbolic
//! analysis), assembly, factorisation (numeric), solve, other (inside the load-step driver)
//! and SIFs. The static solve is the initial model solved alone (from the case's analytic
//! shape), run before and after the increments; the fastest of the two is reported.
//! Floor (issue 21): the mean 2D increment costs at most 1.3× one static solve.
//! The static solve before the increments and the increments share one
//! `ReusedOrdering`, as the entries of `fissure run` do (the 2D node order is computed
//! once and expanded); the static solve after them computes its own. The last summary
//! line gives the time of the ordering itself and nnz(L); `FISSURE_BENCH_NO_REUSE=1`
//! makes every analysis order anew (the reference for the reuse).
//! The per-increment output (VTU, summary, CSV) of `fissure run` is not timed here.

use fissure::case::resolve::{build_mesh, build_model};
use fissure::case::Case;
use fissure::cut::{cut_crack, CutOptions};
use fissure::enrich::{enrich, CrackGeometry, EnrichOptions};
use fissure::growth::criteria;
use fissure::growth::polyline::{Body2d, GrowingCurve};
use fissure::growth::surface::{interpolate_on_front, smooth_k_eq, Body3d, GrowingSurface};
use fissure::growth::{Criterion, Propagation};
use fissure::levelset::{self, CrackShape};
use fissure::mesh::Mesh;
use fissure::post::sif::{crack_sifs, SifOptions, SifPoint};
use fissure::run::solve_model;
use fissure::solve::ordering::reuse::ReusedOrdering;
use fissure::solve::statics::SolveOptions;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::{centre_case, peak_rss_mb, penny_case, penny_mesh};

const INCREMENT: f64 = 0.1;

/// Wall seconds of one solve of a cracked model, by phase.
#[derive(Debug, Clone, Copy, Default)]
struct Phases {
    geometry: f64,
    model: f64,
    levelsets: f64,
    cut: f64,
    enrich: f64,
    pattern: f64,
    /// The parts of `pattern`: the layout (sparsity pattern, colouring) and the symbolic
    /// analysis (ordering, elimination tree, supernodes).
    layout: f64,
    symbolic: f64,
    /// The part of `symbolic` in the fill-reducing ordering itself (computed, or the kept
    /// node order expanded: `solve::ordering::reuse`).
    ordering: f64,
    /// Entries of the factor.
    nnz_factor: usize,
    assembly: f64,
    numeric: f64,
    solve: f64,
    other: f64,
    sif: f64,
}

impl Phases {
    fn total(&self) -> f64 {
        self.geometry
            + self.model
            + self.levelsets
            + self.cut
            + self.enrich
            + self.pattern
            + self.assembly
            + self.numeric
            + self.solve
            + self.other
            + self.sif
    }
    fn row(&self, label: &str, dofs: usize) -> String {
        format!(
            "| {label:26} | {dofs:>7} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} |",
            self.geometry,
            self.model,
            self.levelsets,
            self.cut,
            self.enrich,
            self.pattern,
            self.assembly,
            self.numeric,
            self.solve,
            self.other,
            self.sif,
            self.total()
        )
    }
}

/// Builds the model of `shape` (the case's other keys), solves it and computes the SIFs of
/// crack 0; `phases.geometry` is left to the caller.
fn solve_cracked(
    case: &Case,
    mesh: &Mesh,
    shape: &CrackShape,
    phases: &mut Phases,
    options: &SolveOptions,
) -> (Vec<SifPoint>, usize) {
    let t = Instant::now();
    let mut bare = case.clone();
    let defs = std::mem::take(&mut bare.cracks);
    let mut model = build_model(&bare, mesh).unwrap_or_else(|e| panic!("{e}"));
    phases.model = t.elapsed().as_secs_f64();
    let def = &defs[0];

    let t = Instant::now();
    let mut ls = levelset::sample(shape, mesh).unwrap_or_else(|e| panic!("{e}"));
    levelset::snap(&mut ls, mesh, case.xfem.snap);
    levelset::check_crack_in_mesh(&ls, mesh).unwrap_or_else(|e| panic!("{e}"));
    phases.levelsets = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let opts = CutOptions {
        subcell_degree: case.xfem.quadrature.subcell_degree,
        front_degree: case.xfem.quadrature.front_degree,
    };
    let cut = cut_crack(mesh, &ls, &opts).unwrap_or_else(|e| panic!("{e}"));
    phases.cut = t.elapsed().as_secs_f64();
    model.cracks.push(CrackGeometry { name: def.name.clone(), levelsets: ls, cut });
    model.crack_pressure.push(def.pressure.clone());
    let t = Instant::now();
    let opts = EnrichOptions { tip: vec![def.tip], min_side_fraction: case.xfem.min_side_fraction };
    model.enrichment = enrich(mesh, &model.cracks, &opts).unwrap_or_else(|e| panic!("{e}"));
    phases.enrich = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let ordering_before = options.reuse_ordering.as_ref().map_or(0.0, |r| r.seconds());
    let (report, mut sols) = solve_model(&model, options).unwrap_or_else(|e| panic!("{e}"));
    phases.ordering = options.reuse_ordering.as_ref().map_or(0.0, |r| r.seconds()) - ordering_before;
    phases.nnz_factor = report.nnz_factor.unwrap_or(0);
    let u = sols.pop().expect("one load step");
    let driver = t.elapsed().as_secs_f64();
    let tm = report.timings;
    phases.pattern = tm.pattern + tm.symbolic;
    (phases.layout, phases.symbolic) = (tm.pattern, tm.symbolic);
    phases.assembly = tm.assembly;
    phases.numeric = tm.numeric;
    phases.solve = tm.solve;
    phases.other = driver - (tm.pattern + tm.assembly + tm.symbolic + tm.numeric + tm.solve);

    let t = Instant::now();
    let sifs = crack_sifs(&model, 0, &u, None, &SifOptions { radius: def.sif_radius });
    phases.sif = t.elapsed().as_secs_f64();
    assert!(!sifs.is_empty(), "no SIF point on the front");
    (sifs, report.dofs.n_total())
}

fn propagation(steps: usize) -> Propagation {
    Propagation {
        criterion: Criterion::MaxHoopStress,
        increment: INCREMENT,
        steps,
        exponent: 2.0,
        fracture_toughness: None,
        stop_length: None,
        threshold: 0.0,
        fatigue: None,
    }
}

/// The static solve of the initial model, then `steps` increments, then the static solve
/// again; prints one table row per increment and the summary lines.
fn run_row(name: &str) {
    let (text, steps, dim3) = match name {
        "2d-centre-1e5" => (centre_case(157, 315), 20, false),
        _ => {
            let path = std::env::var_os("FISSURE_BENCH_PENNY_MESH").map_or_else(|| penny_mesh().0, PathBuf::from);
            (penny_case(&path, "auto"), 5, true)
        }
    };
    let case = Case::parse(&text, Path::new("bench.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mesh = build_mesh(&case).unwrap_or_else(|e| panic!("{e}"));
    let prop = propagation(steps);
    let initial = case.cracks[0].shape.clone();

    // One node order for the run, as `run::growth` does (FISSURE_BENCH_NO_REUSE=1: each
    // analysis computes its own, the reference).
    let reuse = Arc::new(if std::env::var_os("FISSURE_BENCH_NO_REUSE").is_some() {
        ReusedOrdering::never()
    } else {
        ReusedOrdering::new()
    });
    let options = SolveOptions { reuse_ordering: Some(reuse.clone()), ..SolveOptions::default() };
    let mut statics = vec![];
    let mut p = Phases::default();
    let (first_sifs, dofs) = solve_cracked(&case, &mesh, &initial, &mut p, &options);
    statics.push(p);
    println!("{}", p.row(&format!("{name} static"), dofs));

    let mut increments = vec![];
    let mut sifs = first_sifs;
    if dim3 {
        let body = Body3d::new(&mesh);
        let first = GrowingSurface::from_shape(&initial, mesh.typical_size()).expect("a disc");
        let spacing = body.spacing(&first.front_points());
        let mut surface = GrowingSurface::from_shape(&initial, spacing).expect("a disc");
        for step in 1..=steps {
            let mut p = Phases::default();
            let t = Instant::now();
            // As run_growth_3d: the driving force smoothed along the front, then the advances.
            let at: Vec<[f64; 3]> = sifs.iter().map(|s| s.x).collect();
            let front = surface.front_points();
            let drives: Vec<(f64, f64)> =
                sifs.iter().map(|s| criteria::drive_3d(prop.criterion, s.k1, s.k2, s.k3)).collect();
            let k_eq = smooth_k_eq(&front, &at, &drives.iter().map(|d| d.1).collect::<Vec<_>>());
            let ds: Vec<(f64, f64, bool)> = drives.iter().zip(&k_eq).map(|(d, k)| (d.0, *k, true)).collect();
            let plan = criteria::advances(&ds, &prop).expect("a front above the threshold");
            let adv: Vec<f64> = plan.iter().map(|q| q.advance).collect();
            let th: Vec<f64> = plan.iter().map(|q| q.theta).collect();
            let spacing = body.spacing(&front);
            let adv = interpolate_on_front(&front, &at, &adv);
            let th = interpolate_on_front(&front, &at, &th);
            let new = surface.advance(&adv, &th, spacing);
            assert!(new.iter().all(|x| body.depth(*x) > body.cell_size(*x)), "the front reached the boundary");
            let shape = surface.shape().unwrap_or_else(|e| panic!("{e}"));
            p.geometry = t.elapsed().as_secs_f64();
            let (s, dofs) = solve_cracked(&case, &mesh, &shape, &mut p, &options);
            sifs = s;
            println!("{}", p.row(&format!("{name} increment {step}"), dofs));
            increments.push(p);
        }
        let r: Vec<f64> = sifs.iter().map(|s| s.x[0].hypot(s.x[1])).collect();
        eprintln!("{name}: front mean radius after {steps} increments {:.5}", r.iter().sum::<f64>() / r.len() as f64);
    } else {
        let body = Body2d::new(&mesh);
        let mut curve = GrowingCurve::from_shape(&initial, &body).expect("a segment");
        for step in 1..=steps {
            let mut p = Phases::default();
            let t = Instant::now();
            let ks: Vec<(f64, f64, bool)> = sifs.iter().map(|s| (s.k1, s.k2, true)).collect();
            let plan = criteria::plan(&ks, &prop).expect("a tip above the threshold");
            for (s, q) in sifs.iter().zip(&plan) {
                let end = if dist(curve.end(0), s.x) < dist(curve.end(1), s.x) { 0 } else { 1 };
                let (c, sn) = (q.theta.cos(), q.theta.sin());
                let from = curve.end(end);
                let to = [
                    from[0] + q.advance * (c * s.e1[0] + sn * s.e2[0]),
                    from[1] + q.advance * (c * s.e1[1] + sn * s.e2[1]),
                    0.0,
                ];
                assert!(body.contains_segment(from, to) && body.depth(to) > body.cell_size(to), "a tip left the body");
                curve.extend(end, to);
            }
            let shape = curve.shape().unwrap_or_else(|e| panic!("{e}"));
            p.geometry = t.elapsed().as_secs_f64();
            let (s, dofs) = solve_cracked(&case, &mesh, &shape, &mut p, &options);
            sifs = s;
            println!("{}", p.row(&format!("{name} increment {step}"), dofs));
            increments.push(p);
        }
        eprintln!("{name}: tips after {steps} increments at {:?} and {:?}", curve.end(0), curve.end(1));
    }
    let mut p = Phases::default();
    solve_cracked(&case, &mesh, &initial, &mut p, &SolveOptions::default());
    statics.push(p);
    println!("{}", p.row(&format!("{name} static again"), dofs));

    let n = increments.len() as f64;
    let mean = increments.iter().map(Phases::total).sum::<f64>() / n;
    let fastest = increments.iter().map(Phases::total).fold(f64::INFINITY, f64::min);
    let stat = statics.iter().map(Phases::total).fold(f64::INFINITY, f64::min);
    let share = |f: fn(&Phases) -> f64| 100.0 * increments.iter().map(f).sum::<f64>() / (n * mean);
    println!(
        "{name}: one static solve {stat:.3} s (fastest of 2); an increment {mean:.3} s mean, {fastest:.3} s fastest: {:.2}x a static solve (mean){}",
        mean / stat,
        if dim3 { String::new() } else { format!(", floor 1.3x: {}", if mean <= 1.3 * stat { "met" } else { "NOT met" }) }
    );
    println!(
        "{name}: share of an increment: geometry {:.1}%, model {:.1}%, level sets {:.1}%, cut {:.1}%, enrichment {:.1}%, pattern+ordering {:.1}%, assembly {:.1}%, factorisation {:.1}%, solve {:.1}%, SIFs {:.1}%; peak {:.0} MB",
        share(|p| p.geometry),
        share(|p| p.model),
        share(|p| p.levelsets),
        share(|p| p.cut),
        share(|p| p.enrich),
        share(|p| p.pattern),
        share(|p| p.assembly),
        share(|p| p.numeric),
        share(|p| p.solve),
        share(|p| p.sif),
        peak_rss_mb()
    );
    println!(
        "{name}: pattern + ordering of a mean increment: layout (pattern, colouring) {:.3} s, symbolic analysis (ordering, elimination tree) {:.3} s",
        increments.iter().map(|p| p.layout).sum::<f64>() / n,
        increments.iter().map(|p| p.symbolic).sum::<f64>() / n
    );
    let (computed, reused) = reuse.counts();
    println!(
        "{name}: of the symbolic analysis, the ordering itself {:.3} s (mean increment; static solve {:.3} s); orderings computed {computed}, reused {reused}; nnz(L) static {}, increment 1 {}, increment {} {}",
        increments.iter().map(|p| p.ordering).sum::<f64>() / n,
        statics[0].ordering,
        statics[0].nnz_factor,
        increments[0].nnz_factor,
        increments.len(),
        increments[increments.len() - 1].nnz_factor,
    );
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

const ROWS: [&str; 2] = ["2d-centre-1e5", "3d-penny-1e5"];

fn main() {
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if let Some(name) = args.first() {
        if ROWS.contains(&name.as_str()) && std::env::var("FISSURE_BENCH_CHILD").is_ok() {
            run_row(name);
            return;
        }
    }
    let selected: Vec<&str> = ROWS.iter().copied().filter(|r| args.is_empty() || args.iter().any(|a| a == r)).collect();
    let penny = selected.contains(&"3d-penny-1e5").then(penny_mesh);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("fissure crack growth benchmark ({} threads, load average {})", rayon::current_num_threads(), load.trim());
    println!("| row                        | dofs    | geom.  | model  | lsets  | cut    | enrich | pat+ord| assem. | factor.| solve  | other  | SIF    | total  |");
    println!("|----------------------------|---------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|");
    let exe = std::env::current_exe().expect("bench executable path");
    for row in selected {
        let mut child = std::process::Command::new(&exe);
        child.arg(row).env("FISSURE_BENCH_CHILD", "1");
        if let Some((path, _)) = &penny {
            child.env("FISSURE_BENCH_PENNY_MESH", path);
        }
        match child.output() {
            Ok(o) if o.status.success() => {
                print!("{}", String::from_utf8_lossy(&o.stdout));
                eprint!("{}", String::from_utf8_lossy(&o.stderr));
            }
            Ok(o) => {
                println!("| {row:26} | failed: {}", String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or(""))
            }
            Err(e) => println!("| {row:26} | could not start: {e}"),
        }
    }
    if let Some((_, note)) = penny {
        println!("\n3d-penny-1e5: {note}");
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average at the end: {}", load.trim());
}
