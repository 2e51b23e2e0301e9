//! Case files (TOML): reading, validating and resolving them against a mesh.
//!
//! Entry points: [`Case::from_file`] / [`Case::parse`] (text → typed, validated
//! [`Case`]), and [`resolve::build_mesh`] / [`resolve::build_model`] (Case + mesh →
//! [`crate::physics::model::Model`]). Every key is documented in
//! `docs/case-format.md`; unknown keys are errors; every error names the key and line.

pub mod overrides;
pub mod reader;
pub mod resolve;

use crate::contact::law::{Asperity, Method, Wear, WearCoupling};
use crate::contact::multipliers::LbbStrategy;
use crate::contact::points::{ContactCrackOptions, ContactFormulation, ContactIntegration, Sliding};
use crate::contact::zone::ZoneChoice;
use crate::contact::{ContactAlgorithm, ContactLoops};
use crate::element::CellType;
use crate::enrich::{TipEnrichment, COVERING_NODE_SHARE};
use crate::formula::Scalar;
use crate::growth::{Criterion, Fatigue, Propagation};
use crate::io::vtu::Compression;
use crate::levelset::CrackShape;
use crate::physics::elasticity::FaceLoad;
use crate::physics::material::{Analysis, Isotropic};
use crate::physics::model::DirichletMethod;
use crate::physics::xfem::XfemQuadrature;
use crate::solve::linear::{Backend, LinearMethod, OrderingChoice, PetscSettings, Precision};
use reader::{Source, Table};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use toml_edit::{Item, Value};

/// An error in a case file: the file, the line (when known), the key path and what is wrong.
/// For an error in a command-line override, `file` is the override (`--set KEY=VALUE`)
/// and `line` is `None`.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseError {
    pub file: String,
    pub line: Option<usize>,
    pub key: String,
    pub message: String,
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            // An override names its key itself: `--set a.b=1: message`.
            None if self.file.starts_with("--set ") => write!(f, "{}: {}", self.file, self.message),
            Some(l) => write!(f, "{}:{}: key '{}': {}", self.file, l, self.key, self.message),
            None => write!(f, "{}: key '{}': {}", self.file, self.key, self.message),
        }
    }
}

impl std::error::Error for CaseError {}

/// Largest number of load steps (`steps.count`): each step is a solve and a set of files.
pub const MAX_STEPS: usize = 1_000_000;

/// Where the mesh comes from.
#[derive(Debug, Clone)]
pub enum MeshSource {
    /// A Gmsh MSH 4.1 file (path resolved relative to the case file).
    File(PathBuf),
    /// A structured rectangle (2D) or box (3D).
    Generated { cell: CellType, lower: [f64; 3], upper: [f64; 3], divisions: [usize; 3] },
    /// Several generated blocks, one body each (`[[mesh.parts]]`), sharing no nodes.
    Parts(Vec<PartDef>),
}

/// What a formula-defined set selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetKind {
    Nodes,
    Faces,
    Cells,
}

/// A group defined by formulas: entities where `|on| ≤ tol` and `inside ≤ tol`.
#[derive(Debug, Clone)]
pub struct SetDef {
    pub name: String,
    pub kind: SetKind,
    pub on: Option<Scalar>,
    pub inside: Option<Scalar>,
    /// Absolute tolerance (None: 1e-6 × the typical cell size).
    pub tolerance: Option<f64>,
    pub at: Located,
}

/// Where a definition sits in the case file, for errors found after reading
/// (unknown groups, components that do not exist in 2D).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Located {
    pub file: String,
    pub key: String,
    pub line: Option<usize>,
}

impl Located {
    pub fn error(&self, field: &str, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.clone(),
            line: self.line,
            key: format!("{}.{}", self.key, field),
            message: message.into(),
        }
    }
}

#[derive(Debug, Clone)]
pub struct MaterialDef {
    pub group: String,
    pub material: Isotropic,
    /// Mass density (mass/volume, > 0), for an implicit dynamic time scheme; `None`: not
    /// given (quasi-static runs do not use it).
    pub density: Option<f64>,
    pub at: Located,
}

#[derive(Debug, Clone)]
pub struct DirichletDef {
    pub group: String,
    /// Components 0 = x, 1 = y, 2 = z.
    pub components: Vec<usize>,
    /// One value per component.
    pub values: Vec<Scalar>,
    /// A prescribed displacement of one lip: the crack's name and the side (+1 / −1).
    pub lip: Option<(String, i8)>,
    pub at: Located,
}

/// A linear relation Σ_k a_k u_{c_k}(node of group k) = value, one per node of the
/// first group (the nodes of the other groups paired by translation).
#[derive(Debug, Clone)]
pub struct RelationDef {
    pub groups: Vec<String>,
    pub components: Vec<usize>,
    pub coefficients: Vec<f64>,
    pub value: Scalar,
    pub at: Located,
}

#[derive(Debug, Clone)]
pub struct FaceLoadDef {
    pub group: String,
    pub load: FaceLoad,
    /// Number of components given (traction), to check against the dimension.
    pub n_components: usize,
    pub at: Located,
}

#[derive(Debug, Clone)]
pub struct BodyForceDef {
    pub group: String,
    pub value: [Scalar; 3],
    pub n_components: usize,
    pub at: Located,
}

/// `[dynamics]`: an implicit time scheme instead of quasi-static load steps.
#[derive(Debug, Clone)]
pub struct DynamicsDef {
    pub scheme: crate::solve::time::DynamicScheme,
    /// Write the VTU files every this many steps (the first and last steps always).
    pub output_every: usize,
    /// Velocity contact formulation: project the displacements back onto the lips'
    /// non-penetration after each step where they overlap (`position_correction`, default
    /// true; `solve::position_correction`).
    pub position_correction: bool,
    /// The mass matrix (`mass = "consistent"` (default) or `"redistributed"`:
    /// [`crate::physics::inertia::MassMatrix`]).
    pub mass: crate::physics::inertia::MassMatrix,
    pub at: Located,
}

/// `[[initial_velocity]]` / `[[initial_displacement]]`: a value (numbers or formulas of
/// x, y, z) on the nodes of a group.
#[derive(Debug, Clone)]
pub struct InitialFieldDef {
    pub group: String,
    pub value: [Scalar; 3],
    pub n_components: usize,
    pub at: Located,
}

/// One crack or interface of the case.
#[derive(Debug, Clone)]
pub struct CrackDef {
    pub name: String,
    pub shape: CrackShape,
    /// Pressure on both crack faces (opens the crack when positive).
    pub pressure: Option<Scalar>,
    pub tip: TipEnrichment,
    /// Radius of the interaction-integral domain (None: three front-cell sizes).
    pub sif_radius: Option<f64>,
    /// Contact on the crack faces (`[cracks.contact]`), when switched on.
    pub contact: Option<ContactCrackOptions>,
    /// With `[propagation]`: whether this crack grows (`grow`, default true).
    pub grow: bool,
    pub at: Located,
    /// Where `[cracks.contact]` `rho_n` was given (for the checks that need the model).
    pub rho_n_at: Option<Located>,
}

/// The `[propagation]` table: crack growth options and where they were given.
#[derive(Debug, Clone)]
pub struct PropagationDef {
    pub options: Propagation,
    pub at: Located,
    /// Where `increment` is (errors found against the mesh name its line).
    pub increment_at: Located,
}

/// Global X-FEM options.
#[derive(Debug, Clone, Copy)]
pub struct XfemDef {
    pub quadrature: XfemQuadrature,
    pub min_side_fraction: f64,
    /// Nodal |φ| below this fraction of the local cell size is set to 0.
    pub snap: f64,
}

#[derive(Debug, Clone)]
pub struct SolverDef {
    pub linear: LinearMethod,
    pub dirichlet: DirichletMethod,
    pub residual_tolerance: f64,
    /// Contact systems: factorise the bulk once and condense onto the crack unknowns.
    pub condense: bool,
    /// The fill-reducing ordering of the direct solver.
    pub ordering: OrderingChoice,
    /// The arithmetic of the direct solver's factor (`[solver] precision`).
    pub precision: Precision,
    /// The linear backend: faer (default) or PETSc (`[solver] backend`, `[solver.petsc]`).
    pub backend: Backend,
}

#[derive(Debug, Clone)]
pub struct OutputDef {
    pub vtu: bool,
    pub compression: Compression,
    /// Write the PNG plots (SIFs, contact profiles, convergence) next to `summary.json`.
    pub plots: bool,
}

/// `[solver] backend` and `[solver.petsc]` (`ksp`, `pc`, `rtol`, `options`).
fn read_backend(s: &reader::Table<'_, '_>) -> Result<Backend, CaseError> {
    let name = s.opt_choice("backend", &["faer", "petsc"])?;
    let petsc = s.opt_table("petsc")?;
    let is_petsc = name.as_deref() == Some("petsc");
    let Some(p) = petsc else {
        if !is_petsc {
            return Ok(Backend::Faer);
        }
        let backend = Backend::Petsc(PetscSettings::default());
        check_backend_available(s, &backend)?;
        return Ok(backend);
    };
    let mut settings = PetscSettings::default();
    let type_name = |key: &str| -> Result<Option<String>, CaseError> {
        match p.opt_str(key)? {
            Some(t) if t.is_empty() || !t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') => {
                Err(p.error(key, format!("\"{t}\" is not a PETSc type name (letters, digits, _)")))
            }
            other => Ok(other),
        }
    };
    settings.ksp = type_name("ksp")?;
    settings.pc = type_name("pc")?;
    if let Some(r) = p.opt_f64("rtol")? {
        if !(r > 0.0 && r < 1.0) {
            return Err(p.error("rtol", "must be in (0, 1)"));
        }
        settings.rtol = r;
    }
    if let Some(o) = p.opt_str("options")? {
        if let Some(bad) = o.split_whitespace().next().filter(|w| !w.starts_with('-')) {
            return Err(p.error(
                "options",
                format!("PETSc options start with '-' (-ksp_monitor, -pc_gamg_threshold 0.05); found '{bad}'"),
            ));
        }
        settings.options = o;
    }
    p.finish(&["ksp", "pc", "rtol", "options"])?;
    if !is_petsc {
        return Err(p.error("ksp", "[solver.petsc] is read only with backend = \"petsc\" in [solver]"));
    }
    let backend = Backend::Petsc(settings);
    check_backend_available(s, &backend)?;
    Ok(backend)
}

