//! The enriched basis of a cell and its evaluation at a point: standard shape
//! functions N_a, shifted Heaviside functions N_a (H − H_a), and the four shifted
//! branch functions N_a (F_l − F_l(x_a)).
//!
//! Entry points: [`CellBasis::build`], [`Evaluator::eval`] (and [`Evaluator::eval_with_shape`],
//! which also gives the standard shape functions), [`field_at`].
//!
//! Local dofs are basis-major: basis function k, component i is local dof `k * dim + i`,
//! so elasticity kernels treat enriched functions exactly like standard ones.
//!
//! Branch functions (formulation §2), in the front frame r = √(φn² + φt²),
//! θ = atan2(φn, φt): F = {√r sin(θ/2), √r cos(θ/2), √r sin(θ/2) sin θ, √r cos(θ/2) sin θ}.
//! Tip functions of the blending cells are ramped (corrected X-FEM, `enrich` module doc):
//! N_a (R F_l − R(x_a) F_l(x_a)) with R = Σ_{b∈K} N_b, R(x_a) = 1 on K nodes and 0 on
//! blending nodes; R ≡ 1 in the cells without blending nodes.
//! In a cell cut by the crack, the side of the sub-cell (or crack lip) a point belongs to
//! fixes the sign of θ and the value of H, so both are consistent with the cut geometry.

use super::{side_of, CrackGeometry, EnrichKind, Enrichment};
use crate::element::{self, SingularMap, MAX_NODES};
use crate::mesh::Mesh;

/// One scalar basis function of a cell (`a` is the local node index).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BasisFn {
    Standard {
        a: u8,
    },
    Heaviside {
        a: u8,
        crack: u16,
    },
    /// `blending`: the node is a blending node (ramped function, zero shift).
    Tip {
        a: u8,
        crack: u16,
        l: u8,
        blending: bool,
    },
}

/// The basis functions of one cell and their global dofs (`dofs[k * dim + i]`).
#[derive(Debug, Clone, Default)]
pub struct CellBasis {
    pub funcs: Vec<BasisFn>,
    pub dofs: Vec<u32>,
    /// The shift R(x_a) F_l(x_a) of each tip function (0 for the others), constant over
    /// the cell: filled by the first [`Evaluator::eval`] after [`CellBasis::build`] rather
    /// than at every quadrature point.
    shifts: std::sync::OnceLock<Vec<f64>>,
    /// The cell's nodal coordinates and, on a simplex (constant shape gradients), its
    /// physical shape gradients and Jacobian determinant: filled by the first evaluation
    /// after [`CellBasis::build`], so that a cell's quadrature points do not each invert
    /// the same Jacobian.
    geometry: std::sync::OnceLock<CellGeometry>,
}

/// What [`CellBasis`] keeps of its cell's geometry (see its `geometry` field).
#[derive(Debug, Clone)]
struct CellGeometry {
    cell: usize,
    xs: [[f64; 3]; MAX_NODES],
    nn: usize,
    /// Simplices: the physical gradients and det J (or the singular map), the same at
    /// every point.
    affine: Option<Result<AffineMap, SingularMap>>,
}

/// The physical shape gradients and det J of a simplex.
type AffineMap = ([[f64; 3]; MAX_NODES], f64);

impl CellBasis {
    /// Fills `self` with the basis of cell `c` (reusing its allocations).
    pub fn build(&mut self, mesh: &Mesh, enr: &Enrichment, c: usize) {
        self.funcs.clear();
        self.dofs.clear();
        self.shifts.take();
        self.geometry.take();
        let dim = mesh.dim;
        let nodes = mesh.cells[c].nodes();
        for (a, &n) in nodes.iter().enumerate() {
            self.funcs.push(BasisFn::Standard { a: a as u8 });
            for i in 0..dim {
                self.dofs.push((n * dim + i) as u32);
            }
        }
        for (a, &n) in nodes.iter().enumerate() {
            for item in enr.node_items(n) {
                match item.kind {
                    EnrichKind::Heaviside => {
                        self.funcs.push(BasisFn::Heaviside { a: a as u8, crack: item.crack });
                        for i in 0..dim {
                            self.dofs.push(item.first_dof + i as u32);
                        }
                    }
                    EnrichKind::Tip => {
                        for l in 0..item.n_functions() as u32 {
                            self.funcs.push(BasisFn::Tip {
                                a: a as u8,
                                crack: item.crack,
                                l: l as u8,
                                blending: item.blending,
                            });
                            for i in 0..dim {
                                self.dofs.push(item.first_dof + l * dim as u32 + i as u32);
                            }
                        }
                    }
                }
            }
        }
    }

