//! Unit tests of the level-set module: shape distances and signs, normals, parameter
//! errors, sampling on generated meshes, formulas, the crack-in-mesh check, snapping and
//! front frames. Each test states what it checks and its tolerance.

use super::shapes::{cross, dot, ellipse_signed_distance, norm, sub};
use super::*;
use crate::element::CellType;
use crate::mesh::generate::{box_mesh, rectangle};
use std::collections::BTreeMap;

fn ls(shape: &CrackShape, p: [f64; 3]) -> (f64, Option<f64>) {
    shape.level_sets_at(p).unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn assert_ls(shape: &CrackShape, p: [f64; 3], n: f64, t: Option<f64>, tol: f64) {
    let (gn, gt) = ls(shape, p);
    assert!(close(gn, n, tol), "{} at {p:?}: φn = {gn}, expected {n}", shape.name());
    match (gt, t) {
        (Some(a), Some(b)) => assert!(close(a, b, tol), "{} at {p:?}: φt = {a}, expected {b}", shape.name()),
        (None, None) => {}
        _ => panic!("{} at {p:?}: φt = {gt:?}, expected {t:?}", shape.name()),
    }
}

fn formula(src: &str) -> crate::formula::Formula {
    crate::formula::Formula::parse(src, &BTreeMap::new()).unwrap()
}

const S2: f64 = std::f64::consts::SQRT_2;

// --- signed distances and signs of each shape (hand values, 1e-14) -----------------------

/// Segment a = (1, 1), b = (4, 5): t = (0.6, 0.8), n = (−0.8, 0.6) (left of a→b).
/// Points a + s t + h n give φn = h, φt = max(−s, s − 5). Tolerance 1e-14.
#[test]
fn segment_distances_and_signs() {
    let sh = CrackShape::Segment { a: [1.0, 1.0], b: [4.0, 5.0] };
    let at = |s: f64, h: f64| [1.0 + 0.6 * s - 0.8 * h, 1.0 + 0.8 * s + 0.6 * h, 0.0];
    assert_ls(&sh, at(2.0, 3.0), 3.0, Some(-2.0), 1e-14);
    assert_ls(&sh, at(4.5, -0.5), -0.5, Some(-0.5), 1e-14);
    assert_ls(&sh, at(7.0, -1.0), -1.0, Some(2.0), 1e-14);
    assert_ls(&sh, at(-1.5, 0.0), 0.0, Some(1.5), 1e-14);
    assert_ls(&sh, [4.0, 5.0, 0.0], 0.0, Some(0.0), 1e-14);
    // The left of a→b is `+`: (0, 1) from a is to the left of the direction (0.6, 0.8).
    assert!(ls(&sh, [1.0, 2.0, 0.0]).0 > 0.0);
    assert!(sh.has_front() && sh.dim() == Some(2));
}

/// Half-line towards tip (1, 2) along direction (0, −3): the crack is x = 1, y > 2;
/// n = d rotated +90° = (1, 0). φn = x − 1, φt = −(y − 2). Tolerance 1e-14.
#[test]
fn half_line_distances_and_signs() {
    let sh = CrackShape::HalfLine { tip: [1.0, 2.0], direction: [0.0, -3.0] };
    assert_ls(&sh, [3.0, 5.0, 0.0], 2.0, Some(-3.0), 1e-14);
    assert_ls(&sh, [0.5, -1.0, 0.0], -0.5, Some(3.0), 1e-14);
    assert_ls(&sh, [1.0, 2.0, 0.0], 0.0, Some(0.0), 1e-14);
}

/// Line through (0, 1) with normal (0, 2): φn = y − 1, no φt. Tolerance 1e-14.
#[test]
fn line_distances_and_signs() {
    let sh = CrackShape::Line { point: [0.0, 1.0], normal: [0.0, 2.0] };
    assert_ls(&sh, [5.0, 3.5, 0.0], 2.5, None, 1e-14);
    assert_ls(&sh, [-5.0, 0.0, 0.0], -1.0, None, 1e-14);
    assert!(!sh.has_front());
}

/// Circle (equal semi-axes) of centre (1, 1), radius 2: φn = |x − c| − 2, `+` outside.
/// Ellipse of centre (1, −1), semi-axes (3, 1), angle π/2 (major axis along y):
/// on the axes the distance is exact by hand; at local (0.5, 0) (inside, near the centre)
/// the closest point is off-axis, d = √(31/32). Tolerance 1e-14.
#[test]
fn circle_and_ellipse_distances_and_signs() {
    let c = CrackShape::Ellipse { centre: [1.0, 1.0], semi_axes: [2.0, 2.0], angle: 0.3 };
    assert_ls(&c, [4.0, 5.0, 0.0], 3.0, None, 1e-14);
    assert_ls(&c, [1.0, 1.5, 0.0], -1.5, None, 1e-14);
    let e = CrackShape::Ellipse { centre: [1.0, -1.0], semi_axes: [3.0, 1.0], angle: std::f64::consts::FRAC_PI_2 };
    assert_ls(&e, [1.0, 4.0, 0.0], 2.0, None, 1e-14); // along the major axis: 5 − 3
    assert_ls(&e, [1.0, -1.5, 0.0], -(31.0f64 / 32.0).sqrt(), None, 1e-14);
    assert_ls(&e, [-1.0, -1.0, 0.0], 1.0, None, 1e-14); // along the minor axis: 2 − 1
    assert_ls(&e, [1.2, -1.0, 0.0], -0.8, None, 1e-14);
    assert!(!e.has_front());
}

/// The ellipse distance at scattered points (in and out, near and far, near the axes):
/// the closest point q is on the ellipse (1e-14), p − q is along the normal at q
/// (tangential part of p − q ≤ 1e-14), |d| = |p − q| (1e-14), and |d| is not above the minimum over 20 000
/// points of the curve (+1e-12): a global minimum, not just a stationary point.
#[test]
fn ellipse_distance_is_the_closest_point_distance() {
    for e in [[2.5, 0.7], [0.3, 1.1], [1.0, 0.01], [1.0 + 1e-7, 1.0]] {
        ellipse_distance_case(e);
    }
}

fn ellipse_distance_case(e: [f64; 2]) {
    let curve: Vec<[f64; 2]> = (0..20_000)
        .map(|k| {
            let th = 2.0 * std::f64::consts::PI * k as f64 / 20_000.0;
            [e[0] * th.cos(), e[1] * th.sin()]
        })
        .collect();
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (a, b) = (e[0], e[1]);
    let mut pts = vec![[0.0, 0.0], [1e-9, 0.0], [0.0, 1e-9], [0.8 * a, 1e-12], [1e-12, 0.8 * b], [a, 0.0], [0.0, b]];
    pts.push([-1.2 * a, -0.1 * b]);
    for _ in 0..300 {
        pts.push([4.0 * a * (rnd() - 0.5), 4.0 * b * (rnd() - 0.5)]);
        // Near the curve, in and out.
        let th = 2.0 * std::f64::consts::PI * rnd();
        let f = 1.0 + 1e-3 * (rnd() - 0.5);
        pts.push([f * a * th.cos(), f * b * th.sin()]);
    }
    for p in pts {
        let (d, q) = ellipse_signed_distance(e, p);
        assert!(close((q[0] / e[0]).powi(2) + (q[1] / e[1]).powi(2), 1.0, 1e-14), "q off the ellipse for {p:?}");
        let r = [p[0] - q[0], p[1] - q[1]];
        let g = [q[0] / (e[0] * e[0]), q[1] / (e[1] * e[1])];
        let rl = r[0].hypot(r[1]);
        // Component of p − q along the tangent at q (an absolute length).
        let tangential = (r[0] * g[1] - r[1] * g[0]) / g[0].hypot(g[1]);
        assert!(tangential.abs() <= 1e-14, "p − q not normal at {p:?}: tangential part {tangential}");
        assert!(close(d.abs(), rl, 1e-14));
        let brute = curve.iter().map(|c| (p[0] - c[0]).hypot(p[1] - c[1])).fold(f64::INFINITY, f64::min);
        assert!(d.abs() <= brute + 1e-12, "not the global minimum at {p:?}: {d} vs {brute}");
        let inside = (p[0] / e[0]).powi(2) + (p[1] / e[1]).powi(2) < 1.0;
        assert_eq!(d < 0.0, inside, "sign at {p:?}");
    }
}

/// Disc: centre (1, 2, 3), normal (0, 0, 2), radius 0.5: φn = z − 3, φt = ρ − 0.5 with ρ
/// the distance to the axis. Tilted disc with normal (1, 1, 0)/√2. Tolerance 1e-14.
#[test]
fn disc_distances_and_signs() {
    let sh = CrackShape::Disc { centre: [1.0, 2.0, 3.0], normal: [0.0, 0.0, 2.0], radius: 0.5 };
    assert_ls(&sh, [1.3, 2.4, 2.3], -0.7, Some(0.0), 1e-14);
    assert_ls(&sh, [1.0, 4.0, 3.1], 0.1, Some(1.5), 1e-14);
    assert_ls(&sh, [1.1, 2.0, 3.0], 0.0, Some(-0.4), 1e-14);
    let t = CrackShape::Disc { centre: [0.0; 3], normal: [1.0, 1.0, 0.0], radius: 1.0 };
    assert_ls(&t, [1.0, 1.0, 2.0], S2, Some(1.0), 1e-14);
    assert_ls(&t, [-0.5, 0.5, 0.0], 0.0, Some(S2 / 2.0 - 1.0), 1e-14);
}

/// Elliptic disc: centre 0, normal +z, major_axis (0, 1, 0) ⇒ u = y, v = n × u = −x;
/// semi-axes (2 along u, 1 along v). In-plane local (ξ, η) = (y, −x). Tolerance 1e-14.
#[test]
fn elliptic_disc_distances_and_signs() {
    let sh = CrackShape::EllipticDisc {
        centre: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        major_axis: [0.0, 3.0, 0.0],
        semi_axes: [2.0, 1.0],
    };
    assert_ls(&sh, [0.0, 3.0, 0.5], 0.5, Some(1.0), 1e-14);
    assert_ls(&sh, [-1.5, 0.0, 0.0], 0.0, Some(0.5), 1e-14);
    assert_ls(&sh, [0.5, 0.0, -1.0], -1.0, Some(-0.5), 1e-14);
    // Inside on the major axis, local (−1, 0): the closest point is off-axis,
    // (−4/3, ±√5/3), so φt = −√(1/9 + 5/9) = −√6/3.
    assert_ls(&sh, [0.0, -1.0, 0.0], 0.0, Some(-(6.0f64).sqrt() / 3.0), 1e-14);
    // Equal semi-axes: the disc formula exactly.
    let c = CrackShape::EllipticDisc {
        centre: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        major_axis: [1.0, 0.0, 0.0],
        semi_axes: [1.0, 1.0],
    };
    assert_ls(&c, [3.0, 4.0, 1.0], 1.0, Some(4.0), 1e-14);
}

/// Rectangle: centre 0, normal +z, axis_u (1, 1, 0) ⇒ u = (1, 1, 0)/√2,
/// v = n × u = (−1, 1, 0)/√2; half-lengths (2, 1). Points c + ξ u + η v + ζ n:
/// beside a side, beyond a corner (distance to the corner), inside (sharp). Tolerance 1e-14.
#[test]
fn rectangle_distances_and_signs() {
    let sh = CrackShape::Rectangle {
        centre: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        axis_u: [1.0, 1.0, 0.0],
        half_lengths: [2.0, 1.0],
    };
    let at = |xi: f64, eta: f64, z: f64| [(xi - eta) / S2, (xi + eta) / S2, z];
    assert_ls(&sh, at(3.0, 0.0, 0.25), 0.25, Some(1.0), 1e-14);
    assert_ls(&sh, at(-5.0, 5.0, 0.0), 0.0, Some(5.0), 1e-14); // corner region: hypot(3, 4)
    assert_ls(&sh, at(0.5, 0.2, -1.0), -1.0, Some(-0.8), 1e-14);
    assert_ls(&sh, at(1.9, -0.2, 0.0), 0.0, Some(-0.1), 1e-14);
    assert_ls(&sh, at(2.0, 1.0, 0.0), 0.0, Some(0.0), 1e-14);
}

/// Half-plane: front through (1, 0, 0), normal +y, direction +x (crack where x < 1, y = 0).
/// A direction 1e-9 off the plane is accepted and orthogonalised. Tolerance 1e-14.
#[test]
fn half_plane_distances_and_signs() {
    let sh =
        CrackShape::HalfPlane { point_on_front: [1.0, 0.0, 0.0], normal: [0.0, 1.0, 0.0], direction: [2.0, 0.0, 0.0] };
    assert_ls(&sh, [3.0, -2.0, 7.0], -2.0, Some(2.0), 1e-14);
    assert_ls(&sh, [0.0, 0.5, -7.0], 0.5, Some(-1.0), 1e-14);
    let tilted =
        CrackShape::HalfPlane { point_on_front: [1.0, 0.0, 0.0], normal: [0.0, 1.0, 0.0], direction: [1.0, 1e-9, 0.0] };
    assert_ls(&tilted, [3.0, -2.0, 7.0], -2.0, Some(2.0), 1e-14);
}

/// Plane, sphere, cylinder (interfaces, `+` outside for the closed ones). Tolerance 1e-14.
#[test]
fn plane_sphere_cylinder_distances_and_signs() {
    let p = CrackShape::Plane { point: [0.0, 0.0, 1.0], normal: [0.0, 0.0, -3.0] };
    assert_ls(&p, [5.0, 5.0, 3.0], -2.0, None, 1e-14);
    let s = CrackShape::Sphere { centre: [1.0, 1.0, 1.0], radius: 1.0 };
    assert_ls(&s, [3.0, 3.0, 2.0], 2.0, None, 1e-14);
    assert_ls(&s, [1.0, 1.0, 1.25], -0.75, None, 1e-14);
    let c = CrackShape::Cylinder { point: [0.0, 0.0, 0.0], axis: [0.0, 0.0, 5.0], radius: 2.0 };
    assert_ls(&c, [3.0, 4.0, 100.0], 3.0, None, 1e-14);
    assert_ls(&c, [0.0, 1.0, -3.0], -1.0, None, 1e-14);
    assert!(!p.has_front() && !s.has_front() && !c.has_front());
}

// --- normals ----------------------------------------------------------------------------

/// `normal_at` is a unit vector (1e-14) equal to the central-difference gradient of φn
/// (step 1e-6, tolerance 1e-7) at points away from kinks, for every built-in shape; the
/// segment normal is (−0.8, 0.6) by hand (1e-14).
#[test]
fn normals_are_the_gradient_of_lsn() {
    let shapes = vec![
        (CrackShape::Segment { a: [1.0, 1.0], b: [4.0, 5.0] }, [0.3, 0.2, 0.0]),
        (CrackShape::HalfLine { tip: [1.0, 2.0], direction: [1.0, -3.0] }, [0.3, 0.2, 0.0]),
        (CrackShape::Line { point: [0.0, 1.0], normal: [1.0, 2.0] }, [0.3, 0.2, 0.0]),
        (CrackShape::Ellipse { centre: [0.1, 0.2], semi_axes: [1.0, 1.0], angle: 0.0 }, [0.7, 0.9, 0.0]),
        (CrackShape::Ellipse { centre: [0.1, 0.2], semi_axes: [2.0, 0.5], angle: 0.4 }, [1.7, 1.9, 0.0]),
        (CrackShape::Ellipse { centre: [0.1, 0.2], semi_axes: [2.0, 0.5], angle: 0.4 }, [0.5, 0.5, 0.0]),
        (CrackShape::Disc { centre: [0.0; 3], normal: [1.0, 2.0, 3.0], radius: 1.0 }, [0.3, 0.2, 0.9]),
        (
            CrackShape::EllipticDisc {
                centre: [0.0; 3],
                normal: [0.0, 1.0, 1.0],
                major_axis: [1.0, 0.0, 0.0],
                semi_axes: [1.0, 2.0],
            },
            [0.3, 0.2, 0.9],
        ),
        (
            CrackShape::Rectangle {
                centre: [0.0; 3],
                normal: [0.0, 1.0, 1.0],
                axis_u: [1.0, 0.0, 0.0],
                half_lengths: [1.0, 2.0],
            },
            [0.3, 0.2, 0.9],
        ),
        (
            CrackShape::HalfPlane { point_on_front: [0.0; 3], normal: [1.0, 1.0, 1.0], direction: [1.0, -1.0, 0.0] },
            [0.3, 0.2, 0.9],
        ),
        (CrackShape::Plane { point: [0.0; 3], normal: [1.0, -1.0, 2.0] }, [0.3, 0.2, 0.9]),
        (CrackShape::Sphere { centre: [0.0; 3], radius: 1.0 }, [0.3, 0.2, 0.9]),
        (CrackShape::Cylinder { point: [0.0; 3], axis: [1.0, 1.0, 0.0], radius: 1.0 }, [0.3, 0.2, 0.9]),
    ];
    for (sh, p) in shapes {
        let n = sh.normal_at(p).unwrap().unwrap();
        assert!(close(norm(n), 1.0, 1e-14), "{}: |n| = {}", sh.name(), norm(n));
        let h = 1e-6;
        let d = sh.dim().unwrap();
        for k in 0..d {
            let (mut a, mut b) = (p, p);
            a[k] += h;
            b[k] -= h;
            let g = (ls(&sh, a).0 - ls(&sh, b).0) / (2.0 * h);
            assert!(close(g, n[k], 1e-7), "{}: ∂φn/∂x{k} = {g}, n = {n:?}", sh.name());
        }
    }
    let n = CrackShape::Segment { a: [1.0, 1.0], b: [4.0, 5.0] }.normal_at([0.0; 3]).unwrap().unwrap();
    assert!(close(n[0], -0.8, 1e-14) && close(n[1], 0.6, 1e-14) && n[2] == 0.0);
    let f = CrackShape::formula(formula("y"), None);
    assert_eq!(f.normal_at([0.0; 3]).unwrap(), None);
    let s = CrackShape::Sphere { centre: [0.0; 3], radius: 1.0 };
    assert_eq!(s.normal_at([0.0; 3]).unwrap(), None);
}

// --- bad parameters -----------------------------------------------------------------------

/// Impossible parameters are `BadShape` errors whose message names the culprit; a normal
/// 1e-9 off orthogonal to axis_u is accepted and made exactly orthogonal (|cos| ≤ 1e-15).
#[test]
fn bad_parameters_are_errors() {
    let z = [0.0, 0.0, 1.0];
    let bad = vec![
        (CrackShape::Segment { a: [1.0, 1.0], b: [1.0, 1.0] }, "coincide"),
        (CrackShape::Segment { a: [f64::NAN, 1.0], b: [1.0, 1.0] }, "finite"),
        (CrackShape::HalfLine { tip: [0.0, 0.0], direction: [0.0, 0.0] }, "direction"),
        (CrackShape::Line { point: [0.0, 0.0], normal: [0.0, 0.0] }, "normal"),
        (CrackShape::Ellipse { centre: [0.0, 0.0], semi_axes: [1.0, 0.0], angle: 0.0 }, "semi_axes[1]"),
        (CrackShape::Disc { centre: [0.0; 3], normal: z, radius: 0.0 }, "radius"),
        (CrackShape::Disc { centre: [0.0; 3], normal: z, radius: -1.0 }, "radius"),
        (CrackShape::Disc { centre: [0.0; 3], normal: [0.0; 3], radius: 1.0 }, "normal"),
        (
            CrackShape::EllipticDisc {
                centre: [0.0; 3],
                normal: z,
                major_axis: [1.0, 0.0, 0.1],
                semi_axes: [1.0, 1.0],
            },
            "orthogonal",
        ),
        (
            CrackShape::EllipticDisc {
                centre: [0.0; 3],
                normal: z,
                major_axis: [1.0, 0.0, 0.0],
                semi_axes: [-1.0, 1.0],
            },
            "semi_axes[0]",
        ),
        (
            CrackShape::Rectangle { centre: [0.0; 3], normal: z, axis_u: [0.0, 0.0, 1.0], half_lengths: [1.0, 1.0] },
            "orthogonal",
        ),
        (
            CrackShape::Rectangle { centre: [0.0; 3], normal: z, axis_u: [1.0, 0.0, 0.0], half_lengths: [1.0, 0.0] },
            "half_lengths[1]",
        ),
        (CrackShape::HalfPlane { point_on_front: [0.0; 3], normal: z, direction: [0.0; 3] }, "direction"),
        (CrackShape::Plane { point: [0.0; 3], normal: [0.0; 3] }, "normal"),
        (CrackShape::Sphere { centre: [0.0; 3], radius: f64::INFINITY }, "radius"),
        (CrackShape::Cylinder { point: [0.0; 3], axis: [0.0; 3], radius: 1.0 }, "axis"),
    ];
    for (sh, word) in bad {
        match sh.normalised() {
            Err(e @ LevelSetError::BadShape { .. }) => {
                let m = e.to_string();
                assert!(m.contains(word) && m.starts_with(sh.name()), "{}: message '{m}' lacks '{word}'", sh.name());
            }
            other => panic!("{}: expected a BadShape error, got {other:?}", sh.name()),
        }
        assert!(sh.level_sets_at([0.0; 3]).is_err());
        assert!(front_points(&sh, 4).is_none());
    }
    let ok = CrackShape::Rectangle { centre: [0.0; 3], normal: z, axis_u: [1.0, 0.0, 1e-9], half_lengths: [1.0, 1.0] };
    match ok.normalised().unwrap() {
        CrackShape::Rectangle { normal, axis_u, .. } => {
            assert!(dot(normal, axis_u).abs() <= 1e-15 && close(norm(axis_u), 1.0, 1e-15));
        }
        _ => unreachable!(),
    }
}

// --- sampling on meshes -------------------------------------------------------------------

/// Segment (0.25, 0.55)–(0.75, 0.55) on a 10×10 tri3 unit square: φn = y − 0.55,
/// φt = |x − 0.5| − 0.25 at every node (1e-14).
#[test]
fn sample_segment_on_rectangle() {
    let mesh = rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
    let sh = CrackShape::Segment { a: [0.25, 0.55], b: [0.75, 0.55] };
    let l = sample(&sh, &mesh).unwrap();
    let t = l.lst.as_ref().unwrap();
    assert_eq!(l.lsn.len(), mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        assert!(close(l.lsn[i], p[1] - 0.55, 1e-14));
        assert!(close(t[i], (p[0] - 0.5).abs() - 0.25, 1e-14));
    }
    check_crack_in_mesh(&l, &mesh).unwrap();
}

/// Disc centre (0.5, 0.5, 0.5), normal +z, radius 0.3 on a 6³ tet4 box: φn = z − 0.5,
/// φt = hypot(x − 0.5, y − 0.5) − 0.3 at every node (1e-14). A 20³ hex8 box (9261 nodes,
/// parallel path) gives exactly the pointwise values.
#[test]
fn sample_disc_on_box() {
    let mesh = box_mesh(CellType::Tet4, [0.0; 3], [1.0; 3], [6, 6, 6]).unwrap();
    let sh = CrackShape::Disc { centre: [0.5; 3], normal: [0.0, 0.0, 1.0], radius: 0.3 };
    let l = sample(&sh, &mesh).unwrap();
    let t = l.lst.as_ref().unwrap();
    for (i, p) in mesh.nodes.iter().enumerate() {
        assert!(close(l.lsn[i], p[2] - 0.5, 1e-14));
        assert!(close(t[i], (p[0] - 0.5).hypot(p[1] - 0.5) - 0.3, 1e-14));
    }
    check_crack_in_mesh(&l, &mesh).unwrap();

    let big = box_mesh(CellType::Hex8, [0.0; 3], [1.0; 3], [20, 20, 20]).unwrap();
    assert!(big.nodes.len() >= PARALLEL_NODES);
    let l = sample(&sh, &big).unwrap();
    for (i, p) in big.nodes.iter().enumerate() {
        let (n, t) = ls(&sh, *p);
        assert_eq!(l.lsn[i], n + 0.0);
        assert_eq!(l.lst.as_ref().unwrap()[i], t.unwrap() + 0.0);
    }
}

/// A 3D shape on a 2D mesh, and the reverse, are `DimensionMismatch` errors; a formula
/// fits both; an interface samples without `lst`.
#[test]
fn sample_checks_the_dimension() {
    let m2 = rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [2, 2]).unwrap();
    let m3 = box_mesh(CellType::Hex8, [0.0; 3], [1.0; 3], [2, 2, 2]).unwrap();
    let disc = CrackShape::Disc { centre: [0.5; 3], normal: [0.0, 0.0, 1.0], radius: 0.3 };
    let seg = CrackShape::Segment { a: [0.25, 0.55], b: [0.75, 0.55] };
    assert!(matches!(sample(&disc, &m2), Err(LevelSetError::DimensionMismatch { shape_dim: 3, mesh_dim: 2, .. })));
    assert!(matches!(sample(&seg, &m3), Err(LevelSetError::DimensionMismatch { shape_dim: 2, mesh_dim: 3, .. })));
    let f = CrackShape::formula(formula("x - 0.5"), None);
    assert!(sample(&f, &m2).unwrap().lst.is_none());
    assert!(sample(&f, &m3).unwrap().lst.is_none());
    let plane = CrackShape::Plane { point: [0.5; 3], normal: [0.0, 0.0, 1.0] };
    assert!(sample(&plane, &m3).unwrap().lst.is_none());
}

