//! The layout of a linear system: equation numbers, the sparsity pattern, element dof
//! lists and the element colouring; and the parallel assembly into that layout.
//!
//! Entry points: [`SystemLayout::build`] (once per pattern), [`SystemLayout::assemble`]
//! (each refill), [`SystemLayout::element_forces_of`] (reactions and residuals); for
//! assembly distributed among MPI ranks straight into a distributed matrix,
//! [`SystemLayout::build_distributed`] (equations numbered rank by rank, the preallocation
//! counts of this rank's rows, no pattern) and [`SystemLayout::assemble_elements`] (each
//! element matrix handed to the caller's sink).

use super::{CscPattern, Kernel, LocalOut, NO_EQ};
use rayon::prelude::*;

/// Element dof lists of one kernel, back to back: of every element of the kernel, or with
/// `ids` of the listed elements only (a distributed layout: this rank's).
#[derive(Debug, Clone, Default)]
struct DofLists {
    offsets: Vec<usize>,
    dofs: Vec<u32>,
    /// The kernel's element index of each listed element; empty: every element, in order.
    ids: Vec<u32>,
}

impl DofLists {
    /// The dofs of listed element `i`.
    fn get(&self, i: usize) -> &[u32] {
        &self.dofs[self.offsets[i]..self.offsets[i + 1]]
    }
    /// The number of listed elements.
    fn len(&self) -> usize {
        self.offsets.len() - 1
    }
    /// The kernel's index of listed element `i` (what [`Kernel::compute`] takes).
    fn id(&self, i: usize) -> usize {
        if self.ids.is_empty() {
            i
        } else {
            self.ids[i] as usize
        }
    }
}

/// One element reference: (kernel index, index in the kernel's [`DofLists`]).
type ElemRef = (u32, u32);

/// Equation numbering, pattern and colouring for a set of kernels.
#[derive(Debug, Clone)]
pub struct SystemLayout {
    /// Equation of each dof, or [`NO_EQ`] for eliminated dofs.
    pub eq_of_dof: Vec<u32>,
    /// Number of equations (unknowns of the linear system).
    pub n_eq: usize,
    /// Equations `0..n_primal_eq` are displacement-like, the rest multipliers.
    pub n_primal_eq: usize,
    /// Sparsity pattern over equations (both triangles).
    pub pattern: CscPattern,
    lists: Vec<DofLists>,
    /// For each matrix kernel, the value-array position of every local entry (row-major,
    /// element after element; `u32::MAX` where the row or column is eliminated), so that
    /// a refill does no searching. `None` for kernels without a matrix.
    positions: Vec<Option<Vec<u32>>>,
    /// Start of each element's block in `positions` (per kernel).
    position_offsets: Vec<Vec<usize>>,
    colors: Vec<Vec<ElemRef>>,
    max_local: usize,
    /// Distributed assembly (PETSc backend): this rank's rows and their preallocation
    /// counts. The layout then lists only the elements this rank assembles (`lists`,
    /// `colors`), has no pattern and no positions (the matrix lives in the backend, filled
    /// by [`Self::assemble_elements`]), and [`Self::assemble_kernels`] and
    /// [`Self::element_forces_of`] give this rank's elements' vectors only (partial sums,
    /// completed across the ranks by the caller). `None`: every element (the default).
    pub distributed: Option<DistributedRows>,
}

/// What a distributed layout knows of the matrix (see [`SystemLayout::build_distributed`]):
/// the equations this rank owns (a contiguous block) and, for each of them, the number of
/// nonzero columns inside the block (`d_nnz`) and outside it (`o_nnz`), counted from every
/// element touching the row, whichever rank assembles it.
#[derive(Debug, Clone, Default)]
pub struct DistributedRows {
    /// This rank's equations `rows.start..rows.end`.
    pub rows: std::ops::Range<usize>,
    pub d_nnz: Vec<u32>,
    pub o_nnz: Vec<u32>,
    /// Entries of the whole matrix (summed over the ranks by the caller; this rank's rows'
    /// count until then).
    pub nnz_total: usize,
    /// The matrix's block size: the dimension when every run of that many equations is the
    /// components of one node (see [`Ownership::node_blocks`]), 1 otherwise.
    pub block: usize,
}

/// Where [`SystemLayout::assemble_elements`] hands each element matrix: its equations
/// (one per element dof, [`NO_EQ`] for eliminated dofs) and its values, row-major.
pub type ElementSink<'s> = dyn FnMut(&[u32], &[f64]) + 's;

/// A fill of a distributed matrix: calls the sink it is given with every element matrix
/// (e.g. a closure around [`SystemLayout::assemble_elements`]).
pub type ElementFill<'f> = dyn FnMut(&mut ElementSink<'_>) + 'f;

/// Who assembles what, for [`SystemLayout::build_distributed`].
pub struct Ownership {
    /// Per kernel, per element: whether this rank assembles it.
    pub elements: Vec<Vec<bool>>,
    /// The rank owning each dof's equation (primal dofs; multipliers go to the last rank).
    pub dof_rank: Vec<u32>,
    /// This rank and the number of ranks.
    pub rank: u32,
    pub ranks: u32,
    /// `Some(dim)` when the primal dofs come in runs of `dim` (starting at multiples of
    /// `dim`) that are the components of one node, each run eliminated or kept as a whole,
    /// and there are no multipliers: the equations then keep those runs, and the matrix
    /// has block size `dim` (an aggregation multigrid aggregates nodes, not components).
    pub node_blocks: Option<usize>,
}

