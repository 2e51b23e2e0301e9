//! The quasi-static load-step driver for linear elasticity, shaped for the nested
//! nonlinear loops of contact (geometry ⊃ friction threshold ⊃ active set ⊃ Newton):
//! one layout (pattern) per model, one symbolic factorisation, and per step a refill
//! of the values only when they change.
//!
//! Entry point: [`solve_load_steps`].
//!
//! ```text
//! layout (pattern, colouring) ─► symbolic factorisation
//! assemble K ─► numeric factorisation          (K does not depend on the load factor)
//! for each load step t:  assemble f(t) ─► solve ─► residual check ─► reactions ─► callback
//! ```

use crate::assembly::LocalOut;
use crate::assembly::{DofKind, DofMap, Kernel, SystemLayout, NO_EQ};
use crate::contact::kernel::ContactKernel;
use crate::contact::law::PointState;
use crate::contact::pairing::{pair, Pairing, PairingOptions};
use crate::contact::ContactSetup;
use crate::physics::constraints::check_rigid_modes_with;
use crate::physics::elasticity::{BulkKernel, DirichletMultiplierKernel, TractionKernel};
use crate::physics::model::{DirichletMethod, Model};
use crate::physics::relations::{self, ConstraintKernel, RelationKernel};
use crate::physics::xfem::{CrackPressureKernel, XfemBulkKernel};
use crate::solve::contact::{contact_step, ContactReport, StepContext};
use crate::solve::linear::{LinearError, LinearMethod, LinearSolver};
use crate::solve::observe::{Phase, Silent, SolveObserver};
use crate::solve::ordering::{EquationPoints, NO_POINT};
use std::fmt;
use std::time::Instant;

