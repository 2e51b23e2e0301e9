//! Meshed contact pairs (`[[contact_pairs]]`): the slave and master boundary surfaces of
//! separately meshed bodies as facets, the multiplier space on the slave surface, and the
//! segment-to-segment integration rule. The points, the pairing, the law, the kernel and
//! the loops are those of the cracks: a pair is one more [`super::points::ContactCrack`]
//! whose facets are the slave faces and whose master lip is the master faces.
//!
//! Entry points: [`PairSurfaces::build`], [`PairSurfaces::segment_rule`],
//! [`PairSurfaces::rigid_rows`].
//!
//! ```text
//! slave face (body A, outward normal n)    master face (body B)
//! facet: the face in its cell              x⁺(Y) = Y + u(Y), Y on the master faces
//! jump:  ⟦u⟧ = x⁺(Y) − x⁻(X)               d_n = −⟦u⟧·n − g₀  (as for a crack, − = slave)
//! multipliers: one packet per slave node, linear on the slave faces (Code_Aster's
//! continuous method); the basis is the standard one (no lip side: `side` 0)
//! ```
//!
//! Integration (`gauss`, the default): segment-to-segment. In 2D each slave segment is cut
//! at the projections of the master nodes (in the initial configuration), and a 2-point
//! Gauss rule is placed on each piece: the master shape functions are linear on each
//! piece, so the contact virtual work ∫ λ δ⟦u⟧ of a linear λ is integrated exactly (the
//! contact patch test on non-matching meshes). In 3D each slave triangle is clipped
//! against the master triangles projected on its plane (Sutherland–Hodgman, in the initial
//! configuration), the clipped polygons are split into triangles and each carries the
//! 3-point rule (degree 2): on each piece the master trace is one polynomial of degree ≤ 2
//! (linear on tet faces, bilinear on affine hex faces), so ∫ λ δ⟦u⟧ of a constant λ is
//! exact (the 3D patch test on non-matching meshes). The part of a slave triangle that no
//! master face covers keeps points (they pair outside: out of contact). `vertex` and
//! `nodes` put the points at the slave nodes (node-to-segment collocation).

use crate::cut::Facet;
use crate::mesh::{Face, Mesh};
use std::collections::HashMap;

/// The two surfaces of one contact pair.
#[derive(Debug, Clone)]
pub struct PairSurfaces {
    /// Index of the pair in the case (`contact_pairs[i]`).
    pub index: usize,
    pub name: String,
    /// Slave facets (segments in 2D, triangles in 3D), normal outward from the slave body.
    pub slave: Vec<Facet>,
    /// Master facets.
    pub master: Vec<Facet>,
    /// Per master facet, its sides on the boundary of the master surface (2D: per vertex; 3D:
    /// per edge, edge k opposite vertex k), as [`crate::cut::lip_boundary`] gives for a lip.
    pub master_boundary: Vec<Vec<bool>>,
    /// Per slave facet, its sides on the boundary of the slave surface (as
    /// `master_boundary`): the large-sliding pairing tells a slave point on its own
    /// surface's edge from one inside it ([`super::pairing::EDGE_REACH`]).
    pub slave_boundary: Vec<Vec<bool>>,
    /// Per slave facet, whether it ends the slave surface where the body's boundary goes
    /// on smoothly (within 45°) beyond the group: contact reaching such a facet may
    /// continue past the surface given (a warning, `run`).
    pub slave_open_edge: Vec<bool>,
    /// The slave nodes in packet order.
    pub slave_nodes: Vec<usize>,
    /// Per slave facet, the packet of each vertex.
    pub slave_packets: Vec<Vec<u32>>,
    /// Mean edge length of the slave and master cells.
    pub cell_size: f64,
    /// The nodes of the slave and master faces, sorted: the only nodes whose basis
    /// functions are non-zero on the faces (the others vanish there), hence the only ones
    /// a contact element of the pair couples ([`super::pairing::ElementBasis::build`]).
    pub surface_nodes: Vec<usize>,
}

