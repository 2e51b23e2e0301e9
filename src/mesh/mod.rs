//! The mesh: nodes, cells, named groups, validation, structured generators and the
//! Gmsh reader.
//!
//! Entry points: [`Mesh`], [`generate::rectangle`], [`generate::box_mesh`],
//! [`gmsh::read_msh`].
//!
//! Coordinates are stored as `[f64; 3]` in 2D too (z = 0): one storage for both
//! dimensions, the dimension is the value [`Mesh::dim`]. Groups are named sets:
//! cell groups (materials, body forces), face groups (tractions, pressures) and
//! node groups (Dirichlet conditions). Every face group also yields its node set.

pub mod generate;
pub mod gmsh;

use crate::element::{self, CellType, FaceType, MAX_NODES};
use crate::geometry::quadrature::QuadratureRule;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::fmt;

/// One volume cell: its type and node indices (only the first `kind.n_nodes()` are used).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cell {
    pub kind: CellType,
    pub nodes: [usize; MAX_NODES],
}

impl Cell {
    pub fn new(kind: CellType, nodes: &[usize]) -> Cell {
        let mut n = [usize::MAX; MAX_NODES];
        n[..nodes.len()].copy_from_slice(nodes);
        Cell { kind, nodes: n }
    }
    pub fn nodes(&self) -> &[usize] {
        &self.nodes[..self.kind.n_nodes()]
    }
}

/// One boundary face (a segment in 2D, a triangle or quad in 3D).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Face {
    pub kind: FaceType,
    pub nodes: [usize; 4],
}

impl Face {
    pub fn new(kind: FaceType, nodes: &[usize]) -> Face {
        let mut n = [usize::MAX; 4];
        n[..nodes.len()].copy_from_slice(nodes);
        Face { kind, nodes: n }
    }
    pub fn nodes(&self) -> &[usize] {
        &self.nodes[..self.kind.n_nodes()]
    }
}

/// The degree-2 rule of a cell type (cell measures and mesh checks), built once.
fn measure_rule(kind: CellType) -> std::borrow::Cow<'static, QuadratureRule> {
    kind.cached_quadrature(2)
}

/// A finite element mesh of one dimension (2 or 3).
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub dim: usize,
    pub nodes: Vec<[f64; 3]>,
    pub cells: Vec<Cell>,
    /// Named cell sets (materials, body forces, output group ids).
    pub cell_groups: BTreeMap<String, Vec<usize>>,
    /// Named boundary face sets (tractions, pressures; their nodes for Dirichlet).
    pub face_groups: BTreeMap<String, Vec<Face>>,
    /// Named node sets (Dirichlet conditions, point constraints).
    pub node_groups: BTreeMap<String, Vec<usize>>,
}

/// What can be wrong with a mesh or a request on it.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    /// A group name that the mesh does not have; lists those it has.
    UnknownGroup { name: String, available: Vec<String> },
    /// A cell with a non-positive or vanishing Jacobian (0-based id).
    InvertedCell { cell: usize, det: f64 },
    /// A cell that references a node that does not exist.
    BadNodeIndex { cell: usize, node: usize },
    /// Cells of a dimension other than the mesh's.
    MixedDimension { cell: usize },
    /// A mesh without cells.
    Empty,
    /// A file problem (format, version, I/O), with a message saying which.
    File(String),
    /// Bad generator parameters.
    Generator(String),
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::UnknownGroup { name, available } => {
                write!(f, "unknown group '{name}'; the mesh has: {}", available.join(", "))
            }
            MeshError::InvertedCell { cell, det } => write!(
                f,
                "cell {cell} is inverted or degenerate (Jacobian determinant {det:.3e}); fix the node order or the mesh"
            ),
            MeshError::BadNodeIndex { cell, node } => {
                write!(f, "cell {cell} references node {node}, which does not exist")
            }
            MeshError::MixedDimension { cell } => write!(f, "cell {cell} has a dimension other than the mesh's"),
            MeshError::Empty => write!(f, "the mesh has no cells"),
            MeshError::File(m) => write!(f, "{m}"),
            MeshError::Generator(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for MeshError {}

/// The kind of group a name refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupKind {
    Cells,
    Faces,
    Nodes,
}

