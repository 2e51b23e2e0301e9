//! Contact results on the crack-lip grid of [`super::xfem_output::crack_lips_grid`]: the
//! multipliers and statuses a person looks at in ParaView.
//!
//! Entry points: [`add_contact_fields`], [`wear_figures`]; [`contact_pairs_grid`] (the
//! surfaces of the meshed contact pairs, the `contact` block of the `.pvd`).
//!
//! Point data: `lambda` (normal traction, ≤ 0 in compression), `pressure` (−λ),
//! `pressure_recovered` (the pressure recovered from −λ at the contact points by a local
//! linear fit over three cells, [`crate::contact::recovery`]: the pointwise pressure without
//! the multipliers' packet-to-packet oscillation), `Lambda`
//! (the friction semi-multiplier as a tangent vector Σ Λ_α τ_α), `Lambda_norm` (|Λ| ≤ 1).
//! Cell data: `status` (0 open, 1 stick, 2 slip, the worst over the facet's contact
//! points; −1 on cracks without contact). Gap and slip are the lips' `normal_opening`
//! and `tangential_slip`.
//!
//! With wear (some crack has `[cracks.contact.wear]`), point data `wear_plus`,
//! `wear_minus`, `wear_total` (w⁺, w⁻, w⁺ + w⁻: per facet, the mean over its contact
//! points, except the `+` lip of a 3D crack under large sliding, its nodal field at the
//! facet's vertices; 0 on cracks without wear), and the lips' `displacement` becomes that of the worn
//! surfaces: + w⁺ n on the `+` lip, − w⁻ n on the `−` lip (the worn material is gone when
//! warped). The wear summary of a step is [`wear_figures`]. On the `contact` block of the
//! meshed contact pairs with wear, each face carries its own wear: `wear_minus` on the
//! slave face (per facet, the mean w⁻ of its points), `wear_plus` on the master face (its
//! field: 2D one depth per master facet, 3D the nodal depths at the facet's vertices), 0
//! on the other face, `wear_total` their sum; the
//! `displacement` of each face is that of its worn surface (− w n, n its outward normal).

use crate::contact::law::{PointState, Status};
use crate::contact::points::tangent_basis;
use crate::contact::recovery;
use crate::contact::state::{point_values, statuses};
use crate::contact::ContactSetup;
use crate::io::vtu::{DataArray, UnstructuredGrid};
use crate::physics::model::Model;
use std::collections::HashMap;

