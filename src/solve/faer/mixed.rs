//! Mixed precision: the whole-system Cholesky (`LLᵀ`) or `LDLᵀ` factor of the scaled
//! matrix computed in single precision (half the memory of `L`, and faer's f32 dense
//! kernels do about twice the flops of its f64 ones on AVX2), each solve brought back to
//! the double-precision accuracy by iterations in double precision preconditioned by that
//! factor (conjugate gradients for `LLᵀ`, [`super::refine::solve_pcg`]; for the indefinite
//! `LDLᵀ` of a contact saddle point, GMRES when the factor is the kept factor of a contact
//! system, [`super::kept`], whose solves are GMRES already, and iterative refinement
//! otherwise, [`super::refine::solve_refined`]), and the double-precision factor computed
//! instead when the single-precision one breaks down or the iterations fall short.
//!
//! Entry point: [`MixedCholesky`], held by the solver as `Factor::Mixed`
//! ([`super::FaerSolver`]); the choice between double and mixed precision is
//! [`mixed_wanted`].

use super::cholesky::{for_each_pivot, numeric_llt, pivot_threshold, LDLT_DELTA};
use super::memory::try_zeroed_vec;
use crate::solve::backend::{LinearError, LinearMethod, Precision};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::sparse::linalg::cholesky::{LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::RealField;
use faer::{Conj, MatMut, Par, Side, Spec};
use rayon::prelude::*;
use std::sync::{Mutex, OnceLock, RwLock};

/// `[solver] precision = "auto"` chooses mixed precision for whole-system Cholesky
/// factors with at least this many entries in `L` (below, the numeric phase takes about
/// a second or less and the iterations of each solve would eat what it gains; the value
/// is a judgement, not a measured crossover). Measured (docs/performance.md, "Mixed
/// precision"): at 3e5 dofs (390M entries) the numeric phase's CPU time went from 97 to
/// 46 s and its peak from 4843 to 3094 MB, the solve taking 3 iterations.
pub const MIXED_AUTO_MIN_NNZ: usize = 20_000_000;

/// Conjugate-gradient iterations allowed to reach the double-precision residual before
/// the double-precision factor is computed instead. The 3e5-dof hex8 bench needed 3 (the
/// single-precision factor is an excellent preconditioner unless κ(S A S) ε₃₂ approaches 1).
pub(super) const MIXED_MAX_ITERATIONS: usize = 20;

/// `[solver] precision = "auto"` chooses mixed precision for the whole-system `LDLᵀ` kept
/// across the contact iterations of a contact saddle point ([`super::kept`]) with at
/// least this many entries in `L`. Each of its solves is then a GMRES solve preconditioned
/// by the single-precision factor (a few iterations even on a fresh factor, where the
/// double-precision factor solves directly), against half the numeric factorisation: it
/// pays when a factorisation is worth many iterations, i.e. on large 3D factors
/// (`docs/performance.md`, "The 3D penny with contact at 5e5 unknowns: a mixed-precision
/// kept factor"). The example's sliding penny (`examples/penny_crack_contact_3d.toml`,
/// 65.9M entries, a factorisation worth ~50 iterations) stays in double precision; its
/// × 0.6 model (333M) and the 5e5 bench row (807M) take mixed precision.
pub const MIXED_AUTO_MIN_NNZ_LDLT: usize = 200_000_000;

/// Whether a whole-system factor of `method` with `nnz` entries is factorised in single
/// precision for the `precision` asked; `kept`: the factor is a contact system's kept
/// factor ([`super::kept`]), whose solves are GMRES. `auto` keeps any other `LDLᵀ` in double
/// precision: the single-precision `LDLᵀ` of an X-FEM contact saddle point with
/// tip-enriched unknowns can overflow to a non-finite pivot (the 2D inclined crack with
/// friction, the 5e5-unknown penny with the example's tip radius 0.25) or, with a larger
/// regularisation threshold, perturb too many pivots for iterative refinement (325 on the
/// 2D crack), and falls back (`docs/performance.md`, "The 3D penny with contact at 5e5
/// unknowns, seventh session"); the kept factor's GMRES is the robust solve, and its
/// fallbacks are the same.
pub(super) fn mixed_wanted(precision: Precision, method: LinearMethod, nnz: usize, kept: bool) -> bool {
    match (precision, method) {
        (_, LinearMethod::Lu) | (Precision::Double, _) => false,
        (Precision::Mixed, _) => true,
        (Precision::Auto, LinearMethod::Cholesky) => nnz >= MIXED_AUTO_MIN_NNZ,
        (Precision::Auto, LinearMethod::Ldlt) => kept && nnz >= MIXED_AUTO_MIN_NNZ_LDLT,
    }
}

/// The developer's fault switch `FISSURE_FAULT_MIXED` (read once, at the analysis): `pivot`
/// makes every single-precision factorisation report a non-positive pivot, `solve` makes
/// every preconditioned solve fall short of the residual (the preconditioner returns
/// zero, which neither conjugate gradients, nor iterative refinement, nor GMRES can use:
/// GMRES is blind to a negated preconditioner), so that the fallback to the
/// double-precision factor is exercised by the tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Fault {
    None,
    Pivot,
    Solve,
}