/// The facets of a face group, from the cells having each of its faces (`owner`: per
/// sorted face, the number of cells having it and the last of them).
fn facets_of(mesh: &Mesh, faces: &[Face], owner: &HashMap<Vec<usize>, (usize, usize)>) -> Result<Vec<Facet>, String> {
    let mut out = vec![];
    for f in faces {
        let mut key = f.nodes().to_vec();
        key.sort_unstable();
        let at = || {
            let x: Vec<f64> = (0..mesh.dim)
                .map(|i| f.nodes().iter().map(|&a| mesh.nodes[a][i]).sum::<f64>() / f.nodes().len() as f64)
                .collect();
            format!("the face centred at {x:.4?}")
        };
        let cell = match owner.get(&key).copied().unwrap_or((0, 0)) {
            (1, cell) => cell,
            (0, _) => {
                return Err(format!("{} (nodes {:?}) is not a boundary face of the mesh: no cell has it", at(), f.nodes()))
            }
            (n, _) => {
                return Err(format!(
                    "{} (nodes {:?}) is not a boundary face of the mesh: {n} cells share it, so it lies inside one body; the two bodies of a contact pair share no nodes (in Gmsh, mesh them without Coherence or boolean fragments between them, e.g. meshes/two_blocks.geo)",
                    at(),
                    f.nodes()
                ))
            }
        };
        let c = &mesh.cells[cell];
        let refs = c.kind.reference_nodes();
        let local = |a: usize| c.nodes().iter().position(|&b| b == a).expect("a face node is a cell node");
        let nodes = f.nodes();
        // Triangles (3D quads split in two), segments in 2D.
        let pieces: Vec<Vec<usize>> = match nodes.len() {
            4 => vec![vec![nodes[0], nodes[1], nodes[2]], vec![nodes[0], nodes[2], nodes[3]]],
            _ => vec![nodes.to_vec()],
        };
        let centroid = {
            let mut x = [0.0; 3];
            for &a in c.nodes() {
                for i in 0..3 {
                    x[i] += mesh.nodes[a][i] / c.nodes().len() as f64;
                }
            }
            x
        };
        for mut p in pieces {
            let (n, measure) = normal_of(mesh.dim, &p.iter().map(|&a| mesh.nodes[a]).collect::<Vec<_>>());
            let mid = p.iter().fold([0.0; 3], |mut m, &a| {
                for i in 0..3 {
                    m[i] += mesh.nodes[a][i] / p.len() as f64;
                }
                m
            });
            let out_dir = (0..3).map(|i| n[i] * (mid[i] - centroid[i])).sum::<f64>();
            let n = if out_dir < 0.0 {
                p.swap(0, 1);
                [-n[0], -n[1], -n[2]]
            } else {
                n
            };
            if !(measure > 0.0) {
                return Err(format!("face {:?} has zero measure", f.nodes()));
            }
            out.push(Facet {
                cell,
                vertices_ref: p.iter().map(|&a| refs[local(a)]).collect(),
                vertices: p.iter().map(|&a| mesh.nodes[a]).collect(),
                normal: n,
                measure,
                vertex_edges: vec![None; p.len()],
                vertex_nodes: p.iter().map(|&a| Some(a)).collect(),
                vertex_on_front: vec![false; p.len()],
            });
        }
    }
    Ok(out)
}

/// Unit normal (2D: the tangent x1 − x0 rotated by −90°; 3D: right-hand of x0, x1, x2) and
/// measure of a flat facet.
fn normal_of(dim: usize, v: &[[f64; 3]]) -> ([f64; 3], f64) {
    let e1 = [v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]];
    let (n, m) = if dim == 2 {
        ([e1[1], -e1[0], 0.0], 1.0)
    } else {
        let e2 = [v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]];
        ([e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]], 0.5)
    };
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 {
        ([n[0] / l, n[1] / l, n[2] / l], m * l)
    } else {
        ([0.0; 3], 0.0)
    }
}

