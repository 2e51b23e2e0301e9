//! Reference elements: cell and face types, their shape functions, default
//! quadrature rules, and the isoparametric map (Jacobian, physical gradients).
//!
//! Entry points: [`CellType`], [`FaceType`], [`shape`] and [`physical_gradients`].
//!
//! Node orderings follow Gmsh and VTK (they agree for these linear types):
//! - `Tri3`: (0,0), (1,0), (0,1); `Tet4`: origin, then the unit points on ξ, η, ζ;
//! - `Quad4`: (−1,−1), (1,−1), (1,1), (−1,1), counter-clockwise;
//! - `Hex8`: the `Quad4` square at ζ = −1, then the same at ζ = +1.

use crate::geometry::quadrature::{self, QuadratureRule};
use std::sync::OnceLock;

/// Largest number of nodes of any cell type (hex8).
pub const MAX_NODES: usize = 8;

/// Volume (bulk) element types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CellType {
    Tri3,
    Quad4,
    Tet4,
    Hex8,
}

/// Boundary (face) element types: segments in 2D, triangles and quads in 3D.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FaceType {
    Line2,
    Tri3,
    Quad4,
}

impl CellType {
    pub fn n_nodes(self) -> usize {
        match self {
            CellType::Tri3 => 3,
            CellType::Quad4 => 4,
            CellType::Tet4 => 4,
            CellType::Hex8 => 8,
        }
    }
    pub fn dim(self) -> usize {
        match self {
            CellType::Tri3 | CellType::Quad4 => 2,
            CellType::Tet4 | CellType::Hex8 => 3,
        }
    }
    pub fn is_simplex(self) -> bool {
        matches!(self, CellType::Tri3 | CellType::Tet4)
    }
    pub fn name(self) -> &'static str {
        match self {
            CellType::Tri3 => "tri3",
            CellType::Quad4 => "quad4",
            CellType::Tet4 => "tet4",
            CellType::Hex8 => "hex8",
        }
    }
    /// Measure of the reference element.
    pub fn reference_measure(self) -> f64 {
        match self {
            CellType::Tri3 => 0.5,
            CellType::Quad4 => 4.0,
            CellType::Tet4 => 1.0 / 6.0,
            CellType::Hex8 => 8.0,
        }
    }
    /// Reference coordinates of the nodes.
    pub fn reference_nodes(self) -> &'static [[f64; 3]] {
        match self {
            CellType::Tri3 => &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            CellType::Quad4 => &[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
            CellType::Tet4 => &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            CellType::Hex8 => &[
                [-1.0, -1.0, -1.0],
                [1.0, -1.0, -1.0],
                [1.0, 1.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, -1.0, 1.0],
                [1.0, -1.0, 1.0],
                [1.0, 1.0, 1.0],
                [-1.0, 1.0, 1.0],
            ],
        }
    }
    /// Reference centroid.
    pub fn reference_centroid(self) -> [f64; 3] {
        match self {
            CellType::Tri3 => [1.0 / 3.0, 1.0 / 3.0, 0.0],
            CellType::Tet4 => [0.25, 0.25, 0.25],
            CellType::Quad4 | CellType::Hex8 => [0.0; 3],
        }
    }
    /// Quadrature rule exact for polynomials of `degree` on the reference element
    /// (per variable for tensor-product elements).
    pub fn quadrature(self, degree: usize) -> QuadratureRule {
        match self {
            CellType::Tri3 => quadrature::gauss_triangle(degree),
            CellType::Quad4 => quadrature::gauss_square(degree),
            CellType::Tet4 => quadrature::gauss_tetrahedron(degree),
            CellType::Hex8 => quadrature::gauss_cube(degree),
        }
    }
    /// [`Self::quadrature`], built once per cell type and degree (degrees up to 20; higher
    /// degrees are built on each call).
    pub fn cached_quadrature(self, degree: usize) -> std::borrow::Cow<'static, QuadratureRule> {
        const MAX_CACHED: usize = 20;
        static CACHE: [[OnceLock<QuadratureRule>; MAX_CACHED + 1]; 4] =
            [const { [const { OnceLock::new() }; MAX_CACHED + 1] }; 4];
        if degree > MAX_CACHED {
            return std::borrow::Cow::Owned(self.quadrature(degree));
        }
        let k = match self {
            CellType::Tri3 => 0,
            CellType::Quad4 => 1,
            CellType::Tet4 => 2,
            CellType::Hex8 => 3,
        };
        std::borrow::Cow::Borrowed(CACHE[k][degree].get_or_init(|| self.quadrature(degree)))
    }
    /// Boundary faces of the cell, as local node indices, oriented with an outward normal.
    pub fn faces(self) -> &'static [(FaceType, &'static [usize])] {
        match self {
            CellType::Tri3 => &[(FaceType::Line2, &[0, 1]), (FaceType::Line2, &[1, 2]), (FaceType::Line2, &[2, 0])],
            CellType::Quad4 => &[
                (FaceType::Line2, &[0, 1]),
                (FaceType::Line2, &[1, 2]),
                (FaceType::Line2, &[2, 3]),
                (FaceType::Line2, &[3, 0]),
            ],
            CellType::Tet4 => &[
                (FaceType::Tri3, &[0, 2, 1]),
                (FaceType::Tri3, &[0, 1, 3]),
                (FaceType::Tri3, &[1, 2, 3]),
                (FaceType::Tri3, &[0, 3, 2]),
            ],
            CellType::Hex8 => &[
                (FaceType::Quad4, &[0, 3, 2, 1]),
                (FaceType::Quad4, &[4, 5, 6, 7]),
                (FaceType::Quad4, &[0, 1, 5, 4]),
                (FaceType::Quad4, &[1, 2, 6, 5]),
                (FaceType::Quad4, &[2, 3, 7, 6]),
                (FaceType::Quad4, &[3, 0, 4, 7]),
            ],
        }
    }
    /// Edges of the cell as pairs of local node indices.
    pub fn edges(self) -> &'static [[usize; 2]] {
        match self {
            CellType::Tri3 => &[[0, 1], [1, 2], [2, 0]],
            CellType::Quad4 => &[[0, 1], [1, 2], [2, 3], [3, 0]],
            CellType::Tet4 => &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]],
            CellType::Hex8 => {
                &[[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]]
            }
        }
    }
}

