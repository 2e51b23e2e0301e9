//! The X-FEM assembly's batched stiffness (`physics::elasticity::StiffnessBatch`, one
//! matrix product per cell with many quadrature points) against the point-by-point
//! `add_isotropic_stiffness` it replaces there.

use fissure::physics::elasticity::{add_isotropic_stiffness, mirror_lower, StiffnessBatch};

/// [`StiffnessBatch`] against [`add_isotropic_stiffness`] point by point: the same sum
/// (to round-off, 1e-12 relative to the largest entry) for 2D and 3D, over more points
/// than one product gathers (600 > `CHUNK`) and with a change of Lamé constants in the
/// middle (a bimaterial cut). Gradients and weights are a fixed pseudo-random sequence.
#[test]
fn batched_stiffness_equals_the_point_by_point_sum() {
    let mut seed = 12345u64;
    let mut rnd = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    for dim in [2, 3] {
        let nb = 23;
        let m = nb * dim;
        let (mut k_ref, mut k_bat) = (vec![0.0; m * m], vec![0.0; m * m]);
        let mut batch = StiffnessBatch::default();
        batch.start(nb, dim);
        let mut current: Option<(f64, f64)> = None;
        for p in 0..600 {
            let (lam, mu) = if p < 350 { (1.7, 0.8) } else { (5.0, 2.5) };
            let g: Vec<[f64; 3]> = (0..nb).map(|_| [rnd(), rnd(), if dim == 3 { rnd() } else { 0.0 }]).collect();
            let wd = 0.5 + rnd().abs();
            add_isotropic_stiffness(&mut k_ref, &g, dim, lam, mu, wd);
            if let Some((l0, m0)) = current.filter(|&c| c != (lam, mu)) {
                batch.finish(&mut k_bat, dim, l0, m0);
            }
            current = Some((lam, mu));
            batch.push(&g, dim, wd);
        }
        let (l0, m0) = current.unwrap();
        batch.finish(&mut k_bat, dim, l0, m0);
        mirror_lower(&mut k_ref, m);
        mirror_lower(&mut k_bat, m);
        let scale = k_ref.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = k_ref.iter().zip(&k_bat).fold(0.0f64, |a, (r, b)| a.max((r - b).abs()));
        assert!(scale > 1.0, "dim {dim}: the reference is not trivial ({scale})");
        assert!(worst <= 1e-12 * scale, "dim {dim}: differs by {worst:e} (scale {scale:e})");
    }
}
