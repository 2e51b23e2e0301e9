//! The faer direct solver: one sparse factorisation behind the [`LinearBackend`] seam,
//! chosen among the whole-system Cholesky / LDLᵀ ([`super::cholesky`]), faer's LU, the
//! Cholesky split at the top separator ([`super::split`]) and the condensed contact
//! factor ([`super::condensed`]).
//!
//! Entry point: [`FaerSolver`]. [`FaerSolver::analyse`] validates a [`CscPattern`],
//! computes the fill-reducing ordering and the symbolic factorisation (and reserves the
//! scratch memory); [`FaerSolver::factorize`] computes the numeric factor for a value
//! array on that pattern and may be called again and again (Newton / active-set loops)
//! without redoing the symbolic work; [`FaerSolver::solve_in_place`] solves with the
//! current factor, checks the residual and refines it iteratively when that helps
//! ([`super::refine`]). A contact system on the whole-system factor (too large to condense)
//! keeps its factor across contact iterations ([`super::kept`]): a new matrix that differs
//! in few contact columns is solved by GMRES preconditioned by the old factor.

use super::cholesky::{
    factor_flops, for_each_pivot, numeric_llt, pivot_threshold, symbolic_cholesky, symbolic_cholesky_ordered,
    SymbolicAnalysis, LDLT_DELTA,
};
use super::condensed::{condensed_error, condensed_factor, Condensation, CondensedError, CondensedFactor};
use super::kept::{
    iterations_per_factorisation, iterations_per_single_factorisation, process_cpu_seconds, Decision, KeptFactor,
};

/// The shift of the crack block of a condensed factor whose bulk is not positive definite
/// (scaled units: the scaled diagonal of a primal unknown is 1).
const CRACK_SHIFT: f64 = 1.0;
use super::memory::{check_factor_memory, try_zeroed_vec};
use super::mixed::{mixed_wanted, MixedCholesky, MIXED_MAX_ITERATIONS};
use super::refine::{
    refinement_plan, solve_gmres, solve_pcg, solve_refined, SolveWorkspace, ETA_TARGET_CHOLESKY, ETA_TARGET_PIVOTING,
    MAX_RELATIVE_RESIDUAL,
};
use super::scaling::{compute_scaling, fill_scaled, row_sum_norm, ScaledSystem, Structure};
use super::split::{split_candidate, SplitCholesky, SplitError, SPLIT_MAX_SEPARATOR};
use crate::assembly::CscPattern;
use crate::solve::backend::{
    EquationPoints, LinearBackend, LinearError, LinearMethod, LinearStats, OrderingChoice, Precision, SystemStructure,
};
use crate::solve::ordering::dissection_split;
use crate::solve::ordering::Order;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::sparse::linalg::cholesky::{LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};
use rayon::prelude::*;
use std::fmt;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, RwLock, TryLockError};
use std::time::Instant;

/// The factor behind a [`FaerSolver`].
pub(super) enum Factor {
    /// n == 0: nothing to factorise.
    Empty,
    /// Cholesky `LLᵀ` or LDLᵀ (same symbolic structure).
    /// (The values behind a lock: a kept factor refactorises inside a solve, `kept.rs`.)
    Cholesky {
        symbolic: SymbolicCholesky<usize>,
        l_values: RwLock<Vec<f64>>,
    },
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: RwLock<NumericLu<usize, f64>>,
    },
    /// Cholesky split at the top separator (large 2D systems), halves in parallel.
    Split(Box<SplitCholesky>),
    /// Contact systems: the bulk factorised once, a dense factor on the crack unknowns.
    Condensed(Box<CondensedFactor>),
    /// Cholesky `LLᵀ` in single precision, solves refined to double precision
    /// (`mixed.rs`).
    Mixed(Box<MixedCholesky>),
}

/// The whole-system Cholesky / LDLᵀ of a symbolic analysis as a [`Factor`], with the
/// scratch sizes of the numeric phase and of a solve, and the entries of `L`.
fn whole(sa: SymbolicAnalysis) -> (Factor, StackReq, StackReq, Option<usize>) {
    let SymbolicAnalysis { symbolic, l_values, factor_req, solve_req, nnz } = sa;
    (Factor::Cholesky { symbolic, l_values: RwLock::new(l_values) }, factor_req, solve_req, Some(nnz))
}

/// A sparse direct solver: [`analyse`](Self::analyse) once per pattern,
/// [`factorize`](Self::factorize) for each new set of values,
/// [`solve_in_place`](Self::solve_in_place) for each right-hand side.
pub struct FaerSolver {
    method: LinearMethod,
    n: usize,
    n_primal: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position of each diagonal entry in the value array, if stored.
    diag_pos: Vec<Option<usize>>,
    pub(super) factor: Factor,
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
    factor_mem: Mutex<MemBuffer>,
    /// Bytes of `factor_mem` (the numeric phase's scratch).
    factor_scratch_bytes: usize,
    solve_req: StackReq,
    workspace: Mutex<SolveWorkspace>,
    par: Par,
    factorized: bool,
    /// The primal scaling was fixed by [`FaerSolver::set_bulk`] (condensed factor: the
    /// scaled bulk must not change between contact iterations).
    primal_scale_fixed: bool,
    regularised: AtomicUsize,
    /// A contact system on the whole-system factor: the factor kept across contact
    /// iterations (`kept.rs`).
    pub(super) kept: Option<KeptFactor>,
    nnz_factor: Option<usize>,
    /// The ordering asked for at the analysis (also used if the condensed factor falls
    /// back to the plain LDLᵀ).
    ordering: OrderingChoice,
    /// The memory limit given at the analysis (`None`: the machine's).
    memory_limit: Option<u64>,
    /// Mixed precision: why the factor fell back to double precision in a factorisation.
    fallback: Option<&'static str>,
    symbolic_s: f64,
    numeric_s: f64,
    solve_s: AtomicU64,
    last_residual: AtomicU64,
    last_refinements: AtomicUsize,
    /// Condensed factor: crack corrections of deferred solves not yet propagated to the
    /// interior (scaled units; see [`FaerSolver::solve_in_place_deferred`]).
    pending: Mutex<Vec<f64>>,
    /// Condensed factor: bulk stages attempted (a floating bulk's failed one included).
    bulk_attempts: usize,
}

