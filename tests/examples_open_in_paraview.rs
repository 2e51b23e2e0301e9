//! Every bundled example runs, everything it writes opens in ParaView, and the view its
//! header recommends renders (offscreen, `xvfb-run pvpython`) to an image that is not
//! blank.

mod common;

use fissure::run::{run_case, RunOptions};
use std::path::Path;

/// Reference: the README's promise that ParaView opens our output directly.
/// For each `examples/*.toml`: the case runs to `"status": "ok"`; ParaView's own PVD
/// reader (pvpython, Debian ParaView 5.11) sees one time step per load step with the
/// load factors as times (per growth entry with the entry as time, for crack growth), and in each step the mesh's point and cell counts and the
/// arrays `displacement` (3), `strain` (6), `stress` (6), `von_mises` (1), `group_id` (1).
/// The largest displacement component ParaView reads does not exceed the
/// `max_displacement` of summary.json (tolerance 1e-12 relative) and is positive.
#[test]
fn every_example_runs_and_its_output_opens_in_paraview() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut cases: Vec<_> = std::fs::read_dir(root.join("examples"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    cases.sort();
    assert!(cases.len() >= 3, "examples: {cases:?}");
    let out_root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("examples");
    let mut runs = vec![];
    for case in &cases {
        let stem = case.file_stem().unwrap().to_string_lossy().to_string();
        let out = out_root.join(&stem);
        let _ = std::fs::remove_dir_all(&out);
        let summary =
            run_case(case, &out, &RunOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", case.display()));
        assert_eq!(summary.status, "ok");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        for key in ["version", "case", "dim", "mesh", "dofs", "steps", "timings_s"] {
            assert!(json.get(key).is_some(), "{stem}: summary.json lacks '{key}'");
        }
        for key in ["assembly", "factorisation", "solve", "output", "total"] {
            assert!(json["timings_s"][key].is_number(), "{stem}: timings_s.{key}");
        }
        runs.push((stem.clone(), out.join(format!("{stem}.pvd")), summary));
    }
    render_recommended_views(root, &runs);
    let paths: Vec<&Path> = runs.iter().map(|r| r.1.as_path()).collect();
    let Some(seen) = common::paraview::pvpython_check_many(&paths) else { return };
    for ((stem, _, summary), desc) in runs.iter().zip(seen) {
        let steps = desc["steps"].as_array().unwrap_or_else(|| panic!("{stem}: no steps in {desc}"));
        assert_eq!(steps.len(), summary.steps.len(), "{stem}: time steps");
        for (step, info) in steps.iter().zip(&summary.steps) {
            // Crack growth: one time per growth entry (time = entry).
            let growth = info.cracks.iter().any(|c| c.growth.is_some());
            let time = if growth { info.index as f64 } else { info.load_factor };
            assert!((step["time"].as_f64().unwrap() - time).abs() < 1e-12, "{stem}: time");
            let blocks = step["blocks"].as_array().unwrap();
            let cracked = !info.cracks.is_empty();
            let block = &blocks[0];
            if cracked {
                // body (sub-cells, nodes duplicated across the crack), crack lips, level sets.
                let names: Vec<&str> = blocks.iter().map(|b| b["name"].as_str().unwrap_or("")).collect();
                // A crack and a meshed contact pair in one model: the pairs' surfaces follow.
                let expected: &[&str] = if info.contact_pairs.is_empty() {
                    &["body", "crack", "levelsets"]
                } else {
                    &["body", "crack", "levelsets", "contact"]
                };
                assert_eq!(names, expected, "{stem}: blocks");
                assert!(block["points"].as_u64().unwrap() as usize > summary.mesh.nodes, "{stem}: duplicated nodes");
                assert!(block["cells"].as_u64().unwrap() as usize > summary.mesh.elements, "{stem}: sub-cells");
                for name in ["jump", "normal_opening", "tangential_slip"] {
                    assert!(blocks[1]["point_data"].get(name).is_some(), "{stem}: crack lips lack {name}");
                }
                assert_eq!(blocks[2]["points"].as_u64().unwrap() as usize, summary.mesh.nodes, "{stem}: level sets");
                assert!(blocks[2]["point_data"].get("enrichment").is_some(), "{stem}: enrichment flags");
            } else {
                // Meshed contact pairs: their surfaces are the `contact` block.
                if !info.contact_pairs.is_empty() {
                    let contact = blocks.iter().find(|b| b["name"] == "contact");
                    let contact = contact.unwrap_or_else(|| panic!("{stem}: no contact block"));
                    for name in ["lambda", "pressure", "Lambda"] {
                        assert!(contact["point_data"].get(name).is_some(), "{stem}: contact lacks {name}");
                    }
                    for name in ["status", "gap", "slip"] {
                        assert!(contact["cell_data"].get(name).is_some(), "{stem}: contact lacks {name}");
                    }
                }
                assert_eq!(block["points"].as_u64().unwrap() as usize, summary.mesh.nodes, "{stem}: points");
                assert_eq!(block["cells"].as_u64().unwrap() as usize, summary.mesh.elements, "{stem}: cells");
            }
            assert_eq!(block["point_data"]["displacement"]["components"].as_u64(), Some(3), "{stem}: displacement");
            for (name, n) in [("strain", 6), ("stress", 6), ("von_mises", 1), ("group_id", 1)] {
                assert_eq!(block["cell_data"][name]["components"].as_u64(), Some(n), "{stem}: {name}");
            }
            let ranges = block["point_data"]["displacement"]["component_ranges"].as_array().unwrap();
            let big = ranges
                .iter()
                .flat_map(|r| r.as_array().unwrap().iter().map(|v| v.as_f64().unwrap().abs()))
                .fold(0.0, f64::max);
            assert!(
                // A dynamic run's first file is t = 0, where an example may start undeformed.
                (big > 0.0 || info.max_displacement == 0.0) && big <= info.max_displacement * (1.0 + 1e-12),
                "{stem}: displacement range {big} vs {}",
                info.max_displacement
            );
        }
    }
}

/// The view an example's header recommends, as `tests/paraview/render_view.py` draws it:
/// (stem, block, warp scale, colour association, array, component, the header's words
/// for the warp scale). 3D examples with a crack use the `<stem>_view.py` their run writes.
#[allow(clippy::type_complexity)]
const RECIPES: [(&str, Option<&str>, Option<f64>, &str, &str, Option<usize>, &str); 15] = [
    ("bar_impact_2d", Some("body"), None, "POINTS", "velocity", Some(0), "colour by `velocity` (X)"),
    ("cantilever_3d", None, Some(1.0), "CELLS", "stress", Some(0), "(scale 1)"),
    ("contact_laws_2d", Some("body"), Some(0.1), "CELLS", "von_mises", None, "scale 0.1"),
    ("crack_growth_inclined_2d", Some("body"), Some(20.0), "CELLS", "von_mises", None, "scale ≈ 20"),
    ("edge_crack_2d", Some("body"), Some(1000.0), "CELLS", "von_mises", None, "scale ≈ 1000"),
    ("fretting_wear_2d", Some("body"), Some(10.0), "CELLS", "von_mises", None, "scale 10"),
    ("hertz_cylinder_2d", Some("body"), Some(10.0), "CELLS", "von_mises", None, "scale 10"),
    ("inclined_crack_friction_2d", Some("body"), Some(0.1), "CELLS", "von_mises", None, "scale 0.1"),
    ("plate_with_hole", None, Some(100.0), "CELLS", "von_mises", None, "scale factor of ~100"),
    ("punch_on_cracked_plate_2d", Some("body"), Some(10.0), "CELLS", "von_mises", None, "scale 10"),
    ("sliding_block_2d", Some("body"), Some(1.0), "CELLS", "von_mises", None, "scale 1"),
    ("sphere_on_block_3d", Some("body"), Some(20.0), "CELLS", "von_mises", None, "scale 20"),
    ("pad_fretting_wear_3d", Some("crack"), None, "POINTS", "wear_total", None, "colour by `wear_total`"),
    ("thick_cylinder", None, None, "POINTS", "displacement", None, "`displacement` magnitude"),
    ("drilled_beam_2d", Some("body"), Some(100.0), "CELLS", "von_mises", None, "scale 100"),
];

/// The recipes that look at a 3D interface from above (the default camera looks along −z).
const LOOK_ALONG: [(&str, [f64; 3]); 1] = [("pad_fretting_wear_3d", [0.0, -1.0, 0.0])];

/// Reference: each example's header ("What to look at in ParaView"). Every example's
/// recommended view renders offscreen to a 900 × 600 image that is not blank: at least 5%
/// of the pixels differ from the background (the top-left pixel) and at least 16 colours
/// (a colour map) appear. The header of each 2D example names the warp scale rendered here;
/// the 3D examples with a crack front render their own `<stem>_view.py` (as
/// `paraview --script=`); a 3D interface (no front) has a recipe like the 2D ones.
fn render_recommended_views(root: &Path, runs: &[(String, std::path::PathBuf, fissure::run::summary::Summary)]) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("examples_render");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut jobs = vec![];
    for (stem, pvd, summary) in runs {
        let png = dir.join(format!("{stem}.png"));
        let view = pvd.with_file_name(format!("{stem}_view.py"));
        // A 3D crack with a front gets its view script; an interface (no front) a recipe.
        let cracked_3d = summary.dim == 3 && summary.steps.iter().any(|s| s.cracks.iter().any(|c| !c.front.is_empty()));
        if cracked_3d {
            assert!(view.exists(), "{stem}: no {}", view.display());
            let header = std::fs::read_to_string(root.join(format!("examples/{stem}.toml"))).unwrap();
            assert!(
                header.contains(&format!("{stem}_view.py")),
                "{stem}: the header does not point to its view script"
            );
            jobs.push(serde_json::json!({"png": png, "script": view}));
            continue;
        }
        let Some(&(_, block, warp, assoc, array, component, words)) = RECIPES.iter().find(|r| r.0 == stem) else {
            panic!("{stem}: no recommended view in RECIPES (add the header's recipe)");
        };
        let header = std::fs::read_to_string(root.join(format!("examples/{stem}.toml"))).unwrap();
        assert!(header.contains(words), "{stem}: the header no longer says '{words}'");
        let component = match (array, component) {
            ("displacement", None) => serde_json::json!("Magnitude"),
            (_, c) => serde_json::json!(c),
        };
        let mut job = serde_json::json!({
            "png": png, "pvd": pvd, "block": block, "warp": warp, "colour": [assoc, array, component]
        });
        if let Some((_, d)) = LOOK_ALONG.iter().find(|r| r.0 == stem) {
            job["look_along"] = serde_json::json!(d);
        }
        jobs.push(job);
    }
    let jobs_file = dir.join("jobs.json");
    std::fs::write(&jobs_file, serde_json::to_string_pretty(&jobs).unwrap()).unwrap();
    let Some(run) = common::paraview::pvpython_render(&jobs_file, "render each example's recommended view") else {
        return;
    };
    let json = run.json.clone().unwrap_or_else(|| panic!("no JSON from the render script\n{}", run.report()));
    assert!(run.status.success() && json["ok"] == true, "rendering failed: {json}\n{}", run.report());
    for job in &jobs {
        let png = Path::new(job["png"].as_str().unwrap());
        let (w, h, differ, colours) = image_stats(png);
        assert_eq!((w, h), (900, 600), "{}", png.display());
        let n = (w * h) as usize;
        assert!(differ * 20 > n, "{}: blank ({differ} of {n} pixels differ from the background)", png.display());
        assert!(colours >= 16, "{}: {colours} colours", png.display());
    }
}

/// Width, height, pixels unlike the top-left one, distinct colours.
fn image_stats(path: &Path) -> (u32, u32, usize, usize) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let px = info.color_type.samples() * if info.bit_depth == png::BitDepth::Sixteen { 2 } else { 1 };
    let data = &buf[..info.buffer_size()];
    let first = &data[..px];
    let differ = data.chunks(px).filter(|p| *p != first).count();
    let colours: std::collections::HashSet<&[u8]> = data.chunks(px).collect();
    (info.width, info.height, differ, colours.len())
}
