//! Error norms against a known exact solution, for convergence studies
//! (manufactured solutions, Lamé, Westergaard fields).
//!
//! Entry point: [`error_norms`].

use crate::element::{self, MAX_NODES};
use crate::mesh::Mesh;
use crate::physics::material::{Analysis, Isotropic};

/// L2 and energy norms of the error and of the exact solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorNorms {
    /// ‖u_h − u‖_L2.
    pub l2: f64,
    /// Energy norm of the error, √(∫ (ε_h − ε) : C : (ε_h − ε)).
    pub energy: f64,
    /// ‖u‖_L2 of the exact solution.
    pub l2_exact: f64,
    /// Energy norm of the exact solution.
    pub energy_exact: f64,
}

/// Integrates the error of the standard nodal field `u` (`u[node * dim + c]`) against
/// the exact displacement `exact(x) -> u` and gradient `grad(x) -> ∂u_i/∂x_j`, with a
/// quadrature of degree `degree` per cell.
pub fn error_norms(
    mesh: &Mesh,
    analysis: Analysis,
    material: &Isotropic,
    u: &[f64],
    exact: &dyn Fn([f64; 3]) -> [f64; 3],
    grad: &dyn Fn([f64; 3]) -> [[f64; 3]; 3],
    degree: usize,
) -> ErrorNorms {
    let dim = mesh.dim;
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    let mut xs = [[0.0; 3]; MAX_NODES];
    let (mut l2, mut en, mut l2e, mut ene) = (0.0, 0.0, 0.0, 0.0);
    let energy_density = |eps: &[[f64; 3]; 3]| {
        let s = material.stress(analysis, eps);
        let mut w = 0.0;
        for i in 0..dim {
            for j in 0..dim {
                w += s[i][j] * eps[i][j];
            }
        }
        w
    };
    for c in 0..mesh.n_cells() {
        let kind = mesh.cells[c].kind;
        let nn = mesh.cell_coords(c, &mut xs);
        for (xi, w) in kind.quadrature(degree).iter() {
            element::shape(kind, xi, &mut n, &mut dn);
            let Ok(det) = element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut g) else { continue };
            let x = element::map_point(&n[..nn], &xs[..nn]);
            let (ue, ge) = (exact(x), grad(x));
            let mut uh = [0.0; 3];
            let mut gh = [[0.0; 3]; 3];
            for a in 0..nn {
                let node = mesh.cells[c].nodes[a];
                for i in 0..dim {
                    uh[i] += n[a] * u[node * dim + i];
                    for j in 0..dim {
                        gh[i][j] += g[a][j] * u[node * dim + i];
                    }
                }
            }
            let mut de = [[0.0; 3]; 3];
            let mut ex = [[0.0; 3]; 3];
            for i in 0..dim {
                for j in 0..dim {
                    de[i][j] = 0.5 * (gh[i][j] + gh[j][i] - ge[i][j] - ge[j][i]);
                    ex[i][j] = 0.5 * (ge[i][j] + ge[j][i]);
                }
            }
            let wd = w * det;
            l2 += wd * (0..dim).map(|i| (uh[i] - ue[i]).powi(2)).sum::<f64>();
            l2e += wd * (0..dim).map(|i| ue[i].powi(2)).sum::<f64>();
            en += wd * energy_density(&de);
            ene += wd * energy_density(&ex);
        }
    }
    ErrorNorms { l2: l2.sqrt(), energy: en.max(0.0).sqrt(), l2_exact: l2e.sqrt(), energy_exact: ene.max(0.0).sqrt() }
}
