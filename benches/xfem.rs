//! X-FEM crack benchmark: time per phase, peak memory and K_I accuracy of fissure's
//! cracked models, for comparison with GetFEM 5.4 (`bench/peers/getfem_centre_crack.py`).
//!
//! Run: `cargo bench --bench xfem` (all rows) or `cargo bench --bench xfem -- 2d-centre-1e5`
//! (one row). Each row runs in a child process so that its peak resident memory (VmHWM)
//! is its own.
//!
//! Rows:
//! - `2d-centre-1e5`, `2d-centre-4e5`: centre crack 2a = 2 in the plate [−5, 5] × [−10, 10]
//!   (a/b = 0.2), quad4 157 × 315 and 315 × 631 cells (odd counts: the crack runs between
//!   node rows), E = 1, ν = 0.3, plane strain, σ = 1 on top and bottom, two corner points
//!   holding the rigid modes; tip enrichment radius 0.3, SIF domain radius 0.5. Reference
//!   K_I = σ√(πa)·F, F = 1.02448 (Feddersen, Tada handbook).
//! - `3d-penny-1e5`: penny crack a = 1 in the block [−5, 5]³ (tet4), σ = 1 on z = ±5; a finer
//!   variant of `meshes/penny_block.geo` (sizes × 0.8) generated with gmsh into
//!   `target/bench-meshes/` on first use (the committed mesh if gmsh is missing); tip and
//!   domain radius 0.25. Reference K_I = 2σ√(a/π) (Sneddon), mean and worst over the front.
//!   `3d-penny-1e5` takes the automatic ordering (METIS nested dissection in 3D),
//!   `3d-penny-1e5-amd` the same model with `[solver] ordering = "amd"`.
//! - `3d-penny-contact-5e5`: the penny crack of `examples/penny_crack_contact_3d.toml`
//!   (closed by σ = 1, sheared by τ = 0.5, μ = 0.2, every point sliding) with the default
//!   tip zone (two layers about the front, 0.114 here: 379 638 unknowns; the example's
//!   `tip_radius = 0.25` gives 498 267 unknowns and a double-precision factor of 13.3 GB,
//!   which with the model cannot meet the 16 GB floor, `docs/performance.md`, "The 3D penny
//!   with contact at 5e5 unknowns: the arithmetic, …" and "…: the fewest whole-system
//!   factorisations")
//!   on `meshes/penny_block.geo` with sizes × 0.47 (front cells 0.042; ~4e5 unknowns),
//!   generated with gmsh into `target/bench-meshes/` on first use; `-amd` with
//!   `[solver] ordering = "amd"`. A second table: dofs, wall seconds of mesh + model, contact
//!   set-up, the contact solve (all loops) and the SIFs, peak memory, factorisations and
//!   Newton iterations (the factorisation calls of the Newton loops; the numeric
//!   factorisations of the kept whole-system factor, `solve/faer/kept.rs`, are on the row's
//!   stderr line), and the contact pressure −λ against σ: the worst point farther
//!   than 0.1 a from the front, the worst point overall, and the worst ring average (rings
//!   of width 0.1 a, weighted by the points' areas). Floors (issue 17): ≤ 180 s, ≤ 16 GB.
//!
//! Phases (wall seconds): mesh (generation or reading, formula sets, loads and conditions),
//! level sets (sampling + snap + check), cut, enrich, pattern, assembly, symbolic and
//! numeric factorisation, solve, other (inside the load-step driver: residual check and
//! reactions), SIF (interaction integral over the whole front), total (all of these).
//! Without contact the driver assembles the first step while the symbolic analysis runs
//! (`solve::driver`): `symb.` is the analysis' own time and `assem.` what the assembly
//! added beyond it.

use fissure::case::resolve::{build_mesh, build_model};
use fissure::case::Case;
use fissure::cut::{cut_crack, CutOptions};
use fissure::enrich::{enrich, CrackGeometry, EnrichOptions};
use fissure::levelset;
use fissure::post::sif::{crack_sifs, SifOptions};
use fissure::run::solve_model;
use fissure::solve::linear::Precision;
use fissure::solve::statics::SolveOptions;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::{
    centre_case, cpu_seconds, peak_rss_mb, penny_case, penny_contact_case, penny_mesh, penny_mesh_scaled,
    PENNY_CONTACT_SCALE,
};

