//! Newton on frozen statuses: the innermost loop of the contact loops (formulation §6),
//! and the single linear solve of a model without contact.
//!
//! Entry points: [`Newton::run`] (iterations with the contact and friction thresholds
//! frozen, the stick/slip status updated every iteration), [`linear_step`].
//!
//! The bulk matrix K does not change (linear elasticity, small sliding): it is assembled
//! once, every iteration adds the contact terms to it in place (and restores it,
//! [`ContactColumns`]), and the linear solver factorises it once and condenses each
//! iteration onto the crack unknowns (`FaerSolver::analyse_condensed`; after the first
//! solve of a step the Newton corrections defer the interior). The numeric factorisation is
//! redone only when a status or a threshold changed; otherwise the previous factor solves
//! the next correction (exact in 2D; in 3D the slip direction of a sliding point with a
//! nonzero friction bound μλ̄ also enters the tangent, so those steps are modified-Newton
//! steps, and a step that does not halve the correction triggers a refactorisation; a
//! frictionless pass, every λ̄ = 0, is exact). The time-step driver keeps the factor and its signature
//! from one step to the next ([`super::setup::CarriedFactor`]: its effective matrix is
//! the same at every step), so a time step without a status change factorises nothing.
//!
//! Cap: the caller's `max_iter` ([`crate::contact::ContactLoops::max_newton`]); tolerance:
//! the relative correction [`crate::contact::ContactLoops::tol_newton`] (or the round-off
//! floor, [`ROUNDOFF_FLOOR`], or an iterative backend's residual at its round-off,
//! [`LinearSolver::iterative_residuals`]); log line `newton {it}: open .. stick .. slip .. max|Λ| .. corr ..`
//! with `FISSURE_CONTACT_LOG` set (plus the times of the assembly, factorisation and solve,
//! and each block's relative correction with the backend's ‖b‖ and ‖Ax − b‖).
//! Every iteration is also reported to the step's [`SolveObserver`] (status counts,
//! statuses changed, correction, factorised or not: `fissure run --verbose`).

use super::linear::LinearSolver;
use super::observe::{NewtonIteration, Phase, SolveObserver};
use super::report::{ContactReport, SolveError, SolveOptions, Timings};
use super::setup::{FixedKernels, System};
use crate::assembly::{Kernel, SystemLayout, NO_EQ};
use crate::contact::kernel::ContactKernel;
use crate::contact::law::{Method, PointState, Status, WearCoupling};
use crate::contact::pairing::Pairing;
use crate::contact::points::ContactPoints;
use crate::contact::state::{
    freeze_statuses, hold_reversed_slips, live_thresholds, point_values, set_threshold_scales, statuses,
    update_contact_status, PointValues, COULOMB_TIE,
};
use crate::contact::ContactLoops;
use crate::physics::model::Model;
use std::time::Instant;

/// Whether the contact loops log one line per iteration (`FISSURE_CONTACT_LOG` set).
pub fn contact_log() -> bool {
    std::env::var("FISSURE_CONTACT_LOG").is_ok()
}

/// Relative Newton correction below which a correction that stopped shrinking (with the
/// statuses unchanged and an exact tangent) is taken as the linear solver's round-off.
pub const ROUNDOFF_FLOOR: f64 = 1e-6;

/// Relative Newton correction of the asymptotic phase: above it an iterative backend's
/// residual that stops shrinking is not taken as its round-off (`Newton::run`).
const ASYMPTOTIC_BELOW: f64 = 1e-3;

/// Relative Newton correction below which a 3D sliding step may reuse the previous factor.
const STALE_FACTOR_BELOW: f64 = 1e-3;

/// Relative Newton correction below which a plain factor of a tangent that moves with the
/// iterate (asperity layer, implicit wear) is reused with the same statuses, as modified
/// Newton steps (refreshed when one does not halve the correction). The wear platen's
/// first friction pass refactorised at a correction of 6e-3 and took one more exact step;
/// its modified steps from there converge in two solves, one factorisation of the whole
/// system fewer a step (`docs/performance.md`, "Threshold start").
const STALE_NONLINEAR_BELOW: f64 = 1e-2;

/// Relative change of the friction thresholds since the factorisation, max |λ̄ − λ̄_f| /
/// max |λ̄_f|, below which an iteration with the same statuses may reuse a plain
/// (not condensed) factor: a modified Newton step whose tangent is off by that fraction
/// in the friction terms only, so that each step contracts the correction by about as much
/// (refreshed when it stops halving it). A friction pass that moves the thresholds by 1e-3
/// then costs back-substitutions instead of a factorisation of the whole system.
const STALE_THRESHOLDS_BELOW: f64 = 1e-2;

/// Relative correction of the displacements and of the normal multipliers λ (each block
/// in its own units) below which a Newton loop on frozen stick/slip statuses may end at an
/// iterate where the contact statuses change ([`Newton::allow_contact_change_end`]): the
/// contact law reads λ and the gap only, and with those within this fraction the update
/// the caller makes next is that of the converged loop; the scale of the asymptotic phase
/// ([`STALE_FACTOR_BELOW`]). The tangential multipliers Λ are not required to converge:
/// the iteration is not accepted, and the next active-set iteration continues Newton from
/// the iterate.
const CONTACT_CHANGE_END_BELOW: f64 = 1e-3;

/// Everything a contact step works on.
pub struct StepContext<'a, 'm> {
    pub model: &'a Model<'m>,
    pub points: &'a ContactPoints,
    pub loops: &'a ContactLoops,
    pub layout: &'a SystemLayout,
    /// The fixed kernels (bulk, loads, Dirichlet multipliers) in layout order, without the
    /// contact kernel, which is always the last one.
    pub fixed: &'a [&'a dyn Kernel],
    /// Load vector of the step, lifted by the prescribed values.
    pub rhs_f: &'a [f64],
    pub step: usize,
    /// The pairing of the large-sliding cracks (frozen for this call).
    pub pairing: Option<&'a Pairing>,
    /// Told the factorisations and every Newton iteration.
    pub observer: &'a dyn SolveObserver,
    /// Every dof at the start of the step (for the slip increment v_τ).
    pub u_start: &'a [f64],
    /// A later pass of the geometry loop: the statuses, thresholds and dofs are those of
    /// the previous pass, already close; no stick predictor.
    pub warm: bool,
}

impl StepContext<'_, '_> {
    /// The contact kernel at a state and dof vector.
    pub fn kernel<'s>(&'s self, state: &'s [PointState], u: &'s [f64]) -> ContactKernel<'s> {
        ContactKernel {
            mesh: self.model.mesh,
            enrichment: &self.model.enrichment,
            cracks: &self.model.cracks,
            points: self.points,
            state,
            u,
            pairing: self.pairing,
            live_thresholds: false,
        }
    }

    /// A linear-solver failure at this step, with advice.
    pub fn linear_error(&self, advice: &'static str) -> impl Fn(super::linear::LinearError) -> SolveError + '_ {
        move |error| SolveError::Linear { step: self.step, error, advice }
    }
}

/// The values of K in the columns the contact kernel writes to (the equations of the dofs
/// of the contact elements), to restore K after adding contact terms in place.
pub struct ContactColumns {
    cols: Vec<usize>,
    saved: Vec<f64>,
}

impl ContactColumns {
    pub fn save(layout: &SystemLayout, contact: &dyn Kernel, values: &[f64]) -> ContactColumns {
        let mut mark = vec![false; layout.n_eq];
        let mut dofs = Vec::new();
        for e in 0..contact.n_elements() {
            dofs.clear();
            contact.dofs(e, &mut dofs);
            for &d in &dofs {
                let q = layout.eq_of_dof[d as usize];
                if q != NO_EQ {
                    mark[q as usize] = true;
                }
            }
        }
        let cols: Vec<usize> = (0..layout.n_eq).filter(|&q| mark[q]).collect();
        let cp = &layout.pattern.col_ptr;
        let saved = cols.iter().flat_map(|&j| values[cp[j]..cp[j + 1]].iter().copied()).collect();
        ContactColumns { cols, saved }
    }

    /// The equations the contact kernel writes to (ascending).
    pub fn columns(&self) -> &[usize] {
        &self.cols
    }

