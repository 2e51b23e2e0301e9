//! Propagation criteria at one crack tip, and the advance of every tip in one increment.
//!
//! Entry points: [`kink_angle`], [`equivalent_k`], [`plan`]; for a 3D front [`drive_3d`] and
//! [`advances`] (its K_eq smoothed along the front between the two).
//!
//! - Maximum hoop stress (Erdogan & Sih 1963): the crack kinks where the hoop stress of
//!   the near-tip field is largest, θ = 2 arctan[(K_I − √(K_I² + 8 K_II²)) / (4 K_II)]
//!   (θ = 0 when K_II = 0), and K_eq = cos(θ/2) [K_I cos²(θ/2) − 3/2 K_II sin θ], the K_I
//!   of the hoop stress there (K_eq = K_I in mode I, 2/√3 |K_II| in mode II).
//! - Maximum energy release rate: θ maximises G(θ) ∝ k1(θ)² + k2(θ)² over the kink
//!   angles with k1(θ) ≥ 0, with the K of an infinitesimal kink of Hussain, Pu &
//!   Underwood (1974) ([`kinked_k`], θ's sign turned to this convention):
//!   k1 = F(θ) (K_I cos θ − 3/2 K_II sin θ), k2 = F(θ) (K_II cos θ + ½ K_I sin θ),
//!   F = 4/(3 + cos²θ) · ((1 − θ/π)/(1 + θ/π))^(θ/2π); K_eq = √(k1² + k2²). Its mode II
//!   angle is −75.2°, against −70.5° for the hoop stress. (With the near-tip stresses
//!   on the ray θ as the kinked tip's K instead, G_max gives the hoop-stress angle
//!   exactly, Nuismer 1975; [`hoop_kinked_k`] is that field.)
//!
//! A negative K_I (faces pressed together: a closed crack with contact, or the
//! interpenetration of a crack without it) enters both criteria as 0: the faces carry
//! the compression, and only K_II drives the kink.
//!
//! K_III (3D fronts, [`plan_3d`]): the kink θ stays that of (K_I, K_II) in the plane
//! normal to the front (the twist a K_III would add is not represented, as in
//! Code_Aster's PROPA_FISS); the driving force takes K_III in with the form of Richard,
//! Fulland & Sander's K_V (2005; an approximation of Schöllmann et al.'s 2002 σ1'
//! criterion), K_eq,3D = ½ K_eq + ½ √(K_eq² + 4 K_III²) ([`equivalent_k_3d`]), with
//! the in-plane K_eq of the criterion above in place of Richard's: K_III = 0 gives the
//! 2D growth unchanged, pure mode III gives K_eq,3D = |K_III|, and with the hoop stress
//! criterion pure mode II gives 2/√3 |K_II| = 1.155 |K_II| as in Richard's form.
//!
//! θ is measured from e1 towards e2 of the tip frame (docs/conventions.md, "Crack
//! growth"), so K_II > 0 kinks the crack towards −e2.

use super::Propagation;
use std::f64::consts::PI;

/// The kink angle (radians, from e1 towards e2) of `criterion` at a tip with K_I, K_II.
pub fn kink_angle(criterion: super::Criterion, k1: f64, k2: f64) -> f64 {
    let k1 = k1.max(0.0);
    match criterion {
        super::Criterion::MaxHoopStress => hoop_stress_angle(k1, k2),
        super::Criterion::MaxEnergyRelease => max_energy_angle(k1, k2),
    }
}

/// The equivalent (mode I) stress intensity factor of `criterion` for a kink θ.
pub fn equivalent_k(criterion: super::Criterion, k1: f64, k2: f64, theta: f64) -> f64 {
    let k1 = k1.max(0.0);
    match criterion {
        super::Criterion::MaxHoopStress => {
            let c = (0.5 * theta).cos();
            c * (k1 * c * c - 1.5 * k2 * theta.sin())
        }
        super::Criterion::MaxEnergyRelease => {
            let (a, b) = kinked_k(k1, k2, theta);
            a.hypot(b)
        }
    }
}

