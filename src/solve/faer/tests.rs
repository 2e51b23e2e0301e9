//! Unit tests of the faer solver: every method on SPD, saddle-point, quasi-definite,
//! singular and badly scaled systems, the orderings it uses, the split and condensed
//! factors, bad input and concurrent solves.

use super::solver::{Factor, FaerSolver as LinearSolver};
use super::split::SPLIT_MIN_UNKNOWNS;
use crate::assembly::CscPattern;
use crate::solve::backend::{EquationPoints, LinearError, LinearMethod};
use crate::solve::ordering::geometric::nested_dissection;
use crate::solve::ordering::{multipliers_after_primal_ordering, Order};
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;

/// (pattern, values) from triplets (duplicates summed).
fn matrix(n: usize, triplets: &[(usize, usize, f64)]) -> (CscPattern, Vec<f64>) {
    let entries: Vec<(usize, usize)> = triplets.iter().map(|&(i, j, _)| (i, j)).collect();
    let pattern = CscPattern::from_entries(n, &entries);
    let mut values = vec![0.0; pattern.nnz()];
    for &(i, j, v) in triplets {
        values[pattern.position(i, j).unwrap()] += v;
    }
    (pattern, values)
}

/// 5-point Laplacian on an nx × ny grid: with `dirichlet` the diagonal is 4
/// (homogeneous Dirichlet outside, SPD), otherwise the number of neighbours (pure
/// Neumann, singular with the constants as kernel).
fn laplacian_triplets(nx: usize, ny: usize, dirichlet: bool) -> Vec<(usize, usize, f64)> {
    let id = |x: usize, y: usize| y * nx + x;
    let mut t = vec![];
    for y in 0..ny {
        for x in 0..nx {
            let i = id(x, y);
            let mut neighbours = vec![];
            if x > 0 {
                neighbours.push(id(x - 1, y));
            }
            if x + 1 < nx {
                neighbours.push(id(x + 1, y));
            }
            if y > 0 {
                neighbours.push(id(x, y - 1));
            }
            if y + 1 < ny {
                neighbours.push(id(x, y + 1));
            }
            let d = if dirichlet { 4.0 } else { neighbours.len() as f64 };
            t.push((i, i, d));
            for j in neighbours {
                t.push((i, j, -1.0));
            }
        }
    }
    t
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n).map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0).collect()
}

fn rel_residual(p: &CscPattern, v: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; p.n];
    p.mul_vec(v, x, &mut ax);
    let r: f64 = ax.iter().zip(b).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    r / b.iter().map(|b| b * b).sum::<f64>().sqrt()
}

fn solve(s: &LinearSolver, b: &[f64]) -> Result<Vec<f64>, LinearError> {
    let mut x = b.to_vec();
    s.solve_in_place(&mut x).map(|_| x)
}

/// Newton with deferred interior corrections across a change of statuses: a full solve of
/// system `a`, then three corrections of system `b` whose residuals use the stale interior;
/// once the deferred interior response is applied, the relative residual of system `b`.
fn deferred_newton_residual(cond: &mut LinearSolver, p: &CscPattern, full_a: &[f64], full_b: &[f64], b: &[f64]) -> f64 {
    let x = deferred_newton(cond, p, full_a, full_b, b);
    rel_residual(p, full_b, &x, b)
}

/// The solution of [`deferred_newton_residual`].
fn deferred_newton(cond: &mut LinearSolver, p: &CscPattern, full_a: &[f64], full_b: &[f64], b: &[f64]) -> Vec<f64> {
    cond.factorize(full_a).unwrap();
    let mut x = solve(cond, b).unwrap();
    cond.factorize(full_b).unwrap();
    for _ in 0..3 {
        let mut ax = vec![0.0; p.n];
        p.mul_vec(full_b, &x, &mut ax);
        let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        cond.solve_in_place_deferred(&mut r).unwrap();
        for (xi, d) in x.iter_mut().zip(&r) {
            *xi += d;
        }
    }
    cond.apply_deferred(&mut x);
    x
}

fn supernodal(s: &LinearSolver) -> bool {
    matches!(&s.factor, Factor::Cholesky { symbolic, .. } if matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)))
}

// SPD 2D Laplacians (50×50: faer's simplicial path; 200×200: supernodal) with each
// method: ‖Ax − b‖/‖b‖ < 1e-12; refactorising with values scaled by 3 reuses the
// symbolic phase (same solver, no new analyse) and gives x/3 to 1e-12 relative.
#[test]
fn spd_laplacian_all_methods_and_refactorisation() {
    for (nx, expect_supernodal) in [(50, false), (200, true)] {
        let (p, v) = matrix(nx * nx, &laplacian_triplets(nx, nx, true));
        let b = rhs(p.n);
        for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
            let mut s = LinearSolver::analyse(method, &p, p.n).unwrap();
            if method != LinearMethod::Lu {
                assert_eq!(supernodal(&s), expect_supernodal, "{method} {nx}");
                assert!(s.stats().nnz_factor.unwrap() >= (p.nnz() + p.n) / 2);
            }
            s.factorize(&v).unwrap();
            assert_eq!(s.regularised_pivots(), 0);
            let x = solve(&s, &b).unwrap();
            let r = rel_residual(&p, &v, &x, &b);
            assert!(r < 1e-12, "{method} {nx}: residual {r:e}");
            assert!((s.last_residual().0 - r).abs() < 1e-13);

            let v3: Vec<f64> = v.iter().map(|a| 3.0 * a).collect();
            s.factorize(&v3).unwrap();
            let x3 = solve(&s, &b).unwrap();
            assert!(rel_residual(&p, &v3, &x3, &b) < 1e-12);
            let xn = x.iter().map(|a| a * a).sum::<f64>().sqrt();
            let diff = x3.iter().zip(&x).map(|(a, b)| (3.0 * a - b).powi(2)).sum::<f64>().sqrt();
            assert!(diff < 1e-12 * xn, "{method}: scaled solution off by {:e}", diff / xn);
            let st = s.stats();
            assert!(st.symbolic_s >= 0.0 && st.numeric_s > 0.0 && st.solve_s > 0.0);
        }
    }
}

/// A saddle-point system: K the Laplacian (`dirichlet` false: the singular Neumann
/// one) on nx × nx, B fixing the unknowns `fixed` to values g and tying a − b;
/// returns (pattern, values, rhs, n_primal) with the multipliers last.
#[allow(clippy::type_complexity)]
fn saddle(
    nx: usize,
    dirichlet: bool,
    fixed: &[(usize, f64)],
    tie: Option<(usize, usize)>,
    c: f64,
    store_zero_diagonal: bool,
) -> (CscPattern, Vec<f64>, Vec<f64>, usize) {
    let np = nx * nx;
    let mut t = laplacian_triplets(nx, nx, dirichlet);
    let mut b = rhs(np);
    let mut row = np;
    for &(i, g) in fixed {
        t.push((row, i, 1.0));
        t.push((i, row, 1.0));
        b.push(g);
        row += 1;
    }
    if let Some((a, bb)) = tie {
        t.extend([(row, a, 1.0), (a, row, 1.0), (row, bb, -1.0), (bb, row, -1.0)]);
        b.push(0.0);
        row += 1;
    }
    for m in np..row {
        if c != 0.0 || store_zero_diagonal {
            t.push((m, m, -c));
        }
    }
    let (p, v) = matrix(row, &t);
    (p, v, b, np)
}

/// The primal solution of `saddle(...)` (with c = 0) by eliminating the constraints:
/// fixed unknowns moved to the right-hand side, b merged into a; solved by Cholesky.
fn eliminated(nx: usize, fixed: &[(usize, f64)], tie: Option<(usize, usize)>) -> Vec<f64> {
    let np = nx * nx;
    let t = laplacian_triplets(nx, nx, true);
    let f = rhs(np);
    let mut g = vec![None; np];
    for &(i, v) in fixed {
        g[i] = Some(v);
    }
    let mut target: Vec<usize> = (0..np).collect();
    if let Some((a, b)) = tie {
        target[b] = a;
    }
    let mut red = vec![usize::MAX; np];
    let mut nr = 0;
    for i in 0..np {
        if g[i].is_none() && target[i] == i {
            red[i] = nr;
            nr += 1;
        }
    }
    let r = |i: usize| red[target[i]];
    let mut rt = vec![];
    let mut rf = vec![0.0; nr];
    for i in 0..np {
        if g[i].is_none() {
            rf[r(i)] += f[i];
        }
    }
    for &(i, j, v) in &t {
        match (g[i], g[j]) {
            (None, None) => rt.push((r(i), r(j), v)),
            (None, Some(gj)) => rf[r(i)] -= v * gj,
            _ => {}
        }
    }
    let (p, v) = matrix(nr, &rt);
    let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, nr).unwrap();
    s.factorize(&v).unwrap();
    let z = solve(&s, &rf).unwrap();
    (0..np).map(|i| g[i].unwrap_or_else(|| z[r(i)])).collect()
}

// Saddle point [K Bᵀ; B 0] (K SPD Laplacian, B: Dirichlet-like rows fixing unknowns
// and a tie u_a − u_b = 0; multiplier diagonals absent or stored as zeros): Ldlt and
// Lu reach ‖Ax − b‖/‖b‖ < 1e-10 and the primal part matches the solution with the
// constraints eliminated to 1e-10 relative; Cholesky returns an error (no panic/NaN).
#[test]
fn saddle_point_ldlt_lu_match_elimination() {
    let nx = 30;
    let fixed = [(0, 0.5), (17, -1.0), (nx * nx - 1, 2.0), (nx * 15 + 15, 0.25)];
    let tie = Some((3 * nx + 4, 20 * nx + 25));
    let reference = eliminated(nx, &fixed, tie);
    let rn = reference.iter().map(|a| a * a).sum::<f64>().sqrt();
    for store_zero in [false, true] {
        let (p, v, b, np) = saddle(nx, true, &fixed, tie, 0.0, store_zero);
        for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
            let mut s = LinearSolver::analyse(method, &p, np).unwrap();
            s.factorize(&v).unwrap();
            let x = solve(&s, &b).unwrap();
            let r = rel_residual(&p, &v, &x, &b);
            assert!(r < 1e-10, "{method}: residual {r:e}");
            let d = x[..np].iter().zip(&reference).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
            assert!(d < 1e-10 * rn, "{method}: differs from elimination by {:e}", d / rn);
            if method == LinearMethod::Ldlt {
                assert_eq!(s.regularised_pivots(), 0, "K is SPD: no pivot needs regularising");
            }
        }
        let e = LinearSolver::analyse(LinearMethod::Cholesky, &p, np).unwrap_err();
        assert!(matches!(e, LinearError::CholeskyWithMultipliers { n_multipliers: 5 }), "{e}");
        // Also when the caller declares no multipliers: the zero diagonal is refused.
        let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
        let e = s.factorize(&v).unwrap_err();
        assert!(matches!(e, LinearError::NotPositiveDefinite { unknown, .. } if unknown >= np), "{e}");
        assert!(matches!(solve(&s, &b), Err(LinearError::NotFactorized)));
    }
}