    pub fn len(&self) -> usize {
        self.funcs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.funcs.is_empty()
    }

    /// Whether any function is enriched.
    pub fn is_enriched(&self) -> bool {
        self.funcs.iter().any(|f| !matches!(f, BasisFn::Standard { .. }))
    }
}

/// Values of the enrichment functions of one crack at one point.
#[derive(Debug, Clone, Copy, Default)]
struct CrackPoint {
    crack: u16,
    h: f64,
    f: [f64; 4],
    df: [[f64; 3]; 4],
    /// The blending ramp R = Σ_{a∈K} N_a and its gradient (1 and 0 in cells without
    /// blending nodes).
    ramp: f64,
    dramp: [f64; 3],
}

/// The four branch functions and their (r, θ) derivatives.
#[inline]
pub fn branch_functions(r: f64, theta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let sr = r.sqrt();
    let (s2, c2) = (0.5 * theta).sin_cos();
    let (st, ct) = theta.sin_cos();
    let f = [sr * s2, sr * c2, sr * s2 * st, sr * c2 * st];
    let inv = if sr > 0.0 { 0.5 / sr } else { 0.0 };
    let dr = [s2 * inv, c2 * inv, s2 * st * inv, c2 * st * inv];
    let dth = [0.5 * sr * c2, -0.5 * sr * s2, sr * (0.5 * c2 * st + s2 * ct), sr * (-0.5 * s2 * st + c2 * ct)];
    (f, dr, dth)
}

/// [`branch_functions`] at the point of local crack coordinates `x` = φt (along the
/// crack, ahead of the tip positive), `y` = φn, with `r` = √(x² + y²) (possibly clamped
/// away from 0), without trigonometric calls: the half angles come from
/// cos(θ/2) = √((r + x) / 2r) ahead of the tip and sin(θ/2) = ±√((r − x) / 2r) behind it
/// (each side takes the form that does not cancel), θ = atan2(y, x) ∈ (−π, π] with the
/// sign of a zero `y` deciding ±π as atan2 does.
#[inline]
pub fn branch_functions_xy(x: f64, y: f64, r: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    if r <= 0.0 {
        return branch_functions(0.0, 0.0);
    }
    let (s2, c2) = if y == 0.0 && x >= 0.0 {
        (y, 1.0)
    } else if x >= 0.0 {
        let c2 = ((r + x) / (2.0 * r)).sqrt();
        (y / (2.0 * r * c2), c2)
    } else {
        let s2 = ((r - x) / (2.0 * r)).sqrt().copysign(y);
        (s2, y / (2.0 * r * s2))
    };
    let (st, ct) = (y / r, x / r);
    let sr = r.sqrt();
    let f = [sr * s2, sr * c2, sr * s2 * st, sr * c2 * st];
    let inv = 0.5 / sr;
    let dr = [s2 * inv, c2 * inv, s2 * st * inv, c2 * st * inv];
    let dth = [0.5 * sr * c2, -0.5 * sr * s2, sr * (0.5 * c2 * st + s2 * ct), sr * (-0.5 * s2 * st + c2 * ct)];
    (f, dr, dth)
}

