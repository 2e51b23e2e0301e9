//! The contact tangent factorised by condensation onto the crack unknowns: the bulk is
//! factorised once, and each contact iteration factorises only a small dense matrix.
//!
//! Entry point: [`CondensedFactor`], used by [`super::FaerSolver`] for contact
//! systems (see [`super::FaerSolver::analyse_condensed`]).
//!
//! The unknowns are split into the interior `I`, the crack unknowns `c` (primal unknowns
//! coupled to a multiplier that contact may change: the enriched dofs of the contact
//! elements in small sliding, all their dofs in large sliding) and the multipliers `m`. Contact changes only the `(c ∪ m)²` block:
//! the bulk `K_II`, `K_Ic` never change between iterations (linear elasticity, small
//! sliding). With `I` split further into the parts of a nested dissection and their
//! separator `s` (two halves factorised in parallel, as in [`super::split`]), the ordering is
//! `[part 1, part 2, s, c | m]`. Each half holds its part and the unknowns `t_k ⊆ s ∪ c`
//! (3 = `s ∪ c`) its part couples to: `M_k = [Akk Akt; Atk Att]` is a principal submatrix
//! of the bulk, hence positive definite, and its Cholesky factor gives
//! `T_k T_kᵀ = Att − Atk Akk⁻¹ Akt`. The rows of `A33` outside `t_k` get no update from
//! part `k`, so the Schur complement of the bulk on `s ∪ c` is
//! `E = A33 + Σ_k scatter(T_k T_kᵀ − A33[t_k])` and, eliminating the separator once more
//! with `G = E_ss` (Cholesky) and `Z = G⁻¹ E_sc`,
//!
//! ```text
//! F = [ E_cc − E_cs Z + (A_cc − A_cc^bulk)   A_cm ]     (dense, symmetric indefinite,
//!     [ A_mc                                 A_mm ]      Bunch–Kaufman LBLᵀ)
//! ```
//!
//! (an unsymmetric contact tangent, whose entries differ from their transposes in the
//! crack block: `F` in full and partial-pivoting LU) is all that a new contact tangent needs: [`CondensedFactor::factorize`] refactorises `F`
//! only, of the size of the crack unknowns (a few hundred to a few thousand), while the
//! halves, `E`, `G` and `Z` are redone only when the bulk values change. A solve is the
//! forward substitution in both halves, the dense solves with `G` and `F`, and the backward
//! substitution in both halves (`F`'s factor may be one of an earlier `F` that differs in
//! few rows, the solve then GMRES preconditioned by it: `dense_block.rs`); a Newton
//! correction whose interior residual is zero
//! ([`CondensedFactor::solve_deferred`]) needs the dense solve only, and the interior
//! response is applied once at the end ([`CondensedFactor::apply_pending`]).
//!
//! **Which multipliers `F` holds.** `m` in `F` is the multipliers coupled in the pattern
//! to some primal unknown. The others, the *free* multipliers `f` (their rows and
//! columns have entries in multiplier rows only: today the slave nodes of a meshed pair
//! in small sliding whose points are all dormant, `contact::zone`, or unpaired),
//! hold the open law −M/ρ_n, −M, coupled to each other and to a few kept multipliers `e`
//! at their edge; they are condensed out of `F` exactly by the Schur complement of their
//! block (`free.rs`): `F_ee` gets `− A_ef A_ff⁻¹ A_fe` (a sparse Cholesky factor of
//! `−A_ff`, rebuilt whenever a value of the `f` columns changes, compared at every
//! factorisation), every solve eliminates `b_f` from the right-hand side of `F` and
//! recovers `x_f = A_ff⁻¹ (b_f − A_fe x_e)` after it. This is block Gaussian elimination
//! of the `f` unknowns, in any order equal to the solution of the whole system; the
//! structural criterion does not depend on the contact zone's bookkeeping, and a block
//! that is not symmetric negative definite (no law of the code gives one) abandons the
//! condensed factor for the plain LDLᵀ. Without free multipliers nothing changes.
//!
//! When the interior (the primal unknowns outside `c`) is not connected, as the two bodies
//! of a meshed contact pair, which the bulk couples only through their contact faces'
//! unknowns, the halves may instead be the bodies themselves (`interior_bodies`: no
//! separator, each half's trailing block only its own body's crack unknowns); the analysis
//! keeps the split of fewer predicted flops (`Layout::flops`: the slower half's sparse
//! factor and `T_k T_kᵀ`, then `G`, `Z` and `base`). The bodies' halves are built first;
//! the dissection's (faer's symbolic factorisation of each, a third of the analysis) only
//! when its flops predicted from the bodies' halves (`Layout::predicted_flops`) are below
//! the bodies': never for one part (the 3D case; a lower bound), and in 2D from the
//! `m^{3/2}` cost of a nested dissection factor of `m` unknowns.
//!
//! **The bulk stage in single precision** (opt-in: `FISSURE_BULK_SINGLE`): the halves'
//! Cholesky factors in `f32` (`split.rs`; a breakdown falls back to `f64`, said on the
//! standard error). `E`, `base` and so `F` are then off by about `ε₃₂ κ`: a full solve is
//! refined against the true residual (`solver.rs`), `F` is a preconditioner of the Newton
//! step, but the deferred solves' residual term `(K_cc − S_c) Δ` must be exact, which
//! needs the exact interior response (`interior.rs`: conjugate gradients on `K_II`
//! preconditioned by the `f32` halves, about once per Newton loop). Why it is not the
//! default: `interior.rs` and `docs/contact-algorithms.md`, "The condensed bulk stage in
//! single precision".
//!
//! The bulk values are the ones given to [`CondensedFactor::set_bulk`] (the contact loop
//! passes `K`); entries outside `(c ∪ m)²` must then be equal in every matrix factorised
//! (recognised by a hash, [`CondensedFactor::bulk_matches`]; the linear solver refactorises
//! the bulk otherwise), and the couplings of the multipliers to interior unknowns must be
//! zero (checked; the linear solver falls back to the sparse LDLᵀ otherwise).

use super::cholesky::predicted_flops;
use super::dense_block::DenseBlock;
use super::free::{FreeBlock, FreeError};
use super::interior::{pcg, InteriorSync, SYNC_FORCING};
use super::refine::{ETA_TARGET_CHOLESKY, ETA_TARGET_PIVOTING};
use super::split::{
    add_t_tt, add_t_w, backward_half, build_half, factor_half, forward_half, split_candidate, Half, SplitError,
};
use crate::solve::backend::LinearError;
use crate::solve::ordering::{multipliers_after, primal_ordering, primal_subpattern, Order};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::FaerError;
use faer::{Accum, Mat, MatMut, Par, Spec};
use rayon::prelude::*;

/// No position (in `F`, in the edge pairs).
const NONE: usize = usize::MAX;

/// Each half's `T_k T_kᵀ` and its seconds (factor, product), or why its factor failed.
type HalfResult = Result<(Mat<f64>, [f64; 2]), SplitError>;

/// Whether the bulk stage's halves are factorised in single precision: only when asked,
/// by `FISSURE_BULK_SINGLE` (developer switch) or [`CondensedFactor::set_bulk_precision`]
/// (tests). Measured on the 3D Hertz sphere bench row (`docs/performance.md`, "The
/// condensed bulk stage in single precision"): the halves factorise faster (about 2×
/// expected; the loaded machine's runs scattered) and the peak falls from 2.7 to 1.9 GB, but keeping the deferred Newton solves
/// exact costs about one conjugate-gradient solve on the bulk per Newton loop
/// (`interior.rs`), 41 on that row, more than the factorisation saves; so the default is
/// double precision.
fn bulk_single_asked() -> bool {
    std::env::var_os("FISSURE_BULK_SINGLE").is_some()
}

/// The symbolic part and the factors (see the module documentation).
pub(crate) struct CondensedFactor {
    /// `perm[q]` = unknown at position `q` of `[part 1, part 2, s, c]` (primal unknowns).
    perm: Vec<usize>,
    /// The multipliers `F` keeps, in the order of its last block.
    mults: Vec<usize>,
    /// The free multipliers, condensed out of `F` (`free.rs`).
    free: FreeBlock,
    /// For each `f_entries` entry whose row and column are both edge multipliers of
    /// `free` (indices `a ≥ b`), the index `a·|e| + b` of its pair; `NONE` otherwise.
    f_pair: Vec<usize>,
    /// Whether each lower pair `(a, b)` of edge multipliers is an entry of the pattern.
    pair_in_pattern: Vec<bool>,
    /// The scaled correction `S_e A_ef A_ff⁻¹ A_fe S_e` (both triangles) subtracted from
    /// the edge block of the current `F`; empty: no `F` yet.
    cor_in_f: Mat<f64>,
    /// Sizes of the parts (`n2 = 0`: one half), the separator and the crack unknowns.
    n1: usize,
    n2: usize,
    ns: usize,
    nc: usize,
    halves: Vec<Half>,
    /// Whether the halves are the bodies of the interior ([`interior_bodies`]), not the
    /// parts of the nested dissection.
    by_bodies: bool,
    /// Lower entries of `A33`: (row, col) in `s ∪ c` and the position in the values.
    a33: Vec<(usize, usize, usize)>,
    /// The coefficient of each `a33` entry in `E`: 1 minus the number of halves whose
    /// trailing block holds both its row and column (see [`Layout`]).
    a33_coef: Vec<f64>,
    /// Lower entries of the `(c ∪ m)²` block: (row, col) in `F` and the position in the
    /// values.
    f_entries: Vec<(usize, usize, usize)>,
    /// The position in the values of the transposed entry of each `f_entries` (the
    /// pattern is structurally symmetric): an unsymmetric contact tangent differs there.
    f_mirror: Vec<usize>,
    /// Whether each unknown is a crack unknown or a multiplier (`c ∪ m`, the free ones
    /// included).
    in_f: Vec<bool>,
    /// Hash of the (unscaled) values outside `(c ∪ m)²` (the bulk) when the bulk was
    /// factorised (see [`Self::bulk_hash`]).
    bulk_hash: u64,
    /// Positions of the couplings of multipliers to interior unknowns (must be zero).
    zero_pos: Vec<usize>,
    /// Unscaled values of the `f_entries` when the bulk was factorised.
    f_bulk_raw: Vec<f64>,
    /// Bulk values of the `f_entries` (the `A_cc^bulk` of the module documentation; 0 in
    /// the multiplier rows).
    f_bulk: Vec<f64>,
    /// Whether the bulk stage (halves, `G`, `Z`, `base`) is current.
    bulk_ready: bool,
    /// Positions of the diagonal entries of the crack unknowns in the values.
    crack_diag: Vec<usize>,
    /// The shift σ (scaled units) added to the diagonal of the crack unknowns in the bulk
    /// stage and taken off `base` again ([`Self::shift_crack_block`]); 0: none.
    shift: f64,
    /// Cholesky factor of `G = E_ss` (lower), `ns × ns`.
    g: Mat<f64>,
    /// `Z = G⁻¹ E_sc`, `ns × nc`.
    z: Mat<f64>,
    /// `E_cc − E_cs Z`, `nc × nc` (lower triangle).
    base: Mat<f64>,
    /// `F` and its factor, kept across factorisations while few of its rows change
    /// (`dense_block.rs`).
    dense: DenseBlock,
    /// The values of the `f_entries` and of their mirrors (interleaved) in the last `F`,
    /// to find the rows that change; empty: no `F` since the bulk stage.
    f_last: Vec<f64>,
    /// The developer's fault switch `FISSURE_FAULT_CONDENSED_SOLVE` (read once, at the
    /// analysis): every dense solve returns the negated answer, so the residual check
    /// fails and the caller's recovery (the plain LDLᵀ of the whole system) runs. It
    /// exists to test that recovery, which no ordinary case reaches.
    fault: bool,
    /// The position of every primal unknown in `perm` (`NONE` for the multipliers).
    inv: Vec<usize>,
    /// `‖K_II‖∞` of the scaled bulk (the interior rows and columns), for the backward error
    /// of the exact interior responses (`interior.rs`).
    interior_norm: f64,
    /// With a bulk stage in single precision: the crack corrections whose interior response
    /// is known exactly (`interior.rs`).
    sync: std::sync::Mutex<InteriorSync>,
    /// The developer's fault switch `FISSURE_FAULT_BULK` (read once, at the analysis):
    /// `pivot` makes every single-precision bulk stage report a breakdown, so that the
    /// fallback to double precision is exercised by the tests.
    bulk_fault: bool,
    /// The precision of the bulk stage asked for (`Some(true)`: single), `None`: the
    /// developer switch decides ([`bulk_single_asked`]).
    bulk_precision: Option<bool>,
}

