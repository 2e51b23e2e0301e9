//! Crack growth along a curved path towards holes: the drilled beam of Bittencourt,
//! Wawrzynek, Ingraffea & Sousa, "Quasi-automatic simulation of crack propagation for 2D
//! LEFM problems", Eng. Fract. Mech. 55 (1996) 321–334 (experiments of Ingraffea &
//! Grigoriu 1990), issue 21's curved-path benchmark.
//!
//! Geometry (inches): the beam [0, 20] × [0, 8], three holes of diameter 0.5 at x = 6,
//! centres y = 2.75, 4.75, 6.75; supports at x = 1 (pin) and x = 19 (roller) on the
//! bottom; the load at mid-span on the top, a traction on the patch 9.9 ≤ x ≤ 10.1. A
//! vertical pre-crack from the bottom edge of length a at the distance b from mid-span, in
//! two configurations: (a, b) = (1, 6) and (1.5, 5). Mesh `meshes/drilled_beam_coarse.msh`
//! (`meshes/drilled_beam.geo` with hf = 0.1: tri3, size h = 0.1 in the band
//! 3.5 ≤ x ≤ 10.5 that holds both paths, 0.08 on the holes, 0.5 far away; 7875 nodes).
//! Material: E = 1, ν = 0.35 (PMMA), plane stress (`examples/drilled_beam_2d.toml`, whose
//! case these tests run on the coarser mesh). Growth: maximum hoop stress, Δa = 0.3 per
//! increment (3 cells; sif_radius 0.3).
//!
//! What the sources fix, and what we could check (searched: the web pages, documentation,
//! code and issue corpora for Bittencourt et al., Ingraffea & Grigoriu, "drilled beam",
//! "beam with three holes", the phase-field "asymmetric notched three-point bending test"):
//! - The dimensions: the brief gave hole centres y = 2.25, 4.25, 6.25 (to check). Two
//!   independent open models of the beam put them at 2.75, 4.75, 6.75 with the notch at
//!   x = 4 and length 1, supports at x = 1 and 19, load at x = 10: the Gmsh file
//!   `data/meshes/2D/Geo-Files/asymmetric-three-point-bending.geo` of mohd-afeef-badri/psd
//!   (hole diameter 1 there) and a geometry input file by V. E. Cardoso Nungaray headed
//!   "Asymmetric notched three point bending test, Unit: 1in" (returned by the code search
//!   without its repository; its author's repositories are vecn/*): notch 3.95 ≤ x ≤ 4.05
//!   of depth 1, its first hole a polygon about (6, 2.75) of radius 0.25, i.e. diameter 0.5
//!   as in Bittencourt et al. We use the latter. We did not find the 1996 paper's text or
//!   figures themselves.
//! - The outcome: the crack from (a, b) = (1, 6) ends in the middle hole (the phase-field
//!   reproductions of this configuration, Miehe, Hofacker & Welschinger 2010 and Ambati,
//!   Gerasimov & De Lorenzis 2015, show it so; the brief says one configuration
//!   runs into a hole and the other passes the holes). The crack from (1.5, 5) passes the
//!   holes and runs to the top edge; where on the top edge we could not check (the brief
//!   expected near the load point).
//! - The path: no digitised coordinates of the published paths (experimental scatter or
//!   FRANC2D path) were found in any stored source, so the path is NOT compared point by
//!   point with a published one: only the outcome is asserted, with geometric margins,
//!   and the path's convergence with the mesh (the `#[ignore]`d finer variant). This is
//!   the part of issue 21's item still open.
//!
//! Measured (coarse mesh, Δa = 0.3; fine mesh hf = 0.05, Δa = 0.2 in brackets):
//! - (1, 6): 14 [21] entries; the tip at (5.674, 4.502) [(5.731, 4.586)] would grow to
//!   (5.819, 4.765) [(5.860, 4.739)], 0.069 [0.110] inside the middle hole's edge; the
//!   path clears the bottom hole by 0.90 [0.89], the top one by 2.0 [1.9].
//! - (1.5, 5): 23 [35] entries; the path passes 0.136 [0.119] from the bottom hole's edge
//!   (above and right of it), crosses x = 6 at y ≈ 3.3, between the bottom and middle
//!   holes, clears the middle hole by 0.20 [0.18] and the top one by 0.81 [0.78], and
//!   reaches the top edge at x = 7.23 [7.19], 2.8 left of the load point (a figure we
//!   could not compare with the publication).
//! - The coarse path lies within 0.010 (1, 6) and 0.034 (1.5, 5) of the fine one.

#[path = "common/cli.rs"]
mod cli;

use cli::fissure;
use serde_json::Value;
use std::time::Duration;

const LIMIT: Duration = Duration::from_secs(900);
/// The hole centres (x, y) and radius, inches.
const HOLES: [[f64; 2]; 3] = [[6.0, 2.75], [6.0, 4.75], [6.0, 6.75]];
const RADIUS: f64 = 0.25;

