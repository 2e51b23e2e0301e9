//! The partition of the cells among the MPI ranks (distributed assembly): METIS's
//! `METIS_PartMeshDual` on the cell dual graph (cells adjacent when they share a facet:
//! `dim` nodes), each cell weighted by its assembly cost, computed identically on every
//! rank from the replicated mesh (METIS is deterministic for the same input and seed), so
//! no communication is needed; and the ownership that follows from it.
//!
//! Entry points: [`partition_cells`] (the rank of every cell; [`record`] keeps the last one
//! for `summary.json` and the output's pieces: [`recorded`], [`recorded_cells`]), [`node_owners`] (every
//! node owned by the lowest rank among its cells), [`element_owners`] (the rank that
//! assembles each element of each kernel: the cell's rank for the bulk kernel, the owner
//! of the element's first node for the others).

use crate::mesh::Mesh;
use metis_sys::{idx_t, real_t, METIS_PartMeshDual, METIS_SetDefaultOptions, METIS_NOPTIONS};
use std::sync::Mutex;

/// The figures of the last partition of this process (for `summary.json`) and the rank of
/// every cell (for the output's pieces).
static RECORDED: Mutex<Option<(PartitionFigures, Vec<u32>)>> = Mutex::new(None);

/// How the cells were shared among the ranks: the cells and the enriched cells (cells
/// with enriched dofs: cut by a crack or at its tip) of each rank.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PartitionFigures {
    pub cells_per_rank: Vec<usize>,
    pub enriched_cells_per_rank: Vec<usize>,
    /// The contact points each rank assembles (those of its cells' facets; empty without
    /// contact) and the matrix entries of each rank's rows (both gathered over MPI by
    /// [`record_assembly`]).
    pub contact_points_per_rank: Vec<usize>,
    pub matrix_entries_per_rank: Vec<usize>,
}

/// Records the partition's figures (`enriched[c]`: the cell has enriched dofs).
pub fn record(part: &[u32], enriched: &[bool], parts: usize) {
    let mut f = PartitionFigures {
        cells_per_rank: vec![0; parts],
        enriched_cells_per_rank: vec![0; parts],
        ..Default::default()
    };
    for (c, &p) in part.iter().enumerate() {
        f.cells_per_rank[p as usize] += 1;
        if enriched[c] {
            f.enriched_cells_per_rank[p as usize] += 1;
        }
    }
    if let Ok(mut r) = RECORDED.lock() {
        *r = Some((f, part.to_vec()));
    }
}

/// Adds to the recorded figures what each rank assembles: this rank's contact points and
/// the matrix entries of its rows, gathered over the ranks (an all-gather: every rank
/// calls it).
pub fn record_assembly(contact_points: Option<usize>, matrix_entries: usize) {
    let points = contact_points.map(|p| super::gather_over_ranks(p as u64));
    let entries = super::gather_over_ranks(matrix_entries as u64);
    if let Ok(mut r) = RECORDED.lock() {
        if let Some((f, _)) = r.as_mut() {
            f.contact_points_per_rank = points.map_or_else(Vec::new, |p| p.iter().map(|&c| c as usize).collect());
            f.matrix_entries_per_rank = entries.iter().map(|&c| c as usize).collect();
        }
    }
}

/// The figures of the last partition (`None` before any distributed assembly).
pub fn recorded() -> Option<PartitionFigures> {
    RECORDED.lock().ok().and_then(|r| r.as_ref().map(|r| r.0.clone()))
}

/// The rank of every cell in the last partition (`None` before any distributed assembly).
pub fn recorded_cells() -> Option<Vec<u32>> {
    RECORDED.lock().ok().and_then(|r| r.as_ref().map(|r| r.1.clone()))
}

