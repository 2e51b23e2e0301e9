//! The multipliers that the condensed factor's dense block `F` does not keep: the *free*
//! multipliers `f`, whose rows and columns have pattern entries in multiplier rows only
//! (today the multipliers of the slave nodes of a meshed pair in small sliding whose
//! points are all dormant, `contact::zone`, or unpaired: their rows hold only the open
//! law, −M/ρ_n over λ and −M over Λ, coupled to each other and to a few kept multipliers
//! `e` at the edge of the contact zone). Their block `A_ff` is sparse and, for the open law, negative definite;
//! it is eliminated exactly by its Schur complement on `e`:
//!
//! ```text
//! F_ee ← A_ee − A_ef A_ff⁻¹ A_fe,    and after each solve   x_f = A_ff⁻¹ (b_f − A_fe x_e)
//! ```
//!
//! Entry point: [`FreeBlock`], built by [`super::condensed::CondensedFactor::analyse`],
//! refreshed at every factorisation ([`FreeBlock::update`]: the values of the `f` columns
//! are compared with the ones the correction was built from, and the correction is
//! rebuilt when any differs, never used stale) and applied around every solve with `F`
//! ([`FreeBlock::eliminate`], [`FreeBlock::recover`]).
//!
//! The correction is computed on the unscaled values (`C = A_ef A_ff⁻¹ A_fe`, one sparse
//! Cholesky factor of `−A_ff` and `|e|` solves with it) and scaled at every factorisation
//! by the current scaling `S` of the system (`S A S`: `Ĉ = S_e C S_e`), so a new scale of
//! an edge multiplier (its points' statuses changed) rescales it without rebuilding it.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::linalg::LltError;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, MatMut, MatRef, Side};

const NONE: usize = usize::MAX;

/// The free multipliers, their couplings to the kept ones and the correction of `F`.
pub(crate) struct FreeBlock {
    /// The free multipliers (unknowns of the system).
    pub(crate) free: Vec<usize>,
    /// The unknowns of the kept multipliers coupled to some free one (`e`), in the order of
    /// their positions in `F` (ascending).
    edge: Vec<usize>,
    /// Their positions in `F`.
    pub(crate) edge_pos: Vec<usize>,
    /// Lower entries of `A_ff`: (row, column) in `free` and the positions of the entry
    /// and of its transpose in the values.
    ff: Vec<(usize, usize, usize, usize)>,
    /// Couplings: (index in `free`, index in `edge`, position of `A(e, f)`, position of
    /// `A(f, e)`).
    fe: Vec<(usize, usize, usize, usize)>,
    /// The unscaled values at the `ff` and `fe` positions (both) the correction was built
    /// from; empty: not built.
    raw: Vec<f64>,
    /// The unscaled `A(e, f)` and `A(f, e)` of each `fe` coupling, as built.
    a_ef: Vec<f64>,
    a_fe: Vec<f64>,
    /// Cholesky factor of `−A_ff` (unscaled).
    llt: Option<Llt<usize, f64>>,
    /// `C = A_ef A_ff⁻¹ A_fe` (unscaled), `|e| × |e|`, both triangles.
    cor: Mat<f64>,
    /// The scales of the free and edge multipliers at the last factorisation.
    scale_f: Vec<f64>,
    scale_e: Vec<f64>,
}

/// Why the free block cannot be condensed with these values.
#[derive(Debug)]
pub(crate) enum FreeError {
    /// `A_ff` is not symmetric.
    Unsymmetric,
    /// `−A_ff` is not positive definite (or faer's error).
    NotDefinite(LltError),
}

impl std::fmt::Display for FreeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FreeError::Unsymmetric => write!(f, "their block A_ff is not symmetric"),
            FreeError::NotDefinite(e) => write!(f, "their block −A_ff is not positive definite ({e:?})"),
        }
    }
}

impl FreeBlock {
    /// The free multipliers among `mults` (no pattern entry in a primal row: `j <
    /// n_primal`), and the rest, in their order.
    pub(crate) fn split(
        col_ptr: &[usize],
        row_idx: &[usize],
        mults: &[usize],
        n_primal: usize,
    ) -> (Vec<usize>, Vec<usize>) {
        mults.iter().partition(|&&l| row_idx[col_ptr[l]..col_ptr[l + 1]].iter().any(|&i| i < n_primal))
    }

