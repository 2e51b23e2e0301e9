//! Running a case from start to end, the whole algorithm in one readable function:
//!
//! ```text
//! read case ─► build mesh (+ formula sets) ─► build model (cracks: level sets, cut,
//! enrichment) ─► solve load steps
//!            └─► per step: fields, SIFs ─► .vtu (body, crack lips) ─► .pvd ─► step table
//! ─► summary.json ─► sif.csv, contact.csv ─► PNG plots ─► <stem>_view.py (3D cracks)
//! ```
//!
//! The terminal (progress line, step tables, `--verbose` Newton lines) is
//! [`terminal::Terminal`], which watches the solve as its observer.
//!
//! Entry points: [`run_case`] (solve and write), [`run_case_results`] (the same, also
//! keeping each step's fields in memory, for the Python bindings) and [`check_case`]
//! (validate only).
//! On failure, the files of the last converged step stay on disk and `summary.json`
//! says `"status": "failed"` with the error. The `summary.json` schema is [`summary`].

pub mod growth;
pub mod guard;
pub mod paraview_view;
pub mod plots;
pub mod summary;
pub mod tables;
pub mod terminal;

use crate::case::overrides::Override;
use crate::case::{resolve, Case, CaseError};
use crate::contact::law::PointState;
use crate::contact::law::Status;
use crate::contact::ContactSetup;
use crate::enrich::TipEnrichment;
use crate::io::vtu::{self, DataArray, PvdEntry, UnstructuredGrid, VtkCell};
use crate::mesh::Mesh;
use crate::physics::model::Model;
use crate::post::{self, sif, xfem_output};
use crate::solve::dynamics::{self, InitialState};
use crate::solve::linear::{LinearMethod, Precision};
use crate::solve::observe::{NewtonIteration, Phase, SolveObserver};
use crate::solve::statics::{self, SolveError, SolveOptions};
use crate::solve::time::ImplicitScheme;
use paraview_view::ViewSpec;
use plots::{ContactProfile, PlotData};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;
use summary::{ContactCrackInfo, ContactPairInfo};
use summary::{ContactInfo, ContactIterations, CrackInfo, PairingInfo, WearInfo};
use summary::{DofInfo, LinearSolverInfo, MeshInfo, StepInfo, StepSolverInfo, Summary, TimingsInfo};
use summary::{DynamicsInfo, EnergyInfo, PositionCorrectionInfo};
use terminal::{step_table, Terminal};

/// Why a run failed; [`RunError::exit_code`] maps it to the process exit status.
#[derive(Debug)]
pub enum RunError {
    /// The case file (or what it refers to) is wrong: exit code 2.
    Case(CaseError),
    /// The solve failed: exit code 1.
    Solve(SolveError),
    /// Files could not be written: exit code 1.
    Output(String),
}

impl RunError {
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Case(_) => 2,
            _ => 1,
        }
    }
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Case(e) => write!(f, "{e}"),
            // Not a failed solve: the model itself is wrong, and the message says how.
            RunError::Solve(e @ SolveError::UnderConstrained(_)) => write!(f, "{e}"),
            RunError::Solve(e) => write!(f, "solve failed: {e}"),
            RunError::Output(e) => write!(f, "output failed: {e}"),
        }
    }
}

impl std::error::Error for RunError {}

/// What a check found: the case, the mesh and the model are valid.
#[derive(Debug, Clone)]
pub struct CheckReport {
    pub dim: usize,
    pub nodes: usize,
    pub cells: usize,
    pub steps: usize,
    /// What the model is built from but may not give what the user meant (the same
    /// texts as `summary.json` `warnings`).
    pub warnings: Vec<String>,
    /// Per Dirichlet group holding some: the enriched unknowns it holds at 0 on the
    /// boundary faces a crack cuts (`summary.json` `dofs.held_enriched`).
    pub held_enriched: BTreeMap<String, usize>,
}

/// Reads a case, builds its mesh and model, and checks the constraints, without solving.
pub fn check_case(case_path: &Path) -> Result<CheckReport, RunError> {
    check_case_with(case_path, &[])
}

/// [`check_case`] with command-line overrides applied to the case first.
pub fn check_case_with(case_path: &Path, overrides: &[Override]) -> Result<CheckReport, RunError> {
    let case = Case::from_file_with(case_path, overrides).map_err(RunError::Case)?;
    let at = |e| RunError::Case(case.attribute(e));
    let mesh = resolve::build_mesh(&case).map_err(at)?;
    let model = resolve::build_model(&case, &mesh).map_err(at)?;
    resolve::check_memory(&case, &model).map_err(at)?;
    let contact = resolve::build_contact(&case, &model).map_err(at)?;
    if let Some(p) = &case.propagation {
        growth::check_propagation(&case, p, &mesh).map_err(at)?;
    }
    let pairs: Vec<(usize, usize)> = model.dirichlet.iter().map(|c| (c.node, c.component)).collect();
    // In dynamics the mass holds a free body.
    if case.dynamics.is_none() {
        let tied = contact.as_ref().map_or_else(Vec::new, |c| c.points.rigid_rows(&mesh));
        let cracked = crate::physics::constraints::CrackedBody {
            cracks: &model.cracks,
            enrichment: &model.enrichment,
            separating: crate::solve::setup::separating_cracks(model.cracks.len(), contact.as_ref()),
        };
        crate::physics::constraints::check_model_rigid_modes(&mesh, &cracked, &pairs, &model.relations, &tied)
            .map_err(|m| RunError::Solve(SolveError::UnderConstrained(m)))?;
    }
    let mut held_enriched = BTreeMap::new();
    for h in crate::physics::held_faces::held_enriched(&mesh, &model.cracks, &model.enrichment, &model.dirichlet) {
        let g = model.dirichlet[h.condition as usize].group as usize;
        *held_enriched.entry(model.dirichlet_groups[g].clone()).or_insert(0) += 1;
    }
    Ok(CheckReport {
        held_enriched,
        dim: mesh.dim,
        nodes: mesh.n_nodes(),
        cells: mesh.n_cells(),
        steps: case.dynamics.as_ref().map_or(model.load_factors.len(), |d| d.scheme.coefficients().steps),
        warnings: model_warnings(&case, &model)
            .into_iter()
            .chain(contact_notes(&case, &mesh, contact.as_ref()))
            .collect(),
    })
}

/// Notes on the contact set-up: the crosspoint multipliers removed, per pair or crack.
fn contact_notes(case: &Case, mesh: &Mesh, contact: Option<&crate::contact::ContactSetup>) -> Vec<String> {
    let names: Vec<String> = case.cracks.iter().map(|c| c.name.clone()).collect();
    contact.map_or_else(Vec::new, |c| {
        let mut notes = c.crosspoints.notes(mesh, &c.points, &names);
        notes.extend(c.points.frame_notes(&names));
        notes
    })
}

/// Warnings on the model before any solve: formula level sets that are not signed
/// distances near the front ([`crate::levelset::quality`]), whose tip functions and SIF
/// frames then read wrong r and θ.
fn model_warnings(case: &Case, model: &Model<'_>) -> Vec<String> {
    let mut out = vec![];
    // A tip zone that takes in (nearly) the whole body leaves (nearly) no blending cells,
    // the only cells that break the tip functions' zero-energy modes (src/enrich/mod.rs,
    // `BLENDING_FUNCTIONS`): the closed 45° crack of examples/inclined_crack_friction_2d.toml
    // runs with 99.2% of its nodes tip-enriched (tip_radius = 2.6) and fails as singular from
    // tip_radius = 2.75 (docs/reliability.md).
    let (n_tip, n_nodes) = (model.enrichment.n_tip_nodes, model.mesh.n_nodes());
    if n_nodes > 0 && n_tip as f64 > TIP_ZONE_SHARE * n_nodes as f64 {
        let radii: Vec<String> = case
            .cracks
            .iter()
            .zip(&model.enrichment.tip_radius)
            .filter(|(_, r)| **r > 0.0)
            .map(|(d, r)| format!("'{}' {r:.4e}", d.name))
            .collect();
        out.push(format!(
            "the tip enrichment covers {n_tip} of the {n_nodes} nodes ({:.1}%; tip radius of crack {}): with (almost) no blending cells left the tip functions' zero-energy modes are barely held and the matrix can be singular (the solve then fails blaming the supports), and each tip node costs 4 × dim unknowns; a tip_radius of a fraction of the crack length, well inside the body, is the usual choice",
            100.0 * n_tip as f64 / n_nodes as f64,
            radii.join(", ")
        ));
    }
    // A 3D crack with contact whose covering tip zone was over its share of the nodes
    // keeps two cell layers (`enrich::COVERING_NODE_SHARE`): its sliding pressure carries
    // the wave where the zone ends.
    for (k, def) in case.cracks.iter().enumerate() {
        if let TipEnrichment::Covering { half_length, max_node_share: Some(share) } = def.tip {
            let r = model.enrichment.tip_radius.get(k).copied().unwrap_or(0.0);
            if r > 0.0 && r < half_length {
                out.push(format!(
                    "crack '{}': a tip enrichment covering the crack (radius {half_length:.4e}, its depth) would take in more than {:.0}% of the nodes, so the crack keeps two cell layers (tip_radius {r:.4e}): where the edge of that zone crosses a sliding crack the contact pressure can be off by ~10% (docs/contact-algorithms.md, \"Accuracy near the tips\"); give tip_radius = {half_length} to cover it anyway, at about twice the unknowns",
                    def.name,
                    100.0 * share
                ));
            }
        }
    }
    for (k, def) in case.cracks.iter().enumerate() {
        // The nodal and vertex rules do not integrate the √r jump of the tip-enriched cells
        // (measured on the closed 45° crack of examples/inclined_crack_friction_2d.toml,
        // docs/reliability.md): say so rather than let the pressure and K be off silently.
        let Some(opt) = &def.contact else { continue };
        // A large augmentation is accepted but shifts the answer on a crack with a front
        // (measured, docs/reliability.md "Contact numerics": K_II 17% off at 1e3 E/h).
        if let (Some(rho), Some(scale)) = (opt.rho_n, resolve::augmentation_scale(model, k)) {
            if rho > 100.0 * scale {
                out.push(format!(
                    "crack '{}': rho_n = {rho:e} is {:.1e} times E/h = {scale:.4e}: above about 100 E/h the statuses at the edge of a contact zone (a multiplier packet with open and closed points) can depend on rho_n, or the active-set loop fail (where the packets close, the part above E/h of a small-sliding augmented Lagrangian augments the projected gap and changes nothing: docs/reliability.md); leave rho_n at its default E/h or keep it between 0.1 and 100 E/h",
                    def.name,
                    rho / scale
                ));
            }
        }
        // A fixed ρ_τ so small that ρ_τ v_τ is below the round-off of |Λ| = 1 leaves the
        // stick/slip indicator to Λ alone: the answer holds, the labels do not (measured on
        // the closed 45° crack at 41 × 41, h = 0.098: every sliding point reported stick at
        // ρ_τ = 1e-12, half of them at 1e-8, none at 1e-6).
        if let (Some(rho_t), Some(crack)) = (opt.rho_t, model.cracks.get(k)) {
            let cells = &crack.cut.cut_cells;
            if !cells.is_empty() {
                let h = cells.iter().map(|cc| model.mesh.cell_edge_length(cc.cell)).sum::<f64>() / cells.len() as f64;
                if rho_t * h < RHO_T_LABELS {
                    out.push(format!(
                        "crack '{}': rho_t = {rho_t:e} is {:.1e} times 1/h (h = {h:.4e}, the mean edge of the cut cells): the slip term of the stick/slip indicator is then below round-off, so sliding points may be reported as sticking (the answer is not affected); leave rho_t at its default or give at least {RHO_T_LABELS:.0e}/h",
                        def.name,
                        rho_t * h
                    ));
                }
            }
        }
        let tip =
            model.cracks.get(k).is_some_and(|c| c.cut.facets.iter().any(|f| f.vertex_on_front.iter().any(|&b| b)));
        let rule = match opt.integration {
            crate::contact::points::ContactIntegration::Nodes => "nodes",
            crate::contact::points::ContactIntegration::Vertex => "vertex",
            crate::contact::points::ContactIntegration::Gauss => continue,
        };
        if tip && opt.sliding == crate::contact::points::Sliding::Small {
            out.push(format!(
                "crack '{}': integration = \"{rule}\" on a crack with a front: the {rule} rule does not integrate the jump near the front (it varies like sqrt(r)), so the contact pressure and the SIFs are off by several percent there (closed 45° crack: pressure 0.37 to 0.49 for 0.5 and K_II 5% high with nodes); integration = \"gauss\" (the default) is graded towards the front",
                def.name
            ));
        }
    }
    for (k, (def, crack)) in case.cracks.iter().zip(&model.cracks).enumerate() {
        if let Some((cells, e_cell, e_side)) = material_boundary_in_cut_cells(model, crack) {
            out.push(format!(
                "crack '{}': it runs along a material boundary inside {cells} cut cells whose neighbours do not give each side one material (so the cut cells keep one material on both sides): both lips there have E = {e_cell:e} while the cells beside them on one side of the crack have E = {e_side:e}; the lip on that side is too {} in the cut cells (with contact and friction the loops may also fail). Give the cells on each side of the crack one material each (docs/case-format.md, \"Materials and cracks\"), or put the material boundary where the cells are not cut",
                def.name,
                if e_cell > e_side { "stiff" } else { "soft" },
            ));
        }
        let split = model.side_materials.cells_of_crack(k);
        let has_front = crack.cut.facets.iter().any(|f| f.vertex_on_front.iter().any(|&b| b));
        if split > 0 && has_front {
            out.push(format!(
                "crack '{}': it runs along a material boundary ({split} cut cells take the material of each side); its stress intensity factors are computed as in a homogeneous body with the material at each front point, which is not the K of a crack between two materials (oscillatory near-tip field): read them as indicative",
                def.name
            ));
        }
        let Some(c) = crate::levelset::quality::distance_check(&def.shape, model.mesh, &crack.levelsets) else {
            continue;
        };
        if !c.is_distance() {
            out.push(format!(
                "crack '{}': its formula level sets are not signed distances near the front: |grad lsn| in [{:.4}, {:.4}], |grad lst| in [{:.4}, {:.4}], largest cos(grad lsn, grad lst) {:.4} ({} points on the crack within two cells of the front, the worst at {:.4?}; signed distances give 1, 1 and 0 within {}): the tip functions and the SIFs read r and theta from them, so K is off by about as much; write lsn and lst as signed distances (docs/conventions.md, \"Cracks\")",
                def.name,
                c.grad_n[0],
                c.grad_n[1],
                c.grad_t[0],
                c.grad_t[1],
                c.max_cos,
                c.points,
                c.worst,
                crate::levelset::quality::DISTANCE_TOLERANCE,
            ));
        }
    }
    out
}

