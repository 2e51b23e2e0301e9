//! `summary.json`: the machine-readable record of a run. Its keys are public interface
//! (users' scripts read them): add keys, never rename or drop one without a migration
//! note in `docs/summary-json.md`.
//!
//! Entry points: [`Summary`] and [`Summary::write`]. The schema sits with the run (above
//! `post`, whose SIF points it records); `io` only knows file formats.

use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Debug, Clone, Serialize, Default)]
pub struct MeshInfo {
    pub nodes: usize,
    pub elements: usize,
    /// Number of cells per type name (`tri3`, `quad4`, `tet4`, `hex8`).
    pub cell_types: BTreeMap<String, usize>,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct DofInfo {
    /// Every unknown of the model, multipliers included.
    pub total: usize,
    /// Standard displacement dofs (node count × dim).
    pub standard: usize,
    /// Heaviside-enriched dofs (0 without cracks).
    pub heaviside: usize,
    /// Crack-tip dofs (0 without cracks).
    pub tip: usize,
    /// Nodes carrying Heaviside enrichment.
    pub heaviside_nodes: usize,
    /// Nodes carrying tip enrichment.
    pub tip_nodes: usize,
    /// Multipliers of Dirichlet conditions (0 with elimination).
    pub dirichlet_multipliers: usize,
    /// Contact unknowns λ and Λ (0 without contact).
    pub contact_multipliers: usize,
    /// Prescribed (eliminated) dofs.
    pub prescribed: usize,
    /// Per Dirichlet group: the enriched unknowns it holds at 0 on the boundary faces a
    /// crack cuts or whose nodes carry branch functions (counted in `prescribed`; only
    /// groups that hold some; `physics::held_faces`).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub held_enriched: BTreeMap<String, usize>,
    /// Unknowns of the linear system.
    pub equations: usize,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct StepSolverInfo {
    /// Linear solves in this step.
    pub linear_solves: usize,
    /// Numeric factorisations in this step (0 when the previous one was reused).
    pub factorizations: usize,
    /// Relative residual ‖Ax − b‖/‖b‖ of the last linear solve.
    pub residual: f64,
    /// Condensed contact factor only: the `factorizations` above that factorised the
    /// dense crack block, the ones that kept its previous factor instead (its solves by
    /// GMRES preconditioned by that factor), and those GMRES iterations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dense_factorizations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub factor_reuses: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub krylov_iterations: Option<usize>,
    /// Kept whole-system factor only (a contact system too large to condense,
    /// `solve/faer/kept.rs`): the numeric factorisations done in this step (of the
    /// `factorizations` above, which count the new contact tangents), the new tangents
    /// that kept the previous factor instead, and the GMRES iterations of the solves
    /// preconditioned by a kept factor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sparse_factorizations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept_factor_reuses: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept_krylov_iterations: Option<usize>,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct StepInfo {
    /// 1-based step number.
    pub index: usize,
    pub load_factor: f64,
    pub solver: StepSolverInfo,
    /// Largest displacement magnitude over the nodes (cracked bodies: and over the points
    /// of the body grid, the lips included).
    pub max_displacement: f64,
    /// Largest cell von Mises stress.
    pub max_von_mises: f64,
    /// Sum of reaction forces over each Dirichlet group (force units; `[x, y, z]`).
    pub reactions: BTreeMap<String, [f64; 3]>,
    /// Output file of the step (relative to the output directory).
    pub vtu: Option<String>,
    /// Per crack (case order): stress intensity factors along its front.
    pub cracks: Vec<CrackInfo>,
    /// Contact figures (models with contact only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactInfo>,
    /// Per meshed contact pair (case order; models with `[[contact_pairs]]` only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub contact_pairs: Vec<ContactPairInfo>,
    /// Dynamic runs: the largest overlap of the lips the position correction removed
    /// after this time step (length; 0 when none). Absent in quasi-static runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_correction: Option<f64>,
}

/// Contact figures of one meshed contact pair at one step: the keys of [`ContactInfo`]
/// for the pair's own points and unknowns (the iterations, factorisations, solves and
/// residual are the step's: the loops solve every crack and pair at once), and the
/// resultant contact force.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ContactPairInfo {
    pub name: String,
    pub slave: String,
    pub master: String,
    pub method: String,
    pub points: usize,
    pub active: usize,
    pub stick: usize,
    pub slip: usize,
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub iterations: ContactIterations,
    pub factorizations: usize,
    pub linear_solves: usize,
    pub residual: f64,
    /// The pair's λ and Λ unknowns (0 with penalty).
    pub unknowns: usize,
    /// The pair's points whose stick/slip status was accepted against the law.
    pub accepted_disagreements: usize,
    /// The pair's slave points by pairing outcome (last pairing of the step).
    pub pairing: Option<PairingInfo>,
    /// Total normal contact force, −Σ w λ over the slave points (> 0 in compression; force
    /// per unit thickness in 2D).
    pub normal_force: f64,
    /// Magnitude of the total tangential contact force |Σ w μ λ Σ_α Λ_α τ_α|.
    pub tangential_force: f64,
    /// Resultant contact force on the slave body ([x, y, z]): the contact terms of its
    /// equilibrium equations, summed over its nodes (at a packet straddling the edge of the
    /// contact or of the master surface not Σ w λ n over the paired points: the law holds per
    /// packet); the master body takes the opposite.
    pub force_on_slave: [f64; 3],
    /// The pair's points in contact at the end of the modelled slave surface (where the
    /// body's boundary goes on beyond the slave group, or next to points left unpaired):
    /// > 0, a warning (not in summary.json).
    #[serde(skip)]
    pub closed_at_surface_end: usize,
    /// With wear only: the pair's wear so far (cumulative since the start), the keys of
    /// `steps[].contact.wear` over the pair's slave and master faces.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearInfo>,
}

/// Iteration counts of the contact loops in one step.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ContactIterations {
    /// Friction-threshold fixed-point passes.
    pub friction: usize,
    /// Active-set iterations (all passes).
    pub active_set: usize,
    /// Newton iterations (all passes).
    pub newton: usize,
    /// Geometry-loop iterations (re-pairings) of the step; present with large sliding.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geometry: Option<usize>,
}

