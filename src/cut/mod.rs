//! Cutting the mesh by a crack's level sets: per cell, the sub-cells that conform to
//! φn = 0 (and φt = 0 in front cells) with their quadrature; the crack facets with
//! normals and quadrature; the pieces of the front. Pure geometry, no FEM: the output
//! [`CrackCut`] is an immutable value that enrichment, assembly, contact and output read.
//!
//! Entry point: [`cut_crack`]; then [`subcell_quadrature`], [`facet_quadrature`];
//! [`front_on_boundary_subcells`] for the uncut cells a front in a face plane touches;
//! [`boundary::trim_to_body`] removes the parts of a cut lying on the body's boundary.
//!
//! # Conventions
//!
//! - **Interpolation.** Level sets are interpolated on each cell. Simplices (tri3, tet4):
//!   linear from the nodal values, so the crack is a plane piece. quad4/hex8 are first
//!   split into simplices in the **parent reference coordinates** (quad → 2 triangles
//!   along the (0, 2) diagonal; hex → 6 tetrahedra, Kuhn split along the 0–6 diagonal,
//!   the same split as `mesh::generate`), and φ is interpolated linearly on each
//!   reference sub-simplex from the parent's nodal values at its vertices. All cutting
//!   happens in the parent reference space; physical positions are obtained with the
//!   parent's isoparametric map.
//! - **An exact zero counts as positive**: φn = 0 is on the + side, φt = 0 is outside the
//!   crack (the crack is φn = 0, φt < 0). Every cut is then generic: a crack through a
//!   node or along an edge/face yields sub-cells of zero measure, which are dropped, and
//!   its facet is generated once, in the cell on the − side (the cell on the + side sees
//!   no sign change). Likewise a front lying on a face belongs to the cell holding the
//!   crack side. Sub-cells of reference measure below 1e-14 × the parent's are dropped;
//!   facets are dropped only when of zero measure (below 1e-14 × the reference size).
//! - **Sides.** `+` where φn ≥ 0, `−` where φn < 0. A facet's normal points from − to +
//!   (along ∇φn), in physical space.
//! - **Status** (per cell; "φn = 0 in the cell" means its pieces of non-zero measure,
//!   so a sign change that only touches the cell at a node, or along an edge in 3D, is
//!   not a cut): [`CellStatus::Uncut`]: φn = 0 does not meet the cell, or only where
//!   φt ≥ 0 (ahead of the front); [`CellStatus::Cut`]: φt < 0 on all of φn = 0 in the
//!   cell (interfaces: whenever φn = 0 meets the cell); [`CellStatus::Front`]: φt takes
//!   both signs on φn = 0 in the cell (0 counting as +).
//! - **Sub-cells** are simplices in parent reference coordinates, positively oriented,
//!   split by φn and, in front cells only, by φt (`ahead` = φt ≥ 0 side). In front
//!   cells every sub-cell touching the front has a front point as a vertex
//!   ([`SubCell::singular_vertex`]; in 3D also [`SubCell::singular_edge`] when a whole
//!   edge lies on the front); [`subcell_quadrature`] then uses an almost-polar rule
//!   collapsed there (see [`subcell_quadrature`] for what the 2D and 3D rules do).
//! - **Facets** are the part of φn = 0 inside the cell clipped to φt < 0: segments in 2D,
//!   triangles in 3D (a quad or a clipped polygon is fanned into triangles). A facet is
//!   **flat in physical space**: `vertices` are the images of `vertices_ref`, `measure`
//!   and `normal` are those of the flat segment/triangle through them. For simplices
//!   and affine quads/hexes this is exact; in a distorted quad/hex the image of the
//!   reference facet is slightly curved and the flat facet is its chord (the points of
//!   [`facet_quadrature`] lie on the image, their weights are the chord's).
//! - **Facet vertex locations** (for multipliers at crack/edge intersections):
//!   `vertex_edges[i]` is the mesh edge (sorted global node pair) the vertex lies on,
//!   when it lies on an edge of the parent cell. A vertex exactly on a node lies on
//!   every edge touching it: then the edge reported is the parent edge touching that
//!   node with the smallest sorted global pair (deterministic per cell, but two cells
//!   may report different edges), and `vertex_nodes[i]` names the node. `None` for a
//!   vertex inside the cell, on a face, or on a diagonal of the reference split of a
//!   quad/hex (front points are usually such vertices).
//! - **Front pieces**: 2D, the tip point in (or on the boundary of) a front cell, one per
//!   distinct point; 3D, one straight segment per reference sub-simplex the front crosses
//!   (a tet4 holds at most one, a hex8 up to six), segments of zero length omitted (a
//!   front cell where the front only touches φn = 0 at a point has none).

pub mod boundary;
mod cells;
mod facets;
mod lips;
mod rules;
mod simplex;
#[cfg(test)]
mod tests;

pub use lips::lip_boundary;
pub use rules::{facet_quadrature, subcell_measure, subcell_quadrature};

use crate::levelset::NodalLevelSets;
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::fmt;
use std::ops::Range;

