//! Solving a case with contact given as text, and reading the contact state back.

use fissure::case::{resolve, Case};
use fissure::contact::law::Status;
use fissure::contact::state::{point_values, statuses};
use fissure::post::sif::{crack_sifs, SifOptions, SifPoint};
use fissure::run::solve_model_recorded;
use fissure::solve::statics::{SolveError, SolveOptions, StepReport};
use std::path::Path;

/// The contact state of the last step at every contact point.
pub struct ContactRun {
    pub x: Vec<[f64; 3]>,
    pub lambda: Vec<f64>,
    pub big_lambda: Vec<[f64; 2]>,
    pub d_n: Vec<f64>,
    pub jump: Vec<[f64; 3]>,
    /// u⁺ − u⁻ at the same material point (the slip and opening; equal to `jump` in small
    /// sliding; under large sliding `jump` is the gap to the facing master point).
    pub material_jump: Vec<[f64; 3]>,
    pub status: Vec<Status>,
    pub normal: Vec<[f64; 3]>,
    pub tangent: Vec<[f64; 3]>,
    pub friction: Vec<f64>,
    pub steps: Vec<StepReport>,
    pub sifs: Vec<Vec<SifPoint>>,
    pub reactions: Vec<[f64; 3]>,
    pub multipliers: usize,
    pub h: f64,
    /// Per step: (x, λ, d_n, status, paired) at every contact point.
    pub history: Vec<Vec<PointRecord>>,
    /// The contact system was condensed onto the crack unknowns.
    pub condensed: bool,
    /// The friction threshold λ̄ (≤ 0) of every point at the end of the last step.
    pub lam_bar: Vec<f64>,
    /// The hard contact status χ_c of every point at the end of the last step.
    pub contact: Vec<bool>,
    /// Integration weight of every point.
    pub weight: Vec<f64>,
    /// Wear depths (w⁺, w⁻) at every point after the last step (the `+` lip's and the `−`
    /// lip's at the point's reference position).
    pub wear: Vec<[f64; 2]>,
    /// Frictional work per unit area ∫ μ|λ||dslip| at every point (with wear only).
    pub frictional_work: Vec<f64>,
    /// Per meshed contact pair with wear: per master facet, (midpoint, length, wear depth
    /// of the master face after the last step).
    pub master_wear: Vec<Vec<([f64; 3], f64, f64)>>,
    /// Per contact crack or pair with a nodal (3D) master wear field, in contact-crack
    /// order: per vertex, (position, lumped area, depth after the last step).
    pub master_nodal: Vec<Vec<([f64; 3], f64, f64)>>,
    /// Per contact crack or pair (contact-crack order): its wear figures after the last
    /// step (`steps[].contact_pairs[].wear` for a pair).
    pub wear_figures_each: Vec<Option<fissure::post::contact_output::WearFigures>>,
    /// The wear figures of the last step (summary.json's `steps[].contact.wear`).
    pub wear_figures: Option<fissure::post::contact_output::WearFigures>,
}

/// One contact point at one step.
#[derive(Debug, Clone)]
pub struct PointRecord {
    /// Integration weight and multiplier terms (packet, coefficient).
    pub weight: f64,
    pub terms: Vec<(u32, f64)>,
    pub x: [f64; 3],
    pub lambda: f64,
    pub d_n: f64,
    pub big_lambda: [f64; 2],
    pub status: Status,
    pub paired: bool,
    /// Outside its pair's contact zone (`contact::zone`): held open.
    pub dormant: bool,
}

