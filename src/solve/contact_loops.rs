//! The contact loops of one load step (formulation §6), outermost first, each a named
//! piece with its cap, tolerance and log line (`FISSURE_CONTACT_LOG`):
//!
//! ```text
//! geometry loop        (large sliding) re-pair the points with the master lip;
//!                      cap max_geometry, ends when no master point moved by more than
//!                      tol_geometry · h                       log: "geometry {k}: moved .."
//! ⊃ friction threshold fixed point λ̄ ← min(λ, 0); cap max_friction, tol_friction on
//!                      the relative change of λ̄              log: "friction {k}: change .."
//!                      (intermediate passes end their Newton loop provisionally, the
//!                      accepted one is confirmed: `Loops::friction_loop`)
//! ⊃ active set         contact status χ_c from the law; cap max_active_set, ends when no
//!                      status changes and the frozen friction statuses agree with the law
//!                                                             log: "active set {k}: changed .."
//! ⊃ Newton             on frozen statuses (super::newton); cap max_newton, tol_newton
//! ```
//!
//! The semi-smooth strategy ([`ContactAlgorithm::SemiSmooth`]) runs the same pieces in one
//! loop: short Newton passes, each followed by the contact-status and threshold updates.
//! Both strategies share the status freeze ([`freeze_statuses`]) and the law check of the
//! frozen statuses ([`frozen_statuses_agree`]). A stick/slip disagreement that the active
//! set accepted because it repeats (a status cycle) is carried from one friction pass to
//! the next (`CarriedCycle`).
//!
//! Entry points: [`solve_contact`] (the geometry loop and everything inside it, for one
//! step), [`contact_step`] (the loops inside one pairing).

use super::backend::LinearError;
use super::linear::LinearSolver;
use super::newton::{contact_log, copy_to_dofs, ContactColumns, Newton, StepContext};
use super::observe::{Phase, SolveObserver};
use super::report::{ContactReport, SolveError, Timings};
use super::setup::{CarriedFactor, FixedKernels, Setup, System};
use crate::assembly::{Kernel, NO_EQ};
use crate::contact::law::{PointState, Status};
use crate::contact::lip_wear::LipChart;
use crate::contact::pairing::{Pairing, PointPairing};
use crate::contact::state::{
    accumulate_wear, commit_wear, face_master_wear, freeze_statuses, frozen_disagreements, frozen_statuses_agree,
    point_values, project_point_tractions, start_tangential_state, statuses, store_tangential_state,
    update_contact_status, update_thresholds,
};
use crate::contact::ContactAlgorithm;
use std::time::Instant;

/// The friction fixed point stalls when a pass changes the thresholds by at least this
/// fraction of the previous pass's change.
pub const STALL_RATIO: f64 = 0.9;
/// A stalled friction fixed point is accepted (with a warning) when its relative change is
/// at most this × `tol_friction` (1e-2 with the default tolerance, the tolerance of the weak
/// Coulomb tie, [`crate::contact::state::COULOMB_TIE`]). The thresholds of a fretting pad's
/// stick/slip boundary alternate at 1.8e-3 at its reversals (1.7e-4 on a platen's whole
/// interface): there the discrete law has no fixed point, and a relaxed fixed point
/// (λ̄ ← λ̄ + ½(min(λ, 0) − λ̄), tried) stalls at 1.2e-3 the same way.
pub const STALL_ACCEPT: f64 = 1e4;

