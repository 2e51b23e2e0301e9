//! The resolved problem: every load, material and condition attached to mesh entities
//! (cells, faces, nodes), ready for the solver. Built from a case file and a mesh by
//! [`crate::run`]; read-only afterwards.
//!
//! Entry point: [`Model`].

use super::elasticity::{FaceLoad, Vector};
use super::material::{Analysis, Isotropic};
use super::relations::Relation;
use super::xfem::XfemQuadrature;
use crate::enrich::{CrackGeometry, Enrichment};
use crate::formula::Scalar;
use crate::mesh::{Face, Mesh};

/// One prescribed displacement component at one node.
#[derive(Debug, Clone)]
pub struct DirichletCondition {
    pub node: usize,
    pub component: usize,
    pub value: Scalar,
    /// Index into [`Model::dirichlet_groups`] (for reaction sums).
    pub group: u32,
}

/// How Dirichlet conditions enter the linear system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DirichletMethod {
    /// Prescribed dofs are removed from the unknowns (symmetric positive definite system).
    Eliminate,
    /// One Lagrange multiplier per prescribed dof (symmetric indefinite saddle point).
    Multiplier,
}

/// A linear elastic problem on a mesh.
#[derive(Debug, Clone)]
pub struct Model<'a> {
    pub mesh: &'a Mesh,
    pub analysis: Analysis,
    pub materials: Vec<Isotropic>,
    pub cell_material: Vec<u32>,
    pub body_forces: Vec<Vector>,
    pub cell_body_force: Vec<Option<u32>>,
    pub faces: Vec<Face>,
    pub face_load: Vec<u32>,
    pub loads: Vec<FaceLoad>,
    pub dirichlet: Vec<DirichletCondition>,
    pub dirichlet_groups: Vec<String>,
    pub dirichlet_method: DirichletMethod,
    /// Linear relations between unknowns (lip conditions, `[[relations]]`), enforced
    /// with multipliers.
    pub relations: Vec<Relation>,
    /// Load factor of each step, in order (the last is usually 1).
    pub load_factors: Vec<f64>,
    /// Cracks (level sets and cut geometry), in case-file order.
    pub cracks: Vec<CrackGeometry>,
    /// Enriched dofs of the cracks ([`Enrichment::none`] without cracks).
    pub enrichment: Enrichment,
    /// Pressure on the faces of each crack (same order as `cracks`).
    pub crack_pressure: Vec<Option<Scalar>>,
    pub xfem_quadrature: XfemQuadrature,
}
