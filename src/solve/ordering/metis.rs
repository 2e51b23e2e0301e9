//! Nested dissection by METIS (`METIS_NodeND`, the vendored C library through
//! `metis-sys`) on the graph of the mesh nodes, all the dofs of a node kept together.
//!
//! Entry point: [`metis_nested_dissection`], chosen by [`super::primal_ordering`].
//!
//! The unknowns are grouped by point (a node's standard and enriched dofs), or, when some
//! unknown has no point, by supervariable (consecutive columns with identical patterns).
//! The groups form a graph (two groups adjacent when an unknown of one couples to an
//! unknown of the other), weighted by their number of unknowns so that METIS balances the
//! parts and sizes the separators in unknowns, not nodes. METIS orders the groups by
//! multilevel nested dissection (vertex separators refined by Fiduccia–Mattheyses, with
//! minimum degree on the small parts), and each group is expanded in place. Compared with
//! minimum degree in 3D this roughly halves the entries of `L` and the flops
//! (`docs/performance.md`); the ordering itself costs a second or so per million unknowns.

use super::EquationPoints;
use super::NO_POINT;
use crate::solve::backend::LinearError;
use metis_sys::{idx_t, METIS_NodeND, METIS_SetDefaultOptions, METIS_NOPTIONS};

/// The groups of unknowns ordered together: `(members in CSR form: start of each group
/// and the unknowns of all groups, in increasing order within a group; the group of every
/// unknown)`.
struct Groups {
    start: Vec<usize>,
    members: Vec<usize>,
    group_of: Vec<usize>,
}

impl Groups {
    fn len(&self) -> usize {
        self.start.len() - 1
    }

    fn of(&self, g: usize) -> &[usize] {
        &self.members[self.start[g]..self.start[g + 1]]
    }

    /// Groups from a group id per unknown (ids `0..ng`).
    fn from_ids(group_of: Vec<usize>, ng: usize) -> Self {
        let mut start = vec![0usize; ng + 1];
        for &g in &group_of {
            start[g + 1] += 1;
        }
        for g in 0..ng {
            start[g + 1] += start[g];
        }
        let mut next = start.clone();
        let mut members = vec![0usize; group_of.len()];
        for (j, &g) in group_of.iter().enumerate() {
            members[next[g]] = j;
            next[g] += 1;
        }
        Groups { start, members, group_of }
    }

    /// By point when every unknown has one, else by supervariable.
    fn build(col_ptr: &[usize], row_idx: &[usize], n: usize, points: Option<&EquationPoints<'_>>) -> Self {
        if let Some(p) =
            points.filter(|p| p.point_of_eq.len() >= n && p.point_of_eq[..n].iter().all(|&q| q != NO_POINT))
        {
            let mut id = std::collections::HashMap::new();
            let group_of = p.point_of_eq[..n]
                .iter()
                .map(|&q| {
                    let next = id.len();
                    *id.entry(q).or_insert(next)
                })
                .collect();
            let ng = id.len();
            return Self::from_ids(group_of, ng);
        }
        let mut group_of = vec![0usize; n];
        let mut ng = usize::from(n > 0);
        for j in 1..n {
            if row_idx[col_ptr[j]..col_ptr[j + 1]] != row_idx[col_ptr[j - 1]..col_ptr[j]] {
                ng += 1;
            }
            group_of[j] = ng - 1;
        }
        Self::from_ids(group_of, ng)
    }
}