/// The geometry loop of one step and the loops inside it: from `u` and `state` at the
/// start of the step to the converged ones. `pairing` is the pairing of the large-sliding
/// cracks (updated in place); `sys` holds K, which is assembled on first use.
#[allow(clippy::too_many_arguments)]
pub fn solve_contact(
    setup: &Setup<'_, '_>,
    sys: &mut System,
    fixed: &FixedKernels<'_>,
    prescribed: &[f64],
    step: usize,
    u: &mut [f64],
    state: &mut [PointState],
    pairing: &mut Option<Pairing>,
    timings: &mut Timings,
    observer: &dyn SolveObserver,
) -> Result<ContactReport, SolveError> {
    let c = setup.contact.expect("a contact setup");
    let loops = &c.loops;
    let u_start = u.to_vec();
    let wear = c.points.cracks.iter().any(|cc| cc.law.wear.is_some());
    if wear {
        commit_wear(state);
    }
    // Large sliding with wear: where the slave points meet the `+` lip's wear.
    let chart = if wear && setup.large { LipChart::build(&c.points, &setup.model.cracks) } else { None };
    if !c.points.all_have_multipliers() {
        start_tangential_state(&c.points, state);
    }
    for &d in &setup.constrained {
        if sys.layout.eq_of_dof[d] == NO_EQ {
            u[d] = prescribed[d];
        }
    }
    let h_geo =
        c.points.cracks.iter().filter(|cc| cc.large_sliding).map(|cc| cc.cell_size).fold(f64::INFINITY, f64::min);
    let zero_u = vec![0.0; u.len()];
    let fixed_list = fixed.list();
    let fixed_mask = [true, true, true, true, false];
    let mut total: Option<ContactReport> = None;
    let mut rhs_ready = false;
    let (mut geometry, mut rebuilds) = (0, 0);
    // The meshed pairs' contact zones (`contact::zone`): grown, the step is redone from here.
    let mut zone: Vec<f64> = pairing.as_ref().map_or_else(Vec::new, |p| p.zone.clone());
    let state_start = state.to_vec();
    let mut regrowths = 0;
    // After a regrowth the step is redone from its start: displacements (the prescribed
    // values of the constrained dofs outside the equations), statuses.
    let restart = |u: &mut [f64], state: &mut [PointState], eq_of_dof: &[u32]| {
        u.copy_from_slice(&u_start);
        state.copy_from_slice(&state_start);
        for &d in &setup.constrained {
            if eq_of_dof[d] == NO_EQ {
                u[d] = prescribed[d];
            }
        }
    };
    loop {
        geometry += 1;
        if setup.large {
            observer.phase(Phase::Pairing { step });
            let clock = Instant::now();
            let new = setup.pair_in(u, &zone);
            timings.pairing += clock.elapsed().as_secs_f64();
            let old = pairing.as_ref().expect("a pairing");
            if geometry > 1 {
                let (moved, flipped) = new.change_from(old);
                if contact_log() {
                    eprintln!("geometry {geometry}: moved {:.2e} h, flipped {flipped}", moved / h_geo);
                }
                if moved <= loops.tol_geometry * h_geo && !flipped {
                    break;
                }
                if geometry > loops.max_geometry {
                    return Err(SolveError::Contact {
                        step,
                        loop_name: "geometry",
                        iterations: loops.max_geometry,
                        residual: moved / h_geo,
                    });
                }
            }
            if !new.same_pattern(old) {
                // The pairing couples other cells: new pattern, new symbolic analysis.
                let clock = Instant::now();
                let layout = match setup.build_layout_owned(Some(&new), state)? {
                    Some(layout) => layout,
                    None => setup.build_layout(Some(&new), state),
                };
                timings.pattern += clock.elapsed().as_secs_f64();
                observer.phase(Phase::Symbolic { equations: layout.n_eq, nnz_matrix: layout.nnz() });
                let clock = Instant::now();
                let solver = setup.analyse_with(&layout, step, !sys.plain_fallback)?;
                timings.symbolic += clock.elapsed().as_secs_f64();
                sys.rebuild(layout, solver);
                rhs_ready = false;
                rebuilds += 1;
            }
            for (st, p) in state.iter_mut().zip(&new.points) {
                if !matches!(p, PointPairing::Paired(_)) {
                    st.contact = false;
                    st.lock = None;
                }
            }
            if let Some(chart) = &chart {
                face_master_wear(&c.points, state, chart, &new);
            }
            *pairing = Some(new);
            // The contact terms follow the pairing: a carried factor is stale.
            sys.carried = None;
        }
        // K once (again after a pattern rebuild), the load vector once per step.
        let ck = setup.contact_kernel(state, &zero_u, pairing.as_ref()).expect("a contact kernel");
        let mut all: Vec<&dyn Kernel> = fixed_list.to_vec();
        all.push(&ck);
        let clock = Instant::now();
        if !sys.k_assembled && sys.layout.is_distributed() {
            // Distributed assembly: each rank's elements of K straight into the backend's
            // matrix, its part of the load vector on the way (summed over the ranks with
            // the rest of the residual in each Newton iteration).
            let (layout, rhs) = (&sys.layout, &mut sys.rhs);
            sys.solver
                .set_bulk_elements(&mut |sink| {
                    layout.assemble_elements(&all, &fixed_mask, prescribed, Some(&mut *rhs), sink);
                    // The contact entries, as zeros, into the matrix's structure.
                    layout.zero_elements(&[false, false, false, false, true], sink);
                })
                .map_err(|error| SolveError::Linear { step, error, advice: "" })?;
            fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
            sys.k_assembled = true;
            sys.values_generation += 1;
            rhs_ready = true;
        } else if !sys.k_assembled {
            // The driver may have assembled the first step's K and f beside the symbolic
            // analysis (`System::prefilled`, the same kernels and mask).
            if !std::mem::take(&mut sys.prefilled) {
                sys.layout.assemble_kernels(
                    &all,
                    &fixed_mask,
                    prescribed,
                    Some(&mut sys.values),
                    Some(&mut sys.rhs),
                    false,
                );
                fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
            }
            sys.k_assembled = true;
            sys.values_generation += 1;
            rhs_ready = true;
        } else if !rhs_ready {
            let mask = [!fixed.bulk_rhs_zero, true, true, true, false];
            sys.layout.assemble_kernels(&all, &mask, prescribed, None, Some(&mut sys.rhs), false);
            fixed.add_dof_loads(&sys.layout, &mut sys.rhs);
            rhs_ready = true;
        }
        timings.assembly += clock.elapsed().as_secs_f64();
        sys.check_rhs(step)?;
        for (d, &ud) in u.iter().enumerate() {
            let q = sys.layout.eq_of_dof[d];
            if q != NO_EQ {
                sys.x[q as usize] = ud;
            }
        }
        let ctx = StepContext {
            model: setup.model,
            points: &c.points,
            loops,
            layout: &sys.layout,
            fixed: &fixed_list,
            rhs_f: &sys.rhs,
            step,
            pairing: pairing.as_ref(),
            u_start: &u_start,
            warm: geometry > 1,
            observer,
        };
        observer.phase(Phase::ContactLoops { step, geometry });
        // A condensed factor whose solve fails its residual check (an ill-conditioned
        // crack block: a very large ρ_n, collocated contact points) is not the end: the
        // step is redone from its start with the plain LDLᵀ of the whole system.
        let saved = (setup.condenses() && !sys.plain_fallback).then(|| (u.to_vec(), state.to_vec(), sys.x.clone()));
        let carry = sys.carry_factor.then_some(sys.values_generation);
        let attempt = match contact_step(
            &ctx,
            &mut sys.solver,
            &mut sys.x,
            u,
            state,
            timings,
            &mut sys.values,
            carry,
            &mut sys.carried,
        ) {
            Err(SolveError::Linear { error: LinearError::Singular { relative_residual, .. }, .. })
                if saved.is_some() =>
            {
                let (u0, state0, x0) = saved.expect("saved above");
                u.copy_from_slice(&u0);
                state.copy_from_slice(&state0);
                sys.x.copy_from_slice(&x0);
                if contact_log() {
                    eprintln!("condensed solve failed (relative residual {relative_residual:.1e}): plain LDLᵀ");
                }
                let clock = Instant::now();
                let solver = setup.analyse_with(&sys.layout, step, false)?;
                timings.symbolic += clock.elapsed().as_secs_f64();
                sys.solver = solver;
                sys.plain_fallback = true;
                sys.carried = None;
                contact_step(
                    &ctx,
                    &mut sys.solver,
                    &mut sys.x,
                    u,
                    state,
                    timings,
                    &mut sys.values,
                    carry,
                    &mut sys.carried,
                )
                .map(|mut rep| {
                    rep.condensed_fallback = Some(relative_residual);
                    rep
                })
            }
            other => other,
        };
        let rep = match attempt {
            // A singular solve with points left out of a pair's contact zone: a zone too
            // small to hold the bodies. It grows (doubled) and the step is redone.
            Err(e @ SolveError::Linear { .. }) if pairing.as_ref().is_some_and(|p| p.counts.zone_out > 0) => {
                regrowths += 1;
                let pairs: Vec<String> = setup
                    .contact
                    .iter()
                    .flat_map(|c| &c.points.cracks)
                    .zip(&zone)
                    .filter(|(_, z)| z.is_finite())
                    .filter_map(|(cc, z)| cc.pair.as_ref().map(|p| format!("pair '{}' (zone {z:.3e})", p.name)))
                    .collect();
                let names = format!(
                    "{}: the solve with the points outside the contact zone held open failed ({e})",
                    pairs.join(", ")
                );
                zone_regrowth(regrowths, step, names)?;
                for z in &mut zone {
                    *z *= 2.0;
                }
                restart(u, state, &sys.layout.eq_of_dof);
                geometry = 0;
                continue;
            }
            r => r?,
        };
        total = Some(match total {
            None => rep,
            Some(t) => ContactReport {
                friction: t.friction + rep.friction,
                active_set: t.active_set + rep.active_set,
                newton: t.newton + rep.newton,
                factorizations: t.factorizations + rep.factorizations,
                linear_solves: t.linear_solves + rep.linear_solves,
                condensed_fallback: t.condensed_fallback.or(rep.condensed_fallback),
                condensed: match (t.condensed, rep.condensed) {
                    (Some(a), Some(b)) => Some(a.plus(b)),
                    (a, b) => a.or(b),
                },
                kept: match (t.kept, rep.kept) {
                    (Some(a), Some(b)) => Some(a.plus(b)),
                    (a, b) => a.or(b),
                },
                friction_stalled: t.friction_stalled.or(rep.friction_stalled),
                damped_redo: t.damped_redo || rep.damped_redo,
                ..rep
            },
        });
        // Before the step is accepted: every point outside a pair's contact zone must be
        // open by the law, or the zone grows and the step is redone from its start.
        if let Some(growth) = zone_growth(setup, pairing.as_ref(), state, u) {
            regrowths += 1;
            zone_regrowth(regrowths, step, zone_failures(setup, &growth))?;
            zone = growth.zone;
            restart(u, state, &sys.layout.eq_of_dof);
            geometry = 0;
            continue;
        }
        if !setup.large {
            break;
        }
    }
    let mut rep = total.expect("one contact pass");
    rep.zone_regrowths = regrowths;
    // The tangential state of the laws without multipliers, for the next step.
    if !c.points.all_have_multipliers() {
        let vals = point_values(setup.model, &c.points, pairing.as_ref(), state, u);
        store_tangential_state(&c.points, state, &vals);
    }
    // The wear of the step (Archard), from the converged values; deeper than a cell stops.
    if wear {
        let vals = point_values(setup.model, &c.points, pairing.as_ref(), state, u);
        let deepest = accumulate_wear(&c.points, state, &vals, chart.as_ref(), pairing.as_ref());
        for (cc, &depth) in c.points.cracks.iter().zip(&deepest) {
            if depth > cc.cell_size {
                return Err(SolveError::Wear {
                    step,
                    crack: match &cc.pair {
                        Some(p) => format!("contact pair '{}'", p.name),
                        None => format!("crack '{}'", setup.model.cracks[cc.crack].name),
                    },
                    depth,
                    cell_size: cc.cell_size,
                });
            }
        }
    }
    if setup.large {
        rep.geometry = geometry - 1;
        rep.pattern_rebuilds = rebuilds;
        rep.pairing = pairing.as_ref().map(|p| p.counts);
    }
    Ok(rep)
}

/// A contact zone's regrowth number `regrowths` of step `step` (the pairs and why in
/// `names`): logged, or the error once it exceeds [`crate::contact::zone::MAX_REGROWTHS`].
fn zone_regrowth(regrowths: usize, step: usize, names: String) -> Result<(), SolveError> {
    if contact_log() {
        eprintln!("contact zone: {names}: regrowth {regrowths}, the step is redone");
    }
    if regrowths > crate::contact::zone::MAX_REGROWTHS {
        return Err(SolveError::ContactZone { step, regrowths: regrowths - 1, pairs: names });
    }
    Ok(())
}

/// The check of the meshed pairs' contact zones at a converged state
/// (`contact::zone::check`): `None` if every dormant point is open by the law (or no pair
/// has a zone), else the grown zones.
fn zone_growth(
    setup: &Setup<'_, '_>,
    pairing: Option<&Pairing>,
    state: &[PointState],
    u: &[f64],
) -> Option<crate::contact::zone::Growth> {
    let (c, p) = (setup.contact?, pairing?);
    if p.counts.zone_out == 0 {
        return None;
    }
    let vals = point_values(setup.model, &c.points, Some(p), state, u);
    crate::contact::zone::check(&c.points, p, &vals)
}

/// The pairs whose zone failed its check, for the log and the error: "pair 'name': n
/// points outside the zone would touch (largest reference gap g; zone a → b)".
fn zone_failures(setup: &Setup<'_, '_>, growth: &crate::contact::zone::Growth) -> String {
    let Some(c) = setup.contact else { return String::new() };
    let mut out = Vec::new();
    for (ci, cc) in c.points.cracks.iter().enumerate() {
        let n = growth.violations.get(ci).copied().unwrap_or(0);
        if n == 0 {
            continue;
        }
        let name = cc.pair.as_ref().map_or_else(|| format!("crack {ci}"), |p| format!("pair '{}'", p.name));
        out.push(format!(
            "{name}: {n} points outside the contact zone would touch (largest reference gap {:.3e}; zone grown to {:.3e})",
            growth.largest_gap[ci], growth.zone[ci]
        ));
    }
    out.join("; ")
}