/// Options of the solve.
#[derive(Debug, Clone, Copy)]
pub struct SolveOptions {
    pub linear: LinearMethod,
    /// Relative residual above which a step is reported as failed.
    pub residual_tolerance: f64,
    /// Contact systems (LDLᵀ): factorise the bulk once and condense each contact
    /// iteration onto the crack unknowns ([`LinearSolver::analyse_condensed`]).
    pub condense: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions { linear: LinearMethod::Cholesky, residual_tolerance: 1e-8, condense: true }
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
    /// The contact factor was condensed onto the crack unknowns
    /// ([`LinearSolver::analyse_condensed`]).
    pub condensed: bool,
    pub n_colors: usize,
    pub heaviside_nodes: usize,
    pub tip_nodes: usize,
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
    /// A contact loop reached its cap without converging.
    Contact { step: usize, loop_name: &'static str, iterations: usize, residual: f64 },
    /// The per-step callback (output) failed.
    Callback(String),
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
            SolveError::Contact { step, loop_name, iterations, residual } => write!(
                f,
                "step {step}: the {loop_name} loop did not converge in {iterations} iterations (last relative correction {residual:.2e}); raise its cap in [contact_solver], or use smaller load steps"
            ),
            SolveError::Callback(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for SolveError {}

/// Solves every load step of `model`, calling `on_step` after each (for output).
pub fn solve_load_steps(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    solve_load_steps_observed(model, contact, options, &Silent, on_step)
}

/// [`solve_load_steps`], telling `observer` the phases and the contact Newton iterations.
pub fn solve_load_steps_observed(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let mut timings = Timings::default();

    // Constrained dofs: the last condition on a dof wins.
    let mut dofs = model.enrichment.dofs.clone();
    let n_std = dim * mesh.n_nodes();
    if let Some(c) = contact {
        let start = dofs.push_block(DofKind::ContactMultiplier, c.points.n_unknowns);
        debug_assert_eq!(start, model.enrichment.dofs.n_total());
    }
    let mut cond_of_dof = vec![u32::MAX; n_std];
    for (k, c) in model.dirichlet.iter().enumerate() {
        cond_of_dof[dofs.node_dof(c.node, c.component)] = k as u32;
    }
    let constrained: Vec<usize> = (0..n_std).filter(|&d| cond_of_dof[d] != u32::MAX).collect();
    let pairs: Vec<(usize, usize)> = constrained.iter().map(|&d| (d / dim, d % dim)).collect();
    let tied = relations::rigid_rows(&model.relations, dim, n_std);
    check_rigid_modes_with(mesh, &pairs, &tied).map_err(SolveError::UnderConstrained)?;

    let (mut eliminated, mult_rows) = match model.dirichlet_method {
        DirichletMethod::Eliminate => {
            let mut e = vec![false; dofs.n_total()];
            for &d in &constrained {
                e[d] = true;
            }
            (e, vec![])
        }
        DirichletMethod::Multiplier => {
            let start = dofs.push_block(DofKind::DirichletMultiplier, constrained.len());
            let rows: Vec<(u32, u32)> =
                constrained.iter().enumerate().map(|(k, &d)| (d as u32, (start + k) as u32)).collect();
            (vec![false; dofs.n_total()], rows)
        }
    };
    // Linear relations (physics/relations.rs): one multiplier each, after the Dirichlet ones.
    let rel_first = dofs.push_block(DofKind::DirichletMultiplier, model.relations.len());
    eliminated.resize(dofs.n_total(), false);
    let n_total = dofs.n_total();
    let saddle = model.dirichlet_method == DirichletMethod::Multiplier || !model.relations.is_empty();
    let linear = match (saddle, contact.is_some(), options.linear) {
        (true, _, LinearMethod::Cholesky) | (_, true, LinearMethod::Cholesky) => LinearMethod::Ldlt,
        (_, _, m) => m,
    };
    // Per contact point: statuses, thresholds, jump at the start of the step.
    let mut state: Vec<PointState> = contact
        .map(|c| {
            c.points
                .points
                .iter()
                .map(|p| {
                    let cc = &c.points.cracks[p.crack];
                    PointState {
                        contact: cc.start_closed,
                        lam_bar: -cc.initial_threshold,
                        prev_jump: [0.0; 3],
                        lock: None,
                    }
                })
                .collect()
        })
        .unwrap_or_default();

    let mut mult_values = vec![0.0; mult_rows.len()];
    let enriched = model.enrichment.dofs.n_total() > n_std;
    let pressure_facets: Vec<(u16, u32)> = model
        .cracks
        .iter()
        .enumerate()
        .filter(|(k, _)| model.crack_pressure.get(*k).is_some_and(|p| p.is_some()))
        .flat_map(|(k, c)| (0..c.cut.facets.len()).map(move |f| (k as u16, f as u32)))
        .collect();
    let make_kernels = |t: f64| {
        let bulk = if enriched {
            Bulk::Xfem(XfemBulkKernel {
                mesh,
                enrichment: &model.enrichment,
                cracks: &model.cracks,
                analysis: model.analysis,
                cell_material: &model.cell_material,
                materials: &model.materials,
                cell_body_force: &model.cell_body_force,
                body_forces: &model.body_forces,
                quadrature: model.xfem_quadrature,
                t,
            })
        } else {
            Bulk::Plain(BulkKernel {
                mesh,
                dofs: &dofs,
                analysis: model.analysis,
                cell_material: &model.cell_material,
                materials: &model.materials,
                cell_body_force: &model.cell_body_force,
                body_forces: &model.body_forces,
                t,
            })
        };
        let traction = TractionKernel {
            mesh,
            dofs: &dofs,
            faces: &model.faces,
            face_load: &model.face_load,
            loads: &model.loads,
            t,
        };
        let pressure = CrackPressureKernel {
            mesh,
            enrichment: &model.enrichment,
            cracks: &model.cracks,
            facets: &pressure_facets,
            pressure: &model.crack_pressure,
            t,
        };
        (bulk, traction, pressure)
    };

    let zero_u = vec![0.0; n_total];
    // Large sliding: the pairing in the undeformed configuration to start with.
    let large = contact.is_some_and(|c| c.points.cracks.iter().any(|cc| cc.large_sliding));
    let pairing_opts = PairingOptions::default();
    let pair_with = |u: &[f64]| {
        let c = contact.expect("large sliding has contact");
        pair(mesh, &model.enrichment, &model.cracks, &c.points, u, &pairing_opts)
    };
    let mut pairing: Option<Pairing> = large.then(|| pair_with(&zero_u));
    let mult_zero = vec![0.0; mult_rows.len()];
    let build_layout = |pairing: Option<&Pairing>, state: &[PointState]| {
        let (bulk, traction, pressure) = make_kernels(1.0);
        let mk = ConstraintKernel {
            dirichlet: DirichletMultiplierKernel { rows: &mult_rows, values: &mult_zero },
            relations: RelationKernel { relations: &model.relations, first: rel_first as u32, t: 1.0 },
        };
        let ck = contact.map(|c| ContactKernel {
            mesh,
            enrichment: &model.enrichment,
            cracks: &model.cracks,
            points: &c.points,
            state,
            u: &zero_u,
            pairing,
        });
        let mut kernels: Vec<&dyn Kernel> = vec![&bulk, &traction, &pressure, &mk];
        if let Some(ck) = &ck {
            kernels.push(ck);
        }
        SystemLayout::build(n_total, dofs.n_primal(), &eliminated, &kernels)
    };
    observer.phase(Phase::Pattern { equations: n_total });
    let clock = Instant::now();
    let mut layout = build_layout(pairing.as_ref(), &state);
    timings.pattern = clock.elapsed().as_secs_f64();

    // The symbolic analysis of a layout: with the node of every primal equation (for the
    // nested-dissection ordering), condensed onto the crack unknowns for contact.
    let dof_nodes = model.enrichment.dof_nodes();
    let analyse = |layout: &SystemLayout, step: usize| {
        let mut point_of_eq = vec![NO_POINT; layout.n_eq];
        for (d, &q) in layout.eq_of_dof.iter().enumerate() {
            if q != NO_EQ && d < dof_nodes.len() {
                point_of_eq[q as usize] = dof_nodes[d];
            }
        }
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &mesh.nodes, dim };
        let (pattern, n_primal) = (&layout.pattern, layout.n_primal_eq);
        observer.phase(Phase::Symbolic { equations: layout.n_eq, nnz_matrix: pattern.nnz() });
        if contact.is_some() && options.condense {
            // In small sliding the contact terms involve only the enriched dofs (the jump of
            // a standard shape function is zero): the standard dofs stay in the bulk.
            let mut varying = vec![large; n_primal];
            for (d, &q) in layout.eq_of_dof.iter().enumerate() {
                if q != NO_EQ && (q as usize) < n_primal && d >= n_std {
                    varying[q as usize] = true;
                }
            }
            LinearSolver::analyse_condensed(linear, pattern, n_primal, Some(&points), Some(&varying))
        } else {
            LinearSolver::analyse_with_points(linear, pattern, n_primal, Some(&points))
        }
        .map_err(|error| SolveError::Linear { step, error, advice: "" })
    };
    let mut solver = {
        let clock = Instant::now();
        let s = analyse(&layout, 0)?;
        timings.symbolic = clock.elapsed().as_secs_f64();
        s
    };

    let mut values = vec![0.0; layout.pattern.nnz()];
    let mut rhs = vec![0.0; layout.n_eq];
    let mut u = vec![0.0; n_total];
    let mut x = vec![0.0; layout.n_eq];
    let mut prescribed = vec![0.0; n_total];
    let mut steps = vec![];
    let mut factorized = false;
    let fixed_mask = [true, true, true, true, false];
    let mut is_constrained = vec![false; n_total];
    for &d in &constrained {
        is_constrained[d] = true;
    }
    for (si, &t) in model.load_factors.iter().enumerate() {
        let step = si + 1;
        observer.phase(Phase::Step { index: step, total: model.load_factors.len() });
        // Prescribed values at this load factor.
        for &d in &constrained {
            let c = &model.dirichlet[cond_of_dof[d] as usize];
            let v = c.value.eval_load(mesh.nodes[c.node], t);
            if !v.is_finite() {
                return Err(SolveError::NonFinite {
                    what: format!(
                        "the Dirichlet value on group '{}' at node {}",
                        model.dirichlet_groups[c.group as usize], c.node
                    ),
                });
            }
            prescribed[d] = v;
        }
        for (k, &(d, _)) in mult_rows.iter().enumerate() {
            mult_values[k] = prescribed[d as usize];
        }
        let (bulk, traction, pressure) = make_kernels(t);
        let mk = ConstraintKernel {
            dirichlet: DirichletMultiplierKernel { rows: &mult_rows, values: &mult_values },
            relations: RelationKernel { relations: &model.relations, first: rel_first as u32, t },
        };
        let fixed: [&dyn Kernel; 4] = [&bulk, &traction, &pressure, &mk];
        let mut factorizations = 0;
        let mut linear_solves = 1;
        let residual;
        let mut contact_report = None;

        if let Some(c) = contact {
            // K once (again after a pattern rebuild); the load vector each step; then the
            // contact loops, inside the geometry loop when a crack slides large.
            let u_start = u.clone();
            for &d in &constrained {
                if layout.eq_of_dof[d] == NO_EQ {
                    u[d] = prescribed[d];
                }
            }
            let loops = &c.loops;
            let h_geo = c
                .points
                .cracks
                .iter()
                .filter(|cc| cc.large_sliding)
                .map(|cc| cc.cell_size)
                .fold(f64::INFINITY, f64::min);
            let mut total: Option<ContactReport> = None;
            let mut rhs_ready = false;
            let mut geometry = 0;
            let mut rebuilds = 0;
            loop {
                geometry += 1;
                if large {
                    observer.phase(Phase::Pairing { step });
                    let clock = Instant::now();
                    let new = pair_with(&u);
                    timings.pairing += clock.elapsed().as_secs_f64();
                    let old = pairing.as_ref().expect("a pairing");
                    if geometry > 1 {
                        let (moved, flipped) = new.change_from(old);
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
                    if new.facet_masters != old.facet_masters {
                        // The pairing couples other cells: new pattern, new symbolic analysis.
                        let clock = Instant::now();
                        layout = build_layout(Some(&new), &state);
                        timings.pattern += clock.elapsed().as_secs_f64();
                        let clock = Instant::now();
                        solver = analyse(&layout, step)?;
                        timings.symbolic += clock.elapsed().as_secs_f64();
                        values = vec![0.0; layout.pattern.nnz()];
                        factorized = false;
                        rhs_ready = false;
                        rebuilds += 1;
                    }
                    for (st, p) in state.iter_mut().zip(&new.points) {
                        if !matches!(p, crate::contact::pairing::PointPairing::Paired(_)) {
                            st.contact = false;
                            st.lock = None;
                        }
                    }
                    pairing = Some(new);
                }
                let ck = ContactKernel {
                    mesh,
                    enrichment: &model.enrichment,
                    cracks: &model.cracks,
                    points: &c.points,
                    state: &state,
                    u: &zero_u,
                    pairing: pairing.as_ref(),
                };
                let all: [&dyn Kernel; 5] = [&bulk, &traction, &pressure, &mk, &ck];
                let clock = Instant::now();
                if !factorized {
                    layout.assemble_kernels(&all, &fixed_mask, &prescribed, Some(&mut values), Some(&mut rhs), false);
                    factorized = true;
                    rhs_ready = true;
                } else if !rhs_ready {
                    layout.assemble_kernels(&all, &fixed_mask, &prescribed, None, Some(&mut rhs), false);
                    rhs_ready = true;
                }
                timings.assembly += clock.elapsed().as_secs_f64();
                if let Some(bad) = rhs.iter().position(|v| !v.is_finite()) {
                    return Err(SolveError::NonFinite {
                        what: format!("the load vector (equation {bad}) at step {step}"),
                    });
                }
                for d in 0..n_total {
                    let q = layout.eq_of_dof[d];
                    if q != crate::assembly::NO_EQ {
                        x[q as usize] = u[d];
                    }
                }
                let ctx = StepContext {
                    model,
                    points: &c.points,
                    loops,
                    layout: &layout,
                    fixed: &fixed,
                    rhs_f: &rhs,
                    step,
                    pairing: pairing.as_ref(),
                    u_start: &u_start,
                    warm: geometry > 1,
                    observer,
                };
                observer.phase(Phase::ContactLoops { step, geometry });
                let rep = contact_step(&ctx, &mut solver, &mut x, &mut u, &mut state, &mut timings, &mut values)?;
                total = Some(match total {
                    None => rep,
                    Some(t) => ContactReport {
                        friction: t.friction + rep.friction,
                        active_set: t.active_set + rep.active_set,
                        newton: t.newton + rep.newton,
                        factorizations: t.factorizations + rep.factorizations,
                        linear_solves: t.linear_solves + rep.linear_solves,
                        ..rep
                    },
                });
                if !large {
                    break;
                }
            }
            let mut rep = total.expect("one contact pass");
            if large {
                rep.geometry = geometry - 1;
                rep.pattern_rebuilds = rebuilds;
                rep.pairing = pairing.as_ref().map(|p| p.counts);
            }
            factorizations = rep.factorizations;
            linear_solves = rep.linear_solves;
            residual = rep.residual;
            contact_report = Some(rep);
        } else {
            let clock = Instant::now();
            if !factorized {
                layout.assemble(&fixed, &prescribed, Some(&mut values), Some(&mut rhs));
                timings.assembly += clock.elapsed().as_secs_f64();
                observer.phase(Phase::Factorisation { step, nnz_factor: solver.stats().nnz_factor });
                let clock = Instant::now();
                solver.factorize(&values).map_err(|error| SolveError::Linear {
                    step,
                    error,
                    advice: "; check that the Dirichlet conditions hold every part of the body and that the materials are valid",
                })?;
                timings.numeric += clock.elapsed().as_secs_f64();
                factorized = true;
                factorizations = 1;
            } else {
                layout.assemble(&fixed, &prescribed, None, Some(&mut rhs));
                timings.assembly += clock.elapsed().as_secs_f64();
            }
            if let Some(bad) = rhs.iter().position(|v| !v.is_finite()) {
                return Err(SolveError::NonFinite { what: format!("the load vector (equation {bad}) at step {step}") });
            }
            let clock = Instant::now();
            x.copy_from_slice(&rhs);
            solver.solve_in_place(&mut x).map_err(|error| SolveError::Linear { step, error, advice: "" })?;
            timings.solve += clock.elapsed().as_secs_f64();
            residual = solver.last_residual().0;
            if !(residual <= options.residual_tolerance) {
                return Err(SolveError::Residual { step, residual, tolerance: options.residual_tolerance });
            }
            for d in 0..n_total {
                let q = layout.eq_of_dof[d];
                u[d] = if q == NO_EQ { prescribed[d] } else { x[q as usize] };
            }
        }

        // Reactions: bulk, boundary and contact forces on the constrained dofs, per group
        // (only the elements that touch a constrained dof are computed).
        let forces = match contact {
            Some(c) => {
                let ck = ContactKernel {
                    mesh,
                    enrichment: &model.enrichment,
                    cracks: &model.cracks,
                    points: &c.points,
                    state: &state,
                    u: &u,
                    pairing: pairing.as_ref(),
                };
                let all: [&dyn Kernel; 5] = [&bulk, &traction, &pressure, &mk, &ck];
                layout.element_forces_touching(&all, &[true, true, true, false, true], Some(&is_constrained), &u)
            }
            None => layout.element_forces_touching(&fixed, &[true, true, true, false], Some(&is_constrained), &u),
        };
        let mut reactions = vec![[0.0; 3]; model.dirichlet_groups.len()];
        for &d in &constrained {
            let g = model.dirichlet[cond_of_dof[d] as usize].group as usize;
            reactions[g][d % dim] += forces[d];
        }
        let support = |d: usize| {
            (d < n_std && cond_of_dof[d] != u32::MAX).then(|| model.dirichlet[cond_of_dof[d] as usize].group as usize)
        };
        relations::add_reactions(&model.relations, rel_first, &u, dim, &support, &mut reactions);
        let report = StepReport {
            index: step,
            load_factor: t,
            residual,
            linear_solves,
            factorizations,
            reactions,
            contact: contact_report,
        };
        on_step(StepSolution { dofs: &dofs, u: &u, report: &report, contact_state: &state, pairing: pairing.as_ref() })
            .map_err(SolveError::Callback)?;
        steps.push(report);
    }
    let nnz_factor = solver.stats().nnz_factor;
    Ok(SolveReport {
        n_eq: layout.n_eq,
        n_prescribed: constrained.len(),
        nnz_matrix: layout.pattern.nnz(),
        nnz_factor,
        condensed: solver.is_condensed(),
        n_colors: layout.n_colors(),
        heaviside_nodes: model.enrichment.n_heaviside_nodes,
        tip_nodes: model.enrichment.n_tip_nodes,
        steps,
        timings,
        dofs,
        linear_method: linear,
    })
}

/// The bulk kernel of a model: the plain one without cracks, the enriched one with.
enum Bulk<'a> {
    Plain(BulkKernel<'a>),
    Xfem(XfemBulkKernel<'a>),
}

impl Kernel for Bulk<'_> {
    fn n_elements(&self) -> usize {
        match self {
            Bulk::Plain(k) => k.n_elements(),
            Bulk::Xfem(k) => k.n_elements(),
        }
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        match self {
            Bulk::Plain(k) => k.dofs(e, out),
            Bulk::Xfem(k) => k.dofs(e, out),
        }
    }
    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>) {
        match self {
            Bulk::Plain(k) => k.compute(e, dofs, out),
            Bulk::Xfem(k) => k.compute(e, dofs, out),
        }
    }
}
