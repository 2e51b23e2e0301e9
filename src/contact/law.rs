//! The pointwise contact law: the gap, the normal law and the Coulomb friction law at one
//! contact point, with their residual and tangent (formulation §5). Pure functions of the
//! point's kinematics, multipliers and frozen state: no geometry, no numbering, no
//! scatter (the kernel, [`super::kernel`], does those).
//!
//! Entry points: [`CrackLaw`] (the law of one crack: [`CrackLaw::penetration`],
//! [`CrackLaw::respond`], [`CrackLaw::contact_indicator`], [`CrackLaw::friction_indicator`]),
//! [`PointState`], [`Status`].
//!
//! ```text
//! gap      d_n = −⟦u⟧·n − g₀ − w                 (d_n > 0: overlap; g₀ initial gap, w wear)
//! contact  χ_c = [g_n ≤ 0],  g_n = λ − ρ_n d_n    (λ ≤ 0: compression)
//! friction χ_f = [|g_τ| ≤ 1], g_τ = Λ + ρ_τ v_τ    (v_τ: tangential jump increment)
//! ```
//!
//! [`CrackLaw::respond`] returns the residual and tangent at one point in the point's own
//! coordinates: s = (n·⟦u⟧, τ₁·⟦u⟧, τ₂·⟦u⟧) for the jump and m = (λ, Λ₁, Λ₂) for the
//! multipliers ([`PointResponse`]). The kernel maps them onto the element's unknowns
//! with J_k (jump of basis function k), n, τ_α and the multiplier interpolation c_j.
//! [`Method::has_multipliers`] says whether a method has λ, Λ unknowns at all.
//!
//! Wear ([`Wear`], Archard): each point carries the wear depths w⁺, w⁻ of its two lips
//! ([`PointState::wear`]); they shift the gap, d_n^w = d_n − (w⁺ + w⁻), through
//! [`PointState::gap_offset`]. The increment of a step is Δw = (k/H)·p·|v_τ| at a point
//! that slides with friction, p the total normal pressure, hard contact plus asperity
//! layer ([`CrackLaw::wear_pressure`], [`CrackLaw::wear_increment`]). With the implicit
//! coupling it is in the gap of the step itself, as a function of the point's λ and v_τ
//! ([`CrackLaw::wear_compliance`]: Δw = q·p with q = (k/H)|v_τ|), with its derivative in λ
//! (and through the worn gap in the layer's traction, [`CrackLaw::layer_worn_gap`]) in the
//! tangent ([`CrackLaw::respond_with_wear`]); with the staggered one the step sees the wear
//! of the previous steps only.

use crate::geometry::vec3::dot;

/// What a contact point remembers between iterations.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointState {
    /// Contact status χ_c, frozen during the Newton loop.
    pub contact: bool,
    /// Frozen friction threshold λ̄ (≤ 0), updated by the fixed point.
    pub lam_bar: f64,
    /// Displacement jump at the start of the load step (for v_τ).
    pub prev_jump: [f64; 3],
    /// Frozen friction status (Some(true) stick, Some(false) slip) while a Newton loop
    /// that cycles between statuses finishes; the outer loop then checks it.
    pub lock: Option<bool>,
    /// The threshold scale λ_ref (a stress ≥ 0) of the point's crack or pair: the largest
    /// |λ̄| of its points when the current Newton loop started
    /// ([`super::state::set_threshold_scales`]); it weighs the Λ rows of the points where
    /// friction does not act ([`CrackLaw::idle_friction_weight`]).
    pub threshold_scale: f64,
    /// The penalty law's tangential state: Λ at the end of the previous step (zero for the
    /// methods with multipliers, whose Λ is an unknown).
    pub big_lambda_start: [f64; 2],
    /// The penalty law's Λ at the end of the last solved step; it becomes
    /// `big_lambda_start` when the next step starts
    /// ([`super::state::start_tangential_state`]), so that the values read after a step
    /// (outputs, statuses) see the Λ the step started from, not its own twice.
    pub big_lambda_end: [f64; 2],
    /// A shift of the gap for this step, d_n = −⟦u⟧·n − g₀ − shift (0 in statics). The
    /// velocity formulation in dynamics sets it so that d_n = 0 is ⟦v⟧_n = 0 at the end of
    /// the step (`solve::dynamics`).
    pub gap_shift: f64,
    /// Dynamics: the shift of the asperity layer's damping base, so that the layer's
    /// d_n − d_n_start reads the normal relative velocity at the end of the time step
    /// divided by the scheme's γ/(βΔt) (`solve::dynamics`, `asperity_rate_bases`);
    /// 0 in statics (the change of the gap over the load step).
    pub layer_rate_shift: f64,
    /// Wear depths (w⁺, w⁻) of the `+` and `−` lips at this point, before the current step
    /// (length ≥ 0; Archard, [`Wear`]).
    pub wear: [f64; 2],
    /// The converged wear increment (w⁺, w⁻) of the last solved step, committed into
    /// `wear` when the next step starts ([`PointState::commit_wear`]).
    pub wear_step: [f64; 2],
    /// The frictional work per unit area dissipated at this point since the start,
    /// ∫ μ|λ||dslip| (with wear only), the last solved step included.
    pub frictional_work: f64,
    /// Large sliding with wear (2D): the `+` lip's wear before the step where this slave
    /// point meets it ([`super::lip_wear`]); `None`: the point faces itself and the gap
    /// reads `wear[0]`.
    pub facing_wear: Option<f64>,
}

impl PointState {
    /// The shift of the gap d_n = −⟦u⟧·n − g₀ − offset during a step: the dynamics' gap
    /// shift plus the wear of both lips before the step (of the `+` lip where this point
    /// meets it, [`PointState::facing_wear`]).
    #[inline]
    pub fn gap_offset(&self) -> f64 {
        self.gap_shift + self.facing_wear.unwrap_or(self.wear[0]) + self.wear[1]
    }

    /// The wear depths (w⁺, w⁻) after the last solved step.
    #[inline]
    pub fn wear_now(&self) -> [f64; 2] {
        [self.wear[0] + self.wear_step[0], self.wear[1] + self.wear_step[1]]
    }

    /// Starts a step: the last step's wear increment becomes part of the wear.
    #[inline]
    pub fn commit_wear(&mut self) {
        self.wear = self.wear_now();
        self.wear_step = [0.0; 2];
    }
}

/// How the wear increment of a step enters the step's contact problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WearCoupling {
    /// The wear increment is a function of the step's λ and v_τ, in the gap of the step
    /// itself (backward Euler; its λ-derivative in the Newton tangent).
    #[default]
    Implicit,
    /// The step sees the wear of the previous steps; its increment is added after the
    /// step has converged (forward Euler).
    Staggered,
}

impl WearCoupling {
    /// The name used in case files.
    pub fn name(self) -> &'static str {
        match self {
            WearCoupling::Implicit => "implicit",
            WearCoupling::Staggered => "staggered",
        }
    }
}

/// Archard wear on the lips of a crack: ẇ = (k/H)|λ||v_τ| where a point slides with
/// friction, shared between the lips as `split` (on `+`) and 1 − `split` (on `−`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wear {
    /// k/H (1/stress, > 0).
    pub coefficient: f64,
    /// The fraction of the wear on the `+` lip, in [0, 1].
    pub split: f64,
    pub coupling: WearCoupling,
}

/// The status of a point, as written to the output (0 open, 1 stick, 2 slip).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Open = 0,
    Stick = 1,
    Slip = 2,
}

/// How the contact conditions are enforced at the points of a crack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// The continuous augmented Lagrangian (λ, Λ unknowns; formulation §5).
    #[default]
    AugmentedLagrangian,
    /// The stabilised Lagrangian (seed eq. 6): the augmented Lagrangian with the penalty
    /// terms κ_n d_n (contact) and κ_τ μλ̄ v_τ (stick) added to its equilibrium terms.
    Stabilised,
    /// The penalty law (the stabilisation terms alone): no multiplier unknowns; normal
    /// traction κ_n⟨d_n⟩₊, Coulomb friction by a return mapping of Λ_start + κ_τ v_τ onto
    /// the unit disc (tangential traction μλ̄ times the mapped value).
    Penalty,
}

impl Method {
    /// Whether the method has multiplier unknowns (λ, Λ per packet). Without them the
    /// system is the bulk's plus a positive semi-definite contact term (Cholesky).
    pub fn has_multipliers(self) -> bool {
        match self {
            Method::AugmentedLagrangian | Method::Stabilised => true,
            Method::Penalty => false,
        }
    }

    /// The name used in case files and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Method::AugmentedLagrangian => "augmented_lagrangian",
            Method::Stabilised => "stabilised",
            Method::Penalty => "penalty",
        }
    }
}

/// The asperity compliance layer of a crack (seed eq. 5): the lips touch through a layer
/// of thickness a as soon as d_n + a > 0, and the layer pushes back with the traction
/// κ_a⟨d_n + a⟩₊² + c_n⟨d_n + a⟩₊ ḋ_n (ḋ_n: in statics the change of d_n over the load
/// step; in dynamics the normal relative velocity at the end of the time step, which the
/// driver obtains with `damping` scaled by the scheme's γ/(βΔt) and the base d_n_start
/// shifted, [`PointState::layer_rate_shift`]), on top of the method's hard contact, which
/// takes over once the layer is crushed (d_n ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asperity {
    /// Thickness a (length ≥ 0).
    pub thickness: f64,
    /// Stiffness κ_a (stress/length², > 0).
    pub stiffness: f64,
    /// Damping c_n (≥ 0).
    pub damping: f64,
}

