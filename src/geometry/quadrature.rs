//! Quadrature rules on reference shapes.
//!
//! Reference shapes (the same as in [`crate::element`]):
//! - line `[-1, 1]`,
//! - triangle `{ξ, η ≥ 0, ξ + η ≤ 1}` (area 1/2),
//! - square `[-1, 1]²`, cube `[-1, 1]³`,
//! - tetrahedron `{ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1}` (volume 1/6).
//!
//! Points are stored as `[f64; 3]` whatever the dimension (unused coordinates are 0).
//! Simplex rules of any degree are built as collapsed (conical product) Gauss rules,
//! which are exact for polynomials of the requested degree and have positive weights.

use std::sync::OnceLock;

/// A set of points and weights on a reference shape.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadratureRule {
    pub points: Vec<[f64; 3]>,
    pub weights: Vec<f64>,
}

impl QuadratureRule {
    pub fn len(&self) -> usize {
        self.weights.len()
    }
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
    /// Iterate over `(point, weight)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (&[f64; 3], f64)> {
        self.points.iter().zip(self.weights.iter().copied())
    }
}

/// Gauss–Legendre points and weights on `[-1, 1]` with `n` points (exact to degree `2n − 1`).
/// Computed by Newton iteration on the Legendre polynomial, accurate to round-off.
/// Rules with up to 64 points are computed once and then copied.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "a Gauss rule needs at least one point");
    if n <= CACHED_RULES {
        static CACHE: [OnceLock<(Vec<f64>, Vec<f64>)>; CACHED_RULES] = [const { OnceLock::new() }; CACHED_RULES];
        let (x, w) = CACHE[n - 1].get_or_init(|| compute_gauss_legendre(n));
        return (x.clone(), w.clone());
    }
    compute_gauss_legendre(n)
}

/// Largest point count of the cached Gauss–Legendre rules.
const CACHED_RULES: usize = 64;

fn compute_gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    // Legendre P_n(z) and P_{n-1}(z) by the three-term recurrence.
    let legendre = |z: f64| {
        let (mut p0, mut p1) = (1.0, z);
        for k in 2..=n {
            let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
            p0 = p1;
            p1 = p2;
        }
        if n == 1 {
            (z, 1.0)
        } else {
            (p1, p0)
        }
    };
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        // Initial guess (Tricomi), then Newton on P_n; P_n' = n (z P_n − P_{n−1}) / (z² − 1).
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (pn, pm) = legendre(z);
            let dz = pn / (n as f64 * (z * pn - pm) / (z * z - 1.0));
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        let (pn, pm) = legendre(z);
        let dp = n as f64 * (z * pn - pm) / (z * z - 1.0);
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    if n % 2 == 1 {
        x[n / 2] = 0.0;
    }
    (x, w)
}

/// Number of Gauss–Legendre points per direction that integrates `degree` exactly.
fn points_for_degree(degree: usize) -> usize {
    degree / 2 + 1
}

/// Gauss rule on the line `[-1, 1]`, exact to `degree`.
pub fn gauss_line(degree: usize) -> QuadratureRule {
    let (x, w) = gauss_legendre(points_for_degree(degree));
    QuadratureRule { points: x.iter().map(|&xi| [xi, 0.0, 0.0]).collect(), weights: w }
}

/// Tensor Gauss rule on the square `[-1, 1]²`, exact to `degree` in each variable.
pub fn gauss_square(degree: usize) -> QuadratureRule {
    let (x, w) = gauss_legendre(points_for_degree(degree));
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for j in 0..x.len() {
        for i in 0..x.len() {
            rule.points.push([x[i], x[j], 0.0]);
            rule.weights.push(w[i] * w[j]);
        }
    }
    rule
}

/// Tensor Gauss rule on the cube `[-1, 1]³`, exact to `degree` in each variable.
pub fn gauss_cube(degree: usize) -> QuadratureRule {
    let (x, w) = gauss_legendre(points_for_degree(degree));
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for k in 0..x.len() {
        for j in 0..x.len() {
            for i in 0..x.len() {
                rule.points.push([x[i], x[j], x[k]]);
                rule.weights.push(w[i] * w[j] * w[k]);
            }
        }
    }
    rule
}

/// Rule on the reference triangle exact to `degree`. Degrees 1 and 2 use the classical
/// 1- and 3-point rules; higher degrees a collapsed Gauss rule (positive weights).
pub fn gauss_triangle(degree: usize) -> QuadratureRule {
    match degree {
        0 | 1 => QuadratureRule { points: vec![[1.0 / 3.0, 1.0 / 3.0, 0.0]], weights: vec![0.5] },
        2 => QuadratureRule {
            points: vec![[1.0 / 6.0, 1.0 / 6.0, 0.0], [2.0 / 3.0, 1.0 / 6.0, 0.0], [1.0 / 6.0, 2.0 / 3.0, 0.0]],
            weights: vec![1.0 / 6.0; 3],
        },
        _ => collapsed_triangle(degree),
    }
}

