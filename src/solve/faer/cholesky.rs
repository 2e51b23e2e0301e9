//! faer's supernodal (or simplicial) Cholesky `LLᵀ` and LDLᵀ of a whole system: the
//! symbolic phase with the orderings of [`crate::solve::ordering`], the pivot threshold
//! and the figures read off the symbolic factor (flops, entries, pivots).
//!
//! Entry point: [`symbolic_cholesky`]; the numeric phase and its pivot checks run in the
//! solver ([`super::FaerSolver::factorize`]).

use super::memory::try_zeroed_vec;
use crate::solve::backend::{LinearError, LinearMethod};
use crate::solve::ordering::{multipliers_after_primal_ordering, primal_ordering, Order};
use faer::dyn_stack::MemStack;
use faer::dyn_stack::StackReq;
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SymbolicSupernodalParams;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::RealField;
use faer::{Par, Side, Spec};

/// Pivot threshold (relative to the unit diagonal of the scaled matrix), `10 max(n, 1000) ε`
/// (2.2e-9 for 1M unknowns). Cholesky reports a pivot below it as "not positive definite";
/// LDLᵀ replaces a pivot below it (or of the wrong sign) by `±LDLT_DELTA` and lets
/// iterative refinement remove the perturbation. Measured: singular matrices (pure
/// Neumann Laplacians, 2D up to 1M unknowns, 3D up to 216k) leave round-off pivots of
/// about 0.1 n ε, where well-posed stiffness matrices have pivots of order 0.1.
pub(super) fn pivot_threshold(n: usize) -> f64 {
    10.0 * (n.max(1000) as f64) * f64::EPSILON
}
/// The value given to regularised LDLᵀ pivots (≈ √ε: balances the perturbation against
/// the growth it causes, so that refinement converges in a step or two).
pub(super) const LDLT_DELTA: f64 = 1e-8;

/// The symbolic phase of a whole-system Cholesky or LDLᵀ: the symbolic factor, its
/// (zeroed) values, the scratch sizes of the numeric phase and of a solve, and the entries
/// of `L`.
pub(super) struct SymbolicAnalysis {
    pub(super) symbolic: SymbolicCholesky<usize>,
    pub(super) l_values: Vec<f64>,
    pub(super) factor_req: StackReq,
    pub(super) solve_req: StackReq,
    pub(super) nnz: usize,
}

/// faer's symbolic Cholesky / LDLᵀ on the whole system; `par` becomes parallel when
/// the fronts are large.
#[allow(clippy::too_many_arguments)]
pub(super) fn symbolic_cholesky(
    method: LinearMethod,
    a: SymbolicSparseColMatRef<'_, usize>,
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    order: Order<'_>,
    par: &mut Par,
) -> Result<SymbolicAnalysis, LinearError> {
    let custom = if method == LinearMethod::Cholesky {
        primal_ordering(col_ptr, row_idx, n, order)?
    } else {
        multipliers_after_primal_ordering(col_ptr, row_idx, n, n_primal, order)?
    };
    symbolic_cholesky_ordered(method, a, &custom, order, par)
}

/// [`symbolic_cholesky`] in a given ordering (`(forward, inverse)`, `forward[new] = old`:
/// the one [`symbolic_cholesky`] would compute, found already by the condensation's
/// decision, [`super::condensed::condensed_factor`]).
pub(super) fn symbolic_cholesky_ordered(
    method: LinearMethod,
    a: SymbolicSparseColMatRef<'_, usize>,
    custom: &(Vec<usize>, Vec<usize>),
    order: Order<'_>,
    par: &mut Par,
) -> Result<SymbolicAnalysis, LinearError> {
    let n = a.nrows();
    let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&custom.0, &custom.1, n));
    let params = CholeskySymbolicParams { supernodal_params: supernode_relax(order), ..Default::default() };
    let symbolic = factorize_symbolic_cholesky(a, Side::Lower, ordering, params)?;
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
    Ok(SymbolicAnalysis { symbolic, l_values, factor_req, solve_req, nnz })
}

/// Supernode amalgamation of 3D (and point-less) factors: two adjacent supernodes of `n`
/// columns in all are merged when `n ≤ 16`, or `n ≤ 64` with at most 80% of the merged
/// block's entries explicit zeros, or `n ≤ 192` with at most 10%, or at most 5% whatever
/// `n`: faer's default table ((4, 1.0), (16, 0.8), (48, 0.1), (∞, 0.05)) with the column
/// counts × 4. In 3D the nodes' three dofs already make supernodes of three columns or
/// more, so faer's table merges almost nothing (27 419 supernodes on the 3e5-dof hex8
/// block with it and without any amalgamation); this one leaves 20 271 for 0.6% more
/// entries in `L` and 0.1% more flops. Measured on a loaded machine (`docs/performance.md`,
/// "The 3D time floors, fourth session"): the single-precision numeric phase took 43–47
/// CPU s against 46–51 (a tie in wall time on one build), and the mixed-precision solve
/// 2 PCG iterations instead of 3 in every run. 2D factors keep faer's table (their
/// figures were measured with it). `FISSURE_SUPERNODE_RELAX=faer` (developer switch, read
/// at each analysis) gives faer's table everywhere, for comparisons on one build.
const WIDE_RELAX: &[(usize, f64)] = &[(16, 1.0), (64, 0.8), (192, 0.1), (usize::MAX, 0.05)];

