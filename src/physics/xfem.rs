//! X-FEM kernels: the bulk stiffness and body forces with the enriched basis, integrated
//! on the sub-cells of cut cells, and pressure on the crack faces.
//!
//! Entry points: [`XfemBulkKernel`], [`CrackPressureKernel`].
//!
//! Quadrature: cut and front cells are integrated on their sub-cells (almost-polar rules
//! on the sub-cells touching the front, from [`crate::cut::subcell_quadrature`]);
//! uncut cells with tip-enriched nodes use a parent rule of degree `tip_degree`; all
//! other cells the standard rule.

use super::elasticity::{add_isotropic_stiffness, mirror_lower, Vector};
use super::material::{Analysis, Isotropic};
use crate::assembly::{Kernel, LocalOut};
use crate::cut::{facet_quadrature, subcell_quadrature, CutOptions};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::enrich::{CrackGeometry, Enrichment};
use crate::formula::Scalar;
use crate::mesh::Mesh;
use std::cell::RefCell;

/// Quadrature options of the enriched kernels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XfemQuadrature {
    /// Gauss degree on sub-cells of cut cells without tip enrichment.
    pub subcell_degree: usize,
    /// Gauss degree on cells and sub-cells carrying tip enrichment (away from the front).
    pub tip_degree: usize,
    /// Degree of the almost-polar rule on sub-cells touching the front.
    pub front_degree: usize,
}

impl Default for XfemQuadrature {
    fn default() -> Self {
        XfemQuadrature { subcell_degree: 2, tip_degree: 6, front_degree: 8 }
    }
}

/// Per-thread buffers of the enriched kernels.
#[derive(Default)]
struct Scratch {
    basis: CellBasis,
    vals: Vec<f64>,
    grads: Vec<[f64; 3]>,
    vals_minus: Vec<f64>,
    grads_minus: Vec<[f64; 3]>,
    points: Vec<([f64; 3], f64, Option<i8>)>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The quadrature points `(ξ, weight in the reference space, side)` of a cell with the
/// enriched basis: sub-cells of cut cells, a rich rule for tip-enriched cells.
pub fn cell_points(
    mesh: &Mesh,
    enr: &Enrichment,
    cracks: &[CrackGeometry],
    c: usize,
    q: &XfemQuadrature,
    extra_degree: usize,
    out: &mut Vec<([f64; 3], f64, Option<i8>)>,
) {
    out.clear();
    let kind = mesh.cells[c].kind;
    let tip = enr.cell_has_tip(mesh, c);
    if let Some(k) = enr.cell_crack[c] {
        let cut = &cracks[k as usize].cut;
        if let Some(cc) = cut.cell_cut(c) {
            let opts = CutOptions {
                subcell_degree: (if tip { q.tip_degree } else { q.subcell_degree }).max(extra_degree),
                front_degree: q.front_degree,
            };
            for sc in &cc.subcells {
                let rule = subcell_quadrature(sc, mesh.dim, &opts);
                out.extend(rule.points.iter().zip(&rule.weights).map(|(p, w)| (*p, *w, Some(sc.side))));
            }
            return;
        }
    }
    let degree = if tip {
        q.tip_degree
    } else if kind.is_simplex() {
        1
    } else {
        3
    }
    .max(extra_degree);
    let rule = kind.cached_quadrature(degree);
    out.extend(rule.points.iter().zip(&rule.weights).map(|(p, w)| (*p, *w, None)));
}

/// Bulk stiffness and body forces with the enriched basis, for every cell.
pub struct XfemBulkKernel<'a> {
    pub mesh: &'a Mesh,
    pub enrichment: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
    pub analysis: Analysis,
    pub cell_material: &'a [u32],
    pub materials: &'a [Isotropic],
    pub cell_body_force: &'a [Option<u32>],
    pub body_forces: &'a [Vector],
    pub quadrature: XfemQuadrature,
    pub t: f64,
}

