//! Verification of the linear elastic core: patch tests and manufactured solutions.

mod common;

use common::model::*;
use fissure::element::CellType;
use fissure::formula::Scalar;
use fissure::mesh::{generate, Mesh};
use fissure::physics::material::{Analysis, Isotropic};
use fissure::physics::model::DirichletMethod;
use fissure::post::norms::error_norms;
use fissure::run::solve_model;
use fissure::solve::linear::LinearMethod;
use fissure::solve::statics::SolveOptions;
use std::f64::consts::PI;

fn distorted(kind: CellType, n: usize) -> Mesh {
    let mut m = if kind.dim() == 2 {
        generate::rectangle(kind, [0.0, 0.0], [2.0, 1.0], [2 * n, n]).unwrap()
    } else {
        generate::box_mesh(kind, [0.0; 3], [2.0, 1.0, 1.0], [2 * n, n, n]).unwrap()
    };
    generate::perturb_interior(&mut m, 1.0 / n as f64, 0.25, 7);
    m.validate().expect("distorted mesh stays valid");
    m
}

/// Patch test (Irons; MacNeal–Harder 1985 for the distorted-mesh form).
/// Geometry: [0,2]×[0,1] (2D) or [0,2]×[0,1]×[0,1] (3D), interior nodes moved randomly by
/// up to 0.25 h. Material E = 1000, ν = 0.3 (plane strain in 2D). Loads: the linear field
/// u = A x + c prescribed on every boundary node. Reference: u is exact for every
/// conforming linear element, so interior nodal values and the stresses of every cell
/// must match it to round-off. Tolerance 1e-10 (relative to max |u| and max |σ|),
/// for both ways of imposing the conditions (elimination, multipliers with LDLᵀ).
#[test]
fn patch_test_constant_strain_reproduced_on_distorted_meshes_of_each_element_type() {
    let a = [[1.0e-3, 2.0e-4, -3.0e-4], [-5.0e-4, 7.0e-4, 1.0e-4], [2.0e-4, -1.0e-4, 4.0e-4]];
    let c = [0.3, -0.2, 0.1];
    for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
        let mesh = distorted(kind, 4);
        let dim = mesh.dim;
        let analysis = if dim == 2 { Analysis::PlaneStrain } else { Analysis::ThreeD };
        let material = Isotropic { young: 1000.0, poisson: 0.3 };
        let exact = |p: [f64; 3]| {
            let mut u = [0.0; 3];
            for i in 0..dim {
                u[i] = c[i] + (0..dim).map(|j| a[i][j] * p[j]).sum::<f64>();
            }
            u
        };
        for method in [DirichletMethod::Eliminate, DirichletMethod::Multiplier] {
            let mut model = bare_model(&mesh, analysis, material);
            model.dirichlet_method = method;
            let values: Vec<Scalar> = (0..3)
                .map(|i| {
                    formula("c + a0*x + a1*y + a2*z", &[("c", c[i]), ("a0", a[i][0]), ("a1", a[i][1]), ("a2", a[i][2])])
                })
                .collect();
            fix_nodes(&mut model, "boundary", &boundary_nodes(&mesh), &values);
            let (_, sols) = solve_model(
                &model,
                &SolveOptions { linear: LinearMethod::Cholesky, residual_tolerance: 1e-10, ..Default::default() },
            )
            .expect("patch test solves");
            let u = &sols[0];
            let mut err = 0.0f64;
            for (n, p) in mesh.nodes.iter().enumerate() {
                let ue = exact(*p);
                for i in 0..dim {
                    err = err.max((u[n * dim + i] - ue[i]).abs());
                }
            }
            assert!(err < 1e-10 * 1.0, "{kind:?} {method:?}: nodal error {err:e}");
            let fields = fissure::post::cell_fields(
                &mesh,
                analysis,
                &[material],
                &model.cell_material,
                &u[..dim * mesh.n_nodes()],
            );
            let s0 = fields.stress[0];
            let smax = s0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for s in &fields.stress {
                for k in 0..6 {
                    assert!((s[k] - s0[k]).abs() < 1e-10 * smax, "{kind:?}: stress not constant");
                }
            }
        }
    }
}

