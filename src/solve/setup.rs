//! What a solve sets up once per model: the dof numbering (Dirichlet and contact
//! multiplier blocks), the constrained dofs and their prescribed values, the linear
//! method the formulation needs, the element kernels at a load factor, the layout
//! (pattern) and its symbolic analysis, the initial contact state and the reactions.
//!
//! Entry point: [`Setup::new`]; then [`Setup::kernels`], [`Setup::build_layout`],
//! [`Setup::analyse`], [`Setup::reactions`].

use super::linear::{Backend, LinearMethod, LinearSolver, OrderingChoice, Precision, SystemStructure};
use super::ordering::reuse::ReusedOrdering;
use super::ordering::{EquationPoints, NO_POINT};
use super::report::{SolveError, SolveOptions, SolveReport, StepReport, Timings};
use crate::assembly::{DofKind, DofMap, Kernel, LocalOut, SystemLayout, NO_EQ};
use crate::contact::kernel::ContactKernel;
use crate::contact::law::PointState;
use crate::contact::pairing::{pair, Pairing, PairingOptions};
use crate::contact::ContactSetup;
use crate::physics::constraints::{check_model_rigid_modes, CrackedBody};
use crate::physics::elasticity::{BulkKernel, DirichletMultiplierKernel, TractionKernel};
use crate::physics::held_faces::held_enriched;
use crate::physics::inertia::EffectiveKernel;
use crate::physics::model::{DirichletMethod, Model};
use crate::physics::relations::{self, ConstraintKernel, RelationKernel};
use crate::physics::xfem::{CrackPressureKernel, XfemBulkKernel};

/// The starting friction threshold, as a share of the largest Young's modulus of the
/// model, below which the first pass starts frictionless ([`Setup::initial_state`]): the
/// stick predictor's Λ = τ/(μ|λ̄|) keeps a remainder ε·τ/(μ|λ̄|) ≤ ε·E/(μ|λ̄|) after its
/// corrections, below 0.03 for μ ≥ 0.1 at this floor.
pub const START_THRESHOLD_FLOOR: f64 = 1e-13;

/// The set-up of one solve (see the module doc).
pub struct Setup<'a, 'm> {
    pub model: &'a Model<'m>,
    pub contact: Option<&'a ContactSetup>,
    /// Every dof: the model's, then the contact multipliers, then the Dirichlet ones.
    pub dofs: DofMap,
    /// The constrained dofs, ascending: the standard dofs of the Dirichlet conditions, then
    /// the enriched unknowns they hold at 0 on the faces a crack cuts (`physics::held_faces`).
    pub constrained: Vec<usize>,
    /// Per dof: constrained or not.
    pub is_constrained: Vec<bool>,
    /// Per dof of the model (standard and enriched): the Dirichlet condition that sets it
    /// (the last one wins; an enriched unknown held at 0 takes its node's condition).
    cond_of_dof: Vec<u32>,
    /// Per Dirichlet group: the enriched unknowns it holds at 0 (`physics::held_faces`).
    pub held_enriched: Vec<usize>,
    /// Per dof: eliminated from the system (Dirichlet by elimination).
    eliminated: Vec<bool>,
    /// (constrained dof, multiplier dof) per condition (Dirichlet by multipliers).
    pub mult_rows: Vec<(u32, u32)>,
    /// The first multiplier dof of the linear relations (one each, after the Dirichlet
    /// multipliers; `physics/relations.rs`).
    rel_first: usize,
    /// The solver the formulation needs: Cholesky becomes LDLᵀ with multiplier unknowns
    /// (Dirichlet multipliers, or a contact law that has them).
    pub linear: LinearMethod,
    /// Contact with multipliers: the factor is condensed onto the crack unknowns.
    condense: bool,
    /// The fill-reducing ordering of the direct solver.
    ordering: OrderingChoice,
    /// The node order kept across the analyses of a run (`SolveOptions::reuse_ordering`).
    reuse: Option<std::sync::Arc<ReusedOrdering>>,
    /// The arithmetic of the direct solver's factor.
    precision: Precision,
    /// The linear backend.
    backend: Backend,
    /// Some crack slides large: the pairing is redone in the geometry loop.
    pub large: bool,
    pressure_facets: Vec<(u16, u32)>,
    enriched: bool,
    dof_nodes: Vec<u32>,
    pairing_options: PairingOptions,
}

/// The kernels that do not depend on the contact state, at one load factor.
pub struct FixedKernels<'a> {
    bulk: Bulk<'a>,
    traction: TractionKernel<'a>,
    pressure: CrackPressureKernel<'a>,
    multipliers: ConstraintKernel<'a>,
    /// A load vector on every dof added to the kernels' vectors (the dynamics driver's
    /// c_m M ũ − c_p K u_n as mat-vecs, its effective kernel without element products).
    pub dof_loads: Option<&'a [f64]>,
    /// The bulk kernel adds nothing to a load vector assembled without its matrix (no
    /// body forces, no element products, every prescribed value zero: no lifting): the
    /// load vector's assembly skips its elements.
    pub bulk_rhs_zero: bool,
}

impl FixedKernels<'_> {
    /// Bulk, boundary loads, crack pressure, Dirichlet multipliers and linear relations
    /// (layout order).
    pub fn list(&self) -> [&dyn Kernel; 4] {
        [&self.bulk, &self.traction, &self.pressure, &self.multipliers]
    }

    /// Adds [`Self::dof_loads`] to the load vector `rhs` of `layout`'s equations.
    pub fn add_dof_loads(&self, layout: &SystemLayout, rhs: &mut [f64]) {
        if let Some(g) = self.dof_loads {
            for (&q, &gd) in layout.eq_of_dof.iter().zip(g) {
                if q != NO_EQ {
                    rhs[q as usize] += gd;
                }
            }
        }
    }
}