/// The rank of every cell for `parts` ranks, balancing `weights` (one per cell, ≥ 1: the
/// cost of assembling the cell, larger for cut and enriched cells). One part: every cell
/// on rank 0. Errors name METIS's failure, or more ranks than cells.
pub fn partition_cells(mesh: &Mesh, weights: &[i64], parts: usize) -> Result<Vec<u32>, String> {
    let ne = mesh.cells.len();
    if parts <= 1 {
        return Ok(vec![0; ne]);
    }
    if parts > ne {
        return Err(format!(
            "{parts} MPI ranks for a mesh of {ne} cells: every rank needs at least one cell (run with fewer ranks)"
        ));
    }
    let mut eptr: Vec<idx_t> = Vec::with_capacity(ne + 1);
    let mut eind: Vec<idx_t> = vec![];
    eptr.push(0);
    for c in &mesh.cells {
        eind.extend(c.nodes().iter().map(|&n| n as idx_t));
        eptr.push(eind.len() as idx_t);
    }
    // Integer weights in METIS's range, proportional to the costs.
    let wmax = weights.iter().copied().max().unwrap_or(1).max(1);
    let scale = if wmax > 1000 { wmax as f64 / 1000.0 } else { 1.0 };
    let mut vwgt: Vec<idx_t> = weights.iter().map(|&w| ((w.max(1) as f64 / scale).round() as idx_t).max(1)).collect();
    let mut options = [0 as idx_t; METIS_NOPTIONS as usize];
    let (mut ne_i, mut nn_i) = (ne as idx_t, mesh.n_nodes() as idx_t);
    let mut ncommon = mesh.dim as idx_t;
    let mut nparts = parts as idx_t;
    let mut objval: idx_t = 0;
    let mut epart = vec![0 as idx_t; ne];
    let mut npart = vec![0 as idx_t; mesh.n_nodes()];
    // SAFETY: arrays of the sizes METIS expects (ne + 1, the connectivity, ne weights,
    // ne and nn outputs); the options array has METIS_NOPTIONS entries.
    let status = unsafe {
        METIS_SetDefaultOptions(options.as_mut_ptr());
        METIS_PartMeshDual(
            &mut ne_i,
            &mut nn_i,
            eptr.as_mut_ptr(),
            eind.as_mut_ptr(),
            vwgt.as_mut_ptr(),
            std::ptr::null_mut(),
            &mut ncommon,
            &mut nparts,
            std::ptr::null_mut::<real_t>(),
            options.as_mut_ptr(),
            &mut objval,
            epart.as_mut_ptr(),
            npart.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(format!("METIS could not partition the {ne} cells into {parts} parts (status {status})"));
    }
    Ok(epart.into_iter().map(|p| p as u32).collect())
}

/// Every node's owner: the lowest rank among its cells (nodes of no cell: rank 0).
pub fn node_owners(mesh: &Mesh, part: &[u32]) -> Vec<u32> {
    let mut owner = vec![u32::MAX; mesh.n_nodes()];
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &n in cell.nodes() {
            owner[n] = owner[n].min(part[c]);
        }
    }
    owner.iter_mut().filter(|o| **o == u32::MAX).for_each(|o| *o = 0);
    owner
}

/// Whether `rank` assembles each element of each kernel: the bulk kernel (index 0, one
/// element per cell) by the cell's rank; the others (boundary faces, multipliers) by the
/// owner of the node of their first dof that has one (`dof_nodes[d]`, `u32::MAX` for
/// none), rank 0 when none has. `dofs_of(k, e, out)` lists an element's dofs.
pub fn element_owners(
    n_elements: &[usize],
    part: &[u32],
    node_owner: &[u32],
    dof_nodes: &[u32],
    rank: u32,
    dofs_of: &dyn Fn(usize, usize, &mut Vec<u32>),
) -> Vec<Vec<bool>> {
    let mut dofs = vec![];
    n_elements
        .iter()
        .enumerate()
        .map(|(k, &ne)| {
            (0..ne)
                .map(|e| {
                    if k == 0 && ne == part.len() {
                        return part[e] == rank;
                    }
                    dofs.clear();
                    dofs_of(k, e, &mut dofs);
                    let owner = dofs
                        .iter()
                        .filter_map(|&d| dof_nodes.get(d as usize).copied().filter(|&n| n != u32::MAX))
                        .map(|n| node_owner[n as usize])
                        .next()
                        .unwrap_or(0);
                    owner == rank
                })
                .collect()
        })
        .collect()
}
