//! Several bodies in one model and contact pairs between their boundary surfaces (issue 16).
//!
//! Bodies: `[[mesh.parts]]` (generated blocks moved by an offset, groups prefixed by the
//! part name) or a Gmsh file with several surfaces that share no nodes
//! (`meshes/two_blocks.msh`). References are exact statics (uniform stress states, which
//! bilinear elements reproduce to round-off) and the rigid-body motions of a free body.

use fissure::case::{resolve, Case};
use fissure::run::solve_model_recorded;
use fissure::solve::statics::SolveOptions;
use std::path::Path;

fn case(text: &str) -> Case {
    Case::parse(text, Path::new("case.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of a case that must be refused (at reading or at building its mesh or model).
fn refused(text: &str) -> String {
    let c = match Case::parse(text, Path::new("case.toml")) {
        Err(e) => return e.to_string(),
        Ok(c) => c,
    };
    let mesh = match resolve::build_mesh(&c) {
        Err(e) => return e.to_string(),
        Ok(m) => m,
    };
    match resolve::build_model(&c, &mesh) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the case was accepted"),
    }
}

/// Two parts side by side in one case: `lower` = [0, 1]² (quad4 4 × 4, E = 1) and `upper` =
/// [0, 1]² moved by (0, 1) (quad4 3 × 3, E = 2), ν = 0.3, plane strain, each on rollers on
/// its own bottom and left edges and pressed by p = 0.01 on its own top edge.
fn two_parts(extra: &str) -> String {
    format!(
        r#"[mesh]
[[mesh.parts]]
name = "lower"
generator = "rectangle"
cell = "quad4"
upper = [1.0, 1.0]
divisions = [4, 4]
[[mesh.parts]]
name = "upper"
generator = "rectangle"
cell = "quad4"
upper = [1.0, 1.0]
divisions = [3, 3]
offset = [0.0, 1.0]
[[materials]]
group = "lower"
E = 1.0
nu = 0.3
[[materials]]
group = "upper"
E = 2.0
nu = 0.3
[[dirichlet]]
group = "lower.bottom"
components = ["y"]
[[dirichlet]]
group = "lower.left"
components = ["x"]
[[pressure]]
group = "lower.top"
value = 0.01
[[pressure]]
group = "upper.top"
value = 0.01
{extra}"#
    )
}

/// Two parts, each held on its own: each is in uniaxial compression σ_yy = −p with its own
/// modulus. Reference (plane strain): u_y(top) = −p H (1 − ν²)/E, H = 1, at every node of
/// each top edge, relative to the part's own base (bilinear elements are exact: 1e-10
/// relative). The groups are the generator's, prefixed by the part name; each part's cells
/// are the cell group of its name.
#[test]
fn two_parts_each_held_compress_with_their_own_material() {
    let text = two_parts(
        "[[dirichlet]]\ngroup = \"upper.bottom\"\ncomponents = [\"y\"]\n[[dirichlet]]\ngroup = \"upper.left\"\ncomponents = [\"x\"]\n",
    );
    let c = case(&text);
    let mesh = resolve::build_mesh(&c).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mesh.n_nodes(), 25 + 16);
    assert_eq!(mesh.n_cells(), 16 + 9);
    assert_eq!(mesh.cell_groups["upper"].len(), 9);
    assert_eq!(mesh.cell_groups["upper.domain"].len(), 9);
    let model = resolve::build_model(&c, &mesh).unwrap_or_else(|e| panic!("{e}"));
    let (_, steps) = solve_model_recorded(&model, None, &SolveOptions::default()).expect("solves");
    let u = &steps.last().unwrap().u;
    for (part, e_mod, y_top) in [("lower", 1.0, 1.0), ("upper", 2.0, 2.0)] {
        let exact = -0.01 * (1.0 - 0.09) / e_mod;
        let top = mesh.group_nodes(&format!("{part}.top")).unwrap();
        assert!(!top.is_empty());
        for a in top {
            assert!((mesh.nodes[a][1] - y_top).abs() < 1e-12, "{part}.top at y = {}", mesh.nodes[a][1]);
            let uy = u[2 * a + 1];
            assert!((uy / exact - 1.0).abs() < 1e-10, "{part}: u_y = {uy:e}, exact {exact:e}");
        }
    }
}

/// A part with no support and no contact: the under-constrained error names it.
#[test]
fn a_free_part_is_named_in_the_under_constrained_error() {
    let text = two_parts("");
    let c = case(&text);
    let mesh = resolve::build_mesh(&c).unwrap();
    let model = resolve::build_model(&c, &mesh).unwrap();
    let Err(e) = solve_model_recorded(&model, None, &SolveOptions::default()) else { panic!("accepted") };
    let e = e.to_string();
    assert!(e.contains("under-constrained") && e.contains("body 'upper'"), "{e}");
    assert!(!e.contains("body 'lower'"), "{e}");
}

/// Bad input on parts: overlapping parts, a duplicate name, parts of two dimensions, a part
/// with `file`, an unknown prefixed group; each error names the key and the line.
#[test]
fn bad_parts_are_refused_naming_key_and_line() {
    let overlap = two_parts("").replace("offset = [0.0, 1.0]", "offset = [0.5, 0.5]");
    let e = refused(&overlap);
    assert!(e.contains("mesh.parts[1]") && e.contains("overlaps part 'lower'") && e.contains("case.toml:"), "{e}");
    let e = refused(&two_parts("").replace("name = \"upper\"", "name = \"lower\""));
    assert!(e.contains("mesh.parts[1].name") && e.contains("already defined"), "{e}");
    let e = refused(&two_parts("").replace("name = \"upper\"", "name = \"up per\""));
    assert!(e.contains("mesh.parts[1].name"), "{e}");
    let three_d = two_parts("").replace(
        "generator = \"rectangle\"\ncell = \"quad4\"\nupper = [1.0, 1.0]\ndivisions = [3, 3]\noffset = [0.0, 1.0]",
        "generator = \"box\"\ncell = \"hex8\"\nupper = [1.0, 1.0, 1.0]\ndivisions = [3, 3, 3]\noffset = [0.0, 1.0, 0.0]",
    );
    let e = refused(&three_d);
    assert!(e.contains("mesh.parts[1].generator") && e.contains("2D"), "{e}");
    let e = refused(&two_parts("").replace("[mesh]\n", "[mesh]\nfile = \"a.msh\"\n"));
    assert!(e.contains("mesh.file") && e.contains("not both"), "{e}");
    let e = refused(&two_parts("[[traction]]\ngroup = \"upper.topp\"\nvalue = [0.0, 1.0]\n"));
    assert!(e.contains("traction[0].group") && e.contains("upper.top"), "{e}");
    // Touching parts (a shared face, no shared nodes) are accepted.
    assert!(resolve::build_mesh(&case(&two_parts(""))).is_ok());
}

/// A Gmsh file with two surfaces that share no nodes (`meshes/two_blocks.msh`, lower [0, 1]²
/// 8 × 8, upper [0, 1] × [1, 2] 5 × 5): two bodies; holding only the lower one, the error
/// names the upper one by its physical group.
#[test]
fn gmsh_file_with_two_bodies_sharing_no_nodes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let text = format!(
        "[mesh]\nfile = \"{}\"\n[[materials]]\nE = 1.0\nnu = 0.3\n[[dirichlet]]\ngroup = \"lower_bottom\"\ncomponents = [\"x\", \"y\"]\n",
        dir.join("two_blocks.msh").display()
    );
    let c = case(&text);
    let mesh = resolve::build_mesh(&c).unwrap();
    let (_, bodies) = fissure::physics::constraints::node_components(&mesh);
    assert_eq!(bodies, 2);
    assert_eq!(mesh.n_nodes(), 81 + 36);
    let model = resolve::build_model(&c, &mesh).unwrap();
    let Err(e) = solve_model_recorded(&model, None, &SolveOptions::default()) else { panic!("accepted") };
    let e = e.to_string();
    assert!(e.contains("body 'upper'") && !e.contains("body 'lower'"), "{e}");
}

