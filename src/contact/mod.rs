//! Frictional contact on crack faces (formulation §4–6): the LBB-stable multiplier space,
//! the contact points on the crack facets and the numbering of their unknowns, the
//! pairing of large sliding, the pointwise law (gap, normal and Coulomb friction laws
//! with their residual and tangent at one point), the point kinematics and statuses, and
//! the contact kernel that scatters the law into element vectors.
//!
//! Entry points: [`multipliers::multiplier_space`], [`points::ContactPoints::build`],
//! [`pairing::pair`], [`law::CrackLaw`], [`state::point_values`], [`lip_wear::LipChart`],
//! [`kernel::ContactKernel`]; the pressure recovered from the multipliers,
//! [`recovery::recovered_pressure`]; the statuses a growing crack carries to its next geometry,
//! [`carry::CarriedStatuses`]; the multipliers that Dirichlet conditions make redundant,
//! [`crosspoints::find`]; the contact zone of a meshed pair and its check, [`zone::check`]. The loops that drive them are the solver's
//! (`solve::contact_loops`); this module never calls them.
//!
//! Unknowns and signs (docs/conventions.md, "Contact"): λ is the normal traction, λ ≤ 0 in
//! compression; Λ the friction semi-multiplier (tangential traction μ λ Λ, |Λ| ≤ 1); the
//! penetration d_n = −⟦u⟧·n − g₀ is positive when the lips overlap.

pub mod carry;
pub mod crosspoints;
pub mod kernel;
pub mod law;
pub mod lip_wear;
pub mod multipliers;
pub mod pairing;
pub mod points;
pub mod recovery;
pub mod state;
pub mod surfaces;
pub mod zone;

use points::ContactPoints;

/// Which loop structure drives the contact statuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactAlgorithm {
    /// Friction fixed point ⊃ active set ⊃ Newton (the founding paper's nested loops).
    Nested,
    /// One generalized Newton loop updating the contact status, the threshold and the
    /// stick/slip status in every iteration.
    SemiSmooth,
}

/// Caps and tolerances of the loops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLoops {
    pub algorithm: ContactAlgorithm,
    pub max_friction: usize,
    /// Relative change of λ that ends the friction fixed point.
    pub tol_friction: f64,
    pub max_active_set: usize,
    pub max_newton: usize,
    /// Relative size of the Newton correction that ends the Newton loop.
    pub tol_newton: f64,
    /// Geometry loop (large sliding): cap on the re-pairings per step.
    pub max_geometry: usize,
    /// The geometry loop ends when no master point moved by more than this fraction of
    /// the cell size between two pairings (and no point entered or left the master lip).
    pub tol_geometry: f64,
    /// The friction thresholds that are functions of the displacements (the penalty
    /// law's, [`law::CrackLaw::has_live_threshold`]) follow the iterate inside the Newton
    /// loop, with their derivative in the (then unsymmetric) tangent, where the factor is
    /// condensed (`[contact_solver] friction_threshold = "newton"`, the default); false:
    /// frozen in each Newton loop and updated by the fixed point (`"fixed_point"`).
    pub threshold_in_newton: bool,
    /// Whether the augmented and stabilised Lagrangians' thresholds (λ̄ = λ, small
    /// sliding; with wear as [`law::CrackLaw::has_live_threshold`] says) follow the Newton loop too: `Some` when `friction_threshold` is
    /// given. Unset (`None`), the stabilised law's do (fewer Newton iterations and less
    /// time on the contact bench) and the augmented Lagrangian's keep their fixed point
    /// (faster there: the unsymmetric LU of the crack block costs more than the passes it
    /// saves); a model with an augmented-Lagrangian crack with friction then keeps every
    /// threshold frozen (docs/contact-algorithms.md).
    pub threshold_in_newton_multipliers: Option<bool>,
    /// The friction fixed point's intermediate passes end their Newton loop provisionally
    /// (`[contact_solver] intermediate_passes = "provisional"`, the default): once the
    /// statuses settle, without the solve that would confirm the last correction; the pass
    /// whose thresholds meet `tol_friction` is solved again on its own thresholds to
    /// `tol_newton` (`solve::contact_loops`, `Loops::friction_loop`). False
    /// (`"confirmed"`): every pass's Newton loop runs to `tol_newton`.
    pub provisional_passes: bool,
}

impl Default for ContactLoops {
    fn default() -> Self {
        ContactLoops {
            algorithm: ContactAlgorithm::Nested,
            max_friction: 20,
            tol_friction: 1e-6,
            max_active_set: 30,
            max_newton: 30,
            tol_newton: 1e-8,
            max_geometry: 10,
            tol_geometry: 1e-6,
            threshold_in_newton: true,
            threshold_in_newton_multipliers: None,
            provisional_passes: true,
        }
    }
}

/// The contact of a model: its points and unknowns, and how the loops run.
#[derive(Debug, Clone)]
pub struct ContactSetup {
    pub points: ContactPoints,
    pub loops: ContactLoops,
    /// The multiplier components that the Dirichlet conditions of both sides make
    /// redundant: eliminated from the system (`solve::setup`).
    pub crosspoints: crosspoints::Crosspoints,
}

impl ContactSetup {
    /// Whether some crack's law has multiplier unknowns (then the system is symmetric
    /// indefinite: LDLᵀ, condensed onto the crack unknowns).
    pub fn has_multipliers(&self) -> bool {
        self.points.cracks.iter().any(|c| c.law.method.has_multipliers())
    }
}

/// Barycentric coordinates of a point of a flat facet (segment or triangle).
pub fn facet_barycentric(vertices: &[[f64; 3]], x: [f64; 3]) -> Vec<f64> {
    let d = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    if vertices.len() == 2 {
        let e = sub(vertices[1], vertices[0]);
        let t = (d(sub(x, vertices[0]), e) / d(e, e).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        return vec![1.0 - t, t];
    }
    let (v0, v1, v2) = (sub(vertices[1], vertices[0]), sub(vertices[2], vertices[0]), sub(x, vertices[0]));
    let (d00, d01, d11, d20, d21) = (d(v0, v0), d(v0, v1), d(v1, v1), d(v2, v0), d(v2, v1));
    let den = (d00 * d11 - d01 * d01).max(f64::MIN_POSITIVE);
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    vec![1.0 - v - w, v, w]
}

/// The contact traction on the `+` lip of facet `f` of contact crack `ci` at point `x`
/// (the `−` lip carries the opposite): t⁺ = −λ n + μ λ Σ Λ_α τ_α, from the multipliers in `u`.
pub fn face_traction(
    points: &ContactPoints,
    ci: usize,
    facet: &crate::cut::Facet,
    f: usize,
    x: [f64; 3],
    u: &[f64],
) -> [f64; 3] {
    let cc = &points.cracks[ci];
    let bary = facet_barycentric(&facet.vertices, x);
    let mut terms = vec![];
    cc.space.point_terms(f, &bary, &mut terms);
    let (lam, tl) = state::multipliers_at(points, ci, &terms, u);
    let n = facet.normal;
    let tb = points::tangent_basis(points.dim, n, cc.tangent_reference);
    let mut t = [-lam * n[0], -lam * n[1], -lam * n[2]];
    for a in 0..points.dim - 1 {
        for i in 0..3 {
            t[i] += cc.law.friction * lam * tl[a] * tb[a][i];
        }
    }
    t
}
