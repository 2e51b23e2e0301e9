//! Physics on elements: materials and the element kernels that compute local
//! matrices and vectors.
//!
//! Entry points: [`model::Model`] (the resolved problem), [`material::Isotropic`],
//! [`elasticity::BulkKernel`], [`elasticity::TractionKernel`], [`constraints::check_rigid_modes`],
//! [`relations::Relation`] (linear relations and lip conditions, with multipliers),
//! [`inertia::MassKernel`] (the consistent mass with the enriched basis),
//! [`side_materials::SideMaterials`] (one material per side of cut cells on a material boundary),
//! [`held_faces::held_enriched`] (the enriched unknowns a Dirichlet condition holds on the faces a
//! crack cuts).

pub mod constraints;
pub mod elasticity;
pub mod held_faces;
pub mod inertia;
pub mod material;
pub mod model;
pub mod relations;
pub mod side_materials;
pub mod xfem;
