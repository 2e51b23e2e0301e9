//! Crack facets: from reference vertices to the physical [`Facet`] (orientation from −
//! to +, flat physical measure and normal, the mesh edge or node each vertex lies on).
//!
//! Entry points: [`CellGeom`] (a cut cell's kind, nodes and coordinates, with the
//! isoparametric map) and [`make_facet`].

use super::simplex::{cross, dot, norm, sub, Vtx, T};
use super::Facet;
use crate::element::{self, CellType, MAX_NODES};
use crate::mesh::Mesh;

/// The parent cell of a cut: type, global nodes and physical coordinates.
pub(crate) struct CellGeom {
    pub cell: usize,
    pub kind: CellType,
    pub nodes: [usize; MAX_NODES],
    pub coords: [[f64; 3]; MAX_NODES],
}

impl CellGeom {
    pub fn new(mesh: &Mesh, c: usize) -> CellGeom {
        let cell = &mesh.cells[c];
        let mut coords = [[0.0; 3]; MAX_NODES];
        mesh.cell_coords(c, &mut coords);
        CellGeom { cell: c, kind: cell.kind, nodes: cell.nodes, coords }
    }

    /// Physical position of a reference point (the parent's isoparametric map).
    pub fn map(&self, xi: &[f64; 3]) -> [f64; 3] {
        let nn = self.kind.n_nodes();
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        element::shape(self.kind, xi, &mut n, &mut dn);
        element::map_point(&n[..nn], &self.coords[..nn])
    }

    /// The global node a vertex sits on (one support bit), if any.
    fn node_of(&self, supp: u8) -> Option<usize> {
        (supp.count_ones() == 1).then(|| self.nodes[supp.trailing_zeros() as usize])
    }

    /// The mesh edge (sorted global pair) a vertex lies on: its support when that is a
    /// parent edge; for a vertex on a node, the parent edge touching the node whose
    /// sorted global pair is smallest; `None` inside the cell, on a face, or on a
    /// diagonal of the reference split.
    fn edge_of(&self, supp: u8) -> Option<[usize; 2]> {
        let sorted = |e: &[usize; 2]| {
            let (a, b) = (self.nodes[e[0]], self.nodes[e[1]]);
            if a < b {
                [a, b]
            } else {
                [b, a]
            }
        };
        match supp.count_ones() {
            1 => {
                let a = supp.trailing_zeros() as usize;
                self.kind.edges().iter().filter(|e| e[0] == a || e[1] == a).map(sorted).min()
            }
            2 => self.kind.edges().iter().find(|e| supp == (1 << e[0]) | (1 << e[1])).map(sorted),
            _ => None,
        }
    }
}

/// Builds the facet with reference vertices `v` (2 in 2D, 3 in 3D, on φn = 0 of one
/// reference sub-simplex) and `neg_ref`, a reference point strictly on the − side of
/// that sub-simplex, used to order the vertices so that the normal points from − to +.
///
/// Normal convention: 2D, n = (t_y, −t_x)/|t| with t = x1 − x0 (the tangent rotated by
/// −90°); 3D, n = (x1 − x0) × (x2 − x0) normalised. The same rule in reference space
/// gives the reference normal; since the parent map preserves orientation, ordering the
/// vertices in reference space orients the physical normal.
pub(crate) fn make_facet(g: &CellGeom, v: &[Vtx], neg_ref: &[f64; 3]) -> Facet {
    let mut v: Vec<Vtx> = v.to_vec();
    let d = sub(neg_ref, v[0].xi);
    let reversed = if v.len() == 2 {
        let t = sub(v[1].xi, v[0].xi);
        t[1] * d[0] - t[0] * d[1] > 0.0
    } else {
        dot(cross(sub(v[1].xi, v[0].xi), sub(v[2].xi, v[0].xi)), d) > 0.0
    };
    if reversed {
        v.swap(0, 1);
    }
    let x: Vec<[f64; 3]> = v.iter().map(|p| g.map(&p.xi)).collect();
    let (measure, normal) = if v.len() == 2 {
        let t = sub(x[1], x[0]);
        let l = norm(t);
        (l, if l > 0.0 { [t[1] / l, -t[0] / l, 0.0] } else { [0.0; 3] })
    } else {
        let c = cross(sub(x[1], x[0]), sub(x[2], x[0]));
        let a = norm(c);
        (0.5 * a, if a > 0.0 { [c[0] / a, c[1] / a, c[2] / a] } else { [0.0; 3] })
    };
    Facet {
        cell: g.cell,
        vertices_ref: v.iter().map(|p| p.xi).collect(),
        vertices: x,
        normal,
        measure,
        vertex_edges: v.iter().map(|p| g.edge_of(p.supp)).collect(),
        vertex_nodes: v.iter().map(|p| g.node_of(p.supp)).collect(),
        vertex_on_front: v.iter().map(|p| p.on[T]).collect(),
    }
}
