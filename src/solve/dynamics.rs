//! The time-step driver of implicit dynamics (Newmark, HHT-α, the θ-method on velocities):
//! set up once, then per time step predict, solve the effective system (one solve, or the shared contact loops) and
//! update velocities, accelerations and energies.
//!
//! Entry point: [`solve_time_steps`].
//!
//! ```text
//! Setup (dofs, constraints, linear method) ─► element K and M (once) ─► a₀ from M a₀ = f₀ − K u₀
//! ─► layout ─► symbolic analysis
//! for each time step t_{n+1} = (n + 1) Δt:
//!     predictor ũ = u_n + Δt v_n + Δt² β_n a_n   (Newmark: β_n = ½ − β; θ: β_n = θ (1 − θ))
//!     prescribed values at t_{n+1}, effective kernels (loads at t_{n+1} − α Δt)
//!     ─► linear_step | solve_contact  (effective matrix factorised once while nothing changes)
//!     a_{n+1} = (u_{n+1} − ũ) / (β Δt²), v_{n+1} = v_n + Δt ((1 − γ) a_n + γ a_{n+1})
//!     where velocity-law lips overlap: u_{n+1} += Δu (super::position_correction), v, a kept
//!     energies ─► on_step
//! ```
//!
//! The mass is the consistent one or, with `options.mass`, the redistributed one whose
//! Heaviside dofs of the cut cells carry none ([`crate::physics::inertia::MassMatrix`]): the
//! loops are the same, only the element mass matrices differ.
//! Every scheme enters through [`ImplicitScheme::coefficients`] (the generalized Newmark
//! form of [`super::time::StepCoefficients`]; the θ-method is β = θ², γ = θ).
//! The effective matrix (1 − α) K + M / (β Δt²) is assembled and factorised on the first
//! step and kept (linear case: one factorisation for the whole run; with contact, the
//! contact tangent's factor is carried from step to step, [`super::setup::CarriedFactor`],
//! and recomputed only when a status or threshold changes); later steps assemble
//! the load vector only: the inertia predictor and HHT's −α K u_n as two sparse mat-vecs
//! of K and M assembled once on every dof ([`crate::physics::inertia::DofMatrices`], from
//! the element matrices kept by [`crate::physics::inertia::ElementMatrices`]; per element
//! on a distributed layout), the loads by their kernels. Energies: kinetic ½ vᵀ M v and
//! strain ½ uᵀ K u from the same matrices; the external and contact work by the
//! trapezoidal rule over each step (exact for average acceleration, whose total is then
//! constant to round-off on a linear problem). The frictional dissipation of a step is
//! the work of the friction tractions at the end of the step on the slip increment of the
//! step, at the contact points ([`crate::contact::state::frictional_dissipation`], ≥ 0);
//! it is taken out of the contact forces' work, so `contact_work` keeps the normal work
//! (plus, where the friction traction changed during the step, the difference between the
//! trapezoidal and the end-of-step tangential work) and the total is unchanged.
//! An asperity layer's damping acts on the normal relative velocity at the end of the
//! step (c_n scaled by γ/(βΔt), the base shifted per step: `asperity_rate_bases`); its
//! work, the dissipation included, is in the contact work. With the dof matrices the
//! energies' pass over the rows also makes the next step's products
//! ([`DofMatrices::energies_and_products`]), and a contact step resumed on the carried
//! factor solves its first iteration without the product K x₀ (`super::newton`).
//!
//! Under PETSc the assembly is distributed as the quasi-static driver's
//! ([`Setup::build_layout_owned`], `super::petsc`'s module doc): each rank holds the
//! element matrices of its own cells only ([`ElementMatrices::compute_held`]) and adds
//! them, and its contact facets, straight into the distributed matrix; what is summed over
//! elements (the strain and kinetic energies, the reactions, the external loads, K u₀ and
//! the mass diagonal of the initial accelerations, the position correction's K Δu) is
//! each rank's share summed over the ranks (`sum_shares`). The contact work, the
//! frictional dissipation and every decision come from the contact kernel and the point
//! values on the dof vector gathered to every rank: the same on every rank.

use super::contact_loops::solve_contact;
use super::linear::{LinearMethod, LinearSolver, Precision, SystemStructure};
use super::newton::linear_step;
use super::observe::{Phase, SolveObserver};
use super::position_correction::{correct_positions, frictionless, overlap, StepData};
use super::report::{Energies, Motion, SolveError, SolveOptions, SolveReport, StepReport, StepSolution, Timings};
use super::setup::{FixedKernels, Setup, System};
use super::time::{ImplicitScheme, StepCoefficients};
use crate::assembly::{Kernel, LocalOut, SystemLayout, NO_EQ};
use crate::contact::law::PointState;
use crate::contact::state::{frictional_dissipation, point_values};
use crate::contact::ContactSetup;
use crate::physics::inertia::{DofMatrices, EffectiveKernel, ElementMatrices, MassKernel, MassMatrix, ProjectedField};
use crate::physics::model::Model;
use std::time::Instant;

