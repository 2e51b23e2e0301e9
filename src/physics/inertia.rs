//! Inertia: the consistent mass matrix with the enriched basis, the element matrices a
//! time-step driver keeps (stiffness and mass of every cell, computed once), and the
//! effective bulk kernel of an implicit step built from them.
//!
//! Entry points: [`MassKernel`] (ρ ∫ ψ_k ψ_l I of every cell, standard, Heaviside and
//! tip functions integrated on the same sub-cells as the stiffness,
//! [`super::xfem::cell_points`]), [`ElementMatrices::compute`], [`EffectiveKernel`]
//! (matrix c_k K_e + c_m M_e, vector f_e + c_m M_e ũ_e − c_p K_e u_e, or f_e alone when
//! the driver adds c_m M ũ − c_p K u as mat-vecs of [`DofMatrices`], K and M assembled
//! once on every dof).
//!
//! Local dofs are basis-major as in [`crate::enrich::basis`]; on a model without cracks
//! the basis is the standard one and the dof lists are those of the plain bulk kernel.
//!
//! [`MassMatrix::Redistributed`] (`[dynamics] mass = "redistributed"`): the mass
//! redistribution method (Khenous, Laborde & Renard, Eur. J. Mech. A/Solids 27 (2008)
//! 918–932; Renard, J. Comput. Appl. Math. 234 (2010) 906–923) for the lips of X-FEM
//! cracks. In a cell cut by one crack whose enriched functions are all Heaviside, the
//! field on side s is Σ_a N_a ũ_a^s with ũ_a^s = u_a + (H_s − H_a) e_a: the node's own
//! displacement where the node lies on side s, a value carried by its Heaviside dof (a
//! "phantom" node, Hansbo & Hansbo) where it does not. The mass of each side's part of the
//! cell is put on the nodes of that side only, by a quadrature at those nodes
//! ([`MassKernel::compute`]): the Heaviside dofs of the cut cells carry no mass, so the lips
//! can be stopped by the contact without an inelastic impact of their mass. Cells with tip
//! functions or cut by more than one crack keep the consistent mass.

use crate::assembly::{Kernel, LocalOut};
use crate::element::CellType;
use crate::enrich::basis::{BasisFn, CellBasis, Evaluator};
use crate::enrich::{side_of, CrackGeometry, Enrichment};
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::cell::RefCell;

use super::side_materials::SideMaterials;
use super::xfem::{cell_points, XfemQuadrature};

/// Per-thread buffers of the mass kernel.
#[derive(Default)]
struct Scratch {
    basis: CellBasis,
    vals: Vec<f64>,
    grads: Vec<[f64; 3]>,
    points: Vec<([f64; 3], f64, Option<i8>)>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Extra quadrature degree of the mass: the product of two shape functions (degree 2 per
/// variable for quads and hexes, total degree 2 on simplices; on the sub-cells of a cut
/// quad or hex, up to twice the parent's total degree).
fn mass_degree(kind: CellType) -> usize {
    match kind {
        CellType::Tri3 | CellType::Tet4 => 2,
        CellType::Quad4 => 4,
        CellType::Hex8 => 6,
    }
}

/// Which mass matrix a dynamic run uses (`[dynamics] mass`; the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MassMatrix {
    /// ρ ∫ ψ_k ψ_l on every cell.
    #[default]
    Consistent,
    /// The consistent mass except on the cells cut by one crack with Heaviside functions
    /// only, where each side's mass is lumped onto the cell's nodes on that side (the
    /// Heaviside dofs get none): the mass redistribution of the module doc.
    Redistributed,
}

impl MassMatrix {
    /// The name of the case key's value (`consistent`, `redistributed`).
    pub fn name(self) -> &'static str {
        match self {
            MassMatrix::Consistent => "consistent",
            MassMatrix::Redistributed => "redistributed",
        }
    }
}

/// The consistent mass of every cell with the enriched basis:
/// M_(k i)(l j) = δ_ij ∫ ρ ψ_k ψ_l, on the quadrature points of the stiffness (sub-cells of
/// cut cells, rich rules near the front), at a degree that integrates ψ_k ψ_l of the
/// standard functions exactly.
pub struct MassKernel<'a> {
    pub mesh: &'a Mesh,
    pub enrichment: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
    pub cell_material: &'a [u32],
    /// Per-side materials of cut cells on a material boundary.
    pub side_materials: &'a SideMaterials,
    /// Mass density of each material.
    pub densities: &'a [f64],
    pub quadrature: XfemQuadrature,
    /// A field g(cell, x) whose projection load ∫ ρ ψ_k g_i is the kernel's vector (for an L2
    /// projection with the mass); `None`: no vector. On a redistributed cell the load is the
    /// same quadrature's: Σ_a w_a ψ_k(x_a) g_i(x_a) over the nodes x_a that carry mass.
    pub field: Option<&'a ProjectedField<'a>>,
    /// Consistent or redistributed ([`MassMatrix`]).
    pub matrix: MassMatrix,
}

