//! Meshed contact pairs (`[[contact_pairs]]`, issue 16) under a hostile user: bad input
//! named by key, pair and line; geometry at the edge of the surfaces (a slave surface that
//! reaches beyond the master one); the resultant of a pair against the statics of its
//! bodies. The probe and its figures: `docs/reliability.md`, "Meshed contact pairs:
//! hostile-user probe (trust14)".

use fissure::case::{resolve, Case};
use fissure::run::summary::Summary;
use fissure::run::{run_case, RunOptions};
use std::path::{Path, PathBuf};

/// Writes `text` as `<name>.toml` (and the files `extra` beside it) in a fresh directory
/// and runs it; the summary, or the run's error as text.
fn run_text(name: &str, text: &str, extra: &[(&str, &str)]) -> Result<Summary, String> {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("pairs_hostile_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (file, body) in extra {
        std::fs::write(dir.join(file), body).unwrap();
    }
    let case: PathBuf = dir.join(format!("{name}.toml"));
    std::fs::write(&case, text).unwrap();
    run_case(&case, &dir.join("out"), &RunOptions::default()).map_err(|e| e.to_string())
}

/// The error of a case refused at reading or at building its mesh, its model or its
/// contact (where the pairs' surfaces are built).
fn refused(text: &str) -> String {
    let c = match Case::parse(text, Path::new("case.toml")) {
        Err(e) => return e.to_string(),
        Ok(c) => c,
    };
    let mesh = match resolve::build_mesh(&c) {
        Err(e) => return e.to_string(),
        Ok(m) => m,
    };
    let model = match resolve::build_model(&c, &mesh) {
        Err(e) => return e.to_string(),
        Ok(m) => m,
    };
    match resolve::build_contact(&c, &model) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the case was accepted"),
    }
}

/// Two parts: `lower` = [0, 1]² (quad4 4 × 4) and `upper` = [0, 1]² moved by `offset`
/// (quad4 3 × 3), E = 1, ν = 0.3, plane strain; lower on rollers (bottom u_y = 0, left
/// u_x = 0), upper held along x on its left edge and pressed by p = 0.01 on its top; the
/// pair `stack`: slave `upper.bottom`, master `lower.top`.
fn stacked(offset: [f64; 2], pair: &str) -> String {
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
offset = [{}, {}]
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
value = 0.01
[[contact_pairs]]
name = "stack"
{pair}
"#,
        offset[0], offset[1]
    )
}

const STACK: &str = "slave = \"upper.bottom\"\nmaster = \"lower.top\"";

