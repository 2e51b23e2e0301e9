//! The Newman–Raju stress intensity factor of a semi-elliptical surface crack in a finite
//! plate under tension (J. C. Newman Jr. and I. S. Raju, "An empirical stress-intensity
//! factor equation for the surface crack", Engineering Fracture Mechanics 15 (1981)
//! 185–192, equations for a/c ≤ 1), shared by the static and the fatigue tests of the
//! surface crack.

use std::f64::consts::PI;

/// K_I for a remote tension σ = 1 at the parametric angle `phi` (rad; 0 at the surface,
/// π/2 at the deepest point) of a crack of depth `a` and half-length `c` (a/c ≤ 1) in a
/// plate of thickness `t` and half-width `b`.
pub fn k1(a: f64, c: f64, t: f64, b: f64, phi: f64) -> f64 {
    let (r, at) = (a / c, a / t);
    let q = 1.0 + 1.464 * r.powf(1.65);
    let m1 = 1.13 - 0.09 * r;
    let m2 = -0.54 + 0.89 / (0.2 + r);
    let m3 = 0.5 - 1.0 / (0.65 + r) + 14.0 * (1.0 - r).powi(24);
    let g = 1.0 + (0.1 + 0.35 * at * at) * (1.0 - phi.sin()).powi(2);
    let f_phi = (r * r * phi.cos().powi(2) + phi.sin().powi(2)).powf(0.25);
    let f_w = (1.0 / (PI * c / (2.0 * b) * at.sqrt()).cos()).sqrt();
    (PI * a / q).sqrt() * (m1 + m2 * at * at + m3 * at.powi(4)) * g * f_phi * f_w
}