impl fmt::Debug for FaerSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FaerSolver")
            .field("method", &self.method)
            .field("n", &self.n)
            .field("n_primal", &self.n_primal)
            .field("factorized", &self.factorized)
            .field("regularised_pivots", &self.regularised_pivots())
            .field("stats", &self.stats())
            .finish()
    }
}

impl FaerSolver {
    /// Symbolic phase, once per pattern. Unknowns `n_primal..n` are multipliers (ordered
    /// after the primal unknowns they couple to for Ldlt; not allowed for Cholesky).
    pub fn analyse(method: LinearMethod, pattern: &CscPattern, n_primal: usize) -> Result<Self, LinearError> {
        Self::analyse_with_points(method, pattern, n_primal, None)
    }

    /// Like [`Self::analyse`], with the positions of the primal unknowns (their mesh
    /// nodes) for Cholesky and LDLᵀ: the primal unknowns are then ordered by nested
    /// dissection (geometric in 2D, METIS on the node graph in 3D:
    /// [`crate::solve::ordering::primal_ordering`]) instead of minimum degree.
    pub fn analyse_with_points(
        method: LinearMethod,
        pattern: &CscPattern,
        n_primal: usize,
        points: Option<&EquationPoints<'_>>,
    ) -> Result<Self, LinearError> {
        Self::analyse_system(&SystemStructure {
            method,
            pattern,
            n_primal,
            points,
            condense: None,
            ordering: OrderingChoice::Auto,
            memory_limit: None,
            reuse: None,
            precision: Precision::Double,
        })
    }

