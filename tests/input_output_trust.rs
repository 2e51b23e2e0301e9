//! Input and output that must never give a silently wrong answer (issue 11, items 4, 5,
//! 15, 16): parameters named like the formula constants, non-finite results, models too
//! large for the machine, misspelt keys, under-constrained models under `check`, and what a
//! hostile-user audit found on 2026-11-28 (load–unload histories, `ulimit -v`, von Mises
//! at the ends of the double range, a required key given under another name).
//! Each test states its input, the reference and the tolerance.

#[path = "common/cli.rs"]
mod cli;

use fissure::case::{resolve, Case};
use fissure::physics::elasticity::FaceLoad;
use std::path::Path;
use std::time::Duration;

const LIMIT: Duration = Duration::from_secs(120);

/// A 2 × 1 quad4 plate, clamped on the left, with `extra` appended.
fn plate(material: &str, extra: &str) -> String {
    format!(
        r#"[mesh]
generator = "rectangle"
cell = "quad4"
upper = [2.0, 1.0]
divisions = [4, 2]

[[materials]]
{material}

[[dirichlet]]
group = "left"
components = ["x", "y"]
{extra}"#
    )
}

/// Item 4. Geometry: the plate above; parameters E = 1e7 and PI = 2 used as the right
/// edge's traction ["E", "PI"]. Reference: the traction is (1e7, 2) exactly (it was
/// (e, π) = (2.718, 3.142)), and the left reaction balances it: R_x = −1e7 × 1 (edge
/// height 1), R_y = −2, to 1e-9 relative.
#[test]
fn parameters_named_e_and_pi_are_not_replaced_by_the_constants() {
    let text = plate(
        "E = 2e11\nnu = 0.3",
        "[parameters]\nE = 1e7\nPI = 2.0\n\n[[traction]]\ngroup = \"right\"\nvalue = [\"E\", \"PI\"]\n",
    );
    let case = Case::parse(&text, Path::new("params.toml")).unwrap();
    let mesh = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &mesh).unwrap();
    let FaceLoad::Traction(v) = &model.loads[0] else { panic!("a traction") };
    assert_eq!(v[0].eval([2.0, 0.5, 0.0], 1.0), 1e7);
    assert_eq!(v[1].eval([2.0, 0.5, 0.0], 1.0), 2.0);
    let run = cli::fissure("io_trust", "params", &text, false, LIMIT);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let r = &run.summary.unwrap()["steps"][0]["reactions"]["left"];
    let (rx, ry) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
    assert!((rx + 1e7).abs() < 1e-9 * 1e7, "R_x = {rx}");
    assert!((ry + 2.0).abs() < 1e-9 * 1e7, "R_y = {ry}");
}

/// Item 5, result guard. Geometry: the plate above, E = 1e10, ν = 0.3, right-edge
/// traction 1e150 over two steps with factors 1 and 1.5e158: step 1 is finite (stresses
/// ~1e150), step 2 has finite displacements (~3e298) but stresses above the largest
/// double (1.5e308 nominal, more at the clamped corners). (Until 2026-11-28 the test used
/// factor 1e10 with E = 1, whose von Mises *square* overflowed; von Mises is now computed
/// scaled, finite there.) Reference: step 2 fails (exit 1, `"status": "failed"`, the
/// error names the field and the cell), step 1 stays on disk and in summary.json, step 2's
/// VTU is not written.
#[test]
fn non_finite_results_fail_the_step_naming_the_field_and_keep_the_last_good_step() {
    let text = plate(
        "E = 1e10\nnu = 0.3",
        "[[traction]]\ngroup = \"right\"\nvalue = [1e150, 0.0]\n\n[steps]\nfactors = [1.0, 1.5e158]\n",
    );
    let run = cli::fissure("io_trust", "overflow", &text, false, LIMIT);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stderr.contains("step 2: non-finite result"), "{}", run.stderr);
    assert!(run.stderr.contains("field 'stress'") && run.stderr.contains("cell"), "{}", run.stderr);
    let s = run.summary.expect("summary.json is written on failure");
    assert_eq!(s["status"], "failed");
    assert!(s["error"].as_str().unwrap().contains("stress"));
    assert_eq!(s["steps"].as_array().unwrap().len(), 1);
    assert!(cli::non_finite_figures(&s["steps"]).is_empty(), "{:?}", cli::non_finite_figures(&s["steps"]));
    assert!(run.out.join("overflow_step0001.vtu").exists());
    assert!(!run.out.join("overflow_step0002.vtu").exists());
}