// The LDLᵀ ordering puts every multiplier after all the primal unknowns it couples
// to (exact check on the permutation).
#[test]
fn ldlt_ordering_places_multipliers_after_their_unknowns() {
    let nx = 12;
    let fixed: Vec<(usize, f64)> = (0..nx).map(|i| (i * nx, 1.0)).collect();
    let (p, _, _, np) = saddle(nx, true, &fixed, Some((5, 100)), 0.0, false);
    let (fwd, inv) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, Order::default()).unwrap();
    assert_eq!(fwd.len(), p.n);
    for (new, &old) in fwd.iter().enumerate() {
        assert_eq!(inv[old], new);
    }
    for m in np..p.n {
        for &i in &p.row_idx[p.col_ptr[m]..p.col_ptr[m + 1]] {
            if i < np {
                assert!(inv[i] < inv[m], "multiplier {m} ordered before its unknown {i}");
            }
        }
    }
}

/// The grid points of `laplacian_triplets` (unknown y * nx + x at (x, y)).
fn grid_points(nx: usize, ny: usize) -> (Vec<u32>, Vec<[f64; 3]>) {
    let coords: Vec<[f64; 3]> = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
    ((0..(nx * ny) as u32).collect(), coords)
}

/// A quad4-like pattern: an nx × ny grid of nodes with two unknowns each (node-major),
/// every node coupled to its 8 neighbours; values diagonally dominant (SPD).
fn quad_grid(nx: usize, ny: usize) -> (CscPattern, Vec<f64>, Vec<u32>, Vec<[f64; 3]>) {
    quad_grid_shifted(nx, ny, 0.01)
}

/// The element blocks of [`quad_grid`] (two unknowns per node, every node coupled to its
/// 8 neighbours) for the cell rows `y` with `shift(y)` = Some(shift added to the
/// diagonal); rows with None are left out (a grid cut in two).
fn quad_triplets(nx: usize, ny: usize, shift: impl Fn(usize) -> Option<f64>) -> Vec<(usize, usize, f64)> {
    let node = |x: usize, y: usize| y * nx + x;
    let mut t = vec![];
    for y in 0..ny - 1 {
        let Some(shift) = shift(y) else { continue };
        for x in 0..nx - 1 {
            let q = [node(x, y), node(x + 1, y), node(x + 1, y + 1), node(x, y + 1)];
            for &a in &q {
                for &b in &q {
                    for c in 0..2 {
                        t.push((2 * a + c, 2 * b + c, if a == b { 3.0 + shift } else { -1.0 }));
                    }
                }
            }
        }
    }
    t
}

/// [`quad_triplets`] with the two components of every node of an element coupled by the
/// positive semidefinite block `0.5 [1 1; 1 1]` per element: the grid is then one connected
/// body (the uncoupled components of [`quad_triplets`] are two), with the same kernel on a
/// floating part (the constants with equal components are no longer free, the others are).
fn coupled_quad_triplets(nx: usize, ny: usize, shift: impl Fn(usize) -> Option<f64>) -> Vec<(usize, usize, f64)> {
    let node = |x: usize, y: usize| y * nx + x;
    let mut t = quad_triplets(nx, ny, &shift);
    for y in (0..ny - 1).filter(|&y| shift(y).is_some()) {
        for x in 0..nx - 1 {
            for a in [node(x, y), node(x + 1, y), node(x + 1, y + 1), node(x, y + 1)] {
                for (c, d) in [(0, 0), (1, 1), (0, 1), (1, 0)] {
                    t.push((2 * a + c, 2 * a + d, 0.5));
                }
            }
        }
    }
    t
}

/// [`quad_grid`] with `shift` added to the diagonal of every element block (0: the
/// graph Laplacian, singular with the constants per component as kernel).
fn quad_grid_shifted(nx: usize, ny: usize, shift: f64) -> (CscPattern, Vec<f64>, Vec<u32>, Vec<[f64; 3]>) {
    let t = quad_triplets(nx, ny, |_| Some(shift));
    let (p, v) = matrix(2 * nx * ny, &t);
    let point_of_eq = (0..2 * nx * ny).map(|i| (i / 2) as u32).collect();
    let coords = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
    (p, v, point_of_eq, coords)
}

#[test]
fn nested_dissection_on_a_quad_grid_is_a_permutation_with_less_fill_than_amd() {
    let (nx, ny) = (60, 45);
    let (p, v, point_of_eq, coords) = quad_grid(nx, ny);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let (fwd, inv) = nested_dissection(&p.col_ptr, &p.row_idx, p.n, &points).unwrap();
    let mut seen = vec![false; p.n];
    for (new, &old) in fwd.iter().enumerate() {
        assert!(!seen[old]);
        seen[old] = true;
        assert_eq!(inv[old], new);
    }
    let nd = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
    let amd = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
    let (f_nd, f_amd) = (nd.stats().nnz_factor.unwrap(), amd.stats().nnz_factor.unwrap());
    assert!(f_nd < f_amd, "nested dissection fill {f_nd} vs AMD {f_amd}");
    let mut s = nd;
    s.factorize(&v).unwrap();
    let b: Vec<f64> = (0..p.n).map(|i| (i % 7) as f64 - 3.0).collect();
    let x = solve(&s, &b).unwrap();
    assert!(rel_residual(&p, &v, &x, &b) < 1e-12);
    // An unknown without a point: no nested dissection (the caller falls back to AMD).
    let mut partial = point_of_eq.clone();
    partial[5] = crate::solve::ordering::NO_POINT;
    let points = EquationPoints { point_of_eq: &partial, coords: &coords, dim: 2 };
    assert!(nested_dissection(&p.col_ptr, &p.row_idx, p.n, &points).is_none());
}

/// A contact-like saddle point on the quad grid of [`quad_grid`]: one multiplier per
/// node of the "crack" row `y = ny / 3` (x < 2nx/3), coupled to the jump of the second
/// component between that row and the next, `[[u]] = u(x, y + 1) − u(x, y)`; the
/// contact values add `rho [[u]]²` on the crack unknowns for the multipliers with
/// `active[k]`, and `−1/rho` on the diagonal of the others (the augmented Lagrangian
/// structure). Returns (pattern, bulk values, contact values, points, n_primal).
#[allow(clippy::type_complexity)]
pub(super) fn contact_grid(
    nx: usize,
    ny: usize,
    rho: f64,
    active: impl Fn(usize) -> bool,
) -> (CscPattern, Vec<f64>, Vec<f64>, Vec<u32>, Vec<[f64; 3]>, usize) {
    contact_grid_with(nx, ny, rho, active, false)
}

/// [`contact_grid`], with the two components of each node coupled
/// ([`coupled_quad_triplets`]: one connected body) if `coupled`.
#[allow(clippy::type_complexity)]
fn contact_grid_with(
    nx: usize,
    ny: usize,
    rho: f64,
    active: impl Fn(usize) -> bool,
    coupled: bool,
) -> (CscPattern, Vec<f64>, Vec<f64>, Vec<u32>, Vec<[f64; 3]>, usize) {
    let node = |x: usize, y: usize| y * nx + x;
    let np = 2 * nx * ny;
    let mut t =
        if coupled { coupled_quad_triplets(nx, ny, |_| Some(0.01)) } else { quad_triplets(nx, ny, |_| Some(0.01)) };
    let yc = ny / 3;
    let mut contact = vec![];
    for (k, x) in (0..2 * nx / 3).enumerate() {
        let (lo, hi) = (2 * node(x, yc) + 1, 2 * node(x, yc + 1) + 1);
        let m = np + k;
        let (bulk_mm, extra): (f64, Vec<(usize, usize, f64)>) = if active(k) {
            (0.0, vec![(lo, lo, rho), (hi, hi, rho), (lo, hi, -rho), (hi, lo, -rho)])
        } else {
            (-1.0 / rho, vec![])
        };
        t.extend([(m, hi, 0.0), (hi, m, 0.0), (m, lo, 0.0), (lo, m, 0.0), (m, m, 0.0)]);
        t.extend([(lo, hi, 0.0), (hi, lo, 0.0)]);
        contact.extend([(m, hi, 1.0), (hi, m, 1.0), (m, lo, -1.0), (lo, m, -1.0), (m, m, bulk_mm)]);
        contact.extend(extra);
    }
    let n = np + 2 * nx / 3;
    let (p, bulk) = matrix(n, &t);
    let mut full = bulk.clone();
    for &(i, j, v) in &contact {
        full[p.position(i, j).unwrap()] += v;
    }
    let mut point_of_eq: Vec<u32> = (0..np).map(|i| (i / 2) as u32).collect();
    point_of_eq.resize(n, crate::solve::ordering::NO_POINT);
    let coords = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
    (p, bulk, full, point_of_eq, coords, np)
}