/// A raw pointer that may be shared between threads because the colouring
/// guarantees that concurrent writes go to distinct entries.
#[derive(Clone, Copy)]
struct SharedMut(*mut f64);
unsafe impl Send for SharedMut {}
unsafe impl Sync for SharedMut {}

impl SharedMut {
    /// # Safety
    /// No other thread may access index `i` concurrently.
    #[inline]
    unsafe fn add(self, i: usize, v: f64) {
        *self.0.add(i) += v;
    }
}

impl SystemLayout {
    /// Builds the layout. `eliminated[d]` marks prescribed dofs (no equation);
    /// `n_primal_dofs` is the number of non-multiplier dofs (they come first).
    pub fn build(n_dofs: usize, n_primal_dofs: usize, eliminated: &[bool], kernels: &[&dyn Kernel]) -> SystemLayout {
        let mut eq_of_dof = vec![NO_EQ; n_dofs];
        let mut n_eq = 0usize;
        let mut n_primal_eq = 0usize;
        for d in 0..n_dofs {
            if !eliminated[d] {
                eq_of_dof[d] = n_eq as u32;
                n_eq += 1;
                if d < n_primal_dofs {
                    n_primal_eq += 1;
                }
            }
        }
        let lists = element_lists(kernels);
        let max_local = lists.iter().flat_map(|l| l.offsets.windows(2).map(|w| w[1] - w[0])).max().unwrap_or(0);

        // Pattern, column by column: the elements touching each equation (compressed),
        // then for each column the sorted, unique equations of those elements. Parallel
        // over columns, with small sorts instead of one global sort of every pair.
        let mut touch_ptr = vec![0usize; n_eq + 1];
        for (k, l) in kernels.iter().zip(&lists) {
            if !k.has_matrix() {
                continue;
            }
            for e in 0..l.offsets.len() - 1 {
                for &d in l.get(e) {
                    let q = eq_of_dof[d as usize];
                    if q != NO_EQ {
                        touch_ptr[q as usize + 1] += 1;
                    }
                }
            }
        }
        for j in 0..n_eq {
            touch_ptr[j + 1] += touch_ptr[j];
        }
        let mut fill = touch_ptr.clone();
        let mut touch: Vec<ElemRef> = vec![(0, 0); touch_ptr[n_eq]];
        for (k, (kern, l)) in kernels.iter().zip(&lists).enumerate() {
            if !kern.has_matrix() {
                continue;
            }
            for e in 0..l.offsets.len() - 1 {
                for &d in l.get(e) {
                    let q = eq_of_dof[d as usize];
                    if q != NO_EQ {
                        touch[fill[q as usize]] = (k as u32, e as u32);
                        fill[q as usize] += 1;
                    }
                }
            }
        }
        drop(fill);

        // Element-local entry offsets of the matrix kernels' positions.
        let position_offsets: Vec<Vec<usize>> = kernels
            .iter()
            .zip(&lists)
            .map(|(k, l)| {
                let ne = k.n_elements();
                let mut off = Vec::with_capacity(ne + 1);
                off.push(0usize);
                for e in 0..ne {
                    let m = l.offsets[e + 1] - l.offsets[e];
                    off.push(off[e] + if k.has_matrix() { m * m } else { 0 });
                }
                off
            })
            .collect();
        let mut positions: Vec<Option<Vec<u32>>> = kernels
            .iter()
            .zip(&position_offsets)
            .map(|(k, off)| k.has_matrix().then(|| vec![u32::MAX; off[off.len() - 1]]))
            .collect();
        let pos_ptrs: Vec<Option<SharedU32>> =
            positions.iter_mut().map(|p| p.as_mut().map(|v| SharedU32(v.as_mut_ptr()))).collect();

        // Columns in blocks (parallel over blocks): gather the equations of the elements
        // touching the column, sort, dedup; a column whose touching elements are those of
        // the previous one (the components of a node) is a copy of it. While a column is
        // at hand, every element entry in it gets its position relative to the column
        // start (`slot`: row -> rank in the current column), so no searching is needed.
        const BLOCK: usize = 1024;
        let n_blocks = n_eq.div_ceil(BLOCK);
        let blocks: Vec<(Vec<usize>, Vec<usize>)> = (0..n_blocks)
            .into_par_iter()
            .map_init(
                || (Vec::<usize>::new(), vec![0u32; n_eq]),
                |(buf, slot), bi| {
                    let cols = bi * BLOCK..((bi + 1) * BLOCK).min(n_eq);
                    let mut lens = Vec::with_capacity(cols.len());
                    let mut rows: Vec<usize> = Vec::new();
                    let mut prev: Option<(usize, usize)> = None; // (column, start in rows)
                    for j in cols {
                        let tl = &touch[touch_ptr[j]..touch_ptr[j + 1]];
                        let start = rows.len();
                        match prev {
                            Some((pj, ps)) if touch[touch_ptr[pj]..touch_ptr[pj + 1]] == *tl => {
                                rows.extend_from_within(ps..start);
                            }
                            _ => {
                                buf.clear();
                                for &(k, e) in tl {
                                    for &d in lists[k as usize].get(e as usize) {
                                        let q = eq_of_dof[d as usize];
                                        if q != NO_EQ {
                                            buf.push(q as usize);
                                        }
                                    }
                                }
                                buf.sort_unstable();
                                buf.dedup();
                                for (r, &i) in buf.iter().enumerate() {
                                    slot[i] = r as u32;
                                }
                                rows.extend_from_slice(buf);
                            }
                        }
                        lens.push(rows.len() - start);
                        prev = Some((j, start));
                        for &(k, e) in tl {
                            let Some(out) = pos_ptrs[k as usize] else { continue };
                            let dofs = lists[k as usize].get(e as usize);
                            let m = dofs.len();
                            let Some(b) = dofs.iter().position(|&d| eq_of_dof[d as usize] == j as u32) else {
                                continue;
                            };
                            let base = position_offsets[k as usize][e as usize];
                            for (a, &d) in dofs.iter().enumerate() {
                                let ra = eq_of_dof[d as usize];
                                if ra != NO_EQ {
                                    // SAFETY: entry (a, b) of element e is written only here,
                                    // by the column of b's equation.
                                    unsafe { out.set(base + a * m + b, slot[ra as usize]) };
                                }
                            }
                        }
                    }
                    (lens, rows)
                },
            )
            .collect();
        drop(touch);
        let mut col_ptr = Vec::with_capacity(n_eq + 1);
        col_ptr.push(0usize);
        let mut block_off = Vec::with_capacity(n_blocks + 1);
        block_off.push(0usize);
        for (lens, rows) in &blocks {
            for &l in lens {
                col_ptr.push(col_ptr[col_ptr.len() - 1] + l);
            }
            block_off.push(block_off[block_off.len() - 1] + rows.len());
        }
        let nnz = col_ptr[n_eq];
        assert!(nnz < u32::MAX as usize, "more than 4e9 matrix entries: beyond this machine's memory");
        let mut row_idx = vec![0usize; nnz];
        split_by_offsets(&mut row_idx, &block_off)
            .into_par_iter()
            .zip(&blocks)
            .for_each(|(out, (_, rows))| out.copy_from_slice(rows));
        drop(blocks);
        // Relative positions to absolute ones.
        for (k, pos) in positions.iter_mut().enumerate() {
            let Some(pos) = pos else { continue };
            let l = &lists[k];
            let chunks: Vec<&mut [u32]> = split_by_offsets(pos, &position_offsets[k]);
            chunks.into_par_iter().enumerate().for_each(|(e, out)| {
                let dofs = l.get(e);
                let m = dofs.len();
                for (b, &db) in dofs.iter().enumerate() {
                    let cb = eq_of_dof[db as usize];
                    if cb == NO_EQ {
                        continue;
                    }
                    let s = col_ptr[cb as usize] as u32;
                    for a in 0..m {
                        let p = &mut out[a * m + b];
                        if *p != u32::MAX {
                            *p += s;
                        }
                    }
                }
            });
        }
        let pattern = CscPattern { n: n_eq, col_ptr, row_idx };
        let colors = color_elements(n_eq, &eq_of_dof, &lists);
        SystemLayout {
            eq_of_dof,
            n_eq,
            n_primal_eq,
            pattern,
            lists,
            positions,
            position_offsets,
            colors,
            max_local,
            distributed: None,
        }
    }