/// Adds the contact arrays to a crack-lip grid built for the same model.
pub fn add_contact_fields(
    grid: &mut UnstructuredGrid,
    model: &Model<'_>,
    setup: &ContactSetup,
    u: &[f64],
    state: &[PointState],
    pairing: Option<&crate::contact::pairing::Pairing>,
) {
    let pts = &setup.points;
    let dim = pts.dim;
    let vals = point_values(model, pts, pairing, state, u);
    let st = statuses(pts, state, &vals);
    // (crack, facet) → (contact crack index, facet status).
    let mut facet_info: HashMap<(usize, usize), (usize, f64)> = HashMap::new();
    for (ci, fi, range) in &pts.facets {
        let worst = st[range.clone()].iter().map(|s| *s as u8).max().unwrap_or(0);
        let worst = if st[range.clone()].iter().all(|s| *s == Status::Open) { 0 } else { worst };
        facet_info.insert((pts.cracks[*ci].crack, *fi), (*ci, worst as f64));
    }
    let recovery = recovery::crack_recoveries(pts, &vals.iter().map(|v| v.lambda).collect::<Vec<_>>());
    let np = grid.points.len();
    let mut lambda = vec![0.0; np];
    let mut recovered = vec![0.0; np];
    let mut big = vec![0.0; 3 * np];
    let mut big_norm = vec![0.0; np];
    let mut status = vec![];
    let mut cell = 0usize;
    for (k, cr) in model.cracks.iter().enumerate() {
        for (fi, f) in cr.cut.facets.iter().enumerate() {
            let n = f.vertices.len();
            if f.cell >= model.mesh.n_cells() || !(n == 2 || n == 3) || f.vertices_ref.len() != n {
                continue;
            }
            let info = facet_info.get(&(k, fi)).copied();
            for _lip in 0..2 {
                if cell >= grid.kinds.len() {
                    return;
                }
                let start = if cell == 0 { 0 } else { grid.offsets[cell - 1] as usize };
                let ids: Vec<usize> =
                    grid.connectivity[start..grid.offsets[cell] as usize].iter().map(|&p| p as usize).collect();
                status.push(info.map_or(-1.0, |i| i.1));
                if let Some((ci, _)) = info {
                    let cc = &pts.cracks[ci];
                    let tb = tangent_basis(dim, f.normal, cc.tangent_reference);
                    for (v, &pid) in ids.iter().enumerate().take(n) {
                        let terms = &cc.space.vertex_terms[fi][v];
                        let mut lam = 0.0;
                        let mut tl = [0.0; 2];
                        for &(j, c) in terms {
                            lam += c * u[pts.lambda_dof(ci, j)];
                            for a in 0..dim - 1 {
                                tl[a] += c * u[pts.tangent_dof(ci, j, a)];
                            }
                        }
                        lambda[pid] = lam;
                        recovered[pid] = recovery[ci].at(f.vertices[v], f.normal).unwrap_or(-lam);
                        for a in 0..dim - 1 {
                            for i in 0..3 {
                                big[3 * pid + i] += tl[a] * tb[a][i];
                            }
                        }
                        big_norm[pid] = (tl[0] * tl[0] + tl[1] * tl[1]).sqrt();
                    }
                }
                cell += 1;
            }
        }
    }
    grid.point_data.push(DataArray { name: "lambda".into(), components: 1, values: lambda.clone() });
    grid.point_data.push(DataArray {
        name: "pressure".into(),
        components: 1,
        values: lambda.iter().map(|l| -l).collect(),
    });
    grid.point_data.push(DataArray { name: "pressure_recovered".into(), components: 1, values: recovered });
    grid.point_data.push(DataArray { name: "Lambda".into(), components: 3, values: big });
    grid.point_data.push(DataArray { name: "Lambda_norm".into(), components: 1, values: big_norm });
    grid.cell_data.push(DataArray { name: "status".into(), components: 1, values: status });
    if pts.cracks.iter().any(|c| c.law.wear.is_some()) {
        add_wear_fields(grid, model, setup, state);
    }
}