// The condensed factor of a contact-like saddle point (bulk factorised once, dense LBLᵀ
// on the crack unknowns and multipliers) gives the LDLᵀ solution to 1e-9 relative, on
// a small grid (one half) and on a large one (above SPLIT_MIN_UNKNOWNS: two halves in
// parallel), for two sets of contact statuses on the same bulk, and after a change of
// the bulk values without `set_bulk` (the bulk stage is then redone).
#[test]
fn condensed_contact_factor_matches_ldlt() {
    for (nx, ny) in [(40, 30), (120, 90)] {
        let (p, bulk, full_a, point_of_eq, coords, np) = contact_grid(nx, ny, 10.0, |k| k % 3 != 0);
        let (_, _, full_b, _, _, _) = contact_grid(nx, ny, 10.0, |k| k % 2 == 0);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
        assert!(cond.is_condensed(), "{nx}×{ny}");
        if p.n >= SPLIT_MIN_UNKNOWNS {
            let Factor::Condensed(c) = &cond.factor else { unreachable!() };
            assert_eq!(c.halves(), 2);
        }
        let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
        assert!(!ldlt.is_condensed());
        cond.set_bulk(&bulk).unwrap();
        let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut shifted = full_b.clone();
        shifted[p.position(5, 5).unwrap()] += 0.5;
        for (label, vals) in [("a", &full_a), ("b", &full_b), ("bulk changed", &shifted)] {
            cond.factorize(vals).unwrap();
            ldlt.factorize(vals).unwrap();
            let xc = solve(&cond, &b).unwrap();
            let xl = solve(&ldlt, &b).unwrap();
            assert!(rel_residual(&p, vals, &xc, &b) < 1e-10, "{nx}×{ny} {label}");
            let (dmax, xmax) =
                xc.iter().zip(&xl).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
            assert!(dmax < 1e-9 * xmax, "{nx}×{ny} {label}: condensed and LDLT differ by {dmax:e} (max {xmax:e})");
        }
        // Newton with deferred interior corrections: a full solve with the statuses
        // of `a`, then the statuses of `b`, residuals computed with the stale
        // interior; once applied, the result solves system `b`.
        let res = deferred_newton_residual(&mut cond, &p, &full_a, &full_b, &b);
        assert!(res < 1e-10, "{nx}×{ny}: deferred Newton residual {res:e}");
    }
}

// The memory check of a condensed factor counts its dense crack block in full: `F`, its
// factor, the kept factor's reference copy and the low-rank correction's `Y`
// (`DenseBlock`), not only the lower triangle of `F` that `nnz_factor` reports. Model: the
// contact grid 40 × 30 above (26 multipliers). Reference: with a 1-byte limit the analysis
// is refused with predicted bytes equal to the sparse estimate of the factor the same
// analysis builds without a limit (`memory::predicted_bytes`) plus its
// `dense_extra_bytes()` (> 0).
#[test]
fn condensed_factor_memory_check_counts_the_dense_block_in_full() {
    use crate::solve::backend::{OrderingChoice, Precision, SystemStructure};
    let (p, _, _, point_of_eq, coords, np) = contact_grid(40, 30, 10.0, |k| k % 3 != 0);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let structure = |limit: Option<u64>| SystemStructure {
        method: LinearMethod::Ldlt,
        pattern: &p,
        n_primal: np,
        points: Some(&points),
        condense: Some(None),
        ordering: OrderingChoice::Auto,
        memory_limit: limit,
        reuse: None,
        precision: Precision::Double,
    };
    let solver = LinearSolver::analyse_system(&structure(None)).unwrap();
    let Factor::Condensed(c) = &solver.factor else { panic!("not condensed") };
    let (extra, nnz) = (c.dense_extra_bytes(), c.nnz_factor());
    assert!(extra > 0);
    match LinearSolver::analyse_system(&structure(Some(1))) {
        Err(LinearError::FactorTooLarge { predicted_bytes, .. }) => {
            // The sparse estimate (factor entries, matrix copy, vectors) plus the block.
            let sparse = super::memory::predicted_bytes(Some(nnz), 8, &[], p.nnz(), p.n);
            assert_eq!(predicted_bytes, sparse + extra, "sparse estimate {sparse}, dense extra {extra}");
        }
        other => panic!("expected FactorTooLarge, got {other:?}"),
    }
}

// A bulk that is not positive definite on its own: the grid above the "crack" row is
// not connected to the grid below and has no shift (the constants of each component
// are free), and only the multipliers tie the two rows together (both components). The
// condensed factor detects the non-positive bulk and shifts the crack block (the rows
// coupled to the multipliers, which every free motion of the upper grid moves): it stays
// condensed, and the shift comes off exactly in the Schur complement: the same solution
// as the plain LDLᵀ, whose regularisation covers a K positive definite on the kernel of B.
#[test]
fn condensed_factor_shifts_the_crack_block_when_the_bulk_floats() {
    let (p, v, bulk, np, point_of_eq, coords) = tied_rows(0.0);
    let m = p.n;
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
    assert!(cond.is_condensed());
    cond.set_bulk(&bulk).unwrap();
    assert!(cond.is_condensed(), "a floating bulk is condensed with the crack block shifted");
    cond.factorize(&v).unwrap();
    let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
    ldlt.factorize(&v).unwrap();
    let b: Vec<f64> = (0..m).map(|i| if i < np { ((i * 7919) % 13) as f64 - 6.0 } else { 0.0 }).collect();
    let (xc, xl) = (solve(&cond, &b).unwrap(), solve(&ldlt, &b).unwrap());
    assert!(rel_residual(&p, &v, &xc, &b) < 1e-10);
    let d = xc.iter().zip(&xl).fold(0.0f64, |d, (a, c)| d.max((a - c).abs()));
    let xmax = xl.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    assert!(d < 1e-8 * xmax, "shifted condensed factor and LDLT differ by {d:e}");
}

/// The grid of `condensed_factor_shifts_the_crack_block_when_the_bulk_floats` with the
/// element shift `upper` above the crack row (0: the upper grid floats, held only by the
/// multipliers): pattern, values, bulk values (multiplier couplings zeroed), the number of
/// primal unknowns, and the points.
#[allow(clippy::type_complexity)]
fn tied_rows(upper: f64) -> (CscPattern, Vec<f64>, Vec<f64>, usize, Vec<u32>, Vec<[f64; 3]>) {
    tied_rows_with(upper, false)
}

/// [`tied_rows`], with the two components of each node coupled ([`coupled_quad_triplets`]:
/// the interior is then two bodies, below and above the missing element row) if `coupled`.
#[allow(clippy::type_complexity)]
fn tied_rows_with(upper: f64, coupled: bool) -> (CscPattern, Vec<f64>, Vec<f64>, usize, Vec<u32>, Vec<[f64; 3]>) {
    tied_grid(40, 70, 35, upper, coupled)
}

/// [`tied_rows_with`] on a grid of `nx × ny` nodes with the element row missing between
/// `y = yc` and `y = yc + 1`.
#[allow(clippy::type_complexity)]
fn tied_grid(
    nx: usize,
    ny: usize,
    yc: usize,
    upper: f64,
    coupled: bool,
) -> (CscPattern, Vec<f64>, Vec<f64>, usize, Vec<u32>, Vec<[f64; 3]>) {
    let node = |x: usize, y: usize| y * nx + x;
    let np = 2 * nx * ny;
    let shift = |y: usize| match y.cmp(&yc) {
        std::cmp::Ordering::Less => Some(0.01),
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => Some(upper),
    };
    let mut t = if coupled { coupled_quad_triplets(nx, ny, shift) } else { quad_triplets(nx, ny, shift) };
    let mut m = np;
    for x in 0..nx {
        for c in 0..2 {
            let (lo, hi) = (2 * node(x, yc) + c, 2 * node(x, yc + 1) + c);
            t.extend([(m, hi, 1.0), (hi, m, 1.0), (m, lo, -1.0), (lo, m, -1.0)]);
            m += 1;
        }
    }
    let (p, v) = matrix(m, &t);
    let mut bulk = v.clone();
    for j in np..m {
        for k in p.col_ptr[j]..p.col_ptr[j + 1] {
            bulk[k] = 0.0;
            let i = p.row_idx[k];
            bulk[p.position(j, i).unwrap()] = 0.0;
        }
    }
    let mut point_of_eq: Vec<u32> = (0..np).map(|i| (i / 2) as u32).collect();
    point_of_eq.resize(m, crate::solve::ordering::NO_POINT);
    let coords: Vec<[f64; 3]> = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64, 0.0]).collect();
    (p, v, bulk, np, point_of_eq, coords)
}

// `FaerSolver::expect_floating_bulk` (a meshed contact pair's body held only through
// contact): the crack block is shifted before the first bulk factorisation. On the floating
// bulk of the test above the first attempt succeeds: one bulk stage (without the shift up
// front: two, the first failing on the floating grid, checked too); the solution equals the
// plain LDLᵀ's (1e-8 of max |x|, as above). On a bulk that holds every part (shift 0.01 above the crack row too) the
// shifted-up-front factor gives the unshifted one's solution to 1e-10 of max |x| (the shift
// comes off exactly in the Schur complement, up to round-off).
#[test]
fn condensed_factor_shifted_up_front_factorises_a_floating_bulk_once() {
    for upper in [0.0, 0.01] {
        let (p, v, bulk, np, point_of_eq, coords) = tied_rows(upper);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let b: Vec<f64> = (0..p.n).map(|i| if i < np { ((i * 7919) % 13) as f64 - 6.0 } else { 0.0 }).collect();
        let mut shifted = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
        shifted.expect_floating_bulk();
        shifted.set_bulk(&bulk).unwrap();
        assert!(shifted.is_condensed());
        assert_eq!(shifted.bulk_attempts(), 1, "upper {upper}: the shifted-up-front bulk at the first attempt");
        shifted.factorize(&v).unwrap();
        let xs = solve(&shifted, &b).unwrap();
        assert!(rel_residual(&p, &v, &xs, &b) < 1e-10);
        let mut reference = if upper == 0.0 {
            LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap()
        } else {
            let mut r = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
            r.set_bulk(&bulk).unwrap();
            assert!(r.is_condensed());
            assert_eq!(r.bulk_attempts(), 1, "a held bulk needs no shift");
            r
        };
        if upper == 0.0 {
            let mut late = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
            late.set_bulk(&bulk).unwrap();
            assert!(late.is_condensed());
            assert_eq!(late.bulk_attempts(), 2, "without the shift up front the floating bulk fails once");
        }
        reference.factorize(&v).unwrap();
        let xr = solve(&reference, &b).unwrap();
        let d = xs.iter().zip(&xr).fold(0.0f64, |d, (a, c)| d.max((a - c).abs()));
        let xmax = xr.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        let tol = if upper == 0.0 { 1e-8 } else { 1e-10 };
        assert!(d < tol * xmax, "upper {upper}: shifted up front and reference differ by {d:e} (max |x| {xmax:e})");
    }
}

