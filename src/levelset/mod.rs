//! Crack descriptions by two level sets and their sampling at mesh nodes.
//!
//! Entry points: [`CrackShape`] (built-in shapes and formulas, in [`shapes`]; cracks
//! given by a Gmsh mesh, in [`explicit`]), [`sample`]
//! (→ [`NodalLevelSets`]), [`check_crack_in_mesh`], [`snap`], and [`front_points`] (→
//! [`FrontPoint`], analytic front frames for the SIF code, in [`front`]).
//!
//! Conventions (docs/conventions.md, "Cracks"): `lsn` (φn) is the signed distance to
//! the crack surface, positive on the `+` side, whose unit normal n = ∇φn/|∇φn| points
//! from `−` to `+`; `lst` (φt) is the signed distance to the front measured in the crack
//! surface, negative on the crack. An interface (a cut through the whole body) has no φt.
//!
//! # Zero convention
//!
//! **An exact zero counts as positive**: a node with φn = 0.0 is on the `+` side, a node
//! with φt = 0.0 is outside the crack (uncracked). Downstream code classifies nodes with
//! `phi < 0.0` (negative) and `phi >= 0.0` (positive) and nothing else. [`snap`] turns
//! nodal values that are tiny relative to the local mesh size into exact zeros, so that a
//! crack passing (nearly) through a node or along an edge does not leave sliver sub-cells
//! or near-singular enrichments. [`sample`] and [`snap`] never leave a −0.0 (so that
//! `is_sign_negative` agrees too).
//!
//! # Front frames
//!
//! [`FrontPoint`]: e1 propagation direction (in the crack surface, normal to the front,
//! into the uncracked body), e2 crack normal, e3 = e1 × e2 front tangent. In 3D e2 = n.
//! In 2D e3 = +z at every tip and e2 = e3 × e1, which is +n at end `b` of a segment and
//! at the tip of a half-line but −n at end `a` of a segment: the standard right-handed
//! tip frame, so K_I > 0 in opening and K_II follows the usual sign (⟦u⟧·e1 with
//! ⟦u⟧ = u(side e2 points to) − u(other side)); see [`front`] for the reasoning.

pub mod explicit;
pub mod front;
pub mod quality;
pub mod shapes;

pub use front::{front_points, FrontPoint};
pub use shapes::CrackShape;

use crate::formula::Formula;
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::fmt;

/// Meshes with at least this many nodes are sampled in parallel.
const PARALLEL_NODES: usize = 4096;

/// Nodal values of one crack's level sets.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalLevelSets {
    /// φn at each mesh node.
    pub lsn: Vec<f64>,
    /// φt at each mesh node; `None` for an interface (no front).
    pub lst: Option<Vec<f64>>,
}