/// Whether `crack` runs along a material boundary through cut cells that kept one material
/// (the per-side rule of [`crate::physics::side_materials`] did not apply): the cut
/// cells with sub-cells on both sides whose uncut neighbours (sharing a node) lying wholly on one
/// side of the crack all have another Young's modulus. Returns the number of such cells,
/// the cut cells' modulus and the other side's (of the first one found).
fn material_boundary_in_cut_cells(
    model: &Model<'_>,
    crack: &crate::enrich::CrackGeometry,
) -> Option<(usize, f64, f64)> {
    let mesh = model.mesh;
    let young = |c: usize| model.materials[model.cell_material[c] as usize].young;
    let around = mesh.node_cells();
    let mut found: Option<(usize, f64, f64)> = None;
    for cc in &crack.cut.cut_cells {
        // A crack along the cell faces (a mesh that follows it) leaves the cell on one side.
        if cc.subcells.iter().all(|sc| sc.side == cc.subcells[0].side) {
            continue;
        }
        let e_sides = model.side_youngs(cc.cell);
        // Per side (−, +): whether it has whole-side uncut neighbours, and one of another
        // modulus than the cut cell's on that side if all of them differ.
        let mut side = [(0usize, 0usize, 0.0f64); 2];
        for (s, nb) in crate::physics::side_materials::whole_side_neighbours(mesh, &around, crack, cc.cell) {
            side[s].0 += 1;
            let enb = young(nb);
            if enb != e_sides[s] {
                side[s].1 += 1;
                side[s].2 = enb;
            }
        }
        if let Some((s, &(_, _, other))) = side.iter().enumerate().find(|(_, (n, diff, _))| *n > 0 && diff == n) {
            let f = found.get_or_insert((0, e_sides[s], other));
            f.0 += 1;
        }
    }
    found
}

/// The share of a crack's normal force that may sit at open points or as tension at closed
/// ones before a step is warned about (the per-packet law leaves 0.3% on the sliding block of
/// `tests/contact_numerics.rs`; an active set that ended on a spurious state left 1.9%, with
/// |R_x|/R_y 1.3% above μ: docs/reliability.md, "Stiffness contrast across an interface").
const STRAY_NORMAL_FORCE: f64 = 0.01;

/// A crack's normal force at open points or in tension at one step, kept until the step's
/// largest von Mises stress on the sub-cells decides whether the crack carries load
/// ([`NEGLIGIBLE_PRESSURE`]).
struct StrayShare {
    what: String,
    stray: f64,
    pressed: f64,
    peak: f64,
    open_peak: f64,
}

/// The compressive multiplier an open point may carry, as a share of the crack's largest
/// pressure, before a step is warned about (3.3% at the edge of the sliding block's open
/// zone; 90% at the two points next to a tip that a ρ_n of 1e3 E/h opened under
/// compression, with K_II 17% off: docs/reliability.md, "Contact numerics").
const OPEN_UNDER_PRESSURE: f64 = 0.25;

/// The largest contact pressure of a crack, as a share of the step's largest von Mises
/// stress, below which the crack carries no contact force to speak of: its multipliers are
/// the loops' round-off (an open crack), and the two shares above, ratios of round-off,
/// are not warned about (an open penny gave "16297% of the normal force at open points").
const NEGLIGIBLE_PRESSURE: f64 = 1e-6;

/// The share of the mesh nodes that a tip zone may enrich before `check` and the summary
/// warn ([`model_warnings`]).
const TIP_ZONE_SHARE: f64 = 0.98;

/// Default output directory of a case: `out/<case stem>/`.
pub fn default_out_dir(case_path: &Path) -> PathBuf {
    let stem = case_path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_else(|| "case".into());
    PathBuf::from("out").join(stem)
}

/// Options of a run that are not in the case file.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show the run on stderr: a progress line (on a terminal), a table after each step
    /// and the warnings.
    pub verbose: bool,
    /// Command-line overrides of case keys (`--set KEY=VALUE`), applied before reading.
    pub overrides: Vec<Override>,
    /// Also print every Newton iteration of the contact loops (`--verbose`; the
    /// environment variable `FISSURE_CONTACT_LOG` implies it).
    pub newton_iterations: bool,
    /// An MPI run on several ranks (the PETSc backend): this rank writes its piece of the
    /// body grid of every step into `Pieces::dir`, and the rank that writes the output
    /// (rank 0) a `.pvtu` index of the pieces in place of the body `.vtu`. `None`: one
    /// process writes the whole body `.vtu`.
    pub pieces: Option<Pieces>,
}

/// This rank's share of the body output of an MPI run ([`RunOptions::pieces`]).
///
/// The cells of rank `rank` are those its distributed assembly owned (the METIS partition
/// of `solve::petsc::partition`, weighted by element cost) when the assembly was
/// distributed, otherwise (contact: replicated assembly) the contiguous block of cells
/// `n·rank/size .. n·(rank+1)/size` of the mesh order; a sub-cell of a cut cell goes with its
/// cell. Piece `r` of step `k` is `<case>_step<k>_<r>.vtu`, the index `<case>_step<k>.pvtu`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pieces {
    pub rank: usize,
    pub size: usize,
    /// The run's output directory (every rank writes its piece there).
    pub dir: PathBuf,
}

/// Where the case of a run comes from.
#[derive(Debug, Clone)]
pub enum CaseInput {
    /// A case file; its relative paths start from its directory.
    File(PathBuf),
    /// Case-file text built in memory (the Python bindings' dict): `path` names it in
    /// errors and in `summary.json` `case`; its relative paths start from `base`.
    Text { text: String, path: PathBuf, base: PathBuf },
}

impl CaseInput {
    /// The path naming the case.
    pub fn path(&self) -> &Path {
        match self {
            CaseInput::File(p) => p,
            CaseInput::Text { path, .. } => path,
        }
    }

    /// Reads and validates the case with `overrides` applied to its keys first.
    pub fn read(&self, overrides: &[Override]) -> Result<Case, CaseError> {
        match self {
            CaseInput::File(p) => Case::from_file_with(p, overrides),
            CaseInput::Text { text, path, base } => Case::parse_in(text, path, base, overrides),
        }
    }
}

/// The fields of one recorded step kept in memory by [`run_case_results`].
#[derive(Debug, Clone)]
pub struct StepFields {
    /// The step's `index` in `summary.json` `steps`.
    pub index: usize,
    /// Nodal displacements, `dim` values per mesh node: the standard unknowns, which are
    /// the displacement at the node since the enrichment functions are shifted.
    pub displacement: Vec<f64>,
    /// The crack-lip grid of the step, as in `<stem>_crack_stepNNNN.vtu` (point data
    /// `displacement`, `jump`, `normal_opening`, `tangential_slip`, with contact also
    /// `lambda`, `pressure`, `Lambda`, `Lambda_norm`; cell data `lip`, `crack`,
    /// `normal`, with contact `status`); `None` without cracks.
    pub lips: Option<UnstructuredGrid>,
}

/// A run's results in memory: what [`run_case`] writes, plus the fields of every
/// recorded step.
#[derive(Debug, Clone)]
pub struct RunResults {
    /// The summary written to `summary.json`.
    pub summary: Summary,
    pub dim: usize,
    /// The mesh nodes' coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// One entry per `summary.steps` entry, in the same order.
    pub steps: Vec<StepFields>,
}

/// The solve's observer during a run: the terminal, and the record of the Newton
/// iterations for the convergence plot.
struct RunObserver<'a> {
    terminal: &'a Terminal,
    newton: std::sync::Mutex<Vec<NewtonIteration>>,
    /// The system's figures, last told (a failed run's summary reports them).
    sizes: std::sync::Mutex<Option<statics::SolveReport>>,
}

