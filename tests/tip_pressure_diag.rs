//! Diagnostics of issue 4 (contact pressure near the crack tips), ignored by default; run
//! with `cargo test --release --test tip_pressure_diag -- --ignored --nocapture <name>`.
//!
//! - `diag_45`: the closed 45° crack of `contact_friction_cracks.rs` (μ = 0), reference
//!   0.5σ. `DIAG_N` (mesh n × n, default 81), `DIAG_WHICH` (comma-separated variants: base,
//!   vv, none, vertex, topo, r10, rho10, rho1000, q12, q20), `DIAG_EXTRA` (appended case
//!   text, `\n` for new lines), `DIAG_R` (tip radius), `DIAG_NU` (Poisson ratio),
//!   `DIAG_FULL` (print every point).
//! - `diag_flat`: the interior crack along y = 0.0071 under normal compression, reference σ.
//! - `diag_shear`: the 45° problem rotated into the mesh axes: a horizontal crack under
//!   σ_yy = −0.5, σ_xy = 0.5 (reference 0.5); `DIAG_XA`, `DIAG_Y` (crack position),
//!   `DIAG_R` (tip radius or `topo`).
//! - `diag_table`: per mesh (`DIAG_MESHES`), the worst pressure error, K_I and K_II of
//!   the closed 45° crack (μ = 0, 0.3) and of the closed interior crack, and solve times;
//!   `DIAG_R` (tip radius).
//! - `diag_algorithms`: the table of `docs/contact-algorithms.md` (loop counts, slip
//!   points, |K_II| and times of both contact algorithms on the 161 mesh).
//! - `diag_null`: the smallest eigenvalues and modes of the enriched bulk stiffness on a
//!   small edge-crack mesh (how the zero-energy modes of a ramped blending space were found).
//!
//! Each line gives the largest pressure error in the middle (|s| < 0.08) and overall, and
//! the signed largest error in bands of the distance to the nearest tip, in cells.
mod common;

use common::contact::{inclined_crack, solve_contact_text};

fn profile(label: &str, text: &str, p_ref: f64, full: bool) {
    profile_c(label, text, p_ref, full, [0.0123, 0.0071])
}

fn profile_c(label: &str, text: &str, p_ref: f64, full: bool, ctr: [f64; 2]) {
    let r = match solve_contact_text(text) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{label}: FAILED {e:?}");
            return;
        }
    };
    let dir = {
        let (a, b) = (r.x.first().unwrap(), r.x.last().unwrap());
        let d = [b[0] - a[0], b[1] - a[1]];
        let n = (d[0] * d[0] + d[1] * d[1]).sqrt();
        [d[0] / n, d[1] / n]
    };
    let mut rows: Vec<(f64, f64, f64, f64)> = (0..r.lambda.len())
        .map(|i| {
            let s = (r.x[i][0] - ctr[0]) * dir[0] + (r.x[i][1] - ctr[1]) * dir[1];
            let jt = r.jump[i][0] * r.tangent[i][0] + r.jump[i][1] * r.tangent[i][1];
            (s, 100.0 * (-r.lambda[i] / p_ref - 1.0), r.d_n[i], jt)
        })
        .collect();
    rows.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    let mid = rows.iter().filter(|r| r.0.abs() < 0.08).map(|r| r.1.abs()).fold(0.0, f64::max);
    let all = rows.iter().map(|r| r.1.abs()).fold(0.0, f64::max);
    let dn = rows.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
    let h = r.h;
    let mut bands = String::new();
    for k in 0..6 {
        let m = rows
            .iter()
            .filter(|r| {
                let rt = 0.2 - r.0.abs();
                rt >= k as f64 * h && rt < (k + 1) as f64 * h
            })
            .map(|r| r.1)
            .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
        bands += &format!(" {m:+.2}");
    }
    eprintln!(
        "{label}: h={h:.4} mult={} pts={} max|err| mid={mid:.2}% all={all:.2}% ; by r_tip/h bands [0,1)..[5,6): {bands} ; max|d_n|={dn:.2e} ; K_II={:?} ; K_I/σ√πa={:?}",
        r.multipliers,
        rows.len(),
        r.sifs[0].iter().map(|s| (s.k2 * 1e4).round() / 1e4).collect::<Vec<_>>(),
        r.sifs[0].iter().map(|s| format!("{:+.1e}", s.k1 / (std::f64::consts::PI * 0.2).sqrt())).collect::<Vec<_>>()
    );
    if full {
        for (s, e, d, jt) in &rows {
            eprintln!("   s={s:+.4} rtip/h={:.2} err={e:+.3}% d_n={d:+.2e} jt={jt:+.3e}", (0.2 - s.abs()) / h);
        }
    }
}