/// `backend = "petsc"` needs the `petsc` feature.
fn check_backend_available(s: &reader::Table<'_, '_>, backend: &Backend) -> Result<(), CaseError> {
    if !matches!(backend, Backend::Petsc(_)) {
        return Ok(());
    }
    if !cfg!(feature = "petsc") {
        return Err(s.error(
            "backend",
            "backend = \"petsc\" needs fissure built with the cargo feature `petsc` \
             (cargo build --release --features petsc; it needs PETSc and MPI: README, \"Running on a cluster\")",
        ));
    }
    Ok(())
}

/// A validated case.
#[derive(Debug, Clone)]
pub struct Case {
    /// The case file path as given.
    pub path: PathBuf,
    /// File stem, used for output names.
    pub name: String,
    pub parameters: BTreeMap<String, f64>,
    /// `None`: plane strain for 2D meshes, 3D for 3D meshes.
    pub analysis: Option<Analysis>,
    pub analysis_at: Located,
    pub mesh: MeshSource,
    pub mesh_at: Located,
    pub sets: Vec<SetDef>,
    pub materials: Vec<MaterialDef>,
    pub dirichlet: Vec<DirichletDef>,
    pub relations: Vec<RelationDef>,
    pub face_loads: Vec<FaceLoadDef>,
    pub body_forces: Vec<BodyForceDef>,
    pub load_factors: Vec<f64>,
    pub cracks: Vec<CrackDef>,
    /// Contact pairs between boundary surfaces of meshed bodies (`[[contact_pairs]]`).
    pub contact_pairs: Vec<ContactPairDef>,
    pub xfem: XfemDef,
    pub contact_loops: ContactLoops,
    pub solver: SolverDef,
    pub output: OutputDef,
    /// Crack growth (`[propagation]`), when given.
    pub propagation: Option<PropagationDef>,
    /// `[dynamics]`: `None` runs quasi-static load steps.
    pub dynamics: Option<DynamicsDef>,
    pub initial_velocity: Vec<InitialFieldDef>,
    pub initial_displacement: Vec<InitialFieldDef>,
    /// The file's text and the command-line overrides applied to it, to attribute the
    /// errors found after reading ([`Case::attribute`]).
    pub origin: overrides::Origin,
}

/// A meshed contact pair (`[[contact_pairs]]`): slave and master boundary face groups and
/// the contact options of `[cracks.contact]`.
#[derive(Debug, Clone)]
pub struct ContactPairDef {
    pub name: String,
    pub slave: String,
    pub master: String,
    pub options: ContactCrackOptions,
    pub at: Located,
}

fn component_index(name: &str) -> Option<usize> {
    match name {
        "x" | "ux" => Some(0),
        "y" | "uy" => Some(1),
        "z" | "uz" => Some(2),
        _ => None,
    }
}

/// A structured generator block: cell type, corners and divisions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeneratorSpec {
    pub cell: CellType,
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    pub divisions: [usize; 3],
}

/// One part of a multi-body mesh (`[[mesh.parts]]`): a generated block moved by `offset`.
#[derive(Debug, Clone)]
pub struct PartDef {
    /// Prefix of the part's groups (`<name>.top`, …) and name of its cell group.
    pub name: String,
    pub spec: GeneratorSpec,
    pub offset: [f64; 3],
    pub at: Located,
}

impl PartDef {
    /// Lower and upper corners after the offset.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = self.spec.lower;
        let mut hi = self.spec.upper;
        for k in 0..3 {
            lo[k] += self.offset[k];
            hi[k] += self.offset[k];
        }
        (lo, hi)
    }
}

/// Reads a generator block (`[mesh]` or one `[[mesh.parts]]`); `extra` are the other keys
/// the table may hold.
fn read_generator(m: &Table<'_, '_>, extra: &[&str]) -> Result<GeneratorSpec, CaseError> {
    let generator = m.opt_choice("generator", &["rectangle", "box"])?.ok_or_else(|| {
        let mut e = m.error("generator", "missing key 'generator' (rectangle or box) or 'file'");
        e.line = m.line;
        e
    })?;
    let dim = if generator == "rectangle" { 2 } else { 3 };
    let cell = m.req_str("cell", "cell type")?;
    let cell = match (dim, cell.as_str()) {
        (2, "tri3") => CellType::Tri3,
        (2, "quad4") => CellType::Quad4,
        (3, "tet4") => CellType::Tet4,
        (3, "hex8") => CellType::Hex8,
        _ => {
            let ok = if dim == 2 { "tri3, quad4" } else { "tet4, hex8" };
            return Err(m.error("cell", format!("'{cell}' is not a {generator} cell type ({ok})")));
        }
    };
    let get3 = |key: &str, default: Option<f64>| -> Result<[f64; 3], CaseError> {
        let v = m.opt_f64_array(key)?;
        let v = match (v, default) {
            (Some(v), _) => v,
            (None, Some(d)) => vec![d; dim],
            (None, None) => {
                let mut e = m.error(key, format!("missing key '{key}' ({dim} numbers)"));
                e.line = m.line;
                return Err(e);
            }
        };
        if v.len() != dim {
            return Err(m.error(key, format!("expected {dim} numbers for a {generator}, found {}", v.len())));
        }
        let mut out = [0.0; 3];
        out[..dim].copy_from_slice(&v);
        Ok(out)
    };
    let lower = get3("lower", Some(0.0))?;
    let upper = get3("upper", None)?;
    for k in 0..dim {
        if !(upper[k] > lower[k]) {
            return Err(m.error("upper", format!("upper[{k}] must be greater than lower[{k}]")));
        }
    }
    let div = m.opt_usize_array("divisions")?.ok_or_else(|| {
        let mut e = m.error("divisions", format!("missing key 'divisions' ({dim} integers)"));
        e.line = m.line;
        e
    })?;
    if div.len() != dim || div.contains(&0) {
        return Err(m.error("divisions", format!("expected {dim} positive integers")));
    }
    let mut divisions = [1; 3];
    divisions[..dim].copy_from_slice(&div);
    let mut known = vec!["generator", "cell", "lower", "upper", "divisions"];
    known.extend_from_slice(extra);
    m.finish(&known)?;
    Ok(GeneratorSpec { cell, lower, upper, divisions })
}

