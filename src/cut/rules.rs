//! Quadrature on sub-cells and facets, in the parent reference coordinates.
//!
//! Entry points: [`subcell_quadrature`], [`facet_quadrature`], [`subcell_measure`].
//!
//! The rules are described on [`subcell_quadrature`].

use super::simplex::{cross, dot, sub};
use super::{CutOptions, Facet, SubCell};
use crate::element::{self, MAX_NODES};
use crate::geometry::quadrature::{gauss_legendre, gauss_line, gauss_tetrahedron, gauss_triangle, QuadratureRule};
use crate::mesh::Mesh;

/// Gauss–Legendre on [0, 1] with `n` points.
fn gauss01(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre(n.max(1));
    (x.iter().map(|x| 0.5 * (x + 1.0)).collect(), w.iter().map(|w| 0.5 * w).collect())
}

#[inline]
fn lerp(a: &[f64; 3], b: &[f64; 3], s: f64) -> [f64; 3] {
    [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])]
}

/// Quadrature of a sub-cell in the parent reference coordinates: points and weights such
/// that Σ w f(ξ) ≈ ∫_{sub-cell, reference space} f dξ (multiply by the parent det J at ξ
/// for physical integrals). Uses the almost-polar rule collapsed at `singular_vertex`
/// (along `singular_edge` in 3D when set) with degree `opts.front_degree`, the plain
/// Gauss rule of degree `opts.subcell_degree` otherwise. A sub-cell whose vertex count
/// does not match `dim` yields an empty rule.
///
/// - Sub-cells without a front vertex: the plain Gauss rule of degree
///   `CutOptions::subcell_degree` on the reference simplex, mapped affinely.
/// - Sub-cells touching the front (almost-polar rules, degree p = `front_degree`; all of
///   them exact for polynomials of degree p in ξ, with positive weights):
///   * 2D, singular vertex P, opposite edge A–B: x = P + ρ (A + v (B − A) − P), ρ = t²,
///     with (t, v) Gauss on [0, 1]² (p + 2 points in t, p/2 + 2 in v). The Duffy factor
///     ρ removes 1/r, and the grading ρ = t² turns every r^(k/2) into a polynomial in
///     t: integrands like 1/√r, √r and the products of branch-function gradients
///     (1/r × smooth angular part) are integrated to the accuracy of the angular rule.
///   * 3D, one vertex P on the front: conical rule x = P + ρ (T(u, w) − P), T the
///     opposite face by the collapsed triangle map (u, w(1 − u)), ρ = t²; Jacobian
///     6V ρ² (1 − u); p + 3 points in t, p/2 + 2 in u and w.
///   * 3D, an edge P0–P1 on the front (the common case): the rule collapsed onto that
///     edge, x = (1 − ρ) (P0 + a (P1 − P0)) + ρ (C0 + b (C1 − C0)) with C0–C1 the
///     opposite edge, ρ = t²; Jacobian 6V ρ (1 − ρ), and ρ is proportional to the
///     distance to the front line, so the r^(−1/2) singularity along the whole edge is
///     treated as in 2D; p + 3 points in t, p/2 + 2 in a and b.
pub fn subcell_quadrature(sc: &SubCell, dim: usize, opts: &CutOptions) -> QuadratureRule {
    let v = &sc.vertices;
    let empty = QuadratureRule { points: vec![], weights: vec![] };
    if v.len() != dim + 1 || !(dim == 2 || dim == 3) {
        return empty;
    }
    let p = opts.front_degree.max(1);
    match (dim, sc.singular_vertex, sc.singular_edge) {
        (2, Some(s), _) if s < 3 => tri_collapsed(&v[s], &v[(s + 1) % 3], &v[(s + 2) % 3], p),
        (3, _, Some([i, j])) if i < 4 && j < 4 && i != j => {
            let o: Vec<usize> = (0..4).filter(|&k| k != i && k != j).collect();
            tet_edge_collapsed([&v[i], &v[j]], [&v[o[0]], &v[o[1]]], p)
        }
        (3, Some(s), _) if s < 4 => {
            let o: Vec<usize> = (0..4).filter(|&k| k != s).collect();
            tet_vertex_collapsed(&v[s], [&v[o[0]], &v[o[1]], &v[o[2]]], p)
        }
        (2, _, _) => {
            let base = gauss_triangle(opts.subcell_degree);
            let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
            let det = (e1[0] * e2[1] - e1[1] * e2[0]).abs();
            let points = base.points.iter().map(|q| lerp2(&v[0], &e1, &e2, q[0], q[1])).collect();
            QuadratureRule { points, weights: base.weights.iter().map(|w| w * det).collect() }
        }
        _ => {
            let base = gauss_tetrahedron(opts.subcell_degree);
            let (e1, e2, e3) = (sub(v[1], v[0]), sub(v[2], v[0]), sub(v[3], v[0]));
            let det = dot(e1, cross(e2, e3)).abs();
            let points = base
                .points
                .iter()
                .map(|q| {
                    let mut x = v[0];
                    for k in 0..3 {
                        x[k] += q[0] * e1[k] + q[1] * e2[k] + q[2] * e3[k];
                    }
                    x
                })
                .collect();
            QuadratureRule { points, weights: base.weights.iter().map(|w| w * det).collect() }
        }
    }
}

#[inline]
fn lerp2(o: &[f64; 3], e1: &[f64; 3], e2: &[f64; 3], a: f64, b: f64) -> [f64; 3] {
    [o[0] + a * e1[0] + b * e2[0], o[1] + a * e1[1] + b * e2[1], o[2] + a * e1[2] + b * e2[2]]
}

