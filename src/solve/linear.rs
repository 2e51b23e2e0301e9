//! Sparse direct solvers on faer, split into a symbolic phase (done once per sparsity
//! pattern) and a numeric phase (done for every new set of values).
//!
//! Entry point: [`LinearSolver`]. [`LinearSolver::analyse`] validates a [`CscPattern`],
//! computes the fill-reducing ordering and the symbolic factorisation (and reserves the
//! scratch memory); [`LinearSolver::factorize`] computes the numeric factor for a value
//! array on that pattern and may be called again and again (Newton / active-set loops)
//! without redoing the symbolic work; [`LinearSolver::solve_in_place`] solves with the
//! current factor, checks the residual and refines it iteratively when that helps.
//!
//! This module owns the choice of faer paths:
//!
//! - [`LinearMethod::Cholesky`]: faer's sparse `LLᵀ` for symmetric positive definite
//!   matrices. Non-positive and tiny pivots (relative to the diagonal) are reported as
//!   [`LinearError::NotPositiveDefinite`] instead of producing garbage.
//! - [`LinearMethod::Ldlt`]: faer's sparse `LDLᵀ` without pivoting for symmetric
//!   quasi-definite and saddle-point matrices `[K Bᵀ; B −C]`, whose last `n − n_primal`
//!   unknowns are multipliers. The primal block is ordered as for Cholesky (see
//!   "Orderings" below), with every multiplier placed right after the last primal
//!   unknown it couples to (so the zero
//!   diagonal block never gives a zero pivot when `K` is positive definite), and a
//!   sign-aware dynamic regularisation (primal pivots `> 0`, multiplier pivots `< 0`)
//!   covers `K` that is only positive definite on the kernel of `B`; iterative refinement
//!   then restores full accuracy.
//! - [`LinearMethod::Lu`]: faer's sparse LU with partial pivoting (COLAMD ordering), the
//!   general fallback (e.g. unsymmetric friction tangents); several times the time and
//!   memory of Cholesky (6–10× in 2D at 5e5 unknowns, `examples/linear_solver_timing.rs`).
//!
//! Orderings ([`LinearSolver::analyse_with_points`] passes the node of every unknown):
//! geometric nested dissection on 2D meshes ([`super::ordering`]), AMD on the full graph
//! on 3D meshes, supervariable-compressed AMD when no positions are given. Large 2D
//! Cholesky systems are factorised as the two halves of the top separator in parallel
//! (`split.rs`); otherwise faer's dense kernels run in parallel only for large fronts.
//!
//! Contact systems ([`LinearSolver::analyse_condensed`]) change only in the rows and
//! columns of the crack unknowns and multipliers between factorisations: the bulk is then
//! factorised once and each factorisation is a dense `LBLᵀ` of the crack system
//! (`condensed.rs`), with Newton corrections that defer the interior
//! ([`LinearSolver::solve_in_place_deferred`]).
//!
//! Every method factorises the symmetrically scaled matrix `S A S` (unit diagonal on the
//! primal unknowns, unit largest coupling on the multipliers), which makes the pivot
//! thresholds relative and independent of units. Cholesky and LDLᵀ read only the lower
//! triangle of the values; the residual check uses the full matrix.

use super::condensed::{CondensedError, CondensedFactor};
use super::ordering::{nested_dissection, nested_dissection_split, EquationPoints};
use super::split::{SplitCholesky, SplitError};
use crate::assembly::CscPattern;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal, CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::sparse::{FaerError, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};
use rayon::prelude::*;
use std::fmt;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, TryLockError};
use std::time::Instant;

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

/// Figures for `summary.json` and benchmarks.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LinearStats {
    /// Entries of the factor `L` (lower triangle with the diagonal) for Cholesky and
    /// LDLᵀ; `None` for LU (faer does not expose it).
    pub nnz_factor: Option<usize>,
    /// Seconds of the symbolic phase ([`LinearSolver::analyse`]).
    pub symbolic_s: f64,
    /// Seconds of the last numeric phase ([`LinearSolver::factorize`]).
    pub numeric_s: f64,
    /// Seconds of the last [`LinearSolver::solve_in_place`] (refinement included).
    pub solve_s: f64,
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
    /// Another failure reported by faer.
    Internal(String),
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
                write!(
                    f,
                    "; typical causes: a rigid-body motion not prevented, or redundant or conflicting constraints"
                )
            }
            LinearError::NotFactorized => write!(f, "solve requested before a successful numeric factorisation"),
            LinearError::OutOfMemory => write!(f, "not enough memory for the sparse factorisation"),
            LinearError::Internal(why) => write!(f, "sparse solver failure: {why}"),
        }
    }
}

impl std::error::Error for LinearError {}

impl From<FaerError> for LinearError {
    fn from(e: FaerError) -> Self {
        match e {
            FaerError::OutOfMemory => LinearError::OutOfMemory,
            other => LinearError::Internal(format!("{other:?}")),
        }
    }
}

/// Pivot threshold (relative to the unit diagonal of the scaled matrix), `10 max(n, 1000) ε`
/// (2.2e-9 for 1M unknowns). Cholesky reports a pivot below it as "not positive definite";
/// LDLᵀ replaces a pivot below it (or of the wrong sign) by `±LDLT_DELTA` and lets
/// iterative refinement remove the perturbation. Measured: singular matrices (pure
/// Neumann Laplacians, 2D up to 1M unknowns, 3D up to 216k) leave round-off pivots of
/// about 0.1 n ε, where well-posed stiffness matrices have pivots of order 0.1.
fn pivot_threshold(n: usize) -> f64 {
    10.0 * (n.max(1000) as f64) * f64::EPSILON
}
/// The value given to regularised LDLᵀ pivots (≈ √ε: balances the perturbation against
/// the growth it causes, so that refinement converges in a step or two).
const LDLT_DELTA: f64 = 1e-8;
/// Iterative refinement runs while the normwise backward error
/// `‖r‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` (of the scaled system) is above the target, and goes on only
/// while each step at least halves the residual. LDLᵀ (no pivoting) and LU: a first step
/// is almost always taken (it costs one solve and typically gains 30–50 % on large FE
/// systems, much more after regularisation); Cholesky is backward stable and is only
/// refined when the first solve is clearly poor.
const ETA_TARGET_PIVOTING: f64 = 0.5 * f64::EPSILON;
const ETA_TARGET_CHOLESKY: f64 = 1e3 * f64::EPSILON;
/// At most this many refinement steps (more when pivots were regularised).
const MAX_REFINE: usize = 3;
const MAX_REFINE_REGULARISED: usize = 10;
/// A relative residual ‖Ax − b‖/‖b‖ above this after refinement is an error.
const MAX_RELATIVE_RESIDUAL: f64 = 1e-6;

enum Factor {
    /// n == 0: nothing to factorise.
    Empty,
    /// Cholesky `LLᵀ` or LDLᵀ (same symbolic structure).
    Cholesky {
        symbolic: SymbolicCholesky<usize>,
        l_values: Vec<f64>,
    },
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
    /// Cholesky split at the top separator (large 2D systems), halves in parallel.
    Split(Box<SplitCholesky>),
    /// Contact systems: the bulk factorised once, a dense factor on the crack unknowns.
    Condensed(Box<CondensedFactor>),
}

/// Buffers of the solve phase, reused between solves.
struct SolveWorkspace {
    mem: MemBuffer,
    /// Scaled right-hand side `S b`.
    b: Vec<f64>,
    /// Residual (of the scaled system).
    r: Vec<f64>,
    /// Refinement correction.
    dx: Vec<f64>,
}

impl SolveWorkspace {
    fn new(req: StackReq, n: usize) -> Result<Self, LinearError> {
        Ok(SolveWorkspace {
            mem: MemBuffer::try_new(req).map_err(|_| LinearError::OutOfMemory)?,
            b: vec![0.0; n],
            r: vec![0.0; n],
            dx: vec![0.0; n],
        })
    }
}

/// A sparse direct solver: [`analyse`](Self::analyse) once per pattern,
/// [`factorize`](Self::factorize) for each new set of values,
/// [`solve_in_place`](Self::solve_in_place) for each right-hand side.
pub struct LinearSolver {
    method: LinearMethod,
    n: usize,
    n_primal: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position of each diagonal entry in the value array, if stored.
    diag_pos: Vec<Option<usize>>,
    factor: Factor,
    /// LDLᵀ expected pivot signs in the original numbering: +1 primal, −1 multiplier.
    signs: Vec<i8>,
    /// Symmetric scaling `S` (the factor is of `S A S`).
    scale: Vec<f64>,
    /// Values of `S A S`, kept for the residuals.
    scaled: Vec<f64>,
    /// ‖S A S‖∞ (largest absolute row sum).
    norm_inf: f64,
    /// Condensed factor: the largest absolute row sum over the interior rows (bulk).
    interior_norm_inf: f64,
    factor_mem: MemBuffer,
    solve_req: StackReq,
    workspace: Mutex<SolveWorkspace>,
    par: Par,
    factorized: bool,
    /// The primal scaling was fixed by [`LinearSolver::set_bulk`] (condensed factor: the
    /// scaled bulk must not change between contact iterations).
    primal_scale_fixed: bool,
    regularised: usize,
    nnz_factor: Option<usize>,
    symbolic_s: f64,
    numeric_s: f64,
    solve_s: AtomicU64,
    last_residual: AtomicU64,
    last_refinements: AtomicUsize,
    /// Condensed factor: crack corrections of deferred solves not yet propagated to the
    /// interior (scaled units; see [`LinearSolver::solve_in_place_deferred`]).
    pending: Mutex<Vec<f64>>,
}

impl fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LinearSolver")
            .field("method", &self.method)
            .field("n", &self.n)
            .field("n_primal", &self.n_primal)
            .field("factorized", &self.factorized)
            .field("regularised_pivots", &self.regularised)
            .field("stats", &self.stats())
            .finish()
    }
}

impl LinearSolver {
    /// Symbolic phase, once per pattern. Unknowns `n_primal..n` are multipliers (ordered
    /// after the primal unknowns they couple to for Ldlt; not allowed for Cholesky).
    pub fn analyse(method: LinearMethod, pattern: &CscPattern, n_primal: usize) -> Result<Self, LinearError> {
        Self::analyse_with_points(method, pattern, n_primal, None)
    }

    /// Like [`Self::analyse`], with the positions of the primal unknowns (their mesh
    /// nodes) for Cholesky and LDLᵀ: the primal unknowns are then ordered by geometric
    /// nested dissection ([`super::ordering`]) instead of minimum degree.
    pub fn analyse_with_points(
        method: LinearMethod,
        pattern: &CscPattern,
        n_primal: usize,
        points: Option<&EquationPoints<'_>>,
    ) -> Result<Self, LinearError> {
        Self::analyse_impl(method, pattern, n_primal, points, None)
    }

    /// Like [`Self::analyse_with_points`] for LDLᵀ systems whose matrix changes between
    /// factorisations only in the rows and columns of the multipliers and of the primal
    /// unknowns coupled to them (contact: the dofs of the contact elements). The factor is
    /// then condensed onto those unknowns (`condensed.rs`): the bulk is factorised once
    /// (for the values given to [`Self::set_bulk`]), and each [`Self::factorize`] only
    /// factorises a dense matrix of their size. Falls back to the plain LDLᵀ when they are
    /// too many for a dense factor ([`CONDENSED_MAX_DENSE`]) or the method is not LDLᵀ.
    ///
    /// `varying` (one flag per primal unknown), if given, restricts the crack unknowns to
    /// those marked: the couplings of the multipliers to the others must then be zero in
    /// every factorised matrix (checked; the plain LDLᵀ takes over otherwise).
    pub fn analyse_condensed(
        method: LinearMethod,
        pattern: &CscPattern,
        n_primal: usize,
        points: Option<&EquationPoints<'_>>,
        varying: Option<&[bool]>,
    ) -> Result<Self, LinearError> {
        Self::analyse_impl(method, pattern, n_primal, points, Some(varying))
    }