impl SolveObserver for RunObserver<'_> {
    fn phase(&self, phase: Phase) {
        SolveObserver::phase(self.terminal, phase);
    }
    fn newton(&self, it: &NewtonIteration) {
        self.terminal.newton(it);
        if let Ok(mut v) = self.newton.lock() {
            v.push(*it);
        }
    }
    fn system(&self, sizes: &statics::SolveReport) {
        if let Ok(mut s) = self.sizes.lock() {
            *s = Some(sizes.clone());
        }
    }
}

/// Reads, solves and writes a case into `out_dir`. Returns the summary that was written.
pub fn run_case(case_path: &Path, out_dir: &Path, opts: &RunOptions) -> Result<Summary, RunError> {
    run(&CaseInput::File(case_path.to_path_buf()), out_dir, opts, false).map(|r| r.summary)
}

/// [`run_case`] on a case file or on case text, also returning the mesh nodes and every
/// recorded step's nodal displacements and crack-lip fields in memory.
pub fn run_case_results(input: &CaseInput, out_dir: &Path, opts: &RunOptions) -> Result<RunResults, RunError> {
    run(input, out_dir, opts, true)
}

/// The run itself; `keep`: keep the fields of each step in memory.
fn run(input: &CaseInput, out_dir: &Path, opts: &RunOptions, keep: bool) -> Result<RunResults, RunError> {
    let case_path = input.path();
    let total = Instant::now();
    let newton_log = opts.newton_iterations || std::env::var_os("FISSURE_CONTACT_LOG").is_some();
    let terminal = Terminal::new(!opts.verbose, newton_log);
    terminal.phase("reading the case");
    let case = input.read(&opts.overrides).map_err(RunError::Case)?;
    let at = |e| RunError::Case(case.attribute(e));
    let clock = Instant::now();
    terminal.phase("mesh");
    let mesh = resolve::build_mesh(&case).map_err(at)?;
    let mesh_s = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    terminal.phase(&format!("cracks: level sets, cutting, enrichment ({} cells)", mesh.n_cells()));
    let model = resolve::build_model(&case, &mesh).map_err(at)?;
    resolve::check_memory(&case, &model).map_err(at)?;
    let contact = resolve::build_contact(&case, &model).map_err(at)?;
    if let Some(p) = &case.propagation {
        growth::check_propagation(&case, p, &mesh).map_err(at)?;
    }
    let cracks_s = clock.elapsed().as_secs_f64();
    std::fs::create_dir_all(out_dir).map_err(|e| RunError::Output(format!("{}: {e}", out_dir.display())))?;

    let mut summary = Summary {
        version: crate::VERSION.to_string(),
        case: case_path.display().to_string(),
        status: "running".into(),
        dim: mesh.dim,
        analysis: model.analysis.name().to_string(),
        mesh: mesh_info(&mesh),
        ..Default::default()
    };
    summary.warnings.extend(model_warnings(&case, &model));
    summary.warnings.extend(contact_notes(&case, &mesh, contact.as_ref()));
    summary.timings_s.mesh = mesh_s;
    summary.timings_s.cracks = cracks_s;
    let summary_path = out_dir.join("summary.json");
    let options = SolveOptions {
        linear: case.solver.linear,
        residual_tolerance: case.solver.residual_tolerance,
        condense: case.solver.condense,
        ordering: case.solver.ordering,
        // A dynamic run solves at every time step with a factor it keeps: double
        // precision unless asked (one solve instead of the iterations of a mixed one).
        precision: match (case.solver.precision, &case.dynamics) {
            (Precision::Auto, Some(_)) => Precision::Double,
            (p, _) => p,
        },
        backend: case.solver.backend.clone(),
        reuse_ordering: None,
        position_correction: case.dynamics.as_ref().is_none_or(|d| d.position_correction),
        mass: case.dynamics.as_ref().map_or(Default::default(), |d| d.mass),
    };
    let dynamics = case.dynamics.clone();
    let initial = match &dynamics {
        Some(_) => initial_state(&case, &model, &options)?,
        None => Default::default(),
    };
    let energy = match &dynamics {
        Some(_) => Some(EnergyLog::create(out_dir).map_err(RunError::Output)?),
        None => None,
    };
    let observer = RunObserver { terminal: &terminal, newton: Default::default(), sizes: Default::default() };
    let has_contact = contact.is_some();
    let mut rec = Recorder {
        case: &case,
        out_dir,
        summary,
        pvd: vec![],
        pvd_name: format!("{}.pvd", case.name),
        levelset_file: format!("{}_levelsets.vtu", case.name),
        base: None,
        output_s: 0.0,
        sif_s: 0.0,
        terminal: &terminal,
        profiles: vec![],
        n_steps: dynamics.as_ref().map_or(model.load_factors.len(), |d| d.scheme.coefficients().steps),
        output_every: dynamics.as_ref().map(|d| (d.output_every, d.scheme.coefficients().steps)),
        energy,
        fields: keep.then(Vec::new),
        wear: None,
        pieces: opts.pieces.clone().filter(|p| p.size > 1).map(|p| (p, None)),
    };
    let rho_advice = rho_n_advice(&case, &model);
    let result = match (&case.propagation, &dynamics) {
        (Some(prop), _) => growth::run_growth(&mut rec, &mesh, model, contact, &prop.options, &options, &observer),
        (None, dyn_def) => {
            if !model.cracks.is_empty() && case.output.vtu {
                rec.write_levelsets(&model).map_err(RunError::Output)?;
            }
            let mut on_step = |s: statics::StepSolution<'_>| rec.record(&model, contact.as_ref(), s, None);
            match dyn_def {
                None => statics::solve_load_steps_observed(&model, contact.as_ref(), &options, &observer, &mut on_step),
                Some(d) => dynamics::solve_time_steps(
                    &model,
                    contact.as_ref(),
                    &options,
                    &d.scheme,
                    &initial,
                    &observer,
                    &mut on_step,
                ),
            }
        }
    };
    // A contact loop that reached its cap with a ρ_n far above E/h: say that ρ_n is the
    // likely cause and what value works.
    let result = result.map_err(|e| match (e, rho_advice) {
        (e @ (SolveError::Contact { .. } | SolveError::Linear { .. }), Some(advice)) => {
            SolveError::Advised { error: Box::new(e), advice }
        }
        // A contact loop that failed again in its damped redo (`solve::contact_loops`).
        (SolveError::Advised { error, advice: redo }, Some(advice)) if matches!(*error, SolveError::Contact { .. }) => {
            SolveError::Advised { error, advice: format!("{redo}. {advice}") }
        }
        (e, _) => e,
    });
    let mut energy_rows = vec![];
    if let (Some(d), Some(log)) = (&dynamics, rec.energy.take()) {
        energy_rows = log.history;
        rec.summary.dynamics = Some(DynamicsInfo {
            scheme: d.scheme.name().into(),
            dt: d.scheme.coefficients().dt,
            steps: d.scheme.coefficients().steps,
            beta: d.scheme.coefficients().beta,
            gamma: d.scheme.coefficients().gamma,
            alpha: d.scheme.coefficients().alpha,
            theta: d.scheme.theta(),
            output_every: d.output_every,
            energy_history: ENERGY_FILE.into(),
            final_energies: log.last,
            energy_balance_error: log.error,
            position_correction: PositionCorrectionInfo { enabled: d.position_correction, ..log.corrections },
            mass: d.mass.name().into(),
        });
    }
    let newton = observer.newton.into_inner().unwrap_or_default();
    let sizes = observer.sizes.into_inner().ok().flatten();
    let clock = Instant::now();
    terminal.phase("writing the tables and plots");
    let extras = write_extras(&case, &mesh, out_dir, &rec.summary, &newton, &rec.profiles, &energy_rows, has_contact);
    rec.output_s += clock.elapsed().as_secs_f64();
    terminal.finish();
    let fields = rec.fields.take().unwrap_or_default();
    let summary = finish(rec, result, sizes, extras, &summary_path, total)?;
    Ok(RunResults { summary, dim: mesh.dim, nodes: if keep { mesh.nodes.clone() } else { vec![] }, steps: fields })
}

/// Above this multiple of E/h a contact loop that reaches its cap is blamed on `rho_n`
/// (the run's warning starts at 100 E/h; the sliding block of `tests/contact_numerics.rs`
/// converges to the default's answer up to 4.9e4 E/h and fails its linear solve at 1e6 E/h:
/// docs/reliability.md).
pub const RHO_N_BLAMED_ABOVE: f64 = 100.0;

/// What a failed contact loop's message adds when some crack's `rho_n` is above
/// [`RHO_N_BLAMED_ABOVE`] × E/h: the crack, its ρ_n as a multiple of E/h, and the value
/// that works (the default E/h, or at most 100 E/h); `None` when no crack has one.
pub fn rho_n_advice(case: &Case, model: &Model<'_>) -> Option<String> {
    let mut out = vec![];
    for (k, def) in case.cracks.iter().enumerate() {
        let Some(opt) = &def.contact else { continue };
        if let (Some(rho), Some(scale)) = (opt.rho_n, resolve::augmentation_scale(model, k)) {
            if rho > RHO_N_BLAMED_ABOVE * scale {
                out.push(format!(
                    "crack '{}' has rho_n = {rho:e}, {:.1e} times E/h = {scale:.4e}: that is the likely cause (a ρ_n far above E/h makes the contact statuses at the edge of a contact zone, inside a multiplier packet, cycle or the system ill-conditioned: docs/reliability.md); remove rho_n (the default E/h = {scale:.4e} converges) or keep it at most {:.4e} (100 E/h)",
                    def.name,
                    rho / scale,
                    RHO_N_BLAMED_ABOVE * scale
                ));
            }
        }
    }
    (!out.is_empty()).then(|| out.join("; "))
}

/// Writes the final `summary.json` of a run: the solver figures of `result` and `"ok"`,
/// or `"failed"` with its error and the system's figures when they are known (`sizes`,
/// the last the solve told). `extras`: whether the tables and plots were written.
fn finish(
    mut rec: Recorder<'_>,
    result: Result<statics::SolveReport, SolveError>,
    sizes: Option<statics::SolveReport>,
    extras: Result<(), String>,
    summary_path: &Path,
    total: Instant,
) -> Result<Summary, RunError> {
    let summary = &mut rec.summary;
    match result {
        Ok(report) => {
            let t = report.timings;
            summary.dofs = dof_info(&report, rec.case);
            summary.linear_solver = linear_solver_info(&report);
            if let Some(reason) = report.precision_fallback {
                summary.warnings.push(format!(
                    "[solver] precision: the single-precision factor was abandoned ({reason}); the solve used the \
                     double-precision factor"
                ));
            }
            summary.timings_s = TimingsInfo {
                mesh: summary.timings_s.mesh,
                pattern: t.pattern,
                assembly: t.assembly,
                factorisation: t.symbolic + t.numeric,
                factorisation_symbolic: t.symbolic,
                factorisation_numeric: t.numeric,
                solve: t.solve,
                cracks: summary.timings_s.cracks,
                sif: rec.sif_s,
                output: rec.output_s,
                pairing: t.pairing,
                total: total.elapsed().as_secs_f64(),
            };
            summary.status = "ok".into();
            summary.write(summary_path).map_err(|e| RunError::Output(format!("{}: {e}", summary_path.display())))?;
            extras.map_err(RunError::Output)?;
            Ok(rec.summary)
        }
        Err(e) => {
            summary.status = "failed".into();
            summary.error = Some(e.to_string());
            if let Some(sizes) = &sizes {
                summary.dofs = dof_info(sizes, rec.case);
                summary.linear_solver = linear_solver_info(sizes);
            }
            summary.timings_s.total = total.elapsed().as_secs_f64();
            // Best effort: the error itself is what the caller must see.
            let _ = summary.write(summary_path);
            Err(RunError::Solve(e))
        }
    }
}

