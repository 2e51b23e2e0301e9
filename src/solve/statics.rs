//! The quasi-static solve: every load step of a model through the step driver with
//! [`TimeScheme::QuasiStatic`], and the types a caller of a solve uses.
//!
//! Entry points: [`solve_load_steps`], [`solve_load_steps_carrying`] (crack growth).

pub use super::report::{SolveError, SolveOptions, SolveReport, StepReport, StepSolution, Timings};
use super::time::TimeScheme;
use crate::contact::carry::CarriedStatuses;
use crate::contact::ContactSetup;
use crate::physics::model::Model;
use crate::solve::observe::{Silent, SolveObserver};

/// Solves every load step of `model`, calling `on_step` after each (for output).
pub fn solve_load_steps(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    solve_load_steps_observed(model, contact, options, &Silent, on_step)
}

/// [`solve_load_steps`], telling `observer` the phases and the contact Newton iterations.
pub fn solve_load_steps_observed(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    super::driver::solve_steps(model, contact, options, TimeScheme::QuasiStatic, observer, on_step)
}

/// [`solve_load_steps_observed`], the contact points of the first step starting from the
/// `carried` statuses where they have one (crack growth: [`CarriedStatuses`]).
pub fn solve_load_steps_carrying(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    carried: Option<&CarriedStatuses>,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    super::driver::solve_steps_carrying(model, contact, options, TimeScheme::QuasiStatic, carried, observer, on_step)
}
