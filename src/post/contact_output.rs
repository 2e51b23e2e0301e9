//! Contact results on the crack-lip grid of [`super::xfem_output::crack_lips_grid`]: the
//! multipliers and statuses a person looks at in ParaView.
//!
//! Entry point: [`add_contact_fields`].
//!
//! Point data: `lambda` (normal traction, ≤ 0 in compression), `pressure` (−λ), `Lambda`
//! (the friction semi-multiplier as a tangent vector Σ Λ_α τ_α), `Lambda_norm` (|Λ| ≤ 1).
//! Cell data: `status` (0 open, 1 stick, 2 slip, the worst over the facet's contact
//! points; −1 on cracks without contact). Gap and slip are the lips' `normal_opening`
//! and `tangential_slip`.

use crate::contact::law::{PointState, Status};
use crate::contact::points::tangent_basis;
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
    let vals = point_values(model, pts, pairing, u, state);
    let st = statuses(pts, state, &vals);
    // (crack, facet) → (contact crack index, facet status).
    let mut facet_info: HashMap<(usize, usize), (usize, f64)> = HashMap::new();
    for (ci, fi, range) in &pts.facets {
        let worst = st[range.clone()].iter().map(|s| *s as u8).max().unwrap_or(0);
        let worst = if st[range.clone()].iter().all(|s| *s == Status::Open) { 0 } else { worst };
        facet_info.insert((pts.cracks[*ci].crack, *fi), (*ci, worst as f64));
    }
    let np = grid.points.len();
    let mut lambda = vec![0.0; np];
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
                    let tb = tangent_basis(dim, f.normal, cc.tangent_axis);
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
    grid.point_data.push(DataArray { name: "Lambda".into(), components: 3, values: big });
    grid.point_data.push(DataArray { name: "Lambda_norm".into(), components: 1, values: big_norm });
    grid.cell_data.push(DataArray { name: "status".into(), components: 1, values: status });
}
