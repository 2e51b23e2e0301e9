//! The step driver: set up once, then per step prescribe, solve (one linear solve, or the
//! contact loops) and report. Short on purpose: every piece it calls is named.
//!
//! Entry point: [`solve_steps`]. The caller watches the phases and the contact Newton
//! iterations through a [`SolveObserver`].
//!
//! ```text
//! Setup (dofs, constraints, linear method) ─► layout (pattern) ─► symbolic analysis
//!                                              (without contact: ∥ the first step's K and f)
//! for each step of the time scheme:
//!     prescribed values, kernels at t ─► linear_step | solve_contact ─► reactions ─► on_step
//! ```

use super::contact_loops::solve_contact;
use super::newton::contact_log;
use super::newton::linear_step;
use super::observe::{Phase, SolveObserver};
use super::report::{SolveError, SolveOptions, SolveReport, StepReport, StepSolution, Timings};
use super::setup::{Setup, System};
use super::threshold_start::ThresholdStart;
use super::time::TimeScheme;
use crate::assembly::Kernel;
use crate::contact::carry::CarriedStatuses;
use crate::contact::state::{point_values, start_pairs_from_gap};
use crate::contact::ContactSetup;
use crate::physics::model::Model;
use std::time::Instant;

/// Solves every step of `model` under `scheme`, calling `on_step` after each (for output).
/// An implicit dynamic scheme runs the time-step driver ([`super::dynamics`]) from rest.
pub fn solve_steps(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    scheme: TimeScheme,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    solve_steps_carrying(model, contact, options, scheme, None, observer, on_step)
}

