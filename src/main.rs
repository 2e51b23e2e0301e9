//! The `fissure` command line: `fissure run CASE.toml [--out DIR] [--quiet | --verbose]
//! [--set KEY=VALUE]...`, `fissure check CASE.toml [--set KEY=VALUE]...`, and
//! `fissure sweep CASE.toml --set 'KEY=[v1, v2, ...]' [--out DIR]`.
//!
//! With the cargo feature `petsc`, a case with `[solver] backend = "petsc"` runs under
//! `mpirun -np N fissure run CASE.toml [-- PETSC_OPTIONS...]`: every rank solves the same
//! replicated model with the distributed PETSc solver; rank 0 alone prints and writes the
//! output, except the body grid, which every rank writes as its piece of a `.pvtu`
//! (`fissure::run::Pieces`; the other files of the other ranks go to a scratch directory
//! they delete).
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
        /// PETSc options after `--` (`-- -ksp_type gmres -pc_type hypre -ksp_monitor`), for
        /// `[solver] backend = "petsc"`; they override the case file and `PETSC_OPTIONS`.
        #[arg(last = true, value_name = "PETSC_OPTIONS")]
        petsc_options: Vec<String>,
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
    // This thread one of rayon's workers: the solver's many short parallel calls are joins,
    // not hand-overs to the pool (`fissure::threads`).
    fissure::threads::init();
    let cli = Cli::parse();
    match cli.command {
        Command::Run { case, out, quiet, verbose, set, petsc_options } => {
            let mut overrides = match overrides(&set) {
                Ok(o) => o,
                Err(code) => return code,
            };
            let out = out.unwrap_or_else(|| run::default_out_dir(&case));
            // Under MPI with the PETSc backend, only rank 0 prints and writes.
            let session = match cluster::start(&case, &overrides, &petsc_options) {
                Ok(s) => s,
                Err(code) => return code,
            };
            let pieces = session.pieces(&out);
            let (out, quiet) = match session.scratch(&mut overrides) {
                Some(scratch) => (scratch, true),
                None => (out, quiet),
            };
            if !quiet {
                eprintln!("fissure {}: running {} into {}", fissure::VERSION, case.display(), out.display());
            }
            let opts = RunOptions { verbose: !quiet, newton_iterations: verbose, overrides, pieces };
            let result = run::run_case(&case, &out, &opts);
            // The error is printed before MPI is finalised: a rank that leaves with a
            // non-zero status makes mpirun abort the others, rank 0 included.
            if let (Err(e), true) = (&result, session.prints()) {
                eprintln!("error: {e}");
            }
            session.finish();
            match result {
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
                Err(e) => ExitCode::from(e.exit_code() as u8),
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
                for (g, n) in &r.held_enriched {
                    println!("note: Dirichlet group '{g}' also holds {n} enriched unknowns at 0 on the faces a crack cuts (docs/case-format.md, [[dirichlet]])");
                }
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
        Command::Sweep { case, out, quiet, set } => {
            let code = sweep(&case, out, quiet, &set);
            // A swept case with backend = "petsc" starts PETSc in its first solve (one
            // process: sweeps are not run under mpirun).
            #[cfg(feature = "petsc")]
            fissure::solve::petsc::finalize();
            code
        }
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

// ---- the MPI session of the PETSc backend -------------------------------------------------

/// The process's part in an MPI run: started for a case whose backend is PETSc, a no-op
/// otherwise (and always without the `petsc` feature).
mod cluster {
    use fissure::case::overrides::Override;
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;

    pub struct Session {
        /// This rank and the number of ranks (0 and 1 without MPI).
        rank: usize,
        size: usize,
        /// MPI and PETSc were started (finalised by `finish`).
        started: bool,
        /// The case asks for VTU files (`[output] vtu`).
        vtu: bool,
    }

    /// Starts MPI and PETSc when the case (with its overrides) asks for the PETSc backend.
    /// PETSc options after `--` need that backend.
    pub fn start(case: &Path, overrides: &[Override], petsc_options: &[String]) -> Result<Session, ExitCode> {
        let parsed = fissure::case::Case::from_file_with(case, overrides).ok();
        let vtu = parsed.as_ref().is_some_and(|c| c.output.vtu);
        let none = Session { rank: 0, size: 1, started: false, vtu };
        let uses_petsc = parsed.is_some_and(|c| matches!(c.solver.backend, fissure::solve::linear::Backend::Petsc(_)));
        if !uses_petsc {
            if let Some(first) = petsc_options.first() {
                eprintln!(
                    "error: the arguments after -- ({first} ...) are PETSc options, read only with \
                     [solver] backend = \"petsc\" (and a fissure built with --features petsc)"
                );
                return Err(ExitCode::from(2));
            }
            return Ok(none);
        }
        start_petsc(petsc_options, vtu)
    }

    #[cfg(feature = "petsc")]
    fn start_petsc(petsc_options: &[String], vtu: bool) -> Result<Session, ExitCode> {
        use fissure::solve::petsc;
        petsc::set_command_line_options(petsc_options);
        match petsc::initialize() {
            Ok((rank, size)) => Ok(Session { rank, size, started: true, vtu }),
            Err(e) => {
                eprintln!("error: cannot start MPI and PETSc: {e}");
                Err(ExitCode::from(1))
            }
        }
    }

    #[cfg(not(feature = "petsc"))]
    fn start_petsc(_: &[String], vtu: bool) -> Result<Session, ExitCode> {
        // The case reader refuses backend = "petsc" without the feature: run_case reports it.
        Ok(Session { rank: 0, size: 1, started: false, vtu })
    }

    impl Session {
        /// Ranks other than 0: a private scratch output directory, with the VTU files and
        /// the plots turned off (rank 0 writes them).
        pub fn scratch(&self, overrides: &mut Vec<Override>) -> Option<PathBuf> {
            if self.rank == 0 {
                return None;
            }
            for o in ["output.vtu=false", "output.plots=false"] {
                if let Ok(o) = Override::parse(o) {
                    overrides.push(o);
                }
            }
            self.scratch_dir()
        }

        /// Several ranks and VTU files asked for: every rank writes its piece of the body
        /// into the run's output directory `out` (rank 0 the `.pvtu` index).
        pub fn pieces(&self, out: &Path) -> Option<fissure::run::Pieces> {
            (self.size > 1 && self.vtu).then(|| fissure::run::Pieces {
                rank: self.rank,
                size: self.size,
                dir: out.to_path_buf(),
            })
        }

        /// Whether this process prints (rank 0).
        pub fn prints(&self) -> bool {
            self.rank == 0
        }

        /// Finalises PETSc and MPI (every rank) and removes the scratch directory.
        pub fn finish(&self) {
            if let Some(dir) = self.scratch_dir() {
                let _ = std::fs::remove_dir_all(dir);
            }
            #[cfg(feature = "petsc")]
            if self.started {
                fissure::solve::petsc::finalize();
            }
            let _ = self.started;
        }

        fn scratch_dir(&self) -> Option<PathBuf> {
            (self.rank != 0).then(|| {
                std::env::temp_dir().join(format!("fissure-rank{}-of-{}-{}", self.rank, self.size, std::process::id()))
            })
        }
    }
}
