//! Linear elasticity kernels: the bulk stiffness with body forces, boundary tractions
//! and pressures, and Dirichlet conditions enforced by Lagrange multipliers.
//!
//! Entry points: [`BulkKernel`], [`TractionKernel`], [`DirichletMultiplierKernel`].
//!
//! Local dofs are node-major: `[u_0x, u_0y, (u_0z), u_1x, ...]`. Loads follow the
//! ramp convention of [`crate::formula::Scalar::eval_load`].

use crate::assembly::{DofMap, Kernel, LocalOut};
use crate::element::{self, MAX_NODES};
use crate::formula::Scalar;
use crate::mesh::{Face, Mesh};
use crate::physics::material::{Analysis, Isotropic};

/// Body force density per unit volume, one value per component.
pub type Vector = [Scalar; 3];

/// The bulk stiffness of every cell, with optional body forces.
pub struct BulkKernel<'a> {
    pub mesh: &'a Mesh,
    pub dofs: &'a DofMap,
    pub analysis: Analysis,
    /// Material of each cell (index into `materials`).
    pub cell_material: &'a [u32],
    pub materials: &'a [Isotropic],
    /// Body force of each cell (index into `body_forces`), if any.
    pub cell_body_force: &'a [Option<u32>],
    pub body_forces: &'a [Vector],
    /// Load factor of the step.
    pub t: f64,
}

/// Quadrature degree for the bulk stiffness of a cell type.
fn bulk_degree(kind: element::CellType, with_body_force: bool) -> usize {
    match (kind.is_simplex(), with_body_force) {
        (true, false) => 1,
        (true, true) => 2,
        (false, _) => 3,
    }
}

impl Kernel for BulkKernel<'_> {
    fn n_elements(&self) -> usize {
        self.mesh.cells.len()
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        for &n in self.mesh.cells[e].nodes() {
            for c in 0..self.dofs.dim {
                out.push(self.dofs.node_dof(n, c) as u32);
            }
        }
    }

    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let dim = self.mesh.dim;
        let kind = self.mesh.cells[e].kind;
        let mut xs = [[0.0; 3]; MAX_NODES];
        let nn = self.mesh.cell_coords(e, &mut xs);
        let m = nn * dim;
        let mat = self.materials[self.cell_material[e] as usize];
        let (lam, mu) = (mat.lambda_in_plane(self.analysis), mat.mu());
        let bf =
            self.cell_body_force[e].map(|i| &self.body_forces[i as usize]).filter(|b| b.iter().any(|s| !s.is_zero()));
        let want_f = out.vector.is_some() && bf.is_some();
        let rule = kind.quadrature(bulk_degree(kind, want_f));
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        let mut g = [[0.0; 3]; MAX_NODES];
        let LocalOut { matrix, vector } = out;
        let mut matrix = matrix;
        let mut vector = if want_f { vector } else { None };
        if matrix.is_none() && vector.is_none() {
            return;
        }
        for (xi, w) in rule.iter() {
            element::shape(kind, xi, &mut n, &mut dn);
            // Meshes are validated before assembly: a failure here is a bug.
            let det = element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut g).unwrap_or(0.0);
            let wd = w * det;
            if let Some(k) = matrix.as_deref_mut() {
                add_isotropic_stiffness(k, &g[..nn], dim, lam, mu, wd);
            }
            if let (Some(f), Some(b)) = (vector.as_deref_mut(), bf) {
                let x = element::map_point(&n[..nn], &xs[..nn]);
                for i in 0..dim {
                    let bi = b[i].eval_load(x, self.t);
                    if bi == 0.0 {
                        continue;
                    }
                    for a in 0..nn {
                        f[a * dim + i] += wd * n[a] * bi;
                    }
                }
            }
        }
        if let Some(k) = matrix {
            mirror_lower(k, m);
        }
    }
}

