//! Built-in crack shapes and level-set formulas: the [`CrackShape`] enum, its validation
//! and normalisation ([`CrackShape::normalised`]), and the level sets at one point
//! ([`CrackShape::level_sets_at`], [`CrackShape::normal_at`]).
//!
//! Every built-in shape gives φn as the exact signed distance to its surface (the plane or
//! line extended for flat cracks) and φt as the signed distance to its front measured in
//! that surface, negative on the crack. Sign conventions are written on each variant.
//! The ellipse distance (2D [`CrackShape::Ellipse`], the front of
//! [`CrackShape::EllipticDisc`]) is computed by Eberly's robust root bracketing on the
//! closest-point equation, so it is the exact distance to round-off, not an approximation.

use super::LevelSetError;
use crate::formula::Formula as Expr;
pub(super) use crate::geometry::vec3::{add, cross, dot, norm, scale, sub};

/// Largest |cos| between a given normal and an in-plane axis (after both are normalised)
/// that is accepted; the axis is then made exactly orthogonal (Gram-Schmidt, the normal is
/// kept). Beyond it the input is an error: the two were clearly not meant to be orthogonal.
pub const ORTHOGONALITY_TOL: f64 = 1e-6;

/// One crack (or interface) geometry, given by built-in shape parameters or by formulas.
///
/// Directions need not be unit vectors: they are normalised (see [`CrackShape::normalised`]).
/// Angles are in radians. 2D shapes use the x and y coordinates; 3D shapes all three.
#[derive(Debug, Clone)]
pub enum CrackShape {
    /// 2D interior crack, the segment from `a` to `b`, with a tip (front point) at each end.
    /// With t = (b − a)/|b − a|: n = t rotated by +90° = (−t_y, t_x), so the `+` side is on
    /// the left of a→b; φn = (x − a)·n; φt = max(−s, s − L) with s = (x − a)·t, L = |b − a|
    /// (distance along the line to the nearer tip, negative between the tips).
    Segment { a: [f64; 2], b: [f64; 2] },
    /// 2D edge crack: the half-line coming from infinity along `direction` and ending at
    /// `tip` (the single front point). With d the unit direction: n = d rotated by +90°
    /// (`+` side on the left of `direction`), φn = (x − tip)·n, φt = (x − tip)·d.
    HalfLine { tip: [f64; 2], direction: [f64; 2] },
    /// 2D interface: the straight line through `point` with normal `normal` (pointing to the
    /// `+` side); φn = (x − point)·n, no φt.
    Line { point: [f64; 2], normal: [f64; 2] },
    /// 2D closed interface: the ellipse of centre `centre`, semi-axes `semi_axes[0]` along
    /// the direction at `angle` (radians, counter-clockwise from x) and `semi_axes[1]`
    /// across it. φn is the exact signed distance to the curve, `+` outside; a circle when
    /// the semi-axes are equal (φn = |x − c| − r). No φt.
    Ellipse { centre: [f64; 2], semi_axes: [f64; 2], angle: f64 },
    /// 3D penny crack: the disc of `centre`, unit normal `normal` (towards `+`) and `radius`.
    /// φn = (x − c)·n; φt = |(x − c) − φn n| − radius (distance to the axis within the
    /// plane minus the radius, negative on the disc).
    Disc { centre: [f64; 3], normal: [f64; 3], radius: f64 },
    /// 3D elliptic crack: centre, normal (towards `+`), `major_axis` (an in-plane direction,
    /// orthogonalised against the normal) and `semi_axes` = [a along `major_axis`, b along
    /// normal × major_axis]; a ≥ b is not required. φn = (x − c)·n; φt = exact signed
    /// distance, within the plane, from the projection of x to the ellipse (negative inside).
    EllipticDisc { centre: [f64; 3], normal: [f64; 3], major_axis: [f64; 3], semi_axes: [f64; 2] },
    /// 3D crack filling a rectangle: centre, normal (towards `+`), `axis_u` (in-plane,
    /// orthogonalised against the normal), `half_lengths` = [h_u along u, h_v along
    /// v = normal × u]. φn = (x − c)·n; φt = signed distance, in the plane, from the
    /// projection of x to the rectangle boundary (negative inside). Inside, the φt
    /// contours have sharp corners (φt = max(|ξ| − h_u, |η| − h_v)); outside they are
    /// rounded around the corners (distance to the corner point); the front itself, φt = 0,
    /// is exactly the rectangle. The front frame is undefined at the four corners.
    Rectangle { centre: [f64; 3], normal: [f64; 3], axis_u: [f64; 3], half_lengths: [f64; 2] },
    /// 3D crack occupying the half-plane behind the straight front through
    /// `point_on_front`: φn = (x − p)·n, φt = (x − p)·d, with d = `direction` (orthogonalised
    /// against the normal) lying in the plane and pointing from the crack into the
    /// uncracked body. The front is the straight line through `point_on_front` along
    /// d × n (the front tangent e3 of [`super::FrontPoint`]).
    HalfPlane { point_on_front: [f64; 3], normal: [f64; 3], direction: [f64; 3] },
    /// 3D interface: the plane through `point` with normal `normal` (towards `+`);
    /// φn = (x − p)·n, no φt.
    Plane { point: [f64; 3], normal: [f64; 3] },
    /// 3D closed interface: sphere, φn = |x − c| − radius (`+` outside), no φt.
    Sphere { centre: [f64; 3], radius: f64 },
    /// 3D closed interface: infinite circular cylinder around the line through `point`
    /// along `axis`; φn = (distance to the axis) − radius (`+` outside), no φt.
    Cylinder { point: [f64; 3], axis: [f64; 3], radius: f64 },
    /// User formulas of x, y, z (and parameters; evaluated at t = 0), valid in 2D and 3D.
    /// `lsn` should be (close to) a signed distance with n = ∇φn/|∇φn| towards `+`; `lst`
    /// the signed distance to the front within the crack surface, negative on the crack.
    /// Without `lst` the crack is an interface. (A parsed formula is tens of kB, which
    /// makes this enum large; there are a handful of cracks per model, so it is not boxed.)
    Formula { lsn: Expr, lst: Option<Expr> },
    /// A crack read from a Gmsh mesh (`shape = "mesh"`): a polyline in 2D, a triangle
    /// surface in 3D, with its front; level sets are signed distances to it
    /// ([`super::explicit`]). Shared, as the geometry can be large.
    Mesh(std::sync::Arc<super::explicit::ExplicitCrack>),
}

