//! ParaView reads what `fissure::io::vtu` writes.
//!
//! What it checks: a 2D grid (quads and triangles, z = 0, uncompressed), a 3D grid (hexahedra
//! and tetrahedra, LZ4) and a 3-step `.pvd` with two parts per step ("bulk" = the 3D grid,
//! "crack" = the 2D grid, values scaled by the step number) are written under
//! `CARGO_TARGET_TMPDIR`, then opened with ParaView's own readers through `pvpython`
//! (`tests/paraview/check_vtk.py`: XMLUnstructuredGridReader, PVDReader). For every data set
//! ParaView must report no reader error and the same number of points and cells, the same
//! count of each VTK cell type, the arrays "displacement" (point, 3 components),
//! "von_mises" (cell, 1) and "stress" (cell, 6) as doubles, and per-component value ranges
//! equal to the ones of the written arrays; for the `.pvd`, the time steps, the data time
//! delivered at each step, one block per part with its name, and the scaled ranges of that
//! step. A second test feeds a truncated `.vtu` and expects ParaView to report an error, so
//! that the first test cannot pass by not reading anything.
//!
//! Reference: the grids built below (their coordinates and arrays are the expected values).
//! Tolerance: relative 1e-12 on ranges, bounds and times (they are float64 written in
//! binary, so ParaView should return them exactly; the margin covers decimal printing in
//! the JSON); counts, names, component counts and types exact.
//!
//! Without pvpython the tests print a warning and pass, unless `CI=true` (then they fail).

mod common;

use std::path::{Path, PathBuf};

use common::paraview::{pvpython_check_many, pvpython_run};
use fissure::io::vtu::{write_pvd, write_vtu, Compression, DataArray, PvdEntry, UnstructuredGrid, VtkCell};
use serde_json::Value;

const RTOL: f64 = 1e-12;

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Point data "displacement" (3), cell data "von_mises" (1) and "stress" (6), all smooth
/// functions of the coordinates / cell index times `scale`.
fn add_fields(g: &mut UnstructuredGrid, scale: f64) {
    let disp =
        g.points.iter().flat_map(|&[x, y, z]| [1e-3 * x * scale, -2e-3 * y * scale, 0.5e-3 * z * scale]).collect();
    let n = g.kinds.len();
    let vm = (0..n).map(|c| scale * (10.0 + 3.5 * c as f64)).collect();
    let stress = (0..n).flat_map(|c| (0..6).map(move |k| scale * (c as f64 - 2.0 * k as f64 + 0.25))).collect();
    g.point_data = vec![DataArray::new("displacement", 3, disp)];
    g.cell_data = vec![DataArray::new("von_mises", 1, vm), DataArray::new("stress", 6, stress)];
}

/// 3 × 2 squares on [0, 3] × [0, 2]; the square (1, 0) is split into two triangles.
fn grid_2d(scale: f64) -> UnstructuredGrid {
    let mut g = UnstructuredGrid::default();
    for j in 0..3 {
        for i in 0..4 {
            g.push_point([f64::from(i), f64::from(j), 0.0]);
        }
    }
    let id = |i: u64, j: u64| j * 4 + i;
    for j in 0..2 {
        for i in 0..3 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i, j) == (1, 0) {
                g.push_cell(VtkCell::Triangle, &[a, b, c]);
                g.push_cell(VtkCell::Triangle, &[a, c, d]);
            } else {
                g.push_cell(VtkCell::Quad, &[a, b, c, d]);
            }
        }
    }
    add_fields(&mut g, scale);
    g
}

/// Three unit cubes along x on [0, 3] × [0, 1] × [0, 1]: two hexahedra, and the last cube cut
/// into six tetrahedra around its diagonal.
fn grid_3d(scale: f64) -> UnstructuredGrid {
    let mut g = UnstructuredGrid::default();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..4 {
                g.push_point([f64::from(i), f64::from(j), f64::from(k)]);
            }
        }
    }
    let id = |i: u64, j: u64, k: u64| k * 8 + j * 4 + i;
    for i in 0..3 {
        let v = [
            id(i, 0, 0),
            id(i + 1, 0, 0),
            id(i + 1, 1, 0),
            id(i, 1, 0),
            id(i, 0, 1),
            id(i + 1, 0, 1),
            id(i + 1, 1, 1),
            id(i, 1, 1),
        ];
        if i < 2 {
            g.push_cell(VtkCell::Hexahedron, &v);
        } else {
            for [a, b] in [[1, 2], [1, 5], [4, 5], [4, 7], [3, 7], [3, 2]] {
                g.push_cell(VtkCell::Tetra, &[v[0], v[a], v[b], v[6]]);
            }
        }
    }
    add_fields(&mut g, scale);
    g
}

fn close(expected: f64, got: &Value, what: &str) {
    let got = got.as_f64().unwrap_or_else(|| panic!("{what}: not a number: {got}"));
    assert!(
        (expected - got).abs() <= RTOL * expected.abs().max(got.abs()),
        "{what}: ParaView read {got}, we wrote {expected}"
    );
}

fn component_ranges(a: &DataArray) -> Vec<[f64; 2]> {
    (0..a.components)
        .map(|c| {
            let vals = a.values.iter().skip(c).step_by(a.components);
            [vals.clone().copied().fold(f64::INFINITY, f64::min), vals.copied().fold(f64::NEG_INFINITY, f64::max)]
        })
        .collect()
}

