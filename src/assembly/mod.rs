//! Assembly machinery, independent of the physics: the dof map, the equation
//! numbering with eliminated (prescribed) dofs, the sparsity pattern, and the parallel
//! assembly of element kernels into a fixed pattern.
//!
//! Entry points: [`DofMap`], [`SystemLayout::build`], [`SystemLayout::assemble`], and
//! the [`Kernel`] trait that physics implements.
//!
//! The pattern is built once from the kernels' dof lists; later assemblies only
//! refill values (Newton iterations, new load steps). Elements are coloured so that
//! no two elements of a colour share an equation; each colour is assembled in
//! parallel with direct writes, so assembly needs no per-element buffer and no locks.

pub mod dofs;
pub mod layout;
pub mod pattern;

pub use dofs::{DofKind, DofMap};
pub use layout::SystemLayout;
pub use pattern::CscPattern;

/// Marker for a dof that has no equation (it is prescribed and eliminated).
pub const NO_EQ: u32 = u32::MAX;

/// What a kernel is asked to compute for one element.
pub struct LocalOut<'a> {
    /// Row-major `n × n` local matrix, zeroed by the caller.
    pub matrix: Option<&'a mut [f64]>,
    /// Local vector of length `n` (right-hand side contributions), zeroed by the caller.
    pub vector: Option<&'a mut [f64]>,
}

/// A family of elements contributing to the global system (bulk cells, boundary
/// faces, constraint rows, later crack facets and contact points).
pub trait Kernel: Sync {
    /// Number of elements in the family.
    fn n_elements(&self) -> usize;
    /// The global dofs of element `e`, appended to `out`.
    fn dofs(&self, e: usize, out: &mut Vec<u32>);
    /// Whether the kernel contributes to the matrix (boundary loads do not).
    fn has_matrix(&self) -> bool {
        true
    }
    /// Whether the local vector is a load `f` of a linear term `K u − f` (bulk, loads) or
    /// minus a nonlinear residual `−R(u)` with `K` its tangent (contact). Reactions are
    /// `K u − f` for the former and `R` for the latter.
    fn is_linear(&self) -> bool {
        true
    }
    /// Computes the local matrix and/or vector of element `e`, whose dofs are `dofs`.
    fn compute(&self, e: usize, dofs: &[u32], out: LocalOut<'_>);
}
