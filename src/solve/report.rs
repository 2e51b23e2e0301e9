//! What a solve hands back: the options it takes, the figures of each step and of the
//! whole run, the wall-clock times per phase, and why a solve fails.
//!
//! Entry points: [`SolveOptions`], [`SolveReport`], [`StepReport`], [`ContactReport`],
//! [`SolveError`].

use crate::assembly::DofMap;
use crate::contact::law::PointState;
use crate::contact::pairing::{Pairing, PairingCounts};
use crate::solve::backend::CondensedCounts;
use crate::solve::linear::{Backend, BackendInfo, LinearError, LinearMethod, OrderingChoice, Precision};
use std::fmt;

/// Options of the solve.
#[derive(Debug, Clone)]
pub struct SolveOptions {
    pub linear: LinearMethod,
    /// Relative residual above which a step is reported as failed.
    pub residual_tolerance: f64,
    /// Contact systems (LDLᵀ): factorise the bulk once and condense each contact
    /// iteration onto the crack unknowns ([`crate::solve::faer::FaerSolver::analyse_condensed`]).
    pub condense: bool,
    /// The fill-reducing ordering of the direct solver.
    pub ordering: OrderingChoice,
    /// The arithmetic of the direct solver's factor (`[solver] precision`).
    pub precision: Precision,
    /// The linear backend (`[solver] backend`).
    pub backend: Backend,
    /// The node order kept across the symbolic analyses of one run on one mesh (the
    /// growth loop sets it: [`crate::solve::ordering::reuse`]); `None`: each analysis
    /// computes its ordering.
    pub reuse_ordering: Option<std::sync::Arc<crate::solve::ordering::reuse::ReusedOrdering>>,
    /// Dynamics, velocity contact formulation: project the displacements back onto the
    /// lips' non-penetration after each time step where they overlap
    /// ([`super::position_correction`]; `[dynamics] position_correction`, default on).
    pub position_correction: bool,
    /// Dynamics: the consistent or the redistributed mass (`[dynamics] mass`,
    /// [`crate::physics::inertia::MassMatrix`]).
    pub mass: crate::physics::inertia::MassMatrix,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            linear: LinearMethod::Cholesky,
            residual_tolerance: 1e-8,
            condense: true,
            ordering: OrderingChoice::Auto,
            precision: Precision::Auto,
            backend: Backend::Faer,
            reuse_ordering: None,
            position_correction: true,
            mass: crate::physics::inertia::MassMatrix::Consistent,
        }
    }
}

/// Wall-clock seconds per phase, summed over the run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timings {
    pub pattern: f64,
    pub assembly: f64,
    pub symbolic: f64,
    pub numeric: f64,
    pub solve: f64,
    /// Pairing of the large-sliding contact points (BVH build and projections).
    pub pairing: f64,
    /// The time steps of a dynamic run by phase (the contact loops' `columns`, `checksum`
    /// and `bulk` also in a static run).
    pub step_phases: StepPhases,
}

/// Wall-clock seconds per phase of the time steps of a dynamic run
/// ([`super::dynamics::solve_time_steps`]), summed over the steps (t = 0 excluded). The
/// linear system's own work (`system`) is also in [`Timings`]' `assembly`, `numeric` and
/// `solve` (which, summed over the run, include the set-up's element matrices, mass
/// factorisation and first factorisation).
#[derive(Debug, Clone, Copy, Default)]
pub struct StepPhases {
    /// The predictor, the prescribed values, the effective kernels, the velocity law's
    /// gap shifts.
    pub predict: f64,
    /// c_m M ũ − c_p K u_n as mat-vecs (`physics::inertia::DofMatrices`; otherwise the
    /// effective kernel's element products, in the system's assembly).
    pub products: f64,
    /// The step's system: `linear_step` or the contact loops (`solve_contact`).
    pub system: f64,
    /// Of `system`, with contact: saving K's contact columns (`ContactColumns::save`).
    pub columns: f64,
    /// Of `system`, with contact: the carried factor's identification of K (a generation
    /// counter, O(1); before, a checksum of K's values, O(nnz)).
    pub checksum: f64,
    /// Of `system`, with contact: `set_bulk` (K's check, and its factorisation when it changed).
    pub bulk: f64,
    /// Of `system`, with contact: the Newton iterations after the first of each contact
    /// step (their residual, contact assembly and deferred solve).
    pub confirm: f64,
    /// Of `system`, with contact: the deferred interior correction applied at the end of
    /// the step (`LinearSolver::apply_deferred`, a backward substitution in the bulk).
    pub deferred: f64,
    /// The Newmark update of accelerations and velocities.
    pub update: f64,
    /// The constrained forces and the reactions.
    pub reactions: f64,
    /// The external loads at the step's end and their work.
    pub external: f64,
    /// The contact forces, their work and the frictional dissipation.
    pub contact_work: f64,
    /// The position correction of the velocity contact formulation (steps where the lips
    /// overlap only: [`super::position_correction`]).
    pub position_correction: f64,
    /// The strain and kinetic energies.
    pub energies: f64,
    /// The caller's `on_step` (output).
    pub output: f64,
}

