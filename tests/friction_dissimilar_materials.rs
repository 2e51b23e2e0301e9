//! Frictional contact between bodies of different stiffness (3D meshed pair): the contact
//! loops converge, the answer is in equilibrium, meets Coulomb at the points, and its
//! tangential tractions point the way the Dundurs mismatch says (`docs/reliability.md`,
//! "Diagnosed: 3D frictional contact between dissimilar materials").
//!
//! Geometry (all tests): the Hertz sphere of `tests/meshed_contact_pairs.rs` on its coarse
//! mesh. Quarter model (x, z ≥ 0, symmetry planes x = 0 and z = 0). Slave body `upper`: the
//! block [0, L]² × [·, H] whose lower face is the sphere y = R − √(R² − x² − z²), R = 1,
//! L = 0.6, H = 1; master body `lower`: the block [0, L] × [−H, 0] × [0, L]; hex8 8 × 6 × 8
//! (slave) and 10 × 6 × 10 (master), graded towards the contact point. Supports: master
//! bottom u_y = 0; u_x = 0 on x = 0 and u_z = 0 on z = 0 (both bodies); the sphere is held
//! vertically only by the contact. Load: pressure q on the sphere body's top, q L² = P/4
//! with P = 4E₀*a₀³/(3R), E₀* = 1/(2(1 − ν²)), a₀ = 0.1 (the identical-material Hertz load
//! of the sibling tests, P = 7.326e-4), one load step. Materials: `lower` E = 1, `upper` E
//! = E_u (10 or 100), ν = 0.3 both; Coulomb μ = 0.3 on the pair.
//!
//! References and tolerances:
//! - Vertical force: the contact tractions carry the load, Σ_p w_p t_p·e_y = P/4
//!   (equilibrium of the sphere body), with the traction of the multiplier field, λn −
//!   μλΛ on the slave (`force_on_slave`): within 1e-2 relative. The bodies carry the
//!   augmented traction λ − ρ_n d_n at a closed point, which differs from λ where the weak
//!   non-penetration leaves a pointwise d_n: measured +2.5e-4 (E ratio 10) and +4.7e-3 (E
//!   ratio 100, where the redone loops accept 2 points against the law); after the fixes of
//!   defects 1 and 3 (the lead's merge, thirteenth session) +1.1e-4 and +2.5e-3, both from
//!   the plain loops.
//! - Coulomb at every point in contact: μ|λ|(|Λ| − 1) ≤ 0.2 μ max|λ| (the law is enforced per
//!   multiplier packet, not pointwise: the identical-material sphere example exceeds the
//!   disc by up to 0.08 μ max|λ|, `docs/reliability.md`; measured here 0.16 and 0.14); and
//!   the stick/slip statuses
//!   accepted against the law at most a tenth of the points in contact (the loops' own
//!   limit, `solve::contact_loops::DAMPED_REDO_ABOVE`).
//! - Direction (Dundurs, Johnson, Contact Mechanics §5.4, and the surface displacement of
//!   a half-space under the Hertz pressure, eq. 3.41a: u_r = −(1 − 2ν)(1 + ν)/(3E) ·
//!   (a²/r) p₀ [1 − (1 − r²/a²)^{3/2}], inward, ∝ 1/E): under the same pressure the softer
//!   body's surface moves further towards the axis than the stiffer one's, so friction
//!   pushes the softer body (`lower`, the master) outward and the stiffer one inward. The
//!   tangential traction on the master side is μλΛ (the law's Λ points along the slip of
//!   the master over the slave, ⟦u⟧ = x_master − x_slave, and λ ≤ 0 turns it against it;
//!   the slave carries λn − μλΛ, as `force_on_slave` in `summary.json`): its radial component, integrated over the contact zone, must be outward, and
//!   non-zero (at least 5% of μ times the normal force).

mod common;
use common::contact::{solve_contact_text, two_blocks_msh, ContactRun};
use fissure::contact::law::Status;

const MU: f64 = 0.3;

/// The load P/4 of the quarter model.
fn quarter_load() -> f64 {
    let e_star = 1.0 / (2.0 * (1.0 - 0.3f64 * 0.3));
    4.0 * e_star * 0.1f64.powi(3) / 3.0 / 4.0
}

/// The coarse sphere on the block with `upper` E = `e_upper`, `lower` E = 1.
fn sphere_on_block(e_upper: f64) -> Result<ContactRun, fissure::solve::statics::SolveError> {
    sphere_on_block_with(e_upper, "")
}