/// Outcome of the pairing of the contact points with the master lip (large sliding).
#[derive(Debug, Clone, Serialize, Default)]
pub struct PairingInfo {
    /// Points paired with a master point.
    pub paired: usize,
    /// Points that have slid off the master lip (out of contact; a warning).
    pub outside: usize,
    /// Points with no master facet within the narrow band (the lips are far apart, or the
    /// point slid far off the master lip; out of contact; a warning).
    pub far: usize,
    /// Points whose projection failed (out of contact; a warning).
    pub failed: usize,
    /// `outside + far + failed`: points put out of contact by the pairing.
    pub warnings: usize,
    /// Sparsity-pattern rebuilds in the step (the pairing coupled other cells).
    pub pattern_rebuilds: usize,
    /// Of the `paired` points, those outside the contact zone of their meshed pair (held
    /// open, checked at the end of the step; `contact::zone`).
    pub zone_out: usize,
    /// Times the contact zone grew in the step (the step redone each time).
    pub zone_regrowths: usize,
}

/// Contact figures of one step.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ContactInfo {
    /// The contact law's method (`augmented_lagrangian`, `stabilised`), the cracks'
    /// methods joined by `,` when they differ.
    pub method: String,
    /// Contact points (all contact cracks).
    pub points: usize,
    /// Points in contact.
    pub active: usize,
    pub stick: usize,
    pub slip: usize,
    /// Extreme normal tractions (λ ≤ 0 in compression).
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub iterations: ContactIterations,
    /// Numeric factorisations and linear solves of the step.
    pub factorizations: usize,
    pub linear_solves: usize,
    /// Relative size of the last Newton correction.
    pub residual: f64,
    /// Contact unknowns (λ and Λ packets of all cracks).
    pub unknowns: usize,
    /// Points whose stick/slip status was accepted against the law (an accepted status
    /// cycle; every crack and pair): 0 when the law holds at every point.
    pub accepted_disagreements: usize,
    /// Large sliding only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pairing: Option<PairingInfo>,
    /// Per contact crack (case order): its points' statuses and normal tractions (the
    /// iteration counts and the residual above are shared: the loops solve all cracks at once).
    pub cracks: Vec<ContactCrackInfo>,
    /// With wear only: the wear so far (cumulative since the start).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearInfo>,
}