/// The figures of one load step.
#[derive(Debug, Clone)]
pub struct StepReport {
    pub index: usize,
    pub load_factor: f64,
    /// ‖A x − b‖ / ‖b‖ of the linear system (0 when b = 0).
    pub residual: f64,
    pub linear_solves: usize,
    pub factorizations: usize,
    /// Sum of the reaction forces over the nodes of each Dirichlet group (by group).
    pub reactions: Vec<[f64; 3]>,
    /// Contact figures of the step (models with contact).
    pub contact: Option<ContactReport>,
}

/// A solved step handed to the caller: the full dof vector and its report.
pub struct StepSolution<'a> {
    pub dofs: &'a DofMap,
    /// Value of every dof (prescribed ones included).
    pub u: &'a [f64],
    pub report: &'a StepReport,
    /// Per contact point (empty without contact).
    pub contact_state: &'a [PointState],
    /// The pairing used by the step (large sliding only).
    pub pairing: Option<&'a Pairing>,
    /// Velocities, accelerations and energies (dynamics only).
    pub motion: Option<Motion<'a>>,
}

/// The motion of a dynamic step: velocity and acceleration of every dof (zero on the
/// multipliers) and the energies at the end of the step.
pub struct Motion<'a> {
    pub time: f64,
    pub velocity: &'a [f64],
    pub acceleration: &'a [f64],
    pub energies: Energies,
    /// The largest overlap of the lips the position correction removed after this step's
    /// velocity-law solve (length; 0 when none: [`super::position_correction`]).
    pub position_correction: f64,
}

/// The energies of a dynamic run at one time (`energy_history.csv`, docs/case-format.md).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    /// ½ vᵀ M v.
    pub kinetic: f64,
    /// ½ uᵀ K u.
    pub strain: f64,
    /// Work of the loads and of the reactions of prescribed motions since t = 0
    /// (trapezoidal rule over each step).
    pub external_work: f64,
    /// Work dissipated by friction since t = 0: per step, the work of the friction
    /// tractions at the end of the step on the slip increment of the step (≥ 0).
    pub frictional_dissipation: f64,
    /// Work of the contact forces since t = 0 (trapezoidal rule over each step) less the
    /// frictional dissipation: the normal contact work.
    pub contact_work: f64,
}

impl Energies {
    /// kinetic + strain − external work + dissipation + contact work: constant for a
    /// conserving scheme.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain - self.external_work + self.frictional_dissipation + self.contact_work
    }
}

