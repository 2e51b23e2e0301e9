//! Timing of the sparse direct solvers (`fissure::solve::linear`) on a 2D Q1
//! plane-strain elasticity matrix of about 5e5 unknowns.
//!
//! ```text
//! cargo run --release --example linear_solver_timing [-- ELEMENTS_PER_SIDE [lu]]
//! ```
//!
//! Cases: Cholesky and LDLᵀ on the stiffness matrix with the left edge clamped by
//! elimination (SPD), and LDLᵀ on the saddle-point system where the left edge is clamped
//! by Lagrange multipliers (K singular: the constraints remove its rigid-body modes).
//! With `lu`, LU on both too. Each case: analyse, two numeric factorisations (the
//! second reuses the symbolic phase), two solves.

use fissure::assembly::CscPattern;
use fissure::solve::linear::{LinearMethod, LinearSolver};
use std::time::Instant;

/// 8×8 stiffness of a unit-square Q1 element, plane strain, E = 1, ν = 0.3, 2×2 Gauss;
/// dofs ordered (node, component) with nodes (0,0), (1,0), (1,1), (0,1).
fn element_stiffness() -> [[f64; 8]; 8] {
    let (e, nu) = (1.0, 0.3);
    let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let d = [[f * (1.0 - nu), f * nu, 0.0], [f * nu, f * (1.0 - nu), 0.0], [0.0, 0.0, f * (1.0 - 2.0 * nu) / 2.0]];
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let g = 1.0 / 3f64.sqrt();
    let mut k = [[0.0; 8]; 8];
    for &(xi, eta) in &[(-g, -g), (g, -g), (g, g), (-g, g)] {
        // Shape function derivatives in x, y (the element maps [-1,1]² to [0,1]²: ×2).
        let mut b = [[0.0; 8]; 3];
        for (a, &(xa, ya)) in corners.iter().enumerate() {
            let dx = 0.25 * xa * (1.0 + ya * eta) * 2.0;
            let dy = 0.25 * ya * (1.0 + xa * xi) * 2.0;
            b[0][2 * a] = dx;
            b[1][2 * a + 1] = dy;
            b[2][2 * a] = dy;
            b[2][2 * a + 1] = dx;
        }
        let weight = 0.25; // Jacobian determinant (1/4) × Gauss weight (1)
        for i in 0..8 {
            for j in 0..8 {
                let mut s = 0.0;
                for p in 0..3 {
                    for q in 0..3 {
                        s += b[p][i] * d[p][q] * b[q][j];
                    }
                }
                k[i][j] += weight * s;
            }
        }
    }
    k
}

struct System {
    pattern: CscPattern,
    values: Vec<f64>,
    rhs: Vec<f64>,
    n_primal: usize,
}

