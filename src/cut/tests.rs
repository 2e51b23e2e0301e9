//! Tests of the cut module: partition of the parent measure, exact crack lengths/areas
//! and front lengths on structured and distorted meshes, cracks through nodes and along
//! edges/faces, statuses, front points, orientation, vertex locations, quadrature rules.

use super::simplex::{cross, dot, norm, sub};
use super::*;
use crate::element::{self, CellType, MAX_NODES};
use crate::geometry::quadrature::{gauss_legendre, gauss_tetrahedron};
use crate::mesh::{generate, Cell, Mesh};
use proptest::prelude::*;

fn ls(lsn: Vec<f64>, lst: Option<Vec<f64>>) -> NodalLevelSets {
    NodalLevelSets { lsn, lst }
}

fn sample(mesh: &Mesh, f: impl Fn(&[f64; 3]) -> f64) -> Vec<f64> {
    mesh.nodes.iter().map(f).collect()
}

fn one_cell(kind: CellType, nodes: &[[f64; 3]]) -> Mesh {
    let idx: Vec<usize> = (0..nodes.len()).collect();
    Mesh { dim: kind.dim(), nodes: nodes.to_vec(), cells: vec![Cell::new(kind, &idx)], ..Default::default() }
}

/// Distorted single cells of every type (positive Jacobians).
fn distorted(kind: CellType) -> Mesh {
    match kind {
        CellType::Tri3 => one_cell(kind, &[[0.1, -0.2, 0.0], [1.3, 0.1, 0.0], [0.4, 0.9, 0.0]]),
        CellType::Quad4 => one_cell(kind, &[[0.0, 0.0, 0.0], [2.0, 0.2, 0.0], [1.7, 1.5, 0.0], [-0.2, 1.1, 0.0]]),
        CellType::Tet4 => one_cell(kind, &[[0.0, 0.1, 0.0], [1.2, 0.0, 0.1], [0.2, 0.9, -0.1], [0.1, 0.2, 1.1]]),
        CellType::Hex8 => one_cell(
            kind,
            &[
                [0.0, 0.0, 0.0],
                [1.1, 0.1, 0.05],
                [1.2, 1.0, -0.1],
                [-0.1, 0.9, 0.1],
                [0.1, -0.1, 1.0],
                [1.0, 0.05, 1.2],
                [1.1, 1.1, 0.9],
                [0.05, 1.0, 1.1],
            ],
        ),
    }
}

/// Reference sub-simplices used by the cut (same as `cells`), for interpolation in tests.
fn sub_simplices(kind: CellType) -> Vec<Vec<usize>> {
    match kind {
        CellType::Tri3 => vec![vec![0, 1, 2]],
        CellType::Quad4 => vec![vec![0, 1, 2], vec![0, 2, 3]],
        CellType::Tet4 => vec![vec![0, 1, 2, 3]],
        CellType::Hex8 => [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]]
            .iter()
            .map(|s| s.to_vec())
            .collect(),
    }
}

/// The cut's interpolant of nodal values `phi` (local order) at reference point `xi`.
fn interp(kind: CellType, phi: &[f64], xi: &[f64; 3]) -> f64 {
    let r = kind.reference_nodes();
    let d = kind.dim();
    let mut best = (f64::NEG_INFINITY, 0.0);
    for s in sub_simplices(kind) {
        // Barycentric coordinates by Cramer's rule.
        let e: Vec<[f64; 3]> = (1..=d).map(|k| sub(r[s[k]], r[s[0]])).collect();
        let x = sub(xi, r[s[0]]);
        let lam: Vec<f64> = if d == 2 {
            let det = e[0][0] * e[1][1] - e[0][1] * e[1][0];
            vec![(x[0] * e[1][1] - x[1] * e[1][0]) / det, (e[0][0] * x[1] - e[0][1] * x[0]) / det]
        } else {
            let det = dot(e[0], cross(e[1], e[2]));
            vec![dot(x, cross(e[1], e[2])) / det, dot(e[0], cross(x, e[2])) / det, dot(e[0], cross(e[1], x)) / det]
        };
        let l0 = 1.0 - lam.iter().sum::<f64>();
        let minl = lam.iter().fold(l0, |m, &l| m.min(l));
        let val = l0 * phi[s[0]] + lam.iter().enumerate().map(|(k, l)| l * phi[s[k + 1]]).sum::<f64>();
        if minl > best.0 {
            best = (minl, val);
        }
    }
    best.1
}