/// Item 5. E = 1e-300 (a unit slip) under a unit traction: whatever the solver does,
/// the run is never reported ok with a non-finite figure: either it fails cleanly
/// (exit 1, a message naming the field or the solve), or every figure is finite and the
/// displacement is the analytic σL/E to 1e-6 (uniaxial plane strain: at least 1e300).
#[test]
fn tiny_young_modulus_is_never_reported_ok_with_non_finite_figures() {
    let text = plate("E = 1e-300\nnu = 0.3", "[[traction]]\ngroup = \"right\"\nvalue = [1.0, 0.0]\n");
    let run = cli::fissure("io_trust", "tiny_e", &text, false, LIMIT);
    let s = run.summary.expect("summary.json");
    match run.code {
        Some(0) => {
            assert_eq!(s["status"], "ok");
            assert!(cli::non_finite_figures(&s).is_empty(), "{:?}", cli::non_finite_figures(&s));
            let umax = s["steps"][0]["max_displacement"].as_f64().unwrap();
            assert!(umax >= 1e300 * 0.9 && umax.is_finite(), "max |u| {umax}");
        }
        Some(1) => {
            assert_eq!(s["status"], "failed");
            assert!(run.stderr.contains("error:"), "{}", run.stderr);
        }
        other => panic!("exit {other:?}: {}", run.stderr),
    }
}

/// Item 5. Loads and stiffnesses at the ends of the floating-point range: a traction of
/// 1e-300 with E = 1, and a traction of 1 with E = 1e300, on the plate above. The
/// solution is linear in σ/E: reference max |u| = u₁ σ/E with u₁ the same plate at
/// σ = E = 1, to 1e-9 relative (it was 0 with status ok: the norms of the linear solver
/// and of `max_displacement` squared 1e-300 to 0).
#[test]
fn displacement_scales_exactly_with_tiny_loads_and_huge_stiffness() {
    let run = |name: &str, e: &str, sigma: &str| {
        let text =
            plate(&format!("E = {e}\nnu = 0.3"), &format!("[[traction]]\ngroup = \"right\"\nvalue = [{sigma}, 0.0]\n"));
        let o = cli::fissure("io_trust", name, &text, false, LIMIT);
        assert_eq!(o.code, Some(0), "{name}: {}", o.stderr);
        o.summary.unwrap()["steps"][0]["max_displacement"].as_f64().unwrap()
    };
    let u1 = run("unit", "1.0", "1.0");
    for (name, e, sigma, ratio) in [("tiny_load", "1.0", "1e-300", 1e-300), ("huge_e", "1e300", "1.0", 1e-300)] {
        let u = run(name, e, sigma);
        assert!((u - u1 * ratio).abs() <= 1e-9 * u1 * ratio, "{name}: max |u| {u:e} vs {:e}", u1 * ratio);
    }
}

/// Item 15. divisions = [2e8, 2e8] (4e16 cells): refused before the mesh is built, exit 2,
/// the message names `mesh.divisions`, the memory needed and the memory available.
#[test]
fn absurd_divisions_fail_before_meshing_with_needed_and_available_memory() {
    let text = plate("E = 1.0\nnu = 0.3", "").replace("divisions = [4, 2]", "divisions = [200000000, 200000000]");
    let run = cli::fissure("io_trust", "huge", &text, false, LIMIT);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    for what in ["mesh.divisions", "needs at least", "available", "MemAvailable"] {
        assert!(run.stderr.contains(what), "'{what}' missing: {}", run.stderr);
    }
    let check = cli::fissure("io_trust", "huge_check", &text, true, LIMIT);
    assert_eq!(check.code, Some(2), "{}", check.stderr);
    assert!(check.stderr.contains("mesh.divisions"), "{}", check.stderr);
}

/// Item 16a. `nuu = 0.25` instead of `nu`: the error names `nuu` on its own line and
/// suggests `nu`; an optional key misspelt (`compresion`) suggests `compression`.
#[test]
fn misspelt_key_is_named_with_the_close_known_key() {
    let text = plate("E = 1.0\nnuu = 0.25", "");
    let e = Case::parse(&text, Path::new("typo.toml")).unwrap_err();
    assert_eq!(e.key, "materials[0].nuu");
    assert_eq!(e.line, Some(9));
    assert!(e.message.contains("unknown key 'nuu'") && e.message.contains("did you mean 'nu'"), "{e}");
    let text = plate("E = 1.0\nnu = 0.25", "[output]\ncompresion = \"lz4\"\n");
    let e = Case::parse(&text, Path::new("typo.toml")).unwrap_err();
    assert!(e.message.contains("unknown key 'compresion' (did you mean 'compression'?)"), "{e}");
}

