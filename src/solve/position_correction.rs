//! The position correction of the velocity contact formulation in dynamics: after a time
//! step whose contact loops converged with the velocity law (⟦v_{n+1}⟧_n = 0 where the lips
//! touch, [`super::dynamics`]), the displacements alone are projected back onto the lips'
//! non-penetration d_n ≥ 0; the velocities, accelerations, contact pressures and statuses
//! of the step are the velocity law's. The constraint is so enforced at both levels, the
//! velocity (the impact law, which sets the rebound and the energy) and the position (no
//! overlap), each with its own multiplier (Brüls, Acary & Cardona, CMAME 281 (2014)
//! 131–161; the Gear–Gupta–Leimkuhler stabilisation).
//!
//! Entry points: [`overlap`] (the largest overlap of the velocity-law points, the test
//! that a step needs the correction) and [`correct_positions`].
//!
//! ```text
//! A Δu + Gᵀ ν = 0,   0 ≤ ν ⊥ d_n(u_{n+1} + Δu) ≥ 0,   A = K + ε M/(β Δt²)   (ε = MASS_WEIGHT)
//! ```
//!
//! The metric is the stiffness: Δu is the displacement of least strain energy that removes
//! the overlap. The correction changes the strain energy by Δuᵀ K (u + ½ Δu) and, with
//! K Δu = Gᵀ ν, that is −½ ν d for the overlap d: a floating body (the usual impact) moves
//! rigidly and keeps its energy, a held one loses ½ k d² (k its stiffness at the point;
//! d = O(Δt v)). A metric dominated by the mass (M, or the step's effective matrix
//! (1 − α) K + M/(β Δt²)) moves only the lips' neighbourhood and adds the work of the
//! contact pressure on the overlap, ≈ λ d, O(Δt) relative (measured on the bar against a
//! wall with the effective matrix: kinetic + strain after the impact +1.7% at h = 0.05,
//! `docs/contact-algorithms.md`, "Position correction"). ε M only fixes the rigid modes.
//!
//! The correction is one more pass of the contact loops
//! ([`super::contact_loops::solve_contact`]) on its own set-up and system (A with the contact terms;
//! analysed once, at the first correction, its factor carried from one correction to
//! the next while the statuses hold), with
//! - Δu as the unknown, every load, prescribed value and constraint right-hand side zero
//!   (the kernels' loads taken out again by a dof load,
//!   [`super::setup::FixedKernels::dof_loads`]): A Δu + (contact forces of Δu) = 0;
//! - every point on the gap law, its gap shifted by its jump at u_{n+1} (the displacement
//!   formulation's law on d_n(u_{n+1} + Δu): the same law and kernel), frictionless
//!   ([`frictionless`]: the correction is normal to the lips), from a copy of the step's
//!   statuses. Its set-up
//!   ([`super::setup::Setup`] of the frictionless contact) has the dofs of the step's.
//!
//! The multipliers it finds (ν) and its statuses are discarded; only the displacement
//! unknowns move. Its work on the body is the change of the strain energy (the kinetic
//! energy is kept): the driver books it in the contact work.

use super::contact_loops::solve_contact;
use super::observe::SolveObserver;
use super::report::{ContactReport, SolveError, Timings};
use super::setup::{Setup, System};
use crate::assembly::Kernel;
use crate::contact::law::PointState;
use crate::contact::pairing::Pairing;
use crate::contact::points::ContactFormulation;
use crate::contact::state::{point_values, PointValues};
use crate::contact::ContactSetup;
use crate::geometry::vec3::dot;
use crate::physics::inertia::{EffectiveKernel, ElementMatrices};

/// An overlap of the lips below this fraction of its crack's cell size is round-off: the
/// correction leaves it.
pub const OVERLAP_ROUND_OFF: f64 = 1e-12;

/// The largest overlap d_n > 0 (the gap without the velocity law's shift) over the points
/// of velocity-formulation cracks, with `vals` the point values of the step's solution,
/// and whether some point's overlap exceeds [`OVERLAP_ROUND_OFF`] × its crack's cell size.
pub fn overlap(c: &ContactSetup, state: &[PointState], vals: &[PointValues]) -> (f64, bool) {
    let pts = &c.points;
    let (mut largest, mut beyond) = (0.0f64, false);
    for ((st, p), v) in state.iter().zip(&pts.points).zip(vals) {
        let cc = &pts.cracks[p.crack];
        if cc.formulation != ContactFormulation::Velocity || !v.paired {
            continue;
        }
        let d_n = cc.law.penetration(v.jump, p.normal, st.gap_offset() - st.gap_shift);
        largest = largest.max(d_n);
        beyond |= d_n > OVERLAP_ROUND_OFF * cc.cell_size;
    }
    (largest, beyond)
}

/// The weight ε of the mass in the correction's metric K + ε M/(β Δt²): small enough that
/// a floating body's correction is its rigid shift to 1e-6 × its deformation energy scale
/// ((ω₁ Δt)² ≫ ε β for any usual step), large enough to keep the metric positive definite
/// on rigid modes with a condition number of order (ω_max Δt)²/ε.
pub const MASS_WEIGHT: f64 = 1e-6;

/// The gap shift, in cell sizes, that sets a point far apart (inert) in the correction.
const FAR_APART: f64 = 1e6;

/// The contact set-up of the correction: `c` with every law frictionless. The correction
/// enforces d_n ≥ 0 only: a tangential force would hold the tangential rigid modes, on
/// which K + ε M is soft, and a friction law there would measure the slip of the
/// correction from the start of the step.
pub fn frictionless(c: &ContactSetup) -> ContactSetup {
    let mut f = c.clone();
    for cc in &mut f.points.cracks {
        cc.law.friction = 0.0;
    }
    f
}

