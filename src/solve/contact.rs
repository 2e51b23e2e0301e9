//! The nested contact loops of one load step (formulation §6): friction-threshold fixed
//! point ⊃ active set on the contact status ⊃ generalized Newton with the stick/slip status
//! and slip direction updated every iteration; or, as an option, a fully semi-smooth Newton
//! that updates every status and the threshold in each iteration.
//!
//! Entry point: [`contact_step`].
//!
//! Every Newton iteration is reported to the step's [`SolveObserver`] (status counts,
//! statuses changed, correction: `fissure run --verbose`). The environment variable
//! `FISSURE_CONTACT_LOG` (a developer's switch) prints the linear algebra of each iteration
//! on stderr: max |Λ|, the times of the assembly, factorisation and solve, and the sizes
//! and phase times of the condensed factor.
//!
//! The bulk matrix K does not change (linear elasticity, small sliding): it is assembled
//! once, every iteration adds the contact terms to it in place (and restores it), and the
//! linear solver factorises it once and condenses each iteration onto the crack unknowns
//! (`LinearSolver::analyse_condensed`; after the first solve of a step the Newton
//! corrections defer the interior). The numeric
//! factorisation is redone only when a status or a threshold changed; otherwise the previous
//! factor solves the next correction (exact in 2D; in 3D the slip direction also enters the
//! tangent, so those steps are modified-Newton steps, and a step that does not halve the
//! correction triggers a refactorisation).

use crate::assembly::{Kernel, SystemLayout, NO_EQ};
use crate::contact::kernel::{basis_jumps, paired_jumps, point_jump, ContactKernel};
use crate::contact::law::{contact_indicator, friction_indicator, PointState, Status};
use crate::contact::pairing::ElementBasis;
use crate::contact::pairing::Pairing;
use crate::contact::points::ContactPoints;
use crate::contact::{ContactAlgorithm, ContactLoops};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::physics::model::Model;
use crate::solve::linear::LinearSolver;
use crate::solve::observe::{NewtonIteration, Phase, SolveObserver};
use crate::solve::statics::{SolveError, Timings};
use rayon::prelude::*;
use std::time::Instant;

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
    /// Pairing outcomes of the last pairing of the step (large sliding).
    pub pairing: Option<crate::contact::pairing::PairingCounts>,
}

/// Kinematics and multipliers at one contact point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointValues {
    pub jump: [f64; 3],
    /// Penetration d_n = −⟦u⟧·n (positive: overlap).
    pub d_n: f64,
    pub lambda: f64,
    pub big_lambda: [f64; 2],
    /// Whether the point has a master point (always, in small sliding). Unpaired points
    /// are out of contact.
    pub paired: bool,
}

/// λ, Λ, ⟦u⟧ and d_n at every contact point for the dof vector `u` (with the pairing of
/// the large-sliding cracks, if any).
pub fn point_values(
    model: &Model<'_>,
    points: &ContactPoints,
    pairing: Option<&Pairing>,
    u: &[f64],
) -> Vec<PointValues> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let ev = Evaluator { mesh, enr: &model.enrichment, cracks: &model.cracks };
    points
        .points
        .par_iter()
        .enumerate()
        .map_init(
            || (CellBasis::default(), Vec::new(), ElementBasis::default()),
            |(basis, jump, eb), (pi, p)| {
                let large = points.cracks[p.crack].large_sliding;
                let (j, paired) = match (large, pairing) {
                    (true, Some(pr)) => match pr.master(pi) {
                        Some(m) => {
                            eb.build(mesh, &model.enrichment, p.cell, std::slice::from_ref(&m.cell));
                            let ok = paired_jumps(&ev, eb, p, m, jump);
                            let mut j = point_jump(dim, &eb.dofs, jump, u);
                            for i in 0..3 {
                                j[i] += m.x[i] - p.x[i];
                            }
                            (j, ok)
                        }
                        None => ([0.0; 3], false),
                    },
                    _ => {
                        basis.build(mesh, &model.enrichment, p.cell);
                        basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                        (point_jump(dim, &basis.dofs, jump, u), true)
                    }
                };
                let d_n = -(j[0] * p.normal[0] + j[1] * p.normal[1] + j[2] * p.normal[2]);
                let mut lam = 0.0;
                let mut tl = [0.0; 2];
                for &(k, c) in &p.terms {
                    lam += c * u[points.lambda_dof(p.crack, k)];
                    for a in 0..dim - 1 {
                        tl[a] += c * u[points.tangent_dof(p.crack, k, a)];
                    }
                }
                PointValues { jump: j, d_n, lambda: lam, big_lambda: tl, paired }
            },
        )
        .collect()
}

