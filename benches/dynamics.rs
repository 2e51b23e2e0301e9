//! Dynamics benchmark (issue 15 item 8): the time per step of the implicit dynamics driver
//! (`solve::dynamics::solve_time_steps`, Newmark average acceleration) on a 2D bar — a
//! strip [0, 1.05] × [0, ny h] of nx × ny quad4 (h = 1.05/nx, E = ρ = 1, ν = 0, plane
//! stress, Δt = h/(2c)) — at ~1e5 and ~1e6 dofs, without contact (the free strip moving at
//! v₀ = 0.01) and with contact (two blocks meeting at ±v₀ across a frictionless X-FEM
//! interface in the middle of a cell near x = 0.525, velocity formulation, the lips
//! touching at t = 0 and closed for 2L/c ≈ 1.05, longer than the contact rows' runs: no
//! status change after the first steps). The bar against a lip-held rigid wall of
//! tests/dynamics_bar_rigid_wall.rs is `DYN_BENCH_WALL=1` (its first step's Newton loop
//! did not converge from nx = 200 before the corrections stopped deferring the interior
//! with Dirichlet or relation multipliers: docs/performance.md).
//!
//! Run: `cargo bench --bench dynamics` (all rows) or `cargo bench --bench dynamics -- 1e5`.
//! `FISSURE_BENCH_TIMINGS=1` prints under each row the mean time per step of each phase of
//! the step (`Timings::step_phases`).
//! Columns: dofs, steps, numeric factorisations over the run, the median time of a step
//! after the first (the first assembles and factorises the effective matrix), the time of
//! one triangular solve pair and of one residual (right-hand side) assembly measured on the
//! same model and the same effective matrix (best of 5), the ratio step / (solve +
//! assembly) (floor: ≤ 1.5), and the whole run's time (floor: 2 000 steps at 1e5 dofs in
//! under a minute).

use fissure::assembly::Kernel;
use fissure::case::{resolve, Case};
use fissure::physics::inertia::{EffectiveKernel, ElementMatrices};
use fissure::solve::dynamics::{densities, mass_kernel, project_field, solve_time_steps, InitialState};
use fissure::solve::observe::Silent;
use fissure::solve::report::SolveOptions;
use fissure::solve::setup::Setup;
use fissure::solve::time::{DynamicScheme, Newmark};
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::peak_rss_mb;

/// (label, nx, ny, steps without contact, steps with contact).
const ROWS: [(&str, usize, usize, usize, usize); 2] = [("1e5", 1000, 49, 2000, 200), ("1e6", 3162, 157, 20, 10)];

/// Where the interface of the contact rows lies: the middle of a cell near the strip's
/// middle (two blocks), or of the last cell (against the wall, `DYN_BENCH_WALL`).
fn interface(nx: usize) -> f64 {
    let h = 1.05 / nx as f64;
    if std::env::var("DYN_BENCH_WALL").is_ok() {
        1.05 - 0.5 * h
    } else {
        ((nx / 2) as f64 + 0.5) * h
    }
}

fn case_text(nx: usize, ny: usize, contact: bool) -> String {
    let h = 1.05 / nx as f64;
    let len = interface(nx);
    let crack = if contact && std::env::var("DYN_BENCH_WALL").is_err() {
        format!("[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [{len}, 0.0]\nnormal = [1.0, 0.0]\n[cracks.contact]\nfriction = 0.0\n")
    } else if contact {
        format!(
            "[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [{len}, 0.0]\nnormal = [1.0, 0.0]\n\
             [cracks.contact]\nfriction = 0.0\n[[sets]]\nname = \"wall\"\ninside = \"{} - x\"\n\
             [[dirichlet]]\ngroup = \"wall\"\ncomponents = [\"x\", \"y\"]\ncrack = \"interface\"\nlip = \"+\"\n",
            len - 0.75 * h
        )
    } else {
        String::new()
    };
    format!(
        "[model]\nanalysis = \"plane_stress\"\n[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\n\
         upper = [1.05, {}]\ndivisions = [{nx}, {ny}]\n[[materials]]\nE = 1.0\nnu = 0.0\ndensity = 1.0\n{crack}\
         [dynamics]\ndt = {}\nsteps = 1\n",
        h * ny as f64,
        0.5 * h
    )
}

