//! The dense crack block `F` of the condensed contact factor ([`super::condensed`]) and its
//! solves, with a factorisation of `F` kept across contact iterations.
//!
//! Entry point: [`DenseBlock`] (`F`, its factor, and the counts of
//! [`crate::solve::backend::CondensedCounts`]).
//!
//! Between two contact iterations only the rows and columns of the points whose statuses
//! or thresholds changed differ in `F`: `F₁ = F₀ + E D Eᵀ`, `E` the columns of the identity
//! at the `k` changed rows `R` (the entries that change couple two changed rows), `D` the
//! change of the `R × R` block, of rank at most `k`. Instead of a new factorisation (`n³/3`
//! flops for `LBLᵀ`), [`DenseBlock::refresh`] keeps the factor of `F₀` and builds the
//! low-rank correction of Woodbury's identity: `Y = F₀⁻¹ E` (one solve with `k` right-hand
//! sides, `k n²` multiply-adds, blocked and parallel like a factorisation; extended by the
//! new rows only while `R` grows), `C = I + D Eᵀ Y` (`k × k`, LU), and
//! `F₁⁻¹ b = y − Y C⁻¹ D Eᵀ y` with `y = F₀⁻¹ b`. It does so while `k` is at most
//! [`max_rank`] (`n/3`: the solve with `k` columns then costs about what a factorisation
//! costs); beyond, a change that is small in size (the thresholds of a later friction pass)
//! keeps the previous preconditioner, and any other refactorises.
//!
//! Every solve with a kept factor is GMRES on the true `F₁` right-preconditioned by the old
//! factor and its correction ([`gmres`], to [`KRYLOV_TOLERANCE`] on `‖b − F₁ x‖ / ‖b‖`,
//! checked with `F₁`): the correction is exact up to round-off, so it takes 0 or 1
//! iterations; without one, `F₁ F₀⁻¹ = I + ΔF F₀⁻¹` is the identity plus a matrix of rank
//! `k` and GMRES converges in at most `k` iterations (exact arithmetic), each one product
//! with `F₁` and one pair of triangular solves (`2n²` multiply-adds). A solve that does not
//! converge within [`max_iterations`] refactorises `F₁` and ends with the new factor, so the
//! answer is the direct solve's to the tolerance either way. `FISSURE_CONDENSED_REFACTOR`
//! (developer switch, read at the analysis) refactorises at every new `F`, as before the
//! kept factor, to compare.
//!
//! From [`SINGLE_FROM`] rows `F` is factorised in single precision (`LBLᵀ` or `LU` of an
//! `f32` copy, about twice the rate): such a factor is never *current*, so every solve with
//! it is the same GMRES, preconditioned by it (and by its low-rank correction while kept),
//! to the same tolerance, and a solve that does not converge refactorises in double
//! precision. `FISSURE_DENSE_DOUBLE` (developer switch) keeps every factor in double.
//!
//! A single-precision refactorisation goes by blocks when it can ([`BlockFactor`]): the
//! rows changed since the last factor, with the multipliers coupled to them, are *hot*,
//! the others cold; the cold blocks and `W = A_HC A_CC⁻¹ A_CH` are kept, and while the
//! iterations change hot rows only, a refactorisation is the `LU` of the Schur complement
//! `S = A_HH − W` alone (`⅔ h³` for `⅔ n³`). New hot rows rebuild the blocks (about the cost
//! of one `LU` of `F`), more than [`BLOCK_HOT_FRACTION`] of `F` hot or a singular cold
//! block factorises `F` whole. The factor is a preconditioner like any single-precision
//! one: the GMRES above keeps every solve exact. `FISSURE_DENSE_WHOLE` (developer switch)
//! factorises `F` whole every time, to compare.

use crate::solve::backend::CondensedCounts;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::lblt as bunch_kaufman;
use faer::sparse::FaerError;
use faer::{Conj, Mat, MatMut, Par, Spec};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Relative residual `‖b − F x‖ / ‖b‖` a Krylov solve with a stale factor reaches.
pub(crate) const KRYLOV_TOLERANCE: f64 = 1e-13;

/// The GMRES iterations a solve with a kept factor may take: an iteration is `2n²`
/// multiply-adds, memory-bound (matrix–vector product, two triangular solves), a
/// factorisation `n³/6`, compute-bound and parallel; on the 2D Hertz bench row (n = 1476)
/// an iteration took 2.5 ms against 100–160 ms for a factorisation (loaded machine), so
/// `n/70` iterations (21 there) cost a third to a half of one: at least 8, at most 200.
pub(crate) fn max_iterations(n: usize) -> usize {
    (n / 70).clamp(8, 200)
}

/// Rows of `F` changed since its factorisation up to which the factor is kept with a
/// low-rank correction: `Y = F₀⁻¹ E_R` costs `k n²` multiply-adds (a solve with `k`
/// right-hand sides, blocked and parallel), the factorisation `n³/6`, but the solve runs
/// at about twice the factorisation's rate per multiply-add (the 3D Hertz bench row:
/// `Y` of 1 381 columns at nf = 8 701 in 2.9 s, 3.6e10 a second, the `LBLᵀ` in 6.3 s,
/// 1.75e10; at nf = 5 088 the `LBLᵀ` at 1.1e10), and `Y` is extended by the new rows only
/// while the factor is kept: `n/3`. (`n/6` refactorised at every friction iteration of
/// that row once its contact zone made `F` 5 088 wide: 76 factorisations of 2 s where
/// the 8 701-wide `F` kept one.)
pub(crate) fn max_rank(n: usize) -> usize {
    n / 3
}

/// Whether a symmetric `F` of width `n` is factorised in single precision: from
/// [`SINGLE_FROM`] rows, unless `FISSURE_DENSE_DOUBLE` is set (developer switch, to
/// compare). The factor is then a preconditioner: every solve is GMRES on `F` in double
/// precision to [`KRYLOV_TOLERANCE`] (a few iterations while κ(F)·ε₃₂ ≪ 1), and a solve
/// that does not converge refactorises in double precision, so the answer is the direct
/// solve's to the tolerance either way; the `LBLᵀ` runs at about twice the rate.
pub(crate) fn single_precision(n: usize) -> bool {
    n >= SINGLE_FROM && std::env::var_os("FISSURE_DENSE_DOUBLE").is_none()
}

/// The width of `F` from which it is factorised in single precision ([`single_precision`]).
const SINGLE_FROM: usize = 1500;

/// The largest fraction of the rows of `F` that may be hot in a [`BlockFactor`]: beyond,
/// building the blocks costs more than an `LU` of `F` and `S` is most of `F`.
const BLOCK_HOT_FRACTION: f64 = 0.8;

/// Whether single-precision refactorisations of `F` may go by blocks ([`BlockFactor`]):
/// unless `FISSURE_DENSE_WHOLE` is set (developer switch, to compare).
fn blocks_enabled() -> bool {
    std::env::var_os("FISSURE_DENSE_WHOLE").is_none()
}

/// Rows of `C` (the low-rank correction's `k`) from which it is built in parallel.
const PARALLEL_C_ROWS: usize = 512;

/// A factorisation of `F`: Bunch–Kaufman `LBLᵀ` of its coupled rows (the decoupled rows
/// solved by a division), or partial-pivoting LU when `F` is unsymmetric.
struct DenseFactor {
    /// `LBLᵀ` of `F` restricted to `active` (all of `F` when that is empty).
    f: Mat<f64>,
    subdiag: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    /// The rows of `F` factorised by `LBLᵀ` when some rows are decoupled (empty: all).
    active: Vec<usize>,
    /// The decoupled rows of `F` (no off-diagonal entry, non-zero diagonal) and their
    /// diagonal: the multipliers of packets whose points are all open, whose equation is
    /// λ/ρ = 0 alone. They are solved by a division, outside the dense factorisation.
    decoupled: Vec<(usize, f64)>,
    /// `LU` of `F` (partial pivoting) when `F` is unsymmetric; the `LBLᵀ` above is unused.
    lu: Option<faer::linalg::solvers::PartialPivLu<f64>>,
    /// The `LU` in single precision (`single`).
    lu_single: Option<faer::linalg::solvers::PartialPivLu<f32>>,
    /// Whether the factor is in single precision (`f_single`, `subdiag_single` or
    /// `lu_single`): then it is a preconditioner, never a solve on its own.
    single: bool,
    f_single: Mat<f32>,
    subdiag_single: Vec<f32>,
    /// `F` by blocks ([`BlockFactor`], single precision); the factors above are unused.
    block: Option<Box<BlockFactor>>,
    /// Whether it holds a factorisation.
    valid: bool,
}

