//! The interior response of the condensed contact factor when its bulk stage is in single
//! precision: the exact `K_II⁻¹` that the deferred Newton solves need, by conjugate
//! gradients in double precision preconditioned by the single-precision halves.
//!
//! Entry points: [`InteriorSync`] (the deferred solves' record of the crack corrections
//! whose interior response is known exactly) and [`pcg`], used by
//! [`super::condensed::CondensedFactor`] (`solve_deferred`, `apply_pending`).
//!
//! A deferred Newton solve (`CondensedFactor::solve_deferred`) corrects the crack rows of
//! the residual, computed with the interior values of the last full solve, by the interior
//! response to the crack corrections `Δ` since then: `+ K_cI K_II⁻¹ K_Ic Δ`. With a bulk
//! in double precision that term is `(K_cc − S_c) Δ`, `S_c` the Schur complement of the
//! bulk (`base`), exact to round-off. With halves factorised in single precision the
//! computed `S̃_c` is off by `E = S̃_c − S_c`, of relative size about `ε₃₂ κ` (and more in
//! the directions of a body held only through contact, whose rigid motions the crack
//! shift σ holds: `S_c` is zero there and `S̃_c` is `(S_c + σ) − σ` in single precision).
//! The Newton matrix `F̃ = S̃_c + C` may be that far off: it is a preconditioner (an
//! inexact Newton step converges to the same answer, a little more slowly). The residual
//! may not: a loop that converges on the residual `r + E Δ` converges to the answer of a
//! perturbed problem (measured on the 3D Hertz sphere bench row: p0 24% off, a 1.5% off,
//! `docs/performance.md`, "The condensed bulk stage in single precision").
//!
//! So the residual's interior term is computed exactly: `Δ = Δ_s + d`, with `Δ_s` the
//! corrections whose exact term `h_s = K_cI K_II⁻¹ K_Ic Δ_s` and interior response
//! `δ_s = −K_II⁻¹ K_Ic Δ_s` are known (conjugate gradients on `K_II`, SPD, preconditioned
//! by the single-precision halves: [`pcg`], to the backward error of the double-precision
//! path), and `d` the corrections since, whose term `(K_cc − S̃_c) d` is single-precision
//! accurate. A deferred solve brings `d` into `Δ_s` (one [`pcg`] solve, "a sync") unless
//! the estimated error of its term, `ρ ‖(K_cc − S̃_c) d‖` (`ρ` the largest relative error
//! the syncs so far measured, 1 before the first), is below [`SYNC_FORCING`] times the
//! residual being solved: the Newton step is then exact to that fraction (an inexact
//! Newton step with that forcing term), and a converging loop, whose residual falls, syncs
//! before its last correction. The end of the step's interior response
//! (`apply_pending`) is `δ_s` plus the exact response to the rest.
//!
//! The cost is one conjugate-gradient solve on the bulk (a few single-precision forward
//! and backward substitutions in both halves) per sync, where the double-precision bulk
//! needs none: about one per Newton loop of the contact loops.

/// The forcing term of the deferred solves with a single-precision bulk: a deferred
/// solve's residual may carry an estimated error of at most this fraction of itself.
pub(crate) const SYNC_FORCING: f64 = 1e-6;

/// Conjugate-gradient iterations allowed for an exact interior response.
pub(crate) const PCG_MAX_ITERATIONS: usize = 30;

/// The crack corrections whose interior response is known exactly (see the module
/// documentation), in the positions of the condensed factor (interior `0..ni`, crack
/// unknowns `0..nc`, scaled units).
#[derive(Debug, Default)]
pub(crate) struct InteriorSync {
    /// `Δ_s`: the crack corrections brought in.
    pub(crate) delta: Vec<f64>,
    /// `δ_s = −K_II⁻¹ K_Ic Δ_s`, on the interior positions.
    pub(crate) response: Vec<f64>,
    /// `h_s = K_cI K_II⁻¹ K_Ic Δ_s = −K_cI δ_s`, on the crack unknowns.
    pub(crate) term: Vec<f64>,
    /// The largest relative error of the single-precision term measured at a sync (1
    /// before the first).
    pub(crate) rho: f64,
    /// Syncs and conjugate-gradient iterations since the bulk stage (for the log).
    pub(crate) syncs: usize,
    pub(crate) iterations: usize,
}

