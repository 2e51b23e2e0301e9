//! The `fissure` command line: `fissure run CASE.toml [--out DIR] [--quiet | --verbose]
//! [--set KEY=VALUE]...`, `fissure check CASE.toml [--set KEY=VALUE]...`, and
//! `fissure sweep CASE.toml --set 'KEY=[v1, v2, ...]' [--out DIR]`.
//!
//! Exit status: 0 on success; 2 when the case file or its mesh is wrong; 1 when the
//! solve or the output fails (the last converged step is kept on disk and
//! `summary.json` says `"status": "failed"`).

use clap::{Parser, Subcommand};
use fissure::run::{self, RunOptions};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fissure",
    version,
    about = "X-FEM crack contact toolkit: solve a case file, write VTK and summary.json"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a case and write its results (VTU/PVD for ParaView, summary.json).
    Run {
        /// The case file (TOML).
        case: PathBuf,
        /// Output directory (default: out/<case stem>/).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Also print every Newton iteration of the contact loops.
        #[arg(long, short, conflicts_with = "quiet")]
        verbose: bool,
        /// Override a case key, validated like the file: `--set cracks.0.contact.friction=0.3`.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Validate a case file, its mesh and its boundary conditions without solving.
    Check {
        /// The case file (TOML).
        case: PathBuf,
        /// Override a case key, validated like the file: `--set parameters.p=2`.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Run a case once per value of one numeric key; one folder per value and sweep.csv.
    Sweep {
        /// The case file (TOML).
        case: PathBuf,
        /// Output directory holding one folder per value and sweep.csv (default: out/<case stem>/).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// The swept key with its list of values, `--set 'cracks.0.contact.friction=[0, 0.3, 0.6]'`,
        /// and any fixed overrides.
        #[arg(long = "set", value_name = "KEY=VALUE", required = true)]
        set: Vec<String>,
    },
}

/// The `--set` arguments, or the exit status of the first malformed one.
fn overrides(set: &[String]) -> Result<Vec<fissure::case::overrides::Override>, ExitCode> {
    set.iter().map(|s| fissure::case::overrides::Override::parse(s)).collect::<Result<_, _>>().map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run { case, out, quiet, verbose, set } => {
            let overrides = match overrides(&set) {
                Ok(o) => o,
                Err(code) => return code,
            };
            let out = out.unwrap_or_else(|| run::default_out_dir(&case));
            if !quiet {
                eprintln!("fissure {}: running {} into {}", fissure::VERSION, case.display(), out.display());
            }
            match run::run_case(&case, &out, &RunOptions { verbose: !quiet, newton_iterations: verbose, overrides }) {
                Ok(s) => {
                    if !quiet {
                        eprintln!(
                            "done: {} steps, {} dofs, {:.2} s; results in {}",
                            s.steps.len(),
                            s.dofs.total,
                            s.timings_s.total,
                            out.display()
                        );
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(e.exit_code() as u8)
                }
            }
        }
        Command::Check { case, set } => match overrides(&set).map(|o| run::check_case_with(&case, &o)) {
            Err(code) => code,
            Ok(Ok(r)) => {
                println!(
                    "{}: ok ({}D, {} nodes, {} cells, {} load steps)",
                    case.display(),
                    r.dim,
                    r.nodes,
                    r.cells,
                    r.steps
                );
                for w in &r.warnings {
                    eprintln!("warning: {w}");
                }
                ExitCode::SUCCESS
            }
            Ok(Err(e)) => {
                eprintln!("error: {e}");
                ExitCode::from(e.exit_code() as u8)
            }
        },
        Command::Sweep { case, out, quiet, set } => sweep(&case, out, quiet, &set),
    }
}

// ---- fissure sweep ----------------------------------------------------------------------

fn sweep(case: &std::path::Path, out: Option<PathBuf>, quiet: bool, set: &[String]) -> ExitCode {
    let overrides = match overrides(set) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let out = out.unwrap_or_else(|| run::default_out_dir(case));
    match fissure::sweep::sweep_case(
        case,
        &out,
        overrides,
        &RunOptions { verbose: !quiet, overrides: vec![], ..Default::default() },
    ) {
        Ok(r) => {
            let failed = r.runs.iter().filter(|r| r.error.is_some()).count();
            if !quiet {
                eprintln!("sweep done: {} runs, {failed} failed; table in {}", r.runs.len(), r.csv.display());
            }
            for run in r.runs.iter().filter(|r| r.error.is_some()) {
                eprintln!("error: {}: {}", run.dir.display(), run.error.as_deref().unwrap_or(""));
            }
            if failed == 0 {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
