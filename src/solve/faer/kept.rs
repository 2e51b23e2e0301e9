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
//! **Decided by cost, measured at run time.** A numeric factorisation took `t_f` seconds
//! (wall), one iteration (a preconditioner solve pair and a product) `t_i` (from the last
//! direct solve, then from the Krylov solves). A new matrix whose changed columns are all
//! contact unknowns keeps the factor when the predicted Krylov work of its solves fits in
//! what is left of one factorisation's time on this factor:
//! `s · (m + 1) · t_i ≤ t_f − t_stale`, with `m` the predicted iterations of one solve
//! (`min(k + 1, m̄)`, `k` the changed columns, `m̄` the mean iterations of this solver's
//! Krylov solves so far on changes of the same class: *small*, every entry changed by at
//! most [`SMALL_CHANGE`] of the largest entry (the friction thresholds of a later pass, the
//! last Newton iterations), or *large*; before the first of its class, [`PRIOR_SMALL`] or
//! [`PRIOR_ITERATIONS`]), `s` the solves per new
//! matrix measured on this solver (at least 1) and `t_stale` the Krylov seconds already spent
//! on this factor while stale. So a model whose factorisation costs few solves (2D, small
//! 3D) refactorises as without the kept factor, and a large 3D saddle point (one
//! factorisation worth hundreds of solves) keeps its first factor across the contact
//! iterations. Each stale solve may take the iterations the remaining budget allows (at
//! most [`MAX_ITERATIONS`]; the first of its class at most twice its prior, so that a change
//! GMRES cannot follow costs little); one that does not converge within them refactorises in
//! place and solves directly, so the answer is the direct solve's to the tolerance either
//! way. Its iterations count in its class's mean, which then keeps such changes out.
//!
//! Developer switch `FISSURE_KEPT_FACTOR` (read at the analysis): `0` refactorises at every
//! new matrix (the comparison path; `FISSURE_SPARSE_REFACTOR` and
//! `FISSURE_CONDENSED_REFACTOR` do the same), `1` keeps the factor whatever the cost (while
//! the changed columns are contact unknowns and each solve converges within
//! [`MAX_ITERATIONS`]: the tests, which must not depend on timings); unset or any other
//! value: by cost, as above.

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

/// Iterations a solve may take, at least and at most (the measured budget in between).
const MIN_ITERATIONS: usize = 8;
pub(crate) const MAX_ITERATIONS: usize = 150;

/// When a new matrix may keep the factor (`FISSURE_KEPT_FACTOR`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Refactorise at every new matrix.
    Off,
    /// Keep it when the predicted Krylov work fits in one factorisation's time.
    ByCost,
    /// Keep it whenever the changed columns are contact unknowns (tests).
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

/// The measured figures a decision reads ([`keep_by_cost`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Costs {
    /// Seconds of the factor's numeric factorisation.
    pub(crate) factor_s: f64,
    /// Seconds of one Krylov iteration (0: not measured).
    pub(crate) iteration_s: f64,
    /// Krylov seconds already spent on this factor while stale.
    pub(crate) stale_s: f64,
    /// Mean iterations of a Krylov solve on this solver, on changes of the new matrix's
    /// class (`None`: none yet).
    pub(crate) mean_iterations: Option<f64>,
    /// Whether the change is small ([`SMALL_CHANGE`]): the prior of `mean_iterations`.
    pub(crate) small: bool,
    /// Solves per new matrix on this solver (at least 1).
    pub(crate) solves_per_matrix: f64,
}

/// Whether a new matrix with `k` changed contact columns keeps the factor: the predicted
/// Krylov seconds of its solves, `s · (min(k + 1, m̄) + 1) · t_i`, fit in what is left of
/// the factorisation's time (see the module documentation).
pub(crate) fn keep_by_cost(k: usize, c: &Costs) -> bool {
    if !(c.iteration_s > 0.0 && c.factor_s > 0.0) {
        return false;
    }
    let prior = if c.small { PRIOR_SMALL } else { PRIOR_ITERATIONS };
    let m = c.mean_iterations.unwrap_or(prior as f64).min((k + 1) as f64);
    let predicted = c.solves_per_matrix.max(1.0) * (m + 1.0) * c.iteration_s;
    predicted <= c.factor_s - c.stale_s
}