/// Parses, solves, and evaluates the contact state (and SIFs with the contact tractions).
pub fn solve_contact_text(text: &str) -> Result<ContactRun, SolveError> {
    let case = Case::parse(text, Path::new("case.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mesh = resolve::build_mesh(&case).unwrap_or_else(|e| panic!("{e}"));
    let model = resolve::build_model(&case, &mesh).unwrap_or_else(|e| panic!("{e}"));
    let setup = resolve::build_contact(&case, &model).unwrap_or_else(|e| panic!("{e}")).expect("contact");
    // The case's [solver] options.
    let options = SolveOptions {
        linear: case.solver.linear,
        residual_tolerance: case.solver.residual_tolerance,
        condense: case.solver.condense,
        ordering: case.solver.ordering,
        backend: case.solver.backend.clone(),
        ..Default::default()
    };
    let (report, recorded) = solve_model_recorded(&model, Some(&setup), &options)?;
    let pts = &setup.points;
    let history: Vec<Vec<PointRecord>> = recorded
        .iter()
        .map(|r| {
            let vals = point_values(&model, pts, r.pairing.as_ref(), &r.contact_state, &r.u);
            let st = statuses(pts, &r.contact_state, &vals);
            pts.points
                .iter()
                .zip(&vals)
                .zip(&st)
                .map(|((p, v), s)| PointRecord {
                    weight: p.weight,
                    terms: p.terms.clone(),
                    x: p.x,
                    lambda: v.lambda,
                    d_n: v.d_n,
                    big_lambda: v.big_lambda,
                    status: *s,
                    paired: v.paired,
                    dormant: v.dormant,
                })
                .collect()
        })
        .collect();
    let last = recorded.last().unwrap();
    let u = &last.u;
    let vals = point_values(&model, pts, last.pairing.as_ref(), &last.contact_state, u);
    let st = statuses(pts, &last.contact_state, &vals);
    // SIFs with the contact tractions on the faces: t⁺ = −λ n + μ λ Λ (τ components).
    let mut sifs = vec![];
    for (k, _) in model.cracks.iter().enumerate() {
        let Some(ci) = pts.cracks.iter().position(|c| c.crack == k) else {
            sifs.push(crack_sifs(&model, k, u, None, &SifOptions { radius: case.cracks[k].sif_radius }));
            continue;
        };
        let cut = &model.cracks[k].cut;
        let traction = |f: usize, x: [f64; 3]| fissure::contact::face_traction(pts, ci, &cut.facets[f], f, x, u);
        sifs.push(crack_sifs(&model, k, u, Some(&traction), &SifOptions { radius: case.cracks[k].sif_radius }));
    }
    let cut_cells: Vec<usize> = model.cracks.iter().flat_map(|c| c.cut.cut_cells.iter().map(|c| c.cell)).collect();
    let h = cut_cells.iter().map(|&c| mesh.cell_edge_length(c)).sum::<f64>() / cut_cells.len().max(1) as f64;
    Ok(ContactRun {
        x: pts.points.iter().map(|p| p.x).collect(),
        lambda: vals.iter().map(|v| v.lambda).collect(),
        big_lambda: vals.iter().map(|v| v.big_lambda).collect(),
        d_n: vals.iter().map(|v| v.d_n).collect(),
        jump: vals.iter().map(|v| v.jump).collect(),
        material_jump: point_values(&model, pts, None, &last.contact_state, u).iter().map(|v| v.jump).collect(),
        status: st,
        normal: pts.points.iter().map(|p| p.normal).collect(),
        tangent: pts.points.iter().map(|p| p.tangents[0]).collect(),
        friction: pts.points.iter().map(|p| pts.cracks[p.crack].law.friction).collect(),
        reactions: report.steps.last().map(|s| s.reactions.clone()).unwrap_or_default(),
        steps: report.steps,
        sifs,
        multipliers: setup.points.cracks.iter().map(|c| c.space.n_unknowns).sum(),
        h,
        history,
        condensed: report.condensed,
        lam_bar: last.contact_state.iter().map(|s| s.lam_bar).collect(),
        contact: last.contact_state.iter().map(|s| s.contact).collect(),
        weight: pts.points.iter().map(|p| p.weight).collect(),
        wear: last.contact_state.iter().map(|s| s.wear_now()).collect(),
        frictional_work: last.contact_state.iter().map(|s| s.frictional_work).collect(),
        wear_figures: fissure::post::contact_output::wear_figures(&setup, &last.contact_state),
        wear_figures_each: (0..pts.cracks.len())
            .map(|c| fissure::post::contact_output::wear_figures_of(&setup, &last.contact_state, |k| k == c))
            .collect(),
        master_nodal: pts
            .cracks
            .iter()
            .filter(|c| c.master_wear.is_nodal())
            .map(|c| {
                let m = &c.master_wear;
                m.positions().iter().zip(m.areas()).zip(m.now()).map(|((x, a), w)| (*x, *a, w)).collect()
            })
            .collect(),
        master_wear: pts
            .cracks
            .iter()
            .filter_map(|c| {
                c.pair
                    .as_ref()
                    .filter(|_| !c.master_wear.is_empty() && !c.master_wear.is_nodal())
                    .map(|p| (p, c.master_wear.now()))
            })
            .map(|(p, w)| {
                p.master
                    .iter()
                    .zip(w)
                    .map(|(f, w)| {
                        let (a, b) = (f.vertices[0], f.vertices[1]);
                        ([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0], f.measure, w)
                    })
                    .collect()
            })
            .collect(),
    })
}

/// The closed inclined crack of the contact tests: plate [−2, 2]², quad4 n × n, E = 1,
/// ν = 0.3, plane strain, traction −1 on top and bottom (σ = 1 compression), two corner
/// points holding the rigid modes; crack 2a = 0.4 at 45° centred at (0.0123, 0.0071).
pub fn inclined_crack(mu: f64, n: usize, contact_extra: &str) -> String {
    let b = 45f64.to_radians();
    let (c, s, a) = (b.cos(), b.sin(), 0.2);
    let ctr = [0.0123, 0.0071];
    format!(
        "[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [-2.0, -2.0]\nupper = [2.0, 2.0]\ndivisions = [{n}, {n}]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[sets]]\nname = \"pin\"\non = \"abs(x+2) + abs(y+2)\"\n[[sets]]\nname = \"roller\"\non = \"abs(x-2) + abs(y+2)\"\n[[dirichlet]]\ngroup = \"pin\"\ncomponents = [\"x\", \"y\"]\n[[dirichlet]]\ngroup = \"roller\"\ncomponents = [\"y\"]\n[[traction]]\ngroup = \"top\"\nvalue = [0.0, -1.0]\n[[traction]]\ngroup = \"bottom\"\nvalue = [0.0, 1.0]\n[[cracks]]\nname = \"c\"\nshape = \"segment\"\na = [{ax}, {ay}]\nb = [{bx}, {by}]\ntip_radius = 0.05\nsif_radius = 0.06\n[cracks.contact]\nfriction = {mu}\n{contact_extra}",
        ax = ctr[0] - a * c,
        ay = ctr[1] - a * s,
        bx = ctr[0] + a * c,
        by = ctr[1] + a * s
    )
}

/// Block `[0, 20]²` (2D) or `[0, 5] × [0, 20] × [0, 20]` (3D) cut by the flat interface
/// y = y0, E = 1e8, ν = 0, bottom clamped, top displaced by (0, −1e-6(, 0)).
pub fn patch_block(dim: usize, cell: &str, y0: f64, n: usize, contact: &str) -> String {
    let (gen, upper, div, comps, values, shape) = if dim == 2 {
        (
            "rectangle",
            "[20.0, 20.0]".to_string(),
            format!("[{n}, {n}]"),
            "[\"x\", \"y\"]",
            "[0.0, -1e-6]",
            format!("shape = \"line\"\npoint = [0.0, {y0}]\nnormal = [0.0, 1.0]"),
        )
    } else {
        (
            "box",
            "[5.0, 20.0, 20.0]".to_string(),
            format!("[2, {n}, {n}]"),
            "[\"x\", \"y\", \"z\"]",
            "[0.0, -1e-6, 0.0]",
            format!("shape = \"plane\"\npoint = [0.0, {y0}, 0.0]\nnormal = [0.0, 1.0, 0.0]"),
        )
    };
    format!(
        "[mesh]\ngenerator = \"{gen}\"\ncell = \"{cell}\"\nupper = {upper}\ndivisions = {div}\n[[materials]]\nE = 1e8\nnu = 0.0\n[[dirichlet]]\ngroup = \"bottom\"\ncomponents = {comps}\n[[dirichlet]]\ngroup = \"top\"\ncomponents = {comps}\nvalues = {values}\n[[cracks]]\nname = \"iface\"\n{shape}\n[cracks.contact]\n{contact}\n"
    )
}

/// Two stacked blocks for contact patch tests: `lower` = [0, 1]² (quad4 `nl` × `nl`) and
/// `upper` = [0, 1] × [1, 2] (quad4 `nu` × `nu`), E = 1, ν = 0.3, plane strain; rollers on
/// the lower bottom (u_y = 0) and on both left edges (u_x = 0: the common corner (0, 1) is
/// held along x on both sides); pressure `p` on the upper top; one contact pair "stack"
/// (`slave`, `master` face groups) with the `extra` lines appended to it.
pub fn stacked_blocks_2d(nl: usize, nu: usize, p: f64, slave: &str, master: &str, extra: &str) -> String {
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

/// The stacked blocks in 3D: `lower` = [0, 1]³ and `upper` = [0, 1]³ moved by (0, 1, 0),
/// `cell` `nl`³ and `nu`³; E = 1, ν = 0.3; rollers u_y = 0 on the lower bottom, u_x = 0 on
/// both left faces, u_z = 0 on both back faces; pressure `p` on the upper top; one contact
/// pair "stack" (`slave`, `master`) with the `extra` lines appended to it.
pub fn stacked_cubes_3d(cell: &str, nl: usize, nu: usize, p: f64, slave: &str, master: &str, extra: &str) -> String {
    format!(
        r#"[mesh]
[[mesh.parts]]
name = "lower"
generator = "box"
cell = "{cell}"
upper = [1.0, 1.0, 1.0]
divisions = [{nl}, {nl}, {nl}]
[[mesh.parts]]
name = "upper"
generator = "box"
cell = "{cell}"
upper = [1.0, 1.0, 1.0]
divisions = [{nu}, {nu}, {nu}]
offset = [0.0, 1.0, 0.0]
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
[[dirichlet]]
group = "lower.back"
components = ["z"]
[[dirichlet]]
group = "upper.back"
components = ["z"]
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

/// The wear bench's platen (`benches/wear.rs`) on a coarser mesh: the layer [0, 4] ×
/// [−0.5, 0.5] (quad4 40 × 80, h = 0.1 × 0.0125) cut by the flat interface y = 0.27 (inside
/// a cell row), E = 1, ν = 0, bottom clamped, top pressed down by 0.002 at step 1 and slid
/// along x by 0.005 per step for `steps` − 1 more steps, μ = 0.5, Archard k/H = 1 with the
/// wear `coupling`. `sections` (whole sections, e.g. `[solver]`, `[contact_solver]`) go
/// before the crack, `contact` (lines) into its `[cracks.contact]`.
pub fn wear_platen(steps: usize, sections: &str, contact: &str, coupling: &str) -> String {
    format!(
        r#"[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.5]
upper = [4.0, 0.5]
divisions = [40, 80]

[[materials]]
E = 1.0
nu = 0.0

[[dirichlet]]
group = "bottom"
components = ["x", "y"]

[[dirichlet]]
group = "top"
components = ["x", "y"]
values = ["0.005 * ({steps} * t - 1)", "-0.002 + 0 * t"]

[steps]
count = {steps}

[output]
vtu = false
plots = false

{sections}
[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.27]
normal = [0.0, 1.0]

[cracks.contact]
friction = 0.5
{contact}

[cracks.contact.wear]
coefficient = 1.0
coupling = "{coupling}"
"#
    )
}

/// The sliding penny crack on a hex8 box (the whole-system LDLᵀ kept across the contact
/// iterations, `src/solve/faer/kept.rs`): the box [−2.5, 2.5]³ in 10 × 10 × 11 hex8,
/// E = 1, ν = 0.3, three corner points holding the rigid modes, the disc crack a = 1 in
/// z = 0 (tip and SIF radius 0.5), σ = 1 across it and τ = 0.5 in the x–z plane, Coulomb
/// μ = 0.2 (every point slides), then `extra` (more tables, e.g. `[solver]`).
#[allow(dead_code)] // used by some test crates only
pub fn small_sliding_penny_case(extra: &str) -> String {
    let mesh = "[mesh]\ngenerator = \"box\"\ncell = \"hex8\"\nlower = [-2.5, -2.5, -2.5]\nupper = [2.5, 2.5, 2.5]\n\
                divisions = [10, 10, 11]\n";
    format!(
        "{mesh}[[materials]]\nE = 1.0\nnu = 0.3\n\
         [[sets]]\nname = \"p1\"\non = \"abs(x+2.5) + abs(y+2.5) + abs(z+2.5)\"\n\
         [[sets]]\nname = \"p2\"\non = \"abs(x-2.5) + abs(y+2.5) + abs(z+2.5)\"\n\
         [[sets]]\nname = \"p3\"\non = \"abs(x+2.5) + abs(y-2.5) + abs(z+2.5)\"\n\
         [[dirichlet]]\ngroup = \"p1\"\ncomponents = [\"x\", \"y\", \"z\"]\n\
         [[dirichlet]]\ngroup = \"p2\"\ncomponents = [\"y\", \"z\"]\n\
         [[dirichlet]]\ngroup = \"p3\"\ncomponents = [\"z\"]\n\
         [[traction]]\ngroup = \"front\"\nvalue = [0.5, 0.0, -1.0]\n[[traction]]\ngroup = \"back\"\nvalue = [-0.5, 0.0, 1.0]\n\
         [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, 0.5]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, -0.5]\n\
         [[cracks]]\nname = \"penny\"\nshape = \"disc\"\ncentre = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nradius = 1.0\n\
         tip_radius = 0.5\nsif_radius = 0.5\n[cracks.contact]\nfriction = 0.2\n{extra}"
    )
}

/// Two structured hex8 blocks as a Gmsh MSH 4.1 file: block `b` (0: `lower`, 1: `upper`)
/// has `div[b]` cells along its reference coordinates (ξ, η, ζ) ∈ [0, 1]³, placed by
/// `map(b, [ξ, η, ζ])` (increasing in each argument along x, y, z: positive hexes). Groups:
/// volumes `lower`, `upper`; faces `<body>_bottom` (η = 0), `<body>_top` (η = 1),
/// `<body>_left` (ξ = 0), `<body>_back` (ζ = 0), oriented outward.
pub fn two_blocks_msh(div: [[usize; 3]; 2], map: &dyn Fn(usize, [f64; 3]) -> [f64; 3]) -> String {
    let names = ["bottom", "top", "left", "back"];
    let mut nodes = vec![];
    let mut hexes = vec![[0usize; 8]; 0];
    let mut faces: Vec<Vec<[usize; 4]>> = vec![vec![]; 8];
    let mut volumes = vec![vec![]; 2];
    for (b, [nx, ny, nz]) in div.into_iter().enumerate() {
        let base = nodes.len();
        let id = |i: usize, j: usize, k: usize| base + i + (nx + 1) * (j + (ny + 1) * k);
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push(map(b, [i as f64 / nx as f64, j as f64 / ny as f64, k as f64 / nz as f64]));
                }
            }
        }
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    volumes[b].push(hexes.len());
                    hexes.push([
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        for a in 0..nx {
            for d in 0..nz {
                faces[4 * b].push([id(a, 0, d), id(a + 1, 0, d), id(a + 1, 0, d + 1), id(a, 0, d + 1)]);
                faces[4 * b + 1].push([id(a, ny, d), id(a, ny, d + 1), id(a + 1, ny, d + 1), id(a + 1, ny, d)]);
            }
        }
        for a in 0..ny {
            for d in 0..nz {
                faces[4 * b + 2].push([id(0, a, d), id(0, a, d + 1), id(0, a + 1, d + 1), id(0, a + 1, d)]);
            }
        }
        for a in 0..nx {
            for d in 0..ny {
                faces[4 * b + 3].push([id(a, d, 0), id(a, d + 1, 0), id(a + 1, d + 1, 0), id(a + 1, d, 0)]);
            }
        }
    }
    let mut t = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n10\n");
    for (b, body) in ["lower", "upper"].iter().enumerate() {
        for (g, name) in names.iter().enumerate() {
            t += &format!("2 {} \"{body}_{name}\"\n", 4 * b + g + 1);
        }
    }
    t += "3 11 \"lower\"\n3 12 \"upper\"\n$EndPhysicalNames\n$Entities\n0 0 8 2\n";
    for g in 1..=8 {
        t += &format!("{g} 0 0 0 0 0 0 1 {g} 0\n");
    }
    t += "1 0 0 0 0 0 0 1 11 0\n2 0 0 0 0 0 0 1 12 0\n$EndEntities\n";
    t += &format!("$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n", n = nodes.len());
    for k in 1..=nodes.len() {
        t += &format!("{k}\n");
    }
    for x in &nodes {
        t += &format!("{:.17e} {:.17e} {:.17e}\n", x[0], x[1], x[2]);
    }
    let n_el = hexes.len() + faces.iter().map(Vec::len).sum::<usize>();
    t += &format!("$EndNodes\n$Elements\n10 {n_el} 1 {n_el}\n");
    let mut tag = 0;
    for (g, fs) in faces.iter().enumerate() {
        t += &format!("2 {} 3 {}\n", g + 1, fs.len());
        for f in fs {
            tag += 1;
            t += &format!("{tag} {} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
        }
    }
    for (b, vs) in volumes.iter().enumerate() {
        t += &format!("3 {} 5 {}\n", b + 1, vs.len());
        for &v in vs {
            tag += 1;
            t += &format!("{tag}");
            for a in hexes[v] {
                t += &format!(" {}", a + 1);
            }
            t += "\n";
        }
    }
    t + "$EndElements\n"
}
