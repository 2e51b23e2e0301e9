//! The enriched unknowns a Dirichlet condition holds on the boundary faces a crack cuts or
//! whose nodes carry branch functions.
//!
//! Entry point: [`held_enriched`].
//!
//! A `[[dirichlet]]` condition prescribes the standard unknowns of its nodes. The enriched
//! basis functions are shifted (`N_a (ψ − ψ(x_a))`), so they vanish at the nodes but not
//! between them: where one has a non-zero trace on a held face, the held component there
//! is not the interpolant of the prescribed values, and can jump across a crack between
//! two held nodes. So on every boundary face whose nodes all have component `c` held (a
//! *held face*), the component-`c` unknowns of each enrichment function of a face node
//! whose trace on the face is not zero are held at 0 too; the held field on the face is
//! then the standard interpolant of the prescribed values, continuous across the crack.
//! The trace of `N_a (ψ − ψ(x_a))` on a face F of cell C (only the nodes of F have shape
//! functions that do not vanish on F):
//! - Heaviside of crack k: H on F is the side of the sub-cell when C is cut by k
//!   ([`crate::enrich::Enrichment::cell_crack`]; then F has a positive-measure part on the
//!   `−` side iff a node of F has φn < 0, on the `+` side iff a node has φn > 0 or none has
//!   φn < 0), the side of C's mean φn otherwise. The trace is zero iff H ≡ H(x_a) on F:
//!   a face the crack does not cross keeps its nodes' Heaviside unknowns (the enrichment
//!   of a crack that passes near the face), a face it crosses, or a node the crack passes
//!   through whose face lies on the other side, has them held.
//! - Branch functions of a node of the tip set: they vary over every face (r, θ are not
//!   constant on it), so they are held on every held face of the node.
//! - The ramped branch functions of a blending node (`R F_l N_a`, R = Σ_{b∈K} N_b): R
//!   vanishes on a face without a tip-set node of the crack, so they are held only on faces
//!   with one.
//!
//! Where the prescribed values themselves jump across the crack on a face (a formula
//! discontinuous there, e.g. an exact near-tip field with `signum(y)`), the continuous
//! interpolant cannot hold both sides' values: that face keeps its enriched unknowns of
//! that component free, and the condition holds the nodes only (`data_jumps`; a
//! prescribed jump is held per lip by lip conditions).
//!
//! Only boundary faces count: a face shared by two cells is no support. Lip conditions
//! (`crack`, `lip`) are relations, not held nodes here (see [`super::relations`]).

use super::model::DirichletCondition;
use crate::enrich::{side_of, CrackGeometry, EnrichKind, Enrichment};
use crate::mesh::Mesh;

/// One enriched unknown held at 0 by a Dirichlet condition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeldEnriched {
    /// The enriched dof.
    pub dof: usize,
    /// The index (into the model's `dirichlet`) of the condition on the node's standard
    /// dof of the same component that makes it held: its group is the group that holds it.
    pub condition: u32,
}

/// The enriched unknowns held at 0 on the held boundary faces (module doc), ascending by
/// dof. `dirichlet` are the model's plain conditions (the last one on a dof wins, as in
/// the set-up).
pub fn held_enriched(
    mesh: &Mesh,
    cracks: &[CrackGeometry],
    enrichment: &Enrichment,
    dirichlet: &[DirichletCondition],
) -> Vec<HeldEnriched> {
    let dim = mesh.dim;
    let nn = mesh.n_nodes();
    if dirichlet.is_empty() || cracks.is_empty() || enrichment.dofs.n_total() == dim * nn {
        return vec![];
    }
    let mut cond_of_dof = vec![u32::MAX; dim * nn];
    for (k, c) in dirichlet.iter().enumerate() {
        cond_of_dof[c.node * dim + c.component] = k as u32;
    }
    let enriched = |n: usize| !enrichment.node_items(n).is_empty();
    // The candidate faces: faces with an enriched node and, for some component, every node
    // held. A face shared by two cells appears twice (both cells have its enriched node).
    let mut faces: Vec<([usize; 4], usize, u8)> = vec![];
    for (ci, cell) in mesh.cells.iter().enumerate() {
        if !cell.nodes().iter().any(|&n| enriched(n)) {
            continue;
        }
        for (k, (_, loc)) in cell.kind.faces().iter().enumerate() {
            let nodes = loc.iter().map(|&a| cell.nodes[a]);
            if !nodes.clone().any(enriched) {
                continue;
            }
            if !(0..dim).any(|c| nodes.clone().all(|n| cond_of_dof[n * dim + c] != u32::MAX)) {
                continue;
            }
            let mut key = [usize::MAX; 4];
            for (i, n) in nodes.enumerate() {
                key[i] = n;
            }
            key[..loc.len()].sort_unstable();
            faces.push((key, ci, k as u8));
        }
    }
    faces.sort_unstable();
    let mut held: Vec<HeldEnriched> = vec![];
    let mut i = 0;
    while i < faces.len() {
        let mut j = i + 1;
        while j < faces.len() && faces[j].0 == faces[i].0 {
            j += 1;
        }
        if j == i + 1 {
            let (_, ci, k) = faces[i];
            face_unknowns(mesh, cracks, enrichment, dirichlet, &cond_of_dof, ci, k as usize, &mut held);
        }
        i = j;
    }
    held.sort_unstable_by_key(|h| h.dof);
    held.dedup_by_key(|h| h.dof);
    held
}

