//! Analytic crack-front geometry for the stress-intensity-factor code: points on the front
//! of a built-in shape with their local frames. Entry point: [`front_points`] (→
//! [`FrontPoint`]).
//!
//! # Local front frame (e1, e2, e3)
//!
//! - e1: in the crack surface, normal to the front, pointing into the uncracked body (the
//!   propagation direction; φt grows along it).
//! - e2: normal to the crack.
//! - e3 = e1 × e2: tangent to the front. The frame is right-handed and orthonormal.
//!
//! **3D**: e2 = n, the crack normal (from `−` to `+`). Points on closed fronts are listed
//! in the +e3 direction (clockwise when seen from the `+` side, i.e. looking along −n).
//!
//! **2D**: e3 = +z at every tip, e1 = propagation direction, e2 = e3 × e1 = e1 rotated by
//! +90°. So e2 = +n where the `+` side is on the left of the propagation direction (end `b`
//! of a [`CrackShape::Segment`], the tip of a [`CrackShape::HalfLine`]) and e2 = −n at end
//! `a` of a segment. With the Williams fields written in (e1, e2) coordinates (θ from e1
//! towards e2), the "upper" lip θ = +π is the side e2 points to, and
//! K_I ∝ ⟦u⟧·e2 > 0 in opening, K_II ∝ ⟦u⟧·e1 with ⟦u⟧ = u(upper) − u(lower). K_I does
//! not depend on the sign of e2; K_II does, and this choice is the standard right-handed
//! one in the (x, y) plane, so the two tips of an inclined centre crack get the same K_II
//! (σ√(πa) sinβ cosβ, `docs/theory.md` §9). Keeping e2 = n at both tips would
//! give e3 = −z at end `a` and flip its K_II.

use super::shapes::{add, cross, reference_in_plane, scale};
use super::CrackShape;
use std::f64::consts::PI;

/// One point of a crack front and its local frame (see the module doc for orientations).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontPoint {
    /// Position (z = 0 in 2D).
    pub x: [f64; 3],
    /// In the crack surface, normal to the front, pointing into the uncracked body
    /// (propagation direction).
    pub e1: [f64; 3],
    /// Normal to the crack: n in 3D; in 2D e3 × e1 = ±n (see the module doc).
    pub e2: [f64; 3],
    /// Front tangent, e3 = e1 × e2 (+z in 2D).
    pub e3: [f64; 3],
}

fn frame2(x: [f64; 2], e1: [f64; 2]) -> FrontPoint {
    FrontPoint { x: [x[0], x[1], 0.0], e1: [e1[0], e1[1], 0.0], e2: [-e1[1], e1[0], 0.0], e3: [0.0, 0.0, 1.0] }
}

fn frame3(x: [f64; 3], e1: [f64; 3], n: [f64; 3]) -> FrontPoint {
    FrontPoint { x, e1, e2: n, e3: cross(e1, n) }
}

/// Points of the front of a built-in shape, with their frames:
/// - 2D segment: its two tips, `[a, b]` (`n` ignored); half-line: its tip.
/// - disc, elliptic disc: `n` points at equal steps of the polar (disc) or parametric
///   (ellipse: x = c + a cos θ u + b sin θ v, so points gather where the curvature is high)
///   angle, starting at +u and listed along +e3. For the disc u is the coordinate axis
///   least aligned with the normal (first on ties), made orthogonal to it (+x for n = +z);
///   for the elliptic disc u = `major_axis`.
/// - rectangle: `n` points per side at mid-steps ((k + ½)/n of the side, never at a
///   corner), sides in the order +u, −v, −u, +v, each walked along +e3.
/// - half-plane: the single `point_on_front`; the front is the straight line through it
///   along e3: march along e3 as far as the body requires.
/// - interfaces (line, ellipse, plane, sphere, cylinder): an empty list (no front).
///
/// `None` for formulas and meshed cracks (no analytic front) and for shapes with invalid parameters
/// ([`CrackShape::normalised`] says why). `n = 0` gives no point on closed fronts.
pub fn front_points(shape: &CrackShape, n: usize) -> Option<Vec<FrontPoint>> {
    let s = shape.normalised().ok()?;
    Some(match s {
        CrackShape::Segment { a, b } => {
            let d = [b[0] - a[0], b[1] - a[1]];
            let l = d[0].hypot(d[1]);
            let t = [d[0] / l, d[1] / l];
            vec![frame2(a, [-t[0], -t[1]]), frame2(b, t)]
        }
        CrackShape::HalfLine { tip, direction } => vec![frame2(tip, direction)],
        CrackShape::Disc { centre, normal, radius } => {
            let u = reference_in_plane(normal);
            let v = cross(normal, u);
            (0..n)
                .map(|k| {
                    let th = -2.0 * PI * k as f64 / n as f64;
                    let e1 = add(scale(th.cos(), u), scale(th.sin(), v));
                    frame3(add(centre, scale(radius, e1)), e1, normal)
                })
                .collect()
        }
        CrackShape::EllipticDisc { centre, normal, major_axis: u, semi_axes: [a, b] } => {
            let v = cross(normal, u);
            (0..n)
                .map(|k| {
                    let th = -2.0 * PI * k as f64 / n as f64;
                    let (c, sn) = (th.cos(), th.sin());
                    let x = add(centre, add(scale(a * c, u), scale(b * sn, v)));
                    let g = [c / a, sn / b];
                    let l = g[0].hypot(g[1]);
                    let e1 = add(scale(g[0] / l, u), scale(g[1] / l, v));
                    frame3(x, e1, normal)
                })
                .collect()
        }
        CrackShape::Rectangle { centre, normal, axis_u: u, half_lengths: [hu, hv] } => {
            let v = cross(normal, u);
            let m = scale(-1.0, u);
            let w = scale(-1.0, v);
            // (outward side normal e1, side centre offset, e3 direction, half length along e3)
            let sides = [
                (u, scale(hu, u), w, hv),
                (w, scale(hv, w), m, hu),
                (m, scale(hu, m), v, hv),
                (v, scale(hv, v), u, hu),
            ];
            let mut pts = Vec::with_capacity(4 * n);
            for (e1, off, e3, h) in sides {
                for k in 0..n {
                    let s = -h + 2.0 * h * (k as f64 + 0.5) / n as f64;
                    pts.push(frame3(add(centre, add(off, scale(s, e3))), e1, normal));
                }
            }
            pts
        }
        CrackShape::HalfPlane { point_on_front, normal, direction } => {
            vec![frame3(point_on_front, direction, normal)]
        }
        CrackShape::Line { .. }
        | CrackShape::Ellipse { .. }
        | CrackShape::Plane { .. }
        | CrackShape::Sphere { .. }
        | CrackShape::Cylinder { .. } => vec![],
        CrackShape::Formula { .. } | CrackShape::Mesh(_) => return None,
    })
}