/// The whole run.
#[derive(Debug, Clone)]
pub struct SolveReport {
    pub dofs: DofMap,
    /// The solver actually used (Cholesky becomes LDLᵀ with Dirichlet multipliers).
    pub linear_method: LinearMethod,
    pub n_eq: usize,
    pub n_prescribed: usize,
    pub nnz_matrix: usize,
    pub nnz_factor: Option<usize>,
    /// Flops of one numeric factorisation ([`crate::solve::backend::LinearStats::flops_factor`]).
    pub flops_factor: Option<f64>,
    /// The factor in use at the end is in single precision (`[solver] precision`).
    pub mixed_precision: bool,
    /// Mixed precision fell back to the double-precision factor: why.
    pub precision_fallback: Option<&'static str>,
    /// Refinement steps (conjugate-gradient iterations in mixed precision) of the last
    /// solve.
    pub refinements: usize,
    /// The condensed factor's dense crack block over the run (the solver's last analysis):
    /// factorisations, reuses and Krylov solves (`None`: not condensed).
    pub condensed_counts: Option<CondensedCounts>,
    /// The whole-system factor kept across contact iterations over the run (the solver's
    /// last analysis; `solve/faer/kept.rs`): numeric factorisations, new matrices that
    /// kept it, and its Krylov solves (`None`: not a kept factor).
    pub kept_counts: Option<CondensedCounts>,
    /// The contact factor was condensed onto the crack unknowns
    /// ([`crate::solve::faer::FaerSolver::analyse_condensed`]).
    pub condensed: bool,
    /// The linear backend and its figures.
    pub backend: BackendInfo,
    pub n_colors: usize,
    pub heaviside_nodes: usize,
    pub tip_nodes: usize,
    /// Per Dirichlet group: the enriched unknowns it holds at 0 on the faces a crack cuts
    /// (`physics::held_faces`).
    pub held_enriched: Vec<usize>,
    pub steps: Vec<StepReport>,
    pub timings: Timings,
}

/// Why a solve failed.
#[derive(Debug)]
pub enum SolveError {
    /// Rigid-body motions not prevented by the Dirichlet conditions.
    UnderConstrained(String),
    /// The linear solver failed (with advice).
    Linear { step: usize, error: LinearError, advice: &'static str },
    /// A prescribed value or load evaluated to NaN or infinity.
    NonFinite { what: String },
    /// The residual of a step is above the tolerance.
    Residual { step: usize, residual: f64, tolerance: f64 },
    /// A contact loop reached its cap without converging. `residual` is the loop's own
    /// measure: the last relative Newton correction (Newton, semi-smooth), the number of
    /// contact or stick/slip statuses that changed in the last iteration (active set), the
    /// last relative change of the thresholds (friction threshold).
    Contact { step: usize, loop_name: &'static str, iterations: usize, residual: f64 },
    /// The per-step callback (output) failed.
    Callback(String),
    /// A dynamic run cannot start (a material without density, a singular mass).
    Dynamics(String),
    /// A time step did not converge: the time and why, with advice.
    TimeStep { time: f64, error: Box<SolveError> },
    /// The wear of a crack's lip (or a contact pair's face) went deeper than its cells at
    /// this step (the worn lip would leave its element); `crack` names it ("crack 'name'"
    /// or "contact pair 'name'").
    Wear { step: usize, crack: String, depth: f64, cell_size: f64 },
    /// The solution of a step failed its residual check and its largest entry is below
    /// the smallest normal double: the displacements underflow (loads some 1e-300 of the
    /// stiffness in the model's units), so no linear solve can be accurate.
    Underflow { step: usize, largest: f64, residual: f64 },
    /// A meshed pair's contact zone (`contact::zone`) still left out points that the law
    /// would close after this many regrowths of the step; `pairs` says which and by how much.
    ContactZone { step: usize, regrowths: usize, pairs: String },
    /// A failed solve with what the run knows of its likely cause (a contact loop's cap
    /// reached with a `rho_n` far above E/h: `run::rho_n_advice`).
    Advised { error: Box<SolveError>, advice: String },
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveError::UnderConstrained(m) => write!(f, "{m}"),
            SolveError::Linear { step, error, advice } => write!(f, "step {step}: linear solve failed: {error}{advice}"),
            SolveError::NonFinite { what } => write!(f, "{what} is not a finite number"),
            SolveError::Residual { step, residual, tolerance } => write!(
                f,
                "step {step}: the linear system was not solved accurately (relative residual {residual:.2e} > {tolerance:.0e})"
            ),
            SolveError::Contact { step, loop_name, iterations, residual } => {
                write!(f, "step {step}: the {loop_name} loop did not converge in {iterations} iterations (")?;
                match *loop_name {
                    "active set" => {
                        write!(f, "{residual} contact or stick/slip statuses still changing in the last iteration")?
                    }
                    "friction threshold" => write!(f, "last relative change of the friction thresholds {residual:.2e}")?,
                    "stick/slip" => write!(
                        f,
                        "{residual} points in contact accepted against the Coulomb law, more than a tenth of them, after the step was redone with damped Newton steps"
                    )?,
                    _ => write!(f, "last relative correction {residual:.2e}")?,
                }
                write!(f, "); raise its cap in [contact_solver], or use smaller load steps")
            }
            SolveError::Callback(m) => write!(f, "{m}"),
            SolveError::Dynamics(m) => write!(f, "{m}"),
            SolveError::Underflow { step, largest, residual } => write!(
                f,
                "step {step}: the displacements underflow double precision: the largest is {largest:.2e}, below the smallest normal number {:.1e}, so the linear solve cannot be accurate (relative residual {residual:.2e}); the loads are too small for the stiffness in these units: write the model in other units (a smaller unit of stress or a larger unit of length)",
                f64::MIN_POSITIVE
            ),
            SolveError::Wear { step, crack, depth, cell_size } => write!(
                f,
                "step {step}: {crack}: the wear depth {depth:.4e} exceeds the cell size {cell_size:.4e} (the worn lip would leave its element); the results up to step {} are written: lower the wear coefficient or stop the run earlier",
                step.saturating_sub(1)
            ),
            SolveError::TimeStep { time, error } => {
                write!(f, "time {time:.6e}: {error}; try halving dt ([dynamics] dt)")
            }
            SolveError::Advised { error, advice } => write!(f, "{error}. {advice}"),
            SolveError::ContactZone { step, regrowths, pairs } => write!(
                f,
                "step {step}: the contact zone did not settle in {regrowths} regrowths ({pairs}); set zone = \"band\" in the [[contact_pairs]] entry, or a larger zone_gap"
            ),
        }
    }
}