impl Asperity {
    /// The layer's compressive traction (≥ 0) at penetration d_n (d_n_start at the start of
    /// the step), and its derivative with respect to d_n.
    #[inline]
    pub fn traction(&self, d_n: f64, d_n_start: f64) -> (f64, f64) {
        let crush = d_n + self.thickness;
        if crush <= 0.0 {
            return (0.0, 0.0);
        }
        let rate = d_n - d_n_start;
        (
            self.stiffness * crush * crush + self.damping * crush * rate,
            2.0 * self.stiffness * crush + self.damping * (rate + crush),
        )
    }
}

/// The law of one contact crack: its method and parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackLaw {
    pub method: Method,
    /// Coulomb coefficient μ.
    pub friction: f64,
    /// Normal augmentation ρ_n (stress/length).
    pub rho_n: f64,
    /// Tangential augmentation ρ_τ (1/length), when given ([`CrackLaw::rho_t_at`]).
    pub rho_t: f64,
    /// `rho_t` was not given: ρ_τ follows the threshold ([`CrackLaw::rho_t_at`]).
    pub rho_t_relative: bool,
    /// Initial gap g₀ (length): the lips start apart by g₀ along the normal.
    pub initial_gap: f64,
    /// Normal stabilisation or penalty κ_n (stress/length; `Stabilised`, `Penalty`).
    pub kappa_n: f64,
    /// Tangential stabilisation or penalty κ_τ (1/length), when given
    /// ([`CrackLaw::kappa_t_at`]).
    pub kappa_t: f64,
    /// `kappa_t` was not given: κ_τ follows the threshold ([`CrackLaw::kappa_t_at`]).
    pub kappa_t_relative: bool,
    /// The asperity layer, if any (every method).
    pub asperity: Option<Asperity>,
    /// Archard wear of the lips, if any (every method).
    pub wear: Option<Wear>,
    /// The share of ρ_n that augments the closed branch of the normal law with the gap
    /// projected on the multiplier space, Π d_n = Σ_j ψ_j (∫ψ_j d_n / ∫ψ_j), rather than the
    /// pointwise d_n (0: the pointwise law λ − ρ_n d_n). With ρ_p = `rho_projected` the
    /// closed branch is λ − (ρ_n − ρ_p) d_n − ρ_p Π d_n: the point's law has the pointwise
    /// part, the contact kernel the projected one per multiplier packet with its tangent
    /// ([`super::kernel`], `ContactPoints::packets`); the contact status reads the same
    /// sum, and the friction threshold λ − ρ_p Π d_n over the closed points
    /// ([`super::state::update_contact_status`], [`super::state::transmitted_lambdas`]).
    /// `ContactPoints::build` sets it to the part of ρ_n above E/h (the default ρ_n) for
    /// the augmented Lagrangian in small sliding without implicit wear: the projected term
    /// vanishes at every converged state whose packets are closed, so a ρ_n above E/h
    /// changes nothing there (the pointwise gap modes the packets do not see are
    /// penalised by E/h at most; docs/reliability.md, issue 11 item 9).
    pub rho_projected: f64,
    /// γ of the multipliers' local-projection stabilisation (length/stress, ≥ 0; 0: none):
    /// each packet j whose stencil's packets all have a closed point adds −(γ A_j/2) δ_j²
    /// to the point potentials,
    /// δ_j = λ_j − (the local linear fit of its neighbours' λ at its centroid), A_j = ∫ψ_j
    /// (`ContactPoints::stencils`, [`super::kernel`]). `ContactPoints::build` sets it to
    /// γ₀ h/E from the key `multiplier_stabilisation` = γ₀ (its default:
    /// `ContactCrackOptions::stabilisation`: 0).
    pub multiplier_stabilisation: f64,
}

/// What the law reads at one point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointInput {
    /// Penetration d_n ([`CrackLaw::penetration`]).
    pub d_n: f64,
    /// Tangential jump increment v_τ over the step ([`slip_increment`]).
    pub v: [f64; 2],
    pub lambda: f64,
    /// Λ (methods with multipliers), or Λ at the start of the step (penalty): the base of
    /// g_τ ([`CrackLaw::friction_base`]).
    pub big_lambda: [f64; 2],
    /// The frozen contact status, and the point has a master point.
    pub in_contact: bool,
    /// Frozen friction threshold λ̄.
    pub lam_bar: f64,
    /// Frozen friction status.
    pub lock: Option<bool>,
    /// The crack's threshold scale λ_ref ([`PointState::threshold_scale`]): the weight of
    /// the Λ rows where friction does not act ([`CrackLaw::idle_friction_weight`]).
    pub threshold_scale: f64,
    /// d_n at the start of the step (the asperity layer's damping).
    pub d_n_start: f64,
    /// dλ̄/dd_n where the threshold follows the iterate ([`CrackLaw::live_threshold`]: the
    /// penalty law's λ̄ = −κ_n⟨d_n⟩₊ − t_a(d_n) at the current d_n); 0 where it is frozen.
    /// Its term in the tangent, ∂r_s,τ/∂s_n, is what makes that tangent unsymmetric.
    pub threshold_slope: f64,
    /// dλ̄/dλ where the threshold follows the iterate (the methods with multipliers: λ̄ is
    /// the point's λ, [`CrackLaw::live_threshold`]); 0 where it is frozen. Its terms
    /// ∂r_s,τ/∂λ and ∂r_Λ/∂λ are in [`PointResponse::k_sm_live`] and `k_mm`.
    pub threshold_slope_lambda: f64,
}

/// Residual and tangent of the law at one point, per unit weight, in the point's
/// coordinates s = (n·⟦u⟧, τ₁·⟦u⟧, τ₂·⟦u⟧) and m = (λ, Λ₁, Λ₂). With frozen thresholds
/// the tangent is symmetric: the m–s block is `k_sm` transposed, and `k_sm_live`,
/// `k_ms_live` are zero. A threshold that follows the iterate
/// ([`PointInput::threshold_slope`], [`PointInput::threshold_slope_lambda`]) adds the
/// one-sided terms: ∂r_s/∂m = `k_sm` + `k_sm_live`, ∂r_m/∂s = `k_sm`ᵀ + `k_ms_live`, and
/// unsymmetric entries in `k_ss` and `k_mm`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointResponse {
    pub r_s: [f64; 3],
    pub r_m: [f64; 3],
    pub k_ss: [[f64; 3]; 3],
    pub k_sm: [[f64; 3]; 3],
    pub k_mm: [[f64; 3]; 3],
    /// ∂r_s/∂m beyond `k_sm` (rows s, columns m; not mirrored into the m–s block).
    pub k_sm_live: [[f64; 3]; 3],
    /// ∂r_m/∂s beyond `k_sm`ᵀ (rows m, columns s; not mirrored into the s–m block).
    pub k_ms_live: [[f64; 3]; 3],
}

/// The tangential jump increment v_τ,α = τ_α·(⟦u⟧ − ⟦u⟧_start) over the step.
#[inline]
pub fn slip_increment(nt: usize, tangents: &[[f64; 3]; 2], jump: [f64; 3], prev_jump: [f64; 3]) -> [f64; 2] {
    let mut v = [0.0; 2];
    for a in 0..nt {
        let t = tangents[a];
        v[a] = (0..3).map(|i| t[i] * (jump[i] - prev_jump[i])).sum();
    }
    v
}

/// Tie tolerance of the friction indicator: a point exactly at the Coulomb limit
/// (|g_τ| = 1 to round-off, no slip increment) counts as sticking.
pub const STICK_TOLERANCE: f64 = 1e-9;

/// |g_τ| below which a point in contact counts as sticking whatever the indicator says
/// (no tangential direction to slide along).
const NO_DIRECTION: f64 = 1e-14;

/// χ_c: in contact when g_n = λ − ρ_n d_n ≤ 0.
#[inline]
pub fn contact_indicator(lambda: f64, d_n: f64, rho_n: f64) -> bool {
    lambda - rho_n * d_n <= 0.0
}

/// χ_f and g_τ: sticking when |Λ + ρ_τ v_τ| ≤ 1 (+ [`STICK_TOLERANCE`]). Returns (stick, g_τ).
#[inline]
pub fn friction_indicator(big_lambda: [f64; 2], v_tau: [f64; 2], rho_t: f64) -> (bool, [f64; 2]) {
    let g = [big_lambda[0] + rho_t * v_tau[0], big_lambda[1] + rho_t * v_tau[1]];
    ((g[0] * g[0] + g[1] * g[1]).sqrt() <= 1.0 + STICK_TOLERANCE, g)
}

impl CrackLaw {
    /// The penetration d_n = −⟦u⟧·n − g₀ − w at a point with jump ⟦u⟧, normal n and
    /// wear depth w.
    #[inline]
    pub fn penetration(&self, jump: [f64; 3], normal: [f64; 3], wear: f64) -> f64 {
        -dot(jump, normal) - self.initial_gap - wear
    }

    /// χ_c at a point: g_n ≤ 0, or for the penalty law d_n > 0 (the lips overlap).
    #[inline]
    pub fn contact_indicator(&self, lambda: f64, d_n: f64) -> bool {
        match self.method {
            Method::Penalty => d_n > 0.0,
            _ => contact_indicator(lambda, d_n, self.rho_n),
        }
    }

    /// The base of g_τ = base + ρ_τ v_τ: the multiplier Λ of the methods that have one, Λ
    /// at the start of the step for the penalty law (its tangential state).
    #[inline]
    pub fn friction_base(&self, big_lambda: [f64; 2], start: [f64; 2]) -> [f64; 2] {
        if self.method.has_multipliers() {
            big_lambda
        } else {
            start
        }
    }

    /// κ_τ at a point whose friction threshold is λ̄: the given `kappa_t`, or by default
    /// κ_n / (μ|λ̄|), so that the tangential stiffness μ|λ̄|κ_τ of a sticking point is κ_n
    /// (as [`CrackLaw::rho_t_at`] for ρ_τ).
    #[inline]
    pub fn kappa_t_at(&self, lam_bar: f64) -> f64 {
        let bound = self.friction * lam_bar.abs();
        if self.kappa_t_relative && bound > 0.0 {
            self.kappa_n / bound
        } else {
            self.kappa_t
        }
    }

