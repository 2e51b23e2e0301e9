//! The material of each side of a cut cell, where a crack or interface runs along a
//! material boundary through the cells it cuts.
//!
//! A cell has one material (`[[materials]]` selects whole cells). When a crack follows the
//! boundary between two materials through the middle of a row of cells (a plate on a
//! stiffer base, a coating on a substrate, the interface placed by level sets on a mesh
//! that does not follow it), every cut cell of that row would give both of its sides one
//! material: one lip of the crack would have the other body's stiffness over half a cell
//! (with a contrast of 1e3 or more, the contact loops then chatter or the factorisation
//! fails, `docs/reliability.md`, "Stiffness contrast across an interface"). Here the
//! sub-cells on each side of such a cut cell take the material of that side: the crack is
//! taken to be the material boundary inside the cells it cuts.
//!
//! The rule ([`SideMaterials::along_cracks`]): a cut cell with sub-cells on both sides
//! gets per-side materials when its uncut neighbours (sharing a node) lying wholly on the
//! `−` side all have one material m₋, those wholly on the `+` side all have one material
//! m₊, m₋ ≠ m₊, and the cell's own material is m₋ or m₊. Any other cell keeps its own
//! material on both sides (a layer of a third material one cell thick, mixed neighbours).
//!
//! Entry points: [`SideMaterials::along_cracks`], [`whole_side_neighbours`] (the rule's
//! neighbours, also read by the warning on cells it does not cover), [`SideMaterials::index`] (the material of a
//! quadrature point of a cell, given the side the sub-cell rules give it).

use crate::enrich::CrackGeometry;
use crate::mesh::Mesh;
use std::collections::HashMap;

/// Per-side material indices (`[−, +]`) of the cut cells that a crack splits along a
/// material boundary; every other cell uses its own material.
#[derive(Debug, Clone, Default)]
pub struct SideMaterials {
    sides: HashMap<usize, [u32; 2]>,
    /// Per crack, the number of its cut cells given per-side materials.
    per_crack: Vec<usize>,
}

impl SideMaterials {
    /// No per-side materials (every cell one material).
    pub fn none() -> Self {
        Self::default()
    }

    /// The per-side materials of the cut cells of every crack (the rule in the module doc).
    pub fn along_cracks(mesh: &Mesh, cracks: &[CrackGeometry], cell_material: &[u32]) -> Self {
        let mut sides = HashMap::new();
        let mut per_crack = vec![0; cracks.len()];
        if cracks.is_empty() || cell_material.iter().all(|&m| m == cell_material[0]) {
            return SideMaterials { sides, per_crack };
        }
        let around = mesh.node_cells();
        for (k, crack) in cracks.iter().enumerate() {
            for cc in &crack.cut.cut_cells {
                if sides.contains_key(&cc.cell) || cc.subcells.iter().all(|sc| sc.side == cc.subcells[0].side) {
                    continue;
                }
                // Per side (−, +): the one material of its whole-side uncut neighbours, or
                // `None` when there are none or they differ.
                let mut side: [Option<Option<u32>>; 2] = [None, None];
                for (s, nb) in whole_side_neighbours(mesh, &around, crack, cc.cell) {
                    let m = cell_material[nb];
                    side[s] = match side[s] {
                        None => Some(Some(m)),
                        Some(Some(prev)) if prev == m => Some(Some(m)),
                        _ => Some(None),
                    };
                }
                let own = cell_material[cc.cell];
                if let [Some(Some(minus)), Some(Some(plus))] = side {
                    if minus != plus && (own == minus || own == plus) {
                        sides.insert(cc.cell, [minus, plus]);
                        per_crack[k] += 1;
                    }
                }
            }
        }
        SideMaterials { sides, per_crack }
    }

    /// The material index at a point of cell `c` on `side` (the sub-cell side of the cut
    /// rules, `None` off the cut): the side's material in a cell with per-side materials,
    /// the cell's own otherwise.
    #[inline]
    pub fn index(&self, cell_material: &[u32], c: usize, side: Option<i8>) -> u32 {
        match (side, self.sides.is_empty()) {
            (Some(s), false) => match self.sides.get(&c) {
                Some(m) => m[usize::from(s > 0)],
                None => cell_material[c],
            },
            _ => cell_material[c],
        }
    }

    /// The `[−, +]` materials of cell `c`, if it has per-side materials.
    pub fn of_cell(&self, c: usize) -> Option<[u32; 2]> {
        self.sides.get(&c).copied()
    }

    /// How many of crack `k`'s cut cells have per-side materials.
    pub fn cells_of_crack(&self, k: usize) -> usize {
        self.per_crack.get(k).copied().unwrap_or(0)
    }

    pub fn is_empty(&self) -> bool {
        self.sides.is_empty()
    }
}

/// The uncut cells sharing a node with `cell` that lie wholly on one side of `crack`, each
/// with its side (0: `−`, 1: `+`); `around` is [`Mesh::node_cells`].
pub fn whole_side_neighbours<'a>(
    mesh: &'a Mesh,
    around: &'a (Vec<usize>, Vec<usize>),
    crack: &'a CrackGeometry,
    cell: usize,
) -> impl Iterator<Item = (usize, usize)> + 'a {
    let (offsets, cells) = around;
    let lsn = &crack.levelsets.lsn;
    let mut seen: Vec<usize> = vec![];
    mesh.cells[cell]
        .nodes()
        .iter()
        .flat_map(move |&n| cells[offsets[n]..offsets[n + 1]].iter().copied())
        .filter(move |&nb| {
            let new = nb != cell && !seen.contains(&nb) && crack.cut.cell_cut(nb).is_none();
            if new {
                seen.push(nb);
            }
            new
        })
        .filter_map(move |nb| {
            let nodes = mesh.cells[nb].nodes();
            if nodes.iter().all(|&m| lsn[m] < 0.0) {
                Some((0, nb))
            } else if nodes.iter().all(|&m| lsn[m] > 0.0) {
                Some((1, nb))
            } else {
                None
            }
        })
}
