//! Thick cylinder under internal pressure, through the case file examples/thick_cylinder.toml.

use fissure::case::{resolve, Case};
use fissure::run::solve_model;
use fissure::solve::statics::SolveOptions;
use std::path::Path;

/// Lamé thick cylinder (Timoshenko & Goodier, Theory of Elasticity, §28).
/// Geometry: quarter annulus, inner radius a = 1, outer b = 2, Gmsh quad4 mesh
/// meshes/thick_cylinder.msh (30 cells through the thickness). Material E = 1000, ν = 0.3,
/// plane strain. Load: internal pressure p = 1; symmetry u_y = 0 on y = 0, u_x = 0 on x = 0.
/// Reference: u_r(r) = (1+ν) p a² / (E (b² − a²)) · ((1 − 2ν) r + b²/r).
/// Tolerance: 0.5% at every node on the inner and outer arcs (the floor); the
/// tangential displacement is zero to 1e-3 of u_r; the support reaction on y = 0 balances the
/// pressure resultant p·a to 1e-9.
#[test]
fn lame_thick_cylinder_radial_displacement_within_half_percent() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/thick_cylinder.toml");
    let case = Case::from_file(&path).expect("example case reads");
    let mesh = resolve::build_mesh(&case).expect("Gmsh mesh reads");
    let model = resolve::build_model(&case, &mesh).expect("model builds");
    let (report, sols) = solve_model(&model, &SolveOptions::default()).expect("solves");
    // Equilibrium of the quarter ring: the pressure on the inner arc has the resultant p·a
    // along +y (and +x); the supports on y = 0 (and x = 0) balance it. Tolerance 1e-9.
    let g = model.dirichlet_groups.iter().position(|n| n == "xsym").unwrap();
    let ry = report.steps[0].reactions[g][1];
    assert!((ry + 1.0).abs() < 1e-9, "reaction on y = 0: {ry} (expected −p·a = −1)");
    let u = &sols[0];
    let (a, b, p, e, nu) = (1.0f64, 2.0f64, 1.0, 1000.0, 0.3);
    let exact = |r: f64| (1.0 + nu) * p * a * a / (e * (b * b - a * a)) * ((1.0 - 2.0 * nu) * r + b * b / r);
    let mut worst = 0.0f64;
    for group in ["inner", "outer"] {
        for n in mesh.group_nodes(group).unwrap() {
            let [x, y, _] = mesh.nodes[n];
            let r = (x * x + y * y).sqrt();
            let (ux, uy) = (u[2 * n], u[2 * n + 1]);
            let ur = (ux * x + uy * y) / r;
            let ut = (-ux * y + uy * x) / r;
            let rel = (ur - exact(r)).abs() / exact(r);
            worst = worst.max(rel);
            assert!(ut.abs() < 1e-3 * exact(r), "tangential displacement {ut:e} at r = {r}");
        }
    }
    eprintln!("Lamé: worst relative error of u_r on the arcs {worst:.3e}");
    assert!(worst < 5e-3, "u_r off by {:.3}%", 100.0 * worst);
}
