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
//! **Decided by predicted cost, deterministically.** One numeric factorisation costs the
//! symbolic factor's flops `W_f`; one Krylov iteration a preconditioner solve pair and a
//! product with the matrix, `4 nnz(L) + 2 nnz(A)` flops, weighted by [`SOLVE_FLOP_WEIGHT`]
//! (the triangular solves stream the factor from memory at a tenth of the factorisation's
//! arithmetic rate). A factorisation is worth `B = W_f / (w (4 nnz(L) + 2 nnz(A)))`
//! iterations ([`iterations_per_factorisation`]). A new matrix whose changed columns are
//! all contact unknowns keeps the factor when the predicted Krylov work of its solves fits
//! in what is left of that budget: `s · (m + 1) ≤ B − i_stale`, with `m` the predicted
//! iterations of one solve (`min(k + 1, m̄)`, `k` the changed columns, `m̄` the mean
//! iterations of this solver's Krylov solves so far on changes of the same class: *small*,
//! every entry changed by at most [`SMALL_CHANGE`] of the largest entry (the friction
//! thresholds of a later pass, the last Newton iterations), or *large*; before the first of
//! its class, [`PRIOR_SMALL`] or [`PRIOR_ITERATIONS`]), `s` the solves per new matrix on
//! this solver (at least 1) and `i_stale` the iterations already spent on this factor while
//! stale; a change as large as the entries themselves (at least [`WHOLE_CHANGE`] of the
//! largest) in more columns than the iterations a solve may take (so that the bound
//! `k + 1` does not hold it in: a new tangent, such as the first friction tangent after the
//! frictionless pass) is refactorised without a Krylov try. Every figure is a count of the run (flops of the analysis, iterations of its
//! solves), never a measured time: the iteration path does not depend on the machine's
//! load. So a model whose factorisation is worth few iterations (2D, small 3D: a simplicial
//! factor is worth none) refactorises as without the kept factor, and a large 3D saddle
//! point keeps its factor across the small changes of the contact iterations. Each stale
//! solve may take the iterations left in the budget (at least [`MIN_ITERATIONS`], at most
//! [`MAX_ITERATIONS`]; the first of its class at most twice its prior, so that a change
//! GMRES cannot follow costs little); one that does not converge within them refactorises
//! in place and solves directly, so the answer is the direct solve's to the tolerance either
//! way. Its iterations count in its class's mean, which then keeps such changes out.
//!
//! **In single precision** (`[solver] precision`, [`super::mixed`]): the kept factor may be
//! an `LDLᵀ` computed in `f32`. Every solve is then GMRES, a fresh factor's too (a few
//! iterations to the same tolerance: the factor is `Ã₀` to single precision), and the
//! decision counts what changes: a single-precision factorisation costs
//! [`SINGLE_FACTOR_WEIGHT`] of the double one's flops and a Krylov iteration streams the
//! factor in 4 bytes an entry ([`iterations_per_single_factorisation`]); the Krylov work
//! a kept matrix costs is what its solves take beyond the mean iterations of a solve on a
//! fresh factor, `m₀`, which refactorising would not save (`s · (max(m − m₀, 0) + 1)`
//! predicted, each stale solve charged `max(i + 1 − m₀, 1)`, and allowed `m₀` more
//! iterations). With a double-precision factor `m₀ = 0`: the rule above unchanged. A fresh
//! solve that does not converge within [`super::mixed::MIXED_MAX_ITERATIONS`], or a
//! single-precision factorisation that breaks down, computes the double-precision factor
//! (a warning in the run), which the solver keeps from then on, with the double rule.
//!
//! Developer switch `FISSURE_KEPT_FACTOR` (read at the analysis): `0` refactorises at every
//! new matrix (the comparison path; `FISSURE_SPARSE_REFACTOR` and
//! `FISSURE_CONDENSED_REFACTOR` do the same), `1` keeps the factor whatever the cost (while
//! the changed columns are contact unknowns, the change is not a new tangent
//! ([`WHOLE_CHANGE`]) and each solve converges within [`MAX_ITERATIONS`]: the rule with an
//! unlimited budget, for tests on small models); unset or any other value: by the
//! predicted cost, as above.