/// A vector field per cell and point ([`MassKernel::field`]): `None` outside its cells.
pub type ProjectedField<'a> = dyn Fn(usize, [f64; 3]) -> Option<[f64; 3]> + Sync + 'a;

impl Kernel for MassKernel<'_> {
    fn n_elements(&self) -> usize {
        self.mesh.cells.len()
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        SCRATCH.with(|s| {
            let s = &mut *s.borrow_mut();
            s.basis.build(self.mesh, self.enrichment, e);
            out.extend_from_slice(&s.basis.dofs);
        });
    }

    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let LocalOut { mut matrix, vector } = out;
        let mut vector = vector.filter(|_| self.field.is_some());
        if matrix.is_none() && vector.is_none() {
            return;
        }
        let dim = self.mesh.dim;
        let rho_at = |side: Option<i8>| self.densities[self.side_materials.index(self.cell_material, e, side) as usize];
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        SCRATCH.with(|s| {
            let s = &mut *s.borrow_mut();
            let Scratch { basis, vals, grads, points } = s;
            basis.build(self.mesh, self.enrichment, e);
            let nb = basis.len();
            let n = nb * dim;
            vals.resize(nb, 0.0);
            grads.resize(nb, [0.0; 3]);
            let extra = mass_degree(self.mesh.cells[e].kind);
            cell_points(self.mesh, self.enrichment, self.cracks, e, &self.quadrature, extra, points);
            if self.matrix == MassMatrix::Redistributed {
                if let Some(lumped) = self.redistributed(e, basis, points, vals, grads) {
                    for (a, node, w) in lumped {
                        let g = self.field.and_then(|g| g(e, self.mesh.nodes[node]));
                        for i in 0..dim {
                            let d = a * dim + i;
                            if let Some(m) = matrix.as_deref_mut() {
                                m[d * n + d] += w;
                            }
                            if let (Some(f), Some(gv)) = (vector.as_deref_mut(), g) {
                                f[d] += w * gv[i];
                            }
                        }
                    }
                    return;
                }
            }
            for &(xi, w, side) in points.iter() {
                // Meshes are validated before assembly; a singular point contributes nothing.
                let Ok(pi) = ev.eval(e, basis, &xi, side, vals, grads) else { continue };
                let wd = rho_at(side) * w * pi.det;
                if let (Some(f), Some(g)) = (vector.as_deref_mut(), self.field) {
                    if let Some(gv) = g(e, pi.x) {
                        for k in 0..nb {
                            for i in 0..dim {
                                f[k * dim + i] += wd * vals[k] * gv[i];
                            }
                        }
                    }
                }
                let Some(m) = matrix.as_deref_mut() else { continue };
                for k in 0..nb {
                    let vk = wd * vals[k];
                    if vk == 0.0 {
                        continue;
                    }
                    for l in 0..nb {
                        let v = vk * vals[l];
                        for i in 0..dim {
                            m[(k * dim + i) * n + l * dim + i] += v;
                        }
                    }
                }
            }
        });
    }
}