/// Collapsed (Duffy) rule on the triangle: the square `[0,1]²` mapped by
/// `(u, v) ↦ (u, v (1 − u))`, Jacobian `1 − u`. Exact to `degree`.
pub fn collapsed_triangle(degree: usize) -> QuadratureRule {
    let (x, w) = gauss_legendre(points_for_degree(degree + 1));
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for i in 0..x.len() {
        let u = 0.5 * (x[i] + 1.0);
        for j in 0..x.len() {
            let v = 0.5 * (x[j] + 1.0);
            rule.points.push([u, v * (1.0 - u), 0.0]);
            rule.weights.push(0.25 * w[i] * w[j] * (1.0 - u));
        }
    }
    rule
}

/// Rule on the reference tetrahedron exact to `degree`. Degree 1: centroid; degree 2: the
/// classical 4-point rule; higher: a collapsed Gauss rule (positive weights).
pub fn gauss_tetrahedron(degree: usize) -> QuadratureRule {
    match degree {
        0 | 1 => QuadratureRule { points: vec![[0.25, 0.25, 0.25]], weights: vec![1.0 / 6.0] },
        2 => {
            let a = 0.585_410_196_624_968_5;
            let b = 0.138_196_601_125_010_5;
            QuadratureRule { points: vec![[b, b, b], [a, b, b], [b, a, b], [b, b, a]], weights: vec![1.0 / 24.0; 4] }
        }
        _ => collapsed_tetrahedron(degree),
    }
}

/// Collapsed rule on the tetrahedron: `(u, v, w) ↦ (u, v(1−u), w(1−u)(1−v))`,
/// Jacobian `(1−u)²(1−v)`. Exact to `degree`.
pub fn collapsed_tetrahedron(degree: usize) -> QuadratureRule {
    let (x, w) = gauss_legendre(points_for_degree(degree + 2));
    let mut rule = QuadratureRule { points: vec![], weights: vec![] };
    for i in 0..x.len() {
        let u = 0.5 * (x[i] + 1.0);
        for j in 0..x.len() {
            let v = 0.5 * (x[j] + 1.0);
            for k in 0..x.len() {
                let t = 0.5 * (x[k] + 1.0);
                rule.points.push([u, v * (1.0 - u), t * (1.0 - u) * (1.0 - v)]);
                rule.weights.push(0.125 * w[i] * w[j] * w[k] * (1.0 - u) * (1.0 - u) * (1.0 - v));
            }
        }
    }
    rule
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binom_monomial_triangle(p: i32, q: i32) -> f64 {
        // ∫_T ξ^p η^q = p! q! / (p + q + 2)!
        let f = |n: i32| (1..=n).map(|k| k as f64).product::<f64>();
        f(p) * f(q) / f(p + q + 2)
    }

    #[test]
    fn gauss_legendre_integrates_monomials_exactly() {
        for n in 1..=8 {
            let (x, w) = gauss_legendre(n);
            for d in 0..(2 * n) {
                let exact = if d % 2 == 1 { 0.0 } else { 2.0 / (d as f64 + 1.0) };
                let s: f64 = x.iter().zip(&w).map(|(xi, wi)| wi * xi.powi(d as i32)).sum();
                assert!((s - exact).abs() < 1e-14, "n={n} d={d}: {s} vs {exact}");
            }
        }
    }

    #[test]
    fn triangle_rules_exact_to_their_degree() {
        for degree in 1..=8 {
            let rule = gauss_triangle(degree);
            for p in 0..=degree as i32 {
                for q in 0..=(degree as i32 - p) {
                    let s: f64 = rule.iter().map(|(x, w)| w * x[0].powi(p) * x[1].powi(q)).sum();
                    let exact = binom_monomial_triangle(p, q);
                    assert!((s - exact).abs() < 1e-14, "deg {degree} p{p} q{q}");
                }
            }
        }
    }

    #[test]
    fn tetrahedron_rules_exact_to_their_degree() {
        let f = |n: i32| (1..=n).map(|k| k as f64).product::<f64>();
        for degree in 1..=6 {
            let rule = gauss_tetrahedron(degree);
            for p in 0..=degree as i32 {
                for q in 0..=(degree as i32 - p) {
                    for r in 0..=(degree as i32 - p - q) {
                        let s: f64 = rule.iter().map(|(x, w)| w * x[0].powi(p) * x[1].powi(q) * x[2].powi(r)).sum();
                        let exact = f(p) * f(q) * f(r) / f(p + q + r + 3);
                        assert!((s - exact).abs() < 1e-14, "deg {degree} {p}{q}{r}");
                    }
                }
            }
        }
    }
}