    /// Like [`Self::analyse_with_points`] for LDLᵀ systems whose matrix changes between
    /// factorisations only in the rows and columns of the multipliers and of the primal
    /// unknowns coupled to them (contact: the dofs of the contact elements). The factor is
    /// then condensed onto those unknowns (`condensed.rs`): the bulk is factorised once
    /// (for the values given to [`Self::set_bulk`]), and each [`Self::factorize`] only
    /// factorises a dense matrix of their size. Falls back to the plain LDLᵀ when the dense
    /// factor does not pay against the whole system's ([`CONDENSED_COST_RATIO`](super::CONDENSED_COST_RATIO))
    /// or the method is not LDLᵀ.
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
        Self::analyse_system(&SystemStructure {
            method,
            pattern,
            n_primal,
            points,
            condense: Some(varying),
            ordering: OrderingChoice::Auto,
            memory_limit: None,
            reuse: None,
            precision: Precision::Double,
        })
    }

    /// Whether the factor is condensed onto the crack unknowns (see
    /// [`Self::analyse_condensed`]).
    pub fn is_condensed(&self) -> bool {
        matches!(self.factor, Factor::Condensed(_))
    }

    /// Whether this is a contact system's whole-system factor that later contact iterations
    /// may keep (`super::kept`: worth keeping by its predicted cost, whatever the switch).
    pub fn keeps_factor(&self) -> bool {
        self.kept.as_ref().is_some_and(|k| k.may_keep())
    }

    /// The symbolic phase for a [`SystemStructure`] (any ordering, an injected memory
    /// limit): what [`Self::analyse`], [`Self::analyse_with_points`] and
    /// [`Self::analyse_condensed`] call with the automatic ordering and the machine's memory.
    /// Fails with [`LinearError::FactorTooLarge`] when the factor predicted by the symbolic
    /// phase does not fit in the memory available.
    pub fn analyse_system(system: &SystemStructure<'_>) -> Result<Self, LinearError> {
        let &SystemStructure { method, pattern, n_primal, points, condense, ordering, memory_limit, reuse, precision } =
            system;
        let order = Order { points, choice: ordering, reuse };
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

        let (mut factor, factor_req, solve_req, nnz_factor) = if n == 0 {
            (Factor::Empty, StackReq::EMPTY, StackReq::EMPTY, Some(0))
        } else {
            let a = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            // Without multipliers a condensed factor needs the unknowns that change.
            let condensable = condense.is_some() && (n_primal < n || condense.flatten().is_some());
            let condensation = match method {
                LinearMethod::Ldlt | LinearMethod::Cholesky if condensable => {
                    condensed_factor(&col_ptr, &row_idx, n, n_primal, order, condense.flatten())?
                }
                _ => Condensation::Plain(None),
            };
            let (condensed, whole_order) = match condensation {
                Condensation::Condensed(c) => (Some(c), None),
                Condensation::Plain(o) => (None, o),
            };
            match method {
                _ if condensed.is_some() => {
                    let c = condensed.expect("checked");
                    let nnz = c.nnz_factor();
                    (Factor::Condensed(c), StackReq::EMPTY, StackReq::EMPTY, Some(nnz))
                }
                LinearMethod::Cholesky if split_candidate(n, order) => {
                    let p = order.points.expect("split candidates have points");
                    match dissection_split(&col_ptr, &row_idx, n, p, order) {
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
                                None => whole(symbolic_cholesky(
                                    method, a, &col_ptr, &row_idx, n, n_primal, order, &mut par,
                                )?),
                            }
                        }
                        _ => whole(symbolic_cholesky(method, a, &col_ptr, &row_idx, n, n_primal, order, &mut par)?),
                    }
                }
                LinearMethod::Cholesky | LinearMethod::Ldlt => whole(match &whole_order {
                    // The ordering the condensation's decision computed.
                    Some(o) => symbolic_cholesky_ordered(method, a, o, order, &mut par)?,
                    None => symbolic_cholesky(method, a, &col_ptr, &row_idx, n, n_primal, order, &mut par)?,
                }),
                LinearMethod::Lu => {
                    par = Par::rayon(0);
                    let symbolic = factorize_symbolic_lu(a, LuSymbolicParams::default())?;
                    let factor_req = symbolic.factorize_numeric_lu_scratch::<f64>(par, Spec::default());
                    let solve_req = symbolic.solve_in_place_scratch::<f64>(1, par);
                    (Factor::Lu { symbolic, numeric: RwLock::new(NumericLu::new()) }, factor_req, solve_req, None)
                }
            }
        };
        // Mixed precision: the whole-system Cholesky or LDLᵀ factor in single precision
        // (`auto`: a large LDLᵀ only as a contact system's kept factor, `kept.rs`).
        let kept_ldlt = condense.is_some() && method == LinearMethod::Ldlt;
        let mixed = matches!(factor, Factor::Cholesky { .. })
            && mixed_wanted(precision, method, nnz_factor.unwrap_or(0), kept_ldlt);
        if mixed {
            if let Factor::Cholesky { symbolic, l_values } = factor {
                drop(l_values);
                let signs =
                    (method == LinearMethod::Ldlt).then(|| (0..n).map(|i| if i < n_primal { 1 } else { -1 }).collect());
                factor = Factor::Mixed(Box::new(MixedCholesky::new(symbolic, factor_req, signs)?));
            }
        }
        if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
            log_factor(&factor, method, n, nnz_factor);
        }
        let entry_bytes = if mixed { 4 } else { 8 };
        // The condensed factor's dense crack block beyond what nnz_factor counts (checked,
        // not allocated here).
        let dense_req = match &factor {
            Factor::Condensed(c) => StackReq::new::<u8>(c.dense_extra_bytes() as usize),
            _ => StackReq::EMPTY,
        };
        check_factor_memory(
            nnz_factor,
            entry_bytes,
            &[factor_req, solve_req, dense_req],
            pattern.nnz(),
            n,
            memory_limit,
        )?;
        let factor_mem = Mutex::new(MemBuffer::try_new(factor_req).map_err(|_| LinearError::OutOfMemory)?);
        let workspace = Mutex::new(SolveWorkspace::new(solve_req, n)?);
        // A contact system left on the whole-system factor: keep it across iterations, by
        // the iterations a factorisation is worth (predicted flops; none predicted for LU).
        let kept = match (&factor, condense) {
            (Factor::Cholesky { .. } | Factor::Lu { .. }, Some(varying)) => {
                let budget = match &factor {
                    Factor::Cholesky { symbolic, .. } => {
                        iterations_per_factorisation(factor_flops(symbolic), nnz_factor.unwrap_or(0), pattern.nnz())
                    }
                    _ => 0.0,
                };
                Some(KeptFactor::new(contact_unknowns(&col_ptr, &row_idx, n, n_primal, varying), budget))
            }
            // In single precision: every solve is GMRES preconditioned by it.
            (Factor::Mixed(m), Some(varying)) if m.is_ldlt() => {
                let budget = iterations_per_single_factorisation(
                    factor_flops(&m.symbolic),
                    nnz_factor.unwrap_or(0),
                    pattern.nnz(),
                );
                Some(KeptFactor::new_single(contact_unknowns(&col_ptr, &row_idx, n, n_primal, varying), budget))
            }
            _ => None,
        };
        let signs = if method == LinearMethod::Ldlt {
            (0..n).map(|i| if i < n_primal { 1 } else { -1 }).collect()
        } else {
            vec![]
        };
        Ok(FaerSolver {
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
            factor_scratch_bytes: factor_req.unaligned_bytes_required(),
            solve_req,
            workspace,
            par,
            factorized: false,
            primal_scale_fixed: false,
            regularised: AtomicUsize::new(0),
            kept,
            nnz_factor,
            ordering,
            memory_limit,
            fallback: None,
            symbolic_s: clock.elapsed().as_secs_f64(),
            numeric_s: 0.0,
            solve_s: AtomicU64::new(0f64.to_bits()),
            last_residual: AtomicU64::new(f64::NAN.to_bits()),
            last_refinements: AtomicUsize::new(0),
            pending: Mutex::new(vec![]),
            bulk_attempts: 0,
        })
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
        let log = std::env::var("FISSURE_CONTACT_LOG").is_ok();
        loop {
            self.bulk_attempts += 1;
            match c.set_bulk(&self.col_ptr, &self.row_idx, &self.scaled, values) {
                Ok(()) => return Ok(()),
                // The bulk alone is not positive definite: a body held only through contact.
                // Shift the crack block (exact: `CondensedFactor::shift_crack_block`) and
                // factorise again, once.
                Err(CondensedError::NonPositive { unknown }) if c.shift_crack_block(CRACK_SHIFT) => {
                    if log {
                        eprintln!(
                            "condensed: the bulk is not positive definite (unknown {unknown}: a body held only through contact?): crack block shifted by {CRACK_SHIFT}"
                        );
                    }
                }
                // Still not positive definite (a body free of contact too), or a multiplier
                // coupled to the interior: the plain LDLᵀ, whose regularisation covers that.
                Err(e @ (CondensedError::NonPositive { .. } | CondensedError::NotCondensable)) => {
                    if log {
                        eprintln!("condensed factor abandoned ({e:?}): plain LDLᵀ");
                    }
                    return self.fall_back_to_ldlt();
                }
                Err(e) => return Err(condensed_error(e, &self.diag_pos, values)),
            }
        }
    }

    /// A condensed factor for a system whose bulk may not hold every body by itself (a body
    /// pressed by a meshed contact pair): its crack block is shifted from the first bulk
    /// factorisation on (`CondensedFactor::shift_crack_block`, exact), instead of after
    /// a bulk factorisation that fails on the floating body and is done again. A no-op for
    /// the other factors.
    pub fn expect_floating_bulk(&mut self) {
        if let Factor::Condensed(c) = &mut self.factor {
            c.shift_crack_block(CRACK_SHIFT);
        }
    }

    /// The precision of a condensed factor's bulk stage (`condensed.rs`,
    /// `CondensedFactor::set_bulk_precision`): the next [`Self::set_bulk`] factorises it.
    #[cfg(test)]
    pub(crate) fn set_bulk_precision(&mut self, single: Option<bool>, fault: bool) {
        if let Factor::Condensed(c) = &mut self.factor {
            c.set_bulk_precision(single, fault);
            self.primal_scale_fixed = false;
        }
    }

    /// Whether a condensed factor's bulk stage is in single precision.
    #[cfg(test)]
    pub(crate) fn single_bulk(&self) -> bool {
        matches!(&self.factor, Factor::Condensed(c) if c.single_bulk())
    }

    /// Bulk stages of a condensed factor attempted so far (a failed one included).
    #[cfg(test)]
    pub(crate) fn bulk_attempts(&self) -> usize {
        self.bulk_attempts
    }

    /// Replaces a condensed factor by the plain LDLᵀ (minimum-degree ordering, multipliers
    /// after their unknowns), or the plain Cholesky for a system without multipliers.
    fn fall_back_to_ldlt(&mut self) -> Result<(), LinearError> {
        let n = self.n;
        let a = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let mut par = Par::Seq;
        let (factor, factor_req, solve_req, nnz) = whole(symbolic_cholesky(
            self.method,
            a,
            &self.col_ptr,
            &self.row_idx,
            n,
            self.n_primal,
            Order { points: None, choice: self.ordering, reuse: None },
            &mut par,
        )?);
        check_factor_memory(nnz, 8, &[factor_req, solve_req], self.row_idx.len(), n, self.memory_limit)?;
        self.factor = factor;
        self.factor_mem = Mutex::new(MemBuffer::try_new(factor_req).map_err(|_| LinearError::OutOfMemory)?);
        self.factor_scratch_bytes = factor_req.unaligned_bytes_required();
        self.workspace = Mutex::new(SolveWorkspace::new(solve_req, n)?);
        self.solve_req = solve_req;
        self.par = par;
        self.nnz_factor = nnz;
        self.primal_scale_fixed = false;
        self.factorized = false;
        Ok(())
    }

    /// Replaces a single-precision factor by the double-precision one (`reason`: why),
    /// keeping its values if a solve's fallback already computed them. The double factor
    /// must fit in the memory available (checked, as at the analysis).
    fn abandon_mixed(&mut self, reason: &'static str) -> Result<(), LinearError> {
        let Factor::Mixed(m) = &self.factor else { return Ok(()) };
        let fresh = if m.double().is_none() {
            let len = m.symbolic.len_val();
            if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                eprintln!("fissure: mixed precision to be abandoned ({reason}): {len} entries in double precision");
            }
            check_factor_memory(Some(len), 8, &[], 0, 0, self.memory_limit)?;
            // The run reports it as a warning (`linear_solver.precision_fallback`); the
            // developer's log shows it as it happens.
            if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                eprintln!("fissure: mixed precision abandoned ({reason}): the factor is computed in double precision");
            }
            Some(try_zeroed_vec::<f64>(len)?)
        } else {
            None
        };
        let Factor::Mixed(m) = std::mem::replace(&mut self.factor, Factor::Empty) else { unreachable!("checked") };
        let (symbolic, l_values, reason) = match fresh {
            Some(l) => (m.into_symbolic(), l, reason),
            None => m.into_double().expect("computed by a solve"),
        };
        self.fallback = Some(reason);
        if let Some(k) = &mut self.kept {
            // The double rule from now on (`kept.rs`).
            k.switch_to_double(iterations_per_factorisation(
                factor_flops(&symbolic),
                self.nnz_factor.unwrap_or(0),
                self.row_idx.len(),
            ));
        }
        self.factor = Factor::Cholesky { symbolic, l_values: RwLock::new(l_values) };
        Ok(())
    }

    /// Numeric phase for new values on the same pattern (reuses the symbolic factorisation
    /// and the scratch memory). On error the previous factor is no longer usable.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        let was_factorized = self.factorized;
        self.factorized = false;
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
        // A solve of the previous factorisation fell back to double precision: keep it
        // (before a kept factor's decision: a double factor computed by a solve is kept
        // as the plain double-precision factor).
        if let Factor::Mixed(m) = &self.factor {
            if let Some((_, reason)) = m.double() {
                self.abandon_mixed(reason)?;
            }
        }
        // A kept whole-system factor: new values in a few contact columns keep it (the
        // scaling stays the factor's), solved by GMRES preconditioned by it (`kept.rs`).
        if was_factorized && self.kept.is_some() {
            self.fill_scaled(values);
            let kept = self.kept.as_ref().expect("checked");
            if kept.decide(&self.col_ptr, &self.scaled) != Decision::Refactor {
                self.norm_inf = self.row_sum_norm(None);
                self.factorized = true;
                self.numeric_s = clock.elapsed().as_secs_f64();
                return Ok(());
            }
        }
        self.regularised.store(0, Ordering::Relaxed);
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

        if matches!(self.factor, Factor::Cholesky { .. } | Factor::Lu { .. }) {
            if let Some(k) = &mut self.kept {
                k.invalidate();
            }
            let numeric_clock = Instant::now();
            let cpu = process_cpu_seconds();
            self.numeric_whole()?;
            let seconds = numeric_clock.elapsed().as_secs_f64();
            if let Some(k) = &mut self.kept {
                k.factorised(&self.scaled);
                if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                    self.log_numeric(seconds, process_cpu_seconds() - cpu);
                }
            }
            self.factorized = true;
            self.numeric_s = clock.elapsed().as_secs_f64();
            return Ok(());
        }
        if let Factor::Mixed(m) = &self.factor {
            if let Some(k) = &mut self.kept {
                k.invalidate();
            }
            let log = std::env::var_os("FISSURE_CONTACT_LOG").is_some();
            let (numeric_clock, cpu) = (Instant::now(), process_cpu_seconds());
            let mem = self.factor_mem.get_mut().unwrap_or_else(|p| p.into_inner());
            match m.factorize(&self.col_ptr, &self.row_idx, &self.scaled, self.par, MemStack::new(mem)) {
                Ok(regularised) => {
                    self.regularised.store(regularised, Ordering::Relaxed);
                    if regularised > 0 && log {
                        eprintln!("  single-precision factor: {regularised} pivots regularised");
                    }
                    if let Some(k) = &mut self.kept {
                        k.factorised(&self.scaled);
                        if log {
                            let (wall, cpu) = (numeric_clock.elapsed().as_secs_f64(), process_cpu_seconds() - cpu);
                            let flops = factor_flops(&m.symbolic);
                            eprintln!(
                                "  kept factor: numeric factorisation in single precision {wall:.2} s wall, {cpu:.2} \
                                 s CPU: {:.2} GFlop/s wall, {:.2} GFlop per CPU-second",
                                flops / wall / 1e9,
                                flops / cpu / 1e9
                            );
                        }
                    }
                }
                Err(reason) => {
                    self.abandon_mixed(reason)?;
                    return self.factorize(values);
                }
            }
            self.factorized = true;
            self.numeric_s = clock.elapsed().as_secs_f64();
            return Ok(());
        }
        let n = self.n;
        match &mut self.factor {
            Factor::Empty => {}
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
            Factor::Condensed(c) => match c.factorize(&self.scaled, values, &self.scale) {
                Ok(()) => {}
                Err(
                    e @ (CondensedError::NonPositive { .. } | CondensedError::NotCondensable | CondensedError::Free(_)),
                ) => {
                    if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
                        eprintln!("condensed factor abandoned ({e:?}): plain LDLᵀ");
                    }
                    self.fall_back_to_ldlt()?;
                    return self.factorize(values);
                }
                Err(e) => return Err(condensed_error(e, &self.diag_pos, values)),
            },
            Factor::Cholesky { .. } | Factor::Lu { .. } | Factor::Mixed(_) => unreachable!("factorised above"),
        }
        self.factorized = true;
        self.numeric_s = clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The numeric phase of the whole-system Cholesky / LDLᵀ or LU factor for the current
    /// scaled values (`&self`: a kept factor refactorises inside a solve, `kept.rs`).
    fn numeric_whole(&self) -> Result<(), LinearError> {
        let n = self.n;
        let par = self.par;
        let mut mem = self.factor_mem.lock().unwrap_or_else(|p| p.into_inner());
        let stack = MemStack::new(&mut mem);
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.scaled,
        );
        // The unscaled diagonal of an unknown (for the error messages).
        let diagonal = |j: usize| self.diag_pos[j].map_or(0.0, |k| self.scaled[k] / (self.scale[j] * self.scale[j]));
        match &self.factor {
            Factor::Cholesky { symbolic, l_values } => {
                let mut l_values = l_values.write().unwrap_or_else(|p| p.into_inner());
                let l_values = &mut l_values[..];
                let fwd = |p: usize| symbolic.perm().map_or(p, |perm| perm.arrays().0[p]);
                let simplicial = matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
                if self.method == LinearMethod::Cholesky {
                    // Non-positive pivots, and tiny ones: numerically singular (e.g. a
                    // rigid-body motion left free).
                    if let Err((unknown, d)) = numeric_llt::<f64>(symbolic, l_values, a, par, stack) {
                        let diagonal = diagonal(unknown);
                        return Err(LinearError::NotPositiveDefinite { unknown, pivot: d * diagonal, diagonal });
                    }
                    self.regularised.store(0, Ordering::Relaxed);
                } else {
                    // First with the expected signs (+ primal, − multiplier: a pivot of
                    // the wrong sign is replaced by ±LDLT_DELTA, the robust choice for the
                    // quasi-definite systems of contact). A frictional slip tangent frozen
                    // inside the Coulomb disc makes the Λ block indefinite, its pivots are
                    // then of the "wrong" sign by right, and replacing them changes the
                    // matrix so much that the elimination overflows (docs/reliability.md,
                    // "Diagnosed: the 3D sphere example with friction at unit scale"): on
                    // such a breakdown the factorisation is redone once without the sign
                    // assumption (only pivots below the threshold are regularised, with
                    // their own sign). A matrix that breaks down both ways is reported.
                    let mut result = Err(LdltError::ZeroPivot { index: 0 });
                    for signs in [Some(&self.signs[..]), None] {
                        let regularisation = LdltRegularization {
                            dynamic_regularization_signs: signs,
                            dynamic_regularization_delta: LDLT_DELTA,
                            dynamic_regularization_epsilon: pivot_threshold(n),
                        };
                        result = symbolic.factorize_numeric_ldlt::<f64>(
                            l_values,
                            a,
                            Side::Lower,
                            regularisation,
                            par,
                            &mut *stack,
                            Spec::default(),
                        );
                        if result.is_ok() {
                            break;
                        }
                    }
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
                    self.regularised.store(count, Ordering::Relaxed);
                }
            }
            Factor::Lu { symbolic, numeric } => {
                let mut numeric = numeric.write().unwrap_or_else(|p| p.into_inner());
                match symbolic.factorize_numeric_lu::<f64>(&mut numeric, a, par, stack, Spec::default()) {
                    Ok(_) => {}
                    Err(LuError::SymbolicSingular { index }) => {
                        return Err(LinearError::ZeroPivot {
                            unknown: symbolic.col_perm().arrays().0[index.min(n - 1)],
                        })
                    }
                    Err(LuError::Generic(e)) => return Err(e.into()),
                }
                self.regularised.store(0, Ordering::Relaxed);
            }
            _ => unreachable!("a whole-system factor"),
        }
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
        let relative = c.solve_deferred((&self.col_ptr, &self.row_idx, &self.scaled), rhs, &mut pending);
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
        c.apply_pending((&self.col_ptr, &self.row_idx, &self.scaled), &mut pending, &mut dx);
        for ((xi, d), s) in x.iter_mut().zip(&dx).zip(&self.scale) {
            *xi += d * s;
        }
    }

    /// Scales the last correction of [`Self::solve_in_place_deferred`] by `alpha` in the
    /// pending crack corrections (a damped Newton step): `correction` is that solve's
    /// output (unscaled), whose crack rows were added to the pending corrections in full.
    /// A no-op for the factors that do not defer.
    pub fn scale_last_deferred(&self, alpha: f64, correction: &[f64]) {
        let Factor::Condensed(c) = &self.factor else { return };
        let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        for (k, j) in c.varying().take(c.n_crack()).enumerate() {
            pending[k] -= (1.0 - alpha) * correction[j] / self.scale[j];
        }
    }

    /// Drops the crack corrections deferred by [`Self::solve_in_place_deferred`] since the
    /// last full solve without propagating them to the interior: the caller has taken them
    /// back from its solution (a confirming Newton correction at round-off, `newton.rs`).
    pub fn discard_deferred(&self) {
        let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        pending.fill(0.0);
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
        self.regularised.load(Ordering::Relaxed)
    }

    /// ‖Ax − b‖/‖b‖ of the last solve (NaN before any solve) and the number of
    /// refinement steps it took.
    pub fn last_residual(&self) -> (f64, usize) {
        (f64::from_bits(self.last_residual.load(Ordering::Relaxed)), self.last_refinements.load(Ordering::Relaxed))
    }

    /// Figures for `summary.json` and benchmarks.
    pub fn stats(&self) -> LinearStats {
        let flops_factor = match &self.factor {
            Factor::Cholesky { symbolic, .. } => Some(factor_flops(symbolic)),
            Factor::Mixed(m) => Some(factor_flops(&m.symbolic)),
            _ => None,
        }
        .filter(|&f| f > 0.0);
        let (mixed, fallback) = match &self.factor {
            Factor::Mixed(m) => match m.double() {
                Some((_, reason)) => (false, Some(reason)),
                None => (true, None),
            },
            _ => (false, self.fallback),
        };
        LinearStats {
            nnz_factor: self.nnz_factor,
            flops_factor,
            factor_scratch_bytes: Some(self.factor_scratch_bytes),
            symbolic_s: self.symbolic_s,
            numeric_s: self.numeric_s,
            solve_s: f64::from_bits(self.solve_s.load(Ordering::Relaxed)),
            mixed,
            fallback,
            condensed: match &self.factor {
                Factor::Condensed(c) => Some(c.counts()),
                _ => None,
            },
            kept: self.kept.as_ref().map(|k| k.counts()),
        }
    }

    /// Recomputes the primal and/or multiplier part of the scaling for `values`
    /// ([`scaling::compute_scaling`]).
    fn compute_scaling_of(&mut self, values: &[f64], primal: bool, multipliers: bool) -> Result<(), LinearError> {
        let structure = Structure {
            col_ptr: &self.col_ptr,
            row_idx: &self.row_idx,
            diag_pos: &self.diag_pos,
            n_primal: self.n_primal,
            method: self.method,
        };
        compute_scaling(&structure, &mut self.scale, values, primal, multipliers)
    }

    /// ‖S A S‖∞ of the current scaled values; with `interior`, over the rows so marked only.
    fn row_sum_norm(&mut self, interior: Option<&[bool]>) -> f64 {
        // The workspace's residual buffer as scratch (unsymmetric values only).
        let scratch = &mut self.workspace.get_mut().unwrap_or_else(|p| p.into_inner()).r;
        let symmetric = self.method != LinearMethod::Lu;
        row_sum_norm(&self.col_ptr, &self.row_idx, &self.scaled, symmetric, scratch, interior)
    }

    /// `scaled = S A S` for the values `A` and the current scaling `S`.
    fn fill_scaled(&mut self, values: &[f64]) {
        fill_scaled(&self.col_ptr, &self.row_idx, &self.scale, values, &mut self.scaled);
    }

    /// Applies the current factor (of `S A S`) to `x` in place.
    fn factor_solve(&self, x: &mut [f64], stack: &mut MemStack) {
        let n = self.n;
        match &self.factor {
            Factor::Split(split) => return split.solve_in_place(x),
            Factor::Condensed(c) => return c.solve_in_place(x),
            Factor::Mixed(m) => return m.solve(x, self.par, stack),
            _ => {}
        }
        let x = MatMut::from_column_major_slice_mut(x, n, 1);
        match &self.factor {
            Factor::Empty | Factor::Split(_) | Factor::Condensed(_) | Factor::Mixed(_) => {}
            Factor::Cholesky { symbolic, l_values } => {
                let l_values = l_values.read().unwrap_or_else(|p| p.into_inner());
                let l_values = &l_values[..];
                if self.method == LinearMethod::Cholesky {
                    LltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, self.par, stack)
                } else {
                    LdltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, self.par, stack)
                }
            }
            Factor::Lu { symbolic, numeric } => {
                let numeric = numeric.read().unwrap_or_else(|p| p.into_inner());
                LuRef::new_unchecked(symbolic, &numeric).solve_in_place_with_conj(Conj::No, x, self.par, stack)
            }
        }
    }

    /// A full solve with refinement in the workspace `ws` ([`refine::solve_refined`]),
    /// recording the residual and the steps.
    fn solve_with(&self, rhs: &mut [f64], ws: &mut SolveWorkspace) -> Result<(), LinearError> {
        let system = ScaledSystem {
            col_ptr: &self.col_ptr,
            row_idx: &self.row_idx,
            values: &self.scaled,
            scale: &self.scale,
            norm_inf: self.norm_inf,
        };
        if let (Factor::Mixed(m), Some(kept)) = (&self.factor, &self.kept) {
            // A kept factor in single precision: every solve is GMRES (`kept.rs`).
            kept.solve_started();
            return self.solve_kept_single(m, kept, &system, rhs, ws);
        }
        if let Factor::Mixed(m) = &self.factor {
            if m.double().is_none() {
                // Conjugate gradients (LLᵀ) or iterative refinement (the indefinite LDLᵀ)
                // preconditioned by the single-precision factor, to the backward error of
                // the double-precision Cholesky path; short of it, the double-precision
                // factor and the ordinary solve from the original `b`.
                let original = rhs.to_vec();
                let (relative, scaled, steps, ok) = if m.is_ldlt() {
                    let plan = (ETA_TARGET_PIVOTING, MIXED_MAX_ITERATIONS);
                    let (relative, scaled, steps, eta) =
                        solve_refined(&system, rhs, ws, plan, |x, st| m.solve(x, self.par, st));
                    (relative, scaled, steps, eta <= ETA_TARGET_CHOLESKY)
                } else {
                    let plan = (ETA_TARGET_PIVOTING, ETA_TARGET_CHOLESKY, MIXED_MAX_ITERATIONS);
                    solve_pcg(&system, rhs, ws, plan, |x, st| m.solve(x, self.par, st))
                };
                if ok && scaled <= MAX_RELATIVE_RESIDUAL {
                    self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
                    self.last_refinements.store(steps, Ordering::Relaxed);
                    return Ok(());
                }
                let reason = if m.is_ldlt() {
                    "iterative refinement with the single-precision LDLᵀ factor did not reach the double-precision \
                     residual"
                } else {
                    "conjugate gradients preconditioned by the single-precision factor did not reach the \
                     double-precision residual"
                };
                if let Err((unknown, d)) =
                    m.compute_double(&self.col_ptr, &self.row_idx, &self.scaled, self.par, reason)?
                {
                    let (s, a) = (self.scale[unknown], self.diag_pos[unknown].map_or(0.0, |k| self.scaled[k]));
                    let diagonal = a / (s * s);
                    return Err(LinearError::NotPositiveDefinite { unknown, pivot: d * diagonal, diagonal });
                }
                rhs.copy_from_slice(&original);
            }
        }
        if let Some(kept) = &self.kept {
            kept.solve_started();
            if self.solve_kept(kept, &system, rhs, ws)? {
                return Ok(());
            }
        }
        let regularised = self.regularised_pivots();
        let plan = match &self.factor {
            // A bulk stage in single precision: the condensed solve is a preconditioner
            // (`condensed.rs`), refined to the double-precision path's backward error.
            Factor::Condensed(c) if c.single_bulk() => (ETA_TARGET_PIVOTING, MIXED_MAX_ITERATIONS),
            _ => refinement_plan(self.method, regularised, matches!(self.factor, Factor::Condensed(_))),
        };
        let (relative, scaled, steps, _) =
            solve_refined(&system, rhs, ws, plan, |x, stack| self.factor_solve(x, stack));
        if let Some(kept) = &self.kept {
            kept.direct_done(scaled);
        }
        self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
        self.last_refinements.store(steps, Ordering::Relaxed);
        if scaled.is_nan() || relative.is_nan() || scaled > MAX_RELATIVE_RESIDUAL {
            return Err(LinearError::Singular { relative_residual: scaled, regularised_pivots: regularised });
        }
        Ok(())
    }

    /// The developer's log of a numeric factorisation of a kept whole-system factor: wall and
    /// CPU seconds and the arithmetic rate (the symbolic flop count over each).
    fn log_numeric(&self, wall: f64, cpu: f64) {
        let flops = match &self.factor {
            Factor::Cholesky { symbolic, .. } => factor_flops(symbolic),
            _ => f64::NAN,
        };
        eprintln!(
            "  kept factor: numeric factorisation {wall:.2} s wall, {cpu:.2} s CPU: {:.2} GFlop/s wall, {:.2} GFlop \
             per CPU-second",
            flops / wall / 1e9,
            flops / cpu / 1e9
        );
    }

    /// A solve with a kept factor that is stale (`kept.rs`): GMRES on the current matrix
    /// preconditioned by it, within the iterations its cost cap allows. Returns `true` when
    /// it solved `rhs`; otherwise (not stale, or not converged: then refactorised in place,
    /// `rhs` restored) the caller solves directly.
    fn solve_kept(
        &self,
        kept: &KeptFactor,
        system: &ScaledSystem<'_>,
        rhs: &mut [f64],
        ws: &mut SolveWorkspace,
    ) -> Result<bool, LinearError> {
        let mut st = kept.state.lock().unwrap_or_else(|p| p.into_inner());
        if !st.stale {
            return Ok(false);
        }
        let log = std::env::var_os("FISSURE_CONTACT_LOG").is_some();
        if let Some((cap, tol)) = kept.iteration_cap(&st) {
            let original = rhs.to_vec();
            let clock = Instant::now();
            let symmetric = self.method != LinearMethod::Lu;
            let (relative, scaled, iterations, converged) =
                solve_gmres(system, symmetric, rhs, ws, (tol, cap), |x, stack| self.factor_solve(x, stack));
            let seconds = clock.elapsed().as_secs_f64();
            kept.krylov_done(&mut st, iterations);
            if log {
                eprintln!(
                    "  kept factor: GMRES {iterations} iterations (cap {cap}), residual {scaled:.1e}, {:.1} ms",
                    seconds * 1e3
                );
            }
            if converged && scaled <= MAX_RELATIVE_RESIDUAL {
                self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
                self.last_refinements.store(iterations, Ordering::Relaxed);
                return Ok(true);
            }
            rhs.copy_from_slice(&original);
        }
        // Over its budget, or GMRES did not converge: refactorise the current matrix.
        let clock = Instant::now();
        if let Err(e) = self.numeric_whole() {
            kept.lost(&mut st);
            return Err(e);
        }
        let seconds = clock.elapsed().as_secs_f64();
        kept.factorised_locked(&mut st, &self.scaled);
        if log {
            eprintln!("  kept factor: refactorised in the solve, {:.1} ms", seconds * 1e3);
        }
        Ok(false)
    }
}