/// What can be wrong with a crack description or its level sets. Messages say what is
/// wrong; the caller adds the crack's name.
#[derive(Debug, Clone, PartialEq)]
pub enum LevelSetError {
    /// Impossible shape parameters (`shape` is [`CrackShape::name`]).
    BadShape { shape: &'static str, message: String },
    /// A built-in shape used on a mesh of the other dimension.
    DimensionMismatch { shape: &'static str, shape_dim: usize, mesh_dim: usize },
    /// A level-set value that is NaN or infinite (or a formula that failed to evaluate):
    /// `which` is "lsn" or "lst", `node` the 0-based node id when known, `x` the point.
    NotFinite { which: &'static str, node: Option<usize>, x: [f64; 3], detail: String },
    /// Nodal arrays whose length is not the mesh's node count.
    WrongLength { which: &'static str, expected: usize, got: usize },
    /// No cell of the mesh meets the crack surface (where φt < 0, for a crack with a front).
    OutsideMesh { has_front: bool },
    /// The crack lies inside the mesh's bounding box but is smaller than the cells around
    /// it, so that no node sees it (`length`: its largest extent; `cell`: the edge length
    /// of the cells there).
    TooSmall { length: f64, cell: f64 },
    /// A level set that is zero at every node (e.g. `lsn = "0*x"`): it describes no surface
    /// (φn) or no crack (φt).
    ZeroEverywhere { which: &'static str },
}

impl fmt::Display for LevelSetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LevelSetError::BadShape { shape, message } => write!(f, "{shape}: {message}"),
            LevelSetError::DimensionMismatch { shape, shape_dim, mesh_dim } => {
                write!(f, "a {shape} is a {shape_dim}D shape but the mesh is {mesh_dim}D")
            }
            LevelSetError::NotFinite { which, node, x, detail } => {
                let name = if *which == "lst" { "φt (lst)" } else { "φn (lsn)" };
                match node {
                    Some(i) => {
                        write!(f, "{name} is not finite at node {i} (x = {}, y = {}, z = {})", x[0], x[1], x[2])?
                    }
                    None => write!(f, "{name} is not finite at (x = {}, y = {}, z = {})", x[0], x[1], x[2])?,
                }
                if detail.is_empty() {
                    Ok(())
                } else {
                    write!(f, ": {detail}")
                }
            }
            LevelSetError::WrongLength { which, expected, got } => {
                write!(f, "{which} has {got} nodal values but the mesh has {expected} nodes")
            }
            LevelSetError::TooSmall { length, cell } => write!(
                f,
                "the crack is too short for the mesh: its size {length:.4e} is below the size {cell:.4e} of the cells it lies in, so no node sees it (φt > 0 at every node); refine the mesh there (cells at most half the crack's size) or give a larger crack"
            ),
            LevelSetError::ZeroEverywhere { which } => {
                if *which == "lst" {
                    write!(f, "φt (lst) is zero at every node: it describes no crack (φt < 0 on the crack, > 0 ahead of its front)")
                } else {
                    write!(f, "φn (lsn) is zero at every node: it describes no surface (φn must change sign across the crack, e.g. the signed distance to it)")
                }
            }
            LevelSetError::OutsideMesh { has_front } => {
                if *has_front {
                    write!(f, "the crack lies entirely outside the mesh: no cell is cut by φn = 0 where φt < 0")
                } else {
                    write!(f, "the interface lies entirely outside the mesh: no cell is cut by φn = 0")
                }
            }
        }
    }
}

impl std::error::Error for LevelSetError {}

/// A formula value at `p` (t = 0), or an error if evaluation fails or the value is not
/// finite.
pub(crate) fn checked_eval(
    f: &Formula,
    p: [f64; 3],
    which: &'static str,
    node: Option<usize>,
) -> Result<f64, LevelSetError> {
    match f.eval_checked(p, 0.0) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => {
            Err(LevelSetError::NotFinite { which, node, x: p, detail: format!("formula \"{}\" gives {v}", f.source()) })
        }
        Err(e) => Err(LevelSetError::NotFinite { which, node, x: p, detail: e.to_string() }),
    }
}

/// φn and φt of `shape` at every node of `mesh` (formulas at t = 0). The shape's
/// dimension must be the mesh's (formulas fit both). Errors: bad shape parameters, a
/// dimension mismatch, a NaN/infinite value (naming the node and its coordinates).
/// Parallel over nodes for large meshes; the result does not depend on the thread count.
pub fn sample(shape: &CrackShape, mesh: &Mesh) -> Result<NodalLevelSets, LevelSetError> {
    if !shape.accepts_dim(mesh.dim) {
        return Err(LevelSetError::DimensionMismatch {
            shape: shape.name(),
            shape_dim: shape.dim().unwrap_or(0),
            mesh_dim: mesh.dim,
        });
    }
    let s = shape.normalised()?;
    // `+ 0.0` turns a −0.0 into +0.0, so that sign bits agree with the zero convention.
    let eval = |p: &[f64; 3]| {
        let (n, t) = s.eval_normalised(*p);
        (n + 0.0, t.unwrap_or(0.0) + 0.0)
    };
    let (lsn, lst): (Vec<f64>, Vec<f64>) = if mesh.nodes.len() >= PARALLEL_NODES {
        mesh.nodes.par_iter().map(eval).unzip()
    } else {
        mesh.nodes.iter().map(eval).unzip()
    };
    let has_front = s.has_front();
    // Report the first bad node (deterministic, whatever the thread count).
    let bad = (0..lsn.len()).find(|&i| !lsn[i].is_finite() || (has_front && !lst[i].is_finite()));
    if let Some(i) = bad {
        let x = mesh.nodes[i];
        let which = if lsn[i].is_finite() { "lst" } else { "lsn" };
        if let CrackShape::Formula { lsn: fn_, lst: ft } = &s {
            let f = if which == "lsn" { Some(fn_) } else { ft.as_ref() };
            if let Some(f) = f {
                checked_eval(f, x, which, Some(i))?;
            }
        }
        let value = if which == "lsn" { lsn[i] } else { lst[i] };
        let detail = if x.iter().all(|c| c.is_finite()) {
            format!("value {value}")
        } else {
            "the node coordinates are not finite".to_string()
        };
        return Err(LevelSetError::NotFinite { which, node: Some(i), x, detail });
    }
    Ok(NodalLevelSets { lsn, lst: has_front.then_some(lst) })
}

/// Checks that the crack surface meets the mesh: some cell is cut by φn = 0 (its nodal
/// φn has min < 0 ≤ max, or an exact zero) and, for a crack with a front, has a node with
/// φt < 0. Node-based, which is exact for linear simplices (φt on the cut interpolates the
/// nodal values). Errors: [`LevelSetError::ZeroEverywhere`] (φn or φt zero at every node,
/// after snapping), [`LevelSetError::OutsideMesh`] ("the crack lies entirely outside the
/// mesh"; callers that know the shape turn it into [`LevelSetError::TooSmall`] when the
/// crack lies in the mesh but between its nodes), or [`LevelSetError::WrongLength`] if
/// the arrays do not match the mesh.
/// Node ids out of range are skipped (the mesh is validated elsewhere).
pub fn check_crack_in_mesh(ls: &NodalLevelSets, mesh: &Mesh) -> Result<(), LevelSetError> {
    let nn = mesh.nodes.len();
    if ls.lsn.len() != nn {
        return Err(LevelSetError::WrongLength { which: "lsn", expected: nn, got: ls.lsn.len() });
    }
    if let Some(t) = &ls.lst {
        if t.len() != nn {
            return Err(LevelSetError::WrongLength { which: "lst", expected: nn, got: t.len() });
        }
    }
    if !ls.lsn.is_empty() && ls.lsn.iter().all(|&v| v == 0.0) {
        return Err(LevelSetError::ZeroEverywhere { which: "lsn" });
    }
    if let Some(t) = &ls.lst {
        if !t.is_empty() && t.iter().all(|&v| v == 0.0) {
            return Err(LevelSetError::ZeroEverywhere { which: "lst" });
        }
    }
    let meets = mesh.cells.par_iter().any(|cell| {
        let (mut lo, mut hi, mut zero) = (f64::INFINITY, f64::NEG_INFINITY, false);
        let mut tmin = f64::INFINITY;
        for &v in cell.nodes() {
            let Some(&p) = ls.lsn.get(v) else { continue };
            lo = lo.min(p);
            hi = hi.max(p);
            zero |= p == 0.0;
            if let Some(t) = ls.lst.as_ref().and_then(|t| t.get(v)) {
                tmin = tmin.min(*t);
            }
        }
        let cut = (lo < 0.0 && hi >= 0.0) || zero;
        cut && (ls.lst.is_none() || tmin < 0.0)
    });
    if meets {
        Ok(())
    } else {
        Err(LevelSetError::OutsideMesh { has_front: ls.lst.is_some() })
    }
}

/// Local mesh size at each node: the length of the shortest cell edge touching it
/// (`f64::INFINITY` for a node in no cell).
pub fn node_sizes(mesh: &Mesh) -> Vec<f64> {
    let mut h = vec![f64::INFINITY; mesh.nodes.len()];
    for cell in &mesh.cells {
        let nodes = cell.nodes();
        for &[i, j] in cell.kind.edges() {
            let (Some(&a), Some(&b)) = (nodes.get(i), nodes.get(j)) else { continue };
            let (Some(pa), Some(pb)) = (mesh.nodes.get(a), mesh.nodes.get(b)) else { continue };
            let l = shapes::norm(shapes::sub(*pa, *pb));
            h[a] = h[a].min(l);
            h[b] = h[b].min(l);
        }
    }
    h
}

/// Sets nodal φn and φt whose magnitude is below `rel_tol` × (the shortest cell edge
/// touching the node) to exactly 0.0, which then counts as positive (see the module doc:
/// `+` side for φn, outside the crack for φt). Nodes in no cell, and a `rel_tol` that is
/// not positive, change nothing. Typical `rel_tol`: 1e-6.
pub fn snap(ls: &mut NodalLevelSets, mesh: &Mesh, rel_tol: f64) {
    if rel_tol.is_nan() || rel_tol <= 0.0 {
        return;
    }
    let h = node_sizes(mesh);
    let snap_one = |phi: &mut [f64]| {
        for (p, &hi) in phi.iter_mut().zip(&h) {
            if hi.is_finite() && p.abs() < rel_tol * hi {
                *p = 0.0;
            }
        }
    };
    snap_one(&mut ls.lsn);
    if let Some(t) = ls.lst.as_mut() {
        snap_one(t);
    }
}

#[cfg(test)]
mod tests;
