//! Geometric nested dissection: a fill-reducing ordering of the unknowns of a mesh from
//! the positions of their nodes.
//!
//! Entry point: [`nested_dissection`] of the unknowns placed by an [`EquationPoints`],
//! chosen by [`super::primal_ordering`].
//!
//! The unknowns are grouped by point (all the dofs of a node, standard and enriched, stay
//! together), the point graph is read off the matrix pattern, and the points are split
//! recursively at the median of the longest side of their bounding box. The points of one
//! half that are coupled to the other half form the separator, ordered after both halves.
//! The ordering itself costs `O(nnz log n)`, less than AMD on the same graph.
//! Any split is valid (the separator is computed from the graph, not from the geometry),
//! so unusual meshes only lose quality, never correctness.
//!
//! Measured (X-FEM centre crack, quad4, 4e5 unknowns): 5% fewer entries in `L` (40.7M
//! against 42.9M) and fewer flops than AMD, for less ordering time; quad grids with two
//! unknowns per node of 5e3 to 2.4e5 unknowns: less fill than AMD at every size (unit
//! test). Not a universal win: on 5-point single-unknown Laplacians AMD gave 20–30% less
//! fill, and on the graded, enriched tet meshes of the penny benchmark the median splits
//! cut through the refined zone and the fill was 35% above AMD's, so the solver uses it for
//! 2D meshes only (see [`EquationPoints::dim`]).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;
use rayon::prelude::*;

use crate::solve::backend::EquationPoints;

/// Parts at or below this many points are not split further (ordered by AMD). Small:
/// AMD on a part ignores the separators around it, and larger leaves gave more fill
/// (X-FEM 4e5 unknowns: 40.7M entries in `L` with 8, 44.7M with 256, 49.0M with 4096).
const LEAF_POINTS: usize = 8;

/// Nested dissection of the unknowns `0..n` of the symmetric pattern (`col_ptr`,
/// `row_idx`, both triangles). Returns (forward, inverse) with `forward[new] = old`, or
/// `None` when some unknown has no point (the caller then uses another ordering).
pub fn nested_dissection(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    points: &EquationPoints<'_>,
) -> Option<(Vec<usize>, Vec<usize>)> {
    nested_dissection_split(col_ptr, row_idx, n, points).map(|(fwd, inv, _)| (fwd, inv))
}

/// (forward, inverse, (n1, n2)): an ordering with the sizes of its top-level parts.
pub type SplitOrdering = (Vec<usize>, Vec<usize>, (usize, usize));

/// [`nested_dissection`], also returning the numbers of unknowns `(n1, n2)` of the two
/// parts of the top-level split: the ordering is `[part 1, part 2, separator]`, with no
/// coupling between the parts. `(0, 0)` when the top level was a leaf.
pub fn nested_dissection_split(
    col_ptr: &[usize],
    row_idx: &[usize],
    n: usize,
    points: &EquationPoints<'_>,
) -> Option<SplitOrdering> {
    let np = points.coords.len();
    let point_of = &points.point_of_eq[..n];
    if point_of.iter().any(|&p| p as usize >= np) {
        return None;
    }
    // Unknowns of each point, ascending.
    let mut eq_ptr = vec![0usize; np + 1];
    for &p in point_of {
        eq_ptr[p as usize + 1] += 1;
    }
    for p in 0..np {
        eq_ptr[p + 1] += eq_ptr[p];
    }
    let mut fill = eq_ptr.clone();
    let mut eqs = vec![0u32; n];
    for (j, &p) in point_of.iter().enumerate() {
        eqs[fill[p as usize]] = j as u32;
        fill[p as usize] += 1;
    }
    drop(fill);

    // Point graph: p and q are adjacent when an unknown of p couples to one of q.
    let lists: Vec<Vec<u32>> = (0..np)
        .into_par_iter()
        .map_init(
            || vec![u32::MAX; np],
            |mark, p| {
                let mut out = Vec::new();
                mark[p] = p as u32;
                for &j in &eqs[eq_ptr[p]..eq_ptr[p + 1]] {
                    let j = j as usize;
                    for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                        let q = point_of[i];
                        if mark[q as usize] != p as u32 {
                            mark[q as usize] = p as u32;
                            out.push(q);
                        }
                    }
                }
                out
            },
        )
        .collect();
    let mut adj_ptr = Vec::with_capacity(np + 1);
    adj_ptr.push(0usize);
    for l in &lists {
        adj_ptr.push(adj_ptr[adj_ptr.len() - 1] + l.len());
    }
    let mut adj = Vec::with_capacity(adj_ptr[np]);
    for l in lists {
        adj.extend(l);
    }

    let mut nd = Dissection {
        adj_ptr: &adj_ptr,
        adj: &adj,
        coords: points.coords,
        tag: vec![0; np],
        next_tag: 1,
        order: Vec::with_capacity(np),
        local: vec![0; np],
        top: None,
    };
    let mut verts: Vec<u32> = (0..np as u32).filter(|&p| eq_ptr[p as usize + 1] > eq_ptr[p as usize]).collect();
    nd.dissect(&mut verts, 0);

    let mut fwd = Vec::with_capacity(n);
    let mut top = (0, 0);
    for (k, &p) in nd.order.iter().enumerate() {
        if nd.top.is_some_and(|(a, _)| a == k) {
            top.0 = fwd.len();
        }
        if nd.top.is_some_and(|(_, b)| b == k) {
            top.1 = fwd.len() - top.0;
        }
        fwd.extend(eqs[eq_ptr[p as usize]..eq_ptr[p as usize + 1]].iter().map(|&j| j as usize));
    }
    debug_assert_eq!(fwd.len(), n);
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Some((fwd, inv, top))
}

