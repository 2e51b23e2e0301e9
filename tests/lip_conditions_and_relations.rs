//! Prescribed displacements of one lip of a crack or interface, and linear relations
//! between unknowns (issue 11 item 17; Code_Aster's DDL_IMPO on an X-FEM lip, LIAISON_DDL
//! and LIAISON_GROUP), against analytic uniform-strain solutions.

use fissure::case::{resolve, Case};
use fissure::run::solve_model;
use fissure::solve::statics::SolveOptions;
use std::path::Path;

const E: f64 = 100.0;
const NU: f64 = 0.3;

/// Node coordinates, nodal displacements (2D) and the reactions of the Dirichlet groups.
type Solution = (Vec<[f64; 3]>, Vec<[f64; 2]>, Vec<(String, [f64; 3])>);

/// Solves a case text in-process.
fn solve(text: &str) -> Solution {
    let case = Case::parse(text, Path::new("lip.toml")).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &mesh).unwrap();
    let opts = SolveOptions { linear: case.solver.linear, ..Default::default() };
    let (report, sols) = solve_model(&model, &opts).unwrap();
    let u = &sols[0];
    let nodal = (0..mesh.n_nodes()).map(|n| [u[2 * n], u[2 * n + 1]]).collect();
    let reactions = model.dirichlet_groups.iter().cloned().zip(report.steps[0].reactions.iter().copied()).collect();
    (mesh.nodes.clone(), nodal, reactions)
}

/// Block [0, 2] × [0, 1], quad4 5 × 3 (h = 0.4), plane strain, E = 100, ν = 0.3, cut by
/// an interface at x = 1 (`line`, + side x > 1) through the middle of a cell column.
/// Conditions: right edge u_x = 0; bottom edge u_y = 0 (both pieces); the − lip held
/// (u_x = 0) and the + lip pulled by u_x = δ(2 − x) with δ = 0.01 (a formula, so that
/// its nodal values are those of the linear field; on the lip x = 1 it is δ).
/// Reference: the + piece is in uniform uniaxial plane strain ε_xx = −δ, σ_yy = 0:
/// u_x = δ(2 − x), u_y = ν/(1−ν) δ y; the − piece does not move. The reaction of the right
/// edge is σ·n = σ_xx = −E δ/(1−ν²) (reactions are σ·n over the held face, as for the
/// nodal conditions), the + lip's (outward normal −x) the opposite. Tolerance 1e-9 relative (the
/// field is in the discrete space).
#[test]
fn pulled_plus_lip_gives_uniform_strain_in_the_plus_piece_and_the_minus_piece_stays() {
    let delta = 0.01;
    let text = format!(
        r#"[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [5, 3]

[[materials]]
E = {E}
nu = {NU}

[[sets]]
name = "band"
on = "x - 1"
tolerance = 0.21

[[cracks]]
name = "interface"
shape = "line"
point = [1.0, 0.5]
normal = [1.0, 0.0]

[[dirichlet]]
group = "right"
components = ["x"]

[[dirichlet]]
group = "bottom"
components = ["y"]

[[dirichlet]]
group = "band"
crack = "interface"
lip = "-"
components = ["x"]

[[dirichlet]]
group = "band"
crack = "interface"
lip = "+"
components = ["x"]
value = "{delta} * (2 - x)"
"#
    );
    let (x, u, reactions) = solve(&text);
    let c = NU / (1.0 - NU);
    for (n, p) in x.iter().enumerate() {
        // Standard dofs hold the field of the node's own side (shifted enrichment).
        let (ex, ey) = if p[0] > 1.0 { (delta * (2.0 - p[0]), c * delta * p[1]) } else { (0.0, 0.0) };
        assert!((u[n][0] - ex).abs() < 1e-9 * delta, "node {n} at {p:?}: u_x {} vs {ex}", u[n][0]);
        assert!((u[n][1] - ey).abs() < 1e-9 * delta, "node {n} at {p:?}: u_y {} vs {ey}", u[n][1]);
    }
    let force = E * delta / (1.0 - NU * NU);
    let right = reactions.iter().find(|r| r.0 == "right").unwrap().1;
    assert!((right[0] + force).abs() < 1e-9 * force, "right reaction {right:?} vs {}", -force);
    let lip: f64 = reactions.iter().filter(|r| r.0 == "band").map(|r| r.1[0]).sum();
    assert!((lip - force).abs() < 1e-9 * force, "lip reactions {lip} vs {force}");
}