/// A slave surface reaching beyond the master one. Set-up: [`stacked`] with the upper block
/// moved by (0.5, 1): its bottom [0.5, 1.5] overhangs the lower block's top [0, 1] by half
/// its length (the slave points over x > 1 have no master facet: out of contact); 2D, and
/// the same in 3D (hex8 and tet4 cubes 3³ below, 2³ above, the upper one moved by
/// (0.5, 1, 0.5), held along x and z on its left and back faces, lower clamped at its
/// bottom). Reference: statics of the upper body, which only the contact holds vertically:
/// the pair's resultant on the slave body `force_on_slave` = p × (top area 1) along +y,
/// and the lower body's reaction is that force; to 1e-8 relative (both are sums of the
/// same converged equations). Before the fix `force_on_slave` summed λ n at the paired
/// points only, but the multipliers are nodal and the contact law holds per packet: the
/// packets straddling the master's edge transmit through their paired points a traction
/// λ − ρ_n d_n that the unpaired points' λ balances, so the sum missed 5.0% (2D), 12%
/// (hex8) and 11% (tet4) of the force.
#[test]
fn slave_surface_beyond_the_master_force_on_slave_is_the_load() {
    let p = 0.01;
    let s = run_text("overhang_2d", &stacked([0.5, 1.0], STACK), &[]).unwrap_or_else(|e| panic!("{e}"));
    let st = &s.steps[0];
    let pair = &st.contact_pairs[0];
    let lower = st.reactions["lower.bottom"][1];
    eprintln!(
        "2D overhang: force_on_slave {:?}, normal_force {:e}, reaction {lower:e}",
        pair.force_on_slave, pair.normal_force
    );
    assert!(pair.pairing.as_ref().is_some_and(|k| k.outside > 0), "some slave points overhang: {:?}", pair.pairing);
    assert!((lower - p).abs() < 1e-8 * p, "reaction {lower:e}");
    assert!((pair.force_on_slave[1] - p).abs() < 1e-8 * p, "force_on_slave {:?}", pair.force_on_slave);
    assert!(pair.force_on_slave[0].abs() < 1e-8 * p, "force_on_slave {:?}", pair.force_on_slave);
    assert!((pair.normal_force - p).abs() < 1e-8 * p, "normal_force {:e}", pair.normal_force);
    for cell in ["hex8", "tet4"] {
        let text = format!(
            r#"[mesh]
[[mesh.parts]]
name = "lower"
generator = "box"
cell = "{cell}"
upper = [1.0, 1.0, 1.0]
divisions = [3, 3, 3]
[[mesh.parts]]
name = "upper"
generator = "box"
cell = "{cell}"
upper = [1.0, 1.0, 1.0]
divisions = [2, 2, 2]
offset = [0.5, 1.0, 0.5]
[[materials]]
E = 1.0
nu = 0.3
[[dirichlet]]
group = "lower.bottom"
components = ["x", "y", "z"]
[[dirichlet]]
group = "upper.left"
components = ["x"]
[[dirichlet]]
group = "upper.back"
components = ["z"]
[[pressure]]
group = "upper.top"
value = {p}
[[contact_pairs]]
name = "stack"
{STACK}
"#
        );
        let s = run_text(&format!("overhang_{cell}"), &text, &[]).unwrap_or_else(|e| panic!("{e}"));
        let st = &s.steps[0];
        let pair = &st.contact_pairs[0];
        let lower = st.reactions["lower.bottom"][1];
        eprintln!(
            "3D {cell} overhang: force_on_slave {:?}, normal_force {:e}, reaction {lower:e}",
            pair.force_on_slave, pair.normal_force
        );
        assert!((lower - p).abs() < 1e-8 * p, "{cell}: reaction {lower:e}");
        assert!((pair.force_on_slave[1] - p).abs() < 1e-8 * p, "{cell}: force_on_slave {:?}", pair.force_on_slave);
        assert!(
            pair.force_on_slave[0].abs() + pair.force_on_slave[2].abs() < 1e-8 * p,
            "{cell}: {:?}",
            pair.force_on_slave
        );
    }
}

mod common;