use crate::solve::backend::CondensedCounts;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Relative residual `‖S(b − A x)‖ / ‖S b‖` a Krylov solve with a kept factor reaches (the
/// scaled system's; at least the direct solve's own on the same factor's system).
pub(crate) const KRYLOV_TOLERANCE: f64 = 1e-13;

/// Predicted iterations of a Krylov solve with a stale factor before any was measured on
/// the solver: the 31–34 measured on `examples/penny_crack_contact_3d.toml` (every point
/// sliding, the whole tangent of the contact rows changed).
pub(crate) const PRIOR_ITERATIONS: usize = 32;

/// The same for a small change ([`SMALL_CHANGE`]).
pub(crate) const PRIOR_SMALL: usize = 8;

/// Largest change of a scaled entry, relative to the largest scaled entry, of a small
/// change (its iterations predicted apart from the large ones').
pub(crate) const SMALL_CHANGE: f64 = 1e-2;

/// Largest change of a scaled entry, relative to the largest scaled entry, from which a new
/// matrix is a new tangent rather than a correction of the factor's: refactorised without a
/// Krylov try (by cost). The first friction tangent after the frictionless pass changes
/// the friction rows by 1.0 of the largest entry and GMRES did not converge on it in 150
/// iterations (`examples/penny_crack_contact_3d.toml`); the later tangents of the sliding
/// penny (slip directions, thresholds) change them by 0.12 and take 28–30.
pub(crate) const WHOLE_CHANGE: f64 = 0.5;

/// Iterations a solve may take, at least and at most (the budget left in between).
pub(crate) const MIN_ITERATIONS: usize = 8;
pub(crate) const MAX_ITERATIONS: usize = 150;

/// The weight of a Krylov iteration's flops against the numeric factorisation's: the
/// triangular solves and the product stream the factor and the matrix from memory, the
/// supernodal factorisation runs dense kernels. Measured on
/// `examples/penny_crack_contact_3d.toml` (nnz(L) 65.9M, 1.41e11 flops; 2026-11-28, load
/// 2–9): a solve pair 90–270 ms for 2.6e8 flops (1–3 GFlop/s), a factorisation 10–14 s
/// (10–14 GFlop/s wall); quiet, the factorisation reaches ~50 GFlop/s on two cores and a
/// solve stays memory-bound. A constant, so that the decision is a function of the run's
/// counts only.
pub(crate) const SOLVE_FLOP_WEIGHT: f64 = 10.0;

/// The Krylov iterations one numeric factorisation is worth: its predicted flops
/// `factor_flops` over the weighted flops of one iteration (a solve pair with the factor of
/// `nnz_l` entries and a product with the matrix of `nnz_a` entries); 0 when nothing is
/// predicted (a simplicial factor, an LU): such a factor is never kept by cost.
pub(crate) fn iterations_per_factorisation(factor_flops: f64, nnz_l: usize, nnz_a: usize) -> f64 {
    let iteration = 4.0 * nnz_l as f64 + 2.0 * nnz_a as f64;
    if factor_flops.is_finite() && factor_flops > 0.0 && iteration > 0.0 {
        factor_flops / (SOLVE_FLOP_WEIGHT * iteration)
    } else {
        0.0
    }
}

/// The weight of a single-precision numeric factorisation's flops against a double one's:
/// faer's f32 dense kernels do about twice the flops per second of its f64 ones on AVX2
/// (the 3e5-dof Cholesky's numeric phase 97 → 46 CPU seconds, `docs/performance.md`,
/// "Mixed precision").
pub(crate) const SINGLE_FACTOR_WEIGHT: f64 = 0.5;

/// The Krylov iterations one single-precision numeric factorisation is worth, like
/// [`iterations_per_factorisation`]: its flops weighted by [`SINGLE_FACTOR_WEIGHT`], an
/// iteration's solve pair streaming the factor in 4 bytes an entry (half the double
/// factor's traffic: `2 nnz(L)` double-equivalent flops) and its product with the matrix in
/// double precision.
pub(crate) fn iterations_per_single_factorisation(factor_flops: f64, nnz_l: usize, nnz_a: usize) -> f64 {
    let iteration = 2.0 * nnz_l as f64 + 2.0 * nnz_a as f64;
    if factor_flops.is_finite() && factor_flops > 0.0 && iteration > 0.0 {
        SINGLE_FACTOR_WEIGHT * factor_flops / (SOLVE_FLOP_WEIGHT * iteration)
    } else {
        0.0
    }
}

/// When a new matrix may keep the factor (`FISSURE_KEPT_FACTOR`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Refactorise at every new matrix.
    Off,
    /// Keep it when the predicted Krylov work fits in one factorisation's predicted flops.
    ByCost,
    /// Keep it whenever the changed columns are contact unknowns and the change is not a
    /// new tangent ([`WHOLE_CHANGE`], against [`MAX_ITERATIONS`]): the rule with an
    /// unlimited budget (tests: a small model's factorisation is worth few iterations).
    Always,
}

