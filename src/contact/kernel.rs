//! The contact kernel: for every crack facet, the scatter of the pointwise law's residual
//! and tangent ([`super::law::CrackLaw::respond`]) at the facet's contact points into the
//! element vector and matrix. The kernel evaluates the kinematics at a point
//! ([`super::state`]), asks the law, and maps the answer onto the unknowns; it decides
//! nothing itself.
//!
//! Entry point: [`ContactKernel`].
//!
//! With J_k = φ_k⁺ − φ_k⁻ the jump of basis function k at a point, e₀ = n, e_α = τ_α,
//! λ = Σ c_j μ_j and Λ_α = Σ c'_j Λ_jα (multiplier interpolation; c' the friction law's
//! terms, [`super::pairing::Pairing::law_terms`]), and the law's answer (r_s, r_m, k_ss,
//! k_sm, k_mm) in s = (e_a·⟦u⟧) and m = (λ, Λ_α), the element terms at a point of weight w
//! are
//!
//! ```text
//! R_u(k,i)   += w J_k Σ_a r_s,a e_a,i            R_λj += w c_j r_m,0     R_Λjα += w c'_j r_m,α
//! K_uu       += w J_k J_l Σ_ab e_a,i k_ss,ab e_b,i'
//! K_um = K_muᵀ += w J_k Σ_a e_a,i k_sm,ab c_j(b)      K_mm += w c_j(a) c_j'(b) k_mm,ab
//! ```
//! The law's tangent is symmetric with multiplier diagonal blocks ≤ 0, so the system
//! suits LDLᵀ with the multipliers after the displacements. A law without multipliers
//! ([`super::law::Method::has_multipliers`], the penalty law) adds K_uu and R_u only, and
//! its element has no multiplier dofs; its g_τ base is the point's Λ at the start of the
//! step ([`super::law::CrackLaw::friction_base`]).
//!
//! Packet elements (after the facets, one per multiplier packet of a crack whose law
//! augments the projected gap, [`super::law::CrackLaw::rho_projected`] = ρ_p > 0,
//! [`ContactPoints::packets`]): with a = Σ_p w_p ψ(x_p) J_k n over the packet's closed points,
//! G = Σ_p w_p ψ(x_p) d_n,p and W = ∫ψ, R_u += −(ρ_p/W) G a and K_uu += (ρ_p/W) a aᵀ: the term
//! −ρ_p Π d_n of the closed points' normal law, Π d_n = Σ_j ψ_j G_j/W_j, and its tangent.
//!
//! Stencil elements (after the packets, one per multiplier packet of a crack whose law has
//! [`super::law::CrackLaw::multiplier_stabilisation`] = γ > 0, [`ContactPoints::stencils`]),
//! while every packet of the stencil has a closed point (at the edge of a contact zone
//! the open packets stay out of it): with δ_j = Σ_k s_k λ_k (the packet's λ minus
//! the local linear fit of its neighbours' at its centroid) and A_j = ∫ψ_j,
//! R_λk += −γ A_j δ_j s_k and K_λkλl += −γ A_j s_k s_l: the local-projection stabilisation
//! −(γ A_j/2) δ_j² of the multipliers (negative semi-definite, like the open points'
//! −λ/ρ_n; zero for every λ linear over the stencil, so a uniform or linear pressure is
//! kept). It damps the packet-to-packet oscillation of λ that the cut cells' stress feeds
//! under slip on unstructured meshes (`docs/contact-algorithms.md`, "3D contact pressure
//! pointwise: the mechanism and the stabilised multipliers").
//!
//! Large sliding ([`super::pairing`]): with the pairing frozen, J_k = φ_k⁺(Y) − φ_k⁻(X) over
//! the basis of the slave cell and the master cells ([`ElementBasis`]), and ⟦u⟧ gains the
//! constant Y − X; everything above is unchanged. A point without a master point is out
//! of contact, and so is a dormant point (outside a meshed pair's contact zone,
//! [`super::zone`]: J = 0, its friction law on every packet of its terms as a paired
//! point's); a pair's facet in small sliding with no paired point has no displacement
//! unknowns (its multipliers only).