/// The `linear_solver` entry of `summary.json` from the solve's figures.
fn linear_solver_info(report: &statics::SolveReport) -> LinearSolverInfo {
    let method_name = |m: LinearMethod| match m {
        LinearMethod::Cholesky => "cholesky",
        LinearMethod::Ldlt => "ldlt",
        LinearMethod::Lu => "lu",
    };
    LinearSolverInfo {
        method: method_name(report.linear_method).into(),
        nnz_matrix: report.nnz_matrix,
        nnz_factor: report.nnz_factor,
        assembly_colors: report.n_colors,
        condensed: report.condensed,
        backend: report.backend.name.into(),
        precision: if report.mixed_precision { "mixed" } else { "double" }.into(),
        precision_fallback: report.precision_fallback.map(str::to_string),
        ksp: report.backend.ksp.clone(),
        pc: report.backend.pc.clone(),
        ranks: report.backend.ranks,
        iterations: report.backend.iterations,
        cells_per_rank: report.backend.cells_per_rank.clone(),
        enriched_cells_per_rank: report.backend.enriched_cells_per_rank.clone(),
        contact_points_per_rank: report.backend.contact_points_per_rank.clone(),
        matrix_entries_per_rank: report.backend.matrix_entries_per_rank.clone(),
        peak_rss_kib_per_rank: report.backend.peak_rss_kib_per_rank.clone(),
        dense_factorizations: report.condensed_counts.map(|c| c.factorizations),
        factor_reuses: report.condensed_counts.map(|c| c.reused),
        krylov_solves: report.condensed_counts.map(|c| c.krylov_solves),
        krylov_iterations: report.condensed_counts.map(|c| c.krylov_iterations),
        sparse_factorizations: report.kept_counts.map(|c| c.factorizations),
        kept_factor_reuses: report.kept_counts.map(|c| c.reused),
        kept_krylov_solves: report.kept_counts.map(|c| c.krylov_solves),
        kept_krylov_iterations: report.kept_counts.map(|c| c.krylov_iterations),
    }
}

/// The smallest fixed `rho_t` × h below which the stick/slip labels are not trusted (a
/// warning; `docs/reliability.md`, the audit of 2026-11-28).
const RHO_T_LABELS: f64 = 1e-6;

/// The output of a run as it goes: the summary, the PVD collection, the files of each
/// step (or growth entry) and the contact profiles for the plots, written by
/// [`Recorder::record`].
pub(crate) struct Recorder<'a> {
    case: &'a Case,
    out_dir: &'a Path,
    summary: Summary,
    pvd: Vec<PvdEntry>,
    pvd_name: String,
    /// The level-set file the crack entries of the PVD point to.
    levelset_file: String,
    /// The mesh as a grid (uncracked bodies; built at the first step that needs it).
    base: Option<UnstructuredGrid>,
    output_s: f64,
    sif_s: f64,
    terminal: &'a Terminal,
    profiles: Vec<ContactProfile>,
    /// Steps (or growth entries) of the run, for the step table.
    n_steps: usize,
    /// Dynamics: write fields, SIFs and files every this many steps (and the first and
    /// last of the given count).
    output_every: Option<(usize, usize)>,
    /// Dynamics: `energy_history.csv` and the energy balance so far.
    energy: Option<EnergyLog>,
    /// The fields of each recorded step, when kept in memory ([`run_case_results`]).
    fields: Option<Vec<StepFields>>,
    /// Wear: `wear_history.csv`, opened at the first step with wear.
    wear: Option<std::io::BufWriter<std::fs::File>>,
    /// An MPI run's body pieces, with the rank of every mesh cell (found at the first step).
    pieces: Option<(Pieces, Option<Vec<u32>>)>,
}

/// The wear history of a run with wear, next to `summary.json`.
const WEAR_FILE: &str = "wear_history.csv";

/// The energy history of a dynamic run: one row per time step in [`ENERGY_FILE`], and the
/// largest drift of the total energy relative to the largest kinetic + strain energy.
struct EnergyLog {
    csv: std::io::BufWriter<std::fs::File>,
    total0: Option<f64>,
    scale: f64,
    error: f64,
    last: EnergyInfo,
    /// Every row written (for `energy.png`).
    history: Vec<EnergyInfo>,
    /// The position corrections of the run (`summary.json` `dynamics.position_correction`).
    corrections: PositionCorrectionInfo,
}

/// The energy history of a dynamic run, next to `summary.json`.
const ENERGY_FILE: &str = "energy_history.csv";

impl EnergyLog {
    fn create(out_dir: &Path) -> Result<EnergyLog, String> {
        use std::io::Write;
        let path = out_dir.join(ENERGY_FILE);
        let f = std::fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut csv = std::io::BufWriter::new(f);
        writeln!(csv, "time,kinetic,strain,external_work,frictional_dissipation,contact_work,total")
            .map_err(|e| format!("{ENERGY_FILE}: {e}"))?;
        Ok(EnergyLog {
            csv,
            total0: None,
            scale: 0.0,
            error: 0.0,
            last: EnergyInfo::default(),
            history: vec![],
            corrections: PositionCorrectionInfo::default(),
        })
    }

    /// Appends the energies at `time` (flushed, so that a failed run keeps its history).
    fn push(&mut self, time: f64, e: &crate::solve::report::Energies) -> Result<(), String> {
        use std::io::Write;
        let total = e.total();
        let t0 = *self.total0.get_or_insert(total);
        self.scale = self.scale.max(e.kinetic + e.strain);
        if self.scale > 0.0 {
            self.error = self.error.max((total - t0).abs() / self.scale);
        }
        self.last = EnergyInfo {
            time,
            kinetic: e.kinetic,
            strain: e.strain,
            external_work: e.external_work,
            frictional_dissipation: e.frictional_dissipation,
            contact_work: e.contact_work,
            total,
        };
        let row = [time, e.kinetic, e.strain, e.external_work, e.frictional_dissipation, e.contact_work, total];
        if row.iter().any(|v| !v.is_finite()) {
            return Err(format!("time {time}: non-finite energies {row:?}"));
        }
        self.history.push(self.last.clone());
        let text: Vec<String> = row.iter().map(|v| format!("{v:.12e}")).collect();
        writeln!(self.csv, "{}", text.join(","))
            .and_then(|_| self.csv.flush())
            .map_err(|e| format!("{ENERGY_FILE}: {e}"))
    }
}

/// Appends the wear of step `index` to [`WEAR_FILE`] in `out_dir` (created with its header
/// on the first call; flushed, so that a failed run keeps its history).
fn push_wear(
    file: &mut Option<std::io::BufWriter<std::fs::File>>,
    out_dir: &Path,
    index: usize,
    load_factor: f64,
    w: &WearInfo,
) -> Result<(), String> {
    use std::io::Write;
    let err = |e: std::io::Error| format!("{WEAR_FILE}: {e}");
    if file.is_none() {
        let f = std::fs::File::create(out_dir.join(WEAR_FILE)).map_err(err)?;
        let mut csv = std::io::BufWriter::new(f);
        writeln!(csv, "step,load_factor,max,mean,volume,frictional_work").map_err(err)?;
        *file = Some(csv);
    }
    let csv = file.as_mut().expect("opened above");
    writeln!(
        csv,
        "{index},{load_factor:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
        w.max, w.mean, w.volume, w.frictional_work
    )
    .and_then(|_| csv.flush())
    .map_err(err)
}