/// The wear arrays and the worn lip positions (module doc), in the cell order of
/// [`add_contact_fields`].
fn add_wear_fields(grid: &mut UnstructuredGrid, model: &Model<'_>, setup: &ContactSetup, state: &[PointState]) {
    let pts = &setup.points;
    // (crack, facet) → the mean (w⁺, w⁻) of the facet's points.
    let mut facet_wear: HashMap<(usize, usize), [f64; 2]> = HashMap::new();
    for (ci, fi, range) in &pts.facets {
        let n = range.len().max(1) as f64;
        let mut w = [0.0; 2];
        for st in &state[range.clone()] {
            let now = st.wear_now();
            w[0] += now[0] / n;
            w[1] += now[1] / n;
        }
        facet_wear.insert((pts.cracks[*ci].crack, *fi), w);
    }
    let nodal_plus: HashMap<usize, &crate::contact::lip_wear::MasterWear> = pts
        .cracks
        .iter()
        .filter(|c| c.pair.is_none() && c.master_wear.is_nodal())
        .map(|c| (c.crack, &c.master_wear))
        .collect();
    let np = grid.points.len();
    let (mut plus, mut minus) = (vec![0.0; np], vec![0.0; np]);
    let disp = grid.point_data.iter_mut().find(|a| a.name == "displacement");
    let mut disp = disp.map(|a| &mut a.values);
    let mut cell = 0usize;
    for (k, cr) in model.cracks.iter().enumerate() {
        for (fi, f) in cr.cut.facets.iter().enumerate() {
            let n = f.vertices.len();
            if f.cell >= model.mesh.n_cells() || !(n == 2 || n == 3) || f.vertices_ref.len() != n {
                continue;
            }
            let w = facet_wear.get(&(k, fi)).copied().unwrap_or([0.0; 2]);
            // A 3D crack under large sliding: the `+` lip's own (nodal) field at the vertices.
            let nodal = nodal_plus.get(&k).and_then(|m| m.vertex_depths(fi));
            for lip in 0..2 {
                if cell >= grid.kinds.len() {
                    break;
                }
                let start = if cell == 0 { 0 } else { grid.offsets[cell - 1] as usize };
                for (v, &pid) in grid.connectivity[start..grid.offsets[cell] as usize].iter().enumerate() {
                    let pid = pid as usize;
                    let mut w = w;
                    if let Some(d) = nodal {
                        w[0] = d[v.min(2)];
                    }
                    plus[pid] = w[0];
                    minus[pid] = w[1];
                    // The worn surface of the + lip recedes along +n, that of the − lip along −n.
                    let shift = if lip == 0 { w[0] } else { -w[1] };
                    if let Some(d) = disp.as_deref_mut() {
                        for i in 0..3 {
                            d[3 * pid + i] += shift * f.normal[i];
                        }
                    }
                }
                cell += 1;
            }
        }
    }
    let total: Vec<f64> = plus.iter().zip(&minus).map(|(a, b)| a + b).collect();
    grid.point_data.push(DataArray { name: "wear_plus".into(), components: 1, values: plus });
    grid.point_data.push(DataArray { name: "wear_minus".into(), components: 1, values: minus });
    grid.point_data.push(DataArray { name: "wear_total".into(), components: 1, values: total });
}

/// The wear of a run after a step: largest and mean depth w⁺ + w⁻ over the contact points
/// of the cracks with wear (mean weighted by the points' areas), worn volume
/// Σ w_p (w⁺ + w⁻) (an area per unit thickness in 2D) and frictional work Σ w_p ∫μ|λ||dslip|
/// (w_p: the point's integration weight). `None` when no crack has wear. A master surface
/// with its own field (a meshed contact pair's master face, the `+` lip of a 3D crack under
/// large sliding: [`crate::contact::lip_wear::MasterWear`]) adds its Σ_j A_j w⁺_j (A_j the
/// master facet's length in 2D, the vertex's lumped area in 3D) to the volume, and to the
/// largest depth the deepest w⁻ of its slave points plus its deepest w⁺ (a bound of the
/// deepest worn gap, equal to it when the wear is uniform); its slave points' area is the
/// area of the mean (the mean worn gap over the slave face).
pub fn wear_figures(setup: &ContactSetup, state: &[PointState]) -> Option<WearFigures> {
    wear_figures_of(setup, state, |_| true)
}

/// [`wear_figures`] of the contact cracks `keep` selects (by index in
/// `ContactPoints::cracks`): `steps[].contact_pairs[].wear` is one pair's. `None` when none
/// of them has wear.
pub fn wear_figures_of(
    setup: &ContactSetup,
    state: &[PointState],
    keep: impl Fn(usize) -> bool,
) -> Option<WearFigures> {
    let pts = &setup.points;
    let worn = |c: usize| keep(c) && pts.cracks[c].law.wear.is_some();
    if !(0..pts.cracks.len()).any(worn) {
        return None;
    }
    let mut f = WearFigures::default();
    let mut area = 0.0;
    for (p, st) in pts.points.iter().zip(state) {
        if !worn(p.crack) {
            continue;
        }
        let now = st.wear_now();
        let w = now[0] + now[1];
        f.max = f.max.max(w);
        f.volume += p.weight * w;
        f.frictional_work += p.weight * st.frictional_work;
        area += p.weight;
    }
    // The master surfaces with their own field.
    for (c, cc) in pts.cracks.iter().enumerate() {
        if !worn(c) || cc.master_wear.is_empty() {
            continue;
        }
        f.volume += cc.master_wear.volume();
        let deepest = cc.master_wear.now().into_iter().fold(0.0f64, f64::max);
        let slave_deepest = pts
            .points
            .iter()
            .zip(state)
            .filter(|(p, _)| p.crack == c)
            .fold(0.0f64, |m, (_, st)| m.max(st.wear_now()[1]));
        f.max = f.max.max(slave_deepest + deepest);
    }
    f.mean = if area > 0.0 { f.volume / area } else { 0.0 };
    Some(f)
}