impl Mode {
    fn from_env() -> Self {
        let set = |v: &str| std::env::var_os(v).is_some();
        if set("FISSURE_CONDENSED_REFACTOR") || set("FISSURE_SPARSE_REFACTOR") {
            return Mode::Off;
        }
        match std::env::var("FISSURE_KEPT_FACTOR").as_deref() {
            Ok("0") => Mode::Off,
            Ok("1") => Mode::Always,
            _ => Mode::ByCost,
        }
    }
}

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

/// The counts a decision reads ([`keep_by_cost`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Costs {
    /// Krylov iterations one numeric factorisation is worth ([`iterations_per_factorisation`]).
    pub(crate) budget: f64,
    /// Krylov iterations already spent on this factor while stale (each solve's, plus one).
    pub(crate) stale: f64,
    /// Mean iterations of a Krylov solve on this solver, on changes of the new matrix's
    /// class (`None`: none yet).
    pub(crate) mean_iterations: Option<f64>,
    /// Whether the change is small ([`SMALL_CHANGE`]): the prior of `mean_iterations`.
    pub(crate) small: bool,
    /// Solves per new matrix on this solver (at least 1).
    pub(crate) solves_per_matrix: f64,
    /// Mean iterations of a solve on a fresh factor (a single-precision factor's GMRES;
    /// 0 for a double-precision factor, whose fresh solves are direct).
    pub(crate) fresh_iterations: f64,
}

/// Whether a new matrix with `k` changed contact columns keeps the factor: the predicted
/// Krylov iterations of its solves, `s · (min(k + 1, m̄) + 1)`, fit in what is left of the
/// iterations a factorisation is worth (see the module documentation).
pub(crate) fn keep_by_cost(k: usize, c: &Costs) -> bool {
    if !(c.budget > 0.0) {
        return false;
    }
    let prior = if c.small { PRIOR_SMALL } else { PRIOR_ITERATIONS };
    let m = c.mean_iterations.unwrap_or(prior as f64).min((k + 1) as f64);
    // What a fresh factor's solves take anyway is not saved by refactorising.
    let predicted = c.solves_per_matrix.max(1.0) * ((m - c.fresh_iterations).max(0.0) + 1.0);
    // A solve may take at least MIN_ITERATIONS: with less left the solve would refactorise.
    let left = c.budget - c.stale;
    predicted <= left && left >= MIN_ITERATIONS as f64
}

/// The state of the kept factor that solves read and update.
pub(crate) struct KeptState {
    /// The factor is of an earlier matrix: solves go through GMRES.
    pub(crate) stale: bool,
    /// The change from the factor's matrix is small ([`SMALL_CHANGE`]).
    small: bool,
    /// Krylov iterations on this factor while stale (each solve's, plus one).
    stale_iterations: f64,
    /// The scaled values `Ã₀` of the factorised matrix (empty: no valid factor).
    reference: Vec<f64>,
}

/// See the module documentation.
pub(crate) struct KeptFactor {
    mode: Mode,
    /// The contact unknowns (multipliers and the primal unknowns whose contact terms may
    /// change): the only columns whose change keeps the factor.
    contact: Vec<bool>,
    /// Krylov iterations one numeric factorisation is worth ([`iterations_per_factorisation`]).
    budget: f64,
    /// Relative scaled residual of the last direct solve.
    direct_residual: AtomicU64,
    pub(crate) state: Mutex<KeptState>,
    factorizations: AtomicUsize,
    reused: AtomicUsize,
    krylov_solves: AtomicUsize,
    krylov_iterations: AtomicUsize,
    /// Krylov solves and their iterations per class of change (large, small).
    class_solves: [AtomicUsize; 2],
    class_iterations: [AtomicUsize; 2],
    /// New matrices (factorised or kept) and solves, for the solves per matrix.
    matrices: AtomicUsize,
    solves: AtomicUsize,
    /// The factor is in single precision: its fresh solves are GMRES too.
    single: bool,
    /// GMRES solves on a fresh single-precision factor and their iterations.
    fresh_solves: AtomicUsize,
    fresh_iterations: AtomicUsize,
}