impl Recorder<'_> {
    /// Writes the level sets of `model`'s cracks into `self.levelset_file`.
    fn write_levelsets(&mut self, model: &Model<'_>) -> Result<(), String> {
        let clock = Instant::now();
        let grid = xfem_output::levelset_grid(model);
        let file = &self.levelset_file;
        vtu::write_vtu(&self.out_dir.join(file), &grid, self.case.output.compression)
            .map_err(|e| format!("{file}: {e}"))?;
        self.output_s += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Checks and records one solved step: its figures, the SIFs of every crack, the VTU
    /// files and the PVD entry, appended to `summary.steps`. `entry`: the growth entry this
    /// step is (its index and PVD time), or `None` for a load step.
    fn record(
        &mut self,
        model: &Model<'_>,
        contact: Option<&ContactSetup>,
        s: statics::StepSolution<'_>,
        entry: Option<usize>,
    ) -> Result<(), String> {
        let case = self.case;
        let mesh = model.mesh;
        let terminal = self.terminal;
        let summary = &mut self.summary;
        let cracked = !model.cracks.is_empty();
        let dof_nodes = model.enrichment.dof_nodes();
        let r = s.report;
        let index = entry.unwrap_or(r.index);
        // The PVD's time is the load factor while the factors increase step by step (the
        // plots' abscissa too); a history that repeats or reverses a factor (a load–unload
        // cycle) takes the step number instead, which ParaView can order.
        let monotone = case.load_factors.windows(2).all(|w| w[1] > w[0]);
        let time =
            entry.map_or(if monotone || s.motion.is_some() { r.load_factor } else { r.index as f64 }, |e| e as f64);
        let n_warnings = summary.warnings.len();
        terminal.phase("stress intensity factors and output");
        let n_std = s.dofs.dim * mesh.n_nodes();
        // The result guard: nothing non-finite is written or reported as ok.
        let finite = |what: Result<(), String>| what.map_err(|m| format!("step {index}: non-finite result: {m}"));
        finite(guard::check_unknowns(s.u, &dof_nodes, mesh.dim, n_std))?;
        if let Some(m) = &s.motion {
            finite(guard::check_unknowns(m.velocity, &dof_nodes, mesh.dim, n_std))?;
            finite(guard::check_unknowns(m.acceleration, &dof_nodes, mesh.dim, n_std))?;
            if let Some(log) = self.energy.as_mut() {
                log.push(m.time, &m.energies)?;
                if m.position_correction > 0.0 {
                    log.corrections.steps += 1;
                    log.corrections.largest = log.corrections.largest.max(m.position_correction);
                }
            }
        }
        // Dynamics: fields, SIFs and files every output_every steps (and the first and last).
        if let Some((every, last)) = self.output_every {
            if r.index % every != 0 && r.index != 0 && r.index != last {
                return Ok(());
            }
        }
        // An MPI run on several ranks: the body grid and its cell fields of this rank's cells
        // only (its piece); the figures read from them are reduced over the ranks.
        let (rank, size) = mpi_rank_size();
        let piece: Option<Vec<bool>> = (size > 1).then(|| {
            let owner = match self.pieces.as_mut() {
                Some((p, owner)) => owner.get_or_insert_with(|| cell_ranks(mesh.n_cells(), p.size)).clone(),
                None => cell_ranks(mesh.n_cells(), size),
            };
            owner.iter().map(|&r| r as usize == rank).collect()
        });
        // The standard-basis cell fields: the uncracked body's (a cracked body's come with its
        // sub-cells' grid below).
        let fields = if cracked {
            post::CellFields::default()
        } else {
            let (materials, cell_material) = (&model.materials, &model.cell_material);
            post::cell_fields_of(mesh, model.analysis, materials, cell_material, &s.u[..n_std], piece.as_deref())
        };
        let mut info = StepInfo {
            index,
            load_factor: r.load_factor,
            solver: StepSolverInfo {
                linear_solves: r.linear_solves,
                factorizations: r.factorizations,
                residual: r.residual,
                dense_factorizations: r.contact.as_ref().and_then(|c| c.condensed).map(|c| c.factorizations),
                factor_reuses: r.contact.as_ref().and_then(|c| c.condensed).map(|c| c.reused),
                krylov_iterations: r.contact.as_ref().and_then(|c| c.condensed).map(|c| c.krylov_iterations),
                sparse_factorizations: r.contact.as_ref().and_then(|c| c.kept).map(|c| c.factorizations),
                kept_factor_reuses: r.contact.as_ref().and_then(|c| c.kept).map(|c| c.reused),
                kept_krylov_iterations: r.contact.as_ref().and_then(|c| c.kept).map(|c| c.krylov_iterations),
            },
            max_displacement: max_norm(&s.u[..n_std], mesh.dim),
            max_von_mises: match &piece {
                Some(_) if !cracked => max_over_ranks(fields.von_mises.iter().cloned().fold(0.0, f64::max)),
                _ => fields.von_mises.iter().cloned().fold(0.0, f64::max),
            },
            position_correction: s.motion.as_ref().map(|m| m.position_correction),
            ..Default::default()
        };
        for (g, name) in model.dirichlet_groups.iter().enumerate() {
            let e = info.reactions.entry(name.clone()).or_insert([0.0; 3]);
            for i in 0..3 {
                e[i] += r.reactions[g][i];
            }
        }
        // Stress intensity factors of every crack (pressure on the faces included).
        let sif_clock = Instant::now();
        for (k, def) in case.cracks.iter().enumerate() {
            let sif_opts = sif::SifOptions { radius: def.sif_radius };
            let front = crack_front(model, contact, &s, k, &sif_opts);
            let overlaps = sif::overlapping_domains(model, k, &sif_opts, &front);
            if let Some(&(i, j)) = overlaps.first() {
                let (rd, _) = sif::domain_radius(model, k, &sif_opts);
                let (p, q) = (front[i].x, front[j].x);
                let d = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)).sqrt();
                let fit = if model.mesh.dim == 3 { d / 3.0 } else { d / 2.0 };
                summary.warnings.push(format!(
                    "step {index}: crack '{}': the SIF domain (sif_radius {rd:.4}) of the front point at {p:.4?} takes in the front at {q:.4?}, {d:.4} away ({} such pairs): its K values mix both fronts; give a sif_radius below {fit:.4}",
                    def.name,
                    overlaps.len(),
                ));
            }
            if let Some((i, x, d, what, n)) = sif::domains_on_loaded_boundary(model, k, &sif_opts, &front) {
                let (rd, h) = sif::domain_radius(model, k, &sif_opts);
                let what = match what {
                    sif::LoadedBoundary::Load(l) => format!(
                        "a node of the loaded faces of group '{}'",
                        case.face_loads.get(l).map_or("?", |f| f.group.as_str())
                    ),
                    sif::LoadedBoundary::Held(g) => format!(
                        "a node held by [[dirichlet]] group '{}'",
                        model.dirichlet_groups.get(g).map_or("?", |s| s.as_str())
                    ),
                };
                let advice = if d > 2.0 * h {
                    format!("give a sif_radius below {:.4}", d - h)
                } else {
                    "the front is within two cells of it: refine the mesh there or move the load".to_string()
                };
                summary.warnings.push(format!(
                    "step {index}: crack '{}': the SIF domain (sif_radius {rd:.4}, one cell more for the weight's ramp) of the front point at {:.4?} takes in {what} at {x:.4?}, {d:.4} away ({n} front points): the interaction integral takes the load or reaction there from the finite-element stress on the boundary, which converges at first order in the mesh size (K_II 7% off with 12 cells across the ligament, 1.8% with 50), so its K values are less accurate than with a domain clear of it; {advice}",
                    def.name,
                    front[i].x,
                ));
            }
            if let Some((i, y, d, n)) = sif::fronts_near_the_boundary(model, k, &sif_opts, &front) {
                let (_, h) = sif::domain_radius(model, k, &sif_opts);
                summary.warnings.push(format!(
                    "step {index}: crack '{}': the front point at {:.4?} is {d:.4} from the boundary of the body (at {y:.4?}) ahead of it or across the crack plane, less than two cells ({:.4}) ({n} front points): the ligament is not resolved by the mesh and K there is not reliable; refine the mesh between the front and the boundary",
                    def.name,
                    front[i].x,
                    2.0 * h,
                ));
            }
            if let Some((i, y, d, n)) = sif::shallow_crack(model, k, &sif_opts, &front) {
                let (_, h) = sif::domain_radius(model, k, &sif_opts);
                summary.warnings.push(format!(
                    "step {index}: crack '{}': the front point at {:.4?} is {d:.4} from the boundary of the body behind it (at {y:.4?}, back across the crack), the farthest of all front points, less than two cells ({:.4}) ({n} front points within two cells of it): the crack is shallower than two cells, not resolved by the mesh, and its K is not reliable; refine the mesh around the crack",
                    def.name,
                    front[i].x,
                    2.0 * h,
                ));
            }
            let tip_radius = model.enrichment.tip_radius.get(k).copied().filter(|&r| r > 0.0);
            info.cracks.push(CrackInfo { name: def.name.clone(), tip_radius, front, growth: None });
        }
        self.sif_s += sif_clock.elapsed().as_secs_f64();
        // The cracks whose normal force sits partly at open points or in tension, decided
        // once the step's von Mises stress is known on the sub-cells (below).
        let mut stray_shares: Vec<StrayShare> = Vec::new();
        if let (Some(c), Some(cr)) = (&contact, &r.contact) {
            let mut methods: Vec<&str> = c.points.cracks.iter().map(|cc| cc.law.method.name()).collect();
            methods.dedup();
            let (per_crack, step_profiles, mut per_pair) = contact_per_crack(case, model, c, &s);
            for pi in &mut per_pair {
                pi.iterations = ContactIterations {
                    friction: cr.friction,
                    active_set: cr.active_set,
                    newton: cr.newton,
                    geometry: cr.pairing.map(|_| cr.geometry),
                };
                pi.factorizations = cr.factorizations;
                pi.linear_solves = cr.linear_solves;
                pi.residual = cr.residual;
                if let Some(p) = &mut pi.pairing {
                    p.pattern_rebuilds = cr.pattern_rebuilds;
                    p.zone_regrowths = cr.zone_regrowths;
                }
            }
            info.contact_pairs = per_pair;
            self.profiles.extend(step_profiles);
            info.contact = Some(ContactInfo {
                method: methods.join(","),
                points: cr.points,
                active: cr.active,
                stick: cr.stick,
                slip: cr.slip,
                lambda_min: cr.lambda_min,
                lambda_max: cr.lambda_max,
                iterations: ContactIterations {
                    friction: cr.friction,
                    active_set: cr.active_set,
                    newton: cr.newton,
                    geometry: cr.pairing.map(|_| cr.geometry),
                },
                factorizations: cr.factorizations,
                linear_solves: cr.linear_solves,
                residual: cr.residual,
                unknowns: c.points.multiplier_unknowns(),
                accepted_disagreements: cr.accepted_disagreements.iter().sum(),
                pairing: cr.pairing.map(|p| PairingInfo {
                    paired: p.paired,
                    outside: p.outside,
                    far: p.far,
                    failed: p.failed,
                    warnings: p.outside + p.far + p.failed,
                    pattern_rebuilds: cr.pattern_rebuilds,
                    zone_out: p.zone_out,
                    zone_regrowths: cr.zone_regrowths,
                }),
                cracks: per_crack,
                wear: post::contact_output::wear_figures(c, s.contact_state).map(|w| WearInfo {
                    max: w.max,
                    mean: w.mean,
                    volume: w.volume,
                    frictional_work: w.frictional_work,
                }),
            });
            if let Some(w) = info.contact.as_ref().and_then(|c| c.wear) {
                push_wear(&mut self.wear, self.out_dir, index, r.load_factor, &w)?;
            }
            // A penalty too soft for the load: the lips pass through each other.
            let vals = crate::contact::state::point_values(model, &c.points, s.pairing, s.contact_state, s.u);
            for (ci, cc) in c.points.cracks.iter().enumerate() {
                if cc.law.method.has_multipliers() {
                    continue;
                }
                let worst = c
                    .points
                    .points
                    .iter()
                    .zip(&vals)
                    .filter(|(p, v)| p.crack == ci && v.paired)
                    .map(|(_, v)| v.d_n)
                    .fold(0.0, f64::max);
                if worst > cc.cell_size {
                    let what = match &cc.pair {
                        Some(p) => format!("contact pair '{}': the surfaces", p.name),
                        None => format!("crack '{}': the lips", case.cracks[cc.crack].name),
                    };
                    summary.warnings.push(format!(
                        "step {index}: {what} pass through each other by {worst:.4e}, more than a cell ({:.4e}): kappa_n = {:.4e} is too small for this load",
                        cc.cell_size, cc.law.kappa_n
                    ));
                }
            }
            // The multiplier holds the contact law per packet: the normal force it carries at
            // open points, and as tension at closed ones, has no friction to match.
            let st = crate::contact::state::statuses(&c.points, s.contact_state, &vals);
            for (ci, cc) in c.points.cracks.iter().enumerate() {
                if !cc.law.method.has_multipliers() {
                    continue;
                }
                // An asperity layer's traction is normal force too (pressed, and in the peak
                // pressure): where the layer carries the load, λ is round-off and a share of
                // it alone means nothing.
                let (mut pressed, mut stray, mut peak, mut open_peak) = (0.0, 0.0, 0.0f64, 0.0f64);
                for (((p, v), st), ps) in c.points.points.iter().zip(&vals).zip(&st).zip(s.contact_state) {
                    if p.crack != ci {
                        continue;
                    }
                    let layer = cc
                        .law
                        .layer_traction(v.paired, v.d_n, crate::contact::state::start_gap(&cc.law, p, ps))
                        .max(0.0);
                    pressed += p.weight * layer;
                    peak = peak.max(-v.lambda + layer);
                    match st {
                        Status::Open => {
                            stray += p.weight * v.lambda.abs();
                            open_peak = open_peak.max(-v.lambda);
                        }
                        _ if v.lambda > 0.0 => stray += p.weight * v.lambda,
                        _ => pressed -= p.weight * v.lambda,
                    }
                }
                let share = stray > STRAY_NORMAL_FORCE * pressed;
                let open_pressed = open_peak > OPEN_UNDER_PRESSURE * peak;
                if pressed > 0.0 && (share || open_pressed) {
                    let what = match &cc.pair {
                        Some(p) => format!("contact pair '{}'", p.name),
                        None => format!("crack '{}'", case.cracks[cc.crack].name),
                    };
                    stray_shares.push(StrayShare { what, stray, pressed, peak, open_peak });
                }
            }
            if let Some(res) = cr.condensed_fallback {
                summary.warnings.push(format!(
                    "step {index}: the condensed contact factor lost accuracy (relative residual {res:.1e}): the step was solved with the plain LDLᵀ of the whole system ([solver] condense = false), kept for the rest of the run"
                ));
            }
            if let Some(change) = cr.friction_stalled {
                summary.warnings.push(format!(
                    "step {index}: the friction threshold loop stalled at a relative change of {change:.1e}, above tol_friction: points at the Coulomb limit alternate between stick and slip from pass to pass; the step is accepted with the last pass's thresholds"
                ));
            }
            if cr.damped_redo {
                summary.warnings.push(format!(
                    "step {index}: the plain contact loops failed or accepted more than a tenth of the points in contact against the Coulomb law, so the step was redone from its start with damped Newton steps (docs/contact-algorithms.md, \"Damped redo of a friction step\"); its iteration counts include both runs"
                ));
            }
            if let Some(p) = cr.pairing.filter(|p| p.outside + p.far + p.failed > 0) {
                summary.warnings.push(format!(
                    "step {index}: {} contact points are beside the master lip, {} have no master facet within the band and {} could not be projected: out of contact",
                    p.outside, p.far, p.failed
                ));
            }
        }
        let clock = Instant::now();
        // The body on its sub-cells when cracked (its stresses are the enriched ones).
        let grid = if cracked {
            let g = xfem_output::cracked_body_grid_of(model, s.u, piece.as_deref());
            info.max_von_mises = g
                .cell_data
                .iter()
                .find(|a| a.name == "von_mises")
                .map_or(0.0, |a| a.values.iter().cloned().fold(0.0, f64::max));
            // The lips' points too: where the lips slide, a lip can move more than any node.
            if let Some(d) = g.point_data.iter().find(|a| a.name == "displacement") {
                let lips = d.values.chunks(3).map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
                info.max_displacement = lips.fold(info.max_displacement, f64::max);
            }
            if piece.is_some() {
                info.max_von_mises = max_over_ranks(info.max_von_mises);
                info.max_displacement = max_over_ranks(info.max_displacement);
            }
            g
        } else {
            let base = match &piece {
                // A piece of a partition that can change between the entries of a growth run.
                Some(keep) => grid_of_mesh_cells(mesh, Some(keep)),
                None => self.base.get_or_insert_with(|| grid_of_mesh(mesh)).clone(),
            };
            body_grid(base, mesh, &s.u[..n_std], &fields)
        };
        // The stray normal force is warned about where the crack carries load against the
        // body's stresses on its sub-cells: the standard-only field of a cut cell smears
        // the lips' slide over the cell (E·slide/h: 2.9e9 Pa against 4.9e3 on the sub-cells
        // of a steel block sliding by 1e-3 m), which silenced the warning at E/p = 2.1e8.
        for w in &stray_shares {
            if w.peak > NEGLIGIBLE_PRESSURE * info.max_von_mises {
                summary.warnings.push(format!(
                    "step {index}: {}: {:.2}% of the normal force is carried at open points or as tension at closed ones, and open points carry a compressive multiplier up to {:.1}% of the largest pressure (the contact law holds per multiplier packet, not at each point): the statuses there, the friction force (closed points only) and the SIFs nearby can be off; a rho_n nearer E/h, smaller load steps or a finer mesh along the crack usually remove it",
                    w.what,
                    100.0 * w.stray / w.pressed,
                    100.0 * w.open_peak / w.peak,
                ));
            }
        }
        // A contact zone that reaches the end of a slave surface where the body goes on.
        for p in info.contact_pairs.iter().filter(|p| p.closed_at_surface_end > 0) {
            summary.warnings.push(format!(
                "step {index}: contact pair '{}': {} contact points are in contact on the last faces of the slave group '{}' where the body's boundary goes on beyond the group, or next to slave points that had no master facet within reach when paired: the contact zone reaches the end of the slave surface and may extend past it, where contact is not modelled (the bodies can overlap there unseen); extend the slave and master groups (or pair again in the deformed configuration: sliding = \"large\")",
                p.name, p.closed_at_surface_end, p.slave
            ));
        }
        // Stick/slip statuses accepted against the friction law (an accepted status cycle,
        // `docs/contact-algorithms.md`): counted in summary.json and said here.
        if let Some(ci) = &info.contact {
            let named = ci.cracks.iter().map(|c| (&c.name, c.accepted_disagreements, c.active));
            let pairs = info.contact_pairs.iter().map(|p| (&p.name, p.accepted_disagreements, p.active));
            for (name, n, active) in named.chain(pairs).filter(|&(_, n, _)| n > 0) {
                summary.warnings.push(format!(
                    "step {index}: {name}: {n} of its {active} contact points keep a stick/slip status the friction law disagrees with (a status cycle at the stick/slip boundary, accepted by the loops: `accepted_disagreements`): the tangential tractions there break Coulomb's law; smaller load steps or a finer mesh at the stick/slip boundary usually remove it"
                ));
            }
        }
        let mut grid = grid;
        if let Some(m) = &s.motion {
            for (name, field) in [("velocity", m.velocity), ("acceleration", m.acceleration)] {
                let values = if cracked {
                    let g = xfem_output::cracked_body_grid_of(model, field, piece.as_deref());
                    g.point_data.into_iter().find(|a| a.name == "displacement").map(|a| a.values).unwrap_or_default()
                } else {
                    let mut v = vec![0.0; 3 * mesh.n_nodes()];
                    for n in 0..mesh.n_nodes() {
                        v[3 * n..3 * n + mesh.dim].copy_from_slice(&field[n * mesh.dim..(n + 1) * mesh.dim]);
                    }
                    v
                };
                grid.point_data.push(DataArray { name: name.into(), components: 3, values });
            }
        }
        let checked = guard::check_grid(&grid, "the body grid");
        // Every rank checked its own piece: all leave together if one found a bad value.
        let checked = match (&piece, checked) {
            (Some(_), Ok(())) if on_any_rank(false) => {
                Err("the body grid: a non-finite value in another rank's piece (its message is on that rank's standard error)".to_string())
            }
            (Some(_), Err(e)) => {
                on_any_rank(true);
                eprintln!("rank {rank}: {e}");
                Err(e)
            }
            (_, c) => c,
        };
        finite(checked)?;
        finite(guard::check_step(&info))?;
        // The crack lips with their fields (written, or kept in memory).
        let lips_grid = if cracked && (case.output.vtu || self.fields.is_some()) {
            let mut g = xfem_output::crack_lips_grid(model, s.u);
            if let Some(c) = &contact {
                post::contact_output::add_contact_fields(&mut g, model, c, s.u, s.contact_state, s.pairing);
            }
            finite(guard::check_grid(&g, "the crack lips grid"))?;
            Some(g)
        } else {
            None
        };
        // An MPI run: every rank writes its piece of the body.
        let pieces = match self.pieces.as_ref() {
            Some((p, _)) => {
                // The grid is this rank's piece already (`piece`): its points compacted.
                let keep = vec![true; grid.num_cells()];
                let file = format!("{}_step{:04}_{}.vtu", case.name, index, p.rank);
                // Rank 0 creates the directory too; whichever rank comes first.
                std::fs::create_dir_all(&p.dir).map_err(|e| format!("{}: {e}", p.dir.display()))?;
                vtu::write_vtu(&p.dir.join(&file), &grid.subset(&keep), case.output.compression)
                    .map_err(|e| format!("{file}: {e}"))?;
                Some((0..p.size).map(|r| format!("{}_step{:04}_{r}.vtu", case.name, index)).collect::<Vec<_>>())
            }
            None => None,
        };
        if case.output.vtu {
            let out_dir = self.out_dir;
            let file = match &pieces {
                Some(files) => {
                    let file = format!("{}_step{:04}.pvtu", case.name, index);
                    vtu::write_pvtu(&out_dir.join(&file), &grid, files).map_err(|e| format!("{file}: {e}"))?;
                    file
                }
                None => {
                    let file = format!("{}_step{:04}.vtu", case.name, index);
                    vtu::write_vtu(&out_dir.join(&file), &grid, case.output.compression)
                        .map_err(|e| format!("{file}: {e}"))?;
                    file
                }
            };
            self.pvd.push(PvdEntry { time, part: 0, file: file.clone(), name: Some("body".into()) });
            if let Some(g) = &lips_grid {
                let lips = format!("{}_crack_step{:04}.vtu", case.name, index);
                vtu::write_vtu(&out_dir.join(&lips), g, case.output.compression).map_err(|e| format!("{lips}: {e}"))?;
                self.pvd.push(PvdEntry { time, part: 1, file: lips, name: Some("crack".into()) });
                self.pvd.push(PvdEntry {
                    time,
                    part: 2,
                    file: self.levelset_file.clone(),
                    name: Some("levelsets".into()),
                });
            }
            if let Some(g) = contact
                .as_ref()
                .and_then(|c| post::contact_output::contact_pairs_grid(model, c, s.u, s.contact_state, s.pairing))
            {
                let file = format!("{}_contact_step{:04}.vtu", case.name, index);
                finite(guard::check_grid(&g, "the contact pairs grid"))?;
                vtu::write_vtu(&out_dir.join(&file), &g, case.output.compression)
                    .map_err(|e| format!("{file}: {e}"))?;
                self.pvd.push(PvdEntry { time, part: 3, file, name: Some("contact".into()) });
            }
            let pvd_name = &self.pvd_name;
            vtu::write_pvd(&out_dir.join(pvd_name), &self.pvd).map_err(|e| format!("{pvd_name}: {e}"))?;
            info.vtu = Some(file);
            summary.pvd = Some(pvd_name.clone());
        }
        terminal.print(&step_table(&info, self.n_steps, mesh.dim, &summary.warnings[n_warnings..]));
        if let Some(fields) = self.fields.as_mut() {
            fields.push(StepFields { index, displacement: s.u[..n_std].to_vec(), lips: lips_grid });
        }
        summary.steps.push(info);
        self.output_s += clock.elapsed().as_secs_f64();
        Ok(())
    }
}