/// The amalgamation table for a factor ordered by `order` (see [`WIDE_RELAX`]).
fn supernode_relax(order: Order<'_>) -> SymbolicSupernodalParams<'static> {
    let two_d = order.points.is_some_and(|p| p.dim == 2);
    let faer = std::env::var("FISSURE_SUPERNODE_RELAX").is_ok_and(|v| v == "faer");
    if two_d || faer {
        SymbolicSupernodalParams::default()
    } else {
        SymbolicSupernodalParams { relax: Some(WIDE_RELAX) }
    }
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
pub(super) fn factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
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

/// Flops of the numeric Cholesky / LDLᵀ of a pattern (both triangles stored) in the
/// ordering `(fwd, inv)` (`fwd[new] = old`), predicted without the symbolic factor: the
/// column counts `c_j` of `L` (elimination tree, faer's `prefactorize_symbolic_cholesky`)
/// give `Σ c_j²`, which is [`factor_flops`]' `c³/3 + c² r + c r²` summed column by column
/// (without the explicit zeros of the supernodes' amalgamation). Costs a pass over the
/// entries of `L` (indices only) and the upper triangle of the permuted pattern.
pub(super) fn predicted_flops(col_ptr: &[usize], row_idx: &[usize], fwd: &[usize], inv: &[usize]) -> f64 {
    use faer::sparse::linalg::cholesky::simplicial::{
        prefactorize_symbolic_cholesky, prefactorize_symbolic_cholesky_scratch,
    };
    let n = fwd.len();
    if n == 0 {
        return 0.0;
    }
    let upper = |jn: usize| {
        let jo = fwd[jn];
        row_idx[col_ptr[jo]..col_ptr[jo + 1]].iter().map(|&i| inv[i]).filter(move |&i| i < jn)
    };
    let mut ptr = Vec::with_capacity(n + 1);
    ptr.push(0usize);
    for jn in 0..n {
        ptr.push(ptr[jn] + upper(jn).count());
    }
    let mut idx = Vec::with_capacity(ptr[n]);
    for jn in 0..n {
        idx.extend(upper(jn));
    }
    let a = SymbolicSparseColMatRef::new_unsorted_checked(n, n, &ptr, None, &idx);
    let mut etree = vec![0isize; n];
    let mut counts = vec![0usize; n];
    let mut mem = faer::dyn_stack::MemBuffer::new(prefactorize_symbolic_cholesky_scratch::<usize>(n, idx.len()));
    prefactorize_symbolic_cholesky(&mut etree, &mut counts, a, MemStack::new(&mut mem));
    counts.iter().map(|&c| (c as f64) * (c as f64)).sum()
}

/// Entries of the lower triangle (diagonal included) of the factor.
pub(super) fn factor_nnz(symbolic: &SymbolicCholesky<usize>) -> usize {
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
/// `L_kk` for `LLᵀ`, `D_k` for `LDLᵀ` (in double or single precision).
pub(super) fn for_each_pivot<T: RealField + Copy + Into<f64>>(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &[T],
    mut f: impl FnMut(usize, f64),
) {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let col_ptr = s.col_ptr();
            for k in 0..s.ncols() {
                f(k, l_values[col_ptr[k]].into());
            }
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let l = supernodal::SupernodalLltRef::<usize, T>::new(s, l_values);
            for k in 0..s.n_supernodes() {
                let node = l.supernode(k);
                let block = node.val();
                for j in 0..block.ncols() {
                    f(node.start() + j, block[(j, j)].into());
                }
            }
        }
    }
}

/// The numeric `LLᵀ` of the scaled matrix `a` into `l_values` (double or single
/// precision) with the pivot checks of Cholesky: a non-positive pivot (faer's verdict),
/// or a squared pivot below [`pivot_threshold`] (numerically singular: a rigid-body
/// motion left free), is `Err((unknown, d))` with the original index of the unknown and
/// the scaled pivot `d` (NaN when faer stopped on it).
pub(super) fn numeric_llt<T: RealField + Copy + Into<f64>>(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [T],
    a: SparseColMatRef<'_, usize, T>,
    par: Par,
    stack: &mut MemStack,
) -> Result<(), (usize, f64)> {
    let n = a.nrows();
    let fwd = |p: usize| symbolic.perm().map_or(p, |perm| perm.arrays().0[p]);
    let simplicial = matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
    let result = symbolic.factorize_numeric_llt::<T>(
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
        return Err((fwd(p), f64::NAN));
    }
    let mut worst: Option<(usize, f64)> = None;
    for_each_pivot(symbolic, l_values, |p, l| {
        let d = l * l;
        if worst.is_none_or(|(_, w)| !(d >= w)) {
            worst = Some((p, d));
        }
    });
    match worst {
        Some((p, d)) if !(d >= pivot_threshold(n)) => Err((fwd(p), d)),
        _ => Ok(()),
    }
}