    /// The layout for assembly distributed among MPI ranks straight into a distributed
    /// matrix: no pattern, no value array, no positions on any rank. The equations are
    /// numbered rank by rank (`ownership.dof_rank`, in dof order within a rank; the
    /// multipliers after every primal equation, on the last rank), so that each rank owns
    /// a contiguous block of rows ([`DistributedRows::rows`]) holding its nodes' dofs,
    /// enriched ones included; the preallocation counts of those rows come from the
    /// element dof lists of every kernel with a matrix (every element touching the row,
    /// whichever rank assembles it: the model is replicated). The element lists and
    /// colours then keep only the elements of `ownership.elements` (this rank's): every
    /// assembly and [`Self::element_forces_of`] compute those, and the caller sums over
    /// the ranks what it needs whole (the load vector, the reactions).
    pub fn build_distributed(
        n_dofs: usize,
        n_primal_dofs: usize,
        eliminated: &[bool],
        kernels: &[&dyn Kernel],
        ownership: Ownership,
    ) -> SystemLayout {
        let Ownership { elements, dof_rank, rank, ranks, node_blocks } = ownership;
        let ranks = ranks.max(1);
        // Primal equations rank by rank, then the multipliers (last rank's block).
        let mut eq_of_dof = vec![NO_EQ; n_dofs];
        let mut start = vec![0usize; ranks as usize + 1];
        for d in (0..n_primal_dofs.min(n_dofs)).filter(|&d| !eliminated[d]) {
            start[dof_rank[d].min(ranks - 1) as usize + 1] += 1;
        }
        for r in 0..ranks as usize {
            start[r + 1] += start[r];
        }
        let n_primal_eq = start[ranks as usize];
        let mut next = start.clone();
        for d in (0..n_primal_dofs.min(n_dofs)).filter(|&d| !eliminated[d]) {
            let r = dof_rank[d].min(ranks - 1) as usize;
            eq_of_dof[d] = next[r] as u32;
            next[r] += 1;
        }
        let mut n_eq = n_primal_eq;
        for d in (n_primal_dofs..n_dofs).filter(|&d| !eliminated[d]) {
            eq_of_dof[d] = n_eq as u32;
            n_eq += 1;
        }
        let lo = start[rank as usize];
        let hi = if rank + 1 == ranks { n_eq } else { start[rank as usize + 1] };
        // The elements touching this rank's rows (its own and the neighbours' across the
        // partition's boundary) for the counts, then this rank's alone: no rank lists the
        // whole model's elements.
        let mine = |q: u32| q != NO_EQ && (lo..hi).contains(&(q as usize));
        let near = element_lists_where(kernels, &|k, e, dofs| {
            elements[k][e] || dofs.iter().any(|&d| mine(eq_of_dof[d as usize]))
        });
        let with_matrix: Vec<bool> = kernels.iter().map(|k| k.has_matrix()).collect();
        let (d_nnz, o_nnz) = row_counts(&eq_of_dof, &near, &with_matrix, lo..hi);
        let local_nnz = d_nnz.iter().chain(&o_nnz).map(|&c| c as usize).sum();
        let lists: Vec<DofLists> = near.iter().enumerate().map(|(k, l)| l.retain(|i| elements[k][l.id(i)])).collect();
        drop((near, elements));
        let max_local = lists.iter().flat_map(|l| l.offsets.windows(2).map(|w| w[1] - w[0])).max().unwrap_or(0);
        let colors = color_elements(n_eq, &eq_of_dof, &lists);
        SystemLayout {
            eq_of_dof,
            n_eq,
            n_primal_eq,
            pattern: CscPattern { n: n_eq, col_ptr: vec![0; n_eq + 1], row_idx: vec![] },
            lists,
            positions: kernels.iter().map(|_| None).collect(),
            position_offsets: kernels.iter().map(|_| vec![]).collect(),
            colors,
            max_local,
            distributed: Some(DistributedRows {
                rows: lo..hi,
                d_nnz,
                o_nnz,
                nnz_total: local_nnz,
                block: node_blocks.filter(|_| n_primal_eq == n_eq).unwrap_or(1),
            }),
        }
    }

