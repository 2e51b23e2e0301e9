//! Iterative refinement of a direct solve on the scaled system, with the residual check
//! that turns a singular matrix into an error instead of a wrong answer.
//!
//! Entry points: [`solve_refined`], called by the faer solver's solves with a closure that
//! applies the current factor, and [`solve_pcg`], the conjugate gradients in double
//! precision preconditioned by a single-precision factor (mixed precision), and
//! [`solve_gmres`], GMRES preconditioned by a kept factor of an earlier matrix
//! ([`super::kept`]); [`SolveWorkspace`] holds the buffers reused between solves.

use super::scaling::ScaledSystem;
use crate::solve::backend::{LinearError, LinearMethod};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};

/// Iterative refinement runs while the normwise backward error
/// `‖r‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` (of the scaled system) is above the target, and goes on only
/// while each step at least halves the residual. LDLᵀ (no pivoting) and LU: a first step
/// is almost always taken (it costs one solve and typically gains 30–50 % on large FE
/// systems, much more after regularisation); Cholesky is backward stable and is only
/// refined when the first solve is clearly poor.
pub(super) const ETA_TARGET_PIVOTING: f64 = 0.5 * f64::EPSILON;
pub(super) const ETA_TARGET_CHOLESKY: f64 = 1e3 * f64::EPSILON;
/// At most this many refinement steps (more when pivots were regularised).
const MAX_REFINE: usize = 3;
const MAX_REFINE_REGULARISED: usize = 10;
/// A relative residual above this after refinement is an error. It is measured on the
/// scaled system, ‖S(b − Ax)‖/‖Sb‖ (S the symmetric scaling that gives the primal unknowns
/// a unit diagonal): each equation weighed by its own stiffness, so that a part 1e6 times
/// stiffer than its neighbour does not turn the round-off of its stiff rows into a
/// "singular" verdict (a plate on a base 1e5–1e6 times stiffer failed at 5e-6–3.5e-5 in
/// ‖Ax − b‖/‖b‖ with an answer equal to the 1e3 contrast's to 3e-6, docs/reliability.md),
/// while a singular or inconsistent system still leaves a residual of its own size.
pub(super) const MAX_RELATIVE_RESIDUAL: f64 = 1e-6;

/// Buffers of the solve phase, reused between solves.
pub(super) struct SolveWorkspace {
    pub(super) mem: MemBuffer,
    /// Scaled right-hand side `S b`.
    b: Vec<f64>,
    /// Residual (of the scaled system); also scratch for the row sums of an unsymmetric
    /// matrix.
    pub(super) r: Vec<f64>,
    /// Refinement correction.
    dx: Vec<f64>,
    /// Conjugate gradients (mixed precision): search direction and `A p` (empty until the
    /// first such solve).
    p: Vec<f64>,
    q: Vec<f64>,
}

impl SolveWorkspace {
    pub(super) fn new(req: StackReq, n: usize) -> Result<Self, LinearError> {
        Ok(SolveWorkspace {
            mem: MemBuffer::try_new(req).map_err(|_| LinearError::OutOfMemory)?,
            b: vec![0.0; n],
            r: vec![0.0; n],
            dx: vec![0.0; n],
            p: Vec::new(),
            q: Vec::new(),
        })
    }
}

/// The backward-error target and the step cap of the refinement for a factor of `method`
/// with `regularised` perturbed pivots (`condensed`: Cholesky on the bulk, Bunch–Kaufman
/// with pivoting on the dense part).
pub(super) fn refinement_plan(method: LinearMethod, regularised: usize, condensed: bool) -> (f64, usize) {
    match (method, regularised) {
        (LinearMethod::Cholesky, _) => (ETA_TARGET_CHOLESKY, MAX_REFINE),
        _ if condensed => (ETA_TARGET_CHOLESKY, MAX_REFINE),
        (_, 0) => (ETA_TARGET_PIVOTING, MAX_REFINE),
        _ => (ETA_TARGET_PIVOTING, MAX_REFINE_REGULARISED),
    }
}