/// The wear of the lips after a step, cumulative since the start (`steps[].contact.wear`).
#[derive(Debug, Clone, Copy, Serialize, Default)]
pub struct WearInfo {
    /// Largest wear depth w⁺ + w⁻ over the contact points (length).
    pub max: f64,
    /// Mean wear depth w⁺ + w⁻ over the lips (length).
    pub mean: f64,
    /// Worn volume, both lips (an area per unit thickness in 2D).
    pub volume: f64,
    /// Dissipated frictional work ∫∫ μ|λ||dslip| over the lips with wear.
    pub frictional_work: f64,
}

/// Contact figures of one crack at one step.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ContactCrackInfo {
    pub name: String,
    pub points: usize,
    pub active: usize,
    pub stick: usize,
    pub slip: usize,
    /// Extreme normal tractions of the crack's points (λ ≤ 0 in compression).
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// The crack's points whose stick/slip status was accepted against the law.
    pub accepted_disagreements: usize,
}

/// Results of one crack at one step.
#[derive(Debug, Clone, Serialize, Default)]
pub struct CrackInfo {
    pub name: String,
    /// Radius of the geometric tip enrichment used (null for interfaces and topological
    /// enrichment).
    pub tip_radius: Option<f64>,
    /// Front points (2D: the tips) with `x`, `KI`, `KII`, `KIII`, `G` and the local
    /// frame `e1` (propagation), `e2`, `e3` (front tangent). Empty for interfaces.
    pub front: Vec<crate::post::sif::SifPoint>,
    /// Crack growth (runs with `[propagation]`): how this entry's crack was reached.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub growth: Option<GrowthInfo>,
}

/// The growth increment that led to a crack (`steps[].cracks[].growth`).
#[derive(Debug, Clone, Serialize, Default)]
pub struct GrowthInfo {
    /// Cumulative load cycles to reach this crack (fatigue; 0 for the initial crack and in
    /// quasi-static growth).
    pub cycles: f64,
    /// The largest advance of this crack's front points in the increment (0 at entry 0).
    pub advance_max: f64,
    /// The kink angle (degrees, from e1 towards e2) of each front point of the previous
    /// entry, in that entry's order (empty at entry 0).
    pub kink_angle_deg: Vec<f64>,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct LinearSolverInfo {
    /// `cholesky`, `ldlt` or `lu`.
    pub method: String,
    pub nnz_matrix: usize,
    pub nnz_factor: Option<usize>,
    /// Colours of the parallel assembly.
    pub assembly_colors: usize,
    /// Contact: the factor was condensed onto the crack unknowns (bulk factorised once).
    pub condensed: bool,
    /// The linear backend: `faer` or `petsc`.
    pub backend: String,
    /// The arithmetic of the factor in use: `double` or `mixed` (`[solver] precision`).
    pub precision: String,
    /// Mixed precision that fell back to the double-precision factor: why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub precision_fallback: Option<String>,
    /// PETSc only: the KSP and PC types in use, the MPI ranks, the Krylov iterations of
    /// the last linear solve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ksp: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pc: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranks: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iterations: Option<usize>,
    /// PETSc with distributed assembly (a model without contact): the cells, and the
    /// enriched cells, each rank assembles (METIS partition, weighted by element cost).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cells_per_rank: Option<Vec<usize>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub enriched_cells_per_rank: Option<Vec<usize>>,
    /// PETSc with distributed assembly: the contact points whose terms each rank
    /// assembles (models with contact), the matrix entries of each rank's rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_points_per_rank: Option<Vec<usize>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub matrix_entries_per_rank: Option<Vec<usize>>,
    /// PETSc: every rank's peak resident memory (`VmHWM`, KiB) at the end of the last
    /// linear solve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_rss_kib_per_rank: Option<Vec<u64>>,
    /// Condensed contact factor only, over the run: factorisations of the dense crack
    /// block, factorisations that kept its previous factor (refactorisations avoided),
    /// solves by GMRES preconditioned by a kept factor, and their iterations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dense_factorizations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub factor_reuses: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub krylov_solves: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub krylov_iterations: Option<usize>,
    /// Kept whole-system factor only, over the run: numeric factorisations, new contact
    /// tangents that kept the previous factor, solves by GMRES preconditioned by a kept
    /// factor, and their iterations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sparse_factorizations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept_factor_reuses: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept_krylov_solves: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept_krylov_iterations: Option<usize>,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct TimingsInfo {
    pub mesh: f64,
    /// Building the sparsity pattern and the colouring (once).
    pub pattern: f64,
    pub assembly: f64,
    /// Symbolic plus numeric factorisation.
    pub factorisation: f64,
    pub factorisation_symbolic: f64,
    pub factorisation_numeric: f64,
    pub solve: f64,
    /// Level sets, cutting and enrichment of the cracks.
    pub cracks: f64,
    /// Stress intensity factors.
    pub sif: f64,
    pub output: f64,
    /// Pairing of the large-sliding contact points (geometry loop), included in `total`.
    pub pairing: f64,
    pub total: f64,
}

/// The whole `summary.json`.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Summary {
    pub version: String,
    /// Path of the case file as given.
    pub case: String,
    /// `ok` or `failed`.
    pub status: String,
    /// The error message when `status` is `failed`.
    pub error: Option<String>,
    pub dim: usize,
    /// `plane_strain`, `plane_stress` or `3d`.
    pub analysis: String,
    pub mesh: MeshInfo,
    pub dofs: DofInfo,
    pub linear_solver: LinearSolverInfo,
    pub steps: Vec<StepInfo>,
    pub timings_s: TimingsInfo,
    /// The `.pvd` collection (relative to the output directory).
    pub pvd: Option<String>,
    /// Warnings of the run (e.g. contact points that left the master lip), one line each.
    pub warnings: Vec<String>,
    /// The time scheme and energy figures of a dynamic run (`[dynamics]` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsInfo>,
}