    /// Whether this layout assembles only this rank's elements (see
    /// [`Self::build_distributed`]).
    pub fn is_distributed(&self) -> bool {
        self.distributed.is_some()
    }

    /// Whether this rank assembles element `e` (the kernel's own index, as
    /// [`Kernel::compute`] takes it) of kernel `k`: every element of a layout that is not
    /// distributed; on a distributed one, the elements it lists (its own, ascending).
    pub fn owns(&self, k: usize, e: usize) -> bool {
        self.distributed.is_none() || self.lists[k].ids.binary_search(&(e as u32)).is_ok()
    }

    /// Entries of the matrix: the pattern's, or with distributed assembly the whole
    /// matrix's ([`DistributedRows::nnz_total`]).
    pub fn nnz(&self) -> usize {
        self.distributed.as_ref().map_or(self.pattern.nnz(), |d| d.nnz_total)
    }

    /// The dofs of every element of kernel `k` (in the order given to
    /// [`SystemLayout::build`]), element after element, repeats included (on a distributed
    /// layout, of this rank's elements only).
    pub fn kernel_dofs(&self, k: usize) -> &[u32] {
        &self.lists[k].dofs
    }

    /// Number of kernels the layout was built with.
    pub fn n_kernels(&self) -> usize {
        self.lists.len()
    }

    /// Number of colours (for logs and benchmarks).
    pub fn n_colors(&self) -> usize {
        self.colors.len()
    }

    /// Assembles the kernels (same order as at [`SystemLayout::build`]) into `matrix`
    /// (values on [`Self::pattern`]) and/or `rhs` (length `n_eq`). Both are zeroed
    /// first. `prescribed[d]` is the value of each eliminated dof: its column is moved
    /// to the right-hand side (`rhs -= K_fp u_p`).
    pub fn assemble(
        &self,
        kernels: &[&dyn Kernel],
        prescribed: &[f64],
        matrix: Option<&mut [f64]>,
        rhs: Option<&mut [f64]>,
    ) {
        let all = vec![true; kernels.len()];
        self.assemble_kernels(kernels, &all, prescribed, matrix, rhs, false);
    }

    /// Like [`Self::assemble`] for the kernels with `include[k]` only; with `accumulate`
    /// the contributions are added to `matrix` and `rhs` instead of overwriting them (a
    /// fixed part assembled once plus a changing part, as in contact iterations).
    pub fn assemble_kernels(
        &self,
        kernels: &[&dyn Kernel],
        include: &[bool],
        prescribed: &[f64],
        matrix: Option<&mut [f64]>,
        rhs: Option<&mut [f64]>,
        accumulate: bool,
    ) {
        assert_eq!(kernels.len(), self.lists.len(), "the kernels must be those the layout was built with");
        assert!(
            matrix.is_none() || !self.is_distributed(),
            "a distributed layout has no value array: its matrix is filled by assemble_elements"
        );
        let want_m = matrix.is_some();
        let want_f = rhs.is_some();
        let mp = matrix.map(|m| {
            if !accumulate {
                m.par_iter_mut().for_each(|v| *v = 0.0);
            }
            SharedMut(m.as_mut_ptr())
        });
        let fp = rhs.map(|f| {
            if !accumulate {
                f.par_iter_mut().for_each(|v| *v = 0.0);
            }
            SharedMut(f.as_mut_ptr())
        });
        let n = self.max_local;
        let mut items = Vec::new();
        for color in &self.colors {
            // The included elements of the colour, gathered first (a serial scan): a pass
            // over a few kernels' elements (the contact kernel, boundary loads) then does
            // not split the whole colour into parallel jobs that each set up their buffers.
            items.clear();
            items.extend(color.iter().filter(|&&(k, _)| include[k as usize]));
            if items.is_empty() {
                continue;
            }
            items.par_iter().with_min_len(8).for_each_init(
                || (vec![0.0; n * n], vec![0.0; n], Vec::<u32>::with_capacity(n)),
                |(ke, fe, eqs), &&(k, e)| {
                    let kernel = kernels[k as usize];
                    let list = &self.lists[k as usize];
                    let dofs = list.get(e as usize);
                    let m = dofs.len();
                    let need_matrix = kernel.has_matrix()
                        && (want_m || (want_f && dofs.iter().any(|&d| self.eq_of_dof[d as usize] == NO_EQ)));
                    let ke = &mut ke[..m * m];
                    let fe = &mut fe[..m];
                    ke.iter_mut().for_each(|v| *v = 0.0);
                    fe.iter_mut().for_each(|v| *v = 0.0);
                    kernel.compute(
                        list.id(e as usize),
                        dofs,
                        LocalOut { matrix: need_matrix.then_some(&mut *ke), vector: want_f.then_some(&mut *fe) },
                    );
                    eqs.clear();
                    eqs.extend(dofs.iter().map(|&d| self.eq_of_dof[d as usize]));
                    if let Some(fp) = fp {
                        for a in 0..m {
                            if eqs[a] == NO_EQ {
                                continue;
                            }
                            let mut v = fe[a];
                            if need_matrix {
                                for b in 0..m {
                                    if eqs[b] == NO_EQ {
                                        v -= ke[a * m + b] * prescribed[dofs[b] as usize];
                                    }
                                }
                            }
                            // SAFETY: elements of one colour share no equation.
                            unsafe { fp.add(eqs[a] as usize, v) };
                        }
                    }
                    if let (Some(mp), Some(pos)) = (mp, &self.positions[k as usize]) {
                        let start = self.position_offsets[k as usize][e as usize];
                        for (v, &p) in ke.iter().zip(&pos[start..start + m * m]) {
                            if p != u32::MAX {
                                // SAFETY: elements of one colour share no equation, hence no entry.
                                unsafe { mp.add(p as usize, *v) };
                            }
                        }
                    }
                },
            );
        }
    }

