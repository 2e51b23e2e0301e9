//! Structured mesh generators: rectangles (tri3, quad4) and boxes (tet4, hex8), with
//! named boundary groups.
//!
//! Entry points: [`rectangle`], [`box_mesh`], [`perturb_interior`].
//!
//! Boundary face groups (their nodes are node groups too):
//! `left` x = x_min, `right` x = x_max, `bottom` y = y_min, `top` y = y_max, and in 3D
//! `back` z = z_min, `front` z = z_max. The whole body is the cell group `domain`.
//! Triangles split each square along its (0, 2) diagonal; tetrahedra split each cube
//! into six along its main diagonal (Kuhn), which is conforming between neighbours.

use super::{Cell, Mesh, MeshError};
use crate::element::CellType;

fn check(divisions: &[usize], lo: &[f64], hi: &[f64]) -> Result<(), MeshError> {
    for (k, &d) in divisions.iter().enumerate() {
        if d == 0 {
            return Err(MeshError::Generator(format!("divisions[{k}] must be at least 1")));
        }
        if !(hi[k] > lo[k]) {
            return Err(MeshError::Generator(format!(
                "the extent along axis {k} must be positive (got {} to {})",
                lo[k], hi[k]
            )));
        }
    }
    Ok(())
}

/// Rectangle `[lo, hi]` divided into `divisions` squares, as quad4 or tri3 cells.
pub fn rectangle(kind: CellType, lo: [f64; 2], hi: [f64; 2], divisions: [usize; 2]) -> Result<Mesh, MeshError> {
    if !matches!(kind, CellType::Tri3 | CellType::Quad4) {
        return Err(MeshError::Generator(format!("a rectangle takes tri3 or quad4 cells, not {}", kind.name())));
    }
    check(&divisions, &lo, &hi)?;
    let [nx, ny] = divisions;
    let id = |i: usize, j: usize| i + j * (nx + 1);
    let mut mesh = Mesh { dim: 2, ..Default::default() };
    for j in 0..=ny {
        for i in 0..=nx {
            let x = lo[0] + (hi[0] - lo[0]) * i as f64 / nx as f64;
            let y = lo[1] + (hi[1] - lo[1]) * j as f64 / ny as f64;
            mesh.nodes.push([x, y, 0.0]);
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            match kind {
                CellType::Quad4 => mesh.cells.push(Cell::new(kind, &q)),
                _ => {
                    mesh.cells.push(Cell::new(kind, &[q[0], q[1], q[2]]));
                    mesh.cells.push(Cell::new(kind, &[q[0], q[2], q[3]]));
                }
            }
        }
    }
    name_boundaries(&mut mesh);
    Ok(mesh)
}

/// Box `[lo, hi]` divided into `divisions` cubes, as hex8 or tet4 cells.
pub fn box_mesh(kind: CellType, lo: [f64; 3], hi: [f64; 3], divisions: [usize; 3]) -> Result<Mesh, MeshError> {
    if !matches!(kind, CellType::Tet4 | CellType::Hex8) {
        return Err(MeshError::Generator(format!("a box takes tet4 or hex8 cells, not {}", kind.name())));
    }
    check(&divisions, &lo, &hi)?;
    let [nx, ny, nz] = divisions;
    let id = |i: usize, j: usize, k: usize| i + j * (nx + 1) + k * (nx + 1) * (ny + 1);
    let mut mesh = Mesh { dim: 3, ..Default::default() };
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                mesh.nodes.push([
                    lo[0] + (hi[0] - lo[0]) * i as f64 / nx as f64,
                    lo[1] + (hi[1] - lo[1]) * j as f64 / ny as f64,
                    lo[2] + (hi[2] - lo[2]) * k as f64 / nz as f64,
                ]);
            }
        }
    }
    // Kuhn split of the cube along the diagonal 0–6 (positively oriented tetrahedra).
    const KUHN: [[usize; 4]; 6] = [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let h = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                match kind {
                    CellType::Hex8 => mesh.cells.push(Cell::new(kind, &h)),
                    _ => {
                        for t in KUHN {
                            let mut tet = [h[t[0]], h[t[1]], h[t[2]], h[t[3]]];
                            if signed_volume(&mesh, &tet) < 0.0 {
                                tet.swap(1, 2);
                            }
                            mesh.cells.push(Cell::new(kind, &tet));
                        }
                    }
                }
            }
        }
    }
    name_boundaries(&mut mesh);
    Ok(mesh)
}

