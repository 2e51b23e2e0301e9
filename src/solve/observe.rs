//! Hooks through which a caller watches a solve: the phase being worked on (for progress
//! displays) and every Newton iteration of the contact loops (for `--verbose` logs and
//! convergence plots). The solver calls them and never prints these itself.
//!
//! Entry point: [`SolveObserver`] (every method has a do-nothing default); [`Silent`]
//! watches nothing.

/// What the solver is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// Building the sparsity pattern (once, and again after a pairing change).
    Pattern { equations: usize },
    /// Ordering and symbolic factorisation of the matrix.
    Symbolic { equations: usize, nnz_matrix: usize },
    /// Numeric factorisation; `nnz_factor` is the predicted size of the factor when the
    /// solver knows it.
    Factorisation { step: usize, nnz_factor: Option<usize> },
    /// A load step starts (1-based `index` of `total`).
    Step { index: usize, total: usize },
    /// The contact loops of a step start (pass `geometry` of the geometry loop).
    ContactLoops { step: usize, geometry: usize },
    /// Pairing of the large-sliding contact points.
    Pairing { step: usize },
}

/// One Newton iteration of the contact loops of a step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NewtonIteration {
    pub step: usize,
    /// Friction fixed-point pass (1-based; 1 for the semi-smooth Newton).
    pub friction: usize,
    /// Active-set iteration of the step (1-based, counted over the friction passes).
    pub active_set: usize,
    /// Newton iteration of the step (1-based, counted over all loops).
    pub newton: usize,
    /// Status counts the iteration's tangent was built with.
    pub open: usize,
    pub stick: usize,
    pub slip: usize,
    /// Points whose status differs from the previous iteration's (all points on the
    /// first iteration of a step).
    pub changed: usize,
    /// Relative size of the correction, max |δx| / max |x|.
    pub correction: f64,
    /// The matrix was factorised for this iteration (else the previous factor was reused).
    pub factorised: bool,
}

/// Watches a solve. Called from the solving thread; implementations must be cheap.
pub trait SolveObserver: Sync {
    /// A phase starts.
    fn phase(&self, _phase: Phase) {}
    /// A Newton iteration of the contact loops ended.
    fn newton(&self, _iteration: &NewtonIteration) {}
    /// The system's figures (unknowns, matrix, backend; no steps): once the system is set
    /// up, and again when a step fails, so that a failed run can report them.
    fn system(&self, _sizes: &super::report::SolveReport) {}
}

/// The observer that watches nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl SolveObserver for Silent {}