    /// Distributed assembly: a zero matrix for every element of the kernels with
    /// `include[k]` that this rank assembles, handed to `sink` with its equations as
    /// [`Self::assemble_elements`] does. Adding them puts the elements' entries into a
    /// distributed matrix as explicit zeros, so that entries filled later (the contact
    /// terms of each refill) stay in its nonzero structure (PETSc squeezes out the
    /// preallocated entries a final assembly found unset).
    pub fn zero_elements(&self, include: &[bool], sink: &mut ElementSink<'_>) {
        let mut eqs: Vec<u32> = Vec::with_capacity(self.max_local);
        let mut zeros: Vec<f64> = vec![];
        for (_, list) in self.lists.iter().enumerate().filter(|(k, _)| include.get(*k).copied().unwrap_or(false)) {
            for e in 0..list.len() {
                eqs.clear();
                eqs.extend(list.get(e).iter().map(|&d| self.eq_of_dof[d as usize]));
                zeros.clear();
                zeros.resize(eqs.len() * eqs.len(), 0.0);
                sink(&eqs, &zeros);
            }
        }
    }

    /// Distributed assembly ([`Self::build_distributed`]): the matrix of every element of
    /// the kernels with `include[k]` that this rank assembles, handed to `sink` with its
    /// equations (one per element dof, [`NO_EQ`] for eliminated dofs; the matrix row-major,
    /// `m × m` for `m` dofs), one element at a time on the calling thread; the element
    /// matrices are computed in parallel in batches. With `rhs` (length `n_eq`, zeroed
    /// first) the load vector of the same elements is assembled too, the columns of the
    /// eliminated dofs moved to it (`rhs -= K_fp u_p`).
    pub fn assemble_elements(
        &self,
        kernels: &[&dyn Kernel],
        include: &[bool],
        prescribed: &[f64],
        mut rhs: Option<&mut [f64]>,
        sink: &mut ElementSink<'_>,
    ) {
        assert_eq!(kernels.len(), self.lists.len(), "the kernels must be those the layout was built with");
        if let Some(f) = rhs.as_deref_mut() {
            f.iter_mut().for_each(|v| *v = 0.0);
        }
        let want_f = rhs.is_some();
        // The elements to compute, in colour order (as the other assemblies).
        let items: Vec<ElemRef> = self
            .colors
            .iter()
            .flatten()
            .copied()
            .filter(|&(k, _)| include[k as usize] && (kernels[k as usize].has_matrix() || want_f))
            .collect();
        const BATCH: usize = 2048;
        let mut ke_all: Vec<f64> = vec![];
        let mut fe_all: Vec<f64> = vec![];
        // Per batch: the offsets of each element's vector (`m`) and matrix (`m²`, none for
        // a kernel without a matrix) in the batch's buffers.
        let mut offsets: Vec<usize> = Vec::with_capacity(BATCH + 1);
        let mut sq_off: Vec<usize> = Vec::with_capacity(BATCH + 1);
        let mut eqs: Vec<u32> = Vec::with_capacity(self.max_local);
        for batch in items.chunks(BATCH) {
            offsets.clear();
            offsets.push(0);
            sq_off.clear();
            sq_off.push(0);
            for &(k, e) in batch {
                let m = self.lists[k as usize].get(e as usize).len();
                offsets.push(offsets[offsets.len() - 1] + m);
                let mm = if kernels[k as usize].has_matrix() { m * m } else { 0 };
                sq_off.push(sq_off[sq_off.len() - 1] + mm);
            }
            let n_sq = sq_off[batch.len()];
            ke_all.clear();
            ke_all.resize(n_sq, 0.0);
            fe_all.clear();
            fe_all.resize(offsets[batch.len()], 0.0);
            let ke_chunks = split_by_offsets(&mut ke_all, &sq_off);
            let fe_chunks = split_by_offsets(&mut fe_all, &offsets);
            ke_chunks.into_par_iter().zip(fe_chunks).zip(batch).with_min_len(8).for_each(|((ke, fe), &(k, e))| {
                let kernel = kernels[k as usize];
                let list = &self.lists[k as usize];
                let dofs = list.get(e as usize);
                kernel.compute(
                    list.id(e as usize),
                    dofs,
                    LocalOut { matrix: kernel.has_matrix().then_some(&mut *ke), vector: want_f.then_some(&mut *fe) },
                );
            });
            for (i, &(k, e)) in batch.iter().enumerate() {
                let dofs = self.lists[k as usize].get(e as usize);
                let m = dofs.len();
                let ke = &ke_all[sq_off[i]..sq_off[i + 1]];
                eqs.clear();
                eqs.extend(dofs.iter().map(|&d| self.eq_of_dof[d as usize]));
                if let Some(f) = rhs.as_deref_mut() {
                    let fe = &fe_all[offsets[i]..offsets[i + 1]];
                    for a in 0..m {
                        if eqs[a] == NO_EQ {
                            continue;
                        }
                        let mut v = fe[a];
                        if !ke.is_empty() {
                            for b in 0..m {
                                if eqs[b] == NO_EQ {
                                    v -= ke[a * m + b] * prescribed[dofs[b] as usize];
                                }
                            }
                        }
                        f[eqs[a] as usize] += v;
                    }
                }
                if !ke.is_empty() {
                    sink(&eqs, ke);
                }
            }
        }
    }

