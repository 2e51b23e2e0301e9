//! Linear elasticity benchmark: time per phase and peak memory for 2D quad4 models of
//! ~1e5, ~5e5 and ~1e6 dofs and 3D hex8 models of ~1e5 and ~3e5 dofs, the 3D ones with
//! minimum degree (AMD, the `3d-*` rows) and with METIS nested dissection (`3d-*-nd`).
//!
//! Run: `cargo bench --bench elasticity` (all rows) or
//! `cargo bench --bench elasticity -- 2d-1e5` (one row). Each row runs in a child
//! process so that its peak resident memory (VmHWM) is its own.
//!
//! Phases: pattern (equation numbering, sparsity pattern, colouring: once per model),
//! assembly (first fill), refill (values again on the fixed pattern, as in a Newton
//! iteration), symbolic and numeric Cholesky, solve, and the wall total of
//! assemble + factorise + solve (the figure the floors speak of).

use fissure::assembly::{DofMap, Kernel, SystemLayout};
use fissure::element::CellType;
use fissure::formula::Scalar;
use fissure::mesh::{generate, Mesh};
use fissure::physics::elasticity::{BulkKernel, DirichletMultiplierKernel, FaceLoad, TractionKernel};
use fissure::physics::material::{Analysis, Isotropic};
use fissure::solve::linear::{LinearBackend, LinearMethod, LinearSolver, OrderingChoice, Precision, SystemStructure};
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::{cpu_seconds, peak_rss_mb, rss_mb};

struct Row {
    name: &'static str,
    dim: usize,
    n: usize,
    /// `Auto` without points is the supervariable-compressed AMD.
    ordering: OrderingChoice,
}

const ROWS: [Row; 7] = [
    Row { name: "2d-1e5", dim: 2, n: 223, ordering: OrderingChoice::Auto },
    Row { name: "2d-5e5", dim: 2, n: 500, ordering: OrderingChoice::Auto },
    Row { name: "2d-1e6", dim: 2, n: 707, ordering: OrderingChoice::Auto },
    Row { name: "3d-1e5", dim: 3, n: 31, ordering: OrderingChoice::Auto },
    Row { name: "3d-1e5-nd", dim: 3, n: 31, ordering: OrderingChoice::NestedDissection },
    Row { name: "3d-3e5", dim: 3, n: 45, ordering: OrderingChoice::Auto },
    Row { name: "3d-3e5-nd", dim: 3, n: 45, ordering: OrderingChoice::NestedDissection },
];

/// The factor's arithmetic: `FISSURE_BENCH_PRECISION` = `double`, `mixed` or `auto` (the
/// default, as in a case file), so that the two can be compared on one build.
fn row_precision() -> Precision {
    match std::env::var("FISSURE_BENCH_PRECISION").as_deref() {
        Ok("double") => Precision::Double,
        Ok("mixed") => Precision::Mixed,
        _ => Precision::Auto,
    }
}