/// A sparse matrix in compressed columns (both triangles): column pointers, row indices,
/// values (the scaled system of the solver).
pub(crate) type Csc<'a> = (&'a [usize], &'a [usize], &'a [f64]);

/// Why a condensed factorisation failed: a non-positive pivot of the bulk at this
/// unknown, or faer's error.
#[derive(Debug)]
pub(crate) enum CondensedError {
    NonPositive {
        unknown: usize,
    },
    /// A multiplier couples to an interior unknown with a nonzero value: the matrix does
    /// not have the structure the condensation needs.
    NotCondensable,
    /// The block of the free multipliers cannot be condensed out of `F` with these values
    /// (not symmetric, or not definite).
    Free(FreeError),
    Faer(FaerError),
}

impl From<FaerError> for CondensedError {
    fn from(e: FaerError) -> Self {
        CondensedError::Faer(e)
    }
}

impl CondensedFactor {
    /// The backward substitution in the halves (in parallel when there are two) of their
    /// forward results `zs`, with the trailing unknowns `x3` solved.
    fn backward_halves(&self, zs: Vec<Vec<f64>>, x3: &[f64]) -> Vec<Vec<f64>> {
        if self.halves.len() == 2 {
            let mut it = zs.into_iter();
            let (z0, z1) = (it.next().expect("two halves"), it.next().expect("two halves"));
            let (x0, x1) =
                rayon::join(|| backward_half(&self.halves[0], z0, x3), || backward_half(&self.halves[1], z1, x3));
            vec![x0, x1]
        } else {
            vec![backward_half(&self.halves[0], zs.into_iter().next().expect("one half"), x3)]
        }
    }