struct Dissection<'a> {
    adj_ptr: &'a [usize],
    adj: &'a [u32],
    coords: &'a [[f64; 3]],
    /// The part each point is in at the current depth; `SEPARATED` once ordered.
    tag: Vec<u32>,
    next_tag: u32,
    /// Points in elimination order.
    order: Vec<u32>,
    /// Scratch: the index of a point in its leaf.
    local: Vec<u32>,
    /// Ends of the two parts of the top-level split in `order`.
    top: Option<(usize, usize)>,
}

const SEPARATED: u32 = u32::MAX;

impl Dissection<'_> {
    /// Orders `verts` (the points of one part, all with the same tag): both halves, then
    /// the separator.
    fn dissect(&mut self, verts: &mut [u32], depth: usize) {
        if verts.len() <= LEAF_POINTS {
            self.order_leaf(verts);
            return;
        }
        // Longest side of the bounding box.
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &v in verts.iter() {
            let x = self.coords[v as usize];
            for d in 0..3 {
                lo[d] = lo[d].min(x[d]);
                hi[d] = hi[d].max(x[d]);
            }
        }
        let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
        let key = |v: u32| self.coords[v as usize][axis];
        // Split at the median coordinate; points on the median plane go to one side
        // together (straight separators on structured meshes).
        let mid = verts.len() / 2;
        verts.select_nth_unstable_by(mid, |&a, &b| key(a).total_cmp(&key(b)));
        let c = key(verts[mid]);
        let mut k = partition(verts, |v| key(v) < c);
        if k == 0 {
            k = partition(verts, |v| key(v) <= c);
        }
        if k == 0 || k == verts.len() {
            k = mid;
        }
        let (tl, tr) = (self.next_tag, self.next_tag + 1);
        self.next_tag += 2;
        for &v in &verts[..k] {
            self.tag[v as usize] = tl;
        }
        for &v in &verts[k..] {
            self.tag[v as usize] = tr;
        }
        // One-sided vertex separator: the boundary of the half with fewer boundary points.
        let boundary = |tag: &[u32], v: u32, other: u32| {
            self.adj[self.adj_ptr[v as usize]..self.adj_ptr[v as usize + 1]].iter().any(|&u| tag[u as usize] == other)
        };
        let nl = verts[..k].iter().filter(|&&v| boundary(&self.tag, v, tr)).count();
        let nr = verts[k..].iter().filter(|&&v| boundary(&self.tag, v, tl)).count();
        let (left, right) = verts.split_at_mut(k);
        let (side, other) = if nl <= nr { (&mut *left, tr) } else { (&mut *right, tl) };
        // Move the separator to the end of its half.
        let keep = {
            let tag = &self.tag;
            partition(side, |v| !boundary(tag, v, other))
        };
        let sep: Vec<u32> = side[keep..].to_vec();
        for &v in &sep {
            self.tag[v as usize] = SEPARATED;
        }
        let (l_len, r_len) = if nl <= nr { (keep, right.len()) } else { (left.len(), keep) };
        self.dissect(&mut left[..l_len], depth + 1);
        let a = self.order.len();
        self.dissect(&mut right[..r_len], depth + 1);
        if depth == 0 {
            self.top = Some((a, self.order.len()));
        }
        self.order.extend_from_slice(&sep);
    }
}

impl Dissection<'_> {
    /// Orders a part that is not split further by AMD on its own graph.
    fn order_leaf(&mut self, verts: &[u32]) {
        let m = verts.len();
        if m <= 2 {
            self.order.extend_from_slice(verts);
            return;
        }
        for (i, &v) in verts.iter().enumerate() {
            self.local[v as usize] = i as u32;
        }
        let tag = self.tag[verts[0] as usize];
        let mut ptr = Vec::with_capacity(m + 1);
        let mut idx = Vec::new();
        ptr.push(0usize);
        for &v in verts {
            for &u in &self.adj[self.adj_ptr[v as usize]..self.adj_ptr[v as usize + 1]] {
                if self.tag[u as usize] == tag {
                    idx.push(self.local[u as usize] as usize);
                }
            }
            ptr.push(idx.len());
        }
        let mut fwd = vec![0usize; m];
        let mut inv = vec![0usize; m];
        let a = SymbolicSparseColMatRef::new_unsorted_checked(m, m, &ptr, None, &idx);
        let ok = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(m, idx.len())).is_ok_and(|mut mem| {
            amd::order_maybe_unsorted(&mut fwd, &mut inv, a, amd::Control::default(), MemStack::new(&mut mem)).is_ok()
        });
        if ok {
            self.order.extend(fwd.iter().map(|&i| verts[i]));
        } else {
            self.order.extend_from_slice(verts);
        }
    }
}

/// Reorders `v` so that the elements with `pred` come first; returns their count.
fn partition(v: &mut [u32], pred: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for i in 0..v.len() {
        if pred(v[i]) {
            v.swap(i, k);
            k += 1;
        }
    }
    k
}
