//! Cracks given as explicit geometry: a polyline in 2D, a triangulated surface in 3D, each
//! with its front (the polyline's tips; the surface's front edges), and their level sets
//! as signed distances to that geometry.
//!
//! Entry points: [`ExplicitCrack::from_msh`] (a Gmsh MSH 4.1 line or triangle mesh, with an
//! optional physical group naming the front), [`ExplicitCrack::new_curve`] /
//! [`ExplicitCrack::new_surface`] (from points and elements, e.g. a grown crack), and
//! [`ExplicitCrack::level_sets_at`].
//!
//! # Level sets (docs/conventions.md, "Cracks")
//!
//! - φn: the signed distance to the crack, with the closest point found by parry's BVH
//!   queries (`Polyline`, `TriMesh`). Where the closest point is on an end element of the
//!   polyline or a boundary edge of the surface (the point lies beyond the crack's edge),
//!   φn is the signed distance to that element's line or plane: the crack extended by its
//!   tangent, as the built-in shapes extend theirs (a meshed straight segment has the
//!   φn of `segment`, a meshed flat disc the φn of `disc`). Elsewhere the sign comes from
//!   the normal of the closest element, or the (angle-weighted) pseudo-normal at a shared
//!   vertex or edge.
//! - φt: with c the closest front point and e1 the front's outward direction at c (in the
//!   crack's tangent plane, normal to the front, pointing away from the crack),
//!   φt = (x − c)·e1: negative on the crack, zero on the front. 2D: the front points are
//!   the tips, e1 the outward tangent of the end element. 3D: e1 on a front edge is
//!   edge × triangle normal turned away from the triangle; at a front vertex, the mean of
//!   its two edges' e1. For a flat disc φt is the in-plane distance to the (polygonal)
//!   front circle, for a meshed segment max(−s, s − L) as for `segment`.
//! - No front (a closed curve, a surface whose boundary is all outside the body and no
//!   front group): an interface, no φt.
//!
//! # Orientation
//!
//! 2D: the polyline is walked in the direction of its first line element; the `+` side is
//! on its left (as for `segment`, a→b). 3D: the triangles are oriented consistently with
//! the first one; `+` is the side its normal (right-hand rule on Gmsh's node order) points to.

use super::shapes::{add, cross, dot, norm, scale, sub};
use crate::mesh::gmsh::{read_msh_elements, MshElements};
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// A crack given by explicit geometry (held behind an `Arc` by [`super::CrackShape::Mesh`],
/// so the size difference of the variants costs nothing).
#[derive(Clone)]
#[allow(clippy::large_enum_variant)]
pub enum ExplicitCrack {
    Curve(CrackCurve),
    Surface(CrackSurface),
}

impl fmt::Debug for ExplicitCrack {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExplicitCrack::Curve(c) => write!(f, "CrackCurve({} points, {} tips)", c.points.len(), c.tips.len()),
            ExplicitCrack::Surface(s) => {
                write!(f, "CrackSurface({} triangles, {} front edges)", s.triangles.len(), s.front.len())
            }
        }
    }
}

/// A 2D crack: an open or closed polyline and its tips.
#[derive(Clone)]
pub struct CrackCurve {
    /// The polyline's points in order (z = 0); a closed curve does not repeat its first.
    pub points: Vec<[f64; 3]>,
    pub closed: bool,
    /// Tips: (index in `points`, outward unit tangent e1).
    pub tips: Vec<(usize, [f64; 3])>,
    shape: parry2d_f64::shape::Polyline,
}

/// A 3D crack: a consistently oriented triangle surface and its front edges.
#[derive(Clone)]
pub struct CrackSurface {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[usize; 3]>,
    /// Unit normal of each triangle (towards `+`).
    pub normals: Vec<[f64; 3]>,
    /// Front edges (vertex pairs) with the outward in-surface direction e1 of each.
    pub front: Vec<([usize; 2], [f64; 3])>,
    /// Boundary edge (sorted vertex pair) → its triangle.
    boundary: HashMap<[usize; 2], usize>,
    /// Interior edge (sorted vertex pair) → its two triangles.
    interior: HashMap<[usize; 2], [usize; 2]>,
    /// Vertices on the boundary.
    boundary_vertices: std::collections::HashSet<usize>,
    /// Angle-weighted pseudo-normal of each vertex.
    vertex_normals: Vec<[f64; 3]>,
    /// Front direction e1 at each front vertex (mean of its front edges').
    front_vertex_e1: HashMap<usize, [f64; 3]>,
    surface: parry3d_f64::shape::TriMesh,
    front_shape: Option<parry3d_f64::shape::Polyline>,
}

