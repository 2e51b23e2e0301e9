//! `run::run_case_results`, the run that also keeps each step's fields in memory (the
//! Python bindings' entry point), against the files and the summary the same run writes.
//!
//! Case: the edge crack of `examples/edge_crack_2d.toml` (strip 100 × 400 mm, crack
//! a = 30 mm from the left edge, E = 210 000 MPa, ν = 0.3, plane strain, σ = 100 MPa in two
//! load steps) on 2.5 mm cells (`Override::new("mesh.divisions", [40, 160])`). Reference:
//! K_I = σ√(πa)·F(0.3) = 1613.7 MPa√mm (Tada's handbook, F = 1.6622), within 1% on this
//! mesh (0.43% measured). The fields kept must be those of `summary.json` exactly: one per
//! step, the largest nodal displacement equal to `max_displacement` to 1e-12 relative.
//! A case given as text (`CaseInput::Text`) with its base directory runs exactly like the
//! file (`examples/plate_with_hole.toml`, whose mesh path is relative to `examples/`).

use fissure::case::overrides::Override;
use fissure::run::{self, CaseInput, RunOptions};
use std::path::{Path, PathBuf};
use toml_edit::{Array, Value};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fissure-run-results-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn edge_crack_fields_in_memory_match_the_summary_and_tada() {
    let divisions: Array = [40i64, 160].into_iter().collect();
    let opts = RunOptions {
        overrides: vec![Override::new("mesh.divisions", Value::Array(divisions)).unwrap()],
        ..Default::default()
    };
    let out = out_dir("edge");
    let r = run::run_case_results(&CaseInput::File(examples().join("edge_crack_2d.toml")), &out, &opts).unwrap();
    assert_eq!(r.dim, 2);
    assert_eq!(r.nodes.len(), 41 * 161);
    assert_eq!(r.nodes.len(), r.summary.mesh.nodes);
    assert_eq!(r.steps.len(), r.summary.steps.len());
    assert_eq!(r.steps.len(), 2);
    for (f, s) in r.steps.iter().zip(&r.summary.steps) {
        assert_eq!(f.index, s.index);
        assert_eq!(f.displacement.len(), 2 * r.nodes.len());
        let max = f.displacement.chunks(2).map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
        assert!((max - s.max_displacement).abs() <= 1e-12 * s.max_displacement, "{max} vs {}", s.max_displacement);
        let lips = f.lips.as_ref().expect("a cracked model keeps its lips");
        for name in ["displacement", "jump", "normal_opening", "tangential_slip"] {
            assert!(
                lips.point_data.iter().any(|a| a.name == name && a.values.len() % lips.points.len() == 0),
                "{name}"
            );
        }
        assert!(lips.cell_data.iter().any(|a| a.name == "crack"));
    }
    let k1 = r.summary.steps[1].cracks[0].front[0].k1;
    let tada = 100.0 * (30.0 * std::f64::consts::PI).sqrt() * 1.6622;
    assert!((k1 - tada).abs() <= 0.01 * tada, "K_I {k1} vs {tada}");
    // The summary returned is the one written.
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    // (Both through JSON text: the same digits parse to the same numbers.)
    let returned: serde_json::Value = serde_json::from_str(&serde_json::to_string(&r.summary).unwrap()).unwrap();
    assert_eq!(written, returned);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn case_text_takes_its_relative_paths_from_its_base() {
    let file = examples().join("plate_with_hole.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let opts = RunOptions::default();
    let (a, b) = (out_dir("file"), out_dir("text"));
    let from_file = run::run_case_results(&CaseInput::File(file), &a, &opts).unwrap();
    let named = b.join("plate_text.toml");
    let input = CaseInput::Text { text: text.clone(), path: named.clone(), base: examples() };
    let from_text = run::run_case_results(&input, &b, &opts).unwrap();
    assert_eq!(from_text.summary.case, named.display().to_string());
    assert!(b.join("plate_text.pvd").is_file(), "output named after the text's path");
    assert_eq!(from_file.steps.last().unwrap().displacement, from_text.steps.last().unwrap().displacement);
    // From another base the mesh is not found, and the error names mesh.file.
    let input = CaseInput::Text { text, path: named, base: std::env::temp_dir() };
    match run::run_case_results(&input, &b, &opts) {
        Err(run::RunError::Case(e)) => assert_eq!(e.key, "mesh.file", "{e}"),
        other => panic!("expected a case error, got {:?}", other.map(|r| r.summary.status)),
    }
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}