/// Sides of each facet on the boundary of its surface (see [`PairSurfaces::master_boundary`]).
fn surface_boundary(dim: usize, facets: &[Facet]) -> Vec<Vec<bool>> {
    let key = |f: &Facet, k: usize| f.vertex_nodes[k].unwrap_or(usize::MAX);
    if dim == 2 {
        let mut count: HashMap<usize, usize> = HashMap::new();
        for f in facets {
            for k in 0..2 {
                *count.entry(key(f, k)).or_default() += 1;
            }
        }
        facets.iter().map(|f| (0..2).map(|k| count[&key(f, k)] == 1).collect()).collect()
    } else {
        let edge = |f: &Facet, k: usize| {
            let (a, b) = (key(f, (k + 1) % 3), key(f, (k + 2) % 3));
            (a.min(b), a.max(b))
        };
        let mut count: HashMap<(usize, usize), usize> = HashMap::new();
        for f in facets {
            for k in 0..3 {
                *count.entry(edge(f, k)).or_default() += 1;
            }
        }
        facets.iter().map(|f| (0..3).map(|k| count[&edge(f, k)] == 1).collect()).collect()
    }
}

/// Largest angle between a slave facet and the body's boundary beyond the edge of the
/// slave surface for that edge to count as smooth (the surface stops short of where the
/// boundary turns: contact can go on past it), [`PairSurfaces::slave_open_edge`].
const SMOOTH_EDGE_DEG: f64 = 45.0;

/// Per slave facet, whether one of its sides on the boundary of the slave surface
/// (`boundary`) has beyond it a boundary face of the mesh (not a slave face) turned by less
/// than [`SMOOTH_EDGE_DEG`] from the facet: the body's surface goes on smoothly where the
/// slave group stops. Only the cells at the nodes of those sides are visited.
fn open_edges(mesh: &Mesh, slave: &[Facet], boundary: &[Vec<bool>], slave_faces: &[Face]) -> Vec<bool> {
    let dim = mesh.dim;
    let side_nodes = |f: &Facet, k: usize| -> Vec<usize> {
        let v = |j: usize| f.vertex_nodes[j].unwrap_or(usize::MAX);
        if dim == 2 {
            vec![v(k)]
        } else {
            vec![v((k + 1) % 3), v((k + 2) % 3)]
        }
    };
    let mut at: std::collections::HashSet<usize> = std::collections::HashSet::new();
    for (f, b) in slave.iter().zip(boundary) {
        for (k, &on) in b.iter().enumerate() {
            if on {
                at.extend(side_nodes(f, k));
            }
        }
    }
    if at.is_empty() {
        return vec![false; slave.len()];
    }
    let own: std::collections::HashSet<Vec<usize>> = slave_faces
        .iter()
        .map(|f| {
            let mut k = f.nodes().to_vec();
            k.sort_unstable();
            k
        })
        .collect();
    // The faces of the cells at those nodes: (count, cell, nodes).
    let mut faces: HashMap<Vec<usize>, (usize, usize, Vec<usize>)> = HashMap::new();
    for (ci, c) in mesh.cells.iter().enumerate() {
        if !c.nodes().iter().any(|a| at.contains(a)) {
            continue;
        }
        for (_, loc) in c.kind.faces() {
            let nodes: Vec<usize> = loc.iter().map(|&a| c.nodes[a]).collect();
            if !nodes.iter().any(|a| at.contains(a)) {
                continue;
            }
            let mut key = nodes.clone();
            key.sort_unstable();
            let e = faces.entry(key).or_insert((0, ci, nodes));
            e.0 += 1;
        }
    }
    let others: Vec<([f64; 3], Vec<usize>)> = faces
        .into_iter()
        .filter(|(key, (count, _, _))| *count == 1 && !own.contains(key))
        .map(|(_, (_, cell, nodes))| {
            let x: Vec<[f64; 3]> = nodes.iter().map(|&a| mesh.nodes[a]).collect();
            let (n, _) = normal_of(dim, &x);
            let c = mesh.cells[cell].nodes();
            let mut out = 0.0;
            for i in 0..3 {
                let centroid = c.iter().map(|&a| mesh.nodes[a][i]).sum::<f64>() / c.len() as f64;
                let mid = x.iter().map(|p| p[i]).sum::<f64>() / x.len() as f64;
                out += n[i] * (mid - centroid);
            }
            (if out < 0.0 { [-n[0], -n[1], -n[2]] } else { n }, nodes)
        })
        .collect();
    let cos = SMOOTH_EDGE_DEG.to_radians().cos();
    slave
        .iter()
        .zip(boundary)
        .map(|(f, b)| {
            b.iter().enumerate().any(|(k, &on)| {
                on && {
                    let side = side_nodes(f, k);
                    others.iter().any(|(n, nodes)| {
                        side.iter().all(|a| nodes.contains(a)) && (0..3).map(|i| n[i] * f.normal[i]).sum::<f64>() > cos
                    })
                }
            })
        })
        .collect()
}

