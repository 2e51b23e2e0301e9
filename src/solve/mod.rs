//! Solving: the linear-backend seam and its faer implementation, orderings, and the
//! load-step driver.
//!
//! Entry points: [`linear::LinearSolver`] (analyse once, factorise many, solve; the
//! [`backend::LinearBackend`] seam implemented by [`faer::FaerSolver`]), and
//! [`statics::solve_load_steps`] (the load-step loop with room for nested nonlinear loops),
//! watched through [`observe::SolveObserver`].

pub mod backend;
pub mod contact;
pub mod faer;
pub mod linear;
pub mod observe;
pub mod ordering;
pub mod statics;
