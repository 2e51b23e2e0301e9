//! The growing 2D crack: an explicit polyline with its tips, grown by one segment per
//! growing tip and increment, and the body it grows in.
//!
//! Entry points: [`GrowingCurve::from_shape`] (a `segment`, `half_line` or meshed curve →
//! polyline), [`GrowingCurve::extend`], [`GrowingCurve::shape`] (→ the `shape = "mesh"`
//! crack of [`crate::levelset::explicit`], so φn is the signed distance to the polyline
//! and φt the distance along the last segment's direction, docs/conventions.md
//! "Cracks"), and [`Body2d`] (inside / distance to the boundary, segment crossings, the
//! face groups of the boundary nearest a point). The body's boundary is every boundary
//! edge of the mesh: the outer edge and the edges of holes alike.
//!
//! A segment end on or outside the body surface is not a tip: it is carried outward
//! by the body's diagonal (as `cut::boundary` does for the fixed crack), so an edge
//! crack stays an edge crack; a half-line gets a far end outside the body the same way.

use crate::levelset::explicit::{ExplicitCrack, ExplicitError};
use crate::levelset::CrackShape;
use crate::mesh::Mesh;
use std::sync::Arc;

/// A 2D crack as a polyline; `tips[0]` / `tips[1]`: whether its first / last point is a
/// tip (a growing front point) or an end outside the body.
#[derive(Debug, Clone, PartialEq)]
pub struct GrowingCurve {
    pub points: Vec<[f64; 3]>,
    pub tips: [bool; 2],
    /// The path length grown at each end so far.
    pub grown: [f64; 2],
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], 0.0]
}

fn norm(a: [f64; 3]) -> f64 {
    a[0].hypot(a[1])
}

impl GrowingCurve {
    /// The polyline of a 2D crack shape (normalised): a segment, a half-line or a meshed
    /// open curve. `None` for the other shapes (which cannot grow).
    pub fn from_shape(shape: &CrackShape, body: &Body2d) -> Option<GrowingCurve> {
        let far = body.diagonal;
        let tip_ok = |p: [f64; 3]| body.depth(p) > 1e-9 * far;
        match shape {
            CrackShape::Segment { a, b } => {
                let (mut a, mut b) = ([a[0], a[1], 0.0], [b[0], b[1], 0.0]);
                let t = sub(b, a);
                let l = norm(t);
                let t = [t[0] / l, t[1] / l, 0.0];
                let tips = [tip_ok(a), tip_ok(b)];
                if !tips[0] {
                    a = [a[0] - far * t[0], a[1] - far * t[1], 0.0];
                }
                if !tips[1] {
                    b = [b[0] + far * t[0], b[1] + far * t[1], 0.0];
                }
                Some(GrowingCurve { points: vec![a, b], tips, grown: [0.0; 2] })
            }
            CrackShape::HalfLine { tip, direction: d } => {
                let b = [tip[0], tip[1], 0.0];
                let a = [tip[0] - far * d[0], tip[1] - far * d[1], 0.0];
                Some(GrowingCurve { points: vec![a, b], tips: [false, tip_ok(b)], grown: [0.0; 2] })
            }
            CrackShape::Mesh(m) => match m.as_ref() {
                ExplicitCrack::Curve(c) if !c.closed => {
                    let last = c.points.len() - 1;
                    let tips = [c.tips.iter().any(|t| t.0 == 0), c.tips.iter().any(|t| t.0 == last)];
                    Some(GrowingCurve { points: c.points.clone(), tips, grown: [0.0; 2] })
                }
                _ => None,
            },
            _ => None,
        }
    }

    /// The point at end `e` (0: first, 1: last).
    pub fn end(&self, e: usize) -> [f64; 3] {
        if e == 0 {
            self.points[0]
        } else {
            self.points[self.points.len() - 1]
        }
    }

    /// Appends the point `p` at end `e`, the tip moving there; `advance` is its length.
    pub fn extend(&mut self, e: usize, p: [f64; 3]) {
        let advance = norm(sub(p, self.end(e)));
        if e == 0 {
            self.points.insert(0, p);
        } else {
            self.points.push(p);
        }
        self.grown[e] += advance;
    }

