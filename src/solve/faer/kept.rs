//! The whole-system sparse factor kept across contact iterations: a new contact tangent
//! that differs from the factorised one only in the contact rows and columns is solved by
//! GMRES preconditioned by the old factor instead of a new numeric factorisation.
//!
//! Entry point: [`KeptFactor`] (held by [`super::FaerSolver`] for contact systems on the
//! plain Cholesky / LDLᵀ / LU factor: the ones whose crack block is too large for the
//! condensed factor, [`super::condensed`]); [`KeptFactor::decide`] at a new matrix,
//! [`KeptFactor::iteration_cap`] and the counts of
//! [`crate::solve::backend::CondensedCounts`] for its solves.
//!
//! Between two contact iterations the scaled matrix `Ã₁ = S A₁ S` (the scaling `S` of the
//! factorised `Ã₀`, kept while the factor is) differs from `Ã₀` only in the columns `R` of
//! the unknowns whose contact terms changed (and, the matrix being structurally symmetric,
//! in their rows): `Ã₁ − Ã₀` has rank at most `2k`, `k = |R|` (at most `k` when the change
//! is confined to the `R × R` block), so GMRES on `Ã₁` right-preconditioned by the factor of
//! `Ã₀` (`Ã₁ Ã₀⁻¹ = I + ΔÃ Ã₀⁻¹`) converges in at most that many iterations in exact
//! arithmetic, each one product with `Ã₁` and one pair of triangular solves. Right
//! preconditioning keeps the residual the true one: a solve ends when
//! `‖S(b − A₁x)‖ / ‖Sb‖` is at most [`KRYLOV_TOLERANCE`] (or the direct solve's own
//! residual on this system, if larger), or its normwise backward error is at the target
//! the direct Cholesky solve stops refining at (`refine::ETA_TARGET_CHOLESKY`), checked
//! on `Ã₁`.
//!
//! **Cost cap** (measured at run time): a numeric factorisation took `t_f` seconds, an
//! iteration (a solve pair and a product) `t_i` (from the last direct solve, then from the
//! Krylov solves). A new matrix keeps the factor when every changed column is a contact
//! unknown and either `k + 1 ≤ t_f / t_i` (the rank bound fits the budget of one
//! factorisation), or the change is small in size (at most [`SMALL_CHANGE`] of the largest
//! entry: friction thresholds of a later pass), or, once per factor lifetime while no such
//! try failed, a wider change is tried with half that budget. The Krylov time spent on a
//! factor while stale is summed: past `t_f` the next solve or matrix refactorises. A solve
//! that does not converge within its cap refactorises in place and solves directly, so the
//! answer is the direct solve's to the tolerance either way. `FISSURE_CONDENSED_REFACTOR`
//! or `FISSURE_SPARSE_REFACTOR` (developer switches, read at the analysis) refactorise at
//! every new matrix, as before, to compare.

use crate::solve::backend::CondensedCounts;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Relative residual `‖S(b − A x)‖ / ‖S b‖` a Krylov solve with a kept factor reaches (the
/// scaled system's; at least the direct solve's own on the same factor's system).
pub(crate) const KRYLOV_TOLERANCE: f64 = 1e-13;

/// Largest change of a scaled entry, relative to the largest scaled entry, that keeps the
/// factor whatever the number of changed columns.
pub(crate) const SMALL_CHANGE: f64 = 1e-2;

/// Iterations a solve may take, at least and at most (the measured budget in between).
const MIN_ITERATIONS: usize = 8;
const MAX_ITERATIONS: usize = 100;

/// What a new matrix does with the kept factor ([`KeptFactor::decide`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Decision {
    /// The factor's own matrix: solves are direct.
    Exact,
    /// Kept stale: solves by GMRES preconditioned by it.
    Kept,
    /// Refactorise.
    Refactor,
}

/// The state of the kept factor that solves read and update.
pub(crate) struct KeptState {
    /// The factor is of an earlier matrix: solves go through GMRES.
    pub(crate) stale: bool,
    /// The change was wider than the rank budget (tried with half of it).
    wide: bool,
    /// Seconds of Krylov solves on this factor while stale.
    stale_seconds: f64,
    /// A wide try failed on this solver: wider changes refactorise.
    wide_failed: bool,
    /// The scaled values `Ã₀` of the factorised matrix (empty: no valid factor).
    reference: Vec<f64>,
    /// Seconds of the last numeric factorisation.
    factor_s: f64,
}