impl<'a, 'm> Setup<'a, 'm> {
    /// The report of a finished run of steps (the quasi-static and the dynamic drivers
    /// alike): the system's figures, the steps and the timings.
    pub fn report(self, sys: &System, steps: Vec<StepReport>, timings: Timings) -> SolveReport {
        SolveReport { steps, timings, ..self.sizes(sys) }
    }

    /// The system's figures without steps or timings (told the observer once the system is
    /// set up and when a step fails: a failed run's summary still reports them).
    pub fn sizes(&self, sys: &System) -> SolveReport {
        SolveReport {
            n_eq: sys.layout.n_eq,
            n_prescribed: self.constrained.len(),
            nnz_matrix: sys.layout.nnz(),
            nnz_factor: sys.solver.stats().nnz_factor,
            flops_factor: sys.solver.stats().flops_factor,
            mixed_precision: sys.solver.stats().mixed,
            precision_fallback: sys.solver.stats().fallback,
            refinements: sys.solver.last_residual().1,
            condensed_counts: sys.solver.stats().condensed,
            kept_counts: sys.solver.stats().kept,
            condensed: sys.solver.is_condensed(),
            backend: sys.solver.info(),
            n_colors: sys.layout.n_colors(),
            heaviside_nodes: self.model.enrichment.n_heaviside_nodes,
            held_enriched: self.held_enriched.clone(),
            tip_nodes: self.model.enrichment.n_tip_nodes,
            steps: Vec::new(),
            timings: Timings::default(),
            linear_method: self.linear,
            dofs: self.dofs.clone(),
        }
    }

    /// Numbers the dofs, finds the constrained ones and checks that they hold the body.
    pub fn new(
        model: &'a Model<'m>,
        contact: Option<&'a ContactSetup>,
        options: &SolveOptions,
    ) -> Result<Self, SolveError> {
        Self::with_inertia(model, contact, options, false)
    }

    /// [`Setup::new`]; with `inertia` (dynamics, where the mass holds a free body) the
    /// constrained dofs need not prevent the rigid-body motions.
    pub fn with_inertia(
        model: &'a Model<'m>,
        contact: Option<&'a ContactSetup>,
        options: &SolveOptions,
        inertia: bool,
    ) -> Result<Self, SolveError> {
        let mesh = model.mesh;
        let dim = mesh.dim;
        let mut dofs = model.enrichment.dofs.clone();
        let n_std = dim * mesh.n_nodes();
        if let Some(c) = contact {
            let start = dofs.push_block(DofKind::ContactMultiplier, c.points.n_unknowns);
            debug_assert_eq!(start, model.enrichment.dofs.n_total());
        }
        // Constrained dofs: the last condition on a dof wins. On the held faces a crack cuts
        // (or with branch functions), the enriched unknowns of the held components too, at 0
        // (`physics::held_faces`); they take the condition of their node's standard dof.
        let held = held_enriched(mesh, &model.cracks, &model.enrichment, &model.dirichlet);
        let mut cond_of_dof = vec![u32::MAX; model.enrichment.dofs.n_total()];
        for (k, c) in model.dirichlet.iter().enumerate() {
            cond_of_dof[dofs.node_dof(c.node, c.component)] = k as u32;
        }
        let mut held_enriched_per_group = vec![0usize; model.dirichlet_groups.len()];
        for h in &held {
            cond_of_dof[h.dof] = h.condition;
            held_enriched_per_group[model.dirichlet[h.condition as usize].group as usize] += 1;
        }
        let constrained: Vec<usize> = (0..cond_of_dof.len()).filter(|&d| cond_of_dof[d] != u32::MAX).collect();
        let pairs: Vec<(usize, usize)> =
            constrained.iter().filter(|&&d| d < n_std).map(|&d| (d / dim, d % dim)).collect();
        if !inertia {
            let tied = contact.map_or_else(Vec::new, |c| c.points.rigid_rows(mesh));
            let cracked = CrackedBody {
                cracks: &model.cracks,
                enrichment: &model.enrichment,
                separating: separating_cracks(model.cracks.len(), contact),
            };
            check_model_rigid_modes(mesh, &cracked, &pairs, &model.relations, &tied)
                .map_err(SolveError::UnderConstrained)?;
        }

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
        // Linear relations: one multiplier each, after the Dirichlet ones.
        let rel_first = dofs.push_block(DofKind::DirichletMultiplier, model.relations.len());
        eliminated.resize(dofs.n_total(), false);
        // A law without multipliers (penalty) keeps its crack's λ, Λ slots in the dof
        // vector for the output only (the tractions projected on the multiplier space):
        // they are no unknowns of the system.
        if let Some(c) = contact {
            for (ci, cc) in c.points.cracks.iter().enumerate() {
                if !cc.law.method.has_multipliers() {
                    for j in 0..cc.space.n_unknowns as u32 {
                        eliminated[c.points.lambda_dof(ci, j)] = true;
                        for a in 0..dim - 1 {
                            eliminated[c.points.tangent_dof(ci, j, a)] = true;
                        }
                    }
                }
            }
            // Crosspoint multipliers: their constraint is already imposed by the Dirichlet
            // conditions of both sides; they stay 0 (`contact::crosspoints`).
            for d in c.crosspoints.dofs(&c.points) {
                eliminated[d] = true;
            }
        }
        let contact_multipliers = contact.is_some_and(|c| c.has_multipliers());
        let saddle = model.dirichlet_method == DirichletMethod::Multiplier || !model.relations.is_empty();
        let linear = match (saddle, contact_multipliers, options.linear) {
            (true, _, LinearMethod::Cholesky) | (_, true, LinearMethod::Cholesky) => LinearMethod::Ldlt,
            (_, _, m) => m,
        };
        let mut is_constrained = vec![false; dofs.n_total()];
        for &d in &constrained {
            is_constrained[d] = true;
        }
        let pressure_facets: Vec<(u16, u32)> = model
            .cracks
            .iter()
            .enumerate()
            .filter(|(k, _)| model.crack_pressure.get(*k).is_some_and(|p| p.is_some()))
            .flat_map(|(k, c)| (0..c.cut.facets.len()).map(move |f| (k as u16, f as u32)))
            .collect();
        Ok(Setup {
            model,
            contact,
            constrained,
            is_constrained,
            cond_of_dof,
            held_enriched: held_enriched_per_group,
            eliminated,
            mult_rows,
            rel_first,
            linear,
            condense: contact.is_some() && options.condense,
            ordering: options.ordering,
            reuse: options.reuse_ordering.clone(),
            precision: options.precision,
            backend: options.backend.clone(),
            large: contact.is_some_and(|c| c.points.cracks.iter().any(|cc| cc.large_sliding)),
            pressure_facets,
            enriched: model.enrichment.dofs.n_total() > n_std,
            dof_nodes: model.enrichment.dof_nodes(),
            pairing_options: PairingOptions::default(),
            dofs,
        })
    }

