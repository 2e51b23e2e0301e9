//! Resolving a case against its mesh: building the mesh (generator or file), adding
//! the formula-defined sets, and attaching materials, loads and conditions to mesh
//! entities. Errors found here (unknown groups, a `z` component in 2D) still name the
//! key and line of the case file.
//!
//! Entry points: [`build_mesh`], [`build_model`].

use super::{Case, CaseError, MeshSource, SetKind};
use crate::contact::points::{ContactCrackOptions, ContactPoints};
use crate::contact::surfaces::PairSurfaces;
use crate::contact::ContactSetup;
use crate::cut::boundary::{cut_in_body, BodyBoundary};
use crate::cut::CutOptions;
use crate::element::{self, MAX_NODES};
use crate::enrich::{enrich, CrackGeometry, EnrichOptions, Enrichment};
use crate::formula::Scalar;
use crate::levelset;
use crate::memory::{self, Estimate};
use crate::mesh::{generate, gmsh, Mesh};
use crate::physics::material::Analysis;
use crate::physics::model::{DirichletCondition, Model};
use crate::physics::relations::{self, Relation};
use crate::physics::side_materials::SideMaterials;
use crate::solve::linear::{LinearMethod, Precision, MIXED_AUTO_MIN_NNZ};

/// Builds the mesh of a case and adds its formula-defined sets as groups.
pub fn build_mesh(case: &Case) -> Result<Mesh, CaseError> {
    let mut mesh = match &case.mesh {
        MeshSource::File(path) => gmsh::read_msh(path).map_err(|e| case.mesh_at.error("file", e.to_string()))?,
        MeshSource::Generated { cell, lower, upper, divisions } => {
            let spec = super::GeneratorSpec { cell: *cell, lower: *lower, upper: *upper, divisions: *divisions };
            generated(&spec, &case.mesh_at, 1.0, &case.solver)?
        }
        MeshSource::Parts(parts) => {
            // The memory check counts every part, each against its share.
            let total: f64 = parts.iter().map(|p| generated_size(&p.spec)).sum();
            let mut mesh = Mesh::default();
            for p in parts {
                let share = generated_size(&p.spec) / total.max(1.0);
                let part = generated(&p.spec, &p.at, share, &case.solver)?;
                mesh.append_part(&part, &p.name, p.offset);
            }
            mesh
        }
    };
    mesh.validate().map_err(|e| case.mesh_at.error("file", e.to_string()))?;
    add_sets(case, &mut mesh)?;
    Ok(mesh)
}

/// Nodes of a generated block (for the memory shares of parts).
fn generated_size(spec: &super::GeneratorSpec) -> f64 {
    spec.divisions.iter().map(|&d| d as f64 + 1.0).product()
}

/// Generates one block after checking that the model it makes fits in memory (`share`:
/// the fraction of the model this block is, the others' memory counted).
fn generated(
    spec: &super::GeneratorSpec,
    at: &super::Located,
    share: f64,
    solver: &super::SolverDef,
) -> Result<Mesh, CaseError> {
    let super::GeneratorSpec { cell, lower, upper, divisions } = spec;
    // Refuse a mesh that cannot fit before allocating it.
    let d = divisions.map(|v| v as f64);
    let dim = cell.dim();
    let (nodes, boxes) = if dim == 2 {
        ((d[0] + 1.0) * (d[1] + 1.0), d[0] * d[1])
    } else {
        ((d[0] + 1.0) * (d[1] + 1.0) * (d[2] + 1.0), d[0] * d[1] * d[2])
    };
    let per_box = match cell {
        element::CellType::Tri3 => 2.0,
        element::CellType::Tet4 => 6.0,
        _ => 1.0,
    };
    let (nodes, cells) = (nodes / share, per_box * boxes / share);
    let e = Estimate::of_model(dim, nodes, cells, cell.n_nodes() as f64, dim as f64 * nodes, neighbours(*cell));
    let e = with_precision(e, solver);
    e.check(memory::available_bytes())
        .map_err(|t| at.error("divisions", format!("{t}; use fewer divisions ({divisions:?} were given)")))?;
    let r = if cell.dim() == 2 {
        generate::rectangle(*cell, [lower[0], lower[1]], [upper[0], upper[1]], [divisions[0], divisions[1]])
    } else {
        generate::box_mesh(*cell, *lower, *upper, *divisions)
    };
    r.map_err(|e| at.error("generator", e.to_string()))
}