/// What a correction did.
#[derive(Debug, Clone)]
pub struct Correction {
    /// The largest overlap of the lips it removed (length).
    pub overlap_removed: f64,
    /// Δu on every dof (0 on the multiplier unknowns).
    pub du: Vec<f64>,
    /// Its contact loops' counts (factorisations, solves).
    pub report: ContactReport,
}

/// The step's data the correction reads.
pub struct StepData {
    pub step: usize,
    /// The time of the step's loads (t_{n+1} − α Δt) and of its constraints (t_{n+1}).
    pub t_load: f64,
    pub t_constraint: f64,
    /// 1/(β Δt²).
    pub c_m: f64,
}

/// Projects the displacement unknowns of `u` (the velocity step's solution) onto d_n ≥ 0
/// in the metric A = K + ε M/(β Δt²) (the module doc), on the correction's own set-up
/// `setup` (the frictionless contact, [`frictionless`]) and system `system` (built on
/// first use, its factor kept while the statuses hold). `state` are the step's point
/// states, `n_primal` the number of displacement unknowns. `u`'s multiplier unknowns,
/// `state` and `pairing` are left as they are. Small sliding only (the jump is linear in
/// the unknowns): the driver does not call it with a large-sliding crack.
///
/// The unknown is Δu itself, not u + Δu: the correction is many orders below u (an
/// overlap of O(Δt v) against the whole displacement), and its multipliers, solved as the
/// small differences of large forces, would stall the Newton loop's relative measure at
/// round-off. So every load, prescribed value and constraint right-hand side is zero, and
/// the gap of each point is shifted by its jump at u: d_n(Δu) = −(⟦u⟧ + ⟦Δu⟧)·n − g₀ − w.
#[allow(clippy::too_many_arguments)]
pub fn correct_positions(
    setup: &Setup<'_, '_>,
    system: &mut Option<System>,
    em: &ElementMatrices,
    data: &StepData,
    u: &mut [f64],
    state: &[PointState],
    pairing: &Option<Pairing>,
    overlap_removed: f64,
    n_primal: usize,
    timings: &mut Timings,
    observer: &dyn SolveObserver,
) -> Result<Correction, SolveError> {
    let c = setup.contact.expect("a contact setup");
    let n_total = u.len();
    let zeros = vec![0.0; n_total];
    let zero_mult = vec![0.0; setup.mult_rows.len()];
    let kernels = || {
        let metric = EffectiveKernel {
            matrices: em,
            loads: Box::new(setup.bulk(data.t_load)),
            c_k: 1.0,
            c_m: MASS_WEIGHT * data.c_m,
            c_p: 0.0,
            predictor: &zeros,
            previous: &zeros,
            element_products: false,
        };
        setup.dynamic_kernels(metric, data.t_load, data.t_constraint, &zero_mult)
    };
    // Each point's gap shifted by its jump at u. Points of laws without multipliers
    // (penalty, asperity layer: springs on the gap, whose forces at u are the step's) are
    // set far apart: they do not act in the correction.
    let vals = point_values(setup.model, &c.points, pairing.as_ref(), state, u);
    let mut st: Vec<PointState> = state.to_vec();
    for ((s, p), v) in st.iter_mut().zip(&c.points.points).zip(&vals) {
        let cc = &c.points.cracks[p.crack];
        s.gap_shift = if cc.law.method.has_multipliers() && cc.law.asperity.is_none() {
            dot(v.jump, p.normal)
        } else {
            FAR_APART * cc.cell_size
        };
    }
    if system.is_none() {
        // PETSc: distributed as the time step's system, on the same partition (METIS is
        // deterministic: the same cells on the same rank, whose element matrices `em` holds).
        let mut layout = match setup.build_layout_owned_unrecorded(pairing.as_ref(), &st)? {
            Some(layout) => layout,
            None => setup.build_layout(pairing.as_ref(), &st),
        };
        if layout.is_distributed() && (0..em.n_elements()).any(|e| layout.owns(0, e) != em.holds(e)) {
            return Err(SolveError::Dynamics(
                "the position correction's partition of the cells differs from the time step's".into(),
            ));
        }
        let solver = setup.analyse(&layout, data.step)?;
        if let Some(rows) = layout.distributed.as_mut() {
            // The preallocation counts are in PETSc's matrix now.
            (rows.d_nnz, rows.o_nnz) = (Vec::new(), Vec::new());
        }
        let mut sys = System::new(layout, solver);
        // The same K + ε M at every correction: its factor is kept while the statuses hold.
        sys.carry_factor = true;
        *system = Some(sys);
    }
    let sys = system.as_mut().expect("built above");
    // Every load of the kernels (body forces, tractions, crack pressure, the relations'
    // right-hand sides) taken out again: their residual at zero, as a dof load.
    let loads = {
        let (fixed, ck) = (kernels(), setup.contact_kernel(&st, &zeros, pairing.as_ref()).expect("contact"));
        let mut list: Vec<&dyn Kernel> = fixed.list().to_vec();
        list.push(&ck);
        // Distributed: this rank's elements' share, added to its share of the load vector
        // (the contact loops sum the two over the ranks).
        sys.layout.element_forces_touching(&list, &[true, true, true, true, false], None, &zeros)
    };
    let mut fixed = kernels();
    fixed.dof_loads = Some(&loads);
    let mut x = zeros.clone();
    let mut pr = pairing.clone();
    let report = solve_contact(setup, sys, &fixed, &zeros, data.step, &mut x, &mut st, &mut pr, timings, observer)?;
    let mut du = vec![0.0; n_total];
    du[..n_primal].copy_from_slice(&x[..n_primal]);
    for (u, x) in u.iter_mut().zip(&du) {
        *u += x;
    }
    Ok(Correction { overlap_removed, du, report })
}