/// Item 16b. A roller (x only) on the left edge: `check` names the free motion
/// (translation along y) as `run` does, and neither calls it a failed solve.
#[test]
fn check_names_the_free_motions_of_an_under_constrained_model() {
    let text = plate("E = 1.0\nnu = 0.3", "").replace("components = [\"x\", \"y\"]", "components = [\"x\"]");
    let check = cli::fissure("io_trust", "free_check", &text, true, LIMIT);
    let run = cli::fissure("io_trust", "free_run", &text, false, LIMIT);
    for o in [&check, &run] {
        assert_eq!(o.code, Some(1), "{}", o.stderr);
        assert!(o.stderr.contains("under-constrained") && o.stderr.contains("translation along y"), "{}", o.stderr);
        assert!(!o.stderr.contains("solve failed"), "{}", o.stderr);
    }
}

/// Found by the long randomised part of `tests/adversarial.rs` (its input
/// `E=1.751e31 sigma=2.190e-300`): the plate above with E = 1.751e31 under a traction of
/// 2.19e-300, whose displacements, σL/E ≈ 1e-331, lie below the smallest double
/// (4.9e-324), so no solve can represent them. Reference: a clean failure (exit 1,
/// `"status": "failed"`) whose message says that the displacements underflow and how to
/// fix the units (before: "the linear system was not solved accurately (relative residual
/// 3.67e-7 > 1e-8)", which named no cause).
#[test]
fn displacements_below_the_double_range_fail_naming_the_underflow() {
    let text = plate("E = 1.751e31\nnu = 0.3", "[[traction]]\ngroup = \"right\"\nvalue = [2.19e-300, 0.0]\n");
    let run = cli::fissure("io_trust", "underflow", &text, false, LIMIT);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    let s = run.summary.expect("summary.json");
    assert_eq!(s["status"], "failed");
    let e = s["error"].as_str().unwrap_or_default();
    assert!(e.contains("underflow double precision") && e.contains("other units"), "{e}");
}

/// Found by a hostile-user audit (2026-11-28, F6): a load–unload history that repeats or
/// reverses a load factor, `factors = [1, 1, -1, 0]`, failed at step 2 with "pvd entries 0
/// and 3 share time 1 and part 0" (the PVD's time was the load factor), keeping step 1
/// only. Geometry: the plate above (linear, no crack), a traction (1, 0) on the right edge.
/// Reference: every step is run and written; the PVD's times are the step numbers 1..4
/// (distinct and in the order of the history); linearity: step 2 = step 1, step 3 = −step
/// 1 and step 4 = 0 in the left reaction (|R₁| = 1: the traction times the edge height 1),
/// to 1e-12 of |R₁|.
#[test]
fn load_unload_history_writes_every_step_in_the_order_of_the_history() {
    let text = plate(
        "E = 1.0\nnu = 0.3",
        "[[traction]]\ngroup = \"right\"\nvalue = [1.0, 0.0]\n\n[steps]\nfactors = [1, 1, -1, 0]\n",
    );
    let run = cli::fissure("io_trust", "cycle", &text, false, LIMIT);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let s = run.summary.expect("summary.json");
    let steps = s["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 4);
    let rx: Vec<f64> = steps.iter().map(|st| st["reactions"]["left"][0].as_f64().unwrap()).collect();
    let r1 = rx[0].abs();
    assert!((r1 - 1.0).abs() <= 1e-9, "R_x {rx:?}");
    for (k, want) in [(1, rx[0]), (2, -rx[0]), (3, 0.0)] {
        assert!((rx[k] - want).abs() <= 1e-12 * r1, "step {}: R_x {} vs {want}", k + 1, rx[k]);
    }
    let pvd = std::fs::read_to_string(run.out.join("cycle.pvd")).unwrap();
    let times: Vec<&str> = pvd
        .lines()
        .filter(|l| l.contains("part=\"0\""))
        .filter_map(|l| l.split("timestep=\"").nth(1)?.split('"').next())
        .collect();
    assert_eq!(times.len(), 4, "{pvd}");
    for (k, t) in times.iter().enumerate() {
        assert_eq!(t.parse::<f64>().unwrap(), (k + 1) as f64, "{pvd}");
    }
}

/// Found by a hostile-user audit (2026-11-28, F8): under an address-space limit (`ulimit
/// -v 2000000`, 1.9 GiB) a quad4 plate of 1500 × 1500 cells (4.5e6 unknowns; the memory
/// estimate ≈ 3.6 GiB) aborted with SIGABRT in an allocation, no summary.json: the check
/// compared with `MemAvailable` only. Reference: exit 2 before meshing, naming
/// `mesh.divisions`, the memory needed and the memory available.
#[test]
fn a_model_above_the_address_space_limit_is_refused_before_meshing() {
    let text = plate("E = 1.0\nnu = 0.3", "").replace("divisions = [4, 2]", "divisions = [1500, 1500]");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_trust");
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("ulimit.toml");
    std::fs::write(&case, text).unwrap();
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 2000000 && exec {} run {} --quiet --out {}",
            env!("CARGO_BIN_EXE_fissure"),
            case.display(),
            dir.join("ulimit").display()
        ))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    for what in ["mesh.divisions", "needs at least", "available"] {
        assert!(stderr.contains(what), "'{what}' missing: {stderr}");
    }
}