/// The contact keys of `[cracks.contact]` and of a `[[contact_pairs]]` entry (`pair`), in
/// table `c`; `label` names the crack or pair in messages, `extra` are the table's other keys.
fn read_contact_options(
    c: &Table<'_, '_>,
    label: &str,
    pair: bool,
    extra: &[&str],
    implicit: bool,
) -> Result<ContactCrackOptions, CaseError> {
    let friction = c.opt_f64("friction")?.unwrap_or(0.0);
    if !(friction >= 0.0) || !friction.is_finite() {
        return Err(c.error("friction", format!("{label}: the Coulomb coefficient must be ≥ 0")));
    }
    let positive = |key: &str| -> Result<Option<f64>, CaseError> {
        let v = c.opt_f64(key)?;
        if v.is_some_and(|v| !(v > 0.0) || !v.is_finite()) {
            return Err(c.error(key, format!("{label}: must be positive")));
        }
        Ok(v)
    };
    let rho_n = positive("rho_n")?;
    let rho_t = positive("rho_t")?;
    let initial_threshold = c.opt_f64("initial_threshold")?.unwrap_or(0.0);
    if !(initial_threshold >= 0.0) {
        return Err(c.error("initial_threshold", format!("{label}: a pressure ≥ 0")));
    }
    let start_closed = c.opt_bool("start_closed")?.unwrap_or(true);
    let integration = match c.opt_choice("integration", &["gauss", "vertex", "nodes"])?.as_deref() {
        Some("vertex") => ContactIntegration::Vertex,
        Some("nodes") => ContactIntegration::Nodes,
        _ => ContactIntegration::Gauss,
    };
    if pair && c.has("lbb") {
        return Err(c.error("lbb", format!("{label}: the multipliers of a contact pair are nodal on the slave surface; 'lbb' is a key of crack contact")));
    }
    let lbb = match c.opt_choice("lbb", &["vital_edge", "vital_vertex", "none"])?.as_deref() {
        Some("vital_vertex") => LbbStrategy::VitalVertex,
        Some("none") => LbbStrategy::None,
        _ => LbbStrategy::VitalEdge,
    };
    let sliding = match c.opt_choice("sliding", &["small", "large"])?.as_deref() {
        Some("large") => Sliding::Large,
        _ => Sliding::Small,
    };
    let method = match c.opt_choice("method", &["augmented_lagrangian", "stabilised", "penalty"])?.as_deref() {
        Some("stabilised") => Method::Stabilised,
        Some("penalty") => Method::Penalty,
        _ => Method::AugmentedLagrangian,
    };
    let kappa_n = positive("kappa_n")?;
    let kappa_t = positive("kappa_t")?;
    if method == Method::AugmentedLagrangian {
        for (key, v) in [("kappa_n", kappa_n), ("kappa_t", kappa_t)] {
            if v.is_some() {
                return Err(c.error(
                    key,
                    format!("{label}: {key} is a parameter of method = \"stabilised\" or \"penalty\", not of the augmented Lagrangian"),
                ));
            }
        }
    }
    let initial_gap = c.opt_f64("initial_gap")?.unwrap_or(0.0);
    if !(initial_gap >= 0.0) || !initial_gap.is_finite() {
        return Err(c.error("initial_gap", format!("{label}: a length ≥ 0")));
    }
    let asperity = match c.opt_table("asperity")? {
        None => None,
        Some(a) => {
            let thickness = a.req_f64("thickness", "the layer thickness a (length ≥ 0)")?;
            if !(thickness >= 0.0) || !thickness.is_finite() {
                return Err(a.error("thickness", format!("{label}: a length ≥ 0")));
            }
            let stiffness = a.req_f64("stiffness", "the layer stiffness κ_n (stress/length², > 0)")?;
            if !(stiffness > 0.0) || !stiffness.is_finite() {
                return Err(a.error("stiffness", format!("{label}: must be positive (stress/length²)")));
            }
            let damping = a.opt_f64("damping")?.unwrap_or(0.0);
            if !(damping >= 0.0) || !damping.is_finite() {
                return Err(a.error("damping", format!("{label}: must be ≥ 0")));
            }
            a.finish(&["thickness", "stiffness", "damping"])?;
            Some(Asperity { thickness, stiffness, damping })
        }
    };
    // The penalty law has no multiplier: its traction κ_n⟨d_n⟩₊ is a function of the
    // displacement gap, a spring; the velocity formulation (Signorini–Moreau: the law on
    // the normal relative velocity, a shift of the gap) is a law of the multiplier and
    // would turn the spring into a stiff dashpot. Its default in dynamics is the
    // displacement gap, and the velocity formulation is refused.
    let formulation = match c.opt_choice("formulation", &["velocity", "displacement"])?.as_deref() {
        Some("displacement") => ContactFormulation::Displacement,
        Some(_) if method == Method::Penalty => {
            return Err(c.error(
                "formulation",
                format!(
                    "{label}: the penalty law acts on the displacement gap (traction κ_n⟨d_n⟩₊); formulation = \"velocity\" (Signorini–Moreau) needs a contact multiplier: use formulation = \"displacement\" (the default with the penalty), or method = \"augmented_lagrangian\" or \"stabilised\""
                ),
            ))
        }
        // An asperity layer is a nonlinear spring and dashpot on the gap (its damping on
        // the normal relative velocity in dynamics): like the penalty it acts on the
        // displacement gap, and the velocity formulation's shift of the gap would move the
        // layer's crush.
        Some(_) if asperity.is_some() => {
            return Err(c.error(
                "formulation",
                format!(
                    "{label}: an asperity layer ([cracks.contact.asperity]) acts on the displacement gap (traction κ_n⟨d_n + a⟩₊² + c_n⟨d_n + a⟩₊ ḋ_n); formulation = \"velocity\" (Signorini–Moreau) would shift that gap: use formulation = \"displacement\" (the default with an asperity layer)"
                ),
            ))
        }
        None if method == Method::Penalty || asperity.is_some() => ContactFormulation::Displacement,
        _ => ContactFormulation::Velocity,
    };
    let wear = read_wear(c, label, implicit)?;
    // Unset: `ContactCrackOptions::stabilisation`'s 0 (none).
    let multiplier_stabilisation = c.opt_f64("multiplier_stabilisation")?;
    let gamma0 = multiplier_stabilisation.unwrap_or(0.0);
    if !(gamma0 >= 0.0) || !gamma0.is_finite() {
        return Err(c.error("multiplier_stabilisation", format!("{label}: a number ≥ 0 (γ₀; 0: none)")));
    }
    if gamma0 > 0.0 && (pair || method == Method::Penalty) {
        return Err(c.error(
            "multiplier_stabilisation",
            format!("{label}: the gradient stabilisation of the multiplier is for the cracks' multiplier laws (augmented_lagrangian, stabilised), not for a contact pair or the penalty law"),
        ));
    }
    let mut known = vec![
        "friction",
        "rho_n",
        "rho_t",
        "initial_threshold",
        "start_closed",
        "integration",
        "lbb",
        "sliding",
        "method",
        "kappa_n",
        "kappa_t",
        "initial_gap",
        "asperity",
        "formulation",
        "wear",
        "multiplier_stabilisation",
    ];
    known.extend_from_slice(extra);
    c.finish(&known)?;
    Ok(ContactCrackOptions {
        crack: 0,
        friction,
        rho_n,
        rho_t,
        initial_threshold,
        start_closed,
        integration,
        lbb,
        sliding,
        method,
        kappa_n,
        kappa_t,
        initial_gap,
        asperity,
        formulation,
        wear,
        multiplier_stabilisation,
        zone: ZoneChoice::Auto,
    })
}

/// The contact zone of a `[[contact_pairs]]` entry: `zone = "auto"` (default) or
/// `"band"`, and `zone_gap` (a length > 0: the initial zone's threshold on the reference
/// gap, with `zone = "auto"`); `contact::zone`.
fn read_pair_zone(
    t: &Table<'_, '_>,
    name: &str,
    options: &ContactCrackOptions,
    (zone, gap): (Option<String>, Option<f64>),
) -> Result<ZoneChoice, CaseError> {
    let band = zone.as_deref() == Some("band");
    if let Some(g) = gap {
        if !(g > 0.0) || !g.is_finite() {
            return Err(t.error(
                "zone_gap",
                format!("contact pair '{name}': a length > 0 (the initial contact zone's largest reference gap)"),
            ));
        }
        if band {
            return Err(t.error("zone_gap", format!("contact pair '{name}': zone_gap sets the initial contact zone of zone = \"auto\"; zone = \"band\" keeps every paired point")));
        }
        if options.sliding == Sliding::Large {
            return Err(t.error("zone_gap", format!("contact pair '{name}': the contact zone is for sliding = \"small\" (a pair in large sliding keeps every paired point)")));
        }
    }
    Ok(match (band, gap) {
        (true, _) => ZoneChoice::Band,
        (false, Some(g)) => ZoneChoice::Gap(g),
        (false, None) => ZoneChoice::Auto,
    })
}

fn located(t: &Table<'_, '_>) -> Located {
    Located { file: t.src.file.clone(), key: t.path.clone(), line: t.line }
}

/// A vector of 2 or 3 components, each a number or formula; padded with zeros.
fn read_vector(
    t: &Table<'_, '_>,
    key: &str,
    params: &BTreeMap<String, f64>,
) -> Result<([Scalar; 3], usize), CaseError> {
    let v = t.opt_scalar_array(key, params)?.ok_or_else(|| {
        let mut e = t.error(key, format!("missing key '{key}' (a vector: [x, y] or [x, y, z])"));
        e.line = t.line;
        e
    })?;
    if !(2..=3).contains(&v.len()) {
        return Err(t.error(key, format!("expected 2 or 3 components, found {}", v.len())));
    }
    let n = v.len();
    let mut out = [Scalar::Const(0.0), Scalar::Const(0.0), Scalar::Const(0.0)];
    for (i, s) in v.into_iter().enumerate() {
        out[i] = s;
    }
    Ok((out, n))
}

/// The directory a case file's relative paths start from: the file's own.
fn base_dir(path: &Path) -> &Path {
    path.parent().unwrap_or(Path::new("."))
}