/// Manufactured smooth solution (method of manufactured solutions, Roache 2002).
/// Geometry: unit square / unit cube, structured meshes n = 8, 16, 32 (2D) and 4, 8, 16 (3D)
/// per side. Material E = 1, ν = 0.3 (Lamé λ, μ), plane strain in 2D.
/// Exact field: 2D u_x = u_y = sin πx sin πy; 3D u_i = sin πx sin πy sin πz (zero on the
/// boundary), body force b = −div σ(u) written as formula strings.
/// Reference: a-priori estimates for linear elements (Ciarlet 1978): L2 error O(h²),
/// energy error O(h). Tolerance: observed rates over the last refinement 2 ± 0.15 and 1 ± 0.15.
#[test]
fn manufactured_solution_converges_at_optimal_rates_for_each_element_type() {
    let material = Isotropic { young: 1.0, poisson: 0.3 };
    let (lam, mu) = (material.lambda_3d(), material.mu());
    for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
        let dim = kind.dim();
        let sizes: &[usize] = if dim == 2 { &[8, 16, 32] } else { &[4, 8, 16] };
        let mut hs = vec![];
        let (mut l2s, mut ens) = (vec![], vec![]);
        for &n in sizes {
            let mesh = if dim == 2 {
                generate::rectangle(kind, [0.0, 0.0], [1.0, 1.0], [n, n]).unwrap()
            } else {
                generate::box_mesh(kind, [0.0; 3], [1.0; 3], [n, n, n]).unwrap()
            };
            let analysis = if dim == 2 { Analysis::PlaneStrain } else { Analysis::ThreeD };
            let mut model = bare_model(&mesh, analysis, material);
            let zero = [Scalar::Const(0.0), Scalar::Const(0.0), Scalar::Const(0.0)];
            fix_nodes(&mut model, "boundary", &boundary_nodes(&mesh), &zero);
            let p = [("lam", lam), ("mu", mu), ("pi", PI)];
            let b = if dim == 2 {
                let f = "pi^2*((lam+3*mu)*sin(pi*x)*sin(pi*y) - (lam+mu)*cos(pi*x)*cos(pi*y))";
                [formula(f, &p), formula(f, &p), Scalar::Const(0.0)]
            } else {
                let g = "sin(pi*x)*sin(pi*y)*sin(pi*z)";
                let bx = format!(
                    "pi^2*((lam+4*mu)*{g} - (lam+mu)*(cos(pi*x)*cos(pi*y)*sin(pi*z) + cos(pi*x)*sin(pi*y)*cos(pi*z)))"
                );
                let by = format!(
                    "pi^2*((lam+4*mu)*{g} - (lam+mu)*(cos(pi*x)*cos(pi*y)*sin(pi*z) + sin(pi*x)*cos(pi*y)*cos(pi*z)))"
                );
                let bz = format!(
                    "pi^2*((lam+4*mu)*{g} - (lam+mu)*(cos(pi*x)*sin(pi*y)*cos(pi*z) + sin(pi*x)*cos(pi*y)*cos(pi*z)))"
                );
                [formula(&bx, &p), formula(&by, &p), formula(&bz, &p)]
            };
            body_force(&mut model, b);
            let (_, sols) = solve_model(&model, &SolveOptions::default()).expect("manufactured solution solves");
            let exact = |x: [f64; 3]| {
                let s = (PI * x[0]).sin() * (PI * x[1]).sin() * if dim == 3 { (PI * x[2]).sin() } else { 1.0 };
                let mut u = [0.0; 3];
                u[..dim].iter_mut().for_each(|v| *v = s);
                u
            };
            let grad = |x: [f64; 3]| {
                let (s, c) = (
                    [(PI * x[0]).sin(), (PI * x[1]).sin(), (PI * x[2]).sin()],
                    [(PI * x[0]).cos(), (PI * x[1]).cos(), (PI * x[2]).cos()],
                );
                let mut d = [0.0; 3];
                if dim == 2 {
                    d[0] = PI * c[0] * s[1];
                    d[1] = PI * s[0] * c[1];
                } else {
                    d[0] = PI * c[0] * s[1] * s[2];
                    d[1] = PI * s[0] * c[1] * s[2];
                    d[2] = PI * s[0] * s[1] * c[2];
                }
                let mut g = [[0.0; 3]; 3];
                for row in g.iter_mut().take(dim) {
                    row[..dim].copy_from_slice(&d[..dim]);
                }
                g
            };
            let e = error_norms(&mesh, analysis, &material, &sols[0], &exact, &grad, 4);
            hs.push(1.0 / n as f64);
            l2s.push(e.l2);
            ens.push(e.energy);
        }
        let (rl, re) = (rates(&hs, &l2s), rates(&hs, &ens));
        let (rl, re) = (*rl.last().unwrap(), *re.last().unwrap());
        eprintln!("{kind:?}: L2 errors {l2s:?} rate {rl:.3}; energy errors {ens:?} rate {re:.3}");
        assert!((rl - 2.0).abs() <= 0.15, "{kind:?}: L2 rate {rl}");
        assert!((re - 1.0).abs() <= 0.15, "{kind:?}: energy rate {re}");
    }
}