/// `r = b̃ − Ã y` in `ws.r`; returns ‖S⁻¹ r‖₂ (the residual of the original system), ‖r‖₂
/// (of the scaled system) and the normwise backward error ‖r‖∞ / (‖Ã‖∞ ‖y‖∞ + ‖b̃‖∞).
fn residual(sys: &ScaledSystem<'_>, y: &[f64], ws: &mut SolveWorkspace, b_inf: f64) -> (f64, f64, f64) {
    let SolveWorkspace { b, r, .. } = ws;
    r.copy_from_slice(b);
    let mut y_inf = 0.0f64;
    for (j, &yj) in y.iter().enumerate() {
        y_inf = y_inf.max(yj.abs());
        if yj == 0.0 {
            continue;
        }
        let col = sys.col_ptr[j]..sys.col_ptr[j + 1];
        for (&a, &i) in sys.values[col.clone()].iter().zip(&sys.row_idx[col]) {
            r[i] -= a * yj;
        }
    }
    let r_inf = r.iter().fold(0.0f64, |m, ri| m.max(ri.abs()));
    let norm = scaled_norm(r.iter().zip(sys.scale).map(|(ri, s)| ri / s));
    (norm, scaled_norm(r.iter().copied()), r_inf / (sys.norm_inf * y_inf + b_inf))
}

/// The Euclidean norm, scaled by the largest entry so that no square overflows or
/// underflows (a load of 1e-300 or 1e300 has a norm like any other).
fn scaled_norm(v: impl Iterator<Item = f64> + Clone) -> f64 {
    let m = v.clone().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return if v.clone().any(f64::is_nan) { f64::NAN } else { m };
    }
    m * v.map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// Solves `A x = b` in place through the scaled system `S A S (S⁻¹ x) = S b`:
/// `factor_solve` applies the factor of `S A S` in place, then refinement steps run (at
/// most `max_steps`) while the backward error is above `target` and each step at least
/// halves the residual. Returns ‖Ax − b‖/‖b‖, the same on the scaled system
/// ‖S(b − Ax)‖/‖Sb‖ (the one [`MAX_RELATIVE_RESIDUAL`] bounds), the number of steps taken
/// and the final normwise backward error.
pub(super) fn solve_refined(
    sys: &ScaledSystem<'_>,
    rhs: &mut [f64],
    ws: &mut SolveWorkspace,
    (target, max_steps): (f64, usize),
    factor_solve: impl Fn(&mut [f64], &mut MemStack),
) -> (f64, f64, usize, f64) {
    let bnorm = scaled_norm(rhs.iter().copied());
    if bnorm == 0.0 {
        rhs.fill(0.0);
        return (0.0, 0.0, 0, 0.0);
    }
    let mut b_inf = 0.0f64;
    for ((bi, yi), s) in ws.b.iter_mut().zip(rhs.iter_mut()).zip(sys.scale) {
        *bi = *yi * s;
        *yi = *bi;
        b_inf = b_inf.max(bi.abs());
    }
    let b_scaled = scaled_norm(ws.b.iter().copied());
    let y = rhs;
    factor_solve(y, MemStack::new(&mut ws.mem));
    let (mut norm, mut norm_scaled, mut eta) = residual(sys, y, ws, b_inf);
    let mut steps = 0;
    while eta > target && steps < max_steps {
        steps += 1;
        ws.dx.copy_from_slice(&ws.r);
        factor_solve(&mut ws.dx, MemStack::new(&mut ws.mem));
        for (yi, di) in y.iter_mut().zip(&ws.dx) {
            *yi += di;
        }
        let (new_norm, new_scaled, new_eta) = residual(sys, y, ws, b_inf);
        if new_norm.is_nan() || new_norm > norm {
            // Worse (or NaN): step back and stop.
            for (yi, di) in y.iter_mut().zip(&ws.dx) {
                *yi -= di;
            }
            break;
        }
        // Go on only while a step at least halves the residual.
        let progress = new_norm <= 0.5 * norm;
        norm = new_norm;
        norm_scaled = new_scaled;
        eta = new_eta;
        if !progress {
            break;
        }
    }
    for (yi, s) in y.iter_mut().zip(sys.scale) {
        *yi *= s;
    }
    (norm / bnorm, norm_scaled / b_scaled, steps, eta)
}

