//! Contact statuses carried from one crack geometry to the next (crack growth): the
//! converged state of every contact point is kept with where the point is, and put back
//! on the points of a rebuilt model that sit at the same place — the same crack, the same
//! cell and the same position to round-off (10⁻⁶ of the crack's cell size). Those are the
//! points of the part of the crack that the growth did not change: its cells are cut as
//! before, so their facets and contact points are the same. A point that moved or is new
//! (in the cells of the old front and of the new segment or strip) keeps the default
//! start (the case's `start_closed` and `initial_threshold`). Taking the nearest old
//! point's state within ½, 1 or 2 cells instead (so that the points of the old front's
//! cells, and the first ones of a new segment, inherit too) was measured on the contact
//! growth test (`tests/crack_growth_2d.rs`): no fewer iterations than the exact match
//! (Newton iterations of entries 1–3: 60 exact, 57, 64, 62).
//!
//! What is carried: the contact status χ_c and the frozen friction threshold λ̄. The rest
//! of a point's state is the step's own (the jump at the start of the step, the frozen
//! stick/slip lock, the penalty law's Λ at the start of the first step, all reset), and
//! wear is refused with growth.
//!
//! Entry points: [`CarriedStatuses::capture`] (after a converged step),
//! [`CarriedStatuses::apply`] (on the start state of the next geometry's solve).

use super::law::PointState;
use super::points::ContactPoints;
use std::collections::HashMap;

/// Two points closer than this fraction of their crack's cell size are the same point.
pub const SAME_POINT: f64 = 1e-6;

/// A captured point: its position, contact status χ_c and frozen threshold λ̄.
type Captured = ([f64; 3], bool, f64);

/// The converged statuses of a set of contact points, by crack and cell.
#[derive(Debug, Clone, Default)]
pub struct CarriedStatuses {
    /// (contact crack, model crack, cell) → the captured points of that cell: position,
    /// contact status, λ̄.
    by_cell: HashMap<(usize, usize, usize), Vec<Captured>>,
}

impl CarriedStatuses {
    /// The statuses `state` of `points` (one state per point, as the loops hold them).
    pub fn capture(points: &ContactPoints, state: &[PointState]) -> Self {
        let mut by_cell: HashMap<(usize, usize, usize), Vec<Captured>> = HashMap::new();
        for (p, s) in points.points.iter().zip(state) {
            by_cell
                .entry((p.crack, points.cracks[p.crack].crack, p.cell))
                .or_default()
                .push((p.x, s.contact, s.lam_bar));
        }
        CarriedStatuses { by_cell }
    }

    /// Sets the contact status and threshold of every point of `points` that has a
    /// captured point at the same place; returns how many were set. The others keep
    /// what `state` holds (the default start).
    pub fn apply(&self, points: &ContactPoints, state: &mut [PointState]) -> usize {
        let mut carried = 0;
        for (p, s) in points.points.iter().zip(state.iter_mut()) {
            let cc = &points.cracks[p.crack];
            let Some(old) = self.by_cell.get(&(p.crack, cc.crack, p.cell)) else { continue };
            let tol = SAME_POINT * cc.cell_size;
            let d2 = |x: &[f64; 3]| (0..3).map(|i| (x[i] - p.x[i]).powi(2)).sum::<f64>();
            if let Some((_, contact, lam_bar)) = old.iter().find(|(x, _, _)| d2(x) <= tol * tol) {
                s.contact = *contact;
                s.lam_bar = *lam_bar;
                carried += 1;
            }
        }
        carried
    }

    /// The number of captured points.
    pub fn len(&self) -> usize {
        self.by_cell.values().map(Vec::len).sum()
    }

    /// Whether no point was captured.
    pub fn is_empty(&self) -> bool {
        self.by_cell.is_empty()
    }
}
