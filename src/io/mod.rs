//! Output: VTU pieces and PVD collections for ParaView, `summary.json`, the CSV tables,
//! the PNG plots, the ParaView view script of 3D runs, and the terminal display.
//!
//! Entry points: [`vtu::write_vtu`], [`vtu::write_pvd`], [`summary::Summary`],
//! [`tables::write_tables`], [`plots::write_plots`], [`paraview_view::write_view_script`],
//! [`terminal::Terminal`], and the result guard [`guard`] (every figure finite before a
//! step is reported ok).

pub mod guard;
pub mod paraview_view;
pub mod plots;
pub mod summary;
pub mod tables;
pub mod terminal;
pub mod vtu;