    /// Puts K back in the contact columns.
    pub fn restore(&self, cp: &[usize], values: &mut [f64]) {
        let mut k = 0;
        for &j in &self.cols {
            let len = cp[j + 1] - cp[j];
            values[cp[j]..cp[j + 1]].copy_from_slice(&self.saved[k..k + len]);
            k += len;
        }
    }
}

/// The Newton loop of one contact step, with what it carries from one call to the next
/// (the factor's signature, the last correction, the deferred interior).
pub struct Newton {
    rhs: Vec<f64>,
    kx: Vec<f64>,
    zeros: Vec<f64>,
    include: Vec<bool>,
    /// The rows and columns that contact changes (condensed factor): later iterations
    /// refresh and multiply only those (K is symmetric: row i is column i).
    varying: Option<Vec<usize>>,
    /// After the first solve the interior rows (bulk, linear) of the residual are
    /// round-off (condensed factor only; see `LinearSolver::zero_interior_rows`).
    interior_solved: bool,
    /// Whether the corrections after the first solve defer the interior
    /// (`LinearSolver::solve_in_place_deferred`): only without Dirichlet or relation
    /// multipliers. The deferred solve brings the crack rows up to date with the pending
    /// interior response, not the rows of such multipliers (a lip condition's rows read
    /// the wall's standard dofs): with them every correction came out the same, and the
    /// loop never converged (the bar against a lip-held wall from nx = 200, where the
    /// factor is condensed).
    defer: bool,
    stale_slow: bool,
    last_corr: f64,
    /// The signature of the factorised tangent: statuses and thresholds. Same signature,
    /// same matrix (2D, or 3D without slip).
    last_sig: Option<Vec<(u8, u64)>>,
    has_friction: bool,
    three_d: bool,
    /// The block of every equation ([`block_of_eq`]).
    block_of_eq: Vec<u8>,
    /// The largest ρ_n of the cracks (the floor of the λ scale).
    rho_n_max: f64,
    /// Some crack has friction: its sliding points' trial directions are watched
    /// ([`hold_reversed_slips`]).
    watch_slips: bool,
    /// The largest diagonal entry of K over the displacement equations (the floor of the
    /// scale of the other multipliers, [`reaction_floor`]); read from K at the first
    /// iteration.
    k_diag_max: Option<f64>,
    /// The smallest cell size along the cracks (the contact weight of a multiplier is
    /// about h^(dim−1): [`lambda_roundoff`]).
    h_min: f64,
    /// The relative round-off of λ at the last iterate ([`lambda_roundoff`] over max |λ|).
    lambda_roundoff: f64,
    slip_directions: Vec<[f64; 2]>,
    /// Some crack has an asperity layer or implicit wear: its tangent changes with d_n
    /// (with λ and the slip) in every iteration, so every iteration factorises.
    smooth_nonlinear: bool,
    /// The statuses of the previous iteration of the step (for the observer's count of
    /// changes).
    prev_status: Vec<Status>,
    /// Some crack's friction threshold follows the iterate (the penalty law's, or the λ of the
    /// augmented and stabilised Lagrangians in small sliding,
    /// [`crate::contact::law::CrackLaw::has_live_threshold`]) and the factor is condensed,
    /// whose dense crack block takes an unsymmetric tangent (LU): every iteration sets those
    /// thresholds from the iterate and the tangent carries their slope, so that the
    /// friction fixed point converges with the Newton loop instead of one pass per update.
    /// The other factors (sparse LDLᵀ, Cholesky) are symmetric: the thresholds stay frozen.
    live: bool,
    /// Accept an exact first step on its confirming iteration (a time step resumed from
    /// a carried factor: [`Newton::confirm_exact_steps`]).
    confirm_exact: bool,
    /// The last iteration was a full solve (not deferred) of an exact Newton step.
    full_exact_last: bool,
    /// The crack rows of the solution before the last deferred correction (`varying`).
    saved_rows: Vec<f64>,
    /// A linear solve was made in this step (the direct first iteration is the first).
    solved_once: bool,
    /// The caller allows a provisional end of the loop ([`Newton::allow_provisional`]).
    provisional: bool,
    /// The last [`Newton::run`] ended provisionally: its last iterate was not confirmed by
    /// a converged correction.
    unconfirmed: bool,
    /// The stick/slip/open statuses of every iteration of the last [`Newton::run`], in
    /// order (the caller's check for a cycle of the active-set loop,
    /// [`Newton::visited`]).
    visited: Vec<Vec<Status>>,
    /// Per point: its stick/slip status changed within the status cycle the last
    /// [`Newton::run`] froze (empty without one): frozen sliding ([`Newton::cyclers`]).
    cyclers: Vec<bool>,
    /// An iterative backend's ‖b‖ and ‖Ax − b‖ of the last iteration's solve, when that
    /// was an exact step (the backend's floor, [`Newton::run`]).
    lin_prev: Option<(f64, f64)>,
    /// Friction steps are damped where the statuses change without the corrections
    /// contracting ([`Newton::damp`]).
    damped: bool,
    /// The caller's permission to end a loop on frozen statuses where the contact statuses
    /// change ([`Newton::allow_contact_change_end`]), with its points kept closed
    /// whatever the law (the active set's sticky points).
    contact_change_end: Option<Vec<bool>>,
    /// The last [`Newton::run`] ended that way.
    ended_at_contact_change: bool,
}

/// The shortest damped step ([`Newton::damp`]), a fraction of the Newton correction.
const MIN_STEP: f64 = 1.0 / 16.0;

/// The blocks of unknowns whose corrections are measured separately: displacements (and
/// enrichments), normal multipliers λ (a traction), friction multipliers Λ
/// (dimensionless) and the other multipliers (Dirichlet reactions).
const N_BLOCKS: usize = 4;

/// The block (index below [`N_BLOCKS`]) of every equation.
fn block_of_eq(layout: &SystemLayout, points: &ContactPoints) -> Vec<u8> {
    let mut block: Vec<u8> = (0..layout.n_eq).map(|q| if q < layout.n_primal_eq { 0 } else { 3 }).collect();
    for (c, cc) in points.cracks.iter().enumerate() {
        for j in 0..cc.space.n_unknowns as u32 {
            let mut mark = |dof: usize, b: u8| {
                let q = layout.eq_of_dof[dof];
                if q != NO_EQ {
                    block[q as usize] = b;
                }
            };
            mark(points.lambda_dof(c, j), 1);
            for a in 0..points.dim - 1 {
                mark(points.tangent_dof(c, j, a), 2);
            }
        }
    }
    block
}

/// The floor of the scale of the Dirichlet and relation multipliers (block 3, forces):
/// k_max·max|u|, the force the largest displacement makes on the stiffest unknown. A
/// displacement correction within the tolerance, |δu| ≤ tol·max|u|, changes the forces by
/// up to about tol·k_max·max|u|, so a reaction correction below that is as converged as the
/// displacements. Without the floor a support that carries nothing (a lip condition holding
/// a wall that every contact point has left) has multipliers of round-off size, and their
/// round-off corrections measured against themselves never fall below the tolerance.
fn reaction_floor(k_diag_max: f64, u_max: f64) -> f64 {
    k_diag_max * u_max
}

/// The terms of a row of K that a residual sums, in the bound of its round-off (an
/// enriched node of a 2D quad4 mesh couples 9 nodes × 2 components × 2 (standard and
/// Heaviside) = 36 unknowns; the noise measured below is 0.3–2.4 times ε k_max u_max /
/// h^(dim−1), so 16 of them bound it with a margin).
const ROUNDOFF_TERMS: f64 = 16.0;

/// The round-off of the normal multipliers λ (a traction) at a Newton iterate: the nodal
/// forces of the residual, sums of K_ij u_j, carry an error of about
/// [`ROUNDOFF_TERMS`] · ε · k_max · max|u|, spread over a contact weight of h^(dim−1). It is
/// the model's own floor of the λ corrections, below the default tolerances in ordinary
/// models but not where the stiffest material's forces at the largest displacement dwarf
/// the contact force: a steel block in Pa (E/p = 2.1e8) sliding 1e-3 m on a base 1e6
/// times stiffer stalled at a relative λ correction of 4e-5–7e-5 (0.3–0.6 Pa of 8.1e3;
/// this bound: 37 Pa), and at E/p = 1e12 (E = 1) one material stalled at 1e-5 (bound:
/// 7e-5), both above [`ROUNDOFF_FLOOR`].
fn lambda_roundoff(k_diag_max: f64, u_max: f64, h: f64, dim: usize) -> f64 {
    ROUNDOFF_TERMS * f64::EPSILON * k_diag_max * u_max / h.powi(dim as i32 - 1)
}

