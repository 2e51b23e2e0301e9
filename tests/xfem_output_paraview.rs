//! The X-FEM output grids (body on sub-cells, crack lips, level sets) of cracked models in
//! 2D and 3D are written as `.vtu` files with a three-part `.pvd` per model, and ParaView
//! reads them as written.

mod common;

use fissure::cut::{cut_crack, CutOptions};
use fissure::element::CellType;
use fissure::enrich::{enrich, CrackGeometry, EnrichKind, EnrichOptions};
use fissure::io::vtu::{write_pvd, write_vtu, Compression, DataArray, PvdEntry, UnstructuredGrid, VtkCell};
use fissure::levelset::{sample, CrackShape};
use fissure::mesh::{generate, Mesh};
use fissure::physics::material::{Analysis, Isotropic};
use fissure::physics::model::Model;
use fissure::post::xfem_output::{crack_lips_grid, cracked_body_grid, levelset_grid};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Opening imposed through the Heaviside dofs: b = DELTA/2 n, so the jump is DELTA n
/// wherever the cut cell's nodes all carry Heaviside enrichment.
const DELTA: f64 = 1e-2;

fn cracked_model<'m>(mesh: &'m Mesh, shape: CrackShape, analysis: Analysis) -> Model<'m> {
    let mut model = common::model::bare_model(mesh, analysis, Isotropic { young: 210e3, poisson: 0.3 });
    let ls = sample(&shape, mesh).unwrap();
    let cut = cut_crack(mesh, &ls, &CutOptions::default()).unwrap();
    model.cracks = vec![CrackGeometry { name: "main".into(), levelsets: ls, cut }];
    model.enrichment = enrich(mesh, &model.cracks, &EnrichOptions::default()).unwrap();
    model.crack_pressure = vec![None];
    model
}

/// u = t × (a small linear field on the standard dofs, DELTA/2 n on every Heaviside dof,
/// small arbitrary tip dofs).
fn solution(model: &Model<'_>, normal: [f64; 3], t: f64) -> Vec<f64> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let mut u = vec![0.0; model.enrichment.dofs.n_total()];
    for n in 0..mesh.n_nodes() {
        let x = mesh.nodes[n];
        for i in 0..dim {
            u[n * dim + i] = t * 1e-3 * (x[(i + 1) % dim] - 0.5 * x[i]);
        }
        for it in model.enrichment.node_items(n) {
            let f = it.first_dof as usize;
            match it.kind {
                EnrichKind::Heaviside => (0..dim).for_each(|i| u[f + i] = t * 0.5 * DELTA * normal[i]),
                EnrichKind::Tip => (f..f + it.n_functions() * dim).for_each(|d| u[d] = t * 1e-3 * (d as f64).sin()),
            }
        }
    }
    u
}

fn array<'g>(arrays: &'g [DataArray], name: &str) -> &'g DataArray {
    arrays.iter().find(|a| a.name == name).unwrap_or_else(|| panic!("no array {name}"))
}

