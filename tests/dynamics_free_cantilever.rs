//! Free vibration of a cantilever, no contact: the period of the first mode and the energy
//! conservation of average acceleration.
//!
//! Geometry: a 2D strip [0, L] × [0, h], L = 10, h = 1, clamped at x = 0 (both components),
//! quad4 40 × 4 (tri3 80 × 8 for the second mesh type). Material: E = 1000, ν = 0.3,
//! ρ = 1, plane stress. Load: none; initial displacement the Euler–Bernoulli static shape
//! of a tip load, u_y = v(x) = δ x² (3L − x) / (2L³), u_x = −(y − h/2) v'(x), δ = 0.01, at rest.
//! Reference: the first period T₁ = 2π/ω₁ of the same discretisation, ω₁ from the
//! generalized eigenproblem K φ = ω² M φ (consistent mass, `solve::dynamics::lowest_frequency`,
//! inverse iteration); the Euler–Bernoulli value ω = 1.8751² √(EI/(ρ A L⁴)) is checked
//! loosely (5%: shear and the quad4's bending stiffness keep the mesh a few percent off).
//! Measured: the mean time between successive downward zero crossings of the tip's u_y
//! over ~6 periods, Newmark average acceleration with Δt = T₁/100 (period elongation
//! (ω Δt)²/12 ≈ 3e-4). Tolerances: period within 1% of T₁; total energy
//! (kinetic + strain) changes by less than 1e-8 of its initial value per step.

mod common;

use common::dynamics::free_cantilever;
use fissure::element::CellType;
use fissure::solve::time::{DynamicScheme, Newmark};

#[test]
fn free_cantilever_first_period_and_energy_by_average_acceleration() {
    for (kind, div) in [(CellType::Quad4, [40, 4]), (CellType::Tri3, [80, 8])] {
        let (period, t1, totals) =
            free_cantilever(kind, div, &|t1| DynamicScheme::Newmark(Newmark::average_acceleration(t1 / 100.0, 620)));
        let err = period / t1 - 1.0;
        eprintln!("{kind:?}: period {period:.6} against T1 {t1:.6} ({:+.3}%)", 100.0 * err);
        assert!(err.abs() < 0.01, "{kind:?}: period {period} against {t1}");
        let e0 = totals[0];
        let drift = totals.windows(2).map(|w| (w[1] - w[0]).abs() / e0).fold(0.0, f64::max);
        eprintln!("{kind:?}: largest energy change per step {drift:.2e} of E0 = {e0:.4e}");
        assert!(drift < 1e-8, "{kind:?}: energy changes by {drift:.2e} per step");
    }
}

/// HHT-α (α = 0.1) on the same cantilever: the high modes of the initial field (the
/// Euler–Bernoulli shape is not the mesh's first mode: ~10% of its energy) are damped out
/// (between 1% and 20% of the energy lost over the run, against none by average
/// acceleration), the first mode at ω Δt = 0.06 is hardly damped (less than 0.5% lost over
/// the last period), and the first period stays within 1% (second-order accurate). The
/// energy is not monotone step by step: HHT overshoots on modes with ω Δt ≫ 1 during its
/// first steps (a 1-dof model at ω Δt = 100 gains a factor 3.7 in 5 steps before decaying).
#[test]
fn hht_alpha_damps_the_high_modes_not_the_first() {
    let (period, t1, totals) =
        free_cantilever(CellType::Quad4, [40, 4], &|t1| DynamicScheme::Newmark(Newmark::hht(0.1, t1 / 100.0, 620)));
    assert!((period / t1 - 1.0).abs() < 0.01, "period {period} against {t1}");
    let e0 = totals[0];
    let last_period = &totals[totals.len() - 100..];
    let per_period = 1.0 - last_period[99] / last_period[0];
    let lost = 1.0 - totals.last().unwrap() / e0;
    eprintln!(
        "HHT α = 0.1: {:.3}% of the energy dissipated in 620 steps, {:.4}% in the last period",
        100.0 * lost,
        100.0 * per_period
    );
    assert!(lost > 0.01 && lost < 0.2, "dissipated {lost}");
    assert!(per_period.abs() < 5e-3, "the first mode lost {per_period} in one period");
}

/// The redistributed mass (`[dynamics] mass = "redistributed"`, mass redistribution of
/// Khenous, Laborde & Renard 2008) and the first period of a cantilever: the strip of the
/// first test (L = 10, h = 1, E = 1000, ν = 0.3, ρ = 1, plane stress, clamped at x = 0),
/// quad4 40 × 5, (a) without a crack: no cell is cut, so the mass, hence ω₁, is the
/// consistent one exactly (asserted equal to round-off of the inverse iteration, 1e-10);
/// (b) split along its length by a traction-free interface y = 0.5 (mid-cell of the third
/// row): two layers of thickness ½, whose first frequency is half the whole strip's in
/// Euler–Bernoulli (ω ∝ thickness; here with the clamp's half-rows held only through their
/// standard dofs). Reference: ω₁ of the same discretisation with the consistent mass
/// (`lowest_frequency`). Measured: the redistributed mass changes ω₁ of the layers by
/// +0.004% (0.167234 against 0.167227: the cut cells' mass moved onto their nodes, up to
/// h/2 from where it was, in a mode whose motion is nearly uniform across the thickness);
/// asserted below 0.1%, and ω₁ of the layers within 10% of half the strip's (measured
/// 0.5169 of the strip's 0.323510).
#[test]
fn redistributed_mass_changes_the_first_period_of_a_cantilever_only_through_its_cut_cells() {
    use fissure::physics::inertia::MassMatrix;
    use fissure::solve::dynamics::lowest_frequency;
    use fissure::solve::report::SolveOptions;
    let text = |crack: &str| {
        format!(
            r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [10.0, 1.0]
divisions = [40, 5]

[[materials]]
E = 1000.0
nu = 0.3
density = 1.0
{crack}
[[sets]]
name = "clamped"
inside = "x"

[[dirichlet]]
group = "clamped"
components = ["x", "y"]
"#
        )
    };
    let omega = |crack: &str, mass: MassMatrix| {
        let (case, mesh) = common::dynamics::build(&text(crack), "cantilever.toml");
        let model = fissure::case::resolve::build_model(&case, &mesh).unwrap();
        lowest_frequency(&model, &SolveOptions { mass, ..SolveOptions::default() }).unwrap()
    };
    let plain = omega("", MassMatrix::Consistent);
    let plain_red = omega("", MassMatrix::Redistributed);
    let layer = "\n[[cracks]]\nname = \"layer\"\nshape = \"line\"\npoint = [0.0, 0.5]\nnormal = [0.0, 1.0]\n";
    let cons = omega(layer, MassMatrix::Consistent);
    let red = omega(layer, MassMatrix::Redistributed);
    eprintln!(
        "ω₁: strip {plain:.6} (redistributed {plain_red:.6}); layers consistent {cons:.6}, redistributed {red:.6} \
         ({:+.3}%), layers / strip {:.4}",
        100.0 * (red / cons - 1.0),
        cons / plain
    );
    assert!((plain_red / plain - 1.0).abs() < 1e-10, "without a crack: {plain_red} against {plain}");
    assert!((red / cons - 1.0).abs() < 1e-3, "the redistributed mass moves ω₁ by {}", red / cons - 1.0);
    assert!((cons / plain - 0.5).abs() < 0.05, "layers: {cons} against half of {plain}");
}