use super::law::{slip_increment, PointInput, PointState};
use super::pairing::{ElementBasis, Pairing};
use super::points::ContactPoints;
use super::state::{basis_jumps, multipliers_at, paired_jumps, point_jump, start_gap};
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
    /// The friction thresholds of the laws that allow it follow the iterate
    /// ([`super::law::CrackLaw::live_threshold`]; the caller keeps `state`'s λ̄ current):
    /// their slope enters the tangent, which is then unsymmetric. False: λ̄ frozen.
    pub live_thresholds: bool,
}

/// The facet's basis, the jumps at one point, the large-sliding element basis and the law
/// terms of one point.
type FacetScratch = (CellBasis, Vec<f64>, ElementBasis, Vec<(u32, f64)>);

thread_local! {
    static FACET: RefCell<FacetScratch> =
        RefCell::new((CellBasis::default(), Vec::new(), ElementBasis::default(), Vec::new()));
    static BASIS: RefCell<CellBasis> = RefCell::new(CellBasis::default());
}

impl ContactKernel<'_> {
    /// The master cells of contact element `e` other than its own (empty in small sliding).
    pub fn masters(&self, e: usize) -> &[u32] {
        match self.pairing {
            Some(p) if self.points.cracks[self.points.facets[e].0].large_sliding => &p.facet_masters[e],
            _ => &[],
        }
    }
}

impl ContactKernel<'_> {
    /// Whether facet element `e` of a meshed pair in small sliding has no paired point
    /// (every point dormant, [`super::zone`], or without a master facet): its points add
    /// nothing to the displacement rows and its element has multiplier unknowns only.
    fn bare(&self, e: usize) -> bool {
        let cc = &self.points.cracks[self.points.facets[e].0];
        cc.pair.is_some() && !cc.repair && self.pairing.is_some_and(|p| !p.facet_coupled[e])
    }

    /// The nodes a contact element of a meshed pair couples (its faces' nodes); `None` for
    /// a crack, whose facets cross its cells.
    fn surface_nodes(&self, e: usize) -> Option<&[usize]> {
        self.points.cracks[self.points.facets[e].0].pair.as_ref().map(|p| &p.surface_nodes[..])
    }
}

impl ContactKernel<'_> {
    /// The dofs of packet element `q` ([`ContactPoints::packets`]): the functions with a
    /// non-zero jump at one of its points, sorted (they do not depend on the iterate).
    fn packet_dofs(&self, q: usize, out: &mut Vec<u32>) {
        let pk = &self.points.packets[q];
        let dim = self.points.dim;
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        let start = out.len();
        FACET.with(|f| {
            let (basis, jump, ..) = &mut *f.borrow_mut();
            for &(pi, _) in &pk.points {
                let p = &self.points.points[pi];
                basis.build(self.mesh, self.enrichment, p.cell);
                basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                for (k, &jk) in jump.iter().enumerate() {
                    if jk != 0.0 {
                        out.extend_from_slice(&basis.dofs[k * dim..(k + 1) * dim]);
                    }
                }
            }
        });
        out[start..].sort_unstable();
        let mut tail = out.split_off(start);
        tail.dedup();
        out.extend_from_slice(&tail);
    }

    /// The projected-gap augmentation of packet element `q` ([`super::law::CrackLaw::rho_projected`],
    /// ρ_p): with G = Σ_p w_p ψ(x_p) d_n,p over its closed points and W = ∫ψ, the energy
    /// (ρ_p/2W) G², i.e. the residual −ρ_p Π d_n of the closed points' normal law
    /// (Π d_n = Σ_j ψ_j G_j/W_j) and its tangent (ρ_p/W) a aᵀ, a = −∂G/∂u = Σ_p w_p ψ J_k n.
    fn compute_packet(&self, q: usize, dofs: &[u32], out: LocalOut<'_>) {
        let pts = self.points;
        let pk = &pts.packets[q];
        let law = &pts.cracks[pk.crack].law;
        let dim = pts.dim;
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        let m = dofs.len();
        let mut a = vec![0.0; m];
        let mut g = 0.0;
        let mut any = false;
        FACET.with(|f| {
            let (basis, jump, ..) = &mut *f.borrow_mut();
            for &(pi, c) in &pk.points {
                let st = &self.state[pi];
                if !st.contact {
                    continue;
                }
                any = true;
                let p = &pts.points[pi];
                basis.build(self.mesh, self.enrichment, p.cell);
                basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                let jmp = point_jump(dim, &basis.dofs, jump, self.u);
                let wc = p.weight * c;
                g += wc * law.penetration(jmp, p.normal, st.gap_offset());
                for (k, &jk) in jump.iter().enumerate() {
                    if jk != 0.0 {
                        for i in 0..dim {
                            if let Ok(l) = dofs.binary_search(&basis.dofs[k * dim + i]) {
                                a[l] += wc * jk * p.normal[i];
                            }
                        }
                    }
                }
            }
        });
        if !any {
            return;
        }
        let scale = law.rho_projected / pk.weight;
        let LocalOut { matrix, vector } = out;
        if let Some(f) = vector {
            for (fl, al) in f.iter_mut().zip(&a) {
                *fl += scale * g * al;
            }
        }
        if let Some(km) = matrix {
            for (k, ak) in a.iter().enumerate() {
                if *ak != 0.0 {
                    for (l, al) in a.iter().enumerate() {
                        km[k * m + l] += scale * ak * al;
                    }
                }
            }
        }
    }
}