#[test]
fn split_cholesky_of_a_large_2d_system_matches_the_unsplit_one() {
    // 2 × 120 × 90 = 21 600 unknowns: above SPLIT_MIN_UNKNOWNS.
    let (nx, ny) = (120, 90);
    let (p, v, point_of_eq, coords) = quad_grid(nx, ny);
    assert!(p.n >= SPLIT_MIN_UNKNOWNS);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let mut split = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
    assert!(matches!(split.factor, Factor::Split(_)));
    let mut plain = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
    split.factorize(&v).unwrap();
    plain.factorize(&v).unwrap();
    let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    let xs = solve(&split, &b).unwrap();
    let xp = solve(&plain, &b).unwrap();
    assert!(rel_residual(&p, &v, &xs, &b) < 1e-12);
    let (dmax, xmax) =
        xs.iter().zip(&xp).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
    assert!(dmax < 1e-9 * xmax, "split and unsplit solutions differ by {dmax:e} (max |x| {xmax:e})");
    // The factor's size is reported (halves plus the dense separator).
    let nnz = split.stats().nnz_factor.unwrap();
    assert!(nnz > p.n && nnz < 2 * plain.stats().nnz_factor.unwrap());
    // A singular matrix (graph Laplacian) is reported, not solved.
    let (p, v, _, _) = quad_grid_shifted(nx, ny, 0.0);
    let mut s = LinearSolver::analyse_with_points(LinearMethod::Cholesky, &p, p.n, Some(&points)).unwrap();
    let e = s.factorize(&v).unwrap_err();
    assert!(matches!(e, LinearError::NotPositiveDefinite { .. }), "{e}");
}

#[test]
fn ldlt_with_points_keeps_multipliers_after_their_unknowns() {
    let nx = 16;
    let fixed: Vec<(usize, f64)> = (0..nx).map(|i| (i * nx, 1.0)).collect();
    let (p, v, b, np) = saddle(nx, true, &fixed, Some((5, 100)), 0.0, false);
    let (mut point_of_eq, coords) = grid_points(nx, nx);
    point_of_eq.resize(p.n, crate::solve::ordering::NO_POINT);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let (fwd, inv) = multipliers_after_primal_ordering(
        &p.col_ptr,
        &p.row_idx,
        p.n,
        np,
        Order { points: Some(&points), ..Order::default() },
    )
    .unwrap();
    assert_eq!(fwd.len(), p.n);
    for m in np..p.n {
        for &i in &p.row_idx[p.col_ptr[m]..p.col_ptr[m + 1]] {
            if i < np {
                assert!(inv[i] < inv[m], "multiplier {m} ordered before its unknown {i}");
            }
        }
    }
    let mut s = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
    s.factorize(&v).unwrap();
    let x = solve(&s, &b).unwrap();
    assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
}

// K singular but SPD on the kernel of B (pure Neumann Laplacian + one fixed unknown,
// plus or minus a tie): Ldlt and Lu reach ‖Ax − b‖/‖b‖ < 1e-10 and honour the fixed
// value to 1e-9. When the fixed unknown is the last primal one in the AMD order, the
// LDLᵀ meets the zero pivot of K before the constraint: it must regularise it and
// recover by iterative refinement.
#[test]
fn saddle_point_with_singular_k() {
    let nx = 20;
    let (p, _, _, np) = saddle(nx, false, &[(0, 1.0)], None, 0.0, false);
    let (fwd, _) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, np, Order::default()).unwrap();
    let amd_last = *fwd.iter().rev().find(|&&i| i < np).unwrap();
    for fixed in [0, 7, nx * nx / 2 + 3, nx * nx - 1, amd_last] {
        for tie in [None, Some((1, nx * nx - 2))] {
            let (p, v, b, np) = saddle(nx, false, &[(fixed, 1.0)], tie, 0.0, false);
            for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
                let mut s = LinearSolver::analyse(method, &p, np).unwrap();
                s.factorize(&v).unwrap();
                if method == LinearMethod::Ldlt && fixed == amd_last && tie.is_none() {
                    assert!(s.regularised_pivots() > 0);
                }
                let x = solve(&s, &b).unwrap();
                let r = rel_residual(&p, &v, &x, &b);
                assert!(r < 1e-10, "{method} fixed {fixed} tie {tie:?}: residual {r:e}");
                assert!((x[fixed] - 1.0).abs() < 1e-9);
                eprintln!(
                    "{method} fixed {fixed} tie {tie:?}: {} regularised, residual {r:.1e} after {} refinements",
                    s.regularised_pivots(),
                    s.last_residual().1
                );
            }
        }
    }
}

// Quasi-definite [K Bᵀ; B −C] with C = 1e-3 I (stabilised multipliers): Ldlt to 1e-10.
#[test]
fn quasi_definite_ldlt() {
    let (p, v, b, np) = saddle(25, true, &[(3, 1.0), (40, 2.0), (600, -1.0)], Some((10, 11)), 1e-3, false);
    let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, np).unwrap();
    s.factorize(&v).unwrap();
    let x = solve(&s, &b).unwrap();
    assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
}

// Singular "SPD-looking" matrix (pure Neumann Laplacian, kernel = constants):
// Cholesky reports NotPositiveDefinite (50×50 simplicial and 200×200 supernodal),
// never a NaN or a silent garbage solution; Ldlt (which regularises the one zero
// pivot, on both faer paths) and Lu, which cannot tell the matrix is singular at
// factorisation, fail at solve time with a clear error.
#[test]
fn singular_neumann_laplacian_is_reported() {
    for nx in [50, 200] {
        let (p, v) = matrix(nx * nx, &laplacian_triplets(nx, nx, false));
        let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, p.n).unwrap();
        let e = s.factorize(&v).unwrap_err();
        assert!(matches!(e, LinearError::NotPositiveDefinite { .. }), "{e}");
        assert!(e.to_string().contains("not positive definite"));
        let b = rhs(p.n);
        for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
            let mut s = LinearSolver::analyse(method, &p, p.n).unwrap();
            let result = s.factorize(&v).and_then(|_| solve(&s, &b).map(|_| ()));
            if method == LinearMethod::Ldlt {
                assert_eq!(supernodal(&s), nx == 200);
                assert_eq!(s.regularised_pivots(), 1, "the zero pivot of the constants is regularised");
            }
            let e = result.unwrap_err();
            assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{method}: {e}");
        }
    }
}

// Redundant constraints (the same unknown fixed twice: B rank deficient) with Ldlt
// and Lu: conflicting values give a clear error; consistent values either a clear
// error or a solution with ‖Ax − b‖/‖b‖ < 1e-10 (the multipliers then share the
// reaction arbitrarily); never NaN.
#[test]
fn redundant_constraints_are_reported() {
    for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
        let (p, v, b, np) = saddle(10, true, &[(5, 1.0), (5, 2.0)], None, 0.0, false);
        let mut s = LinearSolver::analyse(method, &p, np).unwrap();
        let e = s.factorize(&v).and_then(|_| solve(&s, &b).map(|_| ())).unwrap_err();
        assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{e}");
        let (p, v, b, np) = saddle(10, true, &[(5, 1.0), (5, 1.0)], None, 0.0, false);
        let mut s = LinearSolver::analyse(method, &p, np).unwrap();
        match s.factorize(&v).and_then(|_| solve(&s, &b)) {
            Ok(x) => assert!(rel_residual(&p, &v, &x, &b) < 1e-10),
            Err(e) => assert!(matches!(e, LinearError::Singular { .. } | LinearError::ZeroPivot { .. }), "{e}"),
        }
    }
}

// Tiny systems: 1 unknown solves exactly with every method (x = b/a to 1e-15);
// a 1-unknown zero matrix and an empty system error or work cleanly.
#[test]
fn one_unknown_and_empty_system() {
    let (p, v) = matrix(1, &[(0, 0, 4.0)]);
    for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
        let mut s = LinearSolver::analyse(method, &p, 1).unwrap();
        s.factorize(&v).unwrap();
        let x = solve(&s, &[2.0]).unwrap();
        assert!((x[0] - 0.5).abs() < 1e-15);
        assert_eq!(solve(&s, &[0.0]).unwrap(), vec![0.0]);
        let e = s.factorize(&[0.0]).unwrap_err();
        assert!(matches!(e, LinearError::EmptyRow { unknown: 0 }), "{e}");
    }
    let empty = CscPattern { n: 0, col_ptr: vec![0], row_idx: vec![] };
    for method in [LinearMethod::Cholesky, LinearMethod::Ldlt, LinearMethod::Lu] {
        let mut s = LinearSolver::analyse(method, &empty, 0).unwrap();
        s.factorize(&[]).unwrap();
        let mut x: Vec<f64> = vec![];
        s.solve_in_place(&mut x).unwrap();
        assert_eq!(s.stats().nnz_factor.unwrap_or(0), 0);
    }
}