impl Case {
    /// Reads and validates a case file.
    pub fn from_file(path: &Path) -> Result<Case, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|e| CaseError {
            file: path.display().to_string(),
            line: None,
            key: String::new(),
            message: format!("cannot read the case file: {e}"),
        })?;
        Case::parse(&text, path)
    }

    /// Reads a case file with command-line overrides applied to its keys first; errors in
    /// an overridden value name the override.
    pub fn from_file_with(path: &Path, overrides: &[overrides::Override]) -> Result<Case, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|e| CaseError {
            file: path.display().to_string(),
            line: None,
            key: String::new(),
            message: format!("cannot read the case file: {e}"),
        })?;
        Case::parse_with(&text, path, overrides)
    }

    /// [`Case::parse`] with command-line overrides applied to the text first.
    pub fn parse_with(text: &str, path: &Path, overrides: &[overrides::Override]) -> Result<Case, CaseError> {
        Case::parse_in(text, path, base_dir(path), overrides)
    }

    /// [`Case::parse_with`] with the relative paths of the text (mesh files, crack
    /// meshes) taken from `base` instead of the directory of `path`: for a case built in
    /// memory (a Python dict) that `path` only names in errors and output.
    pub fn parse_in(
        text: &str,
        path: &Path,
        base: &Path,
        overrides: &[overrides::Override],
    ) -> Result<Case, CaseError> {
        if overrides.is_empty() {
            return Case::parse_at(text, path, base);
        }
        let (edited, same_lines) = overrides::apply_all(text, &path.display().to_string(), overrides)?;
        let origin = overrides::Origin::new(text, same_lines, overrides);
        let mut case = Case::parse_at(&edited, path, base).map_err(|e| origin.attribute(e))?;
        case.origin = origin;
        Ok(case)
    }

    /// An error found after reading (in the mesh or the model), attributed to the override
    /// that caused it or put on the case file's own line.
    pub fn attribute(&self, e: CaseError) -> CaseError {
        self.origin.attribute(e)
    }

    /// Parses and validates case-file text; `path` names the file in errors and is the
    /// base for relative mesh paths.
    pub fn parse(text: &str, path: &Path) -> Result<Case, CaseError> {
        Case::parse_at(text, path, base_dir(path))
    }

    /// [`Case::parse`] with relative paths taken from `base`.
    fn parse_at(text: &str, path: &Path, base: &Path) -> Result<Case, CaseError> {
        let file = path.display().to_string();
        let src = Source { file: file.clone(), text };
        let doc = toml_edit::ImDocument::parse(text).map_err(|e| CaseError {
            file: file.clone(),
            line: src.line_of(e.span()),
            key: String::new(),
            message: format!("not valid TOML: {}", e.message()),
        })?;
        let root = Table::new(&src, doc.as_table(), String::new(), Some(1));
        const TOP: [&str; 21] = [
            "contact_pairs",
            "propagation",
            "dynamics",
            "initial_velocity",
            "initial_displacement",
            "contact_solver",
            "cracks",
            "xfem",
            "parameters",
            "model",
            "mesh",
            "sets",
            "materials",
            "dirichlet",
            "relations",
            "traction",
            "pressure",
            "body_force",
            "steps",
            "solver",
            "output",
        ];

        // [parameters]: free-form name = number.
        let mut parameters = BTreeMap::new();
        if let Some(p) = root.opt_table("parameters")? {
            p.use_all();
            for (k, item) in p.entries() {
                let v = match item {
                    Item::Value(Value::Float(f)) => *f.value(),
                    Item::Value(Value::Integer(i)) => *i.value() as f64,
                    _ => return Err(p.error(&k, "a parameter must be a number")),
                };
                if matches!(k.as_str(), "x" | "y" | "z" | "t") {
                    return Err(p.error(&k, "x, y, z and t are reserved for coordinates and the load factor"));
                }
                parameters.insert(k, v);
            }
        }

        // [model]
        let (analysis, analysis_at) = match root.opt_table("model")? {
            Some(m) => {
                let a = m.opt_choice("analysis", &["plane_strain", "plane_stress", "3d"])?.map(|s| match s.as_str() {
                    "plane_strain" => Analysis::PlaneStrain,
                    "plane_stress" => Analysis::PlaneStress,
                    _ => Analysis::ThreeD,
                });
                m.finish(&["analysis"])?;
                (a, located(&m))
            }
            None => (None, Located { file: file.clone(), key: "model".into(), line: None }),
        };

        // [mesh]
        let m = root.opt_table("mesh")?.ok_or_else(|| CaseError {
            file: file.clone(),
            line: None,
            key: "mesh".into(),
            message: "missing table [mesh] (a file = \"...msh\" or a generator)".into(),
        })?;
        let mesh_at = located(&m);
        let mesh = if m.has("parts") {
            let mut parts: Vec<PartDef> = vec![];
            let tables = m.opt_tables("parts")?;
            for other in ["file", "generator"] {
                if m.has(other) {
                    return Err(m.error(other, format!("[mesh] takes either [[mesh.parts]] or '{other}', not both")));
                }
            }
            m.finish(&["parts"])?;
            if tables.is_empty() {
                return Err(m.error("parts", "expected at least one [[mesh.parts]] table"));
            }
            for t in tables {
                let name = t.req_str("name", "name of the part (prefix of its groups)")?;
                if name.is_empty() || name.contains(|c: char| c.is_whitespace() || c == '.') {
                    return Err(t.error("name", format!("'{name}' is not a part name (no spaces or dots)")));
                }
                if parts.iter().any(|p| p.name == name) {
                    return Err(t.error("name", format!("a part named '{name}' is already defined")));
                }
                let offset_given = t.opt_f64_array("offset")?;
                let spec = read_generator(&t, &["name", "offset"])?;
                let dim = spec.cell.dim();
                if let Some(first) = parts.first() {
                    if first.spec.cell.dim() != dim {
                        return Err(t.error(
                            "generator",
                            format!("part '{name}' is {dim}D but part '{}' is {}D", first.name, first.spec.cell.dim()),
                        ));
                    }
                }
                let mut offset = [0.0; 3];
                if let Some(o) = offset_given {
                    if o.len() != dim {
                        return Err(t.error("offset", format!("expected {dim} numbers, found {}", o.len())));
                    }
                    offset[..dim].copy_from_slice(&o);
                }
                parts.push(PartDef { name, spec, offset, at: located(&t) });
            }
            // Parts share no material: boxes that overlap by a volume are refused.
            for (j, b) in parts.iter().enumerate() {
                for a in &parts[..j] {
                    let (alo, ahi) = a.bounds();
                    let (blo, bhi) = b.bounds();
                    let dim = a.spec.cell.dim();
                    let scale = (0..dim).map(|k| (ahi[k] - alo[k]).min(bhi[k] - blo[k])).fold(f64::INFINITY, f64::min);
                    let overlap = (0..dim).all(|k| ahi[k].min(bhi[k]) - alo[k].max(blo[k]) > 1e-9 * scale);
                    if overlap {
                        return Err(b.at.error(
                            "upper",
                            format!(
                                "part '{}' overlaps part '{}' (boxes {:?}–{:?} and {:?}–{:?} after their offsets); parts may touch but not overlap",
                                b.name,
                                a.name,
                                &blo[..dim],
                                &bhi[..dim],
                                &alo[..dim],
                                &ahi[..dim]
                            ),
                        ));
                    }
                }
            }
            MeshSource::Parts(parts)
        } else if m.has("file") {
            let f = m.req_str("file", "path to a Gmsh MSH 4.1 file")?;
            m.finish(&["file"])?;
            MeshSource::File(base.join(f))
        } else {
            let GeneratorSpec { cell, lower, upper, divisions } = read_generator(&m, &["file", "parts"])?;
            MeshSource::Generated { cell, lower, upper, divisions }
        };

        // [[sets]]
        let mut sets = vec![];
        for s in root.opt_tables("sets")? {
            let name = s.req_str("name", "name of the new group")?;
            let kind = match s.opt_choice("kind", &["nodes", "faces", "cells"])?.as_deref() {
                None | Some("nodes") => SetKind::Nodes,
                Some("faces") => SetKind::Faces,
                _ => SetKind::Cells,
            };
            let on = s.opt_scalar("on", &parameters)?;
            let inside = s.opt_scalar("inside", &parameters)?;
            if on.is_none() && inside.is_none() {
                let mut e = s.error("on", "a set needs 'on' (where |f| ≤ tol) and/or 'inside' (where f ≤ tol)");
                e.line = s.line;
                return Err(e);
            }
            let tolerance = s.opt_f64("tolerance")?;
            if tolerance.is_some_and(|t| !(t >= 0.0)) {
                return Err(s.error("tolerance", "must be non-negative"));
            }
            s.finish(&["name", "kind", "on", "inside", "tolerance"])?;
            sets.push(SetDef { name, kind, on, inside, tolerance, at: located(&s) });
        }

        // [[materials]]
        let mut materials = vec![];
        for t in root.opt_tables("materials")? {
            let group = t.opt_str("group")?.unwrap_or_else(|| "all".into());
            let young = t.req_f64("E", "Young's modulus")?;
            let poisson = t.req_f64("nu", "Poisson's ratio")?;
            if !(young > 0.0) || !young.is_finite() {
                return Err(t.error("E", "Young's modulus must be positive"));
            }
            if !(poisson > -1.0 && poisson < 0.5) {
                return Err(t.error("nu", "Poisson's ratio must lie in (−1, 0.5)"));
            }
            let density = t.opt_f64("density")?;
            if density.is_some_and(|r| !(r > 0.0) || !r.is_finite()) {
                return Err(t.error("density", "the mass density must be positive"));
            }
            t.finish(&["group", "E", "nu", "density"])?;
            materials.push(MaterialDef { group, material: Isotropic { young, poisson }, density, at: located(&t) });
        }
        if materials.is_empty() {
            return Err(CaseError {
                file: file.clone(),
                line: None,
                key: "materials".into(),
                message: "missing [[materials]] (at least one, with E and nu)".into(),
            });
        }

        // [[dirichlet]]
        let mut dirichlet = vec![];
        for t in root.opt_tables("dirichlet")? {
            let group = t.req_str("group", "the group whose nodes are constrained")?;
            let comps = t.opt_str_array("components")?.ok_or_else(|| {
                let mut e = t.error("components", "missing key 'components' (e.g. [\"x\", \"y\"])");
                e.line = t.line;
                e
            })?;
            let mut components = vec![];
            for c in &comps {
                let k = component_index(c).ok_or_else(|| t.error("components", format!("'{c}' is not x, y or z")))?;
                if components.contains(&k) {
                    return Err(t.error("components", format!("component '{c}' is listed twice")));
                }
                components.push(k);
            }
            if components.is_empty() {
                return Err(t.error("components", "list at least one component"));
            }
            let values = match (t.opt_scalar("value", &parameters)?, t.opt_scalar_array("values", &parameters)?) {
                (Some(_), Some(_)) => return Err(t.error("values", "give either 'value' or 'values', not both")),
                (Some(v), None) => vec![v; components.len()],
                (None, Some(vs)) => {
                    if vs.len() != components.len() {
                        return Err(
                            t.error("values", format!("{} values for {} components", vs.len(), components.len()))
                        );
                    }
                    vs
                }
                (None, None) => vec![Scalar::Const(0.0); components.len()],
            };
            let lip = match (t.opt_str("crack")?, t.opt_choice("lip", &["+", "-"])?) {
                (None, None) => None,
                (Some(c), Some(l)) => Some((c, if l == "+" { 1 } else { -1 })),
                (Some(_), None) => return Err(t.error("crack", "give the lip too: lip = \"+\" or \"-\"")),
                (None, Some(_)) => return Err(t.error("lip", "give the crack too: crack = \"name\"")),
            };
            t.finish(&["group", "components", "value", "values", "crack", "lip"])?;
            dirichlet.push(DirichletDef { group, components, values, lip, at: located(&t) });
        }

        // [[relations]]
        let mut relations = vec![];
        for t in root.opt_tables("relations")? {
            let groups = t.opt_str_array("groups")?.ok_or_else(|| {
                let mut e = t.error("groups", "missing key 'groups' (one node group per term)");
                e.line = t.line;
                e
            })?;
            let comps = t.opt_str_array("components")?.ok_or_else(|| {
                let mut e = t.error("components", "missing key 'components' (one per term: \"x\", \"y\" or \"z\")");
                e.line = t.line;
                e
            })?;
            let coefficients = t.opt_f64_array("coefficients")?.ok_or_else(|| {
                let mut e = t.error("coefficients", "missing key 'coefficients' (one number per term)");
                e.line = t.line;
                e
            })?;
            if groups.is_empty() {
                return Err(t.error("groups", "list at least one group"));
            }
            if comps.len() != groups.len() {
                return Err(t.error("components", format!("{} components for {} groups", comps.len(), groups.len())));
            }
            if coefficients.len() != groups.len() {
                return Err(t.error(
                    "coefficients",
                    format!("{} coefficients for {} groups", coefficients.len(), groups.len()),
                ));
            }
            if coefficients.iter().any(|a| !a.is_finite()) || coefficients.iter().all(|&a| a == 0.0) {
                return Err(t.error("coefficients", "finite numbers, not all zero"));
            }
            let components = comps
                .iter()
                .map(|c| component_index(c).ok_or_else(|| t.error("components", format!("'{c}' is not x, y or z"))))
                .collect::<Result<Vec<_>, _>>()?;
            let value = t.opt_scalar("value", &parameters)?.unwrap_or(Scalar::Const(0.0));
            t.finish(&["groups", "components", "coefficients", "value"])?;
            relations.push(RelationDef { groups, components, coefficients, value, at: located(&t) });
        }

        // [[traction]] and [[pressure]]
        let mut face_loads = vec![];
        for t in root.opt_tables("traction")? {
            let group = t.req_str("group", "the face group loaded")?;
            let (v, n) = read_vector(&t, "value", &parameters)?;
            t.finish(&["group", "value"])?;
            face_loads.push(FaceLoadDef { group, load: FaceLoad::Traction(v), n_components: n, at: located(&t) });
        }
        for t in root.opt_tables("pressure")? {
            let group = t.req_str("group", "the face group loaded")?;
            let p = t.opt_scalar("value", &parameters)?.ok_or_else(|| {
                let mut e = t.error("value", "missing key 'value' (the pressure)");
                e.line = t.line;
                e
            })?;
            t.finish(&["group", "value"])?;
            face_loads.push(FaceLoadDef { group, load: FaceLoad::Pressure(p), n_components: 0, at: located(&t) });
        }

        // [[body_force]]
        let mut body_forces = vec![];
        for t in root.opt_tables("body_force")? {
            let group = t.opt_str("group")?.unwrap_or_else(|| "all".into());
            let (value, n) = read_vector(&t, "value", &parameters)?;
            t.finish(&["group", "value"])?;
            body_forces.push(BodyForceDef { group, value, n_components: n, at: located(&t) });
        }

        // [dynamics], [[initial_velocity]], [[initial_displacement]]
        let dynamics = match root.opt_table("dynamics")? {
            None => None,
            Some(d) => Some(read_dynamics(&d)?),
        };
        let initial = |key: &str| -> Result<Vec<InitialFieldDef>, CaseError> {
            let mut out = vec![];
            for t in root.opt_tables(key)? {
                let group = t.opt_str("group")?.unwrap_or_else(|| "all".into());
                let (value, n) = read_vector(&t, "value", &parameters)?;
                t.finish(&["group", "value"])?;
                if dynamics.is_none() {
                    let mut e = t.error("value", format!("[[{key}]] needs a [dynamics] table"));
                    e.line = t.line;
                    return Err(e);
                }
                out.push(InitialFieldDef { group, value, n_components: n, at: located(&t) });
            }
            Ok(out)
        };
        let initial_velocity = initial("initial_velocity")?;
        let initial_displacement = initial("initial_displacement")?;
        if let (Some(d), true) = (&dynamics, root.has("steps")) {
            let mut e = d.at.error("steps", "give [dynamics] (time steps) or [steps] (load steps), not both");
            e.line = d.at.line;
            return Err(e);
        }
        if dynamics.is_some() {
            if let Some(m) = materials.iter().find(|m| m.density.is_none()) {
                let mut e =
                    m.at.error("density", "a dynamic run ([dynamics]) needs the mass density of every material");
                e.line = m.at.line;
                return Err(e);
            }
        }

        // [[cracks]]
        let mut cracks: Vec<CrackDef> = vec![];
        for t in root.opt_tables("cracks")? {
            let mut def = read_crack(&t, &parameters, base)?;
            if let Some(c) = def.contact.as_mut() {
                c.crack = cracks.len();
            }
            if cracks.iter().any(|c| c.name == def.name) {
                return Err(t.error("name", format!("two cracks are named '{}'", def.name)));
            }
            cracks.push(def);
        }

        // [xfem]
        let mut xfem = XfemDef { quadrature: XfemQuadrature::default(), min_side_fraction: 1e-4, snap: 1e-9 };
        if let Some(x) = root.opt_table("xfem")? {
            let q = &mut xfem.quadrature;
            for (key, slot) in [
                ("subcell_degree", &mut q.subcell_degree),
                ("tip_degree", &mut q.tip_degree),
                ("front_degree", &mut q.front_degree),
            ] {
                if let Some(d) = x.opt_usize(key)? {
                    if !(1..=30).contains(&d) {
                        return Err(x.error(key, "a quadrature degree from 1 to 30"));
                    }
                    *slot = d;
                }
            }
            if let Some(f) = x.opt_f64("min_side_fraction")? {
                if !(0.0..0.5).contains(&f) {
                    return Err(x.error("min_side_fraction", "a fraction in [0, 0.5)"));
                }
                xfem.min_side_fraction = f;
            }
            if let Some(f) = x.opt_f64("snap")? {
                if !(0.0..0.1).contains(&f) {
                    return Err(x.error("snap", "a relative tolerance in [0, 0.1)"));
                }
                xfem.snap = f;
            }
            x.finish(&["subcell_degree", "tip_degree", "front_degree", "min_side_fraction", "snap"])?;
        }

        // [[contact_pairs]]
        let mut contact_pairs: Vec<ContactPairDef> = vec![];
        for (i, t) in root.opt_tables("contact_pairs")?.into_iter().enumerate() {
            let name = t.opt_str("name")?.unwrap_or_else(|| format!("pair{i}"));
            if contact_pairs.iter().any(|p| p.name == name) {
                return Err(t.error("name", format!("two contact pairs are named '{name}'")));
            }
            let slave = t.req_str("slave", "the slave boundary face group (it carries the multipliers)")?;
            let master = t.req_str("master", "the master boundary face group")?;
            if slave == master {
                return Err(
                    t.error("master", format!("contact pair '{name}': the same group '{slave}' as slave and master"))
                );
            }
            // Read before the contact keys' check of unknown keys.
            let zone_keys = (t.opt_choice("zone", &["auto", "band"])?, t.opt_f64("zone_gap")?);
            let mut options = read_contact_options(
                &t,
                &format!("contact pair '{name}'"),
                true,
                &["name", "slave", "master", "zone", "zone_gap"],
                false,
            )?;
            options.zone = read_pair_zone(&t, &name, &options, zone_keys)?;
            if dynamics.is_some() {
                return Err(t.error(
                    "slave",
                    format!("contact pair '{name}': contact pairs are not verified in a dynamic run ([dynamics]) yet"),
                ));
            }
            contact_pairs.push(ContactPairDef { name, slave, master, options, at: located(&t) });
        }

        // [contact_solver]
        let mut contact_loops = ContactLoops::default();
        if let Some(c) = root.opt_table("contact_solver")? {
            if let Some(a) = c.opt_choice("algorithm", &["nested", "semi_smooth"])? {
                contact_loops.algorithm =
                    if a == "nested" { ContactAlgorithm::Nested } else { ContactAlgorithm::SemiSmooth };
            }
            if let Some(t) = c.opt_choice("friction_threshold", &["newton", "fixed_point"])? {
                contact_loops.threshold_in_newton = t == "newton";
                // Given explicitly: the multiplier laws' thresholds follow the Newton loop too.
                contact_loops.threshold_in_newton_multipliers = Some(t == "newton");
            }
            if let Some(p) = c.opt_choice("intermediate_passes", &["provisional", "confirmed"])? {
                contact_loops.provisional_passes = p == "provisional";
            }
            for (key, slot) in [
                ("max_friction", &mut contact_loops.max_friction),
                ("max_active_set", &mut contact_loops.max_active_set),
                ("max_newton", &mut contact_loops.max_newton),
                ("max_geometry", &mut contact_loops.max_geometry),
            ] {
                if let Some(v) = c.opt_usize(key)? {
                    if v == 0 {
                        return Err(c.error(key, "at least 1"));
                    }
                    *slot = v;
                }
            }
            for (key, slot) in [
                ("tol_friction", &mut contact_loops.tol_friction),
                ("tol_newton", &mut contact_loops.tol_newton),
                ("tol_geometry", &mut contact_loops.tol_geometry),
            ] {
                if let Some(v) = c.opt_f64(key)? {
                    if !(v > 0.0) {
                        return Err(c.error(key, "must be positive"));
                    }
                    *slot = v;
                }
            }
            c.finish(&[
                "algorithm",
                "friction_threshold",
                "max_friction",
                "tol_friction",
                "max_active_set",
                "max_newton",
                "tol_newton",
                "max_geometry",
                "tol_geometry",
                "intermediate_passes",
            ])?;
        }

        // [steps]
        let load_factors = match root.opt_table("steps")? {
            None => vec![1.0],
            Some(s) => {
                let count = s.opt_usize("count")?;
                let factors = s.opt_f64_array("factors")?;
                s.finish(&["count", "factors"])?;
                match (count, factors) {
                    (Some(_), Some(_)) => return Err(s.error("factors", "give either 'count' or 'factors', not both")),
                    (Some(0), None) => return Err(s.error("count", "at least one step")),
                    (Some(n), None) if n > MAX_STEPS => {
                        return Err(s.error("count", format!("at most {MAX_STEPS} steps ({n} given)")))
                    }
                    (Some(n), None) => (1..=n).map(|k| k as f64 / n as f64).collect(),
                    (None, Some(f)) => {
                        if f.is_empty() || f.iter().any(|v| !v.is_finite()) {
                            return Err(s.error("factors", "a non-empty list of finite numbers"));
                        }
                        f
                    }
                    (None, None) => vec![1.0],
                }
            }
        };

        // [solver]
        let mut solver = SolverDef {
            linear: LinearMethod::Cholesky,
            dirichlet: DirichletMethod::Eliminate,
            residual_tolerance: 1e-8,
            condense: true,
            ordering: OrderingChoice::Auto,
            precision: Precision::Auto,
            backend: Backend::Faer,
        };
        if let Some(s) = root.opt_table("solver")? {
            if let Some(l) = s.opt_choice("linear", &["cholesky", "ldlt", "lu"])? {
                solver.linear = match l.as_str() {
                    "cholesky" => LinearMethod::Cholesky,
                    "ldlt" => LinearMethod::Ldlt,
                    _ => LinearMethod::Lu,
                };
            }
            if let Some(d) = s.opt_choice("dirichlet", &["eliminate", "multiplier"])? {
                solver.dirichlet =
                    if d == "eliminate" { DirichletMethod::Eliminate } else { DirichletMethod::Multiplier };
            }
            if let Some(r) = s.opt_f64("residual_tolerance")? {
                if !(r > 0.0) {
                    return Err(s.error("residual_tolerance", "must be positive"));
                }
                solver.residual_tolerance = r;
            }
            if let Some(c) = s.opt_bool("condense")? {
                solver.condense = c;
            }
            if let Some(o) = s.opt_choice("ordering", &["auto", "amd", "nested_dissection"])? {
                solver.ordering = match o.as_str() {
                    "amd" => OrderingChoice::Amd,
                    "nested_dissection" => OrderingChoice::NestedDissection,
                    _ => OrderingChoice::Auto,
                };
            }
            if let Some(p) = s.opt_choice("precision", &["auto", "double", "mixed"])? {
                solver.precision = match p.as_str() {
                    "double" => Precision::Double,
                    "mixed" => Precision::Mixed,
                    _ => Precision::Auto,
                };
            }
            solver.backend = read_backend(&s)?;
            s.finish(&[
                "linear",
                "dirichlet",
                "residual_tolerance",
                "condense",
                "ordering",
                "precision",
                "backend",
                "petsc",
            ])?;
        }

        // [output]
        let mut output = OutputDef { vtu: true, compression: Compression::None, plots: true };
        if let Some(o) = root.opt_table("output")? {
            if let Some(v) = o.opt_bool("vtu")? {
                output.vtu = v;
            }
            if let Some(c) = o.opt_choice("compression", &["none", "lz4"])? {
                output.compression = if c == "lz4" { Compression::Lz4 } else { Compression::None };
            }
            if let Some(v) = o.opt_bool("plots")? {
                output.plots = v;
            }
            o.finish(&["vtu", "compression", "plots"])?;
        }

        // Contact in dynamics (issue 15): the augmented Lagrangian and the stabilised law
        // (velocity or displacement formulation), the penalty law (displacement gap: a
        // spring of stiffness κ_n per unit area) and the asperity layer (displacement gap,
        // its damping on the normal relative velocity) are verified
        // (tests/dynamics_bar_rigid_wall.rs); wear is refused rather than run unchecked.
        if dynamics.is_some() {
            for c in &cracks {
                let Some(o) = &c.contact else { continue };
                if o.wear.is_some() {
                    return Err(c.at.error(
                        "contact.wear",
                        format!("crack '{}': wear is not verified in a dynamic run yet", c.name),
                    ));
                }
            }
        }
        let propagation = read_propagation(&root, &cracks)?;
        if let (Some(p), Some(_)) = (&propagation, &dynamics) {
            return Err(CaseError {
                file: p.at.file.clone(),
                line: p.at.line,
                key: "propagation".into(),
                message: "crack growth in a dynamic run ([propagation] with [dynamics]) is not implemented: \
                          grow the crack in quasi-static steps, or run the dynamics on a fixed crack"
                    .into(),
            });
        }
        if propagation.is_some() {
            if let Some(c) = cracks.iter().find(|c| c.contact.as_ref().is_some_and(|o| o.wear.is_some())) {
                return Err(c.at.error(
                    "contact.wear",
                    format!("crack '{}': wear with crack growth ([propagation]) is not implemented: the wear of the lips is not carried over to the grown crack", c.name),
                ));
            }
            if let Some(c) = cracks.iter().find(|c| c.grow && !c.shape.has_front()) {
                return Err(c.at.error(
                    "grow",
                    format!(
                        "crack '{}' is an interface (a {}, no front): it cannot grow; give grow = false",
                        c.name,
                        c.shape.name()
                    ),
                ));
            }
        }

        root.finish(&TOP)?;
        let name = path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_else(|| "case".into());
        Ok(Case {
            path: path.to_path_buf(),
            name,
            parameters,
            analysis,
            analysis_at,
            mesh,
            mesh_at,
            sets,
            materials,
            dirichlet,
            relations,
            face_loads,
            body_forces,
            load_factors,
            cracks,
            xfem,
            contact_loops,
            contact_pairs,
            solver,
            output,
            propagation,
            dynamics,
            initial_velocity,
            initial_displacement,
            origin: Default::default(),
        })
    }
}