// ---------------------------------------------------------------------------------------
// Small vector helpers (3D; 2D points are embedded with z = 0 where needed).

#[inline]
fn e3(p: [f64; 2]) -> [f64; 3] {
    [p[0], p[1], 0.0]
}

/// Index of the smallest of `d` if it is at most `tol`.
fn nearest(d: &[f64], tol: f64) -> Option<usize> {
    let k = (0..d.len()).min_by(|&i, &j| d[i].total_cmp(&d[j]))?;
    (d[k] <= tol).then_some(k)
}

fn finite(shape: &'static str, what: &str, v: &[f64]) -> Result<(), LevelSetError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(LevelSetError::BadShape { shape, message: format!("{what} must be finite (got {v:?})") })
    }
}

fn positive(shape: &'static str, what: &str, v: f64) -> Result<(), LevelSetError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(LevelSetError::BadShape { shape, message: format!("{what} must be positive and finite (got {v})") })
    }
}

/// `v` normalised; an error if it is zero or not finite.
fn unit(shape: &'static str, what: &str, v: [f64; 3]) -> Result<[f64; 3], LevelSetError> {
    finite(shape, what, &v)?;
    let l = norm(v);
    let u = scale(1.0 / l, v);
    if l > 0.0 && l.is_finite() && u.iter().all(|x| x.is_finite()) {
        Ok(u)
    } else {
        Err(LevelSetError::BadShape { shape, message: format!("{what} must be a non-zero vector (got {v:?})") })
    }
}

fn unit2(shape: &'static str, what: &str, v: [f64; 2]) -> Result<[f64; 2], LevelSetError> {
    let u = unit(shape, what, e3(v))?;
    Ok([u[0], u[1]])
}