/// Erdogan & Sih's angle of maximum hoop stress.
pub fn hoop_stress_angle(k1: f64, k2: f64) -> f64 {
    if k2 == 0.0 {
        return 0.0;
    }
    2.0 * ((k1 - (k1 * k1 + 8.0 * k2 * k2).sqrt()) / (4.0 * k2)).atan()
}

/// The K_I and K_II of an infinitesimal kink θ (Hussain, Pu & Underwood 1974).
pub fn kinked_k(k1: f64, k2: f64, theta: f64) -> (f64, f64) {
    let r = theta / PI;
    let f = 4.0 / (3.0 + theta.cos().powi(2)) * ((1.0 - r) / (1.0 + r)).powf(0.5 * r);
    let (s, c) = theta.sin_cos();
    (f * (k1 * c - 1.5 * k2 * s), f * (k2 * c + 0.5 * k1 * s))
}

/// The near-tip stresses of the straight crack on the ray θ, σ_θθ √(2πr) and
/// σ_rθ √(2πr): the hoop-stress criterion's K_eq is the first.
pub fn hoop_kinked_k(k1: f64, k2: f64, theta: f64) -> (f64, f64) {
    let c = 0.5 * (0.5 * theta).cos();
    let (s, co) = theta.sin_cos();
    (c * (k1 * (1.0 + co) - 3.0 * k2 * s), c * (k1 * s + k2 * (3.0 * co - 1.0)))
}

/// The angle maximising k1(θ)² + k2(θ)² of [`kinked_k`] with k1(θ) ≥ 0: a scan of
/// (−π, π) by 0.1°, then
/// golden-section refinement to 1e-10 rad.
pub fn max_energy_angle(k1: f64, k2: f64) -> f64 {
    if k2 == 0.0 {
        return 0.0;
    }
    let g = |t: f64| {
        let (a, b) = kinked_k(k1, k2, t);
        if a < 0.0 {
            f64::NEG_INFINITY
        } else {
            a * a + b * b
        }
    };
    let n = 3600;
    let step = 2.0 * PI / n as f64;
    let best = (1..n).map(|i| -PI + i as f64 * step).max_by(|a, b| g(*a).total_cmp(&g(*b))).unwrap_or(0.0);
    let (mut lo, mut hi) = (best - step, best + step);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    while hi - lo > 1e-10 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if g(x1) < g(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    0.5 * (lo + hi)
}

/// The 3D equivalent K with K_III (see the module doc): ½ K_eq + ½ √(K_eq² + 4 K_III²);
/// exactly `k_eq` when K_III = 0.
pub fn equivalent_k_3d(k_eq: f64, k3: f64) -> f64 {
    if k3 == 0.0 {
        return k_eq;
    }
    0.5 * k_eq + 0.5 * (k_eq * k_eq + 4.0 * k3 * k3).sqrt()
}

/// One tip's growth in an increment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipPlan {
    /// Kink angle θ (radians, from e1 towards e2).
    pub theta: f64,
    /// K_eq of the criterion: of the static K, or in fatigue of the cycle's ranges
    /// (ΔK_eq, the caller passes the ranges, `growth::fatigue::ranges`).
    pub k_eq: f64,
    /// The advance Δa (0 below the threshold or for a frozen crack).
    pub advance: f64,
}

/// The growth of every tip in one increment: `tips[i] = (K_I, K_II, grows)` (in fatigue
/// the cycle's ranges ΔK_I, ΔK_II). The tip of
/// largest driving force (K_eq; ΔK_eq in fatigue) advances by `increment`, the others by
/// increment·(K_eq/K_eq,max)^p; tips at or below the threshold (and frozen ones) do not
/// advance. `None` when no tip is above the threshold.
pub fn plan(tips: &[(f64, f64, bool)], opts: &Propagation) -> Option<Vec<TipPlan>> {
    let with_k3: Vec<(f64, f64, f64, bool)> = tips.iter().map(|&(k1, k2, g)| (k1, k2, 0.0, g)).collect();
    plan_3d(&with_k3, opts)
}

