//! The PETSc backend of the [`LinearBackend`](super::backend::LinearBackend) seam (cargo
//! feature `petsc`): MPI through the `mpi` crate, PETSc through our own declarations
//! (`ffi.rs`), distributed `MPIAIJ` matrices and a `KSP` chosen by the case file and
//! PETSc's options database.
//!
//! Entry points: [`PetscSolver`] (analyse / factorise / solve, built by
//! [`super::linear::LinearSolver::analyse_on`]), and the process session: [`initialize`]
//! (MPI and PETSc, once per process), [`rank`] / [`size`], [`finalize`] (before exit),
//! [`set_command_line_options`] (the PETSc options after `--` on fissure's command line).
//!
//! Distribution. The model (mesh, level sets, crack fronts, enrichment) is replicated on
//! every rank. The assembly is distributed, with or without contact ([`partition`],
//! `Setup::build_layout_owned`): the cells are partitioned by METIS (identically on every
//! rank, weighted by element cost), each node (and its enriched dofs) is owned by the
//! lowest rank among its cells, the equations are numbered rank by rank so that each rank
//! owns the rows of its nodes, and each rank computes only its own elements and adds each
//! element matrix straight into the `MPIAIJ` matrix (`ADD_VALUES`, PETSc's stash moving
//! the few entries of rows owned by a neighbour), preallocated exactly from the layout's
//! counts of the owned rows (`assembly::layout::DistributedRows`): no rank holds a pattern
//! or a value array of the global matrix, nor the element lists of other ranks' elements
//! (its layout lists and colours its own elements only). The load vector is summed over
//! the ranks, the residual computed by PETSc (`MatMult`), the reactions (each rank's
//! elements' forces on the constrained dofs, `Setup::constrained_forces`) summed over the
//! ranks; the output's cracked body grid is built by each rank for its own cells (its
//! piece, `run`), the figures read from it reduced over the ranks. With contact (both
//! drivers) the
//! contact kernel is one more kernel of the distributed layout: each contact facet (its
//! points) is assembled by the rank of its cell, the multiplier-only packets by rank 0.
//! K is assembled once into the matrix, the contact entries as explicit zeros in its
//! structure; the backend keeps its own rows of K among the contact equations
//! (`PetscSolver::keep_bulk_rows`), puts them back and adds its contact elements at each
//! refactorisation (`refill_contact`), and gives the Newton loop its rows of K x
//! (`bulk_product`, `MatMult` with the kept rows for the contact equations). Each rank's
//! residual (its elements' load and contact vectors, its rows of K x) is summed over the
//! ranks before each solve. What the loops decide from (the dof vector, hence every
//! point's gap, jump, λ and status, the pairing of large sliding on the whole lips, the
//! correction norms) is computed on every rank from the solution gathered to every rank,
//! bit for bit the same: every rank takes the same decisions without further messages;
//! the figures that are sums over ranks (K x, the loads, the preconditioner's scalars) are
//! used only through the solve, whose gathered answer is again the same everywhere. The
//! dynamics driver assembles the same way, with and without contact: each rank computes
//! and keeps the stiffness and mass matrices of its own cells only
//! (`ElementMatrices::compute_held`), assembles the effective matrix and its share of each
//! step's load vector (predictor and HHT products per element) from them, and the
//! figures built from element matrices (strain and kinetic energies, reactions, the
//! external loads, K u₀ and the position correction's K Δu) are its share summed over the
//! ranks; the initial accelerations' mass matrix and the position correction's system are
//! distributed on the same partition. Either way PETSc's
//! preconditioner and Krylov solver (or MUMPS) run distributed, and the solution is
//! gathered back to every rank (`VecScatterCreateToAll`). Rank 0 writes the output
//! (`main.rs`), except the body grid, which every rank writes as its piece of a `.pvtu`
//! (`run::Pieces`, with the cells of [`partition::recorded_cells`]). Every decision that could differ between ranks (a failed PETSc call) is
//! agreed by an all-reduce before the next collective call, so all ranks leave together
//! on an error.
//!
//! Options, later ones win: the backend's defaults (CG + GAMG for positive definite
//! systems, with the rigid-body modes as near null space, or the nodes' coordinates from
//! which GAMG builds them when the matrix has node blocks; GMRES with a field split,
//! GAMG on the standard unknowns and LU by MUMPS on the enriched unknowns with the
//! multipliers, for 3D systems with multipliers and enriched unknowns; `preonly` + LU by
//! MUMPS for the other systems with multipliers or unsymmetric tangents), the case file's `[solver.petsc]`
//! `ksp`, `pc`, `rtol` and `options`, the environment variable `PETSC_OPTIONS`, and the
//! options after `--` on the command line.

mod ffi;
pub mod partition;
mod solver;

pub use solver::PetscSolver;

use mpi::traits::*;
use std::ffi::CString;
use std::sync::Mutex;

/// The process's MPI universe (finalised by [`finalize`]) and its rank and size.
struct Session {
    universe: Option<mpi::environment::Universe>,
    rank: usize,
    size: usize,
    finalized: bool,
}

static SESSION: Mutex<Option<Session>> = Mutex::new(None);
static COMMAND_LINE: Mutex<String> = Mutex::new(String::new());

/// The PETSc options given after `--` on fissure's command line (`-ksp_type cg …`),
/// applied after the case file's and `PETSC_OPTIONS` (they win).
pub fn set_command_line_options(args: &[String]) {
    if let Ok(mut c) = COMMAND_LINE.lock() {
        *c = args.join(" ");
    }
}