fn var(n: usize, crack_sub: &[(&str, &str)], extra: &str) -> String {
    let mut t = inclined_crack(0.0, n, extra);
    for (a, b) in crack_sub {
        t = t.replace(a, b);
    }
    t
}

#[test]
#[ignore]
fn diag_45() {
    let n: usize = std::env::var("DIAG_N").ok().and_then(|s| s.parse().ok()).unwrap_or(81);
    let full = std::env::var("DIAG_FULL").is_ok();
    let which = std::env::var("DIAG_WHICH").unwrap_or("base".into());
    for w in which.split(',') {
        let (sub, extra): (Vec<(&str, &str)>, &str) = match w {
            "base" => (vec![], ""),
            "vv" => (vec![], "lbb = \"vital_vertex\"\n"),
            "none" => (vec![], "lbb = \"none\"\n"),
            "vertex" => (vec![], "integration = \"vertex\"\n"),
            "topo" => (vec![("tip_radius = 0.05", "enrichment = \"topological\"")], ""),
            "r10" => (vec![("tip_radius = 0.05", "tip_radius = 0.10")], ""),
            "rho10" => (vec![], "rho_n = 10.0\n"),
            "rho1000" => (vec![], "rho_n = 1000.0\n"),
            "q20" => (vec![], "[xfem]\ntip_degree = 20\nfront_degree = 20\n"),
            "q12" => (vec![], "[xfem]\ntip_degree = 12\nfront_degree = 12\n"),
            _ => panic!("{w}"),
        };
        let x = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
        let text = var(n, &sub, &format!("{extra}{x}"));
        let text = match std::env::var("DIAG_NU") {
            Ok(v) => text.replace("nu = 0.3", &format!("nu = {v}")),
            _ => text,
        };
        let text = match std::env::var("DIAG_R") {
            Ok(r) => text.replace("tip_radius = 0.05", &format!("tip_radius = {r}")),
            _ => text,
        };
        profile(&format!("n={n} {w}"), &text, 0.5, full);
    }
}

#[test]
#[ignore]
fn diag_flat() {
    let n: usize = std::env::var("DIAG_N").ok().and_then(|s| s.parse().ok()).unwrap_or(161);
    let full = std::env::var("DIAG_FULL").is_ok();
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let text = inclined_crack(0.0, n, &extra)
        .replace("a = [", "a = [-0.1877, 0.0071]\n#a = [")
        .replace("b = [", "b = [0.2123, 0.0071]\n#b = [");
    profile(&format!("flat n={n}"), &text, 1.0, full);
}

/// Horizontal crack under σ_yy = −p, σ_xy = τ (the 45° problem rotated into the mesh axes).
#[test]
#[ignore]
fn diag_shear() {
    let n: usize = std::env::var("DIAG_N").ok().and_then(|s| s.parse().ok()).unwrap_or(161);
    let full = std::env::var("DIAG_FULL").is_ok();
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    let xa: f64 = std::env::var("DIAG_XA").ok().and_then(|s| s.parse().ok()).unwrap_or(-0.1877);
    let y: f64 = std::env::var("DIAG_Y").ok().and_then(|s| s.parse().ok()).unwrap_or(0.0071);
    let text = inclined_crack(0.0, n, &extra)
        .replace("a = [", &format!("a = [{xa}, {y}]\n#a = ["))
        .replace("b = [", &format!("b = [{}, {y}]\n#b = [", xa + 0.4))
        .replace("value = [0.0, -1.0]", "value = [0.5, -0.5]")
        .replace("value = [0.0, 1.0]", "value = [-0.5, 0.5]\n[[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.5]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, -0.5]");
    let text = match std::env::var("DIAG_R") {
        Ok(r) if r == "topo" => text.replace("tip_radius = 0.05", "enrichment = \"topological\""),
        Ok(r) => text.replace("tip_radius = 0.05", &format!("tip_radius = {r}")),
        _ => text,
    };
    profile_c(&format!("shear n={n}"), &text, 0.5, full, [xa + 0.2, y]);
}