/// A mesh of `meshes/drilled_beam.geo` and the growth increment used on it.
#[derive(Clone, Copy)]
struct Resolution {
    /// The mesh file under `meshes/`.
    mesh: &'static str,
    /// The cell size in the band of the paths.
    h: f64,
    /// Δa, also the SIF domain radius.
    da: f64,
}

/// hf = 0.1 (the tests), and hf = 0.05 (the example's mesh and increment).
const COARSE: Resolution = Resolution { mesh: "drilled_beam_coarse.msh", h: 0.1, da: 0.3 };
const FINE: Resolution = Resolution { mesh: "drilled_beam.msh", h: 0.05, da: 0.2 };

/// The example's case on the mesh of `res`, with the pre-crack at x = 10 − b of length
/// a, Δa and the SIF radius of `res` and up to `steps` increments; no VTU.
fn beam(res: Resolution, b: f64, a: f64, steps: usize) -> String {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut out = std::fs::read_to_string(format!("{root}/examples/drilled_beam_2d.toml")).unwrap();
    for (from, to) in [
        ("file = \"../meshes/drilled_beam.msh\"".to_string(), format!("file = \"{root}/meshes/{}\"", res.mesh)),
        ("tip = [4.0, 1.0]".to_string(), format!("tip = [{:.6}, {a:.6}]", 10.0 - b)),
        ("sif_radius = 0.2".to_string(), format!("sif_radius = {}", res.da)),
        ("increment = 0.2".to_string(), format!("increment = {}", res.da)),
        ("steps = 40".to_string(), format!("steps = {steps}")),
        ("compression = \"lz4\"".to_string(), "vtu = false".to_string()),
    ] {
        assert!(out.contains(&from), "the example no longer has '{from}'");
        out = out.replace(&from, &to);
    }
    out
}

/// Runs a case to `"status": "ok"`; returns its summary and the tip positions per entry
/// (`crack_path.csv`).
fn grow(name: &str, text: &str) -> (Value, Vec<[f64; 2]>) {
    let o = fissure("crack_growth_drilled_beam", name, text, false, LIMIT);
    assert_eq!(o.code, Some(0), "{name}: {}", o.stderr);
    let s = o.summary.clone().expect("summary.json");
    assert_eq!(s["status"], "ok");
    let csv = std::fs::read_to_string(o.out.join("crack_path.csv")).expect("crack_path.csv");
    let path: Vec<[f64; 2]> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let r: Vec<&str> = l.split(',').collect();
            [r[3].parse().unwrap(), r[4].parse().unwrap()]
        })
        .collect();
    assert_eq!(path.len(), s["steps"].as_array().unwrap().len(), "one tip per entry");
    (s, path)
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Distance from `p` to the segment a–b.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let s = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0);
    dist(p, [a[0] + s * d[0], a[1] + s * d[1]])
}

/// Distance from `p` to the polyline `path`.
fn to_path(p: [f64; 2], path: &[[f64; 2]]) -> f64 {
    path.windows(2).map(|w| to_segment(p, w[0], w[1])).fold(f64::INFINITY, f64::min)
}

/// The smallest clearance between the path's segments and each hole's edge (negative
/// where a segment enters the hole).
fn clearances(path: &[[f64; 2]]) -> [f64; 3] {
    let mut c = [f64::INFINITY; 3];
    for (k, h) in HOLES.iter().enumerate() {
        c[k] = to_path(*h, path) - RADIUS;
    }
    c
}

/// The "reached the boundary" warning and the point the tip would have grown to.
fn stop_target(s: &Value) -> (String, [f64; 2]) {
    let w = s["warnings"].as_array().unwrap();
    let stop = w
        .iter()
        .filter_map(|m| m.as_str())
        .find(|m| m.contains("crack 'notch' reached the boundary"))
        .unwrap_or_else(|| panic!("no 'reached the boundary' warning: {w:?}"));
    let to = stop.split("would grow to (").nth(1).expect("the target point");
    let nums: Vec<f64> = to.split(')').next().unwrap().split(',').map(|v| v.trim().parse().unwrap()).collect();
    (stop.to_string(), [nums[0], nums[1]])
}