    /// The explicit crack of the polyline (the `shape = "mesh"` representation).
    pub fn shape(&self) -> Result<CrackShape, ExplicitError> {
        let lines: Vec<[usize; 2]> = (0..self.points.len() - 1).map(|i| [i, i + 1]).collect();
        let tips: Vec<usize> =
            [(0, 0), (1, self.points.len() - 1)].iter().filter(|(e, _)| self.tips[*e]).map(|&(_, i)| i).collect();
        let c = ExplicitCrack::new_curve(&self.points, &lines, Some(&tips))?;
        Ok(CrackShape::Mesh(Arc::new(c)))
    }

    /// The distance from `x` to the polyline.
    pub fn distance(&self, x: [f64; 3]) -> f64 {
        self.points.windows(2).map(|w| distance_to_segment(x, w[0], w[1])).fold(f64::INFINITY, f64::min)
    }

    /// Whether the segment p–q crosses this polyline (touching counts).
    pub fn crosses(&self, p: [f64; 3], q: [f64; 3]) -> bool {
        self.points.windows(2).any(|w| segments_meet(p, q, w[0], w[1]))
    }
}

fn cross2(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Whether the closed segments p–q and a–b meet.
pub fn segments_meet(p: [f64; 3], q: [f64; 3], a: [f64; 3], b: [f64; 3]) -> bool {
    let d1 = cross2(sub(q, p), sub(a, p));
    let d2 = cross2(sub(q, p), sub(b, p));
    let d3 = cross2(sub(b, a), sub(p, a));
    let d4 = cross2(sub(b, a), sub(q, a));
    let s = |v: f64| {
        if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    };
    if s(d1) * s(d2) < 0 && s(d3) * s(d4) < 0 {
        return true;
    }
    // Collinear or touching: a shared point within the segments' boxes.
    let on = |x: [f64; 3], u: [f64; 3], v: [f64; 3], d: f64| {
        d == 0.0 && x[0] >= u[0].min(v[0]) && x[0] <= u[0].max(v[0]) && x[1] >= u[1].min(v[1]) && x[1] <= u[1].max(v[1])
    };
    on(a, p, q, d1) || on(b, p, q, d2) || on(p, a, b, d3) || on(q, a, b, d4)
}

/// A 2D body for the growth checks: its cells as polygons and its boundary edges (outer
/// and inner: holes), with the face groups each edge belongs to.
pub struct Body2d {
    cells: Vec<Vec<[f64; 3]>>,
    boundary: Vec<([f64; 3], [f64; 3])>,
    /// Per boundary edge, the indices in `group_names` of the face groups holding it.
    boundary_groups: Vec<Vec<usize>>,
    group_names: Vec<String>,
    /// The diagonal of the bounding box.
    pub diagonal: f64,
}

impl Body2d {
    pub fn new(mesh: &Mesh) -> Body2d {
        let corners = |nodes: &[usize], k: usize| nodes[..k].iter().map(|&n| mesh.nodes[n]).collect::<Vec<_>>();
        let cells = mesh.cells.iter().map(|c| corners(c.nodes(), c.kind.n_nodes().min(4))).collect();
        let edge = |n: &[usize]| (n[0].min(n[1]), n[0].max(n[1]));
        let group_names: Vec<String> = mesh.face_groups.keys().cloned().collect();
        let mut groups_of: std::collections::HashMap<(usize, usize), Vec<usize>> = Default::default();
        for (g, faces) in mesh.face_groups.values().enumerate() {
            for f in faces {
                groups_of.entry(edge(f.nodes())).or_default().push(g);
            }
        }
        let faces = mesh.boundary_faces();
        let boundary = faces
            .iter()
            .map(|f| {
                let n = f.nodes();
                (mesh.nodes[n[0]], mesh.nodes[n[1]])
            })
            .collect();
        let boundary_groups = faces.iter().map(|f| groups_of.remove(&edge(f.nodes())).unwrap_or_default()).collect();
        let (lo, hi) = mesh.bounding_box();
        Body2d { cells, boundary, boundary_groups, group_names, diagonal: (hi[0] - lo[0]).hypot(hi[1] - lo[1]) }
    }

    /// The face groups holding the boundary edge nearest `x` (empty when that edge is in
    /// none), e.g. the hole a growing tip reached.
    pub fn nearest_boundary_groups(&self, x: [f64; 3]) -> Vec<&str> {
        let nearest = (0..self.boundary.len()).min_by(|&a, &b| {
            let d = |i: usize| distance_to_segment(x, self.boundary[i].0, self.boundary[i].1);
            d(a).total_cmp(&d(b))
        });
        nearest.map_or(vec![], |i| self.boundary_groups[i].iter().map(|&g| self.group_names[g].as_str()).collect())
    }

    /// The cell holding `x` (on its edges included), if any.
    pub fn cell_of(&self, x: [f64; 3]) -> Option<usize> {
        self.cells.iter().position(|poly| {
            let n = poly.len();
            let h = norm(sub(poly[1], poly[0]));
            (0..n).all(|i| cross2(sub(poly[(i + 1) % n], poly[i]), sub(x, poly[i])) >= -1e-12 * h * h)
        })
    }

    /// Distance from `x` to the body surface, positive inside, negative outside.
    pub fn depth(&self, x: [f64; 3]) -> f64 {
        let d = self.boundary.iter().map(|(a, b)| distance_to_segment(x, *a, *b)).fold(f64::INFINITY, f64::min);
        if self.cell_of(x).is_some() {
            d
        } else {
            -d
        }
    }

    /// The mean edge length of the cell holding `x` (the diagonal if none).
    pub fn cell_size(&self, x: [f64; 3]) -> f64 {
        self.cell_of(x).map_or(self.diagonal, |c| {
            let poly = &self.cells[c];
            let n = poly.len();
            (0..n).map(|i| norm(sub(poly[(i + 1) % n], poly[i]))).sum::<f64>() / n as f64
        })
    }

    /// Whether the segment p–q lies in the body (sampled at 16 points; the checks of the
    /// growth loop also ask for a margin at q).
    pub fn contains_segment(&self, p: [f64; 3], q: [f64; 3]) -> bool {
        (0..=16).all(|k| {
            let s = k as f64 / 16.0;
            self.cell_of([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), 0.0]).is_some()
        }) && !self.boundary.iter().any(|(a, b)| {
            // The end p may sit on the surface (an edge crack's mouth is not a tip).
            segments_meet(p, q, *a, *b) && distance_to_segment(p, *a, *b) > 0.0
        })
    }
}