/// Formulas written for the segment, the disc and the sphere give the built-in shapes'
/// nodal values (1e-14).
#[test]
fn formulas_equal_built_in_shapes() {
    let m2 = rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [8, 8]).unwrap();
    let m3 = box_mesh(CellType::Tet4, [0.0; 3], [1.0; 3], [4, 4, 4]).unwrap();
    let cases = vec![
        (
            &m2,
            CrackShape::Segment { a: [0.25, 0.55], b: [0.75, 0.55] },
            CrackShape::formula(formula("y - 0.55"), Some(formula("abs(x - 0.5) - 0.25"))),
        ),
        (
            &m3,
            CrackShape::Disc { centre: [0.5; 3], normal: [0.0, 0.0, 1.0], radius: 0.3 },
            CrackShape::formula(formula("z - 0.5"), Some(formula("sqrt((x - 0.5)^2 + (y - 0.5)^2) - 0.3"))),
        ),
        (
            &m3,
            CrackShape::Sphere { centre: [0.5; 3], radius: 0.3 },
            CrackShape::formula(formula("sqrt((x-0.5)^2 + (y-0.5)^2 + (z-0.5)^2) - 0.3"), None),
        ),
    ];
    for (mesh, shape, f) in cases {
        let a = sample(&shape, mesh).unwrap();
        let b = sample(&f, mesh).unwrap();
        assert_eq!(a.lst.is_some(), b.lst.is_some());
        for i in 0..mesh.nodes.len() {
            assert!(close(a.lsn[i], b.lsn[i], 1e-14), "{}: φn at node {i}", shape.name());
            if let (Some(x), Some(y)) = (&a.lst, &b.lst) {
                assert!(close(x[i], y[i], 1e-14), "{}: φt at node {i}", shape.name());
            }
        }
    }
}