mod common;
use common::contact::solve_contact_text;

/// Two stacked blocks for the contact patch test: `lower` = [0, 1]² (quad4 `nl` × `nl`)
/// and `upper` = [0, 1] × [1, 2] (quad4 `nu` × `nu`), E = 1, ν = 0.3, plane strain;
/// rollers on the lower bottom (u_y = 0) and on both left edges (u_x = 0); pressure `p` on
/// the upper top; a frictionless contact pair (`slave`, `master` face groups).
fn stacked(nl: usize, nu: usize, p: f64, slave: &str, master: &str, extra: &str) -> String {
    format!(
        r#"[mesh]
[[mesh.parts]]
name = "lower"
generator = "rectangle"
cell = "quad4"
upper = [1.0, 1.0]
divisions = [{nl}, {nl}]
[[mesh.parts]]
name = "upper"
generator = "rectangle"
cell = "quad4"
upper = [1.0, 1.0]
divisions = [{nu}, {nu}]
offset = [0.0, 1.0]
[[materials]]
E = 1.0
nu = 0.3
[[dirichlet]]
group = "lower.bottom"
components = ["y"]
[[dirichlet]]
group = "lower.left"
components = ["x"]
[[dirichlet]]
group = "upper.left"
components = ["x"]
[[pressure]]
group = "upper.top"
value = {p}
[[contact_pairs]]
name = "stack"
slave = "{slave}"
master = "{master}"
{extra}
"#
    )
}