/// Bounding box of points, widened by `pad`.
fn bbox(v: &[[f64; 3]], pad: f64) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in v {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i] - pad);
            hi[i] = hi[i].max(p[i] + pad);
        }
    }
    (lo, hi)
}

/// Signed area of a plane polygon (positive counter-clockwise).
fn signed_area(p: &[[f64; 2]]) -> f64 {
    let mut a = 0.0;
    for k in 0..p.len() {
        let (x, y) = (p[k], p[(k + 1) % p.len()]);
        a += x[0] * y[1] - x[1] * y[0];
    }
    0.5 * a
}

fn polygon_area(p: &[[f64; 2]]) -> f64 {
    if p.len() < 3 {
        0.0
    } else {
        signed_area(p).abs()
    }
}

/// Which side of the directed edge a → b the point q lies (positive: left).
fn side(a: [f64; 2], b: [f64; 2], q: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])
}

/// The part of polygon `p` on the left of the line a → b (`keep_left`) or on its right
/// (one Sutherland–Hodgman pass).
fn clip_half_plane(p: &[[f64; 2]], a: [f64; 2], b: [f64; 2], keep_left: bool) -> Vec<[f64; 2]> {
    let sgn = if keep_left { 1.0 } else { -1.0 };
    let mut out = vec![];
    for k in 0..p.len() {
        let (x, y) = (p[k], p[(k + 1) % p.len()]);
        let (sx, sy) = (sgn * side(a, b, x), sgn * side(a, b, y));
        if sx >= 0.0 {
            out.push(x);
        }
        if (sx > 0.0 && sy < 0.0) || (sx < 0.0 && sy > 0.0) {
            let t = sx / (sx - sy);
            out.push([x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])]);
        }
    }
    out
}

/// Sutherland–Hodgman: polygon `p` clipped by the convex counter-clockwise polygon `c`.
fn clip_convex(p: &[[f64; 2]], c: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = p.to_vec();
    for k in 0..c.len() {
        if out.len() < 3 {
            return vec![];
        }
        out = clip_half_plane(&out, c[k], c[(k + 1) % c.len()], true);
    }
    out
}

/// Convex polygon `p` minus the convex counter-clockwise polygon `c`, as disjoint convex
/// pieces: the part outside edge 0, then the part inside edge 0 and outside edge 1, …
fn subtract_convex(p: &[[f64; 2]], c: &[[f64; 2]]) -> Vec<Vec<[f64; 2]>> {
    let mut rest = p.to_vec();
    let mut pieces = vec![];
    for k in 0..c.len() {
        if rest.len() < 3 {
            break;
        }
        let (a, b) = (c[k], c[(k + 1) % c.len()]);
        let outside = clip_half_plane(&rest, a, b, false);
        if outside.len() >= 3 {
            pieces.push(outside);
        }
        rest = clip_half_plane(&rest, a, b, true);
    }
    pieces
}