impl KeptFactor {
    /// Whether the model's factorisation is worth keeping at all: worth at least
    /// [`MIN_ITERATIONS`] Krylov iterations (a property of the model, not of the developer
    /// switch, so that the switched-off comparison path takes the same loops). The contact
    /// loops drop the 3D stick predictor only then (its all-stick start is a new tangent
    /// that no kept factor takes): a small model, which refactorises anyway, keeps it.
    pub(crate) fn may_keep(&self) -> bool {
        self.budget >= MIN_ITERATIONS as f64
    }

    /// For a system whose contact unknowns are `contact` (one flag per unknown), whose
    /// numeric factorisation is worth `budget` Krylov iterations.
    pub(crate) fn new(contact: Vec<bool>, budget: f64) -> Self {
        KeptFactor {
            mode: Mode::from_env(),
            contact,
            budget,
            direct_residual: AtomicU64::new(0f64.to_bits()),
            state: Mutex::new(KeptState { stale: false, small: false, stale_iterations: 0.0, reference: Vec::new() }),
            factorizations: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
            krylov_solves: AtomicUsize::new(0),
            krylov_iterations: AtomicUsize::new(0),
            class_solves: [AtomicUsize::new(0), AtomicUsize::new(0)],
            class_iterations: [AtomicUsize::new(0), AtomicUsize::new(0)],
            matrices: AtomicUsize::new(0),
            solves: AtomicUsize::new(0),
            single: false,
            fresh_solves: AtomicUsize::new(0),
            fresh_iterations: AtomicUsize::new(0),
        }
    }

    /// For a single-precision factor: every solve is GMRES, `budget` from
    /// [`iterations_per_single_factorisation`].
    pub(crate) fn new_single(contact: Vec<bool>, budget: f64) -> Self {
        KeptFactor { single: true, ..Self::new(contact, budget) }
    }

    /// The factor fell back to double precision: the double rule from now on, with
    /// `budget` from [`iterations_per_factorisation`].
    pub(crate) fn switch_to_double(&mut self, budget: f64) {
        self.single = false;
        self.budget = budget;
    }

    /// Mean iterations of a solve on a fresh factor (0 in double precision, and before the
    /// first single-precision one).
    fn fresh_mean(&self) -> f64 {
        let solves = self.fresh_solves.load(Ordering::Relaxed);
        if !self.single || solves == 0 {
            return 0.0;
        }
        self.fresh_iterations.load(Ordering::Relaxed) as f64 / solves as f64
    }

    /// A GMRES solve on a fresh single-precision factor took `iterations`.
    pub(crate) fn fresh_done(&self, iterations: usize) {
        self.fresh_solves.fetch_add(1, Ordering::Relaxed);
        self.fresh_iterations.fetch_add(iterations, Ordering::Relaxed);
    }

    /// The tolerance of a GMRES solve on a fresh single-precision factor (the stale
    /// solves'; see [`Self::iteration_cap`]).
    pub(crate) fn tolerance(&self) -> f64 {
        let direct = f64::from_bits(self.direct_residual.load(Ordering::Relaxed));
        KRYLOV_TOLERANCE.max(4.0 * direct).min(1e-10)
    }