enum Geometry {
    /// Centre crack in the tall plate, quad4 `nx` × `ny` cells.
    Centre { nx: usize, ny: usize },
    /// Penny crack in the block, the gmsh tet4 mesh, with this `[solver] ordering`.
    Penny { ordering: &'static str },
    /// The sliding penny crack with friction, the ~5e5-dof gmsh mesh, this ordering.
    PennyContact { ordering: &'static str },
}

struct Row {
    name: &'static str,
    geometry: Geometry,
}

const ROWS: [Row; 6] = [
    Row { name: "2d-centre-1e5", geometry: Geometry::Centre { nx: 157, ny: 315 } },
    Row { name: "2d-centre-4e5", geometry: Geometry::Centre { nx: 315, ny: 631 } },
    Row { name: "3d-penny-1e5", geometry: Geometry::Penny { ordering: "auto" } },
    Row { name: "3d-penny-1e5-amd", geometry: Geometry::Penny { ordering: "amd" } },
    Row { name: "3d-penny-contact-5e5", geometry: Geometry::PennyContact { ordering: "auto" } },
    Row { name: "3d-penny-contact-5e5-amd", geometry: Geometry::PennyContact { ordering: "amd" } },
];

/// Feddersen's finite-width factor for a centre crack (Tada, Paris & Irwin).
fn feddersen(a_over_b: f64) -> f64 {
    let r = a_over_b;
    (1.0 - 0.025 * r * r + 0.06 * r.powi(4)) * (1.0 / (PI * r / 2.0).cos()).sqrt()
}

/// The contact rows: solve the sliding penny, print one row of the second table.
fn run_contact_row(row: &Row, ordering: &str) {
    use fissure::case::resolve;
    use fissure::contact::state::point_values;
    use fissure::run::solve_model_with;
    let total = Instant::now();
    let path = std::env::var_os("FISSURE_BENCH_PENNY_CONTACT_MESH")
        .map_or_else(|| penny_mesh_scaled(PENNY_CONTACT_SCALE, "penny_block_contact").0, PathBuf::from);
    let case =
        Case::parse(&penny_contact_case(&path, ordering), Path::new("bench.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mesh = build_mesh(&case).unwrap_or_else(|e| panic!("{e}"));
    let model = build_model(&case, &mesh).unwrap_or_else(|e| panic!("{e}"));
    let model_s = total.elapsed().as_secs_f64();
    let t = Instant::now();
    let setup = resolve::build_contact(&case, &model).unwrap_or_else(|e| panic!("{e}")).expect("contact");
    let setup_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let options = SolveOptions { ordering: case.solver.ordering, ..Default::default() };
    let (report, sols, states) = solve_model_with(&model, Some(&setup), &options).unwrap_or_else(|e| panic!("{e}"));
    let solve_s = t.elapsed().as_secs_f64();
    let (u, state) = (sols.last().expect("one step"), states.last().expect("one step"));
    let t = Instant::now();
    let pts = &setup.points;
    let cut = &model.cracks[0].cut;
    let traction = |f: usize, x: [f64; 3]| fissure::contact::face_traction(pts, 0, &cut.facets[f], f, x, u);
    let sifs = crack_sifs(&model, 0, u, Some(&traction), &SifOptions { radius: case.cracks[0].sif_radius });
    let sif_s = t.elapsed().as_secs_f64();
    let total_s = total.elapsed().as_secs_f64();
    // The pressure against σ = 1, by the distance d = a − ρ to the front.
    let vals = point_values(&model, pts, None, state, u);
    let (mut far, mut all) = (0.0f64, 0.0f64);
    let mut rings = [(0.0f64, 0.0f64); 10];
    for (p, v) in pts.points.iter().zip(&vals) {
        let d = 1.0 - p.x[0].hypot(p.x[1]);
        let e = -v.lambda - 1.0;
        all = all.max(e.abs());
        if d >= 0.1 {
            far = far.max(e.abs());
        }
        let k = ((d / 0.1) as usize).min(9);
        rings[k].0 += e * p.weight;
        rings[k].1 += p.weight;
    }
    let ring = rings.iter().filter(|r| r.1 > 0.0).map(|r| (r.0 / r.1).abs()).fold(0.0, f64::max);
    let c = report.steps[0].contact.clone().unwrap_or_default();
    println!(
        "| {:24} | {:>7} | {:>6.1} | {:>6.2} | {:>7.1} | {:>5.1} | {:>7.1} | {:>7.0} | {:>4} | {:>4} | {:>6.2}% | {:>6.2}% | {:>6.2}% |",
        row.name,
        report.dofs.n_total(),
        model_s,
        setup_s,
        solve_s,
        sif_s,
        total_s,
        peak_rss_mb(),
        c.factorizations,
        c.newton,
        100.0 * far,
        100.0 * all,
        100.0 * ring,
    );
    eprintln!(
        "{}: {} nodes, {} cells, {} tip nodes, {} Heaviside nodes, {} contact points ({} active), {} front points, nnz(L) {}; kept whole-system factor (numeric factorisations / tangents kept / GMRES iterations): {}; timings {:?}",
        row.name,
        mesh.n_nodes(),
        mesh.n_cells(),
        report.tip_nodes,
        report.heaviside_nodes,
        pts.points.len(),
        c.active,
        sifs.len(),
        report.nnz_factor.map_or("-".to_string(), |v| format!("{:.1}M", v as f64 / 1e6)),
        report.kept_counts.map_or("-".to_string(), |k| format!("{}/{}/{}", k.factorizations, k.reused, k.krylov_iterations)),
        report.timings
    );
}

fn run_row(row: &Row) {
    let total = Instant::now();
    let (text, reference) = match row.geometry {
        Geometry::PennyContact { ordering } => return run_contact_row(row, ordering),
        Geometry::Centre { nx, ny } => (centre_case(nx, ny), PI.sqrt() * feddersen(0.2)),
        Geometry::Penny { ordering } => {
            // The parent made (or chose) the mesh; a row run alone makes its own.
            let path = std::env::var_os("FISSURE_BENCH_PENNY_MESH").map_or_else(|| penny_mesh().0, PathBuf::from);
            (penny_case(&path, ordering), 2.0 / PI.sqrt())
        }
    };
    let mut case = Case::parse(&text, Path::new("bench.toml")).unwrap_or_else(|e| panic!("{e}"));

    // Mesh, sets, loads and conditions (the model without its cracks).
    let t = Instant::now();
    let mesh = build_mesh(&case).unwrap_or_else(|e| panic!("{e}"));
    let build_mesh_s = t.elapsed().as_secs_f64();
    let defs = std::mem::take(&mut case.cracks);
    let mut model = build_model(&case, &mesh).unwrap_or_else(|e| panic!("{e}"));
    case.cracks = defs;
    let mesh_s = t.elapsed().as_secs_f64();

    // The crack phases, as `build_model` runs them.
    let (mut levelset_s, mut cut_s) = (0.0, 0.0);
    for def in &case.cracks {
        let t = Instant::now();
        let mut ls = levelset::sample(&def.shape, &mesh).unwrap_or_else(|e| panic!("{e}"));
        levelset::snap(&mut ls, &mesh, case.xfem.snap);
        levelset::check_crack_in_mesh(&ls, &mesh).unwrap_or_else(|e| panic!("{e}"));
        levelset_s += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let opts = CutOptions {
            subcell_degree: case.xfem.quadrature.subcell_degree,
            front_degree: case.xfem.quadrature.front_degree,
        };
        let cut = cut_crack(&mesh, &ls, &opts).unwrap_or_else(|e| panic!("{e}"));
        cut_s += t.elapsed().as_secs_f64();
        model.cracks.push(CrackGeometry { name: def.name.clone(), levelsets: ls, cut });
        model.crack_pressure.push(def.pressure.clone());
    }
    let t = Instant::now();
    let opts = EnrichOptions {
        tip: case.cracks.iter().map(|c| c.tip).collect(),
        min_side_fraction: case.xfem.min_side_fraction,
    };
    model.enrichment = enrich(&mesh, &model.cracks, &opts).unwrap_or_else(|e| panic!("{e}"));
    let enrich_s = t.elapsed().as_secs_f64();

    // Pattern, assembly, factorisation, solve (one load step).
    let cpu0 = cpu_seconds();
    let t = Instant::now();
    // The factor's arithmetic: `FISSURE_BENCH_PRECISION` = `double`, `mixed` or `auto` (the
    // default, as in a case file).
    let precision = match std::env::var("FISSURE_BENCH_PRECISION").as_deref() {
        Ok("double") => Precision::Double,
        Ok("mixed") => Precision::Mixed,
        _ => Precision::Auto,
    };
    let options = SolveOptions { precision, ..Default::default() };
    let (report, mut sols) = solve_model(&model, &options).unwrap_or_else(|e| panic!("{e}"));
    let u = sols.pop().expect("one load step");
    let driver_s = t.elapsed().as_secs_f64();
    let driver_cpu = cpu_seconds() - cpu0;
    let tm = report.timings;
    let other_s = driver_s - (tm.pattern + tm.assembly + tm.symbolic + tm.numeric + tm.solve);

    // SIFs along the front (no pressure on the faces).
    let cpu0 = cpu_seconds();
    let t = Instant::now();
    let sifs = crack_sifs(&model, 0, &u, None, &SifOptions { radius: case.cracks[0].sif_radius });
    let sif_s = t.elapsed().as_secs_f64();
    let sif_cpu = cpu_seconds() - cpu0;
    let total_s = total.elapsed().as_secs_f64();

    assert!(!sifs.is_empty(), "no SIF point on the front");
    let errs: Vec<f64> = sifs.iter().map(|s| s.k1 / reference - 1.0).collect();
    let mean = sifs.iter().map(|s| s.k1).sum::<f64>() / sifs.len() as f64 / reference - 1.0;
    let worst = errs.iter().cloned().fold(0.0f64, |w, e| if e.abs() > w.abs() { e } else { w });
    println!(
        "| {:13} | {:>7} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.3} | {:>6.2} | {:>6.0} | {:>+7.3}% | {:>+7.3}% |",
        row.name,
        report.dofs.n_total(),
        mesh_s,
        levelset_s,
        cut_s,
        enrich_s,
        tm.pattern,
        tm.assembly,
        tm.symbolic,
        tm.numeric,
        tm.solve,
        other_s,
        sif_s,
        total_s,
        peak_rss_mb(),
        100.0 * mean,
        100.0 * worst,
    );
    // How many cores the phases kept busy (CPU / wall seconds), and the numeric phase's
    // flop rate (flops counted from the supernodal structure).
    println!(
        "|   {}: precision {}{}, {} refinement iterations; pattern to solve CPU {:.1} s = {:.2} cores; SIF CPU {:.1} s = {:.2} cores; numeric {:.3e} flops, {:.1} GFlop/s",
        row.name,
        if report.mixed_precision { "mixed" } else { "double" },
        report.precision_fallback.map_or(String::new(), |r| format!(" (fallback: {r})")),
        report.refinements,
        driver_cpu,
        driver_cpu / driver_s,
        sif_cpu,
        sif_cpu / sif_s,
        report.flops_factor.unwrap_or(f64::NAN),
        report.flops_factor.unwrap_or(f64::NAN) / tm.numeric / 1e9,
    );
    eprintln!(
        "{}: {} nodes, {} cells, {} equations ({} Heaviside nodes, {} tip nodes), nnz(L) {}, {} front points; \
         mesh = build_mesh {:.3} s + build_model without cracks {:.3} s",
        row.name,
        mesh.n_nodes(),
        mesh.n_cells(),
        report.n_eq,
        report.heaviside_nodes,
        report.tip_nodes,
        report.nnz_factor.map_or("-".to_string(), |v| format!("{:.1}M", v as f64 / 1e6)),
        sifs.len(),
        build_mesh_s,
        mesh_s - build_mesh_s
    );
}

fn main() {
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if let Some(name) = args.first() {
        if let Some(row) = ROWS.iter().find(|r| r.name == name) {
            if std::env::var("FISSURE_BENCH_CHILD").is_ok() {
                run_row(row);
                return;
            }
        }
    }
    let selected: Vec<&Row> = ROWS.iter().filter(|r| args.is_empty() || args.iter().any(|a| a == r.name)).collect();
    // The penny meshes are generated once, here, so that gmsh's time is in no row.
    let penny = selected.iter().any(|r| matches!(r.geometry, Geometry::Penny { .. })).then(penny_mesh);
    let penny_contact = selected
        .iter()
        .any(|r| matches!(r.geometry, Geometry::PennyContact { .. }))
        .then(|| penny_mesh_scaled(PENNY_CONTACT_SCALE, "penny_block_contact"));
    println!("fissure X-FEM crack benchmark ({} threads)", rayon::current_num_threads());
    let exe = std::env::current_exe().expect("bench executable path");
    let mut header = None;
    for row in selected {
        let contact = matches!(row.geometry, Geometry::PennyContact { .. });
        if header != Some(contact) {
            header = Some(contact);
            if contact {
                println!("\n| model                    | dofs    | model s| setup s| solve s | SIF s | total s | peak MB | fact.| Newt.| p far  | p all  | p rings |");
                println!("|--------------------------|---------|--------|--------|---------|-------|---------|---------|------|------|--------|--------|---------|");
            } else {
                println!("| model         | dofs    | mesh   | lsets  | cut    | enrich | pattern| assem. | symb.  | numer. | solve  | other  | SIF    | total  | peak MB| K_I mean | K_I worst|");
                println!("|---------------|---------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|--------|----------|----------|");
            }
        }
        let mut child = std::process::Command::new(&exe);
        child.arg(row.name).env("FISSURE_BENCH_CHILD", "1");
        if let Some((path, _)) = &penny {
            child.env("FISSURE_BENCH_PENNY_MESH", path);
        }
        if let Some((path, _)) = &penny_contact {
            child.env("FISSURE_BENCH_PENNY_CONTACT_MESH", path);
        }
        let out = child.output();
        match out {
            Ok(o) if o.status.success() => {
                print!("{}", String::from_utf8_lossy(&o.stdout));
                eprint!("{}", String::from_utf8_lossy(&o.stderr));
            }
            Ok(o) => println!(
                "| {:13} | failed: {}",
                row.name,
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            ),
            Err(e) => println!("| {:13} | could not start: {e}", row.name),
        }
    }
    if let Some((_, note)) = penny {
        println!("\n3d-penny-1e5: {note}");
    }
    if let Some((_, note)) = penny_contact {
        println!("3d-penny-contact-5e5: {note}");
    }
}