fn run_row(row: &Row) {
    let mesh: Mesh = if row.dim == 2 {
        generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [row.n, row.n]).unwrap()
    } else {
        generate::box_mesh(CellType::Hex8, [0.0; 3], [1.0; 3], [row.n, row.n, row.n]).unwrap()
    };
    let dim = mesh.dim;
    let dofs = DofMap::standard(dim, mesh.n_nodes());
    let analysis = if dim == 2 { Analysis::PlaneStrain } else { Analysis::ThreeD };
    let materials = [Isotropic { young: 1.0, poisson: 0.3 }];
    let cell_material = vec![0u32; mesh.n_cells()];
    let cell_bf = vec![None; mesh.n_cells()];
    let bulk = BulkKernel {
        mesh: &mesh,
        dofs: &dofs,
        analysis,
        cell_material: &cell_material,
        materials: &materials,
        cell_body_force: &cell_bf,
        body_forces: &[],
        t: 1.0,
    };
    let faces = mesh.group_faces("right").unwrap().to_vec();
    let face_load = vec![0u32; faces.len()];
    let loads = [FaceLoad::Traction([Scalar::Const(0.0), Scalar::Const(-1e-3), Scalar::Const(0.0)])];
    let traction =
        TractionKernel { mesh: &mesh, dofs: &dofs, faces: &faces, face_load: &face_load, loads: &loads, t: 1.0 };
    let none = DirichletMultiplierKernel { rows: &[], values: &[] };
    let kernels: [&dyn Kernel; 3] = [&bulk, &traction, &none];
    let mut eliminated = vec![false; dofs.n_total()];
    for n in mesh.group_nodes("left").unwrap() {
        for c in 0..dim {
            eliminated[dofs.node_dof(n, c)] = true;
        }
    }
    let prescribed = vec![0.0; dofs.n_total()];

    let t = Instant::now();
    let layout = SystemLayout::build(dofs.n_total(), dofs.n_total(), &eliminated, &kernels);
    let pattern_s = t.elapsed().as_secs_f64();
    let mut values = vec![0.0; layout.pattern.nnz()];
    let mut rhs = vec![0.0; layout.n_eq];
    let t = Instant::now();
    layout.assemble(&kernels, &prescribed, Some(&mut values), Some(&mut rhs));
    let assembly_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    layout.assemble(&kernels, &prescribed, Some(&mut values), None);
    let refill_s = t.elapsed().as_secs_f64();
    if std::env::var("FISSURE_BENCH_PROBE").is_ok() {
        use rayon::prelude::*;
        let t = Instant::now();
        let m = mesh.cells[0].kind.n_nodes() * dim;
        let s: f64 = (0..mesh.n_cells())
            .into_par_iter()
            .map_init(
                || (vec![0.0; m * m], Vec::new()),
                |(k, d), e| {
                    k.iter_mut().for_each(|v| *v = 0.0);
                    d.clear();
                    bulk.dofs(e, d);
                    bulk.compute(e, d, fissure::assembly::LocalOut { matrix: Some(k), vector: None });
                    k[0]
                },
            )
            .sum();
        eprintln!("kernel only: {:.3} s ({s:.1})", t.elapsed().as_secs_f64());
    }
    let t = Instant::now();
    let mut solver = <LinearSolver as LinearBackend>::analyse(&SystemStructure {
        method: LinearMethod::Cholesky,
        pattern: &layout.pattern,
        n_primal: layout.n_eq,
        points: None,
        condense: None,
        ordering: row.ordering,
        memory_limit: None,
        reuse: None,
        precision: row_precision(),
    })
    .unwrap();
    let symbolic_s = t.elapsed().as_secs_f64();
    let rss_before_numeric = rss_mb();
    let peak_before_numeric = peak_rss_mb();
    let cpu0 = cpu_seconds();
    let t = Instant::now();
    solver.factorize(&values).unwrap();
    let numeric_s = t.elapsed().as_secs_f64();
    let numeric_cpu = cpu_seconds() - cpu0;
    let t = Instant::now();
    let mut x = rhs.clone();
    solver.solve_in_place(&mut x).unwrap();
    let solve_s = t.elapsed().as_secs_f64();
    let total = pattern_s + assembly_s + symbolic_s + numeric_s + solve_s;
    let nnz_l = solver.stats().nnz_factor.map_or("-".to_string(), |v| format!("{:.1}M", v as f64 / 1e6));
    println!(
        "| {:9} | {:>9} | {:>8.3} | {:>8.3} | {:>8.3} | {:>8.3} | {:>8.3} | {:>8.3} | {:>8.2} | {:>7} | {:>8.0} |",
        row.name,
        layout.n_eq,
        pattern_s,
        assembly_s,
        refill_s,
        symbolic_s,
        numeric_s,
        solve_s,
        total,
        nnz_l,
        peak_rss_mb()
    );
    // The numeric phase in detail: its flop rate (flops counted from the supernodal
    // structure), how many cores it kept busy (CPU / wall seconds), and what was resident
    // beside the factor (RSS before the numeric phase; the factor's values are zeroed
    // pages until then) and faer's scratch.
    let stats = solver.stats();
    let mb = |b: usize| b as f64 / 1048576.0;
    let entry = if stats.mixed { 4 } else { 8 };
    println!(
        "|   {}: precision {}{}, {} refinement iterations (residual {:.1e}); numeric {:.3e} flops, {:.1} GFlop/s, CPU {:.1} s = {:.2} cores; RSS before numeric {:.0} MB (peak until then {:.0} MB), L {:.0} MB, scratch {:.0} MB",
        row.name,
        if stats.mixed { "mixed" } else { "double" },
        stats.fallback.map_or(String::new(), |r| format!(" (fallback: {r})")),
        solver.last_residual().1,
        solver.last_residual().0,
        stats.flops_factor.unwrap_or(f64::NAN),
        stats.flops_factor.unwrap_or(f64::NAN) / numeric_s / 1e9,
        numeric_cpu,
        numeric_cpu / numeric_s,
        rss_before_numeric,
        peak_before_numeric,
        stats.nnz_factor.map_or(f64::NAN, |n| mb(entry * n)),
        stats.factor_scratch_bytes.map_or(f64::NAN, mb),
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
    println!("fissure linear elasticity benchmark ({} threads)", rayon::current_num_threads());
    println!("| model     | equations | pattern  | assembly | refill   | symbolic | numeric  | solve    | total s  | nnz(L)  | peak MB  |");
    println!("|-----------|-----------|----------|----------|----------|----------|----------|----------|----------|---------|----------|");
    let exe = std::env::current_exe().expect("bench executable path");
    for row in selected {
        let out = std::process::Command::new(&exe).arg(row.name).env("FISSURE_BENCH_CHILD", "1").output();
        match out {
            Ok(o) if o.status.success() => print!("{}", String::from_utf8_lossy(&o.stdout)),
            Ok(o) => println!(
                "| {:9} | failed: {}",
                row.name,
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            ),
            Err(e) => println!("| {:9} | could not start: {e}", row.name),
        }
    }
}