/// A formula that is NaN or infinite at a node is an error naming the first such node and
/// its coordinates.
#[test]
fn non_finite_formula_values_name_the_node() {
    let mesh = rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [4, 4]).unwrap();
    let f = CrackShape::formula(formula("y - 0.5"), Some(formula("sqrt(x - 0.6)")));
    match sample(&f, &mesh) {
        Err(e @ LevelSetError::NotFinite { which: "lst", node: Some(0), .. }) => {
            let m = e.to_string();
            assert!(m.contains("node 0") && m.contains("x = 0, y = 0"), "{m}");
        }
        other => panic!("expected NotFinite at node 0, got {other:?}"),
    }
    let g = CrackShape::formula(formula("1 / (x - 0.25)"), None);
    // Node 1 is (0.25, 0).
    assert!(matches!(sample(&g, &mesh), Err(LevelSetError::NotFinite { which: "lsn", node: Some(1), .. })));
}

// --- crack in mesh ------------------------------------------------------------------------

/// `check_crack_in_mesh`: a crack whose line crosses the mesh but whose segment lies
/// beyond it, and an interface outside the mesh, are `OutsideMesh`; a crack through
/// nodes (exact zeros) and an interface crossing the mesh are fine; wrong lengths are
/// errors.
#[test]
fn crack_outside_mesh_is_caught() {
    let mesh = rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
    let outside = CrackShape::Segment { a: [2.0, 0.55], b: [3.0, 0.55] };
    let l = sample(&outside, &mesh).unwrap();
    let e = check_crack_in_mesh(&l, &mesh).unwrap_err();
    assert_eq!(e, LevelSetError::OutsideMesh { has_front: true });
    assert!(e.to_string().contains("entirely outside the mesh"));
    let line = CrackShape::Line { point: [0.0, 2.0], normal: [0.0, 1.0] };
    let l = sample(&line, &mesh).unwrap();
    assert_eq!(check_crack_in_mesh(&l, &mesh), Err(LevelSetError::OutsideMesh { has_front: false }));
    let line = CrackShape::Line { point: [0.0, 0.55], normal: [0.0, 1.0] };
    check_crack_in_mesh(&sample(&line, &mesh).unwrap(), &mesh).unwrap();
    // Through nodes: φn exactly 0 on the node row y = 0.5.
    let through = CrackShape::Segment { a: [0.2, 0.5], b: [0.6, 0.5] };
    let l = sample(&through, &mesh).unwrap();
    assert!(l.lsn.contains(&0.0));
    check_crack_in_mesh(&l, &mesh).unwrap();
    // A crack whose nodal φn ≥ 0 everywhere with exact zeros on the boundary y = 0.
    let edge = NodalLevelSets { lsn: mesh.nodes.iter().map(|p| p[1]).collect(), lst: None };
    check_crack_in_mesh(&edge, &mesh).unwrap();
    let short = NodalLevelSets { lsn: vec![0.0; 3], lst: None };
    assert!(matches!(check_crack_in_mesh(&short, &mesh), Err(LevelSetError::WrongLength { which: "lsn", .. })));
}

