//! The contact kernel: for every crack facet, the contact and friction residual and its
//! symmetric tangent at the facet's contact points, given the current state.
//!
//! Entry point: [`ContactKernel`].
//!
//! With J_k = φ_k⁺ − φ_k⁻ the jump of basis function k at a point, ⟦u⟧ = Σ J_k u_k,
//! d_n = −⟦u⟧·n − g₀, λ = Σ c_j μ_j and Λ_α = Σ c_j Λ_jα (multiplier interpolation), the
//! residual (weight w, formulation §5) and its derivatives are, in contact (χ_c = 1):
//!
//! ```text
//! R_u  += w g_n J_k n                      g_n = λ − ρ_n d_n
//! R_μj += −w d_n c_j
//! K_uu += w ρ_n J_k J_l n⊗n,   K_uμ = K_μuᵀ = w J_k n c_j,   K_μμ = 0
//! ```
//! and out of contact R_μj += −w λ c_j / ρ_n, K_μμ += −w c_j c_j' / ρ_n. Friction with the
//! frozen threshold λ̄ (μλ̄ ≤ 0), tangents τ_α, T_α = τ_α·⟦·⟧, v = T(⟦u⟧ − ⟦u⟧_start):
//!
//! ```text
//! stick: R_u += −w μλ̄ Σ_α Λ_α T_α,   R_Λjα += −w μλ̄ v_α c_j,   K_uΛ = K_Λuᵀ = −w μλ̄ T_α c_j
//! slip:  e = g/|g|, D = (I − e⊗e)/|g|
//!        R_u += −w μλ̄ Σ_α e_α T_α,   R_Λjα += w (μλ̄/ρ_τ)(Λ_α − e_α) c_j
//!        K_uu += −w μλ̄ ρ_τ Tᵀ D T,  K_uΛ = K_Λuᵀ = −w μλ̄ Tᵀ D c_j,  K_ΛΛ += w (μλ̄/ρ_τ)(I − D) c c'
//! open, or μλ̄ = 0: R_Λjα += −w Λ_α c_j,  K_ΛΛ += −w c_j c_j'
//! ```
//! All multiplier diagonal blocks are ≤ 0 and the tangent is symmetric, so the system
//! suits LDLᵀ with the multipliers after the displacements.
//!
//! Large sliding ([`super::pairing`]): with the pairing frozen, J_k = φ_k⁺(Y) − φ_k⁻(X) over
//! the basis of the slave cell and the master cells ([`ElementBasis`]), and ⟦u⟧ gains the
//! constant Y − X; everything above is unchanged. A point without a master point is out
//! of contact.

use super::law::{friction_indicator, PointState};
use super::pairing::{ElementBasis, Pairing};
use super::points::ContactPoints;
use crate::assembly::{Kernel, LocalOut};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::enrich::{CrackGeometry, Enrichment};
use crate::mesh::Mesh;
use std::cell::RefCell;

/// The contact kernel over every facet of every contact crack.
pub struct ContactKernel<'a> {
    pub mesh: &'a Mesh,
    pub enrichment: &'a Enrichment,
    pub cracks: &'a [CrackGeometry],
    pub points: &'a ContactPoints,
    /// Per contact point.
    pub state: &'a [PointState],
    /// Current value of every dof (displacements, enrichments, multipliers).
    pub u: &'a [f64],
    /// The pairing of the points with the master lip (`None`: every crack slides small).
    pub pairing: Option<&'a Pairing>,
}

#[derive(Default)]
struct Scratch {
    basis: CellBasis,
    vp: Vec<f64>,
    gp: Vec<[f64; 3]>,
    vm: Vec<f64>,
    gm: Vec<[f64; 3]>,
}

/// The facet's basis, the jumps at one point, the large-sliding element basis and the law
/// terms of one point.
type FacetScratch = (CellBasis, Vec<f64>, ElementBasis, Vec<(u32, f64)>);

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
    /// The facet's basis and the jumps at one point, reused by `compute` (separate from
    /// `SCRATCH`, which `basis_jumps` borrows).
    static FACET: RefCell<FacetScratch> =
        RefCell::new((CellBasis::default(), Vec::new(), ElementBasis::default(), Vec::new()));
}

