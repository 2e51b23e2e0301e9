//! Point kinematics and statuses: the jump ⟦u⟧, the penetration d_n and the multipliers
//! λ, Λ at every contact point for a dof vector, the open/stick/slip status the law gives
//! them, and the law checks the contact loops make between Newton solves (contact status,
//! friction threshold, frozen statuses against the law).
//!
//! Entry points: [`point_values`], [`statuses`], [`update_contact_status`],
//! [`update_thresholds`], [`set_threshold_scales`], [`freeze_statuses`], [`frozen_statuses_agree`],
//! [`frozen_disagreements`], and for the laws without multipliers (penalty)
//! [`project_point_tractions`], [`store_tangential_state`], [`start_tangential_state`],
//! [`hold_reversed_slips`]; for
//! wear [`accumulate_wear`] (end of a converged step) and [`commit_wear`] (start of the
//! next); for the energies of dynamics [`frictional_dissipation`].
//!
//! The jump at a point is Σ_k J_k u_k with J_k = φ_k⁺ − φ_k⁻ ([`basis_jumps`]); under large
//! sliding J_k = φ_k⁺(Y) − φ_k⁻(X) over the slave and master cells ([`paired_jumps`]) and
//! ⟦u⟧ gains the constant Y − X.

use super::law::{contact_indicator, slip_increment, CrackLaw, PointInput, PointState, Status};
use super::lip_wear::LipChart;
use super::pairing::{ElementBasis, JumpStencils, MasterPoint, Pairing};
use super::points::{ContactPoint, ContactPoints};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::physics::model::Model;
use rayon::prelude::*;
use std::cell::RefCell;

#[derive(Default)]
struct Scratch {
    vp: Vec<f64>,
    gp: Vec<[f64; 3]>,
    vm: Vec<f64>,
    gm: Vec<[f64; 3]>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
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
/// master point `m`: φ⁺(Y) − φ⁻(X) (a meshed contact pair: φ(Y) − φ(X), the standard basis
/// of the master and slave cells, `pair`). Returns false when a map is singular.
pub fn paired_jumps(
    ev: &Evaluator<'_>,
    eb: &mut ElementBasis,
    p: &ContactPoint,
    m: &MasterPoint,
    pair: bool,
    out: &mut Vec<f64>,
) -> bool {
    out.clear();
    out.resize(eb.len(ev.mesh.dim), 0.0);
    let (plus, minus) = if pair { (0, 0) } else { (1, -1) };
    eb.add_values(ev, m.cell as usize, &m.xi, plus, 1.0, out) && eb.add_values(ev, p.cell, &p.xi, minus, -1.0, out)
}

/// λ and Λ at a point from multiplier terms (packet, coefficient) of contact crack `ci`.
pub fn multipliers_at(points: &ContactPoints, ci: usize, terms: &[(u32, f64)], u: &[f64]) -> (f64, [f64; 2]) {
    let mut lam = 0.0;
    let mut tl = [0.0; 2];
    for &(j, c) in terms {
        lam += c * u[points.lambda_dof(ci, j)];
        for a in 0..points.dim - 1 {
            tl[a] += c * u[points.tangent_dof(ci, j, a)];
        }
    }
    (lam, tl)
}

/// Kinematics and multipliers at one contact point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointValues {
    pub jump: [f64; 3],
    /// Penetration d_n = −⟦u⟧·n − g₀ (positive: overlap).
    pub d_n: f64,
    pub lambda: f64,
    pub big_lambda: [f64; 2],
    /// Whether the point has a master point (always, in small sliding). Unpaired points
    /// are out of contact.
    pub paired: bool,
    /// The point is outside its pair's contact zone ([`super::zone`]): its values are its
    /// true kinematics (with its master point) but it is held open.
    pub dormant: bool,
}