/// Starts MPI (through the `mpi` crate) and PETSc once per process; later calls return the
/// same `(rank, size)`. Under `mpirun` every rank must call it.
pub fn initialize() -> Result<(usize, usize), String> {
    let mut guard = SESSION.lock().map_err(|_| "the PETSc session lock is poisoned".to_string())?;
    if let Some(s) = guard.as_ref() {
        if s.finalized {
            return Err("PETSc was already finalised in this process".into());
        }
        return Ok((s.rank, s.size));
    }
    let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Serialized)
        .ok_or_else(|| "MPI was initialised outside fissure's PETSc session".to_string())?;
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    // SAFETY: PETSC_COMM_WORLD may be set before PetscInitialize; the communicator is
    // MPI_COMM_WORLD, valid until MPI_Finalize. PetscInitialize with null arguments reads
    // PETSC_OPTIONS and does not initialise MPI again.
    unsafe {
        ffi::PETSC_COMM_WORLD = world.as_raw();
        ffi::check(
            "PetscInitialize",
            ffi::PetscInitialize(std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null(), std::ptr::null()),
        )?;
        ffi::check("PetscPushErrorHandler", ffi::PetscPushErrorHandler(ffi::record_error, std::ptr::null_mut()))?;
    }
    *guard = Some(Session { universe: Some(universe), rank, size, finalized: false });
    Ok((rank, size))
}

/// This process's rank (0 before [`initialize`] or without MPI).
pub fn rank() -> usize {
    SESSION.lock().ok().and_then(|s| s.as_ref().map(|s| s.rank)).unwrap_or(0)
}

/// The number of ranks (1 before [`initialize`]).
pub fn size() -> usize {
    SESSION.lock().ok().and_then(|s| s.as_ref().map(|s| s.size)).unwrap_or(1)
}

/// Finalises PETSc and MPI if [`initialize`] started them (every PETSc object must be
/// destroyed before: call it after the run returned). A no-op otherwise.
pub fn finalize() {
    let Ok(mut guard) = SESSION.lock() else { return };
    if let Some(s) = guard.as_mut() {
        if !s.finalized {
            // SAFETY: PETSc was initialised by `initialize`; the solvers of the run are dropped.
            unsafe {
                ffi::PetscFinalize();
            }
            s.finalized = true;
            // MPI_Finalize.
            s.universe.take();
        }
    }
}

/// `Ok` on every rank when `local` is `Ok` on every rank; otherwise `Err` on every rank
/// (this rank's message, or a pointer to the rank that failed). An all-reduce: every rank
/// must call it at the same point.
pub(crate) fn agree<T>(local: Result<T, String>) -> Result<T, String> {
    let failed_here = i32::from(local.is_err());
    let mut failed_anywhere = 0i32;
    mpi::topology::SimpleCommunicator::world().all_reduce_into(
        &failed_here,
        &mut failed_anywhere,
        mpi::collective::SystemOperation::max(),
    );
    match local {
        Err(e) => Err(e),
        Ok(_) if failed_anywhere != 0 => {
            Err("a PETSc call failed on another rank (its message is on that rank's standard error)".into())
        }
        Ok(v) => Ok(v),
    }
}

/// Sums `v` over the ranks in place (an all-reduce: every rank calls it with the same
/// length).
pub fn sum_over_ranks(v: &mut [f64]) -> Result<(), String> {
    initialize()?;
    let local = v.to_vec();
    mpi::topology::SimpleCommunicator::world().all_reduce_into(&local[..], v, mpi::collective::SystemOperation::sum());
    Ok(())
}

/// Whether `local` holds on some rank (an all-reduce: every rank must call it at the same
/// point, and every rank gets the same answer).
pub(crate) fn on_any_rank(local: bool) -> bool {
    let here = i32::from(local);
    let mut any = 0i32;
    mpi::topology::SimpleCommunicator::world().all_reduce_into(
        &here,
        &mut any,
        mpi::collective::SystemOperation::max(),
    );
    any != 0
}

/// The largest of `local` over the ranks (an all-reduce, the same answer on every rank).
pub(crate) fn max_over_ranks(local: f64) -> f64 {
    let mut m = local;
    mpi::topology::SimpleCommunicator::world().all_reduce_into(&local, &mut m, mpi::collective::SystemOperation::max());
    m
}

/// Every rank's value of `local`, in rank order (an all-gather: every rank calls it).
pub(crate) fn gather_over_ranks(local: u64) -> Vec<u64> {
    let world = mpi::topology::SimpleCommunicator::world();
    let mut all = vec![0u64; world.size() as usize];
    world.all_gather_into(&local, &mut all[..]);
    all
}

/// This process's peak resident memory (`VmHWM` of `/proc/self/status`, KiB; 0 where it
/// cannot be read).
pub(crate) fn peak_rss_kib() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse().ok())
        })
        .unwrap_or(0)
}

/// Inserts `text` (PETSc options, `-key value …`) into PETSc's global options database.
fn insert_options(text: &str) -> Result<(), String> {
    if text.trim().is_empty() {
        return Ok(());
    }
    let c = CString::new(text).map_err(|_| format!("PETSc options contain a NUL character: {text:?}"))?;
    // SAFETY: a NUL-terminated string; PETSc copies what it keeps.
    ffi::check("PetscOptionsInsertString", unsafe { ffi::PetscOptionsInsertString(std::ptr::null_mut(), c.as_ptr()) })
        .map_err(|e| format!("PETSc rejected the options \"{text}\": {e}"))
}

/// The options of one analyse, in the order where later ones win: the case file's
/// `options`, then `PETSC_OPTIONS`, then the command line.
fn insert_option_layers(case_options: &str) -> Result<(), String> {
    insert_options(case_options)?;
    if let Ok(env) = std::env::var("PETSC_OPTIONS") {
        insert_options(&env)?;
    }
    let cmd = COMMAND_LINE.lock().map(|c| c.clone()).unwrap_or_default();
    insert_options(&cmd)
}