// Bad input is refused with the matching error: NaN/inf values, wrong lengths,
// non-finite right-hand side, malformed or unsymmetric patterns, n_primal > n.
#[test]
fn bad_input_is_refused() {
    let (p, v) = matrix(9, &laplacian_triplets(3, 3, true));
    let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, 9).unwrap();
    let mut bad = v.clone();
    let k = p.position(4, 1).unwrap();
    bad[k] = f64::NAN;
    assert!(matches!(s.factorize(&bad), Err(LinearError::NonFiniteMatrix { row: 4, col: 1, .. })));
    bad[k] = f64::INFINITY;
    assert!(matches!(s.factorize(&bad), Err(LinearError::NonFiniteMatrix { .. })));
    assert!(matches!(s.factorize(&v[1..]), Err(LinearError::LengthMismatch { .. })));
    s.factorize(&v).unwrap();
    assert!(matches!(solve(&s, &[1.0; 8]), Err(LinearError::LengthMismatch { .. })));
    let mut b = vec![1.0; 9];
    b[2] = f64::NAN;
    assert!(matches!(solve(&s, &b), Err(LinearError::NonFiniteRhs { index: 2, .. })));
    let unsymmetric = CscPattern::from_entries(2, &[(0, 0), (1, 1), (1, 0)]);
    assert!(matches!(LinearSolver::analyse(LinearMethod::Ldlt, &unsymmetric, 2), Err(LinearError::InvalidPattern(_))));
    let unsorted = CscPattern { n: 2, col_ptr: vec![0, 2, 3], row_idx: vec![1, 0, 1] };
    assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &unsorted, 2), Err(LinearError::InvalidPattern(_))));
    let short = CscPattern { n: 2, col_ptr: vec![0, 1], row_idx: vec![0] };
    assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &short, 2), Err(LinearError::InvalidPattern(_))));
    assert!(matches!(LinearSolver::analyse(LinearMethod::Lu, &p, 10), Err(LinearError::InvalidPrimalCount { .. })));
    // Negative diagonal with Cholesky.
    let (p, v) = matrix(2, &[(0, 0, 1.0), (1, 1, -1.0)]);
    let mut s = LinearSolver::analyse(LinearMethod::Cholesky, &p, 2).unwrap();
    assert!(matches!(s.factorize(&v), Err(LinearError::NotPositiveDefinite { unknown: 1, .. })));
}

// Badly scaled saddle point (K ~ 2e11 like steel in Pa, B ~ 1): Ldlt to 1e-10
// without regularisation, thanks to the symmetric scaling.
#[test]
fn badly_scaled_saddle_point() {
    let (p, mut v, mut b, np) = saddle(20, true, &[(0, 1.0), (210, 2.0)], Some((30, 31)), 0.0, false);
    for j in 0..np {
        let col = p.col_ptr[j]..p.col_ptr[j + 1];
        for (x, &i) in v[col.clone()].iter_mut().zip(&p.row_idx[col]) {
            if i < np {
                *x *= 2e11;
            }
        }
    }
    b[..np].iter_mut().for_each(|x| *x *= 2e11);
    let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, np).unwrap();
    s.factorize(&v).unwrap();
    assert_eq!(s.regularised_pivots(), 0);
    let x = solve(&s, &b).unwrap();
    assert!(rel_residual(&p, &v, &x, &b) < 1e-10);
}

// Several threads solving with one factor at once get the same answers (1e-14).
#[test]
fn concurrent_solves() {
    let (p, v) = matrix(900, &laplacian_triplets(30, 30, true));
    let mut s = LinearSolver::analyse(LinearMethod::Ldlt, &p, 900).unwrap();
    s.factorize(&v).unwrap();
    let b = rhs(900);
    let x0 = solve(&s, &b).unwrap();
    std::thread::scope(|scope| {
        for _ in 0..4 {
            scope.spawn(|| {
                for _ in 0..5 {
                    let x = solve(&s, &b).unwrap();
                    assert!(x.iter().zip(&x0).all(|(a, b)| (a - b).abs() < 1e-14));
                }
            });
        }
    });
}

/// 7-point Laplacian on an m³ grid with homogeneous Dirichlet conditions outside (SPD).
fn laplacian_3d_triplets(m: usize) -> Vec<(usize, usize, f64)> {
    let id = |x: usize, y: usize, z: usize| (z * m + y) * m + x;
    let mut t = vec![];
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                let i = id(x, y, z);
                t.push((i, i, 6.0));
                if x + 1 < m {
                    t.extend([(i, id(x + 1, y, z), -1.0), (id(x + 1, y, z), i, -1.0)]);
                }
                if y + 1 < m {
                    t.extend([(i, id(x, y + 1, z), -1.0), (id(x, y + 1, z), i, -1.0)]);
                }
                if z + 1 < m {
                    t.extend([(i, id(x, y, z + 1), -1.0), (id(x, y, z + 1), i, -1.0)]);
                }
            }
        }
    }
    t
}

// What: a factor predicted larger than the memory allowed is refused after the symbolic
// phase with `FactorTooLarge` (predicted and available sizes, entries of L), not a crash.
// Model: 7-point Laplacian on a 24³ grid (13 824 unknowns), Cholesky, each ordering.
// Limit injected: 1 MB (the factor holds ≥ 8 bytes per entry of L, several MB here) →
// refused, with predicted ≥ 8 nnz(L) > limit; a limit of 1 TB → analysed, and the solve
// has a relative residual below 1e-12.
#[test]
fn factor_larger_than_the_memory_limit_is_refused() {
    use crate::solve::backend::{OrderingChoice, SystemStructure};
    let (p, v) = matrix(24 * 24 * 24, &laplacian_3d_triplets(24));
    for ordering in [OrderingChoice::Auto, OrderingChoice::Amd, OrderingChoice::NestedDissection] {
        let structure = |limit: u64| SystemStructure {
            method: LinearMethod::Cholesky,
            pattern: &p,
            n_primal: p.n,
            points: None,
            condense: None,
            ordering,
            memory_limit: Some(limit),
            reuse: None,
            precision: crate::solve::backend::Precision::Double,
        };
        match LinearSolver::analyse_system(&structure(1_000_000)) {
            Err(e @ LinearError::FactorTooLarge { predicted_bytes, available_bytes, nnz_factor }) => {
                assert_eq!(available_bytes, 1_000_000);
                assert!(nnz_factor > p.n && predicted_bytes >= 8 * nnz_factor as u64, "{e:?}");
                assert!(predicted_bytes > available_bytes);
                let msg = e.to_string();
                assert!(msg.contains("GB") && msg.contains("entries in the factor"), "{msg}");
            }
            other => panic!("{ordering:?}: expected FactorTooLarge, got {other:?}"),
        }
        let mut s = LinearSolver::analyse_system(&structure(1 << 40)).unwrap();
        s.factorize(&v).unwrap();
        let b = rhs(p.n);
        let x = solve(&s, &b).unwrap();
        assert!(rel_residual(&p, &v, &x, &b) < 1e-12);
    }
}

// Mixed precision on a contact saddle point: the whole-system LDLᵀ in single precision,
// each solve refined in double precision. Model: the contact grid 120 × 90 above (21 660
// unknowns, 80 multipliers, a supernodal factor), two contact stiffnesses ρ (10 and 1e4:
// the multipliers' rows −1/ρ and the ρ[[u]]² terms), two sets of statuses. Reference: the
// double-precision LDLᵀ on the same pattern. Asserted: the factor stays single precision
// (no fallback), the solve takes refinement steps (at most MIXED_MAX_ITERATIONS) and
// reaches the double path's residual, ‖Ax − b‖/‖b‖ ≤ max(10 × the double path's, 1e-13),
// and the two solutions agree to 1e-10 of the largest entry.
#[test]
fn mixed_precision_ldlt_of_a_saddle_point_reaches_the_double_residual() {
    use crate::solve::backend::{OrderingChoice, Precision, SystemStructure};
    for rho in [10.0, 1e4] {
        let (p, _, full_a, point_of_eq, coords, np) = contact_grid(120, 90, rho, |k| k % 3 != 0);
        let (_, _, full_b, _, _, _) = contact_grid(120, 90, rho, |k| k % 2 == 0);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let structure = |precision| SystemStructure {
            method: LinearMethod::Ldlt,
            pattern: &p,
            n_primal: np,
            points: Some(&points),
            condense: None,
            ordering: OrderingChoice::Auto,
            memory_limit: None,
            reuse: None,
            precision,
        };
        let mut mixed = LinearSolver::analyse_system(&structure(Precision::Mixed)).unwrap();
        assert!(matches!(&mixed.factor, Factor::Mixed(m) if m.is_ldlt()), "ρ = {rho}");
        let mut double = LinearSolver::analyse_system(&structure(Precision::Double)).unwrap();
        assert!(matches!(&double.factor, Factor::Cholesky { .. }));
        let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        for (label, vals) in [("a", &full_a), ("b", &full_b)] {
            mixed.factorize(vals).unwrap();
            double.factorize(vals).unwrap();
            let xm = solve(&mixed, &b).unwrap();
            let xd = solve(&double, &b).unwrap();
            let (rm, rd) = (rel_residual(&p, vals, &xm, &b), rel_residual(&p, vals, &xd, &b));
            let steps = mixed.last_residual().1;
            let stats = mixed.stats();
            assert!(stats.mixed && stats.fallback.is_none(), "ρ = {rho} {label}: fell back ({:?})", stats.fallback);
            assert!((1..=super::mixed::MIXED_MAX_ITERATIONS).contains(&steps), "ρ = {rho} {label}: {steps} steps");
            assert!(rm <= (10.0 * rd).max(1e-13), "ρ = {rho} {label}: mixed residual {rm:e}, double {rd:e}");
            let (dmax, xmax) =
                xm.iter().zip(&xd).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
            assert!(dmax < 1e-10 * xmax, "ρ = {rho} {label}: mixed and double differ by {dmax:e} (max {xmax:e})");
            eprintln!("ρ = {rho} {label}: {steps} refinement steps, residual {rm:.2e} (double {rd:.2e})");
        }
    }
}

