//! Checks that Dirichlet conditions remove every rigid-body motion of every connected
//! body, so that an under-constrained model is reported before any solve.
//!
//! Entry points: [`check_rigid_modes`], [`check_rigid_modes_with`] (linear relations too),
//! [`check_model_rigid_modes`] (a cracked model: the pieces a crack without contact cuts
//! off are checked one by one, each crack's sides having their own values at the
//! Heaviside nodes).

use super::relations::Relation;
use crate::enrich::{side_of, CrackGeometry, EnrichKind, Enrichment};
use crate::mesh::Mesh;
use nalgebra::DMatrix;
use std::collections::HashMap;

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
    let rows: Vec<Vec<(u32, f64)>> =
        relations.iter().map(|r| r.iter().map(|&(a, i, c)| ((a * dim + i) as u32, c)).collect()).collect();
    check_core(mesh, None, constrained, &rows)
}

/// The cracks of a model as the rigid-body check sees them.
pub struct CrackedBody<'a> {
    pub cracks: &'a [CrackGeometry],
    pub enrichment: &'a Enrichment,
    /// Per crack: whether its two sides move independently, i.e. no contact law holds
    /// them together (a crack with contact may hold a piece under compression, and the
    /// contact loops have a bonded first pass for it, so it counts as holding).
    pub separating: Vec<bool>,
}

/// The rigid-body check of a cracked model: the pieces are the connected parts of the
/// body once the cracks without contact are cut (a through crack leaves two pieces,
/// each of which must be held by its own supports), and every linear relation counts
/// with all its terms (a condition on one lip holds the piece on that side). `tied`
/// are rows on standard unknowns (node, component, coefficient), e.g. the meshed
/// contact pairs' ([`crate::contact::points::ContactPoints::rigid_rows`]).
pub fn check_model_rigid_modes(
    mesh: &Mesh,
    cracked: &CrackedBody<'_>,
    constrained: &[(usize, usize)],
    relations: &[Relation],
    tied: &[Vec<(usize, usize, f64)>],
) -> Result<(), String> {
    let dim = mesh.dim;
    let mut rows: Vec<Vec<(u32, f64)>> = relations.iter().map(|r| r.terms.clone()).collect();
    rows.extend(tied.iter().map(|r| r.iter().map(|&(a, i, c)| ((a * dim + i) as u32, c)).collect()));
    check_core(mesh, Some(cracked), constrained, &rows)
}

/// The unknowns of the rigid-body check and the pieces they form. Each node has one
/// value, its displacement, except a node whose only enrichment is the Heaviside function
/// of a separating crack: it has the value of each side's field at the node (with the
/// shifted basis, u_n on its own side and u_n − 2 s_n a_n on the other). Every region of a
/// cell (a side of a cut cell, or the whole cell) interpolates the values of its side at
/// its nodes, so its values move together: the pieces are the connected components of
/// values linked by regions. A node with tip enrichment, or enriched by several cracks,
/// keeps one value (its pieces are joined: the check may then miss a free piece, never
/// invent one).
struct Pieces {
    /// First value of each node.
    base: Vec<usize>,
    /// Node of each value.
    node: Vec<usize>,
    /// Per node: the separating crack whose sides have their own values, and the side of
    /// the node (its own value).
    split: Vec<Option<(usize, i8)>>,
    /// Piece of each value (`usize::MAX` when no region uses it: a node in no cell).
    piece: Vec<usize>,
    count: usize,
    /// Per piece: the (crack, side) of each separating crack that bounds it.
    bounds: Vec<Vec<(usize, i8)>>,
    /// Heaviside unknown → (node, component) at the split nodes.
    heaviside: HashMap<u32, (usize, usize)>,
}

impl Pieces {
    fn value(&self, node: usize, side: i8) -> usize {
        self.base[node] + usize::from(self.split[node].is_some() && side < 0)
    }
    fn own(&self, node: usize) -> usize {
        self.value(node, self.split[node].map_or(1, |s| s.1))
    }

