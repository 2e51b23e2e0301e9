//! The contact pressure recovered from the multipliers: at any point of a crack, the value
//! at that point of the local linear fit, weighted by the contact points' areas and a
//! tricube kernel, of the pressure −λ at the contact points within a radius of
//! [`RECOVERY_CELLS`] cell sizes (a moving least-squares fit, degree 1, in the crack's
//! tangent plane at the point).
//!
//! Entry points: [`Recovery::new`] and [`Recovery::at`] (one crack's points, any position);
//! [`recovered_pressure`] (every contact point of a setup, each crack with its own radius).
//!
//! Why: on a sliding 3D crack the multipliers carry a packet-to-packet oscillation of a few
//! percent (±5% on unstructured tet4 away from the tip zone, ±11% where the tip-enriched
//! zone ends) that carries no force: its averages over a few cells are within a fraction
//! of a percent (`docs/contact-algorithms.md`, "3D contact pressure pointwise: the
//! recovered pressure"). The recovered pressure is the usual answer to a traction
//! that is accurate in the mean but noisy pointwise, the contact counterpart of the
//! superconvergent patch recovery of stresses (Zienkiewicz & Zhu 1992) and of the
//! smoothing of G along a 3D front (`growth::surface::smooth_along_front`, the same kernel
//! and degree). A degree-1 fit reproduces a uniform and a linearly varying pressure exactly
//! (on a flat crack), so the contact patch test is kept; near the front the window is cut
//! by the crack's edge and the fit extrapolates linearly from the points inside. Where the
//! pressure itself varies over less than the window (the edge of a contact zone, where open
//! points have λ = 0, or a contact a few cells wide) the fit rounds it off: read the
//! multipliers there. It is an output only: the contact law, the statuses and the SIFs read
//! the multipliers themselves.

use super::points::{tangent_basis, ContactPoints};
use std::collections::HashMap;

/// The half-width of the fit window in cell sizes (the crack's mean cut-cell edge,
/// [`super::points::ContactCrack::cell_size`]): 3, as the SIF points' smoothing along a 3D
/// front. Measured on the sliding penny (`docs/contact-algorithms.md`): 2 cells leave
/// ±1.3% beyond 0.1 a from the front, 3 cells ±0.5%.
pub const RECOVERY_CELLS: f64 = 3.0;

/// One crack's contact points (position, weight, value), bucketed by the window radius.
#[derive(Debug, Clone)]
pub struct Recovery {
    dim: usize,
    radius: f64,
    points: Vec<([f64; 3], f64, f64)>,
    buckets: HashMap<[i64; 3], Vec<u32>>,
}

impl Recovery {
    /// The points (position, integration weight, value) of one crack and the window radius
    /// (> 0).
    pub fn new(dim: usize, radius: f64, points: Vec<([f64; 3], f64, f64)>) -> Recovery {
        let mut buckets: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            buckets.entry(bucket(p.0, radius)).or_default().push(i as u32);
        }
        Recovery { dim, radius, points, buckets }
    }

    /// The recovered value at `x` on the crack, whose unit normal there is `normal`: the
    /// value at `x` of the weighted linear fit in the tangent plane (the weighted mean
    /// where the points within the window do not span it, e.g. fewer than three in 3D);
    /// `None` when no point lies within the window.
    pub fn at(&self, x: [f64; 3], normal: [f64; 3]) -> Option<f64> {
        let t = tangent_basis(self.dim, normal, [0.0, 0.0, 1.0]);
        let m = self.dim; // unknowns: the value and dim − 1 slopes
        let mut a = [[0.0; 3]; 3];
        let mut b = [0.0; 3];
        let c = bucket(x, self.radius);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(ids) = self.buckets.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else { continue };
                    for &i in ids {
                        let (q, w, v) = self.points[i as usize];
                        let d = [q[0] - x[0], q[1] - x[1], q[2] - x[2]];
                        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / self.radius;
                        if r >= 1.0 {
                            continue;
                        }
                        let k = w * (1.0 - r * r * r).powi(3);
                        let mut phi = [1.0, 0.0, 0.0];
                        for (s, ts) in t.iter().enumerate().take(m - 1) {
                            phi[s + 1] = (d[0] * ts[0] + d[1] * ts[1] + d[2] * ts[2]) / self.radius;
                        }
                        for r in 0..m {
                            b[r] += k * phi[r] * v;
                            for s in 0..m {
                                a[r][s] += k * phi[r] * phi[s];
                            }
                        }
                    }
                }
            }
        }
        if a[0][0] <= 0.0 {
            return None;
        }
        let mean = b[0] / a[0][0];
        Some(solve_spd(&mut a, &mut b, m).unwrap_or(mean))
    }
}