/// Runs the contact loops of one step inside one pairing, from the current `x`
/// (equations), `u` (every dof) and `state` (per point), and leaves the converged solution
/// in them. `k_values` holds K (the fixed kernels) on the layout's pattern: the contact
/// terms are added to it in place (no second matrix-sized array) and K is restored before
/// returning. `carried`: the factor the solver holds from the previous step
/// ([`CarriedFactor`], with `carry` the generation of `k_values`
/// ([`System::values_generation`]): dynamics), reused while the statuses and thresholds
/// are those it was computed with and K's values are those of the same assembly; replaced
/// by this step's on success, left empty on an error.
#[allow(clippy::too_many_arguments)]
pub fn contact_step(
    ctx: &StepContext<'_, '_>,
    solver: &mut LinearSolver,
    x: &mut [f64],
    u: &mut [f64],
    state: &mut [PointState],
    timings: &mut Timings,
    k_values: &mut [f64],
    carry: Option<u64>,
    carried: &mut Option<CarriedFactor>,
) -> Result<ContactReport, SolveError> {
    let clock = Instant::now();
    let counts_before = solver.stats().condensed;
    let kept_before = solver.stats().kept;
    let columns = ContactColumns::save(ctx.layout, &ctx.kernel(state, u), k_values);
    if ctx.layout.is_distributed() {
        // Distributed assembly: the backend keeps K's rows of the contact equations.
        solver.keep_bulk_rows(columns.columns()).map_err(ctx.linear_error(""))?;
    }
    timings.step_phases.columns += clock.elapsed().as_secs_f64();
    // K's generation identifies the bulk of the carried factor (the values of one
    // assembly: a changed ρ, Δt or scheme coefficient is a new assembly).
    let clock = Instant::now();
    let resumed = carried.take().filter(|c| Some(c.bulk_generation) == carry);
    timings.step_phases.checksum += clock.elapsed().as_secs_f64();
    // The bulk of a condensed factor: K (factorised once, unless it changed). A carried
    // factor's bulk is this K already (set by an earlier step on the same values): its
    // O(nnz) check is skipped.
    ctx.observer.phase(Phase::Factorisation { step: ctx.step, nnz_factor: solver.stats().nnz_factor });
    let clock = Instant::now();
    if resumed.is_none() {
        solver.set_bulk(k_values).map_err(ctx.linear_error(
            "; the stiffness matrix without contact must be positive definite: check that every part of the body is held",
        ))?;
    }
    timings.numeric += clock.elapsed().as_secs_f64();
    timings.step_phases.bulk += clock.elapsed().as_secs_f64();
    if contact_log() {
        eprintln!("bulk: {:.1} ms (condensed: {})", clock.elapsed().as_secs_f64() * 1e3, solver.is_condensed());
    }
    // The jump at the start of the step (for v_τ), with the current pairing.
    let vals = point_values(ctx.model, ctx.points, ctx.pairing, state, ctx.u_start);
    for (st, v) in state.iter_mut().zip(&vals) {
        st.prev_jump = v.jump;
    }
    let mut newton = Newton::new(ctx, solver, u.len());
    if let Some(c) = resumed {
        newton.resume_factor(c.signature);
    }
    if carry.is_some() {
        newton.confirm_exact_steps();
    }
    let sticky = vec![false; state.len()];
    // The start of a first step from nonzero friction thresholds (a case's
    // `initial_threshold`), kept to redo the step from thresholds 0 (Loops::restart_frictionless).
    let restart = (!ctx.warm && carry.is_none() && ctx.u_start.iter().all(|&v| v == 0.0))
        .then_some(())
        .filter(|_| state.iter().any(|s| s.lam_bar != 0.0))
        .map(|_| (state.to_vec(), x.to_vec(), u.to_vec()));
    let start = (state.to_vec(), x.to_vec(), u.to_vec());
    let mut loops = Loops {
        ctx,
        columns: &columns,
        solver,
        values: k_values,
        x,
        u,
        state,
        timings,
        newton,
        bonded: false,
        retried: false,
        sticky,
        predicted: false,
        gap: None,
        restart,
        last_ended: None,
        carried_cycle: None,
        start,
        damped: false,
    };
    if !ctx.warm && ctx.u_start.iter().all(|&v| v == 0.0) {
        loops.gap = GapBisection::new(ctx, loops.state, loops.u.len());
    }
    let result = loops.run().map(|mut rep| {
        rep.condensed = loops.solver.stats().condensed.map(|c| c.since(counts_before.unwrap_or_default()));
        rep.kept = loops.solver.stats().kept.map(|c| c.since(kept_before.unwrap_or_default()));
        rep
    });
    columns.restore(&ctx.layout.pattern.col_ptr, loops.values);
    if let (Ok(_), Some(bulk_generation), Some(signature)) = (&result, carry, loops.newton.factor_signature()) {
        *carried = Some(CarriedFactor { signature: signature.to_vec(), bulk_generation });
    }
    result
}

/// The loops of one step and everything they work on.
struct Loops<'a, 'c, 'm> {
    ctx: &'a StepContext<'c, 'm>,
    columns: &'a ContactColumns,
    solver: &'a mut LinearSolver,
    values: &'a mut [f64],
    x: &'a mut [f64],
    u: &'a mut [f64],
    state: &'a mut [PointState],
    timings: &'a mut Timings,
    newton: Newton,
    /// The first friction pass was redone bonded (every point closed and stuck).
    bonded: bool,
    /// The first pass was redone after a singular solve (at most once per step).
    retried: bool,
    /// Points closed by the cycle rule: they stay closed for the rest of the step. At
    /// the edge of a contact zone that the multiplier packets cannot resolve, they would
    /// otherwise reopen in the next friction pass, close again, and keep the thresholds
    /// from converging.
    sticky: Vec<bool>,
    /// A pass has started from the stick predictor with friction thresholds: the later
    /// passes start from the statuses they inherit.
    predicted: bool,
    /// The gap-ordered bisection of the meshed pairs' contact zone ([`GapBisection`]), in a
    /// step that starts from the undeformed configuration.
    gap: Option<GapBisection>,
    /// The statuses and unknowns at the start of a first step whose friction thresholds
    /// start nonzero (`initial_threshold`): loops that fail from them are redone
    /// from the frictionless start ([`Loops::restart_frictionless`]).
    restart: Option<(Vec<PointState>, Vec<f64>, Vec<f64>)>,
    /// The statuses (frozen ones included) the last active-set iteration's solution was
    /// computed with, with friction: a Newton loop that goes through them again is a cycle
    /// of the active-set loop ([`Loops::active_set_loop`]).
    last_ended: Option<Vec<Status>>,
    /// The cycle the last friction pass accepted ([`CarriedCycle`]), for the next pass to
    /// start from.
    carried_cycle: Option<CarriedCycle>,
    /// The statuses and unknowns at the start of the step, for its damped redo
    /// ([`Loops::redo_damped`]).
    start: (Vec<PointState>, Vec<f64>, Vec<f64>),
    /// The loops run with damped Newton steps ([`Newton::damp`]): the step's redo.
    damped: bool,
}

/// The plain loops' answer is redone with damped Newton steps (`Loops::redo_damped`)
/// when the stick/slip statuses they accepted against the law exceed this fraction of
/// the points in contact. A status cycle of a few points at the stick/slip boundary, which
/// the weak law's shared multiplier packets cannot resolve, is accepted (71 of 6 517 on the
/// 3D Hertz sphere row, 1.1%); a third of the zone (the sphere between dissimilar
/// materials on a 24 × 16 × 24 mesh: 721 of 2 029) is the generalized Newton step's
/// overshoot, not the law's limit.
pub const DAMPED_REDO_ABOVE: f64 = 0.1;

/// The stick/slip disagreement a friction pass accepted because its active-set loop
/// repeated it (the same points disagreeing in two iterations running, with the contact
/// statuses settled: points whose stick and slip statuses each violate the law at the
/// other, [`Loops::active_set_loop`]), carried to the next pass when that pass's threshold
/// update is below [`CARRY_CYCLE_BELOW`]: the next pass starts with those points held at
/// the statuses the accepted solution was computed with (the other points free), and its
/// first active-set iteration counts the carried disagreement as its previous one. Found
/// again (the same points or some of them, still at the held statuses), it is the same
/// cycle and is accepted at once; anything else and the loop goes on from the law's
/// statuses as without it. Without it every later pass of the 3D Hertz sphere row ran the
/// cycle twice (the law's statuses, 3–4 Newton iterations of the cycle, its freeze, 3–4 to
/// converge, then again from the law's statuses: 14–24 Newton iterations a pass).
#[derive(Debug, Clone)]
struct CarriedCycle {
    /// Per point: the held status (Some(true) stick, Some(false) slip) of a point of the
    /// cycle, None elsewhere.
    locks: Vec<Option<bool>>,
    /// The points of the cycle: the disagreeing ones and those of the accepted iteration's
    /// own Newton status cycle ([`Newton::cyclers`]; some of them at the Coulomb limit,
    /// where either status agrees with the law).
    members: Vec<bool>,
    /// The cycle was found again in a later pass ([`CarriedCycle::found_again`]): it
    /// persisted through a threshold update, and the next pass holds its points.
    confirmed: bool,
}

