//! The resolved problem: every load, material and condition attached to mesh entities
//! (cells, faces, nodes), ready for the solver. Built from a case file and a mesh by
//! [`crate::run`]; read-only afterwards.
//!
//! Entry point: [`Model`].

use super::elasticity::{FaceLoad, Vector};
use super::material::{Analysis, Isotropic};
use super::relations::Relation;
use super::side_materials::SideMaterials;
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
    /// Mass density of each material (same order as `materials`; `None`: not given, which
    /// only a dynamic run refuses).
    pub densities: Vec<Option<f64>>,
    pub cell_material: Vec<u32>,
    /// The materials of the two sides of cut cells whose crack follows a material boundary
    /// ([`SideMaterials::along_cracks`]; empty without cracks or with one material).
    pub side_materials: SideMaterials,
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

impl Model<'_> {
    /// The material at a point of cell `c` on `side` (the sub-cell side of the cut rules,
    /// `None` off the cut; [`SideMaterials::index`]).
    pub fn material_at(&self, c: usize, side: Option<i8>) -> Isotropic {
        self.materials[self.side_materials.index(&self.cell_material, c, side) as usize]
    }

    /// The Young's moduli of the two sides of cell `c` (`[−, +]`; equal off the cut cells
    /// with per-side materials).
    pub fn side_youngs(&self, c: usize) -> [f64; 2] {
        match self.side_materials.of_cell(c) {
            Some([m, p]) => [self.materials[m as usize].young, self.materials[p as usize].young],
            None => [self.materials[self.cell_material[c] as usize].young; 2],
        }
    }

    /// Reads every load and prescribed value as a function of time (dynamics): numbers stay
    /// constant instead of being ramped by the load factor ([`Scalar::of_time`]).
    pub fn loads_of_time(&mut self) {
        let conv = |s: &mut Scalar| *s = std::mem::replace(s, Scalar::Const(0.0)).of_time();
        for b in &mut self.body_forces {
            b.iter_mut().for_each(conv);
        }
        for l in &mut self.loads {
            match l {
                FaceLoad::Traction(v) => v.iter_mut().for_each(conv),
                FaceLoad::Pressure(p) => conv(p),
            }
        }
        for d in &mut self.dirichlet {
            conv(&mut d.value);
        }
        for r in &mut self.relations {
            conv(&mut r.value);
        }
        for p in self.crack_pressure.iter_mut().flatten() {
            conv(p);
        }
    }
}