    /// Whether the factor is condensed onto the crack unknowns (see
    /// [`Self::analyse_condensed`]).
    pub fn is_condensed(&self) -> bool {
        matches!(self.factor, Factor::Condensed(_))
    }

    fn analyse_impl(
        method: LinearMethod,
        pattern: &CscPattern,
        n_primal: usize,
        points: Option<&EquationPoints<'_>>,
        condense: Option<Option<&[bool]>>,
    ) -> Result<Self, LinearError> {
        let clock = Instant::now();
        let n = pattern.n;
        if n_primal > n {
            return Err(LinearError::InvalidPrimalCount { n_primal, n });
        }
        if method == LinearMethod::Cholesky && n_primal < n {
            return Err(LinearError::CholeskyWithMultipliers { n_multipliers: n - n_primal });
        }
        validate_pattern(pattern)?;
        let diag_pos: Vec<Option<usize>> = (0..n).into_par_iter().map(|j| pattern.position(j, j)).collect();
        let mut par = Par::Seq;
        let col_ptr = pattern.col_ptr.clone();
        let row_idx = pattern.row_idx.clone();

        let (factor, factor_req, solve_req, nnz_factor) = if n == 0 {
            (Factor::Empty, StackReq::EMPTY, StackReq::EMPTY, Some(0))
        } else {
            let a = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            match method {
                LinearMethod::Cholesky if split_candidate(n, points) => {
                    let p = points.expect("split candidates have points");
                    match nested_dissection_split(&col_ptr, &row_idx, n, p) {
                        Some((fwd, _, (n1, n2)))
                            if n1 > 0 && n2 > 0 && (1..=SPLIT_MAX_SEPARATOR).contains(&(n - n1 - n2)) =>
                        {
                            match SplitCholesky::analyse(&col_ptr, &row_idx, fwd, n1, n2)? {
                                Some(split) => {
                                    let nnz = split.nnz_factor();
                                    (Factor::Split(Box::new(split)), StackReq::EMPTY, StackReq::EMPTY, Some(nnz))
                                }
                                // Not a separator (cannot happen with the dissection's
                                // one-sided separators): the unsplit factorisation.
                                None => Self::symbolic_cholesky(
                                    method, a, &col_ptr, &row_idx, n, n_primal, points, &mut par,
                                )?,
                            }
                        }
                        _ => Self::symbolic_cholesky(method, a, &col_ptr, &row_idx, n, n_primal, points, &mut par)?,
                    }
                }
                LinearMethod::Ldlt if condense.is_some() && n_primal < n => {
                    match condensed_factor(&col_ptr, &row_idx, n, n_primal, points, condense.flatten())? {
                        Some(c) => {
                            let nnz = c.nnz_factor();
                            (Factor::Condensed(Box::new(c)), StackReq::EMPTY, StackReq::EMPTY, Some(nnz))
                        }
                        None => Self::symbolic_cholesky(method, a, &col_ptr, &row_idx, n, n_primal, points, &mut par)?,
                    }
                }
                LinearMethod::Cholesky | LinearMethod::Ldlt => {
                    Self::symbolic_cholesky(method, a, &col_ptr, &row_idx, n, n_primal, points, &mut par)?
                }
                LinearMethod::Lu => {
                    par = Par::rayon(0);
                    let symbolic = factorize_symbolic_lu(a, LuSymbolicParams::default())?;
                    let factor_req = symbolic.factorize_numeric_lu_scratch::<f64>(par, Spec::default());
                    let solve_req = symbolic.solve_in_place_scratch::<f64>(1, par);
                    (Factor::Lu { symbolic, numeric: NumericLu::new() }, factor_req, solve_req, None)
                }
            }
        };
        let factor_mem = MemBuffer::try_new(factor_req).map_err(|_| LinearError::OutOfMemory)?;
        let workspace = Mutex::new(SolveWorkspace::new(solve_req, n)?);
        let signs = if method == LinearMethod::Ldlt {
            (0..n).map(|i| if i < n_primal { 1 } else { -1 }).collect()
        } else {
            vec![]
        };
        Ok(LinearSolver {
            method,
            n,
            n_primal,
            col_ptr,
            row_idx,
            diag_pos,
            factor,
            signs,
            scale: vec![1.0; n],
            scaled: vec![0.0; pattern.nnz()],
            norm_inf: 0.0,
            interior_norm_inf: 0.0,
            factor_mem,
            solve_req,
            workspace,
            par,
            factorized: false,
            primal_scale_fixed: false,
            regularised: 0,
            nnz_factor,
            symbolic_s: clock.elapsed().as_secs_f64(),
            numeric_s: 0.0,
            solve_s: AtomicU64::new(0f64.to_bits()),
            last_residual: AtomicU64::new(f64::NAN.to_bits()),
            last_refinements: AtomicUsize::new(0),
            pending: Mutex::new(vec![]),
        })
    }