// --- snapping -----------------------------------------------------------------------------

/// `snap` with rel_tol 1e-6 on a 10×10 mesh (shortest edge 0.1, threshold 1e-7): a
/// segment 1e-9 above the node row y = 0.5 gets φn exactly +0.0 there (not −0.0); its tip
/// 1e-10 from the node x = 0.2 gets φt exactly 0.0; other values are unchanged (bit for
/// bit); a non-positive tolerance changes nothing.
#[test]
fn snap_sets_tiny_values_to_zero() {
    let mesh = rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
    let sh = CrackShape::Segment { a: [0.2 + 1e-10, 0.5 + 1e-9], b: [0.85, 0.5 + 1e-9] };
    let raw = sample(&sh, &mesh).unwrap();
    let mut l = raw.clone();
    snap(&mut l, &mesh, 0.0);
    assert_eq!(l, raw);
    snap(&mut l, &mesh, 1e-6);
    let t = l.lst.as_ref().unwrap();
    let t0 = raw.lst.as_ref().unwrap();
    for (i, p) in mesh.nodes.iter().enumerate() {
        if close(p[1], 0.5, 1e-12) {
            assert!(l.lsn[i] == 0.0 && l.lsn[i].is_sign_positive(), "node {i}: {}", l.lsn[i]);
        } else {
            assert_eq!(l.lsn[i], raw.lsn[i]);
        }
        if close(p[0], 0.2, 1e-12) {
            assert!(t[i] == 0.0 && t[i].is_sign_positive());
        } else {
            assert_eq!(t[i], t0[i]);
        }
    }
    let h = node_sizes(&mesh);
    assert!(h.iter().all(|&x| close(x, 0.1, 1e-15)));
}

