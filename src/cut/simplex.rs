//! Clipping of reference simplices and convex polygons by linear functions.
//!
//! Owns the vertex record [`Vtx`] carried through every cut (reference position, the
//! two level-set values, the parent nodes spanning the face it lies on, on-zero flags)
//! and the three clipping primitives: [`clip_polygon`] (2D pieces and 3D crack
//! polygons, Sutherland–Hodgman producing both sides at once), [`clip_segment`] (2D
//! facets) and [`split_tet`] (a tetrahedron by a plane → tetrahedra on each side plus
//! the cut polygon). Entry points: those three functions.
//!
//! Sign rule: a vertex is negative when φ < 0 and positive otherwise (an exact zero is
//! positive). Cut points on an edge are always interpolated from the negative end to
//! the positive end, so the same edge yields bit-identical points whichever piece or
//! cell cuts it; when the positive end is an exact zero the cut point *is* that vertex.

pub(crate) use crate::geometry::vec3::{cross, dot, norm, sub};

/// Index of φn in [`Vtx::phi`] / [`Vtx::on`].
pub(crate) const N: usize = 0;
/// Index of φt in [`Vtx::phi`] / [`Vtx::on`].
pub(crate) const T: usize = 1;

/// A vertex of a piece, in the parent reference coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Vtx {
    /// Parent reference coordinates.
    pub xi: [f64; 3],
    /// Values of φn and φt (linear on the reference sub-simplex, so interpolation is exact).
    pub phi: [f64; 2],
    /// Bit mask of the parent-local nodes spanning the smallest face of the reference
    /// sub-simplex that contains the vertex (1 bit: a node; 2 bits: a segment between
    /// two nodes, a parent edge or a diagonal of the reference split).
    pub supp: u8,
    /// The vertex lies exactly on φn = 0 / φt = 0 (created by that cut, or an exact zero).
    pub on: [bool; 2],
}

impl Vtx {
    #[inline]
    pub fn neg(&self, f: usize) -> bool {
        self.phi[f] < 0.0
    }
    /// On the front: φn = 0 and φt = 0.
    #[inline]
    pub fn on_front(&self) -> bool {
        self.on[N] && self.on[T]
    }
    #[inline]
    fn marked(mut self, f: usize) -> Vtx {
        if self.phi[f] == 0.0 {
            self.on[f] = true;
        }
        self
    }
}

/// The point where the edge (a, b) crosses φ_f = 0; a and b must be on opposite sides.
pub(crate) fn intersect(a: &Vtx, b: &Vtx, f: usize) -> Vtx {
    let (n, p) = if a.neg(f) { (a, b) } else { (b, a) };
    if p.phi[f] == 0.0 {
        let mut v = *p;
        v.on[f] = true;
        return v;
    }
    let s = n.phi[f] / (n.phi[f] - p.phi[f]);
    let g = 1 - f;
    let mut xi = [0.0; 3];
    for (k, x) in xi.iter_mut().enumerate() {
        *x = n.xi[k] + s * (p.xi[k] - n.xi[k]);
    }
    let mut phi = [0.0; 2];
    let on_g = n.on[g] && p.on[g];
    phi[g] = if on_g { 0.0 } else { n.phi[g] + s * (p.phi[g] - n.phi[g]) };
    let mut on = [false; 2];
    on[f] = true;
    on[g] = on_g;
    Vtx { xi, phi, supp: n.supp | p.supp, on }
}

/// Both sides of a convex polygon cut by φ_f = 0, and the cut points in walk order.
#[derive(Debug, Default)]
pub(crate) struct PolygonClip {
    pub neg: Vec<Vtx>,
    pub pos: Vec<Vtx>,
    pub cross: Vec<Vtx>,
}