/// The largest |K_jj| over the displacement equations (`values` on the layout's pattern).
fn max_primal_diagonal(layout: &SystemLayout, values: &[f64]) -> f64 {
    (0..layout.n_primal_eq).filter_map(|j| layout.pattern.position(j, j)).map(|k| values[k].abs()).fold(0.0, f64::max)
}

/// The relative size of a Newton correction: the largest over the blocks of
/// max |correction| / max |value| (1 for a block whose values are all zero after a nonzero
/// correction). Each block is measured in its own units, so the figure does not depend on
/// the unit system (displacements, tractions and the dimensionless Λ are never compared).
fn relative_correction(dn: &[f64; N_BLOCKS], xn: &[f64; N_BLOCKS]) -> f64 {
    dn.iter()
        .zip(xn)
        .map(|(&d, &x)| {
            if d == 0.0 {
                0.0
            } else if x > 0.0 {
                d / x
            } else {
                1.0
            }
        })
        .fold(0.0, f64::max)
}

impl Newton {
    pub fn new(ctx: &StepContext<'_, '_>, solver: &LinearSolver, n_dofs: usize) -> Newton {
        let mut include = vec![false; ctx.fixed.len() + 1];
        *include.last_mut().expect("the contact kernel") = true;
        let block_of_eq = block_of_eq(ctx.layout, ctx.points);
        let defer = !block_of_eq.contains(&3);
        Newton {
            rhs: vec![0.0; ctx.layout.n_eq],
            kx: vec![0.0; ctx.layout.n_eq],
            zeros: vec![0.0; n_dofs],
            include,
            varying: solver.varying_unknowns().filter(|_| defer),
            interior_solved: false,
            defer,
            stale_slow: false,
            last_corr: f64::INFINITY,
            last_sig: None,
            has_friction: ctx.points.cracks.iter().any(|c| c.law.friction > 0.0),
            three_d: ctx.points.dim == 3,
            block_of_eq,
            rho_n_max: ctx.points.cracks.iter().map(|c| c.law.rho_n).fold(0.0, f64::max),
            watch_slips: ctx.points.cracks.iter().any(|c| c.law.friction > 0.0),
            k_diag_max: None,
            lambda_roundoff: 0.0,
            h_min: ctx.points.cracks.iter().map(|c| c.cell_size).fold(f64::INFINITY, f64::min),
            slip_directions: Vec::new(),
            smooth_nonlinear: ctx
                .points
                .cracks
                .iter()
                .any(|c| c.law.asperity.is_some() || c.law.wear.is_some_and(|w| w.coupling == WearCoupling::Implicit)),
            prev_status: Vec::new(),
            live: ctx.loops.threshold_in_newton
                && solver.is_condensed()
                && ctx.points.cracks.iter().any(|c| c.law.has_live_threshold(c.large_sliding))
                && ctx.points.cracks.iter().all(|c| {
                    // A multiplier law's threshold follows the loop where asked, by default for
                    // the stabilised law only ([`crate::contact::ContactLoops`]).
                    let multiplier_live = c.law.method.has_multipliers() && c.law.has_live_threshold(c.large_sliding);
                    !multiplier_live
                        || ctx.loops.threshold_in_newton_multipliers.unwrap_or(c.law.method == Method::Stabilised)
                }),
            confirm_exact: false,
            full_exact_last: false,
            saved_rows: Vec::new(),
            solved_once: false,
            provisional: false,
            unconfirmed: false,
            visited: Vec::new(),
            cyclers: Vec::new(),
            lin_prev: None,
            damped: false,
            contact_change_end: None,
            ended_at_contact_change: false,
        }
    }

    /// Allows (`Some(sticky)`) or forbids (`None`) the next runs to end a loop whose
    /// stick/slip statuses were frozen (at a third of the cap, or at a status cycle) as
    /// soon as its displacements and λ have converged to `CONTACT_CHANGE_END_BELOW` (1e-3) at an
    /// iterate where the contact statuses the caller's update would set differ from the
    /// frozen ones (`sticky`: points the caller keeps closed whatever the law). The caller
    /// (the active-set loop, while it has closed no contact cycle) accepts no iteration
    /// whose contact statuses change, so converging the tangential multipliers on
    /// statuses about to change only costs iterations: on the 3D Hertz sphere row the
    /// first friction pass froze its statuses at iteration 11, converged them in 6 more
    /// (the Λ of the packets on the symmetry planes near the contact's centre, weakly
    /// determined, took 4 to settle), and the update then changed 6 contact statuses. The
    /// next active-set iteration continues Newton from the iterate
    /// ([`Newton::ended_at_contact_change`]).
    pub fn allow_contact_change_end(&mut self, sticky: Option<&[bool]>) {
        self.contact_change_end = sticky.map(<[bool]>::to_vec);
    }

    /// Whether the last [`Newton::run`] ended at a contact-status change before its
    /// convergence ([`Newton::allow_contact_change_end`]).
    pub fn ended_at_contact_change(&self) -> bool {
        self.ended_at_contact_change
    }

    /// Allows (or forbids) the next runs to end provisionally (2D, or a 3D pass whose
    /// thresholds are all 0; no asperity layer): once
    /// an iteration after the first finds the stick/slip/open statuses of the last one (no
    /// point locked, the thresholds frozen), the loop ends before that iteration's solve, whose only use
    /// would be to confirm the last step's correction. The friction fixed point allows it
    /// in its intermediate passes, whose iterate only seeds the next pass (which continues
    /// the Newton iteration from it); the pass whose thresholds pass the tolerance is then
    /// confirmed by a full run on its own thresholds ([`Newton::unconfirmed`]).
    pub fn allow_provisional(&mut self, allow: bool) {
        self.provisional = allow;
    }

    /// Whether [`Newton::confirm_exact_steps`] was called.
    pub fn confirms_exact_steps(&self) -> bool {
        self.confirm_exact
    }

    /// Damps the steps of the friction passes from now on: an iteration whose
    /// stick/slip/open statuses changed while the last correction did not halve the one
    /// before takes half the step of the last (the generalized Newton step of the
    /// Alart–Curnier law overshoots: the whole stuck set of one iterate slides at the
    /// next, and back, a status cycle of hundreds of points), down to `MIN_STEP`; an
    /// iteration on unchanged statuses doubles it back up to the full step. The merit is the
    /// relative correction, per block of unknowns in its own units (scale-free); the
    /// correction is measured undamped for the convergence test. A damped step is the
    /// solve's correction scaled, the deferred interior response with it
    /// ([`LinearSolver::scale_last_deferred`]). The contact loops switch it on for the
    /// redo of a step whose plain loops failed ([`super::contact_loops`]).
    pub fn damp(&mut self) {
        self.damped = true;
    }

    /// Whether the last [`Newton::run`] ended provisionally (see
    /// [`Newton::allow_provisional`]).
    pub fn unconfirmed(&self) -> bool {
        self.unconfirmed
    }

    /// Per point, whether the last [`Newton::run`] froze it sliding as a point of a status
    /// cycle (its stick/slip status changed within the cycle); empty when no cycle was
    /// frozen.
    pub fn cyclers(&self) -> &[bool] {
        &self.cyclers
    }

    /// Whether some iteration of the last [`Newton::run`] after its first (whose statuses
    /// are the ones the loop inherits) had the statuses `statuses`.
    pub fn visited(&self, statuses: &[Status]) -> bool {
        self.visited.iter().skip(1).any(|v| v.as_slice() == statuses)
    }