    fn build(mesh: &Mesh, cracked: Option<&CrackedBody<'_>>) -> Pieces {
        let n = mesh.nodes.len();
        let mut split = vec![None; n];
        let mut heaviside = HashMap::new();
        if let Some(cb) = cracked {
            for (a, s) in split.iter_mut().enumerate() {
                let items = cb.enrichment.node_items(a);
                if let [it] = items {
                    let k = it.crack as usize;
                    if it.kind == EnrichKind::Heaviside && cb.separating.get(k).copied().unwrap_or(false) {
                        *s = Some((k, side_of(cb.cracks[k].levelsets.lsn[a])));
                        for i in 0..mesh.dim {
                            heaviside.insert(it.first_dof + i as u32, (a, i));
                        }
                    }
                }
            }
        }
        let mut base = Vec::with_capacity(n);
        let mut node = Vec::with_capacity(n);
        for (a, s) in split.iter().enumerate() {
            base.push(node.len());
            node.push(a);
            if s.is_some() {
                node.push(a);
            }
        }
        let nv = node.len();
        let mut p = Pieces { base, node, split, piece: vec![usize::MAX; nv], count: 0, bounds: vec![], heaviside };
        let mut parent: Vec<usize> = (0..nv).collect();
        let mut used = vec![false; nv];
        // The regions of each cell: (cell, side of the separating crack cutting it).
        let mut cut_regions: Vec<(usize, usize, [usize; 2])> = vec![];
        for (c, cell) in mesh.cells.iter().enumerate() {
            let nodes = cell.nodes();
            let cutting = cracked.and_then(|cb| {
                let k = cb.enrichment.cell_crack.get(c).copied().flatten()? as usize;
                if !cb.separating.get(k).copied().unwrap_or(false) {
                    return None;
                }
                let cc = cb.cracks[k].cut.cell_cut(c)?;
                let (plus, minus) = (cc.subcells.iter().any(|s| s.side > 0), cc.subcells.iter().any(|s| s.side < 0));
                Some((k, plus, minus))
            });
            let sides: Vec<Option<i8>> = match cutting {
                Some((_, true, true)) => vec![Some(1), Some(-1)],
                Some((_, true, false)) => vec![Some(1)],
                Some((_, false, true)) => vec![Some(-1)],
                _ => vec![None],
            };
            let mut first_of = [usize::MAX; 2];
            for (r, side) in sides.iter().enumerate() {
                let mut first = usize::MAX;
                for &a in nodes {
                    let v = match (p.split[a], cracked) {
                        (Some((k, _)), Some(cb)) => {
                            let s = match (cutting, side) {
                                (Some((kc, _, _)), Some(s)) if kc == k => *s,
                                _ => {
                                    let lsn = &cb.cracks[k].levelsets.lsn;
                                    side_of(nodes.iter().map(|&b| lsn[b]).sum::<f64>() / nodes.len() as f64)
                                }
                            };
                            p.value(a, s)
                        }
                        _ => p.base[a],
                    };
                    used[v] = true;
                    if first == usize::MAX {
                        first = v;
                    } else {
                        union(&mut parent, first, v);
                    }
                }
                first_of[r] = first;
            }
            if let (Some((k, true, true)), true) = (cutting, first_of[1] != usize::MAX) {
                cut_regions.push((c, k, first_of));
            }
        }
        let mut id = HashMap::new();
        for v in 0..nv {
            if used[v] {
                let r = find(&mut parent, v);
                let k = id.len();
                p.piece[v] = *id.entry(r).or_insert(k);
            }
        }
        p.count = id.len();
        p.bounds = vec![vec![]; p.count];
        for (_, k, [vp, vm]) in cut_regions {
            let (a, b) = (p.piece[vp], p.piece[vm]);
            if a != b {
                p.bounds[a].push((k, 1));
                p.bounds[b].push((k, -1));
            }
        }
        for b in &mut p.bounds {
            b.sort_unstable();
            b.dedup();
        }
        p
    }

    /// The values an unknown is made of, (value, coefficient, node, component): a
    /// displacement is its node's own value; the Heaviside unknown of a split node is
    /// (own − other)/(2 s_n); every other unknown (tip functions, Heaviside of a joined
    /// node) takes no part in a rigid motion of a piece.
    fn terms(&self, dim: usize, n_std: usize, d: u32) -> Vec<(usize, f64, usize, usize)> {
        if (d as usize) < n_std {
            let (a, i) = (d as usize / dim, d as usize % dim);
            return vec![(self.own(a), 1.0, a, i)];
        }
        match self.heaviside.get(&d) {
            Some(&(a, i)) => {
                let s = self.split[a].map_or(1, |s| s.1);
                let h = 0.5 * s as f64;
                vec![(self.value(a, s), h, a, i), (self.value(a, -s), -h, a, i)]
            }
            None => vec![],
        }
    }
}

fn find(p: &mut [usize], mut a: usize) -> usize {
    while p[a] != a {
        p[a] = p[p[a]];
        a = p[a];
    }
    a
}