/// Status of each point (open / stick / slip) for the current values and state.
pub fn statuses(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<Status> {
    points
        .points
        .iter()
        .zip(state)
        .zip(vals)
        .map(|((p, st), v)| {
            if !st.contact || !v.paired {
                return Status::Open;
            }
            let cc = &points.cracks[p.crack];
            if cc.friction == 0.0 || st.lam_bar == 0.0 {
                return Status::Slip;
            }
            let mut vt = [0.0; 2];
            for a in 0..points.dim - 1 {
                vt[a] = (0..3).map(|i| p.tangents[a][i] * (v.jump[i] - st.prev_jump[i])).sum();
            }
            let (free, g) = friction_indicator(v.big_lambda, vt, cc.rho_t);
            if st.lock.unwrap_or(free) || g[0].hypot(g[1]) < 1e-14 {
                Status::Stick
            } else {
                Status::Slip
            }
        })
        .collect()
}

/// Whether the friction statuses disagreed with the law, given whether anything changed and
/// whether the contact statuses changed.
fn has_friction_disagreement(changed: bool, status_changed: bool) -> bool {
    changed && !status_changed
}

/// Recomputes the contact status χ_c of every point; returns whether any changed.
fn update_contact_status(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> bool {
    let mut changed = false;
    for ((st, v), p) in state.iter_mut().zip(vals).zip(&points.points) {
        let c = v.paired && contact_indicator(v.lambda, v.d_n, points.cracks[p.crack].rho_n);
        changed |= c != st.contact;
        st.contact = c;
    }
    changed
}

/// The normal traction that sets a point's friction threshold: λ, or under large sliding
/// the traction the point actually transmits, g_n = λ − ρ_n d_n (Alart–Curnier's augmented
/// pressure). Once the lips have slid, the master nodes no longer face the slave ones and
/// d_n is zero only in the weak (per packet) sense, so λ and g_n differ between the
/// multiplier nodes; with g_n the tangential force is μ times the normal force point by
/// point. Unpaired points carry none.
fn threshold_traction(points: &ContactPoints, p: usize, v: &PointValues) -> f64 {
    let cc = &points.cracks[points.points[p].crack];
    match (cc.large_sliding, v.paired) {
        (false, _) => v.lambda,
        (true, true) => v.lambda - cc.rho_n * v.d_n,
        (true, false) => 0.0,
    }
}

/// Sets the friction thresholds λ̄ ← min(λ, 0) (see [`threshold_traction`]); returns
/// ‖min(λ, 0) − λ̄_old‖ / ‖λ‖.
fn update_thresholds(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> f64 {
    let norm = vals.iter().map(|v| v.lambda * v.lambda).sum::<f64>().sqrt();
    // A point in tension (possible where the weak contact law leaves a small positive λ)
    // has λ̄ = 0 at the fixed point, so compare with min(λ, 0).
    let mut diff = 0.0;
    for (p, (st, v)) in state.iter_mut().zip(vals).enumerate() {
        let new = threshold_traction(points, p, v).min(0.0);
        diff += (new - st.lam_bar).powi(2);
        st.lam_bar = new;
    }
    diff.sqrt() / norm.max(f64::MIN_POSITIVE)
}

/// Relative Newton correction below which a correction that stopped shrinking (with the
/// statuses unchanged and an exact tangent) is taken as the linear solver's round-off.
const ROUNDOFF_FLOOR: f64 = 1e-6;

/// Relative Newton correction below which a 3D sliding step may reuse the previous factor.
const STALE_FACTOR_BELOW: f64 = 1e-3;

/// Relative tolerance of the Coulomb tie: Λ = e is enforced weakly (per multiplier packet),
/// so at sliding points |Λ| is 1 only to about 1e-3.
pub const COULOMB_TIE: f64 = 1e-2;

/// Points in contact whose |g_τ| is 1 within [`COULOMB_TIE`] (stick and slip are both
/// consistent with the law there).
pub fn at_coulomb_limit(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<bool> {
    points
        .points
        .iter()
        .zip(state)
        .zip(vals)
        .map(|((p, st), v)| {
            let cc = &points.cracks[p.crack];
            if !st.contact || cc.friction == 0.0 {
                return false;
            }
            let mut vt = [0.0; 2];
            for a in 0..points.dim - 1 {
                vt[a] = (0..3).map(|i| p.tangents[a][i] * (v.jump[i] - st.prev_jump[i])).sum();
            }
            let g = friction_indicator(v.big_lambda, vt, cc.rho_t).1;
            (g[0].hypot(g[1]) - 1.0).abs() <= COULOMB_TIE
        })
        .collect()
}

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
    /// Every dof at the start of the step (for the slip increment v_τ).
    pub u_start: &'a [f64],
    /// A later pass of the geometry loop: the statuses, thresholds and dofs are those of
    /// the previous pass, already close; no stick predictor.
    pub warm: bool,
    /// Told the factorisations and every Newton iteration.
    pub observer: &'a dyn SolveObserver,
}

/// The values of K in the columns the contact kernel writes to (the equations of the dofs
/// of the contact elements), to restore K after adding contact terms in place.
struct ContactColumns {
    cols: Vec<usize>,
    saved: Vec<f64>,
}

impl ContactColumns {
    fn save(ctx: &StepContext<'_, '_>, contact: &dyn Kernel, values: &[f64]) -> ContactColumns {
        let layout = ctx.layout;
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

    /// Puts K back in the contact columns.
    fn restore(&self, cp: &[usize], values: &mut [f64]) {
        let mut k = 0;
        for &j in &self.cols {
            let len = cp[j + 1] - cp[j];
            values[cp[j]..cp[j + 1]].copy_from_slice(&self.saved[k..k + len]);
            k += len;
        }
    }
}

/// Runs the contact loops of one step from the current `x` (equations), `u` (every dof)
/// and `state` (per point), and leaves the converged solution in them. `k_values` holds K
/// (the fixed kernels) on the layout's pattern: the contact terms are added to it in place
/// (no second matrix-sized array) and K is restored before returning.
#[allow(clippy::too_many_arguments)]
pub fn contact_step(
    ctx: &StepContext<'_, '_>,
    solver: &mut LinearSolver,
    x: &mut [f64],
    u: &mut [f64],
    state: &mut [PointState],
    timings: &mut Timings,
    k_values: &mut [f64],
) -> Result<ContactReport, SolveError> {
    let kernel = ContactKernel {
        mesh: ctx.model.mesh,
        enrichment: &ctx.model.enrichment,
        cracks: &ctx.model.cracks,
        points: ctx.points,
        state,
        u,
        pairing: ctx.pairing,
    };
    let columns = ContactColumns::save(ctx, &kernel, k_values);
    let result = contact_loops(ctx, solver, x, u, state, timings, k_values, &columns);
    columns.restore(&ctx.layout.pattern.col_ptr, k_values);
    result
}

#[allow(clippy::too_many_arguments)]
fn contact_loops(
    ctx: &StepContext<'_, '_>,
    solver: &mut LinearSolver,
    x: &mut [f64],
    u: &mut [f64],
    state: &mut [PointState],
    timings: &mut Timings,
    values: &mut [f64],
    columns: &ContactColumns,
) -> Result<ContactReport, SolveError> {
    let model = ctx.model;
    let pts = ctx.points;
    let layout = ctx.layout;
    let loops = ctx.loops;
    let n_eq = layout.n_eq;
    let mut rhs = vec![0.0; n_eq];
    let mut kx = vec![0.0; n_eq];
    let zeros = vec![0.0; u.len()];
    let mut include = vec![false; ctx.fixed.len() + 1];
    *include.last_mut().expect("the contact kernel") = true;
    let mut rep = ContactReport::default();
    let has_friction = pts.cracks.iter().any(|c| c.friction > 0.0);
    let three_d = pts.dim == 3;
    // The signature of the tangent: statuses and thresholds. Same signature, same matrix
    // (2D, or 3D without slip).
    let mut last_sig: Option<Vec<(u8, u64)>> = None;

    // Start of the step: the jump at the start (for v_τ), with the current pairing.
    let pairing = ctx.pairing;
    // The bulk of a condensed factor: K (factorised once, unless it changed).
    let linear_error = |advice: &'static str| move |error| SolveError::Linear { step: ctx.step, error, advice };
    ctx.observer.phase(Phase::Factorisation { step: ctx.step, nnz_factor: solver.stats().nnz_factor });
    let clock = Instant::now();
    solver.set_bulk(values).map_err(linear_error(
        "; the stiffness matrix without contact must be positive definite: check that every part of the body is held",
    ))?;
    timings.numeric += clock.elapsed().as_secs_f64();
    if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
        eprintln!("bulk: {:.1} ms (condensed: {})", clock.elapsed().as_secs_f64() * 1e3, solver.is_condensed());
    }
    let vals = point_values(model, pts, pairing, ctx.u_start);
    for (st, v) in state.iter_mut().zip(&vals) {
        st.prev_jump = v.jump;
    }

    let mut stale_slow = false;
    let mut last_corr = f64::INFINITY;
    // After the first solve the interior rows (bulk, linear) of the residual are round-off
    // (condensed factor only; see `LinearSolver::zero_interior_rows`).
    let mut interior_solved = false;
    // The rows and columns that contact changes (condensed factor): later iterations refresh
    // and multiply only those (K is symmetric: row i is column i).
    let varying = solver.varying_unknowns();
    // The statuses of the previous Newton iteration (for the count of changes).
    let mut prev_status: Vec<Status> = Vec::new();
    let mut newton = |state: &mut [PointState],
                      x: &mut [f64],
                      u: &mut [f64],
                      rep: &mut ContactReport,
                      last_sig: &mut Option<Vec<(u8, u64)>>,
                      max_iter: usize,
                      predict: bool|
     -> Result<bool, SolveError> {
        let mut predicted = false;
        for it in 1..=max_iter {
            rep.newton += 1;
            // Stick predictor: the first iteration assumes every contact point sticks
            // (return mapping); the law decides from the second on.
            if predict && has_friction && it == 1 && state.iter().any(|p| p.lam_bar != 0.0) {
                for p in state.iter_mut().filter(|p| p.contact) {
                    p.lock = Some(true);
                }
                predicted = true;
            } else if it == 2 && predicted {
                for p in state.iter_mut() {
                    p.lock = None;
                }
            }
            // A loop that cycles between friction statuses: freeze them for the rest of
            // this loop (the caller checks them against the law afterwards).
            if has_friction && max_iter > 3 && it == max_iter / 3 + 1 {
                let vals = point_values(model, pts, pairing, u);
                let st_now = statuses(pts, state, &vals);
                for (p, s) in state.iter_mut().zip(&st_now) {
                    if *s != Status::Open {
                        p.lock = Some(*s == Status::Stick);
                    }
                }
            }
            let state: &[PointState] = state;
            let clock = Instant::now();
            let vals = point_values(model, pts, pairing, u);
            let st_now = statuses(pts, state, &vals);
            let sig: Vec<(u8, u64)> = st_now.iter().zip(state).map(|(s, p)| (*s as u8, p.lam_bar.to_bits())).collect();
            if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
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
                changed: if prev_status.len() == st_now.len() {
                    prev_status.iter().zip(&st_now).filter(|(a, b)| a != b).count()
                } else {
                    st_now.len()
                },
                correction: f64::NAN,
                factorised: false,
            };
            prev_status.clone_from(&st_now);
            let slip3 = three_d && st_now.contains(&Status::Slip) && has_friction;
            // Same statuses and thresholds: reuse the factor (exact in 2D; in 3D with sliding
            // points the slip direction changes the tangent, and the stale factor makes a
            // modified Newton step, refreshed when it stops halving the correction).
            // The stale factor is used only once the corrections are small (the asymptotic
            // phase): far from the answer a modified-Newton step can diverge in 3D slip.
            let same_statuses = last_sig.as_ref() == Some(&sig);
            let refactor = !same_statuses || (slip3 && (stale_slow || last_corr > STALE_FACTOR_BELOW));
            // The step is an exact Newton step (fresh factor, or 2D where the tangent only
            // depends on the statuses).
            let exact_step = refactor || !slip3;
            let kernel = ContactKernel {
                mesh: model.mesh,
                enrichment: &model.enrichment,
                cracks: &model.cracks,
                points: pts,
                state,
                u,
                pairing,
            };
            let mut kernels: Vec<&dyn Kernel> = ctx.fixed.to_vec();
            kernels.push(&kernel);
            rhs.copy_from_slice(ctx.rhs_f);
            let pattern = &layout.pattern;
            // K in the contact columns again (the previous iteration added its terms).
            columns.restore(&pattern.col_ptr, values);
            match varying.as_ref().filter(|_| interior_solved) {
                // Deferred solves read the crack rows only.
                Some(rows) => {
                    for &i in rows {
                        let r = pattern.col_ptr[i]..pattern.col_ptr[i + 1];
                        let ki: f64 = values[r.clone()].iter().zip(&pattern.row_idx[r]).map(|(v, &k)| v * x[k]).sum();
                        rhs[i] -= ki;
                    }
                }
                None => {
                    pattern.mul_vec(values, x, &mut kx);
                    for (r, k) in rhs.iter_mut().zip(&kx) {
                        *r -= k;
                    }
                }
            }
            let matrix = if refactor { Some(&mut *values) } else { None };
            layout.assemble_kernels(&kernels, &include, &zeros, matrix, Some(&mut rhs), true);
            timings.assembly += clock.elapsed().as_secs_f64();
            if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
                eprintln!("  assembly: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
            }
            event.factorised = refactor;
            if refactor {
                ctx.observer.phase(Phase::Factorisation { step: ctx.step, nnz_factor: solver.stats().nnz_factor });
                let clock = Instant::now();
                solver.factorize(values).map_err(linear_error(
                    "; the contact system is singular: check that every part of the body is held (contact alone does not hold a part without friction)",
                ))?;
                timings.numeric += clock.elapsed().as_secs_f64();
                if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
                    eprintln!("  factorize: {:.1} ms", clock.elapsed().as_secs_f64() * 1e3);
                }
                rep.factorizations += 1;
                *last_sig = Some(sig);
            }
            let clock = Instant::now();
            // After the first solve only the crack rows change: the interior correction is
            // deferred to the end of the step (condensed factor; a plain solve otherwise).
            if interior_solved { solver.solve_in_place_deferred(&mut rhs) } else { solver.solve_in_place(&mut rhs) }
                .map_err(linear_error(""))?;
            timings.solve += clock.elapsed().as_secs_f64();
            if std::env::var("FISSURE_CONTACT_LOG").is_ok() {
                let (res, refine) = solver.last_residual();
                eprintln!(
                    "  solve: {:.1} ms, residual {res:.1e}, {refine} refinements",
                    clock.elapsed().as_secs_f64() * 1e3
                );
            }
            rep.linear_solves += 1;
            interior_solved = true;
            let (mut dn, mut xn) = (0.0f64, 0.0f64);
            for (xi, d) in x.iter_mut().zip(&rhs) {
                *xi += d;
                dn = dn.max(d.abs());
                xn = xn.max(xi.abs());
            }
            for (dof, val) in u.iter_mut().enumerate() {
                let q = layout.eq_of_dof[dof];
                if q != NO_EQ {
                    *val = x[q as usize];
                }
            }
            rep.residual = if xn > 0.0 { dn / xn } else { dn };
            event.correction = rep.residual;
            ctx.observer.newton(&event);
            stale_slow = !refactor && rep.residual > 0.5 * last_corr;
            // Round-off floor: with unchanged statuses an exact Newton step on this piecewise
            // linear problem lands on the solution, so a correction that no longer shrinks and
            // is already below ROUNDOFF_FLOOR is the linear solver's accuracy, not a missing
            // iteration (large models with blending tip functions stall at ~1e-7).
            let at_floor = same_statuses
                && exact_step
                && it > 2
                && rep.residual <= ROUNDOFF_FLOOR
                && rep.residual > 0.5 * last_corr;
            last_corr = rep.residual;
            if rep.residual <= loops.tol_newton || at_floor {
                return Ok(true);
            }
        }
        Ok(false)
    };

    match loops.algorithm {
        ContactAlgorithm::Nested => {
            let mut converged_friction = false;
            for fp in 1..=loops.max_friction {
                rep.friction = fp;
                let mut converged_as = false;
                // Contact statuses before the previous update, to detect a 2-cycle.
                let mut before_previous: Option<Vec<bool>> = None;
                let mut cycle_closed = false;
                for asi in 1..=loops.max_active_set {
                    rep.active_set += 1;
                    // The stick predictor starts the first pass with friction (far from the
                    // answer); later passes and iterations start from the statuses they inherit.
                    let predict = asi == 1 && fp <= 2 && !ctx.warm;
                    if !newton(state, x, u, &mut rep, &mut last_sig, loops.max_newton, predict)? {
                        return Err(SolveError::Contact {
                            step: ctx.step,
                            loop_name: "Newton",
                            iterations: loops.max_newton,
                            residual: rep.residual,
                        });
                    }
                    let vals = point_values(model, pts, pairing, u);
                    let mut changed = false;
                    // Frozen friction statuses must agree with the law, else iterate again.
                    // A point at the Coulomb limit (|g_τ| = 1 within COULOMB_TIE) satisfies the law as a
                    // stick and as a slip point alike, so it is not a disagreement.
                    if state.iter().any(|s| s.lock.is_some()) {
                        let locked = statuses(pts, state, &vals);
                        for s in state.iter_mut() {
                            s.lock = None;
                        }
                        let free = statuses(pts, state, &vals);
                        let at_limit = at_coulomb_limit(pts, state, &vals);
                        changed |= locked.iter().zip(&free).zip(&at_limit).any(|((a, b), lim)| a != b && !lim);
                    }
                    let before: Vec<bool> = state.iter().map(|s| s.contact).collect();
                    let status_changed = update_contact_status(pts, state, &vals);
                    changed |= status_changed;
                    if !changed || (cycle_closed && !has_friction_disagreement(changed, status_changed)) {
                        converged_as = true;
                        break;
                    }
                    // A 2-cycle: a few points flip between open and closed, each status
                    // violating the law at the other (the weak law leaves them a small
                    // tension when closed and a small overlap when open). Close them (no
                    // overlap), solve once more and accept.
                    if status_changed
                        && !cycle_closed
                        && before_previous.as_ref().is_some_and(|b| state.iter().zip(b).all(|(s, c)| s.contact == *c))
                    {
                        for (s, b) in state.iter_mut().zip(&before) {
                            s.contact |= *b;
                        }
                        cycle_closed = true;
                        rep.cycles_closed += 1;
                    }
                    before_previous = Some(before);
                }
                if !converged_as {
                    return Err(SolveError::Contact {
                        step: ctx.step,
                        loop_name: "active set",
                        iterations: loops.max_active_set,
                        residual: rep.residual,
                    });
                }
                if !has_friction {
                    converged_friction = true;
                    break;
                }
                // Fixed point on the threshold: λ̄ ← λ.
                let vals = point_values(model, pts, pairing, u);
                if update_thresholds(pts, state, &vals) <= loops.tol_friction {
                    converged_friction = true;
                    break;
                }
            }
            if !converged_friction {
                return Err(SolveError::Contact {
                    step: ctx.step,
                    loop_name: "friction threshold",
                    iterations: loops.max_friction,
                    residual: rep.residual,
                });
            }
        }
        ContactAlgorithm::SemiSmooth => {
            let cap = loops.max_newton * loops.max_active_set;
            // Statuses still chattering after as many iterations as the nested Newton allows
            // before its freeze (at the Coulomb tie
            // |τ| = μp, where stick and slip both satisfy the law) are frozen, as in the
            // nested loops' Newton; the frozen statuses are checked against the law at the end.
            let freeze_at = loops.max_newton / 3 + 1;
            let mut done = false;
            for k in 1..=cap {
                rep.active_set += 1;
                if has_friction && k == freeze_at {
                    let vals = point_values(model, pts, pairing, u);
                    let st_now = statuses(pts, state, &vals);
                    for (p, s) in state.iter_mut().zip(&st_now) {
                        if *s != Status::Open {
                            p.lock = Some(*s == Status::Stick);
                        }
                    }
                }
                // Stick predictor on the first iteration with a friction threshold.
                let predict = !ctx.warm && k > 1 && state.iter().any(|p| p.lam_bar != 0.0) && rep.friction == 0;
                let step_small = newton(state, x, u, &mut rep, &mut last_sig, 2, predict)?;
                if predict {
                    rep.friction = 1;
                }
                let vals = point_values(model, pts, pairing, u);
                let changed = update_contact_status(pts, state, &vals);
                let thr_ok = !has_friction || update_thresholds(pts, state, &vals) <= loops.tol_friction;
                if step_small && !changed && thr_ok {
                    // Frozen statuses must agree with the law (or sit at the Coulomb limit).
                    if state.iter().any(|s| s.lock.is_some()) {
                        let vals = point_values(model, pts, pairing, u);
                        let locked = statuses(pts, state, &vals);
                        for s in state.iter_mut() {
                            s.lock = None;
                        }
                        let free = statuses(pts, state, &vals);
                        let at_limit = at_coulomb_limit(pts, state, &vals);
                        if locked.iter().zip(&free).zip(&at_limit).any(|((a, b), lim)| a != b && !lim) {
                            continue;
                        }
                    }
                    done = true;
                    break;
                }
            }
            for s in state.iter_mut() {
                s.lock = None;
            }
            rep.friction = 1;
            if !done {
                return Err(SolveError::Contact {
                    step: ctx.step,
                    loop_name: "semi-smooth Newton",
                    iterations: cap,
                    residual: rep.residual,
                });
            }
        }
    }

    // The interior corrections deferred by the Newton iterations.
    let clock = Instant::now();
    solver.apply_deferred(x);
    for (dof, val) in u.iter_mut().enumerate() {
        let q = layout.eq_of_dof[dof];
        if q != NO_EQ {
            *val = x[q as usize];
        }
    }
    timings.solve += clock.elapsed().as_secs_f64();

    // Figures of the converged step.
    let vals = point_values(model, pts, pairing, u);
    let st = statuses(pts, state, &vals);
    rep.points = st.len();
    rep.active = st.iter().filter(|s| **s != Status::Open).count();
    rep.stick = st.iter().filter(|s| **s == Status::Stick).count();
    rep.slip = st.iter().filter(|s| **s == Status::Slip).count();
    rep.lambda_min = vals.iter().map(|v| v.lambda).fold(f64::INFINITY, f64::min);
    rep.lambda_max = vals.iter().map(|v| v.lambda).fold(f64::NEG_INFINITY, f64::max);
    if rep.points == 0 {
        rep.lambda_min = 0.0;
        rep.lambda_max = 0.0;
    }
    Ok(rep)
}
