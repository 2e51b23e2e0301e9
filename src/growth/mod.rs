//! Crack growth, the pieces the growth loop (`run::growth::run_growth`) puts together:
//! the propagation criteria and the advance of each front point ([`criteria`]), the Paris
//! law and the cycles of an increment ([`fatigue`]), and the growing 2D crack as an
//! explicit polyline ([`polyline`]: one segment appended at each growing tip, turned into
//! the `shape = "mesh"` crack of [`crate::levelset::explicit`], whose level sets follow).
//!
//! Entry points: [`Propagation`] (the `[propagation]` options), [`criteria::plan`]
//! (K at every tip → kink angle, K_eq and advance of each), [`fatigue::increment_cycles`],
//! [`polyline::GrowingCurve`].
//!
//! Conventions: `docs/conventions.md`, "Crack growth". The kink angle θ is measured in the
//! tip frame from e1 towards e2 (counter-clockwise in 2D, where e3 = +z), so the new
//! segment runs along cos θ e1 + sin θ e2.

pub mod criteria;
pub mod fatigue;
pub mod polyline;
pub mod surface;

/// The direction criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// Maximum hoop stress (Erdogan & Sih 1963).
    MaxHoopStress,
    /// Maximum energy release rate over the kink angle (with the kinked-tip K of the
    /// hoop-stress field, [`criteria::kinked_k`]).
    MaxEnergyRelease,
}

impl Criterion {
    pub fn name(self) -> &'static str {
        match self {
            Criterion::MaxHoopStress => "max_hoop_stress",
            Criterion::MaxEnergyRelease => "max_energy_release",
        }
    }
}

/// Fatigue growth by the Paris law da/dN = C ΔK_eq^m, ΔK_eq of the cycle's effective
/// ranges ([`fatigue::ranges`]; (1 − R) K_eq with `load_ratio` R).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fatigue {
    pub c: f64,
    pub m: f64,
    /// R = K_min / K_max, in [0, 1) (0 when `min_load_factor` is given).
    pub load_ratio: f64,
    /// f < 1: the cycle's minimum is the case's loads × f (one more load step at
    /// t = f · t_max, solved when the model has contact; f ≥ 0 without it).
    pub min_load_factor: Option<f64>,
    /// ΔK_th: a point with ΔK_eq below it does not advance.
    pub threshold: f64,
}

/// The `[propagation]` options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Propagation {
    pub criterion: Criterion,
    /// Δa_max: the advance of the point of largest driving force, per increment.
    pub increment: f64,
    /// Growth increments (the run has steps + 1 solves).
    pub steps: usize,
    /// p in Δa = Δa_max (K_eq / K_eq,max)^p (quasi-static growth; fatigue uses m).
    pub exponent: f64,
    /// K_c: a point whose K_eq exceeds it stops the growth (unstable).
    pub fracture_toughness: Option<f64>,
    /// Stop once a tip has grown by this length in total.
    pub stop_length: Option<f64>,
    /// Quasi-static: a point with K_eq at or below it does not advance.
    pub threshold: f64,
    pub fatigue: Option<Fatigue>,
}

impl Propagation {
    /// The exponent p of the advance: m in fatigue, `exponent` otherwise.
    pub fn advance_exponent(&self) -> f64 {
        self.fatigue.map_or(self.exponent, |f| f.m)
    }
}