    /// faer's symbolic Cholesky / LDLᵀ on the whole system; `par` becomes parallel when
    /// the fronts are large.
    #[allow(clippy::too_many_arguments)]
    fn symbolic_cholesky(
        method: LinearMethod,
        a: SymbolicSparseColMatRef<'_, usize>,
        col_ptr: &[usize],
        row_idx: &[usize],
        n: usize,
        n_primal: usize,
        points: Option<&EquationPoints<'_>>,
        par: &mut Par,
    ) -> Result<(Factor, StackReq, StackReq, Option<usize>), LinearError> {
        let custom = if method == LinearMethod::Cholesky {
            primal_ordering(col_ptr, row_idx, n, points)?
        } else {
            multipliers_after_primal_ordering(col_ptr, row_idx, n, n_primal, points)?
        };
        let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&custom.0, &custom.1, n));
        let symbolic = factorize_symbolic_cholesky(a, Side::Lower, ordering, CholeskySymbolicParams::default())?;
        if factor_flops(&symbolic) > PARALLEL_FLOPS_PER_ENTRY * factor_nnz(&symbolic) as f64 {
            *par = Par::rayon(0);
        }
        let factor_req = if method == LinearMethod::Cholesky {
            symbolic.factorize_numeric_llt_scratch::<f64>(*par, Spec::default())
        } else {
            symbolic.factorize_numeric_ldlt_scratch::<f64>(*par, Spec::default())
        };
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, *par);
        let nnz = factor_nnz(&symbolic);
        let l_values = try_zeroed_vec(symbolic.len_val())?;
        Ok((Factor::Cholesky { symbolic, l_values }, factor_req, solve_req, Some(nnz)))
    }

    /// A matrix value array must have one value per pattern entry.
    fn check_values(&self, values: &[f64]) -> Result<(), LinearError> {
        let nnz = self.row_idx.len();
        if values.len() != nnz {
            return Err(LinearError::LengthMismatch {
                what: "the matrix value array",
                expected: nnz,
                got: values.len(),
            });
        }
        Ok(())
    }

    /// The bulk values of a condensed factor ([`Self::analyse_condensed`]): fixes the
    /// scaling of the primal unknowns and factorises the bulk stage, unless these values
    /// were already factorised. A no-op for the other factors.
    pub fn set_bulk(&mut self, values: &[f64]) -> Result<(), LinearError> {
        if !matches!(self.factor, Factor::Condensed(_)) {
            return Ok(());
        }
        self.check_values(values)?;
        if let Factor::Condensed(c) = &self.factor {
            if self.primal_scale_fixed && c.bulk_matches(&self.col_ptr, &self.row_idx, values, true) {
                return Ok(());
            }
        }
        self.factorized = false;
        self.primal_scale_fixed = false;
        self.compute_scaling_of(values, true, false)?;
        self.primal_scale_fixed = true;
        self.fill_scaled(values);
        let Factor::Condensed(c) = &self.factor else { unreachable!("checked above") };
        let mut interior = vec![true; self.n];
        for j in c.varying() {
            interior[j] = false;
        }
        self.interior_norm_inf = self.row_sum_norm(Some(&interior));
        let Factor::Condensed(c) = &mut self.factor else { unreachable!("checked above") };
        match c.set_bulk(&self.col_ptr, &self.row_idx, &self.scaled, values) {
            Ok(()) => Ok(()),
            // The bulk alone is not positive definite (a part held only through the
            // multipliers): the plain LDLᵀ, whose regularisation covers that.
            Err(CondensedError::NonPositive { .. } | CondensedError::NotCondensable) => self.fall_back_to_ldlt(),
            Err(e) => Err(condensed_error(e, &self.diag_pos, values)),
        }
    }

    /// Replaces a condensed factor by the plain LDLᵀ (minimum-degree ordering, multipliers
    /// after their unknowns).
    fn fall_back_to_ldlt(&mut self) -> Result<(), LinearError> {
        let n = self.n;
        let a = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let mut par = Par::Seq;
        let (factor, factor_req, solve_req, nnz) = Self::symbolic_cholesky(
            LinearMethod::Ldlt,
            a,
            &self.col_ptr,
            &self.row_idx,
            n,
            self.n_primal,
            None,
            &mut par,
        )?;
        self.factor = factor;
        self.factor_mem = MemBuffer::try_new(factor_req).map_err(|_| LinearError::OutOfMemory)?;
        self.workspace = Mutex::new(SolveWorkspace::new(solve_req, n)?);
        self.solve_req = solve_req;
        self.par = par;
        self.nnz_factor = nnz;
        self.primal_scale_fixed = false;
        self.factorized = false;
        Ok(())
    }

    /// Numeric phase for new values on the same pattern (reuses the symbolic factorisation
    /// and the scratch memory). On error the previous factor is no longer usable.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        self.factorized = false;
        self.regularised = 0;
        self.check_values(values)?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let col = self.col_ptr.partition_point(|&p| p <= k) - 1;
            return Err(LinearError::NonFiniteMatrix { row: self.row_idx[k], col, value: values[k] });
        }
        if let Factor::Condensed(c) = &self.factor {
            // New bulk values: the bulk stage first (or the plain LDLᵀ, if it falls back).
            if !(self.primal_scale_fixed && c.bulk_matches(&self.col_ptr, &self.row_idx, values, false)) {
                self.set_bulk(values)?;
                if !matches!(self.factor, Factor::Condensed(_)) {
                    return self.factorize(values);
                }
            }
        }
        let fixed = self.primal_scale_fixed && matches!(self.factor, Factor::Condensed(_));
        self.compute_scaling_of(values, !fixed, true)?;
        match (&self.factor, fixed) {
            // Condensed, after the bulk: only the columns of the crack unknowns and the
            // multipliers change (the matrix is symmetric: their rows too).
            (Factor::Condensed(c), true) => {
                let mut norm = self.interior_norm_inf;
                for j in c.varying() {
                    let sj = self.scale[j];
                    let col = self.col_ptr[j]..self.col_ptr[j + 1];
                    let mut sum = 0.0;
                    for ((out, &a), &i) in
                        self.scaled[col.clone()].iter_mut().zip(&values[col.clone()]).zip(&self.row_idx[col])
                    {
                        *out = self.scale[i] * a * sj;
                        sum += out.abs();
                    }
                    norm = norm.max(sum);
                }
                // The transposed entries (row j of the interior columns are bulk entries,
                // unchanged; rows j of crack and multiplier columns are refreshed above).
                self.norm_inf = norm;
            }
            _ => {
                if matches!(self.factor, Factor::Condensed(_)) {
                    self.primal_scale_fixed = true;
                }
                self.fill_scaled(values);
                self.norm_inf = self.row_sum_norm(None);
            }
        }

        let n = self.n;
        let par = self.par;
        let stack = MemStack::new(&mut self.factor_mem);
        match &mut self.factor {
            Factor::Empty => {}
            Factor::Cholesky { symbolic, l_values } => {
                let a = SparseColMatRef::new(
                    SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
                    &self.scaled,
                );
                let fwd = |p: usize| symbolic.perm().map_or(p, |perm| perm.arrays().0[p]);
                let simplicial = matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
                if self.method == LinearMethod::Cholesky {
                    let result = symbolic.factorize_numeric_llt::<f64>(
                        l_values,
                        a,
                        Side::Lower,
                        LltRegularization::default(),
                        par,
                        stack,
                        Spec::default(),
                    );
                    if let Err(LltError::NonPositivePivot { index }) = result {
                        // faer's simplicial path reports the pivot one-based.
                        let p = if simplicial { index.saturating_sub(1) } else { index }.min(n - 1);
                        let unknown = fwd(p);
                        let diagonal = self.diagonal_value(values, unknown);
                        return Err(LinearError::NotPositiveDefinite { unknown, pivot: f64::NAN, diagonal });
                    }
                    // Tiny pivots: numerically singular (e.g. a rigid-body motion left free).
                    let mut worst: Option<(usize, f64)> = None;
                    for_each_pivot(symbolic, l_values, |p, l| {
                        let d = l * l;
                        if worst.is_none_or(|(_, w)| d < w) {
                            worst = Some((p, d));
                        }
                    });
                    if let Some((p, d)) = worst {
                        // `d` is finite here: faer rejects NaN pivots.
                        if d < pivot_threshold(n) {
                            let unknown = fwd(p);
                            let diagonal = self.diagonal_value(values, unknown);
                            return Err(LinearError::NotPositiveDefinite { unknown, pivot: d * diagonal, diagonal });
                        }
                    }
                } else {
                    let regularisation = LdltRegularization {
                        dynamic_regularization_signs: Some(&self.signs),
                        dynamic_regularization_delta: LDLT_DELTA,
                        dynamic_regularization_epsilon: pivot_threshold(n),
                    };
                    let result = symbolic.factorize_numeric_ldlt::<f64>(
                        l_values,
                        a,
                        Side::Lower,
                        regularisation,
                        par,
                        stack,
                        Spec::default(),
                    );
                    if let Err(LdltError::ZeroPivot { index }) = result {
                        let p = if simplicial { index.saturating_sub(1) } else { index }.min(n - 1);
                        return Err(LinearError::ZeroPivot { unknown: fwd(p) });
                    }
                    let mut count = 0;
                    for_each_pivot(symbolic, l_values, |_, d| {
                        if d.abs() == LDLT_DELTA {
                            count += 1;
                        }
                    });
                    self.regularised = count;
                }
            }
            Factor::Split(split) => match split.factorize(&self.scaled) {
                Ok((d, position)) => {
                    if d < pivot_threshold(n) {
                        let unknown = split.unknown_at(position);
                        let diagonal = self.diag_pos[unknown].map_or(0.0, |k| values[k]);
                        return Err(LinearError::NotPositiveDefinite { unknown, pivot: d * diagonal, diagonal });
                    }
                }
                Err(SplitError::NonPositive { position }) => {
                    let unknown = split.unknown_at(position);
                    let diagonal = self.diag_pos[unknown].map_or(0.0, |k| values[k]);
                    return Err(LinearError::NotPositiveDefinite { unknown, pivot: f64::NAN, diagonal });
                }
                Err(SplitError::Faer(e)) => return Err(e.into()),
            },
            Factor::Condensed(c) => match c.factorize(&self.scaled) {
                Ok(()) => {}
                Err(CondensedError::NonPositive { .. } | CondensedError::NotCondensable) => {
                    self.fall_back_to_ldlt()?;
                    return self.factorize(values);
                }
                Err(e) => return Err(condensed_error(e, &self.diag_pos, values)),
            },
            Factor::Lu { symbolic, numeric } => {
                let a = SparseColMatRef::new(
                    SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
                    &self.scaled,
                );
                match symbolic.factorize_numeric_lu::<f64>(numeric, a, par, stack, Spec::default()) {
                    Ok(_) => {}
                    Err(LuError::SymbolicSingular { index }) => {
                        return Err(LinearError::ZeroPivot {
                            unknown: symbolic.col_perm().arrays().0[index.min(n - 1)],
                        })
                    }
                    Err(LuError::Generic(e)) => return Err(e.into()),
                }
            }
        }
        self.factorized = true;
        self.numeric_s = clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Solves `A x = b` in place (`rhs` holds `b` on entry, `x` on success) with the
    /// current factor, then checks the residual and refines iteratively while that
    /// reduces the residual (LDLᵀ and LU; Cholesky only when the
    /// first solve is clearly inaccurate). Safe to call from several threads at once.
    /// On error `rhs` holds the best approximation found, or is unspecified.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        self.check_rhs(rhs)?;
        // A full solve corrects every unknown from the true residual: nothing stays deferred.
        if let Ok(mut p) = self.pending.try_lock() {
            p.fill(0.0);
        }
        let result = match self.workspace.try_lock() {
            Ok(mut ws) => self.solve_with(rhs, &mut ws),
            Err(TryLockError::Poisoned(p)) => self.solve_with(rhs, &mut p.into_inner()),
            // Another thread is solving: use a private workspace.
            Err(TryLockError::WouldBlock) => {
                SolveWorkspace::new(self.solve_req, self.n).and_then(|mut ws| self.solve_with(rhs, &mut ws))
            }
        };
        self.solve_s.store(clock.elapsed().as_secs_f64().to_bits(), Ordering::Relaxed);
        result
    }

    /// A Newton correction of a contact iteration (condensed factor): solves for the crack
    /// unknowns and multipliers only, and defers the interior. The interior rows of `rhs`
    /// must be residuals of linear equations already satisfied (they are ignored), and the
    /// crack rows may have been computed without the interior corrections still deferred
    /// (the solver accounts for them). On return `rhs` holds the correction of the crack
    /// unknowns and multipliers, zero on the interior; [`Self::apply_deferred`] then adds
    /// the accumulated interior correction. For the other factors this is
    /// [`Self::solve_in_place`].
    pub fn solve_in_place_deferred(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let Factor::Condensed(c) = &self.factor else { return self.solve_in_place(rhs) };
        let clock = Instant::now();
        self.check_rhs(rhs)?;
        for (v, s) in rhs.iter_mut().zip(&self.scale) {
            *v *= s;
        }
        let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        pending.resize(c.n_crack(), 0.0);
        let relative = c.solve_deferred(rhs, &mut pending);
        for (v, s) in rhs.iter_mut().zip(&self.scale) {
            *v *= s;
        }
        self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
        self.last_refinements.store(0, Ordering::Relaxed);
        self.solve_s.store(clock.elapsed().as_secs_f64().to_bits(), Ordering::Relaxed);
        if relative.is_nan() || relative > MAX_RELATIVE_RESIDUAL {
            return Err(LinearError::Singular { relative_residual: relative, regularised_pivots: 0 });
        }
        Ok(())
    }

    /// The unknowns whose rows and columns may change between factorisations of a
    /// condensed factor (crack unknowns and multipliers); `None` for the other factors.
    pub fn varying_unknowns(&self) -> Option<Vec<usize>> {
        match &self.factor {
            Factor::Condensed(c) => Some(c.varying().collect()),
            _ => None,
        }
    }

    /// Adds to `x` the interior corrections deferred by
    /// [`Self::solve_in_place_deferred`] since the last full solve, and clears them.
    pub fn apply_deferred(&self, x: &mut [f64]) {
        let Factor::Condensed(c) = &self.factor else { return };
        let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        if pending.iter().all(|&v| v == 0.0) {
            return;
        }
        let mut dx = vec![0.0; self.n];
        c.apply_pending(&mut pending, &mut dx);
        for ((xi, d), s) in x.iter_mut().zip(&dx).zip(&self.scale) {
            *xi += d * s;
        }
    }

    /// A right-hand side can be solved: factorised, of the right length, finite.
    fn check_rhs(&self, rhs: &[f64]) -> Result<(), LinearError> {
        if !self.factorized {
            return Err(LinearError::NotFactorized);
        }
        if rhs.len() != self.n {
            return Err(LinearError::LengthMismatch { what: "the right-hand side", expected: self.n, got: rhs.len() });
        }
        if let Some(index) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(LinearError::NonFiniteRhs { index, value: rhs[index] });
        }
        Ok(())
    }

    /// The method chosen at [`analyse`](Self::analyse).
    pub fn method(&self) -> LinearMethod {
        self.method
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of primal unknowns (the rest are multipliers).
    pub fn n_primal(&self) -> usize {
        self.n_primal
    }

    /// LDLᵀ pivots replaced by `±δ` in the last factorisation (0 for a positive definite
    /// `K`; a few for a `K` that is singular until the constraints act).
    pub fn regularised_pivots(&self) -> usize {
        self.regularised
    }

    /// ‖Ax − b‖/‖b‖ of the last solve (NaN before any solve) and the number of
    /// refinement steps it took.
    pub fn last_residual(&self) -> (f64, usize) {
        (f64::from_bits(self.last_residual.load(Ordering::Relaxed)), self.last_refinements.load(Ordering::Relaxed))
    }

    /// Figures for `summary.json` and benchmarks.
    pub fn stats(&self) -> LinearStats {
        LinearStats {
            nnz_factor: self.nnz_factor,
            symbolic_s: self.symbolic_s,
            numeric_s: self.numeric_s,
            solve_s: f64::from_bits(self.solve_s.load(Ordering::Relaxed)),
        }
    }

    fn diagonal_value(&self, values: &[f64], j: usize) -> f64 {
        self.diag_pos[j].map_or(0.0, |k| values[k])
    }

    /// The symmetric scaling: `1/√a_jj` on primal unknowns with a nonzero diagonal (the
    /// largest coupling otherwise), and `1/max_i |a_ij s_i|` over primal `i` on
    /// multipliers, so that scaled couplings are O(1) and thresholds are relative.
    fn compute_scaling_of(&mut self, values: &[f64], primal: bool, multipliers: bool) -> Result<(), LinearError> {
        let n_primal = self.n_primal;
        let (cp, diag_pos, method) = (&self.col_ptr, &self.diag_pos, self.method);
        // Per unknown: the error it raises, or the primal scale (NaN: keep the old one).
        let check = |j: usize| -> Result<f64, LinearError> {
            if (j < n_primal && !primal) || (j >= n_primal && !multipliers) {
                return Ok(f64::NAN);
            }
            let col = &values[cp[j]..cp[j + 1]];
            if col.iter().all(|&v| v == 0.0) {
                return Err(LinearError::EmptyRow { unknown: j });
            }
            let d = diag_pos[j].map_or(0.0, |k| values[k]);
            if method == LinearMethod::Cholesky && d <= 0.0 {
                return Err(LinearError::NotPositiveDefinite { unknown: j, pivot: d, diagonal: d });
            }
            if j >= n_primal {
                return Ok(f64::NAN);
            }
            let d = if d != 0.0 { d.abs() } else { col.iter().fold(0.0f64, |m, v| m.max(v.abs())) };
            Ok(1.0 / d.sqrt())
        };
        let first = if primal { 0 } else { n_primal };
        let last = if multipliers { self.n } else { n_primal };
        let new: Vec<f64> = (first..last).into_par_iter().map(check).collect::<Result<_, _>>()?;
        for (s, v) in self.scale[first..last].iter_mut().zip(new) {
            if !v.is_nan() {
                *s = v;
            }
        }
        for j in n_primal..self.n {
            if !multipliers {
                break;
            }
            let mut coupling = 0.0f64;
            let mut other = 0.0f64;
            let col = self.col_ptr[j]..self.col_ptr[j + 1];
            for (&a, &i) in values[col.clone()].iter().zip(&self.row_idx[col]) {
                if i < n_primal {
                    coupling = coupling.max((a * self.scale[i]).abs());
                } else {
                    other = other.max(a.abs());
                }
            }
            let t = coupling.max(other.sqrt());
            self.scale[j] = 1.0 / t;
        }
        Ok(())
    }

    /// ‖S A S‖∞ (largest absolute row sum; the matrix is symmetric); with `interior`, the
    /// largest over the rows so marked only.
    fn row_sum_norm(&mut self, interior: Option<&[bool]>) -> f64 {
        if self.method != LinearMethod::Lu {
            // Symmetric values: the row sums are the column sums, in parallel.
            let (cp, scaled) = (&self.col_ptr, &self.scaled);
            return (0..self.n)
                .into_par_iter()
                .filter(|&j| interior.is_none_or(|m| m[j]))
                .map(|j| scaled[cp[j]..cp[j + 1]].iter().map(|v| v.abs()).sum::<f64>())
                .reduce(|| 0.0, f64::max);
        }
        // The workspace's residual buffer as scratch.
        let row_sum = &mut self.workspace.get_mut().unwrap_or_else(|p| p.into_inner()).r;
        row_sum.fill(0.0);
        for (&a, &i) in self.scaled.iter().zip(&self.row_idx) {
            row_sum[i] += a.abs();
        }
        row_sum.iter().enumerate().filter(|(i, _)| interior.is_none_or(|m| m[*i])).fold(0.0, |m: f64, (_, &v)| m.max(v))
    }

    /// `scaled = S A S` for the values `A` and the current scaling `S`.
    fn fill_scaled(&mut self, values: &[f64]) {
        let (cp, ri, scale) = (&self.col_ptr, &self.row_idx, &self.scale);
        for_column_blocks(cp, &mut self.scaled, |cols, out| {
            let base = cp[cols.start];
            for j in cols {
                let sj = scale[j];
                for k in cp[j]..cp[j + 1] {
                    out[k - base] = scale[ri[k]] * values[k] * sj;
                }
            }
        });
    }

    fn factor_solve(&self, x: &mut [f64], stack: &mut MemStack) {
        let n = self.n;
        match &self.factor {
            Factor::Split(split) => return split.solve_in_place(x),
            Factor::Condensed(c) => return c.solve_in_place(x),
            _ => {}
        }
        let x = MatMut::from_column_major_slice_mut(x, n, 1);
        match &self.factor {
            Factor::Empty | Factor::Split(_) | Factor::Condensed(_) => {}
            Factor::Cholesky { symbolic, l_values } => {
                if self.method == LinearMethod::Cholesky {
                    LltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, self.par, stack)
                } else {
                    LdltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, self.par, stack)
                }
            }
            Factor::Lu { symbolic, numeric } => {
                LuRef::new_unchecked(symbolic, numeric).solve_in_place_with_conj(Conj::No, x, self.par, stack)
            }
        }
    }

    /// `r = b̃ − Ã y` in `ws.r`; returns ‖S⁻¹ r‖₂² (the squared residual of the original
    /// system) and the normwise backward error ‖r‖∞ / (‖Ã‖∞ ‖y‖∞ + ‖b̃‖∞).
    fn residual(&self, y: &[f64], ws: &mut SolveWorkspace, b_inf: f64) -> (f64, f64) {
        let SolveWorkspace { b, r, .. } = ws;
        r.copy_from_slice(b);
        let mut y_inf = 0.0f64;
        for (j, &yj) in y.iter().enumerate() {
            y_inf = y_inf.max(yj.abs());
            if yj == 0.0 {
                continue;
            }
            let col = self.col_ptr[j]..self.col_ptr[j + 1];
            for (&a, &i) in self.scaled[col.clone()].iter().zip(&self.row_idx[col]) {
                r[i] -= a * yj;
            }
        }
        let mut norm2 = 0.0;
        let mut r_inf = 0.0f64;
        for (ri, s) in r.iter().zip(&self.scale) {
            let true_ri = ri / s;
            norm2 += true_ri * true_ri;
            r_inf = r_inf.max(ri.abs());
        }
        (norm2, r_inf / (self.norm_inf * y_inf + b_inf))
    }

    fn solve_with(&self, rhs: &mut [f64], ws: &mut SolveWorkspace) -> Result<(), LinearError> {
        let bnorm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        if bnorm == 0.0 {
            rhs.fill(0.0);
            self.last_residual.store(0f64.to_bits(), Ordering::Relaxed);
            self.last_refinements.store(0, Ordering::Relaxed);
            return Ok(());
        }
        let mut b_inf = 0.0f64;
        for ((bi, yi), s) in ws.b.iter_mut().zip(rhs.iter_mut()).zip(&self.scale) {
            *bi = *yi * s;
            *yi = *bi;
            b_inf = b_inf.max(bi.abs());
        }
        let y = rhs;
        self.factor_solve(y, MemStack::new(&mut ws.mem));
        let (mut norm2, mut eta) = self.residual(y, ws, b_inf);
        let condensed = matches!(self.factor, Factor::Condensed(_));
        let (target, max_steps) = match (self.method, self.regularised) {
            (LinearMethod::Cholesky, _) => (ETA_TARGET_CHOLESKY, MAX_REFINE),
            // Cholesky on the bulk, Bunch–Kaufman (pivoting) on the dense part.
            _ if condensed => (ETA_TARGET_CHOLESKY, MAX_REFINE),
            (_, 0) => (ETA_TARGET_PIVOTING, MAX_REFINE),
            _ => (ETA_TARGET_PIVOTING, MAX_REFINE_REGULARISED),
        };
        let mut steps = 0;
        while eta > target && steps < max_steps {
            steps += 1;
            ws.dx.copy_from_slice(&ws.r);
            self.factor_solve(&mut ws.dx, MemStack::new(&mut ws.mem));
            for (yi, di) in y.iter_mut().zip(&ws.dx) {
                *yi += di;
            }
            let (new_norm2, new_eta) = self.residual(y, ws, b_inf);
            if new_norm2.is_nan() || new_norm2 > norm2 {
                // Worse (or NaN): step back and stop.
                for (yi, di) in y.iter_mut().zip(&ws.dx) {
                    *yi -= di;
                }
                break;
            }
            // Go on only while a step at least halves the residual.
            let progress = new_norm2 <= 0.25 * norm2;
            norm2 = new_norm2;
            eta = new_eta;
            if !progress {
                break;
            }
        }
        let relative = norm2.sqrt() / bnorm;
        self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
        self.last_refinements.store(steps, Ordering::Relaxed);
        for (yi, s) in y.iter_mut().zip(&self.scale) {
            *yi *= s;
        }
        if relative.is_nan() || relative > MAX_RELATIVE_RESIDUAL {
            return Err(LinearError::Singular { relative_residual: relative, regularised_pivots: self.regularised });
        }
        Ok(())
    }
}