/// λ, Λ, ⟦u⟧ and d_n at every contact point for the dof vector `u` (with the pairing of
/// the large-sliding cracks, if any, and the gap shifts of `state`). A crack whose law has
/// no multipliers (penalty) gets them from its law at the point: λ = −κ_n⟨d_n⟩₊ and, at a
/// point in contact (`state`) with a friction threshold, Λ the return mapping of
/// Λ_start + κ_τ v_τ.
pub fn point_values(
    model: &Model<'_>,
    points: &ContactPoints,
    pairing: Option<&Pairing>,
    state: &[PointState],
    u: &[f64],
) -> Vec<PointValues> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let ev = Evaluator { mesh, enr: &model.enrichment, cracks: &model.cracks };
    let stencils = pairing.map(|pr| pr.jumps.get_or_init(|| jump_stencils(&ev, points, pr)));
    points
        .points
        .par_iter()
        .enumerate()
        .map_init(
            || (CellBasis::default(), Vec::new()),
            |(basis, jump), (pi, p)| {
                let cc = &points.cracks[p.crack];
                let dormant = pairing.is_some_and(|pr| pr.is_dormant(pi));
                let (j, paired) = match (cc.large_sliding, pairing, stencils) {
                    (true, Some(pr), Some(js)) => match pr.reference_master(pi) {
                        Some(m) => {
                            let mut j = [0.0; 3];
                            let terms = js.offsets[pi]..js.offsets[pi + 1];
                            for (d, &w) in js.dofs[terms.clone()].iter().zip(&js.jumps[terms]) {
                                for i in 0..dim {
                                    j[i] += w * u[d[i] as usize];
                                }
                            }
                            for i in 0..3 {
                                j[i] += m.x[i] - p.x[i];
                            }
                            (j, js.regular[pi])
                        }
                        None => ([0.0; 3], false),
                    },
                    _ => {
                        basis.build(mesh, &model.enrichment, p.cell);
                        basis_jumps(&ev, p.cell, &p.xi, basis, jump);
                        (point_jump(dim, &basis.dofs, jump, u), true)
                    }
                };
                let law = &cc.law;
                let mut d_n = law.penetration(j, p.normal, state.get(pi).map_or(0.0, |s| s.gap_offset()));
                let (mut lambda, big_lambda) = if law.method.has_multipliers() {
                    multipliers_at(points, p.crack, &p.terms, u)
                } else if !paired {
                    (0.0, [0.0; 2])
                } else {
                    let st = &state[pi];
                    let big = if law.friction_acts(st.contact) && law.friction * st.lam_bar != 0.0 {
                        let vt = slip_increment(dim - 1, &p.tangents, j, st.prev_jump);
                        law.penalty_big_lambda(st.big_lambda_start, vt, st.lam_bar, st.lock)
                    } else {
                        [0.0; 2]
                    };
                    (law.penalty_traction(d_n), big)
                };
                // The implicit wear of the step: the worn gap d_n − Δw (CrackLaw::worn_gap).
                if let (true, Some(st)) = (paired, state.get(pi)) {
                    let input = point_input(law, dim - 1, p, st, j, d_n, lambda, big_lambda);
                    let q = law.wear_compliance(&input);
                    if q > 0.0 {
                        d_n = law.worn_gap(&input, q);
                        if !law.method.has_multipliers() {
                            lambda = law.penalty_traction(d_n);
                        }
                    }
                }
                PointValues { jump: j, d_n, lambda, big_lambda, paired, dormant }
            },
        )
        .collect()
}

/// The jump stencils of `pairing` ([`JumpStencils`]): per point of a large-sliding crack or
/// pair with a master point, the functions of its element basis (slave cell and master
/// cell) with a non-zero jump, in the basis' order.
fn jump_stencils(ev: &Evaluator<'_>, points: &ContactPoints, pairing: &Pairing) -> JumpStencils {
    let mesh = ev.mesh;
    let dim = mesh.dim;
    // Per point: its (dofs, jump) terms and whether its maps were regular.
    type Terms = (Vec<([u32; 3], f64)>, bool);
    let per_point: Vec<Terms> = points
        .points
        .par_iter()
        .enumerate()
        .map_init(
            || (Vec::new(), ElementBasis::default()),
            |(jump, eb), (pi, p)| {
                let cc = &points.cracks[p.crack];
                let Some(m) = pairing.reference_master(pi).filter(|_| cc.large_sliding) else {
                    return (Vec::new(), false);
                };
                eb.build(mesh, ev.enr, p.cell, std::slice::from_ref(&m.cell), None);
                let ok = paired_jumps(ev, eb, p, m, cc.pair.is_some(), jump);
                let terms = jump
                    .iter()
                    .enumerate()
                    .filter(|(_, &jk)| jk != 0.0)
                    .map(|(k, &jk)| {
                        let mut d = [0u32; 3];
                        d[..dim].copy_from_slice(&eb.dofs[k * dim..(k + 1) * dim]);
                        (d, jk)
                    })
                    .collect();
                (terms, ok)
            },
        )
        .collect();
    let mut js = JumpStencils { offsets: Vec::with_capacity(per_point.len() + 1), ..Default::default() };
    js.offsets.push(0);
    for (terms, ok) in per_point {
        for (d, w) in terms {
            js.dofs.push(d);
            js.jumps.push(w);
        }
        js.offsets.push(js.dofs.len());
        js.regular.push(ok);
    }
    js
}