    /// The contact state at the start of the run: every point closed or open as its crack
    /// says, with its crack's initial friction threshold. A threshold above the largest
    /// Young's modulus of the model acts as that modulus: a small-strain model has no
    /// stress near E, so the first pass already sticks every point that friction can hold,
    /// and a larger threshold only scales the stick terms μλ̄ of the system far above its
    /// stiffness (`initial_threshold = 1e12` with E = 1 left a relative residual of 3e-5 in
    /// the LDLᵀ solve, reported as a singular matrix). A threshold below
    /// [`START_THRESHOLD_FLOOR`] times that modulus acts as 0 (a frictionless first pass,
    /// the default start): no stress of the model is that small against E within the
    /// round-off of the stiffness, and the first pass's stick predictor sets
    /// Λ = τ/(μ|λ̄|), which the Newton corrections cancel back to O(1) only to
    /// ε·τ/(μ|λ̄|): `initial_threshold = 1e-80` with E = 1 started the next pass from
    /// |Λ| ≈ 5e64 and ended with K_I = 3e32 and every point open, and 1e-200 underflowed
    /// the slip rows (μλ̄)²/ρ_n to zero ("unknown … has no nonzero coefficient").
    pub fn initial_state(&self) -> Vec<PointState> {
        let cap = self.model.materials.iter().map(|m| m.young).fold(0.0f64, f64::max);
        let floor = START_THRESHOLD_FLOOR * cap;
        let start = |value: f64| if value < floor { 0.0 } else { -value.min(cap) };
        // The master faces of the pairs with wear start unworn.
        for cc in self.contact.iter().flat_map(|c| &c.points.cracks) {
            cc.master_wear.reset();
        }
        self.contact
            .map(|c| {
                c.points
                    .points
                    .iter()
                    .map(|p| {
                        let cc = &c.points.cracks[p.crack];
                        PointState {
                            contact: cc.start_closed,
                            lam_bar: start(cc.initial_threshold),
                            prev_jump: [0.0; 3],
                            lock: None,
                            big_lambda_start: [0.0; 2],
                            gap_shift: 0.0,
                            ..PointState::default()
                        }
                    })
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The prescribed value of every constrained dof at load factor `t` (into `out`, by
    /// dof), and of every Dirichlet multiplier row (into `mult_values`).
    pub fn prescribe(&self, t: f64, out: &mut [f64], mult_values: &mut [f64]) -> Result<(), SolveError> {
        let model = self.model;
        let n_std = model.mesh.dim * model.mesh.n_nodes();
        for &d in &self.constrained {
            if d >= n_std {
                out[d] = 0.0; // an enriched unknown held on a cut face
                continue;
            }
            let c = &model.dirichlet[self.cond_of_dof[d] as usize];
            let v = c.value.eval_load(model.mesh.nodes[c.node], t);
            if !v.is_finite() {
                return Err(SolveError::NonFinite {
                    what: format!(
                        "the Dirichlet value on group '{}' at node {}",
                        model.dirichlet_groups[c.group as usize], c.node
                    ),
                });
            }
            out[d] = v;
        }
        for (k, &(d, _)) in self.mult_rows.iter().enumerate() {
            mult_values[k] = out[d as usize];
        }
        Ok(())
    }

    /// Whether the model has boundary loads or crack pressure (kernels with elements
    /// besides the bulk's).
    pub fn has_load_kernels(&self) -> bool {
        !self.model.faces.is_empty() || !self.pressure_facets.is_empty()
    }

    /// The kernels that do not depend on the contact state, at load factor `t`, with the
    /// Dirichlet multiplier values `mult_values` (one per row of [`Self::mult_rows`]).
    pub fn kernels<'s>(&'s self, t: f64, mult_values: &'s [f64]) -> FixedKernels<'s> {
        self.fixed_kernels(self.bulk(t), t, t, mult_values)
    }

    /// The kernels of an implicit time step: the effective bulk kernel `effective` (stiffness,
    /// mass and predictor) in place of the stiffness, the boundary loads and crack pressure at
    /// `t_load`, the Dirichlet multiplier values `mult_values` and the linear relations at
    /// `t_constraint` (the end of the step).
    pub fn dynamic_kernels<'s>(
        &'s self,
        effective: EffectiveKernel<'s>,
        t_load: f64,
        t_constraint: f64,
        mult_values: &'s [f64],
    ) -> FixedKernels<'s> {
        self.fixed_kernels(Bulk::Effective(Box::new(effective)), t_load, t_constraint, mult_values)
    }

    /// The bulk kernel (stiffness and body forces) at load factor or time `t`: the plain one
    /// without cracks, the enriched one with.
    pub fn bulk<'s>(&'s self, t: f64) -> Bulk<'s> {
        let model = self.model;
        let mesh = model.mesh;
        if self.enriched {
            Bulk::Xfem(XfemBulkKernel {
                mesh,
                enrichment: &model.enrichment,
                cracks: &model.cracks,
                analysis: model.analysis,
                cell_material: &model.cell_material,
                side_materials: &model.side_materials,
                materials: &model.materials,
                cell_body_force: &model.cell_body_force,
                body_forces: &model.body_forces,
                quadrature: model.xfem_quadrature,
                t,
            })
        } else {
            Bulk::Plain(BulkKernel {
                mesh,
                dofs: &self.dofs,
                analysis: model.analysis,
                cell_material: &model.cell_material,
                materials: &model.materials,
                cell_body_force: &model.cell_body_force,
                body_forces: &model.body_forces,
                t,
            })
        }
    }