/// Configuration (a, b) = (1, 6) on `res`: the checks of
/// `drilled_beam_crack_from_b6_ends_in_the_middle_hole`; returns the path.
fn ends_in_the_middle_hole(res: Resolution, name: &str) -> Vec<[f64; 2]> {
    let (s, path) = grow(name, &beam(res, 6.0, 1.0, 40));
    let (stop, to) = stop_target(&s);
    let c = clearances(&path);
    eprintln!("{name}: {} entries; path {path:.3?}", path.len());
    eprintln!("{stop}");
    eprintln!("clearance to the holes (bottom, middle, top): {c:.3?}");
    let hit: Vec<f64> = HOLES.iter().map(|h| dist(*h, to) - RADIUS).collect();
    eprintln!("target's distance to the holes' edges: {hit:.3?}");
    assert!(hit[1] < res.h, "the crack does not end in the middle hole: {hit:?}");
    assert!(stop.contains("(face group 'hole_middle')"), "the stop does not name the middle hole: {stop}");
    let last = *path.last().unwrap();
    assert!(dist(last, HOLES[1]) - RADIUS < res.da + res.h, "last tip {last:?}");
    assert!(c[0] > 2.0 * RADIUS && c[2] > 2.0 * RADIUS, "too near the other holes: {c:?}");
    let before_last = clearances(&path[..path.len() - 1]);
    assert!(before_last[1] > 0.0, "the path enters the middle hole before its end: {before_last:?}");
    assert!(path[1..].iter().all(|p| p[0] > 4.0), "the path does not lean towards the load: {path:?}");
    path
}

/// Configuration (a, b) = (1.5, 5) on `res`: the checks of
/// `drilled_beam_crack_from_b5_passes_the_holes_to_the_top`; returns the path.
fn passes_the_holes(res: Resolution, name: &str) -> Vec<[f64; 2]> {
    let (s, path) = grow(name, &beam(res, 5.0, 1.5, 60));
    let (stop, to) = stop_target(&s);
    let c = clearances(&path);
    eprintln!("{name}: {} entries; path {path:.3?}", path.len());
    eprintln!("{stop}");
    eprintln!("clearance to the holes (bottom, middle, top): {c:.3?}");
    assert!(c.iter().all(|&d| d > res.h), "the path comes within a cell of a hole: {c:?}");
    assert!(to[1] > 8.0 - res.h, "the growth did not stop at the top edge: {to:?}");
    assert!(stop.contains("(face group 'top')"), "the stop does not name the top edge: {stop}");
    assert!(to[0] > HOLES[0][0] + RADIUS && to[0] < 10.0, "the top is reached outside (6.25, 10): {to:?}");
    path
}

/// Configuration (a, b) = (1, 6): the crack from the notch at x = 4 ends in the middle
/// hole. Reference: the outcome of Bittencourt et al.'s configuration as reproduced by
/// the phase-field studies (module doc). Asserted (coarse mesh, h = 0.1, Δa = 0.3): the
/// growth stops with "crack 'notch' reached the boundary" naming the face group
/// 'hole_middle' (the stop at an inner boundary is the one at the outer edge, the message
/// names the boundary's face group); the point the tip would have grown to lies inside the
/// middle hole or within one cell h of its edge, and the last tip within Δa + h of that
/// edge; the path clears the other two holes by more than 0.5 (two radii) and the middle
/// one until its last segment; it leans towards the load (every entry after the first at
/// x > 4). About 3 s in release.
#[test]
fn drilled_beam_crack_from_b6_ends_in_the_middle_hole() {
    ends_in_the_middle_hole(COARSE, "b6_a1");
}

/// Configuration (a, b) = (1.5, 5): the crack from the notch at x = 5 passes the holes.
/// Reference: the other configuration of Bittencourt et al. (module doc). Asserted
/// (coarse mesh, h = 0.1, Δa = 0.3): the path clears every hole's edge by more than one
/// cell h; the growth stops with "reached the boundary" at the top edge, naming the face
/// group 'top' (the point the tip would grow to within one cell of y = 8 or beyond),
/// between the hole column and the load point (6.25 < x < 10). About 5 s in release.
#[test]
fn drilled_beam_crack_from_b5_passes_the_holes_to_the_top() {
    passes_the_holes(COARSE, "b5_a15");
}

/// Both configurations on the example's mesh (h = 0.05, Δa = 0.2), the same outcomes,
/// and the convergence of the path: every entry of the coarse path (h = 0.1, Δa = 0.3)
/// lies within 0.05 (half a coarse cell) of the fine path (measured 0.010 and 0.034).
/// About 55 s in release.
#[test]
#[ignore = "about 55 s: the finer mesh of the example"]
fn drilled_beam_paths_converge_with_the_mesh() {
    let fine = [ends_in_the_middle_hole(FINE, "b6_a1_fine"), passes_the_holes(FINE, "b5_a15_fine")];
    // Their own output folders: the coarse tests may run at the same time.
    let coarse =
        [ends_in_the_middle_hole(COARSE, "b6_a1_against_fine"), passes_the_holes(COARSE, "b5_a15_against_fine")];
    for (name, (c, f)) in ["(1, 6)", "(1.5, 5)"].iter().zip(coarse.iter().zip(&fine)) {
        let gap = c.iter().map(|p| to_path(*p, f)).fold(0.0, f64::max);
        eprintln!("{name}: the coarse path lies within {gap:.4} of the fine one");
        assert!(gap < 0.05, "{name}: {gap}");
    }
}