/// The relation of one mesh cell to the crack (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellStatus {
    /// φn = 0 does not meet the crack part inside the cell (it may cross the cell ahead
    /// of the front, φt ≥ 0 there: still uncut).
    Uncut,
    /// Split by the crack surface, φt < 0 on all of φn = 0 inside the cell (interfaces:
    /// any cut of non-zero measure).
    Cut,
    /// The front passes through the cell: on φn = 0 inside the cell φt takes both signs.
    Front,
}

/// An integration sub-cell: a simplex in the parent reference coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct SubCell {
    /// +1 or −1: the sign of φn on it (0 counts as +).
    pub side: i8,
    /// In a front cell: on the φt ≥ 0 side (ahead of the front). Always false elsewhere.
    pub ahead: bool,
    /// Vertices in the PARENT reference coordinates (3 in 2D, 4 in 3D), positively oriented.
    pub vertices: Vec<[f64; 3]>,
    /// Index of a vertex that lies on the front (for a collapsed rule).
    pub singular_vertex: Option<usize>,
    /// 3D: indices of two vertices on the front when a whole edge of the sub-tet lies on
    /// it (then `singular_vertex` is the first); the rule collapses along that edge.
    pub singular_edge: Option<[usize; 2]>,
}

impl SubCell {
    /// Measure in the parent reference space.
    pub fn reference_measure(&self) -> f64 {
        let v = &self.vertices;
        match v.len() {
            3 => simplex::signed_area(&v[0], &v[1], &v[2]).abs(),
            4 => simplex::signed_volume(&v[0], &v[1], &v[2], &v[3]).abs(),
            _ => 0.0,
        }
    }
    /// Centroid in the parent reference coordinates.
    pub fn reference_centroid(&self) -> [f64; 3] {
        let k = self.vertices.len().max(1) as f64;
        let mut c = [0.0; 3];
        for v in &self.vertices {
            for (ci, vi) in c.iter_mut().zip(v) {
                *ci += vi / k;
            }
        }
        c
    }
}

/// A flat piece of the crack surface owned by one cell: a segment (2D) or a triangle (3D).
#[derive(Debug, Clone, PartialEq)]
pub struct Facet {
    /// The mesh cell that owns it.
    pub cell: usize,
    /// Vertices in the parent reference coordinates (2 in 2D, 3 in 3D).
    pub vertices_ref: Vec<[f64; 3]>,
    /// Vertices in physical coordinates.
    pub vertices: Vec<[f64; 3]>,
    /// Unit normal, from − to + (2D: the tangent x1 − x0 rotated by −90°; 3D: the
    /// right-hand normal of (x0, x1, x2)).
    pub normal: [f64; 3],
    /// Physical length / area.
    pub measure: f64,
    /// For each vertex: the mesh edge (sorted global node pair) it lies on, when it lies
    /// on an edge of the parent cell (on a node: the parent edge touching it with the
    /// smallest sorted pair); `None` when it is interior to the cell, on a face, or on a
    /// diagonal of the reference split of a quad/hex.
    pub vertex_edges: Vec<Option<[usize; 2]>>,
    /// For each vertex: the global node it sits on exactly, if any.
    pub vertex_nodes: Vec<Option<usize>>,
    /// For each vertex: it lies on φt = 0 (a point of the front).
    pub vertex_on_front: Vec<bool>,
}

/// The cut of one Cut or Front cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellCut {
    pub cell: usize,
    pub status: CellStatus,
    /// Integration sub-cells covering the cell (both sides; zero-measure ones dropped).
    pub subcells: Vec<SubCell>,
    /// Its facets, as a range into [`CrackCut::facets`].
    pub facets: Range<usize>,
    /// Its front pieces, as a range into [`CrackCut::front`].
    pub front: Range<usize>,
}

/// A piece of the crack front inside one cell.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontPiece {
    pub cell: usize,
    /// Physical points: 1 (2D tip) or 2 (3D front segment).
    pub points: Vec<[f64; 3]>,
    /// The same points in the parent reference coordinates.
    pub points_ref: Vec<[f64; 3]>,
}

/// The cut of a whole mesh by one crack.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackCut {
    /// Dimension of the mesh (2 or 3).
    pub dim: usize,
    /// Status of every mesh cell.
    pub status: Vec<CellStatus>,
    /// Only Cut and Front cells, sorted by cell id.
    pub cut_cells: Vec<CellCut>,
    /// All facets, grouped by cell in the order of `cut_cells`.
    pub facets: Vec<Facet>,
    /// All front pieces, grouped by cell in the order of `cut_cells`.
    pub front: Vec<FrontPiece>,
    /// The options of the cut, for [`subcell_quadrature`] (`subcell_quadrature(sc, cut.dim, &cut.opts)`).
    pub opts: CutOptions,
}

