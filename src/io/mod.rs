//! Output files: VTU pieces and PVD collections for ParaView, and `summary.json`.
//!
//! Entry points: [`vtu::write_vtu`], [`vtu::write_pvd`], [`summary::Summary`], and the
//! result guard [`guard`] (every figure finite before a step is reported ok).

pub mod guard;
pub mod summary;
pub mod vtu;