/// Null space of the enriched bulk stiffness on a small edge-crack mesh.
#[test]
#[ignore]
fn diag_null() {
    use fissure::assembly::{Kernel, LocalOut};
    use fissure::case::{resolve, Case};
    use fissure::physics::xfem::XfemBulkKernel;
    let n: usize = std::env::var("DIAG_N").ok().and_then(|s| s.parse().ok()).unwrap_or(10);
    let r: f64 = std::env::var("DIAG_R").ok().and_then(|s| s.parse().ok()).unwrap_or(0.3);
    let text = format!("[mesh]\ngenerator = \"rectangle\"\ncell = \"quad4\"\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\ndivisions = [{n}, {n}]\n[[materials]]\nE = 1.0\nnu = 0.3\n[[cracks]]\nname = \"c\"\nshape = \"half_line\"\ntip = [0.03, 0.02]\ndirection = [1.0, 0.0]\ntip_radius = {r}\n");
    let case = Case::parse(&text, std::path::Path::new("case.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mesh = resolve::build_mesh(&case).unwrap();
    let model = resolve::build_model(&case, &mesh).unwrap();
    let k = XfemBulkKernel {
        mesh: &mesh,
        enrichment: &model.enrichment,
        cracks: &model.cracks,
        analysis: model.analysis,
        cell_material: &model.cell_material,
        side_materials: &model.side_materials,
        materials: &model.materials,
        cell_body_force: &model.cell_body_force,
        body_forces: &model.body_forces,
        quadrature: model.xfem_quadrature,
        t: 1.0,
    };
    let nd = model.enrichment.dofs.n_total();
    let mut big = nalgebra::DMatrix::<f64>::zeros(nd, nd);
    for e in 0..k.n_elements() {
        let mut d = vec![];
        k.dofs(e, &mut d);
        let m = d.len();
        let mut loc = vec![0.0; m * m];
        k.compute(e, &d, LocalOut { matrix: Some(&mut loc), vector: None });
        for i in 0..m {
            for j in 0..m {
                big[(d[i] as usize, d[j] as usize)] += loc[i * m + j];
            }
        }
    }
    // dof -> (node, kind, blending, l, comp)
    let mut info = vec![String::new(); nd];
    for node in 0..mesh.n_nodes() {
        for c in 0..2 {
            info[node * 2 + c] = format!("std n{node} c{c}");
        }
        for it in model.enrichment.node_items(node) {
            let f = it.first_dof as usize;
            match it.kind {
                fissure::enrich::EnrichKind::Heaviside => {
                    for c in 0..2 {
                        info[f + c] = format!("H n{node} {:?} c{c}", mesh.nodes[node]);
                    }
                }
                fissure::enrich::EnrichKind::Tip => {
                    for l in 0..it.n_functions() {
                        for c in 0..2 {
                            info[f + 2 * l + c] =
                                format!("T n{node} {:?} b={} l{l} c{c}", mesh.nodes[node], it.blending);
                        }
                    }
                }
            }
        }
    }
    let eig = big.clone().symmetric_eigen();
    let max = eig.eigenvalues.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let mut idx: Vec<usize> = (0..nd).collect();
    idx.sort_by(|&a, &b| eig.eigenvalues[a].partial_cmp(&eig.eigenvalues[b]).unwrap());
    eprintln!(
        "nd={nd} max eig {max:.3e}; smallest: {:?}",
        idx.iter().take(14).map(|&i| eig.eigenvalues[i] / max).collect::<Vec<_>>()
    );
    for &i in idx.iter().skip(3).take(std::env::var("DIAG_K").ok().and_then(|s| s.parse().ok()).unwrap_or(2)) {
        let v = eig.eigenvectors.column(i);
        let mut comp: Vec<(usize, f64)> = v.iter().cloned().enumerate().collect();
        comp.sort_by(|a, b| b.1.abs().partial_cmp(&a.1.abs()).unwrap());
        eprintln!("mode eig {:.3e}:", eig.eigenvalues[i] / max);
        for (d, x) in comp.iter().take(24) {
            eprintln!("   {x:+.4} {}", info[*d]);
        }
    }
}

/// The figures of issue 4 per mesh: for the closed 45° crack (μ = 0 and 0.3) and the
/// closed interior crack, the worst pressure error (and its distance to the nearer tip in
/// cells), K_I / σ√(πa) and |K_II| against GetFEM at both tips, and the solve time.
/// `DIAG_MESHES` (comma-separated, default 81,101,121,141,161,181,201,221,241).
#[test]
#[ignore]
fn diag_table() {
    let k0 = (std::f64::consts::PI * 0.2).sqrt();
    let meshes: Vec<usize> = std::env::var("DIAG_MESHES")
        .unwrap_or("81,101,121,141,161,181,201,221,241".into())
        .split(',')
        .map(|s| s.trim().parse().unwrap())
        .collect();
    for &n in &meshes {
        for (label, mu, p_ref, getfem, flat) in [
            ("45° μ=0", 0.0, 0.5, 0.4001, false),
            ("45° μ=0.3", 0.3, 0.5, 0.2801, false),
            ("interior", 0.0, 1.0, 0.0, true),
        ] {
            let mut text = inclined_crack(mu, n, "");
            if let Ok(r) = std::env::var("DIAG_R") {
                text = text.replace("tip_radius = 0.05", &format!("tip_radius = {r}"));
            }
            if flat {
                text = text
                    .replace("a = [", "a = [-0.1877, 0.0071]\n#a = [")
                    .replace("b = [", "b = [0.2123, 0.0071]\n#b = [");
            }
            let t0 = std::time::Instant::now();
            let r = match solve_contact_text(&text) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("n={n} {label}: FAILED {e:?}");
                    continue;
                }
            };
            let dt = t0.elapsed().as_secs_f64();
            let (a, b) = (r.x.first().unwrap(), r.x.last().unwrap());
            let tips: Vec<[f64; 3]> = r.sifs[0].iter().map(|s| s.x).collect();
            let _ = (a, b);
            let mut worst = (0.0f64, 0.0f64);
            for i in 0..r.lambda.len() {
                let e = -r.lambda[i] / p_ref - 1.0;
                if e.abs() > worst.0.abs() {
                    let d = tips
                        .iter()
                        .map(|t| ((r.x[i][0] - t[0]).powi(2) + (r.x[i][1] - t[1]).powi(2)).sqrt())
                        .fold(f64::INFINITY, f64::min);
                    worst = (e, d / r.h);
                }
            }
            let sifs: Vec<String> = r.sifs[0]
                .iter()
                .map(|s| {
                    if flat {
                        format!("K_I {:+.1e} K_II {:+.1e}", s.k1 / k0, s.k2 / k0)
                    } else {
                        format!(
                            "K_I {:+.1e} |K_II| {:.4} ({:+.2}%)",
                            s.k1 / k0,
                            s.k2.abs(),
                            100.0 * (s.k2.abs() / getfem - 1.0)
                        )
                    }
                })
                .collect();
            eprintln!(
                "n={n} {label}: worst pressure {:+.2}% at {:.2} cells from a tip; {}; {dt:.2} s",
                100.0 * worst.0,
                worst.1,
                sifs.join(" / ")
            );
        }
    }
}

