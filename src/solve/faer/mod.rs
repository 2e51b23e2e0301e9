//! The faer backend of the [`LinearBackend`](super::backend::LinearBackend) seam: sparse
//! direct solvers on faer, split into a symbolic phase (done once per sparsity pattern)
//! and a numeric phase (done for every new set of values).
//!
//! Entry point: [`FaerSolver`] (re-exported as [`super::linear::LinearSolver`]). One file
//! per piece, as faer keeps one file per factorisation:
//!
//! - `solver.rs`: the solver, its choice of factor and its entry points;
//! - `cholesky.rs`: the whole-system Cholesky / LDLᵀ (symbolic phase, pivots, flops);
//! - `split.rs`: the Cholesky split at the top separator into two halves in parallel;
//! - `condensed.rs`: the contact factor condensed onto the crack unknowns;
//! - `dense_block.rs`: its dense crack block, factorised, or solved by GMRES preconditioned
//!   by its previous factor when few rows changed;
//! - `interior.rs`: the exact interior response of a condensed factor whose bulk stage is
//!   in single precision (conjugate gradients preconditioned by its halves);
//! - `free.rs`: the multipliers it condenses out of that block (no primal coupling: the
//!   open law's rows of a contact zone's dormant nodes), by a sparse Cholesky factor;
//! - `kept.rs`: the whole-system factor of a contact system too large to condense, kept
//!   across contact iterations (GMRES preconditioned by it while few columns changed);
//! - `scaling.rs`: the symmetric scaling `S A S`;
//! - `mixed.rs`: the Cholesky factor in single precision, its solves refined to double
//!   precision by preconditioned conjugate gradients, and its fallback;
//! - `refine.rs`: iterative refinement, conjugate gradients and the residual check;
//! - `memory.rs`: fallible allocation of the factor's buffers.
//!
//! The orderings are in [`crate::solve::ordering`]. The factorisations:
//!
//! - [`Cholesky`](crate::solve::backend::LinearMethod::Cholesky): faer's sparse `LLᵀ` for
//!   symmetric positive definite matrices. Non-positive and tiny pivots (relative to the
//!   diagonal) are reported as [`LinearError::NotPositiveDefinite`] instead of producing
//!   garbage.
//! - [`Ldlt`](crate::solve::backend::LinearMethod::Ldlt): faer's sparse `LDLᵀ` without
//!   pivoting for symmetric quasi-definite and saddle-point matrices `[K Bᵀ; B −C]`, whose
//!   last `n − n_primal` unknowns are multipliers. The primal block is ordered as for
//!   Cholesky (see "Orderings" below), with every multiplier placed right after the last
//!   primal unknown it couples to (so the zero diagonal block never gives a zero pivot
//!   when `K` is positive definite), and a sign-aware dynamic regularisation (primal
//!   pivots `> 0`, multiplier pivots `< 0`) covers `K` that is only positive definite on
//!   the kernel of `B`; iterative refinement then restores full accuracy.
//! - [`Lu`](crate::solve::backend::LinearMethod::Lu): faer's sparse LU with partial
//!   pivoting (COLAMD ordering), the general fallback (e.g. unsymmetric friction
//!   tangents); several times the time and memory of Cholesky (6–10× in 2D at 5e5
//!   unknowns, `examples/linear_solver_timing.rs`).
//!
//! Orderings ([`FaerSolver::analyse_with_points`] passes the node of every unknown):
//! geometric nested dissection on 2D meshes, AMD on the full graph on 3D meshes,
//! supervariable-compressed AMD when no positions are given
//! ([`crate::solve::ordering::primal_ordering`]). Large 2D Cholesky systems are factorised
//! as the two halves of the top separator in parallel (`split.rs`); otherwise faer's dense
//! kernels run in parallel only for large fronts.
//!
//! Contact systems ([`FaerSolver::analyse_condensed`]) change only in the rows and
//! columns of the crack unknowns and multipliers between factorisations: the bulk is then
//! factorised once and each factorisation is a dense `LBLᵀ` of the crack system
//! (`condensed.rs`), with Newton corrections that defer the interior
//! ([`FaerSolver::solve_in_place_deferred`]).
//!
//! Precision ([`crate::solve::backend::Precision`]): a whole-system Cholesky factor may be
//! computed in single precision (`mixed.rs`; by default when `L` has at least
//! [`MIXED_AUTO_MIN_NNZ`] entries), every solve then reaching the double-precision
//! residual by conjugate gradients preconditioned by it, with a fallback to the
//! double-precision factor; all other factors are in double precision.
//!
//! Every method factorises the symmetrically scaled matrix `S A S` (`scaling.rs`), which
//! makes the pivot thresholds relative and independent of units. Cholesky and LDLᵀ read
//! only the lower triangle of the values; the residual check uses the full matrix.

mod cholesky;
mod condensed;
mod dense_block;
mod free;
mod interior;
mod kept;
mod memory;
mod mixed;
mod refine;
mod scaling;
mod solver;
mod split;
#[cfg(test)]
mod tests;

use super::backend::LinearError;
use faer::sparse::FaerError;

pub use condensed::{CONDENSED_COST_RATIO, CONDENSED_MIN_RATIO, CONDENSED_SMALL_FLOPS};
pub use mixed::MIXED_AUTO_MIN_NNZ;
pub use solver::FaerSolver;

impl From<FaerError> for LinearError {
    fn from(e: FaerError) -> Self {
        match e {
            FaerError::OutOfMemory => LinearError::OutOfMemory,
            other => LinearError::Internal(format!("{other:?}")),
        }
    }
}
