//! The result guard: before a step is reported ok, every output array and every
//! summary figure of the step is checked finite. The first non-finite value fails the
//! step with a message naming the field and where it is (node, cell, group, front
//! point), so that a NaN or an infinity never reaches a user as `"status": "ok"`.
//!
//! Entry points: [`check_unknowns`], [`check_grid`], [`check_step`].

use super::summary::StepInfo;
use crate::io::vtu::UnstructuredGrid;

const XYZ: [&str; 3] = ["x", "y", "z"];

fn bad(v: f64) -> bool {
    !v.is_finite()
}

/// Checks the solution vector: `dof_node[d]` is the node of unknown `d` (`u32::MAX` for
/// multipliers); the first `n_std` unknowns are the nodal displacements.
pub fn check_unknowns(u: &[f64], dof_node: &[u32], dim: usize, n_std: usize) -> Result<(), String> {
    let Some(d) = u.iter().position(|v| bad(*v)) else { return Ok(()) };
    let v = u[d];
    Err(if d < n_std {
        format!("the displacement is {v} at node {} (component {})", d / dim, XYZ[d % dim])
    } else if dof_node.get(d).is_some_and(|&n| n != u32::MAX) {
        format!("the enriched displacement unknown {d} of node {} is {v}", dof_node[d])
    } else {
        format!("the multiplier unknown {d} is {v}")
    })
}

/// Checks every point coordinate and every point and cell array of a grid. `what` names
/// the grid; cells are located by their `parent_cell` array when the grid has one
/// (sub-cells of the cracked body).
pub fn check_grid(grid: &UnstructuredGrid, what: &str) -> Result<(), String> {
    if let Some((i, p)) = grid.points.iter().enumerate().find(|(_, p)| p.iter().any(|v| bad(*v))) {
        return Err(format!("{what}: point {i} has the coordinates {p:?}"));
    }
    for a in &grid.point_data {
        let nc = a.components.max(1);
        if let Some(k) = a.values.iter().position(|v| bad(*v)) {
            return Err(format!(
                "{what}: field '{}' is {} at point {} (component {})",
                a.name,
                a.values[k],
                k / nc,
                k % nc
            ));
        }
    }
    let parent = grid.cell_data.iter().find(|a| a.name == "parent_cell");
    for a in &grid.cell_data {
        let nc = a.components.max(1);
        if let Some(k) = a.values.iter().position(|v| bad(*v)) {
            let c = k / nc;
            let at = match parent.and_then(|p| p.values.get(c)) {
                Some(m) => format!("sub-cell {c} of cell {m}"),
                None => format!("cell {c}"),
            };
            return Err(format!("{what}: field '{}' is {} at {at} (component {})", a.name, a.values[k], k % nc));
        }
    }
    Ok(())
}

/// Checks every figure of a step that goes into `summary.json`.
pub fn check_step(info: &StepInfo) -> Result<(), String> {
    let scalar = |name: &str, v: f64| if bad(v) { Err(format!("{name} is {v}")) } else { Ok(()) };
    scalar("the load factor", info.load_factor)?;
    scalar("the relative residual", info.solver.residual)?;
    scalar("max_displacement", info.max_displacement)?;
    scalar("max_von_mises", info.max_von_mises)?;
    for (g, r) in &info.reactions {
        if let Some(i) = r.iter().position(|v| bad(*v)) {
            return Err(format!("the reaction of group '{g}' is {} (component {})", r[i], XYZ[i]));
        }
    }
    for c in &info.cracks {
        if let Some(r) = c.tip_radius {
            scalar(&format!("the tip radius of crack '{}'", c.name), r)?;
        }
        for (k, p) in c.front.iter().enumerate() {
            let at = format!("crack '{}', front point {k}", c.name);
            for (name, v) in [("KI", p.k1), ("KII", p.k2), ("KIII", p.k3), ("G", p.g)] {
                scalar(&format!("{name} of {at}"), v)?;
            }
            for (name, v) in [("x", p.x), ("e1", p.e1), ("e2", p.e2), ("e3", p.e3)] {
                if v.iter().any(|c| bad(*c)) {
                    return Err(format!("'{name}' of {at} is {v:?}"));
                }
            }
        }
    }
    if let Some(c) = &info.contact {
        scalar("the contact lambda_min", c.lambda_min)?;
        scalar("the contact lambda_max", c.lambda_max)?;
        scalar("the contact residual", c.residual)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::vtu::DataArray;

    /// Every kind of location is named: node and component, cell, sub-cell of a cell,
    /// reaction group, front point.
    #[test]
    fn non_finite_values_are_named_with_their_place() {
        let e = check_unknowns(&[0.0, 1.0, f64::NAN, 0.0], &[0, 0, 1, 1], 2, 4).unwrap_err();
        assert_eq!(e, "the displacement is NaN at node 1 (component x)");
        let e = check_unknowns(&[0.0, 0.0, f64::INFINITY], &[0, 0, 0], 2, 2).unwrap_err();
        assert!(e.contains("enriched displacement unknown 2 of node 0 is inf"), "{e}");
        let mut g = UnstructuredGrid { points: vec![[0.0; 3]; 2], ..Default::default() };
        g.cell_data.push(DataArray { name: "parent_cell".into(), components: 1, values: vec![7.0, 9.0] });
        g.cell_data.push(DataArray { name: "stress".into(), components: 6, values: vec![0.0; 12] });
        assert!(check_grid(&g, "body").is_ok());
        g.cell_data[1].values[8] = f64::NEG_INFINITY;
        let e = check_grid(&g, "body").unwrap_err();
        assert_eq!(e, "body: field 'stress' is -inf at sub-cell 1 of cell 9 (component 2)");
        let mut info = StepInfo::default();
        info.reactions.insert("left".into(), [0.0, f64::NAN, 0.0]);
        assert_eq!(check_step(&info).unwrap_err(), "the reaction of group 'left' is NaN (component y)");
    }
}