    fn fixed_kernels<'s>(
        &'s self,
        bulk: Bulk<'s>,
        t: f64,
        t_constraint: f64,
        mult_values: &'s [f64],
    ) -> FixedKernels<'s> {
        let model = self.model;
        let mesh = model.mesh;
        FixedKernels {
            bulk,
            traction: TractionKernel {
                mesh,
                dofs: &self.dofs,
                faces: &model.faces,
                face_load: &model.face_load,
                loads: &model.loads,
                t,
            },
            pressure: CrackPressureKernel {
                mesh,
                enrichment: &model.enrichment,
                cracks: &model.cracks,
                facets: &self.pressure_facets,
                pressure: &model.crack_pressure,
                t,
            },
            multipliers: ConstraintKernel {
                dirichlet: DirichletMultiplierKernel { rows: &self.mult_rows, values: mult_values },
                relations: RelationKernel {
                    relations: &model.relations,
                    first: self.rel_first as u32,
                    t: t_constraint,
                },
            },
            dof_loads: None,
            bulk_rhs_zero: false,
        }
    }

    /// The dofs without an equation in a system of the mass alone (initial accelerations):
    /// the constrained dofs (their accelerations are prescribed), the Dirichlet and contact
    /// multipliers; the relation multipliers stay.
    pub fn mass_eliminated(&self) -> Vec<bool> {
        let mut e = self.is_constrained.clone();
        let rel = self.rel_first..self.rel_first + self.model.relations.len();
        for block in &self.dofs.blocks {
            if block.kind.is_multiplier() {
                for d in block.start..block.start + block.len {
                    e[d] = !rel.contains(&d);
                }
            }
        }
        e
    }

    /// The contact kernel for a state, a dof vector and a pairing (models with contact).
    pub fn contact_kernel<'s>(
        &'s self,
        state: &'s [PointState],
        u: &'s [f64],
        pairing: Option<&'s Pairing>,
    ) -> Option<ContactKernel<'s>> {
        self.contact.map(|c| ContactKernel {
            mesh: self.model.mesh,
            enrichment: &self.model.enrichment,
            cracks: &self.model.cracks,
            points: &c.points,
            state,
            u,
            pairing,
            live_thresholds: false,
        })
    }

    /// The pairing of the large-sliding contact points for the dof vector `u`, with the
    /// initial contact zone of each meshed pair ([`Self::initial_zone`]).
    pub fn pair(&self, u: &[f64]) -> Pairing {
        self.pair_in(u, &self.initial_zone())
    }

    /// [`Self::pair`] with the contact zones `zone` (per contact crack, the threshold on
    /// the reference gap: `contact::zone`; empty: every paired point).
    pub fn pair_in(&self, u: &[f64], zone: &[f64]) -> Pairing {
        let c = self.contact.expect("large sliding has contact");
        let m = self.model;
        pair(m.mesh, &m.enrichment, &m.cracks, &c.points, u, &self.pairing_options, zone)
    }

    /// The initial contact zone of every contact crack (`contact::zone::initial_gap`).
    pub fn initial_zone(&self) -> Vec<f64> {
        let dim = self.model.mesh.dim;
        self.contact.map_or_else(Vec::new, |c| {
            c.points.cracks.iter().map(|cc| crate::contact::zone::initial_gap(cc, dim)).collect()
        })
    }

    /// The layout (pattern, colouring) of every kernel, with the contact elements of a
    /// pairing.
    pub fn build_layout(&self, pairing: Option<&Pairing>, state: &[PointState]) -> SystemLayout {
        let n_total = self.dofs.n_total();
        let zero_u = vec![0.0; n_total];
        let mult_zero = vec![0.0; self.mult_rows.len()];
        let fixed = self.kernels(1.0, &mult_zero);
        let ck = self.contact_kernel(state, &zero_u, pairing);
        let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
        if let Some(ck) = &ck {
            kernels.push(ck);
        }
        SystemLayout::build(n_total, self.dofs.n_primal(), &self.eliminated, &kernels)
    }

    /// The layout for distributed assembly (PETSc backend): the cells partitioned among
    /// the MPI ranks by METIS (`super::petsc::partition`, cut and enriched cells weighted
    /// by the square of their dofs, the cost of their element matrix), each rank owning the
    /// equations of its nodes (a node's owner: the lowest rank among its cells; an enriched
    /// dof: its node's) and assembling its own elements straight into the backend's matrix
    /// ([`SystemLayout::build_distributed`]: no pattern on any rank). With contact the
    /// contact kernel (with `pairing` and `state`, as [`Self::build_layout`]) is in the
    /// layout, and each contact facet (its points) is assembled by the rank of its cell;
    /// the multiplier-only packets by the last rank's rule of `partition::element_owners`
    /// (rank 0). `Ok(None)` with the faer backend or without the `petsc` feature.
    /// Collective with PETSc: every rank calls it.
    ///
    /// `partition::element_owners`: super::petsc::partition::element_owners
    pub fn build_layout_owned(
        &self,
        pairing: Option<&Pairing>,
        state: &[PointState],
    ) -> Result<Option<SystemLayout>, SolveError> {
        self.layout_owned(pairing, state, true)
    }

    /// [`Self::build_layout_owned`] without recording its partition and matrix entries for
    /// `summary.json` (a second system of the same run: the dynamics driver's position
    /// correction, on the same partition).
    pub fn build_layout_owned_unrecorded(
        &self,
        pairing: Option<&Pairing>,
        state: &[PointState],
    ) -> Result<Option<SystemLayout>, SolveError> {
        self.layout_owned(pairing, state, false)
    }

    fn layout_owned(
        &self,
        pairing: Option<&Pairing>,
        state: &[PointState],
        record: bool,
    ) -> Result<Option<SystemLayout>, SolveError> {
        if !self.distributes() {
            return Ok(None);
        }
        let n_total = self.dofs.n_total();
        let mult_zero = vec![0.0; self.mult_rows.len()];
        let fixed = self.kernels(1.0, &mult_zero);
        let zero_u = if self.contact.is_some() { vec![0.0; n_total] } else { vec![] };
        let ck = self.contact_kernel(state, &zero_u, pairing);
        let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
        if let Some(ck) = &ck {
            kernels.push(ck);
        }
        self.owned_layout(&kernels, &self.eliminated, ck.is_some(), record)
    }

    /// Whether the layouts are distributed among MPI ranks (the PETSc backend):
    /// [`Self::build_layout_owned`] gives one.
    pub fn distributes(&self) -> bool {
        cfg!(feature = "petsc") && matches!(self.backend, Backend::Petsc(_))
    }

    /// [`Self::build_layout_owned`] for any `kernels` whose first is over the cells (its
    /// dofs those of the bulk kernel: the partition's weights) and `eliminated` dofs (the
    /// dynamics driver's mass matrix: [`Self::mass_eliminated`]); with `contact` the last
    /// kernel is the contact kernel, its facets assembled by their cell's rank. `record`:
    /// the partition and the matrix entries per rank go to `summary.json`
    /// (`partition::record`). `Ok(None)` with the faer backend. Collective with PETSc.
    pub fn owned_layout(
        &self,
        kernels: &[&dyn Kernel],
        eliminated: &[bool],
        contact: bool,
        record: bool,
    ) -> Result<Option<SystemLayout>, SolveError> {
        #[cfg(not(feature = "petsc"))]
        let _ = (kernels, eliminated, contact, record);
        #[cfg(feature = "petsc")]
        if let Backend::Petsc(_) = &self.backend {
            let bad =
                |why: String| SolveError::Linear { step: 0, error: super::linear::LinearError::Petsc(why), advice: "" };
            let (rank, size) = super::petsc::initialize().map_err(bad)?;
            let mesh = self.model.mesh;
            let n_total = self.dofs.n_total();
            let mut dofs = vec![];
            let plain = (mesh.dim * mesh.cells.first().map_or(1, |c| c.nodes().len())).max(1) as i64;
            let mut enriched = vec![false; mesh.cells.len()];
            let weights: Vec<i64> = (0..mesh.cells.len())
                .map(|c| {
                    dofs.clear();
                    kernels[0].dofs(c, &mut dofs);
                    let m = dofs.len() as i64;
                    enriched[c] = m > mesh.dim as i64 * mesh.cells[c].nodes().len() as i64;
                    ((m * m + plain * plain / 2) / (plain * plain)).max(1)
                })
                .collect();
            let part =
                super::petsc::agree(super::petsc::partition::partition_cells(mesh, &weights, size)).map_err(bad)?;
            drop(weights);
            if record {
                super::petsc::partition::record(&part, &enriched, size);
            }
            drop(enriched);
            let node_owner = super::petsc::partition::node_owners(mesh, &part);
            let n_elements: Vec<usize> = kernels.iter().map(|k| k.n_elements()).collect();
            let mut owned = super::petsc::partition::element_owners(
                &n_elements,
                &part,
                &node_owner,
                &self.dof_nodes,
                rank as u32,
                &|k, e, out| kernels[k].dofs(e, out),
            );
            // Contact: each facet's points by the rank of the facet's cell.
            let mut own_points = None;
            if let (Some(c), Some(flags)) = (self.contact, owned.last_mut().filter(|_| contact)) {
                let mut count = 0;
                for (e, (_, _, range)) in c.points.facets.iter().enumerate() {
                    let cell = c.points.points.get(range.start).map_or(usize::MAX, |p| p.cell);
                    flags[e] = part.get(cell).is_some_and(|&p| p == rank as u32);
                    if flags[e] {
                        count += range.len();
                    }
                }
                own_points = Some(count);
            }
            drop(part);
            let dof_rank: Vec<u32> = (0..n_total)
                .map(|d| match self.dof_nodes.get(d).copied() {
                    Some(n) if n != u32::MAX => node_owner[n as usize],
                    _ => 0,
                })
                .collect();
            drop(node_owner);
            // Node blocks: every aligned run of `dim` primal dofs one node's, eliminated or
            // kept as a whole, and no multipliers.
            let dim = mesh.dim;
            let n_primal = self.dofs.n_primal();
            let node_blocks = (n_primal == n_total
                && n_primal % dim == 0
                && (0..n_primal).step_by(dim).all(|d| {
                    let node = self.dof_nodes.get(d).copied().unwrap_or(u32::MAX);
                    node != u32::MAX
                        && (d..d + dim)
                            .all(|e| self.dof_nodes.get(e).copied() == Some(node) && eliminated[e] == eliminated[d])
                }))
            .then_some(dim);
            let ownership = crate::assembly::layout::Ownership {
                elements: owned,
                dof_rank,
                rank: rank as u32,
                ranks: size as u32,
                node_blocks,
            };
            let mut layout =
                SystemLayout::build_distributed(n_total, self.dofs.n_primal(), eliminated, kernels, ownership);
            if let Some(rows) = layout.distributed.as_mut() {
                if record {
                    super::petsc::partition::record_assembly(own_points, rows.nnz_total);
                }
                let mut total = [rows.nnz_total as f64];
                super::petsc::sum_over_ranks(&mut total).map_err(bad)?;
                rows.nnz_total = total[0] as usize;
            }
            return Ok(Some(layout));
        }
        Ok(None)
    }

    /// The symbolic analysis of a layout: with the node of every primal equation (for the
    /// nested-dissection ordering), condensed onto the crack unknowns for contact.
    pub fn analyse(&self, layout: &SystemLayout, step: usize) -> Result<LinearSolver, SolveError> {
        self.analyse_with(layout, step, self.condense)
    }

    /// Whether [`Self::analyse`] condenses onto the crack unknowns.
    pub fn condenses(&self) -> bool {
        self.condense
    }

    /// [`Self::analyse`], condensed onto the crack unknowns only when `condense` (and
    /// there is contact with multipliers).
    pub fn analyse_with(&self, layout: &SystemLayout, step: usize, condense: bool) -> Result<LinearSolver, SolveError> {
        let mesh = self.model.mesh;
        let n_std = mesh.dim * mesh.n_nodes();
        let mut point_of_eq = vec![NO_POINT; layout.n_eq];
        for (d, &q) in layout.eq_of_dof.iter().enumerate() {
            if q != NO_EQ && d < self.dof_nodes.len() {
                point_of_eq[q as usize] = self.dof_nodes[d];
            }
        }
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &mesh.nodes, dim: mesh.dim };
        let (pattern, n_primal) = (&layout.pattern, layout.n_primal_eq);
        // The displacement component of every standard equation (the PETSc backend's
        // rigid-body modes; enriched unknowns and multipliers have none).
        let mut component = vec![u8::MAX; layout.n_eq];
        for (d, &q) in layout.eq_of_dof.iter().enumerate().take(n_std) {
            if q != NO_EQ {
                component[q as usize] = (d % mesh.dim) as u8;
            }
        }
        let structure = SystemStructure {
            method: self.linear,
            pattern,
            n_primal,
            points: Some(&points),
            condense: None,
            ordering: self.ordering,
            memory_limit: None,
            reuse: self.reuse.as_deref(),
            precision: self.precision,
        };
        #[cfg(feature = "petsc")]
        if let Some(rows) = &layout.distributed {
            return LinearSolver::analyse_distributed(&self.backend, &structure, Some(&component), rows)
                .map_err(|error| SolveError::Linear { step, error, advice: "" });
        }
        if condense && self.condense {
            // In small sliding the contact terms involve only the enriched dofs of the contact
            // elements (the jump of a standard shape function is zero): the standard dofs and
            // the other enriched ones stay in the bulk. (The multiplier couplings mark them
            // too; a law without multipliers, the penalty, has only this.)
            let mut touched = vec![false; layout.eq_of_dof.len()];
            if let Some(ck) = self.contact_kernel(&[], &[], None) {
                let mut dofs = Vec::new();
                for e in 0..ck.n_elements() {
                    dofs.clear();
                    ck.dofs(e, &mut dofs);
                    for &d in &dofs {
                        if let Some(t) = touched.get_mut(d as usize) {
                            *t = true;
                        }
                    }
                }
            }
            // A large-sliding crack couples cells anywhere along its lips: every unknown
            // varies. A meshed contact pair couples the cells owning its slave faces and the
            // master faces its pairing reaches: the contact kernel of this layout (built
            // with that pairing, last in `build_layout`'s list) names them, and a new
            // pairing that reaches other cells builds a new layout and analysis.
            let cracks = self.contact.map_or(&[][..], |c| &c.points.cracks[..]);
            let large_crack = cracks.iter().any(|cc| cc.large_sliding && cc.pair.is_none());
            if cracks.iter().any(|cc| cc.pair.is_some()) && layout.n_kernels() > 0 {
                for &d in layout.kernel_dofs(layout.n_kernels() - 1) {
                    if let Some(t) = touched.get_mut(d as usize) {
                        *t = true;
                    }
                }
            }
            let pair_cells = cracks.iter().any(|cc| cc.pair.is_some());
            let mut varying = vec![large_crack; n_primal];
            for (d, &q) in layout.eq_of_dof.iter().enumerate() {
                if q != NO_EQ && (q as usize) < n_primal && (d >= n_std || pair_cells) && touched[d] {
                    varying[q as usize] = true;
                }
            }
            let structure = SystemStructure { condense: Some(Some(&varying)), ..structure };
            let mut solver = LinearSolver::analyse_on(&self.backend, &structure, Some(&component));
            // A body pressed by a pair is usually held through the contact only.
            if let (true, Ok(s)) = (pair_cells, &mut solver) {
                s.expect_floating_bulk();
            }
            solver
        } else {
            LinearSolver::analyse_on(&self.backend, &structure, Some(&component))
        }
        .map_err(|error| SolveError::Linear { step, error, advice: "" })
    }

    /// The bulk, boundary and contact forces on the constrained dofs (by dof; other entries
    /// are partial sums). Only the elements that touch a constrained dof are computed.
    pub fn constrained_forces(
        &self,
        layout: &SystemLayout,
        fixed: &FixedKernels<'_>,
        contact: Option<&ContactKernel<'_>>,
        u: &[f64],
    ) -> Vec<f64> {
        let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
        let mut include = vec![true, true, true, false];
        if let Some(ck) = contact {
            kernels.push(ck);
            include.push(true);
        }
        if self.constrained.is_empty() {
            // No element touches a constrained dof: a pass over the elements for nothing.
            return vec![0.0; u.len()];
        }
        let mut forces = layout.element_forces_touching(&kernels, &include, Some(&self.is_constrained), u);
        #[cfg(feature = "petsc")]
        if layout.is_distributed() {
            // Each rank computed its own elements: the constrained dofs' sums over the ranks.
            let mut on: Vec<f64> = self.constrained.iter().map(|&d| forces[d]).collect();
            super::petsc::sum_over_ranks(&mut on).expect("PETSc is initialised: the layout is distributed");
            for (&d, f) in self.constrained.iter().zip(on) {
                forces[d] = f;
            }
        }
        if let Some(g) = fixed.dof_loads {
            for (f, gd) in forces.iter_mut().zip(g) {
                *f -= gd;
            }
        }
        forces
    }

    /// [`Self::constrained_forces`] on a distributed layout from this rank's elements only
    /// (`SystemLayout::element_forces_touching`: the bulk cells, boundary faces and contact
    /// facets it assembles, its share of [`FixedKernels::dof_loads`]), summed over the
    /// ranks: the same forces on every rank, each element computed once (the dynamics
    /// driver, whose ranks hold the element matrices of their own cells only). Otherwise
    /// [`Self::constrained_forces`]. Collective on a distributed layout.
    pub fn constrained_forces_of_ranks(
        &self,
        layout: &SystemLayout,
        fixed: &FixedKernels<'_>,
        contact: Option<&ContactKernel<'_>>,
        u: &[f64],
    ) -> Result<Vec<f64>, SolveError> {
        if !layout.is_distributed() {
            return Ok(self.constrained_forces(layout, fixed, contact, u));
        }
        let mut kernels: Vec<&dyn Kernel> = fixed.list().to_vec();
        let mut include = vec![true, true, true, false];
        if let Some(ck) = contact {
            kernels.push(ck);
            include.push(true);
        }
        if self.constrained.is_empty() {
            return Ok(vec![0.0; u.len()]);
        }
        let mut forces = layout.element_forces_touching(&kernels, &include, Some(&self.is_constrained), u);
        if let Some(g) = fixed.dof_loads {
            for (f, gd) in forces.iter_mut().zip(g) {
                *f -= gd;
            }
        }
        #[cfg(feature = "petsc")]
        super::petsc::sum_over_ranks(&mut forces).map_err(|why| SolveError::Linear {
            step: 0,
            error: super::linear::LinearError::Petsc(why),
            advice: "",
        })?;
        Ok(forces)
    }

    /// Reactions: the sum of the bulk, boundary and contact forces on the constrained dofs,
    /// per Dirichlet group (only the elements that touch a constrained dof are computed).
    pub fn reactions(
        &self,
        layout: &SystemLayout,
        fixed: &FixedKernels<'_>,
        contact: Option<&ContactKernel<'_>>,
        u: &[f64],
    ) -> Vec<[f64; 3]> {
        let forces = self.constrained_forces(layout, fixed, contact, u);
        self.reactions_of(&forces, u)
    }

    /// The reactions per Dirichlet group from the forces on the constrained dofs
    /// ([`Self::constrained_forces`]), with the relations' reactions.
    pub fn reactions_of(&self, forces: &[f64], u: &[f64]) -> Vec<[f64; 3]> {
        let dim = self.model.mesh.dim;
        let mut reactions = vec![[0.0; 3]; self.model.dirichlet_groups.len()];
        let n_std = dim * self.model.mesh.n_nodes();
        // The standard rows only: their sum over the supports balances the loads (a rigid
        // translation has zero enriched coefficients); the enriched rows held on cut faces
        // carry generalized forces of the enrichment functions, no resultant.
        for &d in self.constrained.iter().take_while(|&&d| d < n_std) {
            let g = self.model.dirichlet[self.cond_of_dof[d] as usize].group as usize;
            reactions[g][d % dim] += forces[d];
        }
        let support = |d: usize| {
            (d < n_std && self.cond_of_dof[d] != u32::MAX)
                .then(|| self.model.dirichlet[self.cond_of_dof[d] as usize].group as usize)
        };
        relations::add_reactions(&self.model.relations, self.rel_first, u, dim, &support, &mut reactions);
        reactions
    }
}