impl FaerSolver {
    /// A solve with a kept factor in single precision (`kept.rs`, `mixed.rs`): GMRES on the
    /// current matrix preconditioned by it, stale or fresh. A stale factor over its budget,
    /// or whose GMRES did not converge, is refactorised (in single precision) inside the
    /// solve; a fresh one whose GMRES does not reach the double-precision residual within
    /// [`MIXED_MAX_ITERATIONS`], or a single-precision factorisation that breaks down,
    /// computes the double-precision factor, which solves directly (and is kept by the
    /// next [`Self::factorize`]).
    fn solve_kept_single(
        &self,
        m: &MixedCholesky,
        kept: &KeptFactor,
        system: &ScaledSystem<'_>,
        rhs: &mut [f64],
        ws: &mut SolveWorkspace,
    ) -> Result<(), LinearError> {
        let mut st = kept.state.lock().unwrap_or_else(|p| p.into_inner());
        let log = std::env::var_os("FISSURE_CONTACT_LOG").is_some();
        let original = rhs.to_vec();
        let precondition = |x: &mut [f64], stack: &mut MemStack| m.solve(x, self.par, stack);
        let done = |relative: f64, iterations: usize| {
            self.last_residual.store(relative.to_bits(), Ordering::Relaxed);
            self.last_refinements.store(iterations, Ordering::Relaxed);
        };
        // A stale factor is never a double one: `factorize` keeps a double factor computed
        // by a solve as the plain factor before it decides.
        if st.stale && m.double().is_none() {
            if let Some((cap, tol)) = kept.iteration_cap(&st) {
                let clock = Instant::now();
                let (relative, scaled, iterations, converged) =
                    solve_gmres(system, true, rhs, ws, (tol, cap), precondition);
                kept.krylov_done(&mut st, iterations);
                if log {
                    eprintln!(
                        "  kept factor (single precision): GMRES {iterations} iterations (cap {cap}), residual \
                         {scaled:.1e}, {:.1} ms",
                        clock.elapsed().as_secs_f64() * 1e3
                    );
                }
                if converged && scaled <= MAX_RELATIVE_RESIDUAL {
                    done(relative, iterations);
                    return Ok(());
                }
                rhs.copy_from_slice(&original);
            }
            // Over its budget, or GMRES did not converge: the current matrix factorised.
            let clock = Instant::now();
            let result = {
                let mut mem = self.factor_mem.lock().unwrap_or_else(|p| p.into_inner());
                m.factorize(&self.col_ptr, &self.row_idx, &self.scaled, self.par, MemStack::new(&mut mem))
            };
            match result {
                Ok(regularised) => self.regularised.store(regularised, Ordering::Relaxed),
                Err(reason) => {
                    if let Err(e) = self.double_in_solve(m, reason) {
                        kept.lost(&mut st);
                        return Err(e);
                    }
                }
            }
            kept.factorised_locked(&mut st, &self.scaled);
            if log {
                eprintln!(
                    "  kept factor (single precision): refactorised in the solve, {:.1} ms",
                    clock.elapsed().as_secs_f64() * 1e3
                );
            }
        }
        if m.double().is_none() {
            let clock = Instant::now();
            let (relative, scaled, iterations, converged) =
                solve_gmres(system, true, rhs, ws, (kept.tolerance(), MIXED_MAX_ITERATIONS), precondition);
            kept.fresh_done(iterations);
            if log {
                eprintln!(
                    "  kept factor (single precision, fresh): GMRES {iterations} iterations, residual {scaled:.1e}, \
                     {:.1} ms",
                    clock.elapsed().as_secs_f64() * 1e3
                );
            }
            if converged && scaled <= MAX_RELATIVE_RESIDUAL {
                done(relative, iterations);
                return Ok(());
            }
            rhs.copy_from_slice(&original);
            self.double_in_solve(
                m,
                "GMRES preconditioned by the single-precision LDLᵀ factor did not reach the double-precision residual",
            )?;
        }
        // The double-precision factor of this matrix (a fallback): the direct solve, refined
        // as after regularised pivots (their count is not known here).
        let plan = refinement_plan(self.method, 1, false);
        let (relative, scaled, steps, _) = solve_refined(system, rhs, ws, plan, precondition);
        kept.direct_done(scaled);
        done(relative, steps);
        if scaled.is_nan() || relative.is_nan() || scaled > MAX_RELATIVE_RESIDUAL {
            return Err(LinearError::Singular { relative_residual: scaled, regularised_pivots: 0 });
        }
        Ok(())
    }