    /// Builds the halves for the pattern (both triangles stored) and the primal ordering
    /// `order` (`order[q]` = primal unknown at position `q`) whose first `n1` unknowns are
    /// part 1, the next `n2` part 2 and the rest the separator (`n1 = n2 = 0`: no split,
    /// one part). `crack[j]` marks the primal unknowns coupled to a multiplier; they are
    /// moved out of the parts and the separator to the end. `mults` are the multipliers.
    /// A multiplier may couple in the pattern to an unmarked primal unknown if the value
    /// of that coupling is always zero (the standard dofs of a cut cell in small sliding),
    /// which [`Self::factorize`] checks. `None` if a part 1 unknown couples to a part 2
    /// unknown.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn analyse(
        col_ptr: &[usize],
        row_idx: &[usize],
        order: &[usize],
        (n1, n2): (usize, usize),
        crack: &[bool],
        mults: Vec<usize>,
        candidates: Candidates,
    ) -> Result<Option<CondensedFactor>, FaerError> {
        let n = col_ptr.len() - 1;
        let np = order.len();
        let keep =
            |r: std::ops::Range<usize>| -> Vec<usize> { order[r].iter().copied().filter(|&j| !crack[j]).collect() };
        let (p1, p2, sep) = if n1 + n2 > 0 {
            (keep(0..n1), keep(n1..n1 + n2), keep(n1 + n2..np))
        } else {
            (keep(0..np), vec![], vec![])
        };
        let cr: Vec<usize> = order.iter().copied().filter(|&j| crack[j]).collect();
        let nc = cr.len();
        const NONE: usize = usize::MAX;
        // Position in F of every crack unknown and multiplier (the free ones are taken out
        // below).
        let mut f_of = vec![NONE; n];
        for (t, &j) in cr.iter().chain(&mults).enumerate() {
            f_of[j] = t;
        }
        // Couplings of the multipliers to interior unknowns (both triangles): zero values.
        let mut zero_pos = Vec::new();
        for &l in &mults {
            for (p, &i) in row_idx[col_ptr[l]..col_ptr[l + 1]].iter().enumerate() {
                if f_of[i] == NONE {
                    zero_pos.push(col_ptr[l] + p);
                    zero_pos.push(super::split::lower_position(col_ptr, row_idx, l, i));
                }
            }
        }
        // The split at the top separator applies if no part 1 unknown couples to a part 2
        // unknown.
        let coupled = !p2.is_empty() && {
            let mut part = vec![0u8; n];
            for &j in &p2 {
                part[j] = 2;
            }
            p1.par_iter().any(|&j| row_idx[col_ptr[j]..col_ptr[j + 1]].iter().any(|&i| part[i] == 2))
        };
        let log = std::env::var("FISSURE_CONTACT_LOG").is_ok();
        // The two candidates: the nested dissection's parts and separator, and the bodies
        // (the interior's connected components in two bins, no separator) when the
        // interior is not connected. The bodies' halves are built first; the dissection's
        // only if its predicted flops (`Layout::predicted_flops`) are below the bodies'
        // (`Candidates::Full`: whenever both exist, to check the prediction).
        let clock = std::time::Instant::now();
        let dissection = (!coupled).then(|| {
            let parts = if p2.is_empty() { vec![p1] } else { vec![p1, p2] };
            layout(col_ptr, row_idx, parts, sep, &cr)
        });
        let bodies = interior_bodies(col_ptr, row_idx, order, crack)
            .map(|b| {
                let mut l = Layout { bodies: true, ..layout(col_ptr, row_idx, b, vec![], &cr) };
                l.build(col_ptr, row_idx).map(|()| l)
            })
            .transpose()?;
        if log {
            eprintln!("condensed: the interior's bodies in {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
        }
        let chosen = match (dissection, bodies) {
            (Some(mut d), Some(b)) => {
                let predicted = d.predicted_flops(nc, &b);
                let bodies_flops = b.flops(nc);
                let build = candidates == Candidates::Full || predicted < bodies_flops;
                if build {
                    d.build(col_ptr, row_idx)?;
                }
                if log {
                    let name = if d.n2 == 0 { "one part (no split)" } else { "split at the top separator" };
                    eprintln!("condensed: split at the bodies: {}", b.describe(nc));
                    eprintln!(
                        "condensed: {name}: {}; predicted from the bodies {predicted:.3e} flops{}",
                        d.describe(nc),
                        if build { "" } else { ": not built" }
                    );
                }
                if !build || bodies_flops <= d.flops(nc) {
                    b
                } else {
                    d
                }
            }
            (Some(mut l), None) => {
                l.build(col_ptr, row_idx)?;
                l
            }
            (None, Some(l)) => l,
            (None, None) => return Ok(None),
        };
        let Layout { perm, n1, n2, ns, halves, a33, a33_coef, bodies: by_bodies, .. } = chosen;
        if log {
            eprintln!(
                "condensed: parts {n1} + {n2}, separator {ns}, crack {nc}, multipliers {} ({}; analysis {:.1} ms)",
                mults.len(),
                if by_bodies {
                    "split at the bodies"
                } else if n2 == 0 {
                    "one part"
                } else {
                    "split at the top separator"
                },
                clock.elapsed().as_secs_f64() * 1e3
            );
        }
        let s0 = n1 + n2;
        // The multipliers F keeps (coupled in the pattern to some primal unknown) and the
        // free ones, condensed out of F by their own block (`free.rs`).
        let in_f: Vec<bool> = f_of.iter().map(|&t| t != NONE).collect();
        let (mults, free) = FreeBlock::split(col_ptr, row_idx, &mults, crack.len());
        let nf = nc + mults.len();
        let mut f_of = vec![NONE; n];
        for (t, &j) in cr.iter().chain(&mults).enumerate() {
            f_of[j] = t;
        }
        let free = FreeBlock::new(col_ptr, row_idx, free, &f_of);
        let ne = free.n_edge();
        let mut e_of = vec![NONE; nf];
        for (a, &t) in free.edge_pos.iter().enumerate() {
            e_of[t] = a;
        }
        let mut f_entries = Vec::new();
        let mut f_mirror = Vec::new();
        let mut f_pair = Vec::new();
        let mut pair_in_pattern = vec![false; ne * ne];
        // Only the columns of the crack unknowns and the kept multipliers hold entries of F.
        for &j in perm[s0 + ns..].iter().chain(&mults) {
            for (p, &i) in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().enumerate() {
                let p = col_ptr[j] + p;
                if f_of[i] != NONE && f_of[i] >= f_of[j] {
                    f_entries.push((f_of[i], f_of[j], p));
                    let mirror = col_ptr[i]
                        + row_idx[col_ptr[i]..col_ptr[i + 1]]
                            .binary_search(&j)
                            .expect("a structurally symmetric pattern");
                    f_mirror.push(mirror);
                    let (a, b) = (e_of[f_of[i]], e_of[f_of[j]]);
                    f_pair.push(if a != NONE && b != NONE {
                        pair_in_pattern[a * ne + b] = true;
                        a * ne + b
                    } else {
                        NONE
                    });
                }
            }
        }
        if log {
            eprintln!(
                "condensed: F {nf} wide ({nc} crack unknowns + {} multipliers); {} free multipliers condensed out of F ({ne} kept ones at their edge)",
                mults.len(),
                free.free.len()
            );
        }
        let n_f = f_entries.len();
        let crack_diag =
            perm[s0 + ns..].iter().map(|&j| super::split::lower_position(col_ptr, row_idx, j, j)).collect();
        let mut inv = vec![NONE; n];
        for (q, &j) in perm.iter().enumerate() {
            inv[j] = q;
        }
        Ok(Some(CondensedFactor {
            perm,
            mults,
            free,
            f_pair,
            pair_in_pattern,
            cor_in_f: Mat::zeros(0, 0),
            n1,
            n2,
            ns,
            nc,
            halves,
            by_bodies,
            a33,
            a33_coef,
            f_entries,
            f_mirror,
            zero_pos,
            in_f,
            bulk_hash: 0,
            f_bulk: vec![0.0; n_f],
            f_bulk_raw: vec![0.0; n_f],
            bulk_ready: false,
            crack_diag,
            shift: 0.0,
            g: Mat::zeros(0, 0),
            z: Mat::zeros(0, 0),
            base: Mat::zeros(0, 0),
            dense: {
                let mut dense = DenseBlock::new(nf);
                dense.set_multipliers_from(nc);
                dense
            },
            f_last: Vec::new(),
            fault: std::env::var_os("FISSURE_FAULT_CONDENSED_SOLVE").is_some(),
            inv,
            interior_norm: 0.0,
            sync: std::sync::Mutex::new(InteriorSync::default()),
            bulk_fault: std::env::var("FISSURE_FAULT_BULK").as_deref() == Ok("pivot"),
            bulk_precision: None,
        }))
    }

    /// Number of halves (2: split in parallel at the top separator or at the bodies).
    #[cfg(test)]
    pub(crate) fn halves(&self) -> usize {
        self.halves.len()
    }

    /// The sizes of the halves' trailing blocks, the separator's, and whether the halves
    /// are the bodies.
    #[cfg(test)]
    pub(crate) fn trailing(&self) -> (Vec<usize>, usize, bool) {
        (self.halves.iter().map(Half::nt).collect(), self.ns, self.by_bodies)
    }

    /// Bytes the dense crack block holds beyond the lower triangle of `F` that
    /// [`Self::nnz_factor`] counts: `F` stored in full, its factor, the reference copy of
    /// the kept factor and the low-rank correction's `Y` (at most `nf/3` columns:
    /// `dense_block::max_rank`), a single-precision factor's copies, and the free
    /// multipliers' correction on their edge (three `|e| × |e|` copies: built, scaled, in
    /// `F`), for the memory check before the numeric phase.
    pub(crate) fn dense_extra_bytes(&self) -> u64 {
        let nf = (self.nc + self.mults.len()) as u64;
        let ne = self.free.n_edge() as u64;
        // A single-precision factor (`dense_block::single_precision`): its f32 copy of `F`,
        // and for an unsymmetric `F` the copy its `LU` keeps, 8 bytes an entry at most.
        let single = if super::dense_block::single_precision(nf as usize) { 8 * nf * nf } else { 0 };
        8 * (3 * nf * nf + nf * nf / 3 - nf * (nf + 1) / 2 + 3 * ne * ne) + single
    }

    /// `Σ c_j²` over the parts' unknowns, `c_j` the column counts of the factor of each part
    /// alone (the leading block of its half's factor, read from the supernodal structure):
    /// a lower bound of the flops of the whole system's factor in the primal ordering with
    /// the multipliers after their unknowns (`predicted_flops`' measure), up to the
    /// supernodes' padding. A part is a principal submatrix of the whole in the same
    /// relative order, so a fill path of its factor (through lower-numbered unknowns of the
    /// part) is one of the whole's, column by column, and the parts are disjoint.
    pub(crate) fn part_flops(&self) -> f64 {
        self.halves.iter().map(Half::part_flops).sum()
    }

    /// Entries of the factors: the halves, the dense `G`, `Z`, and `F`.
    pub(crate) fn nnz_factor(&self) -> usize {
        let nf = self.nc + self.mults.len();
        self.halves.iter().map(|h| h.l_values_len()).sum::<usize>()
            + self.ns * (self.ns + 1) / 2
            + self.ns * self.nc
            + nf * (nf + 1) / 2
    }

    /// A hash of the bit patterns of the values outside `(c ∪ m)²`, with their positions:
    /// equal values give equal hashes, and a change anywhere changes it (up to a 2⁻⁶⁴
    /// collision). Costs one pass over the values, in parallel, and no memory (a copy of the
    /// bulk values would be as large as the matrix).
    fn bulk_hash(&self, col_ptr: &[usize], row_idx: &[usize], raw: &[f64]) -> u64 {
        let in_f = &self.in_f;
        (0..col_ptr.len() - 1)
            .into_par_iter()
            .map(|j| {
                let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ (j as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
                for (&v, &i) in raw[col_ptr[j]..col_ptr[j + 1]].iter().zip(&row_idx[col_ptr[j]..col_ptr[j + 1]]) {
                    if !(in_f[i] && in_f[j]) {
                        h = (h ^ v.to_bits() ^ (i as u64).rotate_left(32)).wrapping_mul(0x0000_0100_0000_01b3);
                    }
                }
                // Finalise (splitmix64) so that the sum over columns mixes well.
                h ^= h >> 30;
                h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
                h ^= h >> 27;
                h = h.wrapping_mul(0x94d0_49bb_1331_11eb);
                h ^ (h >> 31)
            })
            .reduce(|| 0, u64::wrapping_add)
    }

    /// Whether the bulk stage is factorised for these (unscaled) values: equal outside the
    /// `(c ∪ m)²` block and, with `crack_block`, in the crack block too.
    pub(crate) fn bulk_matches(&self, col_ptr: &[usize], row_idx: &[usize], raw: &[f64], crack_block: bool) -> bool {
        self.bulk_ready
            && (!crack_block
                || self
                    .f_entries
                    .iter()
                    .zip(&self.f_bulk_raw)
                    .all(|(&(i, j, p), &v)| i >= self.nc || j >= self.nc || raw[p] == v))
            && self.bulk_hash(col_ptr, row_idx, raw) == self.bulk_hash
    }

    /// Factorises the bulk stage (halves, `E`, `G`, `Z`) for the scaled values `vals`
    /// (`raw`: the same unscaled, kept to recognise them).
    pub(crate) fn set_bulk(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        vals: &[f64],
        raw: &[f64],
    ) -> Result<(), CondensedError> {
        self.bulk_ready = false;
        self.dense.invalidate();
        self.f_last.clear();
        self.bulk_hash = self.bulk_hash(col_ptr, row_idx, raw);
        for (v, &(_, _, p)) in self.f_bulk_raw.iter_mut().zip(&self.f_entries) {
            *v = raw[p];
        }
        // The bulk part of F: the crack block (the multiplier rows are not in the halves).
        let nc = self.nc;
        for (v, &(i, j, p)) in self.f_bulk.iter_mut().zip(&self.f_entries) {
            *v = if i < nc && j < nc { vals[p] } else { 0.0 };
        }
        let ns = self.ns;
        let n3 = ns + nc;
        let clock = std::time::Instant::now();
        let log = std::env::var("FISSURE_CONTACT_LOG").is_ok();
        // The bulk with σ on the diagonal of the crack unknowns (see `shift_crack_block`).
        let shifted: Option<Vec<f64>> = (self.shift != 0.0).then(|| {
            let mut v = vals.to_vec();
            for &p in &self.crack_diag {
                v[p] += self.shift;
            }
            v
        });
        let vals = shifted.as_deref().unwrap_or(vals);
        // Each half on its own thread: its factor, then T_k T_kᵀ (lower triangle); in
        // single precision when wanted, in double again if that breaks down.
        let single = self.bulk_precision.unwrap_or_else(bulk_single_asked);
        let mut results = self.factor_halves(vals, single);
        if single {
            let fault = self.bulk_fault.then_some("a non-positive pivot (injected)".to_string());
            if let Some(why) = fault.or_else(|| results.iter().find_map(|r| r.as_ref().err().map(|e| format!("{e:?}"))))
            {
                eprintln!(
                    "fissure: the condensed bulk stage in single precision broke down ({why}): factorised in double precision"
                );
                results = self.factor_halves(vals, false);
            }
        }
        *self.sync.get_mut().unwrap_or_else(|p| p.into_inner()) = InteriorSync::default();
        self.interior_norm = self.interior_norm_inf(col_ptr, row_idx, vals);
        // E = A33 + Σ_k scatter(T_k T_kᵀ − A33[t_k]) (lower triangle; the trailing
        // positions are ascending, so the scatter stays in the lower triangle).
        let mut e = Mat::<f64>::zeros(n3, n3);
        let mut half_s = Vec::new();
        for (h, r) in self.halves.iter().zip(results) {
            match r {
                Ok((tt, seconds)) => {
                    half_s.push(format!("{:.1} + {:.1}", seconds[0] * 1e3, seconds[1] * 1e3));
                    for (c, &tc) in h.trail.iter().enumerate() {
                        for (r, &tr) in h.trail.iter().enumerate().skip(c) {
                            e[(tr, tc)] += tt[(r, c)];
                        }
                    }
                }
                Err(SplitError::NonPositive { position }) => {
                    return Err(CondensedError::NonPositive { unknown: self.perm[position.min(self.perm.len() - 1)] })
                }
                Err(SplitError::Faer(e)) => return Err(e.into()),
            }
        }
        if log {
            let what = if self.by_bodies { "the bodies" } else { "the top separator" };
            eprintln!(
                "  halves (split at {what}): {:.1} ms (each half's factor + T Tᵀ: {} ms)",
                clock.elapsed().as_secs_f64() * 1e3,
                half_s.join(", ")
            );
        }
        for (&(i, j, p), &coef) in self.a33.iter().zip(&self.a33_coef) {
            if coef != 0.0 {
                e[(i, j)] += coef * vals[p];
            }
        }
        if log {
            eprintln!("  E: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
        }
        // G = E_ss (Cholesky), Z = G⁻¹ E_sc, base = E_cc − E_cs Z.
        let mut g = Mat::<f64>::zeros(ns, ns);
        for j in 0..ns {
            for i in j..ns {
                g[(i, j)] = e[(i, j)];
            }
        }
        if ns > 0 {
            let mut mem = MemBuffer::try_new(faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
                ns,
                Par::Seq,
                Spec::default(),
            ))
            .map_err(|_| FaerError::OutOfMemory)?;
            if let Err(LltError::NonPositivePivot { index }) = faer::linalg::cholesky::llt::factor::cholesky_in_place(
                g.as_mut(),
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Spec::default(),
            ) {
                return Err(CondensedError::NonPositive { unknown: self.perm[self.n1 + self.n2 + index.min(ns - 1)] });
            }
        }
        // E_sc: rows ns.. of E hold E_cs (lower storage), so E_sc = E[ns.., ..ns]ᵀ.
        let mut base = Mat::<f64>::zeros(nc, nc);
        for j in 0..nc {
            for i in j..nc {
                base[(i, j)] = e[(ns + i, ns + j)];
            }
        }
        // With W = L_G⁻¹ E_sc: E_cs Z = Wᵀ W and Z = L_Gᵀ⁻¹ W.
        let mut z = Mat::<f64>::zeros(ns, nc);
        if ns > 0 && nc > 0 {
            let mut w = Mat::<f64>::zeros(ns, nc);
            for c in 0..nc {
                for r in 0..ns {
                    w[(r, c)] = e[(ns + c, r)];
                }
            }
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(g.as_ref(), w.as_mut(), Par::rayon(0));
            z.copy_from(&w);
            faer::linalg::triangular_solve::solve_upper_triangular_in_place(g.transpose(), z.as_mut(), Par::rayon(0));
            faer::linalg::matmul::triangular::matmul(
                base.as_mut(),
                faer::linalg::matmul::triangular::BlockStructure::TriangularLower,
                Accum::Add,
                w.transpose(),
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                w.as_ref(),
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                -1.0,
                Par::rayon(0),
            );
        }
        // The Schur complement of K + σ I_c on c is S_c + σ I: σ comes off again.
        for i in 0..nc {
            base[(i, i)] -= self.shift;
        }
        if log {
            eprintln!("  G, Z, base: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
        }
        self.g = g;
        self.z = z;
        self.base = base;
        self.bulk_ready = true;
        Ok(())
    }

    /// Each half's factor (in single precision with `single`) and `T_k T_kᵀ` (lower
    /// triangle), on its own thread, with the seconds of each (factor, product).
    fn factor_halves(&mut self, vals: &[f64], single: bool) -> Vec<HalfResult> {
        self.halves
            .par_iter_mut()
            .map(|h| {
                h.single = single;
                let clock = std::time::Instant::now();
                factor_half(h, vals)?;
                let factor_s = clock.elapsed().as_secs_f64();
                let nt = h.nt();
                let mut tt = Mat::<f64>::zeros(nt, nt);
                if nt > 0 {
                    add_t_tt(tt.as_mut(), faer::MatRef::from_column_major_slice(&h.t, nt, nt), Accum::Replace);
                }
                Ok((tt, [factor_s, clock.elapsed().as_secs_f64() - factor_s]))
            })
            .collect()
    }

    /// Whether the bulk stage's halves are in single precision.
    pub(crate) fn single_bulk(&self) -> bool {
        self.halves.iter().any(Half::is_single)
    }

    /// Asks for the bulk stage in single precision (`Some(true)`) or double, `None`: as the
    /// developer switch says; `fault`: every single-precision bulk stage reports a
    /// breakdown (the fallback's test). Takes effect at the next [`Self::set_bulk`].
    #[cfg(test)]
    pub(crate) fn set_bulk_precision(&mut self, single: Option<bool>, fault: bool) {
        self.bulk_precision = single;
        self.bulk_fault = fault;
        self.bulk_ready = false;
    }

    /// Shifts the crack block of the bulk stage by σ (scaled units; the scaled diagonal of a
    /// primal unknown is 1) from the next [`Self::set_bulk`] on; returns false if it was
    /// already shifted. The bulk `K` is positive definite only if it holds every body by
    /// itself; a body held only through contact (a meshed body pressed by a contact pair, a
    /// part cut off by a closed crack) leaves `K` singular and a half's trailing block not
    /// positive definite. `K + σ I_c` is positive definite as soon as every rigid motion
    /// left free moves some crack unknown, which a body held through contact does (its
    /// contact faces are in `c`). The Schur complement onto `c` of `K + σ I_c` is
    /// `S_c + σ I` exactly (the shift is in the `c × c` block only), so `base` takes σ off
    /// again and `F` is unchanged up to round-off.
    pub(crate) fn shift_crack_block(&mut self, sigma: f64) -> bool {
        if self.shift != 0.0 {
            return false;
        }
        self.shift = sigma;
        self.bulk_ready = false;
        true
    }

    /// Factorises `F` for the scaled values `vals` (`raw`: the same unscaled, `scale` the
    /// scaling `S` of `vals = S raw S`) of a matrix whose bulk is the one of
    /// [`Self::set_bulk`] (see [`Self::bulk_matches`]), or keeps the previous factor of `F`
    /// when few of its rows changed: the solves then run GMRES preconditioned by it
    /// (`dense_block.rs`). The free multipliers' correction of `F` is brought up to the
    /// values first (`free.rs`: rebuilt whenever a value of their columns changed).
    pub(crate) fn factorize(&mut self, vals: &[f64], raw: &[f64], scale: &[f64]) -> Result<(), CondensedError> {
        if self.zero_pos.iter().any(|&p| vals[p] != 0.0) {
            return Err(CondensedError::NotCondensable);
        }
        assert!(self.bulk_ready, "the bulk stage is factorised before F");
        let nc = self.nc;
        let nf = nc + self.mults.len();
        let ne = self.free.n_edge();
        let free_clock = std::time::Instant::now();
        let (cor, rebuilt) = self.free.update(raw, scale).map_err(CondensedError::Free)?;
        let free_ms = free_clock.elapsed().as_secs_f64() * 1e3;
        // An unsymmetric contact tangent (the bulk is symmetric: the difference between an
        // entry and its transpose is the contact's): F in full, factorised by LU. The
        // correction is unsymmetric only if the couplings of the free multipliers are.
        let unsymmetric = self
            .f_entries
            .iter()
            .zip(&self.f_mirror)
            .any(|(&(i, j, p), &q)| i != j && (vals[p] - vals[q]).abs() > 1e-13 * vals[p].abs().max(vals[q].abs()))
            || (0..ne).any(|a| {
                (0..a).any(|b| (cor[(a, b)] - cor[(b, a)]).abs() > 1e-13 * cor[(a, b)].abs().max(cor[(b, a)].abs()))
            });
        // The rows (and columns) of F that changed since the last F: both ends of every
        // entry whose value or mirror's value changed (F − its bulk part is these values),
        // and both ends of every pair of edge multipliers whose correction changed.
        // The largest change relative to the largest entry: a small one (the friction
        // thresholds of a later pass) moves F little, whatever the rows it touches.
        let (mut change, mut largest) = (0.0f64, 0.0f64);
        let cor_changed: Vec<bool> = if self.cor_in_f.nrows() == ne && !self.f_last.is_empty() {
            (0..ne * ne).map(|k| cor[(k / ne, k % ne)] != self.cor_in_f[(k / ne, k % ne)]).collect()
        } else {
            vec![true; ne * ne]
        };
        let changed: Option<Vec<usize>> = (!self.f_last.is_empty()).then(|| {
            let mut mark = vec![false; nf];
            for ((&(i, j, p), &q), last) in self.f_entries.iter().zip(&self.f_mirror).zip(self.f_last.chunks(2)) {
                largest = largest.max(vals[p].abs()).max(vals[q].abs());
                if vals[p] != last[0] || vals[q] != last[1] {
                    mark[i] = true;
                    mark[j] = true;
                    change = change.max((vals[p] - last[0]).abs()).max((vals[q] - last[1]).abs());
                }
            }
            for (k, _) in cor_changed.iter().enumerate().filter(|(_, &c)| c) {
                let (a, b) = (k / ne, k % ne);
                mark[self.free.edge_pos[a]] = true;
                mark[self.free.edge_pos[b]] = true;
                change = change.max((cor[(a, b)] - self.cor_in_f[(a, b)]).abs());
                largest = largest.max(cor[(a, b)].abs());
            }
            (0..nf).filter(|&i| mark[i]).collect()
        });
        let small = change <= SMALL_CHANGE * largest;
        // F = base + (the contact values − their bulk part) at the f_entries − the free
        // multipliers' correction on the edge pairs. The last F is still in the dense
        // block: with the same storage (lower or full) only the entries whose values (or
        // correction) changed are rewritten, by the same expressions as the whole fill (so
        // F is bit for bit the one a whole fill makes); the whole fill writes nf² entries
        // (605 MB on the 3D Hertz sphere row's 8 701 rows) at every contact iteration.
        let incremental = changed.is_some() && self.dense.is_full() == unsymmetric;
        let fill_clock = std::time::Instant::now();
        let base = &self.base;
        let bulk_of = |i: usize, j: usize| if i < nc && j < nc { base[(i, j)] } else { 0.0 };
        // The correction of a lower pair (a ≥ b) and the difference its upper entry adds.
        let cor_lower = |k: usize| cor[(k / ne, k % ne)];
        let cor_upper = |k: usize| cor[(k / ne, k % ne)] - cor[(k % ne, k / ne)];
        let edge_pos = &self.free.edge_pos;
        let f = self.dense.matrix_mut(unsymmetric);
        if incremental {
            for ((((&(i, j, p), &q), last), &b), &k) in self
                .f_entries
                .iter()
                .zip(&self.f_mirror)
                .zip(self.f_last.chunks_mut(2))
                .zip(&self.f_bulk)
                .zip(&self.f_pair)
            {
                let pair = k != NONE && (cor_changed[k] || cor_changed[(k % ne) * ne + k / ne]);
                if vals[p] != last[0] || vals[q] != last[1] || pair {
                    let mut lower = bulk_of(i, j) + (vals[p] - b);
                    if k != NONE {
                        lower -= cor_lower(k);
                    }
                    f[(i, j)] = lower;
                    if unsymmetric && i != j {
                        let mut upper = lower + (vals[q] - vals[p]);
                        if k != NONE {
                            upper += cor_upper(k);
                        }
                        f[(j, i)] = upper;
                    }
                    last[0] = vals[p];
                    last[1] = vals[q];
                }
            }
            for a in 0..ne {
                for b in 0..=a {
                    let k = a * ne + b;
                    if !self.pair_in_pattern[k] && (cor_changed[k] || cor_changed[b * ne + a]) {
                        let (i, j) = (edge_pos[a], edge_pos[b]);
                        let lower = 0.0 - cor_lower(k);
                        f[(i, j)] = lower;
                        if unsymmetric && i != j {
                            f[(j, i)] = lower + cor_upper(k);
                        }
                    }
                }
            }
        } else {
            self.f_last.clear();
            for (&(_, _, p), &q) in self.f_entries.iter().zip(&self.f_mirror) {
                self.f_last.extend([vals[p], vals[q]]);
            }
            f.fill(0.0);
            for j in 0..nc {
                for i in j..nc {
                    f[(i, j)] = self.base[(i, j)];
                }
            }
            for (&(i, j, p), &b) in self.f_entries.iter().zip(&self.f_bulk) {
                f[(i, j)] += vals[p] - b;
            }
            for a in 0..ne {
                for b in 0..=a {
                    f[(edge_pos[a], edge_pos[b])] -= cor_lower(a * ne + b);
                }
            }
            if unsymmetric {
                for j in 0..nf {
                    for i in j + 1..nf {
                        f[(j, i)] = f[(i, j)];
                    }
                }
                for (&(i, j, p), &q) in self.f_entries.iter().zip(&self.f_mirror) {
                    if i != j {
                        f[(j, i)] += vals[q] - vals[p];
                    }
                }
                for a in 0..ne {
                    for b in 0..a {
                        f[(edge_pos[b], edge_pos[a])] += cor_upper(a * ne + b);
                    }
                }
            }
        }
        self.cor_in_f = cor;
        let fill_ms = fill_clock.elapsed().as_secs_f64() * 1e3;
        let refactorised = self.dense.refresh(changed.as_deref(), small)?;
        if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
            let k = changed.as_ref().map_or(nf, Vec::len);
            let free = if rebuilt {
                format!("; the free multipliers' correction rebuilt in {free_ms:.1} ms")
            } else {
                String::new()
            };
            eprintln!(
                "  F: {k} of {nf} rows changed (largest change {:.1e} of the largest entry; {} fill {fill_ms:.1} ms), {}{free}",
                change / largest.max(f64::MIN_POSITIVE),
                if incremental { "incremental" } else { "whole" },
                if refactorised { "refactorised" } else { "previous factor kept (GMRES)" }
            );
        }
        Ok(())
    }

    /// The counts of `F`'s factorisations and Krylov solves.
    pub(crate) fn counts(&self) -> crate::solve::backend::CondensedCounts {
        crate::solve::backend::CondensedCounts {
            width: self.width(),
            free: self.free.free.len(),
            ..self.dense.counts()
        }
    }

    /// Solves `A x = b` in place with the factorisation.
    pub(crate) fn solve_in_place(&self, x: &mut [f64]) {
        let (n1, n2, ns, nc) = (self.n1, self.n2, self.ns, self.nc);
        let n3 = ns + nc;
        let s0 = n1 + n2;
        let bp: Vec<f64> = self.perm.iter().map(|&j| x[j]).collect();
        // Forward in the halves; r3 = b3 + Σ T_k w_k. A right-hand side that is zero on the
        // interior (a contact Newton residual) has nothing to substitute there.
        let interior_zero = bp[..s0 + ns].iter().all(|&v| v == 0.0);
        let zs: Vec<Vec<f64>> = if interior_zero {
            self.halves.iter().map(|h| vec![0.0; h.nk + h.nt()]).collect()
        } else if self.halves.len() == 2 {
            let (z0, z1) =
                rayon::join(|| forward_half(&self.halves[0], &bp[..n1]), || forward_half(&self.halves[1], &bp[n1..s0]));
            vec![z0, z1]
        } else {
            vec![forward_half(&self.halves[0], &bp[..n1])]
        };
        let mut r3: Vec<f64> = bp[s0..].to_vec();
        if !interior_zero {
            for (h, z) in self.halves.iter().zip(&zs) {
                add_t_w(h, &z[h.nk..], &mut r3);
            }
        }
        // Separator: y = G⁻¹ r_s; F [x_c; x_m] = [r_c − Zᵀ r_s; b_m]; x_s = y − Z x_c.
        let mut y = Mat::<f64>::zeros(ns, 1);
        for r in 0..ns {
            y[(r, 0)] = r3[r];
        }
        let nf = nc + self.mults.len();
        let mut rf = Mat::<f64>::zeros(nf, 1);
        for c in 0..nc {
            let zc = self.z.col(c);
            let mut v = r3[ns + c];
            for r in 0..ns {
                v -= zc[r] * r3[r];
            }
            rf[(c, 0)] = v;
        }
        for (t, &l) in self.mults.iter().enumerate() {
            rf[(nc + t, 0)] = x[l];
        }
        let w = self.free.eliminate(x, rf.as_mut());
        if ns > 0 {
            solve_llt_in_place(self.g.as_ref(), y.as_mut());
        }
        self.solve_f_in_place(rf.as_mut());
        self.free.recover(w, rf.as_ref(), x);
        let mut x3 = vec![0.0; n3];
        for r in 0..ns {
            x3[r] = y[(r, 0)];
        }
        for c in 0..nc {
            let xc = rf[(c, 0)];
            x3[ns + c] = xc;
            if xc != 0.0 {
                let zc = self.z.col(c);
                for r in 0..ns {
                    x3[r] -= zc[r] * xc;
                }
            }
        }
        // Backward in the halves.
        let xs = self.backward_halves(zs, &x3);
        for (q, &j) in self.perm.iter().enumerate() {
            x[j] = if q < n1 {
                xs[0][q]
            } else if q < s0 {
                xs[1][q - n1]
            } else {
                x3[q - s0]
            };
        }
        for (t, &l) in self.mults.iter().enumerate() {
            x[l] = rf[(nc + t, 0)];
        }
    }
}

impl CondensedFactor {
    /// Number of crack unknowns.
    pub(crate) fn n_crack(&self) -> usize {
        self.nc
    }

    /// The unknowns whose rows and columns may change between factorisations: the crack
    /// unknowns and the multipliers (the free ones included).
    pub(crate) fn varying(&self) -> impl Iterator<Item = usize> + '_ {
        self.perm[self.n1 + self.n2 + self.ns..].iter().chain(&self.mults).chain(&self.free.free).copied()
    }

    /// The width of `F`: the crack unknowns and the multipliers it keeps.
    pub(crate) fn width(&self) -> usize {
        self.nc + self.mults.len()
    }

    /// Solves for the crack unknowns and multipliers only, for a right-hand side `x` whose
    /// interior rows are zero (ignored) and whose crack rows were computed with interior
    /// values that lack the response to the crack corrections `pending` not yet applied
    /// (see [`Self::apply_pending`]). Leaves the corrections of the crack unknowns and
    /// multipliers in `x`, zero on the interior, and adds the crack corrections to
    /// `pending`. Returns the relative residual of the dense system.
    ///
    /// With `δ_I = −K_II⁻¹ K_Ic Δ_c` the interior response to the pending crack corrections
    /// `Δ_c`, the true crack rows are `r_c + K_cI K_II⁻¹ K_Ic Δ_c = r_c + (K_cc − S_c) Δ_c`,
    /// `S_c` (= `base`) the Schur complement of the bulk on the crack unknowns.
    pub(crate) fn solve_deferred(&self, a: Csc<'_>, x: &mut [f64], pending: &mut [f64]) -> f64 {
        let nc = self.nc;
        let s0 = self.n1 + self.n2 + self.ns;
        let nf = nc + self.mults.len();
        let crack = &self.perm[s0..];
        let mut rf = Mat::<f64>::zeros(nf, 1);
        for (c, &j) in crack.iter().enumerate() {
            rf[(c, 0)] = x[j];
        }
        for (t, &l) in self.mults.iter().enumerate() {
            rf[(nc + t, 0)] = x[l];
        }
        let w = self.free.eliminate(x, rf.as_mut());
        let any = pending.iter().any(|&v| v != 0.0);
        if self.single_bulk() {
            // The interior term exact on the corrections brought in, single-precision
            // accurate on the rest, brought in when its error may matter (`interior.rs`).
            let mut sync = self.sync.lock().unwrap_or_else(|p| p.into_inner());
            if !any || sync.delta.len() != nc {
                sync.reset(s0, nc);
            }
            let d: Vec<f64> = pending.iter().zip(&sync.delta).map(|(p, s)| p - s).collect();
            let mut term = vec![0.0; nc];
            let moved = d.iter().any(|&v| v != 0.0);
            if moved {
                self.schur_term(&d, &mut term);
            }
            let norm2 = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
            let residual = norm2(&mut (0..nf).map(|i| rf[(i, 0)] + if i < nc { sync.term[i] + term[i] } else { 0.0 }));
            let term_norm = norm2(&mut term.iter().copied());
            if moved && sync.rho * term_norm > SYNC_FORCING * residual {
                match self.exact_response(a, &d) {
                    Ok((response, exact, iterations)) => {
                        let error = norm2(&mut exact.iter().zip(&term).map(|(e, t)| e - t));
                        let measured = (error / term_norm.max(f64::MIN_POSITIVE)).max(16.0 * f64::EPSILON);
                        sync.rho = if sync.syncs == 0 { measured } else { sync.rho.max(measured) };
                        sync.syncs += 1;
                        sync.iterations += iterations;
                        sync.delta.copy_from_slice(pending);
                        for (r, v) in sync.response.iter_mut().zip(&response) {
                            *r += v;
                        }
                        for (t, v) in sync.term.iter_mut().zip(&exact) {
                            *t += v;
                        }
                        term.fill(0.0);
                        if std::env::var_os("FISSURE_CONTACT_LOG").is_some() {
                            eprintln!(
                                "  bulk in single precision: interior response brought in ({iterations} CG iterations; relative error of the single-precision term {measured:.1e}; {} so far, {} iterations)",
                                sync.syncs, sync.iterations
                            );
                        }
                    }
                    Err(eta) => {
                        eprintln!(
                            "fissure: the condensed bulk in single precision: conjugate gradients on the interior stopped at a backward error of {eta:.1e}; the contact correction is not solved"
                        );
                        return f64::NAN;
                    }
                }
            }
            for c in 0..nc {
                rf[(c, 0)] += sync.term[c] + term[c];
            }
        } else if any {
            // + K_cc Δ (bulk entries, symmetric) − base Δ (lower storage, symmetric), added
            // to the crack rows in place.
            let mut rows: Vec<f64> = (0..nc).map(|c| rf[(c, 0)]).collect();
            self.schur_term(pending, &mut rows);
            for (c, v) in rows.iter().enumerate() {
                rf[(c, 0)] = *v;
            }
        }
        let rhs = rf.clone();
        self.solve_f_in_place(rf.as_mut());
        // Residual of the dense system.
        let xv: Vec<f64> = rf.col(0).iter().copied().collect();
        let mut fx = vec![0.0; nf];
        self.dense.apply(&xv, &mut fx);
        let mut res = rhs.clone();
        for (r, v) in res.col_mut(0).iter_mut().zip(&fx) {
            *r -= v;
        }
        let norm = |m: &Mat<f64>| m.col(0).iter().map(|v| v * v).sum::<f64>().sqrt();
        let (r, b) = (norm(&res), norm(&rhs));
        for &j in &self.perm[..s0] {
            x[j] = 0.0;
        }
        for (c, &j) in crack.iter().enumerate() {
            x[j] = rf[(c, 0)];
            pending[c] += rf[(c, 0)];
        }
        for (t, &l) in self.mults.iter().enumerate() {
            x[l] = rf[(nc + t, 0)];
        }
        self.free.recover(w, rf.as_ref(), x);
        if b > 0.0 {
            r / b
        } else {
            r
        }
    }

    /// The interior response `δ_I = −K_II⁻¹ K_Ic Δ_c` to the pending crack corrections,
    /// added to `x` (interior rows only); clears `pending`. With a bulk stage in single
    /// precision the response is the exact one (`interior.rs`).
    pub(crate) fn apply_pending(&self, a: Csc<'_>, pending: &mut [f64], x: &mut [f64]) {
        let (n1, n2, ns, nc) = (self.n1, self.n2, self.ns, self.nc);
        if pending.iter().all(|&v| v == 0.0) {
            return;
        }
        if self.single_bulk() {
            let ni = self.n_interior();
            let mut sync = self.sync.lock().unwrap_or_else(|p| p.into_inner());
            if sync.delta.len() != nc {
                sync.reset(ni, nc);
            }
            let d: Vec<f64> = pending.iter().zip(&sync.delta).map(|(p, s)| p - s).collect();
            let mut response = std::mem::take(&mut sync.response);
            if d.iter().any(|&v| v != 0.0) {
                match self.exact_response(a, &d) {
                    Ok((r, _, _)) => {
                        for (t, v) in response.iter_mut().zip(&r) {
                            *t += v;
                        }
                    }
                    Err(eta) => {
                        // Reported, not hidden: the single-precision response stands.
                        eprintln!(
                            "fissure: the condensed bulk in single precision: conjugate gradients on the interior stopped at a backward error of {eta:.1e}; the interior response is the single-precision one"
                        );
                        let mut b = vec![0.0; ni];
                        self.crack_to_interior(a, &d, &mut b);
                        self.interior_solve(&mut b);
                        for (t, v) in response.iter_mut().zip(&b) {
                            *t -= v;
                        }
                    }
                }
            }
            for (q, &j) in self.perm[..ni].iter().enumerate() {
                x[j] += response[q];
            }
            sync.reset(ni, nc);
            pending.fill(0.0);
            return;
        }
        let n3 = ns + nc;
        let s0 = n1 + n2;
        // x3 = [−Z Δ; Δ], then the backward substitution in the halves with y_k = 0.
        let mut x3 = vec![0.0; n3];
        for c in 0..nc {
            let d = pending[c];
            x3[ns + c] = d;
            if d != 0.0 {
                let zc = self.z.col(c);
                for r in 0..ns {
                    x3[r] -= zc[r] * d;
                }
            }
        }
        let zero = |h: &Half| vec![0.0; h.nk + h.nt()];
        let xs: Vec<Vec<f64>> = if self.halves.len() == 2 {
            let (x0, x1) = rayon::join(
                || backward_half(&self.halves[0], zero(&self.halves[0]), &x3),
                || backward_half(&self.halves[1], zero(&self.halves[1]), &x3),
            );
            vec![x0, x1]
        } else {
            vec![backward_half(&self.halves[0], zero(&self.halves[0]), &x3)]
        };
        for (q, &j) in self.perm[..s0 + ns].iter().enumerate() {
            x[j] += if q < n1 {
                xs[0][q]
            } else if q < s0 {
                xs[1][q - n1]
            } else {
                x3[q - s0]
            };
        }
        pending.fill(0.0);
    }
}

