//! X-FEM kernels: the bulk stiffness and body forces with the enriched basis, integrated
//! on the sub-cells of cut cells, and pressure on the crack faces.
//!
//! Entry points: [`XfemBulkKernel`], [`CrackPressureKernel`].
//!
//! Quadrature: cut and front cells are integrated on their sub-cells (almost-polar rules
//! on the sub-cells touching the front, from [`crate::cut::subcell_quadrature`]);
//! uncut cells with tip-enriched nodes use a parent rule of degree `tip_degree`; all
//! other cells the standard rule. In 2D, the tip-enriched pieces that do not touch the
//! front (uncut cells, sub-cells) are quadrisected towards the front wherever it is
//! closer to a piece than the piece's size ([`NEAR_FRONT_DEPTH`] levels at most): a front
//! a few percent of a cell past an edge leaves the 1/√r gradients of the branch
//! functions nearly singular in the next cells, where a plain Gauss rule of degree 6 was
//! off by percents (and the contact pressure with it).

use super::elasticity::{add_isotropic_stiffness, mirror_lower, StiffnessBatch, Vector};
use super::material::{Analysis, Isotropic};
use super::side_materials::SideMaterials;
use crate::assembly::{Kernel, LocalOut};
use crate::cut::{facet_quadrature, front_on_boundary_subcells, subcell_quadrature, CutOptions, SubCell};
use crate::element::{self, CellType, MAX_NODES};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::enrich::{CrackGeometry, EnrichKind, Enrichment};
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
    batch: StiffnessBatch,
}