/// Runs `f(columns, entries)` in parallel on blocks of consecutive columns, with the
/// entries of `data` (one per stored entry, in column order) that belong to them.
fn for_column_blocks(col_ptr: &[usize], data: &mut [f64], f: impl Fn(std::ops::Range<usize>, &mut [f64]) + Sync) {
    let n = col_ptr.len() - 1;
    let blocks = (rayon::current_num_threads() * 8).clamp(1, n.max(1));
    let mut parts = Vec::with_capacity(blocks);
    let mut rest = data;
    let mut start = 0;
    for b in 1..=blocks {
        let end = n * b / blocks;
        let (head, tail) = rest.split_at_mut(col_ptr[end] - col_ptr[start]);
        parts.push((start..end, head));
        rest = tail;
        start = end;
    }
    parts.into_par_iter().for_each(|(cols, out)| f(cols, out));
}

/// Checks the invariants of [`CscPattern`] that faer and this module rely on.
fn validate_pattern(p: &CscPattern) -> Result<(), LinearError> {
    let n = p.n;
    let bad = |why: String| Err(LinearError::InvalidPattern(why));
    if p.col_ptr.len() != n + 1 {
        return bad(format!("{} column pointers for {n} columns", p.col_ptr.len()));
    }
    if p.col_ptr[0] != 0 || p.col_ptr[n] != p.row_idx.len() {
        return bad(format!(
            "column pointers run from {} to {} for {} entries",
            p.col_ptr[0],
            p.col_ptr[n],
            p.row_idx.len()
        ));
    }
    for j in 0..n {
        let (s, e) = (p.col_ptr[j], p.col_ptr[j + 1]);
        if s > e {
            return bad(format!("column pointers decrease at column {j}"));
        }
        let rows = &p.row_idx[s..e];
        if rows.windows(2).any(|w| w[0] >= w[1]) {
            return bad(format!("row indices of column {j} are not sorted and unique"));
        }
        if let Some(&i) = rows.last() {
            if i >= n {
                return bad(format!("row index {i} in column {j} is out of range"));
            }
        }
    }
    // Structural symmetry, in parallel over columns (the first bad column is reported).
    let asymmetric = (0..n).into_par_iter().find_map_first(|j| {
        p.row_idx[p.col_ptr[j]..p.col_ptr[j + 1]]
            .iter()
            .find(|&&i| i > j && p.position(j, i).is_none())
            .map(|&i| (i, j))
    });
    if let Some((i, j)) = asymmetric {
        return bad(format!("entry ({i}, {j}) is stored but ({j}, {i}) is not (not structurally symmetric)"));
    }
    Ok(())
}

/// The LDLᵀ ordering: the primal block ordered by [`primal_ordering`], then each
/// multiplier right after the last (in that order) primal unknown it couples to; multipliers coupled to no primal unknown
/// come last. Every leading block `[K_SS B_Sᵀ; B_S −C_S]` then only holds constraints on
/// already-ordered primal unknowns, so with `K` positive definite no pivot is zero and
/// the pivot signs are known (+ primal, − multiplier). Fill stays close to that of `K`
/// (a Dirichlet multiplier costs about one extra column), where putting all multipliers
/// last would make their Schur complement block dense.
/// Returns (forward, inverse): `forward[new] = old`.
fn multipliers_after_primal_ordering(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    points: Option<&EquationPoints<'_>>,
) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    let (sub_ptr, sub_idx) = primal_subpattern(col_ptr, row_idx, n_primal);
    let (primal_fwd, primal_inv) =
        if n_primal > 0 { primal_ordering(&sub_ptr, &sub_idx, n_primal, points)? } else { (vec![], vec![]) };
    drop((sub_ptr, sub_idx));
    // key[l]: rank of the last primal unknown multiplier l couples to (n_primal if none).
    let m = n - n_primal;
    let key: Vec<usize> = (0..m)
        .map(|l| {
            let j = n_primal + l;
            row_idx[col_ptr[j]..col_ptr[j + 1]]
                .iter()
                .take_while(|&&i| i < n_primal)
                .map(|&i| primal_inv[i])
                .max()
                .unwrap_or(n_primal)
        })
        .collect();
    // Stable counting sort of the multipliers by key.
    let mut start = vec![0usize; n_primal + 2];
    for &k in &key {
        start[k + 1] += 1;
    }
    for r in 0..=n_primal {
        start[r + 1] += start[r];
    }
    let mut sorted = vec![0usize; m];
    for (l, &k) in key.iter().enumerate() {
        sorted[start[k]] = l;
        start[k] += 1;
    }
    let mut fwd = Vec::with_capacity(n);
    let mut q = 0;
    for (r, &p) in primal_fwd.iter().enumerate() {
        fwd.push(p);
        while q < m && key[sorted[q]] == r {
            fwd.push(n_primal + sorted[q]);
            q += 1;
        }
    }
    fwd.extend(sorted[q..].iter().map(|&l| n_primal + l));
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Ok((fwd, inv))
}

