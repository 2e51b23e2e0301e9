//! Approximate minimum degree orderings (faer's AMD), on the full graph or on the graph
//! compressed by supervariables.
//!
//! Entry points: [`plain_amd`] and [`compressed_amd`], chosen by
//! [`super::primal_ordering`].

use crate::solve::backend::LinearError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

/// AMD on the full graph. Returns (forward, inverse): `forward[new] = old`.
pub fn plain_amd(col_ptr: &[usize], row_idx: &[usize], n: usize) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    let mut fwd = vec![0usize; n];
    let mut inv = vec![0usize; n];
    let a = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut mem =
        MemBuffer::try_new(amd::order_scratch::<usize>(n, row_idx.len())).map_err(|_| LinearError::OutOfMemory)?;
    amd::order(&mut fwd, &mut inv, a, amd::Control::default(), MemStack::new(&mut mem))?;
    Ok((fwd, inv))
}

/// AMD on the graph compressed by supervariables: consecutive columns with identical row
/// patterns (the components of a node's displacement, of an enrichment) are merged, the
/// compressed graph is ordered, and every supervariable is expanded in place. The fill is
/// that of AMD on the full graph (AMD merges indistinguishable vertices anyway) for a
/// fraction of its time (1/dim² of the edges). Returns (forward, inverse): `forward[new] = old`.
pub fn compressed_amd(col_ptr: &[usize], row_idx: &[usize], n: usize) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    // Groups of consecutive identical columns.
    let mut group_of = vec![0usize; n];
    let mut starts = vec![0usize];
    for j in 1..n {
        let same = row_idx[col_ptr[j]..col_ptr[j + 1]] == row_idx[col_ptr[j - 1]..col_ptr[j]];
        if !same {
            starts.push(j);
        }
        group_of[j] = starts.len() - 1;
    }
    let ng = starts.len();
    starts.push(n);
    // Compressed pattern: the groups of the rows of each group's first column.
    let mut cptr = Vec::with_capacity(ng + 1);
    let mut cidx = Vec::new();
    cptr.push(0usize);
    for g in 0..ng {
        let j = starts[g];
        let mut last = usize::MAX;
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let gi = group_of[i];
            if gi != last {
                cidx.push(gi);
                last = gi;
            }
        }
        cptr.push(cidx.len());
    }
    // Rows within a column are sorted and groups are contiguous ranges, so the group ids
    // are sorted and unique: a valid compressed pattern.
    let mut gfwd = vec![0usize; ng];
    let mut ginv = vec![0usize; ng];
    let sub = SymbolicSparseColMatRef::new_checked(ng, ng, &cptr, None, &cidx);
    let mut mem =
        MemBuffer::try_new(amd::order_scratch::<usize>(ng, cidx.len())).map_err(|_| LinearError::OutOfMemory)?;
    amd::order(&mut gfwd, &mut ginv, sub, amd::Control::default(), MemStack::new(&mut mem))?;
    let mut fwd = Vec::with_capacity(n);
    for &g in &gfwd {
        fwd.extend(starts[g]..starts[g + 1]);
    }
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Ok((fwd, inv))
}