    /// A confirming iteration that finds an exact step converged keeps the step's solution
    /// and drops its own correction. After a full solve of an exact Newton step (the
    /// tangent of the statuses it was solved with), an iteration on the same statuses
    /// whose correction passes the tolerance measures how far the step was from the
    /// answer; on this piecewise linear problem that correction is the linear solver's
    /// round-off. Kept, it would cost the interior's response to it
    /// ([`LinearSolver::apply_deferred`], a backward substitution through the whole bulk),
    /// about as much as the step's own solve: the correction (crack unknowns and
    /// multipliers) is taken back and its deferred interior response discarded, so the
    /// step's answer is the full solve's, consistent in every unknown. The convergence
    /// test itself is unchanged (the confirming correction still has to pass it). Used by
    /// the time-step driver (a factor carried from step to step, where every step without
    /// a status change is one exact step).
    pub fn confirm_exact_steps(&mut self) {
        self.confirm_exact = true;
    }

    /// Whether `sig` has the statuses of the factorised tangent and thresholds within
    /// [`STALE_THRESHOLDS_BELOW`] of its own.
    fn thresholds_near(&self, sig: &[(u8, u64)]) -> bool {
        let Some(last) = self.last_sig.as_ref().filter(|l| l.len() == sig.len()) else { return false };
        if last.iter().zip(sig).any(|(a, b)| a.0 != b.0) {
            return false;
        }
        let (mut diff, mut scale) = (0.0f64, 0.0f64);
        for (a, b) in last.iter().zip(sig) {
            let (fa, fb) = (f64::from_bits(a.1), f64::from_bits(b.1));
            if (fa == 0.0) != (fb == 0.0) {
                return false;
            }
            diff = diff.max((fa - fb).abs());
            scale = scale.max(fa.abs());
        }
        diff <= STALE_THRESHOLDS_BELOW * scale
    }

    /// The round-off of the normal multipliers relative to their largest value at the last
    /// iterate (`lambda_roundoff`): the friction loop measures the change of its
    /// thresholds (the λ of a pass) down to it.
    pub fn lambda_roundoff(&self) -> f64 {
        self.lambda_roundoff
    }

    /// Forgets the factorised tangent: the next iteration factorises again.
    pub fn forget_factor(&mut self) {
        self.last_sig = None;
    }

    /// Takes the solver's factor as the tangent of `signature` (a factor carried from the
    /// previous step, [`super::setup::CarriedFactor`]): the first iteration reuses it when
    /// the statuses and thresholds are the same.
    pub fn resume_factor(&mut self, signature: Vec<(u8, u64)>) {
        self.last_sig = Some(signature);
    }

    /// The signature of the tangent the solver's factor holds (None before the loop's
    /// first factorisation, unless resumed).
    pub fn factor_signature(&self) -> Option<&[(u8, u64)]> {
        self.last_sig.as_deref()
    }

