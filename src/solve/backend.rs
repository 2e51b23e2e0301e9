//! The linear-backend seam: what the rest of fissure asks of a sparse linear solver, and
//! the vocabulary (methods, errors, figures) shared by every backend.
//!
//! Entry point: [`LinearBackend`]. A backend is built once per sparsity pattern
//! ([`LinearBackend::analyse`], the symbolic phase: ordering, symbolic factorisation,
//! preallocation), takes new values on that fixed pattern as often as needed
//! ([`LinearBackend::factorize`]: numeric factorisation, or a refill of the preconditioner
//! for an iterative backend) and solves with them ([`LinearBackend::solve_in_place`]),
//! reusing the symbolic work between Newton and active-set iterations. The contact loops
//! may also give the backend the bulk values once ([`LinearBackend::set_bulk`]) and ask for
//! corrections that defer the interior ([`LinearBackend::solve_in_place_deferred`],
//! [`LinearBackend::apply_deferred`]): a backend that condenses onto the crack unknowns
//! uses them, the others fall back to the full solve (the default methods).
//!
//! The one backend today is faer's direct solver ([`super::faer::FaerSolver`], re-exported
//! as [`super::linear::LinearSolver`]). The seam is shaped for a distributed one as well
//! (PETSc: a preallocated matrix on the fixed pattern whose values are set by
//! `MatSetValues`, a `KSP` set up once and reused): everything it receives is the
//! pattern in compressed columns, the value array in that pattern's order, the number of
//! primal unknowns (the rest are multipliers) and optionally the point of every unknown
//! ([`EquationPoints`], for orderings and partitioning).

use crate::assembly::CscPattern;
use std::fmt;

/// Which factorisation to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LinearMethod {
    /// `LLᵀ`: symmetric positive definite matrices only (stiffness matrices with the
    /// Dirichlet conditions eliminated).
    Cholesky,
    /// `LDLᵀ` without pivoting: symmetric quasi-definite or saddle-point matrices
    /// `[K Bᵀ; B −C]` with the multipliers as the last unknowns (`K` positive definite on
    /// the kernel of `B`, `C ≥ 0`, `B` of full row rank). About the cost of Cholesky.
    Ldlt,
    /// LU with partial pivoting: any nonsingular matrix; the slow, robust fallback.
    Lu,
}

impl LinearMethod {
    /// The lower-case name used in case files and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            LinearMethod::Cholesky => "cholesky",
            LinearMethod::Ldlt => "ldlt",
            LinearMethod::Lu => "lu",
        }
    }
}

impl fmt::Display for LinearMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The arithmetic of a direct factorisation (`[solver] precision`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// The factor in double precision.
    Double,
    /// A whole-system Cholesky or LDLᵀ factor in single precision (half the memory, about
    /// twice the speed of the dense kernels), with every solve brought back to
    /// double-precision accuracy by iterations in double precision preconditioned by that
    /// factor (conjugate gradients for Cholesky, iterative refinement for LDLᵀ); falls
    /// back to the double-precision factor (logged) when the single-precision one breaks
    /// down or the iterations do not reach the double-precision residual. LU, split and
    /// condensed factors stay in double precision.
    Mixed,
    /// Mixed for whole-system Cholesky factors large enough that it pays (see the faer
    /// backend's `MIXED_AUTO_MIN_NNZ`), double otherwise (LDLᵀ: always double).
    #[default]
    Auto,
}

impl Precision {
    /// The lower-case name used in case files.
    pub fn name(self) -> &'static str {
        match self {
            Precision::Double => "double",
            Precision::Mixed => "mixed",
            Precision::Auto => "auto",
        }
    }
}

/// Figures for `summary.json` and benchmarks.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LinearStats {
    /// Entries of the factor `L` (lower triangle with the diagonal) for Cholesky and
    /// LDLᵀ; `None` for LU (faer does not expose it).
    pub nnz_factor: Option<usize>,
    /// Floating-point operations of one numeric factorisation, counted from the
    /// supernodal structure (dense Cholesky, triangular solve and update of each
    /// supernode); `None` for simplicial, split, condensed and LU factors.
    pub flops_factor: Option<f64>,
    /// Bytes of scratch memory the numeric phase takes besides the factor (faer's
    /// `StackReq`); `None` where not known.
    pub factor_scratch_bytes: Option<usize>,
    /// Seconds of the symbolic phase ([`LinearBackend::analyse`]).
    pub symbolic_s: f64,
    /// Seconds of the last numeric phase ([`LinearBackend::factorize`]).
    pub numeric_s: f64,
    /// Seconds of the last [`LinearBackend::solve_in_place`] (refinement included).
    pub solve_s: f64,
    /// The factor in use is in single precision ([`Precision::Mixed`], and no fallback to
    /// double precision happened).
    pub mixed: bool,
    /// Mixed precision: why the factor fell back to double precision (`None`: it did not).
    pub fallback: Option<&'static str>,
    /// The condensed contact factor's dense crack block since the analysis (`None` for the
    /// other factors).
    pub condensed: Option<CondensedCounts>,
    /// The whole-system factor kept across contact iterations (`solve/faer/kept.rs`:
    /// contact systems too large to condense) since the analysis: its numeric
    /// factorisations, the new matrices that kept it, the solves by GMRES preconditioned by
    /// it and their iterations (`None`: not a kept factor).
    pub kept: Option<CondensedCounts>,
}

