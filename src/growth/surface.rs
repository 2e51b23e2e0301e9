//! The growing 3D crack: a triangulated surface with one closed front, grown by a strip of
//! triangles per increment, and the body it grows in.
//!
//! Entry points: [`GrowingSurface::from_shape`] (a `disc`, `elliptic_disc` or meshed
//! surface with one closed front loop → triangles and front), [`GrowingSurface::frames`]
//! (the front frame at each front vertex), [`GrowingSurface::advance`] (moves the front:
//! each vertex by Δa(s) along cos θ e1 + sin θ e2, then the new front re-sampled and a
//! strip of triangles appended between the old and the new front),
//! [`GrowingSurface::shape`] (→ the `shape = "mesh"` crack of
//! [`crate::levelset::explicit`], whose φn and φt are distances to the surface and its
//! front), [`interpolate_on_front`] (values at the SIF points → the front vertices) and
//! [`Body3d`] (inside / distance to the boundary / local cell size).
//!
//! Front spacing (docs/conventions.md, "Crack growth"): the initial front and every new
//! one are sampled at the mean edge length of the cells the front runs through (at least
//! 12 points), so that the front has about one vertex per cell it crosses. The new front
//! passes through the advanced vertices by a closed Catmull–Rom curve, re-sampled at that
//! spacing by arc length; the advances and kink angles are first smoothed along the front
//! by two passes of the (¼, ½, ¼) filter (exact for a uniform advance, so a circle grows
//! into a circle). The front polygon's vertices are set off the smooth front they sample
//! by their chord offsets ([`GrowingSurface::chord_offsets`]), so that the polygon has
//! the curve's mean radius and area. [`smooth_along_front`] smooths the SIF points' K_eq
//! along the front before the advances are normalised (a local linear fit).
//!
//! Surface cracks (docs/conventions.md, "Crack growth", "Surface cracks"): the front loop
//! may run out of the body through a face (an `elliptic_disc` centred on it); its part
//! outside is ignored by the level sets and moves with the two ends, the points where the
//! loop crosses the surface ([`surface_crossings`]), which therefore stay on the face.
//! [`Body3d::open_faces`] names the faces the loop runs out through, and
//! [`smooth_k_eq_trusted`] extrapolates K_eq from the points inside to those near the
//! faces and to the ends.
//!
//! Orientation: the triangles are oriented with their normal towards `+`, and the front
//! loop runs counter-clockwise seen from `+` (the surface on its left), so at a front
//! vertex e1 = t × n with t the loop tangent and n the surface normal (outward), e2 = n.

use crate::geometry::vec3::{add, cross, dot, norm, scale, sub};
use crate::levelset::explicit::{ExplicitCrack, ExplicitError};
use crate::levelset::CrackShape;
use crate::mesh::Mesh;
use std::f64::consts::PI;
use std::sync::Arc;

/// A 3D crack as a triangulated surface with a closed front.
#[derive(Debug, Clone)]
pub struct GrowingSurface {
    pub vertices: Vec<[f64; 3]>,
    /// Triangles, normals towards `+`.
    pub triangles: Vec<[usize; 3]>,
    /// The front: a closed loop of vertex indices, counter-clockwise seen from `+`.
    pub front: Vec<usize>,
    /// The largest total advance of the front so far (the sum of the increments' largest
    /// advances).
    pub grown: f64,
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    scale(1.0 / norm(a), a)
}