/// Contact patch test on non-matching meshes (Taylor & Papadopoulos 1991), 2D, flat: the
/// stacked blocks above with mesh ratios 1:1 (6:6), 2:3 (4:6) and 1:3 (3:9), each
/// way round (the slave the coarser or the finer side), p = 0.01 (= 1e-2 E). The exact
/// solution is the uniform uniaxial state σ_yy = −p in both blocks, continuous across the
/// interface; with segment-to-segment integration (`gauss`, the slave segments cut at the
/// master nodes) the discrete problem reproduces it, so λ = −p at every slave point.
/// Tolerance: 1e-6 relative to p; gaps below 1e-8 h. Control: node-to-segment integration
/// (`vertex`, the slave nodes only) does not pass it on the 1:3 meshes with the coarse side
/// slave (the master nodes between two slave nodes get no contact force).
#[test]
fn patch_test_non_matching_2d_flat_pressure_is_p_at_every_slave_point() {
    let p = 0.01;
    let worst_of =
        |run: &common::contact::ContactRun| run.lambda.iter().map(|l| (l + p).abs() / p).fold(0.0f64, f64::max);
    for (nl, nu) in [(6, 6), (4, 6), (3, 9)] {
        for (slave, master) in [("upper.bottom", "lower.top"), ("lower.top", "upper.bottom")] {
            let run = solve_contact_text(&stacked(nl, nu, p, slave, master, "")).expect("solves");
            assert!(!run.lambda.is_empty());
            let worst = worst_of(&run);
            eprintln!("{nl}:{nu}, slave {slave}: {} points, max |λ + p|/p = {worst:.2e}", run.lambda.len());
            assert!(worst < 1e-6, "{nl}:{nu}, slave {slave}: max |λ + p|/p = {worst:e}");
            let h = 1.0 / nl.max(nu) as f64;
            assert!(run.d_n.iter().all(|d| d.abs() < 1e-8 * h), "{nl}:{nu}: gaps {:?}", run.d_n);
        }
    }
    let run =
        solve_contact_text(&stacked(9, 3, p, "upper.bottom", "lower.top", "integration = \"vertex\"")).expect("solves");
    let worst = worst_of(&run);
    eprintln!("control, node-to-segment 9:3: max |λ + p|/p = {worst:.2e}");
    assert!(worst > 1e-3, "node-to-segment passed the patch test: {worst:e}");
}

/// The same flat contact as an X-FEM interface in one mesh and as two meshed blocks with a
/// contact pair. Geometry: [0, 1] × [0, 2], interface y = 1.05 (X-FEM: a `line` crack
/// through the middle of a cell row of the quad4 10 × 20 mesh; meshed: parts [0, 1] ×
/// [0, 1.05] (10 × 10) and [0, 1] × [1.05, 2] (10 × 9)). E = 1, ν = 0, plane strain; bottom
/// clamped, top displaced by (0, −δ), δ = 1e-3; frictionless contact. Reference: the
/// uniform state σ_yy = −E δ/2, so λ = −5e-4 at every point of both; the two answers agree
/// to 1e-8 relative (every X-FEM point against every pair point).
#[test]
fn flat_contact_same_lambda_as_an_xfem_interface() {
    let common = "[[materials]]\nE = 1.0\nnu = 0.0\n";
    let xfem = format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [1.0, 2.0]\ndivisions = [10, 20]\n{common}[[dirichlet]]\ngroup = \"bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"top\"\ncomponents = [\"x\", \"y\"]\nvalues = [0.0, -1e-3]\n[[cracks]]\nname = \"iface\"\nshape = \"line\"\npoint = [0.0, 1.05]\nnormal = [0.0, 1.0]\n[cracks.contact]\n"
    );
    let meshed = format!(
        "[mesh]\n[[mesh.parts]]\nname = \"lower\"\ngenerator = \"rectangle\"\ncell = \"quad4\"\nupper = [1.0, 1.05]\ndivisions = [10, 10]\n[[mesh.parts]]\nname = \"upper\"\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [0.0, 1.05]\nupper = [1.0, 2.0]\ndivisions = [10, 9]\n{common}[[dirichlet]]\ngroup = \"lower.bottom\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"upper.top\"\ncomponents = [\"x\", \"y\"]\nvalues = [0.0, -1e-3]\n[[contact_pairs]]\nslave = \"upper.bottom\"\nmaster = \"lower.top\"\n"
    );
    let a = solve_contact_text(&xfem).expect("X-FEM solves");
    let b = solve_contact_text(&meshed).expect("pair solves");
    let p = 5e-4;
    let mut worst = 0.0f64;
    for la in &a.lambda {
        assert!((la + p).abs() < 1e-8 * p, "X-FEM λ = {la:e}");
        for lb in &b.lambda {
            worst = worst.max((la - lb).abs() / p);
        }
    }
    eprintln!("X-FEM {} points, pair {} points: max |λ_xfem − λ_pair|/p = {worst:.2e}", a.lambda.len(), b.lambda.len());
    assert!(worst < 1e-8, "{worst:e}");
}