/// Block [0, 1] × [0, 0.5], quad4 4 × 2, plane strain, E = 100, ν = 0.3. Conditions:
/// bottom edge u_y = 0, bottom-left corner u_x = 0, and the relation
/// u_x(right) − u_x(left) = δ between the paired nodes of the left and right edges
/// (LIAISON_GROUP), δ = 0.02; no load. Reference: uniform uniaxial plane strain
/// u_x = δ x, u_y = −ν/(1−ν) δ y, and zero reactions; each tied pair differs by δ.
/// Tolerance 1e-10 relative to δ.
#[test]
fn relation_between_two_edges_stretches_the_block_uniformly() {
    let delta = 0.02;
    let text = format!(
        r#"[mesh]
generator = "rectangle"
cell = "quad4"
upper = [1.0, 0.5]
divisions = [4, 2]

[[materials]]
E = {E}
nu = {NU}

[[sets]]
name = "corner"
on = "x^2 + y^2"

[[dirichlet]]
group = "bottom"
components = ["y"]

[[dirichlet]]
group = "corner"
components = ["x"]

[[relations]]
groups = ["right", "left"]
components = ["x", "x"]
coefficients = [1.0, -1.0]
value = {delta}
"#
    );
    let (x, u, reactions) = solve(&text);
    let c = NU / (1.0 - NU);
    for (n, p) in x.iter().enumerate() {
        let (ex, ey) = (delta * p[0], -c * delta * p[1]);
        assert!((u[n][0] - ex).abs() < 1e-10 * delta, "node {n}: u_x {} vs {ex}", u[n][0]);
        assert!((u[n][1] - ey).abs() < 1e-10 * delta, "node {n}: u_y {} vs {ey}", u[n][1]);
    }
    for (g, r) in reactions {
        assert!(r[0].abs() < 1e-10 * E * delta && r[1].abs() < 1e-10 * E * delta, "{g}: {r:?}");
    }
}

/// Two nodes tied with coefficients 2 and 1 (LIAISON_DDL): 2 u_y(a) + u_y(b) = 0 under a
/// cantilever load (left clamped, downward traction on the right edge). Reference: the
/// relation holds to 1e-12 of the tip deflection, and the tied model differs from the
/// free one (the relation is active).
#[test]
fn linear_relation_ties_two_node_displacements_exactly() {
    let base = r#"[mesh]
generator = "rectangle"
cell = "quad4"
upper = [4.0, 1.0]
divisions = [8, 2]

[[materials]]
E = 100.0
nu = 0.3

[[sets]]
name = "a"
on = "(x - 2)^2 + (y - 1)^2"

[[sets]]
name = "b"
on = "(x - 4)^2 + y^2"

[[dirichlet]]
group = "left"
components = ["x", "y"]

[[traction]]
group = "right"
value = [0.0, -1.0]
"#;
    let tied = format!(
        "{base}\n[[relations]]\ngroups = [\"a\", \"b\"]\ncomponents = [\"y\", \"y\"]\ncoefficients = [2.0, 1.0]\n"
    );
    let (x, free, _) = solve(base);
    let (_, u, _) = solve(&tied);
    let node = |p: [f64; 2]| x.iter().position(|q| (q[0] - p[0]).abs() < 1e-9 && (q[1] - p[1]).abs() < 1e-9).unwrap();
    let (a, b) = (node([2.0, 1.0]), node([4.0, 0.0]));
    let tip = free[b][1].abs();
    assert!((2.0 * u[a][1] + u[b][1]).abs() < 1e-12 * tip, "{} {}", u[a][1], u[b][1]);
    assert!((2.0 * free[a][1] + free[b][1]).abs() > 0.1 * tip);
}