/// What the law reads at point `p` with state `st`, jump `jump`, gap `d_n` and multipliers
/// (λ, Λ) (the friction base of the law: Λ, or the penalty's Λ at the start of the step).
#[allow(clippy::too_many_arguments)]
fn point_input(
    law: &CrackLaw,
    nt: usize,
    p: &ContactPoint,
    st: &PointState,
    jump: [f64; 3],
    d_n: f64,
    lambda: f64,
    big_lambda: [f64; 2],
) -> PointInput {
    PointInput {
        d_n,
        v: slip_increment(nt, &p.tangents, jump, st.prev_jump),
        lambda,
        big_lambda: law.friction_base(big_lambda, st.big_lambda_start),
        in_contact: st.contact,
        lam_bar: st.lam_bar,
        lock: st.lock,
        threshold_scale: st.threshold_scale,
        d_n_start: start_gap(law, p, st),
        threshold_slope: 0.0,
        threshold_slope_lambda: 0.0,
    }
}

/// The gap at point `p` at the start of the step (the jump `prev_jump`, with the wear
/// before the step and the gap shift: [`PointState::gap_offset`]): the base of the asperity
/// layer's crush rate (in dynamics shifted by [`PointState::layer_rate_shift`], so that
/// the rate is the normal relative velocity at the end of the time step).
#[inline]
pub fn start_gap(law: &CrackLaw, p: &ContactPoint, st: &PointState) -> f64 {
    law.penetration(st.prev_jump, p.normal, st.gap_offset()) + st.layer_rate_shift
}

/// Ends a converged step for the cracks with wear: each point's wear increment and
/// frictional work of the step from its final values `vals` (Archard,
/// [`CrackLaw::wear_increment`]) into [`PointState::wear_step`] and
/// [`PointState::frictional_work`]. Under large sliding (`chart`, with the step's
/// `pairing`) a slave point's `+` lip increment goes where it met the `+` lip
/// ([`LipChart::overlaps`] in 2D, the vertices of the master facet in 3D:
/// [`super::lip_wear::MasterWear::spread`]), not to its own position. Returns, per contact crack, the
/// largest wear depth of one lip after the step.
pub fn accumulate_wear(
    points: &ContactPoints,
    state: &mut [PointState],
    vals: &[PointValues],
    chart: Option<&LipChart>,
    pairing: Option<&Pairing>,
) -> Vec<f64> {
    let mut deepest = vec![0.0f64; points.cracks.len()];
    let remapped = |c: usize| chart.is_some() && pairing.is_some() && LipChart::applies(points, c);
    let mut deposits: Vec<(usize, f64)> = vec![];
    for (pi, ((st, v), p)) in state.iter_mut().zip(vals).zip(&points.points).enumerate() {
        let law = &points.cracks[p.crack].law;
        if law.wear.is_none() {
            continue;
        }
        let input = point_input(law, points.dim - 1, p, st, v.jump, v.d_n, v.lambda, v.big_lambda);
        let (dw, work) = if v.paired { law.wear_increment(&input) } else { ([0.0; 2], 0.0) };
        st.wear_step = dw;
        st.frictional_work += work;
        if remapped(p.crack) || points.cracks[p.crack].pair.is_some() {
            st.wear_step[0] = 0.0;
            if dw[0] != 0.0 {
                deposits.push((pi, dw[0]));
            }
        }
    }
    // The master faces' increments of the pairs (per pair, per master facet).
    let mut master_step: Vec<Vec<f64>> = points.cracks.iter().map(|cc| vec![0.0; cc.master_wear.len()]).collect();
    if let (Some(chart), Some(pairing)) = (chart, pairing) {
        let mut o = vec![];
        for (i, dw) in deposits {
            let Some(m) = pairing.master(i) else { continue };
            let volume = points.points[i].weight * dw;
            let c = points.points[i].crack;
            let field = &points.cracks[c].master_wear;
            if field.is_nodal() {
                // 3D: on the master facet's vertices, with the shape-function weights at Y.
                field.spread(m, volume, &mut master_step[c]);
                continue;
            }
            chart.overlaps(points, i, m, &mut o);
            let total: f64 = o.iter().map(|x| x.1).sum();
            match &points.cracks[c].pair {
                Some(pair) => {
                    for &(j, oij) in &o {
                        let aj = pair.master[j].measure;
                        if aj > 0.0 && total > 0.0 && j < master_step[c].len() {
                            master_step[c][j] += volume * oij / (total * aj);
                        }
                    }
                }
                None => {
                    for &(j, oij) in &o {
                        let aj = points.points[j].weight;
                        if aj > 0.0 && total > 0.0 {
                            state[j].wear_step[0] += volume * oij / (total * aj);
                        }
                    }
                }
            }
        }
    }
    for (c, cc) in points.cracks.iter().enumerate() {
        if !cc.master_wear.is_empty() {
            cc.master_wear.deposit(&master_step[c]);
            deepest[c] = cc.master_wear.now().into_iter().fold(0.0, f64::max);
        }
    }
    for (st, p) in state.iter().zip(&points.points) {
        if points.cracks[p.crack].law.wear.is_some() {
            let now = st.wear_now();
            deepest[p.crack] = deepest[p.crack].max(now[0]).max(now[1]);
        }
    }
    deepest
}