/// Counts of the condensed factor's dense crack block `F` since the analysis
/// (`solve/faer/dense_block.rs`): the factorisations of `F` done, the ones avoided (a new
/// `F` solved by GMRES preconditioned by the previous factor) and those Krylov solves and
/// their iterations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CondensedCounts {
    /// Dense factorisations of `F`.
    pub factorizations: usize,
    /// New values of `F` that kept the previous factor (refactorisations avoided).
    pub reused: usize,
    /// Solves with `F` by GMRES preconditioned by a stale factor.
    pub krylov_solves: usize,
    /// Their iterations (each one product with `F` and one solve with the stale factor).
    pub krylov_iterations: usize,
    /// The width of `F` (crack unknowns and the multipliers it keeps; 0 for a kept
    /// whole-system factor).
    pub width: usize,
    /// The multipliers condensed out of `F` (no displacement unknown in their rows:
    /// `solve/faer/free.rs`).
    pub free: usize,
}

impl CondensedCounts {
    /// The counts since `before` (the same factor's earlier counts).
    pub fn since(self, before: CondensedCounts) -> CondensedCounts {
        CondensedCounts {
            factorizations: self.factorizations.saturating_sub(before.factorizations),
            reused: self.reused.saturating_sub(before.reused),
            krylov_solves: self.krylov_solves.saturating_sub(before.krylov_solves),
            krylov_iterations: self.krylov_iterations.saturating_sub(before.krylov_iterations),
            width: self.width,
            free: self.free,
        }
    }

    /// Both counts together.
    pub fn plus(self, other: CondensedCounts) -> CondensedCounts {
        CondensedCounts {
            factorizations: self.factorizations + other.factorizations,
            reused: self.reused + other.reused,
            krylov_solves: self.krylov_solves + other.krylov_solves,
            krylov_iterations: self.krylov_iterations + other.krylov_iterations,
            width: self.width.max(other.width),
            free: self.free.max(other.free),
        }
    }
}