/// Jump of every basis function of `basis` at reference point `xi` of `cell`.
pub fn basis_jumps(ev: &Evaluator<'_>, cell: usize, xi: &[f64; 3], basis: &CellBasis, out: &mut Vec<f64>) {
    SCRATCH.with(|s| {
        let s = &mut *s.borrow_mut();
        let nb = basis.len();
        s.vp.resize(nb, 0.0);
        s.gp.resize(nb, [0.0; 3]);
        s.vm.resize(nb, 0.0);
        s.gm.resize(nb, [0.0; 3]);
        out.clear();
        let ok = ev.eval(cell, basis, xi, Some(1), &mut s.vp, &mut s.gp).is_ok()
            && ev.eval(cell, basis, xi, Some(-1), &mut s.vm, &mut s.gm).is_ok();
        for k in 0..nb {
            out.push(if ok { s.vp[k] - s.vm[k] } else { 0.0 });
        }
    });
}

/// Kinematics of one point: ⟦u⟧ from the basis jumps (`dofs[k * dim + i]` of function k).
pub fn point_jump(dim: usize, dofs: &[u32], jump: &[f64], u: &[f64]) -> [f64; 3] {
    let mut j = [0.0; 3];
    for (k, &jk) in jump.iter().enumerate() {
        if jk != 0.0 {
            for i in 0..dim {
                j[i] += jk * u[dofs[k * dim + i] as usize];
            }
        }
    }
    j
}

/// Jumps of the functions of a large-sliding contact element at slave point `p` paired with
/// master point `m`: φ⁺(Y) − φ⁻(X). Returns false when a map is singular.
pub fn paired_jumps(
    ev: &Evaluator<'_>,
    eb: &mut ElementBasis,
    p: &super::points::ContactPoint,
    m: &super::pairing::MasterPoint,
    out: &mut Vec<f64>,
) -> bool {
    out.clear();
    out.resize(eb.len(ev.mesh.dim), 0.0);
    eb.add_values(ev, m.cell as usize, &m.xi, 1, 1.0, out) && eb.add_values(ev, p.cell, &p.xi, -1, -1.0, out)
}

impl ContactKernel<'_> {
    /// The master cells of contact element `e` other than its own (empty in small sliding).
    pub fn masters(&self, e: usize) -> &[u32] {
        match self.pairing {
            Some(p) if self.points.cracks[self.points.facets[e].0].large_sliding => &p.facet_masters[e],
            _ => &[],
        }
    }

    /// λ and Λ at a point from its terms.
    pub fn multipliers_at(&self, crack: usize, terms: &[(u32, f64)]) -> (f64, [f64; 2]) {
        let p = self.points;
        let mut lam = 0.0;
        let mut tl = [0.0; 2];
        for &(j, c) in terms {
            lam += c * self.u[p.lambda_dof(crack, j)];
            for a in 0..p.dim - 1 {
                tl[a] += c * self.u[p.tangent_dof(crack, j, a)];
            }
        }
        (lam, tl)
    }
}