/// Checks one cut against the mesh: Σ sub-cell measures = cell measure (rel 1e-12) for
/// every cut cell, sides/ahead flags agree with the interpolated level sets at sub-cell
/// centroids, facet vertices lie on φn = 0 with φt ≤ 0, normals point along ∇φn (checked
/// on simplices, where ∇φn is constant).
fn check_cut(mesh: &Mesh, l: &NodalLevelSets, cut: &CrackCut) {
    assert_eq!(cut.status.len(), mesh.cells.len());
    for cc in &cut.cut_cells {
        let c = cc.cell;
        let kind = mesh.cells[c].kind;
        let exact = mesh.cell_measure(c);
        let s: f64 = cc.subcells.iter().map(|sc| subcell_measure(mesh, c, sc)).sum();
        assert!((s - exact).abs() <= 1e-12 * exact, "cell {c} ({kind:?}): {s} vs {exact}");
        let nodes = mesh.cells[c].nodes();
        let phn: Vec<f64> = nodes.iter().map(|&g| l.lsn[g]).collect();
        let pht: Option<Vec<f64>> = l.lst.as_ref().map(|t| nodes.iter().map(|&g| t[g]).collect());
        let scale = phn.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        for sc in &cc.subcells {
            assert!(sc.side == 1 || sc.side == -1);
            assert_eq!(sc.vertices.len(), kind.dim() + 1);
            let x = sc.reference_centroid();
            let v = interp(kind, &phn, &x);
            assert!(v * sc.side as f64 >= -1e-12 * scale, "cell {c}: side {} but φn = {v}", sc.side);
            if let Some(t) = &pht {
                if cc.status == CellStatus::Front {
                    let vt = interp(kind, t, &x);
                    let ts = t.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(
                        if sc.ahead { vt >= -1e-12 * ts } else { vt <= 1e-12 * ts },
                        "cell {c}: ahead {}",
                        sc.ahead
                    );
                }
            } else {
                assert!(!sc.ahead);
            }
            if cc.status != CellStatus::Front {
                assert!(sc.singular_vertex.is_none());
            } else {
                // A sub-cell with a vertex on a front piece of its cell has a singular
                // vertex, and singular vertices lie on φn = 0 and φt = 0.
                let on_piece = |x: &[f64; 3]| {
                    cut.front[cc.front.clone()].iter().any(|p| match p.points_ref.as_slice() {
                        [a] => norm(sub(x, a)) < 1e-12,
                        [a, b] => {
                            let t = sub(b, a);
                            let s = (dot(sub(x, a), t) / dot(t, t)).clamp(0.0, 1.0);
                            norm(sub(x, [a[0] + s * t[0], a[1] + s * t[1], a[2] + s * t[2]])) < 1e-12
                        }
                        _ => false,
                    })
                };
                if sc.vertices.iter().any(on_piece) {
                    assert!(
                        sc.singular_vertex.is_some(),
                        "cell {c}: sub-cell touching the front without singular vertex"
                    );
                }
                if let (Some(k), Some(t)) = (sc.singular_vertex, &pht) {
                    let ts = t.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(interp(kind, &phn, &sc.vertices[k]).abs() <= 1e-12 * scale);
                    assert!(interp(kind, t, &sc.vertices[k]).abs() <= 1e-12 * ts);
                }
            }
        }
        for f in &cut.facets[cc.facets.clone()] {
            assert_eq!(f.cell, c);
            assert!(f.measure > 0.0);
            assert!((norm(f.normal) - 1.0).abs() < 1e-12);
            for xi in &f.vertices_ref {
                assert!(interp(kind, &phn, xi).abs() <= 1e-12 * scale);
                if let Some(t) = &pht {
                    let ts = t.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(interp(kind, t, xi) <= 1e-12 * ts);
                }
            }
            if kind.is_simplex() {
                let g = physical_gradient(mesh, c, &phn);
                assert!(dot(g, f.normal) > 0.0, "cell {c}: normal {:?} against ∇φn {g:?}", f.normal);
            }
        }
    }
}

/// Physical gradient of a nodal field on a simplex (constant).
fn physical_gradient(mesh: &Mesh, c: usize, phi: &[f64]) -> [f64; 3] {
    let kind = mesh.cells[c].kind;
    let mut xs = [[0.0; 3]; MAX_NODES];
    let nn = mesh.cell_coords(c, &mut xs);
    let (mut n, mut dn, mut g) = ([0.0; MAX_NODES], [[0.0; 3]; MAX_NODES], [[0.0; 3]; MAX_NODES]);
    element::shape(kind, &kind.reference_centroid(), &mut n, &mut dn);
    element::physical_gradients(kind.dim(), &xs[..nn], &dn[..nn], &mut g).unwrap();
    let mut out = [0.0; 3];
    for a in 0..nn {
        for k in 0..3 {
            out[k] += phi[a] * g[a][k];
        }
    }
    out
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

// ---------------------------------------------------------------------------------------
// Partition of the parent measure.

fn nodal_values(raw: &[(f64, bool)]) -> Vec<f64> {
    raw.iter().map(|&(v, zero)| if zero { 0.0 } else { v }).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

    /// What: Σ physical sub-cell measures (Σ over sub-cell quadrature of det J) equals the
    /// parent measure, with arbitrary nodal φn/φt (so lines/planes in any position,
    /// including exact zeros at nodes: through nodes, along edges/faces), on distorted
    /// tri3/quad4/tet4/hex8. Reference: the cell measure. Tolerance: 1e-12 relative.
    #[test]
    fn subcells_partition_the_parent(
        n in prop::collection::vec((-1.0f64..1.0, prop::bool::weighted(0.3)), 8),
        t in prop::collection::vec((-1.0f64..1.0, prop::bool::weighted(0.3)), 8),
        with_front in any::<bool>(),
    ) {
        for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
            let m = distorted(kind);
            let k = kind.n_nodes();
            let l = ls(nodal_values(&n[..k]), with_front.then(|| nodal_values(&t[..k])));
            let cut = cut_crack(&m, &l, &CutOptions::default()).unwrap();
            check_cut(&m, &l, &cut);
        }
    }

    /// What: total facet length of a random straight interface across a distorted tri3
    /// mesh and a quad4 mesh. Reference: the exact chord length √(1 + m²) of
    /// y = y0 + m (x − 0.5) across the unit square. Tolerance 1e-12 relative.
    #[test]
    fn random_interface_length(y0 in 0.3f64..0.7, m in -0.5f64..0.5) {
        let s = (1.0 + m * m).sqrt();
        for kind in [CellType::Tri3, CellType::Quad4] {
            let mut mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [7, 6]).unwrap();
            if kind == CellType::Tri3 {
                generate::perturb_interior(&mut mesh, 1.0 / 7.0, 0.2, 3);
            }
            let l = ls(sample(&mesh, |x| (x[1] - y0 - m * (x[0] - 0.5)) / s), None);
            let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
            prop_assert!(rel(cut.crack_measure(), s) < 1e-12, "{kind:?}: {} vs {s}", cut.crack_measure());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, failure_persistence: None, ..ProptestConfig::default() })]

    /// What: a straight segment crack at a random position, angle and length, with both
    /// tips inside a distorted tri3 mesh and a quad4 mesh. Reference: total facet length
    /// 2a; two tips at centre ± a·direction, in Front cells; sub-cells partition every
    /// cut cell. Tolerance 1e-12.
    #[test]
    fn random_segment_crack(xc in 0.4f64..0.6, yc in 0.4f64..0.6, a in 0.2f64..0.3, beta in -3.2f64..3.2) {
        let (c, s) = (beta.cos(), beta.sin());
        for (kind, perturb) in [(CellType::Tri3, true), (CellType::Quad4, false)] {
            let mut mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
            if perturb {
                generate::perturb_interior(&mut mesh, 0.1, 0.2, 9);
            }
            let l = ls(
                sample(&mesh, |x| -s * (x[0] - xc) + c * (x[1] - yc)),
                Some(sample(&mesh, |x| (c * (x[0] - xc) + s * (x[1] - yc)).abs() - a)),
            );
            let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
            check_cut(&mesh, &l, &cut);
            prop_assert!(rel(cut.crack_measure(), 2.0 * a) < 1e-12, "{kind:?}: {}", cut.crack_measure());
            prop_assert_eq!(cut.front.len(), 2);
            for sign in [-1.0, 1.0] {
                let tip = [xc + sign * a * c, yc + sign * a * s];
                let found = cut.front.iter().any(|p| {
                    (p.points[0][0] - tip[0]).hypot(p.points[0][1] - tip[1]) < 1e-12 && cut.status[p.cell] == CellStatus::Front
                });
                prop_assert!(found, "{kind:?}: tip {tip:?} not in {:?}", cut.front);
            }
        }
    }

    /// What: a tilted half-plane crack at a random position (φn the distance to the
    /// plane z = z0 + α(x − ½) + β(y − ½), φt = x − x0) in a distorted tet4 box and a hex8
    /// box. Reference: area x0 √(1 + α² + β²), front length √(1 + β²); sub-cells partition
    /// every cut cell. Tolerance 1e-12 relative.
    #[test]
    fn random_half_plane_crack(z0 in 0.35f64..0.65, al in -0.2f64..0.2, be in -0.2f64..0.2, x0 in 0.2f64..0.8) {
        let s = (1.0 + al * al + be * be).sqrt();
        for (kind, perturb) in [(CellType::Tet4, true), (CellType::Hex8, false)] {
            let mut mesh = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [5, 4, 5]).unwrap();
            if perturb {
                generate::perturb_interior(&mut mesh, 0.2, 0.2, 4);
            }
            let l = ls(
                sample(&mesh, |x| (x[2] - z0 - al * (x[0] - 0.5) - be * (x[1] - 0.5)) / s),
                Some(sample(&mesh, |x| x[0] - x0)),
            );
            let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
            check_cut(&mesh, &l, &cut);
            prop_assert!(rel(cut.crack_measure(), x0 * s) < 1e-12, "{kind:?}: {}", cut.crack_measure());
            let fl = (1.0 + be * be).sqrt();
            prop_assert!(rel(cut.front_length(), fl) < 1e-12, "{kind:?}: {} vs {fl}", cut.front_length());
        }
    }
}