/// 2D almost-polar rule collapsed at `p` (see the module doc).
fn tri_collapsed(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3], deg: usize) -> QuadratureRule {
    let (e1, e2) = (sub(a, p), sub(b, p));
    let area2 = (e1[0] * e2[1] - e1[1] * e2[0]).abs();
    let (tx, tw) = gauss01(deg + 2);
    let (vx, vw) = gauss01(deg / 2 + 2);
    let mut rule = QuadratureRule { points: Vec::with_capacity(tx.len() * vx.len()), weights: vec![] };
    for (&t, &wt) in tx.iter().zip(&tw) {
        let rho = t * t;
        for (&v, &wv) in vx.iter().zip(&vw) {
            rule.points.push(lerp2(p, &e1, &e2, rho * (1.0 - v), rho * v));
            rule.weights.push(area2 * rho * 2.0 * t * wt * wv);
        }
    }
    rule
}

/// 3D rule collapsed at the vertex `p`, opposite face `f` (see the module doc).
fn tet_vertex_collapsed(p: &[f64; 3], f: [&[f64; 3]; 3], deg: usize) -> QuadratureRule {
    let (e1, e2, e3) = (sub(f[0], p), sub(f[1], p), sub(f[2], p));
    let vol6 = dot(e1, cross(e2, e3)).abs();
    let (tx, tw) = gauss01(deg + 3);
    let (ux, uw) = gauss01(deg / 2 + 2);
    let (wx, ww) = gauss01(deg / 2 + 2);
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for (&t, &wt) in tx.iter().zip(&tw) {
        let rho = t * t;
        for (&u, &wu) in ux.iter().zip(&uw) {
            for (&w, &wwi) in wx.iter().zip(&ww) {
                // T = f0 + u (f1 − f0) + w (1 − u) (f2 − f0), as barycentrics on (f0, f1, f2).
                let (b1, b2) = (u, w * (1.0 - u));
                let b0 = 1.0 - b1 - b2;
                let mut x = *p;
                for k in 0..3 {
                    x[k] += rho * (b0 * e1[k] + b1 * e2[k] + b2 * e3[k]);
                }
                rule.points.push(x);
                rule.weights.push(vol6 * rho * rho * (1.0 - u) * 2.0 * t * wt * wu * wwi);
            }
        }
    }
    rule
}

/// 3D rule collapsed along the edge `e` (both ends on the front), opposite edge `c`.
fn tet_edge_collapsed(e: [&[f64; 3]; 2], c: [&[f64; 3]; 2], deg: usize) -> QuadratureRule {
    let (de, dc, d0) = (sub(e[1], e[0]), sub(c[1], c[0]), sub(c[0], e[0]));
    let vol6 = dot(de, cross(dc, d0)).abs();
    let (tx, tw) = gauss01(deg + 3);
    let (ax, aw) = gauss01(deg / 2 + 2);
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for (&t, &wt) in tx.iter().zip(&tw) {
        let rho = t * t;
        for (&a, &wa) in ax.iter().zip(&aw) {
            let pe = lerp(e[0], e[1], a);
            for (&b, &wb) in ax.iter().zip(&aw) {
                let pc = lerp(c[0], c[1], b);
                rule.points.push(lerp(&pe, &pc, rho));
                rule.weights.push(vol6 * rho * (1.0 - rho) * 2.0 * t * wt * wa * wb);
            }
        }
    }
    rule
}

/// Quadrature on a facet: points in parent reference coords and weights = physical
/// measure weights (Σ w = `f.measure`). The facet is flat in physical space (see the
/// module doc of [`crate::cut`]); the points are the affine images of a Gauss rule of
/// `degree` on the reference facet (segment in 2D, triangle in 3D).
pub fn facet_quadrature(f: &Facet, degree: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    let v = &f.vertices_ref;
    match v.len() {
        2 => {
            let r = gauss_line(degree);
            let pts = r.points.iter().map(|x| lerp(&v[0], &v[1], 0.5 * (x[0] + 1.0))).collect();
            (pts, r.weights.iter().map(|w| 0.5 * w * f.measure).collect())
        }
        3 => {
            let r = gauss_triangle(degree);
            let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
            let pts = r.points.iter().map(|q| lerp2(&v[0], &e1, &e2, q[0], q[1])).collect();
            (pts, r.weights.iter().map(|w| 2.0 * w * f.measure).collect())
        }
        _ => (vec![], vec![]),
    }
}

/// Physical measure (area/volume) of a sub-cell of `cell`: Σ w det J over its rule
/// (degree raised so that det J of a distorted quad/hex is integrated exactly).
/// Returns 0 for a cell index out of range.
pub fn subcell_measure(mesh: &Mesh, cell: usize, sc: &SubCell) -> f64 {
    let Some(c) = mesh.cells.get(cell) else { return 0.0 };
    let kind = c.kind;
    let dim = kind.dim();
    let opts = CutOptions { subcell_degree: if dim == 3 { 6 } else { 2 }, front_degree: 6 };
    let mut xs = [[0.0; 3]; MAX_NODES];
    let nn = kind.n_nodes();
    for (a, &g) in c.nodes().iter().enumerate() {
        match mesh.nodes.get(g) {
            Some(x) => xs[a] = *x,
            None => return 0.0,
        }
    }
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    // det J is constant on a simplex: computed at the first point only.
    let mut affine_det = None;
    subcell_quadrature(sc, dim, &opts)
        .iter()
        .map(|(xi, w)| {
            let det = match affine_det {
                Some(det) => det,
                None => {
                    element::shape(kind, xi, &mut n, &mut dn);
                    let det = element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut g).unwrap_or(0.0);
                    if kind.is_simplex() {
                        affine_det = Some(det);
                    }
                    det
                }
            };
            w * det
        })
        .sum()
}
