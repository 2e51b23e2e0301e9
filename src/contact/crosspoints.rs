//! Crosspoint multipliers: the multiplier components whose constraint the Dirichlet
//! conditions (with the enriched unknowns they hold on the faces a crack cuts,
//! `physics::held_faces`) and linear relations of both sides already impose, found once when the
//! contact is set up and eliminated from the system (value 0), as mortar methods remove the
//! multipliers of their crosspoints.
//!
//! Entry points: [`find`] (the crosspoints of every contact crack) and [`Crosspoints`]
//! (their dofs, [`Crosspoints::dofs`], and the notes the run and `fissure check` print,
//! [`Crosspoints::notes`]).
//!
//! ```text
//! packet j, component d (n: λ; τ_α: Λ_α), node x_j of the packet
//! row r = d·⟦u⟧(x_j) on the dofs        (⟦u⟧ = u_master(Y) − u_slave(x_j) for a pair)
//! crosspoint  ⇔  r ∈ span{e_k : dof k prescribed} + span{relation rows}
//! ```
//!
//! The row at the packet's node: a point with coefficient 1 on the packet (`vertex`,
//! `nodes`: the slave node itself); with segment-to-segment points (`gauss`, 2D), the
//! linear extrapolation to the node of the rows at the two points of the piece next to it
//! (the same slave and master facet, where both traces are linear in the slave
//! coordinate); for a 3D pair, the row at the slave node paired with the point facing it on
//! the master facet of the packet's nearest point. A component
//! whose row is a combination of Dirichlet rows has, at a point at the node, an empty row
//! once the prescribed dofs are eliminated ("unknown … has no nonzero coefficient"), and
//! with segment-to-segment points a row that makes the packets' rows linearly dependent.
//! Tangential components are examined only with friction (μ > 0: without it Λ has no
//! kinematic row). Cracks and pairs that pair again as they slide (`repair`) are not
//! examined: the master point facing a node changes.

use super::pairing::{pair, ElementBasis, Pairing, PairingOptions};
use super::points::ContactPoints;
use super::state::{basis_jumps, paired_jumps};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::mesh::Mesh;
use crate::physics::model::Model;
use std::collections::HashMap;

/// One eliminated multiplier component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crosspoint {
    /// Contact crack (index into `ContactPoints::cracks`).
    pub crack: usize,
    /// Packet of the multiplier space.
    pub packet: u32,
    /// 0: the normal multiplier λ; 1 + α: the friction multiplier Λ_α.
    pub component: usize,
}

/// The crosspoint multipliers of a contact set-up.
#[derive(Debug, Clone, Default)]
pub struct Crosspoints {
    pub list: Vec<Crosspoint>,
}

impl Crosspoints {
    /// The dofs of the eliminated components.
    pub fn dofs<'a>(&'a self, points: &'a ContactPoints) -> impl Iterator<Item = usize> + 'a {
        self.list.iter().map(|c| match c.component {
            0 => points.lambda_dof(c.crack, c.packet),
            a => points.tangent_dof(c.crack, c.packet, a - 1),
        })
    }

    /// One note per contact crack with crosspoints: the pair (or crack) and the number of
    /// multipliers removed, with the nodes (pairs) or positions of the packets.
    pub fn notes(&self, mesh: &Mesh, points: &ContactPoints, crack_names: &[String]) -> Vec<String> {
        let mut out = vec![];
        for (ci, cc) in points.cracks.iter().enumerate() {
            let here: Vec<&Crosspoint> = self.list.iter().filter(|c| c.crack == ci).collect();
            if here.is_empty() {
                continue;
            }
            let what = match &cc.pair {
                Some(p) => format!("contact pair '{}'", p.name),
                None => format!("crack '{}'", crack_names.get(cc.crack).map_or("?", |s| s.as_str())),
            };
            let (n_normal, n_friction) =
                (here.iter().filter(|c| c.component == 0).count(), here.iter().filter(|c| c.component > 0).count());
            let mut packets: Vec<u32> = here.iter().map(|c| c.packet).collect();
            packets.dedup();
            let at: Vec<String> = packets
                .iter()
                .take(6)
                .map(|&j| {
                    let node = cc.pair.as_ref().and_then(|p| p.slave_nodes.get(j as usize)).copied();
                    let x = match node {
                        Some(n) => mesh.nodes[n],
                        None => cc.space.unknown_points.get(j as usize).copied().unwrap_or([f64::NAN; 3]),
                    };
                    let pos = (0..points.dim).map(|i| format!("{:.6e}", x[i])).collect::<Vec<_>>().join(", ");
                    match node {
                        Some(n) => format!("slave node {n} at ({pos})"),
                        None => format!("({pos})"),
                    }
                })
                .collect();
            out.push(format!(
                "{what}: {} crosspoint multiplier(s) removed ({n_normal} normal, {n_friction} friction) at {}{}: the Dirichlet conditions (or relations) of both sides already fix the relative motion there, so the contact point carries no such constraint and its supports take the force (docs/contact-algorithms.md, \"Crosspoints\")",
                here.len(),
                at.join("; "),
                if packets.len() > at.len() { ", …" } else { "" },
            ));
        }
        out
    }
}

