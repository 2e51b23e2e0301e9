//! The linear solver the rest of fissure uses: the vocabulary of the [`LinearBackend`]
//! seam and [`LinearSolver`], the backend chosen by the case (`[solver] backend`): faer's
//! direct solver, or PETSc's distributed solvers with the cargo feature `petsc`.
//!
//! Entry point: [`LinearSolver`]: analyse once per pattern ([`LinearSolver::analyse_on`]
//! for a chosen backend, [`LinearSolver::analyse_system`] for faer), factorise many times,
//! solve. See [`super::backend`] for the seam, [`super::faer`] for the factorisations and
//! `super::petsc` for the PETSc backend.

pub use super::backend::{
    Backend, BackendInfo, EquationPoints, LinearBackend, LinearError, LinearMethod, LinearStats, OrderingChoice,
    PetscSettings, Precision, SystemStructure,
};
pub use super::faer::{FaerSolver, CONDENSED_COST_RATIO, CONDENSED_MIN_RATIO, MIXED_AUTO_MIN_NNZ};
#[cfg(feature = "petsc")]
use super::petsc::PetscSolver;
use crate::assembly::CscPattern;

/// The linear solver of a system: one of the backends behind the [`LinearBackend`] seam.
// One solver per system: the faer variant stays inline (the default path unchanged).
#[allow(clippy::large_enum_variant)]
pub enum LinearSolver {
    /// faer's direct solver (the default backend).
    Faer(FaerSolver),
    /// PETSc's KSP on a distributed matrix (feature `petsc`).
    #[cfg(feature = "petsc")]
    Petsc(Box<PetscSolver>),
}

/// Calls the same method on whichever backend `$s` holds.
macro_rules! dispatch {
    ($s:expr, $v:ident => $e:expr) => {
        match $s {
            LinearSolver::Faer($v) => $e,
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc($v) => $e,
        }
    };
}

impl LinearSolver {
    /// The faer solver's symbolic phase ([`FaerSolver::analyse`]).
    pub fn analyse(method: LinearMethod, pattern: &CscPattern, n_primal: usize) -> Result<Self, LinearError> {
        FaerSolver::analyse(method, pattern, n_primal).map(LinearSolver::Faer)
    }

    /// The faer solver's symbolic phase for a [`SystemStructure`] ([`FaerSolver::analyse_system`]).
    pub fn analyse_system(system: &SystemStructure<'_>) -> Result<Self, LinearError> {
        FaerSolver::analyse_system(system).map(LinearSolver::Faer)
    }

    /// The symbolic phase on the chosen backend. `components`: the displacement component
    /// of every standard equation (`u8::MAX` for enriched unknowns and multipliers), with
    /// the points of `system`, from which the PETSc backend builds the rigid-body modes
    /// (its multigrid's near null space); faer ignores it. With PETSc the call is
    /// collective (every rank makes it).
    pub fn analyse_on(
        backend: &Backend,
        system: &SystemStructure<'_>,
        components: Option<&[u8]>,
    ) -> Result<Self, LinearError> {
        match backend {
            Backend::Faer => Self::analyse_system(system),
            #[cfg(feature = "petsc")]
            Backend::Petsc(settings) => {
                PetscSolver::analyse(system, settings, components).map(|s| LinearSolver::Petsc(Box::new(s)))
            }
            #[cfg(not(feature = "petsc"))]
            Backend::Petsc(_) => {
                let _ = components;
                Err(LinearError::Petsc(
                    "this fissure was built without the `petsc` feature: cargo build --release --features petsc".into(),
                ))
            }
        }
    }

    /// The PETSc backend's symbolic phase for a layout assembled by elements distributed
    /// among the ranks straight into PETSc ([`PetscSolver::analyse_distributed`]):
    /// `system.pattern` is empty, `rows` gives this rank's rows and their preallocation
    /// counts; the values come through [`Self::factorize_elements`]. Collective.
    #[cfg(feature = "petsc")]
    pub fn analyse_distributed(
        backend: &Backend,
        system: &SystemStructure<'_>,
        components: Option<&[u8]>,
        rows: &crate::assembly::layout::DistributedRows,
    ) -> Result<Self, LinearError> {
        match backend {
            Backend::Petsc(settings) => PetscSolver::analyse_distributed(system, settings, components, rows)
                .map(|s| LinearSolver::Petsc(Box::new(s))),
            Backend::Faer => Err(LinearError::Internal("distributed assembly needs the PETSc backend".into())),
        }
    }