/// The comparison table of `docs/contact-algorithms.md`: the closed 45° crack on the 161
/// mesh for both contact algorithms and several Coulomb coefficients: loop counts of the
/// load step, slip points, |K_II| at both tips, wall time.
#[test]
#[ignore]
fn diag_algorithms() {
    use fissure::contact::law::Status;
    for alg in ["nested", "semi_smooth"] {
        for mu in [0.0, 0.3, 0.9, 1.0, 1.1, 1.5] {
            let text = format!("{}\n[contact_solver]\nalgorithm = \"{alg}\"\n", inclined_crack(mu, 161, ""));
            let t0 = std::time::Instant::now();
            let r = match solve_contact_text(&text) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("{alg} μ={mu}: FAILED {e:?}");
                    continue;
                }
            };
            let dt = t0.elapsed().as_secs_f64();
            let c = r.steps[0].contact.as_ref().unwrap();
            let slip = r.status.iter().filter(|s| **s == Status::Slip).count();
            let k2: Vec<String> = r.sifs[0].iter().map(|s| format!("{:.4}", s.k2.abs())).collect();
            eprintln!(
                "| {alg} | {mu} | {} | {} | {} | {} | {slip} | {} | {dt:.2} |  (of {} points)",
                c.friction,
                c.active_set,
                c.newton,
                c.factorizations,
                k2.join(" / "),
                r.status.len()
            );
        }
    }
}

