//! Solving: the step driver and its pieces, and the linear solvers on faer with symbolic
//! reuse.
//!
//! Entry points: [`statics::solve_load_steps`] (quasi-static load steps through
//! [`driver::solve_steps`]) and [`linear::LinearSolver`] (analyse once, factorise many,
//! solve).
//!
//! Pieces, outermost first: [`driver`] (the step loop) ─ [`time`] (the time scheme) ─
//! [`setup`] (dofs, constraints, kernels, layout, analysis, reactions) ─ [`contact_loops`]
//! (geometry ⊃ friction threshold ⊃ active set) ─ [`newton`] (Newton on frozen statuses)
//! ─ [`linear`] (the linear solver). [`report`] holds what a solve hands back.

mod condensed;
pub mod contact_loops;
pub mod driver;
pub mod linear;
pub mod newton;
pub mod ordering;
pub mod report;
pub mod setup;
mod split;
pub mod statics;
pub mod time;