/// METIS nested dissection of the unknowns `0..n` of the symmetric pattern (`col_ptr`,
/// `row_idx`, both triangles), the unknowns grouped by point when `points` gives one to
/// each (else by supervariable). Returns (forward, inverse) with `forward[new] = old`.
pub fn metis_nested_dissection(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    points: Option<&EquationPoints<'_>>,
) -> Result<(Vec<usize>, Vec<usize>), LinearError> {
    let groups = Groups::build(col_ptr, row_idx, n, points);
    let ng = groups.len();
    let order: Vec<usize> = if ng <= 2 {
        (0..ng).collect()
    } else {
        // The group graph, without self loops.
        let too_large =
            |what: &str| LinearError::Internal(format!("the METIS graph has too many {what} for 32-bit indices"));
        let mut xadj: Vec<idx_t> = Vec::with_capacity(ng + 1);
        let mut adjncy: Vec<idx_t> = Vec::new();
        let mut vwgt: Vec<idx_t> = Vec::with_capacity(ng);
        let mut mark = vec![usize::MAX; ng];
        xadj.push(0);
        for g in 0..ng {
            mark[g] = g;
            for &j in groups.of(g) {
                for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                    let h = groups.group_of[i];
                    if mark[h] != g {
                        mark[h] = g;
                        adjncy.push(idx_t::try_from(h).map_err(|_| too_large("vertices"))?);
                    }
                }
            }
            xadj.push(idx_t::try_from(adjncy.len()).map_err(|_| too_large("edges"))?);
            vwgt.push(idx_t::try_from(groups.of(g).len()).map_err(|_| too_large("unknowns"))?);
        }
        let mut nvtxs = idx_t::try_from(ng).map_err(|_| too_large("vertices"))?;
        let mut options: Vec<idx_t> = vec![0; METIS_NOPTIONS as usize];
        let mut perm: Vec<idx_t> = vec![0; ng];
        let mut iperm: Vec<idx_t> = vec![0; ng];
        // SAFETY: `options` has METIS_NOPTIONS entries; the graph arrays are a valid CSR
        // graph of `nvtxs` vertices (`xadj` of nvtxs + 1 entries, `adjncy` of xadj[nvtxs],
        // all indices in range, no self loops, symmetric since the pattern is), `vwgt`
        // has nvtxs entries, and `perm`, `iperm` nvtxs entries each. METIS reads the graph
        // and writes only `perm` and `iperm`.
        let status = unsafe {
            METIS_SetDefaultOptions(options.as_mut_ptr());
            METIS_NodeND(
                &mut nvtxs,
                xadj.as_mut_ptr(),
                adjncy.as_mut_ptr(),
                vwgt.as_mut_ptr(),
                options.as_mut_ptr(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
            )
        };
        match status {
            metis_sys::rstatus_et_METIS_OK => {}
            metis_sys::rstatus_et_METIS_ERROR_MEMORY => return Err(LinearError::OutOfMemory),
            s => return Err(LinearError::Internal(format!("METIS_NodeND failed (status {s})"))),
        }
        // perm[new] = old (METIS manual, METIS_NodeND).
        perm.into_iter().map(|g| g as usize).collect()
    };
    let mut fwd = Vec::with_capacity(n);
    for g in order {
        fwd.extend_from_slice(groups.of(g));
    }
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Ok((fwd, inv))
}