/// The bulk kernel of a model: the plain one without cracks, the enriched one with, or
/// the effective one of an implicit time step.
pub enum Bulk<'a> {
    Plain(BulkKernel<'a>),
    Xfem(XfemBulkKernel<'a>),
    Effective(Box<EffectiveKernel<'a>>),
}

impl Kernel for Bulk<'_> {
    fn n_elements(&self) -> usize {
        match self {
            Bulk::Plain(k) => k.n_elements(),
            Bulk::Xfem(k) => k.n_elements(),
            Bulk::Effective(k) => k.n_elements(),
        }
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        match self {
            Bulk::Plain(k) => k.dofs(e, out),
            Bulk::Xfem(k) => k.dofs(e, out),
            Bulk::Effective(k) => k.dofs(e, out),
        }
    }
    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>) {
        match self {
            Bulk::Plain(k) => k.compute(e, dofs, out),
            Bulk::Xfem(k) => k.compute(e, dofs, out),
            Bulk::Effective(k) => k.compute(e, dofs, out),
        }
    }
}

/// The assembled system: the layout, its solver, the values of K (fixed kernels) and the
/// load vector of the current step, and the equations' unknowns.
pub struct System {
    pub layout: SystemLayout,
    pub solver: LinearSolver,
    pub values: Vec<f64>,
    pub rhs: Vec<f64>,
    pub x: Vec<f64>,
    /// `values` holds K (and, without contact, its factor is computed).
    pub k_assembled: bool,
    /// `values` and `rhs` hold the first step's K and f, assembled during the symbolic
    /// analysis ([`System::prefilled`]) and not yet factorised: the first linear step
    /// factorises them without assembling again (with contact: the contact loops' first
    /// pass takes them as K, the contact terms not included).
    pub prefilled: bool,
    /// Incremented at every assembly of `values` (K): the identity of K's values for a
    /// carried factor ([`CarriedFactor`]; the contact loops add their terms in place and
    /// restore K exactly).
    pub values_generation: u64,
    /// A condensed factor lost accuracy: the plain LDLᵀ is used from then on.
    pub plain_fallback: bool,
    /// Keep the contact tangent's factor from one step to the next
    /// ([`System::carried`]): set by the time-step driver, whose effective matrix does not
    /// change between steps (the quasi-static driver starts every step afresh).
    pub carry_factor: bool,
    /// The factor the solver holds at the end of the last contact step, when
    /// `carry_factor`: the next step's Newton loop reuses it while the statuses and
    /// thresholds are those it was computed with and K is unchanged.
    pub carried: Option<CarriedFactor>,
}

