//! Helpers shared by the benchmarks (`#[path = "common/mod.rs"] mod common;`): the peak
//! resident memory, and the finer penny mesh of the xfem and growth benches.

use std::path::{Path, PathBuf};
use std::time::Instant;

#[allow(dead_code)] // the benches use part of it
#[path = "../../tests/common/penny_block.rs"]
mod penny_block;
use penny_block::{penny_block, PENNY_DISC, PENNY_TENSION};

/// Mesh sizes of the finer penny mesh relative to `meshes/penny_block.geo`.
#[allow(dead_code)]
pub const PENNY_SCALE: f64 = 0.8;

/// Peak resident memory of this process (VmHWM), in MB.
pub fn peak_rss_mb() -> f64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    s.lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

#[allow(dead_code)] // used by the xfem and growth benches only
/// The finer penny mesh: `meshes/penny_block.geo` with every size scaled by
/// [`PENNY_SCALE`], meshed by gmsh (one thread) into `target/bench-meshes/`. Falls back to
/// the committed mesh when gmsh is not installed. Returns the path and a note.
pub fn penny_mesh() -> (PathBuf, String) {
    penny_mesh_scaled(PENNY_SCALE, "penny_block_fine")
}

/// Mesh sizes of the penny mesh of the ~5e5-dof contact rows (`benches/xfem.rs`).
#[allow(dead_code)]
pub const PENNY_CONTACT_SCALE: f64 = 0.47;

