//! A node ordering kept across the symbolic analyses of systems on one mesh: the entries
//! of a crack growth run, whose node graph the growing crack does not change (the new
//! enriched unknowns sit on nodes that exist).
//!
//! Entry point: [`ReusedOrdering`], handed to the solver through
//! [`crate::solve::statics::SolveOptions::reuse_ordering`] (then
//! [`crate::solve::backend::SystemStructure::reuse`] and [`super::Order::reuse`]); the
//! geometric nested dissection of 2D meshes ([`super::dissection_split`], for the whole and
//! the split factorisations) goes through [`by_points`], which records the node order of
//! the first analysis and expands it to the unknowns of the later ones in `O(n)`. Only the
//! elimination tree, the column counts and the supernodes are then redone.
//!
//! Kept while the ordering asked for, the dimension, the number of mesh nodes and the set
//! of nodes that carry unknowns are those recorded; otherwise the ordering is recomputed
//! and recorded anew. The dissection depends on the node graph and the coordinates only,
//! so the expanded order is the one a new analysis would compute: the same factor, bit for
//! bit, while the node graph is unchanged. Any node order is a valid elimination order, so
//! a coupling that appears between nodes that were not coupled when the order was recorded
//! (a large-sliding crack pairing cells far apart) costs fill, never correctness; the split
//! factorisation checks its separator and falls back to the whole one.
//!
//! METIS (the 3D ordering) is not reused: it weights the nodes by their number of
//! unknowns, and the order of entry 0 gave 9.6% more entries in `L` than a new one at the
//! third entry of `examples/fatigue_penny_3d.toml` (35.1M against 32.1M), for a saving
//! (METIS on 1e5 unknowns, a fraction of a second) small beside a 3D factorisation
//! (`docs/performance.md`, "Crack growth").

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use super::{EquationPoints, OrderingChoice};

/// The node order of the first analysis of a run, reused by the later ones (see the
/// module's documentation). Shared by the analyses of one run (`Arc` in the options).
#[derive(Debug, Default)]
pub struct ReusedOrdering {
    kept: Mutex<Option<NodeOrder>>,
    /// Never reuse (the orderings are only counted and timed: a benchmark's reference).
    never: bool,
    computed: AtomicUsize,
    reused: AtomicUsize,
    /// Wall nanoseconds in the orderings (computed or expanded).
    nanos: AtomicU64,
}

/// What an ordering is kept for, and the order.
#[derive(Debug)]
struct NodeOrder {
    choice: OrderingChoice,
    dim: usize,
    n_points: usize,
    /// Whether each node carried unknowns when the order was recorded.
    carries: Vec<bool>,
    /// The nodes in elimination order (those that carried unknowns).
    order: Vec<u32>,
    /// Nodes in the two parts of the top-level split (`(0, 0)` without one).
    top: (usize, usize),
}

impl ReusedOrdering {
    /// An empty record: the first analysis computes the ordering.
    pub fn new() -> Self {
        Self::default()
    }

    /// A record that never reuses: every analysis computes its ordering, counted and
    /// timed as with [`Self::new`] (the reference of a benchmark).
    pub fn never() -> Self {
        ReusedOrdering { never: true, ..Self::default() }
    }

    /// (orderings computed, orderings reused) so far.
    pub fn counts(&self) -> (usize, usize) {
        (self.computed.load(Ordering::Relaxed), self.reused.load(Ordering::Relaxed))
    }

    /// Wall seconds spent in the orderings so far (computing them, or expanding the kept
    /// one).
    pub fn seconds(&self) -> f64 {
        self.nanos.load(Ordering::Relaxed) as f64 * 1e-9
    }
}

/// The nodes carrying unknowns `0..n` of `points` (every unknown must have a node).
fn carrying(points: &EquationPoints<'_>, n: usize) -> Option<Vec<bool>> {
    let np = points.coords.len();
    let mut carries = vec![false; np];
    for &p in &points.point_of_eq[..n] {
        *carries.get_mut(p as usize)? = true;
    }
    Some(carries)
}