/// Relative size of the residual of a row, after removing its Dirichlet and relation
/// parts, below which it is a combination of them.
const DEPENDENT: f64 = 1e-10;

/// The crosspoint multipliers of `points` for the Dirichlet conditions and relations of
/// `model` (see the module doc).
pub fn find(model: &Model<'_>, points: &ContactPoints) -> Crosspoints {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let examined: Vec<bool> =
        points.cracks.iter().map(|cc| cc.law.method.has_multipliers() && !(cc.large_sliding && cc.repair)).collect();
    if !examined.iter().any(|&b| b) || (model.dirichlet.is_empty() && model.relations.is_empty()) {
        return Crosspoints::default();
    }
    let dofs = &model.enrichment.dofs;
    let mut fixed = vec![false; dofs.n_total()];
    for c in &model.dirichlet {
        fixed[dofs.node_dof(c.node, c.component)] = true;
    }
    // The enriched unknowns the conditions hold on the faces a crack cuts.
    for h in crate::physics::held_faces::held_enriched(mesh, &model.cracks, &model.enrichment, &model.dirichlet) {
        fixed[h.dof] = true;
    }
    let mut relations_of: HashMap<u32, Vec<usize>> = HashMap::new();
    for (k, r) in model.relations.iter().enumerate() {
        for &(d, _) in &r.terms {
            relations_of.entry(d).or_default().push(k);
        }
    }
    // Candidates: the packets with a point in a cell that has a held node (a prescribed
    // dof or one in a relation); only they are examined, so that the usual model (no
    // support near its contact surfaces) costs one pass over the points.
    let dof_nodes = model.enrichment.dof_nodes();
    let mut held = vec![false; mesh.n_nodes()];
    for c in &model.dirichlet {
        held[c.node] = true;
    }
    for &d in relations_of.keys() {
        if let Some(&n) = dof_nodes.get(d as usize).filter(|&&n| n != u32::MAX) {
            held[n as usize] = true;
        }
    }
    let near_held = |cell: usize| mesh.cells[cell].nodes().iter().any(|&n| held[n]);
    let mut candidate: Vec<Vec<bool>> = points.cracks.iter().map(|cc| vec![false; cc.space.n_unknowns]).collect();
    for p in points.points.iter().filter(|p| examined[p.crack] && near_held(p.cell)) {
        for &(j, _) in &p.terms {
            candidate[p.crack][j as usize] = true;
        }
    }
    if !candidate.iter().flatten().any(|&b| b) {
        return Crosspoints::default();
    }
    let needs_pairing = points.cracks.iter().zip(&candidate).any(|(cc, c)| cc.large_sliding && c.iter().any(|&b| b));
    let pairing = needs_pairing.then(|| {
        pair(
            mesh,
            &model.enrichment,
            &model.cracks,
            points,
            &vec![0.0; dofs.n_total()],
            &PairingOptions::default(),
            &[],
        )
    });
    let ev = Evaluator { mesh, enr: &model.enrichment, cracks: &model.cracks };
    let (mut basis, mut eb, mut jump) = (CellBasis::default(), ElementBasis::default(), Vec::new());
    // The jump operator at point `pi`: (dof of function k component i at k·dim + i, J_k).
    let mut operator = |pi: usize| -> Option<(Vec<u32>, Vec<f64>)> {
        let p = &points.points[pi];
        let cc = &points.cracks[p.crack];
        if cc.large_sliding {
            let m = pairing.as_ref()?.master(pi)?;
            eb.build(mesh, &model.enrichment, p.cell, std::slice::from_ref(&m.cell), None);
            paired_jumps(&ev, &mut eb, p, m, cc.pair.is_some(), &mut jump).then(|| (eb.dofs.clone(), jump.clone()))
        } else {
            basis.build(mesh, &model.enrichment, p.cell);
            basis_jumps(&ev, p.cell, &p.xi, &basis, &mut jump);
            Some((basis.dofs.clone(), jump.clone()))
        }
    };
    let master_facet = |pi: usize| pairing.as_ref().and_then(|pr: &Pairing| pr.master(pi)).map(|m| m.facet);
    let mut list = vec![];
    for (ci, cc) in points.cracks.iter().enumerate() {
        if !examined[ci] {
            continue;
        }
        // Points by packet: (point, coefficient).
        let mut of_packet: Vec<Vec<(usize, f64)>> = vec![vec![]; cc.space.n_unknowns];
        for (pi, p) in points.points.iter().enumerate().filter(|(_, p)| p.crack == ci) {
            for &(j, c) in &p.terms {
                if c > 0.0 {
                    of_packet[j as usize].push((pi, c));
                }
            }
        }
        let components = if cc.law.friction > 0.0 { dim } else { 1 };
        for (j, pts) in of_packet.iter().enumerate().filter(|(j, _)| candidate[ci][*j]) {
            // The rows at the packet's node, each as (operator, direction per component).
            let at_node: Vec<usize> = pts.iter().filter(|(_, c)| *c > 1.0 - 1e-9).map(|(pi, _)| *pi).collect();
            let mut rows: Vec<Vec<Vec<(u32, f64)>>> = vec![];
            if !at_node.is_empty() {
                for &pi in &at_node {
                    let Some((d, jmp)) = operator(pi) else { continue };
                    rows.push(
                        (0..components).map(|a| directional_row(dim, &d, &jmp, direction(points, pi, a))).collect(),
                    );
                }
            } else if dim == 2 {
                // The two points nearest the node on one piece (same slave and master
                // facet), extrapolated linearly in the coefficient to 1.
                let mut best: Option<(usize, usize)> = None;
                let mut sorted = pts.clone();
                sorted.sort_by(|a, b| b.1.total_cmp(&a.1));
                if let Some(&(p0, c0)) = sorted.first() {
                    let key = |pi: usize| (points.points[pi].facet, master_facet(pi));
                    if let Some(&(p1, _)) =
                        sorted[1..].iter().find(|(pi, c)| key(*pi) == key(p0) && (c0 - c).abs() > 1e-6)
                    {
                        best = Some((p0, p1));
                    }
                }
                if let Some((p0, p1)) = best {
                    let c0 = pts.iter().find(|x| x.0 == p0).map_or(0.0, |x| x.1);
                    let c1 = pts.iter().find(|x| x.0 == p1).map_or(0.0, |x| x.1);
                    if let (Some((d0, j0)), Some((d1, j1))) = (operator(p0), operator(p1)) {
                        let t = (1.0 - c0) / (c1 - c0);
                        rows.push(
                            (0..components)
                                .map(|a| {
                                    let r0 = directional_row(dim, &d0, &j0, direction(points, p0, a));
                                    let r1 = directional_row(dim, &d1, &j1, direction(points, p1, a));
                                    combine(&r0, 1.0 - t, &r1, t)
                                })
                                .collect(),
                        );
                    }
                }
            } else if let (Some(surf), Some(pr)) = (&cc.pair, &pairing) {
                // 3D pair: the row at the slave node itself, paired with the point of the
                // master facet of the packet's nearest point that faces the node.
                let Some(&(p0, _)) = pts.iter().max_by(|a, b| a.1.total_cmp(&b.1)) else { continue };
                let sp0 = &points.points[p0];
                let (Some(m0), Some(v)) = (
                    pr.master(p0),
                    surf.slave_packets.get(sp0.facet).and_then(|f| f.iter().position(|&q| q as usize == j)),
                ) else {
                    continue;
                };
                let (sf, mf) = (&surf.slave[sp0.facet], &surf.master[m0.facet as usize]);
                let b = super::facet_barycentric(&mf.vertices, sf.vertices[v]);
                if b.iter().any(|&x| x < -1e-9) {
                    continue;
                }
                let mut node = sp0.clone();
                node.xi = sf.vertices_ref[v];
                node.x = sf.vertices[v];
                let (mut xi, mut x) = ([0.0; 3], [0.0; 3]);
                for (k, bk) in b.iter().enumerate() {
                    for i in 0..3 {
                        xi[i] += bk * mf.vertices_ref[k][i];
                        x[i] += bk * mf.vertices[k][i];
                    }
                }
                let m = super::pairing::MasterPoint { facet: m0.facet, cell: m0.cell, xi, x };
                let (mut eb3, mut jmp) = (ElementBasis::default(), Vec::new());
                eb3.build(mesh, &model.enrichment, node.cell, std::slice::from_ref(&m.cell), None);
                if paired_jumps(&ev, &mut eb3, &node, &m, true, &mut jmp) {
                    rows.push(
                        (0..components)
                            .map(|a| directional_row(dim, &eb3.dofs, &jmp, direction(points, p0, a)))
                            .collect(),
                    );
                }
            }
            if rows.is_empty() {
                continue;
            }
            for a in 0..components {
                if rows.iter().all(|r| is_dependent(&r[a], &fixed, &relations_of, model)) {
                    list.push(Crosspoint { crack: ci, packet: j as u32, component: a });
                }
            }
        }
    }
    Crosspoints { list }
}

