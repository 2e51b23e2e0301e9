//! The time seam: how the step driver walks through a run.
//!
//! Entry point: [`TimeScheme`].
//!
//! Two schemes:
//! - quasi-static load steps ([`TimeScheme::QuasiStatic`], driver [`super::driver`]): each
//!   step is an equilibrium at the load factor t of `[steps]`, and the contact loops see a
//!   fixed matrix K and a load vector f(t);
//! - implicit dynamics ([`TimeScheme::Newmark`], driver [`super::dynamics`]): Newmark
//!   (β, γ) and HHT-α. Each time step replaces the stiffness kernel by the effective one
//!   (`physics::inertia::EffectiveKernel`: (1 − α) K + M / (β Δt²), the inertia predictor
//!   and −α K u_n in its load vector), and updates velocities and accelerations after the
//!   step; the contact loops in between stay as they are (they see an effective K and f).
//!   Masses come from the materials' `density`.

use crate::physics::model::Model;

/// How the steps of a run follow each other.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimeScheme {
    /// Equilibrium at each load factor of the model, no inertia.
    #[default]
    QuasiStatic,
    /// Implicit dynamics: Newmark / HHT-α time steps of a fixed size.
    Newmark(Newmark),
}

/// The Newmark family with HHT-α: M a_{n+1} + (1 − α) K u_{n+1} + α K u_n = f(t_{n+1} − α Δt),
/// u_{n+1} = u_n + Δt v_n + Δt² ((½ − β) a_n + β a_{n+1}), v_{n+1} = v_n + Δt ((1 − γ) a_n + γ a_{n+1}).
/// α = 0 is Newmark (β = ¼, γ = ½: average acceleration, unconditionally stable, no
/// numerical damping, energy conserving for linear problems); HHT-α takes α ∈ (0, ⅓] with
/// γ = ½ + α and β = (1 + α)² / 4 (second order, damps the high modes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newmark {
    pub beta: f64,
    pub gamma: f64,
    pub alpha: f64,
    /// Time step.
    pub dt: f64,
    /// Number of time steps.
    pub steps: usize,
}

impl Newmark {
    /// Average acceleration (β = ¼, γ = ½, α = 0).
    pub fn average_acceleration(dt: f64, steps: usize) -> Newmark {
        Newmark { beta: 0.25, gamma: 0.5, alpha: 0.0, dt, steps }
    }

    /// HHT-α with its second-order β and γ.
    pub fn hht(alpha: f64, dt: f64, steps: usize) -> Newmark {
        Newmark { beta: 0.25 * (1.0 + alpha) * (1.0 + alpha), gamma: 0.5 + alpha, alpha, dt, steps }
    }

    /// Why the parameters are not unconditionally stable, if they are not: γ ≥ ½,
    /// β ≥ γ / 2, 0 ≤ α ≤ ⅓.
    pub fn instability(&self) -> Option<String> {
        if !(self.gamma >= 0.5) {
            return Some(format!("gamma = {} < 1/2 is unstable (use gamma ≥ 1/2)", self.gamma));
        }
        if !(self.beta >= 0.5 * self.gamma) {
            return Some(format!(
                "beta = {} < gamma/2 = {} is only conditionally stable (use beta ≥ gamma/2)",
                self.beta,
                0.5 * self.gamma
            ));
        }
        if !(0.0..=1.0 / 3.0).contains(&self.alpha) {
            return Some(format!("alpha = {} is outside [0, 1/3]", self.alpha));
        }
        None
    }
}

/// One step of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepTime {
    /// Step number, from 1.
    pub index: usize,
    /// The load factor (quasi-static) or time at the end of the step.
    pub t: f64,
}

impl TimeScheme {
    /// The steps of a run of `model`.
    pub fn steps(&self, model: &Model<'_>) -> Vec<StepTime> {
        match self {
            TimeScheme::QuasiStatic => {
                model.load_factors.iter().enumerate().map(|(i, &t)| StepTime { index: i + 1, t }).collect()
            }
            TimeScheme::Newmark(n) => (1..=n.steps).map(|k| StepTime { index: k, t: k as f64 * n.dt }).collect(),
        }
    }

    /// The name written in logs and reports.
    pub fn name(&self) -> &'static str {
        match self {
            TimeScheme::QuasiStatic => "quasi_static",
            TimeScheme::Newmark(n) if n.alpha > 0.0 => "hht",
            TimeScheme::Newmark(_) => "newmark",
        }
    }
}