/// See the module documentation.
pub(crate) struct KeptFactor {
    /// Whether a factor may be kept (the developer switches unset).
    reuse: bool,
    /// The contact unknowns (multipliers and the primal unknowns whose contact terms may
    /// change): the only columns whose change keeps the factor.
    contact: Vec<bool>,
    /// Seconds of one iteration (solve pair and product), measured (0: not yet).
    iteration_s: AtomicU64,
    /// Relative scaled residual of the last direct solve.
    direct_residual: AtomicU64,
    pub(crate) state: Mutex<KeptState>,
    factorizations: AtomicUsize,
    reused: AtomicUsize,
    krylov_solves: AtomicUsize,
    krylov_iterations: AtomicUsize,
}

impl KeptFactor {
    /// For a system whose contact unknowns are `contact` (one flag per unknown).
    pub(crate) fn new(contact: Vec<bool>) -> Self {
        let off = |v: &str| std::env::var_os(v).is_some();
        KeptFactor {
            reuse: !off("FISSURE_CONDENSED_REFACTOR") && !off("FISSURE_SPARSE_REFACTOR"),
            contact,
            iteration_s: AtomicU64::new(0f64.to_bits()),
            direct_residual: AtomicU64::new(0f64.to_bits()),
            state: Mutex::new(KeptState {
                stale: false,
                wide: false,
                stale_seconds: 0.0,
                wide_failed: false,
                reference: Vec::new(),
                factor_s: 0.0,
            }),
            factorizations: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
            krylov_solves: AtomicUsize::new(0),
            krylov_iterations: AtomicUsize::new(0),
        }
    }

    /// Forces the switch on or off (tests).
    #[cfg(test)]
    pub(crate) fn set_reuse(&mut self, reuse: bool) {
        self.reuse = reuse;
    }

