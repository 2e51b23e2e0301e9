//! A Cholesky factorisation split at the top separator of a nested-dissection ordering,
//! so that the two halves are factorised (and solved) in parallel.
//!
//! Entry point: [`SplitCholesky`], used by [`super::FaerSolver`] for large 2D
//! systems.
//!
//! With the unknowns ordered `[part 1, part 2, separator]` and no coupling between the
//! parts, `A = [A11 0 A13; 0 A22 A23; A31 A32 A33]`. Each half `M_k = [Akk Ak3; A3k A33]`
//! is a principal submatrix of `A`, hence positive definite, and its Cholesky factor
//! `[Lkk 0; L3k T_k]` gives `T_k T_kᵀ = A33 − A3k Akk⁻¹ Ak3`. The Schur complement of `A` on
//! the separator is then `S = T_1 T_1ᵀ + T_2 T_2ᵀ − A33` (dense, small in 2D), and
//!
//! - forward: `L_k [y_k; w_k] = [b_k; 0]` gives `y_k = Lkk⁻¹ b_k` and `L3k y_k = −T_k w_k`;
//! - separator: `S x3 = b3 + T_1 w_1 + T_2 w_2`;
//! - backward: `L_kᵀ [x_k; v] = [y_k; T_kᵀ x3]` gives `x_k` (and `v = x3`).
//!
//! faer's supernodal factorisation runs its supernodes one after the other; the two halves
//! here are independent, so two threads each factorise one with sequential kernels. The
//! price is the dense work on the separator (two more `n3³/3` factorisations and products),
//! a few percent in 2D, which is why the solver uses it for 2D meshes only.

use super::memory::try_zeroed_vec;
use crate::solve::backend::OrderingChoice;
use crate::solve::ordering::Order;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{FaerError, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, Side, Spec};
use rayon::prelude::*;

/// One half: the lower triangle of `M_k` in its own numbering (part, then its trailing
/// unknowns: those of the separator block its part couples to).
pub(super) struct Half {
    /// Unknowns of the part (the trailing block follows).
    pub(super) nk: usize,
    /// The half's trailing unknowns, as positions in the separator block (ascending): the
    /// whole block in [`SplitCholesky`]; in the condensed factor only the rows the part
    /// couples to (the others get no update from it).
    pub(super) trail: Vec<usize>,
    /// First position of the part in the global (permuted) order.
    offset: usize,
    /// First position of the separator in the global order (`n1 + n2`).
    sep_start: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Index in the full value array of every entry.
    src: Vec<usize>,
    values: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    /// The factor's values in double precision (empty while the factor is single).
    l_values: Vec<f64>,
    /// The factor's values in single precision (empty while the factor is double): the
    /// condensed factor's bulk stage in single precision (`condensed.rs`).
    l32: Vec<f32>,
    /// Whether the next [`factor_half`] computes the factor in single precision.
    pub(super) single: bool,
    /// `T_k`, dense column-major `nt × nt` (`nt = trail.len()`, lower triangle).
    pub(super) t: Vec<f64>,
}

impl Half {
    /// Entries stored for the half's factor.
    pub(super) fn l_values_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Whether the current factor is in single precision.
    pub(super) fn is_single(&self) -> bool {
        !self.l32.is_empty()
    }

    /// `Σ c_j²` over the part's columns, `c_j` the column count (diagonal included) of the
    /// factor of the part alone: the leading `nk × nk` block of the half's factor, read
    /// from its supernodal structure (with the explicit zeros of faer's relaxed supernodes).
    pub(super) fn part_flops(&self) -> f64 {
        let SymbolicCholeskyRaw::Supernodal(s) = self.symbolic.raw() else { return 0.0 };
        let nk = self.nk;
        let mut flops = 0.0;
        for k in 0..s.n_supernodes() {
            let (begin, end) = (s.supernode_begin()[k], s.supernode_end()[k].min(nk));
            if begin >= nk {
                continue;
            }
            let below = s.supernode(k).pattern().iter().filter(|&&r| r < nk).count();
            for c in begin..end {
                let count = (end - c + below) as f64;
                flops += count * count;
            }
        }
        flops
    }

    /// Number of trailing unknowns (the order of `T_k`).
    pub(super) fn nt(&self) -> usize {
        self.trail.len()
    }