/// An ordering of the unknowns `0..n` that keeps the unknowns of each node together, as
/// (forward, inverse, (unknowns of part 1, of part 2)) like
/// [`super::geometric::nested_dissection_split`] (the parts `(0, 0)` when the ordering has
/// no top-level split). With `reuse`, the recorded node order is expanded when it applies
/// (see the module's documentation); otherwise `compute` orders the unknowns and, with
/// `reuse`, its node order is recorded. `None` when `compute` gives none.
pub fn by_points<E>(
    n: usize,
    points: &EquationPoints<'_>,
    choice: OrderingChoice,
    reuse: Option<&ReusedOrdering>,
    compute: impl FnOnce() -> Result<Option<super::geometric::SplitOrdering>, E>,
) -> Result<Option<super::geometric::SplitOrdering>, E> {
    let Some(reuse) = reuse else { return compute() };
    let Some(carries) = (points.point_of_eq.len() >= n).then(|| carrying(points, n)).flatten() else {
        return compute();
    };
    let clock = Instant::now();
    let elapsed = || clock.elapsed().as_nanos() as u64;
    let lock = || reuse.kept.lock().unwrap_or_else(|e| e.into_inner());
    {
        let kept = lock();
        if let Some(k) = kept.as_ref().filter(|k| {
            !reuse.never
                && k.choice == choice
                && k.dim == points.dim
                && k.n_points == points.coords.len()
                && k.carries == carries
        }) {
            let expanded = expand(k, &points.point_of_eq[..n]);
            reuse.reused.fetch_add(1, Ordering::Relaxed);
            reuse.nanos.fetch_add(elapsed(), Ordering::Relaxed);
            return Ok(Some(expanded));
        }
    }
    // Not under the lock: the ordering runs rayon tasks, and a task stolen meanwhile could
    // analyse another system of the run.
    let computed = compute()?;
    if let Some((fwd, _, top)) = &computed {
        *lock() = record(fwd, *top, &points.point_of_eq[..n], choice, points.dim, carries);
        reuse.computed.fetch_add(1, Ordering::Relaxed);
    }
    reuse.nanos.fetch_add(elapsed(), Ordering::Relaxed);
    Ok(computed)
}

/// The node order of `fwd` (unknowns in elimination order), or `None` when the unknowns of
/// some node are not consecutive in it.
fn record(
    fwd: &[usize],
    top: (usize, usize),
    point_of: &[u32],
    choice: OrderingChoice,
    dim: usize,
    carries: Vec<bool>,
) -> Option<NodeOrder> {
    let mut order: Vec<u32> = Vec::with_capacity(carries.len());
    let mut seen = vec![false; carries.len()];
    let mut top_nodes = (0, 0);
    for (k, &j) in fwd.iter().enumerate() {
        if k == top.0 && top.0 > 0 {
            top_nodes.0 = order.len();
        }
        if k == top.0 + top.1 && top.1 > 0 {
            top_nodes.1 = order.len() - top_nodes.0;
        }
        let p = point_of[j];
        if order.last() != Some(&p) {
            if seen[p as usize] {
                return None;
            }
            seen[p as usize] = true;
            order.push(p);
        }
    }
    if top.1 > 0 && top.0 + top.1 == fwd.len() {
        top_nodes.1 = order.len() - top_nodes.0;
    }
    Some(NodeOrder { choice, dim, n_points: carries.len(), carries, order, top: top_nodes })
}

/// The recorded node order expanded to the unknowns `0..n` (`point_of[j]`: the node of
/// unknown `j`; every node carrying one is in the order), each node's unknowns in
/// increasing order, with the sizes of the top-level parts in unknowns.
fn expand(k: &NodeOrder, point_of: &[u32]) -> super::geometric::SplitOrdering {
    let n = point_of.len();
    let np = k.n_points;
    let mut eq_ptr = vec![0usize; np + 1];
    for &p in point_of {
        eq_ptr[p as usize + 1] += 1;
    }
    for p in 0..np {
        eq_ptr[p + 1] += eq_ptr[p];
    }
    let mut next = eq_ptr.clone();
    let mut eqs = vec![0usize; n];
    for (j, &p) in point_of.iter().enumerate() {
        eqs[next[p as usize]] = j;
        next[p as usize] += 1;
    }
    let mut fwd = Vec::with_capacity(n);
    let mut top = (0, 0);
    for (r, &p) in k.order.iter().enumerate() {
        if r == k.top.0 && k.top.0 > 0 {
            top.0 = fwd.len();
        }
        if r == k.top.0 + k.top.1 && k.top.1 > 0 {
            top.1 = fwd.len() - top.0;
        }
        fwd.extend_from_slice(&eqs[eq_ptr[p as usize]..eq_ptr[p as usize + 1]]);
    }
    if k.top.1 > 0 && k.top.0 + k.top.1 == k.order.len() {
        top.1 = fwd.len() - top.0;
    }
    debug_assert_eq!(fwd.len(), n, "every node carrying an unknown is in the recorded order");
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    (fwd, inv, top)
}

#[cfg(test)]
mod tests {
    use super::super::geometric::nested_dissection_split;
    use super::super::{primal_ordering, Order};
    use super::*;

