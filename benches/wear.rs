//! Wear benchmark (issue 14): the fretting case of `examples/fretting_wear_2d.toml` (a
//! platen pressing a layer onto a flat interface and rubbing it back and forth, μ = 0.5,
//! k/H = 1) solved without wear, with the staggered and with the implicit coupling, on the
//! same mesh and steps.
//!
//! Run: `cargo bench --bench wear` (both tables) or `cargo bench --bench wear -- 1e5` /
//! `-- 1000` (one). Table 1: time per load step at ~1e5 dofs (quad4 440 × 110, the platen
//! pressing at step 1, then sliding one way by 0.005 per step for 9 steps, ν = 0: at this size the back-and-forth rubbing
//! already fails without wear, the contact Newton loop at the first reversal), runs interleaved (none, staggered, implicit, twice; the faster of the
//! two kept), with each coupling's ratio to the run without wear (floors: ≤ 1.3 staggered,
//! ≤ 2 implicit) and the Newton iterations and factorisations of the run (and of the
//! condensed factor's dense crack block, `-` when not condensed; `sparse n`: the numeric
//! factorisations of a kept whole-system factor, `solve/faer/kept.rs`). Table 2: a
//! 1 000-step fretting run (50 cycles) on the example's mesh (quad4 40 × 10), total time
//! and time per step, with implicit wear. The load average is printed with each table
//! (the machine may be shared: compare ratios, not seconds). `FISSURE_BENCH_TIMINGS=1`
//! prints under table 1 each run's friction passes, linear solves and seconds per phase
//! (assembly, numeric factorisation, solves, the rest) over the run.

use fissure::case::{resolve, Case};
use fissure::solve::statics::{solve_load_steps, SolveOptions};
use std::path::Path;
use std::time::Instant;