fn distance_to_segment(x: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(b, a);
    let l2 = d[0] * d[0] + d[1] * d[1];
    let s = if l2 > 0.0 { ((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / l2 } else { 0.0 };
    let s = s.clamp(0.0, 1.0);
    norm(sub(x, [a[0] + s * d[0], a[1] + s * d[1], 0.0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::CellType;
    use crate::mesh::generate;

    fn square() -> Mesh {
        generate::rectangle(CellType::Quad4, [0.0, 0.0], [2.0, 1.0], [8, 4]).unwrap()
    }

    #[test]
    fn segment_ends_outside_the_body_are_not_tips_and_growth_appends() {
        let mesh = square();
        let body = Body2d::new(&mesh);
        assert!((body.depth([1.0, 0.5, 0.0]) - 0.5).abs() < 1e-12);
        assert!(body.depth([3.0, 0.5, 0.0]) < 0.0);
        let edge = CrackShape::Segment { a: [-0.5, 0.51], b: [0.6, 0.51] };
        let mut g = GrowingCurve::from_shape(&edge, &body).unwrap();
        assert_eq!(g.tips, [false, true]);
        assert!(g.points[0][0] < -2.0);
        g.extend(1, [0.7, 0.61, 0.0]);
        assert!((g.grown[1] - 0.02f64.sqrt()).abs() < 1e-12);
        let CrackShape::Mesh(m) = g.shape().unwrap() else { panic!() };
        let (phi_n, phi_t) = m.level_sets_at([0.8, 0.71, 0.0]);
        assert!(phi_n.abs() < 1e-12, "on the extension of the last segment: {phi_n}");
        assert!((phi_t.unwrap() - 0.02f64.sqrt()).abs() < 1e-12);
        assert!(body.contains_segment([0.6, 0.51, 0.0], [1.9, 0.5, 0.0]));
        assert!(!body.contains_segment([0.6, 0.51, 0.0], [2.1, 0.5, 0.0]));
        assert!(g.crosses([0.65, 0.0, 0.0], [0.65, 1.0, 0.0]));
        assert!(!g.crosses([1.0, 0.0, 0.0], [1.0, 1.0, 0.0]));
        assert!((g.distance([0.5, 0.0, 0.0]) - 0.51).abs() < 1e-12);
        // The boundary nearest a point names its face groups (the generator's sides).
        assert_eq!(body.nearest_boundary_groups([1.95, 0.5, 0.0]), vec!["right"]);
        assert_eq!(body.nearest_boundary_groups([2.3, 0.4, 0.0]), vec!["right"]);
        assert_eq!(body.nearest_boundary_groups([1.0, 0.02, 0.0]), vec!["bottom"]);
    }
}