/// The direction of component `a` at point `pi`: the normal (a = 0) or tangent a − 1.
fn direction(points: &ContactPoints, pi: usize, a: usize) -> [f64; 3] {
    let p = &points.points[pi];
    if a == 0 {
        p.normal
    } else {
        p.tangents[a - 1]
    }
}

/// d·⟦u⟧ as a sorted sparse row from the jump operator (`dofs[k·dim + i]`, J_k).
fn directional_row(dim: usize, dofs: &[u32], jump: &[f64], d: [f64; 3]) -> Vec<(u32, f64)> {
    let mut row: Vec<(u32, f64)> = vec![];
    for (k, &jk) in jump.iter().enumerate() {
        for i in 0..dim {
            let v = jk * d[i];
            if v != 0.0 {
                row.push((dofs[k * dim + i], v));
            }
        }
    }
    merge(row)
}

/// Sorts by dof and adds repeated dofs.
fn merge(mut row: Vec<(u32, f64)>) -> Vec<(u32, f64)> {
    row.sort_by_key(|x| x.0);
    let mut out: Vec<(u32, f64)> = Vec::with_capacity(row.len());
    for (d, v) in row {
        match out.last_mut() {
            Some(l) if l.0 == d => l.1 += v,
            _ => out.push((d, v)),
        }
    }
    out
}