/// `v` made a unit vector orthogonal to the unit vector `n` (see [`ORTHOGONALITY_TOL`]).
fn in_plane_unit(shape: &'static str, what: &str, v: [f64; 3], n: [f64; 3]) -> Result<[f64; 3], LevelSetError> {
    let v = unit(shape, what, v)?;
    let c = dot(v, n);
    if c.abs() > ORTHOGONALITY_TOL {
        return Err(LevelSetError::BadShape {
            shape,
            message: format!(
                "{what} {v:?} must lie in the crack plane, i.e. be orthogonal to the normal {n:?} (cos of their angle is {c:.3e})"
            ),
        });
    }
    unit(shape, what, sub(v, scale(c, n)))
}

/// A unit vector orthogonal to the unit vector `n`: the coordinate axis least aligned with
/// `n` (the first one on ties), orthogonalised. For n = +z it is +x.
pub(crate) fn reference_in_plane(n: [f64; 3]) -> [f64; 3] {
    let mut k = 0;
    for i in 1..3 {
        if n[i].abs() < n[k].abs() {
            k = i;
        }
    }
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let w = sub(e, scale(n[k], n));
    scale(1.0 / norm(w), w)
}

impl CrackShape {
    /// The [`CrackShape::Formula`] variant from parsed formulas (`lst = None`: interface).
    pub fn formula(lsn: Expr, lst: Option<Expr>) -> CrackShape {
        CrackShape::Formula { lsn, lst }
    }