/// Sets, for the slave points of the large-sliding cracks with wear (`chart`), the `+`
/// lip's wear before the step where each meets it under `pairing`
/// ([`PointState::facing_wear`]: in 2D the overlap-weighted mean of the `+` lip's
/// `wear[0]`, or of a pair's master face field [`super::lip_wear::MasterWear`],
/// [`LipChart::overlaps`]; in 3D the nodal field interpolated at the master point,
/// [`super::lip_wear::MasterWear::read`]; 0 for an unpaired point, which is out of contact).
pub fn face_master_wear(points: &ContactPoints, state: &mut [PointState], chart: &LipChart, pairing: &Pairing) {
    let plus: Vec<f64> = state.iter().map(|s| s.wear[0]).collect();
    // The master faces of the pairs: their depth before the step.
    let masters: Vec<Vec<f64>> = points.cracks.iter().map(|cc| cc.master_wear.now()).collect();
    let mut o = vec![];
    for (i, p) in points.points.iter().enumerate() {
        if !LipChart::applies(points, p.crack) {
            continue;
        }
        let nodal = &points.cracks[p.crack].master_wear;
        let field = if points.cracks[p.crack].pair.is_some() { &masters[p.crack][..] } else { &plus[..] };
        let w = match pairing.master(i) {
            // 3D: the nodal field interpolated at the master point.
            Some(m) if nodal.is_nodal() => nodal.read(m),
            Some(m) => {
                chart.overlaps(points, i, m, &mut o);
                let total: f64 = o.iter().map(|x| x.1).sum();
                if total > 0.0 {
                    o.iter().map(|&(j, oij)| oij * field.get(j).copied().unwrap_or(0.0)).sum::<f64>() / total
                } else {
                    0.0
                }
            }
            None => 0.0,
        };
        state[i].facing_wear = Some(w);
    }
}