/// Reads `[dynamics]`.
fn read_dynamics(d: &Table<'_, '_>) -> Result<DynamicsDef, CaseError> {
    use crate::solve::time::{DynamicScheme, Newmark, Theta};
    let scheme = d.opt_choice("scheme", &["newmark", "hht", "theta"])?.unwrap_or_else(|| "newmark".into());
    let dt = d.opt_f64("dt")?.ok_or_else(|| {
        let mut e = d.error("dt", "missing key 'dt' (the time step)");
        e.line = d.line;
        e
    })?;
    if !(dt > 0.0) || !dt.is_finite() {
        return Err(d.error("dt", format!("the time step must be positive ({dt} given)")));
    }
    let steps = match (d.opt_f64("end_time")?, d.opt_usize("steps")?) {
        (Some(_), Some(_)) => return Err(d.error("steps", "give either 'end_time' or 'steps', not both")),
        (None, None) => {
            let mut e = d.error("end_time", "missing key 'end_time' (or 'steps')");
            e.line = d.line;
            return Err(e);
        }
        (Some(end), None) => {
            if !(end >= dt) || !end.is_finite() {
                return Err(d.error("end_time", format!("end_time = {end} is shorter than one time step (dt = {dt})")));
            }
            (end / dt - 1e-9).ceil() as usize
        }
        (None, Some(0)) => return Err(d.error("steps", "at least one time step")),
        (None, Some(n)) => n,
    };
    if steps > MAX_STEPS {
        return Err(d.error("dt", format!("at most {MAX_STEPS} time steps ({steps} asked)")));
    }
    let theta = d.opt_f64("theta")?;
    if scheme != "theta" && theta.is_some() {
        return Err(d.error("theta", format!("theta goes with scheme = \"theta\" (scheme = \"{scheme}\" given)")));
    }
    let output_every = d.opt_usize("output_every")?.unwrap_or(1);
    if output_every == 0 {
        return Err(d.error("output_every", "at least 1"));
    }
    let position_correction = d.opt_bool("position_correction")?.unwrap_or(true);
    let mass = match d.opt_choice("mass", &["consistent", "redistributed"])?.as_deref() {
        Some("redistributed") => crate::physics::inertia::MassMatrix::Redistributed,
        _ => crate::physics::inertia::MassMatrix::Consistent,
    };
    if scheme == "theta" {
        for key in ["beta", "gamma", "alpha"] {
            if d.opt_f64(key)?.is_some() {
                return Err(d.error(key, format!("{key} goes with scheme = \"newmark\" or \"hht\", not \"theta\"")));
            }
        }
        let t = theta.unwrap_or(0.5);
        if !(0.5..=1.0).contains(&t) {
            return Err(d.error(
                "theta",
                format!("theta must lie in [1/2, 1] ({t} given; below 1/2 the θ-method is unstable)"),
            ));
        }
        d.finish(&["scheme", "dt", "end_time", "steps", "theta", "output_every", "position_correction", "mass"])?;
        return Ok(DynamicsDef {
            scheme: DynamicScheme::Theta(Theta::new(t, dt, steps)),
            output_every,
            position_correction,
            mass,
            at: located(d),
        });
    }
    let alpha = d.opt_f64("alpha")?;
    let mut n = match (scheme.as_str(), alpha) {
        ("newmark", Some(_)) => return Err(d.error("alpha", "alpha goes with scheme = \"hht\"")),
        ("newmark", None) => Newmark::average_acceleration(dt, steps),
        (_, a) => {
            let a = a.unwrap_or(0.05);
            if !(a > 0.0 && a <= 1.0 / 3.0) {
                return Err(d.error("alpha", format!("HHT's alpha must lie in (0, 1/3] ({a} given)")));
            }
            Newmark::hht(a, dt, steps)
        }
    };
    if let Some(b) = d.opt_f64("beta")? {
        n.beta = b;
    }
    if let Some(g) = d.opt_f64("gamma")? {
        n.gamma = g;
    }
    if !(n.gamma >= 0.5) || !n.gamma.is_finite() {
        return Err(d.error("gamma", format!("gamma = {} < 1/2 is unstable (use gamma ≥ 1/2)", n.gamma)));
    }
    if !(n.beta >= 0.5 * n.gamma) || !n.beta.is_finite() {
        return Err(d.error(
            "beta",
            format!(
                "beta = {} < gamma/2 = {} is only conditionally stable (use beta ≥ gamma/2)",
                n.beta,
                0.5 * n.gamma
            ),
        ));
    }
    d.finish(&[
        "scheme",
        "dt",
        "end_time",
        "steps",
        "beta",
        "gamma",
        "alpha",
        "output_every",
        "position_correction",
        "mass",
    ])?;
    Ok(DynamicsDef { scheme: DynamicScheme::Newmark(n), output_every, position_correction, mass, at: located(d) })
}