impl CarriedCycle {
    /// The cycle of an accepted iteration: its frozen statuses `locks` (every point's) at
    /// the points of `disagree` and of its Newton loop's status cycle (`cyclers`, empty
    /// without one).
    fn new(locks: &[Option<bool>], disagree: &[bool], cyclers: &[bool], confirmed: bool) -> CarriedCycle {
        let members: Vec<bool> =
            disagree.iter().enumerate().map(|(k, &d)| d || cyclers.get(k) == Some(&true)).collect();
        CarriedCycle {
            locks: locks.iter().zip(&members).map(|(l, &m)| if m { *l } else { None }).collect(),
            members,
            confirmed,
        }
    }

    /// Whether the disagreement `disagree` (some point disagreeing), found at the frozen
    /// statuses `locks`, is this cycle again: every disagreeing point one of the cycle's,
    /// held at the cycle's status, or one of the points of a status cycle of this
    /// iteration's own Newton loop (`cyclers`, frozen sliding: [`Newton::cyclers`]).
    fn found_again(&self, disagree: &[bool], locks: &[Option<bool>], cyclers: &[bool]) -> bool {
        disagree.len() == self.members.len()
            && locks.len() == self.locks.len()
            && disagree.contains(&true)
            && disagree.iter().enumerate().all(|(k, &d)| {
                !d || (self.members[k] && locks[k] == self.locks[k])
                    || (cyclers.get(k) == Some(&true) && locks[k] == Some(false))
            })
    }
}

/// A friction pass whose thresholds changed by more than this fraction (relative, as
/// `tol_friction`) does not carry its accepted cycle to the next pass: the thresholds of
/// the next pass are not close to the ones that cycle was found at. The scale at which a
/// stalled fixed point is accepted ([`STALL_ACCEPT`] × the default `tol_friction`).
pub const CARRY_CYCLE_BELOW: f64 = 1e-2;

/// A faster first active set for the meshed contact pairs, in a step that starts from the
/// undeformed configuration. The active-set update closes every overlapping point at
/// once, but opens only the points in tension: from a contact zone too large (a tie-like
/// start, or the overlap of a first solve held by a few points) it shrinks by one ring of
/// points per iteration (the tension sits at the zone's edge), one factorisation each. For
/// a convex body pressed on another the contact zone is a set of smallest initial gaps, so
/// a shrinking update (points opened, none closed) bounds the zone from above by the closed
/// set's size, a growing one from below; after a shrinking update the closed set becomes
/// the smallest-gap prefix of the midpoint between the bounds, when that opens more than
/// the update would. The bisection stops at the first growth after it or at an update
/// that both opens and closes (a zone that is not gap-ordered); from then on the plain
/// update decides, and the loop converges only on its fixed point, so the answer is the
/// same. A bisected set whose solve is singular (a body held only by the pair and not
/// held by that prefix) is replaced by the update's own set.
struct GapBisection {
    /// The paired points of the meshed pairs, smallest initial gap first.
    order: Vec<usize>,
    /// Closed prefix sizes known too small (a growth followed) and too large (a shrink).
    lo: usize,
    hi: usize,
    /// A bisection step has been taken.
    bisected: bool,
    done: bool,
    /// The update's own statuses, while a bisected set has not been solved.
    fallback: Option<Vec<bool>>,
    /// Per point: outside its pair's contact zone (`contact::zone`, held open).
    dormant: Vec<bool>,
    /// Per point: dormant and closed by the last update's law (held open by the zone),
    /// or closed by the bisected set: counted as closed, so that the bounds are those of
    /// the whole band.
    held: Vec<bool>,
}

impl GapBisection {
    /// None without a paired point of a meshed pair.
    fn new(ctx: &StepContext<'_, '_>, state: &[PointState], n_dofs: usize) -> Option<GapBisection> {
        let pts = ctx.points;
        if !pts.cracks.iter().any(|c| c.pair.is_some()) {
            return None;
        }
        let vals = point_values(ctx.model, pts, ctx.pairing, state, &vec![0.0; n_dofs]);
        let mut order: Vec<usize> = (0..pts.points.len())
            .filter(|&k| pts.cracks[pts.points[k].crack].pair.is_some() && vals[k].paired)
            .collect();
        // Smallest gap −d_n first.
        order.sort_by(|&a, &b| vals[b].d_n.total_cmp(&vals[a].d_n));
        let hi = order.len();
        let dormant: Vec<bool> = vals.iter().map(|v| v.dormant).collect();
        let held = vec![false; dormant.len()];
        (hi > 0).then_some(GapBisection {
            order,
            lo: 0,
            hi,
            bisected: false,
            done: false,
            fallback: None,
            dormant,
            held,
        })
    }

    /// After the update from `before` to `state`'s statuses: the bisected set in `state`
    /// (true) or the update's (false). `would_close`: per point, dormant and closed by the
    /// update's law (`contact::zone::would_close`; empty: none), counted as closed as in
    /// the whole band.
    fn step(&mut self, before: &[bool], state: &mut [PointState], would_close: &[bool]) -> bool {
        if self.done {
            return false;
        }
        let held = std::mem::take(&mut self.held);
        let was = |k: usize| before[k] || held.get(k).copied().unwrap_or(false);
        let now = |k: usize, state: &[PointState]| state[k].contact || would_close.get(k).copied().unwrap_or(false);
        let k_before = self.order.iter().filter(|&&k| was(k)).count();
        let opened = self.order.iter().filter(|&&k| was(k) && !now(k, state)).count();
        let closed = self.order.iter().filter(|&&k| !was(k) && now(k, state)).count();
        self.held = (0..before.len()).map(|k| would_close.get(k).copied().unwrap_or(false)).collect();
        match (opened > 0, closed > 0) {
            (true, false) => {
                self.hi = self.hi.min(k_before);
                let m = (self.lo + self.hi) / 2;
                if m > self.lo && m < k_before - opened {
                    self.fallback = Some(state.iter().map(|s| s.contact).collect());
                    for (i, &k) in self.order.iter().enumerate() {
                        // A dormant point of the prefix stays open, counted as closed.
                        let dormant = self.dormant.get(k).copied().unwrap_or(false);
                        state[k].contact = i < m && !dormant;
                        self.held[k] = i < m && dormant;
                    }
                    self.bisected = true;
                    return true;
                }
            }
            (false, true) => {
                self.lo = self.lo.max(k_before);
                self.done = self.bisected;
            }
            _ => self.done = true,
        }
        false
    }
}