impl InteriorSync {
    /// Nothing brought in, for `ni` interior positions and `nc` crack unknowns (`ρ` kept).
    pub(crate) fn reset(&mut self, ni: usize, nc: usize) {
        self.delta.clear();
        self.delta.resize(nc, 0.0);
        self.response.clear();
        self.response.resize(ni, 0.0);
        self.term.clear();
        self.term.resize(nc, 0.0);
        if self.rho == 0.0 {
            self.rho = 1.0;
        }
    }
}

/// Conjugate gradients on the symmetric positive definite `A` (`apply(v, out)`: `out = A v`)
/// preconditioned by `precond` (in place), for `A w = b`, until the normwise backward error
/// `‖b − A w‖∞ / (‖A‖∞ ‖w‖∞ + ‖b‖∞)` (`norm_inf` = `‖A‖∞`) of the true residual is at most
/// `target` or stops halving after it is within `accept`. `Ok((w, iterations))`, or
/// `Err(backward error)` when `accept` is not met within [`PCG_MAX_ITERATIONS`] or on a
/// breakdown.
pub(crate) fn pcg(
    apply: impl Fn(&[f64], &mut [f64]),
    precond: impl Fn(&mut [f64]),
    b: &[f64],
    norm_inf: f64,
    (target, accept): (f64, f64),
) -> Result<(Vec<f64>, usize), f64> {
    let n = b.len();
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let b_inf = inf(b);
    if b_inf == 0.0 {
        return Ok((vec![0.0; n], 0));
    }
    let eta_of = |w: &[f64], r: &[f64]| inf(r) / (norm_inf * inf(w) + b_inf);
    let true_residual = |w: &[f64], r: &mut Vec<f64>| {
        apply(w, r);
        for (ri, bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
    };
    let mut w = b.to_vec();
    precond(&mut w);
    let mut r = vec![0.0; n];
    true_residual(&w, &mut r);
    let mut eta = eta_of(&w, &r);
    let mut checked = eta;
    let mut iterations = 0;
    let (mut p, mut q, mut z) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut restart = true;
    let mut rz = 0.0;
    while eta.is_finite() && eta > target && iterations < PCG_MAX_ITERATIONS {
        if restart {
            z.copy_from_slice(&r);
            precond(&mut z);
            p.copy_from_slice(&z);
            rz = dot(&r, &z);
            restart = false;
        }
        iterations += 1;
        apply(&p, &mut q);
        let pq = dot(&p, &q);
        if !(pq > 0.0 && rz > 0.0 && rz.is_finite()) {
            break;
        }
        let alpha = rz / pq;
        for (((wi, ri), pi), qi) in w.iter_mut().zip(r.iter_mut()).zip(&p).zip(&q) {
            *wi += alpha * pi;
            *ri -= alpha * qi;
        }
        let eta_recurrence = eta_of(&w, &r);
        if !eta_recurrence.is_finite() {
            break;
        }
        if eta_recurrence <= target {
            // The recurrence may drift from the true residual: check it, and go on from the
            // true one unless it has stagnated at round-off.
            true_residual(&w, &mut r);
            eta = eta_of(&w, &r);
            restart = true;
            if eta <= accept && eta > 0.5 * checked {
                break;
            }
            checked = eta;
            continue;
        }
        z.copy_from_slice(&r);
        precond(&mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for (pi, zi) in p.iter_mut().zip(&z) {
            *pi = zi + beta * *pi;
        }
    }
    if !restart {
        true_residual(&w, &mut r);
        eta = eta_of(&w, &r);
    }
    if eta <= accept {
        Ok((w, iterations))
    } else {
        Err(eta)
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