/// What: the same partition check on whole structured meshes cut by planes through
/// nodes and along faces (exact zeros), interface and half-plane crack. Reference: cell
/// measures. Tolerance 1e-12 relative.
#[test]
fn subcells_partition_on_meshes_with_exact_zeros() {
    for kind in [CellType::Tri3, CellType::Quad4] {
        let m = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [4, 4]).unwrap();
        for f in [|x: &[f64; 3]| x[1] - 0.5, |x: &[f64; 3]| x[1] - x[0], |x: &[f64; 3]| x[0] + x[1] - 1.0] {
            let l = ls(sample(&m, f), Some(sample(&m, |x| x[0] - 0.5)));
            check_cut(&m, &l, &cut_crack(&m, &l, &CutOptions::default()).unwrap());
        }
    }
    for kind in [CellType::Tet4, CellType::Hex8] {
        let m = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [2, 2, 2]).unwrap();
        for f in [|x: &[f64; 3]| x[2] - 0.5, |x: &[f64; 3]| x[2] - x[0], |x: &[f64; 3]| x[0] + x[1] + x[2] - 1.5] {
            let l = ls(sample(&m, f), Some(sample(&m, |x| x[1] - 0.5)));
            check_cut(&m, &l, &cut_crack(&m, &l, &CutOptions::default()).unwrap());
        }
    }
}

// ---------------------------------------------------------------------------------------
// Crack lengths and areas.

/// What: facet lengths of a straight interface across structured and distorted 2D
/// meshes, and facet areas of a tilted plane across 3D meshes. Reference: √(1 + m²) and
/// √(1 + a² + b²) (the plane stays inside the box). Tolerance 1e-12 relative.
#[test]
fn straight_crack_measures() {
    let (y0, m): (f64, f64) = (0.4123, 0.31);
    let s = (1.0 + m * m).sqrt();
    for (kind, perturb) in [(CellType::Tri3, false), (CellType::Tri3, true), (CellType::Quad4, false)] {
        let mut mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [9, 8]).unwrap();
        if perturb {
            generate::perturb_interior(&mut mesh, 1.0 / 9.0, 0.25, 7);
        }
        let l = ls(sample(&mesh, |x| (x[1] - y0 - m * (x[0] - 0.5)) / s), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!(rel(cut.crack_measure(), s) < 1e-12, "{kind:?}: {}", cut.crack_measure());
        assert!(cut.status.iter().all(|s| *s != CellStatus::Front));
        for f in &cut.facets {
            assert!(f.normal[1] > 0.9, "normal {:?}", f.normal);
        }
    }
    let (z0, a, b): (f64, f64, f64) = (0.4711, 0.17, -0.23);
    let s = (1.0 + a * a + b * b).sqrt();
    for (kind, perturb) in [(CellType::Tet4, false), (CellType::Tet4, true), (CellType::Hex8, false)] {
        let mut mesh = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [5, 4, 6]).unwrap();
        if perturb {
            generate::perturb_interior(&mut mesh, 1.0 / 6.0, 0.2, 11);
        }
        let l = ls(sample(&mesh, |x| (x[2] - z0 - a * (x[0] - 0.5) - b * (x[1] - 0.5)) / s), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!(rel(cut.crack_measure(), s) < 1e-12, "{kind:?}: {}", cut.crack_measure());
        for f in &cut.facets {
            assert!(f.normal[2] > 0.9);
        }
    }
}