impl PairSurfaces {
    /// The surfaces of pair `index` from its slave and master face groups. Errors (a
    /// message without the key): a face that is not a boundary face of the mesh, slave and
    /// master sharing a node or lying in the same body.
    pub fn build(
        mesh: &Mesh,
        index: usize,
        name: &str,
        slave_faces: &[Face],
        master_faces: &[Face],
    ) -> Result<PairSurfaces, String> {
        // The cells of the group faces: one pass over the mesh's cell faces, looking up only
        // the keys of the slave and master faces (a face of a group is a boundary face if
        // exactly one cell has it).
        let mut owner: HashMap<Vec<usize>, (usize, usize)> = HashMap::new();
        for f in slave_faces.iter().chain(master_faces) {
            let mut key = f.nodes().to_vec();
            key.sort_unstable();
            owner.insert(key, (0, usize::MAX));
        }
        let mut key = Vec::with_capacity(4);
        for (ci, c) in mesh.cells.iter().enumerate() {
            for (_, loc) in c.kind.faces() {
                key.clear();
                key.extend(loc.iter().map(|&a| c.nodes[a]));
                key.sort_unstable();
                if let Some(e) = owner.get_mut(&key) {
                    e.0 += 1;
                    e.1 = ci;
                }
            }
        }
        let slave = facets_of(mesh, slave_faces, &owner).map_err(|e| format!("slave: {e}"))?;
        let master = facets_of(mesh, master_faces, &owner).map_err(|e| format!("master: {e}"))?;
        let (comp, _) = crate::physics::constraints::node_components(mesh);
        let body = |f: &Facet| comp[mesh.cells[f.cell].nodes()[0]];
        let slave_bodies: std::collections::BTreeSet<usize> = slave.iter().map(body).collect();
        if master.iter().any(|f| slave_bodies.contains(&body(f))) {
            return Err("the slave and master surfaces lie on the same body (a contact pair joins two bodies that share no nodes)".into());
        }
        let mut packet: HashMap<usize, u32> = HashMap::new();
        let mut slave_nodes = vec![];
        let slave_packets = slave
            .iter()
            .map(|f| {
                f.vertex_nodes
                    .iter()
                    .map(|a| {
                        let a = a.expect("a face vertex is a node");
                        *packet.entry(a).or_insert_with(|| {
                            slave_nodes.push(a);
                            slave_nodes.len() as u32 - 1
                        })
                    })
                    .collect()
            })
            .collect();
        let mut cells: Vec<usize> = slave.iter().chain(&master).map(|f| f.cell).collect();
        cells.sort_unstable();
        cells.dedup();
        let cell_size = cells.iter().map(|&c| mesh.cell_edge_length(c)).sum::<f64>() / cells.len().max(1) as f64;
        let master_boundary = surface_boundary(mesh.dim, &master);
        let slave_boundary = surface_boundary(mesh.dim, &slave);
        let slave_open_edge = open_edges(mesh, &slave, &slave_boundary, slave_faces);
        let mut surface_nodes: Vec<usize> =
            slave.iter().chain(&master).flat_map(|f| f.vertex_nodes.iter().flatten().copied()).collect();
        surface_nodes.sort_unstable();
        surface_nodes.dedup();
        Ok(PairSurfaces {
            index,
            name: name.to_string(),
            slave,
            master,
            master_boundary,
            slave_boundary,
            slave_open_edge,
            slave_nodes,
            slave_packets,
            cell_size,
            surface_nodes,
        })
    }

    /// The multiplier space: one packet per slave node, linear on the slave facets.
    pub fn multiplier_space(&self) -> super::multipliers::MultiplierSpace {
        super::multipliers::MultiplierSpace {
            n_unknowns: self.slave_nodes.len(),
            vertex_terms: self.slave_packets.iter().map(|f| f.iter().map(|&j| vec![(j, 1.0)]).collect()).collect(),
            unknown_points: vec![],
            strategy: super::multipliers::LbbStrategy::None,
            stats: Default::default(),
        }
    }