    /// Forces the mode (tests).
    #[cfg(test)]
    pub(crate) fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
    }

    /// The factor is being recomputed: no valid factor until [`Self::factorised`].
    pub(crate) fn invalidate(&mut self) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        st.reference.clear();
        st.stale = false;
    }

    /// A numeric factorisation of the scaled values `scaled` (a new matrix) succeeded.
    pub(crate) fn factorised(&mut self, scaled: &[f64]) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        Self::reset(st, scaled);
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        self.matrices.fetch_add(1, Ordering::Relaxed);
    }

    /// The same after a refactorisation inside a solve (the state locked by the caller; the
    /// matrix was counted when it was kept).
    pub(crate) fn factorised_locked(&self, st: &mut KeptState, scaled: &[f64]) {
        Self::reset(st, scaled);
        self.factorizations.fetch_add(1, Ordering::Relaxed);
    }

    /// A refactorisation inside a solve failed: the factor holds no matrix (the next new
    /// matrix refactorises).
    pub(crate) fn lost(&self, st: &mut KeptState) {
        st.reference.clear();
        st.stale = false;
    }

    fn reset(st: &mut KeptState, scaled: &[f64]) {
        st.reference.clear();
        st.reference.extend_from_slice(scaled);
        st.stale = false;
        st.stale_iterations = 0.0;
    }

    /// The counts of a decision on the factor in `st` for a change of class
    /// `small`.
    fn costs(&self, st: &KeptState, small: bool) -> Costs {
        let class = usize::from(small);
        let solves = self.class_solves[class].load(Ordering::Relaxed);
        let matrices = self.matrices.load(Ordering::Relaxed);
        Costs {
            budget: self.budget,
            stale: st.stale_iterations,
            mean_iterations: (solves > 0)
                .then(|| self.class_iterations[class].load(Ordering::Relaxed) as f64 / solves as f64),
            small,
            solves_per_matrix: if matrices > 0 {
                self.solves.load(Ordering::Relaxed) as f64 / matrices as f64
            } else {
                1.0
            },
            fresh_iterations: self.fresh_mean(),
        }
    }

    /// The new scaled values `scaled` (with the factor's scaling, on its column pointers
    /// `col_ptr`): keep the factor or refactorise (see the module documentation).
    pub(crate) fn decide(&self, col_ptr: &[usize], scaled: &[f64]) -> Decision {
        let mut st = self.state.lock().unwrap_or_else(|p| p.into_inner());
        if self.mode == Mode::Off || st.reference.len() != scaled.len() {
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
        let small = delta <= SMALL_CHANGE * largest;
        let costs = self.costs(&st, small);
        let log = |what: &str| {
            if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                eprintln!(
                    "kept factor: {k} columns changed, largest change {:.1e} of the largest entry ({}); a \
                     factorisation is worth {:.0} iterations, {:.0} spent stale, {} iterations a solve, {:.2} solves \
                     a matrix: {what}",
                    delta / largest.max(f64::MIN_POSITIVE),
                    if small { "small" } else { "large" },
                    costs.budget,
                    costs.stale,
                    costs.mean_iterations.map_or("-".to_string(), |m| format!("{m:.1}")),
                    costs.solves_per_matrix
                );
            }
        };
        if k == 0 {
            // The factor's own matrix (the Krylov time spent on it stays counted).
            log("exact");
            st.stale = false;
            self.reused.fetch_add(1, Ordering::Relaxed);
            self.matrices.fetch_add(1, Ordering::Relaxed);
            return Decision::Exact;
        }
        // GMRES converges within k + 1 iterations of a change in k columns: a change as
        // large as the entries in more columns than the iterations it may take is a new
        // tangent.
        let limit = if self.mode == Mode::Always { f64::INFINITY } else { self.budget }.min(MAX_ITERATIONS as f64);
        if delta >= WHOLE_CHANGE * largest && (k + 1) as f64 > limit {
            log("refactorised (a change as large as the entries in more columns than the iterations allowed: a new tangent)");
            return Decision::Refactor;
        }
        if self.mode == Mode::ByCost && !keep_by_cost(k, &costs) {
            log("refactorised (the predicted Krylov iterations exceed what is left of a factorisation's worth)");
            return Decision::Refactor;
        }
        log("kept");
        st.stale = true;
        st.small = small;
        self.reused.fetch_add(1, Ordering::Relaxed);
        self.matrices.fetch_add(1, Ordering::Relaxed);
        Decision::Kept
    }

    /// The iterations the next stale solve may take and its tolerance; `None` when the
    /// factor has used up its budget (refactorise first).
    pub(crate) fn iteration_cap(&self, st: &KeptState) -> Option<(usize, f64)> {
        let tol = self.tolerance();
        if self.mode == Mode::Always {
            return Some((MAX_ITERATIONS, tol));
        }
        let left = self.budget - st.stale_iterations;
        if !(left >= MIN_ITERATIONS as f64) {
            return None;
        }
        // The first try of a class is capped at twice its prior: a change GMRES cannot
        // follow costs at most that before the factorisation it would have needed.
        let class = usize::from(st.small);
        let first = if self.class_solves[class].load(Ordering::Relaxed) == 0 {
            2 * if st.small { PRIOR_SMALL } else { PRIOR_ITERATIONS }
        } else {
            MAX_ITERATIONS
        };
        // A single-precision factor's solves take `m₀` iterations fresh: allowed on top.
        let fresh = self.fresh_mean().round() as usize;
        Some(((left as usize + fresh).clamp(MIN_ITERATIONS, MAX_ITERATIONS).min(first + fresh), tol))
    }

    /// A solve on this solver (direct or Krylov): counted for the solves per matrix.
    pub(crate) fn solve_started(&self) {
        self.solves.fetch_add(1, Ordering::Relaxed);
    }

    /// A stale solve took `iterations` (the first preconditioned solve and the final
    /// residual are one more).
    pub(crate) fn krylov_done(&self, st: &mut KeptState, iterations: usize) {
        // Beyond what a solve on a fresh factor takes (0 in double precision).
        st.stale_iterations += ((iterations + 1) as f64 - self.fresh_mean()).max(1.0);
        self.krylov_solves.fetch_add(1, Ordering::Relaxed);
        self.krylov_iterations.fetch_add(iterations, Ordering::Relaxed);
        let class = usize::from(st.small);
        self.class_solves[class].fetch_add(1, Ordering::Relaxed);
        self.class_iterations[class].fetch_add(iterations, Ordering::Relaxed);
    }

    /// A direct solve reached the relative scaled residual `residual`.
    pub(crate) fn direct_done(&self, residual: f64) {
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
            width: 0,
            free: 0,
        }
    }
}