/// The interior operators of a bulk stage in single precision (`interior.rs`): positions
/// `0..ni` are the interior (`ni = n1 + n2 + ns`), crack unknowns `0..nc`, scaled units.
impl CondensedFactor {
    /// Interior positions.
    fn n_interior(&self) -> usize {
        self.n1 + self.n2 + self.ns
    }

    /// `‖K_II‖∞` of the scaled values: the largest absolute row sum over the interior.
    fn interior_norm_inf(&self, col_ptr: &[usize], row_idx: &[usize], vals: &[f64]) -> f64 {
        let ni = self.n_interior();
        self.perm[..ni]
            .par_iter()
            .map(|&j| {
                (col_ptr[j]..col_ptr[j + 1]).filter(|&k| self.inv[row_idx[k]] < ni).map(|k| vals[k].abs()).sum::<f64>()
            })
            .reduce(|| 0.0, f64::max)
    }

    /// `out = K_II v` (both on the interior positions; the pattern holds both triangles,
    /// so row `q` is column `perm[q]`).
    fn interior_mul(&self, (col_ptr, row_idx, vals): Csc<'_>, v: &[f64], out: &mut [f64]) {
        let ni = self.n_interior();
        out.par_iter_mut().enumerate().with_min_len(4096).for_each(|(q, o)| {
            let j = self.perm[q];
            let mut acc = 0.0;
            for k in col_ptr[j]..col_ptr[j + 1] {
                let p = self.inv[row_idx[k]];
                if p < ni {
                    acc += vals[k] * v[p];
                }
            }
            *o = acc;
        });
    }