// --- front points -------------------------------------------------------------------------

fn assert_frame(p: &FrontPoint) {
    for e in [p.e1, p.e2, p.e3] {
        assert!(close(norm(e), 1.0, 1e-14));
    }
    assert!(dot(p.e1, p.e2).abs() < 1e-14);
    let c = cross(p.e1, p.e2);
    assert!(norm(sub(c, p.e3)) < 1e-14, "e3 ≠ e1 × e2");
}

/// 2D front frames: segment a = (1, 1), b = (4, 5): tip b has e1 = t = (0.6, 0.8),
/// e2 = n = (−0.8, 0.6), e3 = +z; tip a has e1 = −t, e2 = −n, e3 = +z (the two tips are
/// images by a half-turn, so they give the same K_II). Half-line: e1 = direction, e2 = n.
/// Tolerance 1e-14.
#[test]
fn front_frames_2d() {
    let sh = CrackShape::Segment { a: [1.0, 1.0], b: [4.0, 5.0] };
    let f = front_points(&sh, 7).unwrap();
    assert_eq!(f.len(), 2);
    let [fa, fb] = [f[0], f[1]];
    assert_eq!(fa.x, [1.0, 1.0, 0.0]);
    assert_eq!(fb.x, [4.0, 5.0, 0.0]);
    for (got, want) in [
        (fb.e1, [0.6, 0.8, 0.0]),
        (fb.e2, [-0.8, 0.6, 0.0]),
        (fb.e3, [0.0, 0.0, 1.0]),
        (fa.e1, [-0.6, -0.8, 0.0]),
        (fa.e2, [0.8, -0.6, 0.0]),
        (fa.e3, [0.0, 0.0, 1.0]),
    ] {
        assert!(norm(sub(got, want)) < 1e-14, "{got:?} vs {want:?}");
    }
    for p in &f {
        assert_frame(p);
    }
    let h = CrackShape::HalfLine { tip: [1.0, 2.0], direction: [0.0, -3.0] };
    let f = front_points(&h, 1).unwrap();
    assert_eq!(f.len(), 1);
    assert_frame(&f[0]);
    assert!(norm(sub(f[0].e1, [0.0, -1.0, 0.0])) < 1e-14);
    assert!(norm(sub(f[0].e2, h.normal_at([0.0; 3]).unwrap().unwrap())) < 1e-14);
}