/// Reads fixed-length arrays of numbers.
fn arr<const N: usize>(t: &Table<'_, '_>, key: &str, what: &str) -> Result<[f64; N], CaseError> {
    let v = t.opt_f64_array(key)?.ok_or_else(|| {
        let mut e = t.error(key, format!("missing key '{key}' ({what}, {N} numbers)"));
        e.line = t.line;
        e
    })?;
    v.try_into().map_err(|v: Vec<f64>| t.error(key, format!("expected {N} numbers, found {}", v.len())))
}

fn num(t: &Table<'_, '_>, key: &str, what: &str) -> Result<f64, CaseError> {
    t.req_f64(key, what)
}

/// Reads one `[[cracks]]` entry.
fn read_crack(t: &Table<'_, '_>, params: &BTreeMap<String, f64>, base: &Path) -> Result<CrackDef, CaseError> {
    use crate::formula::Formula;
    const SHAPES: [&str; 13] = [
        "segment",
        "half_line",
        "line",
        "ellipse",
        "disc",
        "elliptic_disc",
        "rectangle",
        "half_plane",
        "plane",
        "sphere",
        "cylinder",
        "formula",
        "mesh",
    ];
    let name = t.req_str("name", "the crack's name")?;
    let kind = t.opt_choice("shape", &SHAPES)?.ok_or_else(|| {
        let mut e = t.error("shape", format!("missing key 'shape' (one of: {})", SHAPES.join(", ")));
        e.line = t.line;
        e
    })?;
    let mut keys: Vec<&str> =
        vec!["name", "shape", "pressure", "enrichment", "tip_radius", "sif_radius", "contact", "grow"];
    let shape = match kind.as_str() {
        "segment" => {
            keys.extend(["a", "b"]);
            CrackShape::Segment { a: arr(t, "a", "first end")?, b: arr(t, "b", "second end")? }
        }
        "half_line" => {
            keys.extend(["tip", "direction"]);
            CrackShape::HalfLine { tip: arr(t, "tip", "the tip")?, direction: arr(t, "direction", "towards the tip")? }
        }
        "line" => {
            keys.extend(["point", "normal"]);
            CrackShape::Line { point: arr(t, "point", "a point")?, normal: arr(t, "normal", "towards +")? }
        }
        "ellipse" => {
            keys.extend(["centre", "semi_axes", "angle"]);
            CrackShape::Ellipse {
                centre: arr(t, "centre", "centre")?,
                semi_axes: arr(t, "semi_axes", "semi-axes")?,
                angle: t.opt_f64("angle")?.unwrap_or(0.0),
            }
        }
        "disc" => {
            keys.extend(["centre", "normal", "radius"]);
            CrackShape::Disc {
                centre: arr(t, "centre", "centre")?,
                normal: arr(t, "normal", "towards +")?,
                radius: num(t, "radius", "radius")?,
            }
        }
        "elliptic_disc" => {
            keys.extend(["centre", "normal", "major_axis", "semi_axes"]);
            CrackShape::EllipticDisc {
                centre: arr(t, "centre", "centre")?,
                normal: arr(t, "normal", "towards +")?,
                major_axis: arr(t, "major_axis", "in-plane direction")?,
                semi_axes: arr(t, "semi_axes", "semi-axes")?,
            }
        }
        "rectangle" => {
            keys.extend(["centre", "normal", "axis_u", "half_lengths"]);
            CrackShape::Rectangle {
                centre: arr(t, "centre", "centre")?,
                normal: arr(t, "normal", "towards +")?,
                axis_u: arr(t, "axis_u", "in-plane direction")?,
                half_lengths: arr(t, "half_lengths", "half lengths")?,
            }
        }
        "half_plane" => {
            keys.extend(["point_on_front", "normal", "direction"]);
            CrackShape::HalfPlane {
                point_on_front: arr(t, "point_on_front", "a point of the front")?,
                normal: arr(t, "normal", "towards +")?,
                direction: arr(t, "direction", "from the crack into the body")?,
            }
        }
        "plane" => {
            keys.extend(["point", "normal"]);
            CrackShape::Plane { point: arr(t, "point", "a point")?, normal: arr(t, "normal", "towards +")? }
        }
        "sphere" => {
            keys.extend(["centre", "radius"]);
            CrackShape::Sphere { centre: arr(t, "centre", "centre")?, radius: num(t, "radius", "radius")? }
        }
        "cylinder" => {
            keys.extend(["point", "axis", "radius"]);
            CrackShape::Cylinder {
                point: arr(t, "point", "a point on the axis")?,
                axis: arr(t, "axis", "axis direction")?,
                radius: num(t, "radius", "radius")?,
            }
        }
        "mesh" => {
            keys.extend(["file", "front"]);
            let file = t.req_str("file", "path to a Gmsh MSH 4.1 line mesh (2D) or triangle mesh (3D) of the crack")?;
            let front = t.opt_str("front")?;
            let crack = crate::levelset::explicit::ExplicitCrack::from_msh(&base.join(&file), front.as_deref())
                .map_err(|e| {
                    t.error(
                        if e.0.contains("physical group") { "front" } else { "file" },
                        format!("crack '{name}': {e}"),
                    )
                })?;
            CrackShape::Mesh(std::sync::Arc::new(crack))
        }
        _ => {
            keys.extend(["lsn", "lst"]);
            let formula = |key: &str| -> Result<Option<Formula>, CaseError> {
                match t.opt_scalar(key, params)? {
                    None => Ok(None),
                    Some(Scalar::Formula(f)) => Ok(Some(f)),
                    Some(Scalar::Const(_) | Scalar::OfTime(_)) => {
                        Err(t.error(key, "expected a formula string of x, y, z"))
                    }
                }
            };
            let lsn = formula("lsn")?.ok_or_else(|| {
                let mut e = t.error("lsn", "missing key 'lsn' (formula of the normal level set)");
                e.line = t.line;
                e
            })?;
            CrackShape::Formula { lsn, lst: formula("lst")? }
        }
    };
    let shape = shape.normalised().map_err(|e| t.error("shape", format!("crack '{name}': {e}")))?;
    let pressure = t.opt_scalar("pressure", params)?;
    let tip = match t.opt_choice("enrichment", &["geometric", "topological"])?.as_deref() {
        Some("topological") => TipEnrichment::Topological,
        _ => TipEnrichment::Geometric { radius: None },
    };
    let tip = match (tip, t.opt_f64("tip_radius")?) {
        (TipEnrichment::Topological, Some(_)) => {
            return Err(t.error("tip_radius", "tip_radius goes with enrichment = \"geometric\""))
        }
        (_, Some(r)) if !(r > 0.0) => return Err(t.error("tip_radius", "must be positive")),
        (_, Some(r)) => TipEnrichment::Geometric { radius: Some(r) },
        (tip, None) => tip,
    };
    let sif_radius = t.opt_f64("sif_radius")?;
    if sif_radius.is_some_and(|r| !(r > 0.0)) {
        return Err(t.error("sif_radius", "must be positive"));
    }
    let mut rho_n_at = None;
    let contact = match t.opt_table("contact")? {
        None => None,
        Some(c) => {
            let implicit = t.table.get("contact").and_then(|i| i.as_table()).is_some_and(|t| t.is_implicit());
            let e = c.error("rho_n", "");
            rho_n_at = c.has("rho_n").then_some(Located { file: e.file, key: e.key, line: e.line });
            Some(read_contact_options(&c, &format!("crack '{name}'"), false, &[], implicit)?)
        }
    };
    let grow = t.opt_bool("grow")?.unwrap_or(true);
    t.finish(&keys)?;
    // With contact, a segment crack's default tip enrichment covers it, and so does that
    // of a disc, elliptic disc or rectangle crack within a share of the nodes (see
    // `TipEnrichment::Covering`).
    let covering =
        |depth: f64| TipEnrichment::Covering { half_length: depth, max_node_share: Some(COVERING_NODE_SHARE) };
    let tip = match (tip, &shape, &contact) {
        (TipEnrichment::Geometric { radius: None }, CrackShape::Segment { a, b }, Some(_)) => {
            TipEnrichment::Covering { half_length: 0.5 * (b[0] - a[0]).hypot(b[1] - a[1]), max_node_share: None }
        }
        (TipEnrichment::Geometric { radius: None }, CrackShape::Disc { radius, .. }, Some(_)) => covering(*radius),
        (TipEnrichment::Geometric { radius: None }, CrackShape::EllipticDisc { semi_axes, .. }, Some(_)) => {
            covering(semi_axes[0].min(semi_axes[1]))
        }
        (TipEnrichment::Geometric { radius: None }, CrackShape::Rectangle { half_lengths, .. }, Some(_)) => {
            covering(half_lengths[0].min(half_lengths[1]))
        }
        (tip, ..) => tip,
    };
    Ok(CrackDef { name, shape, pressure, tip, sif_radius, contact, grow, at: located(t), rho_n_at })
}