/// What is wrong with an explicit crack geometry (the caller names the crack and the key).
#[derive(Debug, Clone, PartialEq)]
pub struct ExplicitError(pub String);

impl fmt::Display for ExplicitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

fn err<T>(m: impl Into<String>) -> Result<T, ExplicitError> {
    Err(ExplicitError(m.into()))
}

impl ExplicitCrack {
    /// Reads a crack mesh: line elements make a 2D crack (a curve in the plane z = 0),
    /// triangles a 3D crack (a surface). `front`: the physical group of the front (2D:
    /// points at the tips; 3D: curves along the front edges); without it every end of the
    /// curve is a tip and every boundary edge of the surface is front.
    pub fn from_msh(path: &Path, front: Option<&str>) -> Result<ExplicitCrack, ExplicitError> {
        let msh = read_msh_elements(path).map_err(|e| ExplicitError(e.to_string()))?;
        let name = path.display().to_string();
        let crack_dim = match msh.elements.iter().map(|e| e.dim).max() {
            Some(d @ (1 | 2)) => d,
            Some(d) => {
                return err(format!(
                    "{name} has elements of dimension {d}: a crack mesh is a curve (line elements, 2D) or a surface (triangles, 3D)"
                ))
            }
            None => return err(format!("{name} has no elements")),
        };
        let dim = crack_dim + 1;
        if dim == 2 {
            let size = msh.nodes.iter().flatten().fold(0.0f64, |m, c| m.max(c.abs()));
            if msh.nodes.iter().any(|p| p[2].abs() > 1e-9 * size.max(f64::MIN_POSITIVE)) {
                return err(format!("{name}: a 2D crack curve must lie in the plane z = 0"));
            }
        }
        let crack: Vec<&crate::mesh::gmsh::MshElement> = msh.elements.iter().filter(|e| e.dim == crack_dim).collect();
        if crack.is_empty() {
            let what = if dim == 2 { "line elements (a curve)" } else { "triangles (a surface)" };
            return err(format!("{name} has no {what}: a {dim}D crack needs them"));
        }
        if let Some(e) = crack.iter().find(|e| e.nodes.len() != dim) {
            return err(format!(
                "{name}: the crack surface has an element of {} nodes; it must be triangles",
                e.nodes.len()
            ));
        }
        let front_elems = match front {
            None => None,
            Some(g) => {
                let fdim = crack_dim - 1;
                if !msh.groups.iter().any(|(d, n)| *d == fdim && n == g) {
                    let have: Vec<String> =
                        msh.groups.iter().filter(|(d, _)| *d == fdim).map(|(_, n)| format!("'{n}'")).collect();
                    let what = if dim == 2 { "points (the tips)" } else { "curves (the front)" };
                    return err(format!(
                        "{name} has no physical group '{g}' of {what}; it has {}",
                        if have.is_empty() { "none".to_string() } else { have.join(", ") }
                    ));
                }
                Some(
                    msh.elements
                        .iter()
                        .filter(|e| e.dim == fdim && e.groups.iter().any(|n| n == g))
                        .map(|e| e.nodes.clone())
                        .collect::<Vec<_>>(),
                )
            }
        };
        let elems: Vec<Vec<usize>> = crack.iter().map(|e| e.nodes.clone()).collect();
        if dim == 2 {
            let tips = front_elems.map(|f| f.into_iter().flatten().collect::<Vec<usize>>());
            Self::curve_from(&msh, &elems, tips.as_deref(), &name)
        } else {
            let edges = front_elems.map(|f| f.into_iter().map(|e| [e[0], e[1]]).collect::<Vec<_>>());
            Self::surface_from(&msh, &elems, edges.as_deref(), &name)
        }
    }