impl Mesh {
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// Appends `part` as a separate body (no node shared), moved by `offset`: its groups
    /// are renamed `<prefix>.<group>` and its cells also form the cell group `<prefix>`.
    /// The dimensions must agree (an empty mesh takes the part's).
    pub fn append_part(&mut self, part: &Mesh, prefix: &str, offset: [f64; 3]) {
        if self.cells.is_empty() && self.nodes.is_empty() {
            self.dim = part.dim;
        }
        let n0 = self.nodes.len();
        let c0 = self.cells.len();
        self.nodes.extend(part.nodes.iter().map(|x| [x[0] + offset[0], x[1] + offset[1], x[2] + offset[2]]));
        for c in &part.cells {
            let nodes: Vec<usize> = c.nodes().iter().map(|&a| a + n0).collect();
            self.cells.push(Cell::new(c.kind, &nodes));
        }
        for (name, cells) in &part.cell_groups {
            self.cell_groups.insert(format!("{prefix}.{name}"), cells.iter().map(|&c| c + c0).collect());
        }
        self.cell_groups.insert(prefix.to_string(), (c0..self.cells.len()).collect());
        for (name, faces) in &part.face_groups {
            let moved = faces
                .iter()
                .map(|f| {
                    let nodes: Vec<usize> = f.nodes().iter().map(|&a| a + n0).collect();
                    Face::new(f.kind, &nodes)
                })
                .collect();
            self.face_groups.insert(format!("{prefix}.{name}"), moved);
        }
        for (name, nodes) in &part.node_groups {
            self.node_groups.insert(format!("{prefix}.{name}"), nodes.iter().map(|&a| a + n0).collect());
        }
    }

    /// All group names of every kind, sorted, for error messages.
    pub fn group_names(&self) -> Vec<String> {
        let mut v: Vec<String> =
            self.cell_groups.keys().chain(self.face_groups.keys()).chain(self.node_groups.keys()).cloned().collect();
        v.push("all".into());
        v.sort();
        v.dedup();
        v
    }

    fn unknown(&self, name: &str) -> MeshError {
        MeshError::UnknownGroup { name: name.to_string(), available: self.group_names() }
    }

    /// Which kinds of group carry this name (`all` is the whole mesh).
    pub fn group_kinds(&self, name: &str) -> Vec<GroupKind> {
        let mut k = vec![];
        if self.cell_groups.contains_key(name) || name == "all" {
            k.push(GroupKind::Cells);
        }
        if self.face_groups.contains_key(name) {
            k.push(GroupKind::Faces);
        }
        if self.node_groups.contains_key(name) || name == "all" {
            k.push(GroupKind::Nodes);
        }
        k
    }

    /// Cells of a cell group; `all` is every cell.
    pub fn group_cells(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        if let Some(c) = self.cell_groups.get(name) {
            return Ok(c.clone());
        }
        if name == "all" {
            return Ok((0..self.cells.len()).collect());
        }
        Err(self.unknown(name))
    }

    /// Faces of a face group.
    pub fn group_faces(&self, name: &str) -> Result<&[Face], MeshError> {
        self.face_groups.get(name).map(|v| v.as_slice()).ok_or_else(|| self.unknown(name))
    }

    /// Nodes of a group of any kind (sorted, unique): a node group as is, the nodes of
    /// a face group or of a cell group; `all` is every node.
    pub fn group_nodes(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let mut v: Vec<usize> = if let Some(n) = self.node_groups.get(name) {
            n.clone()
        } else if let Some(f) = self.face_groups.get(name) {
            f.iter().flat_map(|f| f.nodes().iter().copied()).collect()
        } else if let Some(c) = self.cell_groups.get(name) {
            c.iter().flat_map(|&c| self.cells[c].nodes().iter().copied()).collect()
        } else if name == "all" {
            (0..self.nodes.len()).collect()
        } else {
            return Err(self.unknown(name));
        };
        v.sort_unstable();
        v.dedup();
        Ok(v)
    }