impl DenseFactor {
    fn new(nf: usize) -> Self {
        DenseFactor {
            f: Mat::zeros(nf, nf),
            subdiag: vec![0.0; nf],
            perm: vec![0; nf],
            perm_inv: vec![0; nf],
            active: Vec::new(),
            decoupled: Vec::new(),
            lu: None,
            lu_single: None,
            single: false,
            f_single: Mat::zeros(0, 0),
            subdiag_single: Vec::new(),
            block: None,
            valid: false,
        }
    }

    /// Holds `F` by blocks (a preconditioner, as a single-precision factor).
    fn set_block(&mut self, block: Box<BlockFactor>) {
        self.lu = None;
        self.lu_single = None;
        self.active.clear();
        self.decoupled.clear();
        self.block = Some(block);
        self.single = true;
        self.valid = true;
    }

    /// Factorises `m` (lower triangle, or in full with `full`), the `LBLᵀ` in single
    /// precision with `single` (see [`single_precision`]).
    fn factor(&mut self, m: &Mat<f64>, full: bool, single: bool) -> Result<(), FaerError> {
        self.valid = false;
        self.single = false;
        self.lu = None;
        self.lu_single = None;
        self.block = None;
        self.active.clear();
        self.decoupled.clear();
        let nf = m.nrows();
        if full && single {
            let ms = Mat::<f32>::from_fn(nf, nf, |i, j| m[(i, j)] as f32);
            self.lu_single = Some(faer::linalg::solvers::PartialPivLu::new(ms.as_ref()));
            self.single = true;
            self.valid = true;
            return Ok(());
        }
        if full {
            self.lu = Some(faer::linalg::solvers::PartialPivLu::new(m.as_ref()));
            self.valid = true;
            return Ok(());
        }
        let f = &mut self.f;
        // Rows with no off-diagonal entry (F lower: nothing left of the diagonal in row i,
        // nothing below it in column i) leave the dense factorisation.
        let mut coupled = vec![false; nf];
        for j in 0..nf {
            let col = m.col(j);
            for i in j + 1..nf {
                if col[i] != 0.0 {
                    coupled[i] = true;
                    coupled[j] = true;
                }
            }
        }
        for (i, &c) in coupled.iter().enumerate() {
            let d = m[(i, i)];
            if c || d == 0.0 {
                self.active.push(i);
            } else {
                self.decoupled.push((i, d));
            }
        }
        let na = self.active.len();
        if self.decoupled.is_empty() {
            self.active.clear();
            for j in 0..nf {
                for i in j..nf {
                    f[(i, j)] = m[(i, j)];
                }
            }
        } else {
            // The coupled rows, compacted to the leading na × na block.
            for (jj, &j) in self.active.iter().enumerate() {
                for (ii, &i) in self.active.iter().enumerate().skip(jj) {
                    f[(ii, jj)] = m[(i, j)];
                }
            }
        }
        self.perm.resize(na, 0);
        self.perm_inv.resize(na, 0);
        if single && na > 0 {
            let fs = &mut self.f_single;
            if fs.nrows() < na {
                *fs = Mat::zeros(na, na);
            }
            let mut fs = fs.as_mut().submatrix_mut(0, 0, na, na);
            for j in 0..na {
                for i in j..na {
                    fs[(i, j)] = f[(i, j)] as f32;
                }
            }
            self.subdiag_single.resize(na, 0.0);
            lblt_factor(fs, &mut self.subdiag_single, &mut self.perm, &mut self.perm_inv)?;
            self.single = true;
            self.valid = true;
            return Ok(());
        }
        self.subdiag.resize(na, 0.0);
        if na > 0 {
            lblt_factor(f.as_mut().submatrix_mut(0, 0, na, na), &mut self.subdiag, &mut self.perm, &mut self.perm_inv)?;
        }
        self.valid = true;
        Ok(())
    }

    /// `R ← F⁻¹ R` for the `F` it factorised (every column of `R`).
    fn solve(&self, mut r: MatMut<'_, f64>) {
        if let Some(block) = &self.block {
            block.solve(r);
            return;
        }
        if let Some(lu) = &self.lu_single {
            let mut rs = Mat::<f32>::from_fn(r.nrows(), r.ncols(), |i, c| r[(i, c)] as f32);
            faer::linalg::solvers::SolveCore::solve_in_place_with_conj(lu, Conj::No, rs.as_mut());
            for c in 0..r.ncols() {
                for i in 0..r.nrows() {
                    r[(i, c)] = rs[(i, c)] as f64;
                }
            }
            return;
        }
        if let Some(lu) = &self.lu {
            faer::linalg::solvers::SolveCore::solve_in_place_with_conj(lu, Conj::No, r);
            return;
        }
        let nr = r.ncols();
        let par = if nr > 1 { Par::rayon(0) } else { Par::Seq };
        let na = self.perm.len();
        for &(i, d) in &self.decoupled {
            for c in 0..nr {
                r[(i, c)] /= d;
            }
        }
        if na == 0 {
            return;
        }
        let mut compact = Mat::<f64>::zeros(if self.active.is_empty() { 0 } else { na }, nr);
        for c in 0..nr {
            for (ii, &i) in self.active.iter().enumerate() {
                compact[(ii, c)] = r[(i, c)];
            }
        }
        let perm = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, na);
        let rhs = if self.active.is_empty() { r.as_mut() } else { compact.as_mut() };
        if self.single {
            let mut rs = Mat::<f32>::from_fn(na, nr, |i, c| rhs[(i, c)] as f32);
            let f = self.f_single.as_ref().submatrix(0, 0, na, na);
            lblt_solve(f, &self.subdiag_single, perm, rs.as_mut(), par);
            let mut rhs = rhs;
            for c in 0..nr {
                for i in 0..na {
                    rhs[(i, c)] = rs[(i, c)] as f64;
                }
            }
        } else {
            lblt_solve(self.f.as_ref().submatrix(0, 0, na, na), &self.subdiag, perm, rhs, par);
        }
        for c in 0..nr {
            for (ii, &i) in self.active.iter().enumerate() {
                r[(i, c)] = compact[(ii, c)];
            }
        }
    }
}

/// A partial-pivoting `LU` in single precision, factorised in place in a buffer kept
/// across factorisations (no allocation and no fresh pages per factorisation).
struct LuSingle {
    /// `L` (unit, strictly below the diagonal) and `U` packed, `n × n` at the top left.
    lu: Mat<f32>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    n: usize,
}

impl LuSingle {
    fn new() -> Self {
        LuSingle { lu: Mat::zeros(0, 0), perm: Vec::new(), perm_inv: Vec::new(), n: 0 }
    }