    /// Predicted flops of one factorisation of the half: its supernodal Cholesky factor
    /// (the trailing block included) and the product `T_k T_kᵀ` (`nt³/3`).
    pub(super) fn flops(&self) -> f64 {
        let nt = self.nt() as f64;
        super::cholesky::factor_flops(&self.symbolic) + nt * nt * nt / 3.0
    }
}

/// Why the split factorisation failed: a non-positive pivot at this global (permuted)
/// position, or faer's error.
#[derive(Debug)]
pub(crate) enum SplitError {
    NonPositive { position: usize },
    Faer(FaerError),
}

impl From<FaerError> for SplitError {
    fn from(e: FaerError) -> Self {
        SplitError::Faer(e)
    }
}

/// The split factorisation (see the module documentation).
pub(crate) struct SplitCholesky {
    n1: usize,
    n2: usize,
    n3: usize,
    /// `perm[q]` = unknown at position `q` of `[part 1, part 2, separator]`.
    perm: Vec<usize>,
    halves: [Half; 2],
    /// Lower entries of `A33`: (row, col) in the separator and the index in the values.
    a33: Vec<(usize, usize, usize)>,
    /// Cholesky factor of `S` (lower), dense `n3 × n3`.
    s: Mat<f64>,
}

impl SplitCholesky {
    /// Builds the halves for the pattern (both triangles stored) and the ordering `perm`
    /// whose first `n1` unknowns are part 1, the next `n2` part 2, the rest the separator.
    /// `None` if a part 1 unknown couples to a part 2 unknown (not a separator).
    pub(crate) fn analyse(
        col_ptr: &[usize],
        row_idx: &[usize],
        perm: Vec<usize>,
        n1: usize,
        n2: usize,
    ) -> Result<Option<SplitCholesky>, FaerError> {
        let n = perm.len();
        let n3 = n - n1 - n2;
        let mut inv = vec![0usize; n];
        for (q, &j) in perm.iter().enumerate() {
            inv[j] = q;
        }
        // No coupling between the parts.
        let coupled = (0..n1).into_par_iter().any(|q| {
            let j = perm[q];
            row_idx[col_ptr[j]..col_ptr[j + 1]].iter().any(|&i| (n1..n1 + n2).contains(&inv[i]))
        });
        if coupled {
            return Ok(None);
        }
        let a33: Vec<(usize, usize, usize)> = (n1 + n2..n)
            .flat_map(|qj| {
                let j = perm[qj];
                let (inv, perm) = (&inv, &perm);
                row_idx[col_ptr[j]..col_ptr[j + 1]]
                    .iter()
                    .filter(move |&&i| inv[i] >= qj)
                    .map(move |&i| (inv[i] - n1 - n2, qj - n1 - n2, lower_position(col_ptr, row_idx, i, perm[qj])))
            })
            .collect();
        let all: Vec<usize> = (0..n3).collect();
        let (h0, h1) = rayon::join(
            || build_half(col_ptr, row_idx, &perm, &inv, 0, n1, n1 + n2, n3, &all),
            || build_half(col_ptr, row_idx, &perm, &inv, n1, n2, n1 + n2, n3, &all),
        );
        Ok(Some(SplitCholesky { n1, n2, n3, perm, halves: [h0?, h1?], a33, s: Mat::zeros(n3, n3) }))
    }