impl ContactKernel<'_> {
    /// The local-projection stabilisation of stencil element `q` ([`ContactPoints::stencils`];
    /// its dofs are the λ of its terms, in order): the potential −(γ A_j/2) δ_j², while
    /// every packet of the stencil has a closed point.
    fn compute_stencil(&self, q: usize, out: LocalOut<'_>) {
        let pts = self.points;
        let st = &pts.stencils[q];
        if !st.near.iter().all(|&q| pts.stencils[q].points.iter().any(|&pi| self.state[pi].contact)) {
            return;
        }
        let gamma = pts.cracks[st.crack].law.multiplier_stabilisation * st.weight;
        let delta: f64 = st.terms.iter().map(|&(k, s)| s * self.u[pts.lambda_dof(st.crack, k)]).sum();
        let m = st.terms.len();
        let LocalOut { matrix, vector } = out;
        if let Some(f) = vector {
            for (fk, (_, s)) in f.iter_mut().zip(&st.terms) {
                *fk += gamma * delta * s;
            }
        }
        if let Some(km) = matrix {
            for (k, (_, sk)) in st.terms.iter().enumerate() {
                for (l, (_, sl)) in st.terms.iter().enumerate() {
                    km[k * m + l] -= gamma * sk * sl;
                }
            }
        }
    }
}