/// Why the linear solver failed. The messages are meant for users.
#[derive(Debug, Clone, PartialEq)]
pub enum LinearError {
    /// The sparsity pattern is malformed (a bug in the caller, not in the model).
    InvalidPattern(String),
    /// More primal unknowns than unknowns.
    InvalidPrimalCount { n_primal: usize, n: usize },
    /// Cholesky was asked to factorise a system with multipliers (always indefinite).
    CholeskyWithMultipliers { n_multipliers: usize },
    /// A value array or right-hand side has the wrong length.
    LengthMismatch { what: &'static str, expected: usize, got: usize },
    /// A matrix entry is NaN or infinite.
    NonFiniteMatrix { row: usize, col: usize, value: f64 },
    /// A right-hand side entry is NaN or infinite.
    NonFiniteRhs { index: usize, value: f64 },
    /// Every coefficient of this unknown's row and column is zero.
    EmptyRow { unknown: usize },
    /// Cholesky met a non-positive or tiny pivot: the matrix is not (numerically)
    /// positive definite. `pivot` is what remains of the diagonal entry `diagonal` of
    /// `unknown` once the unknowns ordered before it are eliminated.
    NotPositiveDefinite { unknown: usize, pivot: f64, diagonal: f64 },
    /// LDLᵀ or LU broke down on a zero or non-finite pivot.
    ZeroPivot { unknown: usize },
    /// The solution does not satisfy the system: the matrix is singular or nearly so.
    Singular { relative_residual: f64, regularised_pivots: usize },
    /// `solve_in_place` was called without a successful `factorize`.
    NotFactorized,
    /// Not enough memory for the factorisation or its workspace.
    OutOfMemory,
    /// The factor predicted by the symbolic phase does not fit in the memory available:
    /// refused before the numeric phase (instead of a crash or the OOM killer).
    FactorTooLarge {
        /// Bytes the numeric phase would need (the factor's values and workspace).
        predicted_bytes: u64,
        /// Bytes available (the machine's, or the limit given to the solver).
        available_bytes: u64,
        /// Entries of the factor `L`.
        nnz_factor: usize,
    },
    /// Another failure reported by faer.
    Internal(String),
    /// A PETSc call failed, or PETSc rejected the options (PETSc backend).
    Petsc(String),
    /// PETSc's Krylov solver did not converge (PETSc backend): its converged reason, the
    /// iterations done and the relative residual ‖b − Ax‖/‖b‖ reached.
    KspDiverged { reason: String, iterations: usize, relative_residual: f64 },
}

impl fmt::Display for LinearError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinearError::InvalidPattern(why) => write!(f, "invalid sparsity pattern: {why}"),
            LinearError::InvalidPrimalCount { n_primal, n } => {
                write!(f, "{n_primal} primal unknowns requested but the system has only {n} unknowns")
            }
            LinearError::CholeskyWithMultipliers { n_multipliers } => write!(
                f,
                "Cholesky cannot factorise a system with {n_multipliers} multiplier unknowns (it is indefinite); \
                 use the ldlt or lu solver"
            ),
            LinearError::LengthMismatch { what, expected, got } => {
                write!(f, "{what} has {got} entries, expected {expected}")
            }
            LinearError::NonFiniteMatrix { row, col, value } => {
                write!(f, "matrix entry ({row}, {col}) is {value}: the assembled values contain NaN or infinity")
            }
            LinearError::NonFiniteRhs { index, value } => {
                write!(f, "right-hand side entry {index} is {value}: the load vector contains NaN or infinity")
            }
            LinearError::EmptyRow { unknown } => write!(
                f,
                "unknown {unknown} has no nonzero coefficient (its row and column are zero), so the system is \
                 singular: a dof attached to no element, or a constraint with no terms"
            ),
            LinearError::NotPositiveDefinite { unknown, pivot, diagonal } => {
                if !pivot.is_finite() {
                    write!(
                        f,
                        "the matrix is not positive definite: eliminating the unknowns ordered before unknown \
                         {unknown} (diagonal entry {diagonal:.3e}) leaves it a non-positive pivot \
                         (a zero-energy motion or a dof without stiffness)"
                    )
                } else if *diagonal <= 0.0 {
                    write!(
                        f,
                        "the matrix is not positive definite: unknown {unknown} has diagonal entry {diagonal:.3e} \
                         (a stiffness matrix needs a positive diagonal)"
                    )
                } else {
                    write!(
                        f,
                        "the matrix is not positive definite: eliminating the unknowns ordered before unknown \
                         {unknown} leaves it a pivot of {pivot:.3e} for a diagonal entry of {diagonal:.3e} \
                         (a zero-energy motion or a dof without stiffness)"
                    )
                }
            }
            LinearError::ZeroPivot { unknown } => write!(
                f,
                "the factorisation broke down at unknown {unknown} (zero or non-finite pivot): the matrix is \
                 singular, or not of the form this method needs"
            ),
            LinearError::Singular { relative_residual, regularised_pivots } => {
                write!(
                    f,
                    "the solution does not satisfy the system (relative residual {relative_residual:.2e}): the \
                     matrix is singular or nearly so"
                )?;
                if *regularised_pivots > 0 {
                    write!(f, " ({regularised_pivots} pivots had to be regularised)")?;
                }
                if !relative_residual.is_finite() {
                    // A NaN or infinite residual: the solve left the double range (an
                    // overflow, or norms of values near 1e-300 that underflow).
                    write!(
                        f,
                        ", or the solve left the range of double precision; typical causes: loads some 1e±300 \
                         of the stiffness in these units (write the model in other units), a rigid-body motion \
                         not prevented, or redundant or conflicting constraints"
                    )
                } else {
                    write!(
                        f,
                        "; typical causes: a rigid-body motion not prevented, or redundant or conflicting constraints"
                    )
                }
            }
            LinearError::NotFactorized => write!(f, "solve requested before a successful numeric factorisation"),
            LinearError::OutOfMemory => write!(f, "not enough memory for the sparse factorisation"),
            LinearError::FactorTooLarge { predicted_bytes, available_bytes, nnz_factor } => write!(
                f,
                "the factorisation needs about {:.2} GB ({:.1}M entries in the factor) but only {:.2} GB of \
                 memory is available: use a coarser mesh, [solver] ordering = \"nested_dissection\", or a \
                 machine with more memory",
                *predicted_bytes as f64 / 1e9,
                *nnz_factor as f64 / 1e6,
                *available_bytes as f64 / 1e9
            ),
            LinearError::Internal(why) => write!(f, "sparse solver failure: {why}"),
            LinearError::Petsc(why) => write!(f, "PETSc: {why}"),
            LinearError::KspDiverged { reason, iterations, relative_residual } => write!(
                f,
                "PETSc's KSP did not converge: {reason} after {iterations} iterations (relative residual \
                 {relative_residual:.2e}); change [solver.petsc] ksp, pc, rtol or options (or -ksp_type, \
                 -pc_type, -ksp_max_it on the command line after --)"
            ),
        }
    }
}

