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

/// The points of a cell gathered for [`add_isotropic_stiffness`] in one matrix product
/// (cells with many quadrature points: the tip-enriched sub-cells of X-FEM carry hundreds
/// per cell, where the point-by-point update is the assembly's cost).
///
/// With `H_(a,i),(b,j) = Σ_p wd_p g_a,i g_b,j` (one product `G_wᵀ G` of the gradients of
/// all points), the stiffness is `λ H_(a,i),(b,j) + μ H_(a,j),(b,i) + μ δ_ij Σ_k
/// H_(a,k),(b,k)`, the sum over the points of what [`add_isotropic_stiffness`] adds; only
/// the order of the additions differs.
#[derive(Default)]
pub struct StiffnessBatch {
    /// Gradients of the gathered points, column-major `n_points × (n_basis · dim)`.
    g: Vec<f64>,
    /// The same times each point's `wd`.
    gw: Vec<f64>,
    h: Vec<f64>,
    n_points: usize,
    n_basis: usize,
}

impl StiffnessBatch {
    /// Points gathered per product (bounds the buffers: `CHUNK · n_basis · dim` each).
    const CHUNK: usize = 256;

    /// Starts a cell with `n_basis` basis functions.
    pub fn start(&mut self, n_basis: usize, dim: usize) {
        self.n_basis = n_basis;
        self.n_points = 0;
        let cols = n_basis * dim;
        self.g.resize(Self::CHUNK * cols, 0.0);
        self.gw.resize(Self::CHUNK * cols, 0.0);
        self.h.clear();
        self.h.resize(cols * cols, 0.0);
    }

    /// Adds a point's gradients `g` (one per basis function) and weight `wd`.
    pub fn push(&mut self, g: &[[f64; 3]], dim: usize, wd: f64) {
        debug_assert_eq!(g.len(), self.n_basis);
        if self.n_points == Self::CHUNK {
            self.flush(dim);
        }
        let p = self.n_points;
        for (a, ga) in g.iter().enumerate() {
            for i in 0..dim {
                let at = (a * dim + i) * Self::CHUNK + p;
                self.g[at] = ga[i];
                self.gw[at] = wd * ga[i];
            }
        }
        self.n_points += 1;
    }

    /// `H += G_wᵀ G` over the gathered points.
    fn flush(&mut self, dim: usize) {
        let np = self.n_points;
        if np == 0 {
            return;
        }
        let cols = self.n_basis * dim;
        let chunk = Self::CHUNK;
        let gw = faer::MatRef::from_column_major_slice_with_stride(&self.gw, np, cols, chunk);
        let g = faer::MatRef::from_column_major_slice_with_stride(&self.g, np, cols, chunk);
        let h = faer::MatMut::from_column_major_slice_mut(&mut self.h, cols, cols);
        faer::linalg::matmul::matmul(h, faer::Accum::Add, gw.transpose(), g, 1.0, faer::Par::Seq);
        self.n_points = 0;
    }

    /// Adds the stiffness of the gathered points with Lamé constants `lam`, `mu` to the
    /// lower blocks (b ≤ a) of the row-major local matrix `k`, as
    /// [`add_isotropic_stiffness`] does, and empties the batch.
    pub fn finish(&mut self, k: &mut [f64], dim: usize, lam: f64, mu: f64) {
        self.flush(dim);
        let nb = self.n_basis;
        let m = nb * dim;
        // H is symmetric; column-major (r, c) at r + c m.
        let h = &self.h;
        for a in 0..nb {
            for b in 0..=a {
                let mut dot = 0.0;
                for q in 0..dim {
                    dot += h[(a * dim + q) + (b * dim + q) * m];
                }
                for i in 0..dim {
                    let row = (a * dim + i) * m + b * dim;
                    for j in 0..dim {
                        k[row + j] +=
                            lam * h[(a * dim + i) + (b * dim + j) * m] + mu * h[(a * dim + j) + (b * dim + i) * m];
                    }
                    k[row + i] += mu * dot;
                }
            }
        }
        self.h.iter_mut().for_each(|v| *v = 0.0);
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