impl Fault {
    fn from_env() -> Fault {
        match std::env::var("FISSURE_FAULT_MIXED").as_deref() {
            Ok("pivot") => Fault::Pivot,
            Ok("solve") => Fault::Solve,
            _ => Fault::None,
        }
    }
}

/// A Cholesky or `LDLᵀ` factor in single precision, with the double-precision factor
/// computed on demand (a fallback in a solve, which has only shared access to the solver).
pub(super) struct MixedCholesky {
    pub(super) symbolic: SymbolicCholesky<usize>,
    /// `LDLᵀ`: the expected pivot signs (+1 primal, −1 multiplier) of the dynamic
    /// regularisation, as in the double-precision path; `None`: `LLᵀ`.
    signs: Option<Vec<i8>>,
    /// Values of `L` in single precision (behind a lock: a kept factor refactorises inside
    /// a solve, `kept.rs`).
    l32: RwLock<Vec<f32>>,
    /// The double-precision factor of the same values, after a fallback.
    double: OnceLock<Vec<f64>>,
    /// Serialises the computation of `double`.
    building: Mutex<()>,
    /// Why the double-precision factor was computed.
    reason: OnceLock<&'static str>,
    /// Scratch of the double-precision numeric phase (the single-precision one needs less).
    pub(super) factor_req: StackReq,
    pub(super) fault: Fault,
}

impl MixedCholesky {
    /// The factor of a symbolic analysis, its single-precision values allocated (zeroed);
    /// `signs`: an `LDLᵀ` with these expected pivot signs, `None`: `LLᵀ`.
    pub(super) fn new(
        symbolic: SymbolicCholesky<usize>,
        factor_req: StackReq,
        signs: Option<Vec<i8>>,
    ) -> Result<Self, LinearError> {
        let l32 = try_zeroed_vec::<f32>(symbolic.len_val())?;
        Ok(MixedCholesky {
            symbolic,
            signs,
            l32: RwLock::new(l32),
            double: OnceLock::new(),
            building: Mutex::new(()),
            reason: OnceLock::new(),
            factor_req,
            fault: Fault::from_env(),
        })
    }

    /// The double-precision factor, if a fallback computed it, and why.
    pub(super) fn double(&self) -> Option<(&[f64], &'static str)> {
        self.double.get().map(|d| (d.as_slice(), self.reason.get().copied().unwrap_or("")))
    }

    /// Takes the symbolic factor and the double-precision values out (after a fallback,
    /// the solver keeps the plain double-precision factor).
    pub(super) fn into_double(self) -> Option<(SymbolicCholesky<usize>, Vec<f64>, &'static str)> {
        let reason = self.reason.get().copied().unwrap_or("");
        let MixedCholesky { symbolic, double, .. } = self;
        double.into_inner().map(|d| (symbolic, d, reason))
    }

