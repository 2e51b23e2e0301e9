//! X-FEM enrichment: which nodes carry Heaviside and crack-tip dofs, the dof map that
//! numbers them, and the enriched basis evaluated at a point ([`basis`]).
//!
//! Entry points: [`CrackGeometry`] (a crack's level sets and cut, immutable),
//! [`enrich`] (→ [`Enrichment`]), [`basis::CellBasis`].
//!
//! Sets (formulation §2):
//! - K (tip): nodes of cells the front passes through, plus, with geometric enrichment,
//!   every node within the radius r_e of the front (r = √(φn² + φt²) at the node) that is
//!   also within r_e (plus one cell) of a front piece of the cut, i.e. of the front inside
//!   the body: a front just outside the body enriches nothing;
//!   plus nodes whose support holds a cell crossed by φn = 0 ahead of the front next to
//!   the crack (so that no Heaviside function extends the crack beyond its front).
//! - J (Heaviside): nodes of cells cut by the crack, not in K, whose support has at least
//!   `min_side_fraction` of its measure on each side (near-degenerate cuts, a crack
//!   through nodes or along edges, would otherwise make the system singular).
//! - B (blending, corrected X-FEM after Fries 2008): the nodes not in K of every cell
//!   with a node in K. They carry the branch functions too (besides their Heaviside
//!   function if they are in J), and the branch functions of K ∪ B are multiplied by the
//!   ramp R = Σ_{a∈K} N_a (1 on the cells with all nodes in K, 0 on the outer boundary
//!   of the blending cells). Without B the branch functions of the blending cells (some
//!   nodes in K, some not) are an incomplete partition of unity, and their parasitic
//!   terms spoil the local stresses by an amount that does not decrease with h: on a
//!   closed crack under shear and compression the contact pressure oscillates by ±4% to
//!   ±15% in the cells at the enrichment radius without B. The ramp is used in 2D and 3D;
//!   its effect on K_I, on the contact pressure and on the factor size is measured in
//!   `docs/contact-algorithms.md` and `docs/performance.md`.
//!
//! Dof numbering: standard dofs first (`node * dim + c`), then one Heaviside block
//! (per J node and crack, `dim` dofs), then one tip block (per K or B node and crack,
//! the four branch functions × `dim`, function-major).
//!
//! Enrichment functions are shifted, ψ(x) − ψ(x_i), so the nodal values of the
//! displacement are the standard dofs (for B nodes ψ = R F vanishes at the node).

pub mod basis;

use crate::assembly::{DofKind, DofMap};
use crate::cut::{boundary, subcell_measure, CellStatus, CrackCut};
use crate::levelset::NodalLevelSets;
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::fmt;

/// One crack as the solver sees it: its name, its (snapped) nodal level sets, its cut.
#[derive(Debug, Clone)]
pub struct CrackGeometry {
    pub name: String,
    pub levelsets: NodalLevelSets,
    pub cut: CrackCut,
}

/// The two kinds of enrichment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EnrichKind {
    Heaviside,
    Tip,
}

/// One enrichment carried by a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeEnrichment {
    pub crack: u16,
    pub kind: EnrichKind,
    /// First dof of this enrichment (Heaviside: `dim` dofs; tip: `n_functions() * dim`,
    /// function-major).
    pub first_dof: u32,
    /// Tip enrichment of a *blending* node: a node outside the tip set that belongs to a
    /// cell with a node in it (corrected X-FEM, see [`enrich`]). Its branch functions are
    /// ramped and vanish at the node; it may also carry a Heaviside item. Always false for
    /// Heaviside items and for the nodes of the tip set.
    pub blending: bool,
    /// Number of enrichment functions, each with `dim` dofs: 1 Heaviside, 4 branch
    /// functions, [`BLENDING_FUNCTIONS`] on a blending node.
    pub functions: u8,
}