/// The wear figures of a step ([`wear_figures`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WearFigures {
    pub max: f64,
    pub mean: f64,
    pub volume: f64,
    pub frictional_work: f64,
}

/// The `contact` block of the output: the slave and master surfaces of every meshed contact
/// pair (segments in 2D, triangles in 3D; points at the undeformed facet vertices, with
/// `displacement` for warping), or `None` without pairs.
///
/// Point data: `displacement`; on slave vertices (the multiplier nodes) `lambda`,
/// `pressure` (−λ) and `Lambda` (Σ Λ_α τ_α), zero on master vertices. Cell data: `pair`
/// (index in the case), `surface` (0 slave, 1 master), `status` (the worst over the
/// facet's contact points; on a master facet, over the slave points paired with it; −1:
/// none), `gap` (mean −d_n of those points: > 0 open) and `slip` (mean tangential
/// relative displacement |⟦u⟧ − (⟦u⟧·n) n| since the start of the run).
pub fn contact_pairs_grid(
    model: &Model<'_>,
    setup: &ContactSetup,
    u: &[f64],
    state: &[PointState],
    pairing: Option<&crate::contact::pairing::Pairing>,
) -> Option<UnstructuredGrid> {
    use crate::io::vtu::VtkCell;
    let pts = &setup.points;
    if pts.cracks.iter().all(|c| c.pair.is_none()) {
        return None;
    }
    let dim = pts.dim;
    let vals = point_values(model, pts, pairing, state, u);
    let st = statuses(pts, state, &vals);
    let mut g = UnstructuredGrid {
        points: vec![],
        connectivity: vec![],
        offsets: vec![],
        kinds: vec![],
        point_data: vec![],
        cell_data: vec![],
    };
    let (mut disp, mut lambda, mut big) = (vec![], vec![], vec![]);
    let wear = pts.cracks.iter().any(|c| c.pair.is_some() && c.law.wear.is_some());
    let (mut wear_plus, mut wear_minus) = (vec![], vec![]);
    let (mut pair_id, mut surface, mut status, mut gap, mut slip) = (vec![], vec![], vec![], vec![], vec![]);
    for (ci, cc) in pts.cracks.iter().enumerate() {
        let Some(pair) = &cc.pair else { continue };
        // Per slave and master facet: (worst status, Σ gap, Σ slip, count) of its points.
        let mut acc_s = vec![(-1i32, 0.0, 0.0, 0usize); pair.slave.len()];
        let mut acc_m = vec![(-1i32, 0.0, 0.0, 0usize); pair.master.len()];
        for (p, pt) in pts.points.iter().enumerate().filter(|(_, pt)| pt.crack == ci) {
            let v = &vals[p];
            let s = if v.paired { st[p] as i32 } else { Status::Open as i32 };
            let jn: f64 = (0..3).map(|i| v.jump[i] * pt.normal[i]).sum();
            let sl = (0..3).map(|i| (v.jump[i] - jn * pt.normal[i]).powi(2)).sum::<f64>().sqrt();
            let add = |a: &mut (i32, f64, f64, usize)| {
                a.0 = a.0.max(s);
                a.1 += -v.d_n;
                a.2 += sl;
                a.3 += 1;
            };
            add(&mut acc_s[pt.facet]);
            if let Some(m) = pairing.and_then(|pr| pr.master(p)) {
                add(&mut acc_m[m.facet as usize]);
            }
        }
        // Per slave facet, the mean w⁻ of its points; per master facet, its field's depth.
        let mut slave_wear = vec![0.0; pair.slave.len()];
        for (ci2, fi, range) in &pts.facets {
            if *ci2 == ci && !range.is_empty() {
                slave_wear[*fi] =
                    state[range.clone()].iter().map(|s| s.wear_now()[1]).sum::<f64>() / range.len() as f64;
            }
        }
        // (3D: the nodal field's vertex depths, below.)
        let mut master_wear = if cc.master_wear.is_nodal() { vec![] } else { cc.master_wear.now() };
        master_wear.resize(pair.master.len(), 0.0);
        for (side, facets, acc) in [(0, &pair.slave, &acc_s), (1, &pair.master, &acc_m)] {
            for (fi, f) in facets.iter().enumerate() {
                // Each face's own wear, and its worn surface receding into its body (−w n,
                // n the face's outward normal).
                let own_facet = if side == 0 { slave_wear[fi] } else { master_wear[fi] };
                let nodal = if side == 1 { cc.master_wear.vertex_depths(fi) } else { None };
                for (k, x) in f.vertices.iter().enumerate() {
                    let own = nodal.map_or(own_facet, |d| d[k.min(2)]);
                    if wear {
                        wear_plus.push(if side == 1 { own } else { 0.0 });
                        wear_minus.push(if side == 0 { own } else { 0.0 });
                    }
                    g.points.push(*x);
                    g.connectivity.push(g.points.len() as u64 - 1);
                    let node = f.vertex_nodes[k].unwrap_or(0);
                    let mut d = [0.0; 3];
                    for i in 0..dim {
                        d[i] = u[node * dim + i] - own * f.normal[i];
                    }
                    disp.extend_from_slice(&d);
                    let (l, t) = if side == 0 {
                        let j = pair.slave_packets[fi][k];
                        let l = u.get(pts.lambda_dof(ci, j)).copied().unwrap_or(0.0);
                        let mut t = [0.0; 3];
                        for a in 0..dim - 1 {
                            let la = u.get(pts.tangent_dof(ci, j, a)).copied().unwrap_or(0.0);
                            for i in 0..3 {
                                t[i] += la * tangent_basis(dim, f.normal, cc.tangent_reference)[a][i];
                            }
                        }
                        (l, t)
                    } else {
                        (0.0, [0.0; 3])
                    };
                    lambda.push(l);
                    big.extend_from_slice(&t);
                }
                g.offsets.push(g.connectivity.len() as u64);
                g.kinds.push(if f.vertices.len() == 2 { VtkCell::Line } else { VtkCell::Triangle });
                let a = acc[fi];
                pair_id.push(pair.index as f64);
                surface.push(side as f64);
                status.push(a.0 as f64);
                let n = a.3.max(1) as f64;
                gap.push(a.1 / n);
                slip.push(a.2 / n);
            }
        }
    }
    g.point_data.push(DataArray::new("displacement", 3, disp));
    g.point_data.push(DataArray::new("pressure", 1, lambda.iter().map(|l| -l).collect()));
    g.point_data.push(DataArray::new("lambda", 1, lambda));
    g.point_data.push(DataArray::new("Lambda", 3, big));
    g.cell_data.push(DataArray::new("pair", 1, pair_id));
    g.cell_data.push(DataArray::new("surface", 1, surface));
    g.cell_data.push(DataArray::new("status", 1, status));
    g.cell_data.push(DataArray::new("gap", 1, gap));
    g.cell_data.push(DataArray::new("slip", 1, slip));
    if wear {
        let total: Vec<f64> = wear_plus.iter().zip(&wear_minus).map(|(a, b)| a + b).collect();
        g.point_data.push(DataArray::new("wear_plus", 1, wear_plus));
        g.point_data.push(DataArray::new("wear_minus", 1, wear_minus));
        g.point_data.push(DataArray::new("wear_total", 1, total));
    }
    Some(g)
}
