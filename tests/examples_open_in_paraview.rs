//! Every bundled example runs, and everything it writes opens in ParaView.

mod common;

use fissure::run::{run_case, RunOptions};
use std::path::Path;

/// Reference: the README's promise that ParaView opens our output directly.
/// For each `examples/*.toml`: the case runs to `"status": "ok"`; ParaView's own PVD
/// reader (pvpython, Debian ParaView 5.11) sees one time step per load step with the
/// load factors as times, and in each step the mesh's point and cell counts and the
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
    let paths: Vec<&Path> = runs.iter().map(|r| r.1.as_path()).collect();
    let Some(seen) = common::paraview::pvpython_check_many(&paths) else { return };
    for ((stem, _, summary), desc) in runs.iter().zip(seen) {
        let steps = desc["steps"].as_array().unwrap_or_else(|| panic!("{stem}: no steps in {desc}"));
        assert_eq!(steps.len(), summary.steps.len(), "{stem}: time steps");
        for (step, info) in steps.iter().zip(&summary.steps) {
            assert!((step["time"].as_f64().unwrap() - info.load_factor).abs() < 1e-12, "{stem}: time");
            let blocks = step["blocks"].as_array().unwrap();
            let cracked = !info.cracks.is_empty();
            let block = &blocks[0];
            if cracked {
                // body (sub-cells, nodes duplicated across the crack), crack lips, level sets.
                let names: Vec<&str> = blocks.iter().map(|b| b["name"].as_str().unwrap_or("")).collect();
                assert_eq!(names, ["body", "crack", "levelsets"], "{stem}: blocks");
                assert!(block["points"].as_u64().unwrap() as usize > summary.mesh.nodes, "{stem}: duplicated nodes");
                assert!(block["cells"].as_u64().unwrap() as usize > summary.mesh.elements, "{stem}: sub-cells");
                for name in ["jump", "normal_opening", "tangential_slip"] {
                    assert!(blocks[1]["point_data"].get(name).is_some(), "{stem}: crack lips lack {name}");
                }
                assert_eq!(blocks[2]["points"].as_u64().unwrap() as usize, summary.mesh.nodes, "{stem}: level sets");
                assert!(blocks[2]["point_data"].get("enrichment").is_some(), "{stem}: enrichment flags");
            } else {
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
                big > 0.0 && big <= info.max_displacement * (1.0 + 1e-12),
                "{stem}: displacement range {big} vs {}",
                info.max_displacement
            );
        }
    }
}
