//! The pointwise contact and Coulomb friction laws of the augmented-Lagrangian
//! formulation (formulation §5), as small pure functions.
//!
//! Entry points: [`PointState`], [`contact_indicator`], [`friction_indicator`], [`Status`].
//!
//! ```text
//! contact  χ_c = [g_n ≤ 0],  g_n = λ − ρ_n d_n          (d_n > 0: overlap, λ ≤ 0: compression)
//! friction χ_f = [|g_τ| ≤ 1], g_τ = Λ + ρ_τ v_τ          (v_τ: tangential jump increment)
//! ```

/// What a contact point remembers between iterations.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointState {
    /// Contact status χ_c, frozen during the Newton loop.
    pub contact: bool,
    /// Frozen friction threshold λ̄ (≤ 0), updated by the fixed point.
    pub lam_bar: f64,
    /// Displacement jump at the start of the load step (for v_τ).
    pub prev_jump: [f64; 3],
    /// Frozen friction status (Some(true) stick, Some(false) slip) while a Newton loop
    /// that cycles between statuses finishes; the outer loop then checks it.
    pub lock: Option<bool>,
}

/// The status of a point, as written to the output (0 open, 1 stick, 2 slip).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Open = 0,
    Stick = 1,
    Slip = 2,
}

/// χ_c: in contact when g_n = λ − ρ_n d_n ≤ 0.
#[inline]
pub fn contact_indicator(lambda: f64, d_n: f64, rho_n: f64) -> bool {
    lambda - rho_n * d_n <= 0.0
}

/// Tie tolerance of the friction indicator: a point exactly at the Coulomb limit
/// (|g_τ| = 1 to round-off, no slip increment) counts as sticking.
pub const STICK_TOLERANCE: f64 = 1e-9;

/// χ_f and g_τ: sticking when |Λ + ρ_τ v_τ| ≤ 1 (+ [`STICK_TOLERANCE`]). Returns (stick, g_τ).
#[inline]
pub fn friction_indicator(big_lambda: [f64; 2], v_tau: [f64; 2], rho_t: f64) -> (bool, [f64; 2]) {
    let g = [big_lambda[0] + rho_t * v_tau[0], big_lambda[1] + rho_t * v_tau[1]];
    ((g[0] * g[0] + g[1] * g[1]).sqrt() <= 1.0 + STICK_TOLERANCE, g)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The indicators on hand-picked states: compression with contact, separation, the
    /// boundary g_n = 0 counted as contact; stick inside the unit disc, slip outside.
    #[test]
    fn indicators_follow_their_definitions() {
        assert!(contact_indicator(-1.0, 0.0, 10.0));
        assert!(!contact_indicator(0.0, -0.1, 10.0));
        assert!(contact_indicator(0.0, 0.0, 10.0));
        assert!(contact_indicator(0.5, 0.1, 10.0));
        let (stick, g) = friction_indicator([0.5, 0.0], [0.01, 0.0], 10.0);
        assert!(stick && (g[0] - 0.6).abs() < 1e-15);
        assert!(!friction_indicator([0.9, 0.0], [0.02, 0.0], 10.0).0);
    }
}
