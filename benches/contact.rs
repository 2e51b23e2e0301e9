//! Contact benchmark: the closed inclined crack with Coulomb friction (μ = 0.3) of
//! tests/contact_friction_cracks.rs at ~5e4, ~2e5 and ~1e6 dofs, solved with contact and,
//! on the same cracked mesh, without contact (plain linear elastic X-FEM solve).
//!
//! Run: `cargo bench --bench contact` (all rows) or `cargo bench --bench contact -- 2e5`.
//! Each row runs in a child process (peak memory VmHWM is its own). Columns: dofs, the
//! plain solve (pattern + assembly + factorisation + solve), the contact solve, their ratio
//! (floor: ≤ 3), and the numeric factorisations and Newton iterations of the contact loops.
//!
//! A second table runs the ~2e5 and ~1e6 rows once per contact law (`method` =
//! `augmented_lagrangian`, `stabilised`, `penalty`, default parameters; issue 13), each in
//! its own child process, side by side: contact time, its ratio to the augmented
//! Lagrangian's, factorisations, Newton iterations, peak memory.
//! `cargo bench --bench contact -- methods` runs that table only (`methods 2e5` one row).

use fissure::case::{resolve, Case};
use fissure::run::solve_model_with;
use fissure::solve::statics::SolveOptions;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;
use common::peak_rss_mb;

const ROWS: [(&str, usize); 3] = [("5e4", 161), ("2e5", 321), ("1e6", 707)];

/// The contact laws of the second table.
const METHODS: [&str; 3] = ["augmented_lagrangian", "stabilised", "penalty"];

fn case_text(n: usize, contact: Option<&str>) -> String {
    let b = 45f64.to_radians();
    let (c, s, a) = (b.cos(), b.sin(), 0.2);
    let ctr = [0.0123, 0.0071];
    let contact = match contact {
        Some(method) => format!("[cracks.contact]\nfriction = 0.3\nmethod = \"{method}\"\n"),
        None => String::new(),
    };
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [-2.0, -2.0]\nupper = [2.0, 2.0]\ndivisions = [{n}, {n}]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[sets]]\nname = \"pin\"\non = \"abs(x+2) + abs(y+2)\"\n[[sets]]\nname = \"roller\"\non = \"abs(x-2) + abs(y+2)\"\n[[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, -1.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, 1.0]\n[[cracks]]\nname = \"c\"\nshape = \"segment\"\na = [{}, {}]\nb = [{}, {}]\ntip_radius = 0.05\nsif_radius = 0.06\n{contact}",
        ctr[0] - a * c,
        ctr[1] - a * s,
        ctr[0] + a * c,
        ctr[1] + a * s
    )
}

fn run(n: usize, contact: Option<&str>) -> (usize, f64, usize, usize, Vec<f64>) {
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
            "n = {n}, contact = {contact:?}: mesh {t_mesh:.3} model {:.3} contact set-up {:.3} solve+SIF {:.3}; {:?}",
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
    // The calling thread in rayon's pool (`fissure::threads`), as the `fissure` command.
    fissure::threads::init();
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if let (Some(name), true) = (args.first(), std::env::var("FISSURE_BENCH_CHILD").is_ok()) {
        if let (Some(&(label, n)), Some(method)) = (ROWS.iter().find(|r| r.0 == name), args.get(1)) {
            let (cdofs, with, fact, newton, _) = run(n, Some(method));
            println!("{label} {method} {cdofs} {with} {fact} {newton} {}", peak_rss_mb());
        } else if let Some(&(label, n)) = ROWS.iter().find(|r| r.0 == name) {
            let (dofs, plain, ..) = run(n, None);
            let (cdofs, with, fact, newton, _) = run(n, Some("augmented_lagrangian"));
            println!(
                "| {label:5} | {dofs:>9} | {cdofs:>9} | {plain:>8.2} | {with:>8.2} | {:>5.2} | {fact:>4} | {newton:>6} | {:>7.0} |",
                with / plain,
                peak_rss_mb()
            );
        }
        return;
    }
    println!("fissure contact benchmark: closed inclined crack, μ = 0.3 ({} threads)", rayon::current_num_threads());
    let exe = std::env::current_exe().expect("bench executable");
    if args.first().is_some_and(|a| a == "methods") {
        methods_table(&exe, &args[1..]);
        return;
    }
    println!("| model | dofs      | + contact | plain s  | contact s| ratio | fact | newton | peak MB |");
    println!("|-------|-----------|-----------|----------|----------|-------|------|--------|---------|");
    for &(label, _) in ROWS.iter().filter(|r| args.is_empty() || args.iter().any(|a| a == r.0)) {
        match std::process::Command::new(&exe).arg(label).env("FISSURE_BENCH_CHILD", "1").output() {
            Ok(o) if o.status.success() => print!("{}", String::from_utf8_lossy(&o.stdout)),
            Ok(o) => {
                println!("| {label:5} | failed: {}", String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or(""))
            }
            Err(e) => println!("| {label:5} | could not start: {e}"),
        }
    }
    if args.is_empty() {
        methods_table(&exe, &[]);
    }
}

/// The ~2e5 and ~1e6 rows once per contact law, side by side (one child process each).
fn methods_table(exe: &Path, rows: &[String]) {
    println!();
    println!("contact laws, side by side (issue 13)");
    println!("| model | method               | dofs      | contact s | / AL  | fact | newton | peak MB |");
    println!("|-------|----------------------|-----------|-----------|-------|------|--------|---------|");
    for &(label, _) in ROWS[1..].iter().filter(|r| rows.is_empty() || rows.iter().any(|a| a == r.0)) {
        let mut al_time = f64::NAN;
        for method in METHODS {
            let out = std::process::Command::new(exe).args([label, method]).env("FISSURE_BENCH_CHILD", "1").output();
            match out {
                Ok(o) if o.status.success() => {
                    let text = String::from_utf8_lossy(&o.stdout);
                    let f: Vec<&str> = text.split_whitespace().collect();
                    if f.len() < 7 {
                        println!("| {label:5} | {method:20} | no result |");
                        continue;
                    }
                    let secs: f64 = f[3].parse().unwrap_or(f64::NAN);
                    if method == "augmented_lagrangian" {
                        al_time = secs;
                    }
                    println!(
                        "| {label:5} | {method:20} | {:>9} | {secs:>9.2} | {:>5.2} | {:>4} | {:>6} | {:>7} |",
                        f[2],
                        secs / al_time,
                        f[4],
                        f[5],
                        f[6].split('.').next().unwrap_or(f[6])
                    );
                }
                Ok(o) => println!(
                    "| {label:5} | {method:20} | failed: {}",
                    String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
                ),
                Err(e) => println!("| {label:5} | {method:20} | could not start: {e}"),
            }
        }
    }
}