    /// Numeric phase of distributed assembly: `fill` hands every element matrix this rank
    /// assembles to the sink it is given (the element's equations, `NO_EQ` for eliminated
    /// dofs, and its values row-major), which adds it into the backend's matrix; then the
    /// preconditioner's set-up. A refill zeroes the matrix first (its nonzero structure is
    /// kept). Collective with PETSc; faer has no such path.
    pub fn factorize_elements(
        &mut self,
        fill: &mut crate::assembly::layout::ElementFill<'_>,
    ) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = fill;
                Err(LinearError::Internal("assembly straight into the solver's matrix needs the PETSc backend".into()))
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.factorize_elements(fill),
        }
    }

    /// Distributed assembly with contact (PETSc): the bulk K from this rank's elements
    /// (`PetscSolver::set_bulk_elements`). Collective; faer has no such path.
    pub fn set_bulk_elements(
        &mut self,
        fill: &mut crate::assembly::layout::ElementFill<'_>,
    ) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = fill;
                Err(LinearError::Internal("assembly straight into the solver's matrix needs the PETSc backend".into()))
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.set_bulk_elements(fill),
        }
    }

    /// Distributed assembly with contact: keep K's rows of the contact equations
    /// (`PetscSolver::keep_bulk_rows`). Collective.
    pub fn keep_bulk_rows(&mut self, rows: &[usize]) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = rows;
                Err(LinearError::Internal("kept contact rows need the PETSc backend".into()))
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.keep_bulk_rows(rows),
        }
    }

    /// Distributed assembly with contact: K x on this rank's rows, zero elsewhere
    /// (`PetscSolver::bulk_product`). Collective.
    pub fn bulk_product(&self, x: &[f64], out: &mut [f64]) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = (x, out);
                Err(LinearError::Internal("a product with the distributed K needs the PETSc backend".into()))
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.bulk_product(x, out),
        }
    }

    /// Distributed assembly with contact: K's contact rows restored, this rank's contact
    /// elements added, the preconditioner set up (`PetscSolver::refill_contact`).
    /// Collective.
    pub fn refill_contact(&mut self, fill: &mut crate::assembly::layout::ElementFill<'_>) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = fill;
                Err(LinearError::Internal("assembly straight into the solver's matrix needs the PETSc backend".into()))
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.refill_contact(fill),
        }
    }

    /// Distributed assembly with contact: the largest |K_jj| of the primal equations
    /// (0 with faer).
    pub fn bulk_diagonal_max(&self) -> f64 {
        match self {
            LinearSolver::Faer(_) => 0.0,
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.bulk_diagonal_max(),
        }
    }

    /// Sums `v` over the MPI ranks in place (a vector assembled from each rank's own
    /// elements); nothing to do for faer. Collective with PETSc.
    pub fn sum_over_ranks(&self, v: &mut [f64]) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(_) => {
                let _ = v;
                Ok(())
            }
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => super::petsc::sum_over_ranks(v).map_err(LinearError::Petsc),
        }
    }

    /// The backend's name (`faer`, `petsc`).
    pub fn backend_name(&self) -> &'static str {
        match self {
            LinearSolver::Faer(_) => "faer",
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => "petsc",
        }
    }

    /// The backend's figures for `summary.json`.
    pub fn info(&self) -> BackendInfo {
        match self {
            LinearSolver::Faer(_) => BackendInfo { name: "faer", ..Default::default() },
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => {
                let (ksp, pc) = s.types();
                let partition = s.is_distributed().then(super::petsc::partition::recorded).flatten();
                BackendInfo {
                    name: "petsc",
                    ksp: Some(ksp),
                    pc: Some(pc),
                    ranks: Some(super::petsc::size()),
                    iterations: Some(s.last_residual().1),
                    cells_per_rank: partition.as_ref().map(|p| p.cells_per_rank.clone()),
                    enriched_cells_per_rank: partition.as_ref().map(|p| p.enriched_cells_per_rank.clone()),
                    contact_points_per_rank: partition
                        .as_ref()
                        .map(|p| p.contact_points_per_rank.clone())
                        .filter(|c| !c.is_empty()),
                    matrix_entries_per_rank: partition.map(|p| p.matrix_entries_per_rank).filter(|c| !c.is_empty()),
                    peak_rss_kib_per_rank: Some(s.peak_rss_kib()).filter(|p| !p.is_empty()),
                }
            }
        }
    }

    /// Whether the solver keeps its whole-system factor across contact iterations (faer's
    /// plain factor of a contact system, `faer/kept.rs`), whatever `FISSURE_KEPT_FACTOR`
    /// says: the contact loops' path must not depend on that switch.
    pub fn keeps_factor(&self) -> bool {
        match self {
            LinearSolver::Faer(s) => s.keeps_factor(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => false,
        }
    }

    /// Whether the factor is condensed onto the crack unknowns (faer only).
    pub fn is_condensed(&self) -> bool {
        match self {
            LinearSolver::Faer(s) => s.is_condensed(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => false,
        }
    }

    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        dispatch!(self, s => s.factorize(values))
    }

    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        dispatch!(self, s => s.solve_in_place(rhs))
    }

    /// See [`FaerSolver::expect_floating_bulk`] (a no-op for the other backends).
    pub fn expect_floating_bulk(&mut self) {
        match self {
            LinearSolver::Faer(s) => s.expect_floating_bulk(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => {}
        }
    }

    pub fn set_bulk(&mut self, values: &[f64]) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(s) => s.set_bulk(values),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => Ok(()),
        }
    }

    pub fn solve_in_place_deferred(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        match self {
            LinearSolver::Faer(s) => s.solve_in_place_deferred(rhs),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => s.solve_in_place(rhs),
        }
    }

    pub fn apply_deferred(&self, x: &mut [f64]) {
        match self {
            LinearSolver::Faer(s) => s.apply_deferred(x),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => {}
        }
    }

    /// Scales the last deferred correction by `alpha` ([`FaerSolver::scale_last_deferred`]:
    /// a damped Newton step); the other backends do not defer.
    pub fn scale_last_deferred(&self, alpha: f64, correction: &[f64]) {
        match self {
            LinearSolver::Faer(s) => s.scale_last_deferred(alpha, correction),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => {}
        }
    }

    /// Drops the interior corrections deferred since the last full solve (the caller
    /// took back the crack corrections they respond to).
    pub fn discard_deferred(&self) {
        match self {
            LinearSolver::Faer(s) => s.discard_deferred(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => {}
        }
    }

    pub fn varying_unknowns(&self) -> Option<Vec<usize>> {
        match self {
            LinearSolver::Faer(s) => s.varying_unknowns(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => None,
        }
    }

    pub fn method(&self) -> LinearMethod {
        dispatch!(self, s => s.method())
    }

    pub fn n(&self) -> usize {
        dispatch!(self, s => s.n())
    }

    pub fn n_primal(&self) -> usize {
        dispatch!(self, s => s.n_primal())
    }

    pub fn regularised_pivots(&self) -> usize {
        match self {
            LinearSolver::Faer(s) => s.regularised_pivots(),
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(_) => 0,
        }
    }

    /// ‖Ax − b‖/‖b‖ of the last solve and the refinement (faer) or Krylov (PETSc) steps.
    pub fn last_residual(&self) -> (f64, usize) {
        dispatch!(self, s => s.last_residual())
    }

    /// An iterative backend's ‖b‖ and ‖Ax − b‖ of the last solve, on one scale (PETSc:
    /// over the largest ‖b‖ since the analysis for the corrections of the 3D contact
    /// split); None for faer, whose direct solves are refined to round-off.
    pub fn iterative_residuals(&self) -> Option<(f64, f64)> {
        match self {
            LinearSolver::Faer(_) => None,
            #[cfg(feature = "petsc")]
            LinearSolver::Petsc(s) => Some(s.last_rhs_and_residual()),
        }
    }

    pub fn stats(&self) -> LinearStats {
        dispatch!(self, s => s.stats())
    }
}

impl LinearBackend for LinearSolver {
    fn analyse(system: &SystemStructure<'_>) -> Result<Self, LinearError> {
        Self::analyse_system(system)
    }
    fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        LinearSolver::factorize(self, values)
    }
    fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        LinearSolver::solve_in_place(self, rhs)
    }
    fn set_bulk(&mut self, values: &[f64]) -> Result<(), LinearError> {
        LinearSolver::set_bulk(self, values)
    }
    fn solve_in_place_deferred(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        LinearSolver::solve_in_place_deferred(self, rhs)
    }
    fn apply_deferred(&self, x: &mut [f64]) {
        LinearSolver::apply_deferred(self, x)
    }
    fn varying_unknowns(&self) -> Option<Vec<usize>> {
        LinearSolver::varying_unknowns(self)
    }
    fn method(&self) -> LinearMethod {
        LinearSolver::method(self)
    }
    fn n(&self) -> usize {
        LinearSolver::n(self)
    }
    fn n_primal(&self) -> usize {
        LinearSolver::n_primal(self)
    }
    fn regularised_pivots(&self) -> usize {
        LinearSolver::regularised_pivots(self)
    }
    fn last_residual(&self) -> (f64, usize) {
        LinearSolver::last_residual(self)
    }
    fn stats(&self) -> LinearStats {
        LinearSolver::stats(self)
    }
}