/// Adds `wd · (λ g_a ⊗ g_b + μ g_b ⊗ g_a + μ (g_a · g_b) I)` for scalar basis gradients
/// `g` to the lower blocks (b ≤ a) of the row-major local matrix `k` (basis-major dofs,
/// `m = g.len() * dim`). Call [`mirror_lower`] once after the last point.
#[inline]
pub fn add_isotropic_stiffness(k: &mut [f64], g: &[[f64; 3]], dim: usize, lam: f64, mu: f64, wd: f64) {
    let m = g.len() * dim;
    for (a, ga) in g.iter().enumerate() {
        for (b, gb) in g.iter().enumerate().take(a + 1) {
            let dot = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
            for i in 0..dim {
                let row = (a * dim + i) * m + b * dim;
                for j in 0..dim {
                    k[row + j] += wd * (lam * ga[i] * gb[j] + mu * ga[j] * gb[i]);
                }
                k[row + i] += wd * mu * dot;
            }
        }
    }
}

/// Copies the lower triangle of a row-major `m × m` matrix into its upper triangle.
#[inline]
pub fn mirror_lower(k: &mut [f64], m: usize) {
    for r in 0..m {
        for c in (r + 1)..m {
            k[r * m + c] = k[c * m + r];
        }
    }
}

/// A load on a boundary face.
#[derive(Debug, Clone)]
pub enum FaceLoad {
    /// Traction vector (force per unit area), components x, y, z.
    Traction(Vector),
    /// Pressure: positive pushes against the outward normal (t = −p n).
    Pressure(Scalar),
}

/// Boundary tractions and pressures on faces.
pub struct TractionKernel<'a> {
    pub mesh: &'a Mesh,
    pub dofs: &'a DofMap,
    pub faces: &'a [Face],
    /// Load of each face (index into `loads`).
    pub face_load: &'a [u32],
    pub loads: &'a [FaceLoad],
    pub t: f64,
}

impl Kernel for TractionKernel<'_> {
    fn n_elements(&self) -> usize {
        self.faces.len()
    }
    fn has_matrix(&self) -> bool {
        false
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        for &n in self.faces[e].nodes() {
            for c in 0..self.dofs.dim {
                out.push(self.dofs.node_dof(n, c) as u32);
            }
        }
    }
    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let Some(f) = out.vector else { return };
        let dim = self.dofs.dim;
        let face = &self.faces[e];
        let nn = face.kind.n_nodes();
        let mut xs = [[0.0; 3]; 4];
        for a in 0..nn {
            xs[a] = self.mesh.nodes[face.nodes[a]];
        }
        let load = &self.loads[self.face_load[e] as usize];
        let mut n = [0.0; 4];
        let mut dn = [[0.0; 3]; 4];
        for (xi, w) in face.kind.quadrature(2).iter() {
            face.kind.shape(xi, &mut n, &mut dn);
            let (da, normal) = element::face_measure_and_normal(face.kind, &xs[..nn], &dn[..nn]);
            let x = element::map_point(&n[..nn], &xs[..nn]);
            let mut tr = [0.0; 3];
            match load {
                FaceLoad::Traction(v) => {
                    for i in 0..dim {
                        tr[i] = v[i].eval_load(x, self.t);
                    }
                }
                FaceLoad::Pressure(p) => {
                    let pv = p.eval_load(x, self.t);
                    for i in 0..dim {
                        tr[i] = -pv * normal[i];
                    }
                }
            }
            for a in 0..nn {
                for i in 0..dim {
                    f[a * dim + i] += w * da * n[a] * tr[i];
                }
            }
        }
    }
}

/// Dirichlet conditions `u_d = g` enforced by multipliers: element `e` couples the
/// constrained dof and its multiplier with the local matrix `[[0, 1], [1, 0]]` and the
/// vector `[0, g]`. The multiplier is minus the reaction force.
pub struct DirichletMultiplierKernel<'a> {
    /// (constrained dof, multiplier dof) per condition.
    pub rows: &'a [(u32, u32)],
    /// Prescribed value of each condition at this step.
    pub values: &'a [f64],
}

impl Kernel for DirichletMultiplierKernel<'_> {
    fn n_elements(&self) -> usize {
        self.rows.len()
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        out.extend([self.rows[e].0, self.rows[e].1]);
    }
    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        if let Some(k) = out.matrix {
            k.copy_from_slice(&[0.0, 1.0, 1.0, 0.0]);
        }
        if let Some(f) = out.vector {
            f[1] = self.values[e];
        }
    }
}