/// A vector of `len` zeros from `alloc_zeroed`: large blocks come zeroed from the
/// system, so nothing is written here (the factor's pages are first touched by the
/// numeric phase instead of being filled twice). Transparent huge pages were tried for
/// this buffer (`MADV_HUGEPAGE`): faster when the kernel had free huge pages, but with
/// the usual `defrag = madvise` setting the faults then compact memory synchronously,
/// and on a busy machine that cost up to a second of system time.
pub(crate) fn try_zeroed_vec(len: usize) -> Result<Vec<f64>, LinearError> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| LinearError::OutOfMemory)?;
    // SAFETY: the layout has a nonzero size.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return Err(LinearError::OutOfMemory);
    }
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `len` f64,
    // and all-zero bytes are the f64 value 0.0, so all `len` elements are initialised.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// The condensed factor ([`LinearSolver::analyse_condensed`]) is used when the crack
/// unknowns and multipliers are at most this many (their dense `LBLᵀ` costs `n³/3` per
/// contact iteration) and the crack unknowns and the separator at most
/// `CONDENSED_MAX_SEPARATOR` (the dense part of the bulk factor).
pub const CONDENSED_MAX_DENSE: usize = 2500;
/// ... and when they are at most `1 / CONDENSED_MIN_RATIO` of the unknowns: on small
/// models where contact covers a large part of the mesh (sliding blocks, patch tests) the
/// dense factor costs more than the sparse LDLᵀ of the whole system (the 2D sliding blocks,
/// 5 566 unknowns: 4.2 s condensed against 2.9 s).
pub const CONDENSED_MIN_RATIO: usize = 20;
const CONDENSED_MAX_SEPARATOR: usize = 4000;

/// The condensed factor of a saddle-point pattern, or `None` when it does not apply (see
/// [`CONDENSED_MAX_DENSE`]).
fn condensed_factor(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    points: Option<&EquationPoints<'_>>,
    varying: Option<&[bool]>,
) -> Result<Option<CondensedFactor>, LinearError> {
    // The crack unknowns: primal unknowns coupled to a multiplier (and marked varying).
    let mut crack = vec![false; n_primal];
    for j in n_primal..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i < n_primal && varying.is_none_or(|v| v[i]) {
                crack[i] = true;
            }
        }
    }
    let nc = crack.iter().filter(|&&c| c).count();
    if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
        eprintln!("condensation: {nc} crack unknowns, {} multipliers", n - n_primal);
    }
    let nf = nc + (n - n_primal);
    if nf > CONDENSED_MAX_DENSE || nf * CONDENSED_MIN_RATIO > n || nc == n_primal {
        return Ok(None);
    }
    // The primal sub-pattern and its ordering (nested dissection split in large 2D
    // systems, as for the split Cholesky).
    let (sub_ptr, sub_idx) = primal_subpattern(col_ptr, row_idx, n_primal);
    let split = match points {
        Some(p) if split_candidate(n_primal, points) => nested_dissection_split(&sub_ptr, &sub_idx, n_primal, p)
            .filter(|(_, _, (n1, n2))| *n1 > 0 && *n2 > 0 && n_primal - n1 - n2 + nc <= CONDENSED_MAX_SEPARATOR),
        _ => None,
    };
    let (order, parts) = match split {
        Some((fwd, _, parts)) => (fwd, parts),
        None => (primal_ordering(&sub_ptr, &sub_idx, n_primal, points)?.0, (0, 0)),
    };
    drop((sub_ptr, sub_idx));
    Ok(CondensedFactor::analyse(col_ptr, row_idx, &order, parts, &crack, (n_primal..n).collect())?)
}

/// The pattern of the primal unknowns `0..n_primal` alone (column pointers, row indices).
fn primal_subpattern(col_ptr: &[usize], row_idx: &[usize], n_primal: usize) -> (Vec<usize>, Vec<usize>) {
    let mut sub_ptr = Vec::with_capacity(n_primal + 1);
    let mut sub_idx = Vec::with_capacity(col_ptr[n_primal]);
    sub_ptr.push(0);
    for j in 0..n_primal {
        let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        let end = rows.partition_point(|&i| i < n_primal);
        sub_idx.extend_from_slice(&rows[..end]);
        sub_ptr.push(sub_idx.len());
    }
    (sub_ptr, sub_idx)
}

/// A condensed factorisation error as a [`LinearError`].
fn condensed_error(e: CondensedError, diag_pos: &[Option<usize>], values: &[f64]) -> LinearError {
    match e {
        CondensedError::NonPositive { unknown } => {
            let diagonal = diag_pos[unknown].map_or(0.0, |k| values[k]);
            LinearError::NotPositiveDefinite { unknown, pivot: f64::NAN, diagonal }
        }
        CondensedError::NotCondensable => {
            LinearError::Internal("a multiplier couples to an interior unknown".to_string())
        }
        CondensedError::Faer(e) => e.into(),
    }
}

/// Cholesky systems with at least this many unknowns and points in 2D are factorised as
/// two halves in parallel ([`SplitCholesky`]), when the top separator has at most
/// [`SPLIT_MAX_SEPARATOR`] unknowns (its dense factor costs `n3³/3` three times over).
const SPLIT_MIN_UNKNOWNS: usize = 20_000;
const SPLIT_MAX_SEPARATOR: usize = 3_000;

fn split_candidate(n: usize, points: Option<&EquationPoints<'_>>) -> bool {
    n >= SPLIT_MIN_UNKNOWNS && points.is_some_and(|p| p.dim == 2)
}

/// Cholesky and LDLᵀ run faer's dense kernels in parallel only when the fronts are large:
/// more flops per entry of `L` than this (the mean front size, roughly). faer's
/// parallelism is inside each supernode's dense operations, and with small fronts its
/// fork-join overhead outweighs the gain: 2D X-FEM at 4e5 unknowns (400 flops per entry)
/// took 0.47 s sequential and 0.71 s parallel on 2 shared cores. 3D factors (penny crack:
/// several thousand flops per entry) keep the parallel kernels.
const PARALLEL_FLOPS_PER_ENTRY: f64 = 2000.0;

/// Approximate flops of the numeric Cholesky (0 for a simplicial factor, which faer
/// chooses for small, sparse factors).
fn factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(_) => 0.0,
        SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
            .map(|k| {
                let c = (s.supernode_end()[k] - s.supernode_begin()[k]) as f64;
                let r = s.supernode(k).pattern().len() as f64;
                c * c * c / 3.0 + c * c * r + c * r * r
            })
            .sum(),
    }
}

/// Entries of the lower triangle (diagonal included) of the factor.
fn factor_nnz(symbolic: &SymbolicCholesky<usize>) -> usize {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => s.len_val(),
        SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
            .map(|k| {
                let ncols = s.supernode_end()[k] - s.supernode_begin()[k];
                ncols * (ncols + 1) / 2 + ncols * s.supernode(k).pattern().len()
            })
            .sum(),
    }
}

/// Calls `f(permuted index, diagonal value)` for every diagonal entry of the factor:
/// `L_kk` for `LLᵀ`, `D_k` for `LDLᵀ`.
fn for_each_pivot(symbolic: &SymbolicCholesky<usize>, l_values: &[f64], mut f: impl FnMut(usize, f64)) {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let col_ptr = s.col_ptr();
            for k in 0..s.ncols() {
                f(k, l_values[col_ptr[k]]);
            }
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let l = supernodal::SupernodalLltRef::<usize, f64>::new(s, l_values);
            for k in 0..s.n_supernodes() {
                let node = l.supernode(k);
                let block = node.val();
                for j in 0..block.ncols() {
                    f(node.start() + j, block[(j, j)]);
                }
            }
        }
    }
}

/// The ordering of a pattern without multipliers. With the unknowns' points: geometric
/// nested dissection in 2D (less fill and faster to compute than minimum degree), plain
/// AMD in 3D (on the graded, enriched 3D meshes measured, AMD on the full graph gave
/// 219M entries in `L` where the supervariable-compressed AMD gave 241M and this nested
/// dissection 297M). Without points: the compressed AMD (fast, same 2D fill as plain AMD).
fn primal_ordering(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    points: Option<&EquationPoints<'_>>,
) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    match points {
        Some(p) if p.dim == 2 => match nested_dissection(col_ptr, row_idx, n, p) {
            Some(perm) => Ok(perm),
            None => compressed_amd(col_ptr, row_idx, n),
        },
        Some(_) => plain_amd(col_ptr, row_idx, n),
        None => compressed_amd(col_ptr, row_idx, n),
    }
}

/// AMD on the full graph. Returns (forward, inverse): `forward[new] = old`.
fn plain_amd(col_ptr: &[usize], row_idx: &[usize], n: usize) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    let mut fwd = vec![0usize; n];
    let mut inv = vec![0usize; n];
    let a = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut mem =
        MemBuffer::try_new(amd::order_scratch::<usize>(n, row_idx.len())).map_err(|_| LinearError::OutOfMemory)?;
    amd::order(&mut fwd, &mut inv, a, amd::Control::default(), MemStack::new(&mut mem))?;
    Ok((fwd, inv))
}