    /// Short name of the variant, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            CrackShape::Segment { .. } => "segment",
            CrackShape::HalfLine { .. } => "half-line",
            CrackShape::Line { .. } => "line",
            CrackShape::Ellipse { .. } => "ellipse",
            CrackShape::Disc { .. } => "disc",
            CrackShape::EllipticDisc { .. } => "elliptic disc",
            CrackShape::Rectangle { .. } => "rectangle",
            CrackShape::HalfPlane { .. } => "half-plane",
            CrackShape::Plane { .. } => "plane",
            CrackShape::Sphere { .. } => "sphere",
            CrackShape::Cylinder { .. } => "cylinder",
            CrackShape::Formula { .. } => "formula",
            CrackShape::Mesh(_) => "mesh",
        }
    }

    /// Dimension of the shape: `Some(2)` or `Some(3)`; `None` for formulas, which fit both.
    pub fn dim(&self) -> Option<usize> {
        match self {
            CrackShape::Segment { .. }
            | CrackShape::HalfLine { .. }
            | CrackShape::Line { .. }
            | CrackShape::Ellipse { .. } => Some(2),
            CrackShape::Disc { .. }
            | CrackShape::EllipticDisc { .. }
            | CrackShape::Rectangle { .. }
            | CrackShape::HalfPlane { .. }
            | CrackShape::Plane { .. }
            | CrackShape::Sphere { .. }
            | CrackShape::Cylinder { .. } => Some(3),
            CrackShape::Formula { .. } => None,
            CrackShape::Mesh(m) => Some(m.dim()),
        }
    }

    /// Whether the shape can be used on a mesh of dimension `dim`.
    pub fn accepts_dim(&self, dim: usize) -> bool {
        match self.dim() {
            Some(d) => d == dim,
            None => dim == 2 || dim == 3,
        }
    }

    /// Whether the shape has a front (a φt): cracks yes, interfaces no; a formula has one
    /// when it gives `lst`.
    pub fn has_front(&self) -> bool {
        match self {
            CrackShape::Segment { .. }
            | CrackShape::HalfLine { .. }
            | CrackShape::Disc { .. }
            | CrackShape::EllipticDisc { .. }
            | CrackShape::Rectangle { .. }
            | CrackShape::HalfPlane { .. } => true,
            CrackShape::Line { .. }
            | CrackShape::Ellipse { .. }
            | CrackShape::Plane { .. }
            | CrackShape::Sphere { .. }
            | CrackShape::Cylinder { .. } => false,
            CrackShape::Formula { lst, .. } => lst.is_some(),
            CrackShape::Mesh(m) => m.has_front(),
        }
    }

    /// Checks the parameters and returns the same shape with unit normals and directions,
    /// in-plane axes made exactly orthogonal to the normal (see [`ORTHOGONALITY_TOL`]).
    /// Errors say what is wrong (the caller adds the crack's name).
    pub fn normalised(&self) -> Result<CrackShape, LevelSetError> {
        let s = self.name();
        Ok(match self {
            CrackShape::Segment { a, b } => {
                finite(s, "end point a", a)?;
                finite(s, "end point b", b)?;
                let l = (b[0] - a[0]).hypot(b[1] - a[1]);
                let size = a[0].abs().max(a[1].abs()).max(b[0].abs()).max(b[1].abs());
                if !(l > 1e-12 * size && l > 0.0) {
                    return Err(LevelSetError::BadShape {
                        shape: s,
                        message: format!("the end points a = {a:?} and b = {b:?} coincide (zero-length segment)"),
                    });
                }
                CrackShape::Segment { a: *a, b: *b }
            }
            CrackShape::HalfLine { tip, direction } => {
                finite(s, "tip", tip)?;
                CrackShape::HalfLine { tip: *tip, direction: unit2(s, "direction", *direction)? }
            }
            CrackShape::Line { point, normal } => {
                finite(s, "point", point)?;
                CrackShape::Line { point: *point, normal: unit2(s, "normal", *normal)? }
            }
            CrackShape::Ellipse { centre, semi_axes, angle } => {
                finite(s, "centre", centre)?;
                finite(s, "angle", &[*angle])?;
                positive(s, "semi_axes[0]", semi_axes[0])?;
                positive(s, "semi_axes[1]", semi_axes[1])?;
                CrackShape::Ellipse { centre: *centre, semi_axes: *semi_axes, angle: *angle }
            }
            CrackShape::Disc { centre, normal, radius } => {
                finite(s, "centre", centre)?;
                positive(s, "radius", *radius)?;
                CrackShape::Disc { centre: *centre, normal: unit(s, "normal", *normal)?, radius: *radius }
            }
            CrackShape::EllipticDisc { centre, normal, major_axis, semi_axes } => {
                finite(s, "centre", centre)?;
                positive(s, "semi_axes[0]", semi_axes[0])?;
                positive(s, "semi_axes[1]", semi_axes[1])?;
                let n = unit(s, "normal", *normal)?;
                let u = in_plane_unit(s, "major_axis", *major_axis, n)?;
                CrackShape::EllipticDisc { centre: *centre, normal: n, major_axis: u, semi_axes: *semi_axes }
            }
            CrackShape::Rectangle { centre, normal, axis_u, half_lengths } => {
                finite(s, "centre", centre)?;
                positive(s, "half_lengths[0]", half_lengths[0])?;
                positive(s, "half_lengths[1]", half_lengths[1])?;
                let n = unit(s, "normal", *normal)?;
                let u = in_plane_unit(s, "axis_u", *axis_u, n)?;
                CrackShape::Rectangle { centre: *centre, normal: n, axis_u: u, half_lengths: *half_lengths }
            }
            CrackShape::HalfPlane { point_on_front, normal, direction } => {
                finite(s, "point_on_front", point_on_front)?;
                let n = unit(s, "normal", *normal)?;
                let d = in_plane_unit(s, "direction", *direction, n)?;
                CrackShape::HalfPlane { point_on_front: *point_on_front, normal: n, direction: d }
            }
            CrackShape::Plane { point, normal } => {
                finite(s, "point", point)?;
                CrackShape::Plane { point: *point, normal: unit(s, "normal", *normal)? }
            }
            CrackShape::Sphere { centre, radius } => {
                finite(s, "centre", centre)?;
                positive(s, "radius", *radius)?;
                CrackShape::Sphere { centre: *centre, radius: *radius }
            }
            CrackShape::Cylinder { point, axis, radius } => {
                finite(s, "point", point)?;
                positive(s, "radius", *radius)?;
                CrackShape::Cylinder { point: *point, axis: unit(s, "axis", *axis)?, radius: *radius }
            }
            CrackShape::Formula { lsn, lst } => CrackShape::Formula { lsn: lsn.clone(), lst: lst.clone() },
            CrackShape::Mesh(m) => CrackShape::Mesh(m.clone()),
        })
    }

    /// A point of the crack and its largest extent (segment: midpoint and length; disc,
    /// elliptic disc, rectangle: centre and diameter / largest axis / diagonal), for the
    /// message on a crack too small for the mesh. `None` for shapes without a bounded
    /// crack (half-line, half-plane, interfaces, formulas).
    pub fn centre_and_size(&self) -> Option<([f64; 3], f64)> {
        match self {
            CrackShape::Segment { a, b } => {
                Some(([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0], (b[0] - a[0]).hypot(b[1] - a[1])))
            }
            CrackShape::Disc { centre, radius, .. } => Some((*centre, 2.0 * radius)),
            CrackShape::EllipticDisc { centre, semi_axes, .. } => Some((*centre, 2.0 * semi_axes[0].max(semi_axes[1]))),
            CrackShape::Rectangle { centre, half_lengths, .. } => {
                Some((*centre, 2.0 * half_lengths[0].hypot(half_lengths[1])))
            }
            _ => None,
        }
    }

    /// Number of the straight front parts that [`CrackShape::with_parts_extended`] can
    /// push outward: 2 for a segment (ends `a`, `b`), 4 for a rectangle (sides +u, −v,
    /// −u, +v, the order of [`super::front_points`]), 0 otherwise.
    pub fn n_front_parts(&self) -> usize {
        match self {
            CrackShape::Segment { .. } => 2,
            CrackShape::Rectangle { .. } => 4,
            _ => 0,
        }
    }

    /// The front part (see [`CrackShape::n_front_parts`]) nearest to the point `x` of the
    /// front, if within `tol`: the nearer end of a segment, the rectangle side whose line
    /// is nearest. `None` if none (or not a normalised
    /// segment or rectangle).
    pub fn front_part_of(&self, x: [f64; 3], tol: f64) -> Option<usize> {
        match self {
            CrackShape::Segment { a, b } => {
                let d = [(x[0] - a[0]).hypot(x[1] - a[1]), (x[0] - b[0]).hypot(x[1] - b[1])];
                nearest(&d, tol)
            }
            CrackShape::Rectangle { centre, normal, axis_u, half_lengths } => {
                let r = sub(x, *centre);
                let v = cross(*normal, *axis_u);
                let (xi, eta) = (dot(r, *axis_u), dot(r, v));
                let (hu, hv) = (half_lengths[0], half_lengths[1]);
                let d = [(xi - hu).abs(), (eta + hv).abs(), (xi + hu).abs(), (eta - hv).abs()];
                nearest(&d, tol)
            }
            _ => None,
        }
    }

    /// How far the point `x` lies beyond front part `part` (see
    /// [`CrackShape::n_front_parts`]) in the crack's plane, along the part's outward
    /// direction (negative inside the crack), and whether it lies within the part's extent
    /// (along a rectangle side; always for a segment end). `None` for other shapes.
    pub fn beyond_front_part(&self, x: [f64; 3], part: usize) -> Option<(f64, bool)> {
        match self {
            CrackShape::Segment { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                let s = ((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / l;
                match part {
                    0 => Some((-s, true)),
                    1 => Some((s - l, true)),
                    _ => None,
                }
            }
            CrackShape::Rectangle { centre, normal, axis_u, half_lengths } => {
                let r = sub(x, *centre);
                let v = cross(*normal, *axis_u);
                let (xi, eta) = (dot(r, *axis_u), dot(r, v));
                let (hu, hv) = (half_lengths[0], half_lengths[1]);
                match part {
                    0 => Some((xi - hu, eta.abs() <= hv)),
                    1 => Some((-eta - hv, xi.abs() <= hu)),
                    2 => Some((-xi - hu, eta.abs() <= hv)),
                    3 => Some((eta - hv, xi.abs() <= hu)),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The unit tangent of rectangle side `part` (v for the ±u sides, u for the ±v sides);
    /// `None` for other shapes.
    pub fn front_part_tangent(&self, part: usize) -> Option<[f64; 3]> {
        match self {
            CrackShape::Rectangle { normal, axis_u, .. } => {
                Some(if part % 2 == 0 { cross(*normal, *axis_u) } else { *axis_u })
            }
            _ => None,
        }
    }

    /// The shape with the front parts flagged in `parts` pushed outward by `ext` (a
    /// segment end moved away from the other end, a rectangle side moved along its outward
    /// normal): used to carry a crack through the surface of the body where its front
    /// lies on or outside it. Other shapes, and unflagged parts, are unchanged.
    pub fn with_parts_extended(&self, parts: &[bool], ext: f64) -> CrackShape {
        let flag = |k: usize| parts.get(k).copied().unwrap_or(false);
        match self {
            CrackShape::Segment { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                let t = [d[0] / l, d[1] / l];
                let mut a2 = *a;
                let mut b2 = *b;
                if flag(0) {
                    a2 = [a[0] - ext * t[0], a[1] - ext * t[1]];
                }
                if flag(1) {
                    b2 = [b[0] + ext * t[0], b[1] + ext * t[1]];
                }
                CrackShape::Segment { a: a2, b: b2 }
            }
            CrackShape::Rectangle { centre, normal, axis_u, half_lengths } => {
                let v = cross(*normal, *axis_u);
                let (mut lo_u, mut hi_u) = (-half_lengths[0], half_lengths[0]);
                let (mut lo_v, mut hi_v) = (-half_lengths[1], half_lengths[1]);
                if flag(0) {
                    hi_u += ext;
                }
                if flag(1) {
                    lo_v -= ext;
                }
                if flag(2) {
                    lo_u -= ext;
                }
                if flag(3) {
                    hi_v += ext;
                }
                let c = add(*centre, add(scale(0.5 * (lo_u + hi_u), *axis_u), scale(0.5 * (lo_v + hi_v), v)));
                CrackShape::Rectangle {
                    centre: c,
                    normal: *normal,
                    axis_u: *axis_u,
                    half_lengths: [0.5 * (hi_u - lo_u), 0.5 * (hi_v - lo_v)],
                }
            }
            other => other.clone(),
        }
    }

    /// (φn, φt) at point `p` (`p[2]` ignored by 2D shapes; formulas at t = 0). φt is `None`
    /// for interfaces. Validates and normalises the shape on each call: to sample many
    /// points use [`super::sample`]. A formula value that is not finite is an error.
    pub fn level_sets_at(&self, p: [f64; 3]) -> Result<(f64, Option<f64>), LevelSetError> {
        let s = self.normalised()?;
        if let CrackShape::Formula { lsn, lst } = &s {
            let n = super::checked_eval(lsn, p, "lsn", None)?;
            let t = match lst {
                Some(f) => Some(super::checked_eval(f, p, "lst", None)?),
                None => None,
            };
            return Ok((n, t));
        }
        Ok(s.eval_normalised(p))
    }

    /// The unit normal n = ∇φn/|∇φn| at `p` (z = 0 in 2D), analytic for built-in shapes.
    /// `None` for formulas and where the gradient is undefined (the centre of a circle or
    /// sphere, the axis of a cylinder). For an ellipse it is the outward normal at the
    /// closest point of the curve.
    pub fn normal_at(&self, p: [f64; 3]) -> Result<Option<[f64; 3]>, LevelSetError> {
        let s = self.normalised()?;
        Ok(match s {
            CrackShape::Segment { a, b } => {
                let t = unit2("segment", "b - a", [b[0] - a[0], b[1] - a[1]])?;
                Some([-t[1], t[0], 0.0])
            }
            CrackShape::HalfLine { direction: d, .. } => Some([-d[1], d[0], 0.0]),
            CrackShape::Line { normal, .. } => Some(e3(normal)),
            CrackShape::Ellipse { centre, semi_axes, angle } => {
                let (c, sn) = (angle.cos(), angle.sin());
                let r = [p[0] - centre[0], p[1] - centre[1]];
                let loc = [c * r[0] + sn * r[1], -sn * r[0] + c * r[1]];
                let g = if semi_axes[0] == semi_axes[1] {
                    loc
                } else {
                    let (_, q) = ellipse_signed_distance(semi_axes, loc);
                    [q[0] / (semi_axes[0] * semi_axes[0]), q[1] / (semi_axes[1] * semi_axes[1])]
                };
                let l = g[0].hypot(g[1]);
                (l > 0.0).then(|| [(c * g[0] - sn * g[1]) / l, (sn * g[0] + c * g[1]) / l, 0.0])
            }
            CrackShape::Disc { normal, .. }
            | CrackShape::EllipticDisc { normal, .. }
            | CrackShape::Rectangle { normal, .. }
            | CrackShape::HalfPlane { normal, .. }
            | CrackShape::Plane { normal, .. } => Some(normal),
            CrackShape::Sphere { centre, .. } => {
                let r = sub(p, centre);
                let l = norm(r);
                (l > 0.0).then(|| scale(1.0 / l, r))
            }
            CrackShape::Cylinder { point, axis, .. } => {
                let r = sub(p, point);
                let w = sub(r, scale(dot(r, axis), axis));
                let l = norm(w);
                (l > 0.0).then(|| scale(1.0 / l, w))
            }
            CrackShape::Formula { .. } | CrackShape::Mesh(_) => None,
        })
    }

    /// (φn, φt) at `p` for a shape returned by [`CrackShape::normalised`] (unit vectors
    /// assumed). Formulas are evaluated at t = 0 and give NaN on an evaluation error.
    pub(super) fn eval_normalised(&self, p: [f64; 3]) -> (f64, Option<f64>) {
        match self {
            CrackShape::Segment { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                let t = [d[0] / l, d[1] / l];
                let r = [p[0] - a[0], p[1] - a[1]];
                let phin = -t[1] * r[0] + t[0] * r[1];
                let s = t[0] * r[0] + t[1] * r[1];
                (phin, Some((-s).max(s - l)))
            }
            CrackShape::HalfLine { tip, direction: d } => {
                let r = [p[0] - tip[0], p[1] - tip[1]];
                (-d[1] * r[0] + d[0] * r[1], Some(d[0] * r[0] + d[1] * r[1]))
            }
            CrackShape::Line { point, normal } => ((p[0] - point[0]) * normal[0] + (p[1] - point[1]) * normal[1], None),
            CrackShape::Ellipse { centre, semi_axes, angle } => {
                let r = [p[0] - centre[0], p[1] - centre[1]];
                if semi_axes[0] == semi_axes[1] {
                    return (r[0].hypot(r[1]) - semi_axes[0], None);
                }
                let (c, s) = (angle.cos(), angle.sin());
                let loc = [c * r[0] + s * r[1], -s * r[0] + c * r[1]];
                (ellipse_signed_distance(*semi_axes, loc).0, None)
            }
            CrackShape::Disc { centre, normal, radius } => {
                let r = sub(p, *centre);
                let phin = dot(r, *normal);
                (phin, Some(norm(sub(r, scale(phin, *normal))) - radius))
            }
            CrackShape::EllipticDisc { centre, normal, major_axis, semi_axes } => {
                let r = sub(p, *centre);
                let v = cross(*normal, *major_axis);
                let loc = [dot(r, *major_axis), dot(r, v)];
                let phit = if semi_axes[0] == semi_axes[1] {
                    loc[0].hypot(loc[1]) - semi_axes[0]
                } else {
                    ellipse_signed_distance(*semi_axes, loc).0
                };
                (dot(r, *normal), Some(phit))
            }
            CrackShape::Rectangle { centre, normal, axis_u, half_lengths } => {
                let r = sub(p, *centre);
                let v = cross(*normal, *axis_u);
                let q = [dot(r, *axis_u).abs() - half_lengths[0], dot(r, v).abs() - half_lengths[1]];
                let outside = q[0].max(0.0).hypot(q[1].max(0.0));
                let inside = q[0].max(q[1]).min(0.0);
                (dot(r, *normal), Some(outside + inside))
            }
            CrackShape::HalfPlane { point_on_front, normal, direction } => {
                let r = sub(p, *point_on_front);
                (dot(r, *normal), Some(dot(r, *direction)))
            }
            CrackShape::Plane { point, normal } => (dot(sub(p, *point), *normal), None),
            CrackShape::Sphere { centre, radius } => (norm(sub(p, *centre)) - radius, None),
            CrackShape::Cylinder { point, axis, radius } => {
                let r = sub(p, *point);
                (norm(sub(r, scale(dot(r, *axis), *axis))) - radius, None)
            }
            CrackShape::Formula { lsn, lst } => (lsn.eval(p, 0.0), lst.as_ref().map(|f| f.eval(p, 0.0))),
            CrackShape::Mesh(m) => m.level_sets_at(p),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Distance to an ellipse (D. Eberly, "Distance from a point to an ellipse, an ellipsoid,
// or a hyperellipsoid", Geometric Tools, 2013): the closest point x of the ellipse
// x0²/e0² + x1²/e1² = 1 to y satisfies x_i = e_i² y_i / (t + e_i²); t is the unique root
// of a monotone function, found by bisection on a bracket known in closed form.

/// Signed distance from `p` (in the ellipse's own frame) to the ellipse with semi-axes
/// `e` along the local axes, negative inside, and the closest point of the ellipse.
/// Exact to round-off; requires e[0], e[1] > 0.
pub(super) fn ellipse_signed_distance(e: [f64; 2], p: [f64; 2]) -> (f64, [f64; 2]) {
    // Work with the larger semi-axis first and the point in the first quadrant.
    let swap = e[0] < e[1];
    let (e0, e1, y0, y1) = if swap { (e[1], e[0], p[1], p[0]) } else { (e[0], e[1], p[0], p[1]) };
    let (d, x) = ellipse_first_quadrant(e0, e1, y0.abs(), y1.abs());
    let x = [x[0].copysign(y0), x[1].copysign(y1)];
    let x = if swap { [x[1], x[0]] } else { x };
    let g = (p[0] / e[0]).powi(2) + (p[1] / e[1]).powi(2) - 1.0;
    (if g < 0.0 { -d } else { d }, x)
}

/// Eberly's first-quadrant case: e0 ≥ e1 > 0, y0, y1 ≥ 0. Returns (distance, closest point).
fn ellipse_first_quadrant(e0: f64, e1: f64, y0: f64, y1: f64) -> (f64, [f64; 2]) {
    if y1 > 0.0 {
        if y0 > 0.0 {
            let z0 = y0 / e0;
            let z1 = y1 / e1;
            let g = z0 * z0 + z1 * z1 - 1.0;
            if g != 0.0 {
                let r0 = (e0 / e1) * (e0 / e1);
                // r0 − 1 without cancellation.
                let r0m1 = (e0 - e1) * (e0 + e1) / (e1 * e1);
                let sigma = ellipse_root(r0, r0m1, z0, z1, g);
                let x0 = r0 * y0 / (sigma + r0m1);
                let x1 = y1 / sigma;
                ((x0 - y0).hypot(x1 - y1), [x0, x1])
            } else {
                (0.0, [y0, y1])
            }
        } else {
            ((y1 - e1).abs(), [0.0, e1])
        }
    } else {
        let numer0 = e0 * y0;
        let denom0 = (e0 - e1) * (e0 + e1);
        if numer0 < denom0 {
            let xde0 = numer0 / denom0;
            let x0 = e0 * xde0;
            let x1 = e1 * (1.0 - xde0 * xde0).max(0.0).sqrt();
            ((x0 - y0).hypot(x1), [x0, x1])
        } else {
            ((y0 - e0).abs(), [e0, 0.0])
        }
    }
}

/// Root σ = s + 1 (s = t/e1² in Eberly's notation) of
/// (r0 z0/(σ + r0 − 1))² + (z1/σ)² = 1, by bisection. Working with σ rather than s keeps
/// full relative precision when σ is tiny (points very close to the major axis, inside),
/// where s = −1 + σ would lose it. The bracket is Eberly's, shifted: [z1, 1] inside
/// (g < 0), [1, |(r0 z0, z1)|] outside. Bisection stops when the bracket is below the
/// round-off of σ (≤ ~60 + log2(1/σ) steps).
fn ellipse_root(r0: f64, r0m1: f64, z0: f64, z1: f64, g: f64) -> f64 {
    let n0 = r0 * z0;
    let (mut lo, mut hi) = if g < 0.0 { (z1, 1.0) } else { (1.0, n0.hypot(z1)) };
    let mut s = 0.5 * (lo + hi);
    for _ in 0..2200 {
        s = 0.5 * (lo + hi);
        if s == lo || s == hi || hi - lo <= 0.25 * f64::EPSILON * lo {
            break;
        }
        let ratio0 = n0 / (s + r0m1);
        let ratio1 = z1 / s;
        let g = ratio0 * ratio0 + ratio1 * ratio1 - 1.0;
        if g > 0.0 {
            lo = s;
        } else if g < 0.0 {
            hi = s;
        } else {
            break;
        }
    }
    s
}