    /// The `n × n` buffer to fill before [`Self::factor`].
    fn buffer(&mut self, n: usize) -> MatMut<'_, f32> {
        if self.lu.nrows() < n {
            self.lu = Mat::zeros(n, n);
        }
        self.n = n;
        self.perm.resize(n, 0);
        self.perm_inv.resize(n, 0);
        self.lu.as_mut().submatrix_mut(0, 0, n, n)
    }

    /// Factorises the buffer in place; false when a pivot is zero or not finite, or
    /// below 1e-6 of the largest (the block is singular to single precision).
    fn factor(&mut self) -> bool {
        let n = self.n;
        let par = Par::rayon(0);
        let mut mem = MemBuffer::new(faer::linalg::lu::partial_pivoting::factor::lu_in_place_scratch::<usize, f32>(
            n,
            n,
            par,
            Default::default(),
        ));
        faer::linalg::lu::partial_pivoting::factor::lu_in_place(
            self.lu.as_mut().submatrix_mut(0, 0, n, n),
            &mut self.perm,
            &mut self.perm_inv,
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        let d = self
            .lu
            .as_ref()
            .submatrix(0, 0, n, n)
            .diagonal()
            .column_vector()
            .iter()
            .map(|v| v.abs())
            .collect::<Vec<f32>>();
        let largest = d.iter().copied().fold(0.0f32, f32::max);
        largest.is_finite() && d.iter().all(|&v| v.is_finite() && v > 1e-6 * largest)
    }

    /// `R ← A⁻¹ R`.
    fn solve(&self, mut r: MatMut<'_, f32>) {
        let n = self.n;
        let par = if r.ncols() > 1 { Par::rayon(0) } else { Par::Seq };
        let lu = self.lu.as_ref().submatrix(0, 0, n, n);
        let perm = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let mut mem = MemBuffer::new(faer::perm::permute_rows_in_place_scratch::<usize, f32>(n, r.ncols()));
        faer::perm::permute_rows_in_place(r.as_mut(), perm, MemStack::new(&mut mem));
        faer::linalg::triangular_solve::solve_unit_lower_triangular_in_place(lu, r.as_mut(), par);
        faer::linalg::triangular_solve::solve_upper_triangular_in_place(lu, r, par);
    }
}

/// `F` factorised by blocks, in single precision (a preconditioner): the rows `H` that
/// the contact iterations change (hot) and the others `C` (cold). The changes couple two
/// changed rows (module documentation), so while every changed row is hot, `A_CC`, `A_CH`
/// and `A_HC` are those of the `F` the blocks were built from, and only the Schur
/// complement `S = A_HH − W` changes, `W = A_HC A_CC⁻¹ A_CH` kept: a refactorisation costs
/// `⅔ h³` instead of `⅔ n³` (the 3D Hertz sphere row's friction iterations change ~1 150
/// of 2 193 rows: a sixth of it). Building the blocks costs about one `LU` of `F`
/// (`⅔ c³ + 2c²h + 2ch² + ⅔ h³` against `⅔ n³`, equal at `h = c`).
/// `x = F⁻¹ b`: `y = A_CC⁻¹ b_C`, `x_H = S⁻¹ (b_H − A_HC y)`, `x_C = y − Z x_H` with
/// `Z = A_CC⁻¹ A_CH`.
struct BlockFactor {
    hot: Vec<usize>,
    cold: Vec<usize>,
    is_hot: Vec<bool>,
    a_cc: LuSingle,
    a_hc: Mat<f32>,
    z: Mat<f32>,
    w: Mat<f32>,
    s: LuSingle,
}

impl BlockFactor {
    /// The blocks of `m` (lower triangle, or in full with `full`) for the hot rows `hot`
    /// (increasing), and `S` factorised; `None` when `A_CC` or `S` is singular to single
    /// precision (then `F` is factorised whole).
    fn build(m: &Mat<f64>, full: bool, hot: Vec<usize>) -> Option<BlockFactor> {
        let n = m.nrows();
        let mut is_hot = vec![false; n];
        for &i in &hot {
            is_hot[i] = true;
        }
        let cold: Vec<usize> = (0..n).filter(|&i| !is_hot[i]).collect();
        let (h, c) = (hot.len(), cold.len());
        let mut a_cc = LuSingle::new();
        {
            let mut b = a_cc.buffer(c);
            for (jj, &j) in cold.iter().enumerate() {
                for (ii, &i) in cold.iter().enumerate() {
                    b[(ii, jj)] = entry(m, full, i, j) as f32;
                }
            }
        }
        if !a_cc.factor() {
            return None;
        }
        let mut z = Mat::<f32>::from_fn(c, h, |ii, jj| entry(m, full, cold[ii], hot[jj]) as f32);
        a_cc.solve(z.as_mut());
        let a_hc = Mat::<f32>::from_fn(h, c, |ii, jj| entry(m, full, hot[ii], cold[jj]) as f32);
        let mut w = Mat::<f32>::zeros(h, h);
        faer::linalg::matmul::matmul(
            w.as_mut(),
            faer::Accum::Replace,
            a_hc.as_ref(),
            z.as_ref(),
            1.0f32,
            Par::rayon(0),
        );
        let mut block = BlockFactor { hot, cold, is_hot, a_cc, a_hc, z, w, s: LuSingle::new() };
        block.refactor(m, full).then_some(block)
    }

    /// `S = A_HH − W` from `m` factorised; false when singular to single precision.
    fn refactor(&mut self, m: &Mat<f64>, full: bool) -> bool {
        let h = self.hot.len();
        let (hot, w) = (&self.hot, &self.w);
        let mut s = self.s.buffer(h);
        for (jj, &j) in hot.iter().enumerate() {
            for (ii, &i) in hot.iter().enumerate() {
                s[(ii, jj)] = entry(m, full, i, j) as f32 - w[(ii, jj)];
            }
        }
        self.s.factor()
    }

    /// `R ← F⁻¹ R` (in single precision).
    fn solve(&self, mut r: MatMut<'_, f64>) {
        let nr = r.ncols();
        let par = if nr > 1 { Par::rayon(0) } else { Par::Seq };
        let mut y = Mat::<f32>::from_fn(self.cold.len(), nr, |ii, k| r[(self.cold[ii], k)] as f32);
        self.a_cc.solve(y.as_mut());
        let mut x = Mat::<f32>::from_fn(self.hot.len(), nr, |ii, k| r[(self.hot[ii], k)] as f32);
        faer::linalg::matmul::matmul(x.as_mut(), faer::Accum::Add, self.a_hc.as_ref(), y.as_ref(), -1.0f32, par);
        self.s.solve(x.as_mut());
        faer::linalg::matmul::matmul(y.as_mut(), faer::Accum::Add, self.z.as_ref(), x.as_ref(), -1.0f32, par);
        for k in 0..nr {
            for (ii, &i) in self.cold.iter().enumerate() {
                r[(i, k)] = y[(ii, k)] as f64;
            }
            for (ii, &i) in self.hot.iter().enumerate() {
                r[(i, k)] = x[(ii, k)] as f64;
            }
        }
    }
}

/// Bunch–Kaufman `LBLᵀ` of `f` (lower triangle, in place) in the precision of `T`.
fn lblt_factor<T: faer::traits::ComplexField>(
    f: MatMut<'_, T>,
    subdiag: &mut [T],
    perm: &mut [usize],
    perm_inv: &mut [usize],
) -> Result<(), FaerError> {
    let params = Spec::<bunch_kaufman::factor::LbltParams, T>::default();
    let mut mem = MemBuffer::try_new(bunch_kaufman::factor::cholesky_in_place_scratch::<usize, T>(
        f.nrows(),
        Par::rayon(0),
        params,
    ))
    .map_err(|_| FaerError::OutOfMemory)?;
    bunch_kaufman::factor::cholesky_in_place(
        f,
        faer::diag::DiagMut::from_slice_mut(subdiag),
        perm,
        perm_inv,
        Par::rayon(0),
        MemStack::new(&mut mem),
        params,
    );
    Ok(())
}

/// `R ← F⁻¹ R` with the factor of [`lblt_factor`].
fn lblt_solve<T: faer::traits::ComplexField>(
    f: faer::MatRef<'_, T>,
    subdiag: &[T],
    perm: faer::perm::PermRef<'_, usize>,
    rhs: MatMut<'_, T>,
    par: Par,
) {
    let mut mem = MemBuffer::new(bunch_kaufman::solve::solve_in_place_scratch::<usize, T>(f.nrows(), rhs.ncols(), par));
    bunch_kaufman::solve::solve_in_place_with_conj(
        f,
        f.diagonal(),
        faer::diag::DiagRef::from_slice(subdiag),
        Conj::No,
        perm,
        rhs,
        par,
        MemStack::new(&mut mem),
    );
}