struct Row {
    dofs: usize,
    steps: usize,
    factorizations: usize,
    linear_solves: usize,
    step_median: f64,
    solve_pair: f64,
    assembly: f64,
    run: f64,
    timings: fissure::solve::report::Timings,
}

fn run(nx: usize, ny: usize, steps: usize, contact: bool) -> Row {
    let text = case_text(nx, ny, contact);
    let case = Case::parse(&text, Path::new("bench.toml")).expect("case");
    let mesh = resolve::build_mesh(&case).expect("mesh");
    let model = resolve::build_model(&case, &mesh).expect("model");
    let setup_c = resolve::build_contact(&case, &model).expect("contact");
    let h = 1.05 / nx as f64;
    let len = interface(nx);
    let dt = 0.5 * h;
    let wall = std::env::var("DYN_BENCH_WALL").is_ok();
    let scheme = DynamicScheme::Newmark(Newmark::average_acceleration(dt, steps));
    let options = SolveOptions::default();
    let v0 = 0.01;
    // Two blocks meet at ±v₀ (the wall: the bar at v₀, the wall at rest); no contact: the
    // same field on the uncut strip.
    let field = move |_c: usize, x: [f64; 3]| {
        Some([
            if x[0] < len {
                v0
            } else if wall {
                0.0
            } else {
                -v0
            },
            0.0,
            0.0,
        ])
    };
    let v = project_field(&model, &field, &options).expect("initial velocity");
    let initial = InitialState { u: vec![], v };
    let mut stamps = vec![];
    let (mut factorizations, mut linear_solves) = (0, 0);
    let clock = Instant::now();
    let report = solve_time_steps(&model, setup_c.as_ref(), &options, &scheme, &initial, &Silent, &mut |s| {
        stamps.push(clock.elapsed().as_secs_f64());
        if s.report.index > 0 {
            factorizations += s.report.factorizations;
            linear_solves += s.report.linear_solves;
        }
        Ok(())
    })
    .expect("dynamics");
    let run = clock.elapsed().as_secs_f64();
    let mut per_step: Vec<f64> = stamps.windows(2).skip(1).map(|w| w[1] - w[0]).collect();
    per_step.sort_by(f64::total_cmp);
    let step_median = per_step.get(per_step.len() / 2).copied().unwrap_or(f64::NAN);
    let (solve_pair, assembly) = reference_costs(&model, setup_c.as_ref(), &options, dt);
    Row {
        dofs: report.dofs.n_total(),
        steps,
        factorizations,
        linear_solves,
        step_median,
        solve_pair,
        assembly,
        run,
        timings: report.timings,
    }
}

/// One triangular solve pair and one right-hand-side assembly of the first time step's
/// effective system (the fixed kernels and, with contact, the contact kernel), on the
/// driver's layout and analysis; the best of 5 each.
fn reference_costs(
    model: &fissure::physics::model::Model<'_>,
    contact: Option<&fissure::contact::ContactSetup>,
    options: &SolveOptions,
    dt: f64,
) -> (f64, f64) {
    let rho = densities(model).expect("densities");
    let setup = Setup::with_inertia(model, contact, options, true).expect("setup");
    let em = ElementMatrices::compute(&setup.bulk(0.0), &mass_kernel(model, &rho));
    let n_total = setup.dofs.n_total();
    let state = setup.initial_state();
    let layout = setup.build_layout(None, &state);
    let mut solver = setup.analyse(&layout, 0).expect("analysis");
    let mut prescribed = vec![0.0; n_total];
    let mut mult = vec![0.0; setup.mult_rows.len()];
    setup.prescribe(dt, &mut prescribed, &mut mult).expect("prescribe");
    let u_tilde: Vec<f64> = (0..n_total).map(|i| 1e-3 * (i as f64 * 0.37).sin()).collect();
    let zeros = vec![0.0; n_total];
    let effective = EffectiveKernel {
        matrices: &em,
        loads: Box::new(setup.bulk(dt)),
        c_k: 1.0,
        c_m: 4.0 / (dt * dt),
        c_p: 0.0,
        predictor: &u_tilde,
        previous: &zeros,
        element_products: true,
    };
    let fixed = setup.dynamic_kernels(effective, dt, dt, &mult);
    let ck = setup.contact_kernel(&state, &zeros, None);
    let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
    if let Some(ck) = &ck {
        kernels.push(ck);
    }
    let mut values = vec![0.0; layout.pattern.nnz()];
    let mut rhs = vec![0.0; layout.n_eq];
    layout.assemble(&kernels, &prescribed, Some(&mut values), Some(&mut rhs));
    solver.factorize(&values).expect("factorisation");
    let (mut best_a, mut best_s) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..5 {
        let t = Instant::now();
        layout.assemble(&kernels, &prescribed, None, Some(&mut rhs));
        best_a = best_a.min(t.elapsed().as_secs_f64());
        let mut x = rhs.clone();
        let t = Instant::now();
        solver.solve_in_place(&mut x).expect("solve");
        best_s = best_s.min(t.elapsed().as_secs_f64());
    }
    (best_s, best_a)
}