/// AMD on the graph compressed by supervariables: consecutive columns with identical row
/// patterns (the components of a node's displacement, of an enrichment) are merged, the
/// compressed graph is ordered, and every supervariable is expanded in place. The fill is
/// that of AMD on the full graph (AMD merges indistinguishable vertices anyway) for a
/// fraction of its time (1/dim² of the edges). Returns (forward, inverse): `forward[new] = old`.
fn compressed_amd(col_ptr: &[usize], row_idx: &[usize], n: usize) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    // Groups of consecutive identical columns.
    let mut group_of = vec![0usize; n];
    let mut starts = vec![0usize];
    for j in 1..n {
        let same = row_idx[col_ptr[j]..col_ptr[j + 1]] == row_idx[col_ptr[j - 1]..col_ptr[j]];
        if !same {
            starts.push(j);
        }
        group_of[j] = starts.len() - 1;
    }
    let ng = starts.len();
    starts.push(n);
    // Compressed pattern: the groups of the rows of each group's first column.
    let mut cptr = Vec::with_capacity(ng + 1);
    let mut cidx = Vec::new();
    cptr.push(0usize);
    for g in 0..ng {
        let j = starts[g];
        let mut last = usize::MAX;
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let gi = group_of[i];
            if gi != last {
                cidx.push(gi);
                last = gi;
            }
        }
        cptr.push(cidx.len());
    }
    // Rows within a column are sorted and groups are contiguous ranges, so the group ids
    // are sorted and unique: a valid compressed pattern.
    let mut gfwd = vec![0usize; ng];
    let mut ginv = vec![0usize; ng];
    let sub = SymbolicSparseColMatRef::new_checked(ng, ng, &cptr, None, &cidx);
    let mut mem =
        MemBuffer::try_new(amd::order_scratch::<usize>(ng, cidx.len())).map_err(|_| LinearError::OutOfMemory)?;
    amd::order(&mut gfwd, &mut ginv, sub, amd::Control::default(), MemStack::new(&mut mem))?;
    let mut fwd = Vec::with_capacity(n);
    for &g in &gfwd {
        fwd.extend(starts[g]..starts[g + 1]);
    }
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Ok((fwd, inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (pattern, values) from triplets (duplicates summed).
    fn matrix(n: usize, triplets: &[(usize, usize, f64)]) -> (CscPattern, Vec<f64>) {
        let entries: Vec<(usize, usize)> = triplets.iter().map(|&(i, j, _)| (i, j)).collect();
        let pattern = CscPattern::from_entries(n, &entries);
        let mut values = vec![0.0; pattern.nnz()];
        for &(i, j, v) in triplets {
            values[pattern.position(i, j).unwrap()] += v;
        }
        (pattern, values)
    }

    /// 5-point Laplacian on an nx × ny grid: with `dirichlet` the diagonal is 4
    /// (homogeneous Dirichlet outside, SPD), otherwise the number of neighbours (pure
    /// Neumann, singular with the constants as kernel).
    fn laplacian_triplets(nx: usize, ny: usize, dirichlet: bool) -> Vec<(usize, usize, f64)> {
        let id = |x: usize, y: usize| y * nx + x;
        let mut t = vec![];
        for y in 0..ny {
            for x in 0..nx {
                let i = id(x, y);
                let mut neighbours = vec![];
                if x > 0 {
                    neighbours.push(id(x - 1, y));
                }
                if x + 1 < nx {
                    neighbours.push(id(x + 1, y));
                }
                if y > 0 {
                    neighbours.push(id(x, y - 1));
                }
                if y + 1 < ny {
                    neighbours.push(id(x, y + 1));
                }
                let d = if dirichlet { 4.0 } else { neighbours.len() as f64 };
                t.push((i, i, d));
                for j in neighbours {
                    t.push((i, j, -1.0));
                }
            }
        }
        t
    }

    fn rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0).collect()
    }

    fn rel_residual(p: &CscPattern, v: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let mut ax = vec![0.0; p.n];
        p.mul_vec(v, x, &mut ax);
        let r: f64 = ax.iter().zip(b).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
        r / b.iter().map(|b| b * b).sum::<f64>().sqrt()
    }

    fn solve(s: &LinearSolver, b: &[f64]) -> Result<Vec<f64>, LinearError> {
        let mut x = b.to_vec();
        s.solve_in_place(&mut x).map(|_| x)
    }

    fn supernodal(s: &LinearSolver) -> bool {
        matches!(&s.factor, Factor::Cholesky { symbolic, .. } if matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)))
    }

    // SPD 2D Laplacians (50×50: faer's simplicial path; 200×200: supernodal) with each
    // method: ‖Ax − b‖/‖b‖ < 1e-12; refactorising with values scaled by 3 reuses the
    // symbolic phase (same solver, no new analyse) and gives x/3 to 1e-12 relative.
    #[test]
    fn spd_laplacian_all_methods_and_refactorisation() {
        for (nx, expect_supernodal) in [(50, false), (200, true)] {
            let (p, v) = matrix(nx * nx, &laplacian_triplets(nx, nx, true));
            let b = rhs(p.n);
            for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
                let mut s = LinearSolver::analyse(method, &p, p.n).unwrap();
                if method != LinearMethod::Lu {
                    assert_eq!(supernodal(&s), expect_supernodal, "{method} {nx}");
                    assert!(s.stats().nnz_factor.unwrap() >= (p.nnz() + p.n) / 2);
                }
                s.factorize(&v).unwrap();
                assert_eq!(s.regularised_pivots(), 0);
                let x = solve(&s, &b).unwrap();
                let r = rel_residual(&p, &v, &x, &b);
                assert!(r < 1e-12, "{method} {nx}: residual {r:e}");
                assert!((s.last_residual().0 - r).abs() < 1e-13);

                let v3: Vec<f64> = v.iter().map(|a| 3.0 * a).collect();
                s.factorize(&v3).unwrap();
                let x3 = solve(&s, &b).unwrap();
                assert!(rel_residual(&p, &v3, &x3, &b) < 1e-12);
                let xn = x.iter().map(|a| a * a).sum::<f64>().sqrt();
                let diff = x3.iter().zip(&x).map(|(a, b)| (3.0 * a - b).powi(2)).sum::<f64>().sqrt();
                assert!(diff < 1e-12 * xn, "{method}: scaled solution off by {:e}", diff / xn);
                let st = s.stats();
                assert!(st.symbolic_s >= 0.0 && st.numeric_s > 0.0 && st.solve_s > 0.0);
            }
        }
    }

    /// A saddle-point system: K the Laplacian (`dirichlet` false: the singular Neumann
    /// one) on nx × nx, B fixing the unknowns `fixed` to values g and tying a − b;
    /// returns (pattern, values, rhs, n_primal) with the multipliers last.
    #[allow(clippy::type_complexity)]
    fn saddle(
        nx: usize,
        dirichlet: bool,
        fixed: &[(usize, f64)],
        tie: Option<(usize, usize)>,
        c: f64,
        store_zero_diagonal: bool,
    ) -> (CscPattern, Vec<f64>, Vec<f64>, usize) {
        let np = nx * nx;
        let mut t = laplacian_triplets(nx, nx, dirichlet);
        let mut b = rhs(np);
        let mut row = np;
        for &(i, g) in fixed {
            t.push((row, i, 1.0));
            t.push((i, row, 1.0));
            b.push(g);
            row += 1;
        }
        if let Some((a, bb)) = tie {
            t.extend([(row, a, 1.0), (a, row, 1.0), (row, bb, -1.0), (bb, row, -1.0)]);
            b.push(0.0);
            row += 1;
        }
        for m in np..row {
            if c != 0.0 || store_zero_diagonal {
                t.push((m, m, -c));
            }
        }
        let (p, v) = matrix(row, &t);
        (p, v, b, np)
    }

    /// The primal solution of `saddle(...)` (with c = 0) by eliminating the constraints:
    /// fixed unknowns moved to the right-hand side, b merged into a; solved by Cholesky.
    fn eliminated(nx: usize, fixed: &[(usize, f64)], tie: Option<(usize, usize)>) -> Vec<f64> {
        let np = nx * nx;
        let t = laplacian_triplets(nx, nx, true);
        let f = rhs(np);
        let mut g = vec![None; np];
        for &(i, v) in fixed {
            g[i] = Some(v);
        }
        let mut target: Vec<usize> = (0..np).collect();
        if let Some((a, b)) = tie {
            target[b] = a;
        }
        let mut red = vec![usize::MAX; np];
        let mut nr = 0;
        for i in 0..np {
            if g[i].is_none() && target[i] == i {
                red[i] = nr;
                nr += 1;
            }
        }
        let r = |i: usize| red[target[i]];
        let mut rt = vec![];
        let mut rf = vec![0.0; nr];
        for i in 0..np {
            if g[i].is_none() {
                rf[r(i)] += f[i];
            }
        }
        for &(i, j, v) in &t {
            match (g[i], g[j]) {
                (None, None) => rt.push((r(i), r(j), v)),
                (None, Some(gj)) => rf[r(i)] -= v * gj,
                _ => {}
            }
        }
        let (p, v) = matrix(nr, &rt);
        let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, nr).unwrap();
        s.factorize(&v).unwrap();
        let z = solve(&s, &rf).unwrap();
        (0..np).map(|i| g[i].unwrap_or_else(|| z[r(i)])).collect()
    }

    // Saddle point [K Bᵀ; B 0] (K SPD Laplacian, B: Dirichlet-like rows fixing unknowns
    // and a tie u_a − u_b = 0; multiplier diagonals absent or stored as zeros): Ldlt and
    // Lu reach ‖Ax − b‖/‖b‖ < 1e-10 and the primal part matches the solution with the
    // constraints eliminated to 1e-10 relative; Cholesky returns an error (no panic/NaN).
    #[test]
    fn saddle_point_ldlt_lu_match_elimination() {
        let nx = 30;
        let fixed = [(0, 0.5), (17, -1.0), (nx * nx - 1, 2.0), (nx * 15 + 15, 0.25)];
        let tie = Some((3 * nx + 4, 20 * nx + 25));
        let reference = eliminated(nx, &fixed, tie);
        let rn = reference.iter().map(|a| a * a).sum::<f64>().sqrt();
        for store_zero in [false, true] {
            let (p, v, b, np) = saddle(nx, true, &fixed, tie, 0.0, store_zero);
            for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
                let mut s = LinearSolver::analyse(method, &p, np).unwrap();
                s.factorize(&v).unwrap();
                let x = solve(&s, &b).unwrap();
                let r = rel_residual(&p, &v, &x, &b);
                assert!(r < 1e-10, "{method}: residual {r:e}");
                let d = x[..np].iter().zip(&reference).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
                assert!(d < 1e-10 * rn, "{method}: differs from elimination by {:e}", d / rn);
                if method == LinearMethod::Ldlt {
                    assert_eq!(s.regularised_pivots(), 0, "K is SPD: no pivot needs regularising");
                }
            }
            let e = LinearSolver::analyse(LinearMethod::Cholesky, &p, np).unwrap_err();
            assert!(matches!(e, LinearError::CholeskyWithMultipliers { n_multipliers: 5 }), "{e}");
            // Also when the caller declares no multipliers: the zero diagonal is refused.
            let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
            let e = s.factorize(&v).unwrap_err();
            assert!(matches!(e, LinearError::NotPositiveDefinite { unknown, .. } if unknown >= np), "{e}");
            assert!(matches!(solve(&s, &b), Err(LinearError::NotFactorized)));
        }
    }

    // The LDLᵀ ordering puts every multiplier after all the primal unknowns it couples
    // to (exact check on the permutation).
    #[test]
    fn ldlt_ordering_places_multipliers_after_their_unknowns() {
        let nx = 12;
        let fixed: Vec<(usize, f64)> = (0..nx).map(|i| (i * nx, 1.0)).collect();
        let (p, _, _, np) = saddle(nx, true, &fixed, Some((5, 100)), 0.0, false);
        let (fwd, inv) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, None).unwrap();
        assert_eq!(fwd.len(), p.n);
        for (new, &old) in fwd.iter().enumerate() {
            assert_eq!(inv[old], new);
        }
        for m in np..p.n {
            for &i in &p.row_idx[p.col_ptr[m]..p.col_ptr[m + 1]] {
                if i < np {
                    assert!(inv[i] < inv[m], "multiplier {m} ordered before its unknown {i}");
                }
            }
        }
    }

    /// The grid points of `laplacian_triplets` (unknown y * nx + x at (x, y)).
    fn grid_points(nx: usize, ny: usize) -> (Vec<u32>, Vec<[f64; 3]>) {
        let coords: Vec<[f64; 3]> = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
        ((0..(nx * ny) as u32).collect(), coords)
    }

    /// A quad4-like pattern: an nx × ny grid of nodes with two unknowns each (node-major),
    /// every node coupled to its 8 neighbours; values diagonally dominant (SPD).
    fn quad_grid(nx: usize, ny: usize) -> (CscPattern, Vec<f64>, Vec<u32>, Vec<[f64; 3]>) {
        quad_grid_shifted(nx, ny, 0.01)
    }

    /// The element blocks of [`quad_grid`] (two unknowns per node, every node coupled to its
    /// 8 neighbours) for the cell rows `y` with `shift(y)` = Some(shift added to the
    /// diagonal); rows with None are left out (a grid cut in two).
    fn quad_triplets(nx: usize, ny: usize, shift: impl Fn(usize) -> Option<f64>) -> Vec<(usize, usize, f64)> {
        let node = |x: usize, y: usize| y * nx + x;
        let mut t = vec![];
        for y in 0..ny - 1 {
            let Some(shift) = shift(y) else { continue };
            for x in 0..nx - 1 {
                let q = [node(x, y), node(x + 1, y), node(x + 1, y + 1), node(x, y + 1)];
                for &a in &q {
                    for &b in &q {
                        for c in 0..2 {
                            t.push((2 * a + c, 2 * b + c, if a == b { 3.0 + shift } else { -1.0 }));
                        }
                    }
                }
            }
        }
        t
    }

    /// [`quad_grid`] with `shift` added to the diagonal of every element block (0: the
    /// graph Laplacian, singular with the constants per component as kernel).
    fn quad_grid_shifted(nx: usize, ny: usize, shift: f64) -> (CscPattern, Vec<f64>, Vec<u32>, Vec<[f64; 3]>) {
        let t = quad_triplets(nx, ny, |_| Some(shift));
        let (p, v) = matrix(2 * nx * ny, &t);
        let point_of_eq = (0..2 * nx * ny).map(|i| (i / 2) as u32).collect();
        let coords = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
        (p, v, point_of_eq, coords)
    }

    #[test]
    fn nested_dissection_on_a_quad_grid_is_a_permutation_with_less_fill_than_amd() {
        let (nx, ny) = (60, 45);
        let (p, v, point_of_eq, coords) = quad_grid(nx, ny);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let (fwd, inv) = nested_dissection(&p.col_ptr, &p.row_idx, p.n, &points).unwrap();
        let mut seen = vec![false; p.n];
        for (new, &old) in fwd.iter().enumerate() {
            assert!(!seen[old]);
            seen[old] = true;
            assert_eq!(inv[old], new);
        }
        let nd = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
        let amd = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
        let (f_nd, f_amd) = (nd.stats().nnz_factor.unwrap(), amd.stats().nnz_factor.unwrap());
        assert!(f_nd < f_amd, "nested dissection fill {f_nd} vs AMD {f_amd}");
        let mut s = nd;
        s.factorize(&v).unwrap();
        let b: Vec<f64> = (0..p.n).map(|i| (i % 7) as f64 - 3.0).collect();
        let x = solve(&s, &b).unwrap();
        assert!(rel_residual(&p, &v, &x, &b) < 1e-12);
        // An unknown without a point: no nested dissection (the caller falls back to AMD).
        let mut partial = point_of_eq.clone();
        partial[5] = crate::solve::ordering::NO_POINT;
        let points = EquationPoints { point_of_eq: &partial, coords: &coords, dim: 2 };
        assert!(nested_dissection(&p.col_ptr, &p.row_idx, p.n, &points).is_none());
    }

    /// A contact-like saddle point on the quad grid of [`quad_grid`]: one multiplier per
    /// node of the "crack" row `y = ny / 3` (x < 2nx/3), coupled to the jump of the second
    /// component between that row and the next, `[[u]] = u(x, y + 1) − u(x, y)`; the
    /// contact values add `rho [[u]]²` on the crack unknowns for the multipliers with
    /// `active[k]`, and `−1/rho` on the diagonal of the others (the augmented Lagrangian
    /// structure). Returns (pattern, bulk values, contact values, points, n_primal).
    #[allow(clippy::type_complexity)]
    fn contact_grid(
        nx: usize,
        ny: usize,
        rho: f64,
        active: impl Fn(usize) -> bool,
    ) -> (CscPattern, Vec<f64>, Vec<f64>, Vec<u32>, Vec<[f64; 3]>, usize) {
        let node = |x: usize, y: usize| y * nx + x;
        let np = 2 * nx * ny;
        let mut t = quad_triplets(nx, ny, |_| Some(0.01));
        let yc = ny / 3;
        let mut contact = vec![];
        for (k, x) in (0..2 * nx / 3).enumerate() {
            let (lo, hi) = (2 * node(x, yc) + 1, 2 * node(x, yc + 1) + 1);
            let m = np + k;
            let (bulk_mm, extra): (f64, Vec<(usize, usize, f64)>) = if active(k) {
                (0.0, vec![(lo, lo, rho), (hi, hi, rho), (lo, hi, -rho), (hi, lo, -rho)])
            } else {
                (-1.0 / rho, vec![])
            };
            t.extend([(m, hi, 0.0), (hi, m, 0.0), (m, lo, 0.0), (lo, m, 0.0), (m, m, 0.0)]);
            t.extend([(lo, hi, 0.0), (hi, lo, 0.0)]);
            contact.extend([(m, hi, 1.0), (hi, m, 1.0), (m, lo, -1.0), (lo, m, -1.0), (m, m, bulk_mm)]);
            contact.extend(extra);
        }
        let n = np + 2 * nx / 3;
        let (p, bulk) = matrix(n, &t);
        let mut full = bulk.clone();
        for &(i, j, v) in &contact {
            full[p.position(i, j).unwrap()] += v;
        }
        let mut point_of_eq: Vec<u32> = (0..np).map(|i| (i / 2) as u32).collect();
        point_of_eq.resize(n, crate::solve::ordering::NO_POINT);
        let coords = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
        (p, bulk, full, point_of_eq, coords, np)
    }

    // The condensed factor of a contact-like saddle point (bulk factorised once, dense LBLᵀ
    // on the crack unknowns and multipliers) gives the LDLᵀ solution to 1e-9 relative, on
    // a small grid (one half) and on a large one (above SPLIT_MIN_UNKNOWNS: two halves in
    // parallel), for two sets of contact statuses on the same bulk, and after a change of
    // the bulk values without `set_bulk` (the bulk stage is then redone).
    #[test]
    fn condensed_contact_factor_matches_ldlt() {
        for (nx, ny) in [(40, 30), (120, 90)] {
            let (p, bulk, full_a, point_of_eq, coords, np) = contact_grid(nx, ny, 10.0, |k| k % 3 != 0);
            let (_, _, full_b, _, _, _) = contact_grid(nx, ny, 10.0, |k| k % 2 == 0);
            let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
            let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
            assert!(cond.is_condensed(), "{nx}×{ny}");
            if p.n >= SPLIT_MIN_UNKNOWNS {
                let Factor::Condensed(c) = &cond.factor else { unreachable!() };
                assert_eq!(c.halves(), 2);
            }
            let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
            assert!(!ldlt.is_condensed());
            cond.set_bulk(&bulk).unwrap();
            let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let mut shifted = full_b.clone();
            shifted[p.position(5, 5).unwrap()] += 0.5;
            for (label, vals) in [("a", &full_a), ("b", &full_b), ("bulk changed", &shifted)] {
                cond.factorize(vals).unwrap();
                ldlt.factorize(vals).unwrap();
                let xc = solve(&cond, &b).unwrap();
                let xl = solve(&ldlt, &b).unwrap();
                assert!(rel_residual(&p, vals, &xc, &b) < 1e-10, "{nx}×{ny} {label}");
                let (dmax, xmax) =
                    xc.iter().zip(&xl).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
                assert!(dmax < 1e-9 * xmax, "{nx}×{ny} {label}: condensed and LDLT differ by {dmax:e} (max {xmax:e})");
            }
            // Newton with deferred interior corrections: a full solve with the statuses
            // of `a`, then the statuses of `b`, residuals computed with the stale
            // interior; once applied, the result solves system `b`.
            cond.factorize(&full_a).unwrap();
            let mut x = solve(&cond, &b).unwrap();
            cond.factorize(&full_b).unwrap();
            for _ in 0..3 {
                let mut ax = vec![0.0; p.n];
                p.mul_vec(&full_b, &x, &mut ax);
                let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
                cond.solve_in_place_deferred(&mut r).unwrap();
                for (xi, d) in x.iter_mut().zip(&r) {
                    *xi += d;
                }
            }
            cond.apply_deferred(&mut x);
            let res = rel_residual(&p, &full_b, &x, &b);
            assert!(res < 1e-10, "{nx}×{ny}: deferred Newton residual {res:e}");
        }
    }

    // A bulk that is not positive definite on its own: the grid above the "crack" row is
    // not connected to the grid below and has no shift (the constants of each component
    // are free), and only the multipliers tie the two rows together (both components). The
    // condensed factor detects the non-positive bulk and falls back to the plain LDLᵀ,
    // whose regularisation covers a K positive definite on the kernel of B: same solution.
    #[test]
    fn condensed_factor_falls_back_when_the_bulk_floats() {
        let (nx, ny) = (40, 70);
        let yc = ny / 2;
        let node = |x: usize, y: usize| y * nx + x;
        let np = 2 * nx * ny;
        let mut t = quad_triplets(nx, ny, |y| match y.cmp(&yc) {
            std::cmp::Ordering::Less => Some(0.01),
            std::cmp::Ordering::Equal => None,
            std::cmp::Ordering::Greater => Some(0.0),
        });
        let mut m = np;
        for x in 0..nx {
            for c in 0..2 {
                let (lo, hi) = (2 * node(x, yc) + c, 2 * node(x, yc + 1) + c);
                t.extend([(m, hi, 1.0), (hi, m, 1.0), (m, lo, -1.0), (lo, m, -1.0)]);
                m += 1;
            }
        }
        let (p, v) = matrix(m, &t);
        let mut point_of_eq: Vec<u32> = (0..np).map(|i| (i / 2) as u32).collect();
        point_of_eq.resize(m, crate::solve::ordering::NO_POINT);
        let coords: Vec<[f64; 3]> = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
        assert!(cond.is_condensed());
        let mut bulk = v.clone();
        for j in np..m {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                bulk[k] = 0.0;
                let i = p.row_idx[k];
                bulk[p.position(j, i).unwrap()] = 0.0;
            }
        }
        cond.set_bulk(&bulk).unwrap();
        assert!(!cond.is_condensed(), "a floating bulk must fall back to the plain LDLT");
        cond.factorize(&v).unwrap();
        let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
        ldlt.factorize(&v).unwrap();
        let b: Vec<f64> = (0..m).map(|i| if i < np { ((i * 7919) % 13) as f64 - 6.0 } else { 0.0 }).collect();
        let (xc, xl) = (solve(&cond, &b).unwrap(), solve(&ldlt, &b).unwrap());
        assert!(rel_residual(&p, &v, &xc, &b) < 1e-10);
        let d = xc.iter().zip(&xl).fold(0.0f64, |d, (a, c)| d.max((a - c).abs()));
        let xmax = xl.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        assert!(d < 1e-8 * xmax, "fallback and LDLT differ by {d:e}");
    }

    #[test]
    fn split_cholesky_of_a_large_2d_system_matches_the_unsplit_one() {
        // 2 × 120 × 90 = 21 600 unknowns: above SPLIT_MIN_UNKNOWNS.
        let (nx, ny) = (120, 90);
        let (p, v, point_of_eq, coords) = quad_grid(nx, ny);
        assert!(p.n >= SPLIT_MIN_UNKNOWNS);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let mut split = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
        assert!(matches!(split.factor, Factor::Split(_)));
        let mut plain = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
        split.factorize(&v).unwrap();
        plain.factorize(&v).unwrap();
        let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let xs = solve(&split, &b).unwrap();
        let xp = solve(&plain, &b).unwrap();
        assert!(rel_residual(&p, &v, &xs, &b) < 1e-12);
        let (dmax, xmax) =
            xs.iter().zip(&xp).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
        assert!(dmax < 1e-9 * xmax, "split and unsplit solutions differ by {dmax:e} (max |x| {xmax:e})");
        // The factor's size is reported (halves plus the dense separator).
        let nnz = split.stats().nnz_factor.unwrap();
        assert!(nnz > p.n && nnz < 2 * plain.stats().nnz_factor.unwrap());
        // A singular matrix (graph Laplacian) is reported, not solved.
        let (p, v, _, _) = quad_grid_shifted(nx, ny, 0.0);
        let mut s = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
        let e = s.factorize(&v).unwrap_err();
        assert!(matches!(e, LinearError::NotPositiveDefinite { .. }), "{e}");
    }

    #[test]
    fn ldlt_with_points_keeps_multipliers_after_their_unknowns() {
        let nx = 16;
        let fixed: Vec<(usize, f64)> = (0..nx).map(|i| (i * nx, 1.0)).collect();
        let (p, v, b, np) = saddle(nx, true, &fixed, Some((5, 100)), 0.0, false);
        let (mut point_of_eq, coords) = grid_points(nx, nx);
        point_of_eq.resize(p.n, crate::solve::ordering::NO_POINT);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let (fwd, inv) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, Some(&points)).unwrap();
        assert_eq!(fwd.len(), p.n);
        for m in np..p.n {
            for &i in &p.row_idx[p.col_ptr[m]..p.col_ptr[m + 1]] {
                if i < np {
                    assert!(inv[i] < inv[m], "multiplier {m} ordered before its unknown {i}");
                }
            }
        }
        let mut s = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
        s.factorize(&v).unwrap();
        let x = solve(&s, &b).unwrap();
        assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
    }

    // K singular but SPD on the kernel of B (pure Neumann Laplacian + one fixed unknown,
    // plus or minus a tie): Ldlt and Lu reach ‖Ax − b‖/‖b‖ < 1e-10 and honour the fixed
    // value to 1e-9. When the fixed unknown is the last primal one in the AMD order, the
    // LDLᵀ meets the zero pivot of K before the constraint: it must regularise it and
    // recover by iterative refinement.
    #[test]
    fn saddle_point_with_singular_k() {
        let nx = 20;
        let (p, _, _, np) = saddle(nx, false, &[(0, 1.0)], None, 0.0, false);
        let (fwd, _) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, None).unwrap();
        let amd_last = *fwd.iter().rev().find(|&&i| i < np).unwrap();
        for fixed in [0, 7, nx * nx / 2 + 3, nx * nx - 1, amd_last] {
            for tie in [None, Some((1, nx * nx - 2))] {
                let (p, v, b, np) = saddle(nx, false, &[(fixed, 1.0)], tie, 0.0, false);
                for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
                    let mut s = LinearSolver::analyse(method, &p, np).unwrap();
                    s.factorize(&v).unwrap();
                    if method == LinearMethod::Ldlt && fixed == amd_last && tie.is_none() {
                        assert!(s.regularised_pivots() > 0);
                    }
                    let x = solve(&s, &b).unwrap();
                    let r = rel_residual(&p, &v, &x, &b);
                    assert!(r < 1e-10, "{method} fixed {fixed} tie {tie:?}: residual {r:e}");
                    assert!((x[fixed] - 1.0).abs() < 1e-9);
                    eprintln!(
                        "{method} fixed {fixed} tie {tie:?}: {} regularised, residual {r:.1e} after {} refinements",
                        s.regularised_pivots(),
                        s.last_residual().1
                    );
                }
            }
        }
    }

    // Quasi-definite [K Bᵀ; B −C] with C = 1e-3 I (stabilised multipliers): Ldlt to 1e-10.
    #[test]
    fn quasi_definite_ldlt() {
        let (p, v, b, np) = saddle(25, true, &[(3, 1.0), (40, 2.0), (600, -1.0)], Some((10, 11)), 1e-3, false);
        let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, np).unwrap();
        s.factorize(&v).unwrap();
        let x = solve(&s, &b).unwrap();
        assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
    }

    // Singular "SPD-looking" matrix (pure Neumann Laplacian, kernel = constants):
    // Cholesky reports NotPositiveDefinite (50×50 simplicial and 200×200 supernodal),
    // never a NaN or a silent garbage solution; Ldlt (which regularises the one zero
    // pivot, on both faer paths) and Lu, which cannot tell the matrix is singular at
    // factorisation, fail at solve time with a clear error.
    #[test]
    fn singular_neumann_laplacian_is_reported() {
        for nx in [50, 200] {
            let (p, v) = matrix(nx * nx, &laplacian_triplets(nx, nx, false));
            let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
            let e = s.factorize(&v).unwrap_err();
            assert!(matches!(e, LinearError::NotPositiveDefinite { .. }), "{e}");
            assert!(e.to_string().contains("not positive definite"));
            let b = rhs(p.n);
            for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
                let mut s = LinearSolver::analyse(method, &p, p.n).unwrap();
                let result = s.factorize(&v).and_then(|_| solve(&s, &b).map(|_| ()));
                if method == LinearMethod::Ldlt {
                    assert_eq!(supernodal(&s), nx == 200);
                    assert_eq!(s.regularised_pivots(), 1, "the zero pivot of the constants is regularised");
                }
                let e = result.unwrap_err();
                assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{method}: {e}");
            }
        }
    }

    // Redundant constraints (the same unknown fixed twice: B rank deficient) with Ldlt
    // and Lu: conflicting values give a clear error; consistent values either a clear
    // error or a solution with ‖Ax − b‖/‖b‖ < 1e-10 (the multipliers then share the
    // reaction arbitrarily); never NaN.
    #[test]
    fn redundant_constraints_are_reported() {
        for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
            let (p, v, b, np) = saddle(10, true, &[(5, 1.0), (5, 2.0)], None, 0.0, false);
            let mut s = LinearSolver::analyse(method, &p, np).unwrap();
            let e = s.factorize(&v).and_then(|_| solve(&s, &b).map(|_| ())).unwrap_err();
            assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{e}");
            let (p, v, b, np) = saddle(10, true, &[(5, 1.0), (5, 1.0)], None, 0.0, false);
            let mut s = LinearSolver::analyse(method, &p, np).unwrap();
            match s.factorize(&v).and_then(|_| solve(&s, &b)) {
                Ok(x) => assert!(rel_residual(&p, &v, &x, &b) < 1e-10),
                Err(e) => assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{e}"),
            }
        }
    }

    // Tiny systems: 1 unknown solves exactly with every method (x = b/a to 1e-15);
    // a 1-unknown zero matrix and an empty system error or work cleanly.
    #[test]
    fn one_unknown_and_empty_system() {
        let (p, v) = matrix(1, &[(0, 0, 4.0)]);
        for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
            let mut s = LinearSolver::analyse(method, &p, 1).unwrap();
            s.factorize(&v).unwrap();
            let x = solve(&s, &[2.0]).unwrap();
            assert!((x[0] - 0.5).abs() < 1e-15);
            assert_eq!(solve(&s, &[0.0]).unwrap(), vec![0.0]);
            let e = s.factorize(&[0.0]).unwrap_err();
            assert!(matches!(e, LinearError::EmptyRow { unknown: 0 }), "{e}");
        }
        let empty = CscPattern { n: 0, col_ptr: vec![0], row_idx: vec![] };
        for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
            let mut s = LinearSolver::analyse(method, &empty, 0).unwrap();
            s.factorize(&[]).unwrap();
            let mut x: Vec<f64> = vec![];
            s.solve_in_place(&mut x).unwrap();
            assert_eq!(s.stats().nnz_factor.unwrap_or(0), 0);
        }
    }

    // Bad input is refused with the matching error: NaN/inf values, wrong lengths,
    // non-finite right-hand side, malformed or unsymmetric patterns, n_primal > n.
    #[test]
    fn bad_input_is_refused() {
        let (p, v) = matrix(9, &laplacian_triplets(3, 3, true));
        let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, 9).unwrap();
        let mut bad = v.clone();
        let k = p.position(4, 1).unwrap();
        bad[k] = f64::NAN;
        assert!(matches!(s.factorize(&bad), Err(LinearError::NonFiniteMatrix { row: 4, col: 1, .. })));
        bad[k] = f64::INFINITY;
        assert!(matches!(s.factorize(&bad), Err(LinearError::NonFiniteMatrix { .. })));
        assert!(matches!(s.factorize(&v[1..]), Err(LinearError::LengthMismatch { .. })));
        s.factorize(&v).unwrap();
        assert!(matches!(solve(&s, &[1.0; 8]), Err(LinearError::LengthMismatch { .. })));
        let mut b = vec![1.0; 9];
        b[2] = f64::NAN;
        assert!(matches!(solve(&s, &b), Err(LinearError::NonFiniteRhs { index: 2, .. })));
        let unsymmetric = CscPattern::from_entries(2, &[(0, 0), (1, 1), (1, 0)]);
        assert!(matches!(
            LinearSolver::analyse(LinearMethod::Ldlt, &unsymmetric, 2),
            Err(LinearError::InvalidPattern(_))
        ));
        let unsorted = CscPattern { n: 2, col_ptr: vec![0, 2, 3], row_idx: vec![1, 0, 1] };
        assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &unsorted, 2), Err(LinearError::InvalidPattern(_))));
        let short = CscPattern { n: 2, col_ptr: vec![0, 1], row_idx: vec![0] };
        assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &short, 2), Err(LinearError::InvalidPattern(_))));
        assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &p, 10), Err(LinearError::InvalidPrimalCount { .. })));
        // Negative diagonal with Cholesky.
        let (p, v) = matrix(2, &[(0, 0, 1.0), (1, 1, -1.0)]);
        let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, 2).unwrap();
        assert!(matches!(s.factorize(&v), Err(LinearError::NotPositiveDefinite { unknown: 1, .. })));
    }

    // Badly scaled saddle point (K ~ 2e11 like steel in Pa, B ~ 1): Ldlt to 1e-10
    // without regularisation, thanks to the symmetric scaling.
    #[test]
    fn badly_scaled_saddle_point() {
        let (p, mut v, mut b, np) = saddle(20, true, &[(0, 1.0), (210, 2.0)], Some((30, 31)), 0.0, false);
        for j in 0..np {
            let col = p.col_ptr[j]..p.col_ptr[j + 1];
            for (x, &i) in v[col.clone()].iter_mut().zip(&p.row_idx[col]) {
                if i < np {
                    *x *= 2e11;
                }
            }
        }
        b[..np].iter_mut().for_each(|x| *x *= 2e11);
        let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, np).unwrap();
        s.factorize(&v).unwrap();
        assert_eq!(s.regularised_pivots(), 0);
        let x = solve(&s, &b).unwrap();
        assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
    }

    // Several threads solving with one factor at once get the same answers (1e-14).
    #[test]
    fn concurrent_solves() {
        let (p, v) = matrix(900, &laplacian_triplets(30, 30, true));
        let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, 900).unwrap();
        s.factorize(&v).unwrap();
        let b = rhs(900);
        let x0 = solve(&s, &b).unwrap();
        std::thread::scope(|scope| {
            for _ in 0..4 {
                scope.spawn(|| {
                    for _ in 0..5 {
                        let x = solve(&s, &b).unwrap();
                        assert!(x.iter().zip(&x0).all(|(a, b)| (a - b).abs() < 1e-14));
                    }
                });
            }
        });
    }
}
