//! The friction unknowns' tangent frame on a curved meshed pair (issue 16, defect 3 of
//! `docs/reliability.md`, "Diagnosed: the 3D sphere example with friction at unit scale"):
//! the Λ components of a multiplier packet must be taken in one continuous frame over the
//! packet's support, or the tangential traction is wrong where the frame jumps.

mod common;

use common::contact::{solve_contact_text, ContactRun};
use fissure::contact::law::Status;
use std::path::Path;

/// `examples/sphere_on_block_3d.toml` with `friction = 0.3` in its pair, in pascals (E =
/// 2.1e11, the pressure × 2.1e11: the unit system in which the example with friction
/// converges on every frame tried).
fn sphere_with_friction_in_pascals() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("examples/sphere_on_block_3d.toml")).unwrap();
    let text = text.replace("\"../meshes/", &format!("\"{}/meshes/", root.display()));
    let s = 2.1e11;
    let scaled = text
        .replace("E = 1.0\n", &format!("E = {s:e}\n"))
        .replace("value = 5.0875e-4\n", &format!("value = {:e}\n", 5.0875e-4 * s))
        .replace("[[contact_pairs]]\n", "[[contact_pairs]]\nfriction = 0.3\n");
    assert!(scaled.contains("friction = 0.3") && scaled.contains("E = 2.1e11"));
    scaled
}

/// The hoop share of the tangential traction at the sliding points, |t_τ·e_θ| / |t_τ|
/// weighted by the points' weights (e_θ the azimuthal direction about the sphere's axis y
/// through the contact point), within 10° of the diagonal x = z and elsewhere.
fn slip_hoop_shares(r: &ContactRun, mu: f64) -> (f64, f64, usize) {
    let (mut diag, mut off, mut count) = ([0.0f64; 2], [0.0f64; 2], 0);
    for k in 0..r.lambda.len() {
        if r.status[k] != Status::Slip {
            continue;
        }
        let (n, t1, l, bl, w, x) = (r.normal[k], r.tangent[k], r.lambda[k], r.big_lambda[k], r.weight[k], r.x[k]);
        let t2 = [n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]];
        let t: Vec<f64> = (0..3).map(|i| mu * l * (bl[0] * t1[i] + bl[1] * t2[i])).collect();
        let rr = x[0].hypot(x[2]);
        let tn = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        if rr <= 0.0 || tn <= 0.0 {
            continue;
        }
        let hoop = (-t[0] * x[2] + t[2] * x[0]).abs() / rr;
        let side = if (x[2].atan2(x[0]).to_degrees() - 45.0).abs() < 10.0 { &mut diag } else { &mut off };
        side[0] += w * hoop;
        side[1] += w * tn;
        count += 1;
    }
    (diag[0] / diag[1], off[0] / off[1], count)
}

/// Geometry, material, load: `examples/sphere_on_block_3d.toml` (tet4 quarter model of a
/// ball R = 1 on a 0.6 × 0.6 × 0.6 block, symmetry planes x = 0 and z = 0, E = 2.1e11, ν =
/// 0.3, q = 5.0875e-4 E on the ball's top in 2 load steps) with μ = 0.3. The slave surface
/// `sphere_cap` (the spherical cap and the flat faces x = 0.6, z = 0.6 of the cut ball) has
/// the mean normal (0.56, −0.36, 0.56): the axis y of the old frame rule lies within 6° of
/// the normals over the contact zone, where each facet then took x or z, whichever was less
/// aligned with its normal: τ₁ jumped from e_z to e_x across the diagonal |n_x| = |n_z|.
/// Reference: the problem is axisymmetric about y near the contact (the block's square
/// edges are 6a away), so the slip direction, hence the sliding points' tangential
/// traction, has no preferred azimuth: the hoop share |t_τ·e_θ|/|t_τ| near the diagonal
/// x = z must be that of the rest of the zone within 0.05 (the tet mesh's own scatter;
/// measured with the continuous frame (1, 1, 1)/√3: 0.044 near the diagonal, 0.116
/// elsewhere; with the old jumping frame 0.175 against 0.080). And the answer does not
/// depend on which continuous frame is taken: with the reference (0.33, 0.89, 0.33) (the
/// least-aligned-on-average direction, tried) instead of the body diagonal, the same shares
/// to 3 digits (checked by hand, not asserted: the frame is not a case key). About 25–45 s
/// in release.
#[test]
fn sphere_with_friction_slides_radially_across_the_diagonal_of_its_quarter_model() {
    let r = solve_contact_text(&sphere_with_friction_in_pascals()).unwrap_or_else(|e| panic!("{e}"));
    let (diag, off, count) = slip_hoop_shares(&r, 0.3);
    eprintln!("sliding points {count}: hoop share near the diagonal {diag:.3}, elsewhere {off:.3}");
    assert!(count > 100, "{count} sliding points");
    assert!(
        diag <= off + 0.05,
        "the sliding traction turns near the diagonal x = z: hoop share {diag:.3} against {off:.3}"
    );
}