/// Sutherland–Hodgman clip of a convex (planar) polygon by φ_f, keeping both sides.
/// Consecutive duplicate vertices are merged (their flags OR-ed). A side that is
/// empty or degenerate is returned as is; callers drop pieces by measure.
pub(crate) fn clip_polygon(poly: &[Vtx], f: usize) -> PolygonClip {
    let mut out = PolygonClip::default();
    let n = poly.len();
    for i in 0..n {
        let a = poly[i].marked(f);
        let b = poly[(i + 1) % n].marked(f);
        if a.neg(f) {
            out.neg.push(a);
        } else {
            out.pos.push(a);
        }
        if a.neg(f) != b.neg(f) {
            let p = intersect(&a, &b, f);
            out.neg.push(p);
            out.pos.push(p);
            out.cross.push(p);
        }
    }
    dedup_cyclic(&mut out.neg);
    dedup_cyclic(&mut out.pos);
    out
}

/// Merges consecutive vertices at the same reference position (cyclically).
pub(crate) fn dedup_cyclic(p: &mut Vec<Vtx>) {
    let mut w: Vec<Vtx> = Vec::with_capacity(p.len());
    for v in p.iter() {
        match w.last_mut() {
            Some(last) if last.xi == v.xi => merge(last, v),
            _ => w.push(*v),
        }
    }
    while w.len() > 1 && w[0].xi == w[w.len() - 1].xi {
        let last = w.pop().expect("len > 1");
        merge(&mut w[0], &last);
    }
    *p = w;
}

fn merge(into: &mut Vtx, v: &Vtx) {
    into.on[0] |= v.on[0];
    into.on[1] |= v.on[1];
    into.supp &= v.supp;
    if into.supp == 0 {
        into.supp = v.supp;
    }
}

/// Clips the oriented segment (a, b) by φ_f: its negative part (same orientation) and
/// the cut point when the segment crosses.
pub(crate) fn clip_segment(a: &Vtx, b: &Vtx, f: usize) -> (Option<[Vtx; 2]>, Option<Vtx>) {
    let a = a.marked(f);
    let b = b.marked(f);
    match (a.neg(f), b.neg(f)) {
        (true, true) => (Some([a, b]), None),
        (false, false) => (None, None),
        (true, false) => {
            let p = intersect(&a, &b, f);
            (Some([a, p]), Some(p))
        }
        (false, true) => {
            let p = intersect(&a, &b, f);
            (Some([p, b]), Some(p))
        }
    }
}

/// A tetrahedron split by φ_f = 0: tetrahedra on each side and the cut polygon (a
/// triangle or a quadrilateral in cyclic order; empty when there is no sign change).
#[derive(Debug, Default)]
pub(crate) struct TetSplit {
    pub neg: Vec<[Vtx; 4]>,
    pub pos: Vec<[Vtx; 4]>,
    pub z: Vec<Vtx>,
}

/// Splits a prism (bottom a0 a1 a2, top b0 b1 b2, lateral edges ai–bi) into 3 tetrahedra.
fn prism(a: [Vtx; 3], b: [Vtx; 3], out: &mut Vec<[Vtx; 4]>) {
    out.push([a[0], a[1], a[2], b[0]]);
    out.push([a[1], a[2], b[0], b[1]]);
    out.push([a[2], b[0], b[1], b[2]]);
}