/// The correction of the old factor for `F₁ = F₀ + E D Eᵀ` (`E` the columns of the
/// identity at the changed rows `R`, `D = (F₁ − F₀)_RR`, `k × k`): with `Y = F₀⁻¹ E` and
/// `C = I + D Eᵀ Y`, `F₁⁻¹ b = y − Y C⁻¹ D Eᵀ y` for `y = F₀⁻¹ b` (Woodbury's identity
/// without `D⁻¹`, which may not exist).
struct LowRank {
    d: Mat<f64>,
    c: faer::linalg::solvers::PartialPivLu<f64>,
}

/// Entry `(i, j)` of a matrix stored in full or by its lower triangle.
fn entry(m: &Mat<f64>, full: bool, i: usize, j: usize) -> f64 {
    if full || i >= j {
        m[(i, j)]
    } else {
        m[(j, i)]
    }
}

/// The factor and what it is of.
struct FactorState {
    factor: DenseFactor,
    /// The `F` it factorised (lower triangle, or in full with `reference_full`).
    reference: Mat<f64>,
    reference_full: bool,
    /// The factor is of the current `F` (no Krylov iterations needed).
    current: bool,
    /// Rows of `F` changed since the factor was computed.
    changed: Vec<bool>,
    /// Krylov iterations spent on this factor while stale.
    stale_iterations: usize,
    /// The changed rows `R` in the order of the columns of `y`, and `Y = F₀⁻¹ E_R`.
    rows: Vec<usize>,
    y: Mat<f64>,
    /// The correction for the current `F` (`None`: GMRES on the old factor alone).
    low_rank: Option<LowRank>,
    /// The rows from which `F`'s rows are multipliers: hot in a [`BlockFactor`] when they
    /// couple to a hot displacement row (a stuck point's Λ row has no diagonal; cold, with
    /// its displacement rows hot, it would leave `A_CC` singular).
    multipliers_from: usize,
    /// Blocks built and Schur complements refactorised ([`BlockFactor`]).
    block_builds: usize,
    schur_refactors: usize,
}

impl FactorState {
    /// `v ← F⁻¹ v` with the old factor and the low-rank correction (the preconditioner).
    fn precondition(&self, v: &mut [f64]) {
        let n = v.len();
        self.factor.solve(MatMut::from_column_major_slice_mut(v, n, 1));
        let Some(lr) = &self.low_rank else { return };
        let k = self.rows.len();
        let mut t = Mat::<f64>::zeros(k, 1);
        for a in 0..k {
            t[(a, 0)] = (0..k).map(|b| lr.d[(a, b)] * v[self.rows[b]]).sum();
        }
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&lr.c, Conj::No, t.as_mut());
        for b in 0..k {
            let tb = t[(b, 0)];
            if tb != 0.0 {
                for (vi, &yi) in v.iter_mut().zip(self.y.col(b).iter()) {
                    *vi -= yi * tb;
                }
            }
        }
    }

    /// Factorises `m` and makes it the reference (a single-precision factor is not
    /// current: its solves are GMRES preconditioned by it).
    fn factor(&mut self, m: &Mat<f64>, full: bool, single: bool) -> Result<(), FaerError> {
        self.factor.factor(m, full, single)?;
        self.factorised(m, full);
        Ok(())
    }

    /// A refactorisation of `m` in single precision: by blocks ([`BlockFactor`]) when the
    /// rows changed since the factor are all hot rows of the blocks it has (only `S`
    /// refactorised), or when they are at most [`BLOCK_HOT_FRACTION`] of `F` (new blocks,
    /// the hot rows those and the previous blocks' ones); else whole.
    fn refactor_single(&mut self, m: &Mat<f64>, full: bool) -> Result<(), FaerError> {
        let n = m.nrows();
        let log = std::env::var_os("FISSURE_CONTACT_LOG").is_some();
        if self.factor.valid && blocks_enabled() {
            let clock = std::time::Instant::now();
            let changed = &self.changed;
            if let Some(block) = self.factor.block.as_mut() {
                if (0..n).all(|i| !changed[i] || block.is_hot[i]) && block.refactor(m, full) {
                    self.schur_refactors += 1;
                    if log {
                        eprintln!(
                            "  F by blocks: S of the {} hot rows refactorised ({:.1} ms)",
                            block.hot.len(),
                            clock.elapsed().as_secs_f64() * 1e3
                        );
                    }
                    self.factorised(m, full);
                    return Ok(());
                }
            }
            let old = self.factor.block.as_ref();
            let from = self.multipliers_from;
            let mut is_hot: Vec<bool> = (0..n).map(|i| changed[i] || old.is_some_and(|b| b.is_hot[i])).collect();
            // A multiplier row coupled to a hot displacement row is hot too.
            let hot_rows: Vec<usize> = (0..from).filter(|&j| is_hot[j]).collect();
            for i in from..n {
                if !is_hot[i] {
                    is_hot[i] = hot_rows.iter().any(|&j| entry(m, full, i, j) != 0.0 || entry(m, full, j, i) != 0.0);
                }
            }
            let hot: Vec<usize> = (0..n).filter(|&i| is_hot[i]).collect();
            if !hot.is_empty() && (hot.len() as f64) <= BLOCK_HOT_FRACTION * n as f64 {
                let h = hot.len();
                if let Some(block) = BlockFactor::build(m, full, hot) {
                    self.block_builds += 1;
                    if log {
                        eprintln!(
                            "  F by blocks: built for {h} hot rows of {n} ({:.1} ms)",
                            clock.elapsed().as_secs_f64() * 1e3
                        );
                    }
                    self.factor.set_block(Box::new(block));
                    self.factorised(m, full);
                    return Ok(());
                }
            }
        }
        self.factor(m, full, true)
    }

    /// The bookkeeping of a new factor of `m`.
    fn factorised(&mut self, m: &Mat<f64>, full: bool) {
        self.reference.copy_from(m);
        self.reference_full = full;
        self.current = !self.factor.single;
        self.changed.fill(false);
        self.stale_iterations = 0;
        self.rows.clear();
        self.y = Mat::zeros(0, 0);
        self.low_rank = None;
    }

    /// The low-rank correction for `m` (whose rows differ from the reference in the
    /// `changed` rows only): `Y` extended by the new rows (one multi-column solve), `D`,
    /// and `C` factorised.
    fn low_rank(&mut self, m: &Mat<f64>, full: bool) {
        let n = m.nrows();
        let clock = std::time::Instant::now();
        let new: Vec<usize> = (0..n).filter(|&i| self.changed[i] && !self.rows.contains(&i)).collect();
        let n_new = new.len();
        if !new.is_empty() {
            let mut e = Mat::<f64>::zeros(n, new.len());
            for (c, &i) in new.iter().enumerate() {
                e[(i, c)] = 1.0;
            }
            self.factor.solve(e.as_mut());
            let k0 = self.rows.len();
            let mut y = Mat::<f64>::zeros(n, k0 + new.len());
            if k0 > 0 {
                y.as_mut().submatrix_mut(0, 0, n, k0).copy_from(self.y.as_ref());
            }
            y.as_mut().submatrix_mut(0, k0, n, new.len()).copy_from(e.as_ref());
            self.y = y;
            self.rows.extend(new);
        }
        let y_ms = clock.elapsed().as_secs_f64() * 1e3;
        let k = self.rows.len();
        let mut d = Mat::<f64>::zeros(k, k);
        // The changed rows in increasing order: (row of F, position in `rows`).
        let mut order: Vec<(usize, usize)> = self.rows.iter().enumerate().map(|(a, &i)| (i, a)).collect();
        order.sort_unstable();
        if !full && !self.reference_full {
            // Both lower triangles: each entry (i ≥ j) read once, down column j of both (in
            // increasing i), and mirrored. The same differences as entry by entry; reading
            // the k² entries row-wise across two nf × nf matrices was memory-bound (0.2–0.8 s
            // a kept iteration on the 3D Hertz sphere row, k ≈ 1 400, nf = 8 701).
            for (t, &(j, b)) in order.iter().enumerate() {
                let (mc, rc) = (m.col(j), self.reference.col(j));
                for &(i, a) in &order[t..] {
                    let v = mc[i] - rc[i];
                    d[(a, b)] = v;
                    d[(b, a)] = v;
                }
            }
        } else {
            for &(j, b) in &order {
                for &(i, a) in &order {
                    d[(a, b)] = entry(m, full, i, j) - entry(&self.reference, self.reference_full, i, j);
                }
            }
        }
        // C = I + D Eᵀ Y. D is sparse (a changed point changes the entries among its own
        // element's unknowns only: on the 3D Hertz sphere row 71 flipped points change
        // 1 180 rows and a few percent of D's entries), so Cᵀ = I + (Eᵀ Y)ᵀ Dᵀ is built
        // column by column from D's nonzeros (`nnz(D) k` multiply-adds, against `k³` for
        // the dense product), and the dense product (in parallel) only when D is dense.
        let nnz = d.col_iter().map(|col| col.iter().filter(|&&v| v != 0.0).count()).sum::<usize>();
        let c = if 4 * nnz < k * k {
            // Column b of Sᵀ = row rows[b] of Y.
            // Gathered eight columns of Y at a time (L2-resident), down each in increasing
            // row order, each write a whole cache line of Sᵀ.
            let mut st = Mat::<f64>::zeros(k, k);
            for c0 in (0..k).step_by(8) {
                let c1 = (c0 + 8).min(k);
                for &(j, b) in &order {
                    for col in c0..c1 {
                        st[(col, b)] = self.y[(j, col)];
                    }
                }
            }
            // Row a of C (column a of Cᵀ) from row a of D, in parallel over the rows (each
            // row's terms summed in the order of b, as one sequential pass would).
            let d_rows: Vec<Vec<(usize, f64)>> = (0..k)
                .map(|a| (0..k).filter_map(|b| Some((b, d[(a, b)])).filter(|&(_, v)| v != 0.0)).collect())
                .collect();
            let row_of_c = |(a, row): (usize, &Vec<(usize, f64)>)| {
                let mut dst = vec![0.0; k];
                dst[a] = 1.0;
                for &(b, v) in row {
                    for (o, &s) in dst.iter_mut().zip(st.col(b).iter()) {
                        *o += v * s;
                    }
                }
                dst
            };
            // In parallel from PARALLEL_C_ROWS rows (the 3D sphere row's k ≈ 1 400); below,
            // the threads' wake-up is not worth it (the 2D rows' k ≤ 250).
            let rows_of_c: Vec<Vec<f64>> = if k >= PARALLEL_C_ROWS {
                d_rows.par_iter().enumerate().map(row_of_c).collect()
            } else {
                d_rows.iter().enumerate().map(row_of_c).collect()
            };
            Mat::from_fn(k, k, |a, r| rows_of_c[a][r])
        } else {
            let mut s = Mat::<f64>::zeros(k, k);
            for (a, &i) in self.rows.iter().enumerate() {
                for b in 0..k {
                    s[(a, b)] = self.y[(i, b)];
                }
            }
            let mut c = Mat::<f64>::identity(k, k);
            faer::linalg::matmul::matmul(c.as_mut(), faer::Accum::Add, d.as_ref(), s.as_ref(), 1.0, Par::rayon(0));
            c
        };
        let c_ms = clock.elapsed().as_secs_f64() * 1e3 - y_ms;
        self.low_rank = Some(LowRank { d, c: faer::linalg::solvers::PartialPivLu::new(c.as_ref()) });
        if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
            eprintln!(
                "  kept F: rank {k} ({n_new} new columns of Y: {y_ms:.1} ms), nnz(D) {nnz}, C {c_ms:.1} ms, LU of C {:.1} ms",
                clock.elapsed().as_secs_f64() * 1e3 - y_ms - c_ms
            );
        }
    }
}