/// The branch functions a blending node carries: F1 = √r sin(θ/2) (the one that is
/// discontinuous across the crack) and F2 = √r cos(θ/2). With all four, the ramped
/// space would be singular: y F1 + x F3 − y F4 = 0 and −y F2 + y F3 + x F4 = 0 (x, y the
/// front-frame coordinates φt, φn), and once every node of the blending cells is
/// enriched, the coefficients (y_a, x_a, −y_a) and (−y_a, y_a, x_a) of the nodes
/// interpolate these linear factors exactly: two zero-energy modes per component and tip.
/// (Keeping all four and dropping F3, F4 at one blending node per tip removes those modes
/// but leaves the stiffness so ill-conditioned, smallest eigenvalue 4e-12 of the largest
/// against 1e-7 with two functions, that the contact Newton loop stalls at 1e-7; with
/// F1, F2, F3 it is 3e-9, from r² F3 + x y F1 − y² F2 = 0.)
/// Dropping F3 and F4 instead at the tip-set node farthest from the front in each
/// connected tip region removes both modes with a usable stiffness (the contact loops
/// converge on meshes 81–241, and the solution does not depend on which node is chosen:
/// the span is the complete corrected X-FEM space). Measured on the closed cracks of
/// issue 4, that complete space halves the worst pressure error of the 45° problem rotated
/// into the mesh axes (`diag_shear`: 2.9% → 1.3% over meshes 81–241) but not that of the
/// 45° crack itself (1.41% → 1.25% on 121, 1.16% → 1.44% on 181, 0.36% → 0.56% on 241),
/// so the blending nodes keep two functions.
pub const BLENDING_FUNCTIONS: usize = 2;

impl NodeEnrichment {
    /// Number of enrichment functions (each with `dim` dofs).
    pub fn n_functions(&self) -> usize {
        self.functions as usize
    }
}

/// How tip enrichment is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TipEnrichment {
    /// Only the nodes of the cells the front passes through.
    Topological,
    /// Every node within `radius` of the front; `None` means two layers of cells
    /// (twice the mean edge length of the front cells).
    Geometric { radius: Option<f64> },
    /// Geometric, with the radius max(`half_length`, two cell layers): the enriched zone of
    /// the two tips of a crack of that half-length covers it, so its edge crosses the crack
    /// only at the centre. The default for segment cracks with contact: where the edge of
    /// the enriched zone crosses a sliding crack the contact pressure carries an error of
    /// 1–2% (`docs/contact-algorithms.md`, "Accuracy near the tips"). In 3D (`disc`,
    /// `elliptic_disc` and `rectangle` cracks with contact) `half_length` is the crack's
    /// depth, the largest distance from a point of the crack to its front, and
    /// `max_node_share` bounds the zone: when the covering radius would tip-enrich more
    /// than that share of the mesh's nodes the radius falls back to two cell layers
    /// ([`Enrichment::tip_radius`] reports the radius used).
    Covering { half_length: f64, max_node_share: Option<f64> },
}

/// The largest share of a mesh's nodes a 3D covering tip zone may take in
/// ([`TipEnrichment::Covering`]): a quarter, so that the tip unknowns (four branch
/// functions per component) are at most as many as the standard ones. Measured on the
/// penny crack of `examples/penny_crack_contact_3d.toml` (`docs/contact-algorithms.md`,
/// "Accuracy near the tips"): covering takes in 51% of the nodes, doubles the unknowns and
/// costs 7× the time and 3.7× the memory of two cell layers; on the through crack of a
/// slab it takes in 2% and removes the wave.
pub const COVERING_NODE_SHARE: f64 = 0.25;

/// Options of [`enrich`].
#[derive(Debug, Clone, PartialEq)]
pub struct EnrichOptions {
    /// Tip enrichment of each crack (same order as the cracks; missing entries take the
    /// default, geometric with two cell layers).
    pub tip: Vec<TipEnrichment>,
    /// A Heaviside node is dropped when the smaller side of its support is below this
    /// fraction of the support's measure.
    pub min_side_fraction: f64,
}

impl Default for EnrichOptions {
    fn default() -> Self {
        EnrichOptions { tip: vec![], min_side_fraction: 1e-4 }
    }
}