    /// The normal traction λ (≤ 0) the penalty law transmits at a paired point: −κ_n⟨d_n⟩₊.
    #[inline]
    pub fn penalty_traction(&self, d_n: f64) -> f64 {
        -self.kappa_n * d_n.max(0.0)
    }

    /// Whether the friction threshold of this law can follow the iterate inside a Newton
    /// loop, with its derivative in the tangent: a law with friction whose threshold is a
    /// function of the unknowns at the point — the penalty law's −κ_n⟨d_n⟩₊ of the
    /// displacements, the augmented and stabilised Lagrangians' λ of the multipliers (in
    /// small sliding; under large sliding the threshold λ − ρ d_n of a paired point is left
    /// to the fixed point), plus the layer's −t_a(d_n). The friction fixed point λ̄ ← λ then
    /// converges with the Newton loop (generalized Newton on the non-associated Coulomb
    /// law, as Alart and Curnier's), at the cost of an unsymmetric tangent.
    ///
    /// With wear: the staggered coupling's wear is a constant of the step in the gap
    /// (`PointState::gap_offset`), so every threshold above and its slopes carry over. The
    /// implicit coupling's increment q⟨−λ⟩₊ changes the normal law, not the threshold λ of
    /// the multiplier laws (slope 1 in λ where the hard contact is active, as without
    /// wear): those follow the loop too; the penalty's −κ_n⟨d_n^w⟩₊ and a layer's t_a(x)
    /// read the worn gap, whose slope (through q) is not in [`CrackLaw::live_threshold`]:
    /// they keep the fixed point.
    #[inline]
    pub fn has_live_threshold(&self, large_sliding: bool) -> bool {
        let wear_ok = match self.wear {
            Some(w) if w.coupling == WearCoupling::Implicit => self.method.has_multipliers() && self.asperity.is_none(),
            _ => true,
        };
        self.friction > 0.0 && wear_ok && !(large_sliding && self.method.has_multipliers())
    }

    /// The friction threshold λ̄ (≤ 0) at a point and its derivatives (dλ̄/dd_n, dλ̄/dλ), for
    /// a law with [`CrackLaw::has_live_threshold`] (`None` otherwise): the value the fixed
    /// point's update gives ([`CrackLaw::threshold_traction`] clipped at 0, 0 where the lips
    /// do not touch) and its slopes. Penalty: −κ_n in d_n where the hard contact is active
    /// and paired with d_n ≥ 0 (the frozen contact status decides the one-sided derivative
    /// at d_n = 0, as it does for the normal traction). Methods with multipliers: 1 in λ
    /// where the hard contact is active (λ̄ = λ), 0 where the total traction is tensile
    /// (λ̄ = 0). Minus t_a'(d_n) in d_n where a layer is crushed.
    pub fn live_threshold(
        &self,
        large_sliding: bool,
        paired: bool,
        contact: bool,
        lambda: f64,
        d_n: f64,
        d_n_start: f64,
    ) -> Option<(f64, f64, f64)> {
        if !self.has_live_threshold(large_sliding) {
            return None;
        }
        if !self.touches(contact, d_n) {
            return Some((0.0, 0.0, 0.0));
        }
        let raw = self.threshold_traction(large_sliding, paired, contact, lambda, d_n, d_n_start);
        let layer_slope = match (&self.asperity, paired) {
            (Some(a), true) => a.traction(d_n, d_n_start).1,
            _ => 0.0,
        };
        if self.method == Method::Penalty {
            let slope = if contact && paired && d_n >= 0.0 { -self.kappa_n } else { 0.0 };
            return Some((raw.min(0.0), slope - layer_slope, 0.0));
        }
        if raw >= 0.0 {
            return Some((0.0, 0.0, 0.0));
        }
        Some((raw, -layer_slope, if contact { 1.0 } else { 0.0 }))
    }

    /// The penalty law's Λ at a point in contact: the return mapping of
    /// g_τ = Λ_start + κ_τ v_τ onto the unit disc (the frozen status if any).
    pub fn penalty_big_lambda(&self, start: [f64; 2], v_tau: [f64; 2], lam_bar: f64, lock: Option<bool>) -> [f64; 2] {
        let g = self.friction_indicator(start, v_tau, lam_bar).1;
        let gn = g[0].hypot(g[1]);
        if self.sticks(start, v_tau, lam_bar, lock) || gn == 0.0 {
            g
        } else {
            [g[0] / gn, g[1] / gn]
        }
    }

    /// ρ_τ at a point whose friction threshold is λ̄: the given `rho_t`, or by default
    /// ρ_n / (μ|λ̄|). The slip term of g_τ = Λ + ρ_τ v_τ is then ρ_n v_τ / (μ|λ̄|), the traction
    /// of the normal augmentation over the friction bound, in the units of Λ whatever the
    /// load. (A fixed 1/h makes ρ_τ v_τ of order μp/E: at E/p = 1e4 the slip barely enters
    /// g_τ, the slip direction follows round-off and the stick/slip statuses chatter.)
    /// The penalty law's ρ_τ is its κ_τ ([`CrackLaw::kappa_t_at`]).
    #[inline]
    pub fn rho_t_at(&self, lam_bar: f64) -> f64 {
        if self.method == Method::Penalty {
            return self.kappa_t_at(lam_bar);
        }
        let bound = self.friction * lam_bar.abs();
        if self.rho_t_relative && bound > 0.0 {
            self.rho_n / bound
        } else {
            self.rho_t
        }
    }

    /// χ_f and g_τ at a point with friction threshold λ̄.
    #[inline]
    pub fn friction_indicator(&self, big_lambda: [f64; 2], v_tau: [f64; 2], lam_bar: f64) -> (bool, [f64; 2]) {
        friction_indicator(big_lambda, v_tau, self.rho_t_at(lam_bar))
    }

    /// The stick/slip status of a point in contact with a non-zero threshold λ̄: the frozen
    /// one if any, else the indicator's (a point without a sliding direction sticks).
    pub fn sticks(&self, big_lambda: [f64; 2], v_tau: [f64; 2], lam_bar: f64, lock: Option<bool>) -> bool {
        let (free, g) = self.friction_indicator(big_lambda, v_tau, lam_bar);
        lock.unwrap_or(free) || g[0].hypot(g[1]) < NO_DIRECTION
    }

    /// Whether the lips touch at a point: its hard contact is active (`contact`, the frozen
    /// status χ_c) or its asperity layer is crushed (d_n + a > 0). A point that touches
    /// transmits a normal traction, so it has a friction threshold and a stick/slip status.
    #[inline]
    pub fn touches(&self, contact: bool, d_n: f64) -> bool {
        contact || self.asperity.is_some_and(|a| d_n + a.thickness > 0.0)
    }

    /// Whether the friction law acts at a point (with its frozen threshold λ̄): where the
    /// hard contact is active, and with an asperity layer wherever λ̄ ≠ 0, since the layer
    /// alone carries a normal traction before the hard contact closes. The threshold
    /// update sets λ̄ = 0 where the lips do not touch ([`CrackLaw::touches`]), so at the
    /// fixed point friction acts exactly where the total normal traction is compressive;
    /// within a Newton loop the gate stays frozen (no switch as the layer's crush varies).
    #[inline]
    pub fn friction_acts(&self, in_contact: bool) -> bool {
        in_contact || self.asperity.is_some()
    }

    /// The asperity layer's compressive traction t_a(d_n) (≥ 0) at a paired point; 0
    /// without a layer ([`Asperity::traction`]).
    #[inline]
    pub fn layer_traction(&self, paired: bool, d_n: f64, d_n_start: f64) -> f64 {
        match (&self.asperity, paired) {
            (Some(a), true) => a.traction(d_n, d_n_start).0,
            _ => 0.0,
        }
    }

    /// The normal traction that sets the friction threshold at a point (≤ 0 in
    /// compression): the total one, hard contact plus asperity layer. The hard contact's is
    /// λ where it is active (`contact`), or under large sliding the traction the point
    /// actually transmits, g_n = λ − ρ_n d_n (unpaired points: none); the penalty law's
    /// −κ_n⟨d_n⟩₊. The layer's is −t_a(d_n) ([`Asperity::traction`], `d_n_start` for its
    /// damping) at a paired point.
    pub fn threshold_traction(
        &self,
        large_sliding: bool,
        paired: bool,
        contact: bool,
        lambda: f64,
        d_n: f64,
        d_n_start: f64,
    ) -> f64 {
        let layer = self.layer_traction(paired, d_n, d_n_start);
        let hard = if !contact {
            0.0
        } else if self.method == Method::Penalty {
            if paired {
                self.penalty_traction(d_n)
            } else {
                0.0
            }
        } else {
            match (large_sliding, paired) {
                (false, _) => lambda,
                (true, true) => lambda - (self.rho_n + self.stabilisation_n()) * d_n,
                (true, false) => 0.0,
            }
        };
        hard - layer
    }