fn signed_volume(mesh: &Mesh, t: &[usize; 4]) -> f64 {
    let p = |a: usize| mesh.nodes[t[a]];
    let d = |a: usize| [p(a)[0] - p(0)[0], p(a)[1] - p(0)[1], p(a)[2] - p(0)[2]];
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Names the boundary faces lying on the planes of the bounding box, and the cell
/// group `domain`.
fn name_boundaries(mesh: &mut Mesh) {
    let (lo, hi) = mesh.bounding_box();
    let names = [
        ("left", 0, false),
        ("right", 0, true),
        ("bottom", 1, false),
        ("top", 1, true),
        ("back", 2, false),
        ("front", 2, true),
    ];
    let faces = mesh.boundary_faces();
    for &(name, axis, upper) in names.iter().take(2 * mesh.dim) {
        let target = if upper { hi[axis] } else { lo[axis] };
        let tol = 1e-12 * (hi[axis] - lo[axis]).abs().max(1.0);
        let sel: Vec<_> = faces
            .iter()
            .filter(|f| f.nodes().iter().all(|&n| (mesh.nodes[n][axis] - target).abs() <= tol))
            .copied()
            .collect();
        mesh.face_groups.insert(name.to_string(), sel);
    }
    mesh.cell_groups.insert("domain".into(), (0..mesh.cells.len()).collect());
}

/// Moves every node that is not on the boundary by a pseudo-random offset of at most
/// `amplitude` times the local spacing `h` in each direction (deterministic for a seed).
/// Used to build distorted meshes for patch tests.
pub fn perturb_interior(mesh: &mut Mesh, h: f64, amplitude: f64, seed: u64) {
    let mut on_boundary = vec![false; mesh.nodes.len()];
    for f in mesh.boundary_faces() {
        for &n in f.nodes() {
            on_boundary[n] = true;
        }
    }
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    for (n, p) in mesh.nodes.iter_mut().enumerate() {
        if !on_boundary[n] {
            for c in p.iter_mut().take(mesh.dim) {
                *c += amplitude * h * next();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_meshes_are_valid_and_cover_the_domain() {
        for kind in [CellType::Tri3, CellType::Quad4] {
            let m = rectangle(kind, [0.0, 0.0], [2.0, 1.0], [4, 3]).unwrap();
            m.validate().unwrap();
            let a: f64 = (0..m.n_cells()).map(|c| m.cell_measure(c)).sum();
            assert!((a - 2.0).abs() < 1e-12);
            assert_eq!(m.group_faces("left").unwrap().len(), 3);
            assert_eq!(m.group_nodes("top").unwrap().len(), 5);
        }
        for kind in [CellType::Tet4, CellType::Hex8] {
            let m = box_mesh(kind, [0.0; 3], [1.0, 2.0, 3.0], [2, 3, 4]).unwrap();
            m.validate().unwrap();
            let v: f64 = (0..m.n_cells()).map(|c| m.cell_measure(c)).sum();
            assert!((v - 6.0).abs() < 1e-12);
            assert_eq!(m.group_nodes("front").unwrap().len(), 12);
        }
    }

    #[test]
    fn bad_generator_input_is_an_error() {
        assert!(rectangle(CellType::Quad4, [0.0, 0.0], [1.0, 1.0], [0, 2]).is_err());
        assert!(rectangle(CellType::Quad4, [0.0, 0.0], [-1.0, 1.0], [2, 2]).is_err());
        assert!(box_mesh(CellType::Quad4, [0.0; 3], [1.0; 3], [1, 1, 1]).is_err());
    }
}