/// 3D front frames (disc, elliptic disc, rectangle, half-plane): each point is on the
/// front (φn, φt = 0 to 1e-14), the frame is orthonormal and right-handed (1e-14),
/// e2 = n, e1 = ∇φt (central differences, step 1e-6, 1e-7), and consecutive points
/// advance along +e3. The rectangle has n points per side, none at a corner. Formulas give
/// `None`, interfaces an empty list.
#[test]
fn front_frames_3d() {
    let n = [1.0, 2.0, 2.0];
    let nu = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let shapes = vec![
        (CrackShape::Disc { centre: [0.1, 0.2, 0.3], normal: n, radius: 0.7 }, 12, 12),
        (
            CrackShape::EllipticDisc {
                centre: [0.1, 0.2, 0.3],
                normal: n,
                major_axis: [2.0, -1.0, 0.0],
                semi_axes: [1.5, 0.5],
            },
            16,
            16,
        ),
        (
            CrackShape::Rectangle {
                centre: [0.1, 0.2, 0.3],
                normal: n,
                axis_u: [0.0, 1.0, -1.0],
                half_lengths: [1.0, 0.4],
            },
            5,
            20,
        ),
        (CrackShape::HalfPlane { point_on_front: [0.1, 0.2, 0.3], normal: n, direction: [2.0, -1.0, 0.0] }, 9, 1),
    ];
    for (sh, k, count) in shapes {
        let f = front_points(&sh, k).unwrap();
        assert_eq!(f.len(), count, "{}", sh.name());
        for (i, p) in f.iter().enumerate() {
            assert_frame(p);
            let (phin, phit) = ls(&sh, p.x);
            assert!(phin.abs() < 1e-14 && phit.unwrap().abs() < 1e-14, "{}: point {i} off the front", sh.name());
            assert!(norm(sub(p.e2, nu)) < 1e-14);
            for a in 0..3 {
                let (mut xp, mut xm) = (p.x, p.x);
                xp[a] += 1e-6;
                xm[a] -= 1e-6;
                let g = (ls(&sh, xp).1.unwrap() - ls(&sh, xm).1.unwrap()) / 2e-6;
                assert!(close(g, p.e1[a], 1e-7), "{}: e1 ≠ ∇φt at point {i}", sh.name());
            }
            if i + 1 < f.len() {
                assert!(dot(sub(f[i + 1].x, p.x), p.e3) > 0.0, "{}: points not along +e3", sh.name());
            }
        }
    }
    let f = CrackShape::formula(formula("z"), Some(formula("x")));
    assert!(front_points(&f, 4).is_none());
    let s = CrackShape::Sphere { centre: [0.0; 3], radius: 1.0 };
    assert_eq!(front_points(&s, 4), Some(vec![]));
}
