//! The time seam: how the step driver walks through a run.
//!
//! Entry point: [`TimeScheme`].
//!
//! The schemes:
//! - quasi-static load steps ([`TimeScheme::QuasiStatic`], driver [`super::driver`]): each
//!   step is an equilibrium at the load factor t of `[steps]`, and the contact loops see a
//!   fixed matrix K and a load vector f(t);
//! - implicit dynamics ([`TimeScheme::Newmark`], [`TimeScheme::Theta`], driver
//!   [`super::dynamics`]): Newmark (β, γ), HHT-α and the θ-method on velocities. Each time
//!   step replaces the stiffness kernel by the effective one
//!   (`physics::inertia::EffectiveKernel`: (1 − α) K + M / (β Δt²), the inertia predictor
//!   and −α K u_n in its load vector), and updates velocities and accelerations after the
//!   step; the contact loops in between stay as they are (they see an effective K and f).
//!   Masses come from the materials' `density`. The driver sees a scheme only through
//!   [`ImplicitScheme::coefficients`] (the generalized Newmark form of [`StepCoefficients`]).

use crate::physics::model::Model;

/// How the steps of a run follow each other.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimeScheme {
    /// Equilibrium at each load factor of the model, no inertia.
    #[default]
    QuasiStatic,
    /// Implicit dynamics: Newmark / HHT-α time steps of a fixed size.
    Newmark(Newmark),
    /// Implicit dynamics: the θ-method on velocities, time steps of a fixed size.
    Theta(Theta),
}

/// The coefficients of one implicit time step in the generalized Newmark form the dynamics
/// driver solves: the predictor ũ = u_n + Δt v_n + Δt² β_n a_n, the equation
/// M (u_{n+1} − ũ)/(β Δt²) + (1 − α) K u_{n+1} + α K u_n = f(t_{n+1} − α Δt) (+ contact),
/// then a_{n+1} = (u_{n+1} − ũ)/(β Δt²) and v_{n+1} = v_n + Δt ((1 − γ) a_n + γ a_{n+1}).
/// Newmark / HHT-α: β_n = ½ − β; the θ-method: β = θ², γ = θ, β_n = θ (1 − θ), α = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCoefficients {
    pub beta: f64,
    pub gamma: f64,
    pub alpha: f64,
    /// The weight of a_n in the predictor.
    pub beta_n: f64,
    /// Time step.
    pub dt: f64,
    /// Number of time steps.
    pub steps: usize,
}

/// An implicit time scheme of the dynamics driver (the seam between schemes).
pub trait ImplicitScheme {
    /// The coefficients of its time steps.
    fn coefficients(&self) -> StepCoefficients;
    /// Why its parameters are not unconditionally stable, if they are not.
    fn instability(&self) -> Option<String>;
    /// The name written in logs and reports.
    fn name(&self) -> &'static str;
}

/// The θ-method on velocities (finite differences in time, the founding paper's
/// first-order scheme, Jean–Moreau): with F = f − K u − contact forces,
/// u_{n+1} = u_n + Δt ((1 − θ) v_n + θ v_{n+1}), M (v_{n+1} − v_n) = Δt (θ F_{n+1} + (1 − θ) F_n).
/// With a_k = M⁻¹ F_k it is the generalized Newmark step β = θ², γ = θ, β_n = θ (1 − θ)
/// ([`StepCoefficients`]): the same effective matrix K + M/(θ Δt)² and the same contact
/// loops. θ = ½ is the trapezoidal rule (average acceleration: second order, conserves the
/// energy of a linear problem); θ > ½ is first order and dissipative (θ = 1: backward Euler,
/// amplification 1/√(1 + (ω Δt)²) per step on a mode of frequency ω). θ ∈ [½, 1] is
/// unconditionally stable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theta {
    pub theta: f64,
    /// Time step.
    pub dt: f64,
    /// Number of time steps.
    pub steps: usize,
}

impl Theta {
    pub fn new(theta: f64, dt: f64, steps: usize) -> Theta {
        Theta { theta, dt, steps }
    }
}

impl ImplicitScheme for Theta {
    fn coefficients(&self) -> StepCoefficients {
        let t = self.theta;
        StepCoefficients { beta: t * t, gamma: t, alpha: 0.0, beta_n: t * (1.0 - t), dt: self.dt, steps: self.steps }
    }

    fn instability(&self) -> Option<String> {
        if !(0.5..=1.0).contains(&self.theta) {
            return Some(format!("theta = {} is outside [1/2, 1] (unstable below 1/2)", self.theta));
        }
        None
    }

    fn name(&self) -> &'static str {
        "theta"
    }
}

impl ImplicitScheme for Newmark {
    fn coefficients(&self) -> StepCoefficients {
        StepCoefficients {
            beta: self.beta,
            gamma: self.gamma,
            alpha: self.alpha,
            beta_n: 0.5 - self.beta,
            dt: self.dt,
            steps: self.steps,
        }
    }

    fn instability(&self) -> Option<String> {
        Newmark::instability(self)
    }

    fn name(&self) -> &'static str {
        if self.alpha > 0.0 {
            "hht"
        } else {
            "newmark"
        }
    }
}

/// The implicit scheme of a case's `[dynamics]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DynamicScheme {
    Newmark(Newmark),
    Theta(Theta),
}

impl DynamicScheme {
    fn inner(&self) -> &dyn ImplicitScheme {
        match self {
            DynamicScheme::Newmark(n) => n,
            DynamicScheme::Theta(t) => t,
        }
    }

    /// The θ of a θ-method, None for the Newmark family.
    pub fn theta(&self) -> Option<f64> {
        match self {
            DynamicScheme::Theta(t) => Some(t.theta),
            DynamicScheme::Newmark(_) => None,
        }
    }
}

impl ImplicitScheme for DynamicScheme {
    fn coefficients(&self) -> StepCoefficients {
        self.inner().coefficients()
    }

    fn instability(&self) -> Option<String> {
        self.inner().instability()
    }

    fn name(&self) -> &'static str {
        self.inner().name()
    }
}

impl From<DynamicScheme> for TimeScheme {
    fn from(s: DynamicScheme) -> TimeScheme {
        match s {
            DynamicScheme::Newmark(n) => TimeScheme::Newmark(n),
            DynamicScheme::Theta(t) => TimeScheme::Theta(t),
        }
    }
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
            TimeScheme::Theta(n) => (1..=n.steps).map(|k| StepTime { index: k, t: k as f64 * n.dt }).collect(),
        }
    }

    /// The name written in logs and reports.
    pub fn name(&self) -> &'static str {
        match self {
            TimeScheme::QuasiStatic => "quasi_static",
            TimeScheme::Newmark(n) => ImplicitScheme::name(n),
            TimeScheme::Theta(t) => t.name(),
        }
    }
}