fn union(p: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(p, a), find(p, b));
    if ra != rb {
        p[ra] = rb;
    }
}

/// A coordinate for a message: six significant digits at most.
fn short(v: f64) -> String {
    let s = format!("{:.6}", v);
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if v != 0.0 && v.abs() < 1e-3 || v.abs() >= 1e7 {
        format!("{v:.5e}")
    } else if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// The check: `rows` are the relations as (unknown, coefficient) lists.
fn check_core(
    mesh: &Mesh,
    cracked: Option<&CrackedBody<'_>>,
    constrained: &[(usize, usize)],
    rows: &[Vec<(u32, f64)>],
) -> Result<(), String> {
    let dim = mesh.dim;
    let n_std = dim * mesh.nodes.len();
    let nm = if dim == 2 { 3 } else { 6 };
    let names: &[&str] = if dim == 2 { &NAMES_2D } else { &NAMES_3D };
    let pieces = Pieces::build(mesh, cracked);
    let np = pieces.count;
    // Centre and size of each piece (over the nodes of its values, those across a crack
    // included), to scale rotations like translations.
    let mut centre = vec![[0.0; 3]; np];
    let mut count = vec![0usize; np];
    for (v, &a) in pieces.node.iter().enumerate() {
        let c = pieces.piece[v];
        if c != usize::MAX {
            for i in 0..3 {
                centre[c][i] += mesh.nodes[a][i];
            }
            count[c] += 1;
        }
    }
    for c in 0..np {
        for i in 0..3 {
            centre[c][i] /= count[c].max(1) as f64;
        }
    }
    let mut size = vec![0.0f64; np];
    for (v, &a) in pieces.node.iter().enumerate() {
        let c = pieces.piece[v];
        if c != usize::MAX {
            let d: f64 = (0..3).map(|i| (mesh.nodes[a][i] - centre[c][i]).powi(2)).sum();
            size[c] = size[c].max(d.sqrt());
        }
    }
    // Row of the rigid-mode matrix of piece c for displacement component i at node a.
    let mode_row = |c: usize, a: usize, i: usize| -> [f64; 6] {
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
    // Each condition as a row over (piece, mode).
    let single: Vec<Vec<(u32, f64)>> = constrained.iter().map(|&(a, i)| vec![((a * dim + i) as u32, 1.0)]).collect();
    let mut mode_rows: Vec<Vec<(usize, usize, f64)>> = vec![];
    for r in single.iter().chain(rows) {
        let mut acc: HashMap<(usize, usize), f64> = HashMap::new();
        for &(d, coef) in r {
            for (v, w, a, i) in pieces.terms(dim, n_std, d) {
                let c = pieces.piece[v];
                if c == usize::MAX {
                    continue;
                }
                for (m, x) in mode_row(c, a, i).iter().take(nm).enumerate() {
                    *acc.entry((c, m)).or_insert(0.0) += coef * w * x;
                }
            }
        }
        let big = acc.values().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut row: Vec<(usize, usize, f64)> =
            acc.into_iter().filter(|e| e.1.abs() > 1e-12 * big).map(|((c, m), x)| (c, m, x)).collect();
        row.sort_by_key(|e| (e.0, e.1));
        if !row.is_empty() {
            mode_rows.push(row);
        }
    }
    // Pieces tied by a row are checked together (union-find over pieces).
    let mut parent: Vec<usize> = (0..np).collect();
    for r in &mode_rows {
        for w in r.windows(2) {
            union(&mut parent, w[0].0, w[1].0);
        }
    }
    // Position of each piece in its group's mode vector.
    let mut group_of = vec![0usize; np];
    let mut members: Vec<Vec<usize>> = vec![];
    let mut slot = vec![0usize; np];
    let mut root_group = HashMap::new();
    for c in 0..np {
        let r = find(&mut parent, c);
        let g = *root_group.entry(r).or_insert_with(|| {
            members.push(vec![]);
            members.len() - 1
        });
        group_of[c] = g;
        slot[c] = members[g].len();
        members[g].push(c);
    }
    let mut gram: Vec<DMatrix<f64>> = members.iter().map(|m| DMatrix::zeros(nm * m.len(), nm * m.len())).collect();
    for r in &mode_rows {
        let g = group_of[r[0].0];
        for &(cp, mp, vp) in r {
            for &(cq, mq, vq) in r {
                gram[g][(nm * slot[cp] + mp, nm * slot[cq] + mq)] += vp * vq;
            }
        }
    }
    // Mesh bodies (connected through shared nodes) and their names.
    let (comp, ncomp) = node_components(mesh);
    let body_names = body_names(mesh, &comp, ncomp);
    let body_of_piece: Vec<usize> = {
        let mut b = vec![usize::MAX; np];
        for (v, &a) in pieces.node.iter().enumerate() {
            let c = pieces.piece[v];
            if c != usize::MAX && b[c] == usize::MAX {
                b[c] = comp[a];
            }
        }
        b
    };
    let mut pieces_of_body = vec![0usize; ncomp];
    for &b in &body_of_piece {
        if b != usize::MAX {
            pieces_of_body[b] += 1;
        }
    }
    let crack_name = |k: usize| cracked.map_or(String::new(), |cb| cb.cracks[k].name.clone());
    let mut problems = vec![];
    let mut crack_pieces = false;
    for (g, gm) in gram.into_iter().enumerate() {
        let n = gm.nrows();
        // Relations can mix coefficients of any size: the threshold is relative.
        let scale = (0..n).map(|k| gm[(k, k)]).fold(0.0f64, f64::max).max(1.0);
        let eig = gm.symmetric_eigen();
        let mut free: Vec<(usize, usize)> = vec![];
        for k in 0..n {
            if eig.eigenvalues[k] < 1e-10 * scale {
                let v = eig.eigenvectors.column(k);
                let (imax, _) = v
                    .iter()
                    .enumerate()
                    .fold((0, 0.0), |acc, (i, &x)| if x.abs() > acc.1 { (i, x.abs()) } else { acc });
                free.push((members[g][imax / nm], imax % nm));
            }
        }
        free.sort();
        free.dedup();
        let mut by_piece: Vec<(usize, Vec<&str>)> = vec![];
        for (c, m) in free {
            match by_piece.last_mut() {
                Some((b, v)) if *b == c => v.push(names[m]),
                _ => by_piece.push((c, vec![names[m]])),
            }
        }
        for (c, v) in by_piece {
            let b = body_of_piece[c];
            let body = match (&body_names[b], ncomp > 1) {
                (Some(n), true) => format!("body '{n}' ({} of {ncomp})", b + 1),
                (None, true) => format!("body {} of {}", b + 1, ncomp),
                (_, false) => String::new(),
            };
            let label = if pieces_of_body[b] > 1 {
                crack_pieces = true;
                let sides: Vec<String> = pieces.bounds[c]
                    .iter()
                    .map(|&(k, s)| format!("the {} side of crack '{}'", if s > 0 { "+" } else { "-" }, crack_name(k)))
                    .collect();
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for (a, x) in mesh.nodes.iter().enumerate() {
                    if comp[a] == b && pieces.piece[pieces.own(a)] == c {
                        for i in 0..3 {
                            lo[i] = lo[i].min(x[i]);
                            hi[i] = hi[i].max(x[i]);
                        }
                    }
                }
                let bbox: Vec<String> = (0..dim)
                    .filter(|&i| lo[i] <= hi[i])
                    .map(|i| format!("{} in [{}, {}]", ["x", "y", "z"][i], short(lo[i]), short(hi[i])))
                    .collect();
                let cracks: Vec<String> = {
                    let mut ks: Vec<usize> = pieces.bounds.iter().flatten().map(|b| b.0).collect();
                    ks.sort_unstable();
                    ks.dedup();
                    ks.into_iter().map(|k| format!("'{}'", crack_name(k))).collect()
                };
                format!(
                    "{}{} cut{} {} into {} pieces, and the piece on {} (its nodes: {}) ",
                    if cracks.len() > 1 { "cracks " } else { "crack " },
                    cracks.join(", "),
                    if cracks.len() > 1 { "" } else { "s" },
                    if body.is_empty() { "the body".to_string() } else { body },
                    pieces_of_body[b],
                    if sides.is_empty() { "one side".to_string() } else { sides.join(" and ") },
                    bbox.join(", ")
                )
            } else if body.is_empty() {
                body
            } else {
                format!("{body} ")
            };
            problems.push(format!("{label}can move freely ({})", v.join(", ")));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else if crack_pieces {
        Err(format!(
            "the model is under-constrained: {}; a crack without contact transmits no force, so each piece it cuts off needs its own Dirichlet conditions preventing these rigid-body motions (or give the crack a [cracks.contact] table, which holds the piece where the lips are pressed together)",
            problems.join("; ")
        ))
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