    /// The symbolic factor and the single-precision values, given up for the plain
    /// double-precision factor.
    pub(super) fn into_symbolic(self) -> SymbolicCholesky<usize> {
        self.symbolic
    }

    /// Whether the factor is an `LDLᵀ`.
    pub(super) fn is_ldlt(&self) -> bool {
        self.signs.is_some()
    }

    /// The single-precision numeric phase of the scaled values `scaled` (double
    /// precision, on the pattern `col_ptr`, `row_idx`): the number of `LDLᵀ` pivots
    /// regularised (0 for `LLᵀ`). `Err(reason)` when it broke down (`LLᵀ`: a non-positive
    /// or tiny pivot; `LDLᵀ`: a zero or non-finite pivot): the caller computes the
    /// double-precision factor.
    pub(super) fn factorize(
        &self,
        col_ptr: &[usize],
        row_idx: &[usize],
        scaled: &[f64],
        par: Par,
        stack: &mut MemStack,
    ) -> Result<usize, &'static str> {
        let n = col_ptr.len() - 1;
        let values: Vec<f32> = scaled.par_iter().map(|&v| v as f32).collect();
        let a = SparseColMatRef::new(SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx), &values[..]);
        let mut l32 = self.l32.write().unwrap_or_else(|p| p.into_inner());
        if let Some(signs) = &self.signs {
            let result = numeric_ldlt::<f32>(&self.symbolic, &mut l32, a, signs, par, stack);
            return match (result, self.fault) {
                (_, Fault::Pivot) => Err("a zero pivot in single precision (injected)"),
                (Err(_), _) => Err("a zero or non-finite pivot in single precision"),
                (Ok(count), _) => Ok(count),
            };
        }
        let result = numeric_llt::<f32>(&self.symbolic, &mut l32, a, par, stack);
        match (result, self.fault) {
            (_, Fault::Pivot) => Err("a non-positive pivot in single precision (injected)"),
            (Err((_, d)), _) if d.is_nan() => Err("a non-positive pivot in single precision"),
            (Err(_), _) => Err("a pivot in single precision below the threshold"),
            (Ok(()), _) => Ok(0),
        }
    }

    /// Applies the single-precision factor to `x` in place (converted in and out), or the
    /// double-precision one once it exists.
    pub(super) fn solve(&self, x: &mut [f64], par: Par, stack: &mut MemStack) {
        let n = x.len();
        if let Some(l) = self.double.get() {
            let x = MatMut::from_column_major_slice_mut(x, n, 1);
            if self.is_ldlt() {
                LdltRef::new(&self.symbolic, l).solve_in_place_with_conj(Conj::No, x, par, stack);
            } else {
                LltRef::new(&self.symbolic, l).solve_in_place_with_conj(Conj::No, x, par, stack);
            }
            return;
        }
        let mut x32: Vec<f32> = x.iter().map(|&v| v as f32).collect();
        let x32_mat = MatMut::from_column_major_slice_mut(&mut x32, n, 1);
        let l32 = self.l32.read().unwrap_or_else(|p| p.into_inner());
        if self.is_ldlt() {
            LdltRef::new(&self.symbolic, &l32).solve_in_place_with_conj(Conj::No, x32_mat, par, stack);
        } else {
            LltRef::new(&self.symbolic, &l32).solve_in_place_with_conj(Conj::No, x32_mat, par, stack);
        }
        let keep = if self.fault == Fault::Solve { 0.0 } else { 1.0 };
        for (xi, v) in x.iter_mut().zip(&x32) {
            *xi = keep * *v as f64;
        }
    }

    /// Computes the double-precision factor of the scaled values (a solve's fallback:
    /// shared access, one thread computes it), with `reason` recorded and logged on the
    /// standard error. `Err((unknown, d))`: the double-precision factor is not positive
    /// definite either (see [`numeric_llt`]); a memory error when it does not fit.
    pub(super) fn compute_double(
        &self,
        col_ptr: &[usize],
        row_idx: &[usize],
        scaled: &[f64],
        par: Par,
        reason: &'static str,
    ) -> Result<Result<(), (usize, f64)>, LinearError> {
        let _guard = self.building.lock().unwrap_or_else(|p| p.into_inner());
        if self.double.get().is_some() {
            return Ok(Ok(()));
        }
        // The run reports it as a warning (`linear_solver.precision_fallback`); the
        // developer's log shows it as it happens.
        if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
            eprintln!("fissure: mixed precision abandoned ({reason}): the factor is computed in double precision");
        }
        let n = col_ptr.len() - 1;
        let mut l = try_zeroed_vec::<f64>(self.symbolic.len_val())?;
        let mut mem = MemBuffer::try_new(self.factor_req).map_err(|_| LinearError::OutOfMemory)?;
        let a = SparseColMatRef::new(SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx), scaled);
        if let Some(signs) = &self.signs {
            if let Err(unknown) = numeric_ldlt::<f64>(&self.symbolic, &mut l, a, signs, par, MemStack::new(&mut mem)) {
                return Err(LinearError::ZeroPivot { unknown });
            }
        } else if let Err(e) = numeric_llt::<f64>(&self.symbolic, &mut l, a, par, MemStack::new(&mut mem)) {
            return Ok(Err(e));
        }
        let _ = self.reason.set(reason);
        let _ = self.double.set(l);
        Ok(Ok(()))
    }
}

