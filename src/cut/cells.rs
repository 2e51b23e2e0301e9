//! Cutting one mesh cell: reference split of quads/hexes into simplices, the φn cut,
//! the status decision, the φt cut in front cells, sub-cells, facets and front pieces.
//!
//! Entry point: [`cut_cell`] (called in parallel by [`super::cut_crack`]); it returns
//! `None` for an uncut cell without allocating anything.

use super::facets::{make_facet, CellGeom};
use super::simplex::{
    clip_polygon, clip_segment, norm, polygon_area, signed_area, signed_volume, split_tet, sub, Vtx, N, T,
};
use super::{CellStatus, Facet, FrontPiece, SubCell};
use crate::element::{CellType, MAX_NODES};
use crate::mesh::Mesh;

/// Sub-cells whose reference measure is at most this fraction of the parent's are dropped
/// (zero-measure pieces of cuts through nodes/edges/faces, and round-off slivers). Not
/// 1e-12: a front passing ~1e-4 h from a diagonal of the reference split yields genuine
/// slivers of relative measure ~1e-12, and dropping them breaks the partition of the
/// parent's measure at that level.
pub(crate) const SUBCELL_TOL: f64 = 1e-14;
/// Facets / φn = 0 pieces / front segments whose reference measure is at most this times
/// the reference size to the power (dimension of the piece) are of zero measure.
pub(crate) const FACET_TOL: f64 = 1e-14;

/// Quad → 2 triangles along the (0, 2) diagonal (parent-local nodes).
const QUAD_SPLIT: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];
/// Hex → 6 tetrahedra, Kuhn split along the 0–6 diagonal (parent-local nodes).
const KUHN: [[usize; 4]; 6] = [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]];

/// What a cut cell produces.
#[derive(Debug)]
pub(crate) struct CellOut {
    pub status: CellStatus,
    pub subcells: Vec<SubCell>,
    pub facets: Vec<Facet>,
    pub front: Vec<FrontPiece>,
}

/// One φn = 0 piece inside a reference sub-simplex: a segment (2D) or a convex polygon
/// (3D), with one strictly negative vertex of the sub-simplex to orient it.
struct ZPiece {
    poly: Vec<Vtx>,
    neg_ref: [f64; 3],
}

/// A piece of the φn split: its side and its vertices (a polygon in 2D, a tet in 3D).
enum Piece {
    Poly(i8, Vec<Vtx>),
    Tet(i8, [Vtx; 4]),
}