/// The estimate with the factor in single precision when `[solver] precision` chooses it
/// (`mixed`; `auto` for a Cholesky factor of at least
/// [`MIXED_AUTO_MIN_NNZ`](crate::solve::linear::MIXED_AUTO_MIN_NNZ) entries, as the solver
/// decides on the factor's actual size); without a factor on the PETSc backend unless its
/// `pc` is a factorisation (`lu`, `cholesky`): the Krylov methods keep no factor, and the
/// estimate stays a lower bound (a saddle point's default MUMPS factor is not counted).
fn with_precision(e: Estimate, solver: &super::SolverDef) -> Estimate {
    if let crate::solve::linear::Backend::Petsc(p) = &solver.backend {
        if !matches!(p.pc.as_deref(), Some("lu" | "cholesky")) {
            return e.without_factor();
        }
    }
    let mixed = match solver.precision {
        Precision::Double => false,
        Precision::Mixed => true,
        Precision::Auto => solver.linear == LinearMethod::Cholesky && e.factor_entries() >= MIXED_AUTO_MIN_NNZ as f64,
    };
    if mixed {
        e.single_precision_factor()
    } else {
        e
    }
}

/// Nodes coupled with a node of a regular mesh of `kind` (itself included).
fn neighbours(kind: element::CellType) -> f64 {
    match kind {
        element::CellType::Tri3 => 7.0,
        element::CellType::Quad4 => 9.0,
        element::CellType::Tet4 => 15.0,
        element::CellType::Hex8 => 27.0,
    }
}

/// Checks that a built model (its enriched unknowns counted) fits in the available
/// memory; the error names the mesh of the case.
pub fn check_memory(case: &Case, model: &Model<'_>) -> Result<(), CaseError> {
    let mesh = model.mesh;
    let Some(kind) = mesh.cells.first().map(|c| c.kind) else { return Ok(()) };
    let e = Estimate::of_model(
        mesh.dim,
        mesh.n_nodes() as f64,
        mesh.n_cells() as f64,
        kind.n_nodes() as f64,
        model.enrichment.dofs.n_total() as f64,
        neighbours(kind),
    );
    let e = with_precision(e, &case.solver);
    let key = match case.mesh {
        MeshSource::File(_) => "file",
        MeshSource::Parts(_) => "parts",
        MeshSource::Generated { .. } => "divisions",
    };
    e.check(memory::available_bytes()).map_err(|t| case.mesh_at.error(key, format!("{t}; use a coarser mesh")))
}

fn matches(on: &Option<Scalar>, inside: &Option<Scalar>, p: [f64; 3], tol: f64) -> bool {
    on.as_ref().is_none_or(|f| f.eval(p, 0.0).abs() <= tol) && inside.as_ref().is_none_or(|f| f.eval(p, 0.0) <= tol)
}

fn add_sets(case: &Case, mesh: &mut Mesh) -> Result<(), CaseError> {
    if case.sets.is_empty() {
        return Ok(());
    }
    let h = mesh.typical_size();
    let boundary = if case.sets.iter().any(|s| s.kind == SetKind::Faces) { mesh.boundary_faces() } else { vec![] };
    for s in &case.sets {
        let tol = s.tolerance.unwrap_or(1e-6 * h);
        if !mesh.group_kinds(&s.name).is_empty() {
            return Err(s.at.error("name", format!("a group named '{}' already exists in the mesh", s.name)));
        }
        let hit = |p: [f64; 3]| matches(&s.on, &s.inside, p, tol);
        match s.kind {
            SetKind::Nodes => {
                let v: Vec<usize> = (0..mesh.n_nodes()).filter(|&n| hit(mesh.nodes[n])).collect();
                if v.is_empty() {
                    return Err(s.at.error("on", format!("set '{}' selects no node (tolerance {tol:.3e})", s.name)));
                }
                mesh.node_groups.insert(s.name.clone(), v);
            }
            SetKind::Faces => {
                let v: Vec<_> =
                    boundary.iter().filter(|f| f.nodes().iter().all(|&n| hit(mesh.nodes[n]))).copied().collect();
                if v.is_empty() {
                    return Err(s
                        .at
                        .error("on", format!("set '{}' selects no boundary face (tolerance {tol:.3e})", s.name)));
                }
                mesh.face_groups.insert(s.name.clone(), v);
            }
            SetKind::Cells => {
                let mut n = [0.0; MAX_NODES];
                let mut dn = [[0.0; 3]; MAX_NODES];
                let mut xs = [[0.0; 3]; MAX_NODES];
                let v: Vec<usize> = (0..mesh.n_cells())
                    .filter(|&c| {
                        let nn = mesh.cell_coords(c, &mut xs);
                        let kind = mesh.cells[c].kind;
                        element::shape(kind, &kind.reference_centroid(), &mut n, &mut dn);
                        hit(element::map_point(&n[..nn], &xs[..nn]))
                    })
                    .collect();
                if v.is_empty() {
                    return Err(s.at.error("inside", format!("set '{}' selects no cell", s.name)));
                }
                mesh.cell_groups.insert(s.name.clone(), v);
            }
        }
    }
    Ok(())
}