/// `F` (see the module documentation), its factor, and the counts.
pub(crate) struct DenseBlock {
    /// `F`: its lower triangle, or in full when `full`.
    matrix: Mat<f64>,
    full: bool,
    state: Mutex<FactorState>,
    /// Whether a factor may be reused stale (`FISSURE_CONDENSED_REFACTOR` unset).
    reuse: bool,
    factorizations: AtomicUsize,
    reused: AtomicUsize,
    krylov_solves: AtomicUsize,
    krylov_iterations: AtomicUsize,
}

impl DenseBlock {
    /// An `nf × nf` block, zero, with no factor.
    pub(crate) fn new(nf: usize) -> Self {
        DenseBlock {
            matrix: Mat::zeros(nf, nf),
            full: false,
            state: Mutex::new(FactorState {
                factor: DenseFactor::new(nf),
                reference: Mat::zeros(nf, nf),
                reference_full: false,
                current: false,
                changed: vec![false; nf],
                stale_iterations: 0,
                rows: Vec::new(),
                y: Mat::zeros(0, 0),
                low_rank: None,
                multipliers_from: nf,
                block_builds: 0,
                schur_refactors: 0,
            }),
            reuse: std::env::var_os("FISSURE_CONDENSED_REFACTOR").is_none(),
            factorizations: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
            krylov_solves: AtomicUsize::new(0),
            krylov_iterations: AtomicUsize::new(0),
        }
    }

    /// The rows from `nc` on are multipliers (the rows before, displacements of the crack
    /// unknowns): always hot when `F` is factorised by blocks ([`BlockFactor`]).
    pub(crate) fn set_multipliers_from(&mut self, nc: usize) {
        self.state.get_mut().unwrap_or_else(|p| p.into_inner()).multipliers_from = nc;
    }

    /// Blocks built and Schur complements refactorised so far, and the hot rows of the
    /// current factor when it is by blocks ([`BlockFactor`]).
    #[cfg(test)]
    fn block_counts(&self) -> (usize, usize, Option<usize>) {
        let st = self.state.lock().unwrap_or_else(|p| p.into_inner());
        (st.block_builds, st.schur_refactors, st.factor.block.as_ref().map(|b| b.hot.len()))
    }

    /// `F` to fill: its lower triangle (`full` false) or all of it, before
    /// [`Self::refresh`].
    pub(crate) fn matrix_mut(&mut self, full: bool) -> &mut Mat<f64> {
        self.full = full;
        &mut self.matrix
    }

    /// Whether `F` is stored in full (the last [`Self::matrix_mut`]).
    pub(crate) fn is_full(&self) -> bool {
        self.full
    }

    /// Forgets the factor (the bulk stage changed: `F` is another matrix).
    pub(crate) fn invalidate(&mut self) {
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        st.factor.valid = false;
        st.current = false;
        st.low_rank = None;
        st.rows.clear();
        st.y = Mat::zeros(0, 0);
    }

    /// After `F` was refilled: `changed` are the rows (and columns) that differ from the
    /// previous `F` (`None`: unknown, or every row), `small` whether the change is small in
    /// size (then kept whatever the rows). Refactorises, or keeps the factor stale for
    /// Krylov solves (see the module documentation). Returns whether it refactorised.
    pub(crate) fn refresh(&mut self, changed: Option<&[usize]>, small: bool) -> Result<bool, FaerError> {
        let nf = self.matrix.nrows();
        let st = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        if let (true, true, Some(rows)) = (self.reuse, st.factor.valid, changed) {
            for &i in rows {
                st.changed[i] = true;
            }
            let k = st.changed.iter().filter(|&&c| c).count();
            let kept = if k == 0 {
                // The factor's own F (nothing changed since it).
                true
            } else if k <= max_rank(nf) {
                st.low_rank(&self.matrix, self.full);
                st.current = false;
                true
            } else if small && st.stale_iterations < max_iterations(nf) {
                // The preconditioner stays the inverse of the previous F (the old factor
                // and the correction it had): F moved little from it.
                st.current = false;
                true
            } else {
                false
            };
            if kept {
                self.reused.fetch_add(1, Ordering::Relaxed);
                return Ok(false);
            }
        }
        if single_precision(nf) {
            st.refactor_single(&self.matrix, self.full)?;
        } else {
            st.factor(&self.matrix, self.full, false)?;
        }
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        Ok(true)
    }