/// [`solve_steps`], the contact points of the first step starting from the `carried`
/// statuses where they have one ([`CarriedStatuses::apply`]: crack growth, the points of
/// the part of the crack that did not change) instead of the case's default start.
/// Quasi-statics only: dynamics starts from rest.
pub fn solve_steps_carrying(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    scheme: TimeScheme,
    carried: Option<&CarriedStatuses>,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    let implicit: Option<&dyn super::time::ImplicitScheme> = match &scheme {
        TimeScheme::Newmark(n) => Some(n),
        TimeScheme::Theta(t) => Some(t),
        TimeScheme::QuasiStatic => None,
    };
    if let Some(n) = implicit {
        let initial = super::dynamics::InitialState::default();
        return super::dynamics::solve_time_steps(model, contact, options, n, &initial, observer, on_step);
    }
    let setup = Setup::new(model, contact, options)?;
    let mut timings = Timings::default();
    let n_total = setup.dofs.n_total();
    let mut state = setup.initial_state();
    // Large sliding: the pairing in the undeformed configuration to start with.
    let mut pairing = setup.large.then(|| setup.pair(&vec![0.0; n_total]));
    // Meshed contact pairs start closed only where the bodies touch (the initial gap).
    if let (Some(c), Some(p)) = (contact, pairing.as_ref()) {
        let vals = point_values(model, &c.points, Some(p), &state, &vec![0.0; n_total]);
        let opened = start_pairs_from_gap(&c.points, &mut state, &vals);
        if opened > 0 && contact_log() {
            eprintln!("start: {opened} points of the contact pairs open (initial gap)");
        }
    }
    if let (Some(c), Some(carried)) = (contact, carried) {
        let n = carried.apply(&c.points, &mut state);
        if contact_log() {
            eprintln!("start: {n} of {} contact points carry their previous statuses", state.len());
        }
    }
    observer.phase(Phase::Pattern { equations: n_total });
    let clock = Instant::now();
    let mut layout = match setup.build_layout_owned(pairing.as_ref(), &state)? {
        Some(layout) => layout,
        None => setup.build_layout(pairing.as_ref(), &state),
    };
    timings.pattern = clock.elapsed().as_secs_f64();
    observer.phase(Phase::Symbolic { equations: layout.n_eq, nnz_matrix: layout.nnz() });
    let (mut u, mut prescribed) = (vec![0.0; n_total], vec![0.0; n_total]);
    let mut mult_values = vec![0.0; setup.mult_rows.len()];
    let times = scheme.steps(model);
    // The first step's K and f do not wait for the symbolic analysis (the ordering and
    // faer's symbolic phase are mostly sequential): both at once, the analysis on one
    // thread and the assembly's colours on the others. With contact, K is the fixed
    // kernels' part only (the contact kernel is in the layout's list but not assembled:
    // the contact loops add its terms in each iteration), as the contact loops would
    // assemble it. `symbolic` is the analysis' own time, `assembly` what the join took
    // beyond it.
    let clock = Instant::now();
    let mut sys = match times.first() {
        Some(first) if !layout.is_distributed() => {
            setup.prescribe(first.t, &mut prescribed, &mut mult_values)?;
            let fixed = setup.kernels(first.t, &mult_values);
            let zero_u = vec![0.0; if contact.is_some() { n_total } else { 0 }];
            let ck = setup.contact_kernel(&state, &zero_u, pairing.as_ref());
            let ((solver, symbolic), (values, rhs)) = rayon::join(
                || {
                    let clock = Instant::now();
                    let solver = setup.analyse(&layout, 0);
                    (solver, clock.elapsed().as_secs_f64())
                },
                || {
                    let mut values = vec![0.0; layout.pattern.nnz()];
                    let mut rhs = vec![0.0; layout.n_eq];
                    let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
                    let mut include = vec![true; kernels.len()];
                    if let Some(ck) = ck.as_ref() {
                        kernels.push(ck);
                        include.push(false);
                    }
                    layout.assemble_kernels(&kernels, &include, &prescribed, Some(&mut values), Some(&mut rhs), false);
                    fixed.add_dof_loads(&layout, &mut rhs);
                    (values, rhs)
                },
            );
            timings.symbolic = symbolic;
            timings.assembly += (clock.elapsed().as_secs_f64() - symbolic).max(0.0);
            System::prefilled(layout, solver?, values, rhs)
        }
        _ => {
            let solver = setup.analyse(&layout, 0)?;
            if let Some(rows) = layout.distributed.as_mut() {
                // The preallocation counts are in PETSc's matrix now.
                (rows.d_nnz, rows.o_nnz) = (Vec::new(), Vec::new());
            }
            timings.symbolic = clock.elapsed().as_secs_f64();
            System::new(layout, solver)
        }
    };
    observer.system(&setup.sizes(&sys));
    let mut steps = vec![];
    let n_steps = times.len();
    let mut threshold_start = contact.and_then(|c| ThresholdStart::new(&c.points));
    for st in times {
        let step = st.index;
        observer.phase(Phase::Step { index: step, total: n_steps });
        setup.prescribe(st.t, &mut prescribed, &mut mult_values)?;
        let fixed = setup.kernels(st.t, &mult_values);
        let (residual, factorizations, linear_solves, contact_report) = if contact.is_some() {
            if let Some(ts) = threshold_start.as_mut() {
                let order = ts.start_step(st.t, &mut state);
                if order > 0 && contact_log() {
                    eprintln!("start: friction thresholds extrapolated (order {order}) from the last steps");
                }
            }
            let rep = solve_contact(
                &setup,
                &mut sys,
                &fixed,
                &prescribed,
                step,
                &mut u,
                &mut state,
                &mut pairing,
                &mut timings,
                observer,
            )
            .map_err(|e| told_failure(observer, &setup, &sys, e))?;
            if let Some(ts) = threshold_start.as_mut() {
                ts.end_step(st.t, &state);
            }
            (rep.residual, rep.factorizations, rep.linear_solves, Some(rep))
        } else {
            let (residual, f) =
                linear_step(&mut sys, &fixed, &prescribed, step, options, &mut u, &mut timings, observer)
                    .map_err(|e| told_failure(observer, &setup, &sys, e))?;
            (residual, f, 1, None)
        };
        let ck = setup.contact_kernel(&state, &u, pairing.as_ref());
        let reactions = setup.reactions(&sys.layout, &fixed, ck.as_ref(), &u);
        let report = StepReport {
            index: step,
            load_factor: st.t,
            residual,
            linear_solves,
            factorizations,
            reactions,
            contact: contact_report,
        };
        let solution = StepSolution {
            dofs: &setup.dofs,
            u: &u,
            report: &report,
            contact_state: &state,
            pairing: pairing.as_ref(),
            motion: None,
        };
        on_step(solution).map_err(SolveError::Callback)?;
        steps.push(report);
    }
    Ok(setup.report(&sys, steps, timings))
}

/// Tells `observer` the system's figures at a failed step (the backend's iterations and
/// memory so far) and hands the error on.
pub(super) fn told_failure(
    observer: &dyn SolveObserver,
    setup: &Setup<'_, '_>,
    sys: &System,
    e: SolveError,
) -> SolveError {
    observer.system(&setup.sizes(sys));
    e
}