    /// Element forces gathered per dof: `r[d] = Σ_e (K_e u_e − f_e)[d]` over every dof,
    /// eliminated or not, for the full dof vector `u`, summing only the kernels with
    /// `include[k]`. On constrained dofs this is the reaction; on free dofs the residual.
    /// On a distributed layout, this rank's elements only: the caller sums over the ranks.
    pub fn element_forces_of(&self, kernels: &[&dyn Kernel], include: &[bool], u: &[f64]) -> Vec<f64> {
        self.element_forces_touching(kernels, include, None, u)
    }

    /// Like [`Self::element_forces_of`], computing only the elements that have a dof with
    /// `touching[d]` (e.g. the constrained dofs, for reactions); other entries stay 0 or
    /// are partial.
    /// On a distributed layout (which lists this rank's elements only, [`Self::owns`]):
    /// this rank's share, whose sum over the ranks is the whole.
    pub fn element_forces_touching(
        &self,
        kernels: &[&dyn Kernel],
        include: &[bool],
        touching: Option<&[bool]>,
        u: &[f64],
    ) -> Vec<f64> {
        self.element_forces_select(kernels, include, touching, u)
    }

    fn element_forces_select(
        &self,
        kernels: &[&dyn Kernel],
        include: &[bool],
        touching: Option<&[bool]>,
        u: &[f64],
    ) -> Vec<f64> {
        let mut r = vec![0.0; u.len()];
        let rp = SharedMut(r.as_mut_ptr());
        let n = self.max_local;
        // Colours guarantee distinct equations, not distinct eliminated dofs: gather
        // per colour into a thread-safe layout by running eliminated contributions serially.
        for color in &self.colors {
            let serial: Vec<(usize, f64)> = color
                .par_iter()
                .filter(|&&(k, e)| {
                    include[k as usize]
                        && touching
                            .is_none_or(|t| self.lists[k as usize].get(e as usize).iter().any(|&d| t[d as usize]))
                })
                .map_init(
                    || (vec![0.0; n * n], vec![0.0; n]),
                    |(ke, fe), &(k, e)| {
                        let kernel = kernels[k as usize];
                        let list = &self.lists[k as usize];
                        let dofs = list.get(e as usize);
                        let m = dofs.len();
                        let ke = &mut ke[..m * m];
                        let fe = &mut fe[..m];
                        ke.iter_mut().for_each(|v| *v = 0.0);
                        fe.iter_mut().for_each(|v| *v = 0.0);
                        let hm = kernel.has_matrix() && kernel.is_linear();
                        kernel.compute(
                            list.id(e as usize),
                            dofs,
                            LocalOut { matrix: hm.then_some(&mut *ke), vector: Some(&mut *fe) },
                        );
                        let mut out = vec![];
                        for a in 0..m {
                            let mut v = -fe[a];
                            if hm {
                                for b in 0..m {
                                    v += ke[a * m + b] * u[dofs[b] as usize];
                                }
                            }
                            let d = dofs[a] as usize;
                            if self.eq_of_dof[d] == NO_EQ {
                                out.push((d, v));
                            } else {
                                // SAFETY: free dofs map one-to-one to equations, distinct within a colour.
                                unsafe { rp.add(d, v) };
                            }
                        }
                        out
                    },
                )
                .flatten()
                .collect();
            for (d, v) in serial {
                r[d] += v;
            }
        }
        r
    }
}

/// The element dof lists of every kernel.
fn element_lists(kernels: &[&dyn Kernel]) -> Vec<DofLists> {
    kernels
        .iter()
        .map(|k| {
            let mut l = DofLists { offsets: Vec::with_capacity(k.n_elements() + 1), dofs: vec![], ids: vec![] };
            l.offsets.push(0);
            for e in 0..k.n_elements() {
                k.dofs(e, &mut l.dofs);
                l.offsets.push(l.dofs.len());
            }
            l
        })
        .collect()
}

/// The element dof lists of the elements `e` of each kernel `k` with `keep(k, e, dofs)`
/// (with their `ids`), sized to fit.
fn element_lists_where(kernels: &[&dyn Kernel], keep: &dyn Fn(usize, usize, &[u32]) -> bool) -> Vec<DofLists> {
    let mut buf = vec![];
    kernels
        .iter()
        .enumerate()
        .map(|(k, kern)| {
            let mut l = DofLists { offsets: vec![0], dofs: vec![], ids: vec![] };
            for e in 0..kern.n_elements() {
                buf.clear();
                kern.dofs(e, &mut buf);
                if keep(k, e, &buf) {
                    l.dofs.extend_from_slice(&buf);
                    l.offsets.push(l.dofs.len());
                    l.ids.push(e as u32);
                }
            }
            l.shrink_to_fit();
            l
        })
        .collect()
}