/// What identifies the contact tangent a solver's factor was computed from, kept across
/// steps ([`System::carry_factor`]): the statuses and friction thresholds of every point
/// (the Newton loop's signature) and the generation of K's values
/// ([`System::values_generation`]: the matrix without the contact terms, one per
/// assembly). Same signature and generation, on the same layout and solver and with the
/// same pairing: same matrix, no refactorisation. Cleared on a rebuild, on a new
/// solver (plain fallback) and on every re-pairing of a large-sliding crack.
#[derive(Debug, Clone, PartialEq)]
pub struct CarriedFactor {
    pub signature: Vec<(u8, u64)>,
    pub bulk_generation: u64,
}

/// A checksum of a matrix's values (every bit of every value, in order): a change of K,
/// e.g. of ρ or of the scheme's coefficients in the effective matrix, changes it. (The
/// carried factor identifies K by [`System::values_generation`], O(1) a step.)
pub fn values_checksum(values: &[f64]) -> u64 {
    // A multiply-rotate hash over the 64-bit words (the rotation carries the high bits of
    // each product down), then a final avalanche (splitmix64).
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in values {
        h = (h.rotate_left(23) ^ v.to_bits()).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    h ^= h >> 30;
    h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h ^= h >> 27;
    h = h.wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

impl System {
    pub fn new(layout: SystemLayout, solver: LinearSolver) -> System {
        let (values, rhs) = (vec![0.0; layout.pattern.nnz()], vec![0.0; layout.n_eq]);
        System { values, rhs, ..System::new_empty(layout, solver) }
    }

    /// A system whose `values` and `rhs` already hold the first step's K and f (the
    /// driver assembles them while the symbolic analysis runs).
    pub fn prefilled(layout: SystemLayout, solver: LinearSolver, values: Vec<f64>, rhs: Vec<f64>) -> System {
        debug_assert_eq!(values.len(), layout.pattern.nnz());
        debug_assert_eq!(rhs.len(), layout.n_eq);
        System { values, rhs, prefilled: true, ..System::new_empty(layout, solver) }
    }

    fn new_empty(layout: SystemLayout, solver: LinearSolver) -> System {
        System {
            values: vec![],
            rhs: vec![],
            x: vec![0.0; layout.n_eq],
            layout,
            solver,
            k_assembled: false,
            prefilled: false,
            values_generation: 0,
            plain_fallback: false,
            carry_factor: false,
            carried: None,
        }
    }

    /// A new layout and its solver (the pairing coupled other cells): K must be assembled
    /// again.
    pub fn rebuild(&mut self, layout: SystemLayout, solver: LinearSolver) {
        self.values = vec![0.0; layout.pattern.nnz()];
        self.layout = layout;
        self.solver = solver;
        self.k_assembled = false;
        self.prefilled = false;
        self.carried = None;
    }

    /// An error naming the first equation of the load vector that is not finite.
    pub fn check_rhs(&self, step: usize) -> Result<(), SolveError> {
        match self.rhs.iter().position(|v| !v.is_finite()) {
            Some(bad) => {
                Err(SolveError::NonFinite { what: format!("the load vector (equation {bad}) at step {step}") })
            }
            None => Ok(()),
        }
    }
}

/// Per crack of the model: whether its sides move independently (no contact law on it),
/// for the rigid-body check ([`crate::physics::constraints::CrackedBody`]).
pub fn separating_cracks(n_cracks: usize, contact: Option<&ContactSetup>) -> Vec<bool> {
    let mut sep = vec![true; n_cracks];
    for cc in contact.iter().flat_map(|c| &c.points.cracks) {
        if let Some(s) = sep.get_mut(cc.crack) {
            *s = false;
        }
    }
    sep
}