/// The branch function values of a crack at node `n` (zero-is-positive convention for
/// φn); zeros for a crack without a tangential level set.
#[inline]
fn nodal_branch_values(cr: &CrackGeometry, n: usize) -> [f64; 4] {
    let Some(lst) = cr.levelsets.lst.as_ref() else { return [0.0; 4] };
    let phin = cr.levelsets.lsn[n];
    let phin = if phin == 0.0 { 0.0 } else { phin };
    let r = (phin * phin + lst[n] * lst[n]).sqrt();
    branch_functions_xy(lst[n], phin, r).0
}

/// Evaluates enriched bases.
pub struct Evaluator<'a> {
    pub mesh: &'a Mesh,
    pub enr: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
}

/// Where a point is: its physical position and the parent Jacobian determinant.
#[derive(Debug, Clone, Copy)]
pub struct PointInfo {
    pub x: [f64; 3],
    pub det: f64,
}

impl Evaluator<'_> {
    /// Values `vals[k]` and physical gradients `grads[k]` of every function of `basis` at
    /// the reference point `xi` of cell `c`. `side` is the side (+1 / −1) of the sub-cell
    /// or crack lip the point belongs to, for the crack that cuts the cell; `None` takes
    /// the sign of φn at the point.
    pub fn eval(
        &self,
        c: usize,
        basis: &CellBasis,
        xi: &[f64; 3],
        side: Option<i8>,
        vals: &mut [f64],
        grads: &mut [[f64; 3]],
    ) -> Result<PointInfo, SingularMap> {
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; 3]; MAX_NODES];
        self.eval_with_shape(c, basis, xi, side, vals, grads, &mut n, &mut g)
    }

    /// [`Self::eval`], also giving the standard shape functions `n[a]` and their physical
    /// gradients `g[a]` at the point (computed once per cell on simplices).
    #[allow(clippy::too_many_arguments)]
    pub fn eval_with_shape(
        &self,
        c: usize,
        basis: &CellBasis,
        xi: &[f64; 3],
        side: Option<i8>,
        vals: &mut [f64],
        grads: &mut [[f64; 3]],
        n: &mut [f64; MAX_NODES],
        g: &mut [[f64; 3]; MAX_NODES],
    ) -> Result<PointInfo, SingularMap> {
        let mesh = self.mesh;
        let cell = &mesh.cells[c];
        let (x, det) = self.shape_at(c, basis, xi, n, g)?;
        let nn = cell.kind.n_nodes();

        // Enrichment functions of each crack present in the basis (usually one).
        let mut cache: [CrackPoint; 4] = Default::default();
        let mut n_cache = 0;
        for f in &basis.funcs {
            let k = match *f {
                BasisFn::Standard { .. } => continue,
                BasisFn::Heaviside { crack, .. } | BasisFn::Tip { crack, .. } => crack,
            };
            if !cache[..n_cache].iter().any(|p| p.crack == k) && n_cache < cache.len() {
                cache[n_cache] = self.crack_point(c, k, side, &n[..nn], &g[..nn]);
                n_cache += 1;
            }
        }
        let lookup = |k: u16| cache[..n_cache].iter().find(|p| p.crack == k).copied().unwrap_or_default();
        // The shifts R(x_a) F_l(x_a) (R = 1 at K nodes, 0 at blending nodes): constant over
        // the cell, evaluated at the first point (nodal branch values once per node and crack).
        let shifts: &[f64] = if n_cache == 0 {
            &[]
        } else {
            basis.shifts.get_or_init(|| {
                let mut nodal: [(u16, [f64; 4]); MAX_NODES] = [(u16::MAX, [0.0; 4]); MAX_NODES];
                basis
                    .funcs
                    .iter()
                    .map(|f| match *f {
                        BasisFn::Tip { a, crack, l, blending: false } => {
                            let slot = &mut nodal[a as usize];
                            if slot.0 != crack {
                                *slot =
                                    (crack, nodal_branch_values(&self.cracks[crack as usize], cell.nodes[a as usize]));
                            }
                            slot.1[l as usize]
                        }
                        _ => 0.0,
                    })
                    .collect()
            })
        };

        for (k, f) in basis.funcs.iter().enumerate() {
            match *f {
                BasisFn::Standard { a } => {
                    vals[k] = n[a as usize];
                    grads[k] = g[a as usize];
                }
                BasisFn::Heaviside { a, crack } => {
                    let p = lookup(crack);
                    let node = cell.nodes[a as usize];
                    let psi = p.h - side_of(self.cracks[crack as usize].levelsets.lsn[node]) as f64;
                    vals[k] = psi * n[a as usize];
                    for i in 0..3 {
                        grads[k][i] = psi * g[a as usize][i];
                    }
                }
                BasisFn::Tip { a, crack, l, .. } => {
                    let p = lookup(crack);
                    let fa = shifts[k];
                    let l = l as usize;
                    let psi = p.ramp * p.f[l] - fa;
                    let a = a as usize;
                    vals[k] = psi * n[a];
                    for i in 0..3 {
                        grads[k][i] = psi * g[a][i] + n[a] * (p.ramp * p.df[l][i] + p.f[l] * p.dramp[i]);
                    }
                }
            }
        }
        Ok(PointInfo { x, det })
    }

    /// The shape functions `n[a]` and physical gradients `g[a]` of cell `c` at `xi`, and
    /// the physical point and det J there; on a simplex the gradients and det J are those
    /// `basis` keeps for the cell (computed at its first point, bit for bit what every
    /// point would compute).
    pub fn shape_at(
        &self,
        c: usize,
        basis: &CellBasis,
        xi: &[f64; 3],
        n: &mut [f64; MAX_NODES],
        g: &mut [[f64; 3]; MAX_NODES],
    ) -> Result<([f64; 3], f64), SingularMap> {
        let mesh = self.mesh;
        let dim = mesh.dim;
        let kind = mesh.cells[c].kind;
        let mut dn = [[0.0; 3]; MAX_NODES];
        element::shape(kind, xi, n, &mut dn);
        let fresh = || {
            let mut xs = [[0.0; 3]; MAX_NODES];
            let nn = mesh.cell_coords(c, &mut xs);
            let affine = kind.is_simplex().then(|| {
                let mut ga = [[0.0; 3]; MAX_NODES];
                element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut ga).map(|det| (ga, det))
            });
            CellGeometry { cell: c, xs, nn, affine }
        };
        let mut local = None;
        let geo = match basis.geometry.get_or_init(fresh) {
            geo if geo.cell == c => geo,
            _ => local.insert(fresh()),
        };
        let nn = geo.nn;
        let det = match &geo.affine {
            Some(Ok((ga, det))) => {
                g[..nn].copy_from_slice(&ga[..nn]);
                *det
            }
            Some(Err(e)) => return Err(*e),
            None => element::physical_gradients(dim, &geo.xs[..nn], &dn[..nn], &mut g[..nn])?,
        };
        Ok((element::map_point(&n[..nn], &geo.xs[..nn]), det))
    }

    /// H and the branch functions of crack `k` at a point of cell `c` with shape
    /// function values `n` and physical gradients `g`.
    fn crack_point(&self, c: usize, k: u16, side: Option<i8>, n: &[f64], g: &[[f64; 3]]) -> CrackPoint {
        let cell = &self.mesh.cells[c];
        let nn = n.len();
        let cr = &self.cracks[k as usize];
        let mut p = CrackPoint { crack: k, ramp: 1.0, ..Default::default() };
        // The blending ramp: only cells with a blending node of this crack are ramped.
        let tip_item =
            |a: usize| self.enr.node_items(cell.nodes[a]).iter().find(|i| i.crack == k && i.kind == EnrichKind::Tip);
        if (0..nn).any(|a| tip_item(a).is_some_and(|i| i.blending)) {
            p.ramp = 0.0;
            for a in 0..nn {
                if tip_item(a).is_some_and(|i| !i.blending) {
                    p.ramp += n[a];
                    for i in 0..3 {
                        p.dramp[i] += g[a][i];
                    }
                }
            }
        }
        let cutting = self.enr.cell_crack[c] == Some(k);
        let (mut phin, mut gn) = (0.0, [0.0; 3]);
        for a in 0..nn {
            let v = cr.levelsets.lsn[cell.nodes[a]];
            phin += n[a] * v;
            for i in 0..3 {
                gn[i] += g[a][i] * v;
            }
        }
        let s = match (cutting, side) {
            (true, Some(s)) => s,
            (true, None) => side_of(phin),
            (false, _) => {
                let mean = cell.nodes().iter().map(|&a| cr.levelsets.lsn[a]).sum::<f64>() / nn as f64;
                side_of(mean)
            }
        };
        p.h = s as f64;
        if let Some(lst) = &cr.levelsets.lst {
            let (mut phit, mut gt) = (0.0, [0.0; 3]);
            for a in 0..nn {
                let v = lst[cell.nodes[a]];
                phit += n[a] * v;
                for i in 0..3 {
                    gt[i] += g[a][i] * v;
                }
            }
            let phin_s = if cutting { s as f64 * phin.abs() } else { phin };
            let r = (phin_s * phin_s + phit * phit).sqrt().max(1e-300);
            let (f, dr, dth) = branch_functions_xy(phit, phin_s, r);
            let mut grad_r = [0.0; 3];
            let mut grad_t = [0.0; 3];
            for i in 0..3 {
                grad_r[i] = (phin_s * gn[i] + phit * gt[i]) / r;
                grad_t[i] = (phit * gn[i] - phin_s * gt[i]) / (r * r);
            }
            p.f = f;
            for l in 0..4 {
                for i in 0..3 {
                    p.df[l][i] = dr[l] * grad_r[i] + dth[l] * grad_t[i];
                }
            }
        }
        p
    }
}