impl GrowingSurface {
    /// The surface of a 3D crack shape, its front sampled at `spacing`: a disc or an
    /// elliptic disc (rings of triangles, the outer ring the front) or a meshed surface
    /// whose front edges form one closed loop. `Err` says why the shape cannot grow.
    pub fn from_shape(shape: &CrackShape, spacing: f64) -> Result<GrowingSurface, String> {
        let shape = shape.normalised().map_err(|e| e.to_string())?;
        match &shape {
            CrackShape::Disc { centre, normal, radius } => {
                let u = crate::levelset::shapes::reference_in_plane(*normal);
                let v = cross(*normal, u);
                Ok(rings(*centre, scale(*radius, u), scale(*radius, v), 2.0 * PI * radius, spacing))
            }
            CrackShape::EllipticDisc { centre, normal, major_axis, semi_axes } => {
                let u = unit(sub(*major_axis, scale(dot(*major_axis, *normal), *normal)));
                let v = cross(*normal, u);
                let (a, b) = (semi_axes[0], semi_axes[1]);
                // Ramanujan's perimeter.
                let h = ((a - b) / (a + b)).powi(2);
                let perimeter = PI * (a + b) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()));
                Ok(rings(*centre, scale(a, u), scale(b, v), perimeter, spacing))
            }
            CrackShape::Mesh(m) => match m.as_ref() {
                ExplicitCrack::Surface(s) => {
                    let edges: Vec<[usize; 2]> = s.front.iter().map(|(e, _)| *e).collect();
                    let mut front = closed_loop(&edges).ok_or_else(|| {
                        "its front edges do not form one closed loop (a growing meshed crack has one closed front)"
                            .to_string()
                    })?;
                    // Counter-clockwise seen from +: the surface on the left of the loop.
                    let (a, b) = (front[0], front[1]);
                    let k = s
                        .triangles
                        .iter()
                        .position(|t| t.contains(&a) && t.contains(&b))
                        .ok_or("a front edge has no triangle")?;
                    let t = s.triangles[k];
                    let c = t.iter().copied().find(|v| *v != a && *v != b).ok_or("a triangle on the front has a repeated vertex")?;
                    let out = cross(sub(s.vertices[b], s.vertices[a]), s.normals[k]);
                    if dot(out, sub(s.vertices[c], s.vertices[a])) > 0.0 {
                        front.reverse();
                    }
                    Ok(GrowingSurface {
                        vertices: s.vertices.clone(),
                        triangles: s.triangles.clone(),
                        front,
                        grown: 0.0,
                    })
                }
                ExplicitCrack::Curve(_) => Err("a meshed curve is a 2D crack".into()),
            },
            other => Err(format!(
                "a '{}' cannot grow in 3D: a growing 3D crack is a disc, an elliptic_disc or a meshed surface with one closed front",
                other.name()
            )),
        }
    }

    /// The front vertices' positions, in loop order.
    pub fn front_points(&self) -> Vec<[f64; 3]> {
        self.front.iter().map(|&v| self.vertices[v]).collect()
    }

    /// The front frame (e1, e2) at each front vertex: n the mean normal of the triangles
    /// at the vertex, t the loop tangent (central difference), e1 = t × n normalised, e2 = n.
    pub fn frames(&self) -> Vec<([f64; 3], [f64; 3])> {
        let mut normals = vec![[0.0; 3]; self.vertices.len()];
        for t in &self.triangles {
            let n = cross(sub(self.vertices[t[1]], self.vertices[t[0]]), sub(self.vertices[t[2]], self.vertices[t[0]]));
            let n = unit(n);
            for &v in t {
                normals[v] = add(normals[v], n);
            }
        }
        let m = self.front.len();
        (0..m)
            .map(|i| {
                let (p, q) = (self.vertices[self.front[(i + m - 1) % m]], self.vertices[self.front[(i + 1) % m]]);
                let n = unit(normals[self.front[i]]);
                let t = sub(q, p);
                let t = unit(sub(t, scale(dot(t, n), n)));
                (unit(cross(t, n)), n)
            })
            .collect()
    }

    /// Moves the front: vertex i by `advance[i]` along cos θ_i e1 + sin θ_i e2 (both
    /// smoothed along the front first), the new front re-sampled at `spacing` and joined
    /// to the old one by a strip of triangles. Returns the new front's points.
    /// The smooth front moves, not its polygon: each vertex is first brought back onto
    /// the curve it stands for (by its chord offset, [`GrowingSurface::chord_offsets`]),
    /// moved, and the new front's vertices are set off the new curve by theirs.
    pub fn advance(&mut self, advance: &[f64], theta: &[f64], spacing: f64) -> Vec<[f64; 3]> {
        let m = self.front.len();
        assert_eq!(advance.len(), m);
        let (advance, theta) = (smooth(advance, 2), smooth(theta, 2));
        let frames = self.frames();
        let offsets = self.chord_offsets(&frames);
        let moved: Vec<[f64; 3]> = (0..m)
            .map(|i| {
                let (e1, e2) = frames[i];
                let on_curve = sub(self.vertices[self.front[i]], scale(offsets[i], e1));
                let d = add(scale(theta[i].cos(), e1), scale(theta[i].sin(), e2));
                add(on_curve, scale(advance[i], d))
            })
            .collect();
        let new = resample_closed(&moved, spacing);
        let first = self.vertices.len();
        self.vertices.extend_from_slice(&new);
        let new_loop: Vec<usize> = (first..first + new.len()).collect();
        let strip = strip(&self.vertices, &self.front, &new_loop);
        self.triangles.extend(strip);
        self.front = new_loop;
        self.set_off_chords();
        self.grown += advance.iter().copied().fold(0.0, f64::max);
        self.front_points()
    }

    /// How far each front vertex lies outside the smooth front its polygon stands for,
    /// along e1: one sixth of its sagitta s (the distance from the chord of its two
    /// neighbours to it, along e1). A curve of curvature κ sampled at spacing h has
    /// s = κh²/2, and the chord between two vertices set off the curve by κh²/12 lies on
    /// average on the curve (the curve bulges κh²/8 beyond the chord at its middle,
    /// κh²/12 on average over it): the polygon then has the mean radius and the area of
    /// the curve to O(h⁴) instead of falling short of them by κh²/12 (docs/conventions.md,
    /// "Crack growth").
    pub fn chord_offsets(&self, frames: &[([f64; 3], [f64; 3])]) -> Vec<f64> {
        let m = self.front.len();
        (0..m)
            .map(|i| {
                let (p, q) = (self.vertices[self.front[(i + m - 1) % m]], self.vertices[self.front[(i + 1) % m]]);
                let mid = scale(0.5, add(p, q));
                dot(sub(self.vertices[self.front[i]], mid), frames[i].0) / 6.0
            })
            .collect()
    }

    /// Sets the front vertices, sampled on the smooth front, off it by their chord
    /// offsets (outwards where the front is convex).
    fn set_off_chords(&mut self) {
        let frames = self.frames();
        let offsets = self.chord_offsets(&frames);
        for (i, &v) in self.front.iter().enumerate() {
            self.vertices[v] = add(self.vertices[v], scale(offsets[i], frames[i].0));
        }
    }

    /// The explicit crack of the surface (the `shape = "mesh"` representation).
    pub fn shape(&self) -> Result<CrackShape, ExplicitError> {
        let m = self.front.len();
        let edges: Vec<[usize; 2]> = (0..m).map(|i| [self.front[i], self.front[(i + 1) % m]]).collect();
        let c = ExplicitCrack::new_surface(&self.vertices, &self.triangles, Some(&edges))?;
        Ok(CrackShape::Mesh(Arc::new(c)))
    }
}

