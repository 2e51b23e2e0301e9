//! Output files: VTU pieces and PVD collections for ParaView, and `summary.json`.
//!
//! Entry points: [`vtu::write_vtu`], [`vtu::write_pvd`], [`summary::Summary`].

pub mod summary;
pub mod vtu;