/// Cells with at least this many quadrature points have their stiffness summed by one
/// matrix product ([`StiffnessBatch`]) instead of point by point.
const BATCH_POINTS: usize = 32;

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
    // 2D tip cells: the front's level sets, for the refinement towards it.
    let near = if tip && mesh.dim == 2 { NearFront::new(mesh, enr, cracks, c) } else { None };
    if let Some(k) = enr.cell_crack[c] {
        let cut = &cracks[k as usize].cut;
        if let Some(cc) = cut.cell_cut(c) {
            let opts = CutOptions {
                subcell_degree: (if tip { q.tip_degree } else { q.subcell_degree }).max(extra_degree),
                front_degree: q.front_degree,
            };
            for sc in &cc.subcells {
                if let (Some(nf), None, 3) = (&near, sc.singular_vertex, sc.vertices.len()) {
                    let v = [sc.vertices[0], sc.vertices[1], sc.vertices[2]];
                    nf.rule(Piece::Tri(v), opts.subcell_degree, 0, Some(sc.side), out);
                    continue;
                }
                let rule = subcell_quadrature(sc, mesh.dim, &opts);
                out.extend(rule.points.iter().zip(&rule.weights).map(|(p, w)| (*p, *w, Some(sc.side))));
            }
            return;
        }
    }
    // 3D: a crack lying in a face plane leaves the cell on its + side uncut, with the front
    // on its face: the collapsed rules of a front cell, not a Gauss rule across the
    // singular line.
    if tip && mesh.dim == 3 {
        if let Some(subcells) = front_on_face(mesh, enr, cracks, c) {
            let opts = CutOptions { subcell_degree: q.tip_degree.max(extra_degree), front_degree: q.front_degree };
            for sc in &subcells {
                let rule = subcell_quadrature(sc, mesh.dim, &opts);
                out.extend(rule.points.iter().zip(&rule.weights).map(|(p, w)| (*p, *w, Some(sc.side))));
            }
            return;
        }
    }
    if let Some(nf) = &near {
        let degree = q.tip_degree.max(extra_degree);
        match kind {
            CellType::Quad4 => return nf.rule(Piece::Rect([-1.0, -1.0], [1.0, 1.0]), degree, 0, None, out),
            CellType::Tri3 => {
                let v = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
                return nf.rule(Piece::Tri(v), degree, 0, None, out);
            }
            _ => {}
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

/// The sub-cells of tip cell `c` when the front of one of the cracks tip-enriching its
/// nodes lies on its boundary ([`crate::cut::front_on_boundary_subcells`]).
fn front_on_face(mesh: &Mesh, enr: &Enrichment, cracks: &[CrackGeometry], c: usize) -> Option<Vec<SubCell>> {
    let mut seen: u64 = 0;
    for &n in mesh.cells[c].nodes() {
        for i in enr.node_items(n).iter().filter(|i| i.kind == EnrichKind::Tip) {
            let k = i.crack as usize;
            if k < 64 && seen & (1 << k) != 0 {
                continue;
            }
            if k < 64 {
                seen |= 1 << k;
            }
            let ls = &cracks.get(k)?.levelsets;
            if let Some(sc) = ls.lst.as_ref().and_then(|t| front_on_boundary_subcells(mesh, c, &ls.lsn, t)) {
                return Some(sc);
            }
        }
    }
    None
}

/// Most quadrisection levels of a 2D piece towards the front (pieces of h/64).
pub const NEAR_FRONT_DEPTH: usize = 6;

/// A piece of a 2D cell in its reference coordinates: a triangle, or a rectangle of a
/// quad's [−1, 1]² (lower and upper corners).
#[derive(Debug, Clone, Copy)]
enum Piece {
    Tri([[f64; 3]; 3]),
    Rect([f64; 2], [f64; 2]),
}

/// The nodal data of a 2D tip cell that locate the front (φn = φt = 0) in it.
struct NearFront {
    kind: CellType,
    xs: [[f64; 3]; MAX_NODES],
    lsn: [f64; MAX_NODES],
    lst: [f64; MAX_NODES],
}

impl NearFront {
    /// The front of the crack whose tip set holds a node of cell `c` (None without one).
    fn new(mesh: &Mesh, enr: &Enrichment, cracks: &[CrackGeometry], c: usize) -> Option<NearFront> {
        let cell = &mesh.cells[c];
        let k = cell
            .nodes()
            .iter()
            .find_map(|&n| enr.node_items(n).iter().find(|i| i.kind == EnrichKind::Tip && !i.blending))?
            .crack as usize;
        let ls = &cracks.get(k)?.levelsets;
        let lst = ls.lst.as_ref()?;
        let mut nf =
            NearFront { kind: cell.kind, xs: [[0.0; 3]; MAX_NODES], lsn: [0.0; MAX_NODES], lst: [0.0; MAX_NODES] };
        let nn = mesh.cell_coords(c, &mut nf.xs);
        for (a, &n) in cell.nodes().iter().enumerate().take(nn) {
            nf.lsn[a] = ls.lsn[n];
            nf.lst[a] = lst[n];
        }
        Some(nf)
    }

    /// Physical position and distance r = √(φn² + φt²) to the front at reference point xi.
    fn at(&self, xi: &[f64; 3]) -> ([f64; 3], f64) {
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        element::shape(self.kind, xi, &mut n, &mut dn);
        let (mut x, mut pn, mut pt) = ([0.0; 3], 0.0, 0.0);
        for a in 0..self.kind.n_nodes() {
            for i in 0..3 {
                x[i] += n[a] * self.xs[a][i];
            }
            pn += n[a] * self.lsn[a];
            pt += n[a] * self.lst[a];
        }
        (x, (pn * pn + pt * pt).sqrt())
    }

    /// Appends the rule of `piece`: Gauss of `degree` when the front is farther from it
    /// (r at its corners, edge midpoints and centre) than its physical diameter or at
    /// depth [`NEAR_FRONT_DEPTH`], its four quadrisection children otherwise.
    fn rule(
        &self,
        piece: Piece,
        degree: usize,
        depth: usize,
        side: Option<i8>,
        out: &mut Vec<([f64; 3], f64, Option<i8>)>,
    ) {
        let corners: Vec<[f64; 3]> = match piece {
            Piece::Tri(v) => v.to_vec(),
            Piece::Rect(lo, hi) => {
                vec![[lo[0], lo[1], 0.0], [hi[0], lo[1], 0.0], [hi[0], hi[1], 0.0], [lo[0], hi[1], 0.0]]
            }
        };
        let mid = |a: &[f64; 3], b: &[f64; 3]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0];
        let nc = corners.len();
        let mut probe = corners.clone();
        probe.extend((0..nc).map(|i| mid(&corners[i], &corners[(i + 1) % nc])));
        let cen = corners.iter().fold([0.0; 3], |s, p| [s[0] + p[0] / nc as f64, s[1] + p[1] / nc as f64, 0.0]);
        probe.push(cen);
        let mapped: Vec<([f64; 3], f64)> = probe.iter().map(|xi| self.at(xi)).collect();
        let r_min = mapped.iter().map(|m| m.1).fold(f64::INFINITY, f64::min);
        let mut diam: f64 = 0.0;
        for i in 0..nc {
            for j in i + 1..nc {
                let (a, b) = (mapped[i].0, mapped[j].0);
                diam = diam.max(((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt());
            }
        }
        if depth < NEAR_FRONT_DEPTH && r_min < diam {
            match piece {
                Piece::Tri([a, b, c]) => {
                    let (ab, bc, ca) = (mid(&a, &b), mid(&b, &c), mid(&c, &a));
                    for t in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
                        self.rule(Piece::Tri(t), degree, depth + 1, side, out);
                    }
                }
                Piece::Rect(lo, hi) => {
                    let m = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                    for (l, h) in [(lo, m), ([m[0], lo[1]], [hi[0], m[1]]), ([lo[0], m[1]], [m[0], hi[1]]), (m, hi)] {
                        self.rule(Piece::Rect(l, h), degree, depth + 1, side, out);
                    }
                }
            }
            return;
        }
        match piece {
            Piece::Tri([a, b, c]) => {
                let base = crate::geometry::quadrature::gauss_triangle(degree);
                let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                let det = (e1[0] * e2[1] - e1[1] * e2[0]).abs();
                for (q, w) in base.points.iter().zip(&base.weights) {
                    let xi = [a[0] + q[0] * e1[0] + q[1] * e2[0], a[1] + q[0] * e1[1] + q[1] * e2[1], 0.0];
                    out.push((xi, w * det, side));
                }
            }
            Piece::Rect(lo, hi) => {
                let base = crate::geometry::quadrature::gauss_square(degree);
                let (sx, sy) = (0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1]));
                for (q, w) in base.points.iter().zip(&base.weights) {
                    out.push(([lo[0] + sx * (q[0] + 1.0), lo[1] + sy * (q[1] + 1.0), 0.0], w * sx * sy, side));
                }
            }
        }
    }
}