    /// Entries of the lower triangle of the factors (halves and dense separator).
    pub(crate) fn nnz_factor(&self) -> usize {
        let half = |h: &Half| match h.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
                .map(|k| {
                    let b = s.supernode_begin()[k];
                    let e = s.supernode_end()[k];
                    // Columns of the separator are counted once, in the dense factor.
                    let cols = e.min(h.nk).saturating_sub(b);
                    let rows = s.supernode(k).pattern().len() + (e - b);
                    (0..cols).map(|c| rows - c).sum::<usize>()
                })
                .sum(),
            SymbolicCholeskyRaw::Simplicial(s) => s.len_val(),
        };
        half(&self.halves[0]) + half(&self.halves[1]) + self.n3 * (self.n3 + 1) / 2
    }

    /// The unknown at a global (permuted) position.
    pub(crate) fn unknown_at(&self, position: usize) -> usize {
        self.perm[position.min(self.perm.len() - 1)]
    }

    /// Numeric factorisation of the values `vals` (of the full pattern). Returns the
    /// smallest pivot `L_kk²` and its position.
    pub(crate) fn factorize(&mut self, vals: &[f64]) -> Result<(f64, usize), SplitError> {
        let n3 = self.n3;
        let (n1, n2) = (self.n1, self.n2);
        let [h0, h1] = &mut self.halves;
        let (r0, r1) = rayon::join(|| factor_half(h0, vals), || factor_half(h1, vals));
        let (min0, min1) = (r0?, r1?);
        // S = T1 T1ᵀ + T2 T2ᵀ − A33 (lower triangle used).
        let t0 = faer::MatRef::from_column_major_slice(&self.halves[0].t, n3, n3);
        let t1 = faer::MatRef::from_column_major_slice(&self.halves[1].t, n3, n3);
        let mut s = Mat::<f64>::zeros(n3, n3);
        add_t_tt(s.as_mut(), t0, faer::Accum::Replace);
        add_t_tt(s.as_mut(), t1, faer::Accum::Add);
        for &(i, j, p) in &self.a33 {
            s[(i, j)] -= vals[p];
            if i != j {
                s[(j, i)] -= vals[p];
            }
        }
        let mut mem = MemBuffer::try_new(faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
            n3,
            Par::Seq,
            Spec::default(),
        ))
        .map_err(|_| SplitError::Faer(FaerError::OutOfMemory))?;
        match faer::linalg::cholesky::llt::factor::cholesky_in_place(
            s.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut mem),
            Spec::default(),
        ) {
            Ok(_) => {}
            Err(LltError::NonPositivePivot { index }) => {
                return Err(SplitError::NonPositive { position: n1 + n2 + index.min(n3 - 1) })
            }
        }
        let mut worst = if min1.0 < min0.0 { min1 } else { min0 };
        for t in 0..n3 {
            let d = s[(t, t)] * s[(t, t)];
            if d < worst.0 {
                worst = (d, n1 + n2 + t);
            }
        }
        self.s = s;
        Ok(worst)
    }

    /// Solves `A x = b` in place with the factorisation.
    pub(crate) fn solve_in_place(&self, x: &mut [f64]) {
        let (n1, n2, n3) = (self.n1, self.n2, self.n3);
        let bp: Vec<f64> = self.perm.iter().map(|&j| x[j]).collect();
        // Forward in both halves.
        let (z0, z1) = rayon::join(
            || forward_half(&self.halves[0], &bp[..n1]),
            || forward_half(&self.halves[1], &bp[n1..n1 + n2]),
        );
        // Separator: S x3 = b3 + T1 w1 + T2 w2.
        let mut x3: Vec<f64> = bp[n1 + n2..].to_vec();
        for (h, z) in self.halves.iter().zip([&z0, &z1]) {
            add_t_w(h, &z[h.nk..], &mut x3);
        }
        let l = self.s.as_ref();
        for c in 0..n3 {
            x3[c] /= l[(c, c)];
            let v = x3[c];
            for r in c + 1..n3 {
                x3[r] -= l[(r, c)] * v;
            }
        }
        for c in (0..n3).rev() {
            let mut v = x3[c];
            for r in c + 1..n3 {
                v -= l[(r, c)] * x3[r];
            }
            x3[c] = v / l[(c, c)];
        }
        // Backward in both halves.
        let (x0, x1) =
            rayon::join(|| backward_half(&self.halves[0], z0, &x3), || backward_half(&self.halves[1], z1, &x3));
        for (q, &j) in self.perm.iter().enumerate() {
            x[j] = if q < n1 {
                x0[q]
            } else if q < n1 + n2 {
                x1[q - n1]
            } else {
                x3[q - n1 - n2]
            };
        }
    }
}

/// `S (+)= T Tᵀ` on the lower triangle of `S` (`T` lower triangular): a third of the flops
/// of the full product.
pub(super) fn add_t_tt(s: MatMut<'_, f64>, t: faer::MatRef<'_, f64>, accum: faer::Accum) {
    use faer::linalg::matmul::triangular::{matmul, BlockStructure};
    matmul(
        s,
        BlockStructure::TriangularLower,
        accum,
        t,
        BlockStructure::TriangularLower,
        t.transpose(),
        BlockStructure::TriangularUpper,
        1.0,
        Par::Seq,
    );
}