/// Compares one data set description of check_vtk.py with the grid we wrote.
fn check_dataset(g: &UnstructuredGrid, seen: &Value, what: &str) {
    assert_eq!(seen["class"], "vtkUnstructuredGrid", "{what}: {seen}");
    assert_eq!(seen["points"], g.points.len(), "{what}: point count");
    assert_eq!(seen["cells"], g.kinds.len(), "{what}: cell count");
    let mut types = serde_json::Map::new();
    for k in &g.kinds {
        let e = types.entry(k.vtk_id().to_string()).or_insert(Value::from(0));
        *e = Value::from(e.as_u64().unwrap() + 1);
    }
    assert_eq!(seen["cell_types"], Value::Object(types), "{what}: cell types");
    for (c, bound) in seen["bounds"].as_array().expect("bounds").iter().enumerate() {
        let coord = g.points.iter().map(|p| p[c / 2]);
        let expected =
            if c % 2 == 0 { coord.fold(f64::INFINITY, f64::min) } else { coord.fold(f64::NEG_INFINITY, f64::max) };
        close(expected, bound, &format!("{what}: bounds[{c}]"));
    }
    for (location, arrays) in [("point_data", &g.point_data), ("cell_data", &g.cell_data)] {
        let seen_arrays = seen[location].as_object().unwrap_or_else(|| panic!("{what}: no {location}"));
        let mut names: Vec<_> = seen_arrays.keys().cloned().collect();
        names.sort();
        let mut expected_names: Vec<_> = arrays.iter().map(|a| a.name.clone()).collect();
        expected_names.sort();
        assert_eq!(names, expected_names, "{what}: {location} arrays");
        for a in arrays.iter() {
            let s = &seen_arrays[&a.name];
            let w = format!("{what}: {location} {}", a.name);
            assert_eq!(s["components"], a.components, "{w}: components");
            assert_eq!(s["tuples"], a.values.len() / a.components, "{w}: tuples");
            assert_eq!(s["type"], "double", "{w}: type");
            let ranges = s["component_ranges"].as_array().unwrap_or_else(|| panic!("{w}: no ranges"));
            assert_eq!(ranges.len(), a.components, "{w}: ranges");
            for (c, (r, e)) in ranges.iter().zip(component_ranges(a)).enumerate() {
                close(e[0], &r[0], &format!("{w}: min of component {c}"));
                close(e[1], &r[1], &format!("{w}: max of component {c}"));
            }
        }
    }
}

const TIMES: [f64; 3] = [0.0, 0.25, 0.5];

fn step_scale(step: usize) -> f64 {
    1.0 + step as f64
}

#[test]
fn paraview_reads_vtu_and_pvd() {
    let dir = out_dir("paraview_reads_vtu");
    let (g2, g3) = (grid_2d(1.0), grid_3d(1.0));
    let vtu_2d = dir.join("grid_2d.vtu");
    let vtu_3d = dir.join("grid_3d.vtu");
    write_vtu(&vtu_2d, &g2, Compression::None).unwrap();
    write_vtu(&vtu_3d, &g3, Compression::Lz4).unwrap();

    std::fs::create_dir_all(dir.join("steps")).unwrap();
    let mut entries = Vec::new();
    for (step, &time) in TIMES.iter().enumerate() {
        let scale = step_scale(step);
        for (part, (name, grid, compression)) in
            [("bulk", grid_3d(scale), Compression::Lz4), ("crack", grid_2d(scale), Compression::None)]
                .into_iter()
                .enumerate()
        {
            let file = format!("steps/{name}_{step:03}.vtu");
            write_vtu(&dir.join(&file), &grid, compression).unwrap();
            entries.push(PvdEntry { time, part, file, name: Some(name.to_string()) });
        }
    }
    let pvd = dir.join("run.pvd");
    write_pvd(&pvd, &entries).unwrap();

    let Some(seen) = pvpython_check_many(&[&vtu_2d, &vtu_3d, &pvd]) else { return };
    eprintln!("ParaView {} read the files", seen[0]["paraview"]);

    check_dataset(&g2, &seen[0], "grid_2d.vtu");
    check_dataset(&g3, &seen[1], "grid_3d.vtu");

    let p = &seen[2];
    let times = p["times"].as_array().expect("times");
    assert_eq!(times.len(), TIMES.len(), "time steps: {p}");
    let steps = p["steps"].as_array().expect("steps");
    assert_eq!(steps.len(), TIMES.len());
    for (step, (&time, s)) in TIMES.iter().zip(steps).enumerate() {
        let what = format!("run.pvd step {step}");
        close(time, &times[step], &format!("{what}: time"));
        close(time, &s["data_time"], &format!("{what}: data time"));
        assert_eq!(s["class"], "vtkMultiBlockDataSet", "{what}: parts must make a multiblock");
        let blocks = s["blocks"].as_array().expect("blocks");
        let names: Vec<_> = blocks.iter().map(|b| b["name"].as_str().unwrap_or("<none>")).collect();
        assert_eq!(names, ["bulk", "crack"], "{what}: blocks");
        let scale = step_scale(step);
        check_dataset(&grid_3d(scale), &blocks[0], &format!("{what} bulk"));
        check_dataset(&grid_2d(scale), &blocks[1], &format!("{what} crack"));
    }
}

#[test]
fn paraview_reports_a_truncated_vtu() {
    let dir = out_dir("paraview_reports_a_truncated_vtu");
    let good = dir.join("good.vtu");
    write_vtu(&good, &grid_3d(1.0), Compression::None).unwrap();
    let text = std::fs::read(&good).unwrap();
    let bad = dir.join("truncated.vtu");
    std::fs::write(&bad, &text[..text.len() / 2]).unwrap();

    let Some(run) = pvpython_run(&[&bad], &[]) else { return };
    assert_eq!(run.status.code(), Some(1), "a reader error must exit with 1\n{}", run.report());
    let json = run.json.as_ref().unwrap_or_else(|| panic!("no JSON\n{}", run.report()));
    assert_eq!(json["ok"], false, "{json}");
    assert!(!json["errors"].as_array().unwrap().is_empty(), "{json}");
}