    /// A 2D crack from points and line elements (node indices); `tips`: the nodes that are
    /// tips (`None`: every end of an open curve).
    pub fn new_curve(
        points: &[[f64; 3]],
        lines: &[[usize; 2]],
        tips: Option<&[usize]>,
    ) -> Result<ExplicitCrack, ExplicitError> {
        let msh = MshElements { nodes: points.to_vec(), ..Default::default() };
        let elems: Vec<Vec<usize>> = lines.iter().map(|l| l.to_vec()).collect();
        Self::curve_from(&msh, &elems, tips, "the crack curve")
    }

    /// A 3D crack from vertices and triangles; `front`: the front edges (`None`: every
    /// boundary edge).
    pub fn new_surface(
        vertices: &[[f64; 3]],
        triangles: &[[usize; 3]],
        front: Option<&[[usize; 2]]>,
    ) -> Result<ExplicitCrack, ExplicitError> {
        let msh = MshElements { nodes: vertices.to_vec(), ..Default::default() };
        let elems: Vec<Vec<usize>> = triangles.iter().map(|t| t.to_vec()).collect();
        Self::surface_from(&msh, &elems, front, "the crack surface")
    }

    fn curve_from(
        msh: &MshElements,
        lines: &[Vec<usize>],
        tips: Option<&[usize]>,
        name: &str,
    ) -> Result<ExplicitCrack, ExplicitError> {
        let x = |i: usize| -> Result<[f64; 3], ExplicitError> {
            match msh.nodes.get(i) {
                Some(p) if p.iter().all(|c| c.is_finite()) => Ok([p[0], p[1], 0.0]),
                _ => err(format!("{name}: node {i} does not exist or is not finite")),
            }
        };
        // Node → its lines.
        let mut adj: HashMap<usize, Vec<usize>> = HashMap::new();
        for (k, l) in lines.iter().enumerate() {
            if l[0] == l[1] || norm(sub(x(l[0])?, x(l[1])?)) == 0.0 {
                return err(format!("{name}: line element {k} has zero length"));
            }
            for &v in l {
                adj.entry(v).or_default().push(k);
            }
        }
        if let Some((v, ls)) = adj.iter().find(|(_, ls)| ls.len() > 2) {
            let p = x(*v)?;
            return err(format!(
                "{name} is not a simple curve: {} line elements meet at the point ({}, {}) (a branch)",
                ls.len(),
                p[0],
                p[1]
            ));
        }
        // Walk the chain from an end (or from the first line if the curve is closed),
        // along the first line element's direction.
        let ends: Vec<usize> = adj.iter().filter(|(_, ls)| ls.len() == 1).map(|(&v, _)| v).collect();
        let closed = ends.is_empty();
        let mut order: Vec<usize> = vec![];
        let mut used = vec![false; lines.len()];
        let start = if closed {
            lines[0][0]
        } else {
            // The end from which the walk follows line 0's direction: walk from any end,
            // then reverse if line 0 was traversed backwards.
            *ends.iter().min().expect("an end")
        };
        let mut v = start;
        order.push(v);
        let mut line0_forward = true;
        while let Some(&k) = adj[&v].iter().find(|&&k| !used[k]) {
            used[k] = true;
            let next = if lines[k][0] == v { lines[k][1] } else { lines[k][0] };
            if k == 0 {
                line0_forward = lines[k][0] == v;
            }
            if closed && next == start {
                break;
            }
            order.push(next);
            v = next;
        }
        if used.iter().any(|u| !u) {
            let pieces = 1 + count_pieces(lines, &used);
            return err(format!(
                "{name} is not one connected curve: it has {pieces} separate pieces (a gap, or several cracks in one file: give each its own [[cracks]] entry)"
            ));
        }
        if !line0_forward {
            order.reverse();
        }
        let points: Vec<[f64; 3]> = order.iter().map(|&i| x(i)).collect::<Result<_, _>>()?;
        let m = points.len();
        let tip_nodes: Vec<usize> = match tips {
            Some(t) => {
                for &v in t {
                    if !ends.contains(&v) {
                        let p = msh.nodes.get(v).copied().unwrap_or([f64::NAN; 3]);
                        return err(format!(
                            "{name}: the front point ({}, {}) is not an end of the crack curve",
                            p[0], p[1]
                        ));
                    }
                }
                t.to_vec()
            }
            None => ends.clone(),
        };
        let mut tip_list = vec![];
        if !closed {
            for (pos, inner) in [(0usize, 1usize), (m - 1, m - 2)] {
                if tip_nodes.contains(&order[pos]) && !tip_list.iter().any(|(p, _)| *p == pos) {
                    let t = sub(points[pos], points[inner]);
                    tip_list.push((pos, scale(1.0 / norm(t), t)));
                }
            }
        }
        let v: Vec<parry2d_f64::math::Vector> =
            points.iter().map(|p| parry2d_f64::math::Vector::new(p[0], p[1])).collect();
        let n = v.len() as u32;
        let idx: Vec<[u32; 2]> = (0..if closed { n } else { n - 1 }).map(|i| [i, (i + 1) % n]).collect();
        let shape = parry2d_f64::shape::Polyline::new(v, Some(idx));
        Ok(ExplicitCrack::Curve(CrackCurve { points, closed, tips: tip_list, shape }))
    }