/// The stress intensity factors along the front of crack `k` at a solved step `s`, with
/// the face tractions on the + lip in the interaction integral: the crack's pressure at
/// the step's load factor, plus the contact tractions.
pub(crate) fn crack_front(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    s: &statics::StepSolution<'_>,
    k: usize,
    sif_opts: &sif::SifOptions,
) -> Vec<sif::SifPoint> {
    let facets = &model.cracks[k].cut.facets;
    let pressure = model.crack_pressure[k].as_ref();
    let t = s.report.load_factor;
    let contact_crack = contact.and_then(|c| c.points.cracks.iter().position(|cc| cc.crack == k).map(|ci| (c, ci)));
    let traction = |f: usize, x: [f64; 3]| {
        let p = pressure.map_or(0.0, |p| p.eval_load(x, t));
        let n = facets[f].normal;
        let mut tr = [p * n[0], p * n[1], p * n[2]];
        if let Some((c, ci)) = contact_crack {
            let tc = crate::contact::face_traction(&c.points, ci, &facets[f], f, x, s.u);
            for i in 0..3 {
                tr[i] += tc[i];
            }
        }
        tr
    };
    sif::crack_sifs(model, k, s.u, Some(&traction), sif_opts)
}

/// Per contact crack, the resultant contact force on the slave body of a meshed pair ([0; 3]
/// for a crack): the contact kernel's residual at the step's solution, over the pair's
/// elements (its facets and its projected-gap packets), summed at the standard dofs of the
/// slave body's nodes (the partition of unity: a rigid translation of the body has those
/// dofs at 1 and every other at 0, so this is the force the pair exerts on the body in the
/// equilibrium equations). A sum of λ n over the slave points would not be: the multipliers
/// are nodal and the law holds per packet, so a packet that straddles the edge of the
/// contact, or of the master surface, transmits λ − ρ_n d_n through its closed points and
/// leaves a λ at its open or unpaired ones (`docs/contact-algorithms.md`, "Meshed contact
/// pairs").
fn pair_resultants(model: &Model<'_>, c: &ContactSetup, s: &statics::StepSolution<'_>) -> Vec<[f64; 3]> {
    use crate::assembly::{Kernel, LocalOut};
    let pts = &c.points;
    let mesh = model.mesh;
    let dim = mesh.dim;
    let n_std = dim * mesh.n_nodes();
    let mut out = vec![[0.0; 3]; pts.cracks.len()];
    if pts.cracks.iter().all(|cc| cc.pair.is_none()) {
        return out;
    }
    let kernel = crate::contact::kernel::ContactKernel {
        mesh,
        enrichment: &model.enrichment,
        cracks: &model.cracks,
        points: pts,
        state: s.contact_state,
        u: s.u,
        pairing: s.pairing,
        live_thresholds: false,
    };
    let (comp, _) = crate::physics::constraints::node_components(mesh);
    // The slave body (or bodies) of each pair.
    let slave_bodies: Vec<Vec<usize>> = pts
        .cracks
        .iter()
        .map(|cc| {
            let mut b: Vec<usize> =
                cc.pair.as_ref().map_or_else(Vec::new, |p| p.slave_nodes.iter().map(|&a| comp[a]).collect());
            b.sort_unstable();
            b.dedup();
            b
        })
        .collect();
    let nf = pts.facets.len();
    let (mut dofs, mut vector) = (Vec::new(), Vec::new());
    for e in 0..nf + pts.packets.len() {
        let ci = if e < nf { pts.facets[e].0 } else { pts.packets[e - nf].crack };
        if pts.cracks[ci].pair.is_none() {
            continue;
        }
        dofs.clear();
        kernel.dofs(e, &mut dofs);
        vector.clear();
        vector.resize(dofs.len(), 0.0);
        kernel.compute(e, &dofs, LocalOut { matrix: None, vector: Some(&mut vector) });
        for (&d, &r) in dofs.iter().zip(&vector) {
            let d = d as usize;
            if d < n_std && slave_bodies[ci].binary_search(&comp[d / dim]).is_ok() {
                out[ci][d % dim] += r;
            }
        }
    }
    out
}