    /// Coordinates of a cell's nodes, into a caller buffer; returns the node count.
    #[inline]
    pub fn cell_coords(&self, c: usize, out: &mut [[f64; 3]; MAX_NODES]) -> usize {
        let cell = &self.cells[c];
        let nn = cell.kind.n_nodes();
        for a in 0..nn {
            out[a] = self.nodes[cell.nodes[a]];
        }
        nn
    }

    /// A characteristic mesh size: the mean cell measure to the power 1/dim.
    pub fn typical_size(&self) -> f64 {
        if self.cells.is_empty() {
            return 1.0;
        }
        let measures: Vec<f64> = (0..self.cells.len()).into_par_iter().map(|c| self.cell_measure(c)).collect();
        let total: f64 = measures.iter().sum();
        (total / self.cells.len() as f64).powf(1.0 / self.dim as f64)
    }

    /// Mean edge length of a cell.
    pub fn cell_edge_length(&self, c: usize) -> f64 {
        let cell = &self.cells[c];
        let edges = cell.kind.edges();
        let total: f64 = edges
            .iter()
            .map(|[a, b]| {
                let (p, q) = (self.nodes[cell.nodes[*a]], self.nodes[cell.nodes[*b]]);
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
            })
            .sum();
        total / edges.len() as f64
    }

    /// Bounding box `(min, max)` of the nodes.
    pub fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.nodes {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        (lo, hi)
    }

    /// Area (2D) or volume (3D) of a cell, by quadrature of `det J`.
    pub fn cell_measure(&self, c: usize) -> f64 {
        let kind = self.cells[c].kind;
        let mut xs = [[0.0; 3]; MAX_NODES];
        let nn = self.cell_coords(c, &mut xs);
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        let mut g = [[0.0; 3]; MAX_NODES];
        let mut s = 0.0;
        for (xi, w) in measure_rule(kind).iter() {
            element::shape(kind, xi, &mut n, &mut dn);
            if let Ok(det) = element::physical_gradients(self.dim, &xs[..nn], &dn[..nn], &mut g) {
                s += w * det;
            }
        }
        s
    }