/// The frictional dissipation of a converged step: Σ_p w_p r_τ·v_τ over the paired points
/// in contact, r_τ the law's tangential traction at the point's final values `vals`
/// ([`CrackLaw::respond`]'s r_s,α, the traction the contact kernel applies) and v_τ the
/// slip increment of the step (from `prev_jump`, the jump at its start). It is the work
/// of the friction tractions on the slip, ≥ 0 up to the solver's tolerance for the laws
/// with multipliers: a sliding point's traction lies along its slip (the return mapping)
/// and a sticking point does not slip. (The penalty law's sticking points store elastic
/// energy in their tangential spring, which this counts as well.)
pub fn frictional_dissipation(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> f64 {
    let nt = points.dim - 1;
    let mut work = 0.0;
    for ((p, st), v) in points.points.iter().zip(state).zip(vals) {
        let law = &points.cracks[p.crack].law;
        if !st.contact || !v.paired || law.friction == 0.0 {
            continue;
        }
        let input = point_input(law, nt, p, st, v.jump, v.d_n, v.lambda, v.big_lambda);
        let r = law.respond(nt, &input);
        let w: f64 = (0..nt).map(|a| r.r_s[1 + a] * input.v[a]).sum();
        work += p.weight * w;
    }
    work
}

/// Starts a step: every point's wear increment of the last step joins its wear
/// ([`PointState::commit_wear`]).
pub fn commit_wear(state: &mut [PointState]) {
    for st in state {
        st.commit_wear();
    }
}

/// Status of each point (open / stick / slip) for the current values and state.
pub fn statuses(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<Status> {
    points
        .points
        .iter()
        .zip(state)
        .zip(vals)
        .map(|((p, st), v)| {
            let law = &points.cracks[p.crack].law;
            if !v.paired || !law.touches(st.contact, v.d_n) {
                return Status::Open;
            }
            if law.friction == 0.0 || st.lam_bar == 0.0 {
                return Status::Slip;
            }
            let vt = slip_increment(points.dim - 1, &p.tangents, v.jump, st.prev_jump);
            let base = law.friction_base(v.big_lambda, st.big_lambda_start);
            if law.sticks(base, vt, st.lam_bar, st.lock) {
                Status::Stick
            } else {
                Status::Slip
            }
        })
        .collect()
}

/// Recomputes the contact status χ_c of every point; returns whether any changed. A
/// crack with the projected-gap augmentation ([`CrackLaw::rho_projected`], ρ_p) reads in
/// the indicator the normal traction the point transmits closed,
/// λ − (ρ_n − ρ_p) d_n − ρ_p Π d_n with the projection over the closed points and the point
/// itself ([`trial_projected_gaps`]): the gap modes the multipliers do not see (not zero at
/// a converged closed state) weigh with ρ_n − ρ_p ≤ E/h only, and do not open points.
pub fn update_contact_status(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> bool {
    let projected = trial_projected_gaps(points, state, vals);
    let mut changed = false;
    for (((st, v), p), pd) in state.iter_mut().zip(vals).zip(&points.points).zip(&projected) {
        let law = &points.cracks[p.crack].law;
        // A dormant point stays open; the zone's check ([`super::zone::check`]) grows the
        // zone where the law would close it.
        let c = v.paired
            && !v.dormant
            && match pd {
                // λ − (ρ_n − ρ_p) d_n − ρ_p Π d_n ≤ 0 (CrackLaw::rho_projected).
                Some(g) => contact_indicator(v.lambda - law.rho_projected * g, v.d_n, law.rho_n - law.rho_projected),
                None => law.contact_indicator(v.lambda, v.d_n),
            };
        changed |= c != st.contact;
        st.contact = c;
    }
    changed
}

/// The projected gap each point of the cracks with the projected-gap augmentation would
/// have closed: Π d_n(x_p) = Σ_j ψ_j(x_p) G_j / W_j with G_j = Σ w ψ_j d_n over the closed
/// points and the point itself, W_j = ∫ψ_j (`ContactPoints::packets`); `None` at the points
/// of the other cracks.
pub fn trial_projected_gaps(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<Option<f64>> {
    project_gaps(points, vals, |pi| state[pi].contact, true)
}

/// Π d_n at every point of the cracks with the projected-gap augmentation (`None`
/// elsewhere), with G_j summed over the points that `counts`, and with `own` each point
/// not counted adds its own share to its packets (the value it would have counted).
fn project_gaps(
    points: &ContactPoints,
    vals: &[PointValues],
    counts: impl Fn(usize) -> bool,
    own: bool,
) -> Vec<Option<f64>> {
    let mut out = vec![None; points.points.len()];
    if points.packets.is_empty() {
        return out;
    }
    // Per crack and packet: G_j and W_j.
    let mut gw: Vec<Vec<(f64, f64)>> = points.cracks.iter().map(|cc| vec![(0.0, 0.0); cc.space.n_unknowns]).collect();
    for pk in &points.packets {
        let g: f64 = pk
            .points
            .iter()
            .filter(|(pi, _)| counts(*pi))
            .map(|&(pi, c)| points.points[pi].weight * c * vals[pi].d_n)
            .sum();
        gw[pk.crack][pk.unknown as usize] = (g, pk.weight);
    }
    for (pi, p) in points.points.iter().enumerate() {
        if points.cracks[p.crack].law.rho_projected <= 0.0 {
            continue;
        }
        let extra = if own && !counts(pi) { p.weight * vals[pi].d_n } else { 0.0 };
        out[pi] = Some(
            p.terms
                .iter()
                .map(|&(j, c)| {
                    let (g, w) = gw[p.crack][j as usize];
                    if w > 0.0 {
                        c * (g + c * extra) / w
                    } else {
                        0.0
                    }
                })
                .sum(),
        );
    }
    out
}

/// A meshed contact pair's point starts closed when its initial gap −d_n is at most this
/// fraction of its slave facet's size (the points where the bodies touch, to round-off of
/// a curved surface's facets).
pub const START_GAP: f64 = 1e-3;

/// The contact statuses of the meshed contact pairs at the start of a run, from the gap in
/// the initial configuration (`vals`: [`point_values`] of the initial pairing and dofs): a
/// point whose gap is at most [`START_GAP`] × its slave facet's size starts closed, the
/// others open. A pair where no point touches keeps its start (`start_closed`): the first
/// solve must hold a body pressed only through the pair. Pairs with `start_closed =
/// false` and cracks are left as they are. Returns the number of points opened.
pub fn start_pairs_from_gap(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> usize {
    let mut opened = 0;
    for (ci, cc) in points.cracks.iter().enumerate() {
        let Some(pair) = cc.pair.as_ref() else { continue };
        if !cc.start_closed {
            continue;
        }
        let touches = |k: usize| {
            let p = &points.points[k];
            vals[k].paired && vals[k].d_n >= -START_GAP * pair.slave[p.facet].measure
        };
        let mine: Vec<usize> = (0..points.points.len()).filter(|&k| points.points[k].crack == ci).collect();
        if !mine.iter().any(|&k| touches(k)) {
            continue;
        }
        for k in mine {
            let c = touches(k);
            opened += usize::from(state[k].contact && !c);
            state[k].contact = c;
        }
    }
    opened
}

/// The hard contact's normal traction that every point transmits, for the thresholds: λ,
/// and at a closed point of a crack with the projected-gap augmentation
/// ([`CrackLaw::rho_projected`], ρ_p) λ − ρ_p Π d_n, the projection over its closed points
/// (the contact kernel's packet term; the pointwise share is not in it, as before). The two are equal at a converged state where every point
/// of a packet is closed; in a packet that straddles the edge of the contact zone the
/// augmented term is not zero (its row holds the open points' −λ/ρ_n), and a threshold λ
/// would make the friction force differ from μ times the normal force there.
pub fn transmitted_lambdas(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<f64> {
    let closed = project_gaps(points, vals, |pi| state[pi].contact, false);
    vals.iter()
        .zip(&points.points)
        .zip(state)
        .zip(&closed)
        .map(|(((v, p), st), pd)| match pd {
            Some(g) if st.contact => v.lambda - points.cracks[p.crack].law.rho_projected * g,
            _ => v.lambda,
        })
        .collect()
}

/// Sets the friction thresholds λ̄ ← min(λ, 0), λ the total normal traction at the point
/// (hard contact plus asperity layer, [`super::law::CrackLaw::threshold_traction`]; 0 where
/// the lips do not touch); returns ‖min(λ, 0) − λ̄_old‖ / ‖λ‖.
///
/// Under large sliding the threshold is set by the traction the point actually
/// transmits, g_n = λ − ρ_n d_n (Alart–Curnier's augmented pressure): once the lips have
/// slid, the master nodes no longer face the slave ones and d_n is zero only in the weak
/// (per packet) sense, so λ and g_n differ between the multiplier nodes; with g_n the
/// tangential force is μ times the normal force point by point. Unpaired points carry
/// none ([`super::law::CrackLaw::threshold_traction`]).
pub fn update_thresholds(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> f64 {
    // The scale: the total normal traction (λ minus the layer's) at every point.
    let norm = vals
        .iter()
        .zip(&points.points)
        .zip(state.iter())
        .map(|((v, p), st)| {
            let law = &points.cracks[p.crack].law;
            let t = v.lambda - law.layer_traction(v.paired, v.d_n, start_gap(law, p, st));
            t * t
        })
        .sum::<f64>()
        .sqrt();
    // A point in tension (possible where the weak contact law leaves a small positive λ)
    // has λ̄ = 0 at the fixed point, so compare with min(λ, 0).
    // An open point transmits no traction: its threshold is 0 (round-off multipliers of an
    // open crack must not start friction passes).
    let lambdas = transmitted_lambdas(points, state, vals);
    let mut diff = 0.0;
    for (((st, v), p), lambda) in state.iter_mut().zip(vals).zip(&points.points).zip(lambdas) {
        let cc = &points.cracks[p.crack];
        let new = if cc.law.touches(st.contact, v.d_n) {
            let d_n_start = start_gap(&cc.law, p, st);
            cc.law.threshold_traction(cc.large_sliding, v.paired, st.contact, lambda, v.d_n, d_n_start).min(0.0)
        } else {
            0.0
        };
        diff += (new - st.lam_bar).powi(2);
        st.lam_bar = new;
    }
    diff.sqrt() / norm.max(f64::MIN_POSITIVE)
}

/// Sets the threshold scale λ_ref of every point ([`PointState::threshold_scale`]): the
/// largest |λ̄| over the points of its contact crack or pair, the weight of the Λ rows where
/// friction does not act ([`CrackLaw::idle_friction_weight`]). The Newton loop sets it when
/// it starts, so it is frozen with the thresholds (a function of them where they are
/// frozen) and stays fixed while thresholds that follow the iterate move
/// ([`live_thresholds`]): the tangent is that of the residual within the loop.
pub fn set_threshold_scales(points: &ContactPoints, state: &mut [PointState]) {
    let mut scale = vec![0.0f64; points.cracks.len()];
    for (p, st) in points.points.iter().zip(state.iter()) {
        scale[p.crack] = scale[p.crack].max(st.lam_bar.abs());
    }
    for (p, st) in points.points.iter().zip(state.iter_mut()) {
        st.threshold_scale = scale[p.crack];
    }
}

/// Sets the friction threshold λ̄ of every point whose law lets it follow the iterate
/// ([`CrackLaw::live_threshold`]) and whose stick/slip status is not locked to its value at
/// `vals` (the update [`update_thresholds`] would make). The Newton loop calls it before
/// every iteration when its tangent carries the threshold's slope; returns whether some
/// point has such a threshold.
pub fn live_thresholds(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> bool {
    let lambdas = transmitted_lambdas(points, state, vals);
    let mut any = false;
    for (((st, v), p), lambda) in state.iter_mut().zip(vals).zip(&points.points).zip(lambdas) {
        let cc = &points.cracks[p.crack];
        if st.lock.is_some() {
            continue;
        }
        let d_n_start = start_gap(&cc.law, p, st);
        if let Some((value, ..)) =
            cc.law.live_threshold(cc.large_sliding, v.paired, st.contact, lambda, v.d_n, d_n_start)
        {
            st.lam_bar = value;
            any = true;
        }
    }
    any
}

/// Relative tolerance of the Coulomb tie: Λ = e is enforced weakly (per multiplier packet),
/// so at sliding points |Λ| is 1 only to about 1e-3.
pub const COULOMB_TIE: f64 = 1e-2;

/// Points in contact whose |g_τ| is 1 within [`COULOMB_TIE`] (stick and slip are both
/// consistent with the law there).
pub fn at_coulomb_limit(points: &ContactPoints, state: &[PointState], vals: &[PointValues]) -> Vec<bool> {
    points
        .points
        .iter()
        .zip(state)
        .zip(vals)
        .map(|((p, st), v)| {
            let law = &points.cracks[p.crack].law;
            if !law.touches(st.contact, v.d_n) || law.friction == 0.0 {
                return false;
            }
            let vt = slip_increment(points.dim - 1, &p.tangents, v.jump, st.prev_jump);
            let g = law.friction_indicator(law.friction_base(v.big_lambda, st.big_lambda_start), vt, st.lam_bar).1;
            (g[0].hypot(g[1]) - 1.0).abs() <= COULOMB_TIE
        })
        .collect()
}

/// Freezes the stick/slip status of every point in contact at its current value (the
/// loops do this when the statuses chatter at the Coulomb tie).
///
/// With an asperity layer the friction law acts wherever λ̄ ≠ 0 ([`CrackLaw::friction_acts`]),
/// also at a point whose layer has just separated at the current iterate (reported open):
/// its stick/slip status is frozen too. Left free, such points (7 of 1 440 on the 3D pad
/// pressed into a layer and slid in one step) flipped between stick and slip at every
/// iteration after the freeze, and the Newton loop cycled with its statuses "frozen".
pub fn freeze_statuses(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) {
    let now = statuses(points, state, vals);
    for (((st, s), p), v) in state.iter_mut().zip(&now).zip(&points.points).zip(vals) {
        if *s != Status::Open {
            st.lock = Some(*s == Status::Stick);
            continue;
        }
        let law = &points.cracks[p.crack].law;
        if v.paired && law.friction * st.lam_bar != 0.0 && law.friction_acts(st.contact) {
            let vt = slip_increment(points.dim - 1, &p.tangents, v.jump, st.prev_jump);
            let base = law.friction_base(v.big_lambda, st.big_lambda_start);
            st.lock = Some(law.sticks(base, vt, st.lam_bar, st.lock));
        }
    }
}

/// The law check of frozen statuses: releases every frozen status and returns whether
/// the frozen ones agree with the law's (a point at the Coulomb limit, where stick and
/// slip both satisfy the law, agrees either way). True when nothing was frozen.
pub fn frozen_statuses_agree(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> bool {
    !frozen_disagreements(points, state, vals).contains(&true)
}

/// The law check of frozen statuses, point by point: releases every frozen status and
/// returns, per point, whether its frozen status disagrees with the law's (never at the
/// Coulomb limit). Empty when nothing was frozen.
pub fn frozen_disagreements(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) -> Vec<bool> {
    if state.iter().all(|s| s.lock.is_none()) {
        return Vec::new();
    }
    let locked = statuses(points, state, vals);
    for s in state.iter_mut() {
        s.lock = None;
    }
    let free = statuses(points, state, vals);
    let at_limit = at_coulomb_limit(points, state, vals);
    locked.iter().zip(&free).zip(&at_limit).map(|((a, b), lim)| a != b && !lim).collect()
}

/// The output of the laws without multipliers (penalty): the λ, Λ slots of such a crack in
/// `u` get the point values `vals` (λ, Λ from the law) projected on its multiplier space,
/// lumped: value_j = Σ_p w_p c_pj f_p / Σ_p w_p c_pj over the crack's points. The ParaView
/// fields and the face tractions of the SIFs then read them as they read multipliers.
pub fn project_point_tractions(points: &ContactPoints, vals: &[PointValues], u: &mut [f64]) {
    let nt = points.dim - 1;
    for (ci, cc) in points.cracks.iter().enumerate() {
        if cc.law.method.has_multipliers() {
            continue;
        }
        let n = cc.space.n_unknowns;
        let mut sums = vec![[0.0; 4]; n];
        for (p, v) in points.points.iter().zip(vals).filter(|(p, _)| p.crack == ci) {
            for &(j, c) in &p.terms {
                let w = p.weight * c;
                let s = &mut sums[j as usize];
                s[0] += w;
                s[1] += w * v.lambda;
                s[2] += w * v.big_lambda[0];
                s[3] += w * v.big_lambda[1];
            }
        }
        for (j, s) in sums.iter().enumerate() {
            let d = if s[0] > 0.0 { s[0] } else { f64::INFINITY };
            u[points.lambda_dof(ci, j as u32)] = s[1] / d;
            for a in 0..nt {
                u[points.tangent_dof(ci, j as u32, a)] = s[2 + a] / d;
            }
        }
    }
}

/// Ends a step for the laws without multipliers: every point's Λ (from `vals`) becomes
/// the tangential state the next step starts from ([`PointState::big_lambda_end`], taken
/// up by [`start_tangential_state`]).
pub fn store_tangential_state(points: &ContactPoints, state: &mut [PointState], vals: &[PointValues]) {
    for ((st, v), p) in state.iter_mut().zip(vals).zip(&points.points) {
        if !points.cracks[p.crack].law.method.has_multipliers() {
            st.big_lambda_end = v.big_lambda;
        }
    }
}

/// Starts a step for the laws without multipliers: the Λ stored at the end of the last
/// step becomes the tangential state of this one ([`PointState::big_lambda_start`]).
pub fn start_tangential_state(points: &ContactPoints, state: &mut [PointState]) {
    for (st, p) in state.iter_mut().zip(&points.points) {
        if !points.cracks[p.crack].law.method.has_multipliers() {
            st.big_lambda_start = st.big_lambda_end;
        }
    }
}

/// The guard against a Newton 2-cycle of the slip direction: a sliding point whose trial
/// g_τ = base + ρ_τ v_τ (base: Λ, or Λ at the start of the step for the penalty law)
/// reversed since the previous iteration (`prev`, updated here) is held stuck (frozen,
/// [`PointState::lock`]) for the rest of the loop. The slip force in one direction moved
/// it the other way, so friction holds it; with a stiff ρ_τ (κ_τ) its trial value jumps
/// across the unit disc and would flip forever with the same statuses (the reversals of a
/// fretting load). A point frozen as sliding ([`freeze_statuses`]) is watched too: it
/// slides along g_τ/|g_τ| whatever |g_τ|, and that direction can flip with every iterate.
/// The loops check the frozen status against the law afterwards ([`frozen_disagreements`]).
pub fn hold_reversed_slips(
    points: &ContactPoints,
    state: &mut [PointState],
    vals: &[PointValues],
    prev: &mut Vec<[f64; 2]>,
) {
    prev.resize(state.len(), [0.0; 2]);
    for (((st, v), p), last) in state.iter_mut().zip(vals).zip(&points.points).zip(prev.iter_mut()) {
        let law = &points.cracks[p.crack].law;
        if !law.friction_acts(st.contact) || st.lock == Some(true) || law.friction * st.lam_bar == 0.0 {
            *last = [0.0; 2];
            continue;
        }
        let vt = slip_increment(points.dim - 1, &p.tangents, v.jump, st.prev_jump);
        let (free_stick, g) =
            law.friction_indicator(law.friction_base(v.big_lambda, st.big_lambda_start), vt, st.lam_bar);
        let stick = free_stick && st.lock.is_none();
        if !stick && g[0] * last[0] + g[1] * last[1] < 0.0 {
            st.lock = Some(true);
            *last = [0.0; 2];
        } else {
            *last = if stick { [0.0; 2] } else { g };
        }
    }
}
