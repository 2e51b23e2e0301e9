//! What every run writes next to `summary.json` and shows on the terminal
//! (`docs/outputs.md`): `sif.csv` and `contact.csv` hold exactly the figures of
//! `summary.json` under their documented headers, each PNG plot decodes and is not one
//! colour, the 3D view script is written, `[output] plots = false` writes no plot, the
//! terminal shows a table after each step with the K's, the contact figures and the
//! warnings, `--verbose` one line per contact Newton iteration, `--quiet` nothing.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A closed inclined crack with Coulomb friction (the example
/// `examples/inclined_crack_friction_2d.toml` on a coarser 41 × 41 mesh, 2 load steps):
/// plate [−2, 2]², crack 2a = 0.4 at 45°, E = 1, ν = 0.3, compression σ = 1, μ = 0.3.
fn inclined_case(extra: &str) -> String {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/inclined_crack_friction_2d.toml"))
            .unwrap();
    assert!(text.contains("divisions = [161, 161]"), "the example's mesh line changed");
    let text = text.replace("divisions = [161, 161]", "divisions = [41, 41]");
    format!("{text}\n[steps]\ncount = 2\n{extra}")
}

/// A penny crack (radius 1, in z = 0) in a hex8 block [−2, 2]³ (10 cells a side), closed
/// by σ = 1 and sheared by τ = 0.5 with μ = 0.2: every kind of 3D output on a small mesh.
/// `sif_radius = 0.5` keeps each domain off the far side of the front (the default 1.2
/// would take it in and be warned about) and samples the front every 0.5: 13 points.
const PENNY_3D: &str = r#"
[mesh]
generator = "box"
cell = "hex8"
lower = [-2.0, -2.0, -2.0]
upper = [2.0, 2.0, 2.0]
divisions = [10, 10, 10]

[[materials]]
E = 1.0
nu = 0.3

[[sets]]
name = "p1"
on = "abs(x + 2) + abs(y + 2) + abs(z + 2)"

[[sets]]
name = "p2"
on = "abs(x - 2) + abs(y + 2) + abs(z + 2)"

[[sets]]
name = "p3"
on = "abs(x + 2) + abs(y - 2) + abs(z + 2)"

[[dirichlet]]
group = "p1"
components = ["x", "y", "z"]

[[dirichlet]]
group = "p2"
components = ["y", "z"]

[[dirichlet]]
group = "p3"
components = ["z"]

[[traction]]
group = "front"
value = [0.5, 0.0, -1.0]

[[traction]]
group = "back"
value = [-0.5, 0.0, 1.0]

[[traction]]
group = "right"
value = [0.0, 0.0, 0.5]

[[traction]]
group = "left"
value = [0.0, 0.0, -0.5]

[[cracks]]
name = "penny"
shape = "disc"
centre = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
radius = 1.0
sif_radius = 0.5

[cracks.contact]
friction = 0.2
"#;

struct Run {
    out: PathBuf,
    summary: Value,
    stderr: String,
}

/// Runs `fissure run` on `text` with `args`; panics with stderr when it fails.
fn run(name: &str, text: &str, args: &[&str]) -> Run {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("run_outputs");
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join(format!("{name}.toml"));
    std::fs::write(&case, text).unwrap();
    let out = dir.join(name);
    let _ = std::fs::remove_dir_all(&out);
    let r = Command::new(env!("CARGO_BIN_EXE_fissure"))
        .args(["run", case.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr).into_owned();
    assert!(r.status.success(), "{name}: {stderr}");
    let summary = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    Run { out, summary, stderr }
}

/// The rows of a CSV file as maps column → text, after checking its header.
fn read_csv(path: &Path, header: &[&str]) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(head, header, "{}: header", path.display());
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            head.iter().cloned().zip(rec.iter().map(String::from)).collect()
        })
        .collect()
}

fn num(row: &std::collections::HashMap<String, String>, key: &str) -> f64 {
    row[key].parse().unwrap_or_else(|e| panic!("{key} = {:?}: {e}", row[key]))
}

/// Equal as written by two serialisers of the same f64 (shortest round-trip forms).
fn same(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-14 * a.abs().max(b.abs())
}

