//! The fill-reducing orderings on 3D crack-contact systems: the solution does not depend
//! on the ordering.

mod common;

use common::contact::{solve_contact_text, ContactRun};

/// Block [−1, 1]³ (hex8, 8 × 8 × 8 cells) with a disc crack of radius 0.5 at its
/// centre in the plane y = 0 (tip enrichment radius 0.25), E = 1, ν = 0.3, the bottom face
/// clamped and the top face displaced by (4e-3, −2e-3, 0): the crack faces are pressed
/// together and sheared enough for part of them to slip (Coulomb friction, μ = 0.3).
fn case(ordering: &str, condense: bool) -> String {
    format!(
        r#"
[mesh]
generator = "box"
cell = "hex8"
lower = [-1.0, -1.0, -1.0]
upper = [1.0, 1.0, 1.0]
divisions = [8, 8, 8]
[[materials]]
E = 1.0
nu = 0.3
[[dirichlet]]
group = "bottom"
components = ["x", "y", "z"]
[[dirichlet]]
group = "top"
components = ["x", "y", "z"]
values = [4e-3, -2e-3, 0.0]
[[cracks]]
name = "disc"
shape = "disc"
centre = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
radius = 0.5
tip_radius = 0.25
[cracks.contact]
friction = 0.3
[solver]
ordering = "{ordering}"
condense = {condense}
"#
    )
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, |m, x| m.max(x.abs()))
}

/// Largest difference between two runs' contact pressures, friction tractions, jumps and
/// reactions, each relative to the largest magnitude of that quantity.
fn relative_difference(a: &ContactRun, b: &ContactRun) -> f64 {
    let pairs: [(Vec<f64>, Vec<f64>); 4] = [
        (a.lambda.clone(), b.lambda.clone()),
        (a.big_lambda.iter().flatten().copied().collect(), b.big_lambda.iter().flatten().copied().collect()),
        (a.jump.iter().flatten().copied().collect(), b.jump.iter().flatten().copied().collect()),
        (a.reactions.iter().flatten().copied().collect(), b.reactions.iter().flatten().copied().collect()),
    ];
    pairs
        .iter()
        .map(|(x, y)| {
            assert_eq!(x.len(), y.len());
            let scale = max_abs(x.iter().copied()).max(f64::MIN_POSITIVE);
            max_abs(x.iter().zip(y).map(|(p, q)| p - q)) / scale
        })
        .fold(0.0, f64::max)
}

// What: METIS nested dissection and minimum degree give the same solution of a 3D
// crack-contact problem (the case above: disc crack closed and sheared, Coulomb friction),
// on the condensed contact factor and on the whole saddle point (LDLᵀ with the multipliers
// after their primal unknowns). Reference: the AMD run. Tolerance: 1e-8 of each
// quantity's largest magnitude (round-off of two factorisations of the same systems; the
// contact iterations must take the same decisions, so the statuses and iteration counts
// are compared exactly).
#[test]
fn nested_dissection_and_amd_give_the_same_3d_crack_contact_solution() {
    for condense in [true, false] {
        let amd = solve_contact_text(&case("amd", condense)).expect("AMD run solves");
        let nd = solve_contact_text(&case("nested_dissection", condense)).expect("ND run solves");
        let (ca, cn) = (amd.steps[0].contact.as_ref().unwrap(), nd.steps[0].contact.as_ref().unwrap());
        assert!(ca.active > 0 && ca.active == cn.active, "active {} / {}", ca.active, cn.active);
        assert_eq!((ca.stick, ca.slip), (cn.stick, cn.slip));
        assert_eq!(amd.status, nd.status);
        let d = relative_difference(&amd, &nd);
        println!(
            "condense = {condense}: {} active, stick {} slip {}, max relative difference {d:.2e}",
            ca.active, ca.stick, ca.slip
        );
        assert!(d < 1e-8, "condense = {condense}: ND differs from AMD by {d:.2e}");
        if condense {
            let auto = solve_contact_text(&case("auto", condense)).expect("auto run solves");
            assert!(relative_difference(&nd, &auto) < 1e-12, "auto is nested dissection in 3D");
        }
    }
}