impl std::error::Error for SolveError {}

/// The contact figures of one step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactReport {
    pub points: usize,
    pub active: usize,
    pub stick: usize,
    pub slip: usize,
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// Friction fixed-point passes.
    pub friction: usize,
    /// Active-set iterations (summed over the friction passes).
    pub active_set: usize,
    /// Newton iterations (summed).
    pub newton: usize,
    pub factorizations: usize,
    pub linear_solves: usize,
    /// Relative size of the last Newton correction.
    pub residual: f64,
    /// Geometry-loop iterations (pairings) of the step; 0 without large sliding.
    pub geometry: usize,
    /// Times the sparsity pattern was rebuilt in the step because the pairing changed.
    pub pattern_rebuilds: usize,
    /// Active-set 2-cycles closed (the flipping points kept in contact).
    pub cycles_closed: usize,
    /// Per contact crack or pair (`ContactPoints::cracks` order): the points whose
    /// stick/slip status, accepted with the step, disagrees with the law (an accepted
    /// status cycle, `docs/contact-algorithms.md`); empty or zeros when the law agrees
    /// everywhere.
    pub accepted_disagreements: Vec<usize>,
    /// Times a meshed pair's contact zone grew in the step (`contact::zone`): the step
    /// was redone from its start each time.
    pub zone_regrowths: usize,
    /// Pairing outcomes of the last pairing of the step (large sliding).
    pub pairing: Option<PairingCounts>,
    /// The condensed factor's solve failed its residual check in this step (the relative
    /// residual it reached): the step was redone from its start with the plain LDLᵀ of the
    /// whole system, which the run keeps from then on.
    pub condensed_fallback: Option<f64>,
    /// The friction-threshold fixed point stalled and was accepted at this relative change
    /// of the thresholds (above `tol_friction`, at most `STALL_ACCEPT` × it): one or two
    /// points at the Coulomb limit alternate between stick and slip from pass to pass.
    pub friction_stalled: Option<f64>,
    /// The plain contact loops failed (a cap) or accepted more than
    /// `DAMPED_REDO_ABOVE` of the points in contact against the friction law, and the
    /// step was redone with damped Newton steps (`solve::contact_loops`, `Loops::redo_damped`).
    pub damped_redo: bool,
    /// The condensed factor's dense crack block in this step: its factorisations, the
    /// factorisations above that kept the previous factor instead (solved by GMRES
    /// preconditioned by it) and those Krylov solves (`None`: not condensed).
    pub condensed: Option<CondensedCounts>,
    /// The kept whole-system factor in this step (`solve/faer/kept.rs`): its numeric
    /// factorisations, the new matrices that kept it instead, and its Krylov solves
    /// (`None`: not a kept factor).
    pub kept: Option<CondensedCounts>,
}