/// The numeric `LDLᵀ` of the scaled matrix `a` into `l_values` (double or single
/// precision) with the dynamic regularisation of the double-precision path (pivots of the
/// wrong sign or below [`pivot_threshold`] replaced by `±LDLT_DELTA`): the number of
/// pivots so replaced, or `Err(unknown)` (original numbering) on a zero or non-finite
/// pivot. In single precision these values were measured against others
/// (`FISSURE_LDLT_F32=delta,epsilon`, a developer switch): with them the sliding penny of
/// `examples/penny_crack_contact_3d.toml` factorises and its solves refine in 5–7 steps;
/// with δ = √ε₃₂ and ε = 100 ε₃₂ it regularises 7 pivots there and the refinement stalls;
/// the 2D inclined crack with friction overflows (a non-finite pivot) with every δ from
/// 1e-8 to 3.45e-4 and ε from 1e-9 to 1e-7, and stalls with 325 pivots regularised at
/// ε = 1.2e-5 (`docs/performance.md`, "The 3D penny with contact at 5e5 unknowns,
/// seventh session").
fn numeric_ldlt<T: RealField + Copy + Into<f64>>(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [T],
    a: SparseColMatRef<'_, usize, T>,
    signs: &[i8],
    par: Par,
    stack: &mut MemStack,
) -> Result<usize, usize> {
    let n = a.nrows();
    let single = std::mem::size_of::<T>() == 4;
    let (mut delta, mut epsilon) = (LDLT_DELTA, pivot_threshold(n));
    // Developer switch (measurements): `FISSURE_LDLT_F32=delta,epsilon`.
    if let (true, Ok(v)) = (single, std::env::var("FISSURE_LDLT_F32")) {
        if let Some((d, e)) = v.split_once(',') {
            delta = d.parse().unwrap_or(delta);
            epsilon = e.parse().unwrap_or(epsilon);
        }
    }
    let delta = T::from_f64_impl(delta);
    let regularisation = LdltRegularization {
        dynamic_regularization_signs: Some(signs),
        dynamic_regularization_delta: delta,
        dynamic_regularization_epsilon: T::from_f64_impl(epsilon),
    };
    let result =
        symbolic.factorize_numeric_ldlt::<T>(l_values, a, Side::Lower, regularisation, par, stack, Spec::default());
    if let Err(LdltError::ZeroPivot { index }) = result {
        // faer's simplicial path reports the pivot one-based.
        let simplicial = matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
        let p = if simplicial { index.saturating_sub(1) } else { index }.min(n - 1);
        return Err(symbolic.perm().map_or(p, |perm| perm.arrays().0[p]));
    }
    let delta: f64 = delta.into();
    let mut count = 0;
    for_each_pivot(symbolic, l_values, |_, d| {
        if d.abs() == delta {
            count += 1;
        }
    });
    Ok(count)
}
