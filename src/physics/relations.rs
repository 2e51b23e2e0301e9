//! Linear relations between unknowns, Σ a_k u_{d_k} = c (Code_Aster's LIAISON_DDL and
//! LIAISON_GROUP), enforced with one Lagrange multiplier per relation: the relations of
//! the case file (`[[relations]]`) and the prescribed displacements of one lip of a crack
//! (`[[dirichlet]]` with `crack` and `lip`).
//!
//! Entry points: [`Relation`], [`lip_rows`], [`ConstraintKernel`], [`add_reactions`].
//!
//! A prescribed displacement of the `+` (or `−`) lip holds the field of that side of the
//! crack at the enriched nodes of the group: at node n, component i, the relation is
//! Σ_k ψ_k^s(x_n) u_{k,i} = c(x_n), the enriched basis of a cell around n evaluated at
//! the node on side s. With the shifted Heaviside basis this is u_n + (s − H(x_n)) a_n:
//! u_n at a node on side s, u_n + 2 s a_n at a node across the crack (plus the shifted
//! branch functions at tip-enriched nodes). The side-s field is then the interpolation of
//! these nodal values, so a value that is linear in x (a formula) holds the lip exactly,
//! and a constant holds the whole side-s part of the cut cells. Nodes of the group that
//! are not enriched by the crack and lie on side s get a plain Dirichlet condition;
//! those on the other side are left free.
//!
//! The multiplier rows are symmetric saddle-point rows [0 Bᵀ; B 0] with right-hand side
//! c, like the Dirichlet multipliers ([`super::elasticity::DirichletMultiplierKernel`]),
//! numbered after them.

use super::elasticity::DirichletMultiplierKernel;
use crate::assembly::{Kernel, LocalOut};
use crate::enrich::basis::{CellBasis, Evaluator};
use crate::enrich::{side_of, CrackGeometry, Enrichment};
use crate::formula::Scalar;
use crate::mesh::Mesh;

/// One relation Σ a_k u_{d_k} = value(at, t) between global unknowns.
#[derive(Debug, Clone)]
pub struct Relation {
    /// (global dof, coefficient), each dof once, no zero coefficient.
    pub terms: Vec<(u32, f64)>,
    /// The right-hand side, evaluated at `at` with the ramp of
    /// [`Scalar::eval_load`].
    pub value: Scalar,
    pub at: [f64; 3],
    /// Dirichlet group (index into `Model::dirichlet_groups`) whose reaction sums this
    /// relation's multiplier in `component`; `None` for `[[relations]]`.
    pub reaction: Option<(u32, usize)>,
    /// Human description for errors (`"dirichlet[2], node 14, component x"`).
    pub label: String,
}

impl Relation {
    /// Merges repeated dofs and drops zero coefficients; `None` when nothing is left.
    pub fn new(
        terms: impl IntoIterator<Item = (u32, f64)>,
        value: Scalar,
        at: [f64; 3],
        reaction: Option<(u32, usize)>,
        label: String,
    ) -> Option<Relation> {
        let mut t: Vec<(u32, f64)> = terms.into_iter().collect();
        t.sort_by_key(|p| p.0);
        let mut merged: Vec<(u32, f64)> = vec![];
        for (d, a) in t {
            match merged.last_mut() {
                Some(last) if last.0 == d => last.1 += a,
                _ => merged.push((d, a)),
            }
        }
        let scale = merged.iter().fold(0.0f64, |m, p| m.max(p.1.abs()));
        merged.retain(|p| p.1.abs() > 1e-12 * scale);
        (!merged.is_empty()).then_some(Relation { terms: merged, value, at, reaction, label })
    }
}

/// The relations holding the side `side` (+1 / −1) field of crack `crack` at `node`, one
/// per component, or `None` when the node is not enriched by the crack (the caller then
/// prescribes u_n when the node lies on that side).
pub fn lip_rows(
    mesh: &Mesh,
    enr: &Enrichment,
    cracks: &[CrackGeometry],
    crack: usize,
    node: usize,
    side: i8,
) -> Option<Vec<Vec<(u32, f64)>>> {
    if !enr.node_items(node).iter().any(|i| i.crack as usize == crack) {
        return None;
    }
    let (off, cells) = mesh.node_cells();
    let around = &cells[off[node]..off[node + 1]];
    // A cell cut by the crack if there is one (its sub-cells fix the side), else any.
    let c = around
        .iter()
        .copied()
        .find(|&c| enr.cell_crack[c] == Some(crack as u16))
        .or_else(|| around.first().copied())?;
    let kind = mesh.cells[c].kind;
    let a = mesh.cells[c].nodes().iter().position(|&m| m == node)?;
    let xi = kind.reference_nodes()[a];
    let mut basis = CellBasis::default();
    basis.build(mesh, enr, c);
    let nf = basis.len();
    let (mut vals, mut grads) = (vec![0.0; nf], vec![[0.0; 3]; nf]);
    let ev = Evaluator { mesh, enr, cracks };
    ev.eval(c, &basis, &xi, Some(side), &mut vals, &mut grads).ok()?;
    let dim = mesh.dim;
    Some(
        (0..dim)
            .map(|i| (0..nf).filter(|&k| vals[k] != 0.0).map(|k| (basis.dofs[k * dim + i], vals[k])).collect())
            .collect(),
    )
}