/// The half made of the part at global positions `offset..offset + nk` and the trailing
/// unknowns `trail` (ascending positions in the separator block at `sep_start..sep_start +
/// n3`, in the ordering `perm`, with `inv` its inverse): the lower triangle of its matrix
/// in local numbering (part, then trailing block) and faer's supernodal symbolic
/// factorisation of it (identity ordering: the part's order is kept and the trailing block
/// is eliminated last). `inv` may hold `usize::MAX` for unknowns outside `perm`.
#[allow(clippy::too_many_arguments)]
pub(super) fn build_half(
    col_ptr: &[usize],
    row_idx: &[usize],
    perm: &[usize],
    inv: &[usize],
    offset: usize,
    nk: usize,
    sep_start: usize,
    n3: usize,
    trail: &[usize],
) -> Result<Half, FaerError> {
    let nt = trail.len();
    let m = nk + nt;
    // Local index of each position of the separator block (NONE: not in the half).
    const NONE: usize = usize::MAX;
    let mut rank = vec![NONE; n3];
    for (r, &t) in trail.iter().enumerate() {
        rank[t] = nk + r;
    }
    // Global position of local index c, and back.
    let global = |c: usize| if c < nk { offset + c } else { sep_start + trail[c - nk] };
    let local = |q: usize| {
        if (sep_start..sep_start + n3).contains(&q) {
            let r = rank[q - sep_start];
            (r != NONE).then_some(r)
        } else if (offset..offset + nk).contains(&q) {
            Some(q - offset)
        } else {
            None
        }
    };
    // Lower triangle, column by column of the local numbering.
    let mut cp = Vec::with_capacity(m + 1);
    cp.push(0usize);
    let mut ri = Vec::new();
    let mut src = Vec::new();
    let mut col: Vec<(usize, usize)> = Vec::new();
    for c in 0..m {
        let j = perm[global(c)];
        col.clear();
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if let Some(r) = local(inv[i]) {
                if r >= c {
                    col.push((r, lower_position(col_ptr, row_idx, i, j)));
                }
            }
        }
        col.sort_unstable();
        ri.extend(col.iter().map(|&(r, _)| r));
        src.extend(col.iter().map(|&(_, p)| p));
        cp.push(ri.len());
    }
    // faer's symbolic phase without a permutation reads the upper triangle: the
    // transpose, by counting.
    let mut ucp = vec![0usize; m + 1];
    for &r in &ri {
        ucp[r + 1] += 1;
    }
    for c in 0..m {
        ucp[c + 1] += ucp[c];
    }
    let mut fill = ucp.clone();
    let mut uri = vec![0usize; ri.len()];
    for c in 0..m {
        for &r in &ri[cp[c]..cp[c + 1]] {
            uri[fill[r]] = c;
            fill[r] += 1;
        }
    }
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let symbolic = factorize_symbolic_cholesky(
        SymbolicSparseColMatRef::new_checked(m, m, &ucp, None, &uri),
        Side::Upper,
        SymmetricOrdering::Identity,
        params,
    )?;
    let l_values = try_zeroed_vec(symbolic.len_val()).map_err(|_| FaerError::OutOfMemory)?;
    Ok(Half {
        nk,
        trail: trail.to_vec(),
        offset,
        sep_start,
        values: vec![0.0; src.len()],
        col_ptr: cp,
        row_idx: ri,
        src,
        symbolic,
        l_values,
        l32: Vec::new(),
        single: false,
        t: vec![0.0; nt * nt],
    })
}

/// Forward substitution in a half: `L_k [y_k; w_k] = [b_k; 0]`, returned as `[y_k; w_k]`
/// (then `L3k y_k = −T_k w_k`). A single-precision factor substitutes an `f32` copy.
pub(super) fn forward_half(h: &Half, b_part: &[f64]) -> Vec<f64> {
    let m = h.nk + h.nt();
    let mut z = vec![0.0; m];
    z[..h.nk].copy_from_slice(b_part);
    in_precision(h, &mut z, |l, z, stack| l.forward(z, stack));
    z
}

/// `x3 += T_k w` (`T_k` lower triangular; `w` on the half's trailing unknowns, `x3` on the
/// whole separator block).
pub(super) fn add_t_w(h: &Half, w: &[f64], x3: &mut [f64]) {
    let nt = h.nt();
    for c in 0..nt {
        let wc = w[c];
        if wc != 0.0 {
            for r in c..nt {
                x3[h.trail[r]] += h.t[r + c * nt] * wc;
            }
        }
    }
}