/// What: a straight segment crack with both tips inside the mesh (φt = |s − sc| − a).
/// Reference: total facet length 2a; the two tips at centre ± a·direction, one in each of
/// two Front cells. Tolerance 1e-12.
#[test]
fn segment_crack_with_two_tips() {
    let (xc, yc, a, beta) = (0.503, 0.487, 0.2712, 0.37f64);
    let (c, s) = (beta.cos(), beta.sin());
    let tips = [[xc - a * c, yc - a * s], [xc + a * c, yc + a * s]];
    for (kind, perturb) in [(CellType::Tri3, false), (CellType::Tri3, true), (CellType::Quad4, false)] {
        let mut mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
        if perturb {
            generate::perturb_interior(&mut mesh, 0.1, 0.2, 5);
        }
        let l = ls(
            sample(&mesh, |x| -s * (x[0] - xc) + c * (x[1] - yc)),
            Some(sample(&mesh, |x| (c * (x[0] - xc) + s * (x[1] - yc)).abs() - a)),
        );
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!(rel(cut.crack_measure(), 2.0 * a) < 1e-12, "{kind:?}: {}", cut.crack_measure());
        assert_eq!(cut.front.len(), 2, "{kind:?}: {:?}", cut.front);
        assert_eq!(cut.status.iter().filter(|s| **s == CellStatus::Front).count(), 2);
        for tip in tips {
            let p = cut.front.iter().find(|p| (p.points[0][0] - tip[0]).hypot(p.points[0][1] - tip[1]) < 1e-12);
            let p = p.unwrap_or_else(|| panic!("{kind:?}: tip {tip:?} not found in {:?}", cut.front));
            assert_eq!(cut.status[p.cell], CellStatus::Front);
            // The tip lies in its cell: it is a vertex of some facet of that cell.
            assert!(cut.cell_facets(p.cell).iter().any(|f| f.vertices.iter().any(|v| v == &p.points[0])));
        }
    }
}

/// What: a rectangular crack φn = z − z0, φt = max(|u| − a, |v| − b) in the frame (u, v)
/// of the box's (x, y) turned by 45° about a grid node, with a − b = √2 h, in tet4 and
/// hex8 boxes. Every kink of that max (x = xc ± h, y = yc ± h, through the corners) then
/// lies on grid planes, so the cut's linear interpolant is exact in every cell where φt
/// changes sign. (An axis-aligned rectangle cannot be exact: with corners inside cells the
/// interpolated max is wrong there; with corners on nodes, at two of the four corners the
/// Kuhn sub-simplices next to the corner have φt ≡ 0, outside the crack by the
/// zero-is-positive rule.) Reference: area 4ab, front length (perimeter) 4(a + b), each
/// front point on the rectangle's edge. Tolerance 1e-12 relative.
#[test]
fn rectangular_crack_area_and_front() {
    let h = 1.0 / 16.0;
    let (xc, yc, a, z0) = (0.5, 0.5, 0.3, 0.4321);
    let b = a - 2f64.sqrt() * h;
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let phit = move |x: &[f64; 3]| {
        let (dx, dy) = (x[0] - xc, x[1] - yc);
        let (u, v) = (r * (dx + dy), r * (dy - dx));
        (u.abs() - a).max(v.abs() - b)
    };
    for kind in [CellType::Tet4, CellType::Hex8] {
        let mesh = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [16, 16, 3]).unwrap();
        let l = ls(sample(&mesh, |x| x[2] - z0), Some(sample(&mesh, phit)));
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!(rel(cut.crack_measure(), 4.0 * a * b) < 1e-12, "{kind:?}: {}", cut.crack_measure());
        assert!(rel(cut.front_length(), 4.0 * (a + b)) < 1e-12, "{kind:?}: front {}", cut.front_length());
        for p in &cut.front {
            for x in &p.points {
                assert!((x[2] - z0).abs() < 1e-12);
                assert!(phit(x).abs() < 1e-12, "front point {x:?} off the rectangle edge");
            }
        }
    }
}

/// What: a half-plane crack (φn = z − z0, φt = x − x0, both off-grid) in tet4 (also
/// distorted) and hex8 boxes: the front segments are found and lie on the front line.
/// Reference: area x0 · 1, front length 1 (the box width in y). Tolerance 1e-12.
#[test]
fn front_segment_3d() {
    let (z0, x0) = (0.537, 0.6131);
    for (kind, perturb) in [(CellType::Tet4, false), (CellType::Tet4, true), (CellType::Hex8, false)] {
        let mut mesh = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [5, 3, 4]).unwrap();
        if perturb {
            generate::perturb_interior(&mut mesh, 0.2, 0.2, 2);
        }
        let l = ls(sample(&mesh, |x| x[2] - z0), Some(sample(&mesh, |x| x[0] - x0)));
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!(rel(cut.crack_measure(), x0) < 1e-12, "{kind:?}: {}", cut.crack_measure());
        assert!(rel(cut.front_length(), 1.0) < 1e-12, "{kind:?}: {}", cut.front_length());
        assert!(!cut.front.is_empty());
        for p in &cut.front {
            assert_eq!(cut.status[p.cell], CellStatus::Front);
            assert_eq!(p.points.len(), 2);
            for x in &p.points {
                assert!((x[2] - z0).abs() < 1e-12 && (x[0] - x0).abs() < 1e-12, "{x:?}");
            }
        }
        // Front cells have sub-cells with singular vertices, on both sides and both
        // φt sides; in 3D most touch the front along an edge.
        let fc: Vec<&CellCut> = cut.cut_cells.iter().filter(|c| c.status == CellStatus::Front).collect();
        assert!(fc.iter().all(|c| c.subcells.iter().any(|s| s.singular_vertex.is_some())));
        assert!(fc.iter().any(|c| c.subcells.iter().any(|s| s.singular_edge.is_some())));
        assert!(fc.iter().all(|c| c.subcells.iter().any(|s| s.ahead) && c.subcells.iter().any(|s| !s.ahead)));
    }
}