    /// `r ← F⁻¹ r`: with the factor when it is current, otherwise by GMRES preconditioned
    /// by the old factor and its low-rank correction (refactorising if that does not
    /// converge).
    pub(crate) fn solve(&self, mut r: MatMut<'_, f64>) {
        let mut st = self.state.lock().unwrap_or_else(|p| p.into_inner());
        if st.current {
            st.factor.solve(r);
            return;
        }
        let nf = self.matrix.nrows();
        let cap = max_iterations(nf);
        let b: Vec<f64> = r.as_ref().col(0).iter().copied().collect();
        let st = &mut *st;
        let (x, iterations, converged) =
            gmres(|v, out| self.apply(v, out), |v| st.precondition(v), &b, KRYLOV_TOLERANCE, cap);
        st.stale_iterations += iterations;
        self.krylov_solves.fetch_add(1, Ordering::Relaxed);
        self.krylov_iterations.fetch_add(iterations, Ordering::Relaxed);
        if converged {
            for (i, v) in x.into_iter().enumerate() {
                r[(i, 0)] = v;
            }
            return;
        }
        // Not converged within the budget: refactorise in double precision and solve
        // directly.
        match st.factor(&self.matrix, self.full, false) {
            Ok(()) => {
                self.factorizations.fetch_add(1, Ordering::Relaxed);
                st.factor.solve(r);
            }
            // Out of memory for the factor's scratch: the best iterate (its residual
            // check fails and the caller recovers).
            Err(_) => {
                for (i, v) in x.into_iter().enumerate() {
                    r[(i, 0)] = v;
                }
            }
        }
    }

    /// `out = F v`.
    pub(crate) fn apply(&self, v: &[f64], out: &mut [f64]) {
        mat_vec(&self.matrix, self.full, v, out);
    }

