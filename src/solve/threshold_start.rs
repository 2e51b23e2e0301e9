//! The friction thresholds a quasi-static load step starts from: the last step's, or their
//! extrapolation in the load factor from the last converged steps where they drift.
//!
//! The friction fixed point (`contact_loops`, λ̄ ← min(λ, 0)) contracts by a roughly
//! constant factor a pass, so its pass count is set by how far the step's start is from
//! its answer. Started from the last step's thresholds, that is the step-to-step change of
//! the pressure: with Archard wear (issue 14) the worn gap moves the pressure by ~5e-3
//! relative a step, 5–6 passes. When the pressure drifts smoothly, the Lagrange
//! extrapolation through the last k + 1 steps (k = 1: the line through the last two,
//! λ̄₀(n) = λ̄(n−1) + (t_n − t_{n−1}) / (t_{n−1} − t_{n−2}) · (λ̄(n−1) − λ̄(n−2)); k = 2:
//! the parabola through the last three) starts it at the drift's (k + 1)-th difference
//! instead. Only the start changes: the passes still iterate to the same fixed point and
//! `tol_friction` still decides.
//!
//! Per point, an extrapolation is used where the point was closed with a nonzero
//! threshold at each of those steps and is closed now, and where it stays a drift (each
//! step's change, and the extrapolated one, at most half the threshold; the result ≤ 0);
//! elsewhere the next lower order's start. Over the whole interface the order is chosen by
//! what paid: after each step every candidate start (the last thresholds, order 1, order
//! 2) is compared with the step's answer, and the next step starts from the closest one's
//! order (the first steps after a change of regime, pressing then sliding, or a reversal
//! of a fretting load: the last thresholds).
//!
//! Where: the models with wear (Archard) on a crack or pair with friction, the steady
//! drift it was measured on (`docs/performance.md`, "Threshold start"). Off with
//! `FISSURE_THRESHOLD_START=previous` (the comparisons' switch).
//!
//! Entry point: [`ThresholdStart`] ([`ThresholdStart::new`], then per step
//! [`ThresholdStart::start_step`] before the contact loops and [`ThresholdStart::end_step`]
//! after them).

use crate::contact::law::PointState;
use crate::contact::points::ContactPoints;

/// The largest change of a point's threshold over one step, relative to the threshold,
/// that is extrapolated (beyond it the point's pressure is not drifting).
const DRIFT_MAX: f64 = 0.5;

/// The highest order of the extrapolation (2: the parabola through the last three steps).
const MAX_ORDER: usize = 2;

/// The thresholds of the last converged steps and which extrapolation pays.
pub struct ThresholdStart {
    /// Points whose crack has friction (the others keep their threshold).
    frictional: Vec<bool>,
    /// (t, λ̄ per point) at the end of the last `MAX_ORDER + 1` steps, the last first.
    history: Vec<(f64, Vec<f64>)>,
    /// The order of the start that came closest to the last judged step's answer (0: the
    /// last thresholds, until an extrapolation has done better: the first steps after a
    /// change of regime, pressing then sliding, are not a drift).
    order: usize,
    /// This step's candidate starts, by order (0: the last thresholds), kept to judge them
    /// against the step's answer.
    candidates: Vec<Vec<f64>>,
}

impl ThresholdStart {
    /// None when the model has no wear with friction, or the switch says `previous`.
    pub fn new(points: &ContactPoints) -> Option<ThresholdStart> {
        let wanted = points.cracks.iter().any(|c| c.law.wear.is_some() && c.law.friction > 0.0);
        let off = std::env::var("FISSURE_THRESHOLD_START").is_ok_and(|v| v == "previous");
        (wanted && !off).then(|| ThresholdStart {
            frictional: points.points.iter().map(|p| points.cracks[p.crack].law.friction > 0.0).collect(),
            history: Vec::new(),
            order: 0,
            candidates: Vec::new(),
        })
    }

    /// Before the contact loops of the step at load factor `t`: sets the starting
    /// thresholds in `state` (whose `lam_bar` are the last step's answer). Returns the
    /// order of the start used (0: the last thresholds).
    pub fn start_step(&mut self, t: f64, state: &mut [PointState]) -> usize {
        let previous: Vec<f64> = state.iter().map(|s| s.lam_bar).collect();
        self.candidates = vec![previous];
        // The steps of the history that belong to this model, in increasing load factor.
        let usable = self
            .history
            .iter()
            .take_while(|(_, l)| l.len() == state.len())
            .scan(t, |next, (tk, _)| {
                let ok = *tk < *next;
                *next = *tk;
                ok.then_some(())
            })
            .count();
        if usable == 0 || self.history[0].1 != self.candidates[0] {
            return 0;
        }
        for k in 1..=MAX_ORDER.min(usable - 1) {
            let ts: Vec<f64> = self.history[..=k].iter().map(|h| h.0).collect();
            // Lagrange's weights of the last k + 1 steps at t.
            let w: Vec<f64> =
                (0..=k).map(|i| (0..=k).filter(|&j| j != i).map(|j| (t - ts[j]) / (ts[i] - ts[j])).product()).collect();
            let lower = &self.candidates[k - 1];
            let next: Vec<f64> = (0..state.len())
                .map(|p| {
                    let vals: Vec<f64> = self.history[..=k].iter().map(|h| h.1[p]).collect();
                    let a = vals[0];
                    let drifting = vals.iter().all(|&v| v < 0.0)
                        && vals.windows(2).all(|d| (d[0] - d[1]).abs() <= DRIFT_MAX * a.abs());
                    if !self.frictional[p] || !state[p].contact || !drifting {
                        return lower[p];
                    }
                    let e: f64 = w.iter().zip(&vals).map(|(w, v)| w * v).sum();
                    if e > 0.0 || (e - a).abs() > DRIFT_MAX * a.abs() {
                        lower[p]
                    } else {
                        e
                    }
                })
                .collect();
            self.candidates.push(next);
        }
        let used = self.order.min(self.candidates.len() - 1);
        for (s, &v) in state.iter_mut().zip(&self.candidates[used]) {
            s.lam_bar = v;
        }
        used
    }

    /// After the step at load factor `t` converged with the thresholds in `state`:
    /// records them, and judges this step's candidate starts against its answer.
    pub fn end_step(&mut self, t: f64, state: &[PointState]) {
        let now: Vec<f64> = state.iter().map(|s| s.lam_bar).collect();
        let dist = |v: &[f64]| v.iter().zip(&now).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
        let d: Vec<f64> = self.candidates.iter().map(|c| dist(c)).collect();
        // The closest start; a tie keeps the lower order (an extrapolation that changed
        // no point says nothing).
        if let Some(best) = (0..d.len()).min_by(|&a, &b| d[a].total_cmp(&d[b]).then(a.cmp(&b))) {
            if d.len() > 1 && !(d[1..].iter().all(|&x| x == d[0])) {
                self.order = best;
            }
        }
        self.candidates.clear();
        self.history.insert(0, (t, now));
        self.history.truncate(MAX_ORDER + 1);
    }
}