    /// The residual and tangent at one point (`nt` tangent directions: 1 in 2D, 2 in 3D).
    ///
    /// Augmented Lagrangian, in contact: R_s,n = g_n, R_λ = −d_n, K_ss,nn = ρ_n, K_sλ = 1;
    /// out of contact R_λ = −λ/ρ_n, K_λλ = −1/ρ_n. Friction with μλ̄ ≠ 0 in contact:
    /// stick R_s,α = −μλ̄ Λ_α, R_Λα = −μλ̄ v_α, K_sΛ,αα = −μλ̄; slip (e = g/|g|,
    /// D = (I − e⊗e)/|g|) R_s,α = −μλ̄ e_α, R_Λα = (μλ̄/ρ_τ)(Λ_α − e_α),
    /// K_ss,αβ = −μλ̄ ρ_τ D, K_sΛ = −μλ̄ D, K_ΛΛ = (μλ̄/ρ_τ)(I − D); otherwise (open, or
    /// μλ̄ = 0) R_Λα = −c Λ_α, K_ΛΛ = −c I with c the crack's weight of such rows
    /// ([`CrackLaw::idle_friction_weight`]: the slip row's μ|λ̄|/ρ_τ at the threshold scale
    /// λ_ref, stress × length like every other Λ row).
    ///
    /// Stabilised: the above plus, in contact, R_s,n −= κ_n d_n, K_ss,nn += κ_n, and in
    /// stick R_s,α −= μλ̄ κ_τ v_α, K_ss,αα −= μλ̄ κ_τ. At a solution where d_n = 0 and
    /// v_τ = 0 at the points the added terms vanish: the stabilisation does not perturb it.
    ///
    /// Penalty (no m terms), in contact: R_s,n = −κ_n d_n, K_ss,nn = κ_n; with μλ̄ ≠ 0 and
    /// g = Λ_start + κ_τ v: stick R_s,α = −μλ̄ g_α, K_ss,αα = −μλ̄ κ_τ; slip
    /// R_s,α = −μλ̄ e_α, K_ss = −μλ̄ κ_τ D (e, D of g as above).
    ///
    /// Asperity layer (every method), at a paired point whatever its contact status:
    /// R_s,n −= t_a(d_n), K_ss,nn += t_a'(d_n) ([`Asperity::traction`]). With a layer the
    /// friction terms above act wherever λ̄ ≠ 0, not only in hard contact
    /// ([`CrackLaw::friction_acts`]), and λ̄ is the total normal traction, hard contact plus
    /// layer ([`CrackLaw::threshold_traction`]): the layer alone carries friction before
    /// the hard contact closes.
    ///
    /// Implicit wear: see [`CrackLaw::respond_with_wear`].
    pub fn respond(&self, nt: usize, p: &PointInput) -> PointResponse {
        self.respond_with_wear(nt, p, self.wear_compliance(p))
    }

    /// [`CrackLaw::respond`] with the implicit wear of the step at compliance q (the gap
    /// of a point in contact is d_n^w = d_n − q⟨−λ⟩₊, `p.d_n` being the gap with the wear
    /// before the step). Methods with multipliers, in contact, with ρ = ρ_n + κ_n (κ_n of
    /// the stabilised law, else 0) and q' = q where λ < 0 (else 0):
    /// R_s,n = λ − ρ d_n^w, R_λ = −(1 − ρq') d_n^w, K_ss,nn = ρ, K_sλ = 1 − ρq',
    /// K_λλ = −(1 − ρq') q': the symmetric tangent of the potential
    /// −λ d^w + (ρ/2)(d^w)² + (q'/2)λ², whose λ-equation enforces d_n^w = 0 like the plain
    /// one (ρ is lowered to 1/(2q') at the point if larger, so that 1 − ρq' ≥ 1/2). Penalty:
    /// d_n^w = d_n/(1 + qκ_n) where d_n > 0, i.e. the normal stiffness κ_n/(1 + qκ_n). q is
    /// frozen in the tangent (the wear's dependence on the slip is not in it: the system
    /// stays symmetric); q = 0 is the law without wear. With an asperity layer the layer and
    /// the hard contact are in series with the compliance q on the worn gap
    /// ([`CrackLaw::layer_worn_gap`]; `respond_worn_layer` below).
    pub fn respond_with_wear(&self, nt: usize, p: &PointInput, q: f64) -> PointResponse {
        if let (true, Some(layer)) = (q > 0.0, &self.asperity) {
            return self.respond_worn_layer(nt, p, q, layer);
        }
        let mut r = self.respond_hard(nt, p, q);
        if let Some(layer) = &self.asperity {
            let (t, dt) = layer.traction(p.d_n, p.d_n_start);
            r.r_s[0] -= t;
            r.k_ss[0][0] += dt;
        }
        r
    }

    /// The method's own law (without the asperity layer), with the implicit wear
    /// compliance q.
    fn respond_hard(&self, nt: usize, p: &PointInput, q: f64) -> PointResponse {
        let mut r = PointResponse::default();
        if self.method == Method::Penalty {
            self.penalty(nt, p, q, &mut r);
            return r;
        }
        let worn = q > 0.0 && p.in_contact;
        if worn {
            self.normal_worn(p, q, &mut r);
        } else {
            self.normal_augmented(p, &mut r);
        }
        let stick = self.friction_augmented(nt, p, &mut r);
        if self.method == Method::Stabilised && p.in_contact && !worn {
            r.r_s[0] -= self.kappa_n * p.d_n;
            r.k_ss[0][0] += self.kappa_n;
        }
        self.stabilise_stick(nt, p, stick, &mut r);
        r
    }

    /// The stabilised law's stick term μλ̄κ_τ v_τ (`stick`: the point sticks with a
    /// non-zero threshold); nothing for the other methods.
    fn stabilise_stick(&self, nt: usize, p: &PointInput, stick: bool, r: &mut PointResponse) {
        if self.method == Method::Stabilised && stick {
            let mlb = self.friction * p.lam_bar;
            let kappa_t = self.kappa_t_at(p.lam_bar);
            // A live threshold: with a given κ_τ the term B κ_τ v_τ (B = −μλ̄) moves with B;
            // with the default κ_τ = κ_n/B it is κ_n v_τ, independent of B.
            let per_b = !(self.kappa_t_relative && mlb != 0.0);
            for a in 0..nt {
                r.r_s[1 + a] -= mlb * kappa_t * p.v[a];
                r.k_ss[1 + a][1 + a] -= mlb * kappa_t;
                if per_b {
                    self.threshold_column(p, a, kappa_t * p.v[a], 0.0, r);
                }
            }
        }
    }

    /// The terms of a threshold that follows the iterate ([`CrackLaw::live_threshold`]) in
    /// the tangent of the friction row α = `a`: with B = −μλ̄ the friction bound and
    /// (∂r_s,α/∂B, ∂r_Λα/∂B) = (`dr_s`, `dr_m`) at the point, the chain rule through
    /// dB/ds_n = μ dλ̄/dd_n (d_n = −s_n − ..) and dB/dλ = −μ dλ̄/dλ. Nothing when frozen.
    #[inline]
    fn threshold_column(&self, p: &PointInput, a: usize, dr_s: f64, dr_m: f64, r: &mut PointResponse) {
        let db_ds = self.friction * p.threshold_slope;
        let db_dl = -self.friction * p.threshold_slope_lambda;
        if db_ds != 0.0 {
            r.k_ss[1 + a][0] += db_ds * dr_s;
            r.k_ms_live[1 + a][0] += db_ds * dr_m;
        }
        if db_dl != 0.0 {
            r.k_sm_live[1 + a][0] += db_dl * dr_s;
            r.k_mm[1 + a][0] += db_dl * dr_m;
        }
    }

    /// The hard contact's part of the worn-gap equation with a layer (see
    /// [`CrackLaw::layer_worn_gap`]): (ρ_c, λ_c) = (ρ_n + κ_n of the stabilised law, λ) for
    /// the methods with multipliers in contact, (κ_n, 0) for the penalty law in contact,
    /// (0, 0) out of contact.
    fn hard_series_terms(&self, p: &PointInput) -> (f64, f64) {
        match (self.method, p.in_contact) {
            (_, false) => (0.0, 0.0),
            (Method::Penalty, true) => (self.kappa_n, 0.0),
            (_, true) => (self.rho_n + self.stabilisation_n(), p.lambda),
        }
    }

    /// The worn gap x of a point under the implicit wear of the step at compliance q > 0
    /// on a crack with an asperity layer, with the layer's traction t_a(x) and its
    /// derivative. The step's wear Δw = d_n − x is q times the total normal pressure, the
    /// layer's plus the hard contact's (λ_c − ρ_c x, `CrackLaw::hard_series_terms`):
    /// x (1 + qρ_c) + q t_a(x) = d_n + qλ_c. The left side increases with x (t_a is
    /// convex and non-decreasing on the crush), so the root is unique: Newton from the
    /// layer-free root, which lies on its right, decreases monotonically onto it.
    pub fn layer_worn_gap(&self, layer: &Asperity, p: &PointInput, q: f64) -> (f64, f64, f64) {
        let (rho_c, lam_c) = self.hard_series_terms(p);
        let a = 1.0 + q * rho_c;
        let rhs = p.d_n + q * lam_c;
        let mut x = rhs / a;
        let (mut t, mut dt) = layer.traction(x, p.d_n_start);
        if t == 0.0 {
            return (x, t, dt);
        }
        let scale = rhs.abs().max(layer.thickness).max(f64::MIN_POSITIVE);
        for _ in 0..100 {
            let f = a * x + q * t - rhs;
            let df = a + q * dt;
            let step = f / df;
            // Never left of the layer's edge, where t_a = 0 and the root is rhs/a ≥ −a.
            x = (x - step).max(-layer.thickness);
            (t, dt) = layer.traction(x, p.d_n_start);
            if step.abs() <= 1e-15 * scale {
                break;
            }
        }
        (x, t, dt)
    }

    /// The gap of a point during a step with the implicit wear at compliance q (the
    /// point's gap with the wear before the step in `p.d_n`): d_n − Δw, the gap every law
    /// and check reads. Without a layer: d_n − q⟨−λ⟩₊ for the methods with multipliers,
    /// d_n/(1 + qκ_n) where the penalty's lips overlap; with a layer
    /// [`CrackLaw::layer_worn_gap`]. q = 0: d_n.
    pub fn worn_gap(&self, p: &PointInput, q: f64) -> f64 {
        if q <= 0.0 {
            return p.d_n;
        }
        if let Some(layer) = &self.asperity {
            return self.layer_worn_gap(layer, p, q).0;
        }
        if self.method.has_multipliers() {
            p.d_n + q * p.lambda.min(0.0)
        } else {
            p.d_n * self.penalty_worn_stiffness(p.d_n, q) / self.kappa_n
        }
    }