/// Attaches the case's materials, loads and conditions to `mesh`.
pub fn build_model<'m>(case: &Case, mesh: &'m Mesh) -> Result<Model<'m>, CaseError> {
    let dim = mesh.dim;
    let analysis = match (case.analysis, dim) {
        (None, 2) => Analysis::PlaneStrain,
        (None, _) => Analysis::ThreeD,
        (Some(a), d) if a.dim() == d => a,
        (Some(a), d) => {
            return Err(case.analysis_at.error("analysis", format!("'{}' does not fit a {d}D mesh", a.name())));
        }
    };

    // Materials: later entries override earlier ones on shared cells.
    let mut cell_material = vec![u32::MAX; mesh.n_cells()];
    let mut materials = vec![];
    for (k, m) in case.materials.iter().enumerate() {
        let cells = mesh.group_cells(&m.group).map_err(|e| m.at.error("group", e.to_string()))?;
        for c in cells {
            cell_material[c] = k as u32;
        }
        materials.push(m.material);
    }
    if let Some(c) = cell_material.iter().position(|&m| m == u32::MAX) {
        let at = &case.materials[0].at;
        return Err(
            at.error("group", format!("cell {c} has no material: give a [[materials]] entry covering every cell"))
        );
    }

    let mut body_forces = vec![];
    let mut cell_body_force = vec![None; mesh.n_cells()];
    for (k, b) in case.body_forces.iter().enumerate() {
        if b.n_components != dim {
            return Err(b.at.error("value", format!("{} components for a {dim}D model", b.n_components)));
        }
        for c in mesh.group_cells(&b.group).map_err(|e| b.at.error("group", e.to_string()))? {
            cell_body_force[c] = Some(k as u32);
        }
        body_forces.push(b.value.clone());
    }

    let mut faces = vec![];
    let mut face_load = vec![];
    let mut loads = vec![];
    for (k, l) in case.face_loads.iter().enumerate() {
        if l.n_components != 0 && l.n_components != dim {
            return Err(l.at.error("value", format!("{} components for a {dim}D model", l.n_components)));
        }
        let f = mesh.group_faces(&l.group).map_err(|e| {
            let hint = if mesh.group_kinds(&l.group).is_empty() {
                String::new()
            } else {
                " (this group has no boundary faces: a load needs a face group)".to_string()
            };
            l.at.error("group", format!("{e}{hint}"))
        })?;
        faces.extend_from_slice(f);
        face_load.extend(std::iter::repeat_n(k as u32, f.len()));
        loads.push(l.load.clone());
    }

    let mut dirichlet = vec![];
    let mut dirichlet_groups = vec![];
    for (g, d) in case.dirichlet.iter().enumerate() {
        if let Some(&c) = d.components.iter().find(|&&c| c >= dim) {
            return Err(d
                .at
                .error("components", format!("component {} does not exist in a {dim}D model", ["x", "y", "z"][c])));
        }
        let nodes = mesh.group_nodes(&d.group).map_err(|e| d.at.error("group", e.to_string()))?;
        dirichlet_groups.push(d.group.clone());
        if d.lip.is_some() {
            continue; // after the enrichment, below
        }
        for &n in &nodes {
            for (c, v) in d.components.iter().zip(&d.values) {
                dirichlet.push(DirichletCondition { node: n, component: *c, value: v.clone(), group: g as u32 });
            }
        }
    }

    // Cracks: level sets sampled at the nodes, snapped, cut; then the enrichment.
    let mut cracks = vec![];
    let mut crack_pressure = vec![];
    let mut boundary = None;
    for def in &case.cracks {
        let what = |e: String| {
            let key = match &def.shape {
                levelset::CrackShape::Formula { .. } if e.contains("(lst)") => "lst",
                levelset::CrackShape::Formula { .. } => "lsn",
                _ => "shape",
            };
            def.at.error(key, format!("crack '{}': {e}", def.name))
        };
        if !def.shape.accepts_dim(dim) {
            return Err(what(match (&def.shape, def.shape.dim()) {
                (levelset::CrackShape::Mesh(_), Some(d)) => format!(
                    "the crack mesh is {} (a {d}D crack) but the body mesh is {dim}D",
                    if d == 3 { "a triangle surface" } else { "a curve" }
                ),
                _ => format!("a {} does not fit a {dim}D mesh", def.shape.name()),
            }));
        }
        let opts = CutOptions {
            subcell_degree: case.xfem.quadrature.subcell_degree,
            front_degree: case.xfem.quadrature.front_degree,
        };
        let boundary = boundary.get_or_insert_with(|| BodyBoundary::new(mesh));
        let body = cut_in_body(&def.shape, mesh, boundary, case.xfem.snap, &opts).map_err(|e| what(e.to_string()))?;
        cracks.push(CrackGeometry { name: def.name.clone(), levelsets: body.levelsets, cut: body.cut });
        crack_pressure.push(def.pressure.clone());
    }
    let enrichment = if cracks.is_empty() {
        Enrichment::none(mesh)
    } else {
        let opts = EnrichOptions {
            tip: case.cracks.iter().map(|c| c.tip).collect(),
            min_side_fraction: case.xfem.min_side_fraction,
        };
        enrich(mesh, &cracks, &opts).map_err(|e| case.cracks[0].at.error("shape", e.to_string()))?
    };
    let relations = build_relations(case, mesh, &cracks, &enrichment, &mut dirichlet)?;

    let side_materials = SideMaterials::along_cracks(mesh, &cracks, &cell_material);
    let mut model = Model {
        mesh,
        analysis,
        materials,
        densities: case.materials.iter().map(|m| m.density).collect(),
        cell_material,
        side_materials,
        body_forces,
        cell_body_force,
        faces,
        face_load,
        loads,
        dirichlet,
        dirichlet_groups,
        dirichlet_method: case.solver.dirichlet,
        relations,
        load_factors: case.load_factors.clone(),
        cracks,
        enrichment,
        crack_pressure,
        xfem_quadrature: case.xfem.quadrature,
    };
    if case.dynamics.is_some() {
        // In dynamics t is time: loads are not ramped.
        model.loads_of_time();
    }
    Ok(model)
}