/// Cuts cell `c`. `lsn`/`lst` are the nodal values (already checked for length and
/// finiteness; node indices checked). Returns `None` when the cell is uncut.
pub(crate) fn cut_cell(mesh: &Mesh, c: usize, lsn: &[f64], lst: Option<&[f64]>) -> Option<CellOut> {
    let cell = &mesh.cells[c];
    let kind = cell.kind;
    let nodes = cell.nodes();
    let nn = nodes.len();
    // Quick rejections on the nodal values (the sub-simplex interpolants are convex
    // combinations of them): no sign change of φn, or φt ≥ 0 everywhere.
    let n_neg = nodes.iter().filter(|&&g| lsn[g] < 0.0).count();
    if n_neg == 0 || n_neg == nn {
        return None;
    }
    if let Some(t) = lst {
        if nodes.iter().all(|&g| t[g] >= 0.0) {
            return None;
        }
    }
    let dim = kind.dim();
    let refn = kind.reference_nodes();
    let mut verts = [Vtx { xi: [0.0; 3], phi: [0.0; 2], supp: 0, on: [false; 2] }; MAX_NODES];
    for (a, &g) in nodes.iter().enumerate() {
        let phn = lsn[g];
        // An interface has no φt: the whole φn = 0 surface is crack (φt ≡ −1).
        let pht = lst.map_or(-1.0, |t| t[g]);
        verts[a] = Vtx { xi: refn[a], phi: [phn, pht], supp: 1 << a, on: [phn == 0.0, lst.is_some() && pht == 0.0] };
    }
    let ref_size: f64 = if kind.is_simplex() { 1.0 } else { 2.0 };
    let z_tol = FACET_TOL * ref_size.powi(dim as i32 - 1);
    let sub_tol = SUBCELL_TOL * kind.reference_measure();

    // 1. φn split of every reference sub-simplex.
    let mut pieces: Vec<Piece> = Vec::new();
    let mut zs: Vec<ZPiece> = Vec::new();
    let split_2d = |s: &[usize; 3], pieces: &mut Vec<Piece>, zs: &mut Vec<ZPiece>| {
        let tri = [verts[s[0]], verts[s[1]], verts[s[2]]];
        let clip = clip_polygon(&tri, N);
        if clip.cross.len() == 2 && norm(sub(clip.cross[1].xi, clip.cross[0].xi)) > z_tol {
            let neg_ref = tri.iter().find(|v| v.neg(N)).map_or([0.0; 3], |v| v.xi);
            zs.push(ZPiece { poly: clip.cross.clone(), neg_ref });
        }
        pieces.push(Piece::Poly(-1, clip.neg));
        pieces.push(Piece::Poly(1, clip.pos));
    };
    let split_3d = |s: &[usize; 4], pieces: &mut Vec<Piece>, zs: &mut Vec<ZPiece>| {
        let tet = [verts[s[0]], verts[s[1]], verts[s[2]], verts[s[3]]];
        let sp = split_tet(&tet, N);
        if sp.z.len() >= 3 && polygon_area(&sp.z) > z_tol {
            let neg_ref = tet.iter().find(|v| v.neg(N)).map_or([0.0; 3], |v| v.xi);
            zs.push(ZPiece { poly: sp.z, neg_ref });
        }
        pieces.extend(sp.neg.into_iter().map(|t| Piece::Tet(-1, t)));
        pieces.extend(sp.pos.into_iter().map(|t| Piece::Tet(1, t)));
    };
    match kind {
        CellType::Tri3 => split_2d(&[0, 1, 2], &mut pieces, &mut zs),
        CellType::Quad4 => QUAD_SPLIT.iter().for_each(|s| split_2d(s, &mut pieces, &mut zs)),
        CellType::Tet4 => split_3d(&[0, 1, 2, 3], &mut pieces, &mut zs),
        CellType::Hex8 => KUHN.iter().for_each(|s| split_3d(s, &mut pieces, &mut zs)),
    }

    // 2. Status from the signs of φt on the (non-degenerate) φn = 0 pieces.
    if zs.is_empty() {
        return None;
    }
    let any_neg = zs.iter().any(|z| z.poly.iter().any(|v| v.neg(T)));
    let any_pos = zs.iter().any(|z| z.poly.iter().any(|v| !v.neg(T)));
    let status = match (any_neg, any_pos) {
        (true, false) => CellStatus::Cut,
        (true, true) => CellStatus::Front,
        _ => return None,
    };
    let front_cell = status == CellStatus::Front;

    // 3. Sub-cells.
    let mut subcells = Vec::new();
    let push_tri = |side: i8, ahead: bool, poly: &[Vtx], subcells: &mut Vec<SubCell>| {
        if poly.len() < 3 {
            return;
        }
        let k = poly.iter().position(|v| v.on_front()).unwrap_or(0);
        let m = poly.len();
        for i in 1..m - 1 {
            let (a, b, cc) = (&poly[k], &poly[(k + i) % m], &poly[(k + i + 1) % m]);
            let area = signed_area(&a.xi, &b.xi, &cc.xi);
            if area.abs() <= sub_tol {
                continue;
            }
            let mut tri = [a, b, cc];
            if area < 0.0 {
                tri.swap(1, 2);
            }
            subcells.push(SubCell {
                side,
                ahead,
                vertices: tri.iter().map(|v| v.xi).collect(),
                singular_vertex: if front_cell { tri.iter().position(|v| v.on_front()) } else { None },
                singular_edge: None,
            });
        }
    };
    let push_tet = |side: i8, ahead: bool, t: &[Vtx; 4], subcells: &mut Vec<SubCell>| {
        subcells.extend(sub_tet(side, ahead, t, sub_tol, front_cell));
    };
    for p in &pieces {
        match p {
            Piece::Poly(side, poly) => {
                if front_cell {
                    let cl = clip_polygon(poly, T);
                    push_tri(*side, false, &cl.neg, &mut subcells);
                    push_tri(*side, true, &cl.pos, &mut subcells);
                } else {
                    push_tri(*side, false, poly, &mut subcells);
                }
            }
            Piece::Tet(side, t) => {
                if front_cell {
                    let sp = split_tet(t, T);
                    sp.neg.iter().for_each(|t| push_tet(*side, false, t, &mut subcells));
                    sp.pos.iter().for_each(|t| push_tet(*side, true, t, &mut subcells));
                } else {
                    push_tet(*side, false, t, &mut subcells);
                }
            }
        }
    }

    // 4. Facets (φn = 0 clipped to φt < 0) and front pieces.
    let geom = CellGeom::new(mesh, c);
    let mut facets = Vec::new();
    let mut front: Vec<FrontPiece> = Vec::new();
    for z in &zs {
        if dim == 2 {
            // Orient the segment so that its normal (tangent rotated by −90°) points to +.
            let (mut a, mut b) = (z.poly[0], z.poly[1]);
            let t = sub(b.xi, a.xi);
            let nref = [t[1], -t[0], 0.0];
            let d = sub(z.neg_ref, a.xi);
            if nref[0] * d[0] + nref[1] * d[1] > 0.0 {
                std::mem::swap(&mut a, &mut b);
            }
            let (seg, tip) = if front_cell { clip_segment(&a, &b, T) } else { (Some([a, b]), None) };
            if let Some(s) = seg {
                if norm(sub(s[1].xi, s[0].xi)) > z_tol {
                    facets.push(make_facet(&geom, &s, &z.neg_ref));
                }
            }
            if let Some(p) = tip {
                if !front.iter().any(|f| f.points_ref[0] == p.xi) {
                    front.push(FrontPiece { cell: c, points: vec![geom.map(&p.xi)], points_ref: vec![p.xi] });
                }
            }
        } else {
            let (crack, seg) = if front_cell {
                let cl = clip_polygon(&z.poly, T);
                (cl.neg, cl.cross)
            } else {
                (z.poly.clone(), vec![])
            };
            for i in 1..crack.len().saturating_sub(1) {
                let tri = [crack[0], crack[i], crack[i + 1]];
                if super::simplex::triangle_area(&tri[0].xi, &tri[1].xi, &tri[2].xi) > z_tol {
                    facets.push(make_facet(&geom, &tri, &z.neg_ref));
                }
            }
            if seg.len() == 2 && norm(sub(seg[1].xi, seg[0].xi)) > FACET_TOL * ref_size {
                front.push(FrontPiece {
                    cell: c,
                    points: vec![geom.map(&seg[0].xi), geom.map(&seg[1].xi)],
                    points_ref: vec![seg[0].xi, seg[1].xi],
                });
            }
        }
    }
    Some(CellOut { status, subcells, facets, front })
}