/// Bulk stiffness and body forces with the enriched basis, for every cell.
pub struct XfemBulkKernel<'a> {
    pub mesh: &'a Mesh,
    pub enrichment: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
    pub analysis: Analysis,
    pub cell_material: &'a [u32],
    /// Per-side materials of cut cells on a material boundary.
    pub side_materials: &'a SideMaterials,
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
        let lame = |side: Option<i8>| {
            let mat = self.materials[self.side_materials.index(self.cell_material, e, side) as usize];
            (mat.lambda_in_plane(self.analysis), mat.mu())
        };
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
            let Scratch { basis, vals, grads, points, batch, .. } = s;
            basis.build(self.mesh, self.enrichment, e);
            let nb = basis.len();
            vals.resize(nb, 0.0);
            grads.resize(nb, [0.0; 3]);
            let extra = if bf.is_some() && vector.is_some() { 2 } else { 0 };
            cell_points(self.mesh, self.enrichment, self.cracks, e, &self.quadrature, extra, points);
            // Many points: gathered, and summed by a matrix product per material.
            let batched = points.len() >= BATCH_POINTS && matrix.is_some();
            let mut batch_lame: Option<(f64, f64)> = None;
            if batched {
                batch.start(nb, dim);
            }
            for &(xi, w, side) in points.iter() {
                // Meshes are validated before assembly; a singular point contributes nothing.
                let Ok(pi) = ev.eval(e, basis, &xi, side, vals, grads) else { continue };
                let wd = w * pi.det;
                if let Some(k) = matrix.as_deref_mut() {
                    let (lam, mu) = lame(side);
                    if batched {
                        // A material change (the two sides of a bimaterial cut): the
                        // points so far go in with their constants.
                        if let Some((l0, m0)) = batch_lame.filter(|&c| c != (lam, mu)) {
                            batch.finish(k, dim, l0, m0);
                        }
                        batch_lame = Some((lam, mu));
                        batch.push(grads, dim, wd);
                    } else {
                        add_isotropic_stiffness(k, grads, dim, lam, mu, wd);
                    }
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
                if let Some((lam, mu)) = batch_lame {
                    batch.finish(k, dim, lam, mu);
                }
                mirror_lower(k, nb * dim);
            }
        });
    }
}

/// A pressure on both faces of a crack: it pushes the lips apart (t = −p n_out on each
/// lip), so its virtual work is ∫ p n · ⟦δu⟧ over the crack.
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