/// The relations of a model: the lip conditions of `[[dirichlet]]` entries with a `crack`
/// (nodes not enriched by the crack get plain conditions in `dirichlet`), then the
/// `[[relations]]`. See `physics::relations` for what a lip condition holds.
fn build_relations(
    case: &Case,
    mesh: &Mesh,
    cracks: &[CrackGeometry],
    enrichment: &Enrichment,
    dirichlet: &mut Vec<DirichletCondition>,
) -> Result<Vec<Relation>, CaseError> {
    let dim = mesh.dim;
    let mut out = vec![];
    for (g, d) in case.dirichlet.iter().enumerate() {
        let Some((name, side)) = &d.lip else { continue };
        let k = case.cracks.iter().position(|c| &c.name == name).ok_or_else(|| {
            let known: Vec<&str> = case.cracks.iter().map(|c| c.name.as_str()).collect();
            d.at.error("crack", format!("no crack named '{name}' (cracks: {})", known.join(", ")))
        })?;
        let lip = if *side > 0 { "+" } else { "-" };
        let nodes = mesh.group_nodes(&d.group).map_err(|e| d.at.error("group", e.to_string()))?;
        let mut held = 0;
        for &n in &nodes {
            match relations::lip_rows(mesh, enrichment, cracks, k, n, *side) {
                Some(rows) => {
                    for (c, v) in d.components.iter().zip(&d.values) {
                        let label = format!("{}, node {n}, component {}", d.at.key, ["x", "y", "z"][*c]);
                        if let Some(r) =
                            Relation::new(rows[*c].clone(), v.clone(), mesh.nodes[n], Some((g as u32, *c)), label)
                        {
                            out.push(r);
                        }
                    }
                    held += 1;
                }
                None if relations::node_on_side(cracks, k, n, *side) => {
                    for (c, v) in d.components.iter().zip(&d.values) {
                        dirichlet.push(DirichletCondition {
                            node: n,
                            component: *c,
                            value: v.clone(),
                            group: g as u32,
                        });
                    }
                    held += 1;
                }
                None => {}
            }
        }
        if held == 0 {
            return Err(d.at.error(
                "lip",
                format!("group '{}' has no node on the {lip} side of crack '{name}' nor enriched by it", d.group),
            ));
        }
    }
    let h = mesh.typical_size();
    for (ri, r) in case.relations.iter().enumerate() {
        if let Some(&c) = r.components.iter().find(|&&c| c >= dim) {
            return Err(r
                .at
                .error("components", format!("component {} does not exist in a {dim}D model", ["x", "y", "z"][c])));
        }
        let groups = r
            .groups
            .iter()
            .map(|g| mesh.group_nodes(g).map_err(|e| r.at.error("groups", e.to_string())))
            .collect::<Result<Vec<_>, _>>()?;
        let n0 = groups[0].len();
        if let Some((j, _)) = groups.iter().enumerate().find(|(_, v)| v.len() != n0) {
            return Err(r.at.error(
                "groups",
                format!(
                    "group '{}' has {} nodes and group '{}' {}: relations pair the nodes one to one",
                    r.groups[0],
                    n0,
                    r.groups[j],
                    groups[j].len()
                ),
            ));
        }
        // Pair node i of the first group with the node of group j at the same place after
        // the translation between the groups' centroids.
        let centroid = |v: &[usize]| {
            let mut c = [0.0; 3];
            for &n in v {
                for i in 0..3 {
                    c[i] += mesh.nodes[n][i] / v.len() as f64;
                }
            }
            c
        };
        let c0 = centroid(&groups[0]);
        let mut paired: Vec<Vec<usize>> = vec![groups[0].clone()];
        for (j, gj) in groups.iter().enumerate().skip(1) {
            let cj = centroid(gj);
            let mut used = vec![false; gj.len()];
            let mut v = vec![];
            for &a in &groups[0] {
                let target: [f64; 3] = std::array::from_fn(|i| mesh.nodes[a][i] + cj[i] - c0[i]);
                let (best, dist) = gj
                    .iter()
                    .enumerate()
                    .map(|(q, &b)| (q, (0..3).map(|i| (mesh.nodes[b][i] - target[i]).powi(2)).sum::<f64>().sqrt()))
                    .fold((usize::MAX, f64::INFINITY), |acc, x| if x.1 < acc.1 { x } else { acc });
                if best == usize::MAX || used[best] || dist > 1e-6 * h {
                    return Err(r.at.error(
                        "groups",
                        format!(
                            "cannot pair the nodes of '{}' and '{}' one to one by a translation (node {a} has no partner)",
                            r.groups[0], r.groups[j]
                        ),
                    ));
                }
                used[best] = true;
                v.push(gj[best]);
            }
            paired.push(v);
        }
        for i in 0..n0 {
            let terms = (0..groups.len())
                .map(|j| ((paired[j][i] * dim + r.components[j]) as u32, r.coefficients[j]))
                .collect::<Vec<_>>();
            let a = paired[0][i];
            let label = format!("relations[{ri}], node {a}");
            let rel = Relation::new(terms, r.value.clone(), mesh.nodes[a], None, label).ok_or_else(|| {
                r.at.error("coefficients", format!("the coefficients cancel at node {a} (the same unknown twice)"))
            })?;
            out.push(rel);
        }
    }
    // A relation on prescribed unknowns only is redundant (a singular system).
    let prescribed: std::collections::HashSet<u32> =
        dirichlet.iter().map(|c| (c.node * dim + c.component) as u32).collect();
    if let Some(r) = out.iter().find(|r| r.terms.iter().all(|t| prescribed.contains(&t.0))) {
        let key = if r.reaction.is_some() { "dirichlet" } else { "relations" };
        return Err(CaseError {
            file: case.mesh_at.file.clone(),
            line: None,
            key: key.into(),
            message: format!(
                "{}: every unknown of this relation is already prescribed by a [[dirichlet]] entry",
                r.label
            ),
        });
    }
    Ok(out)
}