/// The points of a meshed pair (`mine`) in contact on a slave facet at the end of the
/// modelled slave surface: a facet that ends the slave group where the body's boundary goes
/// on ([`crate::contact::surfaces::PairSurfaces::slave_open_edge`]), or that shares a node
/// with a facet holding a point with no master facet within reach when the pair was paired
/// (`Far`: in small sliding it stays unpaired whatever the bodies do).
fn closed_at_surface_end(
    pair: &crate::contact::surfaces::PairSurfaces,
    mine: &[usize],
    pts: &crate::contact::points::ContactPoints,
    st: &[Status],
    vals: &[crate::contact::state::PointValues],
    pairing: Option<&crate::contact::pairing::Pairing>,
) -> usize {
    use crate::contact::pairing::PointPairing;
    let mut far_nodes: Vec<usize> = mine
        .iter()
        .filter(|&&p| pairing.is_some_and(|pr| matches!(pr.points[p], PointPairing::Far)))
        .flat_map(|&p| pair.slave[pts.points[p].facet].vertex_nodes.iter().flatten().copied())
        .collect();
    far_nodes.sort_unstable();
    far_nodes.dedup();
    mine.iter()
        .filter(|&&p| st[p] != Status::Open && vals[p].paired)
        .filter(|&&p| {
            let f = pts.points[p].facet;
            pair.slave_open_edge[f]
                || pair.slave[f].vertex_nodes.iter().flatten().any(|a| far_nodes.binary_search(a).is_ok())
        })
        .count()
}

/// The contact figures of each contact crack at a solved step, and the values along it
/// for the plots.
fn contact_per_crack(
    case: &Case,
    model: &Model<'_>,
    c: &ContactSetup,
    s: &statics::StepSolution<'_>,
) -> (Vec<ContactCrackInfo>, Vec<ContactProfile>, Vec<ContactPairInfo>) {
    use crate::contact::state::{point_values, statuses};
    let pts = &c.points;
    let vals = point_values(model, pts, s.pairing, s.contact_state, s.u);
    let st = statuses(pts, s.contact_state, &vals);
    let mut infos = vec![];
    let mut profiles = vec![];
    let mut pairs = vec![];
    let mut slave_resultant: Option<Vec<[f64; 3]>> = None;
    for (ci, cc) in pts.cracks.iter().enumerate() {
        let name = match &cc.pair {
            Some(p) => p.name.clone(),
            None => case.cracks.get(cc.crack).map_or_else(|| format!("crack {}", cc.crack), |d| d.name.clone()),
        };
        let mine: Vec<usize> = (0..pts.points.len()).filter(|&p| pts.points[p].crack == ci).collect();
        let count = |x: Status| mine.iter().filter(|&&p| st[p] == x).count();
        let disagreeing =
            s.report.contact.as_ref().and_then(|r| r.accepted_disagreements.get(ci).copied()).unwrap_or(0);
        let lambda = mine.iter().map(|&p| vals[p].lambda);
        let (lo, hi) = lambda.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), l| (a.min(l), b.max(l)));
        if let Some(pair) = &cc.pair {
            let def = &case.contact_pairs[pair.index];
            let mut tangential = [0.0; 3];
            for &p in &mine {
                let (pt, v) = (&pts.points[p], &vals[p]);
                if !v.paired {
                    continue;
                }
                for i in 0..3 {
                    let mut t = 0.0;
                    for a in 0..pts.dim - 1 {
                        t += cc.law.friction * v.lambda * v.big_lambda[a] * pt.tangents[a][i];
                    }
                    tangential[i] -= pt.weight * t;
                }
            }
            let force = slave_resultant.get_or_insert_with(|| pair_resultants(model, c, s))[ci];
            let counts = s.pairing.map(|pr| {
                let mut k = crate::run::summary::PairingInfo::default();
                for &p in &mine {
                    match pr.points[p] {
                        crate::contact::pairing::PointPairing::Paired(_) => k.paired += 1,
                        crate::contact::pairing::PointPairing::Dormant(_) => {
                            k.paired += 1;
                            k.zone_out += 1;
                        }
                        crate::contact::pairing::PointPairing::OutsideLip => k.outside += 1,
                        crate::contact::pairing::PointPairing::Far => k.far += 1,
                        crate::contact::pairing::PointPairing::Failed => k.failed += 1,
                    }
                }
                k.warnings = k.outside + k.far + k.failed;
                k
            });
            pairs.push(ContactPairInfo {
                name: name.clone(),
                slave: def.slave.clone(),
                master: def.master.clone(),
                method: cc.law.method.name().to_string(),
                points: mine.len(),
                active: mine.len() - count(Status::Open),
                stick: count(Status::Stick),
                slip: count(Status::Slip),
                lambda_min: if mine.is_empty() { 0.0 } else { lo },
                lambda_max: if mine.is_empty() { 0.0 } else { hi },
                unknowns: if cc.law.method.has_multipliers() { cc.space.n_unknowns * pts.dim } else { 0 },
                accepted_disagreements: disagreeing,
                pairing: counts,
                normal_force: -mine.iter().map(|&p| pts.points[p].weight * vals[p].lambda).sum::<f64>(),
                tangential_force: tangential.iter().map(|t| t * t).sum::<f64>().sqrt(),
                force_on_slave: force,
                closed_at_surface_end: closed_at_surface_end(pair, &mine, pts, &st, &vals, s.pairing),
                wear: crate::post::contact_output::wear_figures_of(c, s.contact_state, |k| k == ci).map(|w| {
                    crate::run::summary::WearInfo {
                        max: w.max,
                        mean: w.mean,
                        volume: w.volume,
                        frictional_work: w.frictional_work,
                    }
                }),
                ..Default::default()
            });
        } else {
            infos.push(ContactCrackInfo {
                name: name.clone(),
                points: mine.len(),
                active: mine.len() - count(Status::Open),
                stick: count(Status::Stick),
                slip: count(Status::Slip),
                lambda_min: if mine.is_empty() { 0.0 } else { lo },
                lambda_max: if mine.is_empty() { 0.0 } else { hi },
                accepted_disagreements: disagreeing,
            });
        }
        // Along the crack (2D): the position along the first point's tangent.
        let tangent = mine.first().map_or([1.0, 0.0, 0.0], |&p| pts.points[p].tangents[0]);
        let along: Vec<f64> = mine.iter().map(|&p| (0..3).map(|i| pts.points[p].x[i] * tangent[i]).sum()).collect();
        let start = along.iter().cloned().fold(f64::INFINITY, f64::min);
        let slip = mine
            .iter()
            .map(|&p| {
                let (j, pt) = (vals[p].jump, &pts.points[p]);
                if pts.dim == 2 {
                    (0..3).map(|i| j[i] * pt.tangents[0][i]).sum()
                } else {
                    let jn: f64 = (0..3).map(|i| j[i] * pt.normal[i]).sum();
                    (0..3).map(|i| (j[i] - jn * pt.normal[i]).powi(2)).sum::<f64>().sqrt()
                }
            })
            .collect();
        profiles.push(ContactProfile {
            step: s.report.index,
            crack: name,
            abscissa: if pts.dim == 2 { along.iter().map(|a| a - start).collect() } else { vec![] },
            pressure: mine.iter().map(|&p| -vals[p].lambda).collect(),
            slip,
        });
    }
    (infos, profiles, pairs)
}