/// Found by a hostile-user audit (2026-11-28, F9h): `young = 1.0` in place of `E` gave
/// "missing key 'E'" without naming `young` (too far from `E` to be a likely typo).
/// Reference: the error names the missing key and the key the table holds instead.
#[test]
fn a_missing_key_names_the_unread_keys_of_its_table() {
    let text = plate("young = 1.0\nnu = 0.3", "");
    let e = Case::parse(&text, Path::new("young.toml")).unwrap_err();
    assert!(e.message.contains("missing key 'E'") && e.message.contains("'young'"), "{e}");
}

/// Found by a hostile-user audit (2026-11-28, F7): a traction of 1e-200 gave
/// `max_von_mises = 0` (its squares underflowed), and E = traction = 1e170 failed as
/// "von_mises is inf" (its squares overflowed) although every stress is representable.
/// Reference: the plate above is linear, so max von Mises = m₁ σ with m₁ that of the
/// unit traction (E = 1), to 1e-9 relative, at σ = 1e-200 (E = 1) and σ = E = 1e170
/// (stresses scale with σ, displacements with σ/E).
#[test]
fn von_mises_scales_exactly_with_tiny_and_huge_stresses() {
    let run = |name: &str, e: &str, sigma: &str| {
        let text =
            plate(&format!("E = {e}\nnu = 0.3"), &format!("[[traction]]\ngroup = \"right\"\nvalue = [{sigma}, 0.0]\n"));
        let o = cli::fissure("io_trust", name, &text, false, LIMIT);
        assert_eq!(o.code, Some(0), "{name}: {}", o.stderr);
        o.summary.unwrap()["steps"][0]["max_von_mises"].as_f64().unwrap()
    };
    let m1 = run("vm_unit", "1.0", "1.0");
    assert!(m1 > 0.5, "{m1}");
    for (name, e, sigma, ratio) in [("vm_tiny", "1.0", "1e-200", 1e-200), ("vm_huge", "1e170", "1e170", 1e170)] {
        let m = run(name, e, sigma);
        assert!((m - m1 * ratio).abs() <= 1e-9 * m1 * ratio, "{name}: max von Mises {m:e} vs {:e}", m1 * ratio);
    }
}

/// Found by a hostile-user audit (2026-11-28, F9c, F9d): a traction of 1e308 on the plate
/// above (E = 1: displacements ~2e308, beyond the largest double) and E = 1e300 under a
/// traction of 1e-300 (displacements ~1e-600) failed as "singular … a rigid-body motion not
/// prevented" with a NaN residual. Reference: exit 1, and the message names the range of
/// double precision and the remedy (other units) beside the other causes.
#[test]
fn solves_leaving_the_double_range_say_so() {
    for (name, e, sigma) in [("over_range", "1.0", "1e308"), ("under_range", "1e300", "1e-300")] {
        let text =
            plate(&format!("E = {e}\nnu = 0.3"), &format!("[[traction]]\ngroup = \"right\"\nvalue = [{sigma}, 0.0]\n"));
        let o = cli::fissure("io_trust", name, &text, false, LIMIT);
        assert_eq!(o.code, Some(1), "{name}: {}", o.stderr);
        assert!(
            o.stderr.contains("range of double precision") && o.stderr.contains("other units")
                || o.stderr.contains("underflow double precision")
                || o.stderr.contains("not a finite number"),
            "{name}: {}",
            o.stderr
        );
    }
}

/// Found by a hostile-user audit (2026-11-28, F9a): a block [0, 1] × [−0.5, 0.5] cut by a
/// frictionless X-FEM interface y = 0, clamped at the bottom and pressed on top, has its
/// upper half free to slide along x: the solve fails (right), but the message named only
/// "a rigid-body motion not prevented". Reference: exit 1, and the message says that a
/// frictionless contact leaves a part free to slide along it and how to hold it.
#[test]
fn a_part_held_only_by_frictionless_contact_is_said_to_slide() {
    let text = r#"[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.5]
upper = [1.0, 0.5]
divisions = [10, 11]
[[materials]]
E = 1.0
nu = 0.3
[[dirichlet]]
group = "bottom"
components = ["x", "y"]
[[traction]]
group = "top"
value = [0.0, -1e-3]
[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[cracks.contact]
friction = 0.0
"#;
    let o = cli::fissure("io_trust", "frictionless_free", text, false, LIMIT);
    assert_eq!(o.code, Some(1), "{}", o.stderr);
    assert!(o.stderr.contains("frictionless contact") && o.stderr.contains("free to slide"), "{}", o.stderr);
}
