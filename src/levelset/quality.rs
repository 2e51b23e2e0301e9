//! How close a crack's formula level sets are to signed distances where it matters: on the
//! crack surface near the front, where the tip functions and the SIF frames read r and θ
//! from (φn, φt).
//!
//! Entry point: [`distance_check`] (→ [`DistanceCheck`]). Built-in shapes and meshed cracks
//! are signed distances by construction; a formula is whatever the user wrote, and a
//! polynomial of the right sign but the wrong slope changes K by as much as its slope is
//! off. The check samples points on φn = 0 within two cells of the front (one per cell cut
//! by φn there: the cell centre projected onto φn = 0 by Newton steps), and measures at each
//! |∇φn|, |∇φt| (central differences of the formulas themselves, not of the nodal
//! interpolation, so that the mesh does not blur the answer) and the cosine of their angle.
//! A signed-distance pair has 1, 1 and 0 there to round-off.

use super::{CrackShape, NodalLevelSets};
use crate::mesh::Mesh;

/// The largest departure of |∇φn| or |∇φt| from 1, or of cos(∇φn, ∇φt) from 0, that
/// passes [`DistanceCheck::is_distance`] (relative: these are dimensionless).
pub const DISTANCE_TOLERANCE: f64 = 0.01;

/// What [`distance_check`] measured on the crack near its front.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceCheck {
    /// Number of points sampled.
    pub points: usize,
    /// Smallest and largest |∇φn|.
    pub grad_n: [f64; 2],
    /// Smallest and largest |∇φt|.
    pub grad_t: [f64; 2],
    /// Largest |cos| of the angle between ∇φn and ∇φt.
    pub max_cos: f64,
    /// The point with the largest departure from a signed-distance pair.
    pub worst: [f64; 3],
}

impl DistanceCheck {
    /// The largest departure from a signed-distance pair (|∇φ| − 1 or the cosine).
    pub fn deviation(&self) -> f64 {
        let off = |g: [f64; 2]| (1.0 - g[0]).abs().max((g[1] - 1.0).abs());
        off(self.grad_n).max(off(self.grad_t)).max(self.max_cos)
    }

    /// True when the level sets are signed distances within [`DISTANCE_TOLERANCE`].
    pub fn is_distance(&self) -> bool {
        self.deviation() <= DISTANCE_TOLERANCE
    }
}

