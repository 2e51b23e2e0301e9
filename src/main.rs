//! The `fissure` command line: `fissure run CASE.toml [--out DIR]`, `fissure check CASE.toml`.
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
    },
    /// Validate a case file, its mesh and its boundary conditions without solving.
    Check {
        /// The case file (TOML).
        case: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run { case, out, quiet } => {
            let out = out.unwrap_or_else(|| run::default_out_dir(&case));
            if !quiet {
                eprintln!("fissure {}: running {} into {}", fissure::VERSION, case.display(), out.display());
            }
            match run::run_case(&case, &out, &RunOptions { verbose: !quiet }) {
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
        Command::Check { case } => match run::check_case(&case) {
            Ok(r) => {
                println!(
                    "{}: ok ({}D, {} nodes, {} cells, {} load steps)",
                    case.display(),
                    r.dim,
                    r.nodes,
                    r.cells,
                    r.steps
                );
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(e.exit_code() as u8)
            }
        },
    }
}