/// [`sphere_on_block`] with `extra` appended to the case text.
fn sphere_on_block_with(e_upper: f64, extra: &str) -> Result<ContactRun, fissure::solve::statics::SolveError> {
    let (r_s, l, h) = (1.0f64, 0.6f64, 1.0f64);
    let q = quarter_load() / (l * l);
    let g = |s: f64| s / 3.0 + 2.0 * s.powi(3) / 3.0;
    let msh = two_blocks_msh([[10, 6, 10], [8, 6, 8]], &|b, [xi, eta, zeta]| {
        let (x, z) = (l * g(xi), l * g(zeta));
        if b == 0 {
            [x, -h * g(1.0 - eta), z]
        } else {
            let yb = r_s - (r_s * r_s - x * x - z * z).sqrt();
            [x, yb + (h - yb) * g(eta), z]
        }
    });
    let dir = std::env::temp_dir().join(format!("fissure_dissimilar_{}_{}", std::process::id(), e_upper));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sphere.msh");
    std::fs::write(&file, msh).unwrap();
    let text = format!(
        "[mesh]\nfile = \"{}\"\n[[materials]]\ngroup = \"lower\"\nE = 1.0\nnu = 0.3\n[[materials]]\ngroup = \"upper\"\nE = {e_upper}\nnu = 0.3\n[[dirichlet]]\ngroup = \"lower_bottom\"\ncomponents = [\"y\"]\n[[dirichlet]]\ngroup = \"lower_left\"\ncomponents = [\"x\"]\n[[dirichlet]]\ngroup = \"upper_left\"\ncomponents = [\"x\"]\n[[dirichlet]]\ngroup = \"lower_back\"\ncomponents = [\"z\"]\n[[dirichlet]]\ngroup = \"upper_back\"\ncomponents = [\"z\"]\n[[pressure]]\ngroup = \"upper_top\"\nvalue = {q}\n[[contact_pairs]]\nname = \"hertz\"\nslave = \"upper_bottom\"\nmaster = \"lower_top\"\nfriction = {MU}\n{extra}",
        file.display()
    );
    let run = solve_contact_text(&text);
    let _ = std::fs::remove_dir_all(&dir);
    run
}

/// The checks of the module header on a converged run; returns (vertical force / (P/4),
/// worst Coulomb excess / (μ max|λ|), radial friction force / (μ normal force)).
fn check(run: &ContactRun, label: &str) -> (f64, f64, f64) {
    let rep = run.steps[0].contact.as_ref().expect("a contact report");
    let n = run.x.len();
    let closed = run.status.iter().filter(|s| **s != Status::Open).count();
    let accepted: usize = rep.accepted_disagreements.iter().sum();
    let lam_max = run.lambda.iter().fold(0.0f64, |m, l| m.max(-l));
    let last = run.history.last().expect("a step");
    let (mut fy, mut f_n, mut f_r, mut worst) = (0.0, 0.0, 0.0, 0.0f64);
    for (k, rec) in last.iter().enumerate() {
        if !rec.paired {
            continue;
        }
        let (nv, t1) = (run.normal[k], run.tangent[k]);
        let t2 = [nv[1] * t1[2] - nv[2] * t1[1], nv[2] * t1[0] - nv[0] * t1[2], nv[0] * t1[1] - nv[1] * t1[0]];
        let big = run.big_lambda[k];
        let (w, lam) = (run.weight[k], run.lambda[k]);
        // The tangential traction on the master side, μλΛ (see the module header); the
        // slave carries λn − μλΛ (as `steps[].contact_pairs[].force_on_slave`).
        let tt: Vec<f64> = (0..3).map(|i| MU * lam * (big[0] * t1[i] + big[1] * t2[i])).collect();
        fy += w * (lam * nv[1] - tt[1]);
        f_n += -w * lam;
        let x = run.x[k];
        let r = x[0].hypot(x[2]);
        if r > 0.0 {
            f_r += w * (tt[0] * x[0] + tt[2] * x[2]) / r;
        }
        if run.status[k] != Status::Open {
            worst = worst.max(-MU * lam * (big[0].hypot(big[1]) - 1.0) / (MU * lam_max));
        }
    }
    let load = quarter_load();
    eprintln!(
        "{label}: {closed} of {n} points in contact (stick {}, slip {}), accepted against the law {accepted}, damped redo {}; vertical force {:.6e} ({:+.2e} of P/4 = {load:.6e}), normal force {f_n:.6e}; Coulomb excess {worst:.3e} μ max|λ|; radial friction force on the master {f_r:.3e} ({:.3} μ × normal force); friction {} active set {} Newton {}",
        run.status.iter().filter(|s| **s == Status::Stick).count(),
        run.status.iter().filter(|s| **s == Status::Slip).count(),
        rep.damped_redo,
        fy.abs(),
        fy.abs() / load - 1.0,
        f_r / (MU * f_n),
        rep.friction,
        rep.active_set,
        rep.newton
    );
    assert!(accepted as f64 <= 0.1 * closed as f64, "{label}: {accepted} of {closed} points against the law");
    (fy.abs() / load, worst, f_r / (MU * f_n))
}