/// The enrichment of a model: per node its enrichments, and the dof map.
#[derive(Debug, Clone)]
pub struct Enrichment {
    pub dofs: DofMap,
    offsets: Vec<u32>,
    items: Vec<NodeEnrichment>,
    /// The crack that cuts each cell (or whose front passes through it), if any.
    pub cell_crack: Vec<Option<u16>>,
    /// Tip enrichment radius used for each crack (0 for interfaces).
    pub tip_radius: Vec<f64>,
    pub n_heaviside_nodes: usize,
    pub n_tip_nodes: usize,
    /// Heaviside candidates dropped by the side-fraction test.
    pub n_dropped: usize,
}

/// Why enrichment failed.
#[derive(Debug, Clone, PartialEq)]
pub enum EnrichError {
    /// Two cracks cut the same cell (junctions are not supported).
    SharedCell { first: String, second: String, cell: usize },
    /// Too many cracks for the index type.
    TooManyCracks,
}

impl fmt::Display for EnrichError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EnrichError::SharedCell { first, second, cell } => write!(
                f,
                "cracks '{first}' and '{second}' both cut cell {cell}: crack intersections and junctions are not supported; move one crack or refine the mesh"
            ),
            EnrichError::TooManyCracks => write!(f, "more than 65535 cracks"),
        }
    }
}

impl std::error::Error for EnrichError {}

impl Enrichment {
    /// No cracks: standard dofs only.
    pub fn none(mesh: &Mesh) -> Enrichment {
        Enrichment {
            dofs: DofMap::standard(mesh.dim, mesh.n_nodes()),
            offsets: vec![0; mesh.n_nodes() + 1],
            items: vec![],
            cell_crack: vec![None; mesh.n_cells()],
            tip_radius: vec![],
            n_heaviside_nodes: 0,
            n_tip_nodes: 0,
            n_dropped: 0,
        }
    }

    /// The enrichments of node `n`.
    #[inline]
    pub fn node_items(&self, n: usize) -> &[NodeEnrichment] {
        &self.items[self.offsets[n] as usize..self.offsets[n + 1] as usize]
    }

    /// Whether any node of the cell is enriched.
    pub fn cell_is_enriched(&self, mesh: &Mesh, c: usize) -> bool {
        mesh.cells[c].nodes().iter().any(|&n| self.offsets[n] != self.offsets[n + 1])
    }

    /// Whether any node of the cell is in the tip set K (the branch functions are non-zero
    /// in the cell; the ramped ones of blending nodes vanish in cells without a K node).
    pub fn cell_has_tip(&self, mesh: &Mesh, c: usize) -> bool {
        mesh.cells[c]
            .nodes()
            .iter()
            .any(|&n| self.node_items(n).iter().any(|i| i.kind == EnrichKind::Tip && !i.blending))
    }

    /// The node of every dof of [`Self::dofs`]: `d / dim` for the standard dofs, the
    /// carrying node for the enrichment dofs (dofs of other blocks: `u32::MAX`).
    pub fn dof_nodes(&self) -> Vec<u32> {
        let dim = self.dofs.dim;
        let nn = self.offsets.len() - 1;
        let mut out = vec![u32::MAX; self.dofs.n_total()];
        for (d, v) in out.iter_mut().enumerate().take(dim * nn) {
            *v = (d / dim) as u32;
        }
        for n in 0..nn {
            for item in self.node_items(n) {
                let len = item.functions as usize * dim;
                let start = item.first_dof as usize;
                out[start..start + len].fill(n as u32);
            }
        }
        out
    }

    /// Enrichment flag per node for output: 0 none, 1 Heaviside, 2 tip, 3 both (two cracks).
    /// The ramped tip functions of blending nodes are not flagged.
    pub fn node_flags(&self) -> Vec<f64> {
        (0..self.offsets.len() - 1)
            .map(|n| {
                let mut f = 0u8;
                for i in self.node_items(n).iter().filter(|i| !i.blending) {
                    f |= if i.kind == EnrichKind::Heaviside { 1 } else { 2 };
                }
                f as f64
            })
            .collect()
    }
}

/// The sign of a level-set value with the convention that an exact zero is positive.
#[inline]
pub fn side_of(phi: f64) -> i8 {
    if phi >= 0.0 {
        1
    } else {
        -1
    }
}