    /// Newton iterations with the contact statuses and friction thresholds frozen, until
    /// the relative correction is below the tolerance (true) or `max_iter` (false).
    /// `predict`: the first iteration assumes every contact point sticks (return mapping).
    /// A loop longer than 3 iterations that reaches a third of its cap, or whose
    /// stick/slip statuses return to those of an earlier iteration other than the last one
    /// (a cycle: of period 2, or longer), freezes the stick/slip statuses for the rest of
    /// the loop (at a cycle, the points whose status changes within it sliding:
    /// [`Newton::cyclers`]); the caller checks them against the law
    /// ([`crate::contact::state::frozen_statuses_agree`]).
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        ctx: &StepContext<'_, '_>,
        columns: &ContactColumns,
        solver: &mut LinearSolver,
        values: &mut [f64],
        state: &mut [PointState],
        x: &mut [f64],
        u: &mut [f64],
        rep: &mut ContactReport,
        timings: &mut Timings,
        max_iter: usize,
        predict: bool,
    ) -> Result<bool, SolveError> {
        let (model, pts, layout) = (ctx.model, ctx.points, ctx.layout);
        let log = contact_log();
        let mut predicted = false;
        // The statuses of the last two iterations of this loop ([0]: the last).
        let mut history: [Vec<Status>; 2] = [Vec::new(), Vec::new()];
        // The slip set of the first friction pass, bisected ([`SlipBisection`]).
        let mut bisection: Option<SlipBisection> = None;
        let mut done = false;
        self.unconfirmed = false;
        self.ended_at_contact_change = false;
        // The stick/slip statuses were frozen (at a third of the cap, or at a cycle).
        let mut frozen = false;
        self.visited.clear();
        self.cyclers.clear();
        self.lin_prev = None;
        // The weight of the Λ rows where friction does not act, frozen for this loop.
        set_threshold_scales(pts, state);
        // The damped steps ([`Newton::damp`]): the step length and the correction before
        // the last one.
        let mut alpha = 1.0f64;
        let mut prev_corr = f64::INFINITY;
        for it in 1..=max_iter {
            rep.newton += 1;
            if let Some(b) = bisection.as_mut() {
                b.release(state);
            }
            if predict && self.has_friction && it == 1 && state.iter().any(|p| p.lam_bar != 0.0) {
                // Every point where friction acts: in contact, or carried by an asperity
                // layer (CrackLaw::friction_acts).
                for (p, cp) in state.iter_mut().zip(&pts.points) {
                    if pts.cracks[cp.crack].law.friction_acts(p.contact) {
                        p.lock = Some(true);
                    }
                }
                predicted = true;
            } else if it == 2 && predicted {
                if max_iter > 3 {
                    let vals = point_values(model, pts, ctx.pairing, state, u);
                    bisection = SlipBisection::new(pts, state, &vals);
                }
                for p in state.iter_mut() {
                    p.lock = None;
                }
            } else if let Some(b) = bisection.as_mut().filter(|b| !b.done) {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                let now = statuses(pts, state, &vals);
                if let Some(m) = b.step(state, &now, &history[0]) {
                    if log {
                        eprintln!(
                            "newton {it}: slip bisection: {m} of {} points sliding (bounds {}..{})",
                            b.order.len(),
                            b.lo,
                            b.hi
                        );
                    }
                }
            }
            if self.has_friction && max_iter > 3 && it == max_iter / 3 + 1 {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                freeze_statuses(pts, state, &vals);
                frozen = true;
                // The freeze keeps every status, the bisected ones too.
                bisection = None;
            }
            if self.watch_slips {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                // The guard is against a slip direction that flips while the statuses stay
                // the same. After the stick predictor, while the statuses still change, a
                // reversed g_τ is the predictor's overshoot being given back: the
                // directions are followed but no point is held (held, the 2D Hertz row's
                // points stayed stuck at |Λ| ≈ 35 for the rest of the first Newton loop,
                // and the law's check cost a second active-set iteration).
                let transient = predicted && history[0] != history[1];
                let locks: Vec<Option<bool>> =
                    if transient { state.iter().map(|p| p.lock).collect() } else { Vec::new() };
                hold_reversed_slips(pts, state, &vals, &mut self.slip_directions);
                for (p, l) in state.iter_mut().zip(locks) {
                    p.lock = l;
                }
            }
            // The thresholds that follow the iterate, at this iterate (the factor may have
            // fallen back to a symmetric one: then they stay frozen).
            let live = self.live && solver.is_condensed();
            if live {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                live_thresholds(pts, state, &vals);
            }
            // Stick/slip statuses back to those of an earlier iteration (and not those of the
            // last one): the loop cycles between status sets, each a new tangent, and would
            // until the freeze at a third of the cap. Freeze them now instead (the tangent of
            // this iteration is the same; the caller checks the law). The period is 2 where a
            // few points alternate (fretting reversals) and 4 on the 3D Hertz sphere row
            // (two groups of ~72 points at the edge of the contact zone alternating in turn:
            // stick 4 575, 4 504, 4 576, 4 503, 4 575, … until the freeze at iteration 11).
            if self.has_friction && it >= 4 && self.visited.len() >= 2 {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                let now = statuses(pts, state, &vals);
                let last = self.visited.len() - 1;
                if let Some(k) =
                    self.visited[..last].iter().rposition(|v| *v == now).filter(|_| now != self.visited[last])
                {
                    freeze_statuses(pts, state, &vals);
                    frozen = true;
                    bisection = None;
                    // The points whose status changes within the cycle (visited[k..] and
                    // now) are frozen sliding: each status violates the law at the other,
                    // and sliding keeps the tangential traction at the Coulomb bound
                    // (|t_τ| = μ|λ̄|, admissible) where sticking would hold one above it.
                    // The cycle's phase at this iteration, which depends on where the loop
                    // started, does not decide them.
                    self.cyclers = (0..now.len())
                        .map(|j| {
                            now[j] != Status::Open
                                && self.visited[k..].iter().any(|v| v[j] != now[j] && v[j] != Status::Open)
                        })
                        .collect();
                    for (p, _) in state.iter_mut().zip(&self.cyclers).filter(|(_, &c)| c) {
                        p.lock = Some(false);
                    }
                    if log {
                        eprintln!(
                            "newton {it}: stick/slip statuses cycle with period {}: frozen, its {} flipping points sliding",
                            self.visited.len() - k,
                            self.cyclers.iter().filter(|&&c| c).count()
                        );
                    }
                }
            }
            if log && self.has_friction && !history[0].is_empty() {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                log_flips(pts, state, &vals, &history[0]);
            }
            let state: &[PointState] = state;
            let clock = Instant::now();
            let iteration_clock = clock;
            let vals = point_values(model, pts, ctx.pairing, state, u);
            let st_now = statuses(pts, state, &vals);
            let sig: Vec<(u8, u64)> = st_now.iter().zip(state).map(|(s, p)| (*s as u8, p.lam_bar.to_bits())).collect();
            if log {
                let c = |x: Status| st_now.iter().filter(|s| **s == x).count();
                let lmax = vals.iter().map(|v| v.big_lambda[0].abs()).fold(0.0, f64::max);
                eprintln!(
                    "newton {it}: open {} stick {} slip {} max|Λ| {lmax:.3} corr {:.2e}",
                    c(Status::Open),
                    c(Status::Stick),
                    c(Status::Slip),
                    rep.residual
                );
            }
            let count = |x: Status| st_now.iter().filter(|s| **s == x).count();
            let mut event = NewtonIteration {
                step: ctx.step,
                friction: rep.friction.max(1),
                active_set: rep.active_set,
                newton: rep.newton,
                open: count(Status::Open),
                stick: count(Status::Stick),
                slip: count(Status::Slip),
                changed: if self.prev_status.len() == st_now.len() {
                    self.prev_status.iter().zip(&st_now).filter(|(a, b)| a != b).count()
                } else {
                    st_now.len()
                },
                correction: f64::NAN,
                factorised: false,
            };
            // A provisional end (the caller's intermediate friction pass): the statuses
            // settled, nothing locked, no slip bisection under way (one that has not
            // bisected yet is not, where the tangent is piecewise constant: the first
            // pass's slip statuses settled at once, and its confirming solve would only
            // find its step exact), the thresholds frozen;
            // in 2D without an asperity layer (a 3D pad pressed into a layer and slid,
            // `tests/contact_pad_3d.rs`, stopped its Newton loop with it: not studied), and in
            // 3D in a pass without friction thresholds (every λ̄ = 0: no slip direction in
            // the tangent, which is then that of the statuses, piecewise constant as in 2D:
            // the frictionless first pass of a step, whose active-set iterations each took a
            // solve and its confirming solve).
            let tangent_of_statuses = !self.three_d || state.iter().all(|p| p.lam_bar == 0.0);
            if self.provisional
                && tangent_of_statuses
                && pts.cracks.iter().all(|c| c.law.asperity.is_none())
                && it >= 2
                && event.changed == 0
                && bisection.as_ref().is_none_or(|b| b.done || (!b.bisected && !self.smooth_nonlinear))
                && !self.live
                && state.iter().all(|p| p.lock.is_none())
            {
                rep.newton -= 1;
                self.unconfirmed = true;
                if log {
                    eprintln!("newton {it}: statuses settled: provisional end of the pass");
                }
                done = true;
                break;
            }
            self.prev_status.clone_from(&st_now);
            history.swap(0, 1);
            history[0].clone_from(&st_now);
            if self.has_friction {
                self.visited.push(st_now.clone());
            }
            // The slip direction enters the 3D tangent only at a sliding point with a
            // friction bound μλ̄ ≠ 0 (`CrackLaw::friction_augmented`, the penalty's friction
            // likewise): a frictionless pass (every λ̄ = 0, every closed point `Slip`) has the
            // tangent of its statuses, and its confirming iteration reuses the factor.
            let slip3 = self.three_d
                && self.has_friction
                && st_now.iter().zip(state).zip(&pts.points).any(|((s, p), cp)| {
                    *s == Status::Slip && p.lam_bar != 0.0 && pts.cracks[cp.crack].law.friction > 0.0
                });
            // Same statuses and thresholds: reuse the factor (exact in 2D; in 3D with sliding
            // points the slip direction changes the tangent, and the stale factor makes a
            // modified Newton step, refreshed when it stops halving the correction).
            // The stale factor is used only once the corrections are small (the asymptotic
            // phase): far from the answer a modified-Newton step can diverge in 3D slip.
            let same_statuses = self.last_sig.as_ref() == Some(&sig);
            // The same stick/slip/open statuses, whatever the thresholds (these move every
            // iteration when they follow the iterate).
            let same_kinds = self
                .last_sig
                .as_ref()
                .is_some_and(|l| l.len() == sig.len() && l.iter().zip(&sig).all(|(a, b)| a.0 == b.0));
            // A plain factor is costly to refresh: with the statuses of its tangent and the
            // thresholds near its own (`STALE_THRESHOLDS_BELOW`), or in the asymptotic phase
            // of a tangent that moves with the iterate (asperity layer, implicit wear), it
            // makes modified Newton steps while they contract. (A condensed factor
            // refreshes only its dense crack block: it is refreshed, as the exact step
            // takes fewer iterations.)
            let plain = !solver.is_condensed();
            let near = plain && !same_statuses && self.thresholds_near(&sig);
            let stale_ok = !self.stale_slow;
            let refactor = if near {
                !stale_ok
            } else if self.smooth_nonlinear && plain && same_statuses {
                !stale_ok || self.last_corr > STALE_NONLINEAR_BELOW
            } else {
                !same_statuses
                    || self.smooth_nonlinear
                    || (slip3 && (self.stale_slow || self.last_corr > STALE_FACTOR_BELOW))
            };
            // An exact Newton step: fresh factor, or 2D where the tangent only depends on
            // the statuses (and thresholds).
            let exact_step = refactor || (same_statuses && !slip3 && !self.smooth_nonlinear);
            let kernel = ContactKernel { live_thresholds: live, ..ctx.kernel(state, u) };
            let mut kernels: Vec<&dyn Kernel> = ctx.fixed.to_vec();
            kernels.push(&kernel);
            self.rhs.copy_from_slice(ctx.rhs_f);
            let pattern = &layout.pattern;
            // K in the contact columns again (the previous iteration added its terms).
            columns.restore(&pattern.col_ptr, values);
            // Distributed assembly (PETSc): K lives in the backend's matrix, each rank's
            // residual is its rows' and elements' share, summed over the ranks before the
            // solve; the contact terms go into the matrix with the factorisation.
            let distributed = layout.is_distributed();
            let k_diag_max = *self.k_diag_max.get_or_insert_with(|| {
                if distributed {
                    solver.bulk_diagonal_max()
                } else {
                    max_primal_diagonal(layout, values)
                }
            });
            // The first iteration of a step resumed on the factor's own statuses (the
            // time-step driver, [`Newton::confirm_exact_steps`]): the step is linear, so it
            // solves for the unknowns themselves, A x₁ = f − R(u) + T u (the contact
            // kernel's residual and tangent at the start of the step, [`Linearised`]), the
            // same exact step as x₀ + A⁻¹ (f − K x₀ − R(u)) without the mat-vec K x₀.
            let direct = self.confirm_exact
                && !distributed
                && !self.solved_once
                && ctx.pairing.is_none()
                && !self.interior_solved
                && same_statuses
                && exact_step
                && !refactor
                && !live
                && !self.smooth_nonlinear;
            match self.varying.as_ref().filter(|_| self.interior_solved) {
                _ if direct => {}
                _ if distributed => {
                    solver.bulk_product(x, &mut self.kx).map_err(ctx.linear_error(""))?;
                    for (r, k) in self.rhs.iter_mut().zip(&self.kx) {
                        *r -= k;
                    }
                }
                // Deferred solves read the crack rows only.
                Some(rows) => {
                    for &i in rows {
                        let r = pattern.col_ptr[i]..pattern.col_ptr[i + 1];
                        let ki: f64 = values[r.clone()].iter().zip(&pattern.row_idx[r]).map(|(v, &k)| v * x[k]).sum();
                        self.rhs[i] -= ki;
                    }
                }
                None => {
                    pattern.mul_vec(values, x, &mut self.kx);
                    for (r, k) in self.rhs.iter_mut().zip(&self.kx) {
                        *r -= k;
                    }
                }
            }
            let matrix = if refactor { Some(&mut *values) } else { None };
            let linearised = Linearised { inner: &kernel, eq_of_dof: &layout.eq_of_dof, u };
            if direct {
                *kernels.last_mut().expect("the contact kernel") = &linearised;
            }
            if !(distributed && refactor) {
                let matrix = matrix.filter(|_| !distributed);
                layout.assemble_kernels(&kernels, &self.include, &self.zeros, matrix, Some(&mut self.rhs), true);
            }
            timings.assembly += clock.elapsed().as_secs_f64();
            if log {
                eprintln!("  assembly: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
            }
            event.factorised = refactor;
            if refactor {
                ctx.observer.phase(Phase::Factorisation { step: ctx.step, nnz_factor: solver.stats().nnz_factor });
                let clock = Instant::now();
                let singular = "; the contact system is singular: check that every part of the body is held (contact alone does not hold a part without friction)";
                if distributed {
                    // This rank's contact elements into the matrix, their vector on the way.
                    let (include, zeros, buf) = (&self.include, &self.zeros, &mut self.kx);
                    solver
                        .refill_contact(&mut |sink| {
                            layout.assemble_elements(&kernels, include, zeros, Some(&mut *buf), sink)
                        })
                        .map_err(ctx.linear_error(singular))?;
                    for (r, f) in self.rhs.iter_mut().zip(&self.kx) {
                        *r += f;
                    }
                } else {
                    solver.factorize(values).map_err(ctx.linear_error(singular))?;
                }
                timings.numeric += clock.elapsed().as_secs_f64();
                if log {
                    eprintln!("  factorize: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
                }
                rep.factorizations += 1;
                self.last_sig = Some(sig);
            }
            let clock = Instant::now();
            let deferred_solve = self.interior_solved;
            // The confirming iteration of an exact full step, on the same statuses
            // ([`Newton::confirm_exact_steps`]).
            let confirming = self.confirm_exact
                && deferred_solve
                && self.full_exact_last
                && same_statuses
                && exact_step
                && !refactor
                && !live;
            self.full_exact_last = !deferred_solve && exact_step && !live;
            let rows = self.varying.as_ref().filter(|_| confirming);
            if let Some(rows) = rows {
                self.saved_rows.clear();
                self.saved_rows.extend(rows.iter().map(|&i| x[i]));
            }
            if distributed {
                solver.sum_over_ranks(&mut self.rhs).map_err(ctx.linear_error(""))?;
            }
            // After the first solve only the crack rows change: the interior correction is
            // deferred to the end of the step (condensed factor; a plain solve otherwise).
            // A damped step ([`Newton::damp`]): an iteration whose statuses changed after a
            // correction that did not halve the one before halves the step (down to
            // [`MIN_STEP`]); one on unchanged statuses doubles it back (up to a full step).
            if self.damped && it >= 3 && self.has_friction {
                if event.changed > 0 && rep.residual > 0.5 * prev_corr {
                    alpha = (alpha * 0.5).max(MIN_STEP);
                } else if event.changed == 0 {
                    alpha = (alpha * 2.0).min(1.0);
                }
            }
            prev_corr = rep.residual;
            let alpha_it = if direct { 1.0 } else { alpha };
            if self.interior_solved {
                solver.solve_in_place_deferred(&mut self.rhs)
            } else {
                solver.solve_in_place(&mut self.rhs)
            }
            .map_err(ctx.linear_error(if self.has_friction {
                "; with contact: a part held only through its contact faces is free where its lips open (a part pulled off), and slides when the tangential load exceeds μ times the normal load: it cannot be held then"
            } else {
                "; with frictionless contact: a part held only through its contact faces is free to slide along them (give the contact a friction coefficient or the part a support) and free where its lips open (a part pulled off)"
            }))?;
            timings.solve += clock.elapsed().as_secs_f64();
            if log {
                let (res, refine) = solver.last_residual();
                eprintln!(
                    "  solve: {:.1} ms, residual {res:.1e}, {refine} refinements",
                    clock.elapsed().as_secs_f64() * 1e3
                );
            }
            if alpha_it < 1.0 {
                if self.interior_solved {
                    solver.scale_last_deferred(alpha_it, &self.rhs);
                }
                for r in self.rhs.iter_mut() {
                    *r *= alpha_it;
                }
                if log {
                    eprintln!("  damped step {alpha_it}");
                }
            }
            rep.linear_solves += 1;
            self.solved_once = true;
            self.interior_solved = self.defer;
            // Per block of unknowns (see `block_of_eq`): max |correction| and max |value|.
            let (mut dn, mut xn) = ([0.0f64; N_BLOCKS], [0.0f64; N_BLOCKS]);
            if direct {
                // The solve gave the unknowns: their correction, as the other iterations'.
                for (xi, r) in x.iter_mut().zip(self.rhs.iter_mut()) {
                    let x1 = *r;
                    *r = x1 - *xi;
                    *xi = x1;
                }
            }
            for ((xi, d), &b) in x.iter_mut().zip(&self.rhs).zip(&self.block_of_eq) {
                if !direct {
                    *xi += d;
                }
                dn[b as usize] = dn[b as usize].max(d.abs());
                xn[b as usize] = xn[b as usize].max(xi.abs());
            }
            copy_to_dofs(layout, x, u);
            // Floors of the λ, Λ and reaction scales (each in its own units): a crack with no
            // shear has Λ of round-off size (|Λ| ≤ 1 is its natural scale), an open one λ of
            // round-off size (ρ_n times the largest displacement is a traction of the model),
            // an unloaded support reactions of round-off size (`reaction_floor`).
            // λ carries the contact force only where it is above its floor (a penalty law or
            // an asperity layer leave it at round-off): only then is its round-off a floor of
            // the corrections (`lambda_roundoff`).
            let lambda_genuine = xn[1] > 1e-12 * self.rho_n_max * xn[0];
            xn[1] = xn[1].max(1e-12 * self.rho_n_max * xn[0]);
            xn[2] = xn[2].max(1.0);
            xn[3] = xn[3].max(reaction_floor(k_diag_max, xn[0]));
            rep.residual = relative_correction(&dn, &xn) / alpha_it;
            event.correction = rep.residual;
            ctx.observer.newton(&event);
            // The first step of a loop follows a change of the thresholds or statuses: its
            // correction is not compared with the previous loop's last one.
            self.stale_slow = !refactor && it > 1 && rep.residual > 0.5 * self.last_corr;
            // Round-off floor: with unchanged statuses an exact Newton step on this piecewise
            // linear problem lands on the solution, so a correction that no longer shrinks and
            // is already below ROUNDOFF_FLOOR is the linear solver's accuracy, not a missing
            // iteration (large models with blending tip functions stall at ~1e-7).
            // The floor is the larger of ROUNDOFF_FLOOR and the round-off of the λ block in
            // the model's own scales (`lambda_roundoff`).
            self.lambda_roundoff = if lambda_genuine {
                lambda_roundoff(k_diag_max, xn[0], self.h_min, ctx.points.dim) / xn[1]
            } else {
                0.0
            };
            let floor = ROUNDOFF_FLOOR.max(self.lambda_roundoff);
            let at_floor = (same_statuses || (live && same_kinds))
                && exact_step
                && it > 2
                && rep.residual <= floor
                && rep.residual > 0.5 * self.last_corr;
            // A correction within λ's own round-off, after a solve on these statuses, is as
            // converged as the model's scales allow (the semi-smooth loop's two-iteration
            // Newton passes never reach the floor's third iteration).
            // Per block: λ's correction within its round-off, every other block's within the
            // Newton tolerance (the round-off of λ must not loosen the displacements').
            let others = {
                let mut d = dn;
                d[1] = 0.0;
                relative_correction(&d, &xn)
            };
            let within_roundoff = (same_statuses || (live && same_kinds))
                && exact_step
                && it > 1
                && self.lambda_roundoff > 0.0
                && dn[1] <= self.lambda_roundoff * xn[1]
                && others <= ctx.loops.tol_newton;
            // An iterative backend's floor: after an exact step on these statuses solved to a
            // linear residual r, the Newton residual b at the new iterate is r plus what
            // evaluating f − K x − c(x) adds in floating point. Once b no longer shrinks
            // (b > b_prev / 2) though the last solve left r well below it (r ≤ b / 10), b is
            // that round-off and every later correction is the solve's response to it:
            // no iteration makes the answer more accurate. Measured on the penny with
            // contact (GMRES + field split, 2 ranks): b stalls at 8.6e-14 of the load while
            // each solve leaves 7e-18; the corrections, A⁻¹ applied to that round-off, wander
            // at 1e-10 on 216 k unknowns and at 1e-6–9e-6 on 1.07 M, above ROUNDOFF_FLOOR,
            // where the loop ran to its cap (docs/reliability.md). faer's direct solves
            // report nothing here: their loops keep the floors above.
            let lin = solver.iterative_residuals();
            let at_solver_floor = match (lin, self.lin_prev) {
                (Some((b, _)), Some((b_prev, r_prev))) => {
                    same_statuses && !live && rep.residual <= ASYMPTOTIC_BELOW && b > 0.5 * b_prev && r_prev <= 0.1 * b
                }
                _ => false,
            };
            if log {
                let rel = |k: usize| if xn[k] > 0.0 { dn[k] / xn[k] } else { 0.0 };
                // The linear residuals only where the backend reports them (iterative ones).
                let linear = lin.map_or(String::new(), |(b, r)| format!("; rhs {b:.2e}, left {r:.2e}"));
                eprintln!(
                    "  corrections: u {:.2e} λ {:.2e} Λ {:.2e} reactions {:.2e}{linear}{}",
                    rel(0),
                    rel(1),
                    rel(2),
                    rel(3),
                    if at_solver_floor { " (solver floor)" } else { "" }
                );
            }
            self.lin_prev = lin.filter(|_| exact_step && !live);
            self.last_corr = rep.residual;
            let converged = rep.residual <= ctx.loops.tol_newton || at_floor || within_roundoff || at_solver_floor;
            if let (true, Some(rows)) = (converged, rows) {
                // Keep the exact step: its correction back, its interior response dropped.
                for (&i, &v) in rows.iter().zip(&self.saved_rows) {
                    x[i] = v;
                }
                solver.discard_deferred();
                copy_to_dofs(layout, x, u);
            }
            if deferred_solve {
                timings.step_phases.confirm += iteration_clock.elapsed().as_secs_f64();
            }
            if converged {
                done = true;
                break;
            }
            // Frozen statuses, displacements and λ converged, and the caller's contact update
            // would change a status at this iterate: the caller will not accept it
            // ([`Newton::allow_contact_change_end`]).
            // (Measured undamped, as the convergence test: a damped step's correction is
            // the solve's scaled by `alpha_it`.)
            let settled = |k: usize| dn[k] <= CONTACT_CHANGE_END_BELOW * alpha_it * xn[k];
            if let Some(sticky) = self.contact_change_end.as_ref().filter(|_| frozen && settled(0) && settled(1)) {
                let vals = point_values(model, pts, ctx.pairing, state, u);
                let mut trial = state.to_vec();
                update_contact_status(pts, &mut trial, &vals);
                let changed = trial.iter().zip(state).zip(sticky).any(|((t, s), &k)| (t.contact || k) != s.contact);
                if changed {
                    if log {
                        eprintln!(
                            "newton {it}: frozen statuses, u and λ within {CONTACT_CHANGE_END_BELOW:.0e}: the contact statuses change here, the loop ends"
                        );
                    }
                    self.ended_at_contact_change = true;
                    done = true;
                    break;
                }
            }
        }
        // A converged loop keeps the statuses it was solved with (bisected ones too): the
        // caller checks them against the law ([`crate::contact::state::frozen_disagreements`]).
        Ok(done)
    }
}

/// A faster first friction pass: the slip set of the stick predictor's statuses bisected by
/// the predictor's |g_τ|. The predictor solves with every contact point stuck; the next
/// iteration lets slide every point where that stuck solution exceeds the Coulomb bound
/// (|g_τ| > 1), too many where the bound is small (at the edge of a Hertz contact the
/// stuck Λ reached 4.6 μλ̄ on the coarse sphere), and the following iterations give the
/// excess back a fraction at a time, each a factorisation (the coarse sphere's slip set
/// went 255 → 182 → 146 → 130 → 124, every update slip → stick only). As
/// [`super::contact_loops`]' gap bisection of the first active set: the points are ordered
/// by the predictor's |g_τ|, largest first; an update that only sticks points bounds the
/// slip set from above by the size it had, one that only lets points slide bounds it from
/// below; after a shrinking update that gives back at least a quarter of the bracket, the
/// slip set becomes the largest-|g_τ| prefix of the midpoint between the bounds, when that
/// sticks more than the update would. The bisected statuses are held for one iteration
/// ([`PointState::lock`]) and the law decides the next; the first growth after a bisection
/// or an update that both sticks and lets slide ends it, and the loop converges only on
/// statuses that agree with the law (the caller's check), so the answer is the same.
struct SlipBisection {
    /// The points stuck by the predictor, largest |g_τ| of the stuck solution first.
    order: Vec<usize>,
    /// Slip-set sizes known too small (a growth followed) and too large (a shrink).
    lo: usize,
    hi: usize,
    bisected: bool,
    done: bool,
    /// The points whose bisected status is held for the current iteration.
    locked: Vec<usize>,
}

impl SlipBisection {
    /// At the stick predictor's solution (`state` with the predictor's locks, `vals`):
    /// None when no point was stuck.
    fn new(pts: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Option<SlipBisection> {
        let mut g: Vec<(usize, f64)> = state
            .iter()
            .zip(vals)
            .zip(&pts.points)
            .enumerate()
            .filter(|(_, ((st, v), _))| st.lock == Some(true) && v.paired && st.lam_bar != 0.0)
            .map(|(k, ((st, v), p))| {
                let law = &pts.cracks[p.crack].law;
                let vt = crate::contact::law::slip_increment(pts.dim - 1, &p.tangents, v.jump, st.prev_jump);
                let g = law.friction_indicator(law.friction_base(v.big_lambda, st.big_lambda_start), vt, st.lam_bar).1;
                (k, g[0].hypot(g[1]))
            })
            .collect();
        g.sort_by(|a, b| b.1.total_cmp(&a.1));
        let order: Vec<usize> = g.into_iter().map(|(k, _)| k).collect();
        let hi = order.len();
        (hi > 0).then_some(SlipBisection { order, lo: 0, hi, bisected: false, done: false, locked: Vec::new() })
    }

    /// Releases the statuses held by the last bisection.
    fn release(&mut self, state: &mut [PointState]) {
        for k in self.locked.drain(..) {
            state[k].lock = None;
        }
    }

    /// After the update from `prev` to `now` (the law's statuses at the iterate): holds the
    /// bisected slip set in `state` and returns its size, or None (the update's statuses).
    fn step(&mut self, state: &mut [PointState], now: &[Status], prev: &[Status]) -> Option<usize> {
        if prev.len() != now.len() {
            self.done = true;
            return None;
        }
        let n_prev = self.order.iter().filter(|&&k| prev[k] == Status::Slip).count();
        let stuck = self.order.iter().filter(|&&k| prev[k] == Status::Slip && now[k] == Status::Stick).count();
        let slid = self.order.iter().filter(|&&k| prev[k] == Status::Stick && now[k] == Status::Slip).count();
        let other = self.order.iter().filter(|&&k| (prev[k] == Status::Open) != (now[k] == Status::Open)).count();
        match (stuck > 0, slid > 0) {
            (true, false) if other == 0 => {
                self.hi = self.hi.min(n_prev);
                let m = (self.lo + self.hi) / 2;
                if m > self.lo && m < n_prev - stuck && 4 * stuck >= self.hi - self.lo {
                    for (i, &k) in self.order.iter().enumerate() {
                        if state[k].lock.is_none() && now[k] != Status::Open {
                            state[k].lock = Some(i >= m);
                            self.locked.push(k);
                        }
                    }
                    self.bisected = true;
                    return Some(m);
                }
            }
            (false, true) if other == 0 => {
                self.lo = self.lo.max(n_prev);
                self.done = self.bisected;
            }
            (false, false) => {}
            _ => self.done = true,
        }
        None
    }
}

/// Log: the stick/slip flips since `prev` and their margins ||g_τ| − 1|.
fn log_flips(pts: &ContactPoints, state: &[PointState], vals: &[PointValues], prev: &[Status]) {
    let now = statuses(pts, state, vals);
    let (mut to_slip, mut to_stick) = (0, 0);
    let mut margins = Vec::new();
    for (k, (a, b)) in prev.iter().zip(&now).enumerate() {
        if a == b || *a == Status::Open || *b == Status::Open {
            continue;
        }
        if *b == Status::Slip {
            to_slip += 1;
        } else {
            to_stick += 1;
        }
        let (p, st, v) = (&pts.points[k], &state[k], &vals[k]);
        let law = &pts.cracks[p.crack].law;
        let vt = crate::contact::law::slip_increment(pts.dim - 1, &p.tangents, v.jump, st.prev_jump);
        let g = law.friction_indicator(law.friction_base(v.big_lambda, st.big_lambda_start), vt, st.lam_bar).1;
        margins.push((g[0].hypot(g[1]) - 1.0).abs());
    }
    if margins.is_empty() {
        return;
    }
    margins.sort_by(f64::total_cmp);
    let within = margins.iter().filter(|&&m| m <= COULOMB_TIE).count();
    eprintln!(
        "  flips: stick→slip {to_slip}, slip→stick {to_stick}; ||g|−1| min {:.1e} median {:.1e} max {:.1e}; {within} within the Coulomb tie",
        margins[0],
        margins[margins.len() / 2],
        margins[margins.len() - 1]
    );
}

/// The contact kernel linearised at `u` and evaluated at zero on the equations: its
/// vector is −R(u) + T(u) u_f, with T its tangent and u_f the values of `u` on the dofs
/// that have an equation (the prescribed ones keep their values in R and are not lifted).
/// With the statuses frozen the contact terms are affine in the unknowns, so the system
/// (K + T) x = f − R(u) + T u_f has the Newton step's answer as its solution, without the
/// product K x of the iterate ([`Newton::run`]'s first iteration of a resumed time step).
struct Linearised<'k> {
    inner: &'k dyn Kernel,
    eq_of_dof: &'k [u32],
    u: &'k [f64],
}

impl Kernel for Linearised<'_> {
    fn n_elements(&self) -> usize {
        self.inner.n_elements()
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        self.inner.dofs(e, out)
    }

    fn has_matrix(&self) -> bool {
        self.inner.has_matrix()
    }

    fn is_linear(&self) -> bool {
        self.inner.is_linear()
    }

    fn compute(&self, e: usize, dofs: &[u32], out: crate::assembly::LocalOut<'_>) {
        let m = dofs.len();
        let mut own = Vec::new();
        let ke: &mut [f64] = match out.matrix {
            Some(k) => k,
            None => {
                own.resize(m * m, 0.0);
                &mut own
            }
        };
        let Some(fe) = out.vector else {
            return self.inner.compute(e, dofs, crate::assembly::LocalOut { matrix: Some(ke), vector: None });
        };
        self.inner.compute(e, dofs, crate::assembly::LocalOut { matrix: Some(&mut *ke), vector: Some(&mut *fe) });
        for (a, f) in fe.iter_mut().enumerate() {
            let mut t = 0.0;
            for (b, &d) in dofs.iter().enumerate() {
                if self.eq_of_dof[d as usize] != NO_EQ {
                    t += ke[a * m + b] * self.u[d as usize];
                }
            }
            *f += t;
        }
    }
}