impl CrackCut {
    /// The cut of `cell` if it is Cut or Front (binary search).
    pub fn cell_cut(&self, cell: usize) -> Option<&CellCut> {
        self.cut_cells.binary_search_by_key(&cell, |c| c.cell).ok().map(|i| &self.cut_cells[i])
    }
    /// The facets of `cell` (empty when it has none).
    pub fn cell_facets(&self, cell: usize) -> &[Facet] {
        self.cell_cut(cell).map_or(&[], |c| &self.facets[c.facets.clone()])
    }
    /// Σ facet measures: the crack length (2D) or area (3D) inside the mesh.
    pub fn crack_measure(&self) -> f64 {
        self.facets.iter().map(|f| f.measure).sum()
    }
    /// Σ front piece lengths (3D; 0 in 2D).
    pub fn front_length(&self) -> f64 {
        self.front
            .iter()
            .filter(|p| p.points.len() == 2)
            .map(|p| simplex::norm(simplex::sub(p.points[1], p.points[0])))
            .sum()
    }
}

/// Quadrature choices for the sub-cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CutOptions {
    /// Gauss degree on sub-cells (default 2).
    pub subcell_degree: usize,
    /// Degree of the almost-polar (collapsed) rule on sub-cells touching the front
    /// (default 8).
    pub front_degree: usize,
}

impl Default for CutOptions {
    fn default() -> Self {
        CutOptions { subcell_degree: 2, front_degree: 8 }
    }
}

/// What can be wrong with the input of [`cut_crack`].
#[derive(Debug, Clone, PartialEq)]
pub enum CutError {
    /// A level-set array whose length is not the number of mesh nodes.
    WrongLength { which: &'static str, len: usize, nodes: usize },
    /// A NaN or infinite nodal value.
    NotFinite { which: &'static str, node: usize, value: f64 },
    /// A cell referencing a node that does not exist.
    BadNodeIndex { cell: usize, node: usize },
    /// A cell whose dimension is not the mesh's.
    MixedDimension { cell: usize },
}

impl fmt::Display for CutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CutError::WrongLength { which, len, nodes } => {
                write!(f, "level set {which} has {len} values but the mesh has {nodes} nodes")
            }
            CutError::NotFinite { which, node, value } => {
                write!(f, "level set {which} is not finite at node {node} (value {value})")
            }
            CutError::BadNodeIndex { cell, node } => {
                write!(f, "cell {cell} references node {node}, which does not exist")
            }
            CutError::MixedDimension { cell } => write!(f, "cell {cell} has a dimension other than the mesh's"),
        }
    }
}

impl std::error::Error for CutError {}

fn check_values(which: &'static str, v: &[f64], nodes: usize) -> Result<(), CutError> {
    if v.len() != nodes {
        return Err(CutError::WrongLength { which, len: v.len(), nodes });
    }
    match v.iter().position(|x| !x.is_finite()) {
        Some(node) => Err(CutError::NotFinite { which, node, value: v[node] }),
        None => Ok(()),
    }
}

/// The sub-cells of a 3D cell that the crack does not cut but whose boundary holds a piece
/// of its front (a crack lying exactly in a face plane of the mesh: the front belongs to
/// the cell on the − side, yet the tip functions of the cell on the + side are singular on
/// its face). Split by φt like a front cell, with the singular vertices and edges that
/// [`subcell_quadrature`] collapses onto; `None` for any other cell. `lsn`, `lst`: nodal
/// values (checked by [`cut_crack`]).
pub fn front_on_boundary_subcells(mesh: &Mesh, cell: usize, lsn: &[f64], lst: &[f64]) -> Option<Vec<SubCell>> {
    cells::front_on_boundary_subcells(mesh, cell, lsn, lst)
}

/// Cuts every cell of `mesh` by the crack `ls` (see the module doc for the conventions).
/// Cells are processed in parallel; an uncut cell costs only its status.
pub fn cut_crack(mesh: &Mesh, ls: &NodalLevelSets, opts: &CutOptions) -> Result<CrackCut, CutError> {
    let nodes = mesh.nodes.len();
    check_values("lsn", &ls.lsn, nodes)?;
    if let Some(t) = &ls.lst {
        check_values("lst", t, nodes)?;
    }
    for (c, cell) in mesh.cells.iter().enumerate() {
        if cell.kind.dim() != mesh.dim {
            return Err(CutError::MixedDimension { cell: c });
        }
        if let Some(&node) = cell.nodes().iter().find(|&&n| n >= nodes) {
            return Err(CutError::BadNodeIndex { cell: c, node });
        }
    }
    let lst = ls.lst.as_deref();
    let outs: Vec<Option<cells::CellOut>> =
        (0..mesh.cells.len()).into_par_iter().map(|c| cells::cut_cell(mesh, c, &ls.lsn, lst)).collect();
    let mut out = CrackCut {
        dim: mesh.dim,
        status: Vec::with_capacity(outs.len()),
        cut_cells: vec![],
        facets: vec![],
        front: vec![],
        opts: *opts,
    };
    for (c, o) in outs.into_iter().enumerate() {
        match o {
            None => out.status.push(CellStatus::Uncut),
            Some(o) => {
                out.status.push(o.status);
                let f0 = out.facets.len();
                out.facets.extend(o.facets);
                let p0 = out.front.len();
                out.front.extend(o.front);
                out.cut_cells.push(CellCut {
                    cell: c,
                    status: o.status,
                    subcells: o.subcells,
                    facets: f0..out.facets.len(),
                    front: p0..out.front.len(),
                });
            }
        }
    }
    Ok(out)
}