/// Σ of the measures of the cells (triangles, tetrahedra, axis-aligned quads and hexes).
fn total_measure(g: &UnstructuredGrid) -> f64 {
    let mut total = 0.0;
    let mut start = 0;
    for (&end, &kind) in g.offsets.iter().zip(&g.kinds) {
        let p: Vec<[f64; 3]> = g.connectivity[start..end as usize].iter().map(|&i| g.points[i as usize]).collect();
        start = end as usize;
        let d = |a: usize, k: usize| -> [f64; 3] { std::array::from_fn(|i| p[k][i] - p[a][i]) };
        total += match p.len() {
            3 => {
                let (a, b) = (d(0, 1), d(0, 2));
                0.5 * (a[0] * b[1] - a[1] * b[0])
            }
            4 if kind == VtkCell::Tetra => {
                let (a, b, c) = (d(0, 1), d(0, 2), d(0, 3));
                (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    .abs()
                    / 6.0
            }
            4 => d(0, 1)[0].abs() * d(0, 3)[1].abs(),
            8 => d(0, 1)[0].abs() * d(0, 3)[1].abs() * d(0, 4)[2].abs(),
            n => panic!("unexpected cell with {n} nodes"),
        };
    }
    total
}

/// An array name and its number of components.
type Expected = (&'static str, u64);

/// What one model wrote: its name, the `.pvd`, and per step (time, [body, lips, levelsets]).
struct Written {
    name: String,
    pvd: PathBuf,
    steps: Vec<(f64, [UnstructuredGrid; 3])>,
}

fn write_model(dir: &Path, name: &str, model: &Model<'_>, normal: [f64; 3]) -> Written {
    let mut entries = vec![];
    let mut steps = vec![];
    for (k, t) in [0.5, 1.0].into_iter().enumerate() {
        let u = solution(model, normal, t);
        let grids = [cracked_body_grid(model, &u), crack_lips_grid(model, &u), levelset_grid(model)];
        for (part, (grid, label)) in grids.iter().zip(["body", "crack", "levelsets"]).enumerate() {
            let file = format!("{name}_{label}_step{:04}.vtu", k + 1);
            write_vtu(&dir.join(&file), grid, Compression::Lz4).unwrap();
            entries.push(PvdEntry { time: t, part, file, name: Some(label.into()) });
        }
        steps.push((t, grids));
    }
    let pvd = dir.join(format!("{name}.pvd"));
    write_pvd(&pvd, &entries).unwrap();
    Written { name: name.into(), pvd, steps }
}

/// Reference: formulation §8 (visual output) and the module doc of `post::xfem_output`.
/// Three models — 2D quad4 with an inclined edge crack (half-line), 3D hex8 with a penny
/// crack (disc), 3D tet4 cut by a plane interface — each written for two steps with a
/// three-part `.pvd` (`body`, `crack`, `levelsets`). Before writing: the body cells tile
/// the domain (Σ measures = 1, tolerance 1e-12); the lips have 2 × facets cells; for the
/// interface (every cut cell Heaviside-only) `jump` = t·DELTA·e_z and `normal_opening` =
/// t·DELTA at every lip point (1e-12). ParaView's PVD reader then sees, per step, three
/// blocks named as written with the grids' point and cell counts and the arrays with their
/// component counts, and the displacement range it reads matches ours (1e-12 relative).
#[test]
fn cracked_output_opens_in_paraview() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("xfem_output_paraview");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    let quad = generate::rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [10, 10]).unwrap();
    let hex = generate::box_mesh(CellType::Hex8, [0.0; 3], [1.0; 3], [5, 5, 5]).unwrap();
    let tet = generate::box_mesh(CellType::Tet4, [0.0; 3], [1.0; 3], [5, 5, 5]).unwrap();
    let dir2: [f64; 2] = [1.0, 0.2];
    let len = (dir2[0] * dir2[0] + dir2[1] * dir2[1]).sqrt();
    let n2 = [-dir2[1] / len, dir2[0] / len, 0.0];
    let cases = [
        (
            "edge2d",
            cracked_model(&quad, CrackShape::HalfLine { tip: [0.55, 0.45], direction: dir2 }, Analysis::PlaneStrain),
            n2,
        ),
        (
            "penny3d",
            cracked_model(
                &hex,
                CrackShape::Disc { centre: [0.5, 0.5, 0.5], normal: [0.0, 0.0, 1.0], radius: 0.3 },
                Analysis::ThreeD,
            ),
            [0.0, 0.0, 1.0],
        ),
        (
            "plane3d",
            cracked_model(
                &tet,
                CrackShape::Plane { point: [0.5, 0.5, 0.5], normal: [0.0, 0.0, 1.0] },
                Analysis::ThreeD,
            ),
            [0.0, 0.0, 1.0],
        ),
    ];
    let mut written = vec![];
    for (name, model, normal) in &cases {
        let w = write_model(&dir, name, model, *normal);
        let n_facets = model.cracks[0].cut.facets.len();
        let n_sub: usize = model.cracks[0].cut.cut_cells.iter().map(|c| c.subcells.len()).sum();
        for (t, [body, lips, _]) in &w.steps {
            assert!((total_measure(body) - 1.0).abs() < 1e-12, "{name}: measure {}", total_measure(body));
            assert_eq!(body.num_cells(), model.mesh.n_cells() - model.cracks[0].cut.cut_cells.len() + n_sub);
            assert_eq!(lips.num_cells(), 2 * n_facets, "{name}");
            if *name == "plane3d" {
                let (jump, open) = (array(&lips.point_data, "jump"), array(&lips.point_data, "normal_opening"));
                for p in 0..lips.num_points() {
                    let j = &jump.values[3 * p..3 * p + 3];
                    assert!(j[0].abs() < 1e-12 && j[1].abs() < 1e-12 && (j[2] - t * DELTA).abs() < 1e-12, "{j:?}");
                    assert!((open.values[p] - t * DELTA).abs() < 1e-12);
                }
            }
        }
        written.push(w);
    }

    let paths: Vec<&Path> = written.iter().map(|w| w.pvd.as_path()).collect();
    let Some(seen) = common::paraview::pvpython_check_many(&paths) else { return };
    let expected_arrays: [(&[Expected], &[Expected]); 3] = [
        (
            &[("displacement", 3)],
            &[("group_id", 1), ("parent_cell", 1), ("side", 1), ("strain", 6), ("stress", 6), ("von_mises", 1)],
        ),
        (
            &[("displacement", 3), ("jump", 3), ("normal_opening", 1), ("tangential_slip", 1)],
            &[("lip", 1), ("crack", 1), ("normal", 3)],
        ),
        (&[("lsn_main", 1), ("enrichment", 1)], &[("group_id", 1), ("status_main", 1)]),
    ];
    for (w, desc) in written.iter().zip(&seen) {
        let name = &w.name;
        let steps = desc["steps"].as_array().unwrap_or_else(|| panic!("{name}: no steps in {desc}"));
        assert_eq!(steps.len(), w.steps.len(), "{name}: time steps");
        for (step, (t, grids)) in steps.iter().zip(&w.steps) {
            assert!((step["time"].as_f64().unwrap() - t).abs() < 1e-12, "{name}: time");
            let blocks = step["blocks"].as_array().unwrap();
            assert_eq!(blocks.len(), 3, "{name}: blocks {blocks:?}");
            for ((block, grid), (label, (point_arrays, cell_arrays))) in
                blocks.iter().zip(grids).zip(["body", "crack", "levelsets"].iter().zip(&expected_arrays))
            {
                assert_eq!(block["name"], Value::from(*label), "{name}: block name");
                assert_eq!(block["points"].as_u64().unwrap() as usize, grid.num_points(), "{name} {label}: points");
                assert_eq!(block["cells"].as_u64().unwrap() as usize, grid.num_cells(), "{name} {label}: cells");
                for (arrays, location) in [(point_arrays, "point_data"), (cell_arrays, "cell_data")] {
                    for (array_name, comps) in arrays.iter() {
                        assert_eq!(
                            block[location][array_name]["components"].as_u64(),
                            Some(*comps),
                            "{name} {label}: {location} {array_name}"
                        );
                    }
                }
                let has_lst = block["point_data"].get("lst_main").is_some();
                assert_eq!(has_lst, *label == "levelsets" && *name != "plane3d", "{name} {label}: lst_main");
                if *label != "levelsets" {
                    let ours = array(&grid.point_data, "displacement");
                    let ranges = block["point_data"]["displacement"]["component_ranges"].as_array().unwrap();
                    for (c, r) in ranges.iter().enumerate() {
                        let vals = ours.values.iter().skip(c).step_by(3);
                        let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
                        let (plo, phi) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
                        let tol = 1e-12 * lo.abs().max(hi.abs()).max(1e-300);
                        assert!((plo - lo).abs() <= tol && (phi - hi).abs() <= tol, "{name} {label}: component {c}");
                    }
                }
            }
        }
    }
}