    /// Computes the double-precision factor of the current scaled matrix in a solve (a
    /// single-precision factor's fallback, `reason`: why).
    fn double_in_solve(&self, m: &MixedCholesky, reason: &'static str) -> Result<(), LinearError> {
        if let Err((unknown, d)) = m.compute_double(&self.col_ptr, &self.row_idx, &self.scaled, self.par, reason)? {
            let (s, a) = (self.scale[unknown], self.diag_pos[unknown].map_or(0.0, |k| self.scaled[k]));
            let diagonal = a / (s * s);
            return Err(LinearError::NotPositiveDefinite { unknown, pivot: d * diagonal, diagonal });
        }
        Ok(())
    }
}

impl LinearBackend for FaerSolver {
    fn analyse(system: &SystemStructure<'_>) -> Result<Self, LinearError> {
        Self::analyse_system(system)
    }

    fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        FaerSolver::factorize(self, values)
    }

    fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        FaerSolver::solve_in_place(self, rhs)
    }

    fn set_bulk(&mut self, values: &[f64]) -> Result<(), LinearError> {
        FaerSolver::set_bulk(self, values)
    }

    fn solve_in_place_deferred(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        FaerSolver::solve_in_place_deferred(self, rhs)
    }

    fn apply_deferred(&self, x: &mut [f64]) {
        FaerSolver::apply_deferred(self, x)
    }

    fn varying_unknowns(&self) -> Option<Vec<usize>> {
        FaerSolver::varying_unknowns(self)
    }

    fn method(&self) -> LinearMethod {
        self.method
    }

    fn n(&self) -> usize {
        self.n
    }

    fn n_primal(&self) -> usize {
        self.n_primal
    }

    fn regularised_pivots(&self) -> usize {
        FaerSolver::regularised_pivots(self)
    }

    fn last_residual(&self) -> (f64, usize) {
        FaerSolver::last_residual(self)
    }

    fn stats(&self) -> LinearStats {
        FaerSolver::stats(self)
    }
}