/// The files written after the steps from the summary: `sif.csv`, `contact.csv`, the
/// plots (`[output] plots`; dynamics: `energy.png` from `energy`, the rows of
/// `energy_history.csv`) and, for 3D cracks with VTU output, `<stem>_view.py`.
#[allow(clippy::too_many_arguments)]
fn write_extras(
    case: &Case,
    mesh: &Mesh,
    out_dir: &Path,
    summary: &Summary,
    newton: &[NewtonIteration],
    profiles: &[ContactProfile],
    energy: &[EnergyInfo],
    contact: bool,
) -> Result<(), String> {
    tables::write_tables(summary, out_dir)?;
    if case.output.plots {
        let data = PlotData { summary, newton, contact: profiles, energy };
        plots::write_plots(&data, out_dir)?;
    }
    let front = summary.steps.last().and_then(|s| s.cracks.iter().find(|c| !c.front.is_empty()));
    if let (3, true, Some(front), Some(pvd)) = (mesh.dim, case.output.vtu, front, &summary.pvd) {
        let n = front.front.len() as f64;
        let mut centre = [0.0; 3];
        let mut normal = [0.0; 3];
        for p in &front.front {
            for i in 0..3 {
                centre[i] += p.x[i] / n;
                normal[i] += p.e2[i];
            }
        }
        let crack_size = front
            .front
            .iter()
            .map(|p| (0..3).map(|i| (p.x[i] - centre[i]).powi(2)).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        let len = normal.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
        normal.iter_mut().for_each(|v| *v /= len);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &mesh.nodes {
            for i in 0..3 {
                lo[i] = lo[i].min(x[i]);
                hi[i] = hi[i].max(x[i]);
            }
        }
        let size = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
        let spec = ViewSpec {
            stem: case.name.clone(),
            pvd: pvd.clone(),
            crack_centre: centre,
            crack_normal: normal,
            crack_size,
            size,
            max_displacement: summary.steps.iter().map(|s| s.max_displacement).fold(0.0, f64::max),
            contact,
        };
        let abs = std::path::absolute(out_dir).unwrap_or_else(|_| out_dir.to_path_buf());
        paraview_view::write_view_script(&spec, out_dir, &abs).map_err(|e| format!("{}_view.py: {e}", case.name))?;
    }
    Ok(())
}

/// The initial displacement and velocity of a dynamic case: on a model without cracks the
/// values at the nodes of each group (later entries win); with cracks the L2 projection with
/// the consistent mass over the cells whose nodes all lie in the group (so a field that
/// jumps across a crack or interface is represented exactly on the enriched basis).
fn initial_state(case: &Case, model: &Model<'_>, options: &SolveOptions) -> Result<InitialState, RunError> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let field = |defs: &[crate::case::InitialFieldDef]| -> Result<Vec<f64>, RunError> {
        let mut node_def = vec![u32::MAX; mesh.n_nodes()];
        let mut in_group = vec![vec![false; mesh.n_nodes()]; defs.len()];
        for (k, d) in defs.iter().enumerate() {
            if d.n_components != dim {
                return Err(RunError::Case(
                    case.attribute(d.at.error("value", format!("{} components for a {dim}D model", d.n_components))),
                ));
            }
            let nodes = mesh
                .group_nodes(&d.group)
                .map_err(|e| RunError::Case(case.attribute(d.at.error("group", e.to_string()))))?;
            for n in nodes {
                node_def[n] = k as u32;
                in_group[k][n] = true;
            }
        }
        if defs.is_empty() {
            return Ok(vec![]);
        }
        let value = |k: u32, x: [f64; 3]| {
            let d = &defs[k as usize];
            let mut v = [0.0; 3];
            for i in 0..dim {
                v[i] = d.value[i].eval(x, 0.0);
            }
            v
        };
        let out = if model.enrichment.dofs.n_total() == dim * mesh.n_nodes() {
            let mut u = vec![0.0; dim * mesh.n_nodes()];
            for (n, &k) in node_def.iter().enumerate() {
                if k != u32::MAX {
                    u[n * dim..(n + 1) * dim].copy_from_slice(&value(k, mesh.nodes[n])[..dim]);
                }
            }
            u
        } else {
            // Per cell: the last definition whose group holds every node of the cell.
            let cell_def: Vec<u32> = mesh
                .cells
                .iter()
                .map(|c| {
                    (0..defs.len())
                        .rev()
                        .find(|&k| c.nodes().iter().all(|&n| in_group[k][n]))
                        .map_or(u32::MAX, |k| k as u32)
                })
                .collect();
            let g = |c: usize, x: [f64; 3]| (cell_def[c] != u32::MAX).then(|| value(cell_def[c], x));
            dynamics::project_field(model, &g, options).map_err(RunError::Solve)?
        };
        if let Some(bad) = out.iter().position(|v| !v.is_finite()) {
            let d = &defs[node_def.get(bad / dim).copied().filter(|&k| k != u32::MAX).unwrap_or(0) as usize];
            return Err(RunError::Case(
                case.attribute(d.at.error("value", "the initial value is not a finite number")),
            ));
        }
        Ok(out)
    };
    Ok(InitialState { u: field(&case.initial_displacement)?, v: field(&case.initial_velocity)? })
}

fn mesh_info(mesh: &Mesh) -> MeshInfo {
    let mut cell_types = BTreeMap::new();
    for c in &mesh.cells {
        *cell_types.entry(c.kind.name().to_string()).or_insert(0) += 1;
    }
    MeshInfo { nodes: mesh.n_nodes(), elements: mesh.n_cells(), cell_types }
}

fn dof_info(r: &statics::SolveReport, case: &Case) -> DofInfo {
    use crate::assembly::DofKind;
    let mut held_enriched = BTreeMap::new();
    for (d, &n) in case.dirichlet.iter().zip(&r.held_enriched) {
        if n > 0 {
            *held_enriched.entry(d.group.clone()).or_insert(0) += n;
        }
    }
    DofInfo {
        held_enriched,
        total: r.dofs.n_total(),
        standard: r.dofs.count(DofKind::Displacement),
        heaviside: r.dofs.count(DofKind::Heaviside),
        tip: r.dofs.count(DofKind::Tip),
        heaviside_nodes: r.heaviside_nodes,
        tip_nodes: r.tip_nodes,
        dirichlet_multipliers: r.dofs.count(DofKind::DirichletMultiplier),
        contact_multipliers: r.dofs.count(DofKind::ContactMultiplier),
        prescribed: r.n_prescribed,
        equations: r.n_eq,
    }
}

/// Largest nodal displacement magnitude, scaled so that no square overflows.
fn max_norm(u: &[f64], dim: usize) -> f64 {
    u.chunks(dim)
        .map(|c| {
            let m = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if m > 0.0 && m.is_finite() {
                m * c.iter().map(|v| (v / m) * (v / m)).sum::<f64>().sqrt()
            } else {
                m
            }
        })
        .fold(0.0, f64::max)
}

/// This process's MPI rank and the number of ranks of a PETSc run ((0, 1) otherwise).
#[cfg(feature = "petsc")]
fn mpi_rank_size() -> (usize, usize) {
    (crate::solve::petsc::rank(), crate::solve::petsc::size())
}
#[cfg(not(feature = "petsc"))]
fn mpi_rank_size() -> (usize, usize) {
    (0, 1)
}

/// The largest of `local` over the ranks of a PETSc run (an all-reduce: every rank calls
/// it; called only when there are several ranks).
#[cfg(feature = "petsc")]
fn max_over_ranks(local: f64) -> f64 {
    crate::solve::petsc::max_over_ranks(local)
}
#[cfg(not(feature = "petsc"))]
fn max_over_ranks(local: f64) -> f64 {
    local
}

/// Whether `local` holds on some rank of a PETSc run (an all-reduce: every rank calls it;
/// called only when there are several ranks).
#[cfg(feature = "petsc")]
fn on_any_rank(local: bool) -> bool {
    crate::solve::petsc::on_any_rank(local)
}
#[cfg(not(feature = "petsc"))]
fn on_any_rank(local: bool) -> bool {
    local
}

/// The mesh as a VTK grid without data (reused for every step).
pub fn grid_of_mesh(mesh: &Mesh) -> UnstructuredGrid {
    grid_of_mesh_cells(mesh, None)
}

/// [`grid_of_mesh`] with the cells `c` with `keep[c]` only (`None`: every cell): every node
/// stays a point.
fn grid_of_mesh_cells(mesh: &Mesh, keep: Option<&[bool]>) -> UnstructuredGrid {
    use crate::element::CellType;
    let kept = |c: usize| keep.is_none_or(|k| k.get(c).copied().unwrap_or(false));
    let mut g = UnstructuredGrid { points: mesh.nodes.clone(), ..Default::default() };
    for c in mesh.cells.iter().enumerate().filter(|(i, _)| kept(*i)).map(|(_, c)| c) {
        g.connectivity.extend(c.nodes().iter().map(|&n| n as u64));
        g.offsets.push(g.connectivity.len() as u64);
        g.kinds.push(match c.kind {
            CellType::Tri3 => VtkCell::Triangle,
            CellType::Quad4 => VtkCell::Quad,
            CellType::Tet4 => VtkCell::Tetra,
            CellType::Hex8 => VtkCell::Hexahedron,
        });
    }
    // Group id of each cell: index of the first cell group (sorted by name) holding it, −1 if none.
    let mut group = vec![-1.0; mesh.n_cells()];
    for (k, cells) in mesh.cell_groups.values().enumerate().rev() {
        for &c in cells {
            group[c] = k as f64;
        }
    }
    if keep.is_some() {
        group = group.into_iter().enumerate().filter(|(c, _)| kept(*c)).map(|(_, v)| v).collect();
    }
    g.cell_data.push(DataArray { name: "group_id".into(), components: 1, values: group });
    g
}

/// The rank that writes each mesh cell's part of the body in an MPI run of `size` ranks
/// ([`Pieces`]): the distributed assembly's partition when there was one, else contiguous
/// blocks of the mesh order.
fn cell_ranks(n_cells: usize, size: usize) -> Vec<u32> {
    #[cfg(feature = "petsc")]
    if let Some(part) = crate::solve::petsc::partition::recorded_cells().filter(|p| p.len() == n_cells) {
        return part;
    }
    (0..n_cells).map(|c| (c * size / n_cells.max(1)) as u32).collect()
}

fn body_grid(base: UnstructuredGrid, mesh: &Mesh, u: &[f64], f: &post::CellFields) -> UnstructuredGrid {
    let dim = mesh.dim;
    let mut g = base;
    let mut disp = vec![0.0; 3 * mesh.n_nodes()];
    for n in 0..mesh.n_nodes() {
        disp[3 * n..3 * n + dim].copy_from_slice(&u[n * dim..n * dim + dim]);
    }
    g.point_data.push(DataArray { name: "displacement".into(), components: 3, values: disp });
    g.cell_data.push(DataArray { name: "strain".into(), components: 6, values: f.strain.concat() });
    g.cell_data.push(DataArray { name: "stress".into(), components: 6, values: f.stress.concat() });
    g.cell_data.push(DataArray { name: "von_mises".into(), components: 1, values: f.von_mises.clone() });
    g
}

/// Solves a model built in code (tests, benches): the report and the dof vector of every step.
pub fn solve_model(
    model: &Model<'_>,
    options: &SolveOptions,
) -> Result<(statics::SolveReport, Vec<Vec<f64>>), SolveError> {
    solve_model_with(model, None, options).map(|(r, u, _)| (r, u))
}

/// One solved step as recorded by [`solve_model_recorded`].
#[derive(Debug, Clone)]
pub struct RecordedStep {
    pub u: Vec<f64>,
    pub contact_state: Vec<PointState>,
    /// The pairing the step used (large sliding).
    pub pairing: Option<crate::contact::pairing::Pairing>,
}

/// Like [`solve_model_with`], recording the pairing of each step too.
pub fn solve_model_recorded(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
) -> Result<(statics::SolveReport, Vec<RecordedStep>), SolveError> {
    let mut steps = vec![];
    let report = statics::solve_load_steps(model, contact, options, &mut |s: statics::StepSolution<'_>| {
        steps.push(RecordedStep {
            u: s.u.to_vec(),
            contact_state: s.contact_state.to_vec(),
            pairing: s.pairing.cloned(),
        });
        Ok(())
    })?;
    Ok((report, steps))
}

/// Like [`solve_model`] with contact: also the contact state of every step.
#[allow(clippy::type_complexity)]
pub fn solve_model_with(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
) -> Result<(statics::SolveReport, Vec<Vec<f64>>, Vec<Vec<PointState>>), SolveError> {
    let mut sols = vec![];
    let mut states = vec![];
    let report = statics::solve_load_steps(model, contact, options, &mut |s: statics::StepSolution<'_>| {
        sols.push(s.u.to_vec());
        states.push(s.contact_state.to_vec());
        Ok(())
    })?;
    Ok((report, sols, states))
}