/// The contact setup of a case: contact points and unknowns of every crack with a
/// `[cracks.contact]` table, numbered after the model's enriched dofs; `None` without.
pub fn build_contact(case: &Case, model: &Model<'_>) -> Result<Option<ContactSetup>, CaseError> {
    let mesh = model.mesh;
    let mut opts = vec![];
    for (k, def) in case.cracks.iter().enumerate() {
        let Some(c) = def.contact else { continue };
        if model.cracks[k].cut.facets.is_empty() {
            return Err(def.at.error(
                "contact",
                format!("crack '{}' has no facet in the mesh: contact needs a crack that cuts cells", def.name),
            ));
        }
        opts.push(ContactCrackOptions { crack: k, ..c });
    }
    let pairs = build_pairs(case, model)?;
    if opts.is_empty() && pairs.is_empty() {
        return Ok(None);
    }
    // Stiffness scale for the default augmentation: the mean Young's modulus of the cut
    // cells, each the softer of its two sides (docs/contact-algorithms.md).
    let mut e_sum = 0.0;
    let mut n = 0usize;
    for o in &opts {
        for cc in &model.cracks[o.crack].cut.cut_cells {
            e_sum += softer_side(model, cc.cell);
            n += 1;
        }
    }
    let young = if n > 0 { e_sum / n as f64 } else { model.materials[0].young };
    // An augmentation far above E/h swamps the stiffness: refused (see `RHO_N_LIMIT`).
    for o in &opts {
        let def = &case.cracks[o.crack];
        if let (Some(rho), Some(scale)) = (o.rho_n, augmentation_scale(model, o.crack)) {
            if rho > RHO_N_LIMIT * scale {
                let err = |m: String| match &def.rho_n_at {
                    Some(at) => CaseError { file: at.file.clone(), line: at.line, key: at.key.clone(), message: m },
                    None => def.at.error("contact.rho_n", m),
                };
                return Err(err(
                    format!(
                        "crack '{}': rho_n = {rho:e} is {:.1e} times E/h = {scale:.4e} (E the mean Young's modulus of the cut cells, h their mean edge length; the default is E/h): the augmented terms then swamp the stiffness and the solve fails or drifts (docs/reliability.md, \"Contact numerics\"); give at most {RHO_N_LIMIT:.0e} E/h = {:.4e}, best between 0.1 and 100 E/h",
                        def.name,
                        rho / scale,
                        RHO_N_LIMIT * scale
                    ),
                ));
            }
        }
    }
    let points = ContactPoints::build(mesh, &model.cracks, young, &opts, &pairs, model.enrichment.dofs.n_total());
    let crosspoints = crate::contact::crosspoints::find(model, &points);
    Ok(Some(ContactSetup { points, loops: case.contact_loops, crosspoints }))
}