impl DofLists {
    /// The listed elements `i` with `keep(i)`, sized to fit (`ids` kept).
    fn retain(&self, keep: impl Fn(usize) -> bool) -> DofLists {
        let mut l = DofLists { offsets: vec![0], dofs: vec![], ids: vec![] };
        for i in (0..self.len()).filter(|&i| keep(i)) {
            l.dofs.extend_from_slice(self.get(i));
            l.offsets.push(l.dofs.len());
            l.ids.push(self.id(i) as u32);
        }
        l.shrink_to_fit();
        l
    }

    fn shrink_to_fit(&mut self) {
        self.offsets.shrink_to_fit();
        self.dofs.shrink_to_fit();
        self.ids.shrink_to_fit();
    }
}

/// For each equation of `rows`: the number of distinct equations coupled to it by the
/// elements of the kernels `with_matrix` inside `rows` (`d_nnz`) and outside (`o_nnz`).
/// Parallel over blocks of rows; a row whose touching elements are those of the previous
/// row (the components of a node) has its counts.
fn row_counts(
    eq_of_dof: &[u32],
    lists: &[DofLists],
    with_matrix: &[bool],
    rows: std::ops::Range<usize>,
) -> (Vec<u32>, Vec<u32>) {
    let n_rows = rows.len();
    let local = |d: u32| {
        let q = eq_of_dof[d as usize];
        (q != NO_EQ && rows.contains(&(q as usize))).then(|| q as usize - rows.start)
    };
    let mut touch_ptr = vec![0usize; n_rows + 1];
    for (l, _) in lists.iter().zip(with_matrix).filter(|(_, &m)| m) {
        for &d in &l.dofs {
            if let Some(r) = local(d) {
                touch_ptr[r + 1] += 1;
            }
        }
    }
    for r in 0..n_rows {
        touch_ptr[r + 1] += touch_ptr[r];
    }
    let mut fill = touch_ptr.clone();
    let mut touch: Vec<ElemRef> = vec![(0, 0); touch_ptr[n_rows]];
    for (k, (l, _)) in lists.iter().zip(with_matrix).enumerate().filter(|(_, (_, &m))| m) {
        for e in 0..l.offsets.len() - 1 {
            for &d in l.get(e) {
                if let Some(r) = local(d) {
                    touch[fill[r]] = (k as u32, e as u32);
                    fill[r] += 1;
                }
            }
        }
    }
    drop(fill);
    const BLOCK: usize = 1024;
    let counts: Vec<(Vec<u32>, Vec<u32>)> = (0..n_rows.div_ceil(BLOCK))
        .into_par_iter()
        .map_init(Vec::<u32>::new, |buf, bi| {
            let block = bi * BLOCK..((bi + 1) * BLOCK).min(n_rows);
            let (mut d_nnz, mut o_nnz) = (Vec::with_capacity(block.len()), Vec::with_capacity(block.len()));
            let mut prev: Option<usize> = None;
            for r in block {
                let tl = &touch[touch_ptr[r]..touch_ptr[r + 1]];
                if let Some(p) = prev.filter(|&p| touch[touch_ptr[p]..touch_ptr[p + 1]] == *tl) {
                    let (dp, op) = (d_nnz[p - bi * BLOCK], o_nnz[p - bi * BLOCK]);
                    d_nnz.push(dp);
                    o_nnz.push(op);
                } else {
                    buf.clear();
                    for &(k, e) in tl {
                        buf.extend(lists[k as usize].get(e as usize).iter().map(|&d| eq_of_dof[d as usize]));
                    }
                    buf.retain(|&q| q != NO_EQ);
                    buf.sort_unstable();
                    buf.dedup();
                    let inside = buf.iter().filter(|&&q| rows.contains(&(q as usize))).count() as u32;
                    d_nnz.push(inside);
                    o_nnz.push(buf.len() as u32 - inside);
                }
                prev = Some(r);
            }
            (d_nnz, o_nnz)
        })
        .collect();
    let mut d_nnz = Vec::with_capacity(n_rows);
    let mut o_nnz = Vec::with_capacity(n_rows);
    for (d, o) in counts {
        d_nnz.extend(d);
        o_nnz.extend(o);
    }
    (d_nnz, o_nnz)
}

/// A raw pointer into a `u32` array written at distinct indices by several threads.
#[derive(Clone, Copy)]
struct SharedU32(*mut u32);
unsafe impl Send for SharedU32 {}
unsafe impl Sync for SharedU32 {}

impl SharedU32 {
    /// # Safety
    /// `i` is in bounds and no other thread accesses index `i` concurrently.
    #[inline]
    unsafe fn set(self, i: usize, v: u32) {
        *self.0.add(i) = v;
    }
}

/// Splits `v` into consecutive mutable chunks `v[off[i]..off[i + 1]]`.
fn split_by_offsets<'a, T>(mut v: &'a mut [T], off: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(off.len().saturating_sub(1));
    for w in off.windows(2) {
        let (head, tail) = v.split_at_mut(w[1] - w[0]);
        out.push(head);
        v = tail;
    }
    out
}