/// The state of the kept factor that solves read and update.
pub(crate) struct KeptState {
    /// The factor is of an earlier matrix: solves go through GMRES.
    pub(crate) stale: bool,
    /// The change from the factor's matrix is small ([`SMALL_CHANGE`]).
    small: bool,
    /// Seconds of Krylov solves on this factor while stale.
    stale_seconds: f64,
    /// The scaled values `Ã₀` of the factorised matrix (empty: no valid factor).
    reference: Vec<f64>,
    /// Seconds of the last numeric factorisation.
    factor_s: f64,
}

/// See the module documentation.
pub(crate) struct KeptFactor {
    mode: Mode,
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
    /// Krylov solves and their iterations per class of change (large, small).
    class_solves: [AtomicUsize; 2],
    class_iterations: [AtomicUsize; 2],
    /// New matrices (factorised or kept) and solves, for the solves per matrix.
    matrices: AtomicUsize,
    solves: AtomicUsize,
}

impl KeptFactor {
    /// For a system whose contact unknowns are `contact` (one flag per unknown).
    pub(crate) fn new(contact: Vec<bool>) -> Self {
        KeptFactor {
            mode: Mode::from_env(),
            contact,
            iteration_s: AtomicU64::new(0f64.to_bits()),
            direct_residual: AtomicU64::new(0f64.to_bits()),
            state: Mutex::new(KeptState {
                stale: false,
                small: false,
                stale_seconds: 0.0,
                reference: Vec::new(),
                factor_s: 0.0,
            }),
            factorizations: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
            krylov_solves: AtomicUsize::new(0),
            krylov_iterations: AtomicUsize::new(0),
            class_solves: [AtomicUsize::new(0), AtomicUsize::new(0)],
            class_iterations: [AtomicUsize::new(0), AtomicUsize::new(0)],
            matrices: AtomicUsize::new(0),
            solves: AtomicUsize::new(0),
        }
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

    /// A numeric factorisation of the scaled values `scaled` (a new matrix) succeeded in
    /// `seconds`.
    pub(crate) fn factorised(&mut self, scaled: &[f64], seconds: f64) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        Self::reset(st, scaled, seconds);
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        self.matrices.fetch_add(1, Ordering::Relaxed);
    }