/// CPU seconds of this process so far (user + system, from `/proc/self/stat`; NaN where it
/// cannot be read): the developer's log of a factorisation's arithmetic rate.
pub(crate) fn process_cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // The fields after the command name (which may hold spaces) closed by ')'.
    let rest = s.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok());
    // utime and stime are fields 14 and 15 of the line: 12 and 13 after ')' (index 11, 12).
    match (ticks(11), ticks(12)) {
        (Some(u), Some(t)) => (u + t) / 100.0,
        _ => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The cost rule on the run's counts: a 3D saddle point whose factorisation is worth 400
    // iterations keeps its factor for a large change at the prior 32 iterations, and while
    // the mean and the iterations already spent stale leave room; a 2D model whose
    // factorisation is worth 10 iterations refactorises a large change unless it is of rank
    // ≤ 8, keeps a small one at the prior 8 until a mean says otherwise; two solves per
    // matrix count twice; no budget (nothing predicted): refactorise. The budget itself: the
    // 58k penny example (nnz(L) 65.9M, 1.41e11 flops, nnz(A) 4.6M) is worth ~50 iterations,
    // its ×0.47 model (807.2M, 5.67e12, ~6e7) ~170.
    #[test]
    fn kept_factor_keeps_when_the_predicted_krylov_work_fits_in_a_factorisation() {
        let big = Costs {
            budget: 400.0,
            stale: 0.0,
            mean_iterations: None,
            small: false,
            solves_per_matrix: 1.0,
            fresh_iterations: 0.0,
        };
        assert!(keep_by_cost(20_000, &big));
        assert!(keep_by_cost(20_000, &Costs { mean_iterations: Some(150.0), ..big }));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(150.0), stale: 300.0, ..big }));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(250.0), solves_per_matrix: 2.0, ..big }));
        let small = Costs { budget: 10.0, ..big };
        assert!(!keep_by_cost(20_000, &small));
        assert!(keep_by_cost(8, &small));
        assert!(!keep_by_cost(9, &small));
        let small_change = Costs { small: true, ..small };
        assert!(keep_by_cost(20_000, &small_change));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(12.0), ..small_change }));
        assert!(!keep_by_cost(4, &Costs { budget: 0.0, ..big }));
        let penny = iterations_per_factorisation(1.41e11, 65_900_000, 4_600_000);
        assert!((45.0..60.0).contains(&penny), "58k penny: {penny}");
        let row = iterations_per_factorisation(5.67e12, 807_200_000, 60_000_000);
        assert!((150.0..190.0).contains(&row), "the 5e5 row: {row}");
        assert_eq!(iterations_per_factorisation(0.0, 1000, 100), 0.0);
        // A single-precision factor: half the flops, half the factor's traffic per
        // iteration (about the same worth), and what a fresh solve takes anyway is not
        // charged: 12 iterations where a fresh solve takes 5 fit in a budget of 8 left.
        let single = iterations_per_single_factorisation(5.67e12, 807_200_000, 60_000_000);
        assert!((150.0..200.0).contains(&single), "the 5e5 row in single precision: {single}");
        let mixed = Costs { budget: 10.0, stale: 2.0, mean_iterations: Some(12.0), ..big };
        assert!(!keep_by_cost(20_000, &mixed));
        assert!(keep_by_cost(20_000, &Costs { fresh_iterations: 5.0, ..mixed }));
    }
}