/// Greedy colouring: an element gets the smallest colour not yet used by any element
/// sharing one of its equations. Up to 64 colours are tracked with a bit mask per
/// equation; elements that find none free go to trailing single-element colours.
fn color_elements(n_eq: usize, eq_of_dof: &[u32], lists: &[DofLists]) -> Vec<Vec<ElemRef>> {
    let mut used = vec![0u64; n_eq];
    let mut colors: Vec<Vec<ElemRef>> = vec![];
    let mut leftovers: Vec<ElemRef> = vec![];
    for (k, l) in lists.iter().enumerate() {
        for e in 0..l.offsets.len() - 1 {
            let mut mask = 0u64;
            let mut any = false;
            for &d in l.get(e) {
                let q = eq_of_dof[d as usize];
                if q != NO_EQ {
                    mask |= used[q as usize];
                    any = true;
                }
            }
            if !any {
                // Only eliminated dofs: still needed for reactions, harmless in colour 0.
                if colors.is_empty() {
                    colors.push(vec![]);
                }
                colors[0].push((k as u32, e as u32));
                continue;
            }
            let c = (!mask).trailing_zeros() as usize;
            if c >= 64 {
                leftovers.push((k as u32, e as u32));
                continue;
            }
            while colors.len() <= c {
                colors.push(vec![]);
            }
            colors[c].push((k as u32, e as u32));
            for &d in l.get(e) {
                let q = eq_of_dof[d as usize];
                if q != NO_EQ {
                    used[q as usize] |= 1 << c;
                }
            }
        }
    }
    colors.extend(leftovers.into_iter().map(|r| vec![r]));
    colors
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1D chain of springs of stiffness 1 between consecutive dofs.
    struct Springs(usize);
    impl Kernel for Springs {
        fn n_elements(&self) -> usize {
            self.0
        }
        fn dofs(&self, e: usize, out: &mut Vec<u32>) {
            out.extend([e as u32, e as u32 + 1]);
        }
        fn compute(&self, _e: usize, _dofs: &[u32], out: LocalOut<'_>) {
            if let Some(k) = out.matrix {
                k.copy_from_slice(&[1.0, -1.0, -1.0, 1.0]);
            }
        }
    }

    #[test]
    fn spring_chain_assembles_tridiagonal_and_lifts_prescribed_values() {
        // 4 springs, dofs 0..=4; dof 0 fixed at 0, dof 4 prescribed at 1: u = x/4.
        let k = Springs(4);
        let mut elim = vec![false; 5];
        elim[0] = true;
        elim[4] = true;
        let layout = SystemLayout::build(5, 5, &elim, &[&k]);
        assert_eq!(layout.n_eq, 3);
        assert_eq!(layout.pattern.nnz(), 7);
        let mut vals = vec![0.0; 7];
        let mut rhs = vec![0.0; 3];
        let pres = [0.0, 0.0, 0.0, 0.0, 1.0];
        layout.assemble(&[&k], &pres, Some(&mut vals), Some(&mut rhs));
        assert_eq!(rhs, vec![0.0, 0.0, 1.0]);
        assert_eq!(vals[layout.pattern.position(1, 1).unwrap()], 2.0);
        assert_eq!(vals[layout.pattern.position(0, 1).unwrap()], -1.0);
        let u = [0.0, 0.25, 0.5, 0.75, 1.0];
        let r = layout.element_forces_of(&[&k], &[true], &u);
        assert!((r[0] + 0.25).abs() < 1e-15 && (r[4] - 0.25).abs() < 1e-15 && r[2].abs() < 1e-15);
    }

    /// A chain of 8 springs (dofs 0..=8, dof 0 eliminated) shared by two ranks, elements
    /// 0..4 on rank 0 and 4..8 on rank 1, the dofs 1..=4 owned by rank 0 and 5..=8 by rank
    /// 1: each rank's layout lists its own elements only, yet counts the entries of its rows
    /// coupled by the other rank's elements (dof 4 by element 4, dof 5 by element 3), and
    /// the element forces of the two ranks sum to those of the whole chain (exactly: each
    /// entry is one element's or the sum of two in the same order).
    #[test]
    fn distributed_layouts_list_their_own_elements_and_count_their_rows_whole() {
        let k = Springs(8);
        let mut elim = vec![false; 9];
        elim[0] = true;
        let u: Vec<f64> = (0..9).map(|d| (d * d) as f64 / 7.0).collect();
        let whole = SystemLayout::build(9, 9, &elim, &[&k]).element_forces_of(&[&k], &[true], &u);
        let mut sum = vec![0.0; 9];
        let expected = [(0..4, vec![2, 3, 3, 2], vec![0, 0, 0, 1]), (4..8, vec![2, 3, 3, 2], vec![1, 0, 0, 0])];
        for (rank, (rows, d_nnz, o_nnz)) in expected.into_iter().enumerate() {
            let ownership = Ownership {
                elements: vec![(0..8).map(|e| (e >= 4) == (rank == 1)).collect()],
                dof_rank: (0..9).map(|d| u32::from(d > 4)).collect(),
                rank: rank as u32,
                ranks: 2,
                node_blocks: None,
            };
            let layout = SystemLayout::build_distributed(9, 9, &elim, &[&k], ownership);
            let own: Vec<u32> = (0..4).flat_map(|e| [4 * rank as u32 + e, 4 * rank as u32 + e + 1]).collect();
            assert_eq!(layout.kernel_dofs(0), &own[..], "rank {rank}: its own elements only");
            let dr = layout.distributed.as_ref().unwrap();
            assert_eq!((dr.rows.clone(), dr.d_nnz.clone(), dr.o_nnz.clone()), (rows, d_nnz, o_nnz), "rank {rank}");
            for (s, f) in sum.iter_mut().zip(layout.element_forces_of(&[&k], &[true], &u)) {
                *s += f;
            }
        }
        assert_eq!(sum, whole);
    }
}