    /// `out = K_Ic d` (`d` on the crack unknowns, `out` on the interior positions).
    fn crack_to_interior(&self, (col_ptr, row_idx, vals): Csc<'_>, d: &[f64], out: &mut [f64]) {
        let ni = self.n_interior();
        out.fill(0.0);
        for (c, &dc) in d.iter().enumerate() {
            if dc == 0.0 {
                continue;
            }
            let j = self.perm[ni + c];
            for k in col_ptr[j]..col_ptr[j + 1] {
                let p = self.inv[row_idx[k]];
                if p < ni {
                    out[p] += vals[k] * dc;
                }
            }
        }
    }

    /// `out = K_cI w` (`w` on the interior positions, `out` on the crack unknowns).
    fn interior_to_crack(&self, (col_ptr, row_idx, vals): Csc<'_>, w: &[f64], out: &mut [f64]) {
        let ni = self.n_interior();
        for (c, o) in out.iter_mut().enumerate() {
            let j = self.perm[ni + c];
            let mut acc = 0.0;
            for k in col_ptr[j]..col_ptr[j + 1] {
                let p = self.inv[row_idx[k]];
                if p < ni {
                    acc += vals[k] * w[p];
                }
            }
            *o = acc;
        }
    }

    /// `b ← K_II⁻¹ b` on the interior positions with the bulk stage's factors (the halves,
    /// then `G` on the separator): exact up to their precision.
    fn interior_solve(&self, b: &mut [f64]) {
        let (n1, n2, ns, nc) = (self.n1, self.n2, self.ns, self.nc);
        let s0 = n1 + n2;
        let zs: Vec<Vec<f64>> = if self.halves.len() == 2 {
            let (z0, z1) =
                rayon::join(|| forward_half(&self.halves[0], &b[..n1]), || forward_half(&self.halves[1], &b[n1..s0]));
            vec![z0, z1]
        } else {
            vec![forward_half(&self.halves[0], &b[..n1])]
        };
        let mut x3 = vec![0.0; ns + nc];
        if ns > 0 {
            x3[..ns].copy_from_slice(&b[s0..s0 + ns]);
            for (h, z) in self.halves.iter().zip(&zs) {
                add_t_w(h, &z[h.nk..], &mut x3);
            }
            let mut y = Mat::<f64>::zeros(ns, 1);
            for r in 0..ns {
                y[(r, 0)] = x3[r];
            }
            solve_llt_in_place(self.g.as_ref(), y.as_mut());
            for r in 0..ns {
                x3[r] = y[(r, 0)];
            }
        }
        x3[ns..].fill(0.0);
        let xs = self.backward_halves(zs, &x3);
        b[..n1].copy_from_slice(&xs[0][..n1]);
        if self.halves.len() == 2 {
            b[n1..s0].copy_from_slice(&xs[1][..n2]);
        }
        b[s0..s0 + ns].copy_from_slice(&x3[..ns]);
    }