/// Backward substitution in a half: `L_kᵀ [x_k; v] = [y_k; T_kᵀ x3]` with `z = [y_k; ·]`
/// from [`forward_half`] (`x3` on the whole separator block); returns `[x_k; v]`.
pub(super) fn backward_half(h: &Half, mut z: Vec<f64>, x3: &[f64]) -> Vec<f64> {
    let nt = h.nt();
    for c in 0..nt {
        let mut v = 0.0;
        for r in c..nt {
            v += h.t[r + c * nt] * x3[h.trail[r]];
        }
        z[h.nk + c] = v;
    }
    in_precision(h, &mut z, |l, z, stack| l.backward(z, stack));
    z
}

/// A half's supernodal factor in one precision, for its two substitutions.
enum HalfFactor<'a> {
    Double(supernodal::SupernodalLltRef<'a, usize, f64>),
    Single(supernodal::SupernodalLltRef<'a, usize, f32>),
}

/// A vector of the half's size in the factor's precision.
enum HalfVector<'a> {
    Double(&'a mut [f64]),
    Single(&'a mut [f32]),
}

impl HalfFactor<'_> {
    fn forward(&self, z: HalfVector<'_>, stack: &mut MemStack) {
        match (self, z) {
            (HalfFactor::Double(l), HalfVector::Double(z)) => {
                let n = z.len();
                l.l_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(z, n, 1), Par::Seq, stack)
            }
            (HalfFactor::Single(l), HalfVector::Single(z)) => {
                let n = z.len();
                l.l_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(z, n, 1), Par::Seq, stack)
            }
            _ => unreachable!("the vector is in the factor's precision"),
        }
    }

    fn backward(&self, z: HalfVector<'_>, stack: &mut MemStack) {
        match (self, z) {
            (HalfFactor::Double(l), HalfVector::Double(z)) => {
                let n = z.len();
                l.l_transpose_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(z, n, 1), Par::Seq, stack)
            }
            (HalfFactor::Single(l), HalfVector::Single(z)) => {
                let n = z.len();
                l.l_transpose_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(z, n, 1), Par::Seq, stack)
            }
            _ => unreachable!("the vector is in the factor's precision"),
        }
    }
}

/// Runs the substitution `f` on `z` with the half's factor in its precision: a
/// single-precision factor works on an `f32` copy of `z`, converted back.
fn in_precision(h: &Half, z: &mut [f64], f: impl FnOnce(HalfFactor<'_>, HalfVector<'_>, &mut MemStack)) {
    let SymbolicCholeskyRaw::Supernodal(s) = h.symbolic.raw() else { unreachable!("the halves are forced supernodal") };
    if h.is_single() {
        let mut mem = MemBuffer::new(s.solve_in_place_scratch::<f32>(1, Par::Seq));
        let mut z32: Vec<f32> = z.iter().map(|&v| v as f32).collect();
        f(
            HalfFactor::Single(supernodal::SupernodalLltRef::new(s, &h.l32)),
            HalfVector::Single(&mut z32),
            MemStack::new(&mut mem),
        );
        for (v, &w) in z.iter_mut().zip(&z32) {
            *v = w as f64;
        }
    } else {
        let mut mem = MemBuffer::new(s.solve_in_place_scratch::<f64>(1, Par::Seq));
        f(
            HalfFactor::Double(supernodal::SupernodalLltRef::new(s, &h.l_values)),
            HalfVector::Double(z),
            MemStack::new(&mut mem),
        );
    }
}

/// Position in the value array of the entry (i, j) or (j, i), whichever is in the lower
/// triangle of the original numbering (where the unsplit factorisation reads values).
pub(super) fn lower_position(col_ptr: &[usize], row_idx: &[usize], i: usize, j: usize) -> usize {
    let (r, c) = if i >= j { (i, j) } else { (j, i) };
    let col = &row_idx[col_ptr[c]..col_ptr[c + 1]];
    col_ptr[c] + col.binary_search(&r).expect("the pattern is structurally symmetric")
}