    /// The pattern (both triangles) of a quad grid of `nx × ny` nodes with two standard
    /// unknowns per node but the `fixed` ones (none there), and two enriched unknowns on
    /// each of the nodes `enriched` (numbered after the standard ones, as fissure's dof
    /// map does): every unknown of a node couples to every unknown of the nodes sharing a
    /// cell. Returns (col_ptr, row_idx, node of each unknown, node coordinates).
    #[allow(clippy::type_complexity)]
    fn grid(
        nx: usize,
        ny: usize,
        enriched: &[usize],
        fixed: &[usize],
    ) -> (Vec<usize>, Vec<usize>, Vec<u32>, Vec<[f64; 3]>) {
        let np = nx * ny;
        let mut of_node: Vec<Vec<usize>> = vec![vec![]; np];
        let mut point: Vec<u32> = vec![];
        for p in (0..np).filter(|p| !fixed.contains(p)) {
            for _ in 0..2 {
                of_node[p].push(point.len());
                point.push(p as u32);
            }
        }
        for &p in enriched {
            for _ in 0..2 {
                of_node[p].push(point.len());
                point.push(p as u32);
            }
        }
        let n = point.len();
        let mut cols: Vec<Vec<usize>> = vec![vec![]; n];
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let cell = [y * nx + x, y * nx + x + 1, (y + 1) * nx + x, (y + 1) * nx + x + 1];
                for &a in &cell {
                    for &b in &cell {
                        for &i in &of_node[a] {
                            cols[i].extend_from_slice(&of_node[b]);
                        }
                    }
                }
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = vec![];
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        let coords = (0..np).map(|p| [(p % nx) as f64, (p / nx) as f64, 0.0]).collect();
        (col_ptr, row_idx, point, coords)
    }

    fn order<'a>(points: &'a EquationPoints<'a>, reuse: &'a ReusedOrdering) -> Order<'a> {
        Order { points: Some(points), choice: OrderingChoice::Auto, reuse: Some(reuse) }
    }

    /// A growth increment in 2D: the crack's enriched nodes change (a longer line of them),
    /// the node graph does not. The node order recorded on the first pattern, expanded to
    /// the second's unknowns, is the ordering a new dissection of the second computes
    /// (the same unknowns in the same order, the same top-level parts: the same factor);
    /// a pattern whose unknowns sit on other nodes is ordered anew.
    #[test]
    fn the_kept_node_order_expanded_to_a_grown_crack_is_the_new_dissection() {
        let (nx, ny) = (41, 33);
        let line = |len: usize| -> Vec<usize> { (0..len).map(|x| 16 * nx + 10 + x).collect() };
        let reuse = ReusedOrdering::new();
        for (step, len) in [8, 10, 14].into_iter().enumerate() {
            let (col_ptr, row_idx, point, coords) = grid(nx, ny, &line(len), &[]);
            let n = point.len();
            let points = EquationPoints { point_of_eq: &point, coords: &coords, dim: 2 };
            let kept = super::super::dissection_split(&col_ptr, &row_idx, n, &points, order(&points, &reuse)).unwrap();
            let fresh = nested_dissection_split(&col_ptr, &row_idx, n, &points).unwrap();
            assert_eq!(kept.0, fresh.0, "increment {step}: the forward permutation");
            assert_eq!(kept.1, fresh.1, "increment {step}: the inverse permutation");
            assert_eq!(kept.2, fresh.2, "increment {step}: the top-level parts");
            assert!(kept.2 .0 > 0 && kept.2 .1 > 0);
            assert_eq!(
                reuse.counts(),
                (1, 2 * step),
                "increment {step}: computed once, then reused (twice per increment)"
            );
            // Through `primal_ordering` (the unsplit path) too.
            let (fwd, _) = primal_ordering(&col_ptr, &row_idx, n, order(&points, &reuse)).unwrap();
            assert_eq!(fwd, fresh.0);
        }
        // A node without unknowns (held by a Dirichlet condition, say): ordered anew.
        let (col_ptr, row_idx, point, coords) = grid(nx, ny, &line(14), &[0, 1]);
        let n = point.len();
        let points = EquationPoints { point_of_eq: &point, coords: &coords, dim: 2 };
        let before = reuse.counts();
        super::super::dissection_split(&col_ptr, &row_idx, n, &points, order(&points, &reuse)).unwrap();
        assert_eq!(reuse.counts().1, before.1, "a changed set of nodes is not reused");
        assert_eq!(reuse.counts().0, before.0 + 1);
    }
}