/// The time scheme and energies of a dynamic run.
#[derive(Debug, Clone, Serialize, Default)]
pub struct DynamicsInfo {
    /// `newmark`, `hht` or `theta`.
    pub scheme: String,
    pub dt: f64,
    /// Time steps of the run (step 0 is t = 0).
    pub steps: usize,
    /// β, γ, α of the step (with `theta`: the equivalent generalized Newmark β = θ², γ = θ, α = 0).
    pub beta: f64,
    pub gamma: f64,
    pub alpha: f64,
    /// θ of the θ-method (absent with `newmark` and `hht`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    pub output_every: usize,
    /// The per-step energy table (relative to the output directory).
    pub energy_history: String,
    /// Energies at the last step written.
    pub final_energies: EnergyInfo,
    /// max over the steps of |total − total at t = 0| / max(kinetic + strain): 0 for a
    /// conserving scheme up to round-off.
    pub energy_balance_error: f64,
    /// The position corrections of the velocity contact formulation over the run.
    pub position_correction: PositionCorrectionInfo,
    /// `[dynamics] mass`: `consistent` or `redistributed`.
    pub mass: String,
}

/// The position corrections of a dynamic run (`solve::position_correction`).
#[derive(Debug, Clone, Copy, Serialize, Default)]
pub struct PositionCorrectionInfo {
    /// `[dynamics] position_correction`.
    pub enabled: bool,
    /// Time steps after which the lips' overlap was removed.
    pub steps: usize,
    /// The largest overlap removed (length; 0 when none).
    pub largest: f64,
}

/// The energies at one time (the columns of `energy_history.csv`).
#[derive(Debug, Clone, Serialize, Default)]
pub struct EnergyInfo {
    pub time: f64,
    pub kinetic: f64,
    pub strain: f64,
    pub external_work: f64,
    pub frictional_dissipation: f64,
    pub contact_work: f64,
    pub total: f64,
}

impl Summary {
    /// Writes the summary as pretty JSON.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(path, text + "\n")
    }
}
