//! Solving: the step driver and its pieces, the linear-backend seam and its faer
//! implementation, and the orderings.
//!
//! Entry points: [`statics::solve_load_steps`] (quasi-static load steps through
//! [`driver::solve_steps`]), [`dynamics::solve_time_steps`] (implicit dynamics) and [`linear::LinearSolver`] (analyse once, factorise many,
//! solve; the [`backend::LinearBackend`] seam implemented by [`faer::FaerSolver`]).
//!
//! Pieces, outermost first: [`driver`] (the step loop; with wear its steps start the
//! friction thresholds from [`threshold_start`]) and [`dynamics`] (the time-step
//! loop, with [`position_correction`] after a step of the velocity contact law) ─ [`time`]
//! (the time scheme) ─
//! [`setup`] (dofs, constraints, kernels, layout, analysis, reactions) ─ [`contact_loops`]
//! (geometry ⊃ friction threshold ⊃ active set) ─ [`newton`] (Newton on frozen statuses)
//! ─ [`linear`] (the linear solver). [`report`] holds what a solve hands back; a caller
//! watches a solve through [`observe::SolveObserver`].

pub mod backend;
pub mod contact_loops;
pub mod driver;
pub mod dynamics;
pub mod faer;
pub mod linear;
pub mod newton;
pub mod observe;
pub mod ordering;
#[cfg(feature = "petsc")]
pub mod petsc;
pub mod position_correction;
pub mod report;
pub mod setup;
pub mod statics;
pub mod threshold_start;
pub mod time;