/// Reads `[cracks.contact.wear]` (`label` names the crack; `implicit_contact`: the contact
/// table exists only because the wear table is inside it).
fn read_wear(c: &Table<'_, '_>, label: &str, implicit_contact: bool) -> Result<Option<Wear>, CaseError> {
    let Some(w) = c.opt_table("wear")? else { return Ok(None) };
    if implicit_contact {
        let mut e = c.error(
            "wear",
            format!("{label}: wear on a crack without contact: [cracks.contact.wear] needs [cracks.contact] (the lips wear where they touch and slide with friction)"),
        );
        e.line = w.line.or(e.line);
        return Err(e);
    }
    let positive = |key: &str, what: &str| -> Result<Option<f64>, CaseError> {
        let v = w.opt_f64(key)?;
        if v.is_some_and(|v| !(v > 0.0) || !v.is_finite()) {
            return Err(w.error(key, format!("{label}: {what} must be positive")));
        }
        Ok(v)
    };
    let coefficient = positive("coefficient", "the wear coefficient k/H (1/stress)")?;
    let k = positive("k", "the Archard coefficient k (dimensionless)")?;
    let hardness = positive("hardness", "the hardness H (stress)")?;
    let coefficient = match (coefficient, k, hardness) {
        (Some(c), None, None) => c,
        (None, Some(k), Some(h)) => k / h,
        (Some(_), _, _) => {
            let key = if k.is_some() { "k" } else { "hardness" };
            return Err(w.error(key, format!("{label}: give either coefficient (k/H) or k and hardness, not both")));
        }
        (None, Some(_), None) => return Err(w.error("k", format!("{label}: k needs hardness (H, stress) beside it"))),
        (None, None, Some(_)) => {
            return Err(w.error("hardness", format!("{label}: hardness needs k (dimensionless) beside it")))
        }
        (None, None, None) => {
            let mut e = w
                .error("coefficient", format!("{label}: missing key 'coefficient' (k/H, 1/stress), or k and hardness"));
            e.line = w.line;
            return Err(e);
        }
    };
    let split = w.opt_f64("split")?.unwrap_or(0.5);
    if !(0.0..=1.0).contains(&split) {
        return Err(w.error("split", format!("{label}: the fraction of the wear on the + lip, in [0, 1]")));
    }
    let coupling = match w.opt_choice("coupling", &["implicit", "staggered"])?.as_deref() {
        Some("staggered") => WearCoupling::Staggered,
        _ => WearCoupling::Implicit,
    };
    w.finish(&["coefficient", "k", "hardness", "split", "coupling"])?;
    Ok(Some(Wear { coefficient, split, coupling }))
}

