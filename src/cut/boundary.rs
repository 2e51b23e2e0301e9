//! The parts of a crack's cut that lie on the boundary of the body, and their removal.
//!
//! Entry points: [`cut_in_body`] (sample, snap and cut a crack shape, carry its front
//! through the surface where it lies on or outside it, then trim), [`BodyBoundary`] (the
//! boundary faces of a mesh, indexed by node), [`trim_to_body`].
//!
//! A crack meets the body only where it has material on both sides. Two pieces of a cut
//! have none and are removed by [`trim_to_body`]:
//! - **front pieces on the boundary**: a 2D tip, or a 3D front segment, lying in a
//!   boundary face (a segment crack drawn to end exactly on an edge, a rectangle whose side
//!   lies in a face). Material exists on the crack side only, so the crack reaches the
//!   surface there: it is an edge crack, not a tip. A Front cell left without front pieces
//!   becomes a Cut cell (its sub-cells lose their `ahead` and singular marks).
//! - **facets on the boundary**: a crack lying in a boundary face (φn = 0 on the face)
//!   cuts nothing. A Cut cell left without facets becomes Uncut.
//!
//! "Lies on a boundary face" is tested in physical space against the boundary faces that
//! share a node with the cell, with a tolerance of 1e-6 × the cell's edge length (the
//! default snap tolerance of the level sets).

use super::{CellStatus, CrackCut, CutOptions, FrontPiece};
use crate::element::FaceType;
use crate::levelset::{self, CrackShape, LevelSetError, NodalLevelSets};
use crate::mesh::{Face, Mesh};

/// Relative tolerance of the on-boundary tests (× the cell's edge length).
pub const ON_BOUNDARY_TOL: f64 = 1e-6;

/// The boundary faces of a mesh, with the faces touching each node.
#[derive(Debug, Clone)]
pub struct BodyBoundary {
    pub faces: Vec<Face>,
    /// Faces touching node `n`: `face_ids[offsets[n]..offsets[n + 1]]`.
    offsets: Vec<usize>,
    face_ids: Vec<usize>,
}

impl BodyBoundary {
    pub fn new(mesh: &Mesh) -> BodyBoundary {
        let faces = mesh.boundary_faces();
        let nn = mesh.n_nodes();
        let mut offsets = vec![0usize; nn + 1];
        for f in &faces {
            for &n in f.nodes() {
                offsets[n + 1] += 1;
            }
        }
        for n in 0..nn {
            offsets[n + 1] += offsets[n];
        }
        let mut fill = offsets.clone();
        let mut face_ids = vec![0; offsets[nn]];
        for (k, f) in faces.iter().enumerate() {
            for &n in f.nodes() {
                face_ids[fill[n]] = k;
                fill[n] += 1;
            }
        }
        BodyBoundary { faces, offsets, face_ids }
    }

    /// Whether a node lies on the boundary.
    pub fn node_on_boundary(&self, n: usize) -> bool {
        self.offsets[n] != self.offsets[n + 1]
    }

    /// Whether all `points` lie on one boundary face that shares a node with `cell`
    /// (within [`ON_BOUNDARY_TOL`] × the cell's edge length).
    pub fn on_boundary(&self, mesh: &Mesh, cell: usize, points: &[[f64; 3]]) -> bool {
        if points.is_empty() {
            return false;
        }
        let tol = ON_BOUNDARY_TOL * mesh.cell_edge_length(cell);
        let mut seen: Vec<usize> = vec![];
        for &n in mesh.cells[cell].nodes() {
            for &k in &self.face_ids[self.offsets[n]..self.offsets[n + 1]] {
                if seen.contains(&k) {
                    continue;
                }
                seen.push(k);
                let f = &self.faces[k];
                if points.iter().all(|p| distance_to_face(mesh, f, p) <= tol) {
                    return true;
                }
            }
        }
        false
    }
}

/// Distance from `p` to a boundary face (a segment, a triangle, or a quad taken as two
/// triangles).
fn distance_to_face(mesh: &Mesh, f: &Face, p: &[f64; 3]) -> f64 {
    let x = |i: usize| mesh.nodes[f.nodes[i]];
    match f.kind {
        FaceType::Line2 => distance_to_segment(p, &x(0), &x(1)),
        FaceType::Tri3 => distance_to_triangle(p, &x(0), &x(1), &x(2)),
        FaceType::Quad4 => {
            distance_to_triangle(p, &x(0), &x(1), &x(2)).min(distance_to_triangle(p, &x(0), &x(2), &x(3)))
        }
    }
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = sub(a, b);
    dot(&d, &d).sqrt()
}