    /// [`CrackLaw::respond_with_wear`] with an asperity layer (q > 0): the layer and the
    /// hard contact in parallel, in series with the wear compliance q. The point's
    /// potential (1/2q)(d_n − x)² + U_a(x) + the hard contact's on x (the augmented
    /// Lagrangian's −λx + (ρ_c/2)x² in contact, the penalty's (κ_n/2)x²), U_a' = t_a, with the
    /// worn gap x condensed out at the point ([`CrackLaw::layer_worn_gap`]): with
    /// k = ρ_c + t_a'(x) and D = 1 + qk,
    /// R_s,n = λ_c − ρ_c x − t_a(x) (minus the total pressure), K_ss,nn = k/D, and in
    /// contact (multipliers) R_λ = −x, K_sλ = 1/D, K_λλ = −q/D (out of contact the plain
    /// −λ/ρ_n). Symmetric, exact in s and λ at frozen q; q → 0 gives the law without
    /// wear. The layer's dependence on the wear depth is in it through x.
    fn respond_worn_layer(&self, nt: usize, p: &PointInput, q: f64, layer: &Asperity) -> PointResponse {
        let mut r = PointResponse::default();
        let (rho_c, lam_c) = self.hard_series_terms(p);
        let (x, t, dt) = self.layer_worn_gap(layer, p, q);
        let k = rho_c + dt;
        let d = 1.0 + q * k;
        r.r_s[0] = lam_c - rho_c * x - t;
        r.k_ss[0][0] = k / d;
        if self.method == Method::Penalty {
            self.penalty_friction(nt, p, &mut r);
            return r;
        }
        if p.in_contact {
            r.r_m[0] = -x;
            r.k_sm[0][0] = 1.0 / d;
            r.k_mm[0][0] = -q / d;
        } else {
            r.r_m[0] = -p.lambda / self.rho_n;
            r.k_mm[0][0] = -1.0 / self.rho_n;
        }
        let stick = self.friction_augmented(nt, p, &mut r);
        self.stabilise_stick(nt, p, stick, &mut r);
        r
    }

    /// κ_n of a stabilised law, 0 otherwise.
    fn stabilisation_n(&self) -> f64 {
        if self.method == Method::Stabilised {
            self.kappa_n
        } else {
            0.0
        }
    }

    fn penalty(&self, nt: usize, p: &PointInput, q: f64, r: &mut PointResponse) {
        if p.in_contact {
            let kappa = self.penalty_worn_stiffness(p.d_n, q);
            r.r_s[0] = -kappa * p.d_n;
            r.k_ss[0][0] = kappa;
        }
        self.penalty_friction(nt, p, r);
    }

    /// The penalty law's friction terms (return mapping of Λ_start + κ_τ v_τ).
    fn penalty_friction(&self, nt: usize, p: &PointInput, r: &mut PointResponse) {
        let mlb = self.friction * p.lam_bar;
        if mlb == 0.0 || !self.friction_acts(p.in_contact) {
            return;
        }
        let kappa_t = self.kappa_t_at(p.lam_bar);
        let g = self.friction_indicator(p.big_lambda, p.v, p.lam_bar).1;
        // With a live threshold (p.threshold_slope ≠ 0): the friction bound B = −μλ̄ moves
        // with s_n, dB/ds_n = μ·dλ̄/dd_n (d_n = −s_n − ..), and r_s,τ's derivative in B
        // (κ_τ = κ_n/B by default, so that B·κ_τ is constant) enters column n.
        let relative = self.kappa_t_relative;
        let db_ds = self.friction * p.threshold_slope;
        let start = p.big_lambda;
        if self.sticks(p.big_lambda, p.v, p.lam_bar, p.lock) {
            for a in 0..nt {
                r.r_s[1 + a] = -mlb * g[a];
                r.k_ss[1 + a][1 + a] = -mlb * kappa_t;
                // r = B g: ∂r/∂B = g, or Λ_start with κ_τ = κ_n/B (r = BΛ_start + κ_n v).
                if db_ds != 0.0 {
                    r.k_ss[1 + a][0] += db_ds * if relative { start[a] } else { g[a] };
                }
            }
        } else {
            let gn = g[0].hypot(g[1]);
            let e = [g[0] / gn, g[1] / gn];
            for a in 0..nt {
                r.r_s[1 + a] = -mlb * e[a];
                // r = B e: ∂r/∂B = e, plus D Λ_start (D = (I − e⊗e)/|g|) with κ_τ = κ_n/B.
                let mut dr_db = e[a];
                for b in 0..nt {
                    let id = if a == b { 1.0 } else { 0.0 };
                    let d = (id - e[a] * e[b]) / gn;
                    r.k_ss[1 + a][1 + b] = -mlb * kappa_t * d;
                    if relative {
                        dr_db += d * start[b];
                    }
                }
                if db_ds != 0.0 {
                    r.k_ss[1 + a][0] += db_ds * dr_db;
                }
            }
        }
    }

    /// The penalty law's normal stiffness at gap d_n (before the step's wear) with the
    /// implicit wear compliance q: κ_n/(1 + qκ_n) where the lips overlap, κ_n elsewhere.
    #[inline]
    pub fn penalty_worn_stiffness(&self, d_n: f64, q: f64) -> f64 {
        if d_n > 0.0 && q > 0.0 {
            self.kappa_n / (1.0 + q * self.kappa_n)
        } else {
            self.kappa_n
        }
    }

    /// The normal law of a point in contact with the implicit wear compliance q (methods
    /// with multipliers; the stabilisation κ_n included): see [`CrackLaw::respond_with_wear`].
    fn normal_worn(&self, p: &PointInput, q: f64, r: &mut PointResponse) {
        let dq = if p.lambda < 0.0 { q } else { 0.0 };
        let mut rho = self.rho_n + self.stabilisation_n();
        if dq > 0.0 {
            rho = rho.min(0.5 / dq);
        }
        let d_w = p.d_n + dq * p.lambda;
        let alpha = 1.0 - rho * dq;
        r.r_s[0] = p.lambda - rho * d_w;
        r.r_m[0] = -alpha * d_w;
        r.k_ss[0][0] = rho;
        r.k_sm[0][0] = alpha;
        r.k_mm[0][0] = -alpha * dq;
    }

    /// The implicit wear compliance q = (k/H)|v_τ| at a point in contact that slides with
    /// friction (μλ̄ ≠ 0, not sticking) on a crack with implicit wear; 0 elsewhere. The
    /// step's wear increment at the point is q⟨−λ⟩₊.
    #[inline]
    pub fn wear_compliance(&self, p: &PointInput) -> f64 {
        match self.wear {
            Some(w) if w.coupling == WearCoupling::Implicit => self.sliding_rate(p, w.coefficient),
            _ => 0.0,
        }
    }

    /// c|v_τ| at a point in contact sliding with friction, 0 elsewhere.
    #[inline]
    fn sliding_rate(&self, p: &PointInput, c: f64) -> f64 {
        if !self.friction_acts(p.in_contact)
            || self.friction * p.lam_bar == 0.0
            || self.sticks(p.big_lambda, p.v, p.lam_bar, p.lock)
        {
            return 0.0;
        }
        c * p.v[0].hypot(p.v[1])
    }

    /// The wear increment (Δw⁺, Δw⁻) and the frictional work per unit area μ|λ||v_τ| of a
    /// converged step at a point (`p.lambda`: the point's normal traction): Archard,
    /// Δw = (k/H)⟨−λ⟩₊|v_τ| where the point slides with friction, split between the lips.
    /// Zero without wear.
    pub fn wear_increment(&self, p: &PointInput) -> ([f64; 2], f64) {
        let Some(w) = self.wear else { return ([0.0; 2], 0.0) };
        let slide = self.sliding_rate(p, 1.0);
        let pressure = self.wear_pressure(p);
        let dw = w.coefficient * pressure * slide;
        ([w.split * dw, (1.0 - w.split) * dw], self.friction * pressure * slide)
    }

    /// The normal pressure (≥ 0) that wears a point: the total one, hard contact plus
    /// asperity layer, ⟨−λ⟩₊ + t_a(d_n) (`p.lambda`: the hard contact's traction, the
    /// penalty's −κ_n⟨d_n⟩₊ for that law; `p.d_n`: the gap the step ended with, the worn
    /// one under the implicit coupling). The layer's share is the one that enters the
    /// friction threshold ([`CrackLaw::threshold_traction`]), so the frictional work
    /// μ p |v_τ| is the work of the friction traction at the fixed point.
    #[inline]
    pub fn wear_pressure(&self, p: &PointInput) -> f64 {
        (-p.lambda).max(0.0) + self.layer_traction(true, p.d_n, p.d_n_start)
    }

    fn normal_augmented(&self, p: &PointInput, r: &mut PointResponse) {
        if p.in_contact {
            // The projected share −ρ_p Π d_n is the kernel's, per packet (CrackLaw::rho_projected).
            let rho = self.rho_n - self.rho_projected;
            r.r_s[0] = p.lambda - rho * p.d_n;
            r.r_m[0] = -p.d_n;
            r.k_ss[0][0] = rho;
            r.k_sm[0][0] = 1.0;
        } else {
            r.r_m[0] = -p.lambda / self.rho_n;
            r.k_mm[0][0] = -1.0 / self.rho_n;
        }
    }

