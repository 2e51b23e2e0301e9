//! Derived fields from a solution: strain, stress and von Mises per cell, averaged
//! over the cell's Gauss points.
//!
//! Entry points: [`cell_fields`], [`norms::error_norms`], and for cracked models the ParaView
//! grids of [`xfem_output`] (body on sub-cells, crack lips, level sets).
//!
//! Symmetric tensors are stored as 6 components in ParaView's order
//! `[xx, yy, zz, xy, yz, xz]` (tensor components, not engineering shear). In plane
//! strain ε_zz = 0 and σ_zz = ν(σ_xx + σ_yy); in plane stress σ_zz = 0 and
//! ε_zz = −ν/(1−ν)(ε_xx + ε_yy).

pub mod contact_output;
pub mod norms;
pub mod sif;
pub mod xfem_output;

use crate::element::{self, MAX_NODES};
use crate::mesh::Mesh;
use crate::physics::material::{von_mises, Analysis, Isotropic};
use rayon::prelude::*;

/// Per-cell fields.
#[derive(Debug, Clone, Default)]
pub struct CellFields {
    pub strain: Vec<[f64; 6]>,
    pub stress: Vec<[f64; 6]>,
    pub von_mises: Vec<f64>,
}

fn to_voigt6(t: &[[f64; 3]; 3]) -> [f64; 6] {
    [t[0][0], t[1][1], t[2][2], t[0][1], t[1][2], t[0][2]]
}

/// Strain, stress and von Mises of every cell for the standard displacement dofs `u`
/// (`u[node * dim + c]`).
pub fn cell_fields(
    mesh: &Mesh,
    analysis: Analysis,
    materials: &[Isotropic],
    cell_material: &[u32],
    u: &[f64],
) -> CellFields {
    cell_fields_of(mesh, analysis, materials, cell_material, u, None)
}

/// [`cell_fields`] of the cells `c` with `keep[c]` only, in mesh order (`None`: every cell;
/// an MPI rank's piece of the output).
pub fn cell_fields_of(
    mesh: &Mesh,
    analysis: Analysis,
    materials: &[Isotropic],
    cell_material: &[u32],
    u: &[f64],
    keep: Option<&[bool]>,
) -> CellFields {
    let dim = mesh.dim;
    // Written in place: no per-cell tuples collected and copied (at 2.7 M dofs the copy
    // was the run's peak memory, on top of the linear solver's).
    let cells: Option<Vec<usize>> =
        keep.map(|k| (0..mesh.n_cells()).filter(|&c| k.get(c).copied().unwrap_or(false)).collect());
    let nc = cells.as_ref().map_or(mesh.n_cells(), |c| c.len());
    let mut f = CellFields { strain: vec![[0.0; 6]; nc], stress: vec![[0.0; 6]; nc], von_mises: vec![0.0; nc] };
    f.strain.par_iter_mut().zip(f.stress.par_iter_mut()).zip(f.von_mises.par_iter_mut()).enumerate().for_each(
        |(i, ((strain, stress), vm))| {
            let c = cells.as_ref().map_or(i, |cells| cells[i]);
            let kind = mesh.cells[c].kind;
            let mut xs = [[0.0; 3]; MAX_NODES];
            let nn = mesh.cell_coords(c, &mut xs);
            let mut n = [0.0; MAX_NODES];
            let mut dn = [[0.0; 3]; MAX_NODES];
            let mut g = [[0.0; 3]; MAX_NODES];
            let mat = materials[cell_material[c] as usize];
            let rule = kind.quadrature(if kind.is_simplex() { 1 } else { 3 });
            let (mut eps_avg, mut sig_avg, mut vm_avg, mut wsum) = ([0.0; 6], [0.0; 6], 0.0, 0.0);
            for (xi, w) in rule.iter() {
                element::shape(kind, xi, &mut n, &mut dn);
                let Ok(det) = element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut g) else { continue };
                let mut grad = [[0.0; 3]; 3];
                for a in 0..nn {
                    let node = mesh.cells[c].nodes[a];
                    for i in 0..dim {
                        for j in 0..dim {
                            grad[i][j] += u[node * dim + i] * g[a][j];
                        }
                    }
                }
                let mut eps = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        eps[i][j] = 0.5 * (grad[i][j] + grad[j][i]);
                    }
                }
                let sig = mat.stress(analysis, &eps);
                if analysis == Analysis::PlaneStress {
                    let nu = mat.poisson;
                    eps[2][2] = -nu / (1.0 - nu) * (eps[0][0] + eps[1][1]);
                }
                let wd = w * det;
                let (e6, s6) = (to_voigt6(&eps), to_voigt6(&sig));
                for k in 0..6 {
                    eps_avg[k] += wd * e6[k];
                    sig_avg[k] += wd * s6[k];
                }
                vm_avg += wd * von_mises(&sig);
                wsum += wd;
            }
            if wsum > 0.0 {
                for k in 0..6 {
                    eps_avg[k] /= wsum;
                    sig_avg[k] /= wsum;
                }
                vm_avg /= wsum;
            }
            (*strain, *stress, *vm) = (eps_avg, sig_avg, vm_avg);
        },
    );
    f
}