/// The state at t = 0: displacement and velocity of every dof of the model's dof map
/// (standard and enriched; shorter vectors are padded with zeros, empty ones are zero).
#[derive(Debug, Clone, Default)]
pub struct InitialState {
    pub u: Vec<f64>,
    pub v: Vec<f64>,
}

/// The density of every material, or an error naming the first material without one.
pub fn densities(model: &Model<'_>) -> Result<Vec<f64>, SolveError> {
    model
        .densities
        .iter()
        .enumerate()
        .map(|(k, d)| match d {
            Some(r) if *r > 0.0 && r.is_finite() => Ok(*r),
            _ => Err(SolveError::Dynamics(format!(
                "material {} has no positive density: a dynamic run needs [[materials]] density",
                k + 1
            ))),
        })
        .collect()
}

/// The consistent mass kernel of a model with its densities.
pub fn mass_kernel<'a>(model: &'a Model<'_>, densities: &'a [f64]) -> MassKernel<'a> {
    MassKernel {
        mesh: model.mesh,
        enrichment: &model.enrichment,
        cracks: &model.cracks,
        cell_material: &model.cell_material,
        side_materials: &model.side_materials,
        densities,
        quadrature: model.xfem_quadrature,
        field: None,
        matrix: MassMatrix::Consistent,
    }
}

/// The mass kernel of a dynamic run: consistent or redistributed (`options.mass`).
pub fn run_mass_kernel<'a>(model: &'a Model<'_>, densities: &'a [f64], options: &SolveOptions) -> MassKernel<'a> {
    MassKernel { matrix: options.mass, ..mass_kernel(model, densities) }
}

/// The L2 projection with the consistent mass of a field g(cell, x) onto every primal dof
/// (standard and enriched): M x = ∫ ρ ψ g. A field that lies in the enriched space (one that
/// jumps across a crack or interface, per side a field of the standard space) is
/// represented exactly, not smeared over the cut cells.
pub fn project_field(
    model: &Model<'_>,
    field: &ProjectedField<'_>,
    options: &SolveOptions,
) -> Result<Vec<f64>, SolveError> {
    let rho = densities(model)?;
    let dofs = &model.enrichment.dofs;
    let n_total = dofs.n_total();
    let kernel = MassKernel { field: Some(field), ..mass_kernel(model, &rho) };
    let eliminated = vec![false; n_total];
    let layout = SystemLayout::build(n_total, n_total, &eliminated, &[&kernel]);
    let zeros = vec![0.0; n_total];
    let mut values = vec![0.0; layout.pattern.nnz()];
    let mut x = vec![0.0; layout.n_eq];
    layout.assemble(&[&kernel], &zeros, Some(&mut values), Some(&mut x));
    let solver = factorise_plain(&layout, LinearMethod::Cholesky, &values, options, "mass matrix")?;
    let bad = |error| SolveError::Dynamics(format!("the mass matrix cannot be factorised: {error}"));
    solver.solve_in_place(&mut x).map_err(bad)?;
    let mut out = vec![0.0; n_total];
    for (d, o) in out.iter_mut().enumerate() {
        let q = layout.eq_of_dof[d];
        if q != NO_EQ {
            *o = x[q as usize];
        }
    }
    Ok(out)
}