    /// The friction terms; returns whether the point sticks with a non-zero threshold.
    fn friction_augmented(&self, nt: usize, p: &PointInput, r: &mut PointResponse) -> bool {
        let mlb = self.friction * p.lam_bar;
        let tl = p.big_lambda;
        let rho_t = self.rho_t_at(p.lam_bar);
        if self.friction_acts(p.in_contact) && mlb != 0.0 {
            // With a live threshold the bound B = −μλ̄ moves with the iterate
            // (CrackLaw::threshold_column): stick r_s = BΛ, r_Λ = Bv; slip r_s = Be,
            // r_Λ = −(B/ρ_τ)(Λ − e), and with the default ρ_τ = ρ_n/B also through g:
            // ∂e/∂B = D ∂g/∂B = −ρ_τ D v/B = DΛ/B (Dg = 0), so ∂r_s/∂B = e + DΛ and
            // ∂r_Λ/∂B = −2(Λ − e)/ρ_τ + DΛ/ρ_τ.
            if self.sticks(tl, p.v, p.lam_bar, p.lock) {
                for a in 0..nt {
                    r.r_s[1 + a] = -mlb * tl[a];
                    r.r_m[1 + a] = -mlb * p.v[a];
                    r.k_sm[1 + a][1 + a] = -mlb;
                    self.threshold_column(p, a, tl[a], p.v[a], r);
                }
                return true;
            } else {
                let relative = self.rho_t_relative;
                let g = self.friction_indicator(tl, p.v, p.lam_bar).1;
                let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
                let e = [g[0] / gn, g[1] / gn];
                for a in 0..nt {
                    r.r_s[1 + a] = -mlb * e[a];
                    r.r_m[1 + a] = (mlb / rho_t) * (tl[a] - e[a]);
                    let mut d_lam = 0.0;
                    for b in 0..nt {
                        let id = if a == b { 1.0 } else { 0.0 };
                        let d = (id - e[a] * e[b]) / gn;
                        r.k_ss[1 + a][1 + b] = -mlb * rho_t * d;
                        r.k_sm[1 + a][1 + b] = -mlb * d;
                        r.k_mm[1 + a][1 + b] = (mlb / rho_t) * (id - d);
                        d_lam += d * tl[b];
                    }
                    let (dr_s, dr_m) = if relative {
                        (e[a] + d_lam, (-2.0 * (tl[a] - e[a]) + d_lam) / rho_t)
                    } else {
                        (e[a], -(tl[a] - e[a]) / rho_t)
                    };
                    self.threshold_column(p, a, dr_s, dr_m, r);
                }
            }
        } else {
            let c = self.idle_friction_weight(p.threshold_scale);
            for a in 0..nt {
                r.r_m[1 + a] = -c * tl[a];
                r.k_mm[1 + a][1 + a] = -c;
            }
        }
        false
    }