/// sif.csv against `steps[].cracks[].front[]`.
fn check_sif_csv(run: &Run) -> usize {
    let rows =
        read_csv(&run.out.join("sif.csv"), &["step", "crack", "point", "x", "y", "z", "K_I", "K_II", "K_III", "G"]);
    let mut expected = 0;
    let mut it = rows.iter();
    for step in run.summary["steps"].as_array().unwrap() {
        for crack in step["cracks"].as_array().unwrap() {
            for (i, p) in crack["front"].as_array().unwrap().iter().enumerate() {
                expected += 1;
                let row = it.next().expect("a sif.csv row per front point");
                assert_eq!(row["step"], step["index"].to_string());
                assert_eq!(row["crack"], crack["name"].as_str().unwrap());
                assert_eq!(row["point"], (i + 1).to_string());
                for (col, v) in [
                    ("x", &p["x"][0]),
                    ("y", &p["x"][1]),
                    ("z", &p["x"][2]),
                    ("K_I", &p["KI"]),
                    ("K_II", &p["KII"]),
                    ("K_III", &p["KIII"]),
                    ("G", &p["G"]),
                ] {
                    assert!(same(num(row, col), v.as_f64().unwrap()), "sif.csv {col}: {} vs {v}", row[col]);
                }
            }
        }
    }
    assert_eq!(rows.len(), expected, "sif.csv rows");
    expected
}

/// contact.csv against `steps[].contact` and `steps[].contact.cracks[]`.
fn check_contact_csv(run: &Run) {
    let header = [
        "step",
        "crack",
        "points",
        "active",
        "stick",
        "slip",
        "lambda_min",
        "lambda_max",
        "friction_iterations",
        "active_set_iterations",
        "newton_iterations",
        "geometry_iterations",
        "residual",
    ];
    let rows = read_csv(&run.out.join("contact.csv"), &header);
    let steps = run.summary["steps"].as_array().unwrap();
    assert_eq!(rows.len(), steps.len(), "one contact.csv row per step and contact crack");
    for (row, step) in rows.iter().zip(steps) {
        let c = &step["contact"];
        let k = &c["cracks"][0];
        assert_eq!(row["step"], step["index"].to_string());
        assert_eq!(row["crack"], k["name"].as_str().unwrap());
        for col in ["points", "active", "stick", "slip"] {
            assert_eq!(row[col], k[col].to_string(), "contact.csv {col}");
        }
        // One contact crack: its figures are the step's.
        for col in ["points", "active", "stick", "slip", "lambda_min", "lambda_max"] {
            assert!(
                same(k[col].as_f64().unwrap(), c[col].as_f64().unwrap()),
                "contact.cracks[0].{col} vs contact.{col}"
            );
        }
        for col in ["lambda_min", "lambda_max"] {
            assert!(same(num(row, col), k[col].as_f64().unwrap()), "contact.csv {col}");
        }
        assert!(same(num(row, "residual"), c["residual"].as_f64().unwrap()), "contact.csv residual");
        for (col, key) in [
            ("friction_iterations", "friction"),
            ("active_set_iterations", "active_set"),
            ("newton_iterations", "newton"),
        ] {
            assert_eq!(row[col], c["iterations"][key].to_string(), "contact.csv {col}");
        }
        assert_eq!(row["geometry_iterations"], "", "small sliding: no geometry loop");
    }
}

/// Decodes a PNG; checks its size and that it is not one colour (at least 2% of the
/// pixels differ from the top-left one, and at least 8 colours).
fn check_png(path: &Path) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let px = info.color_type.samples() * if info.bit_depth == png::BitDepth::Sixteen { 2 } else { 1 };
    let data = &buf[..info.buffer_size()];
    let n = (info.width * info.height) as usize;
    assert!(info.width >= 400 && info.height >= 300, "{}: {}×{}", path.display(), info.width, info.height);
    let first = &data[..px];
    let differ = data.chunks(px).filter(|p| *p != first).count();
    let colours: std::collections::HashSet<&[u8]> = data.chunks(px).collect();
    assert!(differ * 50 > n, "{}: {differ} of {n} pixels differ from the background", path.display());
    assert!(colours.len() >= 8, "{}: {} colours", path.display(), colours.len());
}

