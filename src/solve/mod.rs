//! Solving: linear solvers on faer with symbolic reuse, and the load-step driver.
//!
//! Entry points: [`linear::LinearSolver`] (analyse once, factorise many, solve), and
//! [`statics::solve_load_steps`] (the load-step loop with room for nested nonlinear loops).

mod condensed;
pub mod contact;
pub mod linear;
pub mod ordering;
mod split;
pub mod statics;
