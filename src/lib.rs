//! # fissure
//!
//! An X-FEM crack contact toolkit. Data flows one way, each arrow producing an
//! immutable value that the next step reads:
//!
//! ```text
//! case file ──► Case ──┐
//! mesh file/generator ─┴► Mesh ──► DofMap ──► Assembly ──► solve ──► post ──► io
//! ```
//!
//! Layers, each allowed to use only the ones above it (`docs/architecture.md`):
//!
//! 0. [`io`]: VTU/PVD file formats (imports nothing from the crate).
//! 1. [`formula`], [`geometry`]: expressions of x, y, z; quadrature rules; 3-vector helpers;
//!    [`memory`]: the memory a model needs against the memory available; [`threads`]: the
//!    process's worker threads.
//! 2. [`element`]: reference elements and shape functions.
//! 3. [`mesh`]: the mesh, groups, generators, the Gmsh reader.
//!    3½. [`levelset`]: cracks as two level sets (built-in shapes, formulas), sampled at
//!    the mesh nodes; analytic front frames.
//!    3¾. [`cut`]: cells cut by a crack's level sets into integration sub-cells, crack
//!    facets, front pieces and lip boundaries (pure geometry).
//! 4. [`assembly`]: dof maps, sparsity patterns, the [`assembly::Kernel`] trait and the
//!    parallel assembly with value refill on a fixed pattern.
//!    4½. [`enrich`]: enrichment sets, numbering and the enriched basis.
//! 5. [`physics`]: materials and the element kernels (bulk, boundary, constraints).
//!    5½. [`contact`]: multipliers, contact points, pairing, the pointwise law, point
//!    kinematics and statuses, the contact kernel (never imports `solve`).
//! 6. [`solve`]: the step driver, its time scheme, the contact loops, Newton, the linear
//!    backend seam and its faer implementation.
//! 7. [`post`]: derived fields (strain, stress), SIFs, output grids, contact fields.
//!    7½. [`growth`]: crack growth criteria, the Paris law, the growing 2D polyline.
//! 8. [`case`]: reading and validating case files (and command-line overrides); [`run`]
//!    ties everything together, owns the `summary.json` schema and the result guard;
//!    [`sweep`] runs a case once per value of one key.
//!
//! The conventions (signs, units, orientations) are written once in `docs/conventions.md`.

// Numerical kernels index several arrays with the same loop variable (nodes, components,
// quadrature points); iterator chains would hide the index algebra the formulas use.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod assembly;
pub mod case;
pub mod contact;
pub mod cut;
pub mod element;
pub mod enrich;
pub mod formula;
pub mod geometry;
pub mod growth;
pub mod io;
pub mod levelset;
pub mod memory;
pub mod mesh;
pub mod physics;
pub mod post;
pub mod run;
pub mod solve;
pub mod sweep;
pub mod threads;

/// Version string written into `summary.json`.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