/// Conjugate gradients on the scaled system `S A S y = S b` (symmetric positive definite)
/// in double precision, preconditioned by `precond` (the solve with a single-precision
/// Cholesky factor of `S A S`), for at most `max_iter` iterations. The normwise backward
/// error of the true residual must end at most `accept` (the target of the
/// double-precision Cholesky path); the iterations aim at `aim` (below: the round-off
/// level a double-precision factor reaches in one solve) and stop earlier when the true
/// residual stagnates there. The first preconditioned solve alone is the start (as one
/// solve with a double factor); each iteration then costs one preconditioned solve and one
/// product by `A`. When the recurrence's residual reaches `aim`, the true residual
/// `S b − S A S y` is computed and the iterations go on from it while it still at least
/// halves. Returns ‖Ax − b‖/‖b‖, ‖S(b − Ax)‖/‖Sb‖, the iterations and whether `accept` was
/// met (`false`: not within `max_iter`, or a breakdown `pᵀAp ≤ 0`, `rᵀz ≤ 0` or NaN, which
/// the caller answers by falling back to a double factor).
pub(super) fn solve_pcg(
    sys: &ScaledSystem<'_>,
    rhs: &mut [f64],
    ws: &mut SolveWorkspace,
    (aim, accept, max_iter): (f64, f64, usize),
    precond: impl Fn(&mut [f64], &mut MemStack),
) -> (f64, f64, usize, bool) {
    let n = rhs.len();
    let bnorm = scaled_norm(rhs.iter().copied());
    if bnorm == 0.0 {
        rhs.fill(0.0);
        return (0.0, 0.0, 0, true);
    }
    let mut b_inf = 0.0f64;
    for ((bi, yi), s) in ws.b.iter_mut().zip(rhs.iter_mut()).zip(sys.scale) {
        *bi = *yi * s;
        *yi = *bi;
        b_inf = b_inf.max(bi.abs());
    }
    let b_scaled = scaled_norm(ws.b.iter().copied());
    let y = rhs;
    precond(y, MemStack::new(&mut ws.mem));
    let (mut norm, mut norm_scaled, mut eta) = residual(sys, y, ws, b_inf);
    ws.p.resize(n, 0.0);
    ws.q.resize(n, 0.0);
    let mut iterations = 0;
    // z = M r in `dx`; p = z.
    let mut restart = true;
    let mut rz = 0.0;
    // The backward error of the last true residual.
    let mut checked = eta;
    while eta.is_finite() && eta > aim && iterations < max_iter {
        if restart {
            ws.dx.copy_from_slice(&ws.r);
            precond(&mut ws.dx, MemStack::new(&mut ws.mem));
            ws.p.copy_from_slice(&ws.dx);
            rz = dot(&ws.r, &ws.dx);
            restart = false;
        }
        iterations += 1;
        mat_vec(sys, &ws.p, &mut ws.q);
        let pq = dot(&ws.p, &ws.q);
        // A breakdown: `A` or the preconditioner is not positive definite (numerically).
        if !(pq > 0.0 && rz > 0.0 && rz.is_finite()) {
            break;
        }
        let alpha = rz / pq;
        let mut y_inf = 0.0f64;
        let mut r_inf = 0.0f64;
        for (((yi, ri), pi), qi) in y.iter_mut().zip(ws.r.iter_mut()).zip(&ws.p).zip(&ws.q) {
            *yi += alpha * pi;
            *ri -= alpha * qi;
            y_inf = y_inf.max(yi.abs());
            r_inf = r_inf.max(ri.abs());
        }
        let eta_recurrence = r_inf / (sys.norm_inf * y_inf + b_inf);
        if !eta_recurrence.is_finite() {
            break;
        }
        if eta_recurrence <= aim {
            // The recurrence may drift from the true residual: check it, and go on from
            // the true one unless it has stagnated at round-off.
            (norm, norm_scaled, eta) = residual(sys, y, ws, b_inf);
            restart = true;
            if eta <= accept && eta > 0.5 * checked {
                break;
            }
            checked = eta;
            continue;
        }
        ws.dx.copy_from_slice(&ws.r);
        precond(&mut ws.dx, MemStack::new(&mut ws.mem));
        let rz_new = dot(&ws.r, &ws.dx);
        let beta = rz_new / rz;
        rz = rz_new;
        for (pi, zi) in ws.p.iter_mut().zip(&ws.dx) {
            *pi = zi + beta * *pi;
        }
    }
    if !restart {
        (norm, norm_scaled, eta) = residual(sys, y, ws, b_inf);
    }
    for (yi, s) in y.iter_mut().zip(sys.scale) {
        *yi *= s;
    }
    (norm / bnorm, norm_scaled / b_scaled, iterations, eta <= accept)
}