/// Which linear backend solves the systems (`[solver] backend`).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Backend {
    /// faer's direct solvers, in this process (the default).
    #[default]
    Faer,
    /// PETSc's distributed solvers over MPI (cargo feature `petsc`).
    Petsc(PetscSettings),
}

impl Backend {
    /// The lower-case name used in case files and `summary.json`.
    pub fn name(&self) -> &'static str {
        match self {
            Backend::Faer => "faer",
            Backend::Petsc(_) => "petsc",
        }
    }
}

/// The PETSc backend's settings (`[solver.petsc]`); PETSc's options database
/// (`PETSC_OPTIONS`, the command line after `--`) overrides them.
#[derive(Debug, Clone, PartialEq)]
pub struct PetscSettings {
    /// The `KSPType` (`cg`, `gmres`, `fgmres`, `preonly`, …); `None`: `cg` for positive
    /// definite systems, `preonly` for the others.
    pub ksp: Option<String>,
    /// The `PCType` (`gamg`, `hypre`, `lu`, `fieldsplit`, …); `None`: `gamg` for positive
    /// definite systems, `lu` (by MUMPS) for the others.
    pub pc: Option<String>,
    /// The KSP's relative tolerance.
    pub rtol: f64,
    /// More options for PETSc's options database (`-pc_gamg_threshold 0.05 …`).
    pub options: String,
}

impl Default for PetscSettings {
    fn default() -> Self {
        PetscSettings { ksp: None, pc: None, rtol: 1e-10, options: String::new() }
    }
}

/// What a run reports of its backend (`summary.json` `linear_solver`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BackendInfo {
    /// `faer` or `petsc`.
    pub name: &'static str,
    /// PETSc: the KSP and PC types in use (after the options database), the MPI ranks and
    /// the Krylov iterations of the last solve; `None` with faer.
    pub ksp: Option<String>,
    pub pc: Option<String>,
    pub ranks: Option<usize>,
    pub iterations: Option<usize>,
    /// PETSc with distributed assembly: the cells, and the enriched cells (cut by a crack
    /// or at its tip), each rank assembles.
    pub cells_per_rank: Option<Vec<usize>>,
    pub enriched_cells_per_rank: Option<Vec<usize>>,
    /// PETSc with distributed assembly: the contact points whose terms each rank
    /// assembles (models with contact), and the matrix entries of each rank's rows.
    pub contact_points_per_rank: Option<Vec<usize>>,
    pub matrix_entries_per_rank: Option<Vec<usize>>,
    /// PETSc: every rank's peak resident memory (`VmHWM`, KiB) at the end of the last
    /// solve.
    pub peak_rss_kib_per_rank: Option<Vec<u64>>,
}

/// Where the unknowns of a system sit: the point (usually the mesh node) of each unknown
/// and the coordinates of the points.
#[derive(Debug, Clone, Copy)]
pub struct EquationPoints<'a> {
    /// The point of each unknown (indices into `coords`), [`NO_POINT`] for unknowns that
    /// have none (multipliers).
    pub point_of_eq: &'a [u32],
    /// Coordinates of the points (unused components 0).
    pub coords: &'a [[f64; 3]],
    /// Dimension of the mesh (2 or 3): the automatic ordering is geometric nested
    /// dissection on 2D meshes and METIS nested dissection on 3D meshes.
    pub dim: usize,
}

/// Marks an unknown without a point.
pub const NO_POINT: u32 = u32::MAX;

/// The fill-reducing ordering of the primal unknowns asked of a direct backend.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OrderingChoice {
    /// The best measured for the system: geometric nested dissection on 2D meshes, METIS
    /// nested dissection on 3D meshes, minimum degree when the unknowns have no points.
    #[default]
    Auto,
    /// Approximate minimum degree.
    Amd,
    /// METIS nested dissection, on the node graph when the unknowns have points.
    NestedDissection,
}