/// Displacement and its gradient `∂u_i/∂x_j` at a point from evaluated basis values.
pub fn field_at(
    dim: usize,
    basis: &CellBasis,
    vals: &[f64],
    grads: &[[f64; 3]],
    u: &[f64],
) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [0.0; 3];
    let mut gu = [[0.0; 3]; 3];
    for k in 0..basis.funcs.len() {
        for i in 0..dim {
            let d = u[basis.dofs[k * dim + i] as usize];
            if d == 0.0 {
                continue;
            }
            v[i] += vals[k] * d;
            for j in 0..dim {
                gu[i][j] += grads[k][j] * d;
            }
        }
    }
    (v, gu)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trig_free_branch_functions_match_the_polar_form() {
        let mut angles: Vec<f64> = (-40..=40).map(|k| k as f64 * std::f64::consts::PI / 40.0).collect();
        angles.extend([1e-9, -1e-9, std::f64::consts::PI - 1e-9, -std::f64::consts::PI + 1e-9]);
        for r in [1e-6, 0.3, 2.0] {
            for &t in &angles {
                let (x, y) = (r * t.cos(), r * t.sin());
                let rr = (x * x + y * y).sqrt();
                let (f0, dr0, dt0) = branch_functions(rr, y.atan2(x));
                let (f1, dr1, dt1) = branch_functions_xy(x, y, rr);
                for l in 0..4 {
                    let scale = 1.0 / rr.sqrt();
                    assert!((f0[l] - f1[l]).abs() < 1e-14, "f{l} at r {r} θ {t}");
                    assert!((dr0[l] - dr1[l]).abs() < 1e-13 * scale, "dr{l} at r {r} θ {t}");
                    assert!((dt0[l] - dt1[l]).abs() < 1e-14, "dθ{l} at r {r} θ {t}");
                }
            }
        }
        // On the crack faces behind the tip the sign of a zero φn picks ±π.
        let (fp, _, _) = branch_functions_xy(-1.0, 0.0, 1.0);
        let (fm, _, _) = branch_functions_xy(-1.0, -0.0, 1.0);
        assert_eq!((fp[0], fm[0]), (1.0, -1.0));
        assert_eq!(branch_functions_xy(0.0, 0.0, 1e-300).0, branch_functions(1e-300, 0.0).0);
    }
}