/// The surface c + s (cos φ a + sin φ b), s ∈ [0, 1], in rings about one `spacing` apart,
/// each ring with about perimeter·s / spacing points (at least 6; the front at least 12).
fn rings(c: [f64; 3], a: [f64; 3], b: [f64; 3], perimeter: f64, spacing: f64) -> GrowingSurface {
    let radius = 0.5 * (norm(a) + norm(b));
    let nr = ((radius / spacing).round() as usize).max(1);
    let mut vertices = vec![c];
    let mut triangles = vec![];
    let mut previous = vec![0usize];
    for k in 1..=nr {
        let s = k as f64 / nr as f64;
        let min = if k == nr { 12 } else { 6 };
        let n = ((perimeter * s / spacing).round() as usize).max(min);
        let first = vertices.len();
        for j in 0..n {
            let phi = 2.0 * PI * j as f64 / n as f64;
            vertices.push(add(c, scale(s, add(scale(phi.cos(), a), scale(phi.sin(), b)))));
        }
        let ring: Vec<usize> = (first..first + n).collect();
        if k == 1 {
            for j in 0..n {
                triangles.push([0, ring[j], ring[(j + 1) % n]]);
            }
        } else {
            triangles.extend(strip(&vertices, &previous, &ring));
        }
        previous = ring;
    }
    let mut g = GrowingSurface { vertices, triangles, front: previous, grown: 0.0 };
    g.set_off_chords();
    g
}

/// The triangles between two closed loops `old` (inner) and `new` (outer), both
/// counter-clockwise seen from `+`, normals towards `+`: the new loop is started at its
/// vertex nearest old[0], then the shorter diagonal is taken at each step.
fn strip(x: &[[f64; 3]], old: &[usize], new: &[usize]) -> Vec<[usize; 3]> {
    let (n, m) = (old.len(), new.len());
    let d = |a: usize, b: usize| norm(sub(x[a], x[b]));
    let j0 = (0..m).min_by(|&i, &j| d(new[i], old[0]).total_cmp(&d(new[j], old[0]))).unwrap_or(0);
    let o = |i: usize| old[i % n];
    let w = |j: usize| new[(j0 + j) % m];
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::with_capacity(n + m);
    while i < n || j < m {
        let take_old = if i == n {
            false
        } else if j == m {
            true
        } else {
            d(o(i + 1), w(j)) <= d(w(j + 1), o(i))
        };
        if take_old {
            out.push([o(i), w(j), o(i + 1)]);
            i += 1;
        } else {
            out.push([o(i), w(j), w(j + 1)]);
            j += 1;
        }
    }
    out
}

/// Passes of the periodic (¼, ½, ¼) filter.
fn smooth(v: &[f64], passes: usize) -> Vec<f64> {
    let mut v = v.to_vec();
    let m = v.len();
    if m < 3 {
        return v;
    }
    for _ in 0..passes {
        v = (0..m).map(|i| 0.25 * v[(i + m - 1) % m] + 0.5 * v[i] + 0.25 * v[(i + 1) % m]).collect();
    }
    v
}

/// A closed curve through `p` (uniform Catmull–Rom), re-sampled by arc length at about
/// `spacing` (at least 12 points), starting at `p[0]`.
pub fn resample_closed(p: &[[f64; 3]], spacing: f64) -> Vec<[f64; 3]> {
    let m = p.len();
    let sub_n = 16;
    let mut dense = Vec::with_capacity(m * sub_n + 1);
    for i in 0..m {
        let (p0, p1, p2, p3) = (p[(i + m - 1) % m], p[i], p[(i + 1) % m], p[(i + 2) % m]);
        for k in 0..sub_n {
            let t = k as f64 / sub_n as f64;
            let (t2, t3) = (t * t, t * t * t);
            let c0 = -0.5 * t3 + t2 - 0.5 * t;
            let c1 = 1.5 * t3 - 2.5 * t2 + 1.0;
            let c2 = -1.5 * t3 + 2.0 * t2 + 0.5 * t;
            let c3 = 0.5 * t3 - 0.5 * t2;
            dense.push(add(add(scale(c0, p0), scale(c1, p1)), add(scale(c2, p2), scale(c3, p3))));
        }
    }
    dense.push(p[0]);
    let mut s = vec![0.0];
    for w in dense.windows(2) {
        s.push(s.last().unwrap() + norm(sub(w[1], w[0])));
    }
    let total = *s.last().unwrap();
    let n = ((total / spacing).round() as usize).max(12);
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    for j in 0..n {
        let target = total * j as f64 / n as f64;
        while k + 1 < s.len() - 1 && s[k + 1] < target {
            k += 1;
        }
        let f = if s[k + 1] > s[k] { ((target - s[k]) / (s[k + 1] - s[k])).clamp(0.0, 1.0) } else { 0.0 };
        out.push(add(dense[k], scale(f, sub(dense[k + 1], dense[k]))));
    }
    out
}

/// The closed loop of `edges`, as vertex indices, or `None` if they are not one loop.
fn closed_loop(edges: &[[usize; 2]]) -> Option<Vec<usize>> {
    let mut adj: std::collections::HashMap<usize, Vec<usize>> = std::collections::HashMap::new();
    for e in edges {
        adj.entry(e[0]).or_default().push(e[1]);
        adj.entry(e[1]).or_default().push(e[0]);
    }
    if edges.len() < 3 || adj.values().any(|n| n.len() != 2) {
        return None;
    }
    let start = edges[0][0];
    let mut out = vec![start];
    let (mut prev, mut v) = (start, edges[0][1]);
    while v != start {
        out.push(v);
        let next = adj[&v].iter().copied().find(|&w| w != prev)?;
        (prev, v) = (v, next);
        if out.len() > edges.len() {
            return None;
        }
    }
    (out.len() == edges.len()).then_some(out)
}