    /// The same after a refactorisation inside a solve (the state locked by the caller; the
    /// matrix was counted when it was kept).
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
        st.stale_seconds = 0.0;
    }

    /// The measured figures of a decision on the factor in `st` for a change of class
    /// `small`.
    fn costs(&self, st: &KeptState, small: bool) -> Costs {
        let class = usize::from(small);
        let solves = self.class_solves[class].load(Ordering::Relaxed);
        let matrices = self.matrices.load(Ordering::Relaxed);
        Costs {
            factor_s: st.factor_s,
            iteration_s: self.iteration_seconds(),
            stale_s: st.stale_seconds,
            mean_iterations: (solves > 0)
                .then(|| self.class_iterations[class].load(Ordering::Relaxed) as f64 / solves as f64),
            small,
            solves_per_matrix: if matrices > 0 {
                self.solves.load(Ordering::Relaxed) as f64 / matrices as f64
            } else {
                1.0
            },
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
                    "kept factor: {k} columns changed, largest change {:.1e} of the largest entry ({}); factorisation \
                     {:.2} s, iteration {:.1} ms, {:.1} s spent stale, {} iterations a solve, {:.2} solves a \
                     matrix: {what}",
                    delta / largest.max(f64::MIN_POSITIVE),
                    if small { "small" } else { "large" },
                    costs.factor_s,
                    costs.iteration_s * 1e3,
                    costs.stale_s,
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
        if self.mode == Mode::ByCost && !keep_by_cost(k, &costs) {
            log("refactorised (the predicted Krylov work exceeds what is left of a factorisation)");
            return Decision::Refactor;
        }
        log("kept");
        st.stale = true;
        st.small = small;
        self.reused.fetch_add(1, Ordering::Relaxed);
        self.matrices.fetch_add(1, Ordering::Relaxed);
        Decision::Kept
    }

    fn iteration_seconds(&self) -> f64 {
        f64::from_bits(self.iteration_s.load(Ordering::Relaxed))
    }

    /// The iterations the next stale solve may take and its tolerance; `None` when the
    /// factor has used up its budget (refactorise first).
    pub(crate) fn iteration_cap(&self, st: &KeptState) -> Option<(usize, f64)> {
        let direct = f64::from_bits(self.direct_residual.load(Ordering::Relaxed));
        let tol = KRYLOV_TOLERANCE.max(4.0 * direct).min(1e-10);
        if self.mode == Mode::Always {
            return Some((MAX_ITERATIONS, tol));
        }
        let (t, left) = (self.iteration_seconds(), st.factor_s - st.stale_seconds);
        if !(t > 0.0) || left < MIN_ITERATIONS as f64 * t {
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
        Some((((left / t) as usize).clamp(MIN_ITERATIONS, MAX_ITERATIONS).min(first), tol))
    }

    /// A solve on this solver (direct or Krylov): counted for the solves per matrix.
    pub(crate) fn solve_started(&self) {
        self.solves.fetch_add(1, Ordering::Relaxed);
    }

    /// A stale solve took `iterations` in `seconds`.
    pub(crate) fn krylov_done(&self, st: &mut KeptState, iterations: usize, seconds: f64) {
        st.stale_seconds += seconds;
        self.krylov_solves.fetch_add(1, Ordering::Relaxed);
        self.krylov_iterations.fetch_add(iterations, Ordering::Relaxed);
        let class = usize::from(st.small);
        self.class_solves[class].fetch_add(1, Ordering::Relaxed);
        self.class_iterations[class].fetch_add(iterations, Ordering::Relaxed);
        // The first preconditioned solve and the final residual are one more iteration.
        self.iteration_s.store((seconds / (iterations + 1) as f64).to_bits(), Ordering::Relaxed);
    }

    /// A direct solve took `seconds` with `steps` refinement steps, to the relative scaled
    /// residual `residual`.
    pub(crate) fn direct_done(&self, seconds: f64, steps: usize, residual: f64) {
        // Before any Krylov solve, a direct solve's pass stands for one iteration.
        if self.krylov_solves.load(Ordering::Relaxed) == 0 {
            self.iteration_s.store((seconds / (steps + 1) as f64).to_bits(), Ordering::Relaxed);
        }
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

    // The cost rule on measured figures: a 3D saddle point whose factorisation is worth 400
    // iterations keeps its factor for a large change at the prior 32 iterations, and while
    // the measured mean and the stale time leave room; a 2D model whose factorisation is
    // worth 10 iterations refactorises a large change unless it is of rank ≤ 8, keeps a small
    // one at the prior 8 until a measured mean says otherwise; two solves per matrix count
    // twice; nothing measured: refactorise.
    #[test]
    fn kept_factor_keeps_when_the_predicted_krylov_work_fits_in_a_factorisation() {
        let big = Costs {
            factor_s: 400.0,
            iteration_s: 1.0,
            stale_s: 0.0,
            mean_iterations: None,
            small: false,
            solves_per_matrix: 1.0,
        };
        assert!(keep_by_cost(20_000, &big));
        assert!(keep_by_cost(20_000, &Costs { mean_iterations: Some(150.0), ..big }));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(150.0), stale_s: 300.0, ..big }));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(250.0), solves_per_matrix: 2.0, ..big }));
        let small = Costs { factor_s: 10.0, ..big };
        assert!(!keep_by_cost(20_000, &small));
        assert!(keep_by_cost(8, &small));
        assert!(!keep_by_cost(9, &small));
        let small_change = Costs { small: true, ..small };
        assert!(keep_by_cost(20_000, &small_change));
        assert!(!keep_by_cost(20_000, &Costs { mean_iterations: Some(12.0), ..small_change }));
        assert!(!keep_by_cost(4, &Costs { iteration_s: 0.0, ..big }));
    }
}