// ---------------------------------------------------------------------------------------
// Cracks along edges and through nodes.

/// What: a crack along a row of element edges (φn = y − 0.5 exactly zero at the nodes of
/// that row): each edge's facet appears once, in the cell on the − side, with both
/// vertices on mesh nodes. Reference: total length 1 (interface) and 0.5 (segment crack
/// with tips on nodes x = 0.25, 0.75), number of facets = number of edges on the crack.
/// Tolerance 1e-14.
#[test]
fn crack_along_element_edges() {
    for kind in [CellType::Tri3, CellType::Quad4] {
        let mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [4, 4]).unwrap();
        let l = ls(sample(&mesh, |x| x[1] - 0.5), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!((cut.crack_measure() - 1.0).abs() < 1e-14, "{kind:?}: {}", cut.crack_measure());
        assert_eq!(cut.facets.len(), 4, "{kind:?}");
        for f in &cut.facets {
            // The owner is below the crack (− side).
            let c = mesh.cells[f.cell].nodes().iter().map(|&g| mesh.nodes[g][1]).fold(0.0, f64::max);
            assert!((c - 0.5).abs() < 1e-15, "facet owned by a cell above the crack");
            assert!(f.vertex_nodes.iter().all(|n| n.is_some()));
            assert!(f.vertex_edges.iter().all(|e| e.is_some()));
            // The sub-cells of the owning cell are all on the − side.
            assert!(cut.cell_cut(f.cell).unwrap().subcells.iter().all(|s| s.side == -1));
        }
        // A segment crack along the same row, tips exactly on nodes.
        let l = ls(sample(&mesh, |x| x[1] - 0.5), Some(sample(&mesh, |x| (x[0] - 0.5).abs() - 0.25)));
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!((cut.crack_measure() - 0.5).abs() < 1e-14, "{kind:?}: {}", cut.crack_measure());
        assert_eq!(cut.facets.len(), 2);
        let mut tips: Vec<f64> = cut.front.iter().map(|p| p.points[0][0]).collect();
        tips.sort_by(f64::total_cmp);
        assert_eq!(tips, vec![0.25, 0.75], "{kind:?}: {:?}", cut.front);
    }
    // 3D: a crack along a layer of faces.
    for kind in [CellType::Tet4, CellType::Hex8] {
        let mesh = generate::box_mesh(kind, [0.0; 3], [1.0; 3], [3, 2, 4]).unwrap();
        let l = ls(sample(&mesh, |x| x[2] - 0.5), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        check_cut(&mesh, &l, &cut);
        assert!((cut.crack_measure() - 1.0).abs() < 1e-14, "{kind:?}: {}", cut.crack_measure());
        for f in &cut.facets {
            assert!(f.normal[2] > 1.0 - 1e-14);
            let top = mesh.cells[f.cell].nodes().iter().map(|&g| mesh.nodes[g][2]).fold(0.0, f64::max);
            assert_eq!(top, 0.5);
        }
    }
}

/// What: cracks through nodes: y = x along the (0, 2) diagonals of the tri3 split and
/// through the quad4 diagonals, y = 1 − x across the other diagonals (through nodes,
/// crossing edges at their ends). Reference: length √2. Tolerance 1e-14 relative.
#[test]
fn crack_through_nodes() {
    for kind in [CellType::Tri3, CellType::Quad4] {
        let mesh = generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [5, 5]).unwrap();
        for f in [|x: &[f64; 3]| x[1] - x[0], |x: &[f64; 3]| x[0] + x[1] - 1.0] {
            let l = ls(sample(&mesh, f), None);
            let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
            check_cut(&mesh, &l, &cut);
            assert!(rel(cut.crack_measure(), 2f64.sqrt()) < 1e-14, "{kind:?}: {}", cut.crack_measure());
            for fa in &cut.facets {
                for (k, x) in fa.vertices.iter().enumerate() {
                    // Every facet vertex is a node, or the midpoint of a (0, 2) diagonal: a
                    // mesh edge for tri3, the split diagonal (no edge) for quad4.
                    if fa.vertex_nodes[k].is_none() {
                        assert_eq!(fa.vertex_edges[k].is_some(), kind == CellType::Tri3);
                    } else {
                        assert_eq!(mesh.nodes[fa.vertex_nodes[k].unwrap()], *x);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Statuses, vertex locations, errors.

/// What: statuses on a hand-made strip of 4 quads [0,4]×[0,1] (and the tri3 version)
/// cut by y = 0.5 up to a tip at x = 2.5. Reference: Cut, Cut, Front, Uncut (φn = 0
/// crosses the last cell ahead of the front); the tip (2.5, 0.5) in cell 2; crack length
/// 2.5. Tolerance 1e-14.
#[test]
fn statuses_on_a_strip() {
    let mesh = generate::rectangle(CellType::Quad4, [0.0, 0.0], [4.0, 1.0], [4, 1]).unwrap();
    let l = ls(sample(&mesh, |x| x[1] - 0.5), Some(sample(&mesh, |x| x[0] - 2.5)));
    let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
    check_cut(&mesh, &l, &cut);
    use CellStatus::*;
    assert_eq!(cut.status, vec![Cut, Cut, Front, Uncut]);
    assert_eq!(cut.cut_cells.iter().map(|c| c.cell).collect::<Vec<_>>(), vec![0, 1, 2]);
    assert!(cut.cell_cut(3).is_none());
    assert_eq!(cut.front.len(), 1);
    assert_eq!(cut.front[0].cell, 2);
    let p = cut.front[0].points[0];
    assert!((p[0] - 2.5).abs() < 1e-14 && (p[1] - 0.5).abs() < 1e-14);
    assert!((cut.crack_measure() - 2.5).abs() < 1e-14);
    // The sub-cells touching the tip carry it as their singular vertex.
    let cc = cut.cell_cut(2).unwrap();
    let sing: Vec<&SubCell> = cc.subcells.iter().filter(|s| s.singular_vertex.is_some()).collect();
    assert!(sing.len() >= 4);
    for s in &sing {
        let v = s.vertices[s.singular_vertex.unwrap()];
        assert!((v[0] - 0.0).abs() < 1e-14 && v[1].abs() < 1e-14, "tip in reference coords: {v:?}");
    }
    for s in cc.subcells.iter().filter(|s| s.singular_vertex.is_none()) {
        assert!(s.vertices.iter().all(|v| v[0].abs() > 1e-14 || v[1].abs() > 1e-14));
    }
    // Interface: every crossed cell is Cut.
    let l = ls(sample(&mesh, |x| x[1] - 0.5), None);
    let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
    assert_eq!(cut.status, vec![Cut; 4]);
    assert!(cut.front.is_empty());
    // Tri3: the tip is inside the lower triangle of the third square.
    let mesh = generate::rectangle(CellType::Tri3, [0.0, 0.0], [4.0, 1.0], [4, 1]).unwrap();
    let l = ls(sample(&mesh, |x| x[1] - 0.3), Some(sample(&mesh, |x| x[0] - 2.5)));
    let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
    check_cut(&mesh, &l, &cut);
    // Square 2: the lower triangle (cell 4) holds the tip, the upper one (cell 5) only
    // crack; square 3 is crossed ahead of the front.
    assert_eq!(cut.status, vec![Cut, Cut, Cut, Cut, Front, Cut, Uncut, Uncut]);
    assert_eq!(cut.front[0].cell, 4);
}

/// What: facet vertices of a generic interface lie on the mesh edge they report, whose
/// end nodes have opposite signs; on quads a vertex on the (0, 2) split diagonal reports
/// none. Reference: the edge segment. Tolerance 1e-12.
#[test]
fn facet_vertices_know_their_edges() {
    for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
        let mesh = if kind.dim() == 2 {
            generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [4, 3]).unwrap()
        } else {
            generate::box_mesh(kind, [0.0; 3], [1.0; 3], [3, 3, 2]).unwrap()
        };
        let l = ls(sample(&mesh, |x| x[1] - 0.37 * x[0] - 0.11 * x[2] - 0.3123), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        let mut n_none = 0;
        for f in &cut.facets {
            for (k, x) in f.vertices.iter().enumerate() {
                match f.vertex_edges[k] {
                    Some([a, b]) => {
                        assert!(a < b);
                        assert!((l.lsn[a] < 0.0) != (l.lsn[b] < 0.0));
                        let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
                        let t = sub(pb, pa);
                        let s = dot(sub(x, pa), t) / dot(t, t);
                        let q = [pa[0] + s * t[0], pa[1] + s * t[1], pa[2] + s * t[2]];
                        assert!((0.0..=1.0).contains(&s) && norm(sub(x, q)) < 1e-12);
                    }
                    None => {
                        assert!(!kind.is_simplex(), "{kind:?}: a simplex facet vertex is always on an edge");
                        n_none += 1;
                    }
                }
            }
        }
        if !kind.is_simplex() {
            assert!(n_none > 0);
        }
    }
}

/// What: input errors. Reference: the messages name the array and the node.
#[test]
fn bad_input_is_reported() {
    let mesh = generate::rectangle(CellType::Tri3, [0.0, 0.0], [1.0, 1.0], [2, 2]).unwrap();
    let e = cut_crack(&mesh, &ls(vec![0.0; 3], None), &CutOptions::default()).unwrap_err();
    assert!(matches!(e, CutError::WrongLength { which: "lsn", len: 3, nodes: 9 }), "{e}");
    assert!(e.to_string().contains("9 nodes"));
    let mut v = vec![1.0; 9];
    v[4] = f64::NAN;
    let e = cut_crack(&mesh, &ls(vec![1.0; 9], Some(v)), &CutOptions::default()).unwrap_err();
    assert!(e.to_string().contains("lst") && e.to_string().contains("node 4"), "{e}");
    let e = cut_crack(&mesh, &ls(vec![1.0; 9], Some(vec![0.0; 8])), &CutOptions::default()).unwrap_err();
    assert!(matches!(e, CutError::WrongLength { which: "lst", .. }));
    let mut bad = mesh.clone();
    bad.cells[1].nodes[2] = 99;
    let e = cut_crack(&bad, &ls(vec![1.0; 9], None), &CutOptions::default()).unwrap_err();
    assert!(matches!(e, CutError::BadNodeIndex { cell: 1, node: 99 }));
}

// ---------------------------------------------------------------------------------------
// Quadrature.

/// Reference ∫_T r^(−1/2) dA over a triangle with the singular point at its vertex p:
/// (2/3) ∫_θ R(θ)^(3/2) dθ, by composite 20-point Gauss over 200 panels in θ.
fn inv_sqrt_r_over_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (x, w) = gauss_legendre(20);
    let panels = 200;
    let mut s = 0.0;
    // Parametrise the opposite edge by v ∈ [0, 1]: q(v) = a + v (b − a); dθ = |cross| / |q − p|² dv.
    let cr = ((a[0] - p[0]) * (b[1] - p[1]) - (a[1] - p[1]) * (b[0] - p[0])).abs();
    for k in 0..panels {
        for (xi, wi) in x.iter().zip(&w) {
            let v = (k as f64 + 0.5 * (xi + 1.0)) / panels as f64;
            let q = [a[0] + v * (b[0] - a[0]) - p[0], a[1] + v * (b[1] - a[1]) - p[1]];
            let r2 = q[0] * q[0] + q[1] * q[1];
            s += wi * 0.5 / panels as f64 * (2.0 / 3.0) * r2.powf(0.75) * cr / r2;
        }
    }
    s
}

/// What: the almost-polar rule on a triangle with its singular vertex at the tip
/// integrates 1/√r (r = distance to the tip) accurately, whichever vertex is singular;
/// the plain Gauss rule of the same size does not. Reference: (2/3) ∫ R(θ)^(3/2) dθ by a
/// fine 1D rule. Tolerance 1e-6 relative (default front_degree 8).
#[test]
fn collapsed_rule_integrates_inverse_sqrt_r() {
    let tri = [[0.2, 0.1, 0.0], [1.1, 0.3, 0.0], [0.4, 0.8, 0.0]];
    let opts = CutOptions::default();
    for s in 0..3 {
        let p = tri[s];
        let exact = inv_sqrt_r_over_triangle(
            [p[0], p[1]],
            [tri[(s + 1) % 3][0], tri[(s + 1) % 3][1]],
            [tri[(s + 2) % 3][0], tri[(s + 2) % 3][1]],
        );
        let sc =
            SubCell { side: 1, ahead: false, vertices: tri.to_vec(), singular_vertex: Some(s), singular_edge: None };
        let q = subcell_quadrature(&sc, 2, &opts);
        let f = |x: &[f64; 3]| 1.0 / ((x[0] - p[0]).hypot(x[1] - p[1])).sqrt();
        let v: f64 = q.iter().map(|(x, w)| w * f(x)).sum();
        eprintln!("MARGIN 2D vertex {s}: {:e} (plain {:e})", rel(v, exact), {
            let plain = SubCell { singular_vertex: None, ..sc.clone() };
            let g = subcell_quadrature(&plain, 2, &CutOptions { subcell_degree: 8, ..opts });
            rel(g.iter().map(|(x, w)| w * f(x)).sum::<f64>(), exact)
        });
        assert!(rel(v, exact) < 1e-6, "vertex {s}: {v} vs {exact} ({:e})", rel(v, exact));
        let plain = SubCell { singular_vertex: None, ..sc.clone() };
        let g = subcell_quadrature(&plain, 2, &CutOptions { subcell_degree: 8, ..opts });
        let vg: f64 = g.iter().map(|(x, w)| w * f(x)).sum();
        assert!(rel(vg, exact) > 1e-4, "the plain rule should be visibly worse: {:e}", rel(vg, exact));
    }
}

/// What: in a tri3 Front cell of an actual cut, Σ over the sub-cell rules of 1/√r (r to
/// the tip) matches the integral over the parent triangle. Reference: the parent split
/// at the tip into three triangles, each by the fine 1D rule. Tolerance 1e-6 relative.
#[test]
fn inverse_sqrt_r_over_a_front_cell() {
    let mesh = one_cell(CellType::Tri3, &[[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.3, 0.9, 0.0]]);
    let tip = [0.41, 0.33];
    let d = [0.8f64.cos(), 0.8f64.sin()];
    let l = ls(
        sample(&mesh, |x| -d[1] * (x[0] - tip[0]) + d[0] * (x[1] - tip[1])),
        Some(sample(&mesh, |x| d[0] * (x[0] - tip[0]) + d[1] * (x[1] - tip[1]))),
    );
    let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
    assert_eq!(cut.status, vec![CellStatus::Front]);
    let p = cut.front[0].points[0];
    assert!((p[0] - tip[0]).abs() < 1e-14 && (p[1] - tip[1]).abs() < 1e-14);
    let cc = &cut.cut_cells[0];
    // 4 regions around the tip, fanned from it: 7 triangles, all with the tip as a vertex.
    assert_eq!(cc.subcells.len(), 7);
    assert!(cc.subcells.iter().all(|s| s.singular_vertex.is_some()));
    let n = &mesh.nodes;
    let mut exact = 0.0;
    for k in 0..3 {
        let (a, b) = (n[k], n[(k + 1) % 3]);
        exact += inv_sqrt_r_over_triangle(tip, [a[0], a[1]], [b[0], b[1]]);
    }
    let mut v = 0.0;
    for sc in &cc.subcells {
        let q = subcell_quadrature(sc, 2, &cut.opts);
        for (xi, w) in q.iter() {
            // Affine parent: det J constant = 2 × area.
            let x = [
                n[0][0] + xi[0] * (n[1][0] - n[0][0]) + xi[1] * (n[2][0] - n[0][0]),
                n[0][1] + xi[0] * (n[1][1] - n[0][1]) + xi[1] * (n[2][1] - n[0][1]),
            ];
            let det = (n[1][0] - n[0][0]) * (n[2][1] - n[0][1]) - (n[1][1] - n[0][1]) * (n[2][0] - n[0][0]);
            v += w * det / ((x[0] - tip[0]).hypot(x[1] - tip[1])).sqrt();
        }
    }
    eprintln!("MARGIN front cell {:e}", rel(v, exact));
    assert!(rel(v, exact) < 1e-6, "{v} vs {exact}: {:e}", rel(v, exact));
}

/// What: the collapsed rules (2D vertex, 3D vertex, 3D edge) are exact for polynomials
/// of degree front_degree on their simplex. Reference: the plain Gauss rule of that
/// degree mapped to the same simplex. Tolerance 1e-13 relative.
#[test]
fn collapsed_rules_are_exact_for_polynomials() {
    let p = 6usize;
    let opts = CutOptions { subcell_degree: p, front_degree: p };
    let tri = vec![[0.2, 0.1, 0.0], [1.1, 0.3, 0.0], [0.4, 0.8, 0.0]];
    let tet = vec![[0.1, 0.0, 0.2], [1.0, 0.2, 0.1], [0.3, 0.9, 0.0], [0.2, 0.3, 1.1]];
    let f2 = |x: &[f64; 3]| (1.0 + x[0]).powi(3) * (0.5 - x[1]).powi(3) + x[0].powi(6) - 2.0 * x[1].powi(5);
    let f3 = |x: &[f64; 3]| (1.0 + x[0]).powi(2) * (0.5 - x[1]).powi(2) * (x[2] + 0.3).powi(2) + x[2].powi(6);
    for s in 0..3 {
        let plain =
            SubCell { side: 1, ahead: false, vertices: tri.clone(), singular_vertex: None, singular_edge: None };
        let sing = SubCell { singular_vertex: Some(s), ..plain.clone() };
        let a: f64 = subcell_quadrature(&plain, 2, &opts).iter().map(|(x, w)| w * f2(x)).sum();
        let b: f64 = subcell_quadrature(&sing, 2, &opts).iter().map(|(x, w)| w * f2(x)).sum();
        assert!(rel(b, a) < 1e-13, "2D vertex {s}: {b} vs {a}");
    }
    let plain = SubCell { side: 1, ahead: false, vertices: tet.clone(), singular_vertex: None, singular_edge: None };
    let a: f64 = subcell_quadrature(&plain, 3, &opts).iter().map(|(x, w)| w * f3(x)).sum();
    // Cross-check the plain rule itself against a higher-degree one.
    let hi: f64 = {
        let r = gauss_tetrahedron(12);
        let (e1, e2, e3) = (sub(tet[1], tet[0]), sub(tet[2], tet[0]), sub(tet[3], tet[0]));
        let det = dot(e1, cross(e2, e3)).abs();
        r.iter()
            .map(|(q, w)| {
                let x: [f64; 3] = std::array::from_fn(|k| tet[0][k] + q[0] * e1[k] + q[1] * e2[k] + q[2] * e3[k]);
                w * det * f3(&x)
            })
            .sum()
    };
    assert!(rel(a, hi) < 1e-13);
    for s in 0..4 {
        let sing = SubCell { singular_vertex: Some(s), ..plain.clone() };
        let b: f64 = subcell_quadrature(&sing, 3, &opts).iter().map(|(x, w)| w * f3(x)).sum();
        assert!(rel(b, a) < 1e-13, "3D vertex {s}: {b} vs {a}");
        for t in 0..4 {
            if t != s {
                let sing = SubCell { singular_vertex: Some(s), singular_edge: Some([s, t]), ..plain.clone() };
                let b: f64 = subcell_quadrature(&sing, 3, &opts).iter().map(|(x, w)| w * f3(x)).sum();
                assert!(rel(b, a) < 1e-13, "3D edge {s}{t}: {b} vs {a}");
            }
        }
    }
}

/// What: the edge-collapsed tet rule on 1/√d, d the distance to the line through the
/// singular edge, converges fast: the default degree agrees with a degree-30 rule.
/// Reference: the degree-30 rule (the plain Gauss rule of degree 8 is far off).
/// Tolerance 1e-6 relative.
#[test]
fn edge_collapsed_rule_on_inverse_sqrt_distance() {
    let tet = vec![[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.1, 0.2], [0.2, 0.9, 0.7]];
    let f = |x: &[f64; 3]| 1.0 / x[0].hypot(x[1]).sqrt();
    let sc = SubCell { side: 1, ahead: false, vertices: tet, singular_vertex: Some(0), singular_edge: Some([0, 1]) };
    let v8: f64 = subcell_quadrature(&sc, 3, &CutOptions::default()).iter().map(|(x, w)| w * f(x)).sum();
    let v30: f64 = subcell_quadrature(&sc, 3, &CutOptions { subcell_degree: 2, front_degree: 30 })
        .iter()
        .map(|(x, w)| w * f(x))
        .sum();
    eprintln!("MARGIN 3D edge {:e}", rel(v8, v30));
    assert!(rel(v8, v30) < 1e-6, "{v8} vs {v30}: {:e}", rel(v8, v30));
    let plain = SubCell { singular_vertex: None, singular_edge: None, ..sc };
    let vp: f64 = subcell_quadrature(&plain, 3, &CutOptions { subcell_degree: 8, front_degree: 8 })
        .iter()
        .map(|(x, w)| w * f(x))
        .sum();
    assert!(rel(vp, v30) > 1e-4, "{:e}", rel(vp, v30));
}

/// What: facet quadrature weights sum to the facet measure and integrate x exactly
/// (centroid), in 2D and 3D. Reference: measure and measure × centroid of the flat facet
/// on affine meshes. Tolerance 1e-13.
#[test]
fn facet_quadrature_matches_measure_and_centroid() {
    for kind in [CellType::Tri3, CellType::Tet4] {
        let mesh = if kind.dim() == 2 {
            generate::rectangle(kind, [0.0, 0.0], [2.0, 1.0], [3, 3]).unwrap()
        } else {
            generate::box_mesh(kind, [0.0; 3], [2.0, 1.0, 1.0], [3, 2, 2]).unwrap()
        };
        let l = ls(sample(&mesh, |x| x[1] - 0.2 * x[0] - 0.1 * x[2] - 0.33), None);
        let cut = cut_crack(&mesh, &l, &CutOptions::default()).unwrap();
        assert!(!cut.facets.is_empty());
        for f in &cut.facets {
            let (pts, w) = facet_quadrature(f, 3);
            assert!((w.iter().sum::<f64>() - f.measure).abs() < 1e-13);
            let k = f.vertices.len() as f64;
            let g = super::facets::CellGeom::new(&mesh, f.cell);
            for d in 0..3 {
                let c: f64 = f.vertices.iter().map(|v| v[d]).sum::<f64>() / k;
                let s: f64 = pts.iter().zip(&w).map(|(p, w)| w * g.map(p)[d]).sum();
                assert!((s - c * f.measure).abs() < 1e-13);
            }
        }
    }
}