fn main() {
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let filter: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    println!(
        "{:>5} {:>8} {:>8} {:>6} {:>6} {:>7} {:>11} {:>11} {:>11} {:>6} {:>9} {:>8}",
        "row",
        "contact",
        "dofs",
        "steps",
        "factor",
        "solves",
        "step (ms)",
        "solve (ms)",
        "asm (ms)",
        "ratio",
        "run (s)",
        "rss (MB)"
    );
    let mut rows = ROWS.to_vec();
    if filter.first().map(String::as_str) == Some("custom") {
        let n = |k: usize| filter[k].parse::<usize>().expect("custom nx ny steps");
        rows = vec![("custom", n(1), n(2), n(3), n(3))];
    }
    for (label, nx, ny, steps, steps_contact) in rows {
        if label != "custom" && !filter.is_empty() && !filter.iter().any(|f| f == label) {
            continue;
        }
        for contact in [false, true] {
            let r = run(nx, ny, if contact { steps_contact } else { steps }, contact);
            println!(
                "{:>5} {:>8} {:>8} {:>6} {:>6} {:>7} {:>11.3} {:>11.3} {:>11.3} {:>6.2} {:>9.2} {:>8.0}",
                label,
                if contact { "yes" } else { "no" },
                r.dofs,
                r.steps,
                r.factorizations,
                r.linear_solves,
                1e3 * r.step_median,
                1e3 * r.solve_pair,
                1e3 * r.assembly,
                r.step_median / (r.solve_pair + r.assembly),
                r.run,
                peak_rss_mb()
            );
            if std::env::var("FISSURE_BENCH_TIMINGS").is_ok() {
                print_phases(&r);
            }
        }
    }
}

/// The mean time per step of each phase (ms; `FISSURE_BENCH_TIMINGS`): the driver's
/// phases, and the linear system's assembly, numeric and solve over the run (set-up
/// included) divided by the steps.
fn print_phases(r: &Row) {
    let t = &r.timings;
    let p = &t.step_phases;
    let per = |x: f64| 1e3 * x / r.steps as f64;
    let rows = [
        ("predict", p.predict),
        ("products", p.products),
        ("system", p.system),
        ("  assembly (run)", t.assembly),
        ("  numeric (run)", t.numeric),
        ("  solve (run)", t.solve),
        ("  columns", p.columns),
        ("  checksum", p.checksum),
        ("  set_bulk", p.bulk),
        ("  confirm", p.confirm),
        ("  deferred", p.deferred),
        ("update", p.update),
        ("reactions", p.reactions),
        ("external", p.external),
        ("contact work", p.contact_work),
        ("position corr.", p.position_correction),
        ("energies", p.energies),
        ("output", p.output),
    ];
    let sum: f64 = [
        p.predict,
        p.products,
        p.system,
        p.update,
        p.reactions,
        p.external,
        p.contact_work,
        p.position_correction,
        p.energies,
        p.output,
    ]
    .iter()
    .sum();
    for (name, x) in rows {
        println!("    {name:<18} {:>9.3} ms/step", per(x));
    }
    println!("    {:<18} {:>9.3} ms/step (mean; the median step above)", "sum of phases", per(sum));
}