/// Copies the equations' values `x` into the dof vector `u` (prescribed dofs untouched).
pub fn copy_to_dofs(layout: &SystemLayout, x: &[f64], u: &mut [f64]) {
    for (dof, val) in u.iter_mut().enumerate() {
        let q = layout.eq_of_dof[dof];
        if q != NO_EQ {
            *val = x[q as usize];
        }
    }
}

/// A step without contact: one linear solve (K is assembled and factorised on the first
/// step only; later steps assemble the load vector). Returns the relative residual and
/// the factorisations made.
#[allow(clippy::too_many_arguments)] // the step's state, as the driver holds it
pub fn linear_step(
    sys: &mut System,
    fixed: &FixedKernels<'_>,
    prescribed: &[f64],
    step: usize,
    options: &SolveOptions,
    u: &mut [f64],
    timings: &mut Timings,
    observer: &dyn SolveObserver,
) -> Result<(f64, usize), SolveError> {
    let kernels = fixed.list();
    let mut factorizations = 0;
    let clock = Instant::now();
    let advice = "; check that the Dirichlet conditions hold every part of the body and that the materials are valid";
    if !sys.k_assembled && sys.layout.is_distributed() {
        // Each element matrix straight into the backend's distributed matrix (no value
        // array here), the load vector of the same elements on the way.
        observer.phase(Phase::Factorisation { step, nnz_factor: None });
        let all = [true; 4];
        let (layout, rhs) = (&sys.layout, &mut sys.rhs);
        sys.solver
            .factorize_elements(&mut |sink| layout.assemble_elements(&kernels, &all, prescribed, Some(&mut *rhs), sink))
            .map_err(|error| SolveError::Linear { step, error, advice })?;
        fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
        // The backend's numeric time is its preconditioner's set-up; the rest assembly.
        let set_up = sys.solver.stats().numeric_s;
        timings.assembly += (clock.elapsed().as_secs_f64() - set_up).max(0.0);
        timings.numeric += set_up;
        sys.k_assembled = true;
        sys.values_generation += 1;
        factorizations = 1;
    } else if !sys.k_assembled {
        // K and f of the first step may be in place already (`System::prefilled`).
        if !std::mem::take(&mut sys.prefilled) {
            sys.layout.assemble(&kernels, prescribed, Some(&mut sys.values), Some(&mut sys.rhs));
            fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
        }
        timings.assembly += clock.elapsed().as_secs_f64();
        observer.phase(Phase::Factorisation { step, nnz_factor: sys.solver.stats().nnz_factor });
        let clock = Instant::now();
        sys.solver.factorize(&sys.values).map_err(|error| SolveError::Linear { step, error, advice })?;
        timings.numeric += clock.elapsed().as_secs_f64();
        sys.k_assembled = true;
        sys.values_generation += 1;
        factorizations = 1;
    } else {
        let include = [!fixed.bulk_rhs_zero, true, true, true];
        sys.layout.assemble_kernels(&kernels, &include, prescribed, None, Some(&mut sys.rhs), false);
        fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
        timings.assembly += clock.elapsed().as_secs_f64();
    }
    if sys.layout.is_distributed() {
        // Each rank assembled its own elements: the load vector is the sum over the ranks.
        sys.solver.sum_over_ranks(&mut sys.rhs).map_err(|error| SolveError::Linear { step, error, advice: "" })?;
    }
    sys.check_rhs(step)?;
    let clock = Instant::now();
    sys.x.copy_from_slice(&sys.rhs);
    sys.solver.solve_in_place(&mut sys.x).map_err(|error| SolveError::Linear { step, error, advice: "" })?;
    timings.solve += clock.elapsed().as_secs_f64();
    let residual = sys.solver.last_residual().0;
    if !(residual <= options.residual_tolerance) {
        // Displacements below the smallest normal double (σ/E ≈ 1e-331 in the adversarial
        // generator's random values) cannot be solved for in these units: say so.
        let largest = sys.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if largest < f64::MIN_POSITIVE {
            return Err(SolveError::Underflow { step, largest, residual });
        }
        return Err(SolveError::Residual { step, residual, tolerance: options.residual_tolerance });
    }
    for (d, ud) in u.iter_mut().enumerate() {
        let q = sys.layout.eq_of_dof[d];
        *ud = if q == NO_EQ { prescribed[d] } else { sys.x[q as usize] };
    }
    Ok((residual, factorizations))
}
