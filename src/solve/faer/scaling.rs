//! The symmetric scaling `S` of a system: every method factorises `S A S` (unit diagonal
//! on the primal unknowns, unit largest coupling on the multipliers), which makes the
//! pivot thresholds relative and independent of units.
//!
//! Entry points: [`compute_scaling`] (the factors `S`), [`fill_scaled`] (`S A S`) and
//! [`row_sum_norm`] (‖S A S‖∞); [`ScaledSystem`] is the scaled matrix as the refinement
//! reads it.

use crate::solve::backend::{LinearError, LinearMethod};
use rayon::prelude::*;

/// The scaled matrix `S A S` on its pattern, with `S` and ‖S A S‖∞.
pub(super) struct ScaledSystem<'a> {
    pub(super) col_ptr: &'a [usize],
    pub(super) row_idx: &'a [usize],
    /// Values of `S A S`, in the pattern's order.
    pub(super) values: &'a [f64],
    /// The diagonal of `S`.
    pub(super) scale: &'a [f64],
    /// ‖S A S‖∞ (largest absolute row sum).
    pub(super) norm_inf: f64,
}

/// What the scaling reads of a system besides its values.
pub(super) struct Structure<'a> {
    pub(super) col_ptr: &'a [usize],
    pub(super) row_idx: &'a [usize],
    /// Position of each diagonal entry in the value array, if stored.
    pub(super) diag_pos: &'a [Option<usize>],
    /// Unknowns `n_primal..` are multipliers.
    pub(super) n_primal: usize,
    pub(super) method: LinearMethod,
}

/// The symmetric scaling, into `scale`: `1/√a_jj` on primal unknowns with a nonzero
/// diagonal (the largest coupling otherwise), and `1/max_i |a_ij s_i|` over primal `i` on
/// multipliers, so that scaled couplings are O(1) and thresholds are relative. Only the
/// primal and/or the multiplier part is recomputed, as asked; an empty row, or a
/// non-positive diagonal for Cholesky, is an error.
pub(super) fn compute_scaling(
    st: &Structure<'_>,
    scale: &mut [f64],
    values: &[f64],
    primal: bool,
    multipliers: bool,
) -> Result<(), LinearError> {
    let n = scale.len();
    let n_primal = st.n_primal;
    let (cp, diag_pos, method) = (st.col_ptr, st.diag_pos, st.method);
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
    let last = if multipliers { n } else { n_primal };
    let new: Vec<f64> = (first..last).into_par_iter().map(check).collect::<Result<_, _>>()?;
    for (s, v) in scale[first..last].iter_mut().zip(new) {
        if !v.is_nan() {
            *s = v;
        }
    }
    for j in n_primal..n {
        if !multipliers {
            break;
        }
        let mut coupling = 0.0f64;
        let mut other = 0.0f64;
        let col = cp[j]..cp[j + 1];
        for (&a, &i) in values[col.clone()].iter().zip(&st.row_idx[col]) {
            if i < n_primal {
                coupling = coupling.max((a * scale[i]).abs());
            } else {
                other = other.max(a.abs());
            }
        }
        let t = coupling.max(other.sqrt());
        scale[j] = 1.0 / t;
    }
    Ok(())
}

/// ‖S A S‖∞ (largest absolute row sum) of the scaled values `scaled`; with `interior`, the
/// largest over the rows so marked only. `symmetric` values are summed by columns in
/// parallel; otherwise `scratch` (one entry per unknown) holds the row sums.
pub(super) fn row_sum_norm(
    col_ptr: &[usize],
    row_idx: &[usize],
    scaled: &[f64],
    symmetric: bool,
    scratch: &mut [f64],
    interior: Option<&[bool]>,
) -> f64 {
    let n = col_ptr.len() - 1;
    if symmetric {
        // Symmetric values: the row sums are the column sums, in parallel.
        let cp = col_ptr;
        return (0..n)
            .into_par_iter()
            .filter(|&j| interior.is_none_or(|m| m[j]))
            .map(|j| scaled[cp[j]..cp[j + 1]].iter().map(|v| v.abs()).sum::<f64>())
            .reduce(|| 0.0, f64::max);
    }
    let row_sum = scratch;
    row_sum.fill(0.0);
    for (&a, &i) in scaled.iter().zip(row_idx) {
        row_sum[i] += a.abs();
    }
    row_sum.iter().enumerate().filter(|(i, _)| interior.is_none_or(|m| m[*i])).fold(0.0, |m: f64, (_, &v)| m.max(v))
}

/// `out = S A S` for the values `A` and the scaling `S`.
pub(super) fn fill_scaled(col_ptr: &[usize], row_idx: &[usize], scale: &[f64], values: &[f64], out: &mut [f64]) {
    let (cp, ri) = (col_ptr, row_idx);
    for_column_blocks(cp, out, |cols, out| {
        let base = cp[cols.start];
        for j in cols {
            let sj = scale[j];
            for k in cp[j]..cp[j + 1] {
                out[k - base] = scale[ri[k]] * values[k] * sj;
            }
        }
    });
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