    /// The weight c of the Λ rows of a point where friction does not act (open, or closed
    /// with μλ̄ = 0: R_Λ = −cΛ), from the crack's threshold scale λ_ref
    /// ([`PointState::threshold_scale`], its largest |λ̄|): the coefficient μ|λ̄|/ρ_τ(λ̄) of
    /// the slip row (μλ̄/ρ_τ)(Λ − e) at λ̄ = λ_ref, i.e. (μλ_ref)²/ρ_n with the default
    /// ρ_τ = ρ_n/(μ|λ̄|) and μλ_ref/ρ_τ with a given ρ_τ. Every Λ row is then stress ×
    /// length, so a multiplier packet that adds rows of both kinds (the edge of a contact
    /// zone, a point that closed after its threshold was set) weighs them alike in every
    /// unit system. Without a threshold on the crack (μλ_ref = 0: no friction acts at any
    /// of its points, every Λ row is of this kind and any uniform weight gives Λ = 0) the
    /// weight is ρ_n/ρ_τ² with the law's fixed ρ_τ (`rho_t`, 1/h by default: ρ_n h²), the
    /// slip row's coefficient at the threshold whose default ρ_τ is that one; 1 for a law
    /// built without ρ_τ. (docs/contact-algorithms.md, "The Λ rows where friction does not
    /// act".)
    pub fn idle_friction_weight(&self, threshold_scale: f64) -> f64 {
        let bound = self.friction * threshold_scale.abs();
        if bound > 0.0 && bound.is_finite() {
            let c = bound / self.rho_t_at(-threshold_scale.abs());
            if c > 0.0 && c.is_finite() {
                return c;
            }
        }
        if self.rho_t > 0.0 && self.rho_n > 0.0 {
            let c = self.rho_n / (self.rho_t * self.rho_t);
            if c > 0.0 && c.is_finite() {
                return c;
            }
        }
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The law the tangent tests start from: μ = 0.3, ρ_n = 50, ρ_τ = 20, κ_n = 70,
    /// κ_τ = 5, no gap, layer or wear.
    fn test_law(method: Method) -> CrackLaw {
        CrackLaw {
            method,
            friction: 0.3,
            rho_n: 50.0,
            rho_t: 20.0,
            rho_t_relative: false,
            initial_gap: 0.0,
            kappa_n: 70.0,
            kappa_t: 5.0,
            kappa_t_relative: false,
            asperity: None,
            wear: None,
            rho_projected: 0.0,
            multiplier_stabilisation: 0.0,
        }
    }

    /// The Λ rows of a point where friction does not act (open; closed with λ̄ = 0) change
    /// with the stress unit exactly as those of a point where it acts: stress × length.
    /// Laws (3D, μ = 0.3, h = 0.01): the augmented Lagrangian with the default
    /// ρ_τ = ρ_n/(μ|λ̄|) (ρ_n = 100 s, the law's fixed ρ_τ 1/h) and with a given ρ_τ = 20 (1/length:
    /// no stress in it), the stabilised law (κ_n = 140 s), and the augmented Lagrangian with
    /// an asperity layer (a = 0.015, κ_a = 900 s), at the stress units s = 1 and s = 2.1e11;
    /// every stress (λ, λ̄, λ_ref = 0.035 s, or no threshold scale: λ_ref = 0) × s, lengths
    /// and Λ unchanged. Points: stick, slip, open (λ̄ = 0 and λ̄ ≠ 0), closed with λ̄ = 0.
    /// Reference: dimensional analysis, r_Λ(s)/s and K_ΛΛ(s)/s the same at both scales to
    /// 1e-12 relative; and the weight of the non-acting rows is the slip row's coefficient
    /// at λ̄ = −λ_ref, μ|λ_ref|/ρ_τ(λ_ref) (ρ_n/ρ_τ² without a threshold scale), to 1e-14.
    #[test]
    fn idle_friction_rows_scale_with_the_stress_unit_like_the_acting_ones() {
        let laws = |s: f64| {
            let base = CrackLaw {
                rho_n: 100.0 * s,
                rho_t: 100.0,
                rho_t_relative: true,
                kappa_n: 140.0 * s,
                kappa_t: 0.0,
                kappa_t_relative: true,
                ..test_law(Method::AugmentedLagrangian)
            };
            [
                base,
                CrackLaw { rho_t: 20.0, rho_t_relative: false, ..base },
                CrackLaw { method: Method::Stabilised, ..base },
                CrackLaw { asperity: Some(Asperity { thickness: 0.015, stiffness: 900.0 * s, damping: 0.0 }), ..base },
            ]
        };
        // (what, λ, λ̄, v, in contact), stresses at s = 1.
        let points = [
            ("stick", -0.035, -0.035, [1e-7, 5e-8], true),
            ("slip", -0.035, -0.02, [1e-3, -2e-4], true),
            ("closed, λ̄ = 0", -0.01, 0.0, [1e-3, 1e-4], true),
            ("open", 0.0, 0.0, [1e-3, 1e-4], false),
            ("open, λ̄ ≠ 0", 0.0, -0.02, [1e-3, 1e-4], false),
        ];
        for scale in [0.035, 0.0] {
            for (k, _) in laws(1.0).iter().enumerate() {
                for (what, lambda, lam_bar, v, contact) in points {
                    let at = |s: f64| {
                        let input = PointInput {
                            d_n: if contact { 0.0 } else { -0.02 },
                            v,
                            lambda: lambda * s,
                            big_lambda: [0.2, 0.1],
                            in_contact: contact,
                            lam_bar: lam_bar * s,
                            threshold_scale: scale * s,
                            ..Default::default()
                        };
                        laws(s)[k].respond(2, &input)
                    };
                    let (a, b) = (at(1.0), at(2.1e11));
                    let tag = format!("law {k}, {what}, λ_ref {scale}");
                    let same = |x: f64, y: f64| (x - y / 2.1e11).abs() <= 1e-12 * x.abs().max((y / 2.1e11).abs());
                    for i in 1..3 {
                        assert!(a.r_m[i] != 0.0, "{tag}: Λ row {i} is empty");
                        assert!(same(a.r_m[i], b.r_m[i]), "{tag}: Λ row {i}: {:e} against {:e}", a.r_m[i], b.r_m[i]);
                        for j in 1..3 {
                            assert!(same(a.k_mm[i][j], b.k_mm[i][j]), "{tag}: K_ΛΛ {i}{j}");
                        }
                    }
                }
                let law = laws(1.0)[k];
                let expected = if scale > 0.0 {
                    law.friction * scale / law.rho_t_at(-scale)
                } else {
                    law.rho_n / (law.rho_t * law.rho_t)
                };
                let c = law.idle_friction_weight(scale);
                assert!((c - expected).abs() <= 1e-14 * expected, "law {k}: weight {c:e} against {expected:e}");
            }
        }
    }

    /// The indicators on hand-picked states: compression with contact, separation, the
    /// boundary g_n = 0 counted as contact; stick inside the unit disc, slip outside.
    #[test]
    fn indicators_follow_their_definitions() {
        assert!(contact_indicator(-1.0, 0.0, 10.0));
        assert!(!contact_indicator(0.0, -0.1, 10.0));
        assert!(contact_indicator(0.0, 0.0, 10.0));
        assert!(contact_indicator(0.5, 0.1, 10.0));
        let (stick, g) = friction_indicator([0.5, 0.0], [0.01, 0.0], 10.0);
        assert!(stick && (g[0] - 0.6).abs() < 1e-15);
        assert!(!friction_indicator([0.9, 0.0], [0.02, 0.0], 10.0).0);
    }

    /// The response at one point is the derivative of its residual: central differences
    /// of R (in s = (n·⟦u⟧, τ·⟦u⟧) and m = (λ, Λ)) match the tangent to 1e-6 relative, in
    /// contact sticking and sliding (3D, μλ̄ = −0.3) and out of contact, for every method;
    /// the tangent is symmetric by construction (one k_sm block). The penalty law has no
    /// m unknowns: its m is Λ at the start of the step, frozen, so only the s-derivatives
    /// are checked, and its residual has no m rows.
    #[test]
    fn every_method_tangent_is_the_derivative_of_its_residual() {
        for method in [Method::AugmentedLagrangian, Method::Stabilised, Method::Penalty] {
            let law = CrackLaw {
                initial_gap: 0.01,
                asperity: Some(Asperity { thickness: 0.015, stiffness: 900.0, damping: 3.0 }),
                ..test_law(method)
            };
            let n = [0.0, 0.0, 1.0];
            let tangents = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            // R(s, m) with s = jump in (n, τ1, τ2), m = (λ, Λ1, Λ2), other inputs frozen.
            let eval = |s: [f64; 3], m: [f64; 3], contact: bool| {
                let jump = [s[1], s[2], s[0]];
                let d_n = law.penetration(jump, n, 0.0);
                let v = slip_increment(2, &tangents, jump, [0.0; 3]);
                let p = PointInput {
                    d_n,
                    v,
                    lambda: m[0],
                    big_lambda: [m[1], m[2]],
                    in_contact: contact,
                    lam_bar: -1.0,
                    lock: None,
                    threshold_scale: 0.0,
                    d_n_start: 0.002,
                    threshold_slope: 0.0,
                    threshold_slope_lambda: 0.0,
                };
                law.respond(2, &p)
            };
            let cases = [
                ([-0.02, 0.001, 0.0], [-1.0, 0.2, 0.1], true),  // stick: |Λ + ρ v| < 1
                ([-0.02, 0.05, -0.02], [-1.0, 0.6, 0.3], true), // slip (AL), stick (penalty)
                ([-0.02, 0.2, -0.1], [-1.0, 0.6, 0.3], true),   // slip (every method)
                ([0.02, 0.0, 0.0], [0.1, 0.3, 0.0], false),     // open
            ];
            let penalty = method == Method::Penalty;
            for (s, m, contact) in cases {
                let r = eval(s, m, contact);
                if penalty {
                    assert!(r.r_m == [0.0; 3] && r.k_sm == [[0.0; 3]; 3] && r.k_mm == [[0.0; 3]; 3]);
                }
                let at = |s, m| eval(s, m, contact);
                tangent_matches_central_differences(&at, s, m, 3, !penalty, &format!("{method:?} {s:?} {m:?}"));
            }
        }
    }

    /// The penalty law with its threshold following the iterate (λ̄ = −κ_n⟨d_n⟩₊ − t_a(d_n)
    /// recomputed from s, [`CrackLaw::live_threshold`]): central differences of the residual
    /// in s = (n·⟦u⟧, τ·⟦u⟧) match the tangent with its unsymmetric column ∂r_s,τ/∂s_n to
    /// 1e-6 relative (3D, μ = 0.3, κ_n = 70, layer a = 0.015, κ_a = 900, damping 3), sticking
    /// and sliding, with Λ_start ≠ 0, with the default κ_τ = κ_n/(μ|λ̄|) and a given κ_τ = 5;
    /// and the column is there (the tangent is not symmetric).
    #[test]
    fn penalty_tangent_with_the_live_threshold_is_the_derivative_of_its_residual() {
        for relative in [true, false] {
            for layer in [false, true] {
                let law = CrackLaw {
                    initial_gap: 0.01,
                    kappa_t_relative: relative,
                    asperity: layer.then_some(Asperity { thickness: 0.015, stiffness: 900.0, damping: 3.0 }),
                    ..test_law(Method::Penalty)
                };
                let n = [0.0, 0.0, 1.0];
                let tangents = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
                let start = [0.2, -0.1];
                let eval = |s: [f64; 3], _m: [f64; 3]| {
                    let jump = [s[1], s[2], s[0]];
                    let d_n = law.penetration(jump, n, 0.0);
                    let (lam_bar, slope, _) = law.live_threshold(false, true, true, 0.0, d_n, 0.002).expect("penalty");
                    let p = PointInput {
                        d_n,
                        v: slip_increment(2, &tangents, jump, [0.0; 3]),
                        lambda: 0.0,
                        big_lambda: start,
                        in_contact: true,
                        lam_bar,
                        lock: None,
                        threshold_scale: 0.0,
                        d_n_start: 0.002,
                        threshold_slope: slope,
                        threshold_slope_lambda: 0.0,
                    };
                    law.respond(2, &p)
                };
                // Overlap 0.01 (λ̄ = −0.7 without the layer): stick; slip (relative κ_τ; stick with
                // κ_τ = 5); slip.
                for s in [[-0.02, 0.0005, 0.0002], [-0.02, 0.05, -0.02], [-0.02, 0.3, -0.1]] {
                    let tag = format!("relative {relative} layer {layer} s {s:?}");
                    let r = eval(s, [0.0; 3]);
                    assert!(r.k_ss[1][0] != 0.0 && r.k_ss[0][1] == 0.0, "{tag}: the unsymmetric column");
                    tangent_matches_central_differences(&eval, s, [0.0; 3], 3, false, &tag);
                }
            }
        }
    }

    /// The augmented and stabilised Lagrangians with their threshold following the iterate
    /// (λ̄ = λ − t_a(d_n) recomputed from s and m, [`CrackLaw::live_threshold`]): central
    /// differences of the residual in s = (n·⟦u⟧, τ·⟦u⟧) and m = (λ, Λ) match the tangent with
    /// its one-sided terms (`k_sm_live`, `k_ms_live`, and the λ column of `k_mm`) to 1e-6
    /// relative (3D, μ = 0.3, ρ_n = 50, κ_n = 70, λ = −0.7, without and with a layer a = 0.015,
    /// κ_a = 900, damping 3), sticking and sliding, with the default ρ_τ = ρ_n/(μ|λ̄|) and
    /// κ_τ = κ_n/(μ|λ̄|) and with given ρ_τ = 20, κ_τ = 5; and the one-sided λ column is there
    /// (the tangent is not symmetric).
    #[test]
    fn multiplier_tangent_with_the_live_threshold_is_the_derivative_of_its_residual() {
        for method in [Method::AugmentedLagrangian, Method::Stabilised] {
            for relative in [true, false] {
                for layer in [false, true] {
                    let law = CrackLaw {
                        rho_t_relative: relative,
                        kappa_t_relative: relative,
                        asperity: layer.then_some(Asperity { thickness: 0.015, stiffness: 900.0, damping: 3.0 }),
                        ..test_law(method)
                    };
                    let n = [0.0, 0.0, 1.0];
                    let tangents = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
                    let eval = |s: [f64; 3], m: [f64; 3]| {
                        let jump = [s[1], s[2], s[0]];
                        let d_n = law.penetration(jump, n, 0.0);
                        let (lam_bar, slope, slope_lambda) =
                            law.live_threshold(false, true, true, m[0], d_n, 0.002).expect("live");
                        let p = PointInput {
                            d_n,
                            v: slip_increment(2, &tangents, jump, [0.0; 3]),
                            lambda: m[0],
                            big_lambda: [m[1], m[2]],
                            in_contact: true,
                            lam_bar,
                            lock: None,
                            threshold_scale: 0.0,
                            d_n_start: 0.002,
                            threshold_slope: slope,
                            threshold_slope_lambda: slope_lambda,
                        };
                        law.respond(2, &p)
                    };
                    // Stick (small slip increment, |Λ| < 1); slip; slip with |Λ| > 1.
                    let cases = [
                        ([-0.02, 0.0002, -0.0001], [-0.7, 0.2, -0.1]),
                        ([-0.02, 0.05, -0.02], [-0.7, 0.3, 0.4]),
                        ([-0.02, 0.3, -0.1], [-0.7, 0.9, -0.8]),
                    ];
                    for (s, m) in cases {
                        let tag = format!("{method:?} relative {relative} layer {layer} s {s:?} m {m:?}");
                        let r = eval(s, m);
                        assert!(r.k_sm_live[1][0] != 0.0 && r.k_mm[1][0] != 0.0, "{tag}: the one-sided λ column");
                        assert!(r.k_mm[0][1] == 0.0, "{tag}: the transposed entry stays empty");
                        tangent_matches_central_differences(&eval, s, m, 3, true, &tag);
                    }
                }
            }
        }
    }

    /// Central differences (step 1e-7) of `eval`'s residual in the first `dims` components
    /// of s = (n·⟦u⟧, τ·⟦u⟧) and, with `multipliers`, of m = (λ, Λ) match its tangent to
    /// 1e-6 relative at (s, m).
    fn tangent_matches_central_differences(
        eval: &dyn Fn([f64; 3], [f64; 3]) -> PointResponse,
        s: [f64; 3],
        m: [f64; 3],
        dims: usize,
        multipliers: bool,
        tag: &str,
    ) {
        let r = eval(s, m);
        let h = 1e-7;
        let ok = |fd: f64, k: f64| (fd - k).abs() < 1e-6 * (1.0 + k.abs());
        for b in 0..dims {
            let (mut sp, mut sm) = (s, s);
            sp[b] += h;
            sm[b] -= h;
            let (rp, rm) = (eval(sp, m), eval(sm, m));
            for a in 0..dims {
                assert!(ok((rp.r_s[a] - rm.r_s[a]) / (2.0 * h), r.k_ss[a][b]), "{tag}: k_ss {a}{b}");
                let k_ms = r.k_sm[b][a] + r.k_ms_live[a][b];
                assert!(ok((rp.r_m[a] - rm.r_m[a]) / (2.0 * h), k_ms), "{tag}: k_ms {a}{b}");
            }
            if !multipliers {
                continue;
            }
            let (mut mp, mut mm) = (m, m);
            mp[b] += h;
            mm[b] -= h;
            let (rp, rm) = (eval(s, mp), eval(s, mm));
            for a in 0..dims {
                let k_sm = r.k_sm[a][b] + r.k_sm_live[a][b];
                assert!(ok((rp.r_s[a] - rm.r_s[a]) / (2.0 * h), k_sm), "{tag}: k_sm {a}{b}");
                assert!(ok((rp.r_m[a] - rm.r_m[a]) / (2.0 * h), r.k_mm[a][b]), "{tag}: k_mm {a}{b}");
            }
        }
    }

    /// The implicit wear's response is the derivative of its residual at a frozen
    /// compliance q (the slip dependence of q is not in the tangent): central differences in
    /// s = (n·⟦u⟧, τ·⟦u⟧) and m = (λ, Λ) match the tangent to 1e-6 relative for every
    /// method, in contact sliding (2D, μλ̄ = −0.3, q = 2e-3 with ρ_n = 50 and q = 0.05,
    /// where ρ is lowered to 1/(2q)), and the λ-equation vanishes exactly where the worn gap
    /// d_n − q⟨−λ⟩₊ does.
    #[test]
    fn implicit_wear_tangent_is_the_derivative_of_its_residual_at_frozen_compliance() {
        for method in [Method::AugmentedLagrangian, Method::Stabilised, Method::Penalty] {
            for q in [2e-3, 0.05] {
                let law = CrackLaw {
                    wear: Some(Wear { coefficient: 1.0, split: 0.5, coupling: WearCoupling::Implicit }),
                    ..test_law(method)
                };
                let n = [0.0, 1.0, 0.0];
                let tangents = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
                let eval = |s: [f64; 3], m: [f64; 3]| {
                    let jump = [s[1], s[0], 0.0];
                    let p = PointInput {
                        d_n: law.penetration(jump, n, 0.0),
                        v: slip_increment(1, &tangents, jump, [0.0; 3]),
                        lambda: m[0],
                        big_lambda: [m[1], 0.0],
                        in_contact: true,
                        lam_bar: -1.0,
                        lock: None,
                        threshold_scale: 0.0,
                        d_n_start: 0.0,
                        threshold_slope: 0.0,
                        threshold_slope_lambda: 0.0,
                    };
                    law.respond_with_wear(1, &p, q)
                };
                let (s, m) = ([0.01, 0.2, 0.0], [-0.7, 0.6, 0.0]);
                tangent_matches_central_differences(
                    &eval,
                    s,
                    m,
                    2,
                    method != Method::Penalty,
                    &format!("{method:?} q {q}"),
                );
                // λ-equation zero on the worn gap: s_n = −d_n, d_n = q·0.7 (λ = −0.7).
                if method != Method::Penalty {
                    let r0 = eval([-q * 0.7, 0.2, 0.0], m);
                    assert!(r0.r_m[0].abs() < 1e-15, "{method:?}: R_λ = {}", r0.r_m[0]);
                }
            }
        }
    }

    /// The implicit wear with a threshold that follows the iterate (the multiplier laws,
    /// [`CrackLaw::has_live_threshold`]): the friction bound's slope in λ adds to the wear's
    /// normal terms without touching them, so central differences of the residual with
    /// λ̄ = λ in s and m match the tangent at frozen q to 1e-6 relative (2D, AL and
    /// stabilised, q = 2e-3 and 0.05, sticking and sliding); which wear laws may follow
    /// the loop: staggered every method, implicit the multiplier laws without a layer.
    #[test]
    fn implicit_wear_tangent_with_the_live_threshold_is_the_derivative_of_its_residual() {
        for method in [Method::AugmentedLagrangian, Method::Stabilised] {
            for q in [2e-3, 0.05] {
                let law = CrackLaw {
                    wear: Some(Wear { coefficient: 1.0, split: 0.5, coupling: WearCoupling::Implicit }),
                    ..test_law(method)
                };
                assert!(law.has_live_threshold(false) && !law.has_live_threshold(true), "{method:?}");
                let n = [0.0, 1.0, 0.0];
                let tangents = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
                let eval = |s: [f64; 3], m: [f64; 3]| {
                    let jump = [s[1], s[0], 0.0];
                    let d_n = law.penetration(jump, n, 0.0);
                    let (lam_bar, slope, slope_lambda) =
                        law.live_threshold(false, true, true, m[0], d_n, 0.0).expect("live");
                    let p = PointInput {
                        d_n,
                        v: slip_increment(1, &tangents, jump, [0.0; 3]),
                        lambda: m[0],
                        big_lambda: [m[1], 0.0],
                        in_contact: true,
                        lam_bar,
                        lock: None,
                        threshold_scale: 0.0,
                        d_n_start: 0.0,
                        threshold_slope: slope,
                        threshold_slope_lambda: slope_lambda,
                    };
                    law.respond_with_wear(1, &p, q)
                };
                // Slip (|Λ| > 1 after the slip increment) and stick (tiny increment).
                for (s, m) in [([0.01, 0.2, 0.0], [-0.7, 0.6, 0.0]), ([0.01, 1e-5, 0.0], [-0.7, 0.2, 0.0])] {
                    let tag = format!("{method:?} q {q} s {s:?}");
                    let r = eval(s, m);
                    assert!(r.k_sm_live[1][0] != 0.0, "{tag}: the one-sided λ column");
                    tangent_matches_central_differences(&eval, s, m, 2, true, &tag);
                }
            }
        }
        let with = |method: Method, coupling: WearCoupling, layer: bool| CrackLaw {
            wear: Some(Wear { coefficient: 1.0, split: 0.5, coupling }),
            asperity: layer.then_some(Asperity { thickness: 0.015, stiffness: 900.0, damping: 3.0 }),
            ..test_law(method)
        };
        for method in [Method::AugmentedLagrangian, Method::Stabilised, Method::Penalty] {
            for layer in [false, true] {
                assert!(with(method, WearCoupling::Staggered, layer).has_live_threshold(false), "{method:?} {layer}");
            }
        }
        assert!(!with(Method::Penalty, WearCoupling::Implicit, false).has_live_threshold(false));
        assert!(!with(Method::AugmentedLagrangian, WearCoupling::Implicit, true).has_live_threshold(false));
    }

    /// The implicit wear with an asperity layer (the layer and the hard contact in series
    /// with the wear compliance q, [`CrackLaw::respond_worn_layer`]): for every method, in
    /// hard contact and carried by the layer alone (2D, sliding, μλ̄ = −0.3, q = 2e-3 and
    /// 0.05, layer a = 0.015, κ_a = 900, damping 3), central differences of the residual
    /// in s and m match the tangent to 1e-6 relative (q frozen), and the worn gap x makes
    /// the step's wear d_n − x equal to q times the total pressure −R_s,n, with
    /// −R_s,n = t_a(x) + the hard contact's traction, to 1e-12.
    #[test]
    fn implicit_wear_with_a_layer_is_a_series_compliance_with_an_exact_tangent() {
        for method in [Method::AugmentedLagrangian, Method::Stabilised, Method::Penalty] {
            for q in [2e-3, 0.05] {
                for contact in [true, false] {
                    let law = CrackLaw {
                        asperity: Some(Asperity { thickness: 0.015, stiffness: 900.0, damping: 3.0 }),
                        wear: Some(Wear { coefficient: 1.0, split: 0.5, coupling: WearCoupling::Implicit }),
                        ..test_law(method)
                    };
                    let n = [0.0, 1.0, 0.0];
                    let tangents = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
                    let input = |s: [f64; 3], m: [f64; 3]| {
                        let jump = [s[1], s[0], 0.0];
                        PointInput {
                            d_n: law.penetration(jump, n, 0.0),
                            v: slip_increment(1, &tangents, jump, [0.0; 3]),
                            lambda: m[0],
                            big_lambda: [m[1], 0.0],
                            in_contact: contact,
                            lam_bar: -1.0,
                            lock: None,
                            threshold_scale: 0.0,
                            d_n_start: -0.004,
                            threshold_slope: 0.0,
                            threshold_slope_lambda: 0.0,
                        }
                    };
                    let eval = |s: [f64; 3], m: [f64; 3]| law.respond_with_wear(1, &input(s, m), q);
                    // Hard contact: overlap 0.01 and λ = −0.7; layer alone: crush 0.007.
                    let (s, m) = if contact {
                        ([-0.01, 0.2, 0.0], [-0.7, 0.6, 0.0])
                    } else {
                        ([0.008, 0.2, 0.0], [0.0, 0.6, 0.0])
                    };
                    let r = eval(s, m);
                    let tag = format!("{method:?} q {q} contact {contact}");
                    // The series law: d_n − x = q · (total pressure).
                    let p = input(s, m);
                    let x = law.worn_gap(&p, q);
                    let (_, t, _) = law.layer_worn_gap(law.asperity.as_ref().unwrap(), &p, q);
                    assert!(t > 0.0, "{tag}: the layer carries load");
                    assert!(
                        ((p.d_n - x) - q * (-r.r_s[0])).abs() < 1e-12,
                        "{tag}: Δw {} vs q p {}",
                        p.d_n - x,
                        q * -r.r_s[0]
                    );
                    if method == Method::Penalty {
                        assert!(r.r_m == [0.0; 3] && r.k_sm == [[0.0; 3]; 3] && r.k_mm == [[0.0; 3]; 3]);
                    }
                    tangent_matches_central_differences(&eval, s, m, 2, method != Method::Penalty, &tag);
                }
            }
        }
    }
}