/// The largest `rho_n` accepted, as a multiple of E/h ([`augmentation_scale`]): the closed
/// 45° crack of `examples/inclined_crack_friction_2d.toml` (41 × 41) fails from 1e7 E/h (the
/// active-set loop cap at 1e7, a singular-looking LDLᵀ residual of 1.7e-3 from 1e9), while
/// a uniformly compressed interface stays exact to 1.7e5 E/h (`tests/adversarial.rs`).
pub const RHO_N_LIMIT: f64 = 1e6;

/// The Young's modulus of the softer side of cell `c` (its own modulus unless it has
/// per-side materials): the stiffness the contact terms of a cut cell work against.
fn softer_side(model: &Model<'_>, c: usize) -> f64 {
    let [minus, plus] = model.side_youngs(c);
    minus.min(plus)
}

/// E/h of crack `k`: the mean Young's modulus of its cut cells (each the softer of its
/// sides) over their mean edge length
/// (the default `rho_n`'s scale); `None` for a crack that cuts no cell.
pub fn augmentation_scale(model: &Model<'_>, k: usize) -> Option<f64> {
    let cells = &model.cracks.get(k)?.cut.cut_cells;
    if cells.is_empty() {
        return None;
    }
    let n = cells.len() as f64;
    let e = cells.iter().map(|cc| softer_side(model, cc.cell)).sum::<f64>() / n;
    let h = cells.iter().map(|cc| model.mesh.cell_edge_length(cc.cell)).sum::<f64>() / n;
    Some(e / h)
}