/// The plate of `ne × ne` elements, clamped on the left edge (x = 0), loaded by a
/// downward force on the right edge. `multipliers`: clamp with Lagrange multipliers
/// (saddle point, multipliers last) instead of eliminating the clamped dofs.
fn build(ne: usize, multipliers: bool) -> System {
    let nn = ne + 1;
    let node = |x: usize, y: usize| y * nn + x;
    let clamped = |dof: usize| (dof / 2) % nn == 0;
    let n_dof = 2 * nn * nn;
    // Equation numbers.
    let mut eq = vec![usize::MAX; n_dof];
    let mut n_primal = 0;
    for (d, e) in eq.iter_mut().enumerate() {
        if multipliers || !clamped(d) {
            *e = n_primal;
            n_primal += 1;
        }
    }
    let clamped_dofs: Vec<usize> = (0..n_dof).filter(|&d| clamped(d)).collect();
    let n = if multipliers { n_primal + clamped_dofs.len() } else { n_primal };
    let ke = element_stiffness();
    let element_dofs = |ex: usize, ey: usize| {
        let nodes = [node(ex, ey), node(ex + 1, ey), node(ex + 1, ey + 1), node(ex, ey + 1)];
        let mut d = [0usize; 8];
        for (a, &m) in nodes.iter().enumerate() {
            d[2 * a] = 2 * m;
            d[2 * a + 1] = 2 * m + 1;
        }
        d
    };
    let mut entries = Vec::with_capacity(64 * ne * ne + 2 * clamped_dofs.len());
    for ey in 0..ne {
        for ex in 0..ne {
            let d = element_dofs(ex, ey);
            for &i in &d {
                for &j in &d {
                    if eq[i] != usize::MAX && eq[j] != usize::MAX {
                        entries.push((eq[i], eq[j]));
                    }
                }
            }
        }
    }
    for (l, &d) in clamped_dofs.iter().enumerate().filter(|_| multipliers) {
        entries.push((eq[d], n_primal + l));
        entries.push((n_primal + l, eq[d]));
    }
    let pattern = CscPattern::from_entries(n, &entries);
    drop(entries);
    let mut values = vec![0.0; pattern.nnz()];
    for ey in 0..ne {
        for ex in 0..ne {
            let d = element_dofs(ex, ey);
            for (a, &i) in d.iter().enumerate() {
                for (b, &j) in d.iter().enumerate() {
                    if eq[i] != usize::MAX && eq[j] != usize::MAX {
                        values[pattern.position(eq[i], eq[j]).unwrap()] += ke[a][b];
                    }
                }
            }
        }
    }
    for (l, &d) in clamped_dofs.iter().enumerate().filter(|_| multipliers) {
        values[pattern.position(eq[d], n_primal + l).unwrap()] = 1.0;
        values[pattern.position(n_primal + l, eq[d]).unwrap()] = 1.0;
    }
    let mut rhs = vec![0.0; n];
    for y in 0..nn {
        rhs[eq[2 * node(ne, y) + 1]] = -1.0 / nn as f64;
    }
    System { pattern, values, rhs, n_primal: if multipliers { n_primal } else { n } }
}

fn run(name: &str, method: LinearMethod, s: &System) {
    let clock = Instant::now();
    let mut solver = match LinearSolver::analyse(method, &s.pattern, s.n_primal) {
        Ok(solver) => solver,
        Err(e) => return println!("{name:<34} analyse failed: {e}"),
    };
    let analyse = clock.elapsed().as_secs_f64();
    let mut numeric = vec![];
    let mut solves = vec![];
    let mut residual = (f64::NAN, 0);
    for round in 0..2 {
        let values: Vec<f64> = s.values.iter().map(|v| v * (1.0 + round as f64)).collect();
        if let Err(e) = solver.factorize(&values) {
            return println!("{name:<34} factorize failed: {e}");
        }
        numeric.push(solver.stats().numeric_s);
        let mut x = s.rhs.clone();
        if let Err(e) = solver.solve_in_place(&mut x) {
            return println!("{name:<34} solve failed: {e}");
        }
        solves.push(solver.stats().solve_s);
        residual = solver.last_residual();
    }
    let st = solver.stats();
    println!(
        "{name:<34} n {:>7}  nnz(A) {:>8}  nnz(L) {:>10}  symbolic {:>6.2} s  numeric {:>6.2} / {:>6.2} s  \
         solve {:>5.2} / {:>5.2} s  residual {:.1e} ({} refinements)  regularised {}",
        s.pattern.n,
        s.pattern.nnz(),
        st.nnz_factor.map_or("-".to_string(), |v| v.to_string()),
        analyse,
        numeric[0],
        numeric[1],
        solves[0],
        solves[1],
        residual.0,
        residual.1,
        solver.regularised_pivots(),
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ne: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(499);
    let lu = args.iter().any(|a| a == "lu");
    println!("2D Q1 plane strain, {ne}×{ne} elements, {} threads", rayon::current_num_threads());
    let clock = Instant::now();
    let eliminated = build(ne, false);
    let saddle = build(ne, true);
    println!("matrices built in {:.1} s", clock.elapsed().as_secs_f64());
    run("cholesky, clamp eliminated", LinearMethod::Cholesky, &eliminated);
    run("ldlt, clamp eliminated", LinearMethod::Ldlt, &eliminated);
    run("ldlt, clamp by multipliers", LinearMethod::Ldlt, &saddle);
    if lu {
        run("lu, clamp eliminated", LinearMethod::Lu, &eliminated);
        run("lu, clamp by multipliers", LinearMethod::Lu, &saddle);
    }
}