    /// The segment-to-segment rule of slave facet `f` (barycentric points and weights
    /// relative to the facet's measure): in 2D, 2 Gauss points on each piece of the segment
    /// between the projections of the master nodes within `band` of it; in 3D the rule of
    /// the slave triangle clipped against every master triangle (`clipped_rule`).
    pub fn segment_rule(&self, dim: usize, f: usize, band: f64) -> Vec<(Vec<f64>, f64)> {
        let s = &self.slave[f];
        if dim != 2 {
            let near: Vec<usize> = (0..self.master.len()).collect();
            return self.clipped_rule(f, &near, band);
        }
        let (a, b) = (s.vertices[0], s.vertices[1]);
        let e = [b[0] - a[0], b[1] - a[1]];
        let l2 = e[0] * e[0] + e[1] * e[1];
        let mut cuts = vec![0.0, 1.0];
        for m in &self.master {
            for p in &m.vertices {
                let r = [p[0] - a[0], p[1] - a[1]];
                let t = (r[0] * e[0] + r[1] * e[1]) / l2;
                let d = ((r[0] - t * e[0]).powi(2) + (r[1] - t * e[1]).powi(2)).sqrt();
                if t > 1e-9 && t < 1.0 - 1e-9 && d <= band {
                    cuts.push(t);
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
        let g = 0.5 / 3f64.sqrt();
        let mut rule = vec![];
        for w in cuts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            for q in [0.5 - g, 0.5 + g] {
                let t = t0 + q * (t1 - t0);
                rule.push((vec![1.0 - t, t], 0.5 * (t1 - t0)));
            }
        }
        rule
    }

    /// The segment-to-segment rules of every slave facet (as [`PairSurfaces::segment_rule`]),
    /// with the master facets near each slave facet found through a uniform grid of cell
    /// `band` (3D); the same rules as one call per facet.
    pub fn segment_rules(&self, dim: usize, band: f64) -> Vec<Vec<(Vec<f64>, f64)>> {
        if dim == 2 {
            return (0..self.slave.len()).map(|f| self.segment_rule(dim, f, band)).collect();
        }
        let g = band.max(f64::MIN_POSITIVE);
        let cell = |x: f64| (x / g).floor() as i64;
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (mi, m) in self.master.iter().enumerate() {
            let (lo, hi) = bbox(&m.vertices, band);
            for i in cell(lo[0])..=cell(hi[0]) {
                for j in cell(lo[1])..=cell(hi[1]) {
                    for k in cell(lo[2])..=cell(hi[2]) {
                        grid.entry([i, j, k]).or_default().push(mi);
                    }
                }
            }
        }
        (0..self.slave.len())
            .map(|f| {
                let (lo, hi) = bbox(&self.slave[f].vertices, 0.0);
                let mut near = vec![];
                for i in cell(lo[0])..=cell(hi[0]) {
                    for j in cell(lo[1])..=cell(hi[1]) {
                        for k in cell(lo[2])..=cell(hi[2]) {
                            if let Some(v) = grid.get(&[i, j, k]) {
                                near.extend_from_slice(v);
                            }
                        }
                    }
                }
                near.sort_unstable();
                near.dedup();
                self.clipped_rule(f, &near, band)
            })
            .collect()
    }

    /// The 3D segment-to-segment rule of slave triangle `f` against the master facets
    /// `near`: each master triangle facing the slave one (opposite normals) and within
    /// `band` of its plane is projected along the slave normal onto the slave plane, the
    /// slave triangle is clipped against it (Sutherland–Hodgman; both convex), each clipped
    /// polygon is split into a fan of triangles and each of those carries the 3-point rule
    /// (degree 2). The part of the slave triangle that no master triangle covers is cut
    /// into convex pieces (the slave polygon minus each master triangle, one half-plane at
    /// a time) with the same rule: its points pair outside the master surface (out of
    /// contact) and keep the multipliers there determined. Pieces below 1e-12 of the slave
    /// area (round-off along shared edges) are dropped.
    fn clipped_rule(&self, f: usize, near: &[usize], band: f64) -> Vec<(Vec<f64>, f64)> {
        let s = &self.slave[f];
        let [v0, v1, v2] = [s.vertices[0], s.vertices[1], s.vertices[2]];
        let n = s.normal;
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        // Local frame of the slave plane: x along v0→v1, y = n × x.
        let e1 = {
            let d = sub(v1, v0);
            let l = dot(d, d).sqrt();
            [d[0] / l, d[1] / l, d[2] / l]
        };
        let e2 = [n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]];
        let local = |p: [f64; 3]| {
            let d = sub(p, v0);
            [dot(d, e1), dot(d, e2)]
        };
        let tri = [local(v0), local(v1), local(v2)];
        let area = signed_area(&tri);
        let tiny = 1e-12 * area.abs();
        // Barycentric coordinates in the slave triangle of a local point.
        let bary = |q: [f64; 2]| {
            let l1 = signed_area(&[tri[0], q, tri[2]]) / area;
            let l2 = signed_area(&[tri[0], tri[1], q]) / area;
            vec![1.0 - l1 - l2, l1, l2]
        };
        let mut rule = vec![];
        let add = |poly: &[[f64; 2]], rule: &mut Vec<(Vec<f64>, f64)>| {
            for k in 1..poly.len().saturating_sub(1) {
                let t = [poly[0], poly[k], poly[k + 1]];
                let a = signed_area(&t).abs();
                if a <= tiny {
                    continue;
                }
                for (wa, wb, wc) in [
                    (2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0),
                    (1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0),
                    (1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0),
                ] {
                    let q = [wa * t[0][0] + wb * t[1][0] + wc * t[2][0], wa * t[0][1] + wb * t[1][1] + wc * t[2][1]];
                    rule.push((bary(q), a / area.abs() / 3.0));
                }
            }
        };
        let mut uncovered: Vec<Vec<[f64; 2]>> = vec![tri.to_vec()];
        for &mi in near {
            let m = &self.master[mi];
            if dot(m.normal, n) >= 0.0 {
                continue;
            }
            let dist: Vec<f64> = m.vertices.iter().map(|&p| dot(sub(p, v0), n)).collect();
            if dist.iter().all(|d| d.abs() > band) {
                continue;
            }
            let mut clip: Vec<[f64; 2]> = m.vertices.iter().map(|&p| local(p)).collect();
            if signed_area(&clip) < 0.0 {
                clip.reverse();
            }
            if signed_area(&clip) <= tiny {
                continue;
            }
            let piece = clip_convex(&tri, &clip);
            if polygon_area(&piece) <= tiny {
                continue;
            }
            add(&piece, &mut rule);
            uncovered =
                uncovered.iter().flat_map(|r| subtract_convex(r, &clip)).filter(|r| polygon_area(r) > tiny).collect();
        }
        for r in &uncovered {
            add(r, &mut rule);
        }
        rule
    }

    /// Rows for the rigid-body check (node, component, coefficient): each slave node tied
    /// to its nearest master node along the slave normal (and, with `friction`, along the
    /// tangents): the motions that the contact of this pair holds.
    pub fn rigid_rows(&self, mesh: &Mesh, friction: bool) -> Vec<Vec<(usize, usize, f64)>> {
        let dim = mesh.dim;
        let mut normal_at: HashMap<usize, [f64; 3]> = HashMap::new();
        for f in &self.slave {
            for a in f.vertex_nodes.iter().flatten() {
                normal_at.entry(*a).or_insert(f.normal);
            }
        }
        let mut master_nodes: Vec<usize> =
            self.master.iter().flat_map(|f| f.vertex_nodes.iter().flatten().copied()).collect();
        master_nodes.sort_unstable();
        master_nodes.dedup();
        let mut rows = vec![];
        for &s in &self.slave_nodes {
            let x = mesh.nodes[s];
            let d2 = |m: usize| (0..3).map(|i| (mesh.nodes[m][i] - x[i]).powi(2)).sum::<f64>();
            let Some(&m) = master_nodes.iter().min_by(|&&a, &&b| d2(a).total_cmp(&d2(b))) else { continue };
            let n = normal_at[&s];
            let mut dirs = vec![n];
            if friction {
                let t = super::points::tangent_basis(dim, n, super::points::tangent_reference(&[(n, 1.0)]).0);
                dirs.extend_from_slice(&t[..dim - 1]);
            }
            for d in dirs {
                let mut row = vec![];
                for i in 0..dim {
                    if d[i] != 0.0 {
                        row.push((s, i, d[i]));
                        row.push((m, i, -d[i]));
                    }
                }
                rows.push(row);
            }
        }
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: plane geometry. The triangle (0, 0), (2, 0), (0, 2) clipped by the square
    /// [0.5, 1.5]² is the square minus its corner beyond x + y = 2 (the triangle (1.5, 0.5),
    /// (1.5, 1.5), (0.5, 1.5), area 0.5): area 0.5, to round-off; that part and the pieces
    /// of the triangle outside the square add up to the triangle's area 2.
    #[test]
    fn clip_and_subtract_partition_the_triangle() {
        let tri = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        let square = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]];
        let inside = clip_convex(&tri, &square);
        let outside = subtract_convex(&tri, &square);
        let a_in = polygon_area(&inside);
        let a_out: f64 = outside.iter().map(|p| polygon_area(p)).sum();
        assert!((a_in - 0.5).abs() < 1e-14, "inside {a_in}");
        assert!((a_in + a_out - 2.0).abs() < 1e-14, "inside {a_in} + outside {a_out}");
        for p in &outside {
            assert!(signed_area(p) > 0.0, "a piece keeps the orientation: {p:?}");
        }
        // Disjoint: no overlap → nothing inside, the whole triangle outside.
        let far = [[5.0, 5.0], [6.0, 5.0], [6.0, 6.0], [5.0, 6.0]];
        assert!(polygon_area(&clip_convex(&tri, &far)) == 0.0);
        let rest: f64 = subtract_convex(&tri, &far).iter().map(|p| polygon_area(p)).sum();
        assert!((rest - 2.0).abs() < 1e-14);
    }

