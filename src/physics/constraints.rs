//! Checks that Dirichlet conditions remove every rigid-body motion of every connected
//! body, so that an under-constrained model is reported before any solve.
//!
//! Entry points: [`check_rigid_modes`], [`check_rigid_modes_with`] (linear relations too).

use crate::mesh::Mesh;
use nalgebra::DMatrix;

/// Names of the rigid modes in the order they are built.
const NAMES_2D: [&str; 3] = ["translation along x", "translation along y", "rotation about z"];
const NAMES_3D: [&str; 6] = [
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
];

/// Connected components of the mesh cells (through shared nodes): component id per node
/// (`usize::MAX` for nodes in no cell) and the number of components.
pub fn node_components(mesh: &Mesh) -> (Vec<usize>, usize) {
    let n = mesh.nodes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    let mut used = vec![false; n];
    for c in &mesh.cells {
        let v = c.nodes();
        used[v[0]] = true;
        for &b in &v[1..] {
            used[b] = true;
            let (ra, rb) = (find(&mut parent, v[0]), find(&mut parent, b));
            if ra != rb {
                parent[ra] = rb;
            }
        }
    }
    let mut id = vec![usize::MAX; n];
    let mut root_id = std::collections::HashMap::new();
    for a in 0..n {
        if used[a] {
            let r = find(&mut parent, a);
            let k = root_id.len();
            id[a] = *root_id.entry(r).or_insert(k);
        }
    }
    let count = root_id.len();
    (id, count)
}

/// Returns an error message naming the free motions if some connected body is not held
/// by the constrained `(node, component)` pairs against all its rigid-body motions.
pub fn check_rigid_modes(mesh: &Mesh, constrained: &[(usize, usize)]) -> Result<(), String> {
    check_rigid_modes_with(mesh, constrained, &[])
}

/// Like [`check_rigid_modes`], with linear relations too: each relation is a list of
/// (node, component, coefficient) (its standard-displacement terms). A relation between
/// two bodies ties their motions, so the bodies it links are checked together.
pub fn check_rigid_modes_with(
    mesh: &Mesh,
    constrained: &[(usize, usize)],
    relations: &[Vec<(usize, usize, f64)>],
) -> Result<(), String> {
    let dim = mesh.dim;
    let nm = if dim == 2 { 3 } else { 6 };
    let names: &[&str] = if dim == 2 { &NAMES_2D } else { &NAMES_3D };
    let (comp, ncomp) = node_components(mesh);
    // Centre and size of each body, to scale rotations like translations.
    let mut centre = vec![[0.0; 3]; ncomp];
    let mut count = vec![0usize; ncomp];
    for (a, &c) in comp.iter().enumerate() {
        if c != usize::MAX {
            for i in 0..3 {
                centre[c][i] += mesh.nodes[a][i];
            }
            count[c] += 1;
        }
    }
    for c in 0..ncomp {
        for i in 0..3 {
            centre[c][i] /= count[c].max(1) as f64;
        }
    }
    let mut size = vec![0.0f64; ncomp];
    for (a, &c) in comp.iter().enumerate() {
        if c != usize::MAX {
            let d: f64 = (0..3).map(|i| (mesh.nodes[a][i] - centre[c][i]).powi(2)).sum();
            size[c] = size[c].max(d.sqrt());
        }
    }
    // Bodies tied by relations are checked together (union-find over bodies).
    let mut parent: Vec<usize> = (0..ncomp).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    for r in relations {
        let bodies: Vec<usize> = r.iter().map(|t| comp[t.0]).filter(|&c| c != usize::MAX).collect();
        for w in bodies.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            if a != b {
                parent[a] = b;
            }
        }
    }
    // Position of each body in its group's mode vector.
    let mut group_of = vec![0usize; ncomp];
    let mut members: Vec<Vec<usize>> = vec![];
    let mut root_group = std::collections::HashMap::new();
    for c in 0..ncomp {
        let r = find(&mut parent, c);
        let g = *root_group.entry(r).or_insert_with(|| {
            members.push(vec![]);
            members.len() - 1
        });
        group_of[c] = g;
        members[g].push(c);
    }
    let slot = |c: usize| members[group_of[c]].iter().position(|&m| m == c).expect("member");
    // Row of the rigid-mode matrix for displacement component i at node a.
    let mode_row = |a: usize, i: usize| -> [f64; 6] {
        let c = comp[a];
        let s = size[c].max(f64::MIN_POSITIVE);
        let x = [
            (mesh.nodes[a][0] - centre[c][0]) / s,
            (mesh.nodes[a][1] - centre[c][1]) / s,
            (mesh.nodes[a][2] - centre[c][2]) / s,
        ];
        let mut r = [0.0; 6];
        r[i] = 1.0;
        if dim == 2 {
            r[2] = if i == 0 { -x[1] } else { x[0] };
        } else {
            // rotation ω × x: about x → (0, −z, y); about y → (z, 0, −x); about z → (−y, x, 0)
            let rot = [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]];
            for k in 0..3 {
                r[3 + k] = rot[k][i];
            }
        }
        r
    };
    let mut gram: Vec<DMatrix<f64>> = members.iter().map(|m| DMatrix::zeros(nm * m.len(), nm * m.len())).collect();
    let single: Vec<Vec<(usize, usize, f64)>> = constrained.iter().map(|&(a, i)| vec![(a, i, 1.0)]).collect();
    for r in single.iter().chain(relations) {
        let mut g = None;
        let mut row: Vec<(usize, f64)> = vec![];
        for &(a, i, coef) in r {
            let c = comp[a];
            if c == usize::MAX {
                continue;
            }
            g = Some(group_of[c]);
            let base = nm * slot(c);
            for (p, v) in mode_row(a, i).iter().take(nm).enumerate() {
                row.push((base + p, coef * v));
            }
        }
        let Some(g) = g else { continue };
        for &(p, vp) in &row {
            for &(q, vq) in &row {
                gram[g][(p, q)] += vp * vq;
            }
        }
    }
    let body_names = body_names(mesh, &comp, ncomp);
    let mut problems = vec![];
    for (g, gm) in gram.into_iter().enumerate() {
        let n = gm.nrows();
        // Relations can mix coefficients of any size: the threshold is relative.
        let scale = (0..n).map(|k| gm[(k, k)]).fold(0.0f64, f64::max).max(1.0);
        let eig = gm.symmetric_eigen();
        let mut free: Vec<(usize, &str)> = vec![];
        for k in 0..n {
            if eig.eigenvalues[k] < 1e-10 * scale {
                let v = eig.eigenvectors.column(k);
                let (imax, _) = v
                    .iter()
                    .enumerate()
                    .fold((0, 0.0), |acc, (i, &x)| if x.abs() > acc.1 { (i, x.abs()) } else { acc });
                free.push((members[g][imax / nm], names[imax % nm]));
            }
        }
        free.sort();
        free.dedup();
        let mut by_body: Vec<(usize, Vec<&str>)> = vec![];
        for (c, name) in free {
            match by_body.last_mut() {
                Some((b, v)) if *b == c => v.push(name),
                _ => by_body.push((c, vec![name])),
            }
        }
        for (c, v) in by_body {
            let label = match (&body_names[c], ncomp > 1) {
                (Some(n), true) => format!("body '{n}' ({} of {ncomp}) ", c + 1),
                (None, true) => format!("body {} of {} ", c + 1, ncomp),
                (_, false) => String::new(),
            };
            problems.push(format!("{label}can move freely ({})", v.join(", ")));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "the model is under-constrained: {}; add Dirichlet conditions that prevent these rigid-body motions",
            problems.join("; ")
        ))
    }
}