/// Solves every time step of `scheme` from `initial`, calling `on_step` at t = 0 (step 0)
/// and after each step (for output).
pub fn solve_time_steps(
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    scheme: &dyn ImplicitScheme,
    initial: &InitialState,
    observer: &dyn SolveObserver,
    on_step: &mut dyn FnMut(StepSolution<'_>) -> Result<(), String>,
) -> Result<SolveReport, SolveError> {
    if let Some(why) = scheme.instability() {
        return Err(SolveError::Dynamics(why));
    }
    let coef = scheme.coefficients();
    if !(coef.dt > 0.0 && coef.dt.is_finite()) {
        return Err(SolveError::Dynamics(format!("the time step {} must be positive", coef.dt)));
    }
    let rho = densities(model)?;
    // The asperity layers' damping on the normal relative velocity: the law's rate
    // d_n − d_n_start, times c_n scaled by the scheme's γ/(βΔt), is c_n ḋ_n at the end of
    // the step once the base is shifted by the known part of the velocity
    // ([`asperity_rate_bases`]).
    let scaled_contact;
    let contact = match contact {
        Some(c) if c.points.cracks.iter().any(|cc| cc.law.asperity.is_some_and(|a| a.damping > 0.0)) => {
            let mut s = c.clone();
            for cc in &mut s.points.cracks {
                if let Some(layer) = &mut cc.law.asperity {
                    layer.damping *= coef.gamma / (coef.beta * coef.dt);
                }
            }
            scaled_contact = s;
            Some(&scaled_contact)
        }
        other => other,
    };
    let setup = Setup::with_inertia(model, contact, options, true)?;
    let mut timings = Timings::default();
    let n_total = setup.dofs.n_total();
    let n_primal = setup.dofs.n_primal();

    let (beta, gamma, alpha, dt, beta_n) = (coef.beta, coef.gamma, coef.alpha, coef.dt, coef.beta_n);
    let (mut u, mut v) = (vec![0.0; n_total], vec![0.0; n_total]);
    let n0 = initial.u.len().min(n_primal);
    u[..n0].copy_from_slice(&initial.u[..n0]);
    let n0 = initial.v.len().min(n_primal);
    v[..n0].copy_from_slice(&initial.v[..n0]);
    let mut prescribed = vec![0.0; n_total];
    let mut mult_values = vec![0.0; setup.mult_rows.len()];
    setup.prescribe(0.0, &mut prescribed, &mut mult_values)?;
    for &d in &setup.constrained {
        u[d] = prescribed[d];
    }

    let mut state = setup.initial_state();
    let mut pairing = setup.large.then(|| setup.pair(&u));
    let clock = Instant::now();
    // PETSc: each rank assembles its own cells (and contact facets) straight into the
    // distributed matrix, and holds the element matrices of those cells only.
    let mut layout = match setup.build_layout_owned(pairing.as_ref(), &state)? {
        Some(layout) => layout,
        None => setup.build_layout(pairing.as_ref(), &state),
    };
    timings.pattern = clock.elapsed().as_secs_f64();
    let distributed = layout.is_distributed();
    let clock = Instant::now();
    let mass = run_mass_kernel(model, &rho, options);
    let em = ElementMatrices::compute_held(&setup.bulk(0.0), &mass, &|e| layout.owns(0, e));
    timings.assembly += clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let solver = setup.analyse(&layout, 0)?;
    if let Some(rows) = layout.distributed.as_mut() {
        // The preallocation counts are in PETSc's matrix now.
        (rows.d_nnz, rows.o_nnz) = (Vec::new(), Vec::new());
    }
    timings.symbolic = clock.elapsed().as_secs_f64();
    let mut sys = System::new(layout, solver);
    observer.system(&setup.sizes(&sys));
    // The effective matrix is the same at every step: the contact tangent's factor is
    // kept from one step to the next while the statuses do not change.
    sys.carry_factor = true;

    // The loads at t = 0 and the initial acceleration.
    let has_body_forces = model.cell_body_force.iter().any(|b| b.is_some());
    let has_loads = has_body_forces || setup.has_load_kernels();
    let external = |sys: &System, t: f64| -> Result<Vec<f64>, SolveError> {
        if !has_loads {
            return Ok(vec![0.0; n_total]);
        }
        let zero_mult = vec![0.0; setup.mult_rows.len()];
        let fixed = setup.kernels(t, &zero_mult);
        let zeros = vec![0.0; n_total];
        // The contact kernel's slot (the layout's last, with contact) is left out.
        let list = fixed.list();
        let mut kernels: Vec<&dyn Kernel> = list.to_vec();
        let mut include = vec![has_body_forces, true, true, false];
        if contact.is_some() {
            kernels.push(list[0]);
            include.push(false);
        }
        // Distributed: each rank's elements, summed over the ranks.
        let mut f = if distributed {
            let mut f = sys.layout.element_forces_touching(&kernels, &include, None, &zeros);
            sum_shares(distributed, &mut f)?;
            f
        } else {
            sys.layout.element_forces_of(&kernels, &include, &zeros)
        };
        f.iter_mut().for_each(|x| *x = -*x);
        Ok(f)
    };
    let mut f_prev = external(&sys, 0.0)?;
    let clock = Instant::now();
    let mut a = initial_acceleration(&setup, &em, &mass, distributed, &u, &f_prev, options)?;
    timings.numeric += clock.elapsed().as_secs_f64();

    let mut energies = Energies::default();
    (energies.strain, energies.kinetic) = summed_energies(distributed, em.energies(&u, &v))?;
    let mut steps = vec![];
    let mut r_prev = vec![0.0; n_total];
    {
        let report = StepReport {
            index: 0,
            load_factor: 0.0,
            residual: 0.0,
            linear_solves: 1,
            factorizations: 1,
            reactions: vec![[0.0; 3]; model.dirichlet_groups.len()],
            contact: None,
        };
        let solution = StepSolution {
            dofs: &setup.dofs,
            u: &u,
            report: &report,
            contact_state: &state,
            pairing: pairing.as_ref(),
            motion: Some(Motion { time: 0.0, velocity: &v, acceleration: &a, energies, position_correction: 0.0 }),
        };
        on_step(solution).map_err(SolveError::Callback)?;
        steps.push(report);
    }

    let c_m = 1.0 / (beta * dt * dt);
    let mut u_tilde = vec![0.0; n_total];
    let mut u_prev = u.clone();
    let mut fc_prev = vec![0.0; n_total];
    // The step's products c_m M ũ − c_p K u_n as two mat-vecs of K and M assembled on every
    // dof (a distributed layout sums its ranks' element vectors: there the effective kernel
    // computes them per element; so does `FISSURE_DYN_ELEMENT_PRODUCTS`, the former path,
    // for timing comparisons).
    let clock = Instant::now();
    let element_products = sys.layout.is_distributed() || std::env::var_os("FISSURE_DYN_ELEMENT_PRODUCTS").is_some();
    let dof_matrices = (!element_products).then(|| DofMatrices::assemble(&em, n_total));
    timings.assembly += clock.elapsed().as_secs_f64();
    let mut dof_loads = vec![0.0; n_total];
    // The position correction's frictionless contact set-up, set-up and system (built on
    // its first use).
    let frictionless_contact = std::cell::OnceCell::new();
    let mut correction_setup: Option<Setup> = None;
    let mut correction_system: Option<System> = None;
    // The predictor and the products of the step, when the previous step's energy pass
    // computed them (`DofMatrices::energies_and_products`).
    let mut products_ready = false;
    for step in 1..=coef.steps {
        observer.phase(Phase::Step { index: step, total: coef.steps });
        let mut clock = Instant::now();
        let t1 = step as f64 * dt;
        let t_load = t1 - alpha * dt;
        if !products_ready {
            for d in 0..n_primal {
                u_tilde[d] = u[d] + dt * v[d] + dt * dt * beta_n * a[d];
            }
        }
        u_prev.copy_from_slice(&u);
        let at_time = |e: SolveError| SolveError::TimeStep { time: t1, error: Box::new(e) };
        setup.prescribe(t1, &mut prescribed, &mut mult_values).map_err(at_time)?;
        timings.step_phases.predict += lap(&mut clock);
        if let (Some(dm), false) = (&dof_matrices, products_ready) {
            dm.products(-alpha, &u_prev, c_m, &u_tilde, &mut dof_loads);
        }
        timings.step_phases.products += lap(&mut clock);
        let effective = EffectiveKernel {
            matrices: &em,
            loads: Box::new(setup.bulk(t_load)),
            c_k: 1.0 - alpha,
            c_m,
            c_p: alpha,
            predictor: &u_tilde,
            previous: &u_prev,
            element_products: dof_matrices.is_none(),
        };
        let mut fixed = setup.dynamic_kernels(effective, t_load, t1, &mult_values);
        if dof_matrices.is_some() {
            fixed.dof_loads = Some(&dof_loads);
            fixed.bulk_rhs_zero = !has_body_forces && setup.constrained.iter().all(|&d| prescribed[d] == 0.0);
        }
        let (residual, mut factorizations, mut linear_solves, contact_report) = if let Some(c) = contact {
            velocity_law_shifts(model, c, pairing.as_ref(), &u, &v, &a, &u_tilde, &coef, &mut state);
            asperity_rate_bases(model, c, pairing.as_ref(), &v, &a, &coef, &mut state);
            timings.step_phases.predict += lap(&mut clock);
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
            .map_err(at_time)?;
            (rep.residual, rep.factorizations, rep.linear_solves, Some(rep))
        } else {
            timings.step_phases.predict += lap(&mut clock);
            let (residual, f) =
                linear_step(&mut sys, &fixed, &prescribed, step, options, &mut u, &mut timings, observer)
                    .map_err(at_time)?;
            (residual, f, 1, None)
        };
        timings.step_phases.system += lap(&mut clock);
        // The (generalized) Newmark update of the accelerations and velocities.
        for d in 0..n_primal {
            let a_new = c_m * (u[d] - u_tilde[d]);
            v[d] += dt * ((1.0 - gamma) * a[d] + gamma * a_new);
            a[d] = a_new;
        }
        timings.step_phases.update += lap(&mut clock);
        let ck = setup.contact_kernel(&state, &u, pairing.as_ref());
        let mut r_now = if distributed {
            setup.constrained_forces_of_ranks(&sys.layout, &fixed, ck.as_ref(), &u).map_err(at_time)?
        } else {
            setup.constrained_forces(&sys.layout, &fixed, ck.as_ref(), &u)
        };
        let reactions = setup.reactions_of(&r_now, &u);
        timings.step_phases.reactions += lap(&mut clock);
        // Energies: the loads' and supports' work by the trapezoidal rule.
        let f_now = external(&sys, t1).map_err(at_time)?;
        let mut w = 0.0;
        for d in 0..n_primal {
            let du = u[d] - u_prev[d];
            if du != 0.0 {
                w += 0.5 * (f_prev[d] + f_now[d]) * du;
            }
        }
        for &d in &setup.constrained {
            w -= 0.5 * (r_prev[d] + r_now[d]) * (u[d] - u_prev[d]);
        }
        energies.external_work += w;
        timings.step_phases.external += lap(&mut clock);
        // The largest overlap of velocity-law points, when it is beyond round-off.
        let mut overlap_to_correct = None;
        if let (Some(ck), Some(c)) = (&ck, contact) {
            let fc_now = contact_forces(&sys.layout, &fixed, ck, &u)?;
            let mut wc = 0.0;
            for d in 0..n_primal {
                wc += 0.5 * (fc_prev[d] + fc_now[d]) * (u[d] - u_prev[d]);
            }
            // The friction tractions' work on the slip of the step, split out of the
            // contact forces' work (the total keeps the trapezoidal sum of the step).
            let vals = point_values(model, &c.points, pairing.as_ref(), &state, &u);
            let friction = frictional_dissipation(&c.points, &state, &vals);
            energies.frictional_dissipation += friction;
            energies.contact_work += wc - friction;
            fc_prev = fc_now;
            // Small sliding only: the correction's gap is linear in Δu.
            if options.position_correction && !setup.large {
                let (largest, beyond) = overlap(c, &state, &vals);
                overlap_to_correct = beyond.then_some(largest);
            }
            timings.step_phases.contact_work += lap(&mut clock);
        }
        // The position correction (velocity formulation, where the lips overlap): the
        // displacements projected onto d_n ≥ 0, v and a kept. Its work is the change of
        // the strain energy, booked as contact work; the next step's trapezoidal rule
        // starts from the forces of the corrected state, M a_{n+1} + K u_{n+1} − f (the
        // contact forces less K Δu on the free dofs, the reactions plus K Δu on the
        // constrained ones), so the total stays constant with average acceleration.
        let mut position_correction = 0.0;
        if let (Some(largest), Some(c)) = (overlap_to_correct, contact) {
            if correction_setup.is_none() {
                let fc = frictionless_contact.get_or_init(|| frictionless(c));
                correction_setup = Some(Setup::with_inertia(model, Some(fc), options, true).map_err(at_time)?);
            }
            let data = StepData { step, t_load, t_constraint: t1, c_m };
            let corr = correct_positions(
                correction_setup.as_ref().expect("built above"),
                &mut correction_system,
                &em,
                &data,
                &mut u,
                &state,
                &pairing,
                largest,
                n_primal,
                &mut timings,
                observer,
            )
            .map_err(at_time)?;
            factorizations += corr.report.factorizations;
            linear_solves += corr.report.linear_solves;
            let du = &corr.du;
            let mut k_du = vec![0.0; n_total];
            em.add_products(1.0, du, 0.0, du, &mut k_du);
            sum_shares(distributed, &mut k_du).map_err(at_time)?;
            // ½ (u + Δu)ᵀ K (u + Δu) − ½ uᵀ K u with u the velocity step's: Δuᵀ K (u + ½ Δu).
            let strain_change: f64 = (0..n_primal).map(|d| k_du[d] * (u[d] - 0.5 * du[d])).sum();
            energies.contact_work -= strain_change;
            for d in 0..n_primal {
                fc_prev[d] -= k_du[d];
            }
            for &d in &setup.constrained {
                fc_prev[d] += k_du[d];
                r_now[d] += k_du[d];
            }
            position_correction = corr.overlap_removed;
            timings.step_phases.position_correction += lap(&mut clock);
        }
        // The energies; with the dof matrices, in the same pass as the next step's
        // predictor products c_m M ũ − α K u (ũ from this step's u, v, a: the next step's
        // predictor, by the same formula).
        products_ready = false;
        drop(fixed);
        (energies.strain, energies.kinetic) = match &dof_matrices {
            Some(dm) if step < coef.steps => {
                for d in 0..n_primal {
                    u_tilde[d] = u[d] + dt * v[d] + dt * dt * beta_n * a[d];
                }
                products_ready = true;
                dm.energies_and_products(&u, &v, -alpha, c_m, &u_tilde, &mut dof_loads)
            }
            Some(dm) => dm.energies(&u, &v),
            None => summed_energies(distributed, em.energies(&u, &v)).map_err(at_time)?,
        };
        timings.step_phases.energies += lap(&mut clock);
        f_prev = f_now;
        r_prev = r_now;
        let report = StepReport {
            index: step,
            load_factor: t1,
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
            motion: Some(Motion { time: t1, velocity: &v, acceleration: &a, energies, position_correction }),
        };
        on_step(solution).map_err(SolveError::Callback)?;
        steps.push(report);
        timings.step_phases.output += lap(&mut clock);
    }
    Ok(setup.report(&sys, steps, timings))
}

/// Sums `v` over the MPI ranks when `distributed` (each rank holds its own elements'
/// share of it: [`ElementMatrices::compute_held`]); leaves it otherwise. Collective when
/// `distributed`.
fn sum_shares(distributed: bool, v: &mut [f64]) -> Result<(), SolveError> {
    #[cfg(feature = "petsc")]
    if distributed {
        super::petsc::sum_over_ranks(v).map_err(|why| SolveError::Linear {
            step: 0,
            error: super::linear::LinearError::Petsc(why),
            advice: "",
        })?;
    }
    #[cfg(not(feature = "petsc"))]
    let _ = (distributed, v);
    Ok(())
}

/// The strain and kinetic energies of this rank's elements summed over the ranks when
/// `distributed` ([`sum_shares`]).
fn summed_energies(distributed: bool, (strain, kinetic): (f64, f64)) -> Result<(f64, f64), SolveError> {
    let mut e = [strain, kinetic];
    sum_shares(distributed, &mut e)?;
    Ok((e[0], e[1]))
}

/// The seconds since `clock`, which restarts.
fn lap(clock: &mut Instant) -> f64 {
    let now = Instant::now();
    let dt = now.duration_since(*clock).as_secs_f64();
    *clock = now;
    dt
}

/// The gap shifts of the velocity formulation for the coming step, from the state at its
/// start (`u`, `v`, `a`) and the predictor `u_tilde`: at a point of a velocity-law crack
/// whose lips touch (d_n ≥ −1e-9 h), the shift makes d_n = 0 mean ⟦v_{n+1}⟧_n = 0
/// (Newmark: v_{n+1} = v_n + Δt (1 − γ) a_n + (γ / (β Δt)) (u_{n+1} − ũ), so ⟦v_{n+1}⟧_n = 0
/// is ⟦u_{n+1}⟧_n = ⟦u*⟧_n with u* = ũ − (β Δt / γ)(v_n + Δt (1 − γ) a_n); for the θ-method
/// β/γ = θ and u* = u_n + (1 − θ) Δt v_n); elsewhere 0 (the gap law).
#[allow(clippy::too_many_arguments)]
fn velocity_law_shifts(
    model: &Model<'_>,
    c: &ContactSetup,
    pairing: Option<&crate::contact::pairing::Pairing>,
    u: &[f64],
    v: &[f64],
    a: &[f64],
    u_tilde: &[f64],
    scheme: &StepCoefficients,
    state: &mut [crate::contact::law::PointState],
) {
    use crate::contact::points::ContactFormulation;
    let pts = &c.points;
    if !pts.cracks.iter().any(|cc| cc.formulation == ContactFormulation::Velocity) {
        return;
    }
    let (beta, gamma, dt) = (scheme.beta, scheme.gamma, scheme.dt);
    let n_primal = model.enrichment.dofs.n_total();
    let mut u_star = u.to_vec();
    for d in 0..n_primal {
        u_star[d] = u_tilde[d] - beta * dt / gamma * (v[d] + dt * (1.0 - gamma) * a[d]);
    }
    for st in state.iter_mut() {
        st.gap_shift = 0.0;
    }
    let now = point_values(model, pts, pairing, state, u);
    let star = point_values(model, pts, pairing, state, &u_star);
    for (((st, p), n), s) in state.iter_mut().zip(&pts.points).zip(&now).zip(&star) {
        let cc = &pts.cracks[p.crack];
        if cc.formulation == ContactFormulation::Velocity && n.paired && n.d_n >= -1e-9 * cc.cell_size {
            st.gap_shift = cc.law.penetration(s.jump, p.normal, 0.0);
        }
    }
}

/// The bases of the asperity layers' damping for the coming step, from the velocity and
/// acceleration at its start: the scheme's velocity at the end of the step is
/// v_{n+1} = s (u_{n+1} − u_n) + w, s = γ/(βΔt), w = (1 − γ/β) v_n + Δt (1 − γ − γ β_n/β) a_n,
/// so the layer's crush rate ḋ_n = −⟦v_{n+1}⟧·n is s (d_n − d_n_start − ⟦w⟧·n / s): the
/// shift ⟦w⟧·n / s of the base ([`PointState::layer_rate_shift`]) makes the law's rate
/// (d_n − base), with c_n scaled by s (`solve_time_steps`), the damping c_n ḋ_n on the true
/// velocity, and its derivative s in the tangent. Points of cracks without a layer: 0.
fn asperity_rate_bases(
    model: &Model<'_>,
    c: &ContactSetup,
    pairing: Option<&crate::contact::pairing::Pairing>,
    v: &[f64],
    a: &[f64],
    scheme: &StepCoefficients,
    state: &mut [PointState],
) {
    let pts = &c.points;
    if !pts.cracks.iter().any(|cc| cc.law.asperity.is_some()) {
        return;
    }
    let (beta, gamma, dt, beta_n) = (scheme.beta, scheme.gamma, scheme.dt, scheme.beta_n);
    let s = gamma / (beta * dt);
    let (c_v, c_a) = (1.0 - gamma / beta, dt * (1.0 - gamma - gamma * beta_n / beta));
    let w: Vec<f64> = v.iter().zip(a).map(|(v, a)| c_v * v + c_a * a).collect();
    let vals = point_values(model, pts, pairing, state, &w);
    for ((st, p), val) in state.iter_mut().zip(&pts.points).zip(&vals) {
        let law = &pts.cracks[p.crack].law;
        st.layer_rate_shift = if law.asperity.is_some() {
            // ⟦w⟧·n, with the law's own sign convention for the gap.
            (law.penetration([0.0; 3], p.normal, 0.0) - law.penetration(val.jump, p.normal, 0.0)) / s
        } else {
            0.0
        };
    }
}

/// The contact forces on the body's dofs (the contact kernel's residual, the last kernel
/// of the layout) for `u`. A distributed layout lists its own rank's elements only: each
/// rank computes its contact facets' share, summed over the ranks ([`sum_shares`]), so
/// every rank holds the whole forces. Collective on a distributed layout.
fn contact_forces(
    layout: &SystemLayout,
    fixed: &FixedKernels<'_>,
    ck: &dyn Kernel,
    u: &[f64],
) -> Result<Vec<f64>, SolveError> {
    let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
    kernels.push(ck);
    let mut include = vec![false; kernels.len()];
    include[kernels.len() - 1] = true;
    let mut f = layout.element_forces_touching(&kernels, &include, None, u);
    sum_shares(layout.is_distributed(), &mut f)?;
    Ok(f)
}

/// The accelerations at t = 0: M a₀ = f₀ − K u₀ on the free dofs (a₀ = 0 on the
/// constrained ones, the linear relations holding for a₀ with a zero right-hand side).
///
/// `distributed`: `em` holds this rank's elements only ([`ElementMatrices::compute_held`]):
/// K u₀ and the mass diagonal are summed over the ranks, and each rank assembles the mass
/// matrix of its own cells from `mass` (the same element matrices, computed again)
/// straight into PETSc, which solves it (its KSP of the case: the solution to PETSc's
/// tolerance, not faer's direct solve).
fn initial_acceleration(
    setup: &Setup<'_, '_>,
    em: &ElementMatrices,
    mass: &MassKernel<'_>,
    distributed: bool,
    u0: &[f64],
    f0: &[f64],
    options: &SolveOptions,
) -> Result<Vec<f64>, SolveError> {
    let n_total = setup.dofs.n_total();
    let n_primal = setup.dofs.n_primal();
    let mut rhs_full = f0.to_vec();
    if distributed {
        let mut ku = vec![0.0; n_total];
        em.add_products(1.0, u0, 0.0, u0, &mut ku);
        sum_shares(distributed, &mut ku)?;
        rhs_full.iter_mut().zip(&ku).for_each(|(r, k)| *r -= k);
    } else {
        em.add_products(-1.0, u0, 0.0, u0, &mut rhs_full);
    }
    let mut a = vec![0.0; n_total];
    if rhs_full[..n_primal].iter().all(|&x| x == 0.0) {
        return Ok(a);
    }
    let zeros = vec![0.0; n_total];
    let mass_only = EffectiveKernel {
        matrices: em,
        loads: Box::new(setup.bulk(0.0)),
        c_k: 0.0,
        c_m: 1.0,
        c_p: 0.0,
        predictor: &zeros,
        previous: &zeros,
        element_products: true,
    };
    let mult_zero = vec![0.0; setup.mult_rows.len()];
    let fixed = setup.kernels(0.0, &mult_zero);
    let constraints = fixed.list()[3];
    let eliminated = setup.mass_eliminated();
    // Dofs without mass (the redistributed mass's Heaviside dofs of the cut cells): their
    // rows of M a₀ = f₀ − K u₀ are static equations, not equations for a₀, which enters
    // only their own (massless) inertia; a₀ = 0 there (an identity row of the mass's scale,
    // right-hand side zero), the linear relations holding.
    let mut diag = em.mass_diagonal(n_total);
    sum_shares(distributed, &mut diag)?;
    let scale = diag[..n_primal].iter().fold(0.0f64, |m, &d| m.max(d));
    let massless: Vec<u32> = (0..n_primal).filter(|&d| !eliminated[d] && diag[d] == 0.0).map(|d| d as u32).collect();
    for &d in &massless {
        rhs_full[d as usize] = 0.0;
    }
    let unit = DiagonalKernel { dofs: &massless, value: scale };
    // c_k K_e + c_m M_e with c_k = 0, c_m = 1 is M_e to the bit: the mass kernel itself
    // where this rank does not hold every element's matrices.
    let mass_matrix: &dyn Kernel = if distributed { mass } else { &mass_only };
    let kernels: [&dyn Kernel; 3] = [mass_matrix, &unit, constraints];
    let bad = |error| SolveError::Dynamics(format!("the mass matrix cannot be factorised: {error}"));
    let (layout, solver) = if distributed {
        // Each rank's cells (and rows) of the mass matrix straight into PETSc, on the
        // partition of the time steps' system (the same cells and weights), solved there.
        let mut layout = setup
            .owned_layout(&kernels, &eliminated, false, false)?
            .ok_or_else(|| SolveError::Dynamics("a distributed mass matrix needs the PETSc backend".into()))?;
        let mut solver = setup.analyse_with(&layout, 0, false)?;
        if let Some(rows) = layout.distributed.as_mut() {
            (rows.d_nnz, rows.o_nnz) = (Vec::new(), Vec::new());
        }
        let all = [true; 3];
        solver
            .factorize_elements(&mut |sink| layout.assemble_elements(&kernels, &all, &zeros, None, sink))
            .map_err(bad)?;
        (layout, solver)
    } else {
        let layout = SystemLayout::build(n_total, n_primal, &eliminated, &kernels);
        let mut values = vec![0.0; layout.pattern.nnz()];
        layout.assemble(&kernels, &zeros, Some(&mut values), None);
        let saddle = layout.n_eq > layout.n_primal_eq;
        let method = if saddle { LinearMethod::Ldlt } else { LinearMethod::Cholesky };
        let solver = factorise_plain(&layout, method, &values, options, "mass matrix")?;
        (layout, solver)
    };
    let mut x = vec![0.0; layout.n_eq];
    for d in 0..n_primal {
        let q = layout.eq_of_dof[d];
        if q != NO_EQ {
            x[q as usize] = rhs_full[d];
        }
    }
    solver.solve_in_place(&mut x).map_err(bad)?;
    for d in 0..n_primal {
        let q = layout.eq_of_dof[d];
        if q != NO_EQ {
            a[d] = x[q as usize];
        }
    }
    Ok(a)
}

/// A diagonal matrix `value` on a list of dofs (one element per dof; no vector).
struct DiagonalKernel<'a> {
    dofs: &'a [u32],
    value: f64,
}