/// The fretting case: [0, 4] × [−0.5, 0.5] in `nx` × `ny` quad4, the interface y = 0.27 (h
/// = 0.1 grid: inside a cell row), `steps` load steps, the platen rubbing with 20 steps per
/// cycle (`fretting`, ν = 0.3) or pressing at step 1 and sliding one way by 0.005 per step
/// after it (ν = 0), wear table lines `wear` (None: no wear).
fn case_text(nx: usize, ny: usize, steps: usize, fretting: bool, wear: Option<&str>) -> String {
    let drive = if fretting {
        format!("0.02 * sin(2 * PI * {} * t)", steps as f64 / 20.0)
    } else {
        format!("0.005 * ({steps} * t - 1)")
    };
    let nu = if fretting { 0.3 } else { 0.0 };
    let wear = wear.map_or(String::new(), |w| format!("[cracks.contact.wear]\ncoefficient = 1.0\n{w}\n"));
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, -0.5]\nupper = [4.0, 0.5]\ndivisions = [{nx}, {ny}]\n\
         [[materials]]\nE = 1.0\nnu = {nu}\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n\
         [[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [\"{drive}\", \"-0.002 + 0 * t\"]\n\
         [steps]\ncount = {steps}\n[[cracks]]\nname = \"interface\"\nshape = \"line\"\npoint = [0.0, 0.27]\nnormal = [0.0, 1.0]\n\
         [cracks.contact]\nfriction = 0.5\n{wear}"
    )
}

/// What a run measured.
#[derive(Clone, Copy)]
struct Run {
    dofs: usize,
    secs: f64,
    friction: usize,
    newton: usize,
    fact: usize,
    /// Factorisations of the condensed factor's dense crack block (None: not condensed).
    dense: Option<usize>,
    /// Numeric factorisations of a kept whole-system factor (`solve/faer/kept.rs`; None:
    /// not one).
    sparse: Option<usize>,
    solves: usize,
    /// Seconds in assembly, numeric factorisation and solves over the run.
    assembly: f64,
    numeric: f64,
    solve: f64,
}

/// Solves the case and measures it.
fn run(text: &str) -> Run {
    let case = Case::parse(text, Path::new("bench.toml")).expect("case");
    let mesh = resolve::build_mesh(&case).expect("mesh");
    let model = resolve::build_model(&case, &mesh).expect("model");
    let setup = resolve::build_contact(&case, &model).expect("contact");
    let t = Instant::now();
    let mut done = 0usize;
    let result = solve_load_steps(&model, setup.as_ref(), &SolveOptions::default(), &mut |_| {
        done += 1;
        Ok(())
    });
    let report = match result {
        Ok(r) => r,
        Err(e) => {
            println!("failed after {done} steps, {:.1} s: {e}", t.elapsed().as_secs_f64());
            std::process::exit(1);
        }
    };
    let secs = t.elapsed().as_secs_f64();
    let contact = || report.steps.iter().filter_map(|s| s.contact.as_ref());
    let t = &report.timings;
    Run {
        dofs: report.dofs.n_total(),
        secs,
        friction: contact().map(|c| c.friction).sum(),
        newton: contact().map(|c| c.newton).sum(),
        fact: contact().map(|c| c.factorizations).sum(),
        dense: report.condensed_counts.map(|c| c.factorizations),
        sparse: report.kept_counts.map(|c| c.factorizations),
        solves: contact().map(|c| c.linear_solves).sum(),
        assembly: t.assembly,
        numeric: t.numeric,
        solve: t.solve,
    }
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map_or("?".into(), |s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

fn main() {
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let want = |name: &str| args.is_empty() || args.iter().any(|a| a == name);
    println!("fissure wear benchmark: fretting, μ = 0.5, k/H = 1 ({} threads)", rayon::current_num_threads());
    if want("1e5") {
        let steps = 10;
        let variants: [(&str, Option<&str>); 3] = [
            ("none", None),
            ("staggered", Some("coupling = \"staggered\"")),
            ("implicit", Some("coupling = \"implicit\"")),
        ];
        let mut best: [Option<Run>; 3] = [None; 3];
        let load_before = load_average();
        for _ in 0..2 {
            for (k, (_, wear)) in variants.iter().enumerate() {
                let r = run(&case_text(440, 110, steps, false, *wear));
                if best[k].is_none_or(|b| r.secs < b.secs) {
                    best[k] = Some(r);
                }
            }
        }
        println!(
            "\n~1e5 dofs, {steps} steps sliding one way; load average {load_before} before, {} after",
            load_average()
        );
        println!("| wear      | dofs    | s/step | ratio | newton | fact | dense fact |");
        println!("|-----------|---------|--------|-------|--------|------|------------|");
        let best = best.map(|b| b.expect("two runs of each"));
        for ((name, _), r) in variants.iter().zip(&best) {
            let per_step = r.secs / steps as f64;
            println!(
                "| {name:9} | {:>7} | {per_step:>6.3} | {:>5.2} | {:>6} | {:>4} | {:>10} |",
                r.dofs,
                r.secs / best[0].secs,
                r.newton,
                r.fact,
                r.dense.map_or_else(|| r.sparse.map_or("-".into(), |s| format!("sparse {s}")), |d| d.to_string())
            );
        }
        if std::env::var("FISSURE_BENCH_TIMINGS").is_ok() {
            println!("\nper run (the faster of two): friction passes, linear solves, seconds by phase");
            println!("| wear      | friction | solves | assembly | numeric | solve | other |");
            println!("|-----------|----------|--------|----------|---------|-------|-------|");
            for ((name, _), r) in variants.iter().zip(&best) {
                let other = r.secs - r.assembly - r.numeric - r.solve;
                println!(
                    "| {name:9} | {:>8} | {:>6} | {:>8.2} | {:>7.2} | {:>5.2} | {other:>5.2} |",
                    r.friction, r.solves, r.assembly, r.numeric, r.solve
                );
            }
        }
    }
    if want("1000") {
        let steps = 1000;
        let load_before = load_average();
        let r = run(&case_text(40, 10, steps, true, Some("coupling = \"implicit\"")));
        println!(
            "\n1 000-step fretting run (50 cycles), implicit wear; load average {load_before} before, {} after",
            load_average()
        );
        println!("| dofs  | total s | s/step | newton | fact |");
        println!("|-------|---------|--------|--------|------|");
        println!(
            "| {:>5} | {:>7.1} | {:>6.4} | {:>6} | {:>4} |",
            r.dofs,
            r.secs,
            r.secs / steps as f64,
            r.newton,
            r.fact
        );
    }
}