impl FaceType {
    pub fn n_nodes(self) -> usize {
        match self {
            FaceType::Line2 => 2,
            FaceType::Tri3 => 3,
            FaceType::Quad4 => 4,
        }
    }
    pub fn quadrature(self, degree: usize) -> QuadratureRule {
        match self {
            FaceType::Line2 => quadrature::gauss_line(degree),
            FaceType::Tri3 => quadrature::gauss_triangle(degree),
            FaceType::Quad4 => quadrature::gauss_square(degree),
        }
    }
    /// Shape functions and their derivatives on the face's reference element.
    pub fn shape(self, xi: &[f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
        match self {
            FaceType::Line2 => {
                n[0] = 0.5 * (1.0 - xi[0]);
                n[1] = 0.5 * (1.0 + xi[0]);
                dn[0] = [-0.5, 0.0, 0.0];
                dn[1] = [0.5, 0.0, 0.0];
            }
            FaceType::Tri3 => shape(CellType::Tri3, xi, n, dn),
            FaceType::Quad4 => shape(CellType::Quad4, xi, n, dn),
        }
    }
}

/// Evaluates the shape functions `n[a]` and their reference derivatives `dn[a][k] = ∂N_a/∂ξ_k`.
/// `n` and `dn` must hold at least `kind.n_nodes()` entries.
pub fn shape(kind: CellType, xi: &[f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let (x, y, z) = (xi[0], xi[1], xi[2]);
    match kind {
        CellType::Tri3 => {
            n[0] = 1.0 - x - y;
            n[1] = x;
            n[2] = y;
            dn[0] = [-1.0, -1.0, 0.0];
            dn[1] = [1.0, 0.0, 0.0];
            dn[2] = [0.0, 1.0, 0.0];
        }
        CellType::Tet4 => {
            n[0] = 1.0 - x - y - z;
            n[1] = x;
            n[2] = y;
            n[3] = z;
            dn[0] = [-1.0, -1.0, -1.0];
            dn[1] = [1.0, 0.0, 0.0];
            dn[2] = [0.0, 1.0, 0.0];
            dn[3] = [0.0, 0.0, 1.0];
        }
        CellType::Quad4 => {
            let r = kind.reference_nodes();
            for a in 0..4 {
                let (xa, ya) = (r[a][0], r[a][1]);
                n[a] = 0.25 * (1.0 + xa * x) * (1.0 + ya * y);
                dn[a] = [0.25 * xa * (1.0 + ya * y), 0.25 * ya * (1.0 + xa * x), 0.0];
            }
        }
        CellType::Hex8 => {
            let r = kind.reference_nodes();
            for a in 0..8 {
                let (xa, ya, za) = (r[a][0], r[a][1], r[a][2]);
                let (fx, fy, fz) = (1.0 + xa * x, 1.0 + ya * y, 1.0 + za * z);
                n[a] = 0.125 * fx * fy * fz;
                dn[a] = [0.125 * xa * fy * fz, 0.125 * ya * fx * fz, 0.125 * za * fx * fy];
            }
        }
    }
}

/// Error of the isoparametric map at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularMap {
    pub det: f64,
}

/// Maps reference gradients to physical ones at one point.
///
/// `coords[a]` are the physical node coordinates, `dn_ref[a]` the reference derivatives;
/// writes `dn_x[a][k] = ∂N_a/∂x_k` and returns `det J`. A non-positive (or tiny relative to
/// the element size) determinant is an error: the element is inverted or degenerate.
pub fn physical_gradients(
    dim: usize,
    coords: &[[f64; 3]],
    dn_ref: &[[f64; 3]],
    dn_x: &mut [[f64; 3]],
) -> Result<f64, SingularMap> {
    let nn = coords.len();
    // J[i][k] = Σ_a x_a,i ∂N_a/∂ξ_k
    let mut j = [[0.0f64; 3]; 3];
    for a in 0..nn {
        for i in 0..dim {
            for k in 0..dim {
                j[i][k] += coords[a][i] * dn_ref[a][k];
            }
        }
    }
    let (det, inv) = if dim == 2 {
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let inv = [[j[1][1] / det, -j[0][1] / det, 0.0], [-j[1][0] / det, j[0][0] / det, 0.0], [0.0; 3]];
        (det, inv)
    } else {
        let c00 = j[1][1] * j[2][2] - j[1][2] * j[2][1];
        let c01 = j[1][2] * j[2][0] - j[1][0] * j[2][2];
        let c02 = j[1][0] * j[2][1] - j[1][1] * j[2][0];
        let det = j[0][0] * c00 + j[0][1] * c01 + j[0][2] * c02;
        let inv = [
            [c00 / det, (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det, (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det],
            [c01 / det, (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det, (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det],
            [c02 / det, (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det, (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det],
        ];
        (det, inv)
    };
    // Scale for the degeneracy test: product of the column norms of J.
    let mut scale = 1.0;
    for k in 0..dim {
        let mut s = 0.0;
        for i in 0..dim {
            s += j[i][k] * j[i][k];
        }
        scale *= s.sqrt();
    }
    if !(det > 1e-12 * scale) {
        return Err(SingularMap { det });
    }
    // ∂N/∂x_i = Σ_k ∂N/∂ξ_k (J^{-1})[k][i]
    for a in 0..nn {
        let mut g = [0.0; 3];
        for i in 0..dim {
            for k in 0..dim {
                g[i] += dn_ref[a][k] * inv[k][i];
            }
        }
        dn_x[a] = g;
    }
    Ok(det)
}

/// Physical position of a reference point: `x = Σ_a N_a x_a`.
pub fn map_point(n: &[f64], coords: &[[f64; 3]]) -> [f64; 3] {
    let mut x = [0.0; 3];
    for (na, c) in n.iter().zip(coords) {
        for i in 0..3 {
            x[i] += na * c[i];
        }
    }
    x
}

/// Area/length element and unit outward normal of a boundary face at one point.
/// For `Line2` in 2D the normal is the tangent rotated by −90° (outward for a
/// counter-clockwise boundary); for 3D faces it is `∂x/∂ξ × ∂x/∂η`.
pub fn face_measure_and_normal(kind: FaceType, coords: &[[f64; 3]], dn_ref: &[[f64; 3]]) -> (f64, [f64; 3]) {
    let nn = kind.n_nodes();
    let mut t1 = [0.0; 3];
    let mut t2 = [0.0; 3];
    for a in 0..nn {
        for i in 0..3 {
            t1[i] += coords[a][i] * dn_ref[a][0];
            t2[i] += coords[a][i] * dn_ref[a][1];
        }
    }
    match kind {
        FaceType::Line2 => {
            let len = (t1[0] * t1[0] + t1[1] * t1[1]).sqrt();
            (len, [t1[1] / len, -t1[0] / len, 0.0])
        }
        _ => {
            let c = [t1[1] * t2[2] - t1[2] * t2[1], t1[2] * t2[0] - t1[0] * t2[2], t1[0] * t2[1] - t1[1] * t2[0]];
            let a = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            (a, [c[0] / a, c[1] / a, c[2] / a])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_partition_unity_and_kronecker() {
        for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
            let mut n = [0.0; MAX_NODES];
            let mut dn = [[0.0; 3]; MAX_NODES];
            for (b, xb) in kind.reference_nodes().iter().enumerate() {
                shape(kind, xb, &mut n, &mut dn);
                for a in 0..kind.n_nodes() {
                    let expect = if a == b { 1.0 } else { 0.0 };
                    assert!((n[a] - expect).abs() < 1e-15);
                }
            }
            shape(kind, &kind.reference_centroid(), &mut n, &mut dn);
            let s: f64 = n[..kind.n_nodes()].iter().sum();
            assert!((s - 1.0).abs() < 1e-15);
            for k in 0..kind.dim() {
                let g: f64 = dn[..kind.n_nodes()].iter().map(|d| d[k]).sum();
                assert!(g.abs() < 1e-15);
            }
        }
    }

    #[test]
    fn reference_measure_by_quadrature() {
        for kind in [CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8] {
            let s: f64 = kind.quadrature(2).weights.iter().sum();
            assert!((s - kind.reference_measure()).abs() < 1e-14);
        }
    }

    #[test]
    fn inverted_element_is_rejected() {
        let coords = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
        let mut n = [0.0; 3];
        let mut dn = [[0.0; 3]; 3];
        shape(CellType::Tri3, &[0.3, 0.3, 0.0], &mut n, &mut dn);
        let mut g = [[0.0; 3]; 3];
        assert!(physical_gradients(2, &coords, &dn, &mut g).is_err());
    }
}