// The kept whole-system factor (`kept.rs`) on the contact-like saddle point of
// `contact_grid` (12 × 9 nodes, 2 unknowns a node: 216 primal unknowns, 8 multipliers,
// ρ = 10), analysed for contact but not condensed (LDLᵀ: its crack block is more than
// 1/20 of the unknowns, `CONDENSED_MIN_RATIO`; LU: never condensed). Statuses `a`: point k
// active when k % 3 ≠ 0; `b`: p = 1, 2 of them flipped. A flip changes 3 columns (the multiplier
// and its two crack unknowns) by a matrix of rank ≤ 2 (ρ [[u]]² and the −1/ρ diagonal),
// so `b − a` has rank k ≤ 2p. Reference: a fresh solver's direct solve of `b`.
// Assertions: the new matrix keeps the factor (one numeric factorisation, one reuse),
// GMRES preconditioned by the old factor converges in ≤ k + 1 iterations, and the answer
// equals the direct one to 1e-10 relative (max norm). LU: a change of a bulk entry (not a
// contact column) refactorises; with the switch off (`FISSURE_KEPT_FACTOR=0`) every new
// matrix refactorises.
#[test]
fn kept_sparse_factor_gmres_converges_in_k_plus_one_iterations_on_a_rank_k_change() {
    use crate::solve::backend::{OrderingChoice, Precision, SystemStructure};
    let (nx, ny) = (12, 9);
    let (p, _, full_a, point_of_eq, coords, np) = contact_grid(nx, ny, 10.0, |k| k % 3 != 0);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    for method in [LinearMethod::Ldlt, LinearMethod::Lu] {
        let structure = SystemStructure {
            method,
            pattern: &p,
            n_primal: np,
            points: Some(&points),
            condense: Some(None),
            ordering: OrderingChoice::Auto,
            memory_limit: None,
            reuse: None,
            precision: Precision::Double,
        };
        for flips in [&[1usize][..], &[1, 4]] {
            let (_, _, full_b, _, _, _) = contact_grid(nx, ny, 10.0, |k| (k % 3 != 0) ^ flips.contains(&k));
            let mut kept = LinearSolver::analyse_system(&structure).unwrap();
            assert!(!kept.is_condensed() && kept.kept.is_some(), "{method:?}");
            kept.kept.as_mut().unwrap().set_mode(super::kept::Mode::Always);
            kept.factorize(&full_a).unwrap();
            let xa = solve(&kept, &b).unwrap();
            assert!(rel_residual(&p, &full_a, &xa, &b) < 1e-10);
            kept.factorize(&full_b).unwrap();
            let x = solve(&kept, &b).unwrap();
            let mut fresh = LinearSolver::analyse_system(&structure).unwrap();
            fresh.kept.as_mut().unwrap().set_mode(super::kept::Mode::Off);
            fresh.factorize(&full_b).unwrap();
            let xd = solve(&fresh, &b).unwrap();
            let (dmax, xmax) =
                x.iter().zip(&xd).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
            let c = kept.stats().kept.unwrap();
            let k = 2 * flips.len();
            assert_eq!(
                (c.factorizations, c.reused, c.krylov_solves),
                (1, 1, 1),
                "{method:?} p = {}: {c:?}",
                flips.len()
            );
            assert!(c.krylov_iterations <= k + 1, "{method:?} rank {k}: {c:?}");
            assert!(dmax <= 1e-10 * xmax, "{method:?} rank {k}: kept and direct differ by {dmax:e} (max {xmax:e})");
        }
        if method == LinearMethod::Lu {
            // A bulk entry changed: refactorised.
            let mut kept = LinearSolver::analyse_system(&structure).unwrap();
            kept.kept.as_mut().unwrap().set_mode(super::kept::Mode::Always);
            kept.factorize(&full_a).unwrap();
            solve(&kept, &b).unwrap();
            let mut shifted = full_a.clone();
            shifted[p.position(5, 5).unwrap()] += 0.5;
            kept.factorize(&shifted).unwrap();
            let x = solve(&kept, &b).unwrap();
            assert!(rel_residual(&p, &shifted, &x, &b) < 1e-10);
            assert_eq!(kept.stats().kept.unwrap().factorizations, 2, "a bulk change refactorises");
            // The switch off: a contact change refactorises too.
            let mut off = LinearSolver::analyse_system(&structure).unwrap();
            off.kept.as_mut().unwrap().set_mode(super::kept::Mode::Off);
            let (_, _, full_b, _, _, _) = contact_grid(nx, ny, 10.0, |k| (k % 3 != 0) ^ (k == 1));
            off.factorize(&full_a).unwrap();
            off.factorize(&full_b).unwrap();
            let c = off.stats().kept.unwrap();
            assert_eq!((c.factorizations, c.reused), (2, 0), "switched off: {c:?}");
        }
    }
}

// The condensed factor split at the bodies (`condensed.rs`, `interior_bodies`): the grid
// of `tied_rows` (40 × 70 nodes, two components a node, coupled: `tied_rows_with`; the
// element row between y = 35 and y = 36 missing, so the interior is two bodies, 2 800 and
// 2 640 unknowns, coupled
// only through the 160 crack unknowns of the two rows the 80 multipliers tie), with the
// upper body held (element shift 0.01) or floating (shift 0: held only by the
// multipliers; the crack block shifted up front, `expect_floating_bulk`). Reference: the
// plain LDLᵀ of the whole saddle point. Asserted: two halves, the bodies, no separator,
// each half's trailing block only its own body's 80 crack unknowns (of 160: the other
// body's rows get no update from it); the solution equal to the plain LDLᵀ's to 1e-10 of
// max |x| on both grids (measured 1.2e-15 held, 1.6e-15 floating), and its residual below
// 1e-10.
#[test]
fn condensed_factor_split_at_the_bodies_matches_ldlt_with_smaller_trailing_blocks() {
    for upper in [0.01, 0.0] {
        let (p, v, bulk, np, point_of_eq, coords) = tied_rows_with(upper, true);
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let b: Vec<f64> = (0..p.n).map(|i| if i < np { ((i * 7919) % 13) as f64 - 6.0 } else { 0.0 }).collect();
        let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
        if upper == 0.0 {
            cond.expect_floating_bulk();
        }
        cond.set_bulk(&bulk).unwrap();
        assert!(cond.is_condensed());
        {
            let Factor::Condensed(c) = &cond.factor else { unreachable!() };
            assert_eq!(c.halves(), 2, "upper {upper}: two halves");
            let (trails, ns, bodies) = c.trailing();
            assert!(bodies, "upper {upper}: split at the bodies");
            assert_eq!(ns, 0, "no separator between the bodies");
            assert_eq!(c.n_crack(), 160);
            assert_eq!(trails, vec![80, 80], "upper {upper}: each half only its own body's crack unknowns");
        }
        cond.factorize(&v).unwrap();
        let xc = solve(&cond, &b).unwrap();
        assert!(rel_residual(&p, &v, &xc, &b) < 1e-10, "upper {upper}");
        let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
        assert!(!ldlt.is_condensed());
        ldlt.factorize(&v).unwrap();
        let xl = solve(&ldlt, &b).unwrap();
        let d = xc.iter().zip(&xl).fold(0.0f64, |d, (a, c)| d.max((a - c).abs()));
        let xmax = xl.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        eprintln!("upper {upper}: bodies split against the plain LDLT: {:.2e} of max |x|", d / xmax);
        assert!(d < 1e-10 * xmax, "upper {upper}: split at the bodies and LDLT differ by {d:e} (max |x| {xmax:e})");
    }
}

// The condensed factor split at the top separator of one body (`contact_grid` 120 × 90
// with the components coupled, `contact_grid_with`: one connected body; 21 600 unknowns,
// above SPLIT_MIN_UNKNOWNS, the crack row y = 30 for x < 80, 80 multipliers): each half's trailing block holds only the separator and crack unknowns its
// own part couples to (`E = A33 + Σ_k scatter(T_k T_kᵀ − A33[t_k])`), at least one of them
// fewer than the whole separator block; the solution equal to the plain LDLᵀ's to 1e-10
// of max |x| (both factor the same positive definite bulk exactly) with residual below
// 1e-10.
#[test]
fn condensed_factor_split_at_the_separator_keeps_each_half_to_its_own_trailing_unknowns() {
    let (p, bulk, full, point_of_eq, coords, np) = contact_grid_with(120, 90, 10.0, |k| k % 3 != 0, true);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
    cond.set_bulk(&bulk).unwrap();
    {
        let Factor::Condensed(c) = &cond.factor else { panic!("not condensed") };
        assert_eq!(c.halves(), 2);
        let (trails, ns, bodies) = c.trailing();
        let n3 = ns + c.n_crack();
        eprintln!("trailing blocks {trails:?} of {n3} (separator {ns}, crack {})", c.n_crack());
        assert!(!bodies && ns > 0, "one body: the split at the top separator");
        assert!(trails.iter().all(|&t| t <= n3) && trails.iter().any(|&t| t < n3), "{trails:?} of {n3}");
    }
    let mut ldlt = LinearSolver::analyse_with_points(LinearMethod::Ldlt, &p, np, Some(&points)).unwrap();
    cond.factorize(&full).unwrap();
    ldlt.factorize(&full).unwrap();
    let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    let (xc, xl) = (solve(&cond, &b).unwrap(), solve(&ldlt, &b).unwrap());
    assert!(rel_residual(&p, &full, &xc, &b) < 1e-10);
    let d = xc.iter().zip(&xl).fold(0.0f64, |d, (a, c)| d.max((a - c).abs()));
    let xmax = xl.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    assert!(d < 1e-10 * xmax, "split at the separator and LDLT differ by {d:e} (max |x| {xmax:e})");
}