/// Distance from `p` to the segment [a, b].
pub fn distance_to_segment(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(&ab, &ab);
    let t = if l2 > 0.0 { (dot(&sub(p, a), &ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    let q = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
    dist(p, &q)
}

/// Distance from `p` to the triangle (a, b, c) (closest point by regions, Ericson,
/// Real-Time Collision Detection §5.1.5).
pub fn distance_to_triangle(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(&ab, &ap);
    let d2 = dot(&ac, &ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return dist(p, a);
    }
    let bp = sub(p, b);
    let d3 = dot(&ab, &bp);
    let d4 = dot(&ac, &bp);
    if d3 >= 0.0 && d4 <= d3 {
        return dist(p, b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return distance_to_segment(p, a, b);
    }
    let cp = sub(p, c);
    let d5 = dot(&ab, &cp);
    let d6 = dot(&ac, &cp);
    if d6 >= 0.0 && d5 <= d6 {
        return dist(p, c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return distance_to_segment(p, a, c);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return distance_to_segment(p, b, c);
    }
    let denom = va + vb + vc;
    if denom.abs() <= 0.0 {
        return distance_to_segment(p, a, b).min(distance_to_segment(p, a, c)).min(distance_to_segment(p, b, c));
    }
    let v = vb / denom;
    let w = vc / denom;
    let q = [a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w];
    dist(p, &q)
}

/// Whether a front piece lies on the boundary of the body (see the module doc).
pub fn front_piece_on_boundary(mesh: &Mesh, boundary: &BodyBoundary, piece: &FrontPiece) -> bool {
    boundary.on_boundary(mesh, piece.cell, &piece.points)
}

/// What [`trim_to_body`] removed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Trimmed {
    /// Front pieces lying on the boundary.
    pub front_pieces: usize,
    /// Facets lying on the boundary.
    pub facets: usize,
    /// Cells whose status changed (Front → Cut, or → Uncut).
    pub cells: usize,
}

/// Removes from `cut` the front pieces and facets that lie on the boundary of the body
/// and updates the cell statuses (see the module doc).
pub fn trim_to_body(mesh: &Mesh, boundary: &BodyBoundary, cut: &mut CrackCut) -> Trimmed {
    let mut t = Trimmed::default();
    let old_facets = std::mem::take(&mut cut.facets);
    let old_front = std::mem::take(&mut cut.front);
    let old_cells = std::mem::take(&mut cut.cut_cells);
    for mut cc in old_cells {
        // Only cells touching the boundary can hold boundary pieces.
        let touches = mesh.cells[cc.cell].nodes().iter().any(|&n| boundary.node_on_boundary(n));
        let f0 = cut.facets.len();
        let mut facets_removed = false;
        for f in &old_facets[cc.facets.clone()] {
            if touches && boundary.on_boundary(mesh, cc.cell, &f.vertices) {
                t.facets += 1;
                facets_removed = true;
            } else {
                cut.facets.push(f.clone());
            }
        }
        let p0 = cut.front.len();
        let mut front_removed = false;
        for p in &old_front[cc.front.clone()] {
            if touches && front_piece_on_boundary(mesh, boundary, p) {
                t.front_pieces += 1;
                front_removed = true;
            } else {
                cut.front.push(p.clone());
            }
        }
        cc.facets = f0..cut.facets.len();
        cc.front = p0..cut.front.len();
        let before = cc.status;
        if cc.status == CellStatus::Front && front_removed && cc.front.is_empty() {
            cc.status = CellStatus::Cut;
        }
        if (facets_removed || cc.status != before) && cc.facets.is_empty() {
            cc.status = CellStatus::Uncut;
        }
        if cc.status != before {
            t.cells += 1;
            cut.status[cc.cell] = cc.status;
            for sc in &mut cc.subcells {
                sc.ahead = false;
                sc.singular_vertex = None;
                sc.singular_edge = None;
            }
        }
        if cc.status != CellStatus::Uncut {
            cut.cut_cells.push(cc);
        }
    }
    t
}

/// Why [`cut_in_body`] failed.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyCutError {
    LevelSet(crate::levelset::LevelSetError),
    Cut(super::CutError),
    /// Every facet of the crack lies on the boundary of the body (φn = 0 on boundary
    /// faces): it has material on one side only and cuts nothing.
    OnBoundary {
        facets: usize,
    },
}

impl std::fmt::Display for BodyCutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BodyCutError::LevelSet(e) => write!(f, "{e}"),
            BodyCutError::Cut(e) => write!(f, "{e}"),
            BodyCutError::OnBoundary { facets } => write!(
                f,
                "the crack lies on the boundary of the body ({facets} facets, all on boundary faces): with material on one side only it cuts nothing; move it inside the body, or remove it (the boundary is already a free surface)"
            ),
        }
    }
}