impl Kernel for XfemBulkKernel<'_> {
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
        let dim = self.mesh.dim;
        let mat = self.materials[self.cell_material[e] as usize];
        let (lam, mu) = (mat.lambda_in_plane(self.analysis), mat.mu());
        let bf =
            self.cell_body_force[e].map(|i| &self.body_forces[i as usize]).filter(|b| b.iter().any(|s| !s.is_zero()));
        let LocalOut { mut matrix, vector } = out;
        let mut vector = if bf.is_some() { vector } else { None };
        if matrix.is_none() && vector.is_none() {
            return;
        }
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        SCRATCH.with(|s| {
            let s = &mut *s.borrow_mut();
            let Scratch { basis, vals, grads, points, .. } = s;
            basis.build(self.mesh, self.enrichment, e);
            let nb = basis.len();
            vals.resize(nb, 0.0);
            grads.resize(nb, [0.0; 3]);
            let extra = if bf.is_some() && vector.is_some() { 2 } else { 0 };
            cell_points(self.mesh, self.enrichment, self.cracks, e, &self.quadrature, extra, points);
            for &(xi, w, side) in points.iter() {
                // Meshes are validated before assembly; a singular point contributes nothing.
                let Ok(pi) = ev.eval(e, basis, &xi, side, vals, grads) else { continue };
                let wd = w * pi.det;
                if let Some(k) = matrix.as_deref_mut() {
                    add_isotropic_stiffness(k, grads, dim, lam, mu, wd);
                }
                if let (Some(f), Some(b)) = (vector.as_deref_mut(), bf) {
                    for i in 0..dim {
                        let bi = b[i].eval_load(pi.x, self.t);
                        if bi != 0.0 {
                            for k in 0..nb {
                                f[k * dim + i] += wd * vals[k] * bi;
                            }
                        }
                    }
                }
            }
            if let Some(k) = matrix {
                mirror_lower(k, nb * dim);
            }
        });
    }
}

/// A pressure on both faces of a crack: it pushes the lips apart (t = −p n_out on each
/// lip), so its virtual work is ∫ p n · [[δu]] over the crack.
pub struct CrackPressureKernel<'a> {
    pub mesh: &'a Mesh,
    pub enrichment: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
    /// (crack index, facet index) of every loaded facet.
    pub facets: &'a [(u16, u32)],
    /// Pressure of each crack (indexed by crack; `None` for unloaded cracks).
    pub pressure: &'a [Option<Scalar>],
    pub t: f64,
}

impl Kernel for CrackPressureKernel<'_> {
    fn n_elements(&self) -> usize {
        self.facets.len()
    }
    fn has_matrix(&self) -> bool {
        false
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        let (k, f) = self.facets[e];
        let cell = self.cracks[k as usize].cut.facets[f as usize].cell;
        SCRATCH.with(|s| {
            let s = &mut *s.borrow_mut();
            s.basis.build(self.mesh, self.enrichment, cell);
            out.extend_from_slice(&s.basis.dofs);
        });
    }
    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let Some(fv) = out.vector else { return };
        let (k, fi) = self.facets[e];
        let Some(p) = &self.pressure[k as usize] else { return };
        let facet = &self.cracks[k as usize].cut.facets[fi as usize];
        let dim = self.mesh.dim;
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        SCRATCH.with(|s| {
            let s = &mut *s.borrow_mut();
            let Scratch { basis, vals, grads, vals_minus, grads_minus, .. } = s;
            basis.build(self.mesh, self.enrichment, facet.cell);
            let nb = basis.len();
            vals.resize(nb, 0.0);
            grads.resize(nb, [0.0; 3]);
            vals_minus.resize(nb, 0.0);
            grads_minus.resize(nb, [0.0; 3]);
            let (pts, wts) = facet_quadrature(facet, 2);
            for (xi, w) in pts.iter().zip(&wts) {
                let (Ok(pi), Ok(_)) = (
                    ev.eval(facet.cell, basis, xi, Some(1), vals, grads),
                    ev.eval(facet.cell, basis, xi, Some(-1), vals_minus, grads_minus),
                ) else {
                    continue;
                };
                let pv = p.eval_load(pi.x, self.t);
                for kk in 0..nb {
                    let jump = vals[kk] - vals_minus[kk];
                    if jump == 0.0 {
                        continue;
                    }
                    for i in 0..dim {
                        fv[kk * dim + i] += w * pv * facet.normal[i] * jump;
                    }
                }
            }
        });
    }
}