/// [`plan`] for the points of a 3D front, `tips[i] = (K_I, K_II, K_III, grows)`: the kink
/// from (K_I, K_II), the driving force [`equivalent_k_3d`] ([`drive_3d`], then
/// [`advances`]).
pub fn plan_3d(tips: &[(f64, f64, f64, bool)], opts: &Propagation) -> Option<Vec<TipPlan>> {
    let drives: Vec<(f64, f64, bool)> = tips
        .iter()
        .map(|&(k1, k2, k3, grows)| {
            let (theta, k_eq) = drive_3d(opts.criterion, k1, k2, k3);
            (theta, k_eq, grows)
        })
        .collect();
    advances(&drives, opts)
}

/// The kink θ and the driving force K_eq,3D ([`equivalent_k_3d`]) of a front point.
pub fn drive_3d(criterion: super::Criterion, k1: f64, k2: f64, k3: f64) -> (f64, f64) {
    let theta = kink_angle(criterion, k1, k2);
    (theta, equivalent_k_3d(equivalent_k(criterion, k1, k2, theta), k3))
}

/// The advance of every point from its kink θ and driving force K_eq,
/// `points[i] = (θ, K_eq, grows)` (the K_eq as the caller wants them read: a 3D front
/// smooths them along the front first, `growth::surface::smooth_along_front`; in fatigue
/// they are the ΔK_eq of the cycle's ranges): the point
/// of largest driving force advances by `increment`, the others
/// by increment·(K_eq/K_eq,max)^p; points at or below the threshold (and frozen ones) do
/// not advance. `None` when no point is above the threshold.
pub fn advances(points: &[(f64, f64, bool)], opts: &Propagation) -> Option<Vec<TipPlan>> {
    let threshold = opts.fatigue.map_or(opts.threshold, |f| f.threshold);
    let mut out: Vec<TipPlan> = points.iter().map(|&(theta, k_eq, _)| TipPlan { theta, k_eq, advance: 0.0 }).collect();
    let active: Vec<bool> =
        (0..points.len()).map(|i| points[i].2 && out[i].k_eq > threshold && out[i].k_eq > 0.0).collect();
    let max = (0..points.len()).filter(|&i| active[i]).map(|i| out[i].k_eq).fold(0.0, f64::max);
    if !(max > 0.0) {
        return None;
    }
    let p = opts.advance_exponent();
    for i in 0..points.len() {
        if active[i] {
            out[i].advance = opts.increment * (out[i].k_eq / max).powf(p);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::Criterion;

    #[test]
    fn pure_mode_two_kinks_by_minus_70_5_degrees() {
        let t = hoop_stress_angle(0.0, 1.0).to_degrees();
        assert!((t + 70.528_779).abs() < 1e-5, "{t}");
        assert!((hoop_stress_angle(0.0, -1.0).to_degrees() - 70.528_779).abs() < 1e-5);
        // K_eq = 2/√3 K_II at that angle, and the hoop stress is stationary there.
        let th = hoop_stress_angle(0.0, 1.0);
        let k = equivalent_k(Criterion::MaxHoopStress, 0.0, 1.0, th);
        assert!((k - 2.0 / 3f64.sqrt()).abs() < 1e-12, "{k}");
        let (a, b) = (
            equivalent_k(Criterion::MaxHoopStress, 0.0, 1.0, th - 1e-4),
            equivalent_k(Criterion::MaxHoopStress, 0.0, 1.0, th + 1e-4),
        );
        assert!(a < k && b < k);
        // Mode I: straight ahead, K_eq = K_I.
        assert_eq!(hoop_stress_angle(2.0, 0.0), 0.0);
        assert_eq!(equivalent_k(Criterion::MaxHoopStress, 2.0, 0.0, 0.0), 2.0);
    }

    #[test]
    fn hoop_stress_angle_is_where_the_shear_stress_vanishes() {
        // σ_rθ ∝ k2(θ) of the kinked tip is zero at the hoop-stress maximum.
        for (k1, k2) in [(1.0, 0.3), (0.4, 1.0), (1.0, -0.7), (0.0, 2.0)] {
            let th = hoop_stress_angle(k1, k2);
            let (_, b) = hoop_kinked_k(k1, k2, th);
            assert!(b.abs() < 1e-12 * k1.hypot(k2), "{k1} {k2}: {b}");
        }
    }

    #[test]
    fn energy_release_angle_mode_two_and_mixed() {
        let t = max_energy_angle(0.0, 1.0).to_degrees();
        assert!((t + 75.2).abs() < 0.1, "{t}");
        assert!((max_energy_angle(0.0, -1.0).to_degrees() - 75.2).abs() < 0.1);
        // Mode I: the kinked-tip K is the straight one.
        assert_eq!(kinked_k(1.5, 0.0, 0.0), (1.5, 0.0));
        assert_eq!(max_energy_angle(1.0, 0.0), 0.0);
        // Small K_II: θ ≈ −2 K_II/K_I by the hoop stress, ≈ −2.2 K_II/K_I by G_max.
        let (a, b) = (max_energy_angle(1.0, 0.01), hoop_stress_angle(1.0, 0.01));
        assert!((b + 0.02).abs() < 1e-5 && (a + 0.0221).abs() < 1e-4, "{a} {b}");
    }

    #[test]
    fn advances_scale_with_the_driving_force_and_stop_at_the_threshold() {
        let mut p = Propagation {
            criterion: Criterion::MaxHoopStress,
            increment: 0.1,
            steps: 1,
            exponent: 2.0,
            fracture_toughness: None,
            stop_length: None,
            threshold: 0.0,
            fatigue: None,
        };
        let r = plan(&[(1.0, 0.0, true), (0.5, 0.0, true), (2.0, 0.0, false)], &p).unwrap();
        assert_eq!(r[0].advance, 0.1);
        assert!((r[1].advance - 0.025).abs() < 1e-15);
        assert_eq!(r[2].advance, 0.0);
        p.threshold = 0.6;
        let r = plan(&[(1.0, 0.0, true), (0.5, 0.0, true)], &p).unwrap();
        assert_eq!((r[0].advance, r[1].advance), (0.1, 0.0));
        assert!(plan(&[(0.5, 0.0, true), (-1.0, 0.0, true)], &p).is_none());
    }

    #[test]
    fn k_three_enters_the_driving_force_as_richards_k_v_in_the_pure_modes() {
        // Pure mode III: K_eq = |K_III|; no K_III: the 2D K_eq; K_I with K_III: Richard's
        // K_V = ½K_I + ½√(K_I² + 4K_III²).
        assert_eq!(equivalent_k_3d(0.0, -2.0), 2.0);
        assert_eq!(equivalent_k_3d(1.3, 0.0), 1.3);
        assert!((equivalent_k_3d(1.0, 1.0) - 0.5 * (1.0 + 5f64.sqrt())).abs() < 1e-15);
        let p = Propagation {
            criterion: Criterion::MaxHoopStress,
            increment: 0.1,
            steps: 1,
            exponent: 2.0,
            fracture_toughness: None,
            stop_length: None,
            threshold: 0.0,
            fatigue: None,
        };
        let r = plan_3d(&[(1.0, 0.0, 0.0, true), (1.0, 0.0, 1.0, true)], &p).unwrap();
        assert_eq!(r[0].theta, 0.0);
        assert_eq!(r[1].advance, 0.1);
        assert!((r[0].advance - 0.1 / (0.25 * (1.0 + 5f64.sqrt()).powi(2))).abs() < 1e-15);
    }
}