/// Measures a formula crack's level sets on the crack near its front (see the module doc).
/// `None` for shapes other than [`CrackShape::Formula`] with a φt (built-in and meshed
/// cracks are distances by construction; an interface has no front and its φn enters only
/// by its sign and its normal direction), and when no point of the crack near the front
/// lies in the mesh. `ls` are the nodal values (they select the cells).
pub fn distance_check(shape: &CrackShape, mesh: &Mesh, ls: &NodalLevelSets) -> Option<DistanceCheck> {
    let CrackShape::Formula { lst: Some(_), .. } = shape else { return None };
    let shape = shape.normalised().ok()?;
    let lst = ls.lst.as_ref()?;
    let eval = |p: [f64; 3]| {
        let (n, t) = shape.eval_normalised(p);
        (n, t.unwrap_or(f64::NAN))
    };
    let dim = mesh.dim;
    let grad = |p: [f64; 3], h: f64| {
        let d = 1e-6 * h;
        let (mut gn, mut gt) = ([0.0; 3], [0.0; 3]);
        for i in 0..dim {
            let (mut a, mut b) = (p, p);
            a[i] += d;
            b[i] -= d;
            let (na, ta) = eval(a);
            let (nb, tb) = eval(b);
            gn[i] = (na - nb) / (2.0 * d);
            gt[i] = (ta - tb) / (2.0 * d);
        }
        (gn, gt)
    };
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut out: Option<DistanceCheck> = None;
    let mut worst_dev = -1.0;
    for (c, cell) in mesh.cells.iter().enumerate() {
        let nodes = cell.nodes();
        let h = mesh.cell_edge_length(c);
        let (mut lo, mut hi, mut tmin) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        let mut centre = [0.0; 3];
        for &v in nodes {
            let (Some(&pn), Some(&pt), Some(x)) = (ls.lsn.get(v), lst.get(v), mesh.nodes.get(v)) else { return None };
            lo = lo.min(pn);
            hi = hi.max(pn);
            tmin = tmin.min(pt.abs());
            for i in 0..3 {
                centre[i] += x[i] / nodes.len() as f64;
            }
        }
        if !(lo <= 0.0 && hi >= 0.0) || tmin > 2.0 * h || !(h > 0.0) {
            continue;
        }
        // The cell centre moved onto φn = 0 (Newton along ∇φn).
        let mut p = centre;
        let mut on = false;
        for _ in 0..8 {
            let (phin, _) = eval(p);
            if !phin.is_finite() {
                break;
            }
            if phin.abs() <= 1e-9 * h {
                on = true;
                break;
            }
            let (gn, _) = grad(p, h);
            let g2 = gn[0] * gn[0] + gn[1] * gn[1] + gn[2] * gn[2];
            if !(g2 > 0.0) || !g2.is_finite() {
                break;
            }
            for i in 0..3 {
                p[i] -= phin * gn[i] / g2;
            }
        }
        let moved = norm([p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]]);
        let (_, phit) = eval(p);
        if !on || moved > 2.0 * h || !(phit.abs() <= 2.0 * h) {
            continue;
        }
        let (gn, gt) = grad(p, h);
        let (a, b) = (norm(gn), norm(gt));
        if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0) {
            continue;
        }
        let cos = ((gn[0] * gt[0] + gn[1] * gt[1] + gn[2] * gt[2]) / (a * b)).abs();
        let dev = (a - 1.0).abs().max((b - 1.0).abs()).max(cos);
        let r = out.get_or_insert(DistanceCheck { points: 0, grad_n: [a, a], grad_t: [b, b], max_cos: cos, worst: p });
        r.points += 1;
        r.grad_n = [r.grad_n[0].min(a), r.grad_n[1].max(a)];
        r.grad_t = [r.grad_t[0].min(b), r.grad_t[1].max(b)];
        r.max_cos = r.max_cos.max(cos);
        if dev > worst_dev {
            worst_dev = dev;
            r.worst = p;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::CellType;
    use crate::formula::Formula;
    use crate::mesh::generate;
    use std::collections::BTreeMap;

    fn formula_shape(lsn: &str, lst: &str) -> CrackShape {
        let f = |s: &str| Formula::parse(s, &BTreeMap::new()).unwrap();
        CrackShape::formula(f(lsn), Some(f(lst)))
    }

    fn check(mesh: &Mesh, shape: &CrackShape) -> DistanceCheck {
        let ls = super::super::sample(shape, mesh).unwrap();
        distance_check(shape, mesh, &ls).expect("points near the front")
    }

    /// A formula written as the signed distances of a straight edge crack (y = 0.013,
    /// tip at x = 0.0071) passes: |∇φ| = 1 and orthogonal gradients to round-off.
    #[test]
    fn signed_distance_formulas_pass() {
        let mesh = generate::rectangle(CellType::Quad4, [-1.0, -1.0], [1.0, 1.0], [20, 20]).unwrap();
        let c = check(&mesh, &formula_shape("y - 0.013", "x - 0.0071"));
        assert!(c.points >= 2, "{c:?}");
        assert!(c.deviation() < 1e-6, "{c:?}");
        assert!(c.is_distance());
    }

    /// A circular-arc crack (radius 0.6 about the origin, from the negative x axis to the
    /// tip at angle 0.3 rad): φn = ρ − R and φt = R·(θ − 0.3) are signed distances on the
    /// crack (|∇φt| = R/ρ is 1 only at ρ = R, which is where the check looks).
    #[test]
    fn curved_crack_distances_pass_on_the_crack() {
        // Shifted so that no node lies on x = 0, where atan(y/x) is not defined.
        let mesh = generate::rectangle(CellType::Tri3, [-1.03, -1.0], [0.97, 1.0], [16, 16]).unwrap();
        let c = check(&mesh, &formula_shape("sqrt(x^2 + y^2) - 0.6", "0.6 * (atan(y / x) - 0.3)"));
        assert!(c.points >= 2, "{c:?}");
        assert!(c.deviation() < 1e-6, "{c:?}");
    }

    /// φn = 2·(y − 0.013) (the right sign, twice the slope) and φt = x + x³ near a tip at
    /// x = 0: |∇φn| = 2 is reported (and the check fails); the cubic term is 1 + 3x², which
    /// the check sees as soon as the sampled points reach |x| > 0.06.
    #[test]
    fn scaled_and_polynomial_level_sets_are_measured() {
        let mesh = generate::rectangle(CellType::Quad4, [-1.0, -1.0], [1.0, 1.0], [20, 20]).unwrap();
        let c = check(&mesh, &formula_shape("2 * (y - 0.013)", "x"));
        assert!((c.grad_n[0] - 2.0).abs() < 1e-6 && (c.grad_n[1] - 2.0).abs() < 1e-6, "{c:?}");
        assert!(!c.is_distance());
        let c = check(&mesh, &formula_shape("y - 0.013", "x + x^3"));
        assert!(c.grad_t[1] > 1.0 + DISTANCE_TOLERANCE && c.grad_t[1] < 1.2, "{c:?}");
        assert!(!c.is_distance());
        // A φt that is not orthogonal to φn: the front line tilted in the crack's plane.
        let c = check(&mesh, &formula_shape("y - 0.013", "(x + 0.5 * y) / sqrt(1.25)"));
        assert!((c.max_cos - 0.5 / 1.25f64.sqrt()).abs() < 1e-6, "{c:?}");
    }

    /// Built-in shapes and interfaces are not checked (distances by construction; an
    /// interface has no front).
    #[test]
    fn only_formula_cracks_are_checked() {
        let mesh = generate::rectangle(CellType::Quad4, [-1.0, -1.0], [1.0, 1.0], [8, 8]).unwrap();
        let seg = CrackShape::Segment { a: [-0.5, 0.01], b: [0.5, 0.01] };
        let ls = super::super::sample(&seg, &mesh).unwrap();
        assert!(distance_check(&seg, &mesh, &ls).is_none());
        let f = Formula::parse("2 * (y - 0.01)", &BTreeMap::new()).unwrap();
        let iface = CrackShape::formula(f, None);
        let ls = super::super::sample(&iface, &mesh).unwrap();
        assert!(distance_check(&iface, &mesh, &ls).is_none());
    }
}
