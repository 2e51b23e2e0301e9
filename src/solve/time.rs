//! The time seam: how the step driver walks through a run.
//!
//! Entry point: [`TimeScheme`].
//!
//! Today one scheme: quasi-static load steps, where each step is an equilibrium at the
//! load factor t of `[steps]` and the contact loops see a fixed matrix K and a load
//! vector f(t). An implicit dynamic scheme (Newmark, HHT, θ) is a new variant beside it:
//! it adds the inertia (and damping) kernel to the fixed kernels and its predictor to the
//! load vector of a step, and updates velocities and accelerations after the step; the
//! contact loops in between stay as they are (they see an effective K and f). Its
//! masses come from the materials' `density` (`case::MaterialDef::density`).

use crate::physics::model::Model;

/// How the steps of a run follow each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimeScheme {
    /// Equilibrium at each load factor of the model, no inertia.
    #[default]
    QuasiStatic,
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
        }
    }

    /// The name written in logs and reports.
    pub fn name(&self) -> &'static str {
        match self {
            TimeScheme::QuasiStatic => "quasi_static",
        }
    }
}