impl MassKernel<'_> {
    /// The redistributed mass of cell `e` (its basis and quadrature points given) as
    /// (local node, mesh node, mass) of every node that carries mass, or `None` where the
    /// cell keeps the consistent mass: cells not cut by a crack, with tip functions or
    /// Heaviside functions of another crack, or with a side that has mass but no node.
    /// The mass m_s = ∫_{Ω_s} ρ of each side s is shared among the cell's nodes on that
    /// side in proportion to ∫_{Ω_s} ρ N_a (the row sums of the side's consistent mass):
    /// the cell's mass and each side's are kept, the Heaviside dofs (and the nodes of the
    /// other side, in the side's field) get none.
    fn redistributed(
        &self,
        e: usize,
        basis: &CellBasis,
        points: &[([f64; 3], f64, Option<i8>)],
        vals: &mut [f64],
        grads: &mut [[f64; 3]],
    ) -> Option<Vec<(usize, usize, f64)>> {
        let crack = self.enrichment.cell_crack[e]?;
        let only_heaviside = basis.funcs.iter().all(|f| match *f {
            BasisFn::Standard { .. } => true,
            BasisFn::Heaviside { crack: k, .. } => k == crack,
            BasisFn::Tip { .. } => false,
        });
        if !only_heaviside || !basis.funcs.iter().any(|f| matches!(f, BasisFn::Heaviside { .. })) {
            return None;
        }
        let cell = &self.mesh.cells[e];
        let nodes = cell.nodes();
        let nn = nodes.len();
        let levelsets = &self.cracks[crack as usize].levelsets;
        // A cell the crack's front passes through is not separated into two sides.
        if levelsets.lst.as_ref().is_some_and(|lst| nodes.iter().any(|&m| lst[m] >= 0.0)) {
            return None;
        }
        let lsn = &levelsets.lsn;
        let node_side: Vec<usize> = nodes.iter().map(|&m| usize::from(side_of(lsn[m]) > 0)).collect();
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        // Per side (0: −, 1: +): its mass and ∫ ρ N_a over it.
        let mut mass = [0.0; 2];
        let mut moment = vec![[0.0; 2]; nn];
        for &(xi, w, side) in points {
            let Ok(pi) = ev.eval(e, basis, &xi, side, vals, grads) else { continue };
            let rho = self.densities[self.side_materials.index(self.cell_material, e, side) as usize];
            let wd = rho * w * pi.det;
            // The standard functions come first, one per node.
            let s = match side {
                Some(s) => usize::from(s > 0),
                None => usize::from(side_of((0..nn).map(|a| vals[a] * lsn[nodes[a]]).sum()) > 0),
            };
            mass[s] += wd;
            for a in 0..nn {
                moment[a][s] += wd * vals[a];
            }
        }
        let mut out = Vec::with_capacity(nn);
        for s in 0..2 {
            let on_side: Vec<usize> = (0..nn).filter(|&a| node_side[a] == s).collect();
            if mass[s] == 0.0 {
                continue;
            }
            if on_side.is_empty() {
                return None;
            }
            let total: f64 = on_side.iter().map(|&a| moment[a][s]).sum();
            for &a in &on_side {
                let share = if total > 0.0 { moment[a][s] / total } else { 1.0 / on_side.len() as f64 };
                out.push((a, nodes[a], mass[s] * share));
            }
        }
        Some(out)
    }
}

/// The stiffness and mass matrices of every cell, with their dofs, computed once (linear
/// elasticity: they do not change from step to step).
pub struct ElementMatrices {
    /// Start of each cell's dofs in `dofs` (and of its `n × n` block in `k` and `m` at
    /// `block_offsets`).
    offsets: Vec<usize>,
    block_offsets: Vec<usize>,
    dofs: Vec<u32>,
    k: Vec<f64>,
    m: Vec<f64>,
}

impl ElementMatrices {
    /// Computes the element matrices of `stiffness` (its matrix part) and `mass`, which must
    /// list the same dofs for every element (panics otherwise: a programming error).
    pub fn compute(stiffness: &dyn Kernel, mass: &dyn Kernel) -> ElementMatrices {
        Self::compute_held(stiffness, mass, &|_| true)
    }

    /// [`Self::compute`] holding the matrices of the elements with `held(e)` only (a rank's
    /// own cells under distributed assembly): the others keep their dofs and have empty
    /// blocks, which [`Self::energies`], [`Self::add_products`] and
    /// [`Self::mass_diagonal`] skip (their results are then this rank's share, summed over
    /// the ranks by the caller) and which [`EffectiveKernel`] must not be asked for.
    pub fn compute_held(
        stiffness: &dyn Kernel,
        mass: &dyn Kernel,
        held: &(dyn Fn(usize) -> bool + Sync),
    ) -> ElementMatrices {
        let ne = stiffness.n_elements();
        assert_eq!(ne, mass.n_elements(), "stiffness and mass over the same cells");
        let per: Vec<(Vec<u32>, Vec<f64>, Vec<f64>)> = (0..ne)
            .into_par_iter()
            .map(|e| {
                let mut dofs = vec![];
                stiffness.dofs(e, &mut dofs);
                if !held(e) {
                    return (dofs, vec![], vec![]);
                }
                let mut check = vec![];
                mass.dofs(e, &mut check);
                assert_eq!(dofs, check, "stiffness and mass list the same dofs");
                let n = dofs.len();
                let (mut k, mut m) = (vec![0.0; n * n], vec![0.0; n * n]);
                stiffness.compute(e, &dofs, LocalOut { matrix: Some(&mut k), vector: None });
                mass.compute(e, &dofs, LocalOut { matrix: Some(&mut m), vector: None });
                (dofs, k, m)
            })
            .collect();
        let mut em = ElementMatrices { offsets: vec![0], block_offsets: vec![0], dofs: vec![], k: vec![], m: vec![] };
        for (d, k, m) in per {
            em.dofs.extend_from_slice(&d);
            em.k.extend_from_slice(&k);
            em.m.extend_from_slice(&m);
            em.offsets.push(em.dofs.len());
            em.block_offsets.push(em.k.len());
        }
        em
    }