impl Kernel for DiagonalKernel<'_> {
    fn n_elements(&self) -> usize {
        self.dofs.len()
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        out.push(self.dofs[e]);
    }

    fn compute(&self, _e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        if let Some(m) = out.matrix {
            m[0] = self.value;
        }
    }
}

/// The lowest angular frequency ω₁ of the model's free vibrations (its Dirichlet conditions
/// held at zero) from the generalized eigenproblem K φ = ω² M φ of the same discretisation,
/// by inverse iteration (to a relative change of ω² below 1e-12, at most 500 iterations).
/// Models with linear relations or Dirichlet multipliers are not handled.
pub fn lowest_frequency(model: &Model<'_>, options: &SolveOptions) -> Result<f64, SolveError> {
    let rho = densities(model)?;
    let setup = Setup::new(model, None, options)?;
    let mass = run_mass_kernel(model, &rho, options);
    let em = ElementMatrices::compute(&setup.bulk(0.0), &mass);
    let n_total = setup.dofs.n_total();
    let n_primal = setup.dofs.n_primal();
    let zeros = vec![0.0; n_total];
    let part = |c_k: f64, c_m: f64| EffectiveKernel {
        matrices: &em,
        loads: Box::new(setup.bulk(0.0)),
        c_k,
        c_m,
        c_p: 0.0,
        predictor: &zeros,
        previous: &zeros,
        element_products: true,
    };
    let (stiffness, mass) = (part(1.0, 0.0), part(0.0, 1.0));
    let eliminated = setup.mass_eliminated();
    let layout = SystemLayout::build(n_total, n_primal, &eliminated, &[&stiffness]);
    if layout.n_eq > layout.n_primal_eq {
        return Err(SolveError::Dynamics("lowest_frequency: models with relations are not handled".into()));
    }
    let (mut k, mut m) = (vec![0.0; layout.pattern.nnz()], vec![0.0; layout.pattern.nnz()]);
    layout.assemble(&[&stiffness], &zeros, Some(&mut k), None);
    layout.assemble(&[&mass], &zeros, Some(&mut m), None);
    let solver = factorise_plain(&layout, LinearMethod::Cholesky, &k, options, "stiffness matrix")?;
    let bad = |error| SolveError::Dynamics(format!("the stiffness matrix cannot be factorised: {error}"));
    let n = layout.n_eq;
    // A start with every mode in it: a smooth, non-symmetric field.
    let mut x: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.618).sin()).collect();
    let (mut mx, mut kx) = (vec![0.0; n], vec![0.0; n]);
    let mut omega2 = f64::INFINITY;
    for _ in 0..500 {
        layout.pattern.mul_vec(&m, &x, &mut mx);
        x.copy_from_slice(&mx);
        solver.solve_in_place(&mut x).map_err(bad)?;
        layout.pattern.mul_vec(&k, &x, &mut kx);
        layout.pattern.mul_vec(&m, &x, &mut mx);
        let xkx: f64 = x.iter().zip(&kx).map(|(a, b)| a * b).sum();
        let xmx: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
        let w2 = xkx / xmx;
        let scale = xmx.sqrt();
        x.iter_mut().for_each(|v| *v /= scale);
        let done = (w2 - omega2).abs() <= 1e-12 * w2;
        omega2 = w2;
        if done {
            return Ok(omega2.sqrt());
        }
    }
    Err(SolveError::Dynamics("lowest_frequency: the inverse iteration did not converge in 500 iterations".into()))
}

/// Analyses and factorises `values` on `layout`'s pattern with `method`, without contact
/// points, condensation or a memory limit (the mass and stiffness matrices of the set-up
/// computations); an error names the matrix (`what`).
fn factorise_plain(
    layout: &SystemLayout,
    method: LinearMethod,
    values: &[f64],
    options: &SolveOptions,
    what: &str,
) -> Result<LinearSolver, SolveError> {
    let structure = SystemStructure {
        method,
        pattern: &layout.pattern,
        n_primal: layout.n_primal_eq,
        points: None,
        condense: None,
        ordering: options.ordering,
        memory_limit: None,
        reuse: None,
        // Solved at every time step: one double-precision solve is cheaper than the
        // iterations of a mixed-precision one.
        precision: Precision::Double,
    };
    let bad = |error| SolveError::Dynamics(format!("the {what} cannot be factorised: {error}"));
    let mut solver = LinearSolver::analyse_system(&structure).map_err(bad)?;
    solver.factorize(values).map_err(bad)?;
    Ok(solver)
}