/// Issue 11 item 8: a closed penny crack (radius 1, frictionless) in a hex8 box
/// [−2, 2]³ under uniform compression σ_zz = −1 (reference pressure 1 everywhere), with
/// the crack plane at `DIAG_Z` (0: a node plane; default) on a `DIAG_N`³ mesh (16).
/// Prints the pressure error in bands of the distance to the front, in cells.
#[test]
#[ignore]
fn diag_penny_plane() {
    let n: usize = std::env::var("DIAG_N").ok().and_then(|s| s.parse().ok()).unwrap_or(16);
    let cell = std::env::var("DIAG_CELL").unwrap_or("hex8".into());
    let nu: f64 = std::env::var("DIAG_NU").ok().and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let extra = std::env::var("DIAG_EXTRA").unwrap_or_default().replace("\\n", "\n");
    for z in std::env::var("DIAG_Z").unwrap_or("0.0,0.001".into()).split(',') {
        let text = format!(
            "[mesh]\ngenerator = \"box\"\ncell = \"{cell}\"\nlower = [-2.0, -2.0, -2.0]\nupper = [2.0, 2.0, 2.0]\n\
             divisions = [{n}, {n}, {n}]\n[[materials]]\nE = 1.0\nnu = {nu}\n[[dirichlet]]\ngroup = \"back\"\n\
             components = [\"x\", \"y\", \"z\"]\n[[traction]]\ngroup = \"front\"\nvalue = [0.0, 0.0, -1.0]\n\
             [[cracks]]\nname = \"penny\"\nshape = \"disc\"\ncentre = [0.0, 0.0, {z}]\nnormal = [0.0, 0.0, 1.0]\n\
             radius = 1.0\n[cracks.contact]\nfriction = 0.0\n{extra}"
        );
        let r = match solve_contact_text(&text) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("z = {z}: FAILED {e:?}");
                continue;
            }
        };
        let h = 4.0 / n as f64;
        let mut bands = std::collections::BTreeMap::<usize, (f64, f64, f64, usize)>::new();
        for (x, l) in r.x.iter().zip(&r.lambda) {
            let d = (1.0 - (x[0] * x[0] + x[1] * x[1]).sqrt()) / h;
            let b = bands.entry(d.max(0.0) as usize).or_insert((f64::INFINITY, f64::NEG_INFINITY, 0.0, 0));
            let e = -l - 1.0;
            b.0 = b.0.min(e);
            b.1 = b.1.max(e);
            b.2 += e;
            b.3 += 1;
        }
        eprintln!("z = {z}: {} points, {} multipliers", r.x.len(), r.multipliers);
        if std::env::var("DIAG_FULL").is_ok() {
            let mut v: Vec<(f64, [f64; 3])> = r.x.iter().zip(&r.lambda).map(|(x, l)| (-l - 1.0, *x)).collect();
            v.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
            for (e, x) in v.iter().take(12) {
                eprintln!("    error {e:+.4} at [{:.4}, {:.4}, {:.4}] (r = {:.4})", x[0], x[1], x[2], x[0].hypot(x[1]));
            }
        }
        for (k, (mn, mx, s, c)) in bands {
            eprintln!(
                "  {k}-{} cells from the front: {c:5} points, error {mn:+.4} .. {mx:+.4}, mean {:+.4}",
                k + 1,
                s / c as f64
            );
        }
    }
}