/// a·x + b·y.
fn combine(x: &[(u32, f64)], a: f64, y: &[(u32, f64)], b: f64) -> Vec<(u32, f64)> {
    merge(x.iter().map(|&(d, v)| (d, a * v)).chain(y.iter().map(|&(d, v)| (d, b * v))).collect())
}

fn norm(x: &[(u32, f64)]) -> f64 {
    x.iter().map(|v| v.1 * v.1).sum::<f64>().sqrt()
}

fn dot(x: &[(u32, f64)], y: &[(u32, f64)]) -> f64 {
    let (mut i, mut k, mut s) = (0, 0, 0.0);
    while i < x.len() && k < y.len() {
        match x[i].0.cmp(&y[k].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => k += 1,
            std::cmp::Ordering::Equal => {
                s += x[i].1 * y[k].1;
                i += 1;
                k += 1;
            }
        }
    }
    s
}

/// Whether `row` is a combination of the unit rows of the prescribed dofs and of the
/// relations that share a free dof with it (Gram–Schmidt on those relations' free parts).
fn is_dependent(
    row: &[(u32, f64)],
    fixed: &[bool],
    relations_of: &HashMap<u32, Vec<usize>>,
    model: &Model<'_>,
) -> bool {
    let scale = norm(row);
    let free = |r: &[(u32, f64)]| -> Vec<(u32, f64)> {
        r.iter().filter(|(d, v)| *v != 0.0 && !fixed.get(*d as usize).copied().unwrap_or(false)).copied().collect()
    };
    let mut res = free(row);
    if scale == 0.0 || norm(&res) <= DEPENDENT * scale {
        return true;
    }
    let mut touching: Vec<usize> =
        res.iter().flat_map(|(d, _)| relations_of.get(d).into_iter().flatten().copied()).collect();
    touching.sort_unstable();
    touching.dedup();
    let mut basis: Vec<Vec<(u32, f64)>> = vec![];
    for k in touching {
        let mut q = free(&model.relations[k].terms);
        for b in &basis {
            let c = dot(&q, b);
            q = combine(&q, 1.0, b, -c);
        }
        let nq = norm(&q);
        if nq > 1e-12 * norm(&model.relations[k].terms) {
            basis.push(q.iter().map(|&(d, v)| (d, v / nq)).collect());
        }
    }
    for b in &basis {
        let c = dot(&res, b);
        res = combine(&res, 1.0, b, -c);
    }
    norm(&res) <= DEPENDENT * scale
}