/// Reference: the documented columns (`docs/outputs.md`) and `summary.json` of the same
/// run, value for value (shortest round-trip decimal forms on both sides: equal, with a
/// 1e-14 relative allowance for the last digit). The terminal table's K values are those
/// of `summary.json` rounded to 4 decimals. `--verbose` prints one Newton line per
/// iteration: as many as `steps[].contact.iterations.newton` summed over the steps.
#[test]
fn inclined_crack_with_friction_writes_tables_equal_to_summary_and_plots_that_open() {
    let r = run("inclined", &inclined_case(""), &["--verbose"]);
    assert_eq!(check_sif_csv(&r), 4, "2 steps × 2 tips");
    check_contact_csv(&r);
    for png in ["sif_inclined.png", "contact_inclined.png", "contact_convergence.png"] {
        check_png(&r.out.join(png));
    }
    // The terminal: one table per step with the tips' K's and the contact line.
    let steps = r.summary["steps"].as_array().unwrap();
    for step in steps {
        let head = format!("step {}/2  load factor", step["index"]);
        assert!(r.stderr.contains(&head), "no '{head}' in\n{}", r.stderr);
        for p in step["cracks"][0]["front"].as_array().unwrap() {
            let k2 = format!("{:.4}", p["KII"].as_f64().unwrap());
            assert!(r.stderr.contains(&k2), "K_II {k2} not shown:\n{}", r.stderr);
        }
        let c = &step["contact"];
        let line = format!("{} points, {} active ({} stick, {} slip)", c["points"], c["active"], c["stick"], c["slip"]);
        assert!(r.stderr.contains(&line), "no '{line}' in\n{}", r.stderr);
    }
    let newton: u64 = steps.iter().map(|s| s["contact"]["iterations"]["newton"].as_u64().unwrap()).sum();
    let lines = r.stderr.lines().filter(|l| l.trim_start().starts_with("newton ")).count() as u64;
    assert_eq!(lines, newton, "--verbose: one line per Newton iteration\n{}", r.stderr);
    assert!(r.stderr.contains("correction"), "{}", r.stderr);
    // Not a terminal: no progress line drawn (no carriage returns or escape codes).
    assert!(!r.stderr.contains('\r') && !r.stderr.contains('\u{1b}'), "progress drawn off a terminal");
}

/// Reference: `docs/outputs.md`: `--quiet` prints nothing on success; `[output] plots =
/// false` writes the CSV files and no PNG.
#[test]
fn quiet_prints_nothing_and_plots_false_writes_no_png() {
    let r = run("inclined_quiet", &inclined_case("\n[output]\nplots = false\n"), &["--quiet"]);
    assert_eq!(r.stderr, "", "--quiet");
    assert!(r.out.join("sif.csv").exists() && r.out.join("contact.csv").exists());
    let pngs: Vec<_> = std::fs::read_dir(&r.out)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "png"))
        .collect();
    assert!(pngs.is_empty(), "plots = false wrote {pngs:?}");
}

/// Reference: `docs/outputs.md` for 3D: `sif.csv` has a row per front point, the terminal
/// table the min / mean / max of each K along the front, the contact plot is a histogram,
/// and `<stem>_view.py` is written with a warp scale that draws the largest displacement
/// as at most 5% of the model's size (`run::paraview_view::warp_scale`).
#[test]
fn penny_crack_3d_writes_tables_plots_and_the_view_script() {
    let r = run("penny3d", PENNY_3D, &[]);
    let n = check_sif_csv(&r);
    assert!(n >= 12, "{n} front points");
    check_contact_csv(&r);
    for png in ["sif_penny.png", "contact_penny.png", "contact_convergence.png"] {
        check_png(&r.out.join(png));
    }
    let front = r.summary["steps"][0]["cracks"][0]["front"].as_array().unwrap();
    let k1: Vec<f64> = front.iter().map(|p| p["KII"].as_f64().unwrap()).collect();
    let mean = k1.iter().sum::<f64>() / k1.len() as f64;
    assert!(r.stderr.contains(&format!("{} points, min", front.len())), "{}", r.stderr);
    assert!(r.stderr.contains(&format!("{mean:.4}")), "mean K_II {mean:.4} not shown:\n{}", r.stderr);
    let view = std::fs::read_to_string(r.out.join("penny3d_view.py")).unwrap();
    assert!(view.contains("PVD = \"penny3d.pvd\""), "{view}");
    let warp: f64 = view.lines().find_map(|l| l.strip_prefix("WARP = ")).unwrap().parse().unwrap();
    let umax = r.summary["steps"][0]["max_displacement"].as_f64().unwrap();
    let size = 48f64.sqrt();
    assert!(warp * umax <= 0.05 * size && warp * umax > 0.01 * size, "warp {warp}, max |u| {umax}");
}