    /// The exact interior response `δ = −K_II⁻¹ K_Ic d` to the crack corrections `d` and
    /// the crack rows' term `K_cI K_II⁻¹ K_Ic d = −K_cI δ`, by conjugate gradients
    /// preconditioned by the single-precision halves (`interior.rs`); `Err` with the
    /// backward error reached when they fall short.
    fn exact_response(&self, a: Csc<'_>, d: &[f64]) -> Result<(Vec<f64>, Vec<f64>, usize), f64> {
        let ni = self.n_interior();
        let mut b = vec![0.0; ni];
        self.crack_to_interior(a, d, &mut b);
        for v in &mut b {
            *v = -*v;
        }
        let (response, iterations) = pcg(
            |v, out| self.interior_mul(a, v, out),
            |v| self.interior_solve(v),
            &b,
            self.interior_norm,
            (ETA_TARGET_PIVOTING, ETA_TARGET_CHOLESKY),
        )?;
        let mut term = vec![0.0; self.nc];
        self.interior_to_crack(a, &response, &mut term);
        for v in &mut term {
            *v = -*v;
        }
        Ok((response, term, iterations))
    }

    /// `out += (K_cc − S̃_c) d`: the crack rows' interior term from the bulk stage's Schur
    /// complement `base` (bulk entries of `K_cc` symmetric, `base` in lower storage).
    fn schur_term(&self, d: &[f64], out: &mut [f64]) {
        let nc = self.nc;
        for (&(i, j, _), &v) in self.f_entries.iter().zip(&self.f_bulk) {
            if i < nc && j < nc {
                out[i] += v * d[j];
                if i != j {
                    out[j] += v * d[i];
                }
            }
        }
        for j in 0..nc {
            let dj = d[j];
            let col = self.base.col(j);
            let mut acc = 0.0;
            for i in j..nc {
                acc += col[i] * d[i];
            }
            out[j] -= acc;
            if dj != 0.0 {
                for i in j + 1..nc {
                    out[i] -= col[i] * dj;
                }
            }
        }
    }
}

impl CondensedFactor {
    /// `r ← F⁻¹ r` with the factorisation of `F` (negated under the fault switch, see
    /// `fault`).
    fn solve_f_in_place(&self, mut r: MatMut<'_, f64>) {
        self.solve_f_exact(r.as_mut());
        if self.fault {
            for v in r.col_mut(0).iter_mut() {
                *v = -*v;
            }
        }
    }

    /// `r ← F⁻¹ r` with the factorisation of `F` (or GMRES preconditioned by its
    /// previous factorisation, `dense_block.rs`).
    fn solve_f_exact(&self, r: MatMut<'_, f64>) {
        self.dense.solve(r);
    }
}

/// `X ← G⁻¹ X` with `G = L Lᵀ`, `L` stored in the lower triangle.
fn solve_llt_in_place(l: faer::MatRef<'_, f64>, mut x: MatMut<'_, f64>) {
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), x, Par::Seq);
}

/// Which split candidates [`CondensedFactor::analyse`] builds (faer's symbolic
/// factorisation of their halves) when the interior has bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Candidates {
    /// The bodies, and the dissection only if its flops predicted from the bodies' halves
    /// ([`Layout::predicted_flops`]) are below the bodies' flops.
    Predicted,
    /// Both, to compare their flops (the check of the prediction in the tests).
    #[cfg_attr(not(test), allow(dead_code))]
    Full,
}

/// One way of cutting the interior into halves (see [`CondensedFactor::analyse`]): the
/// ordering `[part 1, part 2, s, c]`, the sizes, the halves, each with the trailing
/// unknowns its part couples to (`t_k ⊆ s ∪ c`), and the entries of `A33` with their
/// coefficient in `E`. Rows of `A33` that part `k` does not couple to get no update from
/// it (`A3k` is zero there), so `E = A33 + Σ_k scatter(T_k T_kᵀ − A33[t_k])`, each half's
/// dense work `|t_k|³/3` twice (its factor's trailing block and `T_k T_kᵀ`) instead of
/// `|s ∪ c|³/3`.
struct Layout {
    perm: Vec<usize>,
    inv: Vec<usize>,
    n1: usize,
    n2: usize,
    ns: usize,
    /// Each half's trailing unknowns (positions in `s ∪ c`, ascending).
    trails: Vec<Vec<usize>>,
    /// The halves, once built ([`Self::build`]: faer's symbolic factorisation of each).
    halves: Vec<Half>,
    a33: Vec<(usize, usize, usize)>,
    a33_coef: Vec<f64>,
    /// The parts are bodies of the interior (no separator).
    bodies: bool,
    /// Wall time of the halves' construction (for the log).
    seconds: f64,
}

