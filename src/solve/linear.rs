//! The linear solver the rest of fissure uses: the vocabulary of the
//! [`LinearBackend`] seam and its one implementation today, faer's direct solver.
//!
//! Entry point: [`LinearSolver`] ([`super::faer::FaerSolver`]): analyse once per pattern,
//! factorise many times, solve. See [`super::backend`] for the seam and [`super::faer`]
//! for the factorisations.

pub use super::backend::{LinearBackend, LinearError, LinearMethod, LinearStats, OrderingChoice, SystemStructure};
pub use super::faer::{FaerSolver as LinearSolver, CONDENSED_MAX_DENSE, CONDENSED_MIN_RATIO};