/// The surfaces of every `[[contact_pairs]]` entry with its options and the mean Young's
/// modulus of the cells along its surfaces (the default augmentation's scale).
fn build_pairs(case: &Case, model: &Model<'_>) -> Result<Vec<(PairSurfaces, ContactCrackOptions, f64)>, CaseError> {
    let mesh = model.mesh;
    let mut out = vec![];
    for (i, def) in case.contact_pairs.iter().enumerate() {
        let faces = |key: &str, group: &str| -> Result<&[crate::mesh::Face], CaseError> {
            let f = mesh.group_faces(group).map_err(|e| {
                let kinds = mesh.group_kinds(group);
                if kinds.is_empty() {
                    def.at.error(key, format!("contact pair '{}': {e}", def.name))
                } else {
                    def.at.error(
                        key,
                        format!("contact pair '{}': '{group}' is not a boundary face group ({kinds:?})", def.name),
                    )
                }
            })?;
            if f.is_empty() {
                return Err(def.at.error(key, format!("contact pair '{}': face group '{group}' is empty", def.name)));
            }
            Ok(f)
        };
        let slave = faces("slave", &def.slave)?;
        let master = faces("master", &def.master)?;
        let surfaces = PairSurfaces::build(mesh, i, &def.name, slave, master).map_err(|e| {
            let key = if e.starts_with("master") { "master" } else { "slave" };
            def.at.error(key, format!("contact pair '{}': {e}", def.name))
        })?;
        let cells: Vec<usize> = surfaces.slave.iter().chain(&surfaces.master).map(|f| f.cell).collect();
        let young = cells.iter().map(|&c| model.materials[model.cell_material[c] as usize].young).sum::<f64>()
            / cells.len() as f64;
        check_initial_penetration(mesh, def, &surfaces)?;
        out.push((surfaces, def.options, young));
    }
    Ok(out)
}

/// Refuses a pair whose slave nodes start inside the master body deeper than a cell: the
/// projection onto the master surface would pair them with the wrong side.
fn check_initial_penetration(mesh: &Mesh, def: &super::ContactPairDef, s: &PairSurfaces) -> Result<(), CaseError> {
    let h = s.cell_size;
    for f in &s.slave {
        for (k, x) in f.vertices.iter().enumerate() {
            // The nearest master facet point and the penetration along its outward normal.
            let mut best: Option<(f64, f64)> = None;
            for m in &s.master {
                let b = crate::contact::facet_barycentric(&m.vertices, *x);
                let mut y = [0.0; 3];
                for (v, bv) in b.iter().enumerate() {
                    for i in 0..3 {
                        y[i] += bv * m.vertices[v][i];
                    }
                }
                let d: f64 = (0..3).map(|i| (x[i] - y[i]).powi(2)).sum::<f64>().sqrt();
                let pen = -(0..3).map(|i| (x[i] - y[i]) * m.normal[i]).sum::<f64>();
                if best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, pen));
                }
            }
            if let Some((_, pen)) = best {
                if pen > h {
                    let a = f.vertex_nodes[k].unwrap_or(usize::MAX);
                    return Err(def.at.error(
                        "slave",
                        format!(
                            "contact pair '{}': slave node {a} at {:?} starts {pen:.3e} inside the master body, more than a cell ({h:.3e}); move the bodies apart",
                            def.name,
                            &x[..mesh.dim]
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}
