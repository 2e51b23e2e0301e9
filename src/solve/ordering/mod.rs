//! Fill-reducing orderings of the unknowns of a system, for the direct solvers.
//!
//! Entry points: [`primal_ordering`] (a pattern without multipliers) and
//! [`multipliers_after_primal_ordering`] (saddle points, for LDLᵀ without pivoting). The
//! orderings themselves sit one per file: the geometric nested dissection of 2D meshes
//! ([`geometric`]), METIS nested dissection on the node graph ([`metis`]) and minimum
//! degree ([`amd`]). Every ordering is returned as
//! (forward, inverse) with `forward[new] = old`.

pub mod amd;
pub mod geometric;
pub mod metis;
pub mod reuse;

use super::backend::LinearError;
pub use super::backend::{EquationPoints, OrderingChoice, NO_POINT};
use amd::{compressed_amd, plain_amd};
use geometric::{nested_dissection_split, SplitOrdering};
use metis::metis_nested_dissection;
use reuse::{by_points, ReusedOrdering};

/// What an ordering may read besides the pattern: where the unknowns sit, and which
/// ordering was asked for.
#[derive(Debug, Clone, Copy, Default)]
pub struct Order<'a> {
    /// The point (mesh node) of every unknown.
    pub points: Option<&'a EquationPoints<'a>>,
    /// The ordering asked for.
    pub choice: OrderingChoice,
    /// The node order kept from an earlier analysis on the same mesh, to reuse
    /// ([`reuse`]).
    pub reuse: Option<&'a ReusedOrdering>,
}

/// The ordering of a pattern without multipliers, as `order.choice` asks:
///
/// - `Auto` with the unknowns' points: geometric nested dissection in 2D (less fill and
///   faster to compute than minimum degree, and it allows the split factorisation), METIS
///   nested dissection on the node graph in 3D (about half the fill of AMD on hex8 and on
///   the graded, enriched tet meshes: `docs/performance.md`); without points, the
///   supervariable-compressed AMD (fast, same fill as plain AMD);
/// - `Amd`: plain AMD on the full graph for 3D points, the compressed AMD otherwise;
/// - `NestedDissection`: METIS, on the node graph when every unknown has a point.
pub fn primal_ordering(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    order: Order<'_>,
) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    match (order.choice, order.points) {
        (OrderingChoice::Auto, Some(p)) if p.dim == 2 => match dissection_split(col_ptr, row_idx, n, p, order) {
            Some((fwd, inv, _)) => Ok((fwd, inv)),
            None => compressed_amd(col_ptr, row_idx, n),
        },
        // METIS is not reused (`reuse`): it weights the nodes by their unknowns.
        (OrderingChoice::Auto, Some(p)) => metis_nested_dissection(col_ptr, row_idx, n, Some(p)),
        (OrderingChoice::Auto, None) => compressed_amd(col_ptr, row_idx, n),
        (OrderingChoice::Amd, Some(p)) if p.dim == 3 => plain_amd(col_ptr, row_idx, n),
        (OrderingChoice::Amd, _) => compressed_amd(col_ptr, row_idx, n),
        (OrderingChoice::NestedDissection, points) => metis_nested_dissection(col_ptr, row_idx, n, points),
    }
}

/// The geometric nested dissection of the unknowns `0..n`
/// ([`geometric::nested_dissection_split`]), its node order reused from `order.reuse`
/// when that applies ([`reuse`]); `None` when some unknown has no point.
pub fn dissection_split(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    points: &EquationPoints<'_>,
    order: Order<'_>,
) -> Option<SplitOrdering> {
    let computed: Result<_, std::convert::Infallible> =
        by_points(n, points, order.choice, order.reuse, || Ok(nested_dissection_split(col_ptr, row_idx, n, points)));
    match computed {
        Ok(o) => o,
        Err(never) => match never {},
    }
}

/// The LDLᵀ ordering: the primal block ordered by [`primal_ordering`], then each
/// multiplier right after the last (in that order) primal unknown it couples to; multipliers coupled to no primal unknown
/// come last. Every leading block `[K_SS B_Sᵀ; B_S −C_S]` then only holds constraints on
/// already-ordered primal unknowns, so with `K` positive definite no pivot is zero and
/// the pivot signs are known (+ primal, − multiplier). Fill stays close to that of `K`
/// (a Dirichlet multiplier costs about one extra column), where putting all multipliers
/// last would make their Schur complement block dense.
/// Returns (forward, inverse): `forward[new] = old`.
pub fn multipliers_after_primal_ordering(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    n_primal: usize,
    order: Order<'_>,
) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    let (sub_ptr, sub_idx) = primal_subpattern(col_ptr, row_idx, n_primal);
    let (primal_fwd, primal_inv) =
        if n_primal > 0 { primal_ordering(&sub_ptr, &sub_idx, n_primal, order)? } else { (vec![], vec![]) };
    drop((sub_ptr, sub_idx));
    Ok(multipliers_after(col_ptr, row_idx, n, &primal_fwd, &primal_inv))
}

/// [`multipliers_after_primal_ordering`] for a given ordering of the primal block
/// (`primal_fwd[new] = old`, `primal_inv` its inverse; the primal unknowns are
/// `0..primal_fwd.len()`): each multiplier right after the last primal unknown it couples
/// to. Returns (forward, inverse).
pub fn multipliers_after(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    primal_fwd: &[usize],
    primal_inv: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n_primal = primal_fwd.len();
    // key[l]: rank of the last primal unknown multiplier l couples to (n_primal if none).
    let m = n - n_primal;
    let key: Vec<usize> = (0..m)
        .map(|l| {
            let j = n_primal + l;
            row_idx[col_ptr[j]..col_ptr[j + 1]]
                .iter()
                .take_while(|&&i| i < n_primal)
                .map(|&i| primal_inv[i])
                .max()
                .unwrap_or(n_primal)
        })
        .collect();
    // Stable counting sort of the multipliers by key.
    let mut start = vec![0usize; n_primal + 2];
    for &k in &key {
        start[k + 1] += 1;
    }
    for r in 0..=n_primal {
        start[r + 1] += start[r];
    }
    let mut sorted = vec![0usize; m];
    for (l, &k) in key.iter().enumerate() {
        sorted[start[k]] = l;
        start[k] += 1;
    }
    let mut fwd = Vec::with_capacity(n);
    let mut q = 0;
    for (r, &p) in primal_fwd.iter().enumerate() {
        fwd.push(p);
        while q < m && key[sorted[q]] == r {
            fwd.push(n_primal + sorted[q]);
            q += 1;
        }
    }
    fwd.extend(sorted[q..].iter().map(|&l| n_primal + l));
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    (fwd, inv)
}

/// The pattern of the primal unknowns `0..n_primal` alone (column pointers, row indices).
pub fn primal_subpattern(col_ptr: &[usize], row_idx: &[usize], n_primal: usize) -> (Vec<usize>, Vec<usize>) {
    let mut sub_ptr = Vec::with_capacity(n_primal + 1);
    let mut sub_idx = Vec::with_capacity(col_ptr[n_primal]);
    sub_ptr.push(0);
    for j in 0..n_primal {
        let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        let end = rows.partition_point(|&i| i < n_primal);
        sub_idx.extend_from_slice(&rows[..end]);
        sub_ptr.push(sub_idx.len());
    }
    (sub_ptr, sub_idx)
}