/// Splits a tetrahedron by φ_f (standard cases: 1|3 → tet + prism, 2|2 → two prisms,
/// prisms into 3 tets). Orientation and degeneracy are left to the caller.
pub(crate) fn split_tet(t: &[Vtx; 4], f: usize) -> TetSplit {
    let v: [Vtx; 4] = [t[0].marked(f), t[1].marked(f), t[2].marked(f), t[3].marked(f)];
    let mut neg = [0usize; 4];
    let mut pos = [0usize; 4];
    let (mut kn, mut kp) = (0, 0);
    for (i, x) in v.iter().enumerate() {
        if x.neg(f) {
            neg[kn] = i;
            kn += 1;
        } else {
            pos[kp] = i;
            kp += 1;
        }
    }
    let mut out = TetSplit::default();
    let x = |i: usize, j: usize| intersect(&v[i], &v[j], f);
    match kn {
        0 => out.pos.push(v),
        4 => out.neg.push(v),
        1 | 3 => {
            // The lone vertex a, the three others b, c, d.
            let (a, o) = if kn == 1 { (neg[0], [pos[0], pos[1], pos[2]]) } else { (pos[0], [neg[0], neg[1], neg[2]]) };
            let p = [x(a, o[0]), x(a, o[1]), x(a, o[2])];
            let tip = [v[a], p[0], p[1], p[2]];
            let (tips, rest) = if kn == 1 { (&mut out.neg, &mut out.pos) } else { (&mut out.pos, &mut out.neg) };
            tips.push(tip);
            prism(p, [v[o[0]], v[o[1]], v[o[2]]], rest);
            out.z = p.to_vec();
        }
        _ => {
            let (a, b, c, d) = (neg[0], neg[1], pos[0], pos[1]);
            let (pac, pad, pbc, pbd) = (x(a, c), x(a, d), x(b, c), x(b, d));
            prism([v[a], pac, pad], [v[b], pbc, pbd], &mut out.neg);
            prism([v[c], pac, pbc], [v[d], pad, pbd], &mut out.pos);
            out.z = vec![pac, pad, pbd, pbc];
        }
    }
    out
}

/// Signed area of a triangle in the (ξ, η) plane.
#[inline]
pub(crate) fn signed_area(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let (u, v) = (sub(b, a), sub(c, a));
    0.5 * (u[0] * v[1] - u[1] * v[0])
}

/// Signed volume of a tetrahedron.
#[inline]
pub(crate) fn signed_volume(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0
}

/// Area of a triangle in 3D.
#[inline]
pub(crate) fn triangle_area(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

/// Area of a convex planar polygon (fan from vertex 0), 3D.
pub(crate) fn polygon_area(p: &[Vtx]) -> f64 {
    (1..p.len().saturating_sub(1)).map(|i| triangle_area(&p[0].xi, &p[i].xi, &p[i + 1].xi)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vtx(xi: [f64; 3], phi: f64, bit: u8) -> Vtx {
        Vtx { xi, phi: [phi, -1.0], supp: 1 << bit, on: [phi == 0.0, false] }
    }

    /// Tet split: the two sides' volumes add up to the tet's for every sign pattern
    /// (reference: the tet volume 1/6; tolerance 1e-15), and cut points carry the union
    /// of their edge's supports.
    #[test]
    fn tet_split_partitions_volume() {
        let r = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for mask in 0..16u32 {
            let phis: Vec<f64> =
                (0..4).map(|i| if mask & (1 << i) != 0 { -0.3 - 0.1 * i as f64 } else { 0.7 }).collect();
            let t = [vtx(r[0], phis[0], 0), vtx(r[1], phis[1], 1), vtx(r[2], phis[2], 2), vtx(r[3], phis[3], 3)];
            let s = split_tet(&t, N);
            let vol: f64 = s
                .neg
                .iter()
                .chain(s.pos.iter())
                .map(|t| signed_volume(&t[0].xi, &t[1].xi, &t[2].xi, &t[3].xi).abs())
                .sum();
            assert!((vol - 1.0 / 6.0).abs() < 1e-15, "mask {mask}: {vol}");
            for p in &s.z {
                assert!(p.on[N] && p.supp.count_ones() == 2);
            }
        }
    }

    /// Cut points are bit-identical whichever way the edge is walked (reference: the
    /// same point from (a, b) and (b, a); exact equality).
    #[test]
    fn cut_points_do_not_depend_on_orientation() {
        let a = vtx([0.1, 0.2, 0.0], -0.37, 0);
        let b = vtx([0.9, 0.05, 0.0], 0.52, 1);
        assert_eq!(intersect(&a, &b, N), intersect(&b, &a, N));
        let z = vtx([0.9, 0.05, 0.0], 0.0, 1);
        assert_eq!(intersect(&a, &z, N).xi, z.xi);
    }
}