// The condensed analysis's choice between its split candidates (`condensed.rs`,
// `Layout::predicted_flops`): the dissection's halves are built only when their flops
// predicted from the bodies' halves are below the bodies' flops. Reference: the full
// comparison (`Candidates::Full`: both candidates built, the one of fewer flops kept, the
// rule before the prediction). Grids: `tied_grid` (two components a node, coupled; the
// element row above `y = yc` missing, so the interior is two bodies tied by multipliers):
// 40 × 70 nodes cut at 35 (5 600 primal unknowns, below SPLIT_MIN_UNKNOWNS: the dissection
// is one part, which the prediction never builds), 120 × 200 cut at 100 (48 000, balanced
// bodies), 160 × 150 cut at 30 (48 000, bodies of 9 920 and 38 080: unbalanced), 200 × 200
// and 300 × 200 cut at 3 (a thin body of 1 600 or 2 400 under one of 78 400 or 117 600:
// the full comparison keeps the bodies on the first and the dissection on the second); and
// `contact_grid` 240 × 180 (86 400, the two displacement components uncoupled: two equal
// bodies, each a whole grid). Asserted: on each, the prediction keeps the candidate the full
// comparison keeps (the same halves' trailing blocks, separator and bodies flag), the one
// part of the 40 × 70 grid loses to the bodies in the full comparison too, and the
// 300 × 200 grid keeps the dissection (both outcomes are exercised).
#[test]
fn condensed_split_candidate_predicted_as_the_full_comparison_picks() {
    use super::condensed::{condensed_factor_with, Candidates, Condensation};
    let choice = |p: &CscPattern, np: usize, point_of_eq: &[u32], coords: &[[f64; 3]], c: Candidates| {
        let points = EquationPoints { point_of_eq, coords, dim: 2 };
        let order = Order { points: Some(&points), ..Default::default() };
        match condensed_factor_with(&p.col_ptr, &p.row_idx, p.n, np, order, None, c).unwrap() {
            Condensation::Condensed(f) => f.trailing(),
            Condensation::Plain(_) => panic!("not condensed"),
        }
    };
    let mut cases = vec![];
    for (nx, ny, yc) in [(40, 70, 35), (120, 200, 100), (160, 150, 30), (200, 200, 3), (300, 200, 3)] {
        let (p, _, _, np, point_of_eq, coords) = tied_grid(nx, ny, yc, 0.01, true);
        cases.push((format!("tied {nx} x {ny} at {yc}"), p, np, point_of_eq, coords));
    }
    let (p, _, _, point_of_eq, coords, np) = contact_grid(240, 180, 10.0, |_| true);
    cases.push(("contact grid 240 x 180".to_string(), p, np, point_of_eq, coords));
    for (name, p, np, point_of_eq, coords) in &cases {
        let full = choice(p, *np, point_of_eq, coords, Candidates::Full);
        let predicted = choice(p, *np, point_of_eq, coords, Candidates::Predicted);
        eprintln!("{name}: full comparison {full:?}, predicted {predicted:?}");
        assert_eq!(predicted, full, "{name}: the prediction keeps the full comparison's candidate");
    }
    let full = |k: usize| choice(&cases[k].1, cases[k].2, &cases[k].3, &cases[k].4, Candidates::Full);
    let first = full(0);
    assert!(first.2 && first.1 == 0, "40 x 70: one part loses to the bodies: {first:?}");
    let thin = full(4);
    assert!(!thin.2 && thin.1 > 0, "300 x 200 at 3: the dissection: {thin:?}");
}

// The lower bound that lets the condensed analysis skip the prediction of the whole
// system's flops (`condensed.rs`, `CondensedFactor::part_flops`: `Σ c_j²` of the factors of
// its parts alone, read from the halves' supernodal structure). Reference: the whole
// system's flops predicted from its exact column counts (`predicted_flops`, the primal
// ordering with the multipliers after their unknowns: the measure the decision uses).
// Grids: `tied_grid` 120 × 200 cut at 100 (two balanced bodies) and 300 × 200 cut at 3 (a
// thin body; split at the top separator), `contact_grid` 240 × 180 (two uncoupled
// components) and, coupled, 120 × 90 (one body, split at the separator). Asserted: the
// parts' flops over the padding allowance (2) are at most the whole system's (measured
// before the division: 0.70–1.01 of them, the 1.01 from the supernodes' explicit zeros),
// and the parts' flops at least a tenth of the whole system's (a bound that decides).
#[test]
fn condensed_parts_bound_the_whole_system_flops() {
    use super::cholesky::predicted_flops;
    use super::condensed::{condensed_factor, Condensation};
    let mut cases = vec![];
    for (nx, ny, yc) in [(120, 200, 100), (300, 200, 3)] {
        let (p, _, _, np, point_of_eq, coords) = tied_grid(nx, ny, yc, 0.01, true);
        cases.push((format!("tied {nx} x {ny} at {yc}"), p, np, point_of_eq, coords));
    }
    let (p, _, _, point_of_eq, coords, np) = contact_grid(240, 180, 10.0, |_| true);
    cases.push(("contact grid 240 x 180".to_string(), p, np, point_of_eq, coords));
    let (p, _, _, point_of_eq, coords, np) = contact_grid_with(120, 90, 10.0, |k| k % 3 != 0, true);
    cases.push(("coupled contact grid 120 x 90".to_string(), p, np, point_of_eq, coords));
    for (name, p, np, point_of_eq, coords) in &cases {
        let points = EquationPoints { point_of_eq, coords, dim: 2 };
        let order = Order { points: Some(&points), ..Default::default() };
        let parts = match condensed_factor(&p.col_ptr, &p.row_idx, p.n, *np, order, None).unwrap() {
            Condensation::Condensed(f) => f.part_flops(),
            Condensation::Plain(_) => panic!("{name}: not condensed"),
        };
        let (fwd, inv) = multipliers_after_primal_ordering(&p.col_ptr, &p.row_idx, p.n, *np, order).unwrap();
        let whole = predicted_flops(&p.col_ptr, &p.row_idx, &fwd, &inv);
        eprintln!("{name}: parts {parts:.4e} flops, whole system {whole:.4e} ({:.3})", parts / whole);
        assert!(parts / 2.0 <= whole, "{name}: the parts' flops {parts:e} above twice the whole system's {whole:e}");
        assert!(parts >= 0.1 * whole, "{name}: the parts' flops {parts:e} far below the whole system's {whole:e}");
    }
}

/// The contact grid of [`contact_grid`] with `nfree` more multipliers coupled only to each
/// other and to the last two contact multipliers: the open law's rows of a contact zone's
/// dormant nodes (`free.rs`), a chain with the mass matrix of linear functions, −M/ρ
/// (diagonal −2/(3ρ) scaled by `mass`, neighbours −1/(6ρ) by `mass`), the first one
/// coupled to contact multiplier `m − 2` and the last to `m − 1` by −1/(6ρ) (their
/// transposes by `skew` times that). Returns the same tuple as [`contact_grid`] (values
/// with the chain: the bulk values hold it too, since it is not a crack unknown's entry).
#[allow(clippy::type_complexity)]
fn contact_grid_with_free(
    (nx, ny): (usize, usize),
    rho: f64,
    active: impl Fn(usize) -> bool,
    nfree: usize,
    (mass, skew): (f64, f64),
) -> (CscPattern, Vec<f64>, Vec<f64>, Vec<u32>, Vec<[f64; 3]>, usize) {
    let (p0, bulk0, full0, mut point_of_eq, coords, np) = contact_grid(nx, ny, rho, active);
    let n0 = p0.n;
    let mut t = vec![];
    let mut bulk_t = vec![];
    for j in 0..n0 {
        for k in p0.col_ptr[j]..p0.col_ptr[j + 1] {
            t.push((p0.row_idx[k], j, full0[k]));
            bulk_t.push((p0.row_idx[k], j, bulk0[k]));
        }
    }
    let mut chain = vec![];
    for k in 0..nfree {
        let f = n0 + k;
        chain.push((f, f, -mass * 2.0 / (3.0 * rho)));
        if k + 1 < nfree {
            chain.push((f, f + 1, -mass / (6.0 * rho)));
            chain.push((f + 1, f, -mass / (6.0 * rho)));
        }
    }
    let c = -1.0 / (6.0 * rho);
    chain.extend([(n0 - 2, n0, c), (n0, n0 - 2, skew * c)]);
    chain.extend([(n0 - 1, n0 + nfree - 1, c), (n0 + nfree - 1, n0 - 1, skew * c)]);
    t.extend(&chain);
    bulk_t.extend(&chain);
    let n = n0 + nfree;
    let (p, full) = matrix(n, &t);
    let (_, bulk) = matrix(n, &bulk_t);
    point_of_eq.resize(n, crate::solve::ordering::NO_POINT);
    (p, bulk, full, point_of_eq, coords, np)
}

/// `A x = b` by faer's dense LU with partial pivoting (the reference of the condensed
/// factor's tests).
fn dense_solve(p: &CscPattern, v: &[f64], b: &[f64]) -> Vec<f64> {
    use faer::linalg::solvers::Solve;
    let n = p.n;
    let mut a = faer::Mat::<f64>::zeros(n, n);
    for j in 0..n {
        for k in p.col_ptr[j]..p.col_ptr[j + 1] {
            a[(p.row_idx[k], j)] = v[k];
        }
    }
    let mut x = faer::Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    a.partial_piv_lu().solve_in_place(x.as_mut());
    x.col(0).iter().copied().collect()
}