/// E ratio 10 (Dundurs β = 0.23 for ν = 0.3): converges, in equilibrium, Coulomb at the
/// points, friction outward on the softer body (tolerances in the module header).
#[test]
fn sphere_ten_times_stiffer_than_block_converges_with_coulomb_and_dundurs_direction() {
    let run = sphere_on_block(10.0).expect("converges");
    let (fy, worst, radial) = check(&run, "E ratio 10");
    assert!((fy - 1.0).abs() < 1e-2, "vertical force {fy} P/4");
    assert!(worst < 0.2, "Coulomb excess {worst} μ max|λ|");
    assert!(radial > 0.05, "radial friction on the softer body {radial} μ N: not outward");
}

/// E ratio 100 (β = 0.28): meets the module header's checks. Before the fixes of defects 1
/// and 3 (docs/reliability.md) the plain loops accepted 203 of 206 points in contact
/// against the law (the generalized Newton's status cycle of the whole zone) and the step
/// was redone with damped Newton steps (2 of 206 accepted); with them the plain loops
/// converge (measured at the merge: 4 of 206 accepted, friction 4, active set 16, Newton
/// 74, vertical force +2.5e-3 of P/4, Coulomb excess 0, radial friction 0.240 μN), and the
/// redo does not run. Either path must meet the checks.
#[test]
fn sphere_hundred_times_stiffer_than_block_meets_coulomb() {
    let run = sphere_on_block(100.0).expect("converges");
    let (fy, worst, radial) = check(&run, "E ratio 100");
    assert!((fy - 1.0).abs() < 1e-2, "vertical force {fy} P/4");
    assert!(worst < 0.2, "Coulomb excess {worst} μ max|λ|");
    assert!(radial > 0.05, "radial friction on the softer body {radial} μ N: not outward");
}

/// E ratio 1e4 (β → 0.29, a rigid sphere): the plain loops and their damped redo both end
/// with every point in contact against the law and no tangential traction; the run fails
/// loudly, naming the law (or the loop at its cap), instead of returning that answer with
/// status ok, and saying that the step was redone with damped Newton steps.
#[test]
fn sphere_rigid_on_block_fails_loudly_naming_the_coulomb_law() {
    let err = match sphere_on_block(1e4) {
        Ok(run) => {
            check(&run, "E ratio 1e4");
            return;
        }
        Err(e) => e.to_string(),
    };
    eprintln!("E ratio 1e4: {err}");
    assert!(err.contains("against the Coulomb law") || err.contains("did not converge"), "{err}");
    // Either way after the damped redo, and the message says so.
    assert!(err.contains("damped Newton steps"), "{err}");
}

/// E ratio 10 with the Newton loops capped at 3 iterations (`[contact_solver] max_newton =
/// 3`; the case converges with the default cap, test above): the plain loops stop at the
/// cap, the step is redone with damped Newton steps, which stop at it too. The error names
/// the Newton loop and its cap, and says that the step had been redone and why (the
/// plain loops' own failure), instead of the redo's failure alone.
#[test]
fn newton_cap_in_the_damped_redo_says_the_step_was_redone_and_why() {
    let err = match sphere_on_block_with(10.0, "[contact_solver]\nmax_newton = 3\n") {
        Ok(_) => panic!("a Newton cap of 3 converged: the test no longer reaches the redo"),
        Err(e) => e.to_string(),
    };
    eprintln!("max_newton = 3: {err}");
    assert!(err.contains("the Newton loop did not converge in 3 iterations"), "{err}");
    assert!(
        err.contains("redone with damped Newton steps because the plain contact loops failed first (step 1: the Newton loop did not converge"),
        "{err}"
    );
}