impl Kernel for ContactKernel<'_> {
    fn n_elements(&self) -> usize {
        self.points.facets.len()
    }

    fn is_linear(&self) -> bool {
        false
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        let (ci, fi, _) = &self.points.facets[e];
        let cell = self.cracks[self.points.cracks[*ci].crack].cut.facets[*fi].cell;
        let masters = self.masters(e);
        if masters.is_empty() {
            SCRATCH.with(|s| {
                let s = &mut *s.borrow_mut();
                s.basis.build(self.mesh, self.enrichment, cell);
                out.extend_from_slice(&s.basis.dofs);
            });
        } else {
            FACET.with(|f| {
                let eb = &mut f.borrow_mut().2;
                eb.build(self.mesh, self.enrichment, cell, masters);
                out.extend_from_slice(&eb.dofs);
            });
        }
        let unk = &self.points.facet_unknowns[e];
        for &j in unk {
            out.push(self.points.lambda_dof(*ci, j) as u32);
        }
        for &j in unk {
            for a in 0..self.points.dim - 1 {
                out.push(self.points.tangent_dof(*ci, j, a) as u32);
            }
        }
    }

    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let pts = self.points;
        let dim = pts.dim;
        let nt = dim - 1;
        let (ci, _, range) = &pts.facets[e];
        let cc = &pts.cracks[*ci];
        let unk = &pts.facet_unknowns[e];
        let nu = unk.len();
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        let large = cc.large_sliding && self.pairing.is_some();
        FACET.with(|f| {
            let (basis, jump, eb, law_terms) = &mut *f.borrow_mut();
            let LocalOut { mut matrix, mut vector } = out;
            let cell = pts.points[range.start].cell;
            if large {
                eb.build(self.mesh, self.enrichment, cell, self.masters(e));
            } else {
                basis.build(self.mesh, self.enrichment, cell);
            }
            let nb = if large { eb.len(dim) } else { basis.len() };
            let nuu = nb * dim;
            let m = nuu + nu + nu * nt;
            let (rho_n, rho_t, mu) = (cc.rho_n, cc.rho_t, cc.friction);
            // Local index of packet j's λ and Λ_α.
            let li = |j: u32| nuu + unk.binary_search(&j).unwrap_or(0);
            let lt = |j: u32, a: usize| nuu + nu + unk.binary_search(&j).unwrap_or(0) * nt + a;
            for pi in range.clone() {
                let p = &pts.points[pi];
                let st = &self.state[pi];
                let mut offset = [0.0; 3];
                let paired = match (large, self.pairing.and_then(|pr| pr.master(pi))) {
                    (false, _) => {
                        basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                        true
                    }
                    (true, Some(m)) => {
                        offset = [m.x[0] - p.x[0], m.x[1] - p.x[1], m.x[2] - p.x[2]];
                        paired_jumps(&ev, eb, p, m, jump)
                    }
                    (true, None) => {
                        jump.clear();
                        jump.resize(nb, 0.0);
                        false
                    }
                };
                let jump = &*jump;
                let ldofs = if large { &eb.dofs } else { &basis.dofs };
                let mut jmp = point_jump(dim, ldofs, jump, self.u);
                for i in 0..3 {
                    jmp[i] += offset[i];
                }
                let in_contact = st.contact && paired;
                // The packets this point's friction law acts on (large sliding: see
                // Pairing::law_terms); the normal law always uses every term.
                let terms: &[(u32, f64)] = match self.pairing {
                    Some(pr) if large => {
                        pr.law_terms(*ci, pi, &p.terms, law_terms);
                        law_terms
                    }
                    _ => &p.terms,
                };
                let n = p.normal;
                let d_n = -(jmp[0] * n[0] + jmp[1] * n[1] + jmp[2] * n[2]);
                let (lam, _) = self.multipliers_at(*ci, &p.terms);
                let (_, tl) = self.multipliers_at(*ci, terms);
                let w = p.weight;
                // Normal part.
                if in_contact {
                    let g_n = lam - rho_n * d_n;
                    if let Some(f) = vector.as_deref_mut() {
                        for k in 0..nb {
                            for i in 0..dim {
                                f[k * dim + i] -= w * g_n * jump[k] * n[i];
                            }
                        }
                        for &(j, c) in &p.terms {
                            f[li(j)] -= -w * d_n * c;
                        }
                    }
                    if let Some(km) = matrix.as_deref_mut() {
                        for k in 0..nb {
                            if jump[k] == 0.0 {
                                continue;
                            }
                            for i in 0..dim {
                                let r = k * dim + i;
                                for l in 0..nb {
                                    for jj in 0..dim {
                                        km[r * m + l * dim + jj] += w * rho_n * jump[k] * jump[l] * n[i] * n[jj];
                                    }
                                }
                                for &(j, c) in &p.terms {
                                    let v = w * jump[k] * n[i] * c;
                                    km[r * m + li(j)] += v;
                                    km[li(j) * m + r] += v;
                                }
                            }
                        }
                    }
                } else {
                    if let Some(f) = vector.as_deref_mut() {
                        for &(j, c) in &p.terms {
                            f[li(j)] -= -w * lam * c / rho_n;
                        }
                    }
                    if let Some(km) = matrix.as_deref_mut() {
                        for &(j, c) in &p.terms {
                            for &(j2, c2) in &p.terms {
                                km[li(j) * m + li(j2)] += -w * c * c2 / rho_n;
                            }
                        }
                    }
                }
                // Friction part.
                let mlb = mu * st.lam_bar;
                if in_contact && mlb != 0.0 {
                    let mut v = [0.0; 2];
                    for a in 0..nt {
                        let t = p.tangents[a];
                        v[a] = (0..3).map(|i| t[i] * (jmp[i] - st.prev_jump[i])).sum();
                    }
                    let (free, g) = friction_indicator(tl, v, rho_t);
                    let gn0 = (g[0] * g[0] + g[1] * g[1]).sqrt();
                    let stick = st.lock.unwrap_or(free) || gn0 < 1e-14;
                    // T_α as coefficients on the u dofs: τ_α,i J_k.
                    let t_coef = |a: usize, k: usize, i: usize| p.tangents[a][i] * jump[k];
                    if stick {
                        if let Some(f) = vector.as_deref_mut() {
                            for k in 0..nb {
                                for i in 0..dim {
                                    let s: f64 = (0..nt).map(|a| tl[a] * t_coef(a, k, i)).sum();
                                    f[k * dim + i] -= -w * mlb * s;
                                }
                            }
                            for &(j, c) in terms {
                                for a in 0..nt {
                                    f[lt(j, a)] -= -w * mlb * v[a] * c;
                                }
                            }
                        }
                        if let Some(km) = matrix.as_deref_mut() {
                            for k in 0..nb {
                                for i in 0..dim {
                                    let r = k * dim + i;
                                    for &(j, c) in terms {
                                        for a in 0..nt {
                                            let val = -w * mlb * t_coef(a, k, i) * c;
                                            km[r * m + lt(j, a)] += val;
                                            km[lt(j, a) * m + r] += val;
                                        }
                                    }
                                }
                            }
                        }
                    } else {
                        let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
                        let ev = [g[0] / gn, g[1] / gn];
                        let mut dm = [[0.0; 2]; 2];
                        for a in 0..nt {
                            for b in 0..nt {
                                dm[a][b] = ((if a == b { 1.0 } else { 0.0 }) - ev[a] * ev[b]) / gn;
                            }
                        }
                        if let Some(f) = vector.as_deref_mut() {
                            for k in 0..nb {
                                for i in 0..dim {
                                    let s: f64 = (0..nt).map(|a| ev[a] * t_coef(a, k, i)).sum();
                                    f[k * dim + i] -= -w * mlb * s;
                                }
                            }
                            for &(j, c) in terms {
                                for a in 0..nt {
                                    f[lt(j, a)] -= w * (mlb / rho_t) * (tl[a] - ev[a]) * c;
                                }
                            }
                        }
                        if let Some(km) = matrix.as_deref_mut() {
                            for k in 0..nb {
                                for i in 0..dim {
                                    let r = k * dim + i;
                                    for a in 0..nt {
                                        for b in 0..nt {
                                            if dm[a][b] == 0.0 {
                                                continue;
                                            }
                                            let ta = t_coef(a, k, i);
                                            for l in 0..nb {
                                                for jj in 0..dim {
                                                    km[r * m + l * dim + jj] +=
                                                        -w * mlb * rho_t * ta * dm[a][b] * t_coef(b, l, jj);
                                                }
                                            }
                                            for &(j, c) in terms {
                                                let val = -w * mlb * ta * dm[a][b] * c;
                                                km[r * m + lt(j, b)] += val;
                                                km[lt(j, b) * m + r] += val;
                                            }
                                        }
                                    }
                                }
                            }
                            for &(j, c) in terms {
                                for &(j2, c2) in terms {
                                    for a in 0..nt {
                                        for b in 0..nt {
                                            let id = if a == b { 1.0 } else { 0.0 };
                                            km[lt(j, a) * m + lt(j2, b)] +=
                                                w * (mlb / rho_t) * (id - dm[a][b]) * c * c2;
                                        }
                                    }
                                }
                            }
                        }
                    }
                } else if nt > 0 {
                    if let Some(f) = vector.as_deref_mut() {
                        for &(j, c) in terms {
                            for a in 0..nt {
                                f[lt(j, a)] -= -w * tl[a] * c;
                            }
                        }
                    }
                    if let Some(km) = matrix.as_deref_mut() {
                        for &(j, c) in terms {
                            for &(j2, c2) in terms {
                                for a in 0..nt {
                                    km[lt(j, a) * m + lt(j2, a)] += -w * c * c2;
                                }
                            }
                        }
                    }
                }
            }
        });
    }
}