    /// Reference: mesh topology. Two quad4 blocks 2 × 2 (unit squares, the second 0.5 above
    /// the first, sharing no nodes): the first's top and the second's bottom build a pair
    /// whose facets lie in their own cells; a group holding the interior edge between two
    /// cells of the first block, or an edge that no cell has, is refused as not a boundary
    /// face of the mesh.
    #[test]
    fn pair_surfaces_take_boundary_faces_only() {
        use crate::element::{CellType, FaceType};
        let block = crate::mesh::generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [2, 2]).unwrap();
        let mut mesh = Mesh::default();
        mesh.append_part(&block, "a", [0.0; 3]);
        mesh.append_part(&block, "b", [0.0, 1.5, 0.0]);
        let slave = mesh.group_faces("a.top").unwrap().to_vec();
        let master = mesh.group_faces("b.bottom").unwrap().to_vec();
        let s = PairSurfaces::build(&mesh, 0, "p", &slave, &master).unwrap();
        assert_eq!((s.slave.len(), s.master.len()), (2, 2));
        for f in s.slave.iter().chain(&s.master) {
            assert!(mesh.cells[f.cell].nodes().iter().filter(|&&a| f.vertex_nodes.contains(&Some(a))).count() == 2);
        }
        assert!(s.slave.iter().all(|f| f.normal[1] > 0.99) && s.master.iter().all(|f| f.normal[1] < -0.99));
        // The edge x = 0.5, y in [0, 0.5] of block a: nodes 1 and 4, shared by two cells.
        let interior = vec![Face::new(FaceType::Line2, &[1, 4])];
        let e = PairSurfaces::build(&mesh, 0, "p", &interior, &master).unwrap_err();
        assert!(e.contains("slave") && e.contains("not a boundary face"), "{e}");
        // Nodes 0 and 8 (opposite corners): no cell has that edge.
        let stray = vec![Face::new(FaceType::Line2, &[0, 8])];
        let e = PairSurfaces::build(&mesh, 0, "p", &slave, &stray).unwrap_err();
        assert!(e.contains("master") && e.contains("not a boundary face"), "{e}");
    }
}