    fn surface_from(
        msh: &MshElements,
        tris: &[Vec<usize>],
        front: Option<&[[usize; 2]]>,
        name: &str,
    ) -> Result<ExplicitCrack, ExplicitError> {
        // Compact the vertices used by the triangles.
        let mut index: HashMap<usize, usize> = HashMap::new();
        let mut vertices: Vec<[f64; 3]> = vec![];
        let mut triangles: Vec<[usize; 3]> = vec![];
        for t in tris {
            let mut tri = [0; 3];
            for a in 0..3 {
                let v = t[a];
                let p = match msh.nodes.get(v) {
                    Some(p) if p.iter().all(|c| c.is_finite()) => *p,
                    _ => return err(format!("{name}: node {v} does not exist or is not finite")),
                };
                tri[a] = *index.entry(v).or_insert_with(|| {
                    vertices.push(p);
                    vertices.len() - 1
                });
            }
            triangles.push(tri);
        }
        let area2 = |t: &[usize; 3]| cross(sub(vertices[t[1]], vertices[t[0]]), sub(vertices[t[2]], vertices[t[0]]));
        if let Some(k) = triangles.iter().position(|t| norm(area2(t)) == 0.0) {
            return err(format!("{name}: triangle {k} is degenerate (zero area)"));
        }
        // Edges → triangles.
        let key = |a: usize, b: usize| if a < b { [a, b] } else { [b, a] };
        let mut edges: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        for (k, t) in triangles.iter().enumerate() {
            for e in 0..3 {
                edges.entry(key(t[e], t[(e + 1) % 3])).or_default().push(k);
            }
        }
        if let Some((e, ts)) = edges.iter().find(|(_, ts)| ts.len() > 2) {
            let (p, q) = (vertices[e[0]], vertices[e[1]]);
            return err(format!("{name} is not a surface: {} triangles share the edge {p:?}–{q:?}", ts.len()));
        }
        // Orient consistently with triangle 0 (breadth-first); check connectivity.
        let mut oriented = vec![false; triangles.len()];
        oriented[0] = true;
        let mut queue = std::collections::VecDeque::from([0usize]);
        let has_directed = |t: &[usize; 3], a: usize, b: usize| (0..3).any(|e| t[e] == a && t[(e + 1) % 3] == b);
        while let Some(k) = queue.pop_front() {
            let t = triangles[k];
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                for &j in &edges[&key(a, b)] {
                    if j == k {
                        continue;
                    }
                    // A consistent neighbour runs the shared edge the other way (b → a).
                    let consistent = has_directed(&triangles[j], b, a);
                    if oriented[j] {
                        if !consistent {
                            return err(format!(
                                "{name} is not orientable (a Möbius-like surface): it has no + and − side"
                            ));
                        }
                        continue;
                    }
                    if !consistent {
                        triangles[j].swap(1, 2);
                    }
                    oriented[j] = true;
                    queue.push_back(j);
                }
            }
        }
        if oriented.iter().any(|o| !o) {
            let pieces = 1 + count_pieces_tri(&triangles, &oriented, &edges, key);
            return err(format!(
                "{name} is not one connected surface: it has {pieces} separate pieces (several cracks in one file: give each its own [[cracks]] entry)"
            ));
        }
        let normals: Vec<[f64; 3]> = triangles
            .iter()
            .map(|t| {
                let n = area2(t);
                scale(1.0 / norm(n), n)
            })
            .collect();
        let boundary: HashMap<[usize; 2], usize> =
            edges.iter().filter(|(_, ts)| ts.len() == 1).map(|(e, ts)| (*e, ts[0])).collect();
        // Boundary loops (holes are extra loops).
        let front_edges: Vec<[usize; 2]> = match front {
            Some(f) => {
                let mut out = vec![];
                for e in f {
                    let (Some(&a), Some(&b)) = (index.get(&e[0]), index.get(&e[1])) else {
                        return err(format!("{name}: a front edge has a node that no triangle of the crack uses"));
                    };
                    if !boundary.contains_key(&key(a, b)) {
                        return err(format!(
                            "{name}: the front edge {:?}–{:?} is not on the boundary of the crack surface",
                            vertices[a], vertices[b]
                        ));
                    }
                    out.push(key(a, b));
                }
                out.sort();
                out.dedup();
                out
            }
            None => {
                let loops = count_loops(&boundary);
                if loops > 1 {
                    return err(format!(
                        "{name} has {loops} boundary loops: a crack surface without a front group must have one boundary (the front); a surface with holes needs its front given as a physical group"
                    ));
                }
                let mut all: Vec<[usize; 2]> = boundary.keys().copied().collect();
                all.sort();
                all
            }
        };
        let mut front_list = vec![];
        for e in &front_edges {
            let k = boundary[e];
            let t = triangles[k];
            let third = t.iter().copied().find(|v| !e.contains(v)).expect("a triangle has a third vertex");
            let d = sub(vertices[e[1]], vertices[e[0]]);
            let mut e1 = cross(d, normals[k]);
            e1 = scale(1.0 / norm(e1), e1);
            if dot(sub(vertices[third], vertices[e[0]]), e1) > 0.0 {
                e1 = scale(-1.0, e1);
            }
            front_list.push((*e, e1));
        }
        let mut front_vertex_e1: HashMap<usize, [f64; 3]> = HashMap::new();
        for (e, e1) in &front_list {
            for &v in e {
                let s = front_vertex_e1.entry(v).or_insert([0.0; 3]);
                *s = add(*s, *e1);
            }
        }
        for s in front_vertex_e1.values_mut() {
            let l = norm(*s);
            if l > 0.0 {
                *s = scale(1.0 / l, *s);
            }
        }
        // Angle-weighted vertex pseudo-normals.
        let mut vertex_normals = vec![[0.0; 3]; vertices.len()];
        for (k, t) in triangles.iter().enumerate() {
            for a in 0..3 {
                let (p, q, r) = (vertices[t[a]], vertices[t[(a + 1) % 3]], vertices[t[(a + 2) % 3]]);
                let (u, w) = (sub(q, p), sub(r, p));
                let angle = (dot(u, w) / (norm(u) * norm(w))).clamp(-1.0, 1.0).acos();
                vertex_normals[t[a]] = add(vertex_normals[t[a]], scale(angle, normals[k]));
            }
        }
        use parry3d_f64::math::Vector;
        let v: Vec<Vector> = vertices.iter().map(|p| Vector::new(p[0], p[1], p[2])).collect();
        let idx: Vec<[u32; 3]> = triangles.iter().map(|t| [t[0] as u32, t[1] as u32, t[2] as u32]).collect();
        let surface = parry3d_f64::shape::TriMesh::new(v.clone(), idx)
            .map_err(|e| ExplicitError(format!("{name}: the triangles do not form a valid surface: {e:?}")))?;
        let front_shape = (!front_list.is_empty()).then(|| {
            let fidx: Vec<[u32; 2]> = front_list.iter().map(|(e, _)| [e[0] as u32, e[1] as u32]).collect();
            parry3d_f64::shape::Polyline::new(v, Some(fidx))
        });
        let interior: HashMap<[usize; 2], [usize; 2]> =
            edges.iter().filter(|(_, ts)| ts.len() == 2).map(|(e, ts)| (*e, [ts[0], ts[1]])).collect();
        let boundary_vertices = boundary.keys().flatten().copied().collect();
        Ok(ExplicitCrack::Surface(CrackSurface {
            interior,
            boundary_vertices,
            vertices,
            triangles,
            normals,
            front: front_list,
            boundary,
            vertex_normals,
            front_vertex_e1,
            surface,
            front_shape,
        }))
    }

    /// The dimension of the body this crack lives in.
    pub fn dim(&self) -> usize {
        match self {
            ExplicitCrack::Curve(_) => 2,
            ExplicitCrack::Surface(_) => 3,
        }
    }

    /// Whether the crack has a front (φt); without one it is an interface.
    pub fn has_front(&self) -> bool {
        match self {
            ExplicitCrack::Curve(c) => !c.tips.is_empty(),
            ExplicitCrack::Surface(s) => !s.front.is_empty(),
        }
    }

    /// (φn, φt) at `p` (see the module doc); φt is `None` without a front.
    pub fn level_sets_at(&self, p: [f64; 3]) -> (f64, Option<f64>) {
        match self {
            ExplicitCrack::Curve(c) => c.level_sets_at(p),
            ExplicitCrack::Surface(s) => s.level_sets_at(p),
        }
    }
}