/// Factorises one half, in single precision when [`Half::single`] is set (the values
/// rounded to `f32`; `T_k` is kept in double precision, from the single-precision
/// entries); fills `T_k`. Returns the smallest pivot `L_kk²` of the part and its global
/// (permuted) position. A single-precision factor that meets a non-positive or non-finite
/// pivot reports it as a double-precision one does (the caller then factorises in double).
pub(super) fn factor_half(h: &mut Half, vals: &[f64]) -> Result<(f64, usize), SplitError> {
    for (v, &p) in h.values.iter_mut().zip(&h.src) {
        *v = vals[p];
    }
    let len = h.symbolic.len_val();
    if h.single {
        h.l_values = Vec::new();
        if h.l32.len() != len {
            h.l32 = try_zeroed_vec(len).map_err(|_| SplitError::Faer(FaerError::OutOfMemory))?;
        }
        let values: Vec<f32> = h.values.iter().map(|&v| v as f32).collect();
        let mut l32 = std::mem::take(&mut h.l32);
        let r = factor_numeric::<f32>(h, &mut l32, &values);
        h.l32 = l32;
        if r.is_err() {
            h.l32 = Vec::new();
        }
        r
    } else {
        h.l32 = Vec::new();
        if h.l_values.len() != len {
            h.l_values = try_zeroed_vec(len).map_err(|_| SplitError::Faer(FaerError::OutOfMemory))?;
        }
        let mut l = std::mem::take(&mut h.l_values);
        let values = std::mem::take(&mut h.values);
        let r = factor_numeric::<f64>(h, &mut l, &values);
        h.values = values;
        h.l_values = l;
        r
    }
}

/// The numeric phase of [`factor_half`] in `T` (`f64` or `f32`) into `l`, then `T_k`.
fn factor_numeric<T: faer::traits::RealField + Copy + Into<f64>>(
    h: &mut Half,
    l: &mut [T],
    values: &[T],
) -> Result<(f64, usize), SplitError> {
    let nt = h.nt();
    let m = h.nk + nt;
    let a = SparseColMatRef::new(SymbolicSparseColMatRef::new_checked(m, m, &h.col_ptr, None, &h.row_idx), values);
    let req = h.symbolic.factorize_numeric_llt_scratch::<T>(Par::Seq, Spec::default());
    let mut mem = MemBuffer::try_new(req).map_err(|_| SplitError::Faer(FaerError::OutOfMemory))?;
    let r = h.symbolic.factorize_numeric_llt::<T>(
        l,
        a,
        Side::Lower,
        LltRegularization::default(),
        Par::Seq,
        MemStack::new(&mut mem),
        Spec::default(),
    );
    let position = |index: usize| {
        if index < h.nk {
            h.offset + index
        } else {
            h.sep_start + h.trail[(index - h.nk).min(nt.max(1) - 1)]
        }
    };
    if let Err(LltError::NonPositivePivot { index }) = r {
        // Within the separator the half's pivots belong to T_k: A is not positive definite
        // there either (T_k T_kᵀ ≥ S).
        return Err(SplitError::NonPositive { position: position(index) });
    }
    let SymbolicCholeskyRaw::Supernodal(s) = h.symbolic.raw() else { unreachable!("the halves are forced supernodal") };
    let lref = supernodal::SupernodalLltRef::<usize, T>::new(s, l);
    let mut worst = (f64::INFINITY, 0usize);
    h.t.fill(0.0);
    for k in 0..s.n_supernodes() {
        let node = lref.supernode(k);
        let block = node.val();
        let start = node.start();
        let ncols = block.ncols();
        let pattern = node.pattern();
        for c in 0..ncols {
            let gc = start + c;
            if gc < h.nk {
                let b: f64 = block[(c, c)].into();
                let d = b * b;
                if !d.is_finite() {
                    return Err(SplitError::NonPositive { position: h.offset + gc });
                }
                if d < worst.0 {
                    worst = (d, h.offset + gc);
                }
                continue;
            }
            let tc = gc - h.nk;
            for r in c..block.nrows() {
                let gr = if r < ncols { start + r } else { pattern[r - ncols] };
                let v: f64 = block[(r, c)].into();
                if !v.is_finite() {
                    return Err(SplitError::NonPositive { position: position(gc) });
                }
                h.t[(gr - h.nk) + tc * nt] = v;
            }
        }
    }
    Ok(worst)
}

/// Cholesky systems with at least this many unknowns and points in 2D (and the automatic
/// ordering) are factorised as
/// two halves in parallel ([`SplitCholesky`]), when the top separator has at most
/// [`SPLIT_MAX_SEPARATOR`] unknowns (its dense factor costs `n3³/3` three times over).
pub(super) const SPLIT_MIN_UNKNOWNS: usize = 20_000;
pub(super) const SPLIT_MAX_SEPARATOR: usize = 3_000;

pub(super) fn split_candidate(n: usize, order: Order<'_>) -> bool {
    n >= SPLIT_MIN_UNKNOWNS && order.choice == OrderingChoice::Auto && order.points.is_some_and(|p| p.dim == 2)
}
