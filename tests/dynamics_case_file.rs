//! Dynamic runs from case files (`[dynamics]`, `[[initial_displacement]]`,
//! `[[initial_velocity]]`, loads as functions of time): the energy table, the velocity and
//! acceleration fields, initial fields that jump across an interface, and bad input.

#[path = "common/cli.rs"]
mod cli;

use cli::fissure;
use fissure::case::{Case, CaseError};
use std::path::Path;
use std::time::Duration;

/// Cantilever [0, 10] × [0, 1], clamped at x = 0, quad4 40 × 4, E = 1000, ν = 0.3, ρ = 1,
/// plane stress (first period T₁ ≈ 19.4, tests/dynamics_free_cantilever.rs).
const CANTILEVER: &str = r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [10.0, 1.0]
divisions = [40, 4]

[[materials]]
E = 1000.0
nu = 0.3
density = 1.0

[[dirichlet]]
group = "left"
components = ["x", "y"]
"#;

fn energy_rows(out: &Path) -> (String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(out.join("energy_history.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect()).collect();
    (header, rows)
}

/// Free vibration from the Euler–Bernoulli tip-load shape (δ = 0.01, formulas of x and y),
/// average acceleration, Δt = 0.2, 50 steps, output every 10 steps.
/// Checks: `energy_history.csv` has exactly the columns of the issue and one row per time
/// step (t = 0 included), kinetic + strain constant to 1e-8 of itself (average acceleration
/// conserves it; reference: Newmark's energy identity), `summary.json` reports the balance
/// error, and the .pvd lists steps 0, 10, …, 50 whose VTU files carry `velocity` and
/// `acceleration`.
#[test]
fn cantilever_case_writes_energy_history_and_velocity_fields() {
    let case = format!(
        "{CANTILEVER}
[dynamics]
dt = 0.2
steps = 50
output_every = 10

[[initial_displacement]]
value = [\"-(y - 0.5) * 0.03 * x * (20 - x) / 2000\", \"0.01 * x^2 * (30 - x) / 2000\"]
"
    );
    let o = fissure("dynamics_case", "cantilever_free", &case, false, Duration::from_secs(120));
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let (header, rows) = energy_rows(&o.out);
    assert_eq!(header, "time,kinetic,strain,external_work,frictional_dissipation,contact_work,total");
    assert_eq!(rows.len(), 51);
    assert_eq!(rows[0][0], 0.0);
    assert!((rows[50][0] - 10.0).abs() < 1e-12);
    let e0 = rows[0][6];
    assert!(e0 > 0.0 && rows[0][1] == 0.0, "starts at rest with strain energy");
    for r in &rows {
        assert!((r[6] - e0).abs() < 1e-8 * e0, "total {} against {e0} at t = {}", r[6], r[0]);
        assert!((r[1] + r[2] - r[3] + r[4] + r[5] - r[6]).abs() < 1e-12 * e0, "total is the sum");
    }
    // Energy moves between strain and kinetic (a quarter period is ~4.9).
    assert!(rows.iter().any(|r| r[1] > 0.5 * e0), "the kinetic energy never rose");
    let s = o.summary.unwrap();
    assert_eq!(s["status"], "ok");
    assert_eq!(s["dynamics"]["scheme"], "newmark");
    assert!(s["dynamics"]["energy_balance_error"].as_f64().unwrap() < 1e-8);
    let pvd = std::fs::read_to_string(o.out.join("cantilever_free.pvd")).unwrap();
    for k in [0, 10, 20, 30, 40, 50] {
        let vtu = format!("cantilever_free_step{k:04}.vtu");
        assert!(pvd.contains(&vtu), "{vtu} not in the pvd");
        let text = std::fs::read_to_string(o.out.join(&vtu)).unwrap();
        assert!(text.contains("Name=\"velocity\"") && text.contains("Name=\"acceleration\""), "{vtu}");
    }
    assert!(!pvd.contains("step0005"), "output_every = 10 skips step 5");
}

/// The same cantilever with `scheme = "theta"`, `theta = 1` (backward Euler on velocities,
/// `tests/dynamics_theta_method.rs`): `summary.json` says `"scheme": "theta"`, `"theta": 1`
/// and the equivalent generalized Newmark β = θ² = 1, γ = θ = 1; the total energy falls at
/// every step (the scheme dissipates), and the run ends `"status": "ok"`.
#[test]
fn cantilever_case_with_the_theta_method_reports_it_and_dissipates() {
    let case = format!(
        "{CANTILEVER}
[dynamics]
scheme = \"theta\"
theta = 1.0
dt = 0.2
steps = 20

[[initial_displacement]]
value = [\"-(y - 0.5) * 0.03 * x * (20 - x) / 2000\", \"0.01 * x^2 * (30 - x) / 2000\"]
"
    );
    let o = fissure("dynamics_case", "cantilever_theta", &case, false, Duration::from_secs(120));
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let (_, rows) = energy_rows(&o.out);
    assert_eq!(rows.len(), 21);
    assert!(rows.windows(2).all(|w| w[1][6] < w[0][6]), "the total energy does not fall at every step");
    let s = o.summary.unwrap();
    assert_eq!(s["status"], "ok");
    let d = &s["dynamics"];
    assert_eq!(d["scheme"], "theta");
    assert_eq!(d["theta"].as_f64(), Some(1.0));
    assert_eq!((d["beta"].as_f64(), d["gamma"].as_f64(), d["alpha"].as_f64()), (Some(1.0), Some(1.0), Some(0.0)));
}

/// A tip traction switched on at t = 0 and held (a number: not ramped in dynamics):
/// the tip deflection swings between 0 and about twice the static one (dynamic
/// amplification of a suddenly applied load, 2 for one mode; bounds [1.9, 2.1]), and the
/// total energy kinetic + strain − external work stays 0 to 1e-8 of the work (the external
/// work by the trapezoidal rule is exact for average acceleration).
/// Reference static deflection: the quasi-static run of the same case.
#[test]
fn suddenly_applied_load_swings_to_twice_the_static_deflection() {
    let load = "\n[[traction]]\ngroup = \"right\"\nvalue = [0.0, -0.001]\n";
    let stat =
        fissure("dynamics_case", "cantilever_static", &format!("{CANTILEVER}{load}"), false, Duration::from_secs(60));
    assert_eq!(stat.code, Some(0), "{}", stat.stderr);
    let u_static = stat.summary.unwrap()["steps"][0]["max_displacement"].as_f64().unwrap();
    let case = format!("{CANTILEVER}{load}\n[dynamics]\ndt = 0.2\nend_time = 30.0\n");
    let o = fissure("dynamics_case", "cantilever_step_load", &case, false, Duration::from_secs(120));
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let s = o.summary.unwrap();
    let peak =
        s["steps"].as_array().unwrap().iter().map(|st| st["max_displacement"].as_f64().unwrap()).fold(0.0, f64::max);
    let ratio = peak / u_static;
    eprintln!("peak {peak:.5e}, static {u_static:.5e}, ratio {ratio:.4}");
    assert!((1.9..=2.1).contains(&ratio), "dynamic amplification {ratio}");
    let (_, rows) = energy_rows(&o.out);
    assert_eq!(rows.len(), 151);
    let work = rows.iter().map(|r| r[3].abs()).fold(0.0, f64::max);
    for r in &rows {
        assert!(r[6].abs() < 1e-8 * work, "total {} at t = {} (work {work})", r[6], r[0]);
    }
}

/// Two blocks [0, 1.05] and [1.05, 2] × [0, 1] across an X-FEM interface (a line crack at
/// x = 1.05, inside a column of quad4 cells 0.2 wide), no supports, no contact, moving
/// apart: u̇₀ = (0.01 sign(1.05 − x), 0). The initial velocity is the L2 projection with the
/// enriched mass, which holds the jump exactly: the kinetic energy at t = 0 is ½ ρ V v₀²
/// (ρ = 2, V = 2) to 1e-10, and the blocks fly apart rigidly: the strain energy stays below
/// 1e-10 of the kinetic one (a field smeared over the cut cells would strain them).
#[test]
fn initial_velocity_that_jumps_across_an_interface_is_exact() {
    let case = r#"[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [10, 5]

[[materials]]
E = 1000.0
nu = 0.25
density = 2.0

[[cracks]]
name = "interface"
shape = "line"
point = [1.05, 0.0]
normal = [1.0, 0.0]

[dynamics]
dt = 0.01
steps = 10

[[initial_velocity]]
value = ["0.01 * signum(1.05 - x)", "0"]
"#;
    let o = fissure("dynamics_case", "blocks_apart", case, false, Duration::from_secs(60));
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let (_, rows) = energy_rows(&o.out);
    let want = 0.5 * 2.0 * 2.0 * 1e-4;
    assert!((rows[0][1] - want).abs() < 1e-10 * want, "kinetic {} against {want}", rows[0][1]);
    for r in &rows {
        assert!((r[1] - want).abs() < 1e-9 * want, "kinetic {} at t = {}", r[1], r[0]);
        assert!(r[2] < 1e-10 * want, "strain {} at t = {}", r[2], r[0]);
    }
}

fn parse_err(text: &str) -> CaseError {
    Case::parse(text, Path::new("case.toml")).expect_err("must fail")
}

/// Bad input in `[dynamics]`: each error names the key and its line.
#[test]
fn bad_dynamics_input_names_the_key_and_line() {
    let with = |extra: &str| format!("{CANTILEVER}\n[dynamics]\n{extra}");
    // [dynamics] is at line 21 of the text (CANTILEVER has 19 lines, then a blank one).
    let line = with("").lines().position(|l| l == "[dynamics]").unwrap() + 1;
    for (extra, key, offset, words) in [
        ("dt = 0.0\nsteps = 10\n", "dynamics.dt", 1, "positive"),
        ("dt = -1.0\nsteps = 10\n", "dynamics.dt", 1, "positive"),
        ("dt = 0.5\nend_time = 0.1\n", "dynamics.end_time", 2, "shorter than one time step"),
        ("dt = 0.1\nsteps = 10\ngamma = 0.4\n", "dynamics.gamma", 3, "unstable"),
        ("dt = 0.1\nsteps = 10\nbeta = 0.1\n", "dynamics.beta", 3, "conditionally stable"),
        ("dt = 0.1\nsteps = 10\nalpha = 0.1\n", "dynamics.alpha", 3, "hht"),
        ("scheme = \"hht\"\ndt = 0.1\nsteps = 10\nalpha = 0.5\n", "dynamics.alpha", 4, "(0, 1/3]"),
        ("steps = 10\n", "dynamics.dt", 0, "missing"),
        ("dt = 0.1\n", "dynamics.end_time", 0, "missing"),
        ("dt = 0.1\nsteps = 10\ntheta = 0.5\n", "dynamics.theta", 3, "goes with scheme = \"theta\""),
        ("scheme = \"hht\"\ndt = 0.1\nsteps = 10\ntheta = 0.5\n", "dynamics.theta", 4, "goes with scheme"),
        ("scheme = \"theta\"\ndt = 0.1\nsteps = 10\ntheta = 0.4\n", "dynamics.theta", 4, "[1/2, 1]"),
        ("scheme = \"theta\"\ndt = 0.1\nsteps = 10\ntheta = 1.5\n", "dynamics.theta", 4, "[1/2, 1]"),
        ("scheme = \"theta\"\ndt = 0.1\nsteps = 10\nbeta = 0.25\n", "dynamics.beta", 4, "not \"theta\""),
        ("scheme = \"theta\"\ndt = 0.1\nsteps = 10\nalpha = 0.1\n", "dynamics.alpha", 4, "not \"theta\""),
        ("scheme = \"theta\"\ndt = -0.1\nsteps = 10\n", "dynamics.dt", 2, "positive"),
    ] {
        let e = parse_err(&with(extra));
        assert_eq!(e.key, key, "{extra}: {e}");
        assert_eq!(e.line, Some(line + offset), "{extra}: {e}");
        assert!(e.message.contains(words), "{extra}: {e}");
    }
    // A material without density.
    let no_density = with("dt = 0.1\nsteps = 10\n").replace("density = 1.0\n", "");
    let e = parse_err(&no_density);
    assert_eq!(e.key, "materials[0].density", "{e}");
    assert_eq!(e.line, Some(no_density.lines().position(|l| l == "[[materials]]").unwrap() + 1), "{e}");
    // A non-positive density.
    let e = parse_err(&with("dt = 0.1\nsteps = 10\n").replace("density = 1.0", "density = 0.0"));
    assert_eq!(e.key, "materials[0].density", "{e}");
    // [steps] and [dynamics] together.
    let e = parse_err(&format!("{}\n[steps]\ncount = 2\n", with("dt = 0.1\nsteps = 10\n")));
    assert!(e.key.starts_with("dynamics"), "{e}");
    // The command line: exit status 2 and the message on stderr.
    let o = fissure("dynamics_case", "bad_dt", &with("dt = 0.0\nsteps = 10\n"), false, Duration::from_secs(30));
    assert_eq!(o.code, Some(2), "{}", o.stderr);
    assert!(o.stderr.contains("dynamics.dt"), "{}", o.stderr);
}

/// Contact laws in dynamics (issue 15): `examples/bar_impact_2d.toml` (frictionless,
/// `formulation = "velocity"`) is accepted by `fissure check` with `method = "stabilised"`
/// and with `method = "penalty"` and `formulation = "displacement"` (both verified in
/// tests/dynamics_bar_rigid_wall.rs); the penalty with the velocity formulation (the
/// example's, a law of a multiplier the penalty does not have) is refused naming
/// `contact.formulation`, and so is an asperity layer with the velocity formulation (the
/// velocity law's shift of the gap would move the layer's crush): exit 2; the layer on the
/// displacement gap (its default formulation, its damping on the normal relative velocity,
/// verified in tests/dynamics_bar_rigid_wall.rs) is accepted.
#[test]
fn contact_laws_in_dynamics_accepted_or_refused_naming_the_key() {
    let case = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/bar_impact_2d.toml");
    let check = |sets: &[&str]| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_fissure"));
        cmd.args(["check", case]);
        for s in sets {
            cmd.args(["--set", s]);
        }
        let out = cmd.output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).to_string())
    };
    for sets in [
        &["cracks.0.contact.method=\"stabilised\""][..],
        &["cracks.0.contact.method=\"penalty\"", "cracks.0.contact.formulation=\"displacement\""][..],
    ] {
        let (code, stderr) = check(sets);
        assert_eq!(code, Some(0), "{sets:?}: {stderr}");
    }
    let (code, stderr) = check(&["cracks.0.contact.method=\"penalty\""]);
    assert_eq!(code, Some(2), "penalty with the velocity formulation: {stderr}");
    assert!(stderr.contains("contact.formulation") && stderr.contains("displacement gap"), "{stderr}");
    let text = std::fs::read_to_string(case).unwrap().replace(
        "formulation = \"velocity\"\n",
        "formulation = \"velocity\"\n\n[cracks.contact.asperity]\nthickness = 0.001\nstiffness = 1.0\n",
    );
    let o = fissure("dynamics_case", "asperity", &text, true, Duration::from_secs(30));
    assert_eq!(o.code, Some(2), "{}", o.stderr);
    assert!(o.stderr.contains("contact.formulation") && o.stderr.contains("asperity layer"), "{}", o.stderr);
    let layered = text.replace("formulation = \"velocity\"\n", "");
    let o = fissure("dynamics_case", "asperity_displacement", &layered, true, Duration::from_secs(30));
    assert_eq!(o.code, Some(0), "the asperity layer on the displacement gap: {}", o.stderr);
}

/// Decodes a PNG; returns its width, height and the set of its RGB colours, after checking
/// that it is not one colour (at least 2% of the pixels differ from the top-left one).
fn decode_png(path: &Path) -> (u32, u32, std::collections::HashSet<[u8; 3]>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
    let px = info.color_type.samples();
    assert!(px >= 3, "{}: not RGB", path.display());
    let data = &buf[..info.buffer_size()];
    let n = (info.width * info.height) as usize;
    let first = &data[..px];
    let differ = data.chunks(px).filter(|p| *p != first).count();
    assert!(differ * 50 > n, "{}: {differ} of {n} pixels differ from the background", path.display());
    (info.width, info.height, data.chunks(px).map(|p| [p[0], p[1], p[2]]).collect())
}

/// The sliding block of tests/dynamics_friction_sliding.rs (block [0, 2] × [0.55, 1] on a
/// clamped lower piece across an X-FEM interface, E = 1e6, ν = 0, ρ = 1, pressure 0.015 on
/// top, μ = 0.3, initial velocity v₀ = 0.01 on the block, HHT α = 0.3, Δt = 0.005) run
/// from a case file to t = 1.2 (the block stops at t = 1).
/// Checks: `energy_history.csv`'s `frictional_dissipation` never decreases (to 1e-12 of
/// its final value) and ends within 1% of the kinetic energy lost, ½ m v₀² = 4.5e-5
/// (m = 0.9; reference: the block's Coulomb deceleration, the friction test); the total
/// stays equal to the sum of its columns (to 1e-10 of ½ m v₀², the CSV's rounding);
/// `summary.json`'s `final_energies` has the CSV's last row (to its 13 digits); `energy.png` is written next to it, decodes, is at least 800 × 500 and
/// has the colours of the kinetic (31, 119, 180) and frictional dissipation (214, 39, 40)
/// lines (the plot draws every column; `docs/outputs.md`).
#[test]
fn sliding_block_case_writes_frictional_dissipation_and_energy_png() {
    let case = r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [20, 10]

[[materials]]
E = 1.0e6
nu = 0.0
density = 1.0

[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.55]
normal = [0.0, 1.0]

[cracks.contact]
friction = 0.3

[[dirichlet]]
group = "bottom"
components = ["x", "y"]

[[traction]]
group = "top"
value = [0.0, -0.015]

[dynamics]
scheme = "hht"
alpha = 0.3
dt = 0.005
end_time = 1.2
output_every = 60

[[initial_velocity]]
value = ["0.005 * (1 + signum(y - 0.55))", "0"]
"#;
    let o = fissure("dynamics_case", "sliding_block", case, false, Duration::from_secs(180));
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let (_, rows) = energy_rows(&o.out);
    assert_eq!(rows.len(), 241);
    let last = rows.last().unwrap();
    let lost = rows[0][1] - last[1];
    let half_m_v2 = 0.5 * 0.9 * 1e-4;
    eprintln!("dissipation {:.6e}, kinetic energy lost {lost:.6e} (½ m v0² = {half_m_v2:.6e})", last[4]);
    assert!((rows[0][1] / half_m_v2 - 1.0).abs() < 1e-9, "initial kinetic energy {}", rows[0][1]);
    assert!((last[4] / lost - 1.0).abs() < 0.01, "dissipation {} against {lost}", last[4]);
    for w in rows.windows(2) {
        assert!(w[1][4] >= w[0][4] - 1e-12 * last[4], "dissipation decreases at t = {}", w[1][0]);
    }
    for r in &rows {
        assert!((r[1] + r[2] - r[3] + r[4] + r[5] - r[6]).abs() < 1e-10 * half_m_v2, "total is the sum");
    }
    let s = o.summary.unwrap();
    let fin = &s["dynamics"]["final_energies"];
    // The CSV has 13 significant digits.
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-11 * a.abs().max(b.abs());
    assert!(same(fin["frictional_dissipation"].as_f64().unwrap(), last[4]), "summary.json against the CSV");
    assert!(same(fin["contact_work"].as_f64().unwrap(), last[5]), "summary.json against the CSV");
    let (w, h, colours) = decode_png(&o.out.join("energy.png"));
    assert!(w >= 800 && h >= 500, "energy.png is {w}×{h}");
    assert!(colours.contains(&[31, 119, 180]), "no kinetic energy line in energy.png");
    assert!(colours.contains(&[214, 39, 40]), "no frictional dissipation line in energy.png");
}

/// `[dynamics] position_correction` and its `summary.json` keys: the two blocks of
/// tests/dynamics_impact_contact.rs (quad4 41 × 1 over [0, 2.05] × [0, 0.05], the
/// interface x = 1.025, E = ρ = 1, ν = 0, ±v₀ = 0.01 towards each other, frictionless,
/// velocity formulation, Newmark average acceleration, Δt = 0.025, 4 steps). Reference:
/// the velocity law leaves the lips overlapping by ½ Δt · 2v₀ = 2.5e-4 after the impact
/// step (step 1) and by nothing more (⟦v⟧ = 0 from then on). Asserted: with the default
/// (`position_correction` absent) `dynamics.position_correction` is enabled, one step
/// corrected, the largest overlap removed 2.5e-4 to 1e-9 relative, the same figure in
/// `steps[1].position_correction` and 0 in the later steps; with `position_correction =
/// false` it is disabled with no step and 0; the energy balance error (the correction's work
/// in `contact_work`) below 1e-10 in both.
#[test]
fn position_correction_key_and_its_summary() {
    for (name, extra, on) in [("corrected", "", true), ("uncorrected", "position_correction = false", false)] {
        let o = fissure("dynamics_case", name, &two_block_case(extra), false, Duration::from_secs(180));
        assert_eq!(o.code, Some(0), "{}", o.stderr);
        let s = o.summary.unwrap();
        let pc = &s["dynamics"]["position_correction"];
        eprintln!("{name}: {pc}, energy balance error {}", s["dynamics"]["energy_balance_error"]);
        assert_eq!(pc["enabled"].as_bool(), Some(on), "{name}: enabled");
        let per_step: Vec<f64> =
            s["steps"].as_array().unwrap().iter().map(|st| st["position_correction"].as_f64().unwrap()).collect();
        assert_eq!(per_step.len(), 5, "{name}: steps 0..4");
        if on {
            assert_eq!(pc["steps"].as_u64(), Some(1), "{name}: corrected steps");
            let largest = pc["largest"].as_f64().unwrap();
            assert!((largest / 2.5e-4 - 1.0).abs() < 1e-9, "{name}: largest overlap removed {largest}");
            assert_eq!(per_step[1], largest, "{name}: steps[1]");
            assert!(per_step.iter().enumerate().all(|(k, &x)| k == 1 || x == 0.0), "{name}: {per_step:?}");
        } else {
            assert_eq!(pc["steps"].as_u64(), Some(0), "{name}: corrected steps");
            assert_eq!(pc["largest"].as_f64(), Some(0.0), "{name}: largest");
            assert!(per_step.iter().all(|&x| x == 0.0), "{name}: {per_step:?}");
        }
        assert!(s["dynamics"]["energy_balance_error"].as_f64().unwrap() < 1e-10, "{name}: energy balance");
    }
}

/// `[dynamics] mass` and its `summary.json` key: the two blocks of
/// tests/dynamics_impact_contact.rs (quad4 41 × 1 over [0, 2.05] × [0, 0.05], the interface
/// x = 1.025, E = ρ = 1, ν = 0, ±v₀ = 0.01 towards each other, frictionless, velocity
/// formulation, Newmark average acceleration, Δt = 0.025, 4 steps). Asserted: the default
/// run reports `dynamics.mass = "consistent"`, `mass = "redistributed"` reports itself; in
/// both the energy balance error (kinetic + strain + contact work, the position
/// correction's work included) stays below 1e-10 (average acceleration is conserving
/// with either mass), and with the redistributed mass the impact step loses less kinetic +
/// strain energy than with the consistent one (the lips' mass no longer stops at once:
/// measured at step 1, 0.9947 against 0.9859 of the initial). A value other than the two
/// is refused naming `dynamics.mass` and its line (exit 2).
#[test]
fn dynamics_mass_key_and_its_summary() {
    let mut after_impact = vec![];
    for (name, extra, want) in
        [("consistent_mass", "", "consistent"), ("redistributed_mass", "mass = \"redistributed\"", "redistributed")]
    {
        let o = fissure("dynamics_case", name, &two_block_case(extra), false, Duration::from_secs(180));
        assert_eq!(o.code, Some(0), "{}", o.stderr);
        let s = o.summary.unwrap();
        assert_eq!(s["dynamics"]["mass"].as_str(), Some(want), "{name}");
        let error = s["dynamics"]["energy_balance_error"].as_f64().unwrap();
        assert!(error < 1e-10, "{name}: energy balance {error}");
        let (header, rows) = energy_rows(&o.out);
        let cols: Vec<&str> = header.split(',').collect();
        let col = |c: &str| cols.iter().position(|h| *h == c).unwrap_or_else(|| panic!("column {c}: {header}"));
        let (k, e) = (col("kinetic"), col("strain"));
        let ratio = (rows[1][k] + rows[1][e]) / (rows[0][k] + rows[0][e]);
        eprintln!("{name}: kinetic + strain after the impact step / t = 0: {ratio:.5}");
        after_impact.push(ratio);
    }
    assert!(after_impact[1] > after_impact[0], "the redistributed mass loses more at the impact: {after_impact:?}");
    let text = two_block_case("mass = \"lumped\"");
    let e = parse_err(&text);
    assert_eq!(e.key, "dynamics.mass", "{e}");
    assert_eq!(e.line, Some(text.lines().position(|l| l.starts_with("mass =")).unwrap() + 1), "{e}");
    assert!(e.message.contains("redistributed"), "{e}");
}

/// The two blocks of tests/dynamics_impact_contact.rs as a case file (quad4 41 × 1 over
/// [0, 2.05] × [0, 0.05], the interface x = 1.025, E = ρ = 1, ν = 0, ±v₀ = 0.01 towards
/// each other, frictionless, velocity formulation, Δt = 0.025, 4 steps), with `extra` lines
/// in `[dynamics]`.
fn two_block_case(extra: &str) -> String {
    format!(
        r#"[model]
analysis = "plane_stress"

[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.05, 0.05]
divisions = [41, 1]

[[materials]]
E = 1.0
nu = 0.0
density = 1.0

[[cracks]]
name = "interface"
shape = "line"
point = [1.025, 0.0]
normal = [1.0, 0.0]

[cracks.contact]
friction = 0.0

[dynamics]
dt = 0.025
steps = 4
{extra}

[[initial_velocity]]
value = ["0.01 * signum(1.025 - x)", "0"]

[output]
vtu = false
plots = false
"#
    )
}