/// The name of each body: the first cell group (by name) holding exactly its cells (a
/// part of `[[mesh.parts]]`, a Gmsh physical volume), if any besides `all`.
fn body_names(mesh: &Mesh, comp: &[usize], ncomp: usize) -> Vec<Option<String>> {
    let mut sizes = vec![0usize; ncomp];
    let body_of_cell = |c: usize| comp[mesh.cells[c].nodes()[0]];
    for c in 0..mesh.cells.len() {
        sizes[body_of_cell(c)] += 1;
    }
    let mut names = vec![None; ncomp];
    for (name, cells) in &mesh.cell_groups {
        let Some(&first) = cells.first() else { continue };
        let b = body_of_cell(first);
        if names[b].is_none() && name != "all" && cells.len() == sizes[b] && cells.iter().all(|&c| body_of_cell(c) == b)
        {
            let mut sorted = cells.clone();
            sorted.sort_unstable();
            sorted.dedup();
            if sorted.len() == sizes[b] {
                names[b] = Some(name.clone());
            }
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::CellType;
    use crate::mesh::generate;

    #[test]
    fn clamped_edge_holds_all_modes_and_roller_does_not() {
        let m = generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [3, 3]).unwrap();
        let left = m.group_nodes("left").unwrap();
        let clamped: Vec<_> = left.iter().flat_map(|&n| [(n, 0), (n, 1)]).collect();
        assert!(check_rigid_modes(&m, &clamped).is_ok());
        let roller: Vec<_> = left.iter().map(|&n| (n, 0)).collect();
        let e = check_rigid_modes(&m, &roller).unwrap_err();
        assert!(e.contains("translation along y"), "{e}");
        let none: Vec<(usize, usize)> = vec![];
        let e3 = check_rigid_modes(&generate::box_mesh(CellType::Tet4, [0.0; 3], [1.0; 3], [1, 1, 1]).unwrap(), &none);
        assert!(e3.unwrap_err().contains("rotation about z"));
    }

    /// A relation u_y(a) − u_y(b) = 0 between two nodes holds nothing; u_y(a) + u_y(b) = 0
    /// with a roller in x on the left edge holds the y translation (the rotation is
    /// held by the roller's lever arm).
    #[test]
    fn relations_count_in_the_rigid_mode_check() {
        let m = generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [3, 3]).unwrap();
        let left = m.group_nodes("left").unwrap();
        let roller: Vec<_> = left.iter().map(|&n| (n, 0)).collect();
        let (a, b) = (0, m.n_nodes() - 1);
        let tie = vec![vec![(a, 1, 1.0), (b, 1, -1.0)]];
        assert!(check_rigid_modes_with(&m, &roller, &tie).unwrap_err().contains("translation along y"));
        let sum = vec![vec![(a, 1, 1.0), (b, 1, 1.0)]];
        assert!(check_rigid_modes_with(&m, &roller, &sum).is_ok());
    }
}