    /// The counts so far.
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

/// `out = M v` for `M` stored in full or, symmetric, by its lower triangle.
pub(crate) fn mat_vec(m: &Mat<f64>, full: bool, v: &[f64], out: &mut [f64]) {
    let n = m.nrows();
    out.fill(0.0);
    if full {
        for (j, &vj) in v.iter().enumerate() {
            if vj != 0.0 {
                for (o, &a) in out.iter_mut().zip(m.col(j).iter()) {
                    *o += a * vj;
                }
            }
        }
        return;
    }
    for j in 0..n {
        let col = m.col(j);
        let vj = v[j];
        let mut acc = col[j] * vj;
        for i in j + 1..n {
            let a = col[i];
            out[i] += a * vj;
            acc += a * v[i];
        }
        out[j] += acc;
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// GMRES on `A x = b` right-preconditioned by `M⁻¹` (`precondition` applies it in place),
/// from `x₀ = M⁻¹ b`, to `‖b − A x‖ ≤ tol ‖b‖` (the true residual, checked at the end),
/// in at most `max_it` iterations after the first preconditioned solve. Returns `x`, the
/// iterations taken (each one product with `A` and one with `M⁻¹`) and whether it
/// converged. Arnoldi by classical Gram–Schmidt applied twice, the least-squares problem
/// by Givens rotations; the preconditioned directions are kept (flexible form), so `x` is
/// a combination of them without a last preconditioned solve.
pub(crate) fn gmres(
    apply: impl Fn(&[f64], &mut [f64]),
    precondition: impl Fn(&mut [f64]),
    b: &[f64],
    tol: f64,
    max_it: usize,
) -> (Vec<f64>, usize, bool) {
    let n = b.len();
    let norm = |v: &[f64]| dot(v, v).sqrt();
    let bnorm = norm(b);
    let mut x = b.to_vec();
    precondition(&mut x);
    if bnorm == 0.0 {
        return (vec![0.0; n], 0, true);
    }
    let target = tol * bnorm;
    let mut r = vec![0.0; n];
    apply(&x, &mut r);
    for (ri, bi) in r.iter_mut().zip(b) {
        *ri = bi - *ri;
    }
    let beta = norm(&r);
    if beta <= target {
        return (x, 0, true);
    }
    if !beta.is_finite() {
        return (x, 0, false);
    }
    let mut v: Vec<Vec<f64>> = vec![r.iter().map(|ri| ri / beta).collect()];
    let mut z: Vec<Vec<f64>> = Vec::new();
    // Columns of the Hessenberg matrix, rotated to upper triangular.
    let mut h: Vec<Vec<f64>> = Vec::new();
    let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut g = vec![beta];
    let mut w = vec![0.0; n];
    let mut it = 0;
    while it < max_it {
        let mut zj = v[it].clone();
        precondition(&mut zj);
        apply(&zj, &mut w);
        z.push(zj);
        let mut hj = vec![0.0; it + 2];
        for _ in 0..2 {
            let coef: Vec<f64> = v.iter().map(|vi| dot(vi, &w)).collect();
            for (vi, &c) in v.iter().zip(&coef) {
                for (wk, &vk) in w.iter_mut().zip(vi) {
                    *wk -= c * vk;
                }
            }
            for (hk, c) in hj.iter_mut().zip(coef) {
                *hk += c;
            }
        }
        let hn = norm(&w);
        hj[it + 1] = hn;
        for k in 0..it {
            let (a, b2) = (hj[k], hj[k + 1]);
            hj[k] = cs[k] * a + sn[k] * b2;
            hj[k + 1] = -sn[k] * a + cs[k] * b2;
        }
        let (a, b2) = (hj[it], hj[it + 1]);
        let d = a.hypot(b2);
        let (c, s) = if d == 0.0 { (1.0, 0.0) } else { (a / d, b2 / d) };
        hj[it] = d;
        hj[it + 1] = 0.0;
        cs.push(c);
        sn.push(s);
        let gi = g[it];
        g[it] = c * gi;
        g.push(-s * gi);
        h.push(hj);
        it += 1;
        let estimate = g[it].abs();
        if !estimate.is_finite() {
            return (x, it, false);
        }
        if estimate <= 0.5 * target || hn == 0.0 {
            break;
        }
        v.push(w.iter().map(|wk| wk / hn).collect());
    }
    // y = R⁻¹ g, x += Z y.
    let m = it;
    let mut y = vec![0.0; m];
    for i in (0..m).rev() {
        let mut s = g[i];
        for (k, yk) in y.iter().enumerate().skip(i + 1) {
            s -= h[k][i] * yk;
        }
        y[i] = if h[i][i] != 0.0 { s / h[i][i] } else { 0.0 };
    }
    for (zk, &yk) in z.iter().zip(&y) {
        for (xi, &zi) in x.iter_mut().zip(zk) {
            *xi += yk * zi;
        }
    }
    apply(&x, &mut r);
    for (ri, bi) in r.iter_mut().zip(b) {
        *ri = bi - *ri;
    }
    let rn = norm(&r);
    (x, it, rn.is_finite() && rn <= target)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric indefinite `n × n` matrix (saddle-point-like: a positive definite block
    /// and a negative one, coupled), deterministic.
    /// ‖b − F x‖ / ‖b‖ for `F` stored in full and the first column of `x`.
    fn relative_residual(f: &Mat<f64>, x: &Mat<f64>, b: &[f64]) -> f64 {
        let n = b.len();
        let xv: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
        let mut r = vec![0.0; n];
        mat_vec(f, true, &xv, &mut r);
        r.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt() / b.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    fn indefinite(n: usize, seed: u64) -> Mat<f64> {
        let mut s = seed;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut m = Mat::<f64>::zeros(n, n);
        for j in 0..n {
            for i in j..n {
                let v = rnd();
                m[(i, j)] = v;
                m[(j, i)] = v;
            }
        }
        for i in 0..n {
            m[(i, i)] += if i < 2 * n / 3 { n as f64 / 4.0 } else { -(n as f64) / 4.0 };
        }
        m
    }

    /// A rank-k change of a dense symmetric indefinite F (n = 120): O(1) random values
    /// added to the k × k block of rows and columns 10, 37, 64, … (how new statuses enter
    /// F: in the rows and columns of their points among themselves). GMRES preconditioned
    /// by the factor of the old F reaches ‖b − F₁ x‖ ≤ 1e-12 ‖b‖ in at most k + 1
    /// iterations (exact arithmetic: k; module documentation), for k = 1, 3, 6, 20; and
    /// [`DenseBlock`], after [`DenseBlock::refresh`] with those changed rows (k ≤
    /// [`max_rank`] = 40 here), keeps the old factor, corrects it by the low-rank update
    /// (exact: at most one GMRES iteration) and gives the answer of a fresh factorisation
    /// to 1e-11 relative.
    #[test]
    fn stale_factor_gmres_converges_in_k_plus_one_iterations_on_a_rank_k_change() {
        let n = 120;
        let f0 = indefinite(n, 7);
        for k in [1usize, 3, 6, 20] {
            let rows: Vec<usize> = (0..k).map(|t| (10 + 27 * t) % n).collect();
            let delta = indefinite(n, 100 + k as u64);
            let mut f1 = f0.clone();
            for &r in &rows {
                for &c in &rows {
                    f1[(r, c)] += delta[(r, c)];
                }
            }
            let lower = |m: &Mat<f64>| {
                let mut l = Mat::<f64>::zeros(n, n);
                for j in 0..n {
                    for i in j..n {
                        l[(i, j)] = m[(i, j)];
                    }
                }
                l
            };
            let mut old = DenseFactor::new(n);
            old.factor(&lower(&f0), false, false).unwrap();
            let b: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
            let (x, it, ok) = gmres(
                |v, out| mat_vec(&f1, true, v, out),
                |v| old.solve(MatMut::from_column_major_slice_mut(v, n, 1)),
                &b,
                1e-12,
                50,
            );
            let mut r = vec![0.0; n];
            mat_vec(&f1, true, &x, &mut r);
            let res = r.iter().zip(&b).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt()
                / b.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!(ok && res <= 1e-12, "k = {k}: residual {res:e}, converged {ok}");
            assert!(it <= k + 1, "k = {k}: {it} iterations");
            // The same through DenseBlock: F₀ factorised, F₁ solved stale.
            let mut block = DenseBlock::new(n);
            block.reuse = true;
            *block.matrix_mut(false) = lower(&f0);
            assert!(block.refresh(None, false).unwrap(), "the first refresh factorises");
            *block.matrix_mut(false) = lower(&f1);
            assert!(!block.refresh(Some(&rows), false).unwrap(), "k = {k}: a rank-{k} change keeps the factor");
            let mut xs = Mat::<f64>::zeros(n, 1);
            for i in 0..n {
                xs[(i, 0)] = b[i];
            }
            block.solve(xs.as_mut());
            let mut fresh = DenseFactor::new(n);
            fresh.factor(&lower(&f1), false, false).unwrap();
            let mut xd = xs.clone();
            for i in 0..n {
                xd[(i, 0)] = b[i];
            }
            fresh.solve(xd.as_mut());
            let scale = (0..n).map(|i| xd[(i, 0)].abs()).fold(0.0, f64::max);
            let diff = (0..n).map(|i| (xs[(i, 0)] - xd[(i, 0)]).abs()).fold(0.0, f64::max);
            assert!(diff <= 1e-11 * scale, "k = {k}: stale solve differs from the fresh one by {diff:e} ({scale:e})");
            let c = block.counts();
            assert_eq!((c.factorizations, c.reused, c.krylov_solves), (1, 1, 1), "k = {k}: {c:?}");
            assert!(c.krylov_iterations <= 1, "k = {k}: {c:?}");
        }
    }

    /// A sparse change in many rows, as a stick/slip flip of a few points makes it: n = 600,
    /// 30 "points" of two rows each (k = 60 ≤ [`max_rank`] = 200), each changing its own
    /// 2 × 2 block only (nnz(D) = 120 < k²/4: `C = I + D Eᵀ Y` built from D's nonzeros).
    /// The kept factor with its correction gives the fresh factorisation's answer to 1e-11
    /// relative with at most one GMRES iteration (a wrong `C` would need up to k).
    #[test]
    fn sparse_low_rank_change_of_many_rows_is_exact() {
        let n = 600;
        let f0 = indefinite(n, 11);
        let rows: Vec<usize> = (0..30).flat_map(|t| [7 + 19 * t, 8 + 19 * t]).collect();
        let mut f1 = f0.clone();
        for (t, pair) in rows.chunks(2).enumerate() {
            let (a, b) = (pair[0], pair[1]);
            let v = 0.3 + 0.01 * t as f64;
            f1[(a, a)] += 2.0 * v;
            f1[(b, b)] -= v;
            f1[(a, b)] += 0.5 * v;
            f1[(b, a)] += 0.5 * v;
        }
        let lower = |m: &Mat<f64>| {
            let mut l = Mat::<f64>::zeros(n, n);
            for j in 0..n {
                for i in j..n {
                    l[(i, j)] = m[(i, j)];
                }
            }
            l
        };
        let mut block = DenseBlock::new(n);
        block.reuse = true;
        *block.matrix_mut(false) = lower(&f0);
        assert!(block.refresh(None, false).unwrap());
        *block.matrix_mut(false) = lower(&f1);
        assert!(!block.refresh(Some(&rows), false).unwrap(), "a change in 60 ≤ n/3 rows keeps the factor");
        let b: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
        let mut xs = Mat::<f64>::zeros(n, 1);
        for i in 0..n {
            xs[(i, 0)] = b[i];
        }
        let mut xd = xs.clone();
        block.solve(xs.as_mut());
        let mut fresh = DenseFactor::new(n);
        fresh.factor(&lower(&f1), false, false).unwrap();
        fresh.solve(xd.as_mut());
        let scale = (0..n).map(|i| xd[(i, 0)].abs()).fold(0.0, f64::max);
        let diff = (0..n).map(|i| (xs[(i, 0)] - xd[(i, 0)]).abs()).fold(0.0, f64::max);
        assert!(diff <= 1e-11 * scale, "kept solve differs from the fresh one by {diff:e} ({scale:e})");
        let c = block.counts();
        assert_eq!((c.factorizations, c.reused), (1, 1), "{c:?}");
        assert!(c.krylov_iterations <= 1, "{c:?}");
    }

    /// An unsymmetric F (LU) changed in entries of 6 rows and columns: the stale LU with
    /// its low-rank correction solves it to 1e-12 in at most one GMRES iteration. A change
    /// in more rows than [`max_rank`], not small, refactorises.
    #[test]
    fn stale_lu_and_the_refactorisation_rule() {
        let n = 80;
        let mut f0 = indefinite(n, 3);
        f0[(5, 9)] += 0.7; // unsymmetric
        let mut block = DenseBlock::new(n);
        block.reuse = true;
        *block.matrix_mut(true) = f0.clone();
        assert!(block.refresh(None, false).unwrap());
        let rows = [2usize, 30, 31, 77];
        let mut f1 = f0.clone();
        for &r in &rows {
            f1[(r, 3)] += 1.5;
            f1[(40, r)] -= 0.8;
        }
        *block.matrix_mut(true) = f1.clone();
        let mut touched = rows.to_vec();
        touched.extend([3, 40]);
        assert!(!block.refresh(Some(&touched), false).unwrap());
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = Mat::<f64>::zeros(n, 1);
        for i in 0..n {
            x[(i, 0)] = b[i];
        }
        block.solve(x.as_mut());
        let xv: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
        let mut r = vec![0.0; n];
        mat_vec(&f1, true, &xv, &mut r);
        let res = r.iter().zip(&b).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt()
            / b.iter().map(|v| v * v).sum::<f64>().sqrt();
        let c = block.counts();
        assert!(res <= 1e-12 && c.krylov_iterations <= 1, "residual {res:e}, {c:?}");
        // Every row changed: more than the budget, refactorised.
        let all: Vec<usize> = (0..n).collect();
        assert!(block.refresh(Some(&all), false).unwrap(), "a change of every row refactorises");
        assert_eq!(block.counts().factorizations, 2);
    }

    /// The single-precision factor of a wide `F` ([`single_precision`], from
    /// [`SINGLE_FROM`] = 1 500 rows): a symmetric indefinite `F` (n = 1 600, `LBLᵀ`) and
    /// an unsymmetric one (`LU`), each factorised in single precision by
    /// [`DenseBlock::refresh`] and solved by GMRES preconditioned by it: the residual
    /// ‖b − F x‖ ≤ 1e-12 ‖b‖ (the double-precision factor's answer to the Krylov tolerance,
    /// 1e-13), in at least one and at most 10 GMRES iterations (κ(F)·ε₃₂ ≪ 1 here), and
    /// one factorisation. Then a change of a few rows keeps the single factor with its
    /// low-rank correction, the same residual bound. A width below 1 500 stays in double
    /// precision (no GMRES iteration).
    #[test]
    fn single_precision_factor_of_a_wide_f_solves_to_the_krylov_tolerance() {
        let n = 1600;
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() + 0.1).collect();
        let residual = |f: &Mat<f64>, x: &Mat<f64>| relative_residual(f, x, &b);
        let rhs = || Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        for unsymmetric in [false, true] {
            let mut f0 = indefinite(n, 11);
            if unsymmetric {
                f0[(5, 900)] += 0.7;
                f0[(1300, 2)] -= 0.4;
            }
            let mut block = DenseBlock::new(n);
            block.reuse = true;
            {
                let m = block.matrix_mut(unsymmetric);
                *m = f0.clone();
            }
            assert!(block.refresh(None, false).unwrap());
            let mut x = rhs();
            block.solve(x.as_mut());
            let res = residual(&f0, &x);
            let c = block.counts();
            assert!(
                res <= 1e-12 && (1..=10).contains(&c.krylov_iterations) && c.factorizations == 1,
                "unsymmetric {unsymmetric}: residual {res:e}, {c:?}"
            );
            // A few rows change: the single factor is kept with its correction.
            let rows = [3usize, 400, 401, 1500];
            let mut f1 = f0.clone();
            for &r in &rows {
                f1[(r, r)] += 2.0;
                f1[(r, 10)] += 0.5;
                f1[(10, r)] += 0.5;
            }
            *block.matrix_mut(unsymmetric) = f1.clone();
            let mut touched = rows.to_vec();
            touched.push(10);
            assert!(!block.refresh(Some(&touched), false).unwrap());
            let mut x = rhs();
            block.solve(x.as_mut());
            let res = residual(&f1, &x);
            assert!(res <= 1e-12 && block.counts().factorizations == 1, "kept: residual {res:e}, {:?}", block.counts());
        }
        // Below the width: double precision, a direct solve.
        let m = 1200;
        let f = indefinite(m, 5);
        let mut block = DenseBlock::new(m);
        *block.matrix_mut(true) = f.clone();
        block.refresh(None, false).unwrap();
        let mut x = Mat::<f64>::from_fn(m, 1, |i, _| (i as f64).cos());
        block.solve(x.as_mut());
        assert_eq!(block.counts().krylov_iterations, 0);
    }

    /// A wide `F` (n = 1 600, single precision) whose iterations change more rows than a
    /// low-rank correction takes (`max_rank` = 533) is refactorised by blocks
    /// ([`BlockFactor`]): after a whole factorisation, rows 0–699 change (symmetric pattern,
    /// as the contact terms): blocks built with those 700 hot rows (the rows from 1 500 on,
    /// "multipliers", hot too since they couple to them: 800 in all); rows 100–649 change
    /// again: only `S` is refactorised (hot rows unchanged); rows 900–1 459 change (cold
    /// ones): new blocks with the union, 1 360 > 0.8 n rows, so `F` is factorised whole. A
    /// cold row with no diagonal coupled only to hot rows (a stuck multiplier left cold)
    /// makes `A_CC` singular: the blocks are refused and `F` is factorised whole. Every
    /// solve: ‖b − F x‖ ≤ 1e-12 ‖b‖ (GMRES to the Krylov tolerance 1e-13 on the true `F`),
    /// symmetric (lower triangle stored) and unsymmetric.
    #[test]
    fn wide_f_refactorised_by_blocks_at_its_hot_rows_solves_to_the_krylov_tolerance() {
        let n = 1600;
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() + 0.1).collect();
        let residual = |f: &Mat<f64>, x: &Mat<f64>| relative_residual(f, x, &b);
        // The rows in `rows` changed among themselves (pattern symmetric), by `amount`.
        let change = |f: &mut Mat<f64>, rows: std::ops::Range<usize>, amount: f64| {
            for i in rows.clone() {
                f[(i, i)] += amount;
                let j = rows.start + (i * 7 + 3) % rows.len();
                f[(i, j)] += 0.3 * amount;
                f[(j, i)] += 0.3 * amount;
            }
        };
        for unsymmetric in [false, true] {
            let mut f = indefinite(n, 11);
            if unsymmetric {
                f[(5, 900)] += 0.7;
                f[(1300, 2)] -= 0.4;
            }
            let mut block = DenseBlock::new(n);
            block.reuse = true;
            block.set_multipliers_from(1500);
            let solve_check = |block: &DenseBlock, f: &Mat<f64>, what: &str| {
                let mut x = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
                block.solve(x.as_mut());
                let res = residual(f, &x);
                assert!(res <= 1e-12, "unsymmetric {unsymmetric}, {what}: residual {res:e}, {:?}", block.counts());
            };
            *block.matrix_mut(unsymmetric) = f.clone();
            assert!(block.refresh(None, false).unwrap());
            solve_check(&block, &f, "whole");
            change(&mut f, 0..700, 3.0);
            *block.matrix_mut(unsymmetric) = f.clone();
            assert!(block.refresh(Some(&(0..700).collect::<Vec<_>>()), false).unwrap());
            assert_eq!(block.block_counts(), (1, 0, Some(800)), "unsymmetric {unsymmetric}: blocks built");
            solve_check(&block, &f, "blocks built");
            change(&mut f, 100..650, -2.0);
            *block.matrix_mut(unsymmetric) = f.clone();
            assert!(block.refresh(Some(&(100..650).collect::<Vec<_>>()), false).unwrap());
            assert_eq!(block.block_counts(), (1, 1, Some(800)), "unsymmetric {unsymmetric}: S refactorised");
            solve_check(&block, &f, "S refactorised");
            change(&mut f, 900..1460, 1.5);
            *block.matrix_mut(unsymmetric) = f.clone();
            assert!(block.refresh(Some(&(900..1460).collect::<Vec<_>>()), false).unwrap());
            assert_eq!(block.block_counts(), (1, 1, None), "unsymmetric {unsymmetric}: whole");
            solve_check(&block, &f, "whole again");
            assert_eq!(block.counts().factorizations, 4);
        }
        // A cold row with no diagonal, coupled to hot rows only: A_CC singular, F whole.
        let mut f = indefinite(n, 13);
        for j in 0..n {
            f[(1550, j)] = 0.0;
            f[(j, 1550)] = 0.0;
        }
        f[(1550, 3)] = 1.0;
        f[(3, 1550)] = 1.0;
        let mut block = DenseBlock::new(n);
        block.reuse = true;
        *block.matrix_mut(false) = f.clone();
        assert!(block.refresh(None, false).unwrap());
        change(&mut f, 0..700, 3.0);
        *block.matrix_mut(false) = f.clone();
        assert!(block.refresh(Some(&(0..700).collect::<Vec<_>>()), false).unwrap());
        assert_eq!(block.block_counts(), (0, 0, None), "a singular A_CC is refused");
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        block.solve(x.as_mut());
        let res = residual(&f, &x);
        assert!(res <= 1e-12, "singular A_CC: residual {res:e}");
    }
}