impl OrderingChoice {
    /// The lower-case name used in case files.
    pub fn name(self) -> &'static str {
        match self {
            OrderingChoice::Auto => "auto",
            OrderingChoice::Amd => "amd",
            OrderingChoice::NestedDissection => "nested_dissection",
        }
    }
}

/// What a solver is asked to analyse: the pattern, the method, the multipliers, and
/// optionally where the unknowns sit and which of them vary between factorisations.
#[derive(Debug, Clone, Copy)]
pub struct SystemStructure<'a> {
    /// The factorisation (for a direct backend) or the class of the matrix.
    pub method: LinearMethod,
    /// The sparsity pattern (both triangles, structurally symmetric).
    pub pattern: &'a CscPattern,
    /// Unknowns `0..n_primal` are primal; `n_primal..n` are multipliers.
    pub n_primal: usize,
    /// The point (mesh node) of every unknown, for orderings and partitioning.
    pub points: Option<&'a EquationPoints<'a>>,
    /// `Some` for contact systems whose matrix changes between factorisations only in the
    /// rows and columns of the multipliers and of the primal unknowns coupled to them (a
    /// backend may then condense onto those unknowns); the inner flags, if given, restrict
    /// the varying primal unknowns to those marked.
    pub condense: Option<Option<&'a [bool]>>,
    /// The fill-reducing ordering.
    pub ordering: OrderingChoice,
    /// Bytes the factorisation may use; `None`: the memory available on the machine.
    pub memory_limit: Option<u64>,
    /// The node order of an earlier analysis on the same mesh, reused when it applies
    /// (the entries of a crack growth run: [`crate::solve::ordering::reuse`]); `None`:
    /// computed for this system.
    pub reuse: Option<&'a crate::solve::ordering::reuse::ReusedOrdering>,
    /// The arithmetic of the factor (direct backends).
    pub precision: Precision,
}

/// A sparse linear solver for the systems of fissure: symbolic phase once per pattern,
/// numeric phase for every new set of values on it, solves with the current values.
///
/// Values are always given as one array in the order of the pattern's entries
/// ([`CscPattern`]); right-hand sides and solutions are in the original numbering of the
/// unknowns. Errors are [`LinearError`]s, whose messages are meant for users.
pub trait LinearBackend: Sized + Send + Sync {
    /// Symbolic phase: checks the pattern, chooses the ordering and prepares the factor
    /// (or the distributed matrix and its preallocation).
    fn analyse(system: &SystemStructure<'_>) -> Result<Self, LinearError>;

    /// Numeric phase for new values on the analysed pattern (reuses the symbolic work).
    /// On error the previous factor is no longer usable.
    fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError>;

    /// Solves `A x = b` in place (`rhs` holds `b` on entry, `x` on success) with the values
    /// of the last successful [`Self::factorize`], checking the residual.
    fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError>;

    /// The bulk values of a contact system (the matrix without the contact terms), given
    /// once before the contact iterations. A no-op unless the backend condenses.
    fn set_bulk(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let _ = values;
        Ok(())
    }

    /// A Newton correction of a contact iteration whose interior rows are residuals of
    /// equations already satisfied: a condensing backend solves for the crack unknowns
    /// and multipliers only and defers the interior; by default a full solve.
    fn solve_in_place_deferred(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        self.solve_in_place(rhs)
    }

    /// Adds to `x` the interior corrections deferred since the last full solve. Nothing to
    /// add by default.
    fn apply_deferred(&self, x: &mut [f64]) {
        let _ = x;
    }

    /// The unknowns whose rows and columns may change between factorisations of a
    /// condensed factor; `None` when the backend does not condense.
    fn varying_unknowns(&self) -> Option<Vec<usize>> {
        None
    }

    /// The method chosen at [`Self::analyse`].
    fn method(&self) -> LinearMethod;

    /// Number of unknowns.
    fn n(&self) -> usize;

    /// Number of primal unknowns (the rest are multipliers).
    fn n_primal(&self) -> usize;

    /// Pivots perturbed in the last factorisation (0 when none was).
    fn regularised_pivots(&self) -> usize;

    /// ‖Ax − b‖/‖b‖ of the last solve (NaN before any solve) and the number of
    /// refinement (or iterative) steps it took.
    fn last_residual(&self) -> (f64, usize);

    /// Figures for `summary.json` and benchmarks.
    fn stats(&self) -> LinearStats;
}