impl Kernel for ContactKernel<'_> {
    fn n_elements(&self) -> usize {
        self.points.facets.len() + self.points.packets.len() + self.points.stencils.len()
    }

    fn is_linear(&self) -> bool {
        false
    }

    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        let nf = self.points.facets.len();
        let np = nf + self.points.packets.len();
        if e >= np {
            let st = &self.points.stencils[e - np];
            out.extend(st.terms.iter().map(|&(k, _)| self.points.lambda_dof(st.crack, k) as u32));
            return;
        }
        if e >= nf {
            return self.packet_dofs(e - nf, out);
        }
        let (ci, _, range) = &self.points.facets[e];
        let cell = self.points.points[range.start].cell;
        let masters = self.masters(e);
        // The basis `compute` uses: the element basis whenever the crack is paired (also
        // for a facet without master cells: a pair's basis keeps only its faces' nodes).
        if self.bare(e) {
            // No displacement unknowns.
        } else if !(self.points.cracks[*ci].large_sliding && self.pairing.is_some()) {
            BASIS.with(|b| {
                let b = &mut *b.borrow_mut();
                b.build(self.mesh, self.enrichment, cell);
                out.extend_from_slice(&b.dofs);
            });
        } else {
            FACET.with(|f| {
                let eb = &mut f.borrow_mut().2;
                eb.build(self.mesh, self.enrichment, cell, masters, self.surface_nodes(e));
                out.extend_from_slice(&eb.dofs);
            });
        }
        if !self.points.cracks[*ci].law.method.has_multipliers() {
            return;
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

    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>) {
        let nf = self.points.facets.len();
        let np = nf + self.points.packets.len();
        if e >= np {
            return self.compute_stencil(e - np, out);
        }
        if e >= nf {
            return self.compute_packet(e - nf, dofs, out);
        }
        let pts = self.points;
        let dim = pts.dim;
        let nt = dim - 1;
        let (ci, _, range) = &pts.facets[e];
        let cc = &pts.cracks[*ci];
        let multipliers = cc.law.method.has_multipliers();
        let unk: &[u32] = if multipliers { &pts.facet_unknowns[e] } else { &[] };
        let nu = unk.len();
        let ev = Evaluator { mesh: self.mesh, enr: self.enrichment, cracks: self.cracks };
        let large = cc.large_sliding && self.pairing.is_some();
        let bare = self.bare(e);
        FACET.with(|f| {
            let (basis, jump, eb, law_terms) = &mut *f.borrow_mut();
            let LocalOut { mut matrix, mut vector } = out;
            let cell = pts.points[range.start].cell;
            if bare {
                // Multiplier unknowns only (every point unpaired or dormant).
            } else if large {
                eb.build(self.mesh, self.enrichment, cell, self.masters(e), self.surface_nodes(e));
            } else {
                basis.build(self.mesh, self.enrichment, cell);
            }
            let nb = if bare {
                0
            } else if large {
                eb.len(dim)
            } else {
                basis.len()
            };
            let nuu = nb * dim;
            let m = nuu + nu + nu * nt;
            // Local index of multiplier component b (0: λ, 1 + α: Λ_α) of packet j.
            let local = |j: u32, b: usize| {
                let q = unk.binary_search(&j).unwrap_or(0);
                if b == 0 {
                    nuu + q
                } else {
                    nuu + nu + q * nt + b - 1
                }
            };
            for pi in range.clone() {
                let p = &pts.points[pi];
                let st = &self.state[pi];
                let mut offset = [0.0; 3];
                let paired = match (large, self.pairing.and_then(|pr| pr.master(pi))) {
                    (false, _) => {
                        basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                        true
                    }
                    (true, Some(mp)) => {
                        offset = [mp.x[0] - p.x[0], mp.x[1] - p.x[1], mp.x[2] - p.x[2]];
                        paired_jumps(&ev, eb, p, mp, cc.pair.is_some(), jump)
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
                // The packets this point's friction law acts on (large sliding: see
                // Pairing::law_terms); the normal law always uses every term.
                let terms: &[(u32, f64)] = match self.pairing {
                    Some(pr) if large => {
                        pr.law_terms(*ci, pi, &p.terms, law_terms);
                        law_terms
                    }
                    _ => &p.terms,
                };
                let (lambda, big_lambda) = if multipliers {
                    (multipliers_at(pts, *ci, &p.terms, self.u).0, multipliers_at(pts, *ci, terms, self.u).1)
                } else {
                    (0.0, [0.0; 2])
                };
                let d_n = cc.law.penetration(jmp, p.normal, st.gap_offset());
                // A locked stick/slip status keeps its threshold frozen too.
                let (threshold_slope, threshold_slope_lambda) =
                    match (self.live_thresholds && paired && st.lock.is_none(), st.contact) {
                        (true, contact) => {
                            cc.law.live_threshold(large, paired, contact, lambda, d_n, start_gap(&cc.law, p, st))
                        }
                        _ => None,
                    }
                    .map_or((0.0, 0.0), |t| (t.1, t.2));
                let input = PointInput {
                    d_n,
                    v: slip_increment(nt, &p.tangents, jmp, st.prev_jump),
                    lambda,
                    big_lambda: cc.law.friction_base(big_lambda, st.big_lambda_start),
                    in_contact: st.contact && paired,
                    // An unpaired point transmits nothing: no friction either (with an
                    // asperity layer friction acts wherever λ̄ ≠ 0, CrackLaw::friction_acts).
                    lam_bar: if paired { st.lam_bar } else { 0.0 },
                    lock: st.lock,
                    threshold_scale: st.threshold_scale,
                    d_n_start: start_gap(&cc.law, p, st),
                    threshold_slope,
                    threshold_slope_lambda,
                };
                let r = cc.law.respond(nt, &input);
                let w = p.weight;
                // The point's frame e_a and the terms of multiplier component b.
                let frame = [p.normal, p.tangents[0], p.tangents[1]];
                let ns = 1 + nt;
                let mult_terms = |b: usize| {
                    if !multipliers {
                        &[][..]
                    } else if b == 0 {
                        &p.terms[..]
                    } else {
                        terms
                    }
                };
                if let Some(f) = vector.as_deref_mut() {
                    let mut force = [0.0; 3];
                    for a in 0..ns {
                        if r.r_s[a] != 0.0 {
                            for i in 0..dim {
                                force[i] += r.r_s[a] * frame[a][i];
                            }
                        }
                    }
                    for k in 0..nb {
                        if jump[k] != 0.0 {
                            for i in 0..dim {
                                f[k * dim + i] -= w * jump[k] * force[i];
                            }
                        }
                    }
                    for b in 0..ns {
                        if r.r_m[b] != 0.0 {
                            for &(j, c) in mult_terms(b) {
                                f[local(j, b)] -= w * c * r.r_m[b];
                            }
                        }
                    }
                }
                if let Some(km) = matrix.as_deref_mut() {
                    // K_uu's dim × dim block per pair of functions, and K_um's per function.
                    // With a live threshold, K_um and K_mu also get one-sided terms
                    // (`k_sm_live`, `k_ms_live`).
                    let mut kuu = [[0.0; 3]; 3];
                    let mut kum = [[0.0; 3]; 3];
                    let mut kum_live = [[0.0; 3]; 3];
                    let mut kmu_live = [[0.0; 3]; 3];
                    for a in 0..ns {
                        for b in 0..ns {
                            for i in 0..dim {
                                if r.k_ss[a][b] != 0.0 {
                                    for i2 in 0..dim {
                                        kuu[i][i2] += frame[a][i] * r.k_ss[a][b] * frame[b][i2];
                                    }
                                }
                                kum[i][b] += frame[a][i] * r.k_sm[a][b];
                                kum_live[i][b] += frame[a][i] * r.k_sm_live[a][b];
                                kmu_live[i][b] += r.k_ms_live[b][a] * frame[a][i];
                            }
                        }
                    }
                    let has_kuu = kuu.iter().flatten().any(|v| *v != 0.0);
                    for k in 0..nb {
                        if jump[k] == 0.0 {
                            continue;
                        }
                        for i in 0..dim {
                            let row = k * dim + i;
                            if has_kuu {
                                for l in 0..nb {
                                    let wkl = w * jump[k] * jump[l];
                                    for i2 in 0..dim {
                                        km[row * m + l * dim + i2] += wkl * kuu[i][i2];
                                    }
                                }
                            }
                            for b in 0..ns {
                                if kum[i][b] != 0.0 {
                                    for &(j, c) in mult_terms(b) {
                                        let v = w * jump[k] * kum[i][b] * c;
                                        let col = local(j, b);
                                        km[row * m + col] += v;
                                        km[col * m + row] += v;
                                    }
                                }
                                if kum_live[i][b] != 0.0 || kmu_live[i][b] != 0.0 {
                                    for &(j, c) in mult_terms(b) {
                                        let col = local(j, b);
                                        km[row * m + col] += w * jump[k] * kum_live[i][b] * c;
                                        km[col * m + row] += w * jump[k] * kmu_live[i][b] * c;
                                    }
                                }
                            }
                        }
                    }
                    for a in 0..ns {
                        for b in 0..ns {
                            if r.k_mm[a][b] != 0.0 {
                                for &(j, c) in mult_terms(a) {
                                    for &(j2, c2) in mult_terms(b) {
                                        km[local(j, a) * m + local(j2, b)] += w * c * c2 * r.k_mm[a][b];
                                    }
                                }
                            }
                        }
                    }
                }
            }
        });
    }
}