#[cfg(test)]
mod tests {
    use super::super::amd::plain_amd;
    use super::super::{multipliers_after_primal_ordering, Order, OrderingChoice};
    use super::*;
    use faer::perm::PermRef;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering};
    use faer::sparse::SymbolicSparseColMatRef;
    use faer::Side;

    /// The pattern of hex8 elasticity on an `m`³-node grid with 3 dofs per node, numbered
    /// like fissure's dof map: standard dofs `3 node + c` first, then 3 "enriched" dofs
    /// for every node of the middle layer `z = m / 2` (the Heaviside block of a crack
    /// plane), then `n_mult` multipliers, multiplier `l` coupled to the 3 enriched dofs of
    /// enriched node `l`. Returns (col_ptr, row_idx, n_primal, point of each unknown,
    /// coordinates).
    #[allow(clippy::type_complexity)]
    fn hex_pattern(m: usize, n_mult: usize) -> (Vec<usize>, Vec<usize>, usize, Vec<u32>, Vec<[f64; 3]>) {
        let id = |x: usize, y: usize, z: usize| (z * m + y) * m + x;
        let nn = m * m * m;
        let enriched: Vec<usize> =
            (0..m).flat_map(|y| (0..m).map(move |x| (x, y))).map(|(x, y)| id(x, y, m / 2)).collect();
        let mut dofs_of: Vec<Vec<usize>> = (0..nn).map(|p| (0..3).map(|c| 3 * p + c).collect()).collect();
        let mut point = vec![0u32; 3 * nn];
        for p in 0..nn {
            for c in 0..3 {
                point[3 * p + c] = p as u32;
            }
        }
        for &p in &enriched {
            for _ in 0..3 {
                dofs_of[p].push(point.len());
                point.push(p as u32);
            }
        }
        let n_primal = point.len();
        let mut cols: Vec<Vec<usize>> = vec![vec![]; n_primal + n_mult];
        for z in 0..m {
            for y in 0..m {
                for x in 0..m {
                    let p = id(x, y, z);
                    for dz in z.saturating_sub(1)..(z + 2).min(m) {
                        for dy in y.saturating_sub(1)..(y + 2).min(m) {
                            for dx in x.saturating_sub(1)..(x + 2).min(m) {
                                let q = id(dx, dy, dz);
                                for &j in &dofs_of[p] {
                                    cols[j].extend_from_slice(&dofs_of[q]);
                                }
                            }
                        }
                    }
                }
            }
        }
        for l in 0..n_mult {
            let j = n_primal + l;
            let p = enriched[l];
            for &e in &dofs_of[p][3..] {
                cols[j].push(e);
                cols[e].push(j);
            }
            cols[j].push(j);
        }
        point.extend(std::iter::repeat_n(NO_POINT, n_mult));
        let mut col_ptr = vec![0];
        let mut row_idx = vec![];
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        let coords = (0..nn).map(|p| [(p % m) as f64, ((p / m) % m) as f64, (p / (m * m)) as f64]).collect();
        (col_ptr, row_idx, n_primal, point, coords)
    }

    fn nnz_l(col_ptr: &[usize], row_idx: &[usize], n: usize, (fwd, inv): &(Vec<usize>, Vec<usize>)) -> usize {
        let a = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
        let ordering = SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n));
        factorize_symbolic_cholesky(a, Side::Lower, ordering, CholeskySymbolicParams::default()).unwrap().len_val()
    }

    fn assert_permutation((fwd, inv): &(Vec<usize>, Vec<usize>), n: usize) {
        assert_eq!(fwd.len(), n);
        let mut seen = vec![false; n];
        for (new, &old) in fwd.iter().enumerate() {
            assert!(!seen[old], "unknown {old} twice");
            seen[old] = true;
            assert_eq!(inv[old], new);
        }
    }

    // What: METIS nested dissection on a 3D hex8 elasticity pattern (14³ nodes, 3 dofs each,
    // plus 3 enriched dofs per node of a middle plane numbered after all standard dofs, as
    // fissure's dof map numbers a Heaviside block). Checks: the ordering is a permutation;
    // the dofs of every node (standard and enriched) are consecutive in it; the factor of
    // the nested-dissection ordering has fewer entries than AMD's on the full graph (the
    // point of the ordering; measured 0.80× here). Exact checks, no tolerance.
    #[test]
    fn metis_ordering_keeps_node_dofs_together_with_less_fill_than_amd() {
        let m = 14;
        let (col_ptr, row_idx, n, point, coords) = hex_pattern(m, 0);
        let points = EquationPoints { point_of_eq: &point, coords: &coords, dim: 3 };
        let nd = metis_nested_dissection(&col_ptr, &row_idx, n, Some(&points)).unwrap();
        assert_permutation(&nd, n);
        let mut last_point = NO_POINT;
        let mut done = vec![false; m * m * m];
        for &old in &nd.0 {
            let p = point[old];
            if p != last_point {
                assert!(!done[p as usize], "the dofs of node {p} are split");
                done[p as usize] = true;
                last_point = p;
            }
        }
        // Without points: the supervariables (3 standard dofs of a node; the enriched dofs)
        // stay together too.
        let sv = metis_nested_dissection(&col_ptr, &row_idx, n, None).unwrap();
        assert_permutation(&sv, n);
        let amd = plain_amd(&col_ptr, &row_idx, n).unwrap();
        let (l_nd, l_amd) = (nnz_l(&col_ptr, &row_idx, n, &nd), nnz_l(&col_ptr, &row_idx, n, &amd));
        println!("nnz(L): METIS {l_nd}, AMD {l_amd} ({:.2}×)", l_nd as f64 / l_amd as f64);
        assert!(l_nd < l_amd, "METIS {l_nd} against AMD {l_amd}");
    }

    // What: the LDLᵀ ordering with METIS on the primal block (the saddle point of a crack
    // with one multiplier per enriched node, coupled to its enriched dofs). Checks: a
    // permutation; every multiplier after every primal unknown it couples to; the dofs of
    // a node still consecutive apart from the multipliers placed among them. Exact.
    #[test]
    fn metis_ldlt_ordering_places_multipliers_after_their_unknowns() {
        let m = 10;
        let (col_ptr, row_idx, n_primal, point, coords) = hex_pattern(m, m * m);
        let n = col_ptr.len() - 1;
        let points = EquationPoints { point_of_eq: &point, coords: &coords, dim: 3 };
        let order = Order { points: Some(&points), choice: OrderingChoice::NestedDissection, reuse: None };
        let perm = multipliers_after_primal_ordering(&col_ptr, &row_idx, n, n_primal, order).unwrap();
        assert_permutation(&perm, n);
        for j in n_primal..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                if i < n_primal {
                    assert!(perm.1[i] < perm.1[j], "multiplier {j} before its unknown {i}");
                }
            }
        }
        let primal_order: Vec<u32> = perm.0.iter().filter(|&&u| u < n_primal).map(|&u| point[u]).collect();
        let mut done = vec![false; m * m * m];
        for (k, &p) in primal_order.iter().enumerate() {
            if k == 0 || primal_order[k - 1] != p {
                assert!(!done[p as usize], "the dofs of node {p} are split");
                done[p as usize] = true;
            }
        }
    }
}