impl Loops<'_, '_, '_> {
    fn has_friction(&self) -> bool {
        self.ctx.points.cracks.iter().any(|c| c.law.friction > 0.0)
    }

    fn newton(&mut self, rep: &mut ContactReport, max_iter: usize, predict: bool) -> Result<bool, SolveError> {
        self.newton.run(
            self.ctx,
            self.columns,
            self.solver,
            self.values,
            self.state,
            self.x,
            self.u,
            rep,
            self.timings,
            max_iter,
            predict,
        )
    }

    /// The strategy's loops, then the deferred interior corrections and the step's figures.
    fn run(&mut self) -> Result<ContactReport, SolveError> {
        let mut rep = ContactReport::default();
        let mut solved = self.strategy(&mut rep);
        if let Err(e) = solved {
            solved = match self.restart_frictionless(e) {
                Ok(()) => self.strategy(&mut rep),
                Err(e) => Err(e),
            };
        }
        if let Some(why) = self.damped_redo_reason(&solved, &rep) {
            self.redo_damped(&why, &mut rep);
            // A loop of the redo at its cap: the error says that the step was redone and
            // why (the loop's own message stays first, its public name unchanged).
            solved = self.strategy(&mut rep).map_err(|e| match e {
                e @ SolveError::Contact { .. } => SolveError::Advised {
                    error: Box::new(e),
                    advice: format!(
                        "The step had been redone with damped Newton steps because the plain contact loops failed first ({why})"
                    ),
                },
                e => e,
            });
            // Still a large part of the zone against the law: loud, not an answer.
            let accepted: usize = rep.accepted_disagreements.iter().sum();
            let closed = self.points_in_contact();
            if solved.is_ok() && accepted as f64 > DAMPED_REDO_ABOVE * closed as f64 {
                solved = Err(SolveError::Contact {
                    step: self.ctx.step,
                    loop_name: "stick/slip",
                    iterations: rep.active_set,
                    residual: accepted as f64,
                });
            }
        }
        solved?;
        // The interior corrections deferred by the Newton iterations.
        let clock = Instant::now();
        self.solver.apply_deferred(self.x);
        copy_to_dofs(self.ctx.layout, self.x, self.u);
        self.timings.solve += clock.elapsed().as_secs_f64();
        self.timings.step_phases.deferred += clock.elapsed().as_secs_f64();
        // The output slots of the laws without multipliers (penalty).
        let ctx = self.ctx;
        if !ctx.points.all_have_multipliers() {
            let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
            project_point_tractions(ctx.points, &vals, self.u);
        }
        self.figures(&mut rep);
        Ok(rep)
    }

    /// The loops of the case's strategy.
    fn strategy(&mut self, rep: &mut ContactReport) -> Result<(), SolveError> {
        match self.ctx.loops.algorithm {
            ContactAlgorithm::Nested => self.friction_loop(rep),
            ContactAlgorithm::SemiSmooth => self.semi_smooth(rep),
        }
    }

    /// Friction-threshold fixed point ⊃ active set: λ̄ ← min(λ, 0) until it changes by
    /// less than `tol_friction` (relative), at most `max_friction` passes. A fixed point
    /// that stalls (two passes running without contracting by [`STALL_RATIO`]) below
    /// [`STALL_ACCEPT`] × `tol_friction` is accepted and reported
    /// ([`ContactReport::friction_stalled`], a warning of the step).
    ///
    /// The passes end their Newton loop provisionally
    /// ([`Newton::allow_provisional`], `ContactLoops::provisional_passes`): one solve a pass
    /// where the statuses settle, instead of two (the step and the solve confirming it), as
    /// the next pass continues the Newton iteration from the iterate. The pass whose
    /// thresholds are accepted is solved again on its own thresholds to `tol_newton`, and
    /// the thresholds of that solution decide, so the accepted answer meets the same
    /// tolerances as with every pass confirmed. The provisional ends stop for the rest of
    /// the step at the first stalling pass and in the second half of the cap.
    fn friction_loop(&mut self, rep: &mut ContactReport) -> Result<(), SolveError> {
        let (ctx, loops) = (self.ctx, self.ctx.loops);
        // The loop's own measure, for the message at its cap.
        let mut last_change = f64::NAN;
        let mut stalls = 0;
        // Intermediate passes end their Newton loops provisionally (one solve a pass where
        // the statuses settle, [`Newton::allow_provisional`]) while the fixed point
        // contracts, in the first half of the cap. Without friction the first pass is the
        // answer (no threshold to confirm it on): its Newton loop runs to the end.
        let mut provisional = loops.provisional_passes && self.has_friction();
        for fp in 1..=loops.max_friction {
            rep.friction = fp;
            provisional &= 2 * fp <= loops.max_friction;
            self.newton.allow_provisional(provisional);
            self.active_set_loop(rep, fp)?;
            if !self.has_friction() {
                return Ok(());
            }
            // The bonded pass's stuck statuses are released for the thresholds' passes.
            if self.bonded && fp == 1 {
                for s in self.state.iter_mut() {
                    s.lock = None;
                }
            }
            let unconfirmed = self.newton.unconfirmed();
            let frozen: Vec<f64> =
                if unconfirmed { self.state.iter().map(|s| s.lam_bar).collect() } else { Vec::new() };
            let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
            let mut change = update_thresholds(ctx.points, self.state, &vals);
            // A fixed point that stopped contracting near the answer: the accepted
            // stick/slip statuses of a point or two at the Coulomb limit alternate between
            // passes (seen at the reversals of fretting loads), and the thresholds with them.
            stalls = if fp >= 3 && change >= STALL_RATIO * last_change { stalls + 1 } else { 0 };
            provisional &= stalls == 0;
            if contact_log() {
                eprintln!("friction {fp}: threshold change {change:.2e}");
            }
            // The thresholds are the λ of the pass: their change is measured down to λ's
            // round-off in the model's scales (Newton::lambda_roundoff), not below.
            let tol = loops.tol_friction.max(self.newton.lambda_roundoff());
            let accept = |change: f64, stalls: usize| {
                change <= tol || (stalls >= 2 && change <= STALL_ACCEPT * loops.tol_friction)
            };
            if unconfirmed && accept(change, stalls) {
                // The last pass ended provisionally: it is solved again on its own
                // thresholds to the Newton tolerance, and the thresholds updated from that
                // solution decide.
                for (s, &l) in self.state.iter_mut().zip(&frozen) {
                    s.lam_bar = l;
                }
                provisional = false;
                self.newton.allow_provisional(false);
                self.active_set_loop(rep, fp)?;
                let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
                change = update_thresholds(ctx.points, self.state, &vals);
                if !(fp >= 3 && change >= STALL_RATIO * last_change) {
                    stalls = 0;
                }
                if contact_log() {
                    eprintln!("friction {fp}: confirmed, threshold change {change:.2e}");
                }
            }
            if change > CARRY_CYCLE_BELOW {
                self.carried_cycle = None;
            }
            last_change = change;
            if change <= loops.tol_friction.max(self.newton.lambda_roundoff()) {
                return Ok(());
            }
            if stalls >= 2 && change <= STALL_ACCEPT * loops.tol_friction {
                rep.friction_stalled = Some(change);
                return Ok(());
            }
        }
        Err(SolveError::Contact {
            step: ctx.step,
            loop_name: "friction threshold",
            iterations: loops.max_friction,
            residual: last_change,
        })
    }

    /// Active set ⊃ Newton: the contact statuses from the law after each Newton loop,
    /// until none changes and the frozen friction statuses agree with the law, at most
    /// `max_active_set` times. A cycle (a few points flipping between open and closed,
    /// each status violating the weak law at the other; period 2, or longer: the update
    /// returns to the statuses of any earlier iteration) is closed once: the flipping
    /// points are kept in contact for the rest of the step, solved once more and accepted
    /// with the statuses that solution was computed with. The same stick/slip disagreement
    /// in two iterations running, with the contact statuses settled, is accepted too, and
    /// so is, in a pass's first iteration, the disagreement of the cycle the previous pass
    /// accepted that way ([`CarriedCycle`], held at its statuses once found again). A
    /// singular first solve of the step, where it starts open or without friction, is
    /// redone once closed and (with friction) bonded ([`Loops::retry_closed`]).
    fn active_set_loop(&mut self, rep: &mut ContactReport, fp: usize) -> Result<(), SolveError> {
        let (ctx, loops) = (self.ctx, self.ctx.loops);
        // Contact statuses before each earlier update of this loop, to detect a cycle.
        let mut earlier: Vec<Vec<bool>> = Vec::new();
        let mut cycle_closed = false;
        // Points whose frozen stick/slip status disagreed with the law, last iteration.
        let mut prev_disagree: Vec<bool> = Vec::new();
        // And the iteration before it: the disagreements can alternate between two sets.
        let mut prev2_disagree: Vec<bool> = Vec::new();
        // The frozen stick/slip statuses the last iteration's Newton loop ended with.
        let mut prev_locks: Vec<Option<bool>> = Vec::new();
        // Every earlier iteration's disagreements (the damped redo accepts any period).
        let mut earlier_disagree: Vec<Vec<bool>> = Vec::new();
        // The loop's own measure, for the message at its cap: the contact statuses that
        // changed and the stick/slip disagreements of the last iteration.
        let mut flips = 0usize;
        let bonded_pass = self.bonded && fp == 1;
        // The cycle the last pass accepted: its points held at their accepted statuses for
        // the first iteration ([`CarriedCycle`]).
        let carried = self.carried_cycle.take();
        if let Some(c) = carried.as_ref().filter(|c| c.confirmed) {
            for (s, l) in self.state.iter_mut().zip(&c.locks) {
                if l.is_some() {
                    s.lock = *l;
                }
            }
            if contact_log() {
                eprintln!(
                    "active set: {} points of the last pass's accepted cycle held at their statuses",
                    c.members.iter().filter(|&&d| d).count()
                );
            }
        }
        for asi in 1..=loops.max_active_set {
            rep.active_set += 1;
            // The stick predictor starts the first pass with friction (far from the
            // answer: pass 1, or pass 2 after a frictionless first pass); later passes and
            // iterations start from the statuses they inherit.
            // Not with a kept whole-system factor in 3D (`faer/kept.rs`): the flip of every
            // point from the predictor's stick to slip is a change of every friction row
            // that the kept factor's GMRES does not follow (150 iterations, not converged,
            // on the sliding penny), one more factorisation of the whole system; the pass
            // starts from the statuses the law gives at the iterate instead.
            let kept_3d = ctx.points.dim == 3 && self.solver.keeps_factor();
            let predict = asi == 1 && fp <= 2 && !ctx.warm && !bonded_pass && !self.predicted && !kept_3d;
            self.predicted |= predict && self.state.iter().any(|s| s.lam_bar != 0.0);
            // The first pass must not be singular for want of contact or friction that is
            // not active yet. A pass that starts open (`start_closed = false`) leaves a
            // part held only through the crack free, and a pass without friction (every
            // threshold 0) one held sideways only by friction.
            let frictionless = self.has_friction() && self.state.iter().all(|s| s.lam_bar == 0.0);
            let some_open = self.state.iter().any(|s| !s.contact);
            let retry = fp == 1 && !self.bonded && !self.retried && (frictionless || some_open);
            // Until a contact cycle is closed, an iteration whose contact statuses change is
            // not accepted: its Newton loop may end on frozen statuses once the update is
            // known (`Newton::allow_contact_change_end`).
            self.newton.allow_contact_change_end(if cycle_closed { None } else { Some(&self.sticky) });
            let mut result = self.newton(rep, loops.max_newton, predict);
            // A bisected set that leaves a body free: the update's own set instead.
            if let (Err(SolveError::Linear { .. }), Some(g)) = (&result, self.gap.as_mut()) {
                if let Some(set) = g.fallback.take() {
                    g.done = true;
                    for (s, c) in self.state.iter_mut().zip(set) {
                        s.contact = c;
                    }
                    if contact_log() {
                        eprintln!("active set {asi}: the bisected set is singular: the update's set instead");
                    }
                    self.newton.forget_factor();
                    result = self.newton(rep, loops.max_newton, predict);
                }
            }
            if let Some(g) = self.gap.as_mut() {
                g.fallback = None;
            }
            let converged = match result {
                Err(SolveError::Linear { error, .. }) if retry => {
                    if contact_log() {
                        eprintln!("active set {asi}: the linear solve failed ({error}): every point closed");
                    }
                    self.retry_closed(rep, frictionless)?
                }
                r => r?,
            };
            if !converged {
                return Err(SolveError::Contact {
                    step: ctx.step,
                    loop_name: "Newton",
                    iterations: loops.max_newton,
                    residual: rep.residual,
                });
            }
            let bonded_pass = self.bonded && fp == 1;
            // The loop ended before converging, at a contact-status change: its stick/slip
            // disagreements are not those of a converged iterate, and no later iteration
            // compares its own with them (`repeated`).
            let unconverged = self.newton.ended_at_contact_change();
            let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
            let locks: Vec<Option<bool>> = self.state.iter().map(|s| s.lock).collect();
            // The statuses this solution was computed with (the frozen ones included).
            let ended = if self.has_friction() { statuses(ctx.points, self.state, &vals) } else { Vec::new() };
            // The bonded pass keeps its points stuck whatever the law says.
            let disagree = if bonded_pass { Vec::new() } else { frozen_disagreements(ctx.points, self.state, &vals) };
            let friction_disagrees = disagree.contains(&true);
            let before: Vec<bool> = self.state.iter().map(|s| s.contact).collect();
            let mut status_changed = update_contact_status(ctx.points, self.state, &vals);
            if self.sticky.contains(&true) {
                for (s, &k) in self.state.iter_mut().zip(&self.sticky) {
                    s.contact |= k;
                }
                status_changed = self.state.iter().zip(&before).any(|(s, b)| s.contact != *b);
            }
            flips = self.state.iter().zip(&before).filter(|(s, b)| s.contact != **b).count()
                + disagree.iter().filter(|&&d| d).count();
            // The same stick/slip disagreement as in the previous iteration, with the
            // contact statuses settled: those points alternate between stick and slip in
            // every Newton loop, each status violating the law at the other (a packet of
            // the weak law shared with open or sliding neighbours). Another iteration would
            // repeat it: accept the frozen statuses. Likewise when the disagreements
            // alternate between two sets (a 2-cycle of the loop: seen at the reversals of
            // a fretting load, one or two points at the stick/slip boundary).
            //
            // The cycle at this loop's level (the Newton loop went through the very statuses
            // the previous active-set iteration ended with: the 3D Hertz sphere row's
            // 4-periodic cycle of ~72 points) is logged but not accepted: accepted, it ended
            // the first step of a sliding block restarted from frictionless thresholds on
            // |R_x|/R_y = 0.532 for μ = 0.5 (`contact_scales.rs`), a friction law violated
            // with status ok.
            let returned = !status_changed
                && friction_disagrees
                && self.last_ended.as_ref().is_some_and(|e| self.newton.visited(e));
            let repeated = !status_changed
                && friction_disagrees
                && (prev_disagree == disagree
                    || prev2_disagree == disagree
                    || (self.damped && earlier_disagree.contains(&disagree)));
            // The first iteration of a pass that started from the last pass's accepted cycle
            // finds it again: the same points (or some of them) disagreeing at the statuses
            // they were held at ([`CarriedCycle`]).
            let again = asi == 1
                && !status_changed
                && carried.as_ref().is_some_and(|c| c.found_again(&disagree, &locks, self.newton.cyclers()));
            if repeated || again {
                rep.cycles_closed += 1;
            }
            if contact_log() {
                eprintln!(
                    "active set {asi}: contact changed {status_changed}, friction disagrees {friction_disagrees}, {flips} statuses changed"
                );
                log_disagreements(ctx, self.state, &vals, &locks, &prev_locks, &prev_disagree, &prev2_disagree);
                if returned {
                    eprintln!("active set {asi}: the Newton loop returned to the statuses the last iteration ended with (not accepted)");
                }
                if again {
                    eprintln!("active set {asi}: the disagreement of the last pass's accepted cycle again: accepted");
                }
            }
            // Accepted for a repeated stick/slip disagreement: carried to the next pass.
            let carry_next =
                (repeated || again).then(|| CarriedCycle::new(&locks, &disagree, self.newton.cyclers(), again));
            self.last_ended = (!ended.is_empty()).then_some(ended);
            prev_locks = locks;
            if self.damped && !unconverged {
                earlier_disagree.push(disagree.clone());
            }
            prev2_disagree = std::mem::replace(&mut prev_disagree, if unconverged { Vec::new() } else { disagree });
            // Converged: nothing changed; or, once a 2-cycle is closed, no friction status
            // disagrees with the law unless the contact statuses moved too.
            let friction_only = friction_disagrees && !status_changed;
            let accepted =
                !(friction_disagrees || status_changed) || repeated || again || (cycle_closed && !friction_only);
            debug_assert!(!(accepted && unconverged), "a loop ended at a contact change is never accepted");
            if accepted {
                self.carried_cycle = carry_next;
                // The points accepted against the law (the last pass's acceptance is the
                // step's: every pass overwrites it), per crack, for `summary.json`.
                let mut counts = vec![0; ctx.points.cracks.len()];
                for (j, _) in prev_disagree.iter().enumerate().filter(|(_, &d)| d) {
                    counts[ctx.points.points[j].crack] += 1;
                }
                rep.accepted_disagreements = counts;
                // Accepted after a 2-cycle: keep the statuses this solution was computed
                // with (the flipping points closed), so that the thresholds and the next
                // friction pass start from a consistent state.
                if cycle_closed && status_changed {
                    for (s, b) in self.state.iter_mut().zip(&before) {
                        s.contact = *b;
                    }
                }
                return Ok(());
            }
            // A cycle: the update returns to the statuses the iteration before last started
            // from (period 2). Every point closed somewhere in the cycle is kept closed.
            let cycle_start = if status_changed && !cycle_closed {
                let now: Vec<bool> = self.state.iter().map(|s| s.contact).collect();
                earlier.push(before.clone());
                let n = earlier.len();
                // Period 2 only. Longer periods closed once they had run twice (tried: the
                // 2D sliding block at a ρ_n of 4.9e4 E/h then converged) ended the first step
                // of a steel block restarted from a starting threshold far above its pressure
                // on |R_x|/R_y = 0.532 for μ = 0.5, status ok (`contact_scales.rs`): points
                // kept closed in tension. Such a cycle fails the loop instead (loudly, with
                // the ρ_n advice where ρ_n is far above E/h).
                let start = (n >= 2 && earlier[n - 2] == now).then_some(n - 2);
                earlier.pop();
                start
            } else {
                None
            };
            if let Some(i) = cycle_start {
                for (j, (s, k)) in self.state.iter_mut().zip(self.sticky.iter_mut()).enumerate() {
                    let closed = before[j] || earlier[i..].iter().any(|b| b[j]);
                    *k |= closed && !s.contact;
                    s.contact |= closed;
                }
                cycle_closed = true;
                rep.cycles_closed += 1;
            }
            if let Some(g) = self.gap.as_mut().filter(|_| fp == 1 && !cycle_closed && !bonded_pass) {
                let would_close = crate::contact::zone::would_close(ctx.points, &vals);
                if g.step(&before, self.state, &would_close) && contact_log() {
                    eprintln!(
                        "active set {asi}: gap bisection: {} of {} pair points closed (bounds {}..{})",
                        (g.lo + g.hi) / 2,
                        g.order.len(),
                        g.lo,
                        g.hi
                    );
                }
            }
            earlier.push(before);
        }
        Err(SolveError::Contact {
            step: ctx.step,
            loop_name: "active set",
            iterations: loops.max_active_set,
            residual: flips as f64,
        })
    }

    /// After the loops of a first step failed from nonzero starting friction thresholds
    /// (`initial_threshold`): puts the step back at its start with every threshold 0 (the
    /// default start; a singular first solve there is then redone bonded, as for any
    /// frictionless start), for the loops to run again; `err` when there is no such start.
    /// The starting threshold only starts the fixed point, whose answer does not depend on
    /// it; but a start far above the pressures is a fictitious problem that may have no
    /// equilibrium: on a steel block pressed by 1e3 Pa and dragged sideways, a threshold of
    /// 1e5 Pa makes a friction force that tips the block until no contact point holds it
    /// (a singular matrix blamed on the supports), 1e4 Pa one whose active set never
    /// settles, and 1e9 Pa holds it stuck on one corner point, from which the next pass
    /// fails.
    fn restart_frictionless(&mut self, err: SolveError) -> Result<(), SolveError> {
        let Some((state, x, u)) = self.restart.take() else {
            return Err(err);
        };
        if contact_log() {
            eprintln!("the loops from the starting thresholds failed ({err}): redone from thresholds 0");
        }
        for (s, mut s0) in self.state.iter_mut().zip(state) {
            s0.lam_bar = 0.0;
            *s = s0;
        }
        self.x.copy_from_slice(&x);
        self.u.copy_from_slice(&u);
        self.solver.discard_deferred();
        self.newton = Newton::new(self.ctx, self.solver, self.u.len());
        if self.gap.is_some() {
            self.gap = GapBisection::new(self.ctx, self.state, self.u.len());
        }
        self.sticky.fill(false);
        (self.bonded, self.retried, self.predicted) = (false, false, false);
        self.carried_cycle = None;
        Ok(())
    }

    /// The points whose lips touch at the current iterate (status stick or slip: hard
    /// contact, or a crushed asperity layer).
    fn points_in_contact(&self) -> usize {
        let ctx = self.ctx;
        let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
        statuses(ctx.points, self.state, &vals).iter().filter(|s| **s != Status::Open).count()
    }

    /// Why the plain nested loops' outcome `solved` calls for their damped redo
    /// ([`Loops::redo_damped`]), or None: with friction, not redone yet, and either a loop
    /// at its cap (Newton, active set, friction threshold) or stick/slip disagreements
    /// accepted at more than [`DAMPED_REDO_ABOVE`] of the points in contact.
    fn damped_redo_reason(&self, solved: &Result<(), SolveError>, rep: &ContactReport) -> Option<String> {
        if self.damped || !self.has_friction() || self.ctx.loops.algorithm != ContactAlgorithm::Nested {
            return None;
        }
        match solved {
            Err(e @ SolveError::Contact { .. }) => Some(format!("{e}")),
            Err(_) => None,
            Ok(()) => {
                let accepted: usize = rep.accepted_disagreements.iter().sum();
                let closed = self.points_in_contact();
                (accepted as f64 > DAMPED_REDO_ABOVE * closed as f64)
                    .then(|| format!("{accepted} of {closed} points in contact accepted against the friction law"))
            }
        }
    }

    /// Puts the step back at its start (statuses, thresholds, unknowns) for the loops to
    /// run again with damped Newton steps ([`Newton::damp`]), because the plain loops
    /// failed or accepted a large part of the contact zone against the law (`why`). The
    /// Alart–Curnier generalized Newton is only locally convergent: on the 3D Hertz sphere
    /// between dissimilar materials its full steps carry the stuck set of one iterate out
    /// of the Coulomb cone and the sliding set of the next back inside (hundreds of points
    /// in turn), and the loops either run to a cap or freeze a third of the zone against
    /// the law. Converging runs never come here: their answer is unchanged. In the redo an
    /// active-set iteration whose stick/slip disagreement repeats an earlier one's (any
    /// period) accepts it, as the plain loops do for periods 1 and 2.
    fn redo_damped(&mut self, why: &str, rep: &mut ContactReport) {
        if contact_log() {
            eprintln!("the plain contact loops failed ({why}): the step is redone with damped Newton steps");
        }
        let (state, x, u) = &self.start;
        self.state.clone_from_slice(state);
        self.x.copy_from_slice(x);
        self.u.copy_from_slice(u);
        self.solver.discard_deferred();
        let confirm = self.newton.confirms_exact_steps();
        self.newton = Newton::new(self.ctx, self.solver, self.u.len());
        if confirm {
            self.newton.confirm_exact_steps();
        }
        self.newton.damp();
        if self.gap.is_some() || (!self.ctx.warm && self.ctx.u_start.iter().all(|&v| v == 0.0)) {
            self.gap = GapBisection::new(self.ctx, self.state, self.u.len());
        }
        self.sticky.fill(false);
        (self.bonded, self.retried, self.predicted) = (false, false, false);
        self.carried_cycle = None;
        self.last_ended = None;
        self.restart = None;
        self.damped = true;
        rep.friction_stalled = None;
        rep.accepted_disagreements.clear();
        rep.damped_redo = true;
    }

    /// Redoes a singular first solve with every point closed and, when the pass had no
    /// friction threshold yet (`frictionless`), every contact point of a crack with
    /// friction stuck (a bonded pass; the thresholds then come from its pressures).
    fn retry_closed(&mut self, rep: &mut ContactReport, frictionless: bool) -> Result<bool, SolveError> {
        let pts = self.ctx.points;
        self.retried = true;
        self.bonded = frictionless;
        self.newton.forget_factor();
        for (s, p) in self.state.iter_mut().zip(&pts.points) {
            s.contact = true;
            let law = &pts.cracks[p.crack].law;
            if self.bonded && law.friction > 0.0 {
                // Any nonzero traction scale will do: with every point stuck the solution
                // does not depend on it.
                s.lam_bar = -law.rho_n / law.rho_t;
                s.lock = Some(true);
            }
        }
        self.newton(rep, self.ctx.loops.max_newton, false)
    }

    /// One generalized Newton loop: every iteration a short Newton pass (2 iterations),
    /// then the contact statuses and thresholds from the law; cap
    /// `max_newton · max_active_set`. Statuses still chattering after as many iterations as
    /// the nested Newton allows before its freeze (at the Coulomb tie, where stick and
    /// slip both satisfy the law) are frozen as there, and checked against the law at the
    /// end.
    fn semi_smooth(&mut self, rep: &mut ContactReport) -> Result<(), SolveError> {
        let (ctx, loops) = (self.ctx, self.ctx.loops);
        let has_friction = self.has_friction();
        let cap = loops.max_newton * loops.max_active_set;
        let freeze_at = loops.max_newton / 3 + 1;
        let mut done = false;
        for k in 1..=cap {
            rep.active_set += 1;
            if has_friction && k == freeze_at {
                let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
                freeze_statuses(ctx.points, self.state, &vals);
            }
            // Stick predictor on the first iteration with a friction threshold.
            let predict = !ctx.warm && k > 1 && self.state.iter().any(|p| p.lam_bar != 0.0) && rep.friction == 0;
            let step_small = self.newton(rep, 2, predict)?;
            if predict {
                rep.friction = 1;
            }
            let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
            let changed = update_contact_status(ctx.points, self.state, &vals);
            let tol = loops.tol_friction.max(self.newton.lambda_roundoff());
            let thr_ok = !has_friction || update_thresholds(ctx.points, self.state, &vals) <= tol;
            if contact_log() {
                eprintln!("semi-smooth {k}: small step {step_small}, contact changed {changed}, threshold ok {thr_ok}");
            }
            if step_small && !changed && thr_ok && frozen_statuses_agree(ctx.points, self.state, &vals) {
                done = true;
                break;
            }
        }
        for s in self.state.iter_mut() {
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
        Ok(())
    }

    /// The figures of the converged step.
    fn figures(&self, rep: &mut ContactReport) {
        let ctx = self.ctx;
        let vals = point_values(ctx.model, ctx.points, ctx.pairing, self.state, self.u);
        let st = statuses(ctx.points, self.state, &vals);
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
        if contact_log() && rep.slip > 0 && rep.stick > 0 {
            log_stick_slip_zones(ctx, self.state, &vals, &st);
        }
    }
}