/// The bucket of `x` for cells of side `h`.
fn bucket(x: [f64; 3], h: f64) -> [i64; 3] {
    [(x[0] / h).floor() as i64, (x[1] / h).floor() as i64, (x[2] / h).floor() as i64]
}

/// The first unknown of the m × m symmetric system `a` u = `b` by Cholesky, or `None` when a
/// pivot falls below 1e-6 of the first (the points do not span the tangent plane).
fn solve_spd(a: &mut [[f64; 3]; 3], b: &mut [f64; 3], m: usize) -> Option<f64> {
    let scale = a[0][0];
    for j in 0..m {
        let d = a[j][j] - (0..j).map(|k| a[j][k] * a[j][k]).sum::<f64>();
        if d < 1e-6 * scale {
            return None;
        }
        a[j][j] = d.sqrt();
        for i in j + 1..m {
            a[i][j] = (a[i][j] - (0..j).map(|k| a[i][k] * a[j][k]).sum::<f64>()) / a[j][j];
        }
    }
    // Forward then back substitution with the lower factor.
    for i in 0..m {
        for j in 0..i {
            b[i] -= a[i][j] * b[j];
        }
        b[i] /= a[i][i];
    }
    for i in (0..m).rev() {
        for j in i + 1..m {
            b[i] -= a[j][i] * b[j];
        }
        b[i] /= a[i][i];
    }
    Some(b[0])
}

/// The recovered pressure at every contact point of `pts`, from the pressure −λ at the
/// points (`lambda`, one λ per point): each contact crack's points are fitted among
/// themselves with the window [`RECOVERY_CELLS`] × its cell size.
pub fn recovered_pressure(pts: &ContactPoints, lambda: &[f64]) -> Vec<f64> {
    let recoveries = crack_recoveries(pts, lambda);
    pts.points.iter().zip(lambda).map(|(p, l)| recoveries[p.crack].at(p.x, p.normal).unwrap_or(-l)).collect()
}

/// One [`Recovery`] of the pressure −λ per contact crack of `pts`.
pub fn crack_recoveries(pts: &ContactPoints, lambda: &[f64]) -> Vec<Recovery> {
    let mut per: Vec<Vec<([f64; 3], f64, f64)>> = vec![vec![]; pts.cracks.len()];
    for (p, l) in pts.points.iter().zip(lambda) {
        per[p.crack].push((p.x, p.weight, -l));
    }
    per.into_iter()
        .zip(&pts.cracks)
        .map(|(points, c)| Recovery::new(pts.dim, RECOVERY_CELLS * c.cell_size, points))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear pressure on a flat crack is recovered exactly, inside and at the edge of the
    /// point cloud (where the window is cut), and with too few points the mean is returned.
    #[test]
    fn linear_pressure_is_recovered_exactly_on_a_flat_crack() {
        let f = |x: [f64; 3]| 1.0 + 0.3 * x[0] - 0.2 * x[1];
        let mut pts = vec![];
        for i in 0..21 {
            for j in 0..21 {
                // An irregular cloud in the plane z = 0.5, weights varying.
                let x = [0.05 * i as f64 + 0.01 * ((i * j) % 3) as f64, 0.05 * j as f64, 0.5];
                pts.push((x, 1.0 + 0.5 * ((i + 2 * j) % 4) as f64, f(x)));
            }
        }
        let r = Recovery::new(3, 0.2, pts);
        for x in [[0.5, 0.5, 0.5], [0.0, 0.0, 0.5], [1.0, 0.3, 0.5]] {
            let v = r.at(x, [0.0, 0.0, 1.0]).unwrap();
            assert!((v - f(x)).abs() < 1e-12, "{v} vs {}", f(x));
        }
        assert!(r.at([5.0, 5.0, 0.5], [0.0, 0.0, 1.0]).is_none());
        // Two points on a line: the fit is singular across it, the mean is returned.
        let r = Recovery::new(3, 1.0, vec![([0.0, 0.0, 0.0], 1.0, 1.0), ([0.1, 0.0, 0.0], 3.0, 2.0)]);
        assert!((r.at([0.05, 0.0, 0.0], [0.0, 0.0, 1.0]).unwrap() - 1.75).abs() < 1e-12);
    }
}