    pub fn n_elements(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The dofs of element `e`.
    pub fn dofs(&self, e: usize) -> &[u32] {
        &self.dofs[self.offsets[e]..self.offsets[e + 1]]
    }

    /// Whether this process holds element `e`'s matrices ([`Self::compute_held`]).
    pub fn holds(&self, e: usize) -> bool {
        self.block_offsets[e + 1] > self.block_offsets[e]
    }

    /// The stiffness and mass blocks (row-major) of element `e`.
    pub fn blocks(&self, e: usize) -> (&[f64], &[f64]) {
        let r = self.block_offsets[e]..self.block_offsets[e + 1];
        (&self.k[r.clone()], &self.m[r])
    }

    /// ½ xᵀ K x and ½ yᵀ M y summed over the elements (strain and kinetic energy of a
    /// displacement `x` and a velocity `y`, full dof vectors).
    pub fn energies(&self, x: &[f64], y: &[f64]) -> (f64, f64) {
        (0..self.n_elements())
            .into_par_iter()
            .map(|e| {
                let dofs = self.dofs(e);
                let (k, m) = self.blocks(e);
                if k.is_empty() {
                    return (0.0, 0.0); // not held here
                }
                let n = dofs.len();
                let (mut sk, mut sm) = (0.0, 0.0);
                for a in 0..n {
                    let (xa, ya) = (x[dofs[a] as usize], y[dofs[a] as usize]);
                    let (mut kx, mut my) = (0.0, 0.0);
                    for b in 0..n {
                        kx += k[a * n + b] * x[dofs[b] as usize];
                        my += m[a * n + b] * y[dofs[b] as usize];
                    }
                    sk += xa * kx;
                    sm += ya * my;
                }
                (0.5 * sk, 0.5 * sm)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1))
    }

    /// The diagonal of the mass matrix on `n` dofs (every dof of the elements below `n`):
    /// zero on the dofs that carry no mass ([`MassMatrix::Redistributed`]).
    pub fn mass_diagonal(&self, n: usize) -> Vec<f64> {
        let mut diag = vec![0.0; n];
        for e in 0..self.n_elements() {
            let dofs = self.dofs(e);
            let (_, m) = self.blocks(e);
            if m.is_empty() {
                continue; // not held here
            }
            let nd = dofs.len();
            for (a, &d) in dofs.iter().enumerate() {
                diag[d as usize] += m[a * nd + a];
            }
        }
        diag
    }

    /// Accumulates `ck K x + cm M y` into the full dof vector `out`.
    pub fn add_products(&self, ck: f64, x: &[f64], cm: f64, y: &[f64], out: &mut [f64]) {
        for e in 0..self.n_elements() {
            let dofs = self.dofs(e);
            let (k, m) = self.blocks(e);
            if k.is_empty() {
                continue; // not held here
            }
            let n = dofs.len();
            for a in 0..n {
                let mut v = 0.0;
                for b in 0..n {
                    let d = dofs[b] as usize;
                    v += ck * k[a * n + b] * x[d] + cm * m[a * n + b] * y[d];
                }
                out[dofs[a] as usize] += v;
            }
        }
    }
}

/// The global stiffness and mass matrices on every dof of the model's dof map (rows of
/// dofs outside the cells empty), assembled once from [`ElementMatrices`] on one CSR
/// pattern: a time step's products K x and M y are two sparse mat-vecs instead of a pass
/// over the elements.
pub struct DofMatrices {
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    k: Vec<f64>,
    m: Vec<f64>,
}

impl DofMatrices {
    /// Assembles `em` on `n` dofs (every dof of `em` below `n`).
    pub fn assemble(em: &ElementMatrices, n: usize) -> DofMatrices {
        // The pattern: the sorted, distinct columns of every row.
        let mut count = vec![0usize; n + 1];
        for e in 0..em.n_elements() {
            let dofs = em.dofs(e);
            for &a in dofs {
                count[a as usize + 1] += dofs.len();
            }
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut raw = vec![0u32; count[n]];
        let mut fill = count.clone();
        for e in 0..em.n_elements() {
            let dofs = em.dofs(e);
            for &a in dofs {
                let f = &mut fill[a as usize];
                raw[*f..*f + dofs.len()].copy_from_slice(dofs);
                *f += dofs.len();
            }
        }
        let rows: Vec<Vec<u32>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut r = raw[count[i]..count[i + 1]].to_vec();
                r.sort_unstable();
                r.dedup();
                r
            })
            .collect();
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        let mut col = Vec::with_capacity(rows.iter().map(Vec::len).sum());
        for r in rows {
            col.extend_from_slice(&r);
            row_ptr.push(col.len());
        }
        let (mut k, mut m) = (vec![0.0; col.len()], vec![0.0; col.len()]);
        for e in 0..em.n_elements() {
            let dofs = em.dofs(e);
            let (ke, me) = em.blocks(e);
            let nd = dofs.len();
            for (a, &da) in dofs.iter().enumerate() {
                let r = row_ptr[da as usize]..row_ptr[da as usize + 1];
                let cols = &col[r.clone()];
                for (b, &db) in dofs.iter().enumerate() {
                    let at = r.start + cols.binary_search(&db).expect("a column of the pattern");
                    k[at] += ke[a * nd + b];
                    m[at] += me[a * nd + b];
                }
            }
        }
        DofMatrices { row_ptr, col, k, m }
    }