/// The log of the stick/slip disagreements of an active-set iteration
/// (`FISSURE_CONTACT_LOG`): how many, of which frozen status, how many were disagreeing in
/// the last two iterations too, how many frozen statuses differ from the last iteration's,
/// and where the disagreeing points are: their threshold relative to the largest |λ̄| (the
/// edge of the contact zone: near 0), |g_τ| (the Coulomb margin) and the traction by which
/// they miss the law relative to the largest bound, −μλ̄ ||g_τ| − 1| / max(−μλ̄).
#[allow(clippy::too_many_arguments)]
fn log_disagreements(
    ctx: &StepContext<'_, '_>,
    state: &[PointState],
    vals: &[crate::contact::state::PointValues],
    locks: &[Option<bool>],
    prev_locks: &[Option<bool>],
    prev: &[bool],
    prev2: &[bool],
) {
    let pts = ctx.points;
    let frozen = locks.iter().filter(|l| l.is_some()).count();
    let lock_changes = if prev_locks.len() == locks.len() {
        locks.iter().zip(prev_locks).filter(|(a, b)| a != b).count()
    } else {
        locks.len()
    };
    let vals_d: Vec<usize> = (0..pts.points.len())
        .filter(|&k| {
            let law = &pts.cracks[pts.points[k].crack].law;
            if locks[k].is_none() || !law.touches(state[k].contact, vals[k].d_n) || law.friction == 0.0 {
                return false;
            }
            let vt = crate::contact::law::slip_increment(
                pts.dim - 1,
                &pts.points[k].tangents,
                vals[k].jump,
                state[k].prev_jump,
            );
            let base = law.friction_base(vals[k].big_lambda, state[k].big_lambda_start);
            law.sticks(base, vt, state[k].lam_bar, None) != law.sticks(base, vt, state[k].lam_bar, locks[k])
        })
        .collect();
    if vals_d.is_empty() && frozen == 0 {
        return;
    }
    let bound_max = pts
        .points
        .iter()
        .zip(state)
        .map(|(p, s)| -pts.cracks[p.crack].law.friction * s.lam_bar)
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    // Where the points are in the contact zone: the distance from the point of the
    // largest bound over the largest such distance of a point with a bound (r/a of a
    // Hertz contact whose centre is that point: a symmetry model's corner or a full one's
    // middle).
    let bounds: Vec<f64> =
        pts.points.iter().zip(state).map(|(p, s)| -pts.cracks[p.crack].law.friction * s.lam_bar).collect();
    let centre = (0..bounds.len()).max_by(|&a, &b| bounds[a].total_cmp(&bounds[b])).map(|k| pts.points[k].x);
    let dist =
        |k: usize| centre.map_or(0.0, |c| crate::geometry::vec3::norm(crate::geometry::vec3::sub(pts.points[k].x, c)));
    let extent = (0..bounds.len()).filter(|&k| bounds[k] > 0.0).map(dist).fold(0.0f64, f64::max).max(f64::MIN_POSITIVE);
    let mut radius: Vec<f64> = vals_d.iter().map(|&k| dist(k) / extent).collect();
    let (mut rel, mut marg, mut excess) = (Vec::new(), Vec::new(), Vec::new());
    let (mut to_slip, mut to_stick, mut again, mut again2) = (0, 0, 0, 0);
    for &k in &vals_d {
        let (p, st, v) = (&pts.points[k], &state[k], &vals[k]);
        let law = &pts.cracks[p.crack].law;
        let vt = crate::contact::law::slip_increment(pts.dim - 1, &p.tangents, v.jump, st.prev_jump);
        let g = law.friction_indicator(law.friction_base(v.big_lambda, st.big_lambda_start), vt, st.lam_bar).1;
        let bound = -law.friction * st.lam_bar;
        rel.push(bound / bound_max);
        marg.push(g[0].hypot(g[1]) - 1.0);
        excess.push(bound * (g[0].hypot(g[1]) - 1.0).abs() / bound_max);
        if locks[k] == Some(true) {
            to_slip += 1;
        } else {
            to_stick += 1;
        }
        again += usize::from(prev.get(k) == Some(&true));
        again2 += usize::from(prev2.get(k) == Some(&true));
    }
    let q = |v: &mut Vec<f64>| {
        if v.is_empty() {
            return String::from("-");
        }
        v.sort_by(f64::total_cmp);
        format!("{:.2e}/{:.2e}/{:.2e}", v[0], v[v.len() / 2], v[v.len() - 1])
    };
    eprintln!(
        "  frozen {frozen} ({lock_changes} differ from the last iteration's); law differs at {} (frozen stick {to_slip}, frozen slip {to_stick}; {again} of them last iteration, {again2} the one before); r/a min/med/max {}; bound/max min/med/max {}; |g|-1 {}; traction miss/max bound {}",
        vals_d.len(),
        q(&mut radius),
        q(&mut rel),
        q(&mut marg),
        q(&mut excess)
    );
}