impl Layout {
    /// Builds the halves (in parallel).
    fn build(&mut self, col_ptr: &[usize], row_idx: &[usize]) -> Result<(), FaerError> {
        let clock = std::time::Instant::now();
        let sizes = [self.n1, self.n2];
        let (s0, n3) = (self.n1 + self.n2, self.perm.len() - self.n1 - self.n2);
        let (perm, inv, trails) = (&self.perm, &self.inv, &self.trails);
        self.halves = (0..trails.len())
            .into_par_iter()
            .map(|k| build_half(col_ptr, row_idx, perm, inv, k * sizes[0], sizes[k], s0, n3, &trails[k]))
            .collect::<Result<Vec<Half>, FaerError>>()?;
        self.seconds = clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Predicted flops of the bulk stage: the slower half (the halves run in parallel),
    /// then `G`'s Cholesky (`ns³/3`), `Z` (`2 ns² nc`) and `base` (`ns nc²`).
    fn flops(&self, nc: usize) -> f64 {
        let half = self.halves.iter().map(Half::flops).fold(0.0, f64::max);
        half + self.separator_flops(nc)
    }

    /// `G`'s Cholesky, `Z` and `base`.
    fn separator_flops(&self, nc: usize) -> f64 {
        let (s, c) = (self.ns as f64, nc as f64);
        s * s * s / 3.0 + 2.0 * s * s * c + s * c * c
    }

    /// The dense part of [`Self::flops`], known before the halves are built: the largest
    /// trailing block's factor and product (`2 nt³/3`: a connected part fills its trailing
    /// block of `L`), then `G`, `Z` and `base`.
    fn dense_flops(&self, nc: usize) -> f64 {
        let nt = self.trails.iter().map(Vec::len).max().unwrap_or(0) as f64;
        2.0 * nt * nt * nt / 3.0 + self.separator_flops(nc)
    }

    /// The flops of this candidate (the dissection's) predicted from the built halves of
    /// the `bodies` candidate, before its own halves are built:
    ///
    /// - one part (no split; 3D): the largest of the bodies' factor flops plus the cube of
    ///   its trailing block over 3. Each body's half is a principal submatrix of the one
    ///   part's matrix in the same relative order, so its factor's fill is contained in the
    ///   one part's (a fill path through lower-numbered unknowns of a body is one of the
    ///   whole), column by column, and its trailing unknowns are among the one part's:
    ///   this is a lower bound of [`Self::flops`], never below the bodies' flops, and the
    ///   one part is never built (up to faer's supernode amalgamation, which pads both);
    /// - two parts and a separator (2D): [`Self::dense_flops`] plus, for the slower part,
    ///   `Σ_b s_b (|P ∩ B_b| / |B_b|)^{3/2}`, `s_b` the sparse flops of body `b`'s half
    ///   (its flops less its trailing block's `2 nt³/3`) and `|P ∩ B_b|` the unknowns of
    ///   body `b` in the part: a 2D nested dissection factor of `m` unknowns costs
    ///   `O(m^{3/2})` flops, and the part's pieces of the two bodies are independent.
    fn predicted_flops(&self, nc: usize, bodies: &Layout) -> f64 {
        let cube = |t: usize| (t as f64).powi(3);
        if self.n2 == 0 {
            let nt = self.trails.first().map_or(0, Vec::len);
            let largest = bodies.halves.iter().map(|h| h.flops() - cube(h.nt()) / 3.0).fold(0.0, f64::max);
            return largest + cube(nt) / 3.0 + self.separator_flops(nc);
        }
        let sizes = [bodies.n1, bodies.n2];
        let sparse: Vec<f64> = bodies.halves.iter().map(|h| (h.flops() - 2.0 * cube(h.nt()) / 3.0).max(0.0)).collect();
        let slower = [0..self.n1, self.n1..self.n1 + self.n2]
            .into_iter()
            .map(|r| {
                let mut count = [0usize; 2];
                for &j in &self.perm[r] {
                    let q = bodies.inv[j];
                    if q < sizes[0] {
                        count[0] += 1;
                    } else if q < sizes[0] + sizes[1] {
                        count[1] += 1;
                    }
                }
                (0..2.min(sparse.len()))
                    .filter(|&b| sizes[b] > 0)
                    .map(|b| sparse[b] * (count[b] as f64 / sizes[b] as f64).powf(1.5))
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        slower + self.dense_flops(nc)
    }

    /// The sizes, for the log: parts, separator, and each half's trailing unknowns
    /// (separator + crack).
    fn describe(&self, nc: usize) -> String {
        let trails: Vec<String> = self
            .trails
            .iter()
            .map(|t| {
                let sep = t.iter().filter(|&&t| t < self.ns).count();
                format!("{} ({sep} + {})", t.len(), t.len() - sep)
            })
            .collect();
        let built = if self.halves.is_empty() {
            "halves not built".to_string()
        } else {
            format!("predicted {:.3e} flops, built in {:.1} ms", self.flops(nc), self.seconds * 1e3)
        };
        format!(
            "parts {} + {}, separator {}, crack {nc}; trailing blocks {} (separator + crack) of {}; {built}",
            self.n1,
            self.n2,
            self.ns,
            trails.join(" and "),
            self.ns + nc
        )
    }
}

/// The [`Layout`] of `parts` (one or two, each in its order), the separator `sep` and the
/// crack unknowns `cr`: each half's trailing block holds the positions of `sep ∪ cr` its
/// part couples to. The halves are built by [`Layout::build`].
fn layout(col_ptr: &[usize], row_idx: &[usize], parts: Vec<Vec<usize>>, sep: Vec<usize>, cr: &[usize]) -> Layout {
    const NONE: usize = usize::MAX;
    let n = col_ptr.len() - 1;
    let sizes: Vec<usize> = parts.iter().map(Vec::len).collect();
    let ns = sep.len();
    let n3 = ns + cr.len();
    let mut perm: Vec<usize> = parts.into_iter().flatten().collect();
    let s0 = perm.len();
    perm.extend(sep);
    perm.extend_from_slice(cr);
    let mut inv = vec![NONE; n];
    for (q, &j) in perm.iter().enumerate() {
        inv[j] = q;
    }
    let part_of = |q: usize| usize::from(q >= sizes[0]);
    // The positions of the separator block each part couples to.
    let mut touch = vec![vec![false; n3]; sizes.len()];
    for t in 0..n3 {
        let j = perm[s0 + t];
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if inv[i] < s0 {
                touch[part_of(inv[i])][t] = true;
            }
        }
    }
    let trails: Vec<Vec<usize>> = touch.iter().map(|m| (0..n3).filter(|&t| m[t]).collect()).collect();
    let mut a33 = Vec::new();
    let mut a33_coef = Vec::new();
    for t in 0..n3 {
        let j = perm[s0 + t];
        for (p, &i) in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().enumerate() {
            if i >= j && inv[i] != NONE && inv[i] >= s0 {
                let (a, b) = (inv[i] - s0, t);
                let (r, c) = (a.max(b), a.min(b));
                let held = touch.iter().filter(|m| m[r] && m[c]).count();
                a33.push((r, c, col_ptr[j] + p));
                a33_coef.push(1.0 - held as f64);
            }
        }
    }
    let (n1, n2) = (sizes[0], sizes.get(1).copied().unwrap_or(0));
    Layout { perm, inv, n1, n2, ns, trails, halves: vec![], a33, a33_coef, bodies: false, seconds: 0.0 }
}

/// The interior unknowns (primal, not `crack`) in two bins of the connected components of
/// their graph (the largest components first, each to the bin with fewer unknowns), each
/// bin in the order `order`: the bodies of a meshed contact pair, which the bulk couples
/// only through their contact faces' unknowns. `None` if the interior is connected.
fn interior_bodies(col_ptr: &[usize], row_idx: &[usize], order: &[usize], crack: &[bool]) -> Option<Vec<Vec<usize>>> {
    let np = order.len();
    let mut parent: Vec<usize> = (0..np).collect();
    fn root(parent: &mut [usize], mut a: usize) -> usize {
        while parent[a] != a {
            parent[a] = parent[parent[a]];
            a = parent[a];
        }
        a
    }
    for j in (0..np).filter(|&j| !crack[j]) {
        for &i in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().take_while(|&&i| i < j) {
            if !crack[i] {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    let mut size = vec![0usize; np];
    let mut roots = Vec::new();
    for j in (0..np).filter(|&j| !crack[j]) {
        let r = root(&mut parent, j);
        if size[r] == 0 {
            roots.push(r);
        }
        size[r] += 1;
    }
    if roots.len() < 2 {
        return None;
    }
    roots.sort_by_key(|&r| std::cmp::Reverse(size[r]));
    let mut bin = vec![0u8; np];
    let mut load = [0usize; 2];
    for &r in &roots {
        let b = usize::from(load[1] < load[0]);
        load[b] += size[r];
        bin[r] = b as u8;
    }
    let mut bins = vec![Vec::with_capacity(load[0]), Vec::with_capacity(load[1])];
    for &j in order.iter().filter(|&&j| !crack[j]) {
        let r = root(&mut parent, j);
        bins[usize::from(bin[r])].push(j);
    }
    Some(bins)
}

/// A change of `F` (largest entry change over the largest entry) below which its previous
/// factor is kept whatever the number of rows changed (`dense_block.rs`): GMRES then
/// converges in a few iterations (the later friction passes change every sliding point's
/// threshold by 1e-2 to 1e-7 of itself).
const SMALL_CHANGE: f64 = 1e-2;

/// Condensation pays when a dense factorisation of the crack block (`nf³/3` flops for its
/// `LBLᵀ`) costs at most this many times the sparse `LDLᵀ` of the whole system (its flops
/// from the symbolic analysis in the plain path's own ordering): both are predicted per
/// factorisation (`CondensationCost`), since the number of refactorisations a contact
/// solve makes is unknown at the analysis. See `CondensationCost::decide` for the choice
/// of the value.
pub const CONDENSED_COST_RATIO: f64 = 2.0;
/// A dense block whose factorisation costs at most this many flops (`nf ≤ 669`: tens of
/// milliseconds) is condensed whatever the whole system's cost (with `n ≥ 20 nf`): both
/// paths then factorise in milliseconds, and the small models of the tests keep the
/// condensed path they were written for.
pub const CONDENSED_SMALL_FLOPS: f64 = 1e8;
/// ... and when they are at most `1 / CONDENSED_MIN_RATIO` of the unknowns: on small
/// models where contact covers a large part of the mesh (sliding blocks, patch tests) the
/// dense factor costs more than the sparse LDLᵀ of the whole system (the 2D sliding blocks,
/// 5 566 unknowns: 4.2 s condensed against 2.9 s).
pub const CONDENSED_MIN_RATIO: usize = 20;
/// A bound on the overcount of the column counts read from a supernodal symbolic factor
/// (faer's relaxed supernodes store explicit zeros) against the exact ones of
/// `predicted_flops`: [`CondensedFactor::part_flops`] over it is a lower bound of the
/// whole system's flops. Measured (`condensed_parts_bound_the_whole_system_flops`, and the
/// bench rows' logs in `docs/performance.md`): the parts' flops are 0.70–1.01 of the whole
/// system's before the division.
const AMALGAMATION_PADDING: f64 = 2.0;
/// The crack unknowns and the separator at most this many: the dense part of the bulk
/// factor (else the condensed factor has no split, one part).
const CONDENSED_MAX_SEPARATOR: usize = 4000;

/// The predicted cost of one factorisation of a contact tangent on each path, for the
/// choice between the condensed factor and the plain `LDLᵀ` ([`Self::decide`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CondensationCost {
    /// Unknowns of the whole system.
    pub(crate) n: usize,
    /// Crack unknowns and multipliers: the size of the dense block `F`.
    pub(crate) nf: usize,
    /// Flops of one numeric factorisation of the whole system (the plain path).
    pub(crate) whole_flops: f64,
}

impl CondensationCost {
    /// Flops of one dense `LBLᵀ` of `F`.
    pub(crate) fn dense_flops(&self) -> f64 {
        let nf = self.nf as f64;
        nf * nf * nf / 3.0
    }

    /// `None`: condense; `Some(why)`: the plain `LDLᵀ`. The condensed factor pays when
    /// its dense factorisation costs at most [`CONDENSED_COST_RATIO`] times the whole
    /// system's (or is small: [`CONDENSED_SMALL_FLOPS`]), with `n ≥ 20 nf`
    /// ([`CONDENSED_MIN_RATIO`]). Per flop the dense kernels run about twice as fast as a
    /// 2D sparse factor's small fronts, and after the first factorisations of a solve most
    /// status changes are taken by the kept factor's low-rank correction
    /// (`dense_block.rs`) without a dense factorisation; against that the condensed path
    /// pays its bulk stage (about one factorisation of the bulk) once per bulk, and a dense
    /// factorisation at every large change of the statuses. Measured
    /// (`docs/performance.md`, "The condensation decided by cost"): the wear bench's 1e5
    /// row (`nf` 2 646, ratio 4.6) is 1.7× slower condensed than plain, with most of its
    /// factorisations dense; the Hertz rows (2D 2e5: ratio 0.12, 2D 1e6: 0.09, 3D 2e5:
    /// 0.44) are faster condensed.
    pub(crate) fn decide(&self) -> Option<String> {
        let ratio = self.dense_flops() / self.whole_flops.max(1.0);
        if self.nf * CONDENSED_MIN_RATIO > self.n {
            Some(format!("more than 1/{CONDENSED_MIN_RATIO} of the {} unknowns", self.n))
        } else if ratio > CONDENSED_COST_RATIO && self.dense_flops() > CONDENSED_SMALL_FLOPS {
            Some(format!(
                "its dense factorisation, {:.2e} flops, costs {ratio:.2} times the whole system's, {:.2e}",
                self.dense_flops(),
                self.whole_flops
            ))
        } else {
            None
        }
    }
}

/// What the analysis of a contact system chose ([`condensed_factor`]).
pub(super) enum Condensation {
    Condensed(Box<CondensedFactor>),
    /// The plain factor; with the ordering of the whole system when the decision computed
    /// it (the one [`super::cholesky::symbolic_cholesky`] would compute).
    Plain(Option<(Vec<usize>, Vec<usize>)>),
}

/// The condensed factor of a saddle-point pattern, or of a positive definite one whose
/// `varying` unknowns change between factorisations (no multipliers: `F` is then the Schur
/// complement of the bulk on them plus their contact terms), or the plain factor when it
/// does not apply or does not pay ([`CondensationCost::decide`]).
pub(super) fn condensed_factor(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    order: Order<'_>,
    varying: Option<&[bool]>,
) -> Result<Condensation, LinearError> {
    condensed_factor_with(col_ptr, row_idx, n, n_primal, order, varying, Candidates::Predicted)
}

/// [`condensed_factor`] building the split candidates `candidates`.
pub(super) fn condensed_factor_with(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    order: Order<'_>,
    varying: Option<&[bool]>,
    candidates: Candidates,
) -> Result<Condensation, LinearError> {
    // The crack unknowns: primal unknowns coupled to a multiplier (and marked varying);
    // without multipliers (a contact law without them, the penalty), the varying ones.
    let mut crack = vec![false; n_primal];
    if n == n_primal {
        match varying {
            Some(v) => crack.copy_from_slice(&v[..n_primal]),
            None => return Ok(Condensation::Plain(None)),
        }
    }
    for j in n_primal..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i < n_primal && varying.is_none_or(|v| v[i]) {
                crack[i] = true;
            }
        }
    }
    let nc = crack.iter().filter(|&&c| c).count();
    if nc == 0 {
        return Ok(Condensation::Plain(None));
    }
    let m = n - n_primal;
    // F keeps the multipliers coupled to some primal unknown; the free ones are condensed
    // out of it (`free.rs`).
    let kept = FreeBlock::split(col_ptr, row_idx, &(n_primal..n).collect::<Vec<_>>(), n_primal).0.len();
    let nf = nc + kept;
    let log = std::env::var("FISSURE_CONTACT_LOG").is_ok();
    let refuse = |why: String| {
        if log {
            eprintln!(
                "condensation refused: {nc} crack unknowns + {kept} of the {m} multipliers = {nf} ({why}): the plain LDLᵀ of all {n} unknowns"
            );
        }
    };
    // Refusals that need no ordering.
    let dense_bytes = 8.0 * 3.2 * (nf as f64) * (nf as f64);
    if nf * CONDENSED_MIN_RATIO > n {
        refuse(format!("more than 1/{CONDENSED_MIN_RATIO} of the {n} unknowns"));
        return Ok(Condensation::Plain(None));
    } else if nc == n_primal {
        refuse("every primal unknown".to_string());
        return Ok(Condensation::Plain(None));
    } else if super::memory::available_memory().is_some_and(|a| dense_bytes > 0.5 * a as f64) {
        refuse(format!("its dense block, {:.1} GB, is above half the memory available", dense_bytes / 1e9));
        return Ok(Condensation::Plain(None));
    }
    // The primal sub-pattern and its ordering (nested dissection split in large 2D
    // systems, as for the split Cholesky): the ordering the plain path would compute too.
    let order_clock = std::time::Instant::now();
    let (sub_ptr, sub_idx) = primal_subpattern(col_ptr, row_idx, n_primal);
    let split = match order.points {
        Some(p) if split_candidate(n_primal, order) => {
            crate::solve::ordering::dissection_split(&sub_ptr, &sub_idx, n_primal, p, order)
        }
        _ => None,
    };
    let (primal, parts) = match split {
        Some((fwd, inv, (n1, n2))) => {
            let split = n1 > 0 && n2 > 0 && n_primal - n1 - n2 + nc <= CONDENSED_MAX_SEPARATOR;
            ((fwd, inv), if split { (n1, n2) } else { (0, 0) })
        }
        None => (primal_ordering(&sub_ptr, &sub_idx, n_primal, order)?, (0, 0)),
    };
    drop((sub_ptr, sub_idx));
    if log {
        eprintln!("condensed: the primal ordering in {:.1} ms", order_clock.elapsed().as_secs_f64() * 1e3);
    }
    // The whole system's factor in the plain path's ordering (multipliers after their
    // primal unknowns): its flops against the dense block's.
    // A small dense block is condensed whatever the whole system costs
    // ([`CondensationCost::decide`]): its prediction (a column-count walk of the whole
    // pattern, ~0.1 s at 2e5 unknowns) is skipped.
    let small = CondensationCost { n, nf, whole_flops: f64::INFINITY }.dense_flops() <= CONDENSED_SMALL_FLOPS;
    // The condensed analysis (the interior's bodies and the halves' symbolic factors) first:
    // the factors of its parts alone bound the whole system's flops from below
    // ([`CondensedFactor::part_flops`]), and when the condensation pays against that bound
    // (less the amalgamation's padding, [`AMALGAMATION_PADDING`]) it pays against the
    // whole system's flops too (the decision is monotone in them), so the prediction (one
    // sequential walk of the whole pattern) is skipped. Otherwise it is computed, and the
    // analysis is dropped if the decision refuses the condensation.
    let analysed =
        CondensedFactor::analyse(col_ptr, row_idx, &primal.0, parts, &crack, (n_primal..n).collect(), candidates);
    let bound = match &analysed {
        Ok(Some(c)) => c.part_flops() / AMALGAMATION_PADDING,
        _ => 0.0,
    };
    let settled = !small && bound > 0.0 && CondensationCost { n, nf, whole_flops: bound }.decide().is_none();
    let clock = std::time::Instant::now();
    let (whole, whole_flops) = if small || settled {
        (None, if settled { bound } else { f64::NAN })
    } else {
        let whole = multipliers_after(col_ptr, row_idx, n, &primal.0, &primal.1);
        let flops = predicted_flops(col_ptr, row_idx, &whole.0, &whole.1);
        (Some(whole), flops)
    };
    let cost = CondensationCost { n, nf, whole_flops };
    if log && !small {
        if settled {
            eprintln!(
                "condensation cost not predicted: the whole system's LDLᵀ ≥ {bound:.2e} flops (its parts' factors)"
            );
        } else {
            eprintln!("condensation cost predicted in {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
        }
    }
    if let (false, Some(why)) = (small, cost.decide()) {
        refuse(why);
        return Ok(Condensation::Plain(whole));
    }
    if log {
        // A small block's decision skips the whole system's prediction: say so, not NaN.
        let whole_cost = if small {
            "not predicted: a small block".to_string()
        } else if settled {
            format!("≥ {:.2e}, not predicted", cost.whole_flops)
        } else {
            format!("{:.2e}", cost.whole_flops)
        };
        eprintln!(
            "condensation: {nc} crack unknowns, {m} multipliers, {kept} of them in F (dense block {nf}², {:.2e} flops; the whole system's LDLᵀ {whole_cost})",
            cost.dense_flops(),
        );
    }
    drop(whole);
    Ok(match analysed? {
        Some(c) => Condensation::Condensed(Box::new(c)),
        None => Condensation::Plain(None),
    })
}

/// A condensed factorisation error as a [`LinearError`].
pub(super) fn condensed_error(e: CondensedError, diag_pos: &[Option<usize>], values: &[f64]) -> LinearError {
    match e {
        CondensedError::NonPositive { unknown } => {
            let diagonal = diag_pos[unknown].map_or(0.0, |k| values[k]);
            LinearError::NotPositiveDefinite { unknown, pivot: f64::NAN, diagonal }
        }
        CondensedError::NotCondensable => {
            LinearError::Internal("a multiplier couples to an interior unknown".to_string())
        }
        CondensedError::Free(e) => {
            LinearError::Internal(format!("the free multipliers cannot be condensed out of F: {e}"))
        }
        CondensedError::Faer(e) => e.into(),
    }
}

#[cfg(test)]
mod cost_tests {
    use super::CondensationCost;

    // The decision by cost on the four bench rows it was calibrated on, with their
    // figures from the analysis log (`FISSURE_CONTACT_LOG=1`: unknowns n, crack unknowns
    // and multipliers nf, predicted flops of the whole system's LDLᵀ), and the reason it
    // gives. Reference: the measured times (docs/performance.md, "The condensation
    // decided by cost"): the wear 1e5 row is faster plain, the Hertz rows condensed.
    #[test]
    fn condensation_decided_by_cost_on_the_bench_rows() {
        let cost = |n, nf, whole_flops| CondensationCost { n, nf, whole_flops };
        // Wear 1e5 (quad4 440 × 110, one interface): 2 646 in 98 784, W = 1.33e9.
        let wear = cost(98_784, 2_646, 1.33e9).decide();
        assert!(wear.as_deref().is_some_and(|w| w.contains("4.6")), "wear 1e5 stays plain: {wear:?}");
        // Hertz 2D 2e5: 1 476 in 189 559, W = 9.30e9.
        assert_eq!(cost(189_559, 1_476, 9.30e9).decide(), None, "Hertz 2D 2e5 condensed");
        // Hertz 3D sphere 2e5: 8 701 in 186 348, W = 4.97e11.
        assert_eq!(cost(186_348, 8_701, 4.97e11).decide(), None, "Hertz 3D 2e5 condensed");
        // Hertz 2D 1e6: 3 026 in 941 704, W = 1.02e11 (refused by the fixed 2D limit 2 500).
        assert_eq!(cost(941_704, 3_026, 1.02e11).decide(), None, "Hertz 2D 1e6 condensed");
        // The structural rule stays: a dense block above 1/20 of the unknowns is refused
        // whatever the flops (the 2D sliding blocks), and a small block is condensed.
        assert!(cost(5_566, 600, 1e12).decide().is_some_and(|w| w.contains("1/20")));
        assert_eq!(cost(20_000, 400, 1e6).decide(), None, "a small dense block");
        // A large dense block on a cheap whole system: plain.
        assert!(cost(1_000_000, 20_000, 1e11).decide().is_some());
    }

    // The whole system's flops predicted from its column counts (`predicted_flops`, no
    // symbolic factor) against faer's supernodal symbolic factor in the same ordering
    // (`factor_flops`), on the contact-like saddle points of the faer tests (quad grids
    // 240 × 180 and 400 × 300 with a crack row of multipliers, LDLᵀ with the multipliers
    // after their unknowns). Tolerance: within 10% (the supernodes' amalgamation adds
    // explicit zeros the column counts do not see).
    #[test]
    fn predicted_whole_system_flops_match_the_symbolic_factor() {
        use crate::solve::backend::{EquationPoints, LinearMethod};
        use crate::solve::faer::cholesky::{factor_flops, predicted_flops};
        use crate::solve::faer::solver::{Factor, FaerSolver};
        use crate::solve::ordering::{multipliers_after_primal_ordering, Order};
        for (nx, ny) in [(240, 180), (400, 300)] {
            let (p, _, _, point_of_eq, coords, np) = crate::solve::faer::tests::contact_grid(nx, ny, 10.0, |_| true);
            let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
            let order = Order { points: Some(&points), ..Default::default() };
            let (fwd, inv) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, order).unwrap();
            let predicted = predicted_flops(&p.col_ptr, &p.row_idx, &fwd, &inv);
            let solver = FaerSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
            let Factor::Cholesky { symbolic, .. } = &solver.factor else { panic!("not a whole-system factor") };
            let actual = factor_flops(symbolic);
            eprintln!("{nx} × {ny}: predicted {predicted:.4e} flops, symbolic factor {actual:.4e}");
            assert!(actual > 0.0, "a supernodal factor");
            assert!((predicted / actual - 1.0).abs() < 0.10, "{nx} × {ny}: {predicted:e} against {actual:e}");
        }
    }
}