/// Reads `[propagation]` and its `[propagation.fatigue]` (`cracks`: a compressive
/// `min_load_factor` needs contact on every crack).
fn read_propagation(root: &Table<'_, '_>, cracks: &[CrackDef]) -> Result<Option<PropagationDef>, CaseError> {
    let Some(p) = root.opt_table("propagation")? else { return Ok(None) };
    let criterion = match p.opt_choice("criterion", &["max_hoop_stress", "max_energy_release"])?.as_deref() {
        Some("max_energy_release") => Criterion::MaxEnergyRelease,
        _ => Criterion::MaxHoopStress,
    };
    let increment = p.req_f64("increment", "the advance of the tip of largest driving force per increment")?;
    if !(increment > 0.0) || !increment.is_finite() {
        return Err(p.error("increment", format!("the increment must be a positive length (got {increment})")));
    }
    let steps = p.opt_usize("steps")?.ok_or_else(|| {
        let mut e = p.error("steps", "missing key 'steps' (the number of growth increments, ≥ 1)");
        e.line = p.line;
        e
    })?;
    if steps < 1 {
        return Err(p.error("steps", "at least one growth increment (steps ≥ 1)"));
    }
    if steps > MAX_STEPS {
        return Err(p.error("steps", format!("at most {MAX_STEPS} increments ({steps} given)")));
    }
    let positive = |key: &str, what: &str| -> Result<Option<f64>, CaseError> {
        let v = p.opt_f64(key)?;
        if v.is_some_and(|v| !(v > 0.0) || !v.is_finite()) {
            return Err(p.error(key, format!("{what} must be positive (got {})", v.unwrap_or(f64::NAN))));
        }
        Ok(v)
    };
    let exponent = positive("exponent", "the exponent")?;
    let fracture_toughness = positive("fracture_toughness", "the fracture toughness K_c")?;
    let stop_length = positive("stop_length", "the stop length")?;
    let threshold = p.opt_f64("threshold")?.unwrap_or(0.0);
    if !(threshold >= 0.0) || !threshold.is_finite() {
        return Err(p.error("threshold", format!("the threshold K_eq must be ≥ 0 (got {threshold})")));
    }
    let fatigue = match p.opt_table("fatigue")? {
        None => None,
        Some(f) => {
            let c = f.req_f64("C", "the Paris coefficient C in da/dN = C ΔK^m")?;
            if !(c > 0.0) || !c.is_finite() {
                return Err(f.error("C", format!("the Paris coefficient must be positive (got {c})")));
            }
            let m = f.req_f64("m", "the Paris exponent m in da/dN = C ΔK^m")?;
            if !(m > 0.0) || !m.is_finite() {
                return Err(f.error("m", format!("the Paris exponent must be positive (got {m})")));
            }
            let load_ratio = f.opt_f64("load_ratio")?.unwrap_or(0.0);
            if !(0.0..1.0).contains(&load_ratio) {
                return Err(f.error("load_ratio", format!("R = K_min/K_max must lie in [0, 1) (got {load_ratio})")));
            }
            let threshold = f.opt_f64("threshold")?.unwrap_or(0.0);
            if !(threshold >= 0.0) || !threshold.is_finite() {
                return Err(f.error("threshold", format!("the threshold ΔK_th must be ≥ 0 (got {threshold})")));
            }
            let min_load_factor = f.opt_f64("min_load_factor")?;
            if let Some(v) = min_load_factor {
                if !(v < 1.0) || !v.is_finite() {
                    return Err(f.error(
                        "min_load_factor",
                        format!("the cycle's minimum is the loads × min_load_factor, a number below 1 (got {v})"),
                    ));
                }
                if f.has("load_ratio") {
                    return Err(f.error(
                        "min_load_factor",
                        "give either load_ratio (K_min = R K_max, the faces open) or min_load_factor (the minimum solved), not both",
                    ));
                }
                if let Some(c) = cracks.iter().find(|c| v < 0.0 && c.contact.is_none()) {
                    return Err(f.error(
                        "min_load_factor",
                        format!(
                            "min_load_factor = {v} < 0 is a compressive minimum, but crack '{}' has no [cracks.contact]: its faces would pass through each other at the minimum (give it [cracks.contact], or a min_load_factor ≥ 0)",
                            c.name
                        ),
                    ));
                }
            }
            f.finish(&["C", "m", "load_ratio", "min_load_factor", "threshold"])?;
            Some(Fatigue { c, m, load_ratio, min_load_factor, threshold })
        }
    };
    if fatigue.is_some() && exponent.is_some() {
        return Err(p.error(
            "exponent",
            "the exponent is for quasi-static growth; in fatigue the advances follow the Paris exponent m",
        ));
    }
    if fatigue.is_some() && p.has("threshold") {
        return Err(p.error("threshold", "in fatigue the threshold is ΔK_th, [propagation.fatigue] threshold"));
    }
    p.finish(&[
        "criterion",
        "increment",
        "steps",
        "exponent",
        "fracture_toughness",
        "stop_length",
        "threshold",
        "fatigue",
    ])?;
    let options = Propagation {
        criterion,
        increment,
        steps,
        exponent: exponent.unwrap_or(2.0),
        fracture_toughness,
        stop_length,
        threshold,
        fatigue,
    };
    let increment_at = Located { line: p.error("increment", "").line, ..located(&p) };
    Ok(Some(PropagationDef { options, at: located(&p), increment_at }))
}