/// GMRES on the scaled system `S A S y = S b` right-preconditioned by `precond` (the solve
/// with the factor of an earlier matrix, [`super::kept`]), from `y₀ = M⁻¹ S b`, to
/// `‖S(b − A x)‖ ≤ tol ‖S b‖` in at most `max_it` iterations after the first
/// preconditioned solve ([`super::dense_block::gmres`]; right preconditioning: the residual
/// it checks is the true one). `symmetric`: the values are symmetric (the product is then
/// parallel by columns). Returns ‖Ax − b‖/‖b‖, ‖S(b − Ax)‖/‖Sb‖, the iterations and
/// whether it converged (that residual at `tol`, or the normwise backward error at
/// [`ETA_TARGET_CHOLESKY`]); `rhs` holds `x` (the best iterate when it did not).
pub(super) fn solve_gmres(
    sys: &ScaledSystem<'_>,
    symmetric: bool,
    rhs: &mut [f64],
    ws: &mut SolveWorkspace,
    (tol, max_it): (f64, usize),
    precond: impl Fn(&mut [f64], &mut MemStack),
) -> (f64, f64, usize, bool) {
    let bnorm = scaled_norm(rhs.iter().copied());
    if bnorm == 0.0 {
        rhs.fill(0.0);
        return (0.0, 0.0, 0, true);
    }
    let mut b_inf = 0.0f64;
    for (bi, (yi, s)) in ws.b.iter_mut().zip(rhs.iter().zip(sys.scale)) {
        *bi = *yi * s;
        b_inf = b_inf.max(bi.abs());
    }
    let b_scaled = scaled_norm(ws.b.iter().copied());
    let mem = std::cell::RefCell::new(&mut ws.mem);
    let apply = |p: &[f64], q: &mut [f64]| {
        if symmetric {
            mat_vec(sys, p, q)
        } else {
            q.fill(0.0);
            for (j, &pj) in p.iter().enumerate() {
                if pj != 0.0 {
                    let col = sys.col_ptr[j]..sys.col_ptr[j + 1];
                    for (&a, &i) in sys.values[col.clone()].iter().zip(&sys.row_idx[col]) {
                        q[i] += a * pj;
                    }
                }
            }
        }
    };
    let (y, iterations, converged) =
        super::dense_block::gmres(apply, |v| precond(v, MemStack::new(&mut mem.borrow_mut())), &ws.b, tol, max_it);
    let (norm, norm_scaled, eta) = residual(sys, &y, ws, b_inf);
    for ((xi, yi), s) in rhs.iter_mut().zip(&y).zip(sys.scale) {
        *xi = yi * s;
    }
    // Converged: the relative residual at `tol`, or the normwise backward error at the
    // target the direct Cholesky and condensed solves stop refining at (a stale factor's
    // round-off can keep the relative residual of an ill-conditioned system above `tol`
    // where the direct solve itself stops, e.g. at 1e-12).
    let ok = (converged && norm_scaled <= tol * b_scaled) || eta <= ETA_TARGET_CHOLESKY;
    (norm / bnorm, norm_scaled / b_scaled, iterations, ok)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `q = S A S p` for the symmetric scaled matrix: each entry a column's dot product (the
/// pattern stores both triangles), in parallel.
fn mat_vec(sys: &ScaledSystem<'_>, p: &[f64], q: &mut [f64]) {
    use rayon::prelude::*;
    let (cp, ri, v) = (sys.col_ptr, sys.row_idx, sys.values);
    q.par_iter_mut().enumerate().with_min_len(4096).for_each(|(j, qj)| {
        *qj = (cp[j]..cp[j + 1]).map(|k| v[k] * p[ri[k]]).sum();
    });
}
