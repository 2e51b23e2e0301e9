//! The contact zone of a meshed contact pair in small sliding: the paired points that can
//! touch. The other paired points (their master facet within the pairing band, their
//! reference gap beyond the zone's threshold) are *dormant*: held open, with no
//! displacement unknown in their contact terms, so that neither their slave nor their
//! master surface nodes enter the contact elements, the pattern or the condensed factor's
//! dense block. An exact a-posteriori check at every converged step grows the zone where
//! the law would close a dormant point.
//!
//! Entry points: [`ZoneChoice`] (the case's choice, `[[contact_pairs]] zone`),
//! [`initial_gap`] (a contact crack's initial threshold), [`reference_gap`] (the criterion
//! at one paired point) and [`check`] (the dormant points the law would close at a
//! solution, and the grown thresholds).
//!
//! Why the answer is that of the whole band: an open point of the augmented Lagrangian
//! (without asperity layer, wear or the stabilised law's closed terms) adds nothing to the
//! displacement rows and only −λ/ρ_n and −Λ to its multiplier rows, whatever its gap and
//! slip; a dormant point adds exactly those (the kernel evaluates it unpaired, with the
//! friction law on every packet of its terms as a paired point,
//! [`super::pairing::Pairing::law_terms`]). So while every dormant point is open in the
//! whole-band problem, both problems have the same equations on the same unknowns (the
//! displacement couplings a dormant point would add are structural zeros), and the loops
//! converge to the same discrete solution. The check evaluates each dormant point with its
//! true kinematics (its master point of the initial pairing) and the law's own contact
//! indicator, λ − ρ_n d_n ≤ 0, as the active-set update would: if it says open at every
//! dormant point (with a margin of [`MARGIN`] cells on the gap), the converged state is a
//! fixed point of the whole-band loops; if not, the zone grows and the step is redone from
//! its start.

use super::law::Method;
use super::pairing::{MasterPoint, Pairing, PointPairing};
use super::points::{ContactCrack, ContactPoint, ContactPoints};
use super::state::PointValues;

/// The contact zone of a pair (`[[contact_pairs]] zone`, `zone_gap`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ZoneChoice {
    /// Every paired point (the whole pairing band).
    Band,
    /// The points whose reference gap is at most [`AUTO_GAP`] cells.
    Auto,
    /// The points whose reference gap is at most this length.
    Gap(f64),
}

/// The automatic zone's initial threshold on the reference gap, in cells (the pair's mean
/// cell size h): a quarter of the pairing band (2 h), in 3D. In 2D the automatic zone is
/// the whole band: the dense block is a line of nodes there (cheap), and the approach of a
/// 2D contact grows with the log of the bodies' size, not bounded by a cell (the 2D Hertz
/// bench row at h/2: 46 points beyond it touched, one regrowth, the step twice). See
/// `docs/contact-algorithms.md`, "The contact zone of a meshed pair".
pub const AUTO_GAP: f64 = 0.5;

/// A dormant point within this many cells of touching (its gap −d_n below it) grows the
/// zone even if the law still calls it open: the law's decision there hangs on the
/// round-off of the solve.
pub const MARGIN: f64 = 1e-6;

/// Regrowths of a step after which a zone that still has dormant points the law would
/// close is an error. Each regrowth at least doubles the threshold.
pub const MAX_REGROWTHS: usize = 4;

/// The initial zone's threshold on the reference gap of contact crack `cc` in a mesh of
/// dimension `dim` (a length); infinite (every paired point) for cracks, pairs that re-pair
/// (`sliding = "large"`), laws without multipliers (penalty), with an asperity layer or
/// wear (their open points are not inert: the layer acts before contact, the worn gap
/// moves), `zone = "band"`, and `zone = "auto"` in 2D (see [`AUTO_GAP`]).
pub fn initial_gap(cc: &ContactCrack, dim: usize) -> f64 {
    let inert_open = cc.law.method != Method::Penalty
        && cc.law.asperity.is_none()
        && cc.law.wear.is_none()
        && cc.law.rho_projected == 0.0;
    if cc.pair.is_none() || cc.repair || !inert_open {
        return f64::INFINITY;
    }
    match cc.zone {
        ZoneChoice::Band => f64::INFINITY,
        ZoneChoice::Auto if dim == 2 => f64::INFINITY,
        ZoneChoice::Auto => AUTO_GAP * cc.cell_size,
        ZoneChoice::Gap(g) => g,
    }
}

/// The reference gap −d_n of point `p` paired with `m` in the initial configuration (no
/// displacement, no wear: ⟦u⟧ = Y − X), with the law's initial gap g₀.
pub fn reference_gap(cc: &ContactCrack, p: &ContactPoint, m: &MasterPoint) -> f64 {
    let jump = [m.x[0] - p.x[0], m.x[1] - p.x[1], m.x[2] - p.x[2]];
    -cc.law.penetration(jump, p.normal, 0.0)
}

/// The outcome of a failed check: the dormant points the law would close (or that are
/// within [`MARGIN`] of touching), per contact crack, and the grown thresholds.
#[derive(Debug, Clone)]
pub struct Growth {
    /// Per contact crack: its dormant points that fail the check.
    pub violations: Vec<usize>,
    /// Per contact crack: the threshold to pair with next (unchanged where nothing failed).
    pub zone: Vec<f64>,
    /// Per contact crack: the largest reference gap among its failing points (0: none).
    pub largest_gap: Vec<f64>,
}

/// The check of a converged state (`vals`: [`super::state::point_values`] with `pairing`,
/// which gives the dormant points their true kinematics): `None` if every dormant point is
/// open by the law's contact indicator with a margin; else the grown zone: each failing
/// crack's threshold becomes at least twice its old one and twice the largest reference
/// gap of its failing points.
pub fn check(points: &ContactPoints, pairing: &Pairing, vals: &[PointValues]) -> Option<Growth> {
    let n = points.cracks.len();
    let mut g = Growth { violations: vec![0; n], zone: pairing.zone.clone(), largest_gap: vec![0.0; n] };
    g.zone.resize(n, f64::INFINITY);
    let mut any = false;
    for (pi, (p, v)) in points.points.iter().zip(vals).enumerate() {
        let PointPairing::Dormant(m) = pairing.points[pi] else { continue };
        let cc = &points.cracks[p.crack];
        let closes = cc.law.contact_indicator(v.lambda, v.d_n) || v.d_n > -MARGIN * cc.cell_size;
        if closes {
            any = true;
            g.violations[p.crack] += 1;
            g.largest_gap[p.crack] = g.largest_gap[p.crack].max(reference_gap(cc, p, &m));
        }
    }
    if !any {
        return None;
    }
    for c in 0..n {
        if g.violations[c] > 0 {
            g.zone[c] = (2.0 * g.zone[c]).max(2.0 * g.largest_gap[c]);
        }
    }
    Some(g)
}

/// Per point: dormant and closed by its law's contact indicator at `vals` (the status the
/// active-set update would give it in the whole band); empty when no point is dormant.
/// The first active set's gap bisection counts these as closed (`solve::contact_loops`).
pub fn would_close(points: &ContactPoints, vals: &[PointValues]) -> Vec<bool> {
    if !vals.iter().any(|v| v.dormant) {
        return Vec::new();
    }
    points
        .points
        .iter()
        .zip(vals)
        .map(|(p, v)| v.dormant && points.cracks[p.crack].law.contact_indicator(v.lambda, v.d_n))
        .collect()
}