    /// ½ xᵀ K x and ½ yᵀ M y (strain and kinetic energy of a displacement `x` and a
    /// velocity `y`, full dof vectors), in one pass over the rows.
    pub fn energies(&self, x: &[f64], y: &[f64]) -> (f64, f64) {
        let (sk, sm) = (0..self.row_ptr.len() - 1)
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| {
                let r = self.row_ptr[i]..self.row_ptr[i + 1];
                let (mut kx, mut my) = (0.0, 0.0);
                for ((k, m), &j) in self.k[r.clone()].iter().zip(&self.m[r.clone()]).zip(&self.col[r]) {
                    kx += k * x[j as usize];
                    my += m * y[j as usize];
                }
                (x[i] * kx, y[i] * my)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
        (0.5 * sk, 0.5 * sm)
    }

    /// [`Self::energies`] of `x` and `y` and, in the same pass over the rows,
    /// [`Self::products`] `out = ck K x + cm M z` (the next time step's products, whose
    /// K x is the energy's: one read of K and M instead of two; the same sums, in the same
    /// order, as the two separate calls).
    pub fn energies_and_products(
        &self,
        x: &[f64],
        y: &[f64],
        ck: f64,
        cm: f64,
        z: &[f64],
        out: &mut [f64],
    ) -> (f64, f64) {
        let (sk, sm) = out
            .par_iter_mut()
            .enumerate()
            .with_min_len(4096)
            .map(|(i, o)| {
                let r = self.row_ptr[i]..self.row_ptr[i + 1];
                let (mut kx, mut my) = (0.0, 0.0);
                for ((k, m), &j) in self.k[r.clone()].iter().zip(&self.m[r.clone()]).zip(&self.col[r.clone()]) {
                    kx += k * x[j as usize];
                    my += m * y[j as usize];
                }
                let mut v = 0.0;
                if ck != 0.0 {
                    let kx: f64 =
                        self.k[r.clone()].iter().zip(&self.col[r.clone()]).map(|(a, &j)| a * x[j as usize]).sum();
                    v += ck * kx;
                }
                if cm != 0.0 {
                    let mz: f64 = self.m[r.clone()].iter().zip(&self.col[r]).map(|(a, &j)| a * z[j as usize]).sum();
                    v += cm * mz;
                }
                *o = v;
                (x[i] * kx, y[i] * my)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
        (0.5 * sk, 0.5 * sm)
    }

    /// `out = ck K x + cm M y` (full dof vectors; a zero coefficient skips its matrix).
    pub fn products(&self, ck: f64, x: &[f64], cm: f64, y: &[f64], out: &mut [f64]) {
        out.par_iter_mut().enumerate().with_min_len(4096).for_each(|(i, o)| {
            let r = self.row_ptr[i]..self.row_ptr[i + 1];
            let cols = &self.col[r.clone()];
            let mut v = 0.0;
            if ck != 0.0 {
                let kx: f64 = self.k[r.clone()].iter().zip(cols).map(|(a, &j)| a * x[j as usize]).sum();
                v += ck * kx;
            }
            if cm != 0.0 {
                let my: f64 = self.m[r].iter().zip(cols).map(|(a, &j)| a * y[j as usize]).sum();
                v += cm * my;
            }
            *o = v;
        });
    }
}

/// The bulk kernel of an implicit time step: matrix `c_k K_e + c_m M_e`, vector the body
/// forces of `loads` (its vector part) plus, with `element_products`,
/// `c_m M_e ũ_e − c_p K_e u_e` (the inertia predictor and, for HHT-α, the stiffness at the
/// start of the step; without, the caller adds them, e.g. [`DofMatrices::products`]). `ũ`
/// and `u` are full dof vectors.
pub struct EffectiveKernel<'a> {
    pub matrices: &'a ElementMatrices,
    /// The bulk kernel whose vector part gives the body forces at the step's load time.
    pub loads: Box<dyn Kernel + 'a>,
    pub c_k: f64,
    pub c_m: f64,
    pub c_p: f64,
    pub predictor: &'a [f64],
    pub previous: &'a [f64],
    /// The vector part includes `c_m M_e ũ_e − c_p K_e u_e`.
    pub element_products: bool,
}

impl Kernel for EffectiveKernel<'_> {
    fn n_elements(&self) -> usize {
        self.matrices.n_elements()
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        out.extend_from_slice(self.matrices.dofs(e));
    }

    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>) {
        let (k, m) = self.matrices.blocks(e);
        let n = dofs.len();
        assert!(k.len() == n * n, "the effective kernel asked for element {e}, whose matrices this rank does not hold");
        let LocalOut { matrix, vector } = out;
        if let Some(a) = matrix {
            for ((a, k), m) in a.iter_mut().zip(k).zip(m) {
                *a = self.c_k * k + self.c_m * m;
            }
        }
        if let Some(f) = vector {
            self.loads.compute(e, dofs, LocalOut { matrix: None, vector: Some(&mut *f) });
            if !self.element_products {
                return;
            }
            for a in 0..n {
                let mut v = 0.0;
                for b in 0..n {
                    let d = dofs[b] as usize;
                    v += self.c_m * m[a * n + b] * self.predictor[d] - self.c_p * k[a * n + b] * self.previous[d];
                }
                f[a] += v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::Kernel;
    use crate::cut::{cut_crack, CutOptions};
    use crate::enrich::{enrich, EnrichOptions, TipEnrichment};
    use crate::levelset::NodalLevelSets;
    use crate::mesh::generate;

    /// xᵀ M x summed element by element.
    fn quadratic_form(k: &MassKernel<'_>, x: &[f64]) -> f64 {
        let mut total = 0.0;
        for e in 0..k.n_elements() {
            let mut dofs = vec![];
            k.dofs(e, &mut dofs);
            let n = dofs.len();
            let mut m = vec![0.0; n * n];
            k.compute(e, &dofs, LocalOut { matrix: Some(&mut m), vector: None });
            for a in 0..n {
                for b in 0..n {
                    total += x[dofs[a] as usize] * m[a * n + b] * x[dofs[b] as usize];
                }
            }
        }
        total
    }

    /// A straight interface φ = n·x − offset through `mesh` (no tips): its nodal level set,
    /// the crack geometry and the Heaviside enrichment.
    fn straight_interface(mesh: &Mesh, normal: [f64; 2], offset: f64) -> (Vec<f64>, Vec<CrackGeometry>, Enrichment) {
        let lsn: Vec<f64> = mesh.nodes.iter().map(|p| normal[0] * p[0] + normal[1] * p[1] - offset).collect();
        let ls = NodalLevelSets { lsn: lsn.clone(), lst: None };
        let cut = cut_crack(mesh, &ls, &CutOptions::default()).unwrap();
        let cracks = vec![CrackGeometry { name: "i".into(), levelsets: ls, cut }];
        let enr =
            enrich(mesh, &cracks, &EnrichOptions { tip: vec![TipEnrichment::Topological], min_side_fraction: 0.0 })
                .unwrap();
        (lsn, cracks, enr)
    }

    /// uᵀ M u of two translations by `c` on the enriched basis of `k`: the whole body's
    /// (u_i = c at every node) and the side φ > 0's (u_i = c [φ_i > 0], a_i = c/2 on the
    /// shifted Heaviside dofs), with `lsn` the nodal level set.
    fn translation_masses(k: &MassKernel, lsn: &[f64], c: [f64; 2]) -> (f64, f64) {
        let (mesh, enr) = (k.mesh, k.enrichment);
        let n_total = enr.dofs.n_total();
        let mut u = vec![0.0; n_total];
        for n in 0..mesh.n_nodes() {
            u[2 * n..2 * n + 2].copy_from_slice(&c);
        }
        let total = quadratic_form(k, &u);
        let mut u = vec![0.0; n_total];
        for n in 0..mesh.n_nodes() {
            if lsn[n] > 0.0 {
                u[2 * n..2 * n + 2].copy_from_slice(&c);
            }
            for item in enr.node_items(n) {
                let d = item.first_dof as usize;
                u[d] = 0.5 * c[0];
                u[d + 1] = 0.5 * c[1];
            }
        }
        (total, quadratic_form(k, &u))
    }

    /// Rigid translation of a 2 × 1 rectangle (ρ = 3), plain and cut through by a straight
    /// line x = 0.77 (Heaviside cells) or a slanted one: uᵀ M u = ρ V |c|² exactly (the
    /// shape functions are a partition of unity). Per-side translation c·[φ > 0], on the
    /// enriched basis u_i = c [φ_i > 0], a_i = c/2 (shifted Heaviside): uᵀ M u = ρ V₊ |c|²,
    /// which only holds when the enriched mass is integrated on the sub-cells.
    #[test]
    fn mass_sums_to_the_body_mass_also_on_cut_cells() {
        for kind in [CellType::Quad4, CellType::Tri3] {
            let mesh = generate::rectangle(kind, [0.0, 0.0], [2.0, 1.0], [9, 5]).unwrap();
            let rho = 3.0;
            let c = [0.7, -1.3];
            let c2 = c[0] * c[0] + c[1] * c[1];
            // (normal, offset): φ = n·x − offset; the + side volume.
            for (normal, offset, v_plus) in [([1.0, 0.0], 0.77, (2.0 - 0.77) * 1.0), ([1.0, 0.25], 1.0, -1.0)] {
                let (lsn, cracks, enr) = straight_interface(&mesh, normal, offset);
                let k = MassKernel {
                    mesh: &mesh,
                    enrichment: &enr,
                    cracks: &cracks,
                    cell_material: &vec![0; mesh.n_cells()],
                    side_materials: &SideMaterials::none(),
                    densities: &[rho],
                    quadrature: XfemQuadrature::default(),
                    field: None,
                    matrix: MassMatrix::Consistent,
                };
                let (total, side) = translation_masses(&k, &lsn, c);
                assert!((total - rho * 2.0 * c2).abs() < 1e-12 * rho * 2.0 * c2, "{kind:?}: {total}");
                assert!(enr.n_heaviside_nodes > 0);
                // The + side's area: exact for the vertical line; for the slanted one, the
                // polygon x ≥ 1 − 0.25 y in [0, 2] × [0, 1].
                let v_plus = if v_plus > 0.0 { v_plus } else { 2.0 - (1.0 - 0.125) };
                let want = rho * v_plus * c2;
                assert!((side - want).abs() < 1e-12 * want, "{kind:?} {normal:?}: {side} against {want}");
            }
        }
    }

    /// The global matrices (`DofMatrices`) against the element matrices they come from, on
    /// the 2 × 1 rectangle of 9 × 5 quad4 cut by the slanted line x + 0.25 y = 1 (Heaviside
    /// cells): the products K x + M y and the energies ½ xᵀ K x, ½ yᵀ M y of smooth
    /// non-polynomial vectors agree with the element-by-element sums
    /// (`ElementMatrices::add_products`, `ElementMatrices::energies`) to 1e-13 relative
    /// (round-off: only the summation order differs); and ½ cᵀ M c of a rigid translation c
    /// is ½ ρ V |c|² (ρ = 3, V = 2, the partition of unity) to 1e-12.
    #[test]
    fn dof_matrices_match_the_element_matrices_and_the_body_mass() {
        let mesh = generate::rectangle(CellType::Quad4, [0.0, 0.0], [2.0, 1.0], [9, 5]).unwrap();
        let lsn: Vec<f64> = mesh.nodes.iter().map(|p| p[0] + 0.25 * p[1] - 1.0).collect();
        let ls = NodalLevelSets { lsn, lst: None };
        let cut = cut_crack(&mesh, &ls, &CutOptions::default()).unwrap();
        let cracks = vec![CrackGeometry { name: "i".into(), levelsets: ls, cut }];
        let enr =
            enrich(&mesh, &cracks, &EnrichOptions { tip: vec![TipEnrichment::Topological], min_side_fraction: 0.0 })
                .unwrap();
        let cell_material = vec![0; mesh.n_cells()];
        let side = SideMaterials::none();
        // Two different matrices on the same dofs: "K" the mass of ρ = 1, "M" of ρ = 3.
        let (r1, r3) = ([1.0], [3.0]);
        let k1 = MassKernel {
            mesh: &mesh,
            enrichment: &enr,
            cracks: &cracks,
            cell_material: &cell_material,
            side_materials: &side,
            densities: &r1,
            quadrature: XfemQuadrature::default(),
            field: None,
            matrix: MassMatrix::Consistent,
        };
        let k3 = MassKernel { densities: &r3, quadrature: XfemQuadrature::default(), field: None, ..k1 };
        let em = ElementMatrices::compute(&k1, &k3);
        let n = enr.dofs.n_total();
        let dm = DofMatrices::assemble(&em, n);
        let x: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let y: Vec<f64> = (0..n).map(|i| 1.0 + (0.61 * i as f64).cos()).collect();
        let (ck, cm) = (0.7, -2.5);
        let mut want = vec![0.0; n];
        em.add_products(ck, &x, cm, &y, &mut want);
        let mut got = vec![0.0; n];
        dm.products(ck, &x, cm, &y, &mut got);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!((g - w).abs() <= 1e-13 * scale, "dof {i}: {g} against {w}");
        }
        let (sk, sm) = dm.energies(&x, &y);
        let (wk, wm) = em.energies(&x, &y);
        assert!((sk - wk).abs() <= 1e-13 * wk.abs() && (sm - wm).abs() <= 1e-13 * wm.abs(), "{sk} {wk} {sm} {wm}");
        let c = [0.7, -1.3];
        let mut u = vec![0.0; n];
        for node in 0..mesh.n_nodes() {
            u[2 * node..2 * node + 2].copy_from_slice(&c);
        }
        let (_, kinetic) = dm.energies(&u, &u);
        let exact = 0.5 * 3.0 * 2.0 * (c[0] * c[0] + c[1] * c[1]);
        assert!((kinetic - exact).abs() <= 1e-12 * exact, "{kinetic} against {exact}");
    }

    /// The redistributed mass (`MassMatrix::Redistributed`) on the 2 × 1 rectangle of
    /// 9 × 5 quad4 and tri3 (ρ = 3) cut by the vertical line x = 0.77 and the slanted line
    /// x + 0.25 y = 1 (Heaviside cells only): the body's mass and each side's are those of
    /// the consistent mass (uᵀ M u = ρ V |c|² for a rigid translation c, ρ V₊ |c|² for the
    /// translation of the side φ > 0 on the enriched basis) to 1e-12; every Heaviside dof
    /// carries no mass (its diagonal entry of M is exactly zero, hence its row, M being
    /// positive semi-definite); the matrix of an uncut cell is the consistent one bit for
    /// bit. Source of the method: Khenous, Laborde & Renard,
    /// Eur. J. Mech. A/Solids 27 (2008) 918–932 (the contact unknowns carry no mass, total
    /// mass kept).
    #[test]
    fn redistributed_mass_keeps_each_sides_mass_and_leaves_the_heaviside_dofs_massless() {
        for kind in [CellType::Quad4, CellType::Tri3] {
            let mesh = generate::rectangle(kind, [0.0, 0.0], [2.0, 1.0], [9, 5]).unwrap();
            let rho = 3.0;
            let c = [0.7, -1.3];
            let c2 = c[0] * c[0] + c[1] * c[1];
            for (normal, offset, v_plus) in [([1.0, 0.0], 0.77, 2.0 - 0.77), ([1.0, 0.25], 1.0, 2.0 - 0.875)] {
                let (lsn, cracks, enr) = straight_interface(&mesh, normal, offset);
                let consistent = MassKernel {
                    mesh: &mesh,
                    enrichment: &enr,
                    cracks: &cracks,
                    cell_material: &vec![0; mesh.n_cells()],
                    side_materials: &SideMaterials::none(),
                    densities: &[rho],
                    quadrature: XfemQuadrature::default(),
                    field: None,
                    matrix: MassMatrix::Consistent,
                };
                let k = MassKernel { matrix: MassMatrix::Redistributed, ..consistent };
                let n_total = enr.dofs.n_total();
                let (total, side) = translation_masses(&k, &lsn, c);
                assert!((total - rho * 2.0 * c2).abs() < 1e-12 * rho * 2.0 * c2, "{kind:?}: {total}");
                let want = rho * v_plus * c2;
                assert!((side - want).abs() < 1e-12 * want, "{kind:?} {normal:?}: {side} against {want}");
                // Every Heaviside dof is massless; uncut cells keep the consistent matrix.
                let em = ElementMatrices::compute(&k, &k);
                let diag = em.mass_diagonal(n_total);
                let enriched: Vec<usize> = (0..mesh.n_nodes())
                    .flat_map(|n| enr.node_items(n).iter().map(|i| i.first_dof as usize).collect::<Vec<_>>())
                    .collect();
                assert!(!enriched.is_empty());
                for &d in &enriched {
                    assert_eq!(diag[d], 0.0, "{kind:?}: Heaviside dof {d} has mass");
                    assert_eq!(diag[d + 1], 0.0, "{kind:?}: Heaviside dof {} has mass", d + 1);
                }
                let plain = ElementMatrices::compute(&consistent, &consistent);
                let mut cut_cells = 0;
                for e in 0..mesh.n_cells() {
                    if enr.cell_crack[e].is_some() {
                        cut_cells += 1;
                        continue;
                    }
                    assert_eq!(em.blocks(e).1, plain.blocks(e).1, "{kind:?}: uncut cell {e}");
                }
                assert!(cut_cells > 0);
            }
        }
    }
}