/// Computes the enrichment of `mesh` by `cracks`.
pub fn enrich(mesh: &Mesh, cracks: &[CrackGeometry], opts: &EnrichOptions) -> Result<Enrichment, EnrichError> {
    if cracks.len() > u16::MAX as usize {
        return Err(EnrichError::TooManyCracks);
    }
    let nn = mesh.n_nodes();
    let (nc_off, nc) = mesh.node_cells();
    let mut cell_crack: Vec<Option<u16>> = vec![None; mesh.n_cells()];
    for (k, crack) in cracks.iter().enumerate() {
        for cc in &crack.cut.cut_cells {
            if let Some(prev) = cell_crack[cc.cell] {
                return Err(EnrichError::SharedCell {
                    first: cracks[prev as usize].name.clone(),
                    second: crack.name.clone(),
                    cell: cc.cell,
                });
            }
            cell_crack[cc.cell] = Some(k as u16);
        }
    }

    // Per node, per crack: (crack, kind, blending, number of functions).
    let mut per_node: Vec<Vec<(u16, EnrichKind, bool, u8)>> = vec![vec![]; nn];
    let mut tip_radius = vec![0.0; cracks.len()];
    let mut n_dropped = 0;
    for (k, crack) in cracks.iter().enumerate() {
        let cut = &crack.cut;
        let lsn = &crack.levelsets.lsn;
        let mut tip = vec![false; nn];
        if let Some(lst) = &crack.levelsets.lst {
            let front_cells: Vec<usize> =
                cut.cut_cells.iter().filter(|c| c.status == CellStatus::Front).map(|c| c.cell).collect();
            for &c in &front_cells {
                for &n in mesh.cells[c].nodes() {
                    tip[n] = true;
                }
            }
            let choice = opts.tip.get(k).copied().unwrap_or(TipEnrichment::Geometric { radius: None });
            let two_layers = || {
                let h: f64 = front_cells.iter().map(|&c| mesh.cell_edge_length(c)).sum::<f64>()
                    / front_cells.len().max(1) as f64;
                2.0 * h
            };
            let radius = match choice {
                TipEnrichment::Topological => None,
                TipEnrichment::Geometric { radius } => Some(radius.unwrap_or_else(two_layers)),
                TipEnrichment::Covering { half_length, .. } => Some(half_length.max(two_layers())),
            };
            // Within r_e of the front by the level sets (the distance to the front line or
            // surface, extended beyond the body) and of a front piece in the body (up to one
            // cell): a front that lies outside the body, near its surface, enriches nothing.
            let zone = |r_e: f64| -> Vec<usize> {
                if front_cells.is_empty() {
                    return vec![];
                }
                let slack = 0.5 * two_layers();
                let near_piece = |x: &[f64; 3]| {
                    cut.front.iter().any(|p| match p.points.as_slice() {
                        [a] => boundary::distance_to_segment(x, a, a) <= r_e + slack,
                        [a, b] => boundary::distance_to_segment(x, a, b) <= r_e + slack,
                        _ => false,
                    })
                };
                (0..nn)
                    .into_par_iter()
                    .filter(|&n| (lsn[n] * lsn[n] + lst[n] * lst[n]).sqrt() <= r_e && near_piece(&mesh.nodes[n]))
                    .collect()
            };
            if let Some(mut r_e) = radius {
                let mut hits = zone(r_e);
                if let TipEnrichment::Covering { max_node_share: Some(share), .. } = choice {
                    if hits.len() as f64 > share * nn as f64 {
                        r_e = two_layers();
                        hits = zone(r_e);
                    }
                }
                tip_radius[k] = r_e;
                for n in hits {
                    tip[n] = true;
                }
            }
            // Cells crossed by φn = 0 ahead of the front: their nodes must not carry a
            // Heaviside function (it would extend the crack).
            for (c, cell) in mesh.cells.iter().enumerate() {
                if cut.status[c] != CellStatus::Uncut {
                    continue;
                }
                let v = cell.nodes();
                let crossed = v.iter().any(|&n| side_of(lsn[n]) > 0) && v.iter().any(|&n| side_of(lsn[n]) < 0);
                if !crossed {
                    continue;
                }
                let near_crack =
                    v.iter().any(|&n| nc[nc_off[n]..nc_off[n + 1]].iter().any(|&d| cut.status[d] != CellStatus::Uncut));
                if near_crack {
                    for &n in v {
                        tip[n] = true;
                    }
                }
            }
        }
        // Heaviside candidates: nodes of cut cells not in K, with both sides of their support substantial.
        let mut cand = vec![false; nn];
        for cc in cut.cut_cells.iter().filter(|c| c.status == CellStatus::Cut) {
            for &n in mesh.cells[cc.cell].nodes() {
                cand[n] = !tip[n];
            }
        }
        for n in 0..nn {
            if !cand[n] {
                continue;
            }
            let (mut plus, mut minus) = (0.0, 0.0);
            for &c in &nc[nc_off[n]..nc_off[n + 1]] {
                match cut.cell_cut(c) {
                    Some(cc) if cc.status != CellStatus::Uncut => {
                        for sc in &cc.subcells {
                            let m = subcell_measure(mesh, c, sc);
                            if sc.side > 0 {
                                plus += m;
                            } else {
                                minus += m;
                            }
                        }
                    }
                    _ => {
                        let v = mesh.cells[c].nodes();
                        let mean = v.iter().map(|&a| lsn[a]).sum::<f64>() / v.len() as f64;
                        if side_of(mean) > 0 {
                            plus += mesh.cell_measure(c);
                        } else {
                            minus += mesh.cell_measure(c);
                        }
                    }
                }
            }
            if plus.min(minus) < opts.min_side_fraction * (plus + minus) {
                cand[n] = false;
                n_dropped += 1;
            }
        }
        // Blending nodes (corrected X-FEM, Fries 2008): the other nodes of every cell with
        // a node in the tip set. Their ramped branch functions complete the partition of
        // unity of the blending cells (see `basis`).
        let mut blend = vec![false; nn];
        if tip.iter().any(|&t| t) {
            for cell in &mesh.cells {
                let v = cell.nodes();
                if v.iter().any(|&n| tip[n]) {
                    for &n in v {
                        blend[n] |= !tip[n];
                    }
                }
            }
        }
        for n in 0..nn {
            if tip[n] {
                per_node[n].push((k as u16, EnrichKind::Tip, false, 4));
                continue;
            }
            if cand[n] {
                per_node[n].push((k as u16, EnrichKind::Heaviside, false, 1));
            }
            if blend[n] {
                per_node[n].push((k as u16, EnrichKind::Tip, true, BLENDING_FUNCTIONS as u8));
            }
        }
    }

    // Numbering: standard, then the Heaviside block, then the tip block.
    let dim = mesh.dim;
    let mut dofs = DofMap::standard(dim, nn);
    let n_h: usize = per_node.iter().map(|v| v.iter().filter(|i| i.1 == EnrichKind::Heaviside).count()).sum();
    let n_t: usize =
        per_node.iter().map(|v| v.iter().filter(|i| i.1 == EnrichKind::Tip).map(|i| i.3 as usize).sum::<usize>()).sum();
    let h_start = dofs.push_block(DofKind::Heaviside, n_h * dim);
    let t_start = dofs.push_block(DofKind::Tip, n_t * dim);
    let mut offsets = Vec::with_capacity(nn + 1);
    let mut items = vec![];
    let (mut next_h, mut next_t) = (h_start, t_start);
    offsets.push(0u32);
    for list in &per_node {
        for &(crack, kind, blending, functions) in list {
            let first = match kind {
                EnrichKind::Heaviside => {
                    next_h += dim;
                    next_h - dim
                }
                EnrichKind::Tip => {
                    let m = functions as usize * dim;
                    next_t += m;
                    next_t - m
                }
            };
            items.push(NodeEnrichment { crack, kind, first_dof: first as u32, blending, functions });
        }
        offsets.push(items.len() as u32);
    }
    let n_heaviside_nodes = per_node.iter().filter(|v| v.iter().any(|i| i.1 == EnrichKind::Heaviside)).count();
    let n_tip_nodes = per_node.iter().filter(|v| v.iter().any(|i| i.1 == EnrichKind::Tip && !i.2)).count();
    Ok(Enrichment { dofs, offsets, items, cell_crack, tip_radius, n_heaviside_nodes, n_tip_nodes, n_dropped })
}