/// The arc length along the closed polygon `front` (from its first vertex) of the
/// projection of each of the points `at` (its nearest point on the front), and the
/// perimeter.
fn arc_positions(front: &[[f64; 3]], at: &[[f64; 3]]) -> (Vec<f64>, f64) {
    let m = front.len();
    let mut s = vec![0.0; m + 1];
    for i in 0..m {
        s[i + 1] = s[i] + norm(sub(front[(i + 1) % m], front[i]));
    }
    let positions = at
        .iter()
        .map(|x| {
            let mut best = (f64::INFINITY, 0.0);
            for i in 0..m {
                let (a, b) = (front[i], front[(i + 1) % m]);
                let d = sub(b, a);
                let l2 = dot(d, d);
                let t = if l2 > 0.0 { (dot(sub(*x, a), d) / l2).clamp(0.0, 1.0) } else { 0.0 };
                let dist = norm(sub(*x, add(a, scale(t, d))));
                if dist < best.0 {
                    best = (dist, s[i] + t * l2.sqrt());
                }
            }
            best.1
        })
        .collect();
    (positions, s[m])
}

/// Linear interpolation, periodic in the arc length of the closed `front`, of `values`
/// given at the points `at` (each placed at the arc length of its nearest point on the
/// front): one value per front vertex. Needs at least one point.
pub fn interpolate_on_front(front: &[[f64; 3]], at: &[[f64; 3]], values: &[f64]) -> Vec<f64> {
    let m = front.len();
    let (positions, total) = arc_positions(front, at);
    let mut s = vec![0.0; m];
    for i in 1..m {
        s[i] = s[i - 1] + norm(sub(front[i], front[i - 1]));
    }
    let mut samples: Vec<(f64, f64)> = positions.into_iter().zip(values.iter().copied()).collect();
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = samples.len();
    (0..m)
        .map(|i| {
            if n == 1 {
                return samples[0].1;
            }
            let x = s[i];
            // The samples around x, periodic.
            let k = samples.partition_point(|p| p.0 <= x);
            let (lo, hi) = if k == 0 || k == n {
                let (l, h) = (samples[n - 1], samples[0]);
                let lo_s = if k == 0 { l.0 - total } else { l.0 };
                let hi_s = if k == 0 { h.0 } else { h.0 + total };
                ((lo_s, l.1), (hi_s, h.1))
            } else {
                (samples[k - 1], samples[k])
            };
            if hi.0 > lo.0 {
                lo.1 + (hi.1 - lo.1) * (x - lo.0) / (hi.0 - lo.0)
            } else {
                lo.1
            }
        })
        .collect()
}

/// `values` at the points `at` smoothed along the closed `front`: at each point, the
/// local linear fit in the arc length s (periodic: the distance along the front the
/// shorter way round) of all the values, weighted by the tricube kernel
/// (1 − (|Δs|/length)³)³, evaluated there (a LOESS smoother of half-width `length`). A
/// uniform or linearly varying field is returned unchanged. A point with fewer than three
/// values within the window (counting itself) keeps its weighted mean.
pub fn smooth_along_front(front: &[[f64; 3]], at: &[[f64; 3]], values: &[f64], length: f64) -> Vec<f64> {
    fit_along_front(front, at, values, &vec![true; at.len()], length, at)
}

/// The local linear fit of [`smooth_along_front`] built on the values at the points `at`
/// marked `trusted` only, evaluated at the points `targets` (anywhere on the front). A
/// target beyond the trusted points (the end of a surface crack's front, where the corner
/// singularity corrupts K) gets the fit's linear extrapolation: its window is widened by
/// its arc distance to the nearest trusted point, so that it holds as many trusted values
/// as an interior point's.
pub fn fit_along_front(
    front: &[[f64; 3]],
    at: &[[f64; 3]],
    values: &[f64],
    trusted: &[bool],
    length: f64,
    targets: &[[f64; 3]],
) -> Vec<f64> {
    let (s, total) = arc_positions(front, at);
    let (st, _) = arc_positions(front, targets);
    let n = s.len();
    let periodic = |from: f64, to: f64| {
        let mut d = (to - from).rem_euclid(total);
        if d > 0.5 * total {
            d -= total;
        }
        d
    };
    st.iter()
        .map(|&x| {
            let gap = (0..n).filter(|&k| trusted[k]).map(|k| periodic(x, s[k]).abs()).fold(f64::INFINITY, f64::min);
            let length = if gap.is_finite() { length + gap } else { length };
            let (mut w0, mut w1, mut w2, mut v0, mut v1, mut count) = (0.0, 0.0, 0.0, 0.0, 0.0, 0);
            for k in (0..n).filter(|&k| trusted[k]) {
                let d = periodic(x, s[k]);
                let r = d.abs() / length;
                if r >= 1.0 {
                    continue;
                }
                let w = (1.0 - r * r * r).powi(3);
                count += 1;
                w0 += w;
                w1 += w * d;
                w2 += w * d * d;
                v0 += w * values[k];
                v1 += w * d * values[k];
            }
            // The fit a + b·d at d = 0: a = (w2 v0 − w1 v1) / (w0 w2 − w1²).
            let det = w0 * w2 - w1 * w1;
            if count >= 3 && det > 1e-12 * w0 * w2 {
                (w2 * v0 - w1 * v1) / det
            } else {
                v0 / w0
            }
        })
        .collect()
}

/// The half-width of the smoothing of K_eq along a 3D front, in SIF-point spacings
/// ([`smooth_k_eq`]).
pub const SMOOTHING_SPANS: f64 = 3.0;

