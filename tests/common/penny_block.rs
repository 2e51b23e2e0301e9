//! The penny-block case as text: `meshes/penny_block.msh` (the block [−5, 5]³, its faces
//! `front`/`back` at z = ±5, `left`/`right` at x = ±5), E = 1, ν = 0.3, three corner
//! points holding the rigid-body modes and nothing else (p1 = (−5, −5, −5) in x, y, z;
//! p2 = (5, −5, −5) in y, z; p3 = (−5, 5, −5) in z), then the loads and one crack named
//! `penny` with `tip_radius = sif_radius = 0.25`.
//!
//! It uses nothing but `std`, so that the integration tests (`common::penny_block`), the
//! benches (`benches/common`) and the library's test-only SIF reference
//! (`src/post/sif/per_point_reference.rs`) all include this one file by `#[path]`.

/// The disc crack of radius 1 in z = 0 (a crack's shape keys).
pub const PENNY_DISC: &str = "shape = \"disc\"\ncentre = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nradius = 1.0";

/// Tension σ = 1 on the faces z = ±5 (`front`, `back`).
pub const PENNY_TENSION: &str =
    "[[traction]]\ngroup = \"front\"\nvalue = [0.0, 0.0, 1.0]\n[[traction]]\ngroup = \"back\"\nvalue = [0.0, 0.0, -1.0]";

/// The committed mesh `meshes/penny_block.msh`.
pub fn penny_block_mesh() -> String {
    format!("{}/meshes/penny_block.msh", env!("CARGO_MANIFEST_DIR"))
}

/// The case on `mesh` with `loads` (case text before the crack) and the crack's shape keys
/// `crack` (e.g. [`PENNY_DISC`]); the crack's table comes last, so keys appended to the
/// text belong to it.
pub fn penny_block(mesh: &str, loads: &str, crack: &str) -> String {
    format!(
        r#"
[mesh]
file = "{mesh}"
[[materials]]
E = 1.0
nu = 0.3
[[sets]]
name = "p1"
on = "abs(x+5) + abs(y+5) + abs(z+5)"
[[sets]]
name = "p2"
on = "abs(x-5) + abs(y+5) + abs(z+5)"
[[sets]]
name = "p3"
on = "abs(x+5) + abs(y-5) + abs(z+5)"
[[dirichlet]]
group = "p1"
components = ["x", "y", "z"]
[[dirichlet]]
group = "p2"
components = ["y", "z"]
[[dirichlet]]
group = "p3"
components = ["z"]
{loads}
[[cracks]]
name = "penny"
{crack}
tip_radius = 0.25
sif_radius = 0.25
"#
    )
}
