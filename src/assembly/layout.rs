//! The layout of a linear system: equation numbers, the sparsity pattern, element dof
//! lists and the element colouring; and the parallel assembly into that layout.
//!
//! Entry points: [`SystemLayout::build`] (once per pattern), [`SystemLayout::assemble`]
//! (each refill), [`SystemLayout::element_forces_of`] (reactions and residuals).

use super::{CscPattern, Kernel, LocalOut, NO_EQ};
use rayon::prelude::*;

/// Element dof lists of one kernel, back to back.
#[derive(Debug, Clone, Default)]
struct DofLists {
    offsets: Vec<usize>,
    dofs: Vec<u32>,
}

impl DofLists {
    fn get(&self, e: usize) -> &[u32] {
        &self.dofs[self.offsets[e]..self.offsets[e + 1]]
    }
}

/// One element reference: (kernel index, element index).
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
    /// Distributed assembly (PETSc backend): per kernel, whether this rank assembles each
    /// element. The pattern, positions and value array then hold only the entries of the
    /// elements assembled here (global equation numbers), and [`Self::assemble_kernels`]
    /// adds only their contributions (partial sums, completed across the ranks by the
    /// backend). `None`: every element (the default).
    owned: Option<Vec<Vec<bool>>>,
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
        Self::build_owned(n_dofs, n_primal_dofs, eliminated, kernels, None)
    }

    /// [`Self::build`] for distributed assembly: with `owned` (per kernel, per element),
    /// the pattern and positions cover only the elements marked (see the `owned` field);
    /// the element lists and colours keep every element (reactions and residuals are
    /// computed on the replicated model).
    pub fn build_owned(
        n_dofs: usize,
        n_primal_dofs: usize,
        eliminated: &[bool],
        kernels: &[&dyn Kernel],
        owned: Option<Vec<Vec<bool>>>,
    ) -> SystemLayout {
        let is_owned = |k: usize, e: usize| owned.as_ref().is_none_or(|o| o[k][e]);
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
        let lists: Vec<DofLists> = kernels
            .iter()
            .map(|k| {
                let mut l = DofLists { offsets: Vec::with_capacity(k.n_elements() + 1), dofs: vec![] };
                l.offsets.push(0);
                for e in 0..k.n_elements() {
                    k.dofs(e, &mut l.dofs);
                    l.offsets.push(l.dofs.len());
                }
                l
            })
            .collect();
        let max_local = lists.iter().flat_map(|l| l.offsets.windows(2).map(|w| w[1] - w[0])).max().unwrap_or(0);

        // Pattern, column by column: the elements touching each equation (compressed),
        // then for each column the sorted, unique equations of those elements. Parallel
        // over columns, with small sorts instead of one global sort of every pair.
        let mut touch_ptr = vec![0usize; n_eq + 1];
        for (ki, (k, l)) in kernels.iter().zip(&lists).enumerate() {
            if !k.has_matrix() {
                continue;
            }
            for e in 0..l.offsets.len() - 1 {
                if !is_owned(ki, e) {
                    continue;
                }
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
                if !is_owned(k, e) {
                    continue;
                }
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
            .enumerate()
            .map(|(ki, (k, l))| {
                let ne = k.n_elements();
                let mut off = Vec::with_capacity(ne + 1);
                off.push(0usize);
                for e in 0..ne {
                    let m = l.offsets[e + 1] - l.offsets[e];
                    off.push(off[e] + if k.has_matrix() && is_owned(ki, e) { m * m } else { 0 });
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
                if out.len() != m * m {
                    // An element assembled by another rank.
                    return;
                }
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
            owned,
        }
    }

    /// Whether this layout assembles only this rank's elements (see [`Self::build_owned`]).
    pub fn is_distributed(&self) -> bool {
        self.owned.is_some()
    }

    /// The dofs of every element of kernel `k` (in the order given to
    /// [`SystemLayout::build`]), element after element, repeats included.
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
            items.extend(color.iter().filter(|&&(k, e)| {
                include[k as usize] && self.owned.as_ref().is_none_or(|o| o[k as usize][e as usize])
            }));
            if items.is_empty() {
                continue;
            }
            items.par_iter().with_min_len(8).for_each_init(
                || (vec![0.0; n * n], vec![0.0; n], Vec::<u32>::with_capacity(n)),
                |(ke, fe, eqs), &&(k, e)| {
                    let kernel = kernels[k as usize];
                    let dofs = self.lists[k as usize].get(e as usize);
                    let m = dofs.len();
                    let need_matrix = kernel.has_matrix()
                        && (want_m || (want_f && dofs.iter().any(|&d| self.eq_of_dof[d as usize] == NO_EQ)));
                    let ke = &mut ke[..m * m];
                    let fe = &mut fe[..m];
                    ke.iter_mut().for_each(|v| *v = 0.0);
                    fe.iter_mut().for_each(|v| *v = 0.0);
                    kernel.compute(
                        e as usize,
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

    /// Element forces gathered per dof: `r[d] = Σ_e (K_e u_e − f_e)[d]` over every dof,
    /// eliminated or not, for the full dof vector `u`, summing only the kernels with
    /// `include[k]`. On constrained dofs this is the reaction; on free dofs the residual.
    pub fn element_forces_of(&self, kernels: &[&dyn Kernel], include: &[bool], u: &[f64]) -> Vec<f64> {
        self.element_forces_touching(kernels, include, None, u)
    }

    /// Like [`Self::element_forces_of`], computing only the elements that have a dof with
    /// `touching[d]` (e.g. the constrained dofs, for reactions); other entries stay 0 or
    /// are partial.
    pub fn element_forces_touching(
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
                        let dofs = self.lists[k as usize].get(e as usize);
                        let m = dofs.len();
                        let ke = &mut ke[..m * m];
                        let fe = &mut fe[..m];
                        ke.iter_mut().for_each(|v| *v = 0.0);
                        fe.iter_mut().for_each(|v| *v = 0.0);
                        let hm = kernel.has_matrix() && kernel.is_linear();
                        kernel.compute(
                            e as usize,
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
}