/// The log of where the converged stick and slip points are (`FISSURE_CONTACT_LOG`): per
/// status the quantiles of r/a (the distance from the point of the largest pressure over
/// the largest such distance of a point in contact) and of λ/λ_min (the pressure over the
/// largest), and the tangential traction over its bound |Λ| of the sliding points.
fn log_stick_slip_zones(
    ctx: &StepContext<'_, '_>,
    state: &[PointState],
    vals: &[crate::contact::state::PointValues],
    st: &[Status],
) {
    use crate::geometry::vec3::{norm, sub};
    let pts = ctx.points;
    let Some(centre) = (0..vals.len()).min_by(|&a, &b| vals[a].lambda.total_cmp(&vals[b].lambda)) else { return };
    let (c, l_min) = (pts.points[centre].x, vals[centre].lambda.min(-f64::MIN_POSITIVE));
    let r = |k: usize| norm(sub(pts.points[k].x, c));
    let a = (0..st.len()).filter(|&k| st[k] != Status::Open).map(r).fold(0.0f64, f64::max).max(f64::MIN_POSITIVE);
    let q = |mut v: Vec<f64>| {
        if v.is_empty() {
            return String::from("-");
        }
        v.sort_by(f64::total_cmp);
        let at = |f: f64| v[((v.len() - 1) as f64 * f) as usize];
        format!("{:.3}/{:.3}/{:.3}/{:.3}/{:.3}", at(0.0), at(0.1), at(0.5), at(0.9), at(1.0))
    };
    for status in [Status::Stick, Status::Slip] {
        let ks: Vec<usize> = (0..st.len()).filter(|&k| st[k] == status).collect();
        let lam_bar: Vec<f64> = ks.iter().map(|&k| state[k].lam_bar / l_min).collect();
        eprintln!(
            "{:?} {}: r/a min/10%/med/90%/max {}; λ/λ_min {}; λ̄/λ_min {}; |Λ| {}",
            status,
            ks.len(),
            q(ks.iter().map(|&k| r(k) / a).collect()),
            q(ks.iter().map(|&k| vals[k].lambda / l_min).collect()),
            q(lam_bar),
            q(ks.iter().map(|&k| vals[k].big_lambda[0].hypot(vals[k].big_lambda[1])).collect()),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::CarriedCycle;

    /// The carried cycle of the friction passes (`Loops::active_set_loop`): points 1 and 3
    /// disagreed, frozen slip and stick. A later pass's first iteration finds it again when
    /// the same points, or some of them, disagree at the same frozen statuses; a point that
    /// was not in the cycle, a cycle point frozen at the other status, or no disagreement
    /// at all is not the cycle (the loop goes on from the law's statuses).
    #[test]
    fn carried_cycle_is_found_again_only_at_its_own_points_and_statuses() {
        let locks = [Some(true), Some(false), Some(true), Some(true)];
        let c = CarriedCycle::new(&locks, &[false, true, false, true], &[], false);
        assert_eq!(c.locks, vec![None, Some(false), None, Some(true)]);
        let none: [bool; 0] = [];
        assert!(c.found_again(&[false, true, false, true], &locks, &none), "the same points");
        assert!(c.found_again(&[false, false, false, true], &locks, &none), "some of them");
        assert!(!c.found_again(&[true, true, false, true], &locks, &none), "a point outside the cycle");
        let flipped = [Some(true), Some(true), Some(true), Some(true)];
        assert!(!c.found_again(&[false, true, false, false], &flipped, &none), "a cycle point at the other status");
        assert!(!c.found_again(&[false; 4], &locks, &none), "no disagreement");
        assert!(!c.found_again(&[false, true], &locks[..2], &none), "another point set");
        // Point 2 flipped in this loop's own status cycle and was frozen sliding: part of it.
        let slid = [Some(true), Some(false), Some(false), Some(true)];
        let cyclers = [false, false, true, false];
        assert!(c.found_again(&[false, true, true, true], &slid, &cyclers), "with this loop's cycle");
        assert!(!c.found_again(&[false, true, true, true], &locks, &cyclers), "a cycler not sliding");
        assert!(!c.found_again(&[true, true, true, true], &slid, &cyclers), "and a point of neither");
        // The points of the accepted iteration's own Newton cycle are members too (held).
        let d = CarriedCycle::new(&slid, &[false, true, false, false], &cyclers, true);
        assert_eq!(d.locks, vec![None, Some(false), Some(false), None]);
        assert!(d.found_again(&[false, false, true, false], &slid, &none), "a cycler of the accepted iteration");
    }
}
