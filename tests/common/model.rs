//! Building models in code for the verification tests (loads, supports, rates).

use fissure::formula::{Formula, Scalar};
use fissure::mesh::Mesh;
use fissure::physics::elasticity::FaceLoad;
use fissure::physics::material::{Analysis, Isotropic};
use fissure::physics::model::{DirichletCondition, DirichletMethod, Model};
use std::collections::BTreeMap;

/// Nodes on the boundary of the mesh.
pub fn boundary_nodes(mesh: &Mesh) -> Vec<usize> {
    let mut v: Vec<usize> = mesh.boundary_faces().iter().flat_map(|f| f.nodes().to_vec()).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// A formula with the given parameters.
pub fn formula(src: &str, params: &[(&str, f64)]) -> Scalar {
    let p: BTreeMap<String, f64> = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    Scalar::Formula(Formula::parse(src, &p).expect("test formula parses"))
}

/// A one-material model with no loads and no conditions, one load step at t = 1.
pub fn bare_model<'m>(mesh: &'m Mesh, analysis: Analysis, material: Isotropic) -> Model<'m> {
    Model {
        mesh,
        analysis,
        materials: vec![material],
        densities: vec![None],
        cell_material: vec![0; mesh.n_cells()],
        side_materials: Default::default(),
        body_forces: vec![],
        cell_body_force: vec![None; mesh.n_cells()],
        faces: vec![],
        face_load: vec![],
        loads: vec![],
        dirichlet: vec![],
        dirichlet_groups: vec![],
        dirichlet_method: DirichletMethod::Eliminate,
        relations: vec![],
        load_factors: vec![1.0],
        cracks: vec![],
        enrichment: fissure::enrich::Enrichment::none(mesh),
        crack_pressure: vec![],
        xfem_quadrature: Default::default(),
    }
}

/// Prescribes `value[c]` on every listed node for every component `c < dim`.
pub fn fix_nodes(model: &mut Model<'_>, group: &str, nodes: &[usize], value: &[Scalar]) {
    let g = model.dirichlet_groups.len() as u32;
    model.dirichlet_groups.push(group.to_string());
    for &n in nodes {
        for (c, v) in value.iter().enumerate().take(model.mesh.dim) {
            model.dirichlet.push(DirichletCondition { node: n, component: c, value: v.clone(), group: g });
        }
    }
}

/// Adds a body force on every cell.
pub fn body_force(model: &mut Model<'_>, value: [Scalar; 3]) {
    model.body_forces.push(value);
    model.cell_body_force = vec![Some(0); model.mesh.n_cells()];
}

/// Adds a face load on the faces of a group.
pub fn face_load(model: &mut Model<'_>, group: &str, load: FaceLoad) {
    let k = model.loads.len() as u32;
    let faces = model.mesh.group_faces(group).expect("face group exists").to_vec();
    model.face_load.extend(std::iter::repeat_n(k, faces.len()));
    model.faces.extend(faces);
    model.loads.push(load);
}

/// Convergence rate between successive (h, error) pairs.
pub fn rates(h: &[f64], e: &[f64]) -> Vec<f64> {
    (1..h.len()).map(|k| (e[k - 1] / e[k]).ln() / (h[k - 1] / h[k]).ln()).collect()
}