/// The sub-cells of a 3D cell that the crack does not cut but whose boundary holds a piece
/// of the front: the cell on the + side of a crack lying in a face plane of the mesh
/// (φn = 0 exactly on a face, "an exact zero counts as positive", so the facet and the
/// front belong to the cell below). Its tip functions are singular along that face's
/// front line, which a Gauss rule on the whole cell integrates badly; split by φt like a
/// front cell, the sub-tets touching the front get the collapsed rules of
/// [`super::subcell_quadrature`]. `None` when the cell is not such a cell (φn changes sign,
/// fewer than three nodes on φn = 0, or φt of one sign on them), or no sub-tet touches the
/// front.
pub(crate) fn front_on_boundary_subcells(mesh: &Mesh, c: usize, lsn: &[f64], lst: &[f64]) -> Option<Vec<SubCell>> {
    let cell = &mesh.cells[c];
    let kind = cell.kind;
    let nodes = cell.nodes();
    if kind.dim() != 3 || nodes.iter().any(|&g| lsn[g] < 0.0) {
        return None;
    }
    let zero: Vec<usize> = nodes.iter().copied().filter(|&g| lsn[g] == 0.0).collect();
    if zero.len() < 3 || !zero.iter().any(|&g| lst[g] < 0.0) || !zero.iter().any(|&g| lst[g] > 0.0) {
        return None;
    }
    let refn = kind.reference_nodes();
    let mut verts = [Vtx { xi: [0.0; 3], phi: [0.0; 2], supp: 0, on: [false; 2] }; MAX_NODES];
    for (a, &g) in nodes.iter().enumerate() {
        let (phn, pht) = (lsn[g], lst[g]);
        verts[a] = Vtx { xi: refn[a], phi: [phn, pht], supp: 1 << a, on: [phn == 0.0, pht == 0.0] };
    }
    let sub_tol = SUBCELL_TOL * kind.reference_measure();
    let tets: &[[usize; 4]] = match kind {
        CellType::Tet4 => &[[0, 1, 2, 3]],
        _ => &KUHN,
    };
    let mut subcells = Vec::new();
    for s in tets {
        let tet = [verts[s[0]], verts[s[1]], verts[s[2]], verts[s[3]]];
        let sp = split_tet(&tet, T);
        for (ahead, list) in [(false, &sp.neg), (true, &sp.pos)] {
            subcells.extend(list.iter().filter_map(|t| sub_tet(1, ahead, t, sub_tol, true)));
        }
    }
    subcells.iter().any(|s| s.singular_vertex.is_some()).then_some(subcells)
}

/// A positively oriented sub-tet of `t` (None below `sub_tol` in measure), with its front
/// vertices (φn = φt = 0) as the singular vertex and edge of the collapsed rules when
/// `front` (a front cell, or an uncut cell with the front on its boundary).
fn sub_tet(side: i8, ahead: bool, t: &[Vtx; 4], sub_tol: f64, front: bool) -> Option<SubCell> {
    let vol = signed_volume(&t[0].xi, &t[1].xi, &t[2].xi, &t[3].xi);
    if vol.abs() <= sub_tol {
        return None;
    }
    let mut t = *t;
    if vol < 0.0 {
        t.swap(1, 2);
    }
    let mut fv = [0usize; 4];
    let mut nf = 0;
    if front {
        for (i, v) in t.iter().enumerate() {
            if v.on_front() {
                fv[nf] = i;
                nf += 1;
            }
        }
    }
    Some(SubCell {
        side,
        ahead,
        vertices: t.iter().map(|v| v.xi).collect(),
        singular_vertex: (nf >= 1).then_some(fv[0]),
        singular_edge: (nf >= 2).then_some([fv[0], fv[1]]),
    })
}
