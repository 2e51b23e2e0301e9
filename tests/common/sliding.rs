//! The sliding-block cases of `tests/large_sliding.rs`, shared with `benches/sliding.rs`
//! (`#[path]`-included there).

/// The two blocks of the sliding tests, [0, 6] × [−0.5, 0.5] in 120 × 21 quad4 cells, with
/// the top edge driven by `top` (TOML lines for the top edge).
pub fn blocks(mu: f64, top: &str, steps: usize, integration: &str) -> String {
    blocks_sized(6.0, [120, 21], mu, top, steps, integration)
}

/// The same two blocks, [0, length] × [−0.5, 0.5] in `divisions` quad4 cells.
pub fn blocks_sized(length: f64, divisions: [usize; 2], mu: f64, top: &str, steps: usize, integration: &str) -> String {
    let factors: Vec<String> = (0..=steps).map(|k| format!("{k}")).collect();
    let [nx, ny] = divisions;
    format!(
        r#"
[mesh]
generator = "rectangle"
cell = "quad4"
lower = [0.0, -0.5]
upper = [{length}, 0.5]
divisions = [{nx}, {ny}]

[[materials]]
E = 1.0
nu = 0.0

[[dirichlet]]
group = "bottom"
components = ["x", "y"]

{top}

[steps]
factors = [{factors}]

[[cracks]]
name = "interface"
shape = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[cracks.contact]
friction = {mu}
sliding = "large"
integration = "{integration}"
"#,
        factors = factors.join(", ")
    )
}

/// The 3D blocks on the inclined plane: the case text (sliding `sliding`, platen moving by
/// `step` per step for `steps` steps after pressing), the unit normal and the slide direction.
pub fn inclined_plane_blocks(
    sliding: &str,
    step: f64,
    steps: usize,
    integration: &str,
) -> (String, Vec<f64>, Vec<f64>) {
    let n0: [f64; 3] = [-0.04, -0.03, 1.0];
    let ln = (n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]).sqrt();
    let n: Vec<f64> = n0.iter().map(|c| c / ln).collect();
    let dn = n[0] + n[1];
    let t0 = [1.0 - dn * n[0], 1.0 - dn * n[1], -dn * n[2]];
    let lt = (t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]).sqrt();
    let t: Vec<f64> = t0.iter().map(|c| c / lt).collect();
    let vals: Vec<String> = (0..3).map(|i| format!("\"{:.12} + {:.12} * t\"", -0.002 * n[i], step * t[i])).collect();
    let text = format!(
        r#"
[mesh]
generator = "box"
cell = "hex8"
lower = [0.0, 0.0, -0.5]
upper = [2.0, 2.0, 0.5]
divisions = [10, 10, 7]

[[materials]]
E = 1.0
nu = 0.0

[[dirichlet]]
group = "back"
components = ["x", "y", "z"]

[[dirichlet]]
group = "front"
components = ["x", "y", "z"]
values = [{}]

[steps]
factors = [{factors}]

[[cracks]]
name = "interface"
shape = "plane"
point = [1.0, 1.0, 0.0]
normal = [-0.04, -0.03, 1.0]

[cracks.contact]
friction = 0.5
sliding = "{sliding}"
integration = "{integration}"
"#,
        vals.join(", "),
        factors = (0..=steps).map(|k| k.to_string()).collect::<Vec<_>>().join(", ")
    );
    (text, n, t)
}