/// Whether `node` lies on side `side` of crack `crack` (by the sign of its φn).
pub fn node_on_side(cracks: &[CrackGeometry], crack: usize, node: usize, side: i8) -> bool {
    side_of(cracks[crack].levelsets.lsn[node]) == side
}

/// The relation rows: relation `e` couples its terms with multiplier `first + e`.
pub struct RelationKernel<'a> {
    pub relations: &'a [Relation],
    pub first: u32,
    /// Load factor of the step.
    pub t: f64,
}

impl Kernel for RelationKernel<'_> {
    fn n_elements(&self) -> usize {
        self.relations.len()
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        out.extend(self.relations[e].terms.iter().map(|p| p.0));
        out.push(self.first + e as u32);
    }
    fn compute(&self, e: usize, _dofs: &[u32], out: LocalOut<'_>) {
        let r = &self.relations[e];
        let m = r.terms.len() + 1;
        if let Some(k) = out.matrix {
            for (j, &(_, a)) in r.terms.iter().enumerate() {
                k[j * m + m - 1] = a;
                k[(m - 1) * m + j] = a;
            }
        }
        if let Some(f) = out.vector {
            f[m - 1] = r.value.eval_load(r.at, self.t);
        }
    }
}

/// Every multiplier row of a model: the Dirichlet multipliers, then the relations.
pub struct ConstraintKernel<'a> {
    pub dirichlet: DirichletMultiplierKernel<'a>,
    pub relations: RelationKernel<'a>,
}

impl Kernel for ConstraintKernel<'_> {
    fn n_elements(&self) -> usize {
        self.dirichlet.n_elements() + self.relations.n_elements()
    }
    fn dofs(&self, e: usize, out: &mut Vec<u32>) {
        let nd = self.dirichlet.n_elements();
        if e < nd {
            self.dirichlet.dofs(e, out)
        } else {
            self.relations.dofs(e - nd, out)
        }
    }
    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>) {
        let nd = self.dirichlet.n_elements();
        if e < nd {
            self.dirichlet.compute(e, dofs, out)
        } else {
            self.relations.compute(e - nd, dofs, out)
        }
    }
}

/// Adds the relations' forces to the reactions of the Dirichlet groups. The multiplier
/// of relation `e` is λ = `u[first + e]`; the relation exerts −a λ on each of its
/// unknowns. A lip relation's force is the reaction of its own group (−λ, the force on
/// the held lip, as for a nodal condition); on an unknown that a nodal condition also
/// holds (`support_group(dof)` gives its group), the nodal reaction, computed from the
/// element forces, is corrected by the relation's share a λ so that it is the support's
/// force alone.
pub fn add_reactions(
    relations: &[Relation],
    first: usize,
    u: &[f64],
    dim: usize,
    support_group: &dyn Fn(usize) -> Option<usize>,
    reactions: &mut [[f64; 3]],
) {
    for (e, r) in relations.iter().enumerate() {
        let lambda = u[first + e];
        if let Some((g, i)) = r.reaction {
            reactions[g as usize][i] -= lambda;
        }
        for &(d, a) in &r.terms {
            if let Some(g) = support_group(d as usize) {
                reactions[g][d as usize % dim] += a * lambda;
            }
        }
    }
}

/// The standard-displacement part of each relation as (node, component, coefficient),
/// for the rigid-body check (enriched unknowns carry no rigid motion).
pub fn rigid_rows(relations: &[Relation], dim: usize, n_std: usize) -> Vec<Vec<(usize, usize, f64)>> {
    relations
        .iter()
        .map(|r| {
            r.terms
                .iter()
                .filter(|p| (p.0 as usize) < n_std)
                .map(|&(d, a)| (d as usize / dim, d as usize % dim, a))
                .collect()
        })
        .filter(|v: &Vec<_>| !v.is_empty())
        .collect()
}