// The condensed factor with free multipliers (`free.rs`): the contact grid 30 × 24 of
// `contact_grid` (1 440 primal unknowns, 20 contact multipliers, ρ = 10, point k active
// when k % 3 ≠ 0 and k < 15) with a chain of 12 multipliers coupled only to each other
// and to contact multipliers 18 and 19 (`contact_grid_with_free`: the open law's −M/ρ of
// dormant nodes). Reference: faer's dense LU of the whole system. Asserted: `F` keeps the
// 40 crack unknowns and the 20 contact multipliers only (width 60); the solution equals
// the dense one to 1e-12 of max |x| for: the statuses `a`; the statuses `b` (k % 2 = 0:
// an incremental F); the couplings of edge multiplier 19 to its crack unknowns tripled
// (its scale changes: the correction rescaled in F); the chain's values doubled (the correction rebuilt from the changed
// values, never reused stale); an unsymmetric tangent (one crack entry without its
// transpose, and the chain's couplings to the edge 1.3 times their transposes: F by LU);
// a deferred Newton correction after a change of statuses reaches the residual 1e-10.
// A chain that is not negative definite (its diagonal +2/(3ρ)) cannot be condensed out:
// the solver falls back to the plain LDLᵀ, which gives the dense answer or an error (its
// multiplier pivots are expected negative), never a wrong answer.
#[test]
fn condensed_factor_takes_free_multipliers_out_of_f_and_matches_a_dense_solve() {
    let (nx, ny, nfree) = (30, 24, 12);
    let status_a = |k: usize| k % 3 != 0 && k < 15;
    let status_b = |k: usize| k % 2 == 0 && k < 15;
    let (p, bulk, full_a, point_of_eq, coords, np) =
        contact_grid_with_free((nx, ny), 10.0, status_a, nfree, (1.0, 1.0));
    let (_, _, full_b, _, _, _) = contact_grid_with_free((nx, ny), 10.0, status_b, nfree, (1.0, 1.0));
    let (_, _, doubled, _, _, _) = contact_grid_with_free((nx, ny), 10.0, status_b, nfree, (2.0, 1.0));
    let (_, _, mut unsym, _, _, _) = contact_grid_with_free((nx, ny), 10.0, status_b, nfree, (1.0, 1.3));
    // One crack entry without its transpose (crack unknown `lo` of point 2, its multiplier).
    let (lo, m2) = (2 * (ny / 3 * nx + 2) + 1, np + 2);
    unsym[p.position(lo, m2).unwrap()] += 0.3;
    // The edge multiplier 19's couplings to its crack unknowns tripled: its scale changes,
    // the chain's values do not (the correction is rescaled, not rebuilt).
    let mut rescaled = full_b.clone();
    let m19 = np + 19;
    for k in p.col_ptr[m19]..p.col_ptr[m19 + 1] {
        let i = p.row_idx[k];
        if i < np {
            rescaled[k] *= 3.0;
            rescaled[p.position(m19, i).unwrap()] *= 3.0;
        }
    }
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
    assert!(cond.is_condensed());
    cond.set_bulk(&bulk).unwrap();
    let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    let n_contact = 2 * nx / 3;
    for (label, vals) in [
        ("a", &full_a),
        ("b", &full_b),
        ("edge rescaled", &rescaled),
        ("chain doubled", &doubled),
        ("unsymmetric", &unsym),
    ] {
        cond.factorize(vals).unwrap();
        assert!(cond.is_condensed(), "{label}");
        let width = cond.stats().condensed.unwrap().width;
        assert_eq!(width, 2 * n_contact + n_contact, "{label}: F keeps the crack unknowns and contact multipliers");
        let xc = solve(&cond, &b).unwrap();
        let xd = dense_solve(&p, vals, &b);
        let (dmax, xmax) =
            xc.iter().zip(&xd).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
        eprintln!("{label}: condensed against dense LU: {:.2e} of max |x|", dmax / xmax);
        assert!(dmax <= 1e-12 * xmax, "{label}: condensed and dense differ by {dmax:e} (max {xmax:e})");
    }
    // Newton with deferred interior corrections across a change of statuses.
    let res = deferred_newton_residual(&mut cond, &p, &full_a, &full_b, &b);
    assert!(res < 1e-10, "deferred Newton residual {res:e}");
    // A chain that is not negative definite: the plain LDLᵀ, the same answer.
    let (_, bulk_bad, bad, _, _, _) = contact_grid_with_free((nx, ny), 10.0, status_a, nfree, (-1.0, 1.0));
    let mut cond = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
    cond.set_bulk(&bulk_bad).unwrap();
    cond.factorize(&bad).unwrap();
    assert!(!cond.is_condensed(), "a chain that is not definite falls back to the plain LDLᵀ");
    // The plain LDLᵀ expects negative multiplier pivots: it solves, or says it cannot.
    match solve(&cond, &b) {
        Ok(xc) => {
            let xd = dense_solve(&p, &bad, &b);
            let (dmax, xmax) =
                xc.iter().zip(&xd).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
            assert!(dmax <= 1e-10 * xmax, "fallback: {dmax:e} (max {xmax:e})");
        }
        Err(e) => eprintln!("fallback: the plain LDLᵀ refuses it: {e:?}"),
    }
}

/// `max |x − y| / max |y|`.
fn max_difference(x: &[f64], y: &[f64]) -> f64 {
    let (d, m) = x.iter().zip(y).fold((0.0f64, 0.0f64), |(d, m), (a, c)| (d.max((a - c).abs()), m.max(c.abs())));
    d / m
}

/// `v` with the couplings of the first `k` multipliers (from `np`) scaled by `factor`
/// (both triangles): another contact tangent on the same bulk.
fn scaled_couplings(p: &CscPattern, v: &[f64], np: usize, k: usize, factor: f64) -> Vec<f64> {
    let mut w = v.to_vec();
    for j in np..(np + k).min(p.n) {
        for q in p.col_ptr[j]..p.col_ptr[j + 1] {
            let i = p.row_idx[q];
            if i < np {
                w[q] *= factor;
                w[p.position(j, i).unwrap()] *= factor;
            }
        }
    }
    w
}

// The condensed factor with its bulk stage in single precision (`interior.rs`: the halves
// in f32, every full solve refined against the true residual, the deferred Newton
// solves' interior term and the final interior response made exact by conjugate
// gradients preconditioned by the f32 halves). Models: the contact grid 120 × 90 with
// coupled components (one body, 21 600 unknowns: two halves and a separator, so the
// interior solve goes through `G`), statuses `k % 3 ≠ 0` then `k % 2 = 0`; the tied rows
// (40 × 70 nodes, two bodies tied by 80 multipliers) with the upper body held (element
// shift 0.01) and floating (shift 0, held only by the multipliers: the crack block
// shifted up front), the tangents: the first 20 multipliers' couplings halved, then the
// plain ties. Reference: the same condensed factor with its bulk in double precision
// (itself checked against the plain LDLᵀ above). Asserted: the bulk is in single
// precision; for both tangents the full solve equals the reference to 1e-10 of max |x|
// with residual below 1e-10 (the double-precision path's tolerance); a Newton sequence
// (a full solve of the first tangent, three deferred corrections of the second with
// residuals on the stale interior, then the deferred interior response) ends at
// residual below 1e-10 and equal to the double-precision bulk's sequence to 1e-9.
#[test]
fn condensed_factor_with_a_single_precision_bulk_solves_to_the_double_tolerance() {
    let (p, bulk, full_a, point_of_eq, coords, np) = contact_grid_with(120, 90, 10.0, |k| k % 3 != 0, true);
    let (_, _, full_b, _, _, _) = contact_grid_with(120, 90, 10.0, |k| k % 2 == 0, true);
    let mut cases = vec![("one body", p, bulk, full_a, full_b, np, point_of_eq, coords, false)];
    for upper in [0.01, 0.0] {
        let (p, v, bulk, np, point_of_eq, coords) = tied_rows_with(upper, true);
        let a = scaled_couplings(&p, &v, np, 20, 0.5);
        let label = if upper == 0.0 { "two bodies, one floating" } else { "two bodies" };
        cases.push((label, p, bulk, a, v, np, point_of_eq, coords, upper == 0.0));
    }
    for (label, p, bulk, full_a, full_b, np, point_of_eq, coords, floating) in cases {
        let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
        let b: Vec<f64> = (0..p.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let analyse = |single: bool| {
            let mut s = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
            s.set_bulk_precision(Some(single), false);
            if floating {
                s.expect_floating_bulk();
            }
            s.set_bulk(&bulk).unwrap();
            assert!(s.is_condensed(), "{label}");
            s
        };
        let (mut single, mut double) = (analyse(true), analyse(false));
        assert!(single.single_bulk() && !double.single_bulk(), "{label}");
        for (tangent, vals) in [("a", &full_a), ("b", &full_b)] {
            single.factorize(vals).unwrap();
            double.factorize(vals).unwrap();
            let (xs, xd) = (solve(&single, &b).unwrap(), solve(&double, &b).unwrap());
            let (res, diff) = (rel_residual(&p, vals, &xs, &b), max_difference(&xs, &xd));
            eprintln!("{label} {tangent}: full solve residual {res:.1e}, against the double bulk {diff:.1e}");
            assert!(res < 1e-10, "{label} {tangent}: residual {res:e}");
            assert!(diff < 1e-10, "{label} {tangent}: {diff:e} of max |x| from the double bulk");
        }
        let xs = deferred_newton(&mut single, &p, &full_a, &full_b, &b);
        let xd = deferred_newton(&mut double, &p, &full_a, &full_b, &b);
        let (res, diff) = (rel_residual(&p, &full_b, &xs, &b), max_difference(&xs, &xd));
        eprintln!("{label}: deferred Newton residual {res:.1e}, against the double bulk {diff:.1e}");
        assert!(res < 1e-10, "{label}: deferred Newton residual {res:e}");
        assert!(diff < 1e-9, "{label}: deferred Newton {diff:e} of max |x| from the double bulk");
    }
}

// The fallback of a single-precision bulk stage: with the fault switch (every f32 bulk
// stage reports a breakdown, as a non-positive or non-finite f32 pivot does) the halves
// are factorised in double precision, said on the standard error. Model: the tied rows
// with the upper body floating (as above). Reference: the condensed factor with its bulk
// in double precision. Asserted: the bulk asked in single precision ends in double; the
// solution equals the reference to 1e-12 of max |x| (the same factorisation).
#[test]
fn condensed_single_precision_bulk_falls_back_to_double_on_a_breakdown() {
    let (p, v, bulk, np, point_of_eq, coords) = tied_rows_with(0.0, true);
    let points = EquationPoints { point_of_eq: &point_of_eq, coords: &coords, dim: 2 };
    let b: Vec<f64> = (0..p.n).map(|i| if i < np { ((i * 7919) % 13) as f64 - 6.0 } else { 0.0 }).collect();
    let mut x = Vec::new();
    for (single, fault) in [(true, true), (false, false)] {
        let mut s = LinearSolver::analyse_condensed(LinearMethod::Ldlt, &p, np, Some(&points), None).unwrap();
        s.set_bulk_precision(Some(single), fault);
        s.expect_floating_bulk();
        s.set_bulk(&bulk).unwrap();
        assert!(s.is_condensed());
        assert!(!s.single_bulk(), "single {single}, fault {fault}: the bulk in double precision");
        s.factorize(&v).unwrap();
        x.push(solve(&s, &b).unwrap());
    }
    let diff = max_difference(&x[0], &x[1]);
    assert!(diff < 1e-12, "the fallback's answer {diff:e} of max |x| from the double bulk's");
}
