//! Contact benchmark: the closed inclined crack with Coulomb friction (μ = 0.3) of
//! tests/contact_friction_cracks.rs at ~5e4, ~2e5 and ~1e6 dofs, solved with contact and,
//! on the same cracked mesh, without contact (plain linear elastic X-FEM solve).
//!
//! Run: `cargo bench --bench contact` (all rows) or `cargo bench --bench contact -- 2e5`.
//! Each row runs in a child process (peak memory VmHWM is its own). Columns: dofs, the
//! plain solve (pattern + assembly + factorisation + solve), the contact solve, their ratio
//! (floor: ≤ 3), and the numeric factorisations and Newton iterations of the contact loops.

use fissure::case::{resolve, Case};
use fissure::run::solve_model_with;
use fissure::solve::statics::SolveOptions;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::peak_rss_mb;

const ROWS: [(&str, usize); 3] = [("5e4", 161), ("2e5", 321), ("1e6", 707)];

fn case_text(n: usize, contact: bool) -> String {
    let b = 45f64.to_radians();
    let (c, s, a) = (b.cos(), b.sin(), 0.2);
    let ctr = [0.0123, 0.0071];
    let contact = if contact { "[cracks.contact]\nfriction = 0.3\n" } else { "" };
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [-2.0, -2.0]\nupper = [2.0, 2.0]\ndivisions = [{n}, {n}]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[sets]]\nname = \"pin\"\non = \"abs(x+2) + abs(y+2)\"\n[[sets]]\nname = \"roller\"\non = \"abs(x-2) + abs(y+2)\"\n[[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, -1.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, 1.0]\n[[cracks]]\nname = \"c\"\nshape = \"segment\"\na = [{}, {}]\nb = [{}, {}]\ntip_radius = 0.05\nsif_radius = 0.06\n{contact}",
        ctr[0] - a * c,
        ctr[1] - a * s,
        ctr[0] + a * c,
        ctr[1] + a * s
    )
}

fn run(n: usize, contact: bool) -> (usize, f64, usize, usize, Vec<f64>) {
    let text = case_text(n, contact);
    let t = Instant::now();
    let case = Case::parse(&text, Path::new("bench.toml")).expect("case");
    let mesh = resolve::build_mesh(&case).expect("mesh");
    let t_mesh = t.elapsed().as_secs_f64();
    let model = resolve::build_model(&case, &mesh).expect("model");
    let t_model = t.elapsed().as_secs_f64();
    let setup = resolve::build_contact(&case, &model).expect("contact");
    let t_setup = t.elapsed().as_secs_f64();
    let (report, sols, _) = solve_model_with(&model, setup.as_ref(), &SolveOptions::default()).expect("solve");
    let secs = t.elapsed().as_secs_f64();
    if std::env::var("FISSURE_BENCH_TIMINGS").is_ok() {
        eprintln!(
            "n = {n}, contact = {contact}: mesh {t_mesh:.3} model {:.3} contact set-up {:.3} solve+SIF {:.3}; {:?}",
            t_model - t_mesh,
            t_setup - t_model,
            secs - t_setup,
            report.timings
        );
    }
    let c = report.steps[0].contact.clone().unwrap_or_default();
    drop(sols);
    (report.dofs.n_total(), secs, c.factorizations, c.newton, vec![])
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if let (Some(name), true) = (args.first(), std::env::var("FISSURE_BENCH_CHILD").is_ok()) {
        if let Some(&(label, n)) = ROWS.iter().find(|r| r.0 == name) {
            let (dofs, plain, ..) = run(n, false);
            let (cdofs, with, fact, newton, _) = run(n, true);
            println!(
                "| {label:5} | {dofs:>9} | {cdofs:>9} | {plain:>8.2} | {with:>8.2} | {:>5.2} | {fact:>4} | {newton:>6} | {:>7.0} |",
                with / plain,
                peak_rss_mb()
            );
        }
        return;
    }
    println!("fissure contact benchmark: closed inclined crack, μ = 0.3 ({} threads)", rayon::current_num_threads());
    println!("| model | dofs      | + contact | plain s  | contact s| ratio | fact | newton | peak MB |");
    println!("|-------|-----------|-----------|----------|----------|-------|------|--------|---------|");
    let exe = std::env::current_exe().expect("bench executable");
    for &(label, _) in ROWS.iter().filter(|r| args.is_empty() || args.iter().any(|a| a == r.0)) {
        match std::process::Command::new(&exe).arg(label).env("FISSURE_BENCH_CHILD", "1").output() {
            Ok(o) if o.status.success() => print!("{}", String::from_utf8_lossy(&o.stdout)),
            Ok(o) => {
                println!("| {label:5} | failed: {}", String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or(""))
            }
            Err(e) => println!("| {label:5} | could not start: {e}"),
        }
    }
}