/// The driving force K_eq of the SIF points `at` of a closed `front`, smoothed along it
/// ([`smooth_along_front`]) over a half-width of [`SMOOTHING_SPANS`] SIF-point spacings
/// (the length over which the K are resolved along the front: the SIF domain radius).
/// Fewer than three points are returned as they are.
pub fn smooth_k_eq(front: &[[f64; 3]], at: &[[f64; 3]], k_eq: &[f64]) -> Vec<f64> {
    if at.len() < 3 {
        return k_eq.to_vec();
    }
    smooth_along_front(front, at, k_eq, SMOOTHING_SPANS * point_spacing(front, at))
}

/// [`smooth_k_eq`] for a front part of which lies outside the body (a surface crack):
/// the fit is built on the `trusted` points only and evaluated at every point of `at` and
/// at the `extra` points (the front's crossings with the body surface), so that the
/// points near the free surface, whose K the corner singularity corrupts, and the
/// crossings get the linear extrapolation of the K inside ([`fit_along_front`];
/// docs/conventions.md, "Crack growth"). With fewer than three trusted points every point
/// is trusted.
pub fn smooth_k_eq_trusted(
    front: &[[f64; 3]],
    at: &[[f64; 3]],
    k_eq: &[f64],
    trusted: &[bool],
    extra: &[[f64; 3]],
) -> (Vec<f64>, Vec<f64>) {
    let all = vec![true; at.len()];
    let trusted = if trusted.iter().filter(|t| **t).count() >= 3 { trusted } else { &all };
    if at.len() < 3 {
        let mean = k_eq.iter().sum::<f64>() / k_eq.len().max(1) as f64;
        return (k_eq.to_vec(), vec![mean; extra.len()]);
    }
    let length = SMOOTHING_SPANS * point_spacing(front, at);
    let mut targets = at.to_vec();
    targets.extend_from_slice(extra);
    let mut fit = fit_along_front(front, at, k_eq, trusted, length, &targets);
    let tail = fit.split_off(at.len());
    (fit, tail)
}

/// The spacing of the SIF points `at` along the closed `front`: the perimeter over their
/// number, or, when one gap between consecutive points is more than 2.5 times the median
/// gap (a surface crack: the part of the loop outside the body has no point), the rest of
/// the perimeter over the other gaps.
fn point_spacing(front: &[[f64; 3]], at: &[[f64; 3]]) -> f64 {
    let (mut s, total) = arc_positions(front, at);
    let n = s.len();
    s.sort_by(f64::total_cmp);
    let mut gaps: Vec<f64> =
        (0..n).map(|i| if i + 1 < n { s[i + 1] - s[i] } else { s[0] + total - s[n - 1] }).collect();
    gaps.sort_by(f64::total_cmp);
    let (median, largest) = (gaps[n / 2], gaps[n - 1]);
    if n >= 3 && largest > 2.5 * median {
        (total - largest) / (n - 1) as f64
    } else {
        total / n as f64
    }
}

/// The points where the closed `front` crosses the surface of `body` (a surface crack's
/// front ends), in loop order: on each edge from a vertex inside to one outside (or on
/// the surface), where the depth interpolated linearly along the edge vanishes.
pub fn surface_crossings(front: &[[f64; 3]], body: &Body3d) -> Vec<[f64; 3]> {
    let m = front.len();
    let tol = 1e-9 * body.diagonal;
    let depth: Vec<f64> = front.iter().map(|x| body.depth(*x)).collect();
    let mut out = vec![];
    for i in 0..m {
        let j = (i + 1) % m;
        let (a, b) = (depth[i] > tol, depth[j] > tol);
        if a != b {
            let t = (depth[i] / (depth[i] - depth[j])).clamp(0.0, 1.0);
            out.push(add(front[i], scale(t, sub(front[j], front[i]))));
        }
    }
    out
}

/// A 3D body for the growth checks: its cells split into tetrahedra, its boundary faces.
pub struct Body3d {
    tets: Vec<([[f64; 3]; 4], usize)>,
    boxes: Vec<([f64; 3], [f64; 3])>,
    sizes: Vec<f64>,
    surface: Option<parry3d_f64::shape::TriMesh>,
    /// The diagonal of the bounding box.
    pub diagonal: f64,
}