/// The issue's "Bad input" list, each refused with an error naming the key (`slave` or
/// `master` of `contact_pairs[0]`), the pair and the line: a group that does not exist
/// (either side; the message lists the mesh's groups), a cell group and a node group
/// (not boundary face groups), the same group as slave and master, slave and master on
/// the same body, overlapping parts, and a slave surface that starts inside the master
/// body by more than a cell (hex8 blocks from a Gmsh file, [`common::contact::two_blocks_msh`]:
/// lower [0, 1]³ 3³, upper [0, 1] × [0.4, 1.4] × [0, 1] 3³, 0.6 = 1.8 cells deep). A body
/// held only through a frictionless pair is free sideways: the under-constrained error
/// names it and the motion.
#[test]
fn bad_contact_pairs_are_refused_naming_key_pair_and_line() {
    let named = |e: &str, key: &str| {
        assert!(
            e.contains(&format!("key '{key}'")) && e.contains("contact pair 'stack'") && e.contains("case.toml:"),
            "{e}"
        );
    };
    let e = refused(&stacked([0.0, 1.0], "slave = \"upper.botom\"\nmaster = \"lower.top\""));
    named(&e, "contact_pairs[0].slave");
    assert!(e.contains("unknown group 'upper.botom'") && e.contains("upper.bottom"), "{e}");
    let e = refused(&stacked([0.0, 1.0], "slave = \"upper.bottom\"\nmaster = \"lowr.top\""));
    named(&e, "contact_pairs[0].master");
    assert!(e.contains("unknown group 'lowr.top'"), "{e}");
    let e = refused(&stacked([0.0, 1.0], "slave = \"upper\"\nmaster = \"lower.top\""));
    named(&e, "contact_pairs[0].slave");
    assert!(e.contains("'upper' is not a boundary face group"), "{e}");
    let nodes = stacked([0.0, 1.0], "slave = \"upper.bottom\"\nmaster = \"seam\"")
        + "[[sets]]\nname = \"seam\"\nkind = \"nodes\"\non = \"y - 1\"\n";
    let e = refused(&nodes);
    named(&e, "contact_pairs[0].master");
    assert!(e.contains("'seam' is not a boundary face group"), "{e}");
    let e = refused(&stacked([0.0, 1.0], "slave = \"lower.top\"\nmaster = \"lower.top\""));
    named(&e, "contact_pairs[0].master");
    assert!(e.contains("the same group 'lower.top' as slave and master"), "{e}");
    let e = refused(&stacked([0.0, 1.0], "slave = \"upper.bottom\"\nmaster = \"upper.top\""));
    named(&e, "contact_pairs[0].slave");
    assert!(e.contains("same body"), "{e}");
    let e = refused(&stacked([0.0, 0.9], STACK));
    assert!(
        e.contains("mesh.parts[1].upper") && e.contains("overlaps part 'lower'") && e.contains("case.toml:"),
        "{e}"
    );
    // Deep initial penetration (a Gmsh file: parts cannot overlap at all).
    let msh = common::contact::two_blocks_msh([[3, 3, 3], [3, 3, 3]], &|b, [x, y, z]| {
        if b == 0 {
            [x, y, z]
        } else {
            [x, 0.4 + y, z]
        }
    });
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pairs_hostile_penetration");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("deep.msh"), msh).unwrap();
    let text = format!(
        "[mesh]\nfile = \"{}\"\n[[materials]]\nE = 1.0\nnu = 0.3\n[[contact_pairs]]\nname = \"stack\"\nslave = \"upper_bottom\"\nmaster = \"lower_top\"\n",
        dir.join("deep.msh").display()
    );
    let e = refused(&text);
    named(&e, "contact_pairs[0].slave");
    assert!(e.contains("inside the master body, more than a cell"), "{e}");
    // A body held only through a frictionless pair can slide: named in the error.
    let free = stacked([0.0, 1.0], STACK).replace("[[dirichlet]]\ngroup = \"upper.left\"\ncomponents = [\"x\"]\n", "");
    let e = run_text("free_sideways", &free, &[]).map(|_| ()).unwrap_err();
    assert!(
        e.contains("under-constrained") && e.contains("body 'upper' (2 of 2) can move freely (translation along x)"),
        "{e}"
    );
    assert!(!e.contains("body 'lower'"), "{e}");
}

/// A Gmsh file whose two bodies share nodes (one mesh, two quads [0, 1]² and [0, 1] × [1, 2]
/// sharing the edge y = 1, which is both physical curves `lower_top` and `upper_bottom`):
/// the pair is refused, naming the key, the pair, the line and the face, and saying why
/// (the face lies between two cells: the bodies share its nodes, so they are one body).
/// Before: "slave: face [2, 3] is not a boundary face of the mesh" (mesh node indices), which left the user to
/// find out why.
#[test]
fn gmsh_bodies_sharing_nodes_are_refused_saying_so() {
    let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"lower_top\"\n1 2 \"upper_bottom\"\n2 3 \"lower\"\n2 4 \"upper\"\n$EndPhysicalNames\n\
$Entities\n0 1 2 0\n1 0 1 0 1 1 0 2 1 2 0\n1 0 0 0 1 1 0 1 3 0\n2 0 1 0 1 2 0 1 4 0\n$EndEntities\n\
$Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 2 0\n0 2 0\n$EndNodes\n\
$Elements\n3 3 1 3\n1 1 1 1\n1 4 3\n2 1 3 1\n2 1 2 3 4\n2 2 3 1\n3 4 3 5 6\n$EndElements\n";
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pairs_hostile_shared");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("shared.msh"), msh).unwrap();
    let text = format!(
        "[mesh]\nfile = \"{}\"\n[[materials]]\nE = 1.0\nnu = 0.3\n[[contact_pairs]]\nname = \"stack\"\nslave = \"upper_bottom\"\nmaster = \"lower_top\"\n",
        dir.join("shared.msh").display()
    );
    let e = refused(&text);
    assert!(
        e.contains("key 'contact_pairs[0].slave'") && e.contains("contact pair 'stack'") && e.contains("case.toml:"),
        "{e}"
    );
    assert!(
        e.contains("centred at [0.5000, 1.0000]") && e.contains("2 cells share it") && e.contains("share no nodes"),
        "{e}"
    );
}