/// The developer's log (`FISSURE_CONTACT_LOG`) of the factor an analysis chose: which
/// path, its size and its arithmetic.
fn log_factor(factor: &Factor, method: LinearMethod, n: usize, nnz: Option<usize>) {
    let kind = match factor {
        Factor::Empty => "none",
        Factor::Cholesky { .. } if method == LinearMethod::Cholesky => "whole-system Cholesky, double precision",
        Factor::Cholesky { .. } => "whole-system LDLᵀ, double precision",
        Factor::Mixed(m) if m.is_ldlt() => "whole-system LDLᵀ, single precision (mixed)",
        Factor::Mixed(_) => "whole-system Cholesky, single precision (mixed)",
        Factor::Lu { .. } => "LU",
        Factor::Split(_) => "Cholesky split at the top separator",
        Factor::Condensed(_) => "condensed onto the crack unknowns",
    };
    let flops = match factor {
        Factor::Cholesky { symbolic, .. } => factor_flops(symbolic),
        Factor::Mixed(m) => factor_flops(&m.symbolic),
        _ => f64::NAN,
    };
    let nnz = nnz.map_or("-".to_string(), |v| format!("{:.1}M", v as f64 / 1e6));
    eprintln!("factor: {kind}; {n} unknowns, nnz(L) {nnz}, {flops:.3e} flops");
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

/// The contact unknowns of a system analysed for contact (`condense`: the varying primal
/// unknowns, if given): the multipliers, the primal unknowns coupled to a multiplier and
/// the ones marked varying (a law without multipliers).
fn contact_unknowns(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    varying: Option<&[bool]>,
) -> Vec<bool> {
    let mut contact: Vec<bool> =
        (0..n).map(|j| j >= n_primal || varying.is_some_and(|v| v.get(j) == Some(&true))).collect();
    for j in n_primal..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            contact[i] = true;
        }
    }
    contact
}