    /// The factor is being recomputed: no valid factor until [`Self::factorised`].
    pub(crate) fn invalidate(&mut self) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        st.reference.clear();
        st.stale = false;
    }

    /// A numeric factorisation of the scaled values `scaled` succeeded in `seconds`.
    pub(crate) fn factorised(&mut self, scaled: &[f64], seconds: f64) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        Self::reset(st, scaled, seconds);
        self.factorizations.fetch_add(1, Ordering::Relaxed);
    }

    /// The same after a refactorisation inside a solve (the state locked by the caller).
    pub(crate) fn factorised_locked(&self, st: &mut KeptState, scaled: &[f64], seconds: f64) {
        Self::reset(st, scaled, seconds);
        self.factorizations.fetch_add(1, Ordering::Relaxed);
    }

    /// A refactorisation inside a solve failed: the factor holds no matrix (the next new
    /// matrix refactorises).
    pub(crate) fn lost(&self, st: &mut KeptState) {
        st.reference.clear();
        st.stale = false;
    }

    fn reset(st: &mut KeptState, scaled: &[f64], seconds: f64) {
        st.reference.clear();
        st.reference.extend_from_slice(scaled);
        st.factor_s = seconds;
        st.stale = false;
        st.wide = false;
        st.stale_seconds = 0.0;
    }

    /// The new scaled values `scaled` (with the factor's scaling, on its column pointers
    /// `col_ptr`): keep the factor or refactorise (see the module documentation).
    pub(crate) fn decide(&self, col_ptr: &[usize], scaled: &[f64]) -> Decision {
        let mut st = self.state.lock().unwrap_or_else(|p| p.into_inner());
        if !self.reuse || st.reference.len() != scaled.len() || st.stale_seconds >= self.budget(&st) {
            return Decision::Refactor;
        }
        let n = col_ptr.len() - 1;
        let (mut k, mut delta, mut largest) = (0usize, 0.0f64, 0.0f64);
        for j in 0..n {
            let col = col_ptr[j]..col_ptr[j + 1];
            let mut changed = false;
            for (a, r) in scaled[col.clone()].iter().zip(&st.reference[col]) {
                largest = largest.max(r.abs());
                let d = (a - r).abs();
                if d != 0.0 || a.to_bits() != r.to_bits() {
                    changed = true;
                    delta = delta.max(d);
                }
            }
            if changed {
                if !self.contact[j] {
                    return Decision::Refactor;
                }
                k += 1;
            }
        }
        let log = |what: &str| {
            if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                eprintln!(
                    "kept factor: {k} columns changed, largest change {:.1e} of the largest entry: {what}",
                    delta / largest.max(f64::MIN_POSITIVE)
                );
            }
        };
        if k == 0 {
            // The factor's own matrix (the Krylov time spent on it stays counted).
            log("exact");
            st.stale = false;
            self.reused.fetch_add(1, Ordering::Relaxed);
            return Decision::Exact;
        }
        let cap = self.iteration_cap_for(&st, false);
        let small = delta <= SMALL_CHANGE * largest;
        let wide = !(k < cap || small);
        if wide && st.wide_failed {
            log("refactorised (a wider change failed before)");
            return Decision::Refactor;
        }
        log(if wide { "kept, wide" } else { "kept" });
        st.stale = true;
        st.wide = wide;
        self.reused.fetch_add(1, Ordering::Relaxed);
        Decision::Kept
    }

    /// Seconds of Krylov solves a factor may cost while stale: one factorisation's, at
    /// least [`MIN_ITERATIONS`] iterations'.
    fn budget(&self, st: &KeptState) -> f64 {
        st.factor_s.max(MIN_ITERATIONS as f64 * self.iteration_seconds())
    }

    fn iteration_seconds(&self) -> f64 {
        f64::from_bits(self.iteration_s.load(Ordering::Relaxed))
    }

    /// The iterations one solve may take (`wide`: a change wider than the rank budget, half
    /// of it).
    fn iteration_cap_for(&self, st: &KeptState, wide: bool) -> usize {
        let t = self.iteration_seconds();
        let cap = if t > 0.0 { (st.factor_s / t) as usize } else { MAX_ITERATIONS };
        let cap = cap.clamp(MIN_ITERATIONS, MAX_ITERATIONS);
        if wide {
            (cap / 2).max(MIN_ITERATIONS / 2)
        } else {
            cap
        }
    }

    /// The iterations the next stale solve may take and its tolerance; `None` when the
    /// factor has used up its budget (refactorise first).
    pub(crate) fn iteration_cap(&self, st: &KeptState) -> Option<(usize, f64)> {
        if st.stale_seconds >= self.budget(st) {
            return None;
        }
        let direct = f64::from_bits(self.direct_residual.load(Ordering::Relaxed));
        let tol = KRYLOV_TOLERANCE.max(4.0 * direct).min(1e-10);
        Some((self.iteration_cap_for(st, st.wide), tol))
    }

    /// A stale solve took `iterations` in `seconds` (`converged` or not).
    pub(crate) fn krylov_done(&self, st: &mut KeptState, iterations: usize, seconds: f64, converged: bool) {
        st.stale_seconds += seconds;
        self.krylov_solves.fetch_add(1, Ordering::Relaxed);
        self.krylov_iterations.fetch_add(iterations, Ordering::Relaxed);
        // The first preconditioned solve and the final residual are one more iteration.
        self.iteration_s.store((seconds / (iterations + 1) as f64).to_bits(), Ordering::Relaxed);
        if !converged && st.wide {
            st.wide_failed = true;
        }
    }

    /// A direct solve took `seconds` with `steps` refinement steps, to the relative scaled
    /// residual `residual`.
    pub(crate) fn direct_done(&self, seconds: f64, steps: usize, residual: f64) {
        self.iteration_s.store((seconds / (steps + 1) as f64).to_bits(), Ordering::Relaxed);
        if residual.is_finite() {
            self.direct_residual.store(residual.to_bits(), Ordering::Relaxed);
        }
    }

    /// The counts since the analysis: real numeric factorisations, new matrices that kept
    /// the factor, stale solves and their iterations.
    pub(crate) fn counts(&self) -> CondensedCounts {
        CondensedCounts {
            factorizations: self.factorizations.load(Ordering::Relaxed),
            reused: self.reused.load(Ordering::Relaxed),
            krylov_solves: self.krylov_solves.load(Ordering::Relaxed),
            krylov_iterations: self.krylov_iterations.load(Ordering::Relaxed),
        }
    }
}