impl std::error::Error for BodyCutError {}

/// A crack cut against the body: the shape used (with front parts carried through the
/// surface), its snapped level sets, its trimmed cut, and what was changed.
#[derive(Debug, Clone)]
pub struct BodyCut {
    pub shape: CrackShape,
    pub levelsets: NodalLevelSets,
    pub cut: CrackCut,
    /// The front parts ([`CrackShape::n_front_parts`]) carried through the surface.
    pub extended: Vec<bool>,
    pub trimmed: Trimmed,
}

fn sample_and_cut(
    shape: &CrackShape,
    mesh: &Mesh,
    snap: f64,
    opts: &CutOptions,
) -> Result<(NodalLevelSets, CrackCut), BodyCutError> {
    let mut ls = levelset::sample(shape, mesh).map_err(BodyCutError::LevelSet)?;
    levelset::snap(&mut ls, mesh, snap);
    levelset::check_crack_in_mesh(&ls, mesh).map_err(BodyCutError::LevelSet)?;
    let cut = super::cut_crack(mesh, &ls, opts).map_err(BodyCutError::Cut)?;
    Ok((ls, cut))
}

/// Samples, snaps (relative tolerance `snap`, see [`levelset::snap`]) and cuts the crack
/// `shape`, then makes the result describe the crack *in the body*:
///
/// 1. A segment end or a rectangle side with no front inside the body (it lies on the
///    surface, or outside it; a 3D front piece counts for a side when it runs along it)
///    is pushed outward ([`CrackShape::with_parts_extended`]),
///    so that the level sets inside the body are those of a crack running through the
///    surface there (an edge crack drawn as a segment ending on the edge is then the
///    `half_line` crack exactly). The extension is as long as the body's bounding-box
///    diagonal, and divided by four until it adds no cut cell away from the crack's own
///    mouth on the surface (a crack leaving a hole must not re-enter the body across it).
/// 2. The front pieces and facets left on the boundary are removed ([`trim_to_body`]).
///
/// Errors: the level-set errors of [`levelset::sample`] and
/// [`levelset::check_crack_in_mesh`] (with [`LevelSetError::TooSmall`] for a crack inside
/// the body but between its nodes), [`BodyCutError::OnBoundary`] for a crack lying
/// entirely on the boundary.
pub fn cut_in_body(
    shape: &CrackShape,
    mesh: &Mesh,
    boundary: &BodyBoundary,
    snap: f64,
    opts: &CutOptions,
) -> Result<BodyCut, BodyCutError> {
    let s0 = shape.normalised().map_err(BodyCutError::LevelSet)?;
    let (ls0, cut0) = match sample_and_cut(&s0, mesh, snap, opts) {
        Err(BodyCutError::LevelSet(LevelSetError::OutsideMesh { has_front: true })) => {
            return Err(BodyCutError::LevelSet(
                too_small(&s0, mesh).unwrap_or(LevelSetError::OutsideMesh { has_front: true }),
            ))
        }
        r => r?,
    };
    let n = s0.n_front_parts();
    let mut extended = vec![false; n];
    let mut best = (s0.clone(), ls0, cut0);
    if n > 0 {
        // Parts holding a front piece inside the body.
        let mut genuine = vec![false; n];
        for p in &best.2.front {
            if front_piece_on_boundary(mesh, boundary, p) {
                continue;
            }
            let k = p.points.len().max(1) as f64;
            let mut mid = [0.0; 3];
            for x in &p.points {
                for i in 0..3 {
                    mid[i] += x[i] / k;
                }
            }
            if let Some(part) = s0.front_part_of(mid, 0.25 * mesh.cell_edge_length(p.cell)) {
                // A 3D piece counts for a side only if it runs along it (the pieces near
                // a corner, where the front bends between two sides, do not).
                if let ([a, b], Some(t)) = (p.points.as_slice(), s0.front_part_tangent(part)) {
                    let d = sub(b, a);
                    let l = dot(&d, &d).sqrt();
                    if l == 0.0 || dot(&d, &t).abs() < 0.9 * l {
                        continue;
                    }
                }
                genuine[part] = true;
            }
        }
        // A part the body does not extend beyond (no node near the crack's plane lies
        // beyond it, within its extent) has no front in the body, whatever pieces the
        // nodal interpolation makes near it: a rectangle side just outside a face (by less
        // than a cell) bends the front of the neighbouring side in the corner cells, and
        // such a bent piece must not count for it (an edge crack with its sides h/12
        // outside the faces gave K_I 11% low with a spurious front point).
        let h = levelset::node_sizes(mesh);
        let mut beyond = vec![false; n];
        for (v, x) in mesh.nodes.iter().enumerate() {
            let hv = h[v];
            if !hv.is_finite() || best.1.lsn.get(v).is_none_or(|p| p.abs() > 2.0 * hv) {
                continue;
            }
            for (part, b) in beyond.iter_mut().enumerate() {
                if let Some((d, within)) = s0.beyond_front_part(*x, part) {
                    *b |= within && d > ON_BOUNDARY_TOL * hv;
                }
            }
        }
        for (g, b) in genuine.iter_mut().zip(&beyond) {
            *g &= *b;
        }
        let flags: Vec<bool> = genuine.iter().map(|g| !g).collect();
        if flags.iter().any(|&f| f) {
            let (lo, hi) = mesh.bounding_box();
            let diag = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
            let base = &best.2;
            let mut near_base = vec![false; mesh.n_nodes()];
            for cc in &base.cut_cells {
                for &v in mesh.cells[cc.cell].nodes() {
                    near_base[v] = true;
                }
            }
            let mut ext = diag;
            let mut found = None;
            for _ in 0..30 {
                let s1 = s0.with_parts_extended(&flags, ext);
                let (ls1, cut1) = sample_and_cut(&s1, mesh, snap, opts)?;
                // A new cut cell must touch the surface and the original crack's cells.
                let ok = cut1.cut_cells.iter().all(|cc| {
                    base.status[cc.cell] != CellStatus::Uncut || {
                        let v = mesh.cells[cc.cell].nodes();
                        v.iter().any(|&a| boundary.node_on_boundary(a)) && v.iter().any(|&a| near_base[a])
                    }
                });
                if ok {
                    found = Some((s1, ls1, cut1));
                    break;
                }
                ext *= 0.25;
            }
            if let Some(f) = found {
                best = f;
                extended = flags;
            }
        }
    }
    let (shape, levelsets, mut cut) = best;
    let trimmed = trim_to_body(mesh, boundary, &mut cut);
    if trimmed.facets > 0 && cut.facets.is_empty() {
        return Err(BodyCutError::OnBoundary { facets: trimmed.facets });
    }
    Ok(BodyCut { shape, levelsets, cut, extended, trimmed })
}

/// [`LevelSetError::TooSmall`] when the crack's centre lies in a cell of the mesh (the
/// crack is inside the body but between its nodes), with the largest edge length of the
/// cells whose bounding box holds the centre.
fn too_small(shape: &CrackShape, mesh: &Mesh) -> Option<LevelSetError> {
    let (c, length) = shape.centre_and_size()?;
    let dim = mesh.dim;
    let mut cell = 0.0f64;
    for k in 0..mesh.n_cells() {
        let v = mesh.cells[k].nodes();
        let inside = (0..dim).all(|i| {
            let lo = v.iter().map(|&a| mesh.nodes[a][i]).fold(f64::INFINITY, f64::min);
            let hi = v.iter().map(|&a| mesh.nodes[a][i]).fold(f64::NEG_INFINITY, f64::max);
            c[i] >= lo && c[i] <= hi
        });
        if inside {
            cell = cell.max(mesh.cell_edge_length(k));
        }
    }
    (cell > 0.0).then_some(LevelSetError::TooSmall { length, cell })
}