impl Body3d {
    pub fn new(mesh: &Mesh) -> Body3d {
        use crate::element::CellType;
        const HEX: [[usize; 4]; 6] =
            [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]];
        let mut tets = vec![];
        let mut sizes = vec![];
        for (c, cell) in mesh.cells.iter().enumerate() {
            let x = |i: usize| mesh.nodes[cell.nodes()[i]];
            match cell.kind {
                CellType::Tet4 => tets.push(([x(0), x(1), x(2), x(3)], c)),
                CellType::Hex8 => tets.extend(HEX.iter().map(|t| ([x(t[0]), x(t[1]), x(t[2]), x(t[3])], c))),
                _ => {}
            }
            sizes.push(mesh.cell_edge_length(c));
        }
        let boxes = tets
            .iter()
            .map(|(t, _)| {
                let mut lo = t[0];
                let mut hi = t[0];
                for p in &t[1..] {
                    for i in 0..3 {
                        lo[i] = lo[i].min(p[i]);
                        hi[i] = hi[i].max(p[i]);
                    }
                }
                (lo, hi)
            })
            .collect();
        let mut v = vec![];
        let mut idx: Vec<[u32; 3]> = vec![];
        for f in mesh.boundary_faces() {
            let n = f.nodes();
            let base = v.len() as u32;
            let corners = if n.len() >= 4 { 4 } else { 3 };
            for &k in &n[..corners] {
                let p = mesh.nodes[k];
                v.push(parry3d_f64::math::Vector::new(p[0], p[1], p[2]));
            }
            idx.push([base, base + 1, base + 2]);
            if corners == 4 {
                idx.push([base, base + 2, base + 3]);
            }
        }
        let surface = parry3d_f64::shape::TriMesh::new(v, idx).ok();
        let (lo, hi) = mesh.bounding_box();
        Body3d { tets, boxes, sizes, surface, diagonal: norm(sub(hi, lo)) }
    }

    /// The cell holding `x` (on its faces included), if any.
    pub fn cell_of(&self, x: [f64; 3]) -> Option<usize> {
        let tol = 1e-12 * self.diagonal;
        (0..self.tets.len()).find_map(|k| {
            let (lo, hi) = self.boxes[k];
            if (0..3).any(|i| x[i] < lo[i] - tol || x[i] > hi[i] + tol) {
                return None;
            }
            let (t, c) = self.tets[k];
            let vol = |a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]| dot(sub(b, a), cross(sub(c, a), sub(d, a)));
            let v = vol(t[0], t[1], t[2], t[3]);
            let b = [
                vol(x, t[1], t[2], t[3]),
                vol(t[0], x, t[2], t[3]),
                vol(t[0], t[1], x, t[3]),
                vol(t[0], t[1], t[2], x),
            ];
            b.iter().all(|bi| bi / v >= -1e-10).then_some(c)
        })
    }

    /// Distance from `x` to the body surface, positive inside, negative outside.
    pub fn depth(&self, x: [f64; 3]) -> f64 {
        use parry3d_f64::query::PointQuery;
        let d = self.surface.as_ref().map_or(f64::INFINITY, |s| {
            let q = parry3d_f64::math::Vector::new(x[0], x[1], x[2]);
            let p = s.project_local_point(q, false).point;
            norm(sub(x, [p.x, p.y, p.z]))
        });
        if self.cell_of(x).is_some() {
            d
        } else {
            -d
        }
    }

    /// The outward unit normal of the body surface nearest `x`: along x − p (or p − x
    /// inside) with p the nearest surface point, and for `x` on the surface the normal of
    /// the boundary triangle it projects on, turned outwards. `None` without a surface.
    pub fn outward_normal(&self, x: [f64; 3]) -> Option<[f64; 3]> {
        use parry3d_f64::query::PointQueryWithLocation;
        let s = self.surface.as_ref()?;
        let q = parry3d_f64::math::Vector::new(x[0], x[1], x[2]);
        let (proj, (tri, _)) = s.project_local_point_and_get_location(q, false);
        let p = [proj.point.x, proj.point.y, proj.point.z];
        let d = sub(x, p);
        let inside = self.cell_of(x).is_some();
        if norm(d) > 1e-9 * self.diagonal {
            return Some(unit(if inside { scale(-1.0, d) } else { d }));
        }
        let t = s.triangle(tri);
        let n = unit(cross(
            sub([t.b.x, t.b.y, t.b.z], [t.a.x, t.a.y, t.a.z]),
            sub([t.c.x, t.c.y, t.c.z], [t.a.x, t.a.y, t.a.z]),
        ));
        let probe = sub(p, scale(1e-6 * self.diagonal, n));
        Some(if self.cell_of(probe).is_some() { n } else { scale(-1.0, n) })
    }

    /// The faces a crack's front runs out of the body through (a surface crack), as
    /// the outward normals of the body surface nearest its vertices outside the body or
    /// on its surface (one per direction); empty for a front inside the body.
    pub fn open_faces(&self, front: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let tol = 1e-9 * self.diagonal;
        let mut out: Vec<[f64; 3]> = vec![];
        for x in front.iter().filter(|x| self.depth(**x) <= tol) {
            if let Some(n) = self.outward_normal(*x) {
                if !out.iter().any(|o| dot(*o, n) > 0.99) {
                    out.push(n);
                }
            }
        }
        out
    }

    /// Whether the body surface nearest `x` is one of the `open` faces
    /// ([`Body3d::open_faces`]): its outward normal within about 25° of one of theirs.
    pub fn faces_open(&self, x: [f64; 3], open: &[[f64; 3]]) -> bool {
        self.outward_normal(x).is_some_and(|n| open.iter().any(|o| dot(*o, n) > 0.9))
    }

    /// The mean edge length of the cell holding `x` (the diagonal if none).
    pub fn cell_size(&self, x: [f64; 3]) -> f64 {
        self.cell_of(x).map_or(self.diagonal, |c| self.sizes[c])
    }

    /// The front spacing of the points `x`: the mean of their cells' edge lengths.
    pub fn spacing(&self, x: &[[f64; 3]]) -> f64 {
        let s: Vec<f64> = x.iter().filter_map(|p| self.cell_of(*p).map(|c| self.sizes[c])).collect();
        if s.is_empty() {
            self.diagonal / 20.0
        } else {
            s.iter().sum::<f64>() / s.len() as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::CellType;
    use crate::mesh::generate;

    fn radii(p: &[[f64; 3]]) -> (f64, f64, f64) {
        let r: Vec<f64> = p.iter().map(|x| x[0].hypot(x[1])).collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        (mean, r.iter().copied().fold(f64::INFINITY, f64::min), r.iter().copied().fold(0.0, f64::max))
    }

    /// The area enclosed by a front polygon in the plane z = 0.
    fn area(p: &[[f64; 3]]) -> f64 {
        let m = p.len();
        0.5 * (0..m).map(|i| p[i][0] * p[(i + 1) % m][1] - p[(i + 1) % m][0] * p[i][1]).sum::<f64>()
    }

    /// A disc of radius 1 sampled at h = 0.1: the front polygon's vertices lie outside
    /// the circle by its chord offset h²/12 (the polygon then encloses the circle's area
    /// to O(h⁴): an inscribed polygon falls short by h²/6 of it, 1.7e-3); a uniform
    /// advance of 0.1 three times gives a polygon of the circle of radius 1.3 in the same
    /// way, and the level sets of the grown surface are those of the grown disc (φn = z,
    /// φt = r − 1.3) within the chord error.
    #[test]
    fn a_disc_grows_into_a_disc_by_uniform_advances() {
        let disc = CrackShape::Disc { centre: [0.0; 3], normal: [0.0, 0.0, 1.0], radius: 1.0 };
        let mut g = GrowingSurface::from_shape(&disc, 0.1).unwrap();
        let (mean, lo, hi) = radii(&g.front_points());
        let h = 2.0 * PI / g.front.len() as f64;
        assert!((mean - 1.0 - h * h / 12.0).abs() < 1e-5 && hi - lo < 1e-9, "{mean} {lo} {hi}");
        assert!((area(&g.front_points()) / PI - 1.0).abs() < 1e-5, "{}", area(&g.front_points()) / PI);
        assert!((60..=66).contains(&g.front.len()), "{}", g.front.len());
        for (e1, e2) in g.frames() {
            assert!((e2[2] - 1.0).abs() < 1e-12 && e1[2].abs() < 1e-12);
        }
        let (p, (e1, _)) = (g.front_points()[0], g.frames()[0]);
        assert!((dot(e1, unit(p)) - 1.0).abs() < 1e-3, "e1 points outward: {e1:?} at {p:?}");
        for _ in 0..3 {
            let m = g.front.len();
            g.advance(&vec![0.1; m], &vec![0.0; m], 0.1);
        }
        let (mean, lo, hi) = radii(&g.front_points());
        assert!((mean - 1.3).abs() < 2e-3 && hi - lo < 2e-3, "{mean} {lo} {hi}");
        let a = area(&g.front_points()) / (PI * 1.3 * 1.3);
        assert!((a - 1.0).abs() < 1e-4, "area / π1.3² = {a}");
        assert!((g.grown - 0.3).abs() < 1e-12);
        let CrackShape::Mesh(m) = g.shape().unwrap() else { panic!() };
        for x in [[0.5, 0.2, 0.05], [1.2, -0.6, -0.1], [-1.0, -1.0, 0.2]] {
            let (n, t) = m.level_sets_at(x);
            assert!((n - x[2]).abs() < 1e-9, "φn at {x:?}: {n}");
            let r = x[0].hypot(x[1]);
            assert!((t.unwrap() - (r - 1.3)).abs() < 3e-3, "φt at {x:?}: {t:?}");
        }
        // A kink of +90° (towards e2 = +z) lifts the front by the advance (within the
        // chord offset h²/12 ≈ 8e-4: the new front's e1 is then nearly vertical, and the
        // offset along it moves the vertices off z = 0.05 by a small part of it).
        let m = g.front.len();
        let new = g.advance(&vec![0.05; m], &vec![0.5 * PI; m], 0.1);
        let dz = new.iter().map(|p| (p[2] - 0.05).abs()).fold(0.0, f64::max);
        assert!(dz < 1e-4, "{dz}");
    }

    /// The smoothing of K along a front keeps a uniform and a linear field, and takes
    /// most of a point-to-point scatter out: on a circle of 16 points (half-width three
    /// spacings), an alternating ±2% about a uniform value comes down below ±0.5%, so
    /// the largest value is within 0.5% of the mean.
    #[test]
    fn smoothing_along_the_front_keeps_uniform_and_linear_fields_and_damps_scatter() {
        let circle = |n: usize| -> Vec<[f64; 3]> {
            (0..n)
                .map(|k| {
                    let a = 2.0 * PI * (k as f64 + 0.3) / n as f64;
                    [a.cos(), a.sin(), 0.0]
                })
                .collect()
        };
        let front = circle(64);
        let at = circle(16);
        let length = 3.0 * 2.0 * PI / 16.0;
        let uniform = smooth_along_front(&front, &at, &[1.3; 16], length);
        assert!(uniform.iter().all(|v| (v - 1.3).abs() < 1e-12), "{uniform:?}");
        // Linear in the arc length over a part of the front away from where it wraps.
        let (s, _) = arc_positions(&front, &at);
        let linear: Vec<f64> = s.iter().map(|x| 2.0 + 0.1 * x).collect();
        let out = smooth_along_front(&front, &at, &linear, length);
        for i in 0..16 {
            if s[i] > length && s[i] < s.last().unwrap() - length {
                assert!((out[i] - linear[i]).abs() < 1e-9, "{i}: {} {}", out[i], linear[i]);
            }
        }
        let noisy: Vec<f64> = (0..16).map(|i| 1.0 + if i % 2 == 0 { 0.02 } else { -0.02 }).collect();
        let out = smooth_along_front(&front, &at, &noisy, length);
        assert!(out.iter().all(|v| (v - 1.0).abs() < 0.005), "{out:?}");
    }

    #[test]
    fn advances_are_interpolated_along_the_front_and_the_body_knows_its_inside() {
        let front: Vec<[f64; 3]> = (0..8)
            .map(|k| {
                let a = 2.0 * PI * k as f64 / 8.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        // Values at two points between vertices: linear in the arc length, periodic.
        let at = [front[1], front[5]];
        let v = interpolate_on_front(&front, &at, &[1.0, 3.0]);
        assert!((v[1] - 1.0).abs() < 1e-12 && (v[5] - 3.0).abs() < 1e-12);
        assert!((v[3] - 2.0).abs() < 1e-12 && (v[7] - 2.0).abs() < 1e-12, "{v:?}");
        let mesh = generate::box_mesh(CellType::Hex8, [-1.0; 3], [1.0; 3], [4, 4, 4]).unwrap();
        let body = Body3d::new(&mesh);
        assert!((body.depth([0.2, 0.1, 0.0]) - 0.8).abs() < 1e-12);
        assert!((body.depth([1.5, 0.0, 0.0]) + 0.5).abs() < 1e-12);
        assert!((body.cell_size([0.1, 0.1, 0.1]) - 0.5).abs() < 1e-12);
        let err = GrowingSurface::from_shape(&CrackShape::Plane { point: [0.0; 3], normal: [0.0, 0.0, 1.0] }, 0.1);
        assert!(err.unwrap_err().contains("'plane' cannot grow"));
    }

    /// A surface crack: the elliptic disc of semi-axes (c, a) = (1, 0.6) centred on the
    /// face z = 2 of the box [−2, 2]² × [0, 2] (hex8, h = 0.5), half of it outside. Its
    /// front loop crosses the face at (±c, 0, 2) (the ring vertices there lie on the face,
    /// set off along e1 = ±x by their chord offset κh²/12 = 2.3e-3 for the curvature
    /// κ = c/a² there and h = 0.1, so within 3e-3); that face is its one
    /// open face, so a point near it (inside or beyond) is on an open face and a point
    /// near the back face z = 0 is not. A uniform advance of 0.1 moves the loop out by 0.1
    /// (the part outside the body too), so the crossings move along the face, to
    /// (±1.1, 0, 2) within the chord offsets (3e-3), and stay on it.
    #[test]
    fn a_surface_crack_front_crosses_its_open_face_and_its_ends_move_along_it() {
        let mesh = generate::box_mesh(CellType::Hex8, [-2.0, -2.0, 0.0], [2.0, 2.0, 2.0], [8, 8, 4]).unwrap();
        let body = Body3d::new(&mesh);
        let shape = CrackShape::EllipticDisc {
            centre: [0.0, 0.0, 2.0],
            normal: [0.0, 1.0, 0.0],
            major_axis: [1.0, 0.0, 0.0],
            semi_axes: [1.0, 0.6],
        };
        let mut g = GrowingSurface::from_shape(&shape, 0.1).unwrap();
        let front = g.front_points();
        let open = body.open_faces(&front);
        assert_eq!(open.len(), 1, "{open:?}");
        assert!((open[0][2] - 1.0).abs() < 1e-9, "{open:?}");
        assert!(body.faces_open([0.3, 0.0, 1.9], &open) && body.faces_open([0.3, 0.0, 2.4], &open));
        assert!(!body.faces_open([0.3, 0.0, 0.1], &open) && !body.faces_open([1.95, 0.0, 1.0], &open));
        let ends = |front: &[[f64; 3]]| {
            let mut x = surface_crossings(front, &body);
            x.sort_by(|a, b| a[0].total_cmp(&b[0]));
            x
        };
        let before = ends(&front);
        assert_eq!(before.len(), 2, "{before:?}");
        for (e, want) in before.iter().zip([-1.0, 1.0]) {
            assert!((e[0] - want).abs() < 3e-3 && e[1].abs() < 1e-12 && (e[2] - 2.0).abs() < 1e-9, "{e:?}");
        }
        let m = g.front.len();
        let new = g.advance(&vec![0.1; m], &vec![0.0; m], 0.1);
        let after = ends(&new);
        assert_eq!(after.len(), 2, "{after:?}");
        for (e, want) in after.iter().zip([-1.1, 1.1]) {
            assert!((e[0] - want).abs() < 3e-3 && e[1].abs() < 1e-12 && (e[2] - 2.0).abs() < 1e-9, "{e:?}");
        }
        // The new vertices near or beyond the surface are all by the open face; the
        // deepest has moved from 0.6 to 0.7 below it.
        let cell = body.cell_size([0.0, 0.0, 1.0]);
        assert!(new.iter().filter(|x| body.depth(**x) < cell).all(|x| body.faces_open(*x, &open)));
        let deepest = new.iter().map(|x| 2.0 - x[2]).fold(0.0, f64::max);
        assert!((deepest - 0.7).abs() < 2e-3, "{deepest}");
    }

    /// The K of the points near a surface crack's ends, not trusted, are replaced by the
    /// linear extrapolation of the trusted ones: on a half circle of radius 1 (the loop
    /// closed by the other half, where there is no point), a field linear in the arc
    /// length with its two end points on each side 5% low comes back linear at every
    /// point and at the crossings (s = 0 and π), to 1e-9; the point spacing is that of the
    /// points, not the loop's perimeter over their number.
    #[test]
    fn untrusted_end_points_get_the_linear_extrapolation_of_the_inner_ones() {
        let front: Vec<[f64; 3]> = (0..128)
            .map(|k| {
                let a = 2.0 * PI * k as f64 / 128.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let n = 16;
        let at: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let a = PI * (k as f64 + 0.5) / n as f64;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        // Linear in the arc length along the front polygon.
        let field = |s: f64| 2.0 + 0.1 * s;
        let (s, _) = arc_positions(&front, &at);
        let ends = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]];
        let (s_ends, _) = arc_positions(&front, &ends);
        let mut k: Vec<f64> = s.iter().map(|s| field(*s)).collect();
        let mut trusted = vec![true; n];
        for i in [0, 1, n - 2, n - 1] {
            k[i] *= 0.95;
            trusted[i] = false;
        }
        assert!((point_spacing(&front, &at) - PI / n as f64).abs() < 1e-3, "{}", point_spacing(&front, &at));
        let (fit, at_ends) = smooth_k_eq_trusted(&front, &at, &k, &trusted, &ends);
        for i in 0..n {
            assert!((fit[i] - field(s[i])).abs() < 1e-9, "{i}: {} against {}", fit[i], field(s[i]));
        }
        for (v, s) in at_ends.iter().zip(s_ends) {
            assert!((v - field(s)).abs() < 1e-9, "{at_ends:?}");
        }
    }
}
