//! Helpers of the dynamics tests (tests/dynamics_*.rs): a model and its contact set-up
//! from a case text, and the momentum weights of a part of the body.
//!
//! Entry points: [`build`], [`momentum_weights`].

use fissure::assembly::{Kernel, LocalOut};
use fissure::case::{resolve, Case};
use fissure::contact::ContactSetup;
use fissure::mesh::Mesh;
use fissure::physics::inertia::ProjectedField;
use fissure::physics::model::Model;
use fissure::solve::dynamics::mass_kernel;
use std::path::Path;

/// The parsed case of `text` (named `name` in error messages) and its mesh; build the model
/// with [`model_and_contact`] (the model borrows the mesh).
pub fn build(text: &str, name: &str) -> (Case, Mesh) {
    let case = Case::parse(text, Path::new(name)).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    (case, mesh)
}

/// The model of `case` on `mesh` and its contact set-up (None without contact cracks).
pub fn model_and_contact<'m>(case: &Case, mesh: &'m Mesh) -> (Model<'m>, Option<ContactSetup>) {
    let model = resolve::build_model(case, mesh).unwrap();
    let contact = resolve::build_contact(case, &model).unwrap();
    (model, contact)
}

/// The weights b with bᵀ v the momentum of the part of the body where `indicator` is 1
/// (along the direction it gives): b_k = ∫ ρ ψ_k g, the mass kernel's projection load of
/// the indicator g, over every primal dof (standard and enriched).
pub fn momentum_weights(model: &Model<'_>, densities: &[f64], indicator: &ProjectedField<'_>) -> Vec<f64> {
    let kernel = fissure::physics::inertia::MassKernel { field: Some(indicator), ..mass_kernel(model, densities) };
    let mut b = vec![0.0; model.enrichment.dofs.n_total()];
    for e in 0..kernel.n_elements() {
        let mut dofs = vec![];
        kernel.dofs(e, &mut dofs);
        let mut f = vec![0.0; dofs.len()];
        kernel.compute(e, &dofs, LocalOut { matrix: None, vector: Some(&mut f) });
        for (d, v) in dofs.iter().zip(&f) {
            b[*d as usize] += v;
        }
    }
    b
}
