//! The boundary of a crack's lip: which sides of each facet are not shared with another
//! facet of the same crack (pure geometry on the undeformed facets). Large-sliding contact
//! uses it to tell a point that slid off the master lip from one in front of it.
//!
//! Entry point: [`lip_boundary`].

use super::CrackCut;
use std::collections::HashMap;

/// Per facet, which of its sides (2D: vertices, 3D: edges opposite each vertex) lie on
/// the boundary of the lip: not shared with another facet of the crack (found on the
/// undeformed facets; computed once per crack, with the contact points).
pub fn lip_boundary(dim: usize, cut: &CrackCut, h: f64) -> Vec<Vec<bool>> {
    // Quantised positions identify shared vertices across cells.
    let q = |x: &[f64; 3]| -> [i64; 3] {
        let s = 1e-7 * h.max(f64::MIN_POSITIVE);
        [(x[0] / s).round() as i64, (x[1] / s).round() as i64, (x[2] / s).round() as i64]
    };
    if dim == 2 {
        let mut count: HashMap<[i64; 3], u32> = HashMap::new();
        for f in &cut.facets {
            for v in &f.vertices {
                *count.entry(q(v)).or_default() += 1;
            }
        }
        cut.facets.iter().map(|f| f.vertices.iter().map(|v| count[&q(v)] < 2).collect()).collect()
    } else {
        let key = |a: &[f64; 3], b: &[f64; 3]| {
            let (qa, qb) = (q(a), q(b));
            if qa < qb {
                (qa, qb)
            } else {
                (qb, qa)
            }
        };
        let mut count: HashMap<([i64; 3], [i64; 3]), u32> = HashMap::new();
        for f in &cut.facets {
            let v = &f.vertices;
            for k in 0..v.len() {
                *count.entry(key(&v[(k + 1) % 3], &v[(k + 2) % 3])).or_default() += 1;
            }
        }
        // Entry k: the edge opposite vertex k (where barycentric k is 0).
        cut.facets
            .iter()
            .map(|f| {
                let v = &f.vertices;
                (0..v.len()).map(|k| count[&key(&v[(k + 1) % 3], &v[(k + 2) % 3])] < 2).collect()
            })
            .collect()
    }
}