    /// Checks the mesh: node indices in range, cell dimension equal to the mesh's, and a
    /// positive Jacobian at the nodes and Gauss points of every cell (reports the first
    /// bad cell by its 0-based id).
    pub fn validate(&self) -> Result<(), MeshError> {
        if self.cells.is_empty() {
            return Err(MeshError::Empty);
        }
        // In parallel; the error reported is that of the first bad cell.
        let check = |c: usize| -> Result<(), MeshError> {
            let cell = &self.cells[c];
            if cell.kind.dim() != self.dim {
                return Err(MeshError::MixedDimension { cell: c });
            }
            for &v in cell.nodes() {
                if v >= self.nodes.len() {
                    return Err(MeshError::BadNodeIndex { cell: c, node: v });
                }
            }
            let mut n = [0.0; MAX_NODES];
            let mut dn = [[0.0; 3]; MAX_NODES];
            let mut g = [[0.0; 3]; MAX_NODES];
            let mut xs = [[0.0; 3]; MAX_NODES];
            let nn = self.cell_coords(c, &mut xs);
            let rule = measure_rule(cell.kind);
            let pts = cell.kind.reference_nodes().iter().chain(rule.points.iter());
            for xi in pts {
                element::shape(cell.kind, xi, &mut n, &mut dn);
                if let Err(e) = element::physical_gradients(self.dim, &xs[..nn], &dn[..nn], &mut g) {
                    return Err(MeshError::InvertedCell { cell: c, det: e.det });
                }
            }
            Ok(())
        };
        match (0..self.cells.len()).into_par_iter().find_map_first(|c| check(c).err()) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Cells around each node, in compressed form: the cells of node `n` are
    /// `cells[offsets[n]..offsets[n + 1]]` (ascending).
    pub fn node_cells(&self) -> (Vec<usize>, Vec<usize>) {
        let mut offsets = vec![0usize; self.nodes.len() + 1];
        for c in &self.cells {
            for &n in c.nodes() {
                offsets[n + 1] += 1;
            }
        }
        for n in 0..self.nodes.len() {
            offsets[n + 1] += offsets[n];
        }
        let mut fill = offsets.clone();
        let mut cells = vec![0; offsets[self.nodes.len()]];
        for (ci, c) in self.cells.iter().enumerate() {
            for &n in c.nodes() {
                cells[fill[n]] = ci;
                fill[n] += 1;
            }
        }
        (offsets, cells)
    }

    /// Boundary faces of the mesh (faces that belong to exactly one cell), oriented
    /// outward. Used to build face groups from coordinate predicates.
    pub fn boundary_faces(&self) -> Vec<Face> {
        // Every cell face with its sorted node key; faces whose key appears once are on the
        // boundary. A sort of fixed-size keys: no allocation per face, no hashing.
        // The faces are bucketed by their smallest node (a counting sort), and compared
        // within their bucket only: linear time.
        let mut all: Vec<([usize; 4], Face)> = Vec::with_capacity(self.cells.len() * 6);
        for cell in &self.cells {
            for (ft, loc) in cell.kind.faces() {
                let mut nodes = [usize::MAX; 4];
                for (i, &a) in loc.iter().enumerate() {
                    nodes[i] = cell.nodes[a];
                }
                let mut key = nodes;
                key[..loc.len()].sort_unstable();
                all.push((key, Face::new(*ft, &nodes[..loc.len()])));
            }
        }
        let nn = self.nodes.len();
        let mut start = vec![0usize; nn + 2];
        for (key, _) in &all {
            start[key[0].min(nn) + 1] += 1;
        }
        for k in 0..=nn {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut bucketed = vec![0u32; all.len()];
        for (i, (key, _)) in all.iter().enumerate() {
            let b = key[0].min(nn);
            bucketed[fill[b]] = i as u32;
            fill[b] += 1;
        }
        drop(fill);
        let mut faces: Vec<Face> = (0..=nn)
            .into_par_iter()
            .flat_map_iter(|b| {
                let bucket = &bucketed[start[b]..start[b + 1]];
                let all = &all;
                bucket.iter().filter_map(move |&i| {
                    let key = &all[i as usize].0;
                    let shared = bucket.iter().any(|&j| j != i && all[j as usize].0 == *key);
                    (!shared).then_some(all[i as usize].1)
                })
            })
            .collect();
        faces.sort_by_key(|f| f.nodes);
        faces
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_group_lists_available() {
        let m = generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [2, 2]).unwrap();
        let e = m.group_nodes("lefty").unwrap_err();
        let s = e.to_string();
        assert!(s.contains("lefty") && s.contains("left") && s.contains("top"), "{s}");
    }

    #[test]
    fn inverted_cell_reported_with_id() {
        let mut m = generate::rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [2, 2]).unwrap();
        m.cells[3].nodes.swap(0, 1);
        assert!(matches!(m.validate(), Err(MeshError::InvertedCell { cell: 3, .. })));
    }

    #[test]
    fn boundary_faces_of_a_box() {
        let m = generate::box_mesh(CellType::Hex8, [0.0; 3], [1.0; 3], [2, 3, 4]).unwrap();
        assert_eq!(m.boundary_faces().len(), 2 * (2 * 3 + 3 * 4 + 2 * 4));
        let t = generate::box_mesh(CellType::Tet4, [0.0; 3], [1.0; 3], [2, 3, 4]).unwrap();
        assert_eq!(t.boundary_faces().len(), 4 * (2 * 3 + 3 * 4 + 2 * 4));
    }
}