/// The contact zone reaching the end of the slave surface where the body goes on. Set-up:
/// the Hertz cylinder of `examples/hertz_cylinder_2d.toml` (`meshes/hertz_cylinder.msh`:
/// quarter disc R = 1 on the block [0, 5] × [−5, 0], E = 1, ν = 0.3, slave the 30° arc
/// `cylinder_contact`, 2 load steps), with the example's load (q = 2.1577e-3: Hertz b =
/// 0.1, the arc reaches x = 0.5) and with 1000 times that (b = √1000 × 0.1 = 3.2 > R: the
/// contact would run past the end of the arc, where the cylinder's boundary goes on, in
/// no group). Expected: the example runs without that warning; the
/// overloaded case says, at each step, that the contact zone reaches the end of the slave
/// surface: every paired point is closed, up to the faces next to the arc's last ones,
/// whose points were too far from the block to be paired (small sliding pairs once, in the
/// initial configuration), so the cylinder can sink into the block there unseen. The same
/// for a slave group stopping in the middle of a flat face. Control: the stacked blocks of
/// [`stacked`] fully in contact (the slave surface ends at the body's corners, 90°) do not
/// warn. Before: no warning at all.
#[test]
fn contact_zone_reaching_the_end_of_the_slave_surface_is_warned() {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/hertz_cylinder.msh");
    let example =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hertz_cylinder_2d.toml"))
            .unwrap()
            .replace("../meshes/hertz_cylinder.msh", &mesh.display().to_string());
    let warned = |s: &Summary| s.warnings.iter().filter(|w| w.contains("reaches the end of the slave surface")).count();
    let s = run_text("hertz_example", &example, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(warned(&s), 0, "{:?}", s.warnings);
    let huge = example.replace("value = 2.1577e-3", "value = 2.1577");
    assert_ne!(huge, example);
    let s = run_text("hertz_overloaded", &huge, &[]).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{:?}", s.warnings);
    assert_eq!(warned(&s), 2, "{:?}", s.warnings);
    assert!(
        s.warnings.iter().any(|w| w.contains("contact pair 'hertz'") && w.contains("'cylinder_contact'")),
        "{:?}",
        s.warnings
    );
    // A slave group that stops in the middle of a flat face: the upper block 0.001 above
    // the lower one, its slave group the first of its three bottom faces (x ≤ 1/3), pressed
    // by p on its top: the slave face is closed and its end at x = 1/3 goes on flat.
    let part = stacked([0.0, 1.001], "slave = \"start\"\nmaster = \"lower.top\"")
        + "[[sets]]\nname = \"start\"\nkind = \"faces\"\non = \"y - 1.001\"\ninside = \"x - 0.34\"\n";
    let s = run_text("stacked_part", &part, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.steps[0].contact_pairs[0].active > 0);
    assert_eq!(warned(&s), 1, "{:?}", s.warnings);
    let s = run_text("stacked_full", &stacked([0.0, 1.0], STACK), &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.steps[0].contact_pairs[0].active, s.steps[0].contact_pairs[0].points);
    assert_eq!(warned(&s), 0, "{:?}", s.warnings);
}