/// The enriched unknowns held on face `k` of cell `ci` (a boundary face), into `out`.
#[allow(clippy::too_many_arguments)]
fn face_unknowns(
    mesh: &Mesh,
    cracks: &[CrackGeometry],
    enrichment: &Enrichment,
    dirichlet: &[DirichletCondition],
    cond_of_dof: &[u32],
    ci: usize,
    k: usize,
    out: &mut Vec<HeldEnriched>,
) {
    let dim = mesh.dim;
    let cell = &mesh.cells[ci];
    let loc = cell.kind.faces()[k].1;
    let face: Vec<usize> = loc.iter().map(|&a| cell.nodes[a]).collect();
    // The sides the Heaviside of crack `kc` takes on the face with positive measure
    // ([−, +]).
    let sides = |kc: usize| -> [bool; 2] {
        let lsn = &cracks[kc].levelsets.lsn;
        if enrichment.cell_crack[ci] == Some(kc as u16) {
            let neg = face.iter().any(|&n| lsn[n] < 0.0);
            let pos = face.iter().any(|&n| lsn[n] > 0.0) || !neg;
            [neg, pos]
        } else {
            let nodes = cell.nodes();
            let mean = nodes.iter().map(|&n| lsn[n]).sum::<f64>() / nodes.len() as f64;
            let s = side_of(mean);
            [s < 0, s > 0]
        }
    };
    let in_tip_set = |n: usize, kc: u16| {
        enrichment.node_items(n).iter().any(|i| i.crack == kc && i.kind == EnrichKind::Tip && !i.blending)
    };
    for c in 0..dim {
        if !face.iter().all(|&n| cond_of_dof[n * dim + c] != u32::MAX) {
            continue;
        }
        if data_jumps(mesh, cracks, dirichlet, cond_of_dof, &face, c) {
            continue;
        }
        for &n in &face {
            let condition = cond_of_dof[n * dim + c];
            for item in enrichment.node_items(n) {
                let hold = match item.kind {
                    EnrichKind::Heaviside => {
                        let s = sides(item.crack as usize);
                        let own = side_of(cracks[item.crack as usize].levelsets.lsn[n]);
                        // Zero trace iff H is the node's own side everywhere on the face.
                        s != [own < 0, own > 0]
                    }
                    EnrichKind::Tip if item.blending => face.iter().any(|&m| in_tip_set(m, item.crack)),
                    EnrichKind::Tip => true,
                };
                if hold {
                    for l in 0..item.n_functions() {
                        out.push(HeldEnriched { dof: item.first_dof as usize + l * dim + c, condition });
                    }
                }
            }
        }
    }
}

/// Whether the prescribed values of component `c` jump across a crack on the face (nodes
/// `face`, in the cell's face order): on each edge of the face whose ends lie on two sides
/// of a crack, the values of its two nodes' conditions (at t = 1) just before and just after
/// the crossing differ by more than a thousandth of their difference between the two nodes
/// (a continuous value changes by 2e-6 of it there) plus 1e-9 of their size (round-off). The standard interpolant cannot hold
/// both sides' values: such a face keeps its enriched unknowns free, as a condition on the
/// nodes only (an exact near-tip field with `signum(y)` prescribed on a cut boundary).
fn data_jumps(
    mesh: &Mesh,
    cracks: &[CrackGeometry],
    dirichlet: &[DirichletCondition],
    cond_of_dof: &[u32],
    face: &[usize],
    c: usize,
) -> bool {
    let dim = mesh.dim;
    let len = face.len();
    let edges = if len == 2 { 1 } else { len };
    for cr in cracks {
        let lsn = &cr.levelsets.lsn;
        for e in 0..edges {
            let (a, b) = (face[e], face[(e + 1) % len]);
            if side_of(lsn[a]) == side_of(lsn[b]) {
                continue;
            }
            let (xa, xb) = (mesh.nodes[a], mesh.nodes[b]);
            let s = lsn[a] / (lsn[a] - lsn[b]);
            let at = |f: f64| [0, 1, 2].map(|i| xa[i] + f * (xb[i] - xa[i]));
            let delta = 1e-6;
            for n in [a, b] {
                let g = &dirichlet[cond_of_dof[n * dim + c] as usize].value;
                let (g0, g1) = (g.eval_load(at(s - delta), 1.0), g.eval_load(at(s + delta), 1.0));
                let (ga, gb) = (g.eval_load(xa, 1.0), g.eval_load(xb, 1.0));
                let jump = (g1 - g0).abs();
                let size = ga.abs().max(gb.abs()).max(g0.abs()).max(g1.abs());
                if jump > 1e-3 * (gb - ga).abs() + 1e-9 * size {
                    return true;
                }
            }
        }
    }
    false
}
