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

/// The block of [`relation_between_two_edges_stretches_the_block_uniformly`] with one
/// relation u_x(right) − u_x(left) = v per value v.
fn stretched_block(values: &[f64]) -> String {
    let relations: String = values
        .iter()
        .map(|v| {
            format!(
                "\n[[relations]]\ngroups = [\"right\", \"left\"]\ncomponents = [\"x\", \"x\"]\ncoefficients = [1.0, -1.0]\nvalue = {v}\n"
            )
        })
        .collect();
    format!(
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
{relations}"#
    )
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
    let text = stretched_block(&[delta]);
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

/// A block pressed against a wall held by a lip condition, then pulled off (the
/// quasi-static reproduction of `tests/dynamics_bar_rigid_wall.rs`).
///
/// Geometry: strip [0, 1.05] × [0, 0.05], quad4 21 × 1 (h = 0.05), cut by a line interface
/// at x = L = 1.025 (mid-cell): the block is [0, L], the wall the `+` side of the last
/// column, held at zero in x and y by a lip condition (`[[dirichlet]]` with `crack`,
/// `lip = "+"` on the nodes x ≥ 1), frictionless contact (augmented Lagrangian, lips touching
/// at t = 0). Material: E = 100, ν = 0, plane stress. Load: the left face held at
/// u = (U(1 − 2t), 0), U = 0.003, over 3 steps: t = 1/3 presses by U/3, t = 2/3 and 1 pull
/// off by U/3 and U.
/// Reference (1D, exact in the discrete space: the fields are linear in x): pressed, the
/// block is in uniform compression, u_x = (U/3)(1 − x/L), contact pressure −λ = E U/(3L) at
/// every point, reactions ±E U h/(3L) (left +x, wall −x). Pulled off, every point is open,
/// λ = 0, the block translates rigidly, u_x = U(1 − 2t), u_y = 0, the lips open by
/// −U(1 − 2t), the wall does not move and both reactions vanish.
/// With the wall held instead by plain Dirichlet multipliers on the `right` face
/// (`[solver] dirichlet = "multiplier"`), which carry nothing the same way once the lips
/// open, the wall's `+` part of the last cell is elastic: pressed, the whole strip is one
/// bar of length 1.05 in uniform compression (L replaced by 1.05 above).
/// Tolerances: 1e-9 relative (displacements to U, pressures and reactions to the pressed
/// step's); the open λ to 1e-12 of the pressed pressure.
/// Before the fix the second step stopped ("the Newton loop did not converge in 30
/// iterations"): the relative Newton correction measured the relation multipliers of the
/// unloaded wall, of round-off size, against themselves. Run with each linear path and both
/// contact algorithms, and with the plain Dirichlet multipliers.
#[test]
fn block_pulled_off_a_lip_held_wall_opens_with_zero_pressure_and_translates_freely() {
    use fissure::contact::state::point_values;
    let (u0, len, h, e) = (0.003, 1.025, 0.05, E);
    let lip_wall = r#"[[sets]]
name = "wall"
inside = "0.9875 - x"

[[dirichlet]]
group = "wall"
components = ["x", "y"]
crack = "interface"
lip = "+"
"#;
    let plain_wall = "[[dirichlet]]\ngroup = \"right\"\ncomponents = [\"x\", \"y\"]\n";
    // (name, wall conditions, extra tables, length in compression when pressed)
    let variants: [(&str, &str, &str, f64); 6] = [
        ("lip wall, condensed LDLᵀ", lip_wall, "", len),
        ("lip wall, condense = false", lip_wall, "[solver]\ncondense = false\n", len),
        ("lip wall, LU", lip_wall, "[solver]\nlinear = \"lu\"\n", len),
        ("lip wall, semi-smooth", lip_wall, "[contact_solver]\nalgorithm = \"semi_smooth\"\n", len),
        ("lip wall, Dirichlet multipliers", lip_wall, "[solver]\ndirichlet = \"multiplier\"\n", len),
        ("plain wall, Dirichlet multipliers", plain_wall, "[solver]\ndirichlet = \"multiplier\"\n", 1.05),
    ];
    for (name, wall, extra, bar) in variants {
        let text = format!(
            r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [1.05, {h}]
divisions = [21, 1]

[[materials]]
E = {e}
nu = 0.0

[[cracks]]
name = "interface"
shape = "line"
point = [{len}, 0.0]
normal = [1.0, 0.0]

[cracks.contact]
friction = 0.0

{wall}
[[dirichlet]]
group = "left"
components = ["x", "y"]
values = ["{u0} * (1 - 2 * t)", "0"]

[steps]
count = 3

{extra}"#
        );
        let case = Case::parse(&text, Path::new("lip_wall.toml")).unwrap();
        let mesh = resolve::build_mesh(&case).unwrap();
        let model = resolve::build_model(&case, &mesh).unwrap();
        let contact = resolve::build_contact(&case, &model).unwrap().expect("contact");
        let opts = SolveOptions {
            linear: case.solver.linear,
            condense: case.solver.condense,
            ordering: case.solver.ordering,
            backend: case.solver.backend.clone(),
            ..Default::default()
        };
        let (report, sols, states) =
            fissure::run::solve_model_with(&model, Some(&contact), &opts).unwrap_or_else(|err| panic!("{name}: {err}"));
        assert_eq!(sols.len(), 3, "{name}");
        let p1 = e * u0 / (3.0 * bar);
        for (k, (u, state)) in sols.iter().zip(&states).enumerate() {
            let t = (k + 1) as f64 / 3.0;
            let ul = u0 * (1.0 - 2.0 * t);
            let step = &report.steps[k];
            let c = step.contact.as_ref().expect("contact report");
            let vals = point_values(&model, &contact.points, None, state, u);
            let force = |g: &str| {
                let i = model.dirichlet_groups.iter().position(|n| n == g).unwrap();
                step.reactions[i]
            };
            let wall_group = if wall == lip_wall { "wall" } else { "right" };
            let (left, held) = (force("left"), force(wall_group));
            eprintln!(
                "{name}, step {}: active {}, λ in [{:.6e}, {:.6e}], Newton {}, reactions left {:.3e} wall {:.3e}",
                k + 1,
                c.active,
                c.lambda_min,
                c.lambda_max,
                c.newton,
                left[0],
                held[0]
            );
            let (p, active) = if ul > 0.0 { (p1, c.points) } else { (0.0, 0) };
            assert_eq!(c.active, active, "{name}, step {}: points in contact", k + 1);
            for v in &vals {
                if p > 0.0 {
                    assert!((v.lambda + p).abs() < 1e-9 * p1, "{name}, step {}: λ {} vs {}", k + 1, v.lambda, -p);
                } else {
                    assert!(v.lambda.abs() < 1e-12 * p1, "{name}, step {}: open λ {}", k + 1, v.lambda);
                    let opening = v.jump[0];
                    assert!((opening + ul).abs() < 1e-9 * u0, "{name}, step {}: opening {opening} vs {}", k + 1, -ul);
                }
            }
            for (n, x) in mesh.nodes.iter().enumerate() {
                let ex = if p > 0.0 {
                    ul * (1.0 - x[0] / bar).max(0.0)
                } else if x[0] > len {
                    0.0
                } else {
                    ul
                };
                // x = 1.05: the wall's own node (standard dofs: the + field) stays at zero.
                assert!((u[2 * n] - ex).abs() < 1e-9 * u0, "{name}, step {}: node {n} u_x {} vs {ex}", k + 1, u[2 * n]);
                assert!(u[2 * n + 1].abs() < 1e-9 * u0, "{name}, step {}: node {n} u_y {}", k + 1, u[2 * n + 1]);
            }
            let r = p * h;
            assert!((left[0] - r).abs() < 1e-9 * p1 * h, "{name}, step {}: left reaction {left:?} vs {r}", k + 1);
            assert!((held[0] + r).abs() < 1e-9 * p1 * h, "{name}, step {}: wall reaction {held:?} vs {}", k + 1, -r);
        }
    }
}

/// The block of `relation_between_two_edges_stretches_the_block_uniformly` with its
/// relation given twice (found by a hostile-user audit, 2026-11-28: the docs said a
/// repeated relation makes the solve fail; it runs). Reference: the same uniform field
/// u_x = δ x, u_y = −ν/(1−ν) δ y to 1e-10 of δ (the redundant multiplier's pivot is
/// regularised); the same relation repeated with another value (δ and 1.5 δ: no solution)
/// fails the solve with an error naming conflicting constraints, never a result.
#[test]
fn repeated_relation_gives_the_answer_of_one_and_a_conflicting_one_fails() {
    let delta = 0.02;
    let case = |second: f64| stretched_block(&[delta, second]);
    let (x, u, _) = solve(&case(delta));
    let c = NU / (1.0 - NU);
    for (n, p) in x.iter().enumerate() {
        let (ex, ey) = (delta * p[0], -c * delta * p[1]);
        assert!((u[n][0] - ex).abs() < 1e-10 * delta, "node {n}: u_x {} vs {ex}", u[n][0]);
        assert!((u[n][1] - ey).abs() < 1e-10 * delta, "node {n}: u_y {} vs {ey}", u[n][1]);
    }
    let text = case(1.5 * delta);
    let parsed = Case::parse(&text, Path::new("conflict.toml")).unwrap();
    let mesh = resolve::build_mesh(&parsed).unwrap();
    let model = resolve::build_model(&parsed, &mesh).unwrap();
    let opts = SolveOptions { linear: parsed.solver.linear, ..Default::default() };
    let e = solve_model(&model, &opts).expect_err("conflicting relations must fail the solve").to_string();
    assert!(e.contains("conflicting constraints"), "{e}");
}