fn count_pieces(lines: &[Vec<usize>], used: &[bool]) -> usize {
    // Union-find over the lines not reached by the walk.
    let mut parent: HashMap<usize, usize> = HashMap::new();
    fn find(p: &mut HashMap<usize, usize>, v: usize) -> usize {
        let mut r = v;
        while let Some(&q) = p.get(&r) {
            if q == r {
                break;
            }
            r = q;
        }
        p.insert(v, r);
        r
    }
    for (k, l) in lines.iter().enumerate() {
        if used[k] {
            continue;
        }
        parent.entry(l[0]).or_insert(l[0]);
        parent.entry(l[1]).or_insert(l[1]);
        let (a, b) = (find(&mut parent, l[0]), find(&mut parent, l[1]));
        parent.insert(a, b);
    }
    let nodes: Vec<usize> = parent.keys().copied().collect();
    let mut roots: Vec<usize> = nodes.into_iter().map(|v| find(&mut parent, v)).collect();
    roots.sort();
    roots.dedup();
    roots.len()
}

fn count_pieces_tri(
    triangles: &[[usize; 3]],
    reached: &[bool],
    edges: &HashMap<[usize; 2], Vec<usize>>,
    key: impl Fn(usize, usize) -> [usize; 2],
) -> usize {
    let mut seen = reached.to_vec();
    let mut pieces = 0;
    for s in 0..triangles.len() {
        if seen[s] {
            continue;
        }
        pieces += 1;
        seen[s] = true;
        let mut stack = vec![s];
        while let Some(k) = stack.pop() {
            let t = triangles[k];
            for e in 0..3 {
                for &j in &edges[&key(t[e], t[(e + 1) % 3])] {
                    if !seen[j] {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
    }
    pieces
}

/// Number of closed loops formed by the boundary edges.
fn count_loops(boundary: &HashMap<[usize; 2], usize>) -> usize {
    let mut adj: HashMap<usize, Vec<usize>> = HashMap::new();
    for e in boundary.keys() {
        adj.entry(e[0]).or_default().push(e[1]);
        adj.entry(e[1]).or_default().push(e[0]);
    }
    let mut seen: HashMap<usize, bool> = HashMap::new();
    let mut loops = 0;
    let mut starts: Vec<usize> = adj.keys().copied().collect();
    starts.sort();
    for s in starts {
        if seen.contains_key(&s) {
            continue;
        }
        loops += 1;
        let mut stack = vec![s];
        seen.insert(s, true);
        while let Some(v) = stack.pop() {
            for &w in &adj[&v] {
                if seen.insert(w, true).is_none() {
                    stack.push(w);
                }
            }
        }
    }
    loops
}

impl CrackCurve {
    fn level_sets_at(&self, p: [f64; 3]) -> (f64, Option<f64>) {
        use parry2d_f64::query::point::PointQueryWithLocation;
        use parry2d_f64::shape::SegmentPointLocation;
        let q = parry2d_f64::math::Vector::new(p[0], p[1]);
        let (proj, (seg, loc)) = self.shape.project_local_point_and_get_location(q, false);
        let m = self.points.len();
        let seg = seg as usize;
        let (a, b) = (seg, (seg + 1) % m);
        // φn on segment k: the exact formula of `segment` (a→b, + on the left).
        let on_line = |k: usize| {
            let (a, b) = (self.points[k], self.points[(k + 1) % m]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let l = d[0].hypot(d[1]);
            let t = [d[0] / l, d[1] / l];
            let r = [p[0] - a[0], p[1] - a[1]];
            -t[1] * r[0] + t[0] * r[1]
        };
        let n_segments = if self.closed { m } else { m - 1 };
        let phin = match loc {
            SegmentPointLocation::OnEdge(_) => on_line(seg),
            SegmentPointLocation::OnVertex(i) => {
                let v = if i == 0 { a } else { b };
                if !self.closed && v == 0 {
                    on_line(0)
                } else if !self.closed && v == m - 1 {
                    on_line(n_segments - 1)
                } else {
                    // Interior vertex: the sign from the mean of the two segment normals.
                    let prev = (v + n_segments - 1) % n_segments;
                    let c = [proj.point.x, proj.point.y];
                    let d = [p[0] - c[0], p[1] - c[1]];
                    let dist = d[0].hypot(d[1]);
                    let normal = |k: usize| {
                        let (a, b) = (self.points[k], self.points[(k + 1) % m]);
                        let t = sub(b, a);
                        let l = norm(t);
                        [-t[1] / l, t[0] / l]
                    };
                    let (n1, n2) = (normal(prev), normal(v));
                    let s = d[0] * (n1[0] + n2[0]) + d[1] * (n1[1] + n2[1]);
                    if s < 0.0 {
                        -dist
                    } else {
                        dist
                    }
                }
            }
        };
        if self.tips.is_empty() {
            return (phin, None);
        }
        // φt from the nearest tip.
        let (tip, e1) = self
            .tips
            .iter()
            .map(|&(i, e1)| (self.points[i], e1))
            .min_by(|(x, _), (y, _)| norm(sub(p, *x)).total_cmp(&norm(sub(p, *y))))
            .expect("a tip");
        let r = [p[0] - tip[0], p[1] - tip[1], 0.0];
        (phin, Some(dot(r, e1)))
    }
}

impl CrackSurface {
    fn level_sets_at(&self, p: [f64; 3]) -> (f64, Option<f64>) {
        use parry3d_f64::query::point::PointQueryWithLocation;
        use parry3d_f64::shape::{SegmentPointLocation, TrianglePointLocation};
        let q = parry3d_f64::math::Vector::new(p[0], p[1], p[2]);
        let (proj, (tri, loc)) = self.surface.project_local_point_and_get_location(q, false);
        let k = tri as usize;
        let t = self.triangles[k];
        let c = [proj.point.x, proj.point.y, proj.point.z];
        let d = sub(p, c);
        let plane = |k: usize| dot(sub(p, self.vertices[self.triangles[k][0]]), self.normals[k]);
        let signed = |n: [f64; 3]| if dot(d, n) < 0.0 { -norm(d) } else { norm(d) };
        let key = |a: usize, b: usize| if a < b { [a, b] } else { [b, a] };
        let phin = match loc {
            TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => plane(k),
            TrianglePointLocation::OnEdge(i, _) => {
                // parry's edge numbering: 0 = AB, 1 = BC, 2 = AC.
                let (a, b) = match i {
                    0 => (t[0], t[1]),
                    1 => (t[1], t[2]),
                    _ => (t[0], t[2]),
                };
                match self.boundary.get(&key(a, b)) {
                    Some(&bk) => plane(bk),
                    None => {
                        // Interior edge: the pseudo-normal is the sum of the two normals.
                        let [t1, t2] = self.interior.get(&key(a, b)).copied().unwrap_or([k, k]);
                        signed(add(self.normals[t1], self.normals[t2]))
                    }
                }
            }
            TrianglePointLocation::OnVertex(i) => {
                let v = t[i as usize];
                if self.boundary_vertices.contains(&v) {
                    plane(k)
                } else {
                    signed(self.vertex_normals[v])
                }
            }
        };
        let Some(front) = &self.front_shape else { return (phin, None) };
        let (fproj, (seg, floc)) = front.project_local_point_and_get_location(q, false);
        let (e, e1) = self.front[seg as usize];
        let e1 = match floc {
            SegmentPointLocation::OnEdge(_) => e1,
            SegmentPointLocation::OnVertex(i) => self.front_vertex_e1[&e[i as usize]],
        };
        let fc = [fproj.point.x, fproj.point.y, fproj.point.z];
        (phin, Some(dot(sub(p, fc), e1)))
    }
}