#[allow(dead_code)] // used by the xfem and growth benches only
/// [`penny_mesh`] with the sizes of `meshes/penny_block.geo` scaled by `scale`, written to
/// `target/bench-meshes/<stem>.msh`.
pub fn penny_mesh_scaled(scale: f64, stem: &str) -> (PathBuf, String) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let committed = root.join("meshes/penny_block.msh");
    let geo = match std::fs::read_to_string(root.join("meshes/penny_block.geo")) {
        Ok(g) => g,
        Err(e) => return (committed, format!("committed mesh (penny_block.geo unreadable: {e})")),
    };
    let scaled: String = geo
        .lines()
        .map(|l| match l.split_once(".SizeM") {
            Some((head, rest)) if rest.starts_with("in = ") || rest.starts_with("ax = ") => {
                let (key, value) = rest.split_at(5);
                let v: f64 = value.trim_end_matches(';').trim().parse().unwrap_or(f64::NAN);
                format!("{head}.SizeM{key}{:.4};\n", v * scale)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let dir = target.join("bench-meshes");
    let geo_path = dir.join(format!("{stem}.geo"));
    let msh_path = dir.join(format!("{stem}.msh"));
    let fresh = std::fs::read_to_string(&geo_path).is_ok_and(|g| g == scaled) && msh_path.exists();
    if !fresh {
        if std::fs::create_dir_all(&dir).is_err() || std::fs::write(&geo_path, &scaled).is_err() {
            return (committed, "committed mesh (target/bench-meshes not writable)".into());
        }
        let gmsh = |geo: &Path| {
            std::process::Command::new("gmsh")
                .args(["-3", "-format", "msh41", "-nt", "1"])
                .arg(geo)
                .arg("-o")
                .arg(&msh_path)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .status()
                .map(|s| s.success())
        };
        let t = Instant::now();
        let mut ok = gmsh(&geo_path);
        // Gmsh before 4.11 (Debian 12 ships 4.8) names the Distance field's `Sampling`
        // option `NumPointsPerCurve` and rejects the new name.
        if matches!(ok, Ok(false)) {
            let old = dir.join(format!("{stem}_gmsh_pre_4_11.geo"));
            if std::fs::write(&old, scaled.replace(".Sampling = ", ".NumPointsPerCurve = ")).is_ok() {
                ok = gmsh(&old);
            }
        }
        match ok {
            Ok(true) => eprintln!("gmsh: {} in {:.1} s", msh_path.display(), t.elapsed().as_secs_f64()),
            _ => {
                let _ = std::fs::remove_file(&geo_path);
                let _ = std::fs::remove_file(&msh_path);
                let why = if ok.is_err() { "gmsh not found" } else { "gmsh failed" };
                return (committed, format!("committed mesh meshes/penny_block.msh ({why})"));
            }
        }
    }
    let note = format!("gmsh mesh {} (sizes × {scale})", msh_path.display());
    (msh_path, note)
}

/// The penny-crack case of the benches on the mesh `mesh` ([`penny_mesh`]): disc a = 1 in
/// the block [−5, 5]³, σ = 1 on z = ±5, three corner points holding the rigid modes,
/// `[solver] ordering`.
#[allow(dead_code)] // used by the xfem and growth benches only
pub fn penny_case(mesh: &Path, ordering: &str) -> String {
    let mesh = mesh.display().to_string();
    penny_block(&mesh, PENNY_TENSION, PENNY_DISC) + &format!("[solver]\nordering = \"{ordering}\"\n")
}

/// The penny crack of `examples/penny_crack_contact_3d.toml` on the mesh `mesh`
/// ([`penny_mesh_scaled`]): disc a = 1 in the block [−5, 5]³, closed by σ = 1 and sheared
/// by τ = 0.5 in the x–z plane, Coulomb friction μ = 0.2 (every point slides), the default
/// tip zone (two layers of cells about the front; the example's fixed `tip_radius = 0.25`
/// is dropped: on the × 0.47 mesh it gives a factor of 13.3 GB, beyond the row's 16 GB
/// floor with the rest of the model, `docs/performance.md`), the stabilised multipliers
/// as the example sets them (`multiplier_stabilisation = 10`), `[solver] ordering`.
#[allow(dead_code)] // used by the xfem bench only
pub fn penny_contact_case(mesh: &Path, ordering: &str) -> String {
    let mesh = mesh.display().to_string();
    let loads = "[[traction]]\ngroup = \"front\"\nvalue = [0.5, 0.0, -1.0]\n[[traction]]\ngroup = \"back\"\nvalue = [-0.5, 0.0, 1.0]\n\
                 [[traction]]\ngroup = \"right\"\nvalue = [0.0, 0.0, 0.5]\n[[traction]]\ngroup = \"left\"\nvalue = [0.0, 0.0, -0.5]";
    penny_block(&mesh, loads, PENNY_DISC).replace("tip_radius = 0.25\n", "")
        + &format!(
            "[cracks.contact]\nfriction = 0.2\nmultiplier_stabilisation = 10\n[solver]\nordering = \"{ordering}\"\n"
        )
}

/// The centre-crack case of the benches: plate [−5, 5] × [−10, 10] in quad4 `nx` × `ny`,
/// crack 2a = 2 on y = 0, σ = 1 on top and bottom, two corner points holding the rigid
/// modes.
#[allow(dead_code)] // used by the xfem and growth benches only
pub fn centre_case(nx: usize, ny: usize) -> String {
    format!(
        r#"
[mesh]
generator = "rectangle"
cell = "quad4"
lower = [-5.0, -10.0]
upper = [5.0, 10.0]
divisions = [{nx}, {ny}]
[[materials]]
E = 1.0
nu = 0.3
[[sets]]
name = "pin"
on = "abs(x+5) + abs(y+10)"
[[sets]]
name = "roller"
on = "abs(x-5) + abs(y+10)"
[[dirichlet]]
group = "pin"
components = ["x", "y"]
[[dirichlet]]
group = "roller"
components = ["y"]
[[traction]]
group = "top"
value = [0.0, 1.0]
[[traction]]
group = "bottom"
value = [0.0, -1.0]
[[cracks]]
name = "c"
shape = "segment"
a = [-1.0, 0.0]
b = [1.0, 0.0]
tip_radius = 0.3
sif_radius = 0.5
"#
    )
}

#[allow(dead_code)] // used by the elasticity and xfem benches only
/// CPU seconds (user + system, all threads) this process has used so far, from
/// `/proc/self/stat`; NaN where that file is not readable. CPU over wall time of a phase
/// says how many cores it kept busy.
pub fn cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which may hold spaces) closed by ')'.
    let rest = s.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok());
    // utime and stime are fields 14 and 15 of the whole line: 12 and 13 after ')'.
    match (ticks(11), ticks(12)) {
        (Some(u), Some(t)) => (u + t) / 100.0,
        _ => f64::NAN,
    }
}

#[allow(dead_code)] // used by the elasticity and xfem benches only
/// Resident memory now (VmRSS) in MB.
pub fn rss_mb() -> f64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    s.lines()
        .find(|l| l.starts_with("VmRSS:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}