    /// The block of the `free` multipliers; `f_of[j]` is the position in `F` of every kept
    /// unknown (`NONE` otherwise; every row of a free column is free or kept).
    pub(crate) fn new(col_ptr: &[usize], row_idx: &[usize], free: Vec<usize>, f_of: &[usize]) -> FreeBlock {
        let n = col_ptr.len() - 1;
        let mut loc = vec![NONE; n];
        for (t, &j) in free.iter().enumerate() {
            loc[j] = t;
        }
        let mirror = |i: usize, j: usize| -> usize {
            col_ptr[i]
                + row_idx[col_ptr[i]..col_ptr[i + 1]].binary_search(&j).expect("a structurally symmetric pattern")
        };
        // The edge: kept unknowns in the free columns, ordered by their position in F.
        let mut edge_pos: Vec<usize> = free
            .iter()
            .flat_map(|&j| row_idx[col_ptr[j]..col_ptr[j + 1]].iter().filter(|&&i| loc[i] == NONE).map(|&i| f_of[i]))
            .collect();
        edge_pos.sort_unstable();
        edge_pos.dedup();
        assert!(edge_pos.last().is_none_or(|&p| p != NONE), "a free multiplier coupled to an interior unknown");
        let mut e_of = vec![NONE; n];
        let mut edge = vec![NONE; edge_pos.len()];
        for &j in &free {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                if loc[i] == NONE {
                    let a = edge_pos.binary_search(&f_of[i]).expect("collected above");
                    e_of[i] = a;
                    edge[a] = i;
                }
            }
        }
        let (mut ff, mut fe) = (Vec::new(), Vec::new());
        for (c, &j) in free.iter().enumerate() {
            for (p, &i) in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().enumerate() {
                let p = col_ptr[j] + p;
                if loc[i] != NONE {
                    if loc[i] >= c {
                        ff.push((loc[i], c, p, mirror(i, j)));
                    }
                } else {
                    fe.push((c, e_of[i], p, mirror(i, j)));
                }
            }
        }
        FreeBlock {
            free,
            edge,
            edge_pos,
            ff,
            fe,
            raw: Vec::new(),
            a_ef: Vec::new(),
            a_fe: Vec::new(),
            llt: None,
            cor: Mat::zeros(0, 0),
            scale_f: Vec::new(),
            scale_e: Vec::new(),
        }
    }

    /// Number of edge multipliers `|e|`.
    pub(crate) fn n_edge(&self) -> usize {
        self.edge.len()
    }

    /// The unscaled values of the free columns at the positions the correction reads.
    fn current_raw(&self, raw: &[f64]) -> Vec<f64> {
        self.ff
            .iter()
            .map(|e| (e.2, e.3))
            .chain(self.fe.iter().map(|e| (e.2, e.3)))
            .flat_map(|(p, q)| [raw[p], raw[q]])
            .collect()
    }

    /// Brings the block up to the unscaled values `raw` and the scaling `scale`: rebuilds
    /// the factor of `−A_ff` and the correction `C` if any value of the free columns
    /// differs from the ones they were built from (bit for bit), and returns the scaled
    /// correction `S_e C S_e` (`|e| × |e|`, both triangles) for `F`. Returns whether it
    /// rebuilt, for the log.
    pub(crate) fn update(&mut self, raw: &[f64], scale: &[f64]) -> Result<(Mat<f64>, bool), FreeError> {
        let ne = self.edge.len();
        let rebuilt = !self.free.is_empty() && {
            let now = self.current_raw(raw);
            let stale = now != self.raw;
            if stale {
                self.raw.clear();
                self.build(raw)?;
                self.raw = now;
            }
            stale
        };
        self.scale_f = self.free.iter().map(|&j| scale[j]).collect();
        self.scale_e = self.edge.iter().map(|&j| scale[j]).collect();
        let mut c = Mat::<f64>::zeros(ne, ne);
        for b in 0..ne {
            for a in 0..ne {
                c[(a, b)] = self.scale_e[a] * self.cor[(a, b)] * self.scale_e[b];
            }
        }
        Ok((c, rebuilt))
    }

    /// The factor of `−A_ff` and `C = A_ef A_ff⁻¹ A_fe = −A_ef (−A_ff)⁻¹ A_fe` for the
    /// unscaled values `raw`.
    fn build(&mut self, raw: &[f64]) -> Result<(), FreeError> {
        let nfree = self.free.len();
        let ne = self.edge.len();
        self.llt = None;
        for &(r, c, p, q) in &self.ff {
            if r != c && (raw[p] - raw[q]).abs() > 1e-13 * raw[p].abs().max(raw[q].abs()) {
                return Err(FreeError::Unsymmetric);
            }
        }
        let triplets: Vec<Triplet<usize, usize, f64>> =
            self.ff.iter().map(|&(r, c, p, _)| Triplet::new(r, c, -raw[p])).collect();
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(nfree, nfree, &triplets)
            .expect("the free block's entries are in range and distinct");
        let llt = m.sp_cholesky(Side::Lower).map_err(FreeError::NotDefinite)?;
        // C in blocks of columns of e (bounded memory: |f| × 256 at a time).
        let mut cor = Mat::<f64>::zeros(ne, ne);
        const BLOCK: usize = 256;
        for start in (0..ne).step_by(BLOCK) {
            let width = BLOCK.min(ne - start);
            let mut x = Mat::<f64>::zeros(nfree, width);
            for &(f, e, _, q) in &self.fe {
                if (start..start + width).contains(&e) {
                    x[(f, e - start)] += raw[q];
                }
            }
            llt.solve_in_place(x.as_mut());
            // C[e', start..] −= A(e', f) X[f, ..]
            for &(f, e, p, _) in &self.fe {
                let a = raw[p];
                for k in 0..width {
                    cor[(e, start + k)] -= a * x[(f, k)];
                }
            }
        }
        self.cor = cor;
        self.llt = Some(llt);
        self.a_ef = self.fe.iter().map(|e| raw[e.2]).collect();
        self.a_fe = self.fe.iter().map(|e| raw[e.3]).collect();
        Ok(())
    }

    /// Eliminates the free multipliers from a scaled right-hand side: with `b_f` the free
    /// rows of `x`, returns `w = S_f⁻¹ b_f` and subtracts `S_e A_ef A_ff⁻¹ w` from the edge
    /// rows of `rf` (`F`'s right-hand side).
    pub(crate) fn eliminate(&self, x: &[f64], mut rf: MatMut<'_, f64>) -> Vec<f64> {
        let w: Vec<f64> = self.free.iter().zip(&self.scale_f).map(|(&j, s)| x[j] / s).collect();
        if w.iter().all(|&v| v == 0.0) {
            return w;
        }
        let y = self.solve_aff(&w);
        let mut t = vec![0.0; self.edge.len()];
        for (&(f, e, _, _), a) in self.fe.iter().zip(&self.a_ef) {
            t[e] += a * y[f];
        }
        for ((&pos, &s), v) in self.edge_pos.iter().zip(&self.scale_e).zip(&t) {
            rf[(pos, 0)] -= s * v;
        }
        w
    }

    /// The free multipliers from `w` ([`Self::eliminate`]) and `F`'s solution `rf`:
    /// `x_f = S_f⁻¹ A_ff⁻¹ (w − A_fe S_e x_e)`, written into `x`.
    pub(crate) fn recover(&self, mut w: Vec<f64>, rf: MatRef<'_, f64>, x: &mut [f64]) {
        if self.free.is_empty() {
            return;
        }
        for (&(f, e, _, _), a) in self.fe.iter().zip(&self.a_fe) {
            w[f] -= a * self.scale_e[e] * rf[(self.edge_pos[e], 0)];
        }
        let y = self.solve_aff(&w);
        for ((&j, s), v) in self.free.iter().zip(&self.scale_f).zip(&y) {
            x[j] = v / s;
        }
    }

    /// `A_ff⁻¹ w` (unscaled).
    fn solve_aff(&self, w: &[f64]) -> Vec<f64> {
        let llt = self.llt.as_ref().expect("the free block is factorised before a solve");
        let mut y = Mat::<f64>::zeros(w.len(), 1);
        for (i, &v) in w.iter().enumerate() {
            y[(i, 0)] = -v;
        }
        llt.solve_in_place(y.as_mut());
        y.col(0).iter().copied().collect()
    }
}
